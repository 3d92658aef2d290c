//! Rendering a figure — lines of (x, y) points with a title, axis labels and a legend — to PNG or SVG
//! with plotters. The legend goes in a strip below the axes, so it never covers the data.

use std::path::Path;

use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;

use super::axis::{linear_axis, log_axis, AxisScale};
use super::font::{self, FAMILY};
use super::legend::{draw_legend, legend_layout};
use crate::run::CliError;

/// One line of the plot and its legend entry.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: String,
    pub points: Vec<(f64, f64)>,
    pub style: SeriesStyle,
}

/// How a series is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SeriesStyle {
    /// A line in the next colour of the palette.
    #[default]
    Line,
    /// A line in the next colour of the palette with a dot at each point (values computed at a few
    /// points, e.g. frequencies against a swept parameter).
    LineAndPoints,
    /// A dashed black line that takes no colour of the palette (a reference, e.g. a Campbell
    /// diagram's 1× line).
    Reference,
}

/// A point marked with a circle and a short text (e.g. a spectral peak and its frequency).
#[derive(Clone, Debug)]
pub struct Annotation {
    pub x: f64,
    pub y: f64,
    pub text: String,
}

/// Whether an axis is linear or logarithmic (for spectra, errors or costs spanning decades).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scale {
    Linear,
    Log,
}

/// What to draw.
#[derive(Clone, Debug)]
pub struct Figure {
    pub title: String,
    /// Quantity on the x axis and its unit, e.g. `("t", Some("s"))`.
    pub x_quantity: (String, Option<String>),
    pub y_quantity: (String, Option<String>),
    pub series: Vec<Series>,
    pub annotations: Vec<Annotation>,
    pub y_scale: Scale,
    /// Whether the x axis is linear (time, a swept parameter) or logarithmic (a cost spanning decades,
    /// as a work-precision diagram's steps).
    pub x_scale: Scale,
    /// The x range to show; by default that of the data and the annotations.
    pub x_range: Option<(f64, f64)>,
    /// The y range to show; by default that of the data and the annotations, with room (see
    /// [`axis_ranges`]).
    pub y_range: Option<(f64, f64)>,
}

/// The image formats plots are written in, from the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    Png,
    Svg,
}

impl ImageFormat {
    pub fn of(path: &Path) -> Result<Self, CliError> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("png") => Ok(Self::Png),
            Some("svg") => Ok(Self::Svg),
            other => Err(CliError(format!(
                "{}: cannot write {} images; use a .png or .svg file name",
                path.display(),
                other.map_or("extensionless".to_string(), |e| format!(".{e}"))
            ))),
        }
    }
}

/// Most ticks on each axis.
const X_TICKS: usize = 10;
const Y_TICKS: usize = 8;

/// Bitmaps are drawn this many times larger and averaged down, which smooths lines and text
/// (plotters draws bitmap lines without anti-aliasing); not for images over [`SUPERSAMPLED_PIXELS`].
const SUPERSAMPLING: u32 = 2;
const SUPERSAMPLED_PIXELS: u32 = 4_000_000;

/// Smallest and largest image size accepted, in pixels.
pub const SIZE_LIMITS: (u32, u32) = (200, 8000);

/// Line colours, in order (the "tab10" palette: distinct, readable on white, printable).
pub(super) const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Draws `figure` into `path` (`.png` or `.svg`) of `width × height` pixels.
pub fn render(figure: &Figure, path: &Path, (width, height): (u32, u32)) -> Result<(), CliError> {
    check_size(width, height)?;
    axis_ranges(figure).map_err(CliError)?;
    let failed = |e: String| CliError(format!("cannot write {}: {e}", path.display()));
    match ImageFormat::of(path)? {
        ImageFormat::Png => {
            let pixels = render_rgb(figure, (width, height))?;
            write_png(path, (width, height), &pixels).map_err(failed)
        }
        ImageFormat::Svg => {
            font::register();
            let root = SVGBackend::new(path, (width, height)).into_drawing_area();
            draw_figure(&root, figure).and_then(|()| root.present().map_err(|e| e.to_string())).map_err(failed)
        }
    }
}

/// The figure as 8-bit RGB pixels, row by row.
pub fn render_rgb(figure: &Figure, (width, height): (u32, u32)) -> Result<Vec<u8>, CliError> {
    check_size(width, height)?;
    axis_ranges(figure).map_err(CliError)?;
    font::register();
    let factor = if width * height <= SUPERSAMPLED_PIXELS { SUPERSAMPLING } else { 1 };
    let (big_width, big_height) = (factor * width, factor * height);
    let mut pixels = vec![255u8; 3 * big_width as usize * big_height as usize];
    {
        let root = BitMapBackend::with_buffer(&mut pixels, (big_width, big_height)).into_drawing_area();
        draw_figure(&root, figure).and_then(|()| root.present().map_err(|e| e.to_string())).map_err(CliError)?;
    }
    Ok(downsample(&pixels, (width, height), factor as usize))
}

