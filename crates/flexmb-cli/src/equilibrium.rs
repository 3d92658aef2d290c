//! `flexmb equilibrium`: the static equilibrium of a model file at its start time — iterations and
//! residuals printed; `equilibrium.json` (every body's pose and modal coordinates, the multipliers, the
//! joints' reactions, the iterations), `equilibrium.csv` (the model's outputs there, one row, as a run
//! writes them) and with `--vtk` the deformed structure for ParaView.

use std::path::{Path, PathBuf};
use std::time::Instant;

use flexmb::analysis::{equilibrium_outputs, output_columns, static_equilibrium, EquilibriumReport, EquilibriumSettings, OutputFrame, State};
use flexmb::model::BodyId;
use flexmb::{Data, Model};
use flexmb_files::model_file::load_model_with;
use flexmb_files::results::CsvWriter;
use flexmb_files::vtk::{RunSeries, SeriesTimes};
use serde_json::json;

use crate::run::CliError;

/// What `flexmb equilibrium` writes and prints.
#[derive(Clone, Debug, Default)]
pub struct EquilibriumOptions {
    /// Directory of `equilibrium.json` and `equilibrium.csv`.
    pub out_dir: PathBuf,
    /// Also write the equilibrium for ParaView into `out_dir` (`equilibrium.pvd`).
    pub vtk: bool,
    /// Values replacing the model's parameters.
    pub parameters: Vec<(String, f64)>,
    /// Print nothing but errors.
    pub quiet: bool,
}

/// The files written.
#[derive(Clone, Debug)]
pub struct EquilibriumFiles {
    /// `equilibrium.json`.
    pub json: PathBuf,
    /// `equilibrium.csv`.
    pub csv: PathBuf,
    /// `equilibrium.pvd`, with `--vtk`.
    pub pvd: Option<PathBuf>,
}

/// Finds the static equilibrium of the model file at `path` (at t = 0, drivers and loads there) and
/// writes its files.
pub fn run_equilibrium(path: &Path, options: &EquilibriumOptions) -> Result<EquilibriumFiles, CliError> {
    let fail = |e: String| CliError(format!("{}: {e}", path.display()));
    let loaded = load_model_with(path, &crate::parameters::load_options_with(&options.parameters)).map_err(|e| CliError(e.to_string()))?;
    let model = &loaded.model;
    let settings = EquilibriumSettings { assembly: crate::limits::assembly_settings(&loaded.simulation)?, ..Default::default() };
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let start = Instant::now();
    let report = static_equilibrium(model, &mut data, &mut state, 0.0, &settings).map_err(|e| fail(e.to_string()))?;
    let wall_time = start.elapsed().as_secs_f64();
    if !options.quiet {
        print!("{}", describe_equilibrium(model, &report, wall_time));
    }
    std::fs::create_dir_all(&options.out_dir)
        .map_err(|e| CliError(format!("cannot create output directory {}: {e}", options.out_dir.display())))?;
    let json_path = options.out_dir.join("equilibrium.json");
    let document = equilibrium_json(model, &state, &report, path, wall_time);
    let text = serde_json::to_string_pretty(&document).map_err(|e| CliError(e.to_string()))?;
    std::fs::write(&json_path, text).map_err(|e| CliError(format!("cannot write {}: {e}", json_path.display())))?;
    let values = equilibrium_outputs(model, &mut data, &state, &report.multipliers).map_err(|e| fail(e.to_string()))?;
    let csv_path = options.out_dir.join("equilibrium.csv");
    let write_csv = || -> std::io::Result<()> {
        let mut csv = CsvWriter::create(&csv_path, &output_columns(model))?;
        csv.write_row(state.t, &values)?;
        csv.flush()
    };
    write_csv().map_err(|e| CliError(format!("cannot write {}: {e}", csv_path.display())))?;
    let pvd = if options.vtk {
        let times = SeriesTimes { step: None, output_step: 1.0, t_end: 1.0 };
        let mut series = RunSeries::create(&options.out_dir, "equilibrium", &loaded, times, 2).map_err(CliError)?;
        series.observe(&OutputFrame { t: 0.0, values: &values, q: &state.q, v: &state.v });
        Some(series.finish().map_err(CliError)?.pvd)
    } else {
        None
    };
    if !options.quiet {
        println!("results: {}, {}", json_path.display(), csv_path.display());
        if let Some(pvd) = &pvd {
            println!("ParaView: {}", pvd.display());
        }
    }
    Ok(EquilibriumFiles { json: json_path, csv: csv_path, pvd })
}

/// The printed report: iterations with their residuals, method, degrees of freedom, stability.
pub fn describe_equilibrium(model: &Model, report: &EquilibriumReport, wall_time: f64) -> String {
    let mut s = format!(
        "model '{}': {} degrees of freedom; static equilibrium at t = 0 s\n  iteration  method      force residual  constraint residual\n",
        model.name(),
        report.degrees_of_freedom
    );
    for (k, it) in report.history.iter().enumerate() {
        s.push_str(&format!("  {k:>9}  {:<10}  {:>14.3e}  {:>19.3e}\n", it.method.name(), it.force_residual, it.constraint_residual));
    }
    s.push_str(&format!(
        "converged by {} in {} iterations ({:.3} s): force residual {:.3e} (tolerance {:.3e}), constraint residual {:.3e}\n",
        report.method.name(),
        report.iterations,
        wall_time,
        report.force_residual,
        report.force_tolerance,
        report.constraint_residual
    ));
    if report.neutral_directions > 0 {
        s.push_str(&format!("neutral directions (no stiffness, no load): {}\n", report.neutral_directions));
    }
    if report.unstable_directions > 0 {
        s.push_str(&format!(
            "warning: the equilibrium is unstable in {} direction(s) (negative stiffness): a run started there leaves it\n",
            report.unstable_directions
        ));
    }
    s
}

/// `equilibrium.json`: the state (every body's origin, Euler parameters and modal coordinates), the
/// multipliers by equation, the reactions, the iterations.
fn equilibrium_json(model: &Model, state: &State, report: &EquilibriumReport, path: &Path, wall_time: f64) -> serde_json::Value {
    let l = model.layout();
    let bodies: Vec<serde_json::Value> = model
        .bodies()
        .iter()
        .enumerate()
        .map(|(b, body)| {
            let q = &state.q[l.q_range(BodyId(b)).expect("a body of the model")];
            let modal = l.modal_q_range(BodyId(b)).map(|r| state.q[r].to_vec()).unwrap_or_default();
            json!({ "name": body.name, "position": &q[0..3], "euler_parameters": &q[3..7], "modal_coordinates": modal })
        })
        .collect();
    let multipliers: Vec<serde_json::Value> = (0..l.nc)
        .map(|r| json!({ "equation": model.describe_constraint_row(r), "value": report.multipliers[r], "in_force": state.active[r] }))
        .collect();
    json!({
        "model": model.name(),
        "model_file": path.display().to_string(),
        "t": state.t,
        "method": report.method.name(),
        "iterations": report.iterations,
        "wall_time": wall_time,
        "force_residual": report.force_residual,
        "force_tolerance": report.force_tolerance,
        "constraint_residual": report.constraint_residual,
        "degrees_of_freedom": report.degrees_of_freedom,
        "neutral_directions": report.neutral_directions,
        "unstable_directions": report.unstable_directions,
        "history": report.history,
        "bodies": bodies,
        "multipliers": multipliers,
        "reactions": report.reactions,
    })
}
