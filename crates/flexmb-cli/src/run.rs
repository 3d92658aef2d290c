//! `flexmb run`: simulate a model file and write its results.

use std::path::{Path, PathBuf};

use flexmb::integrate::{GeneralizedAlphaConfig, Method, ToleranceSpan};
use flexmb_files::integrator_choice::parse_method;
use flexmb_files::model_file::load_model_with;
use flexmb_files::output_limits::check_output_rows;
use flexmb_files::results::{summary_text, ParaViewSeries};
use flexmb_files::vtk::SeriesTimes;
use flexmb_files::{record_model_run, RecordedRun, ResultFileError, Restart, RunOutputs};
use indicatif::{ProgressBar, ProgressStyle};

use crate::check::{check_model, describe, describe_flexible_bodies};
use crate::interrupt::{Signal, StopSignal};

/// Command-line overrides of the model file's `[simulation]` defaults.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub t_end: Option<f64>,
    pub output_step: Option<f64>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    /// The span of simulated time whose steps together may make an error of the tolerance
    /// (`--tolerance-span`: seconds, `run` or `step`), overriding the model file's `tolerance_span`.
    pub tolerance_span: Option<String>,
    /// Integrator by name (`bdf`, …), overriding the model file's.
    pub integrator: Option<String>,
    /// Spectral radius ρ∞ of the generalized-α method.
    pub spectral_radius: Option<f64>,
    /// Largest step (`--max-step`, s), overriding the model file's `max_step`.
    pub max_step: Option<f64>,
    /// The generalized-α method's fixed step (`--fixed-step`, s), overriding the model file's `fixed_step`.
    pub fixed_step: Option<f64>,
    /// Run the divergence check (`--divergence-check`), whatever the model file's `divergence_check`.
    pub divergence_check: bool,
    /// Estimate the global error (`--global-error-estimate`), whatever the model file's `global_error_estimate`.
    pub global_error_estimate: bool,
    /// Global error control (`--global-error-control`), whatever the model file's `global_error_control`.
    pub global_error_control: bool,
    pub out_dir: PathBuf,
    pub quiet: bool,
    /// Directory for a ParaView time series of the run (`--vtk`); none if not given.
    pub vtk_dir: Option<PathBuf>,
    /// Interval between its frames (`--vtk-step`), overriding the model file's `vtk_step`.
    pub vtk_step: Option<f64>,
    /// Most output rows allowed (`--max-output-rows`), overriding the model file's `max_output_rows`.
    pub max_output_rows: Option<u64>,
    /// Most ParaView frames allowed (`--max-vtk-frames`), overriding the model file's `max_vtk_frames`.
    pub max_vtk_frames: Option<u64>,
    /// Where to save the simulation's checkpoint at the end or at an interruption (`--save-state`).
    pub save_state: Option<PathBuf>,
    /// A checkpoint file to continue from (`--resume`).
    pub resume: Option<PathBuf>,
    /// Pause at the first step at or after this time (`--pause-at`), as an interruption.
    pub pause_at: Option<f64>,
    /// Values replacing those of the model file's `[parameters]` (`--parameter NAME=VALUE`).
    pub parameters: Vec<(String, f64)>,
    /// Catch SIGINT and SIGTERM once the simulation starts, and end the run there with its files
    /// complete (the program does; tests that call [`run_model`] need not).
    pub catch_signals: bool,
}

/// Where a run's files went, and the signal that stopped it early, if one did.
pub struct RunFiles {
    pub csv: PathBuf,
    pub summary: PathBuf,
    pub interrupted: Option<Signal>,
}

/// A failed command, with the message to print.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct CliError(pub String);

impl From<ResultFileError> for CliError {
    fn from(e: ResultFileError) -> Self {
        CliError(e.0)
    }
}

fn positive(name: &str, x: f64) -> Result<f64, CliError> {
    if x > 0.0 && x.is_finite() {
        Ok(x)
    } else {
        Err(CliError(format!("{name} must be a positive number, got {x}")))
    }
}

