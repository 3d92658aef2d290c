//! `flexmb plot` and `flexmb run --plot`: line plots of result columns against time (or another
//! column), from one or several result files, as PNG or SVG; and the Campbell diagram of an
//! eigen-analysis swept over a parameter ([`campbell`]).
//!
//! Units come from the run's JSON summary beside each CSV (see [`ResultTable`]); the legend names
//! each line by its column, and by its file's stem when several files are overlaid. Columns of
//! different units may share a plot: the y label then says "mixed units" and each legend entry
//! carries its own unit.

mod axis;
pub mod campbell;
pub mod figure;
mod font;
mod legend;
mod run_outputs;

use std::path::{Path, PathBuf};

pub use flexmb_files::ResultTable;
pub use figure::{axis_ranges, render, render_rgb, Annotation, Figure, ImageFormat, Series, SeriesStyle, Scale};
pub use run_outputs::plot_run_outputs;

use crate::run::CliError;

/// Image size when none is asked for, in pixels.
pub const DEFAULT_SIZE: (u32, u32) = (1200, 750);

/// What `flexmb plot` draws.
#[derive(Clone, Debug)]
pub struct PlotOptions {
    /// Result CSVs, overlaid.
    pub files: Vec<PathBuf>,
    /// Columns on the y axis.
    pub y: Vec<String>,
    /// Column on the x axis (`t` by default).
    pub x: String,
    /// Image to write (.png or .svg); default `<stem>_<columns>.png` next to the first CSV.
    pub out: Option<PathBuf>,
    pub title: Option<String>,
    pub size: (u32, u32),
    /// The stretch of time drawn.
    pub window: TimeWindow,
}

/// The stretch of time a plot draws: the rows with `from ≤ t ≤ to`, either end open (`flexmb plot
/// --from T --to T`). It selects rows by time whatever column is along the x axis; with `t` along it,
/// the axis spans the window (where the files have rows).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TimeWindow {
    pub from: Option<f64>,
    pub to: Option<f64>,
}

impl TimeWindow {
    /// An error unless the ends are finite and `from` is before `to`.
    fn check(&self) -> Result<(), CliError> {
        for (option, end) in [("--from", self.from), ("--to", self.to)] {
            if let Some(t) = end.filter(|t| !t.is_finite()) {
                return Err(CliError(format!("{option} {t}: the time window needs finite times")));
            }
        }
        match (self.from, self.to) {
            (Some(from), Some(to)) if from >= to => {
                Err(CliError(format!("--from {from} s is not before --to {to} s: the time window is empty")))
            }
            _ => Ok(()),
        }
    }

    /// The rows of `table` in the window; an error if there is none.
    fn rows(&self, table: &ResultTable) -> Result<Vec<usize>, CliError> {
        let t = table.finite_column("t", "a plot")?;
        let inside = |t: f64| self.from.is_none_or(|from| t >= from) && self.to.is_none_or(|to| t <= to);
        let rows: Vec<usize> = (0..t.len()).filter(|&k| inside(t[k])).collect();
        if rows.is_empty() && !t.is_empty() {
            let end = |e: Option<f64>, open: &str| e.map_or(open.to_string(), |v| format!("{v}"));
            return Err(CliError(format!(
                "{}: no row has {} ≤ t ≤ {} s; its times run from {} to {} s",
                table.path().display(),
                end(self.from, "−∞"),
                end(self.to, "∞"),
                t[0],
                t[t.len() - 1]
            )));
        }
        Ok(rows)
    }

    /// The x range of a plot against `t` of files with the times `times`: the window, cut to where they
    /// have rows.
    fn axis_range(&self, times: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
        if *self == Self::default() {
            return None;
        }
        let (lo, hi) = times.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), t| (lo.min(t), hi.max(t)));
        let range = (self.from.map_or(lo, |from| from.max(lo)), self.to.map_or(hi, |to| to.min(hi)));
        (range.0 < range.1).then_some(range)
    }
}

