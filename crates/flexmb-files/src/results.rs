//! Result files: a CSV of the output columns written row by row as the run proceeds (so a run that fails
//! keeps everything computed so far), and a JSON summary with the solver statistics.

use std::cell::Cell;
use std::fs::File;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use flexmb::analysis::{
    output_columns, run_under_global_error_control, OutputColumn, OutputFrame, OutputSink, PhysicsLimits, PhysicsMeasures, Simulation, SimulationError, SimulationFailure, SimulationReport,
    SimulationSettings,
};
use flexmb::Model;
use serde_json::{json, Value};

use crate::model_file::LoadedModel;
use crate::restart::{resume_simulation, save_checkpoint, Restart};
use crate::body_stress::{HotSpot, StressMonitor};
use crate::vtk::{RunSeries, SeriesTimes, SeriesWritten};

/// A result file that could not be written or read, with the message that names it.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct ResultFileError(pub String);

/// Streams output frames into a CSV file with a header `t,<column>,…`, a row per frame, every value
/// written with the fewest digits that read back to the same double (the shortest round-trip
/// formatting of `ryu`: `0.1`, `1.2345678901234567`, `1e-7`, `-3.5e20`; `NaN`, `inf`). Rows reach the
/// file at least every [`FLUSH_INTERVAL`] of wall-clock time, so a long run's file grows as it runs,
/// and at once when the writer is dropped: a run that fails, is interrupted or panics keeps every row.
/// (A flush per row cost a system call per output time: on a run of 0.01 s with 501 rows, about a
/// tenth of the process.)
pub struct CsvWriter {
    path: PathBuf,
    out: csv::Writer<File>,
    rows: usize,
    /// The number being formatted (no allocation per value).
    number: ryu::Buffer,
    last_flush: Instant,
}

/// The longest a written row waits in the writer's buffer before it is flushed to the file.
pub const FLUSH_INTERVAL: Duration = Duration::from_millis(200);

impl CsvWriter {
    /// Creates the file at `path` and writes the header: `t` and the columns' names.
    pub fn create(path: &Path, columns: &[OutputColumn]) -> std::io::Result<Self> {
        let mut out = csv::Writer::from_writer(File::create(path)?);
        out.write_record(std::iter::once("t").chain(columns.iter().map(|c| c.name.as_str())))?;
        out.flush()?;
        Ok(Self { path: path.to_path_buf(), out, rows: 0, number: ryu::Buffer::new(), last_flush: Instant::now() })
    }

    /// Appends one row; flushes the rows written so far to the file when the last flush is
    /// [`FLUSH_INTERVAL`] ago.
    pub fn write_row(&mut self, t: f64, values: &[f64]) -> std::io::Result<()> {
        for &v in std::iter::once(&t).chain(values) {
            self.out.write_field(self.number.format(v))?;
        }
        self.out.write_record(None::<&[u8]>)?;
        self.rows += 1;
        if self.last_flush.elapsed() >= FLUSH_INTERVAL {
            self.last_flush = Instant::now();
            self.out.flush()?;
        }
        Ok(())
    }

    /// Writes every row so far to the file.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.last_flush = Instant::now();
        self.out.flush()
    }

    /// The rows written so far, the header not counted.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The file written.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// What a run was asked to do, for the summary.
pub struct RunRequest<'a> {
    /// The model file, as named in messages.
    pub model_file: &'a str,
    /// The model's name.
    pub model_name: &'a str,
    /// End time (s).
    pub t_end: f64,
    /// Interval between output times (s).
    pub output_step: f64,
    /// Relative error tolerance.
    pub rtol: f64,
    /// Absolute error tolerance.
    pub atol: f64,
    /// The integrator's name.
    pub integrator: &'a str,
    /// The physics watchdog's thresholds.
    pub limits: PhysicsLimits,
    /// The tolerances asked of global error control, if it was on (`rtol` and `atol` are then the run's,
    /// finer where it ran again).
    pub global_error_control: Option<flexmb::analysis::GlobalErrorControl>,
}

