//! From the parsed file to a [`Model`](flexmb::Model): parameters first, then bodies, flexible bodies,
//! markers, joints, drivers, all measures, forces (whose expressions read measures) and outputs, each
//! validated with the key and line it came from; last the engine's own validation.

mod bodies;
pub(crate) mod body_cache;
pub(crate) mod context;
mod drivers;
mod engine_errors;
pub(crate) mod flexible_bodies;
mod forces;
mod inertia;
mod joints;
mod markers;
mod measures;
pub(crate) mod names;
mod nodes;
mod orientation;
mod outputs;
pub(crate) mod reduction_lock;
mod shapes;
mod simulation;

use std::path::Path;

use flexmb::model::{BodyId, ForceId, JointId, MarkerId, MeasureId};
use flexmb::ModelBuilder;

use self::context::Context;
use self::flexible_bodies::FlexibleTables;
use self::names::NameTable;
use self::nodes::FlexibleNodes;
use super::error::ModelFileError;
use super::schema::ModelFile;
use super::source::Source;
use super::{parameters, LoadedModel};

/// The names of every kind of element.
pub(crate) struct Names {
    pub bodies: NameTable<BodyId>,
    pub markers: NameTable<MarkerId>,
    /// Joints and drivers (a driver is a joint of the engine).
    pub joints: NameTable<JointId>,
    pub measures: NameTable<MeasureId>,
    pub forces: NameTable<ForceId>,
    pub outputs: NameTable<usize>,
}

impl Default for Names {
    fn default() -> Self {
        Self {
            bodies: NameTable::new("body"),
            markers: NameTable::new("marker"),
            joints: NameTable::new("joint"),
            measures: NameTable::new("measure"),
            forces: NameTable::new("force"),
            outputs: NameTable::new("output"),
        }
    }
}

/// Builds the model a parsed file describes; `default_name` is used when `[model]` has no name, and
/// the paths of flexible bodies' files are relative to `base_dir`; the mode analysis of a flexible body
/// reduced now may use `memory_limit` bytes.
pub(crate) fn build(
    file: &ModelFile,
    source: &Source,
    default_name: &str,
    base_dir: &Path,
    memory_limit: Option<u64>,
) -> Result<LoadedModel, ModelFileError> {
    let parameters = parameters::evaluate(&file.parameters, source)?;
    let declared_measures = file.measure.iter().map(|m| m.get_ref().name.get_ref().clone()).collect();
    let parameter_values = parameters.clone();
    let mut ctx = Context::new(source, parameters, declared_measures);
    let (name, gravity) = simulation::model_settings(&ctx, file, default_name)?;
    let simulation = simulation::simulation_defaults(&ctx, file.simulation.as_ref())?;
    let mut builder = ModelBuilder::new(name).gravity(gravity);
    let mut names = Names::default();
    let shapes = bodies::add_bodies(&ctx, &file.body, base_dir, &mut builder, &mut names.bodies)?;
    let mut flexible = FlexibleNodes::default();
    let tables = FlexibleTables { sections: &file.flexible_body, base_dir, memory_limit };
    let flexible_bodies =
        flexible_bodies::add_flexible_bodies(&ctx, &tables, &mut builder, &mut names.bodies, &mut flexible)?;
    markers::add_markers(&ctx, &file.marker, &names.bodies, &flexible, &mut builder, &mut names.markers)?;
    joints::add_joints(&ctx, &file.joint, &names.bodies, &names.markers, &mut builder, &mut names.joints)?;
    drivers::add_drivers(&ctx, &file.driver, &mut builder, &mut names.joints)?;
    measures::add_measures(&mut ctx, &file.measure, &names.joints, &names.markers, &mut builder, &mut names.measures)?;
    let force_references = forces::ForceReferences { joints: &names.joints, markers: &names.markers };
    forces::add_forces(&ctx, &file.force, &force_references, &mut builder, &mut names.forces)?;
    let output_references = outputs::OutputReferences {
        markers: &names.markers,
        joints: &names.joints,
        measures: &names.measures,
        bodies: &names.bodies,
        flexible: &flexible,
    };
    outputs::add_outputs(&ctx, &file.output, &output_references, &mut builder, &mut names.outputs)?;
    let model = builder.build().map_err(|e| engine_errors::locate(&e, &names, source))?;
    Ok(LoadedModel { model: std::sync::Arc::new(model), simulation, parameters: parameter_values, flexible_bodies, shapes })
}
