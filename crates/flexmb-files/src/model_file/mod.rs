//! Model files: a mechanism described in TOML (see `docs/model-file.md`), parsed with every value's
//! position kept, validated with errors that name the file, key path and line, and built into a
//! [`flexmb::Model`].

pub(crate) mod build;
mod error;
pub(crate) mod expressions;
pub(crate) mod key_path;
mod overrides;
pub(crate) mod parameters;
pub(crate) mod schema;
pub(crate) mod source;
pub(crate) mod suggest;
pub(crate) mod toml_errors;
pub(crate) mod value;

use std::path::Path;


pub use build::body_cache::{basis_name, CACHE_DIR};
pub use build::flexible_bodies::{FlexibleBodyInfo, FlexibleBodyOrigin};
pub use error::{ErrorKind, ModelFileError};
pub use overrides::ModelOverrides;

use schema::ModelFile;
use source::Source;

/// A model read from a file, with the file's defaults for simulation runs.
#[derive(Clone, Debug)]
pub struct LoadedModel {
    /// The model, built and validated by the engine; shared, so that a [`Simulation`](flexmb::analysis::Simulation) or a binding holds it without a copy.
    pub model: std::sync::Arc<flexmb::Model>,
    /// The file's `[simulation]` values, for runs.
    pub simulation: SimulationDefaults,
    /// The values of the file's `[parameters]`, overrides applied, by name.
    pub parameters: std::collections::BTreeMap<String, f64>,
    /// The flexible bodies, in the order of their `[[flexible_body]]` tables: mode set, frequencies,
    /// and whether each was reduced now, read from the cache or read from a flexible-body file.
    pub flexible_bodies: Vec<FlexibleBodyInfo>,
    /// What the ParaView output draws for each rigid body, in the order of their `[[body]]` tables.
    pub shapes: Vec<crate::shape::BodyShape>,
}

/// `[simulation]`: what `flexmb run` uses unless told otherwise.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimulationDefaults {
    /// End time (s). Default 1.
    pub t_end: f64,
    /// Interval between output times (s). Default 0.01.
    pub output_step: f64,
    /// Relative error tolerance of the integrator. Default 1e-6.
    pub rtol: f64,
    /// Absolute error tolerance of the integrator. Default 1e-6.
    pub atol: f64,
    /// The span of simulated time whose steps together may make an error of the tolerance
    /// (`tolerance_span`: seconds, `"run"` or `"step"`; [`Tolerances::span`](flexmb::integrate::Tolerances::span),
    /// error per unit step; `"run"` keeps the promise of docs/accuracy.md). Default the run's length,
    /// [`ToleranceSpan::default`](flexmb::integrate::ToleranceSpan::default).
    pub tolerance_span: flexmb::integrate::ToleranceSpan,
    /// What the assembly may change in flexible bodies (`modal_assembly`). Default held: the modal
    /// coordinates stay at their initial values and only the reference frames move.
    pub modal_assembly: flexmb::analysis::ModalAssembly,
    /// Where a run starts (`start`): `"assembly"`, the assembled initial configuration (the default), or
    /// `"equilibrium"`, the static equilibrium there ([`Start::Equilibrium`](flexmb::analysis::Start)).
    pub start: flexmb::analysis::Start,
    /// The integration method (`integrator`, with `spectral_radius` for the generalized-α method).
    /// Default BDF.
    pub method: flexmb::integrate::Method,
    /// Highest BDF order (`max_order`, 1 to 5); `None`: 5 (with stability limits on orders 3–5 for
    /// models with flexible bodies, see [`BdfConfig::for_model`](flexmb::integrate::BdfConfig::for_model)).
    pub max_order: Option<usize>,
    /// Largest step of the integrator (`max_step`, s), whatever its error control allows; `None` (the
    /// default): unlimited.
    pub max_step: Option<f64>,
    /// The generalized-α method's step held fixed at this size (`fixed_step`, s), without error control:
    /// a run of length `T` takes `T / fixed_step` steps (the last one shortened to end on `T`), as the
    /// peer's fixed-step generalized-α does; only a Newton failure shortens a step. `None` (the default):
    /// steps from the error estimate. Other methods have no fixed step.
    pub fixed_step: Option<f64>,
    /// Interval between the frames of the ParaView output (`vtk_step`, s); `None`: the output step.
    pub vtk_step: Option<f64>,
    /// Most output rows a run may write (`max_output_rows`). Default
    /// [`DEFAULT_MAX_OUTPUT_ROWS`](crate::output_limits::DEFAULT_MAX_OUTPUT_ROWS), 10⁷.
    pub max_output_rows: u64,
    /// Most ParaView frames a run may write (`max_vtk_frames`). Default
    /// [`DEFAULT_MAX_VTK_FRAMES`](crate::output_limits::DEFAULT_MAX_VTK_FRAMES), 10⁵.
    pub max_vtk_frames: u64,
    /// The physics watchdog's thresholds (`elastic_deflection_warning`, `…_limit`,
    /// `energy_balance_warning`, `…_limit`). Default [`flexmb::analysis::PhysicsLimits::default`].
    pub physics_limits: flexmb::analysis::PhysicsLimits,
    /// A second run alongside that warns where the two separate exponentially (`divergence_check`,
    /// [`SimulationSettings::divergence_check`](flexmb::analysis::SimulationSettings::divergence_check)).
    /// Default off.
    pub divergence_check: bool,
    /// A second run alongside at a tenth of the tolerances that estimates the run's global error
    /// (`global_error_estimate`,
    /// [`SimulationSettings::global_error_estimate`](flexmb::analysis::SimulationSettings::global_error_estimate)).
    /// Default off.
    pub global_error_estimate: bool,
    /// Global error control: the global error estimated against `rtol` and `atol`, and a run whose estimate
    /// exceeds 10 tolerances run again finer (`global_error_control`,
    /// [`SimulationSettings::global_error_control`](flexmb::analysis::SimulationSettings::global_error_control)).
    /// Default off.
    pub global_error_control: bool,
}

