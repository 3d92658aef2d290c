//! `flexmb compare`: one model run with several integrators, and a table with the seed's columns
//! (T_end, CPU time, RMS step size) plus steps, rejected steps, right-hand-side evaluations and the
//! error against a tight-tolerance reference run. With `--tolerances` the command draws a work-precision
//! diagram instead ([`crate::work_precision`]).

use std::fmt::Write as _;
use std::path::Path;

use flexmb::analysis::{output_columns, simulate, OutputColumn, SimulationSettings};
use flexmb::integrate::Method;

use flexmb_files::integrator_choice::parse_method;
use flexmb_files::model_file::{load_model_with, LoadedModel};
use flexmb_files::SimulationDefaults;
use crate::run::CliError;

/// What `flexmb compare` was asked to do.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// The methods to compare, by name (`bdf`, `adams`, `gen-alpha`).
    pub integrators: Vec<String>,
    pub t_end: Option<f64>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    /// Spectral radius ρ∞ of the generalized-α method.
    pub spectral_radius: f64,
}

/// One run's outcome.
pub(crate) struct Run {
    pub(crate) name: String,
    pub(crate) t_reached: f64,
    pub(crate) cpu: f64,
    pub(crate) rms_step: f64,
    pub(crate) steps: usize,
    pub(crate) rejected: usize,
    pub(crate) evaluations: usize,
    pub(crate) factorizations: usize,
    /// The warnings the run reported.
    pub(crate) warnings: usize,
    /// The output times and the output rows, one per output time.
    pub(crate) times: Vec<f64>,
    pub(crate) frames: Vec<Vec<f64>>,
    pub(crate) failure: Option<String>,
}

/// Runs the model with `settings`, keeping every output row.
pub(crate) fn run_with(model: &flexmb::Model, settings: &SimulationSettings, name: &str) -> Run {
    let (mut times, mut frames) = (Vec::new(), Vec::new());
    let result = simulate(model, settings, &mut |f| {
        times.push(f.t);
        frames.push(f.values.to_vec());
    });
    let (report, failure) = match result {
        Ok(r) => (r, None),
        Err(e) => ((*e.report).clone(), Some(e.to_string())),
    };
    Run {
        name: name.to_string(),
        t_reached: report.t_reached,
        cpu: report.wall_time,
        rms_step: report.stats.rms_step(),
        steps: report.stats.steps,
        rejected: report.stats.rejected_steps(),
        evaluations: report.stats.residual_evaluations,
        factorizations: report.stats.factorizations,
        warnings: report.warnings.len(),
        times,
        frames,
        failure,
    }
}

/// Largest difference from the reference over the common output times among the position outputs
/// (columns in m), with the column it occurs in.
fn error_against(run: &Run, reference: &Run, columns: &[OutputColumn]) -> (f64, String) {
    let mut worst = (0.0_f64, String::from("-"));
    for (c, column) in columns.iter().enumerate().filter(|(_, col)| col.unit == "m") {
        for (a, b) in run.frames.iter().zip(&reference.frames) {
            let e = (a[c] - b[c]).abs();
            if e > worst.0 {
                worst = (e, column.name.clone());
            }
        }
    }
    worst
}

/// The model at `path` and the end time of its comparison runs (`t_end`, else the file's), its output
/// rows checked against the file's limit.
pub(crate) fn load_for_comparison(path: &Path, t_end: Option<f64>) -> Result<(LoadedModel, f64), CliError> {
    let loaded = load_model_with(path, &crate::limits::load_options()).map_err(|e| CliError(e.to_string()))?;
    let d = &loaded.simulation;
    let t_end = t_end.unwrap_or(d.t_end);
    flexmb_files::output_limits::check_output_rows(t_end, d.output_step, d.max_output_rows, false)
        .map_err(|e| CliError(format!("{}: {e}", path.display())))?;
    Ok((loaded, t_end))
}

/// The methods named in `--integrators`, each with its name.
pub(crate) fn methods_by_name(names: &[String], spectral_radius: f64) -> Result<Vec<(String, Method)>, CliError> {
    names
        .iter()
        .map(|n| parse_method(n, spectral_radius).map(|m| (n.clone(), m)).map_err(|e| CliError(format!("--integrators: {e}"))))
        .collect()
}

/// Runs the model at `path` with each integrator and a reference; returns the table.
pub fn compare_model(path: &Path, options: &CompareOptions) -> Result<String, CliError> {
    let (loaded, t_end) = load_for_comparison(path, options.t_end)?;
    let model = &loaded.model;
    let d = loaded.simulation;
    let (rtol, atol) = (options.rtol.unwrap_or(d.rtol), options.atol.unwrap_or(d.atol));
    let methods = methods_by_name(&options.integrators, options.spectral_radius)?;
    let columns = output_columns(model);
    if !columns.iter().any(|c| c.unit == "m") {
        return Err(CliError(format!(
            "{}: the model requests no position output to compare; add a marker_position or node_position [[output]]",
            path.display()
        )));
    }
    let assembly = crate::limits::assembly_settings(&d)?;
    let settings = |method: Method, rtol: f64, atol: f64| SimulationDefaults { t_end, rtol, atol, method, ..d }.settings(model, assembly);
    // The reference: the BDF at a thousandth of the tolerances and orders up to 5 (its steps are then
    // small enough to resolve every retained mode, so the high orders are accurate and stable).
    let reference_tolerance = (rtol * 1e-3).max(1e-11);
    let mut reference_settings = settings(Method::default(), reference_tolerance, (atol * 1e-3).max(1e-11));
    if let Method::Bdf(config) = &mut reference_settings.method {
        config.max_order = 5;
    }
    let reference = run_with(model, &reference_settings, "reference");
    if let Some(f) = &reference.failure {
        return Err(CliError(format!("{}: the reference run failed: {f}", path.display())));
    }
    let mut s = String::new();
    let _ = writeln!(s, "model {} ({}), t_end {t_end} s, rtol {rtol:.0e}, atol {atol:.0e}", model.name(), path.display());
    let _ = writeln!(
        s,
        "{:<10} {:>9} {:>9} {:>12} {:>8} {:>9} {:>9} {:>11}  (largest position difference from the reference, in)",
        "method", "T_end [s]", "CPU [s]", "RMS step [s]", "steps", "rejected", "f-evals", "error [m]"
    );
    for (name, method) in methods {
        let run = run_with(model, &settings(method, rtol, atol), &name);
        let (error, column) = error_against(&run, &reference, &columns);
        let _ = writeln!(
            s,
            "{:<10} {:>9.4} {:>9.4} {:>12.3e} {:>8} {:>9} {:>9} {:>11.2e}  {}",
            run.name, run.t_reached, run.cpu, run.rms_step, run.steps, run.rejected, run.evaluations, error, column
        );
        if let Some(f) = &run.failure {
            let _ = writeln!(s, "  {name} stopped: {f}");
        }
    }
    let _ = writeln!(
        s,
        "reference: bdf (orders up to 5) at rtol {reference_tolerance:.0e}: {} steps, {:.4} s; CPU is wall time on this machine",
        reference.steps, reference.cpu
    );
    Ok(s)
}