/// Each output pixel the mean of a `factor × factor` block of the large image.
fn downsample(pixels: &[u8], (width, height): (u32, u32), factor: usize) -> Vec<u8> {
    if factor == 1 {
        return pixels.to_vec();
    }
    let (width, height) = (width as usize, height as usize);
    let big_row = 3 * width * factor;
    let mut out = vec![0u8; 3 * width * height];
    for y in 0..height {
        for x in 0..width {
            for c in 0..3 {
                let sum: usize = (0..factor)
                    .flat_map(|dy| (0..factor).map(move |dx| (y * factor + dy) * big_row + 3 * (x * factor + dx) + c))
                    .map(|i| usize::from(pixels[i]))
                    .sum();
                out[3 * (y * width + x) + c] = ((sum + factor * factor / 2) / (factor * factor)) as u8;
            }
        }
    }
    out
}

fn check_size(width: u32, height: u32) -> Result<(), CliError> {
    let (low, high) = SIZE_LIMITS;
    if (low..=high).contains(&width) && (low..=high).contains(&height) {
        Ok(())
    } else {
        Err(CliError(format!("image size {width}×{height}: width and height must be {low} to {high} pixels")))
    }
}

fn write_png(path: &Path, (width, height): (u32, u32), pixels: &[u8]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| e.to_string())?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer.write_image_data(pixels).map_err(|e| e.to_string())?;
    writer.finish().map_err(|e| e.to_string())
}

/// Sizes that grow with the image, so that text stays readable from 600 to 3000 pixels wide.
pub(super) struct Metrics {
    pub(super) title: f64,
    pub(super) axis_label: f64,
    pub(super) tick_label: f64,
    pub(super) legend: f64,
    pub(super) line_width: u32,
}

impl Metrics {
    fn of(width: u32, height: u32) -> Self {
        let s = (f64::from(width) / 1000.0).min(f64::from(height) / 625.0).max(0.5);
        Self {
            title: 25.0 * s,
            axis_label: 20.0 * s,
            tick_label: 17.0 * s,
            legend: 17.0 * s,
            line_width: (2.0 * s).round().max(1.0) as u32,
        }
    }
}

fn draw_figure<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, figure: &Figure) -> Result<(), String> {
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let (width, height) = root.dim_in_pixel();
    let metrics = Metrics::of(width, height);
    let legend = legend_layout(root, figure, &metrics);
    let (chart_area, legend_area) = root.split_vertically(height.saturating_sub(legend.height));
    let (x_range, y_range) = axis_ranges(figure)?;
    let ranges = (x_range, y_range);
    let (x_lin, y_lin) = (linear_axis(x_range, X_TICKS), linear_axis(y_range, Y_TICKS));
    let (x_span, y_span) = (x_range.0..x_range.1, y_range.0..y_range.1);
    match (figure.x_scale, figure.y_scale) {
        (Scale::Linear, Scale::Linear) => draw_axes(&chart_area, figure, &metrics, ranges, (x_lin, y_lin), (x_span, y_span))?,
        (Scale::Linear, Scale::Log) => draw_axes(&chart_area, figure, &metrics, ranges, (x_lin, log_axis()), (x_span, y_span.log_scale()))?,
        (Scale::Log, Scale::Linear) => draw_axes(&chart_area, figure, &metrics, ranges, (log_axis(), y_lin), (x_span.log_scale(), y_span))?,
        (Scale::Log, Scale::Log) => {
            draw_axes(&chart_area, figure, &metrics, ranges, (log_axis(), log_axis()), (x_span.log_scale(), y_span.log_scale()))?
        }
    }
    draw_legend(&legend_area, figure, &metrics, &legend)
}

