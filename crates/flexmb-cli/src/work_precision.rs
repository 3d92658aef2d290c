//! `flexmb compare --tolerances`: a work-precision diagram, the global error of a model's runs against
//! their cost, for each integration method over a range of tolerances.
//!
//! Each method runs at `rtol = atol = tol` for every tolerance asked (error per unit step over the
//! model's tolerance span, the default over the run's), a reference at a tight tolerance (the Adams
//! method at 1e-12 unless told otherwise; or a result file read instead, [`Reference::File`]), and each
//! run's **global error** is measured in the norm of docs/accuracy.md:
//!
//! ```text
//! E = max over position outputs G of  max_{t, i ∈ G} |y_i(t) − r_i(t)|  /  max_{t, i ∈ G} |r_i(t)|
//! ```
//!
//! `G` runs over the `marker_position` and `node_position` outputs, `i` over their x, y, z, `t` over
//! the output times. The promise of docs/accuracy.md is `E ≤ 10 tol`, falling in proportion to `tol`:
//! the table gives `E / tol` beside the steps, rejected steps, right-hand-side evaluations,
//! factorizations and time of each run, and the diagram (SVG or PNG) `E` against the steps, one line per
//! method, both axes logarithmic. The table is also written as CSV next to the diagram. A tolerance finer
//! than a method keeps over the run (the BDF's 1e-10, generalized-α's 1e-7: `attainable_by_method`) is
//! left out for that method, and the table says so: the run would raise it to that finest one.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use flexmb::analysis::{attainable_by_method, output_columns, position_output_columns, OutputColumn, SimulationSettings};
use flexmb::integrate::{Method, ToleranceSpan};
use flexmb_files::integrator_choice::parse_method;
use flexmb_files::{ResultTable, SimulationDefaults};

use crate::compare::{load_for_comparison, methods_by_name, run_with, Run};
use crate::plot::{render, Figure, Scale, Series, SeriesStyle, DEFAULT_SIZE};
use crate::run::CliError;

/// What `flexmb compare --tolerances` was asked to do.
#[derive(Clone, Debug)]
pub struct WorkPrecisionOptions {
    /// The methods, by name (`bdf`, `adams`, `gen-alpha`).
    pub integrators: Vec<String>,
    /// The tolerances each method runs at (`rtol = atol`).
    pub tolerances: Vec<f64>,
    /// What the runs are measured against.
    pub reference: Reference,
    pub t_end: Option<f64>,
    /// Spectral radius ρ∞ of the generalized-α method.
    pub spectral_radius: f64,
    /// Directory for the diagram and the table (`MODEL_work_precision.svg`, `.csv`).
    pub out: PathBuf,
}

/// The reference `flexmb compare --tolerances` measures against unless told otherwise: the Adams method
/// at rtol = atol = 1e-12, as docs/accuracy.md's tables.
pub const DEFAULT_REFERENCE: &str = "adams:1e-12";

/// What the runs of a work-precision diagram are measured against.
#[derive(Clone, Debug, PartialEq)]
pub enum Reference {
    /// A run of the model by the method named, at rtol = atol = the tolerance.
    Run { method: String, tolerance: f64 },
    /// A result CSV with the model's position outputs' columns (`….position.x`, `.y`, `.z`; others may be
    /// there) at its output times: a run made before (`flexmb run --out DIR` of the model at a tight
    /// tolerance) or a published solution written in those columns.
    File(PathBuf),
}

/// `METHOD:TOL`, e.g. `adams:1e-12`, a reference run's method and tolerance; or a result file, `FILE.csv`.
pub fn parse_reference(text: &str) -> Result<Reference, String> {
    if text.trim().to_ascii_lowercase().ends_with(".csv") {
        return Ok(Reference::File(PathBuf::from(text.trim())));
    }
    let (method, tolerance) =
        text.split_once(':').ok_or_else(|| format!("'{text}': expected METHOD:TOL, e.g. {DEFAULT_REFERENCE}, or a result file FILE.csv"))?;
    let tolerance: f64 = tolerance.trim().parse().map_err(|_| format!("'{text}': the tolerance '{tolerance}' is not a number"))?;
    if !(tolerance > 0.0 && tolerance.is_finite()) {
        return Err(format!("'{text}': the tolerance must be positive"));
    }
    Ok(Reference::Run { method: method.trim().to_string(), tolerance })
}

