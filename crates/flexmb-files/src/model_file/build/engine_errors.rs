//! Errors that `ModelBuilder::build` still finds after the file layer's own checks, placed at the key
//! of the element they name.

use std::ops::Range;

use flexmb::model::ModelError;

use super::Names;
use crate::model_file::error::ModelFileError;
use crate::model_file::key_path::KeyPath;
use crate::model_file::source::Source;

pub(crate) fn locate(error: &ModelError, names: &Names, source: &Source) -> ModelFileError {
    let (kind, name) = element_of(error);
    let definition = match kind {
        "body" => names.bodies.definition(&name).map(|d| (d.element.clone(), d.span.clone())),
        "marker" => names.markers.definition(&name).map(|d| (d.element.clone(), d.span.clone())),
        "joint" => names.joints.definition(&name).map(|d| (d.element.clone(), d.span.clone())),
        "force" => names.forces.definition(&name).map(|d| (d.element.clone(), d.span.clone())),
        "measure" => names.measures.definition(&name).map(|d| (d.element.clone(), d.span.clone())),
        "output" => names.outputs.definition(&name).map(|d| (d.element.clone(), d.span.clone())),
        _ => None,
    };
    let (key, span) = definition.unwrap_or((KeyPath::root(), 0..0));
    source.invalid(&span, &key, error.to_string())
}

/// Places an engine error about the element being added at `span` (its name) and its key `element`,
/// as [`locate`] does for the elements already defined.
pub(crate) fn at<'a>(source: &'a Source, span: &'a Range<usize>, element: &'a KeyPath) -> impl Fn(ModelError) -> ModelFileError + 'a {
    move |error| source.invalid(span, element, error.to_string())
}

/// The kind and name of the element an engine error concerns.
fn element_of(error: &ModelError) -> (&'static str, String) {
    match error {
        ModelError::DuplicateName { kind, name } => (kind, name.clone()),
        ModelError::NonPositiveMass { body, .. } | ModelError::BadInertia { body, .. } => ("body", body.clone()),
        ModelError::BadFrame { what, .. } => {
            let name = what.split('\'').nth(1).unwrap_or_default().to_string();
            (if what.starts_with("marker") { "marker" } else { "body" }, name)
        }
        ModelError::JointOnOneBody { joint, .. } => ("joint", joint.clone()),
        ModelError::WrongJointKind { element, name, .. }
        | ModelError::UnknownId { element, name, .. }
        | ModelError::Expression { element, name, .. }
        | ModelError::BadValue { element, name, .. } => (element_kind(element), name.clone()),
    }
}

/// The engine names some elements by description ("rotational spring-damper"); map to the table.
fn element_kind(element: &str) -> &'static str {
    match element {
        "body" => "body",
        "marker" => "marker",
        "joint" => "joint",
        "measure" => "measure",
        "output" => "output",
        _ => "force",
    }
}