/// The span of `--tolerance-span`: `run`, `step` or a positive number of seconds.
fn tolerance_span(text: &str) -> Result<ToleranceSpan, CliError> {
    match text.trim() {
        "run" => Ok(ToleranceSpan::Run),
        "step" => Ok(ToleranceSpan::Step),
        seconds => match seconds.parse::<f64>() {
            Ok(span) => Ok(ToleranceSpan::Seconds(positive("--tolerance-span", span)?)),
            Err(_) => Err(CliError(format!("--tolerance-span must be `run`, `step` or a positive number of seconds, got `{text}`"))),
        },
    }
}

/// The method of `--integrator` and `--spectral-radius` over the model file's `method`. The spectral radius
/// is the generalized-α method's: alone it selects that method (with the model file's other settings of it,
/// if it is the file's method); beside another `--integrator` it is an error, not silently ignored. Without
/// `--spectral-radius`, `--integrator gen-alpha` keeps the model file's radius if the file chose the
/// method, else 0.9.
fn chosen_method(method: Method, integrator: Option<&str>, spectral_radius: Option<f64>) -> Result<Method, CliError> {
    let file_radius = match method {
        Method::GeneralizedAlpha(c) => Some(c.spectral_radius),
        _ => None,
    };
    match (integrator, spectral_radius) {
        (Some(name), Some(_)) if name != "gen-alpha" => Err(CliError(format!(
            "--spectral-radius is a setting of the generalized-α method, which --integrator {name} is not: give --integrator gen-alpha, or leave --spectral-radius out"
        ))),
        (Some(name), rho) => {
            parse_method(name, rho.or(file_radius).unwrap_or(GeneralizedAlphaConfig::DEFAULT_SPECTRAL_RADIUS)).map_err(|e| CliError(format!("--integrator: {e}")))
        }
        (None, Some(rho)) => {
            // Checks the range.
            parse_method("gen-alpha", rho).map_err(|e| CliError(format!("--spectral-radius: {e}")))?;
            let config = match method {
                Method::GeneralizedAlpha(c) => c,
                _ => GeneralizedAlphaConfig::default(),
            };
            Ok(Method::GeneralizedAlpha(GeneralizedAlphaConfig { spectral_radius: rho, ..config }))
        }
        (None, None) => Ok(method),
    }
}

