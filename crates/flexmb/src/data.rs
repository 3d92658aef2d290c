//! The scratch pad of a model: everything the stages compute from a state, allocated once.

use crate::joint::EquationTerms;
use crate::math::{Mat3, Vec3};
use crate::model::Model;
use crate::stage::{BodyState, MarkerState, ModalState};

/// Per-evaluation scratch data. Each field says which stage fills it.
#[derive(Clone, Debug)]
pub struct Data {
    /// Rotation and angular velocity of each body (kinematics).
    pub(crate) bodies: Vec<BodyState>,
    /// Modal coordinates and invariant expansions of each body (kinematics; empty for rigid bodies).
    pub(crate) modal: Vec<ModalState>,
    /// Global kinematics of each marker (kinematics).
    pub(crate) markers: Vec<MarkerState>,
    /// Current value of each named measure (measures).
    pub(crate) measures: Vec<f64>,
    /// Current value of each parameter of the model (set by the simulation's owner; initially the
    /// model's values).
    pub(crate) parameters: Vec<f64>,
    /// Last accepted relative angle of each joint, for continuing angles past ±π (kept by the analyses).
    pub(crate) angle_reference: Vec<f64>,
    /// Value and derivatives of each constraint row (constraints).
    pub(crate) equations: Vec<EquationTerms>,
    /// Generalized applied forces `Q`, length `nv` (forces).
    pub(crate) applied: Vec<f64>,
    /// The force elements' part of the interface geometric stiffening `K_G a` (modal rows; length
    /// `nv`, included in `applied` with the opposite sign), for the energy balance (forces).
    pub(crate) interface_stiffening: Vec<f64>,
    /// Inertia forces `M v̇ + h(q, v)`, length `nv` (inertia).
    pub(crate) inertia: Vec<f64>,
    /// `Φ_qᵀ`-times-vector scratch, length `nv` (residual).
    pub(crate) scratch_v: Vec<f64>,
}

impl Data {
    /// Scratch data sized for `model`.
    pub fn new(model: &Model) -> Self {
        let nv = model.layout.nv;
        Self {
            bodies: vec![BodyState::default(); model.bodies.len()],
            modal: (0..model.bodies.len())
                .map(|b| {
                    let cases = model.modal[b].as_ref().and_then(|m| m.geometric_stiffness.as_ref()).map_or(0, |g| g.case_count());
                    ModalState::new(model.layout.modes[b], cases)
                })
                .collect(),
            markers: vec![MarkerState::default(); model.markers.len()],
            measures: vec![0.0; model.measures.len()],
            parameters: model.parameters.iter().map(|p| p.value).collect(),
            angle_reference: vec![0.0; model.joints.len()],
            equations: vec![EquationTerms::default(); model.layout.nc],
            applied: vec![0.0; nv],
            interface_stiffening: vec![0.0; nv],
            inertia: vec![0.0; nv],
            scratch_v: vec![0.0; nv],
        }
    }

    /// Global position of a marker origin after the last kinematics stage; `None` if `m` is not a marker
    /// of the model this data was made for.
    pub fn marker_position(&self, m: crate::model::MarkerId) -> Option<Vec3> {
        self.markers.get(m.0).map(|marker| marker.position)
    }

    /// Global axes of a marker (columns x, y, z) after the last kinematics stage; `None` if `m` is not a
    /// marker of the model this data was made for.
    pub fn marker_axes(&self, m: crate::model::MarkerId) -> Option<Mat3> {
        self.markers.get(m.0).map(|marker| marker.axes)
    }

    /// Current value of each measure after the last measures stage.
    pub fn measure_values(&self) -> &[f64] {
        &self.measures
    }

    /// Generalized applied forces `Q(q, v, t)` (length `nv`) after the last force stages.
    pub fn applied_forces(&self) -> &[f64] {
        &self.applied
    }

    /// Inertia forces `M(q) v̇ + h(q, v)` (length `nv`) after the last force stages.
    pub fn inertia_forces(&self) -> &[f64] {
        &self.inertia
    }
}