/// The reference's output times and rows, in the model's output columns `columns`, read from the result
/// CSV at `path`: the position outputs' columns (`groups`, the ones the error is measured in) must be there,
/// the others may be missing (NaN: a published solution gives what it gives), and its times must be those
/// of the model's outputs (checked against the runs' own times by [`check_times`]).
fn reference_from_file(path: &Path, columns: &[OutputColumn], groups: &[[usize; 3]]) -> Result<(Vec<f64>, Vec<Vec<f64>>), CliError> {
    let failed = |e: String| CliError(format!("--reference {}: {e}", path.display()));
    let table = ResultTable::read(path).map_err(|e| failed(e.to_string()))?;
    let times = table.column("t").map_err(|e| failed(e.to_string()))?.to_vec();
    let measured = |k: usize| groups.iter().any(|g| g.contains(&k));
    let values: Vec<Option<&[f64]>> = columns
        .iter()
        .enumerate()
        .map(|(k, c)| match table.column(&c.name) {
            Ok(values) => Ok(Some(values)),
            Err(_) if !measured(k) => Ok(None),
            Err(_) => Err(failed(format!("it has no column {} of the model's position outputs", c.name))),
        })
        .collect::<Result<_, _>>()?;
    let frames = (0..table.rows()).map(|row| values.iter().map(|v| v.map_or(f64::NAN, |v| v[row])).collect()).collect();
    Ok((times, frames))
}

/// Whether the reference's output times `reference` hold the run's `run` (the same times, to rounding, as
/// far as the run went); else what differs.
fn check_times(run: &[f64], reference: &[f64]) -> Result<(), String> {
    if reference.len() < run.len() {
        return Err(format!(
            "it ends at t = {} s, before the run's last output time {} s",
            reference.last().copied().unwrap_or(f64::NAN),
            run.last().copied().unwrap_or(f64::NAN)
        ));
    }
    match run.iter().zip(reference).position(|(a, b)| (a - b).abs() > 1e-9 * a.abs().max(1.0)) {
        Some(row) => Err(format!(
            "its output time in row {} is {} s where the run's is {} s: write it with the model's output_step",
            row + 2,
            reference[row],
            run[row]
        )),
        None => Ok(()),
    }
}

/// The global error of `frames` against `reference` (rows of output values at the same output times; the
/// shorter of the two is compared) in the norm of docs/accuracy.md: over the position groups `groups`,
/// the largest of each group's largest difference over its largest reference value (a group whose
/// reference is zero throughout counts its largest difference).
pub fn global_error(frames: &[Vec<f64>], reference: &[Vec<f64>], groups: &[[usize; 3]]) -> f64 {
    groups
        .iter()
        .map(|group| {
            let scale = reference.iter().flat_map(|r| group.iter().map(|&c| r[c].abs())).fold(0.0, f64::max);
            let difference = frames
                .iter()
                .zip(reference)
                .flat_map(|(a, r)| group.iter().map(move |&c| (a[c] - r[c]).abs()))
                .fold(0.0, f64::max);
            if scale > 0.0 {
                difference / scale
            } else {
                difference
            }
        })
        .fold(0.0, f64::max)
}

/// What `method` would raise the relative tolerance of `settings` to ([`attainable_by_method`]), if it
/// would.
fn raised_to(settings: &SimulationSettings, method: &Method) -> Option<f64> {
    let (attainable, _) = attainable_by_method(&settings.tolerances, method);
    (attainable.rtol != settings.tolerances.rtol).then_some(attainable.rtol)
}

/// One method at one tolerance.
struct Point {
    method: String,
    tolerance: f64,
    error: f64,
    run: Run,
}