impl<'a> RunRequest<'a> {
    /// What a run of `model` with `settings`, from the file named `model_file`, was asked to do; the
    /// integrator named as `report` names it.
    pub fn of(model: &'a Model, settings: &SimulationSettings, model_file: &'a str, report: &SimulationReport) -> Self {
        RunRequest {
            model_file,
            model_name: model.name(),
            t_end: settings.t_end,
            output_step: settings.output_step,
            rtol: settings.tolerances.rtol,
            atol: settings.tolerances.atol,
            integrator: if report.method.is_empty() { "bdf" } else { report.method },
            limits: settings.physics_limits,
            global_error_control: settings.global_error_control,
        }
    }
}

/// The JSON summary of a run (completed or failed).
pub fn summary_json(
    request: &RunRequest,
    report: &SimulationReport,
    columns: &[OutputColumn],
    csv: &Path,
    error: Option<&str>,
) -> Value {
    let s = &report.stats;
    let orders: serde_json::Map<String, Value> = s
        .order_counts
        .iter()
        .enumerate()
        .filter(|(_, n)| **n > 0)
        .map(|(k, n)| (k.to_string(), json!(n)))
        .collect();
    let assembly = report.assembly.as_ref().map(|a| {
        json!({
            "iterations": a.iterations,
            "initial_residual": a.initial_residual,
            "residual": a.residual,
            "degrees_of_freedom": a.degrees_of_freedom,
            "redundant_constraints": a.redundant.iter().map(|r| r.description.clone()).collect::<Vec<_>>(),
        })
    });
    let velocity = report.velocity.as_ref().map(|v| json!({ "residual": v.residual, "adjusted": v.adjusted }));
    let status = match (error, &report.interrupted) {
        (Some(_), _) => "failed",
        (None, Some(_)) => "interrupted",
        (None, None) => "completed",
    };
    let mut summary = json!({
        "model": request.model_name,
        "model_file": request.model_file,
        "status": status,
        "error": error,
        "settings": {
            "t_end": request.t_end,
            "output_step": request.output_step,
            "rtol": request.rtol,
            "atol": request.atol,
            "integrator": request.integrator,
        },
        "t_reached": report.t_reached,
        "assembly": assembly,
        "velocity_analysis": velocity,
        "statistics": {
            "steps": s.steps,
            "rejected_steps": s.rejected_steps(),
            "error_test_failures": s.error_test_failures,
            "newton_failures": s.newton_failures,
            "newton_iterations": s.newton_iterations,
            "residual_evaluations": s.residual_evaluations,
            "jacobian_evaluations": s.jacobian_evaluations,
            "matrix_factorizations": s.factorizations,
            "rounding_floor_steps": s.rounding_floor_steps,
            "rounding_floor": s.rounding_floor,
            "singular_position_steps": s.singular_position_steps,
            "singular_position_condition": s.singular_position_condition,
            "singular_positions": s.singular_positions,
            "singular_position_tolerance": s.singular_position_tolerance,
            "share_floor_steps": s.share_floor_steps,
            "share_floor": s.share_floor,
            "rounding_passed": s.rounding_passed,
            "steps_per_order": orders,
            "rms_step_size": s.rms_step(),
            "wall_time_s": report.wall_time,
        },
        "constraints": {
            "at_steps": { "position": report.max_position_residual, "velocity": report.max_velocity_residual },
            "at_outputs": { "position": report.max_output_position_residual, "velocity": report.max_output_velocity_residual },
            "max_euler_parameter_norm_error": report.max_normalization_error,
        },
        "energy": {
            "initial": report.energy_initial,
            "final": report.energy_final,
            "change": report.energy_final - report.energy_initial,
            "nonconservative_work": report.nonconservative_work,
            "balance_error": balance_error(report),
        },
        "physics_checks": physics_checks_json(request.limits, &report.physics),
        "warnings": report.warnings.iter().map(|w| json!({ "t": w.t, "kind": w.kind.name(), "message": w.message })).collect::<Vec<_>>(),
        "output": {
            "csv": csv.display().to_string(),
            "rows": report.output_frames,
            "columns": columns.iter().map(|c| json!({ "name": c.name, "unit": c.unit })).collect::<Vec<_>>(),
        },
    });
    if let Some(g) = &report.global_error {
        summary["statistics"]["global_error_estimate"] = json!({
            "estimate": g.estimate,
            "tolerances": g.tolerances,
            "t": g.t,
            "norm": g.norm.name(),
            "shadow_rtol": g.shadow_rtol,
            "t_compared": g.t_compared,
            "shadow_steps": g.shadow_steps,
            "shadow_floor_steps": g.shadow_floor_steps,
        });
    }
    if let Some(control) = &request.global_error_control {
        summary["statistics"]["global_error_control"] = json!({
            "asked_rtol": control.rtol,
            "asked_atol": control.atol,
            "rtol": request.rtol,
            "atol": request.atol,
            "earlier_runs": report.global_error_control,
        });
    }
    if let Some(i) = &report.interrupted {
        summary["interrupted_at"] = json!(i.t);
        summary["reason"] = json!(i.reason);
    }
    summary
}