/// Draws the plot `options` ask for and returns the image's path.
pub fn run_plot(options: &PlotOptions) -> Result<PathBuf, CliError> {
    let (Some(first), false) = (options.files.first(), options.y.is_empty()) else {
        return Err(CliError("plot needs at least one result file and one --y column".into()));
    };
    let out = options.out.clone().unwrap_or_else(|| default_image_path(first, &options.y));
    ImageFormat::of(&out)?;
    let tables = options.files.iter().map(|f| ResultTable::read(f)).collect::<Result<Vec<_>, _>>()?;
    let mut figure = compose(&tables, &options.x, &options.y, options.window)?;
    if let Some(title) = &options.title {
        figure.title = title.clone();
    }
    render(&figure, &out, options.size)?;
    Ok(out)
}

/// `<dir of csv>/<stem>_<column>_….png`.
pub fn default_image_path(csv: &Path, columns: &[String]) -> PathBuf {
    let stem = csv.file_stem().and_then(|s| s.to_str()).unwrap_or("plot");
    let name: String = std::iter::once(stem)
        .chain(columns.iter().map(String::as_str))
        .collect::<Vec<_>>()
        .join("_")
        .chars()
        .map(|c| if c.is_alphanumeric() || "._-".contains(c) { c } else { '_' })
        .collect();
    csv.with_file_name(format!("{name}.png"))
}

/// The figure of columns `y` against `x` of every table over the time `window`: one line per table
/// and column. Every value drawn must be finite, and the values along each axis must span no more than
/// an axis can hold.
pub fn compose(tables: &[ResultTable], x: &str, y: &[String], window: TimeWindow) -> Result<Figure, CliError> {
    window.check()?;
    let units: Vec<Option<String>> = y.iter().map(|c| column_unit(tables, c)).collect();
    let mixed = units.iter().any(|u| *u != units[0]);
    let names = run_names(tables);
    let mut series = Vec::new();
    let mut times = Vec::new();
    for (table, run) in tables.iter().zip(&names) {
        let rows = window.rows(table)?;
        let t = table.finite_column("t", "a plot")?;
        times.extend_from_slice(t);
        let xs: Vec<f64> = table.finite_column(x, "a plot").map(|xs| rows.iter().map(|&k| xs[k]).collect())?;
        for (column, unit) in y.iter().zip(&units) {
            let ys: Vec<f64> =
                table.finite_column(column, "a plot").map(|ys| rows.iter().map(|&k| ys[k]).collect())?;
            let mut label = if tables.len() > 1 { format!("{run}: {column}") } else { column.clone() };
            if let (true, Some(u)) = (mixed, unit) {
                label = format!("{label} [{u}]");
            }
            series.push(Series { label, points: xs.iter().copied().zip(ys.iter().copied()).collect(), style: SeriesStyle::Line });
        }
    }
    check_span(tables, std::slice::from_ref(&x.to_string()), "x", |range| range)?;
    check_span(tables, y, "y", figure::padded)?;
    let y_quantity = if mixed {
        let listed: Vec<&str> = units.iter().map(|u| u.as_deref().unwrap_or("none")).collect();
        (format!("value, mixed units: {}", listed.join(", ")), None)
    } else {
        (quantity_name(y), units[0].clone())
    };
    Ok(Figure {
        title: title(y, &names),
        x_quantity: (x.to_string(), column_unit(tables, x)),
        y_quantity,
        series,
        annotations: Vec::new(),
        y_scale: Scale::Linear,
        x_scale: Scale::Linear,
        x_range: if x == "t" { window.axis_range(times.into_iter()) } else { None },
        y_range: None,
    })
}