/// Runs the model at `path`; prints the check and the end-of-run summary unless quiet. The library
/// calls, in order: [`load_model_with`], [`SimulationDefaults::settings`](flexmb_files::SimulationDefaults::settings),
/// [`check_model`] (the engine's assembly and velocity analysis), [`record_model_run`].
pub fn run_model(path: &Path, options: &RunOptions) -> Result<RunFiles, CliError> {
    let loaded = load_model_with(path, &crate::parameters::load_options_with(&options.parameters)).map_err(|e| CliError(e.to_string()))?;
    let model = &loaded.model;
    let mut d = loaded.simulation;
    d.t_end = positive("--t-end", options.t_end.unwrap_or(d.t_end))?;
    d.output_step = positive("--output-step", options.output_step.unwrap_or(d.output_step))?;
    d.rtol = positive("--rtol", options.rtol.unwrap_or(d.rtol))?;
    d.atol = positive("--atol", options.atol.unwrap_or(d.atol))?;
    if let Some(span) = &options.tolerance_span {
        d.tolerance_span = tolerance_span(span)?;
    }
    d.divergence_check |= options.divergence_check;
    d.global_error_estimate |= options.global_error_estimate;
    d.global_error_control |= options.global_error_control;
    let (t_end, output_step) = (d.t_end, d.output_step);
    let max_rows = options.max_output_rows.unwrap_or(d.max_output_rows);
    check_output_rows(t_end, output_step, max_rows, true).map_err(|e| CliError(format!("{}: {e}", path.display())))?;
    d.method = chosen_method(d.method, options.integrator.as_deref(), options.spectral_radius)?;
    if let Some(h) = options.max_step {
        d.max_step = Some(positive("--max-step", h)?);
    }
    if let Some(h) = options.fixed_step {
        d.fixed_step = Some(positive("--fixed-step", h)?);
    }
    d.check_fixed_step().map_err(|e| CliError(format!("{}: {e}", path.display())))?;

    if !options.quiet {
        print!("{}", describe_flexible_bodies(&loaded));
    }
    let assembly = crate::limits::assembly_settings(&d)?;
    let check = check_model(model, assembly).map_err(|e| CliError(format!("{}: {e}", path.display())))?;
    if !options.quiet {
        print!("{}", describe(model, &check));
    }

    std::fs::create_dir_all(&options.out_dir)
        .map_err(|e| CliError(format!("cannot create output directory {}: {e}", options.out_dir.display())))?;
    let stem = path.file_stem().and_then(|s| s.to_str()).unwrap_or("model");
    let mut outputs = RunOutputs::in_directory(&options.out_dir, stem);
    outputs.paraview = options.vtk_dir.as_ref().map(|dir| ParaViewSeries {
        dir: dir.clone(),
        name: stem.to_string(),
        times: SeriesTimes { step: options.vtk_step.or(d.vtk_step), output_step, t_end },
        max_frames: options.max_vtk_frames.unwrap_or(d.max_vtk_frames),
    });

    let settings = d.settings(model, assembly);
    let bar = if options.quiet { ProgressBar::hidden() } else { ProgressBar::new(1000) };
    bar.set_style(
        ProgressStyle::with_template("{bar:40} t = {msg} s  [{elapsed_precise}]").unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let file_name = path.display().to_string();
    let stop = options
        .catch_signals
        .then(StopSignal::catch)
        .transpose()
        .map_err(|e| CliError(format!("cannot catch SIGINT and SIGTERM: {e}")))?;
    let received = || stop.as_ref().and_then(StopSignal::received);
    // Formatting the time costs more than writing the row: only for a bar that is drawn.
    let drawn = !bar.is_hidden();
    let observe = &mut |frame: &flexmb::analysis::OutputFrame| {
        if drawn {
            bar.set_position((frame.t / t_end * 1000.0) as u64);
            bar.set_message(format!("{:.4}", frame.t));
        }
    };
    let pause_at = options.pause_at.map(|t| positive("--pause-at", t)).transpose()?;
    let restart = Restart { resume: options.resume.as_deref(), save_state: options.save_state.as_deref(), pause_at };
    let run = record_model_run(&loaded, &settings, &file_name, &outputs, restart, observe, &|| received().map(|s| s.name().to_string()));
    bar.finish_and_clear();
    let RecordedRun { report, error, rows, paraview, hot_spots } = run?;
    let interrupted = report.interrupted.as_ref().and(received());
    let RunOutputs { csv: csv_path, summary: summary_path, .. } = outputs;
    if !options.quiet {
        match (&error, &report.interrupted) {
            (Some(_), _) => println!("run stopped early:"),
            (None, Some(i)) => println!("run interrupted by {} at t = {:.6} s:", i.reason, i.t),
            (None, None) => println!("run completed:"),
        }
        println!("{}", summary_text(&report));
        print!("{}", flexmb_files::body_stress::hot_spot_text(&hot_spots));
        println!("results: {} ({rows} rows), {}", csv_path.display(), summary_path.display());
        if let (Some(file), None) = (&options.save_state, &error) {
            println!("state saved: {}", file.display());
        }
        if let Some(s) = &paraview {
            println!("ParaView: {} ({} frames of {} blocks)", s.pvd.display(), s.frames, s.blocks);
        }
    }
    match error {
        None => Ok(RunFiles { csv: csv_path, summary: summary_path, interrupted }),
        Some(e) => Err(CliError(format!(
            "{}: simulation failed: {e}\nthe {} output rows computed before the failure are in {}",
            path.display(),
            rows,
            csv_path.display()
        ))),
    }
}
