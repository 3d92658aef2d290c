//! The legend: a strip below the axes, one entry (a line of the series' colour and its label) per
//! series, flowing left to right in centred rows, so that it never covers the data.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::figure::{series_colours, Figure, Metrics};
use super::font::FAMILY;

/// How the legend is laid out: entries flow left to right in rows below the axes.
pub(super) struct LegendLayout {
    /// The (x, row) of each entry, in pixels from the legend area's left edge and in rows.
    positions: Vec<(i32, i32)>,
    row_height: u32,
    pub height: u32,
}

pub(super) fn legend_layout<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
    metrics: &Metrics,
) -> LegendLayout {
    let font = (FAMILY, metrics.legend).into_font();
    let (width, _) = root.dim_in_pixel();
    let swatch = (metrics.legend * 2.5) as i32;
    let gap = (metrics.legend * 1.5) as i32;
    let left = (metrics.legend * 2.0) as i32;
    let (mut x, mut row) = (0, 0);
    let mut positions = Vec::new();
    let mut row_widths = vec![0];
    for series in &figure.series {
        let text_width =
            root.estimate_text_size(&series.label, &TextStyle::from(font.clone())).map(|(w, _)| w as i32).unwrap_or(0);
        let entry = swatch + text_width + gap;
        if x > 0 && x + entry - gap > width as i32 - 2 * left {
            (x, row) = (0, row + 1);
            row_widths.push(0);
        }
        positions.push((x, row));
        x += entry;
        row_widths[row as usize] = x - gap;
    }
    // Each row centred.
    for (x, row) in &mut positions {
        *x += (width as i32 - row_widths[*row as usize]) / 2;
    }
    let row_height = (metrics.legend * 1.5) as u32;
    let rows = if figure.series.is_empty() { 0 } else { row + 1 };
    LegendLayout { positions, row_height, height: rows as u32 * row_height + (metrics.legend * 0.8) as u32 }
}

pub(super) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    figure: &Figure,
    metrics: &Metrics,
    layout: &LegendLayout,
) -> Result<(), String> {
    let font = (FAMILY, metrics.legend).into_font().color(&BLACK);
    let swatch = (metrics.legend * 2.0) as i32;
    let colours = series_colours(figure);
    for ((series, &(x, row)), colour) in figure.series.iter().zip(&layout.positions).zip(colours) {
        let y = row * layout.row_height as i32 + layout.row_height as i32 / 2;
        let style = colour.stroke_width(metrics.line_width + 1);
        area.draw(&PathElement::new(vec![(x, y), (x + swatch, y)], style)).map_err(|e| e.to_string())?;
        let text_style = font.clone().pos(Pos::new(HPos::Left, VPos::Center));
        area.draw(&Text::new(series.label.clone(), (x + swatch + (metrics.legend * 0.5) as i32, y), text_style))
            .map_err(|e| e.to_string())?;
    }
    Ok(())
}