/// An error, naming where the smallest and largest values are, if the `axis` over `columns` of every
/// table cannot be drawn: if its range (as `axis_range` makes it of the values') overflows.
fn check_span(
    tables: &[ResultTable],
    columns: &[String],
    axis: &str,
    axis_range: fn((f64, f64)) -> (f64, f64),
) -> Result<(), CliError> {
    // (value, table, column, row) of the smallest and the largest value.
    type Place<'a> = (f64, &'a ResultTable, &'a str, usize);
    let (mut lo, mut hi): (Option<Place>, Option<Place>) = (None, None);
    for table in tables {
        for column in columns {
            for (row, &v) in table.column(column)?.iter().enumerate() {
                if lo.is_none_or(|(l, ..)| v < l) {
                    lo = Some((v, table, column, row));
                }
                if hi.is_none_or(|(h, ..)| v > h) {
                    hi = Some((v, table, column, row));
                }
            }
        }
    }
    let (Some(lo), Some(hi)) = (lo, hi) else { return Ok(()) };
    if figure::drawable(axis_range((lo.0, hi.0))) {
        return Ok(());
    }
    let place = |(v, table, column, row): Place| format!("{v:e} (column `{column}`, {})", table.location(row));
    Err(CliError(format!(
        "cannot plot: the values along the {axis} axis run from {} to {}; {}",
        place(lo),
        place(hi),
        figure::SPAN_TOO_LARGE
    )))
}

/// A column's unit in the first table that knows it.
fn column_unit(tables: &[ResultTable], column: &str) -> Option<String> {
    tables.iter().find_map(|t| t.unit(column)).map(str::to_string)
}

/// What the y axis shows: the column, the columns if they are few and short, else "value".
fn quantity_name(columns: &[String]) -> String {
    let joined = columns.join(", ");
    if columns.len() == 1 || joined.chars().count() <= 40 {
        joined
    } else {
        "value".to_string()
    }
}

/// Each table's name in legends: its stem, or `dir/stem` when two files share a stem.
fn run_names(tables: &[ResultTable]) -> Vec<String> {
    let stems: Vec<&str> = tables.iter().map(ResultTable::stem).collect();
    tables
        .iter()
        .map(|t| {
            let shared = stems.iter().filter(|s| **s == t.stem()).count() > 1;
            let parent = t.path().parent().and_then(|p| p.file_name()).and_then(|p| p.to_str());
            match (shared, parent) {
                (true, Some(dir)) => format!("{dir}/{}", t.stem()),
                _ => t.stem().to_string(),
            }
        })
        .collect()
}

