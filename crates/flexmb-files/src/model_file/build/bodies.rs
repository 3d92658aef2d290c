//! `[[body]]` → [`RigidBody`], each checked at once by the engine's own rules so that a problem is
//! reported at the body's key.

use std::path::Path;

use flexmb::body::{InitialState, RigidBody};
use flexmb::math::EulerParameters;
use flexmb::model::{BodyId, ModelError};
use flexmb::ModelBuilder;
use flexmb_fem::input::Quantity;
use toml::Spanned;

use super::context::Context;
use super::engine_errors;
use super::inertia::inertia;
use super::names::NameTable;
use super::orientation::orientation;
use super::shapes::body_shape;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::schema::{BodySection, OrientationSection, Vector};
use crate::shape::BodyShape;

/// The name markers use for the inertial frame.
pub(crate) const GROUND: &str = "ground";

/// Adds every `[[body]]` and returns their shapes; mesh files are relative to `base_dir`.
pub(crate) fn add_bodies(
    ctx: &Context,
    sections: &[Spanned<BodySection>],
    base_dir: &Path,
    builder: &mut ModelBuilder,
    names: &mut NameTable<BodyId>,
) -> Result<Vec<BodyShape>, ModelFileError> {
    let mut shapes = Vec::with_capacity(sections.len());
    for (index, section) in sections.iter().enumerate() {
        let element = KeyPath::root().key("body").index(index);
        let b = section.get_ref();
        names.check_new(&b.name, &element, ctx.source)?;
        if b.name.get_ref() == GROUND {
            return Err(ctx.invalid(
                &b.name.span(),
                &element.key("name"),
                "`ground` is the inertial frame and cannot name a body",
            ));
        }
        let body = rigid_body(ctx, b, &element)?;
        check_with_engine(ctx, &body, b, &element)?;
        let shape = body_shape(ctx, b.shape.as_ref(), &element.key("shape"), base_dir, &body)?;
        let id = builder.add_body(body).map_err(engine_errors::at(ctx.source, &b.name.span(), &element))?;
        names.define(&b.name, &element, id);
        shapes.push(BodyShape { body: id, shape });
    }
    Ok(shapes)
}

fn rigid_body(ctx: &Context, b: &BodySection, element: &KeyPath) -> Result<RigidBody, ModelFileError> {
    let mass = ctx.quantity(&b.mass, &element.key("mass"), Quantity::Mass)?;
    if mass <= 0.0 {
        return Err(ctx.invalid(
            &b.mass.span(),
            &element.key("mass"),
            format!("mass must be positive and finite, got {mass}"),
        ));
    }
    let keys = InitialKeys {
        position: &b.position,
        orientation: &b.orientation,
        velocity: &b.velocity,
        angular_velocity: &b.angular_velocity,
    };
    Ok(RigidBody {
        name: b.name.get_ref().clone(),
        mass,
        center_of_mass: ctx.vector_or_zero(&b.center_of_mass, &element.key("center_of_mass"), Quantity::Length)?,
        inertia: inertia(ctx, &b.inertia, &element.key("inertia"))?,
        initial: initial_state(ctx, &keys, element)?,
    })
}

/// The keys of a body table that give its initial pose and velocity.
pub(crate) struct InitialKeys<'a> {
    pub position: &'a Option<Vector>,
    pub orientation: &'a Option<Spanned<OrientationSection>>,
    pub velocity: &'a Option<Vector>,
    pub angular_velocity: &'a Option<Vector>,
}

/// The initial state of a body frame (rigid or flexible): position and orientation (default: the
/// global frame), and the velocities if given.
pub(crate) fn initial_state(
    ctx: &Context,
    keys: &InitialKeys,
    element: &KeyPath,
) -> Result<InitialState, ModelFileError> {
    let orientation = match keys.orientation {
        Some(o) => orientation(ctx, o, &element.key("orientation"))?,
        None => EulerParameters::identity(),
    };
    Ok(InitialState {
        position: ctx.vector_or_zero(keys.position, &element.key("position"), Quantity::Length)?,
        orientation,
        velocity: ctx.optional_vector(keys.velocity, &element.key("velocity"), Quantity::Velocity)?,
        angular_velocity: ctx.optional_vector(
            keys.angular_velocity,
            &element.key("angular_velocity"),
            Quantity::AngularVelocity,
        )?,
    })
}

/// Runs the engine's body checks (mass, physical inertia, proper orientation, finite values) on this
/// body alone.
fn check_with_engine(
    ctx: &Context,
    body: &RigidBody,
    b: &BodySection,
    element: &KeyPath,
) -> Result<(), ModelFileError> {
    let Err(error) = ModelBuilder::new("body check").add_body(body.clone()) else { return Ok(()) };
    let (span, key, message) = match &error {
        ModelError::NonPositiveMass { mass, .. } => {
            (b.mass.span(), element.key("mass"), format!("mass must be positive and finite, got {mass}"))
        }
        ModelError::BadInertia { problem, .. } => {
            (b.inertia.span(), element.key("inertia"), format!("inertia {problem}"))
        }
        ModelError::BadFrame { problem, .. } => match &b.orientation {
            Some(o) => (o.span(), element.key("orientation"), problem.clone()),
            None => (b.name.span(), element.clone(), problem.clone()),
        },
        other => (b.name.span(), element.clone(), other.to_string()),
    };
    Err(ctx.invalid(&span, &key, message))
}
