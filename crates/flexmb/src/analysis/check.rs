//! The check of a model before a run (`flexmb check`, the Python package's `Model.check`): assembly of
//! its initial positions, with the redundant constraints found and removed, and the velocity analysis.

use crate::analysis::{assemble, velocity_analysis, AssemblyError, AssemblyReport, AssemblySettings, State, VelocityReport};
use crate::{Data, Model};

/// What checking a model found: degrees of freedom and redundant constraints (the assembly), and the
/// initial velocities made consistent (the velocity analysis).
#[derive(Clone, Debug)]
pub struct CheckReport {
    /// The assembly of the initial positions.
    pub assembly: AssemblyReport,
    /// The velocity analysis at the assembled positions.
    pub velocity: VelocityReport,
}

/// Assembles the model's initial state with `settings` and runs the velocity analysis, as a
/// simulation starts.
///
/// ```
/// use flexmb::analysis::{check_model, test_models::double_pendulum_with_spring};
///
/// // A spherical joint (3 degrees of freedom) and a revolute one (1).
/// let model = double_pendulum_with_spring();
/// let report = check_model(&model, Default::default()).unwrap();
/// assert_eq!(report.assembly.degrees_of_freedom, 4);
/// assert!(report.assembly.redundant.is_empty());
/// ```
pub fn check_model(model: &Model, settings: AssemblySettings) -> Result<CheckReport, AssemblyError> {
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    let assembly = assemble(model, &mut data, &mut state, settings)?;
    let velocity = velocity_analysis(model, &mut data, &mut state)?;
    Ok(CheckReport { assembly, velocity })
}