impl Default for SimulationDefaults {
    fn default() -> Self {
        Self {
            t_end: 1.0,
            output_step: 0.01,
            rtol: 1e-6,
            atol: 1e-6,
            tolerance_span: flexmb::integrate::ToleranceSpan::default(),
            modal_assembly: flexmb::analysis::ModalAssembly::Held,
            start: flexmb::analysis::Start::Assembly,
            method: flexmb::integrate::Method::default(),
            max_order: None,
            max_step: None,
            fixed_step: None,
            vtk_step: None,
            max_output_rows: crate::output_limits::DEFAULT_MAX_OUTPUT_ROWS,
            max_vtk_frames: crate::output_limits::DEFAULT_MAX_VTK_FRAMES,
            physics_limits: flexmb::analysis::PhysicsLimits::default(),
            divergence_check: false,
            global_error_estimate: false,
            global_error_control: false,
        }
    }
}

impl SimulationDefaults {
    /// The error tolerances and step limits these defaults ask for.
    pub fn tolerances(&self) -> flexmb::integrate::Tolerances {
        flexmb::integrate::Tolerances {
            span: self.tolerance_span,
            h_max: self.max_step.unwrap_or(f64::INFINITY),
            ..flexmb::integrate::Tolerances::new(self.rtol, self.atol)
        }
    }

    /// Why these defaults cannot run: a fixed step with a method other than the generalized-α method.
    pub fn check_fixed_step(&self) -> Result<(), String> {
        match (self.fixed_step, &self.method) {
            (Some(_), flexmb::integrate::Method::GeneralizedAlpha(_)) | (None, _) => Ok(()),
            (Some(h), _) => Err(format!(
                "a fixed step ({h} s) is a setting of the generalized-α method only (integrator `gen-alpha`); \
                 the other integrators choose their steps by error control (limit them with a largest step instead)"
            )),
        }
    }

    /// The integration method for `model`: [`method`](Self::method), the BDF with the settings for the
    /// model ([`BdfConfig::for_model`](flexmb::integrate::BdfConfig::for_model)) and the order limit
    /// [`max_order`](Self::max_order), the generalized-α method with the [`fixed_step`](Self::fixed_step).
    pub fn method_for(&self, model: &flexmb::Model) -> flexmb::integrate::Method {
        use flexmb::integrate::{BdfConfig, GeneralizedAlphaConfig, Method};
        match self.method {
            Method::Bdf(_) => {
                let base = BdfConfig::for_model(model);
                Method::Bdf(BdfConfig { max_order: self.max_order.unwrap_or(base.max_order), ..base })
            }
            Method::GeneralizedAlpha(config) => {
                Method::GeneralizedAlpha(GeneralizedAlphaConfig { fixed_step: self.fixed_step.or(config.fixed_step), ..config })
            }
            other => other,
        }
    }

    /// The assembly settings these defaults ask for (with the memory available on this machine as
    /// the limit of the initial-condition analyses; see [`with_memory_limit`](Self::with_memory_limit)).
    pub fn assembly(&self) -> flexmb::analysis::AssemblySettings {
        flexmb::analysis::AssemblySettings { modal: self.modal_assembly, ..Default::default() }
    }

    /// The assembly settings these defaults ask for, with `memory_limit` for the initial-condition analyses.
    pub fn with_memory_limit(&self, memory_limit: flexmb::analysis::MemoryLimit) -> flexmb::analysis::AssemblySettings {
        flexmb::analysis::AssemblySettings { memory_limit, ..self.assembly() }
    }