/// Runs the model at `path` with each method at each tolerance and the reference; writes the diagram and
/// the table into the output directory and returns the table.
pub fn work_precision(path: &Path, options: &WorkPrecisionOptions) -> Result<String, CliError> {
    let (loaded, t_end) = load_for_comparison(path, options.t_end)?;
    let model = &loaded.model;
    let d = loaded.simulation;
    if options.tolerances.is_empty() || options.tolerances.iter().any(|t| !(*t > 0.0 && t.is_finite())) {
        return Err(CliError(format!("--tolerances: expected positive numbers, e.g. 1e-3,1e-4,1e-5 (got {:?})", options.tolerances)));
    }
    let methods = methods_by_name(&options.integrators, options.spectral_radius)?;
    let columns = output_columns(model);
    let groups: Vec<[usize; 3]> = position_output_columns(model).into_iter().map(|c| [c, c + 1, c + 2]).collect();
    if groups.is_empty() {
        return Err(CliError(format!(
            "{}: the model requests no position output to measure the global error by; add a marker_position or \
             node_position [[output]]",
            path.display()
        )));
    }
    let assembly = crate::limits::assembly_settings(&d)?;
    let settings = |method: Method, tol: f64| SimulationDefaults { t_end, rtol: tol, atol: tol, method, ..d }.settings(model, assembly);
    let (reference_label, reference_times, reference_frames, reference_cost) = match &options.reference {
        Reference::Run { method: name, tolerance } => {
            let method =
                parse_method(name, options.spectral_radius).map_err(|e| CliError(format!("--reference: {e}")))?;
            let reference_settings = settings(method, *tolerance);
            if let Some(finest) = raised_to(&reference_settings, &method) {
                return Err(CliError(format!(
                    "--reference {name}:{tolerance:e}: {name} keeps {finest:e} over the run and would raise the reference's \
                     tolerance to it; take the Adams method for a reference finer than that ({DEFAULT_REFERENCE})"
                )));
            }
            let reference = run_with(model, &reference_settings, "reference");
            if let Some(f) = &reference.failure {
                return Err(CliError(format!("{}: the reference run failed: {f}", path.display())));
            }
            let cost = format!(": {} steps, {:.3} s", reference.steps, reference.cpu);
            (format!("{name} at {tolerance:e}"), reference.times, reference.frames, cost)
        }
        Reference::File(file) => {
            let (times, frames) = reference_from_file(file, &columns, &groups)?;
            (file.display().to_string(), times, frames, String::new())
        }
    };
    // A tolerance finer than a method keeps over the run is not run: the method would raise it (with a
    // warning) and the point would repeat the finest one's under another tolerance.
    let (mut points, mut left_out) = (Vec::new(), Vec::new());
    for (name, method) in &methods {
        for &tolerance in &options.tolerances {
            let asked = settings(*method, tolerance);
            if let Some(finest) = raised_to(&asked, method) {
                left_out.push(format!("{name} at {tolerance:e} (it keeps {finest:e} over the run and raises a finer one to it)"));
                continue;
            }
            let mut run = run_with(model, &asked, name);
            check_times(&run.times, &reference_times).map_err(|e| CliError(format!("--reference {reference_label}: {e}")))?;
            let error = global_error(&run.frames, &reference_frames, &groups);
            run.frames = Vec::new();
            points.push(Point { method: name.clone(), tolerance, error, run });
        }
    }
    if points.is_empty() {
        return Err(CliError(format!("--tolerances: nothing to run: {}", left_out.join("; "))));
    }
    std::fs::create_dir_all(&options.out).map_err(|e| CliError(format!("cannot create {}: {e}", options.out.display())))?;
    let stem = path.file_stem().map_or_else(|| model.name().to_string(), |s| s.to_string_lossy().into_owned());
    let diagram_path = options.out.join(format!("{stem}_work_precision.svg"));
    let table_path = options.out.join(format!("{stem}_work_precision.csv"));
    render(&diagram(model.name(), &reference_label, &points), &diagram_path, DEFAULT_SIZE)?;
    std::fs::write(&table_path, csv_table(&points)).map_err(|e| CliError(format!("cannot write {}: {e}", table_path.display())))?;

    let mut s = String::new();
    let span = match d.tolerance_span {
        ToleranceSpan::Run => "over the run (the promise of docs/accuracy.md: E within about 10 tol)".to_string(),
        ToleranceSpan::Seconds(seconds) => format!("over each {seconds} s (the model's tolerance_span)"),
        ToleranceSpan::Step => "each step the whole tolerance (the model's tolerance_span = \"step\": no promise over the run)".to_string(),
    };
    let _ = writeln!(s, "model {} ({}), t_end {t_end} s, rtol = atol = tol {span}; global error E in the norm of docs/accuracy.md", model.name(), path.display());
    let _ = writeln!(
        s,
        "{:<10} {:>7} {:>10} {:>8} {:>9} {:>9} {:>10} {:>8} {:>9} {:>8}  status",
        "method", "tol", "E", "E/tol", "steps", "rejected", "f-evals", "LU", "CPU [s]", "warnings"
    );
    for p in &points {
        let r = &p.run;
        let status = match &r.failure {
            Some(f) => format!("stopped at t = {:.6} s: {f}", r.t_reached),
            None => "completed".to_string(),
        };
        let _ = writeln!(
            s,
            "{:<10} {:>7.0e} {:>10.3e} {:>8.2} {:>9} {:>9} {:>10} {:>8} {:>9.3} {:>8}  {status}",
            p.method, p.tolerance, p.error, p.error / p.tolerance, r.steps, r.rejected, r.evaluations, r.factorizations, r.cpu, r.warnings
        );
    }
    let _ = writeln!(
        s,
        "reference: {reference_label}{reference_cost}; CPU is wall time on this machine; the warnings are the runs' own \
         (flexmb run at that tolerance prints them)"
    );
    if !left_out.is_empty() {
        let _ = writeln!(s, "not run: {}", left_out.join("; "));
    }
    let _ = writeln!(s, "written: {}, {}", diagram_path.display(), table_path.display());
    Ok(s)
}