/// The x and y ranges the axes show, or an error if one cannot be drawn: those the figure gives, else
/// the data's and the annotations' (every annotated point is inside the axes): the y axis with 5 %
/// room above and below, or on a logarithmic axis from 2 to 7 decades below the largest value (at
/// least a decade below the smallest annotation) to 4 times above it.
pub fn axis_ranges(figure: &Figure) -> Result<(AxisRange, AxisRange), String> {
    let points = || figure.series.iter().flat_map(|s| &s.points).copied();
    let annotated = || figure.annotations.iter().map(|a| (a.x, a.y));
    let x_values = || points().chain(annotated()).map(|p| p.0);
    let x_range = match (figure.x_range, figure.x_scale) {
        (Some(range), _) => range,
        (None, Scale::Linear) => data_range(x_values()),
        (None, Scale::Log) => log_padded(data_range(x_values().filter(|v| *v > 0.0))),
    };
    let y_values = || points().chain(annotated()).map(|p| p.1).filter(|v| v.is_finite());
    let y_range = match (figure.y_range, figure.y_scale) {
        (Some(range), _) => range,
        (None, Scale::Linear) => padded(data_range(y_values())),
        (None, Scale::Log) => {
            let (lo, hi) = log_range(y_values());
            let smallest_annotation = annotated().map(|p| p.1).filter(|y| *y > 0.0).fold(f64::INFINITY, f64::min);
            (lo.min(smallest_annotation / 10.0), hi)
        }
    };
    let axes = [
        ("x", &figure.x_quantity, x_range, x_range),
        ("y", &figure.y_quantity, y_range, data_range(y_values())),
    ];
    for (axis, (quantity, _), range, (lo, hi)) in axes {
        if !drawable(range) {
            return Err(format!("cannot draw the {axis} axis ({quantity}) over values from {lo:e} to {hi:e}: {SPAN_TOO_LARGE}"));
        }
    }
    Ok((x_range, y_range))
}

/// The lowest and highest value an axis shows.
pub type AxisRange = (f64, f64);

/// Why an axis cannot be drawn.
pub(super) const SPAN_TOO_LARGE: &str =
    "with its margins the axis would span more than the largest double-precision number, 1.8e308";

/// Whether an axis over `(lo, hi)` can be drawn: its ends and its span must be finite (plotters' tick
/// computation never ends on an infinite span).
pub(super) fn drawable((lo, hi): (f64, f64)) -> bool {
    lo.is_finite() && hi.is_finite() && (hi - lo).is_finite()
}

/// The axes, grid, lines and annotations over the x and y ranges, on x and y axes of types `X` and `Y`
/// (linear or logarithmic) whose numbers `x_axis` and `y_axis` write.
fn draw_axes<DB, X, Y>(
    area: &DrawingArea<DB, Shift>,
    figure: &Figure,
    metrics: &Metrics,
    (_, (y0, y1)): (AxisRange, AxisRange),
    (x_axis, y_axis): (AxisScale, AxisScale),
    (x_spec, y_spec): (X, Y),
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    X::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let tick_font = (FAMILY, metrics.tick_label).into_font();
    let y_label_width = y_axis_width(area, &y_axis, &tick_font, metrics);
    let mut chart = ChartBuilder::on(area)
        .caption(&figure.title, (FAMILY, metrics.title))
        .margin_top((metrics.title * 0.4) as u32)
        .margin_right((metrics.tick_label * 2.0) as u32)
        .margin_left((metrics.tick_label * 0.6) as u32)
        .x_label_area_size((metrics.tick_label * 1.5 + metrics.axis_label * 1.7) as u32)
        .y_label_area_size(y_label_width)
        .build_cartesian_2d(x_spec, y_spec)
        .map_err(|e| e.to_string())?;
    let x_format = |v: &f64| x_axis.tick(*v);
    let y_format = |v: &f64| y_axis.tick(*v);
    chart
        .configure_mesh()
        .x_desc(x_axis.label(&figure.x_quantity))
        .y_desc(y_axis.label(&figure.y_quantity))
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .x_labels(X_TICKS)
        .y_labels(Y_TICKS)
        .max_light_lines(4)
        .label_style(tick_font.clone())
        .axis_desc_style((FAMILY, metrics.axis_label))
        .bold_line_style(RGBColor(0, 0, 0).mix(0.18))
        .light_line_style(RGBColor(0, 0, 0).mix(0.06))
        .draw()
        .map_err(|e| e.to_string())?;
    for (series, colour) in figure.series.iter().zip(series_colours(figure)) {
        let style = colour.stroke_width(metrics.line_width);
        for segment in finite_segments(&series.points) {
            // Values beyond the y axis (below a logarithmic axis's floor) drawn at its end, inside the frame.
            let points = segment.iter().map(|&(x, y)| (x, y.clamp(y0, y1)));
            match series.style {
                SeriesStyle::Line => chart.draw_series(LineSeries::new(points, style)).map(|_| ()),
                SeriesStyle::LineAndPoints => {
                    let radius = (metrics.line_width * 2 + 1) as i32;
                    chart.draw_series(LineSeries::new(points.clone(), style)).map_err(|e| e.to_string())?;
                    chart.draw_series(points.map(|p| Circle::new(p, radius, colour.filled()))).map(|_| ())
                }
                SeriesStyle::Reference => {
                    let dash = (metrics.legend * 0.6) as u32;
                    chart.draw_series(DashedLineSeries::new(points, dash, dash / 2, style)).map(|_| ())
                }
            }
            .map_err(|e| e.to_string())?;
        }
    }
    draw_annotations(&mut chart, figure, metrics)
}

