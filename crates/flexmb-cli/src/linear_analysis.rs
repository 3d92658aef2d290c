//! `flexmb linearize`: the linear equations of motion of a model at an operating point, in
//! independent coordinates (`M.mtx`, `C.mtx`, `K.mtx`), optionally as a state-space model for named
//! inputs and outputs (`A.mtx`, `B.mtx`, `C_out.mtx`, `D.mtx`), with `linearization.json`; and the
//! operating point and model loading that `flexmb eigen` shares.

use std::path::{Path, PathBuf};

use faer::Mat;
use flexmb::analysis::{linear_model, state_space, LinearModel, OperatingPointChoice, StateSpace};
use flexmb_files::matrix_market::write_matrix_market;
use flexmb_files::model_file::{load_model_with, LoadedModel};
use serde_json::{json, Value};

use crate::run::CliError;

/// Matrices of at most this many rows and columns are also written into the JSON file.
const SMALL: usize = 20;

/// The operating point of `--at initial|equilibrium` and `--at-time T`.
pub fn operating_point_choice(at: Option<&str>, at_time: Option<f64>) -> Result<OperatingPointChoice, CliError> {
    match (at, at_time) {
        (Some(_), Some(_)) => Err(CliError("give either --at or --at-time, not both".into())),
        (None, Some(t)) => Ok(OperatingPointChoice::Time(t)),
        (None | Some("initial"), None) => Ok(OperatingPointChoice::Initial),
        (Some("equilibrium"), None) => Ok(OperatingPointChoice::Equilibrium),
        (Some(other), None) => Err(CliError(format!("--at: expected `initial` or `equilibrium`, got `{other}`"))),
    }
}

/// How the JSON files and printed reports name an operating point.
pub fn describe_choice(choice: OperatingPointChoice, t: f64) -> String {
    match choice {
        OperatingPointChoice::Initial => "the initial state (t = 0 s)".into(),
        OperatingPointChoice::Time(_) => format!("the simulated state at t = {t} s"),
        OperatingPointChoice::Equilibrium => "the static equilibrium".into(),
    }
}

/// Loads the model at `path` with `parameters` and linearizes it at `choice`, with the model file's
/// `[simulation]` settings (assembly; the integrator for `--at-time`).
pub fn load_and_linearize(path: &Path, parameters: &[(String, f64)], choice: OperatingPointChoice) -> Result<(LoadedModel, LinearModel), CliError> {
    let loaded = load_model_with(path, &crate::parameters::load_options_with(parameters)).map_err(|e| CliError(e.to_string()))?;
    let assembly = crate::limits::assembly_settings(&loaded.simulation)?;
    let settings = loaded.simulation.settings(&loaded.model, assembly);
    let linear = linear_model(&loaded.model, choice, &settings).map_err(|e| CliError(format!("{}: {e}", path.display())))?;
    Ok((loaded, linear))
}

/// What `flexmb linearize` is asked for.
pub struct LinearizeOptions {
    /// Where to linearize.
    pub choice: OperatingPointChoice,
    /// Inputs of the state-space model: force elements and drivers.
    pub inputs: Vec<String>,
    /// Measures as its outputs.
    pub outputs: Vec<String>,
    /// Directory of the files.
    pub out: PathBuf,
    /// `--parameter` values.
    pub parameters: Vec<(String, f64)>,
}

/// Runs `flexmb linearize`; returns the report to print.
pub fn run_linearize(path: &Path, options: &LinearizeOptions) -> Result<String, CliError> {
    let (loaded, mut linear) = load_and_linearize(path, &options.parameters, options.choice)?;
    let model = &loaded.model;
    let LinearModel { point, reduced, .. } = &mut linear;
    let space = if options.inputs.is_empty() && options.outputs.is_empty() {
        None
    } else {
        Some(
            state_space(model, &mut point.data, &point.state, &point.accelerations, reduced, &options.inputs, &options.outputs)
                .map_err(|e| CliError(format!("{}: {e}", path.display())))?,
        )
    };
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| CliError(format!("cannot create output directory {}: {e}", out.display())))?;
    let mut files = vec![("M", &reduced.mass), ("C", &reduced.damping), ("K", &reduced.stiffness)];
    if let Some(s) = &space {
        files.extend([("A", &s.a), ("B", &s.b), ("C_out", &s.c), ("D", &s.d)]);
    }
    let mut written = Vec::new();
    for (name, m) in &files {
        let file = out.join(format!("{name}.mtx"));
        write_matrix_market(&file, m.nrows(), m.ncols(), |i, j| m[(i, j)]).map_err(CliError)?;
        written.push(file.display().to_string());
    }
    let n = reduced.degrees_of_freedom();
    let mut json = json!({
        "model": model.name(),
        "operating_point": { "kind": choice_kind(options.choice), "t": point.state.t },
        "degrees_of_freedom": n,
        "coordinates": reduced.independent.names,
        "coordinate_convention": "independent velocity coordinates of a coordinate partitioning; translations and rotations about global axes (R.x, theta.x), modal coordinates (a.k)",
        "velocity_names": model.velocity_names(),
        "basis": matrix_json(&reduced.independent.basis),
        "files": files.iter().map(|(name, _)| format!("{name}.mtx")).collect::<Vec<_>>(),
    });
    if n <= SMALL {
        json["M"] = matrix_json(&reduced.mass);
        json["C"] = matrix_json(&reduced.damping);
        json["K"] = matrix_json(&reduced.stiffness);
    }
    if let Some(s) = &space {
        json["state_space"] = state_space_json(s);
    }
    let json_file = out.join("linearization.json");
    let text = serde_json::to_string_pretty(&json).map_err(|e| CliError(e.to_string()))?;
    std::fs::write(&json_file, text).map_err(|e| CliError(format!("cannot write {}: {e}", json_file.display())))?;
    let mut report = format!(
        "linearized '{}' at {}: {} degrees of freedom ({})\n",
        model.name(),
        describe_choice(options.choice, point.state.t),
        n,
        reduced.independent.names.join(", ")
    );
    if let Some(s) = &space {
        report.push_str(&format!("state space: {} states, inputs [{}], outputs [{}]\n", s.states.len(), s.inputs.join(", "), s.outputs.join(", ")));
    }
    report.push_str(&format!("written: {}, {}\n", written.join(", "), json_file.display()));
    Ok(report)
}

/// `initial`, `time` or `equilibrium`.
pub fn choice_kind(choice: OperatingPointChoice) -> &'static str {
    match choice {
        OperatingPointChoice::Initial => "initial",
        OperatingPointChoice::Time(_) => "time",
        OperatingPointChoice::Equilibrium => "equilibrium",
    }
}

/// A matrix as an array of rows.
pub fn matrix_json(m: &Mat<f64>) -> Value {
    Value::from((0..m.nrows()).map(|i| (0..m.ncols()).map(|j| m[(i, j)]).collect::<Vec<f64>>()).collect::<Vec<_>>())
}

fn state_space_json(s: &StateSpace) -> Value {
    let mut v = json!({ "states": s.states, "inputs": s.inputs, "outputs": s.outputs, "convention": "x' = A x + B u, y = C x + D u, x = [independent coordinates, their rates]" });
    if s.a.nrows() <= 2 * SMALL {
        v["A"] = matrix_json(&s.a);
        v["B"] = matrix_json(&s.b);
        v["C"] = matrix_json(&s.c);
        v["D"] = matrix_json(&s.d);
    }
    v
}