/// The diagram: each method's completed runs, global error against steps, both axes logarithmic.
fn diagram(model: &str, reference: &str, points: &[Point]) -> Figure {
    let mut methods: Vec<&str> = Vec::new();
    for p in points {
        if !methods.contains(&p.method.as_str()) {
            methods.push(&p.method);
        }
    }
    let series = methods
        .iter()
        .map(|&m| {
            let mut line: Vec<(f64, f64)> = points
                .iter()
                .filter(|p| p.method == m && p.run.failure.is_none() && p.error > 0.0)
                .map(|p| (p.run.steps as f64, p.error))
                .collect();
            line.sort_by(|a, b| a.0.total_cmp(&b.0));
            let tolerances = points.iter().filter(|p| p.method == m).map(|p| p.tolerance);
            let (finest, loosest) = tolerances.fold((f64::INFINITY, 0.0_f64), |(lo, hi), t| (lo.min(t), hi.max(t)));
            Series { label: format!("{m}, tol {loosest:e} … {finest:e}"), points: line, style: SeriesStyle::LineAndPoints }
        })
        .collect();
    Figure {
        title: format!("{model}: global error against steps (reference {reference})"),
        x_quantity: ("steps".into(), None),
        y_quantity: ("global error E".into(), None),
        series,
        annotations: Vec::new(),
        y_scale: Scale::Log,
        x_scale: Scale::Log,
        x_range: None,
        y_range: None,
    }
}

/// The table as CSV: one row per method and tolerance.
fn csv_table(points: &[Point]) -> String {
    let mut s = String::from("method,tol,error,error_over_tol,steps,rejected,evaluations,factorizations,cpu_s,warnings,t_reached,completed\n");
    for p in points {
        let r = &p.run;
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{},{},{},{},{:e},{},{:e},{}",
            p.method,
            p.tolerance,
            p.error,
            p.error / p.tolerance,
            r.steps,
            r.rejected,
            r.evaluations,
            r.factorizations,
            r.cpu,
            r.warnings,
            r.t_reached,
            r.failure.is_none()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The norm of docs/accuracy.md: per position output, the largest difference over its largest
    /// reference value; the largest over the outputs. Velocities and other columns do not count.
    #[test]
    fn the_global_error_is_each_position_outputs_largest_difference_over_its_largest_value() {
        // Columns: a.position.x/y/z, a.velocity.x, b.position.x/y/z.
        let groups = [[0, 1, 2], [4, 5, 6]];
        // a: largest |r| 2 (its y at the second time), largest difference 1e-3 → 5e-4;
        // b: largest |r| 0.1, largest difference 1e-4 → 1e-3; the velocity's 1.0 does not count.
        let reference = vec![vec![1.0, 0.5, 0.0, 0.0, 0.1, 0.0, 0.0], vec![0.0, -2.0, 0.0, 0.0, 0.0, 0.05, 0.0]];
        let run = vec![vec![1.001, 0.5, 0.0, 1.0, 0.1, 0.0, 0.0], vec![0.0, -2.0, 0.0, 0.0, 0.0, 0.0501, -0.00005]];
        let e = global_error(&run, &reference, &groups);
        assert!((e - 1e-3).abs() < 1e-12, "{e}");
        assert_eq!(global_error(&reference, &reference, &groups), 0.0);
    }

    /// A reference file's times must hold the run's: as many, the same to rounding.
    #[test]
    fn a_reference_file_holds_the_runs_output_times() {
        assert!(check_times(&[0.0, 0.1, 0.2], &[0.0, 0.1, 0.2, 0.3]).is_ok());
        assert!(check_times(&[0.0, 0.1, 0.2], &[0.0, 0.1 + 1e-12, 0.2]).is_ok());
        assert!(check_times(&[0.0, 0.1, 0.2], &[0.0, 0.1]).unwrap_err().contains("ends at t = 0.1 s"));
        let e = check_times(&[0.0, 0.1, 0.2], &[0.0, 0.2, 0.4]).unwrap_err();
        assert!(e.contains("row 3 is 0.2 s where the run's is 0.1 s"), "{e}");
    }

    #[test]
    fn a_reference_is_a_method_and_a_tolerance_or_a_file() {
        let run = |method: &str, tolerance| Ok(Reference::Run { method: method.to_string(), tolerance });
        assert_eq!(parse_reference("adams:1e-12"), run("adams", 1e-12));
        assert_eq!(parse_reference(" bdf : 1e-10"), run("bdf", 1e-10));
        assert_eq!(parse_reference("ref/pendulum.CSV"), Ok(Reference::File(PathBuf::from("ref/pendulum.CSV"))));
        assert!(parse_reference("adams").unwrap_err().contains("METHOD:TOL"));
        assert!(parse_reference("adams:x").unwrap_err().contains("not a number"));
        assert!(parse_reference("adams:-1").unwrap_err().contains("positive"));
    }
}