/// Each series' colour: the palette's in turn, black for a reference line.
pub(super) fn series_colours(figure: &Figure) -> Vec<RGBColor> {
    let mut next = 0;
    let mut colour = |style| match style {
        SeriesStyle::Reference => BLACK,
        _ => {
            next += 1;
            PALETTE[(next - 1) % PALETTE.len()]
        }
    };
    figure.series.iter().map(|s| colour(s.style)).collect()
}

/// Width of the y label area: the widest tick label and the rotated axis label beside it.
fn y_axis_width<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    axis: &AxisScale,
    font: &FontDesc,
    metrics: &Metrics,
) -> u32 {
    let widest = axis
        .sample_ticks()
        .iter()
        .map(|t| area.estimate_text_size(t, &TextStyle::from(font.clone())).map(|(w, _)| w).unwrap_or(0))
        .max()
        .unwrap_or(0);
    widest + (metrics.axis_label * 2.0) as u32 + (metrics.tick_label * 0.8) as u32
}

fn draw_annotations<DB, X, Y>(
    chart: &mut ChartContext<DB, Cartesian2d<X, Y>>,
    figure: &Figure,
    metrics: &Metrics,
) -> Result<(), String>
where
    DB: DrawingBackend,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let radius = (metrics.legend * 0.3) as i32;
    let font = (FAMILY, metrics.legend * 0.9).into_font().color(&BLACK);
    for a in &figure.annotations {
        let offset = (radius + 3, -(metrics.legend as i32) - radius);
        let marker = EmptyElement::at((a.x, a.y))
            + Circle::new((0, 0), radius, BLACK.stroke_width(metrics.line_width))
            + Text::new(a.text.clone(), offset, font.clone());
        chart.draw_series(std::iter::once(marker)).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// Runs of consecutive finite points: a NaN or infinity breaks the line instead of ending the plot.
fn finite_segments(points: &[(f64, f64)]) -> Vec<&[(f64, f64)]> {
    points.split(|(x, y)| !x.is_finite() || !y.is_finite()).filter(|s| !s.is_empty()).collect()
}

/// Smallest and largest finite value; `(0, 1)` if there is none; widened if they are equal.
fn data_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        (0.0, 1.0)
    } else if lo == hi {
        let half = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        (lo - half, hi + half)
    } else {
        (lo, hi)
    }
}

/// A range with 5 % room above and below, so lines do not run along the frame.
pub(super) fn padded((lo, hi): (f64, f64)) -> (f64, f64) {
    let room = 0.05 * (hi - lo);
    (lo - room, hi + room)
}

/// A range of positive values widened by a fifth of a decade at each end, for a logarithmic axis.
fn log_padded((lo, hi): (f64, f64)) -> (f64, f64) {
    (lo / 1.6, hi * 1.6)
}