    /// The simulation settings these defaults ask for: end time, output step, method, tolerances and
    /// order limit, physics limits, with `assembly` for the initial conditions.
    pub fn settings(
        &self,
        model: &flexmb::Model,
        assembly: flexmb::analysis::AssemblySettings,
    ) -> flexmb::analysis::SimulationSettings {
        flexmb::analysis::SimulationSettings {
            t_end: self.t_end,
            output_step: self.output_step,
            tolerances: self.tolerances(),
            assembly,
            start: self.start,
            method: self.method_for(model),
            physics_limits: self.physics_limits,
            divergence_check: self.divergence_check,
            global_error_estimate: self.global_error_estimate,
            global_error_control: self
                .global_error_control
                .then_some(flexmb::analysis::GlobalErrorControl { rtol: self.rtol, atol: self.atol }),
        }
    }
}

/// How to load a model file beyond what it says: values that replace the file's (a study's case) and
/// the memory the FE mode analysis of its flexible bodies may use.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadOptions {
    /// Values that replace those of the file: parameters, mode sets.
    pub overrides: ModelOverrides,
    /// Most bytes the mode analysis of a flexible body reduced from its FE model may use; `None`: no
    /// limit. Default: the memory available on this machine
    /// ([`MemoryLimit::Available`](flexmb::analysis::MemoryLimit)).
    pub memory_limit: Option<u64>,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self { overrides: ModelOverrides::default(), memory_limit: flexmb::analysis::MemoryLimit::Available.bytes() }
    }
}

/// Reads and builds the model file at `path`.
///
/// ```
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/pendulum.toml");
/// let loaded = flexmb_files::load_model(std::path::Path::new(path))?;
/// assert_eq!(loaded.model.bodies().len(), 1);
/// assert_eq!(loaded.simulation.t_end, 5.0);
/// # Ok::<(), flexmb_files::ModelFileError>(())
/// ```
pub fn load_model(path: &Path) -> Result<LoadedModel, ModelFileError> {
    load_model_with(path, &LoadOptions::default())
}

/// [`load_model`] with some of the file's values replaced and a memory limit for the mode analysis.
///
/// ```
/// use flexmb_files::model_file::{LoadOptions, ModelOverrides};
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../models/pendulum.toml");
/// let overrides = ModelOverrides { parameters: vec![("L".into(), 2.0)], ..Default::default() };
/// let options = LoadOptions { overrides, ..Default::default() };
/// let loaded = flexmb_files::load_model_with(std::path::Path::new(path), &options)?;
/// let settings = loaded.simulation.settings(&loaded.model, loaded.simulation.assembly());
/// assert_eq!(settings.t_end, loaded.simulation.t_end);
/// # Ok::<(), flexmb_files::ModelFileError>(())
/// ```
pub fn load_model_with(path: &Path, options: &LoadOptions) -> Result<LoadedModel, ModelFileError> {
    let file = path.display().to_string();
    let text = source::read_text_file(path, "model")?;
    let base_dir = path.parent().unwrap_or(Path::new(""));
    parse_model_with(&text, &file, base_dir, options)
}

/// Builds a model from the text of a model file; `file_name` is used in error messages, its stem is
/// the model's default name, and its directory is where the paths of flexible bodies' files start.
pub fn parse_model(text: &str, file_name: &str) -> Result<LoadedModel, ModelFileError> {
    let base_dir = Path::new(file_name).parent().unwrap_or(Path::new(""));
    parse_model_in(text, file_name, base_dir)
}

/// [`parse_model`] with the paths of flexible bodies' files (`fe_model`, `body_file`) relative to
/// `base_dir`.
pub fn parse_model_in(text: &str, file_name: &str, base_dir: &Path) -> Result<LoadedModel, ModelFileError> {
    parse_model_with(text, file_name, base_dir, &LoadOptions::default())
}

/// [`parse_model_in`] with some of the file's values replaced and a memory limit for the mode analysis.
pub fn parse_model_with(
    text: &str,
    file_name: &str,
    base_dir: &Path,
    options: &LoadOptions,
) -> Result<LoadedModel, ModelFileError> {
    let source = Source::new(file_name, text);
    let mut file: ModelFile = toml_errors::deserialize_located(&source)?;
    options.overrides.apply(&mut file).map_err(|message| ModelFileError {
        kind: ErrorKind::Invalid,
        file: file_name.to_string(),
        line: None,
        key_path: String::new(),
        message,
    })?;
    let default_name = Path::new(file_name).file_stem().and_then(|s| s.to_str()).unwrap_or("model");
    build::build(&file, &source, default_name, base_dir, options.memory_limit)
}
