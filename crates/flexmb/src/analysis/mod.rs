//! Analyses of a model: the check before a run (`check_model`), redundancy check, assembly (position analysis), velocity analysis,
//! accelerations and reaction forces, the linearized equations of motion (also in independent
//! coordinates, at an operating point), eigen-analysis, and the dynamic simulation.

mod accelerations;
mod assembly;
mod check;
mod equilibrium;
mod eigen_analysis;
mod linearization;
mod massless_motions;
mod memory;
mod mode_tracking;
mod operating_point;
mod outputs;
mod redundancy;
mod redundancy_reference;
mod simulation;
mod static_deformation;
mod state;
mod state_space;
mod velocity;
mod watchdog;
#[cfg(test)]
mod watchdog_tests;
#[doc(hidden)]
pub mod test_models;

pub use accelerations::{AccelerationError, AccelerationSolver, Accelerations};
pub use assembly::{assemble, AssemblyError, AssemblyReport, AssemblySettings, ModalAssembly};
pub use check::{check_model, CheckReport};
pub(crate) use massless_motions::massless_gauges;
pub use equilibrium::{
    equilibrium_outputs, joint_reactions, static_equilibrium, BodyMotion, EquilibriumError, EquilibriumFallback, EquilibriumIteration, EquilibriumMethod,
    EquilibriumReport, EquilibriumSettings, FreeMotion, JointReaction, ReactionSide,
};
pub use eigen_analysis::{eigen_analysis, state_matrix, EigenAnalysis, EigenAnalysisError, Mode, Spin, Whirl};
pub use linearization::{
    displaced_positions, driver_inputs, linearize, reduce_to_independent, DriverInputs, IndependentCoordinates, Linearization, OperatingPoint, ReducedLinearization,
    SparseLinearization,
};
pub use mode_tracking::{modal_assurance, track_modes};
pub use operating_point::{linear_model, operating_point, LinearModel, LinearizationPoint, OperatingPointChoice, OperatingPointError};
pub(crate) use linearization::linearize_at;
pub use outputs::{columns_of_output, output_columns, position_output_columns, ColumnSources, OutputColumn};
pub use memory::{analysis_bytes, format_bytes, MemoryLimit};
pub(crate) use redundancy::{dependency_of, newly_dependent_rows, violated_rows};
pub use redundancy::{RedundantConstraint, ViolatedEquation};
#[doc(hidden)]
pub use redundancy::redundant_rows;
#[doc(hidden)]
pub use redundancy_reference::gram_schmidt_redundant_rows;
pub use simulation::{
    attainable_by_method, global_error_rerun, run_under_global_error_control, simulate, simulate_interruptible, ControlledRun, GlobalErrorControl, GlobalErrorEstimate, GlobalErrorNorm, Interruption, MAX_RERUNS, OutputFrame, OutputSink, OutputTable, Simulation, SimulationCheckpoint,
    SimulationError, SimulationFailure, SimulationReport, SimulationSettings, Start, StateProjection, WorkAtStep, CHECKPOINT_VERSION,
};
pub use state::State;
pub use state_space::{state_space, StateSpace};
pub use velocity::{velocity_analysis, VelocityReport};
pub use watchdog::{
    Balance, Deflection, PhysicsLimits, PhysicsMeasures, SimulationWarning, Unphysical, WarningKind, WatchdogCheckpoint,
};