/// The range of a logarithmic axis: the positive values, 2 to 7 decades below the largest, with
/// room above it for annotations.
fn log_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = data_range(values.filter(|v| *v > 0.0));
    let lo = lo.clamp(hi * 1e-7, hi * 1e-2);
    (lo / 1.5, hi * 4.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sine_figure(series: usize) -> Figure {
        Figure {
            title: "test".into(),
            x_quantity: ("t".into(), Some("s".into())),
            y_quantity: ("x".into(), Some("m".into())),
            series: (0..series)
                .map(|k| Series {
                    label: format!("run{k} x"),
                    points: (0..200).map(|i| (i as f64 * 0.01, (i as f64 * 0.05 + k as f64).sin())).collect(),
                    style: SeriesStyle::Line,
                })
                .collect(),
            annotations: Vec::new(),
            y_scale: Scale::Linear,
            x_scale: Scale::Linear,
            x_range: None,
            y_range: None,
        }
    }

    #[test]
    fn draws_lines_of_the_palette_colours_on_white() {
        let pixels = render_rgb(&sine_figure(2), (640, 400)).unwrap();
        assert_eq!(pixels.len(), 640 * 400 * 3);
        let count = |c: RGBColor| pixels.chunks(3).filter(|p| p == &[c.0, c.1, c.2]).count();
        assert!(count(WHITE) > 640 * 400 / 2, "mostly background");
        assert!(count(PALETTE[0]) > 200, "the first line is drawn: {} pixels", count(PALETTE[0]));
        assert!(count(PALETTE[1]) > 200, "the second line is drawn: {} pixels", count(PALETTE[1]));
    }

    /// A work-precision diagram's axes: both logarithmic, the x axis over the positive values with a fifth of a
    /// decade of room at each end; its points drawn.
    #[test]
    fn draws_on_two_logarithmic_axes() {
        let mut figure = sine_figure(1);
        figure.series[0].points = vec![(100.0, 1e-3), (1_000.0, 1e-5), (10_000.0, 1e-7)];
        figure.series[0].style = SeriesStyle::LineAndPoints;
        (figure.x_scale, figure.y_scale) = (Scale::Log, Scale::Log);
        let ((x0, x1), (y0, y1)) = axis_ranges(&figure).unwrap();
        assert_eq!((x0, x1), (100.0 / 1.6, 10_000.0 * 1.6));
        assert!(y0 > 0.0 && y0 < 1e-7 && y1 > 1e-3, "({y0}, {y1})");
        let pixels = render_rgb(&figure, (640, 400)).unwrap();
        let count = |c: RGBColor| pixels.chunks(3).filter(|p| p == &[c.0, c.1, c.2]).count();
        assert!(count(PALETTE[0]) > 200, "the line is drawn: {} pixels", count(PALETTE[0]));
    }

    #[test]
    fn rejects_unknown_extensions_and_sizes() {
        let e = ImageFormat::of(Path::new("a.jpg")).unwrap_err().to_string();
        assert!(e.contains("cannot write .jpg images; use a .png or .svg"), "{e}");
        assert_eq!(ImageFormat::of(Path::new("a.SVG")).unwrap(), ImageFormat::Svg);
        assert!(render_rgb(&sine_figure(1), (50, 400)).unwrap_err().to_string().contains("200 to 8000"));
    }

    #[test]
    fn refuses_axes_whose_span_overflows_instead_of_hanging() {
        let mut figure = sine_figure(1);
        figure.series[0].points = vec![(0.0, 1.7e308), (1.0, -1.7e308)];
        let e = render_rgb(&figure, (640, 400)).unwrap_err().to_string();
        assert_eq!(e, format!("cannot draw the y axis (x) over values from -1.7e308 to 1.7e308: {SPAN_TOO_LARGE}"));
        figure.series[0].points = vec![(-1e308, 0.0), (1e308, 1.0)];
        assert!(render_rgb(&figure, (640, 400)).unwrap_err().to_string().starts_with("cannot draw the x axis (t)"));
        // 1.5e308 with 5 % room still fits; on a log axis 4 times the largest value does not.
        figure.series[0].points = vec![(0.0, 0.0), (1.0, 1.5e308)];
        assert!(render_rgb(&figure, (640, 400)).is_ok());
        figure.y_scale = Scale::Log;
        assert!(render_rgb(&figure, (640, 400)).unwrap_err().to_string().starts_with("cannot draw the y axis (x)"));
    }

    #[test]
    fn the_axes_hold_every_annotated_point() {
        let mut figure = sine_figure(1);
        figure.y_scale = Scale::Log;
        figure.series[0].points = (0..100).map(|i| (i as f64, 10f64.powi(9 - i % 10))).collect();
        figure.annotations = vec![Annotation { x: 120.0, y: 0.1, text: "small".into() }];
        let ((x0, x1), (y0, y1)) = axis_ranges(&figure).unwrap();
        assert_eq!((x0, x1), (0.0, 120.0));
        assert!(y0 <= 0.01 && y1 >= 4e9, "{y0} to {y1}: a decade below the annotation, room above the data");
        figure.y_scale = Scale::Linear;
        figure.annotations[0].y = -5.0;
        assert!(axis_ranges(&figure).unwrap().1 .0 < -5.0);
    }

    #[test]
    fn breaks_lines_at_non_finite_values() {
        let points = [(0.0, 1.0), (1.0, f64::NAN), (2.0, 2.0), (3.0, 3.0)];
        assert_eq!(finite_segments(&points).len(), 2);
        assert_eq!(log_range([1e-12, 1.0].into_iter()).0, 1e-7 / 1.5);
        assert_eq!(log_range([0.5, 1.0].into_iter()).0, 1e-2 / 1.5);
    }
}