/// The physics watchdog's thresholds and the largest values it measured.
fn physics_checks_json(limits: PhysicsLimits, measured: &PhysicsMeasures) -> Value {
    let deflection = measured.largest_deflection.as_ref();
    json!({
        "elastic_deflection": {
            "warning": limits.elastic_deflection_warning,
            "limit": limits.elastic_deflection_limit,
            "largest_fraction": deflection.map(|d| d.deflection / d.size),
            "largest": deflection.map(|d| json!({ "body": d.body, "node": d.node, "t": d.t, "deflection": d.deflection, "size": d.size })),
        },
        "energy_balance": {
            "warning": limits.energy_balance_warning,
            "limit": limits.energy_balance_limit,
            "largest_fraction": measured.largest_balance_fraction,
            "largest_at": measured.largest_balance_time,
            "energy_scale": measured.energy_scale,
        },
    })
}

/// Human-readable end-of-run summary.
pub fn summary_text(report: &SimulationReport) -> String {
    let s = &report.stats;
    let orders: Vec<String> =
        s.order_counts.iter().enumerate().filter(|(_, n)| **n > 0).map(|(k, n)| format!("{k}:{n}")).collect();
    format!(
        "  time reached        {:.6} s\n  steps               {} ({} rejected: {} error test, {} Newton)\n  \
         steps per order     {}\n  RMS step size       {:.4e} s\n  Newton iterations   {}\n  \
         Jacobians / factorizations  {} / {}\n  wall time           {:.3} s\n  \
         constraint residual at steps                          position {:.2e}, velocity {:.2e}\n  \
         constraint residual at output times (interpolated)    position {:.2e}, velocity {:.2e}\n  \
         energy              initial {:.6e} J, final {:.6e} J, change {:.3e} J\n  \
         energy balance      work of non-conservative forces {:.3e} J; change − work = {:.2e} J{}{}{}",
        report.t_reached,
        s.steps,
        s.rejected_steps(),
        s.error_test_failures,
        s.newton_failures,
        orders.join(" "),
        s.rms_step(),
        s.newton_iterations,
        s.jacobian_evaluations,
        s.factorizations,
        report.wall_time,
        report.max_position_residual,
        report.max_velocity_residual,
        report.max_output_position_residual,
        report.max_output_velocity_residual,
        report.energy_initial,
        report.energy_final,
        report.energy_final - report.energy_initial,
        report.nonconservative_work,
        balance_error(report),
        physics_text(&report.physics),
        global_error_text(report),
        report.warnings.iter().map(|w| format!("\n  warning at t = {:.4} s: {}", w.t, w.message)).collect::<String>(),
    )
}

