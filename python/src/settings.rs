//! The run settings a Python call asks for: the model file's `[simulation]` values with the call's
//! keyword arguments in place of some, checked as `flexmb run` checks its options.

use flexmb::analysis::SimulationSettings;
use flexmb_files::integrator_choice::parse_method;
use flexmb_files::output_limits::check_output_rows;
use flexmb_files::LoadedModel;
use pyo3::PyResult;

use crate::errors::model_error;

/// The keyword arguments of `Model.simulate` and `Model.simulation` that replace the file's values;
/// `None` keeps the file's.
#[derive(Clone, Debug, Default)]
pub struct RunArguments {
    pub t_end: Option<f64>,
    pub output_step: Option<f64>,
    pub rtol: Option<f64>,
    pub atol: Option<f64>,
    /// `bdf`, `adams` or `gen-alpha`.
    pub integrator: Option<String>,
    /// ρ∞ of the generalized-α method (default 0.8).
    pub spectral_radius: Option<f64>,
}

/// `value` if given and a positive finite number, else the file's `default`.
fn positive_or(name: &str, value: Option<f64>, default: f64) -> PyResult<f64> {
    match value {
        None => Ok(default),
        Some(x) if x > 0.0 && x.is_finite() => Ok(x),
        Some(x) => Err(model_error(format!("{name} must be a positive number, got {x}"))),
    }
}

impl RunArguments {
    /// The simulation settings of `loaded` with these arguments; `file` names the model in messages.
    pub fn settings(&self, loaded: &LoadedModel, file: &str) -> PyResult<SimulationSettings> {
        let mut d = loaded.simulation;
        d.t_end = positive_or("t_end", self.t_end, d.t_end)?;
        d.output_step = positive_or("output_step", self.output_step, d.output_step)?;
        d.rtol = positive_or("rtol", self.rtol, d.rtol)?;
        d.atol = positive_or("atol", self.atol, d.atol)?;
        check_output_rows(d.t_end, d.output_step, d.max_output_rows, false).map_err(|e| model_error(format!("{file}: {e}")))?;
        if let Some(name) = &self.integrator {
            d.method = parse_method(name, self.spectral_radius.unwrap_or(flexmb::integrate::GeneralizedAlphaConfig::DEFAULT_SPECTRAL_RADIUS)).map_err(|e| model_error(format!("integrator: {e}")))?;
        }
        Ok(d.settings(&loaded.model, d.assembly()))
    }
}