fn title(columns: &[String], runs: &[String]) -> String {
    let what = columns.join(", ");
    let from = runs.join(", ");
    if from.chars().count() <= 60 {
        format!("{what} — {from}")
    } else {
        format!("{what} — {} result files", runs.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(path: &str, columns: &[(&str, Option<&str>)]) -> ResultTable {
        let columns = columns
            .iter()
            .map(|(name, unit)| (name.to_string(), unit.map(str::to_string), vec![0.0, 1.0, 2.0]))
            .collect();
        ResultTable::from_columns(Path::new(path), columns)
    }

    #[test]
    fn overlays_name_file_and_column_and_carry_units() {
        let a = table("out/door_4N.csv", &[("t", Some("s")), ("latch.y", Some("m"))]);
        let b = table("out/door_8N.csv", &[("t", Some("s")), ("latch.y", Some("m"))]);
        let figure = compose(&[a, b], "t", &["latch.y".into()], TimeWindow::default()).unwrap();
        let labels: Vec<&str> = figure.series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["door_4N: latch.y", "door_8N: latch.y"]);
        assert_eq!(figure.x_quantity, ("t".into(), Some("s".into())));
        assert_eq!(figure.y_quantity, ("latch.y".into(), Some("m".into())));
        assert_eq!(figure.title, "latch.y — door_4N, door_8N");
    }

    #[test]
    fn mixed_units_are_said_in_the_label_and_legend() {
        let a = table("out/p.csv", &[("t", Some("s")), ("x", Some("m")), ("angle", Some("rad"))]);
        let figure = compose(&[a], "t", &["x".into(), "angle".into()], TimeWindow::default()).unwrap();
        assert_eq!(figure.y_quantity, ("value, mixed units: m, rad".into(), None));
        assert_eq!(figure.series[1].label, "angle [rad]");
    }

    #[test]
    fn non_finite_values_and_overflowing_spans_are_errors_that_say_where() {
        let t = ("t".to_string(), None, vec![0.0, 1.0, 2.0]);
        let x = |values: Vec<f64>| ("x".to_string(), None, values);
        let a = ResultTable::from_columns(Path::new("out/a.csv"), vec![t.clone(), x(vec![0.0, f64::INFINITY, 1.0])]);
        let e = compose(&[a], "t", &["x".into()], TimeWindow::default()).unwrap_err().to_string();
        assert_eq!(e, "out/a.csv:3: column `x` holds inf; a plot needs finite values");
        let b = ResultTable::from_columns(Path::new("out/b.csv"), vec![t.clone(), x(vec![1.7e308, 0.0, -1.7e308])]);
        let e = compose(&[b], "t", &["x".into()], TimeWindow::default()).unwrap_err().to_string();
        assert!(
            e.starts_with(
                "cannot plot: the values along the y axis run from -1.7e308 (column `x`, out/b.csv:4) to 1.7e308 \
                 (column `x`, out/b.csv:2); with its margins"
            ),
            "{e}"
        );
        let c = ResultTable::from_columns(Path::new("out/c.csv"), vec![t, x(vec![1.5e308, 0.0, -1.0])]);
        assert!(compose(&[c], "x", &["t".into()], TimeWindow::default()).is_ok(), "the x axis has no margins");
    }

    #[test]
    fn a_time_window_is_the_range_of_the_time_axis_and_selects_rows_for_any_x() {
        let t: Vec<f64> = (0..=500).map(|k| k as f64 * 0.01).collect();
        let x: Vec<f64> = t.iter().map(|t| t * t).collect();
        let a = ResultTable::from_columns(
            Path::new("out/a.csv"),
            vec![("t".into(), Some("s".into()), t.clone()), ("x".into(), None, x)],
        );
        let b = ResultTable::from_columns(Path::new("out/b.csv"), vec![("t".into(), None, t[..201].to_vec())]);
        let window = TimeWindow { from: Some(1.005), to: Some(2.5) };
        let figure = compose(std::slice::from_ref(&a), "t", &["x".into()], window).unwrap();
        let (x_range, _) = axis_ranges(&figure).unwrap();
        assert_eq!(x_range, (1.005, 2.5));
        let drawn: Vec<f64> = figure.series[0].points.iter().map(|p| p.0).collect();
        assert_eq!((drawn.len(), drawn[0], drawn[drawn.len() - 1]), (150, 1.01, 2.5));
        // Cut to the rows there are; with another column along x the window still selects by time.
        let open = TimeWindow { from: Some(3.0), to: None };
        assert_eq!(axis_ranges(&compose(std::slice::from_ref(&a), "t", &["x".into()], open).unwrap()).unwrap().0, (3.0, 5.0));
        let figure = compose(std::slice::from_ref(&a), "x", &["t".into()], window).unwrap();
        let (x0, x1) = axis_ranges(&figure).unwrap().0;
        assert!((x0 - 1.01 * 1.01).abs() < 1e-12 && (x1 - 6.25).abs() < 1e-12, "{x0} to {x1}");

        let e = compose(std::slice::from_ref(&a), "t", &["x".into()], TimeWindow { from: Some(2.0), to: Some(1.0) }).unwrap_err();
        assert_eq!(e.to_string(), "--from 2 s is not before --to 1 s: the time window is empty");
        let e = compose(&[a, b], "t", &["t".into()], TimeWindow { from: Some(2.5), to: Some(3.0) }).unwrap_err();
        assert_eq!(e.to_string(), "out/b.csv: no row has 2.5 ≤ t ≤ 3 s; its times run from 0 to 2 s");
    }

    #[test]
    fn files_with_one_stem_are_told_apart_by_directory() {
        let a = table("runs/a/door.csv", &[("t", None), ("x", None)]);
        let b = table("runs/b/door.csv", &[("t", None), ("x", None)]);
        assert_eq!(run_names(&[a, b]), ["a/door", "b/door"]);
    }

    #[test]
    fn default_image_sits_next_to_the_first_file() {
        let path = default_image_path(Path::new("out/pendulum.csv"), &["bob.position.y".into()]);
        assert_eq!(path, Path::new("out/pendulum_bob.position.y.png"));
    }
}