/// The global error estimated by reintegration, one line, if it was; a line per run that global error
/// control ran again before it.
fn global_error_text(report: &SimulationReport) -> String {
    let earlier = report.global_error_control.iter().map(|r| {
        format!(
            "\n  global error control  the run at rtol {:.2e} ({} steps) was estimated {:.2e} off ({:.1} tolerances asked for): run again finer",
            r.rtol, r.steps, r.estimate, r.tolerances
        )
    });
    earlier.collect::<String>() + &report.global_error.map_or(String::new(), |g| {
        let norm = match g.norm {
            flexmb::analysis::GlobalErrorNorm::PositionOutputs => "position outputs",
            flexmb::analysis::GlobalErrorNorm::State => "positions and velocities",
        };
        format!(
            "\n  global error        estimated {:.2e} ({:.2} tolerances, {norm}) at t = {:.4} s, by a run at rtol {:.2e} ({} steps)",
            g.estimate, g.tolerances, g.t, g.shadow_rtol, g.shadow_steps
        )
    })
}

/// The largest deflection and energy-balance error of the physics watchdog, one line each.
fn physics_text(measured: &PhysicsMeasures) -> String {
    let mut s = String::new();
    if let Some(d) = &measured.largest_deflection {
        s += &format!(
            "\n  largest deflection  {:.3} % of its size: flexible body '{}', {:.3e} m at node {} (t = {:.4} s)",
            100.0 * d.deflection / d.size,
            d.body,
            d.deflection,
            d.node,
            d.t
        );
    }
    s + &format!(
        "\n  balance check       largest error beyond quadrature and tolerance {:.3} % of the {:.3e} J that flowed (t = {:.4} s)",
        100.0 * measured.largest_balance_fraction,
        measured.energy_scale,
        measured.largest_balance_time
    )
}

/// How far the run's energy is from its balance: `E_final − E_initial − W_nc` (J), where `W_nc` is the
/// work of the non-conservative forces (trapezoidal rule over the accepted steps and output times).
pub fn balance_error(report: &SimulationReport) -> f64 {
    report.energy_final - report.energy_initial - report.nonconservative_work
}

/// A run recorded to files: its report, the failure if it stopped early, and the rows written.
pub struct RecordedRun {
    /// The engine's report: statistics, constraint residuals, energy, warnings, interruption.
    pub report: SimulationReport,
    /// The simulation's failure, if it stopped early (the files hold what it computed before).
    pub error: Option<String>,
    /// Rows written to the CSV.
    pub rows: usize,
    /// The ParaView series written, if one was asked for (only [`record_model_run`] writes one).
    pub paraview: Option<SeriesWritten>,
    /// The stress hot spot of each flexible body whose table asks for stresses (only
    /// [`record_model_run`] follows them).
    pub hot_spots: Vec<HotSpot>,
}

/// Where a run's results go: the CSV of its outputs, its JSON summary, and optionally a ParaView
/// series.
#[derive(Clone, Debug, PartialEq)]
pub struct RunOutputs {
    /// The result CSV: a header `t,<column>,…` and a row per output time.
    pub csv: PathBuf,
    /// The JSON summary: settings, statistics, residuals, energy, columns and their units.
    pub summary: PathBuf,
    /// A ParaView time series of the bodies and joints, if wanted.
    pub paraview: Option<ParaViewSeries>,
}

/// A ParaView time series to write as a run proceeds: `dir/name.pvd` and its files in `dir/name/`.
#[derive(Clone, Debug, PartialEq)]
pub struct ParaViewSeries {
    /// The directory of the `.pvd` file.
    pub dir: PathBuf,
    /// The series' name: the `.pvd` file's stem and the folder of its `.vtu` files.
    pub name: String,
    /// When frames are taken.
    pub times: SeriesTimes,
    /// Most frames the series may have; more is an error before the run starts.
    pub max_frames: u64,
}

impl RunOutputs {
    /// `dir/name.csv` and `dir/name.json`, as `flexmb run` names them; no ParaView series.
    pub fn in_directory(dir: &Path, name: &str) -> Self {
        Self { csv: dir.join(format!("{name}.csv")), summary: dir.join(format!("{name}.json")), paraview: None }
    }
}

