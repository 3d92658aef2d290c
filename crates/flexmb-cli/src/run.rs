//! `flexmb run`: simulate a model file and write its results.

use std::path::{Path, PathBuf};

use flexmb::analysis::SimulationSettings;
use indicatif::{ProgressBar, ProgressStyle};

use crate::check::{check_model, describe, describe_flexible_bodies};
use crate::interrupt::{Signal, StopSignal};
use crate::model_file::load_model;
use crate::output_limits::check_output_rows;
use crate::results::{record_run, summary_text, RecordedRun};
use crate::vtk::{RunSeries, SeriesTimes};

/// Command-line overrides of the model file's `[simulation]` defaults.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub t_end: Option<f64>,
    pub output_step: Option<f64>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    /// Integrator by name (`bdf`, …), overriding the model file's.
    pub integrator: Option<String>,
    /// Spectral radius ρ∞ of the generalized-α method.
    pub spectral_radius: Option<f64>,
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

fn positive(name: &str, x: f64) -> Result<f64, CliError> {
    if x > 0.0 && x.is_finite() {
        Ok(x)
    } else {
        Err(CliError(format!("{name} must be a positive number, got {x}")))
    }
}

/// Runs the model at `path`; prints the check and the end-of-run summary unless quiet.
pub fn run_model(path: &Path, options: &RunOptions) -> Result<RunFiles, CliError> {
    let loaded = load_model(path).map_err(|e| CliError(e.to_string()))?;
    let model = &loaded.model;
    let d = loaded.simulation;
    let t_end = positive("--t-end", options.t_end.unwrap_or(d.t_end))?;
    let output_step = positive("--output-step", options.output_step.unwrap_or(d.output_step))?;
    let rtol = positive("--rtol", options.rtol.unwrap_or(d.rtol))?;
    let atol = positive("--atol", options.atol.unwrap_or(d.atol))?;
    let max_rows = options.max_output_rows.unwrap_or(d.max_output_rows);
    check_output_rows(t_end, output_step, max_rows, true).map_err(|e| CliError(format!("{}: {e}", path.display())))?;
    let method = match &options.integrator {
        Some(name) => crate::integrator_choice::parse_method(name, options.spectral_radius.unwrap_or(0.9))
            .map_err(|e| CliError(format!("--integrator: {e}")))?,
        None => d.method,
    };

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
    let csv_path = options.out_dir.join(format!("{stem}.csv"));
    let summary_path = options.out_dir.join(format!("{stem}.json"));
    let mut vtk = options
        .vtk_dir
        .as_deref()
        .map(|dir| {
            let times = SeriesTimes { step: options.vtk_step.or(d.vtk_step), output_step, t_end };
            RunSeries::create(dir, stem, &loaded, times, options.max_vtk_frames.unwrap_or(d.max_vtk_frames))
        })
        .transpose()
        .map_err(CliError)?;

    let settings = SimulationSettings {
        t_end,
        output_step,
        integrator: d.integrator(model, rtol, atol),
        assembly,
        method,
        physics_limits: d.physics_limits,
    };
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
    let observe = &mut |frame: &flexmb::analysis::OutputFrame| {
        if let Some(series) = vtk.as_mut() {
            series.observe(frame);
        }
        bar.set_position((frame.t / t_end * 1000.0) as u64);
        bar.set_message(format!("{:.4}", frame.t));
    };
    let run = record_run(model, &settings, &file_name, (&csv_path, &summary_path), observe, &|| {
        received().map(|s| s.name().to_string())
    });
    bar.finish_and_clear();
    let RecordedRun { report, error, rows } = run?;
    let vtk_written = vtk.map(RunSeries::finish).transpose().map_err(CliError)?;
    let interrupted = report.interrupted.as_ref().and(received());
    if !options.quiet {
        match (&error, &report.interrupted) {
            (Some(_), _) => println!("run stopped early:"),
            (None, Some(i)) => println!("run interrupted by {} at t = {:.6} s:", i.reason, i.t),
            (None, None) => println!("run completed:"),
        }
        println!("{}", summary_text(&report));
        println!("results: {} ({rows} rows), {}", csv_path.display(), summary_path.display());
        if let Some(s) = &vtk_written {
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
