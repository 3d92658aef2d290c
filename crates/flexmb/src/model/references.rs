//! The ids an element refers to, checked against what the builder holds when it is added: an id the
//! builder did not hand out is an error that names the element, never a panic later.

use super::{BodyId, BodyRef, JointId, MarkerId, MeasureId, ModelError, OutputAxes, OutputKind, ParameterId, RotatingFrame};
use crate::force::ForceKind;
use crate::measure::MeasureKind;

/// An id an element refers to.
#[derive(Clone, Copy, Debug)]
pub(super) enum Reference {
    Body(BodyId),
    Marker(MarkerId),
    Joint(JointId),
    Measure(MeasureId),
    Parameter(ParameterId),
}

/// How many elements of each kind the builder holds.
#[derive(Clone, Copy, Debug)]
pub(super) struct Counts {
    pub bodies: usize,
    pub markers: usize,
    pub joints: usize,
    pub measures: usize,
    pub parameters: usize,
}

impl Counts {
    /// `Ok` if the builder handed out `reference`; otherwise the error that names `element` `name`.
    pub(super) fn check(&self, element: &'static str, name: &str, reference: Reference) -> Result<(), ModelError> {
        let (kind, index, count) = match reference {
            Reference::Body(id) => ("body", id.0, self.bodies),
            Reference::Marker(id) => ("marker", id.0, self.markers),
            Reference::Joint(id) => ("joint", id.0, self.joints),
            Reference::Measure(id) => ("measure", id.0, self.measures),
            Reference::Parameter(id) => ("parameter", id.0, self.parameters),
        };
        if index < count {
            Ok(())
        } else {
            Err(ModelError::UnknownId { element, name: name.to_string(), kind, index, count })
        }
    }

    /// Checks every reference of one element.
    pub(super) fn check_all(
        &self,
        element: &'static str,
        name: &str,
        references: impl IntoIterator<Item = Reference>,
    ) -> Result<(), ModelError> {
        references.into_iter().try_for_each(|r| self.check(element, name, r))
    }
}

/// The body a marker is fixed on (none for ground).
pub(super) fn of_body_ref(body: BodyRef) -> Vec<Reference> {
    body.body().map(Reference::Body).into_iter().collect()
}

/// The markers, joints and measures (in its expressions) a force element refers to.
pub(super) fn of_force(kind: &ForceKind) -> Vec<Reference> {
    let mut refs = match kind {
        ForceKind::TranslationalSpringDamper { marker_i, marker_j, .. } => {
            vec![Reference::Marker(*marker_i), Reference::Marker(*marker_j)]
        }
        ForceKind::RotationalSpringDamper { joint, .. } => vec![Reference::Joint(*joint)],
        ForceKind::AppliedForce { marker, .. } | ForceKind::AppliedTorque { marker, .. } => {
            vec![Reference::Marker(*marker)]
        }
    };
    refs.extend(kind.expressions().into_iter().flat_map(|e| e.measures()).map(Reference::Measure));
    refs
}

/// The joint or markers a measure reads.
pub(super) fn of_measure(kind: &MeasureKind) -> Vec<Reference> {
    match *kind {
        MeasureKind::JointAngle(j)
        | MeasureKind::JointRate(j)
        | MeasureKind::JointDisplacement(j)
        | MeasureKind::JointVelocity(j) => vec![Reference::Joint(j)],
        MeasureKind::Distance(a, b) | MeasureKind::DistanceRate(a, b) => {
            vec![Reference::Marker(a), Reference::Marker(b)]
        }
        MeasureKind::Position(m, _) | MeasureKind::Velocity(m, _) | MeasureKind::Speed(m) => {
            vec![Reference::Marker(m)]
        }
        MeasureKind::Parameter(p) => vec![Reference::Parameter(p)],
    }
}

/// The marker, joint, measure or body an output reports.
pub(super) fn of_output(kind: &OutputKind) -> Vec<Reference> {
    match *kind {
        OutputKind::MarkerPosition(m)
        | OutputKind::MarkerVelocity(m)
        | OutputKind::MarkerAcceleration(m)
        | OutputKind::MarkerAngularVelocity(m) => vec![Reference::Marker(m)],
        OutputKind::JointReaction(j) => vec![Reference::Joint(j)],
        OutputKind::Measure(m) => vec![Reference::Measure(m)],
        OutputKind::ModalCoordinates(b)
        | OutputKind::NodePosition(b, _)
        | OutputKind::NodeVelocity(b, _)
        | OutputKind::NodeAcceleration(b, _)
        | OutputKind::NodeDeformation(b, _)
        | OutputKind::StrainEnergy(b) => vec![Reference::Body(b)],
        OutputKind::JointReactionIn(j, m) => vec![Reference::Joint(j), Reference::Marker(m)],
        OutputKind::JointMultipliers(j) | OutputKind::JointCoordinates(j, _) => vec![Reference::Joint(j)],
        OutputKind::Orientation(frame, _) => of_frame(frame),
        OutputKind::AngularVelocity(frame, axes) | OutputKind::AngularAcceleration(frame, axes) => {
            let mut refs = of_frame(frame);
            if let OutputAxes::Marker(m) = axes {
                refs.push(Reference::Marker(m));
            }
            refs
        }
        OutputKind::KineticEnergy(b)
        | OutputKind::LinearMomentum(b)
        | OutputKind::AngularMomentum(b)
        | OutputKind::EulerParameterNormError(Some(b)) => vec![Reference::Body(b)],
        OutputKind::Energy
        | OutputKind::ConstraintResidual
        | OutputKind::SystemMomentum
        | OutputKind::EulerParameterNormError(None)
        | OutputKind::UserExpression(_) => Vec::new(),
    }
}

fn of_frame(frame: RotatingFrame) -> Vec<Reference> {
    match frame {
        RotatingFrame::Body(b) => vec![Reference::Body(b)],
        RotatingFrame::Marker(m) => vec![Reference::Marker(m)],
    }
}