/// Simulates a loaded model as `flexmb run` does: its outputs go to `outputs.csv` as they come, its
/// summary to `outputs.summary` at the end, and a ParaView series frame by frame if
/// `outputs.paraview` asks for one; `observe` sees every output frame, and `interrupt` is asked
/// after every step whether to stop; `restart` resumes from a checkpoint file and saves the state
/// (see [`record_run`]; a resumed run's ParaView series holds the frames after the checkpoint). The directories must exist.
///
/// ```
/// use flexmb_files::{load_model, record_model_run, Restart, RunOutputs};
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/pendulum.toml");
/// let loaded = load_model(std::path::Path::new(path))?;
/// let mut defaults = loaded.simulation;
/// defaults.t_end = 0.1;
/// let settings = defaults.settings(&loaded.model, defaults.assembly());
/// let dir = std::env::temp_dir().join(format!("flexmb-files-doctest-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let outputs = RunOutputs::in_directory(&dir, "pendulum");
/// let mut frames = 0;
/// let run = record_model_run(&loaded, &settings, path, &outputs, Restart::default(), &mut |_frame| frames += 1, &|| None)?;
/// assert!(run.error.is_none());
/// assert_eq!((run.rows, frames), (11, 11));
/// let table = flexmb_files::ResultTable::read(&outputs.csv)?;
/// assert_eq!(table.column("t")?.len(), 11);
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn record_model_run(
    loaded: &LoadedModel,
    settings: &SimulationSettings,
    model_file: &str,
    outputs: &RunOutputs,
    restart: Restart,
    observe: &mut dyn FnMut(&OutputFrame),
    interrupt: &dyn Fn() -> Option<String>,
) -> Result<RecordedRun, ResultFileError> {
    let mut series = outputs
        .paraview
        .as_ref()
        .map(|p| RunSeries::create(&p.dir, &p.name, loaded, p.times, p.max_frames))
        .transpose()
        .map_err(ResultFileError)?;
    let mut stresses = StressMonitor::new(loaded);
    let run_again = Cell::new(false);
    let mut restart_error = None;
    let observe = &mut |frame: &OutputFrame| {
        // Global error control ran the model again from the start: the series and the stresses begin anew.
        if run_again.replace(false) {
            stresses = StressMonitor::new(loaded);
            if let Some(p) = outputs.paraview.as_ref().filter(|_| series.is_some()) {
                match RunSeries::create(&p.dir, &p.name, loaded, p.times, p.max_frames) {
                    Ok(s) => series = Some(s),
                    Err(e) => restart_error = Some(e),
                }
            }
        }
        stresses.observe(&loaded.model, frame);
        if let Some(series) = series.as_mut() {
            series.observe(frame);
        }
        observe(frame);
    };
    let files = (outputs.csv.as_path(), outputs.summary.as_path());
    let run = record_run_again_noticed(&loaded.model, settings, model_file, files, restart, observe, &|| run_again.set(true), interrupt)?;
    if let Some(e) = restart_error {
        return Err(ResultFileError(e));
    }
    let paraview = series.map(RunSeries::finish).transpose().map_err(ResultFileError)?;
    let hot_spots = stresses.hot_spots();
    if !stresses.is_empty() {
        add_hot_spots(&outputs.summary, &hot_spots)?;
    }
    Ok(RecordedRun { paraview, hot_spots, ..run })
}

