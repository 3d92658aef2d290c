//! The preprocessor of `flexmb modes` and of the Python package's `flexmb.modes`: an FE model file
//! read, its mass model, mode set and basis taken from the request or else from the file, and reduced
//! to a flexible body.

use std::path::Path;
use std::time::Instant;

use flexmb_fem::modes::EigenSettings;
use flexmb_fem::reduction::{add_modal_stresses, reduce, Basis, ModeSet, Reduction, ReductionSettings};
use flexmb_fem::{FemError, MassModel};

use super::{load_fe_model, LoadedFeModel, ModelFileError};

/// What to reduce an FE model file to; each `None` takes the file's value (`[modes] set`, `[modes]
/// basis` else orthonormal, `[fe_model] mass` else each kind of element's default, `[modes] stresses` else none).
#[derive(Clone, Debug, Default)]
pub struct ReductionRequest {
    /// The mode set, e.g. `4N5S`.
    pub mode_set: Option<ModeSet>,
    /// Raw or mass-orthonormalized modes.
    pub basis: Option<Basis>,
    /// Lumped or consistent mass for every element (`None`: the file's, else each kind's default).
    pub mass: Option<MassModel>,
    /// The eigensolver and the memory it may use.
    pub eigen: EigenSettings,
    /// Whether to store each mode's stresses (`[modes] stresses` of the file else).
    pub stresses: Option<bool>,
}

/// An FE model file reduced: the model as read, the reduction, and the time the reduction took.
#[derive(Clone, Debug)]
pub struct ReducedFeModel {
    /// The FE model as read, with the requested mass model.
    pub loaded: LoadedFeModel,
    /// The flexible body, the FE modes, the static modes and the reduction's warnings.
    pub reduction: Reduction,
    /// The reduction's wall time (s).
    pub seconds: f64,
}

/// Why an FE model file could not be reduced.
#[derive(Debug, thiserror::Error)]
pub enum ReduceFileError {
    /// The file cannot be read or built.
    #[error("{0}")]
    File(#[from] ModelFileError),
    /// Neither the request nor the file's `[modes]` table gives a mode set.
    #[error("{file}: no mode set: give one (e.g. 6N, 5S or 4N5S) or `set` in the file's [modes] table")]
    NoModeSet {
        /// The FE model file.
        file: String,
    },
    /// The reduction failed (a mode set the model cannot give, too little memory, …).
    #[error("{file}: {source}")]
    Reduction {
        /// The FE model file.
        file: String,
        /// What went wrong.
        source: FemError,
    },
}

/// Reads the FE model file at `path` ([`load_fe_model`]) and reduces it as `request` asks.
pub fn reduce_fe_model_file(path: &Path, request: &ReductionRequest) -> Result<ReducedFeModel, ReduceFileError> {
    let file = path.display().to_string();
    let mut loaded = load_fe_model(path)?;
    if let Some(mass) = request.mass {
        loaded.model.options.mass = Some(mass);
    }
    let mode_set = request.mode_set.clone().or_else(|| loaded.defaults.mode_set.clone());
    let mode_set = mode_set.ok_or_else(|| ReduceFileError::NoModeSet { file: file.clone() })?;
    let basis = request.basis.or(loaded.defaults.basis).unwrap_or_default();
    let settings = ReductionSettings { mode_set, basis, eigen: request.eigen };
    let started = Instant::now();
    let mut reduction =
        reduce(&loaded.model, &loaded.name, &settings).map_err(|source| ReduceFileError::Reduction { file: file.clone(), source })?;
    if request.stresses.or(loaded.defaults.stresses) == Some(true) {
        let warning = add_modal_stresses(&loaded.model, &mut reduction.body)
            .map_err(|source| ReduceFileError::Reduction { file, source })?;
        reduction.warnings.extend(warning);
    }
    Ok(ReducedFeModel { loaded, reduction, seconds: started.elapsed().as_secs_f64() })
}