/// Adds `stress_hot_spots` (one per body whose stresses were followed) to the JSON summary at `path`.
fn add_hot_spots(path: &Path, hot_spots: &[HotSpot]) -> Result<(), ResultFileError> {
    let error = |e: String| ResultFileError(format!("cannot add the stress hot spots to {}: {e}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| error(e.to_string()))?;
    let mut summary: Value = serde_json::from_str(&text).map_err(|e| error(e.to_string()))?;
    summary["stress_hot_spots"] = Value::Array(hot_spots.iter().map(HotSpot::to_json).collect());
    let text = serde_json::to_string_pretty(&summary).map_err(|e| error(e.to_string()))?;
    std::fs::write(path, text + "\n").map_err(|e| error(e.to_string()))
}

/// Simulates `model`, writing every output frame to `csv` as it comes (a run that fails keeps what
/// it computed) and the JSON summary to `summary` at the end; `observe` sees every frame too.
/// `interrupt` is asked after every step whether to stop (see [`Simulation::run`]); an interrupted
/// run's summary says `"status": "interrupted"`, with `interrupted_at` and `reason`. `restart` may
/// resume the run from a checkpoint file and save its state at the end (see [`Restart`]): a resumed
/// run's CSV holds the rows after the checkpoint's time, its summary the counters of the whole run.
pub fn record_run(
    model: &Arc<Model>,
    settings: &SimulationSettings,
    model_file: &str,
    files: (&Path, &Path),
    restart: Restart,
    observe: &mut dyn FnMut(&OutputFrame),
    interrupt: &dyn Fn() -> Option<String>,
) -> Result<RecordedRun, ResultFileError> {
    record_run_again_noticed(model, settings, model_file, files, restart, observe, &|| {}, interrupt)
}

/// [`record_run`] that calls `run_again` when global error control starts the model again from the
/// start, before the first frame of the new run reaches `observe`.
#[allow(clippy::too_many_arguments)]
fn record_run_again_noticed(
    model: &Arc<Model>,
    settings: &SimulationSettings,
    model_file: &str,
    (csv_path, summary_path): (&Path, &Path),
    restart: Restart,
    observe: &mut dyn FnMut(&OutputFrame),
    run_again: &dyn Fn(),
    interrupt: &dyn Fn() -> Option<String>,
) -> Result<RecordedRun, ResultFileError> {
    let (started, resumed_at) = match restart.resume {
        Some(file) => {
            let (simulation, t) = resume_simulation(model, settings, file)?;
            (Ok(simulation), Some((file, t)))
        }
        None => (Simulation::new(Arc::clone(model), *settings), None),
    };
    let columns = output_columns(model);
    let create_csv = || CsvWriter::create(csv_path, &columns).map_err(|e| ResultFileError(format!("cannot write {}: {e}", csv_path.display())));
    let mut csv = create_csv()?;
    let mut write_error: Option<std::io::Error> = None;
    let mut simulation = None;
    // Global error control runs again from the start, into new files, a run whose estimate is beyond
    // the tolerance (not a run resumed or paused: their estimate covers part of the run).
    let controlled = restart.resume.is_none() && restart.pause_at.is_none();
    let mut first = Some(started);
    let (result, settings, earlier) = run_under_global_error_control(settings, |settings| {
        let started = match first.take() {
            Some(started) => started,
            // The last run's buffered rows go to its file before the file is made anew: flushed when its
            // writer was dropped, after the new one truncated the file, they landed past the new run's
            // rows (a shorter run's CSV ended in the tail of the longer one's).
            None => {
                if let Err(e) = csv.flush() {
                    return (Err(ResultFileError(format!("cannot write {}: {e}", csv_path.display()))), None);
                }
                match create_csv() {
                    Ok(new) => {
                        csv = new;
                        run_again();
                        Simulation::new(Arc::clone(model), *settings)
                    }
                    Err(e) => return (Err(e), None),
                }
            }
        };
        let result = started.and_then(|mut s| {
            let sink = &mut |frame: &OutputFrame| {
                if write_error.is_none() {
                    write_error = csv.write_row(frame.t, frame.values).err();
                }
                observe(frame);
            };
            let run = match restart.pause_at {
                None => s.run(sink, interrupt),
                Some(t_pause) => run_with_pause(&mut s, t_pause, sink, interrupt),
            };
            let report = s.report().clone();
            simulation = Some(s);
            match run {
                Ok(()) => Ok(report),
                Err(cause) => Err(SimulationError { cause, report: Box::new(report) }),
            }
        });
        let completed = match &result {
            Ok(report) if controlled && write_error.is_none() => Some(report.clone()),
            _ => None,
        };
        (Ok(result), completed)
    });
    let result = result?;
    if write_error.is_none() {
        write_error = csv.flush().err();
    }
    if let Some(e) = write_error {
        return Err(ResultFileError(format!("cannot write {}: {e}", csv_path.display())));
    }
    let (mut report, error) = match result {
        Ok(r) => (r, None),
        Err(e) => ((*e.report).clone(), Some(e.to_string())),
    };
    report.global_error_control = earlier;
    let settings = &settings;
    let request = RunRequest::of(model, settings, model_file, &report);
    let mut summary = summary_json(&request, &report, &columns, csv_path, error.as_deref());
    if let Some((file, t)) = resumed_at {
        summary["resumed_from"] = json!({ "checkpoint": file.display().to_string(), "t": t });
    }
    let text = serde_json::to_string_pretty(&summary).map_err(|e| ResultFileError(e.to_string()))?;
    std::fs::write(summary_path, text + "\n").map_err(|e| ResultFileError(format!("cannot write {}: {e}", summary_path.display())))?;
    if let (Some(file), Some(simulation), None) = (restart.save_state, simulation.as_mut(), &error) {
        let checkpoint = simulation.checkpoint().map_err(|e| ResultFileError(format!("cannot save the state to {}: {e}", file.display())))?;
        save_checkpoint(file, &checkpoint)?;
    }
    Ok(RecordedRun { report, error, rows: csv.rows(), paraview: None, hot_spots: Vec::new() })
}

/// [`Simulation::run`] that also stops, as an interruption, at the first step at or after `t_pause`.
fn run_with_pause(
    simulation: &mut Simulation,
    t_pause: f64,
    sink: &mut dyn OutputSink,
    interrupt: &dyn Fn() -> Option<String>,
) -> Result<(), SimulationFailure> {
    while !simulation.is_finished() {
        simulation.step(sink)?;
        if simulation.is_finished() {
            break;
        }
        let reason = if simulation.time() >= t_pause { Some(format!("pause at {t_pause} s")) } else { interrupt() };
        if let Some(reason) = reason {
            simulation.interrupt(reason);
            break;
        }
    }
    Ok(())
}

#[cfg(test)]
mod round_trip_tests {
    use super::*;
    use crate::ResultTable;

    /// Every value `CsvWriter` writes reads back through `ResultTable` (the reader of `plot`, `compare`,
    /// `spectrum` and `study`) to the same bits: the pendulum's output rows from a run, and values
    /// chosen to be hard (thirds, the extremes of double precision, subnormals, signed zero).
    #[test]
    fn written_values_read_back_bit_for_bit() {
        let loaded = crate::load_model(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/pendulum.toml"))).unwrap();
        let settings = SimulationSettings { t_end: 1.0, ..loaded.simulation.settings(&loaded.model, loaded.simulation.assembly()) };
        let mut table = flexmb::analysis::OutputTable::new(&loaded.model);
        flexmb::analysis::simulate(&loaded.model, &settings, &mut |frame: &OutputFrame| {
            table.write_frame(frame).unwrap();
        })
        .unwrap();
        let hard = [1.0 / 3.0, -2.0 / 3.0, 0.1, f64::MAX, f64::MIN_POSITIVE, 5e-324, -0.0, 1e-7, 1e16, 123456789.01234567, std::f64::consts::PI];
        let columns: Vec<OutputColumn> = table.columns()[1..].to_vec();
        let path = std::env::temp_dir().join(format!("flexmb-files-round-trip-{}.csv", std::process::id()));
        let mut writer = CsvWriter::create(&path, &columns).unwrap();
        let mut written: Vec<Vec<f64>> = (0..table.len()).map(|i| table.row(i).unwrap().to_vec()).collect();
        for (k, x) in hard.iter().enumerate() {
            let mut row = vec![*x; columns.len() + 1];
            row[0] = 2.0 + k as f64;
            written.push(row);
        }
        for row in &written {
            writer.write_row(row[0], &row[1..]).unwrap();
        }
        writer.flush().unwrap();
        let read = ResultTable::read(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_eq!(read.rows(), written.len());
        for (c, name) in read.names().iter().enumerate() {
            let column = read.column(name).unwrap();
            for (r, row) in written.iter().enumerate() {
                assert_eq!(column[r].to_bits(), row[c].to_bits(), "row {r}, column {name}: wrote {:?}, read {:?}", row[c], column[r]);
            }
        }
    }
}
