//! Kinetic energy and momenta of a body from its block of the mass matrix (formulation.md §3): the
//! generalized momentum `π = M v` of body coordinates `v = [Ṙ, ω̄, ȧ]` holds the linear momentum
//! `L = ∫ ṙ dm` (rows `Ṙ`, global) and the angular momentum about the body's origin in body axes
//! `H̄_O = ∫ r̄ × Aᵀ ṙ dm` (rows `ω̄`), because `∂ṙ/∂Ṙ = I` and `∂ṙ/∂ω̄ = −A r̄̃`. The flexible body's
//! elastic motion is in both through the invariants of its mass matrix, and `T = ½ vᵀ π`.

use crate::data::Data;
use crate::math::Vec3;
use crate::model::Model;
use crate::stage::body_mass_entries;

/// A body's kinetic energy and momenta.
pub(super) struct BodyMomentum {
    /// `½ vᵀ M v` (J).
    pub kinetic_energy: f64,
    /// `L` (N s), global.
    pub linear: Vec3,
    /// Angular momentum about the global origin (N m s), global: `R × L + A H̄_O`.
    pub angular_about_origin: Vec3,
    /// Angular momentum about the centre of mass (N m s), global: `A H̄_O − (A S̄ / m) × L`.
    pub angular_about_center_of_mass: Vec3,
}

/// The kinetic energy and momenta of body `b` at the state of the last kinematics stage.
pub(super) fn body_momentum(model: &Model, data: &Data, q: &[f64], v: &[f64], b: usize) -> BodyMomentum {
    let (qo, vo) = (model.layout.q_offset[b], model.layout.v_offset[b]);
    let mut linear = Vec3::zeros();
    let mut h_bar = Vec3::zeros();
    let mut twice_kinetic = 0.0;
    body_mass_entries(model, data, b, |r, c, m| {
        let pi = m * v[vo + c];
        twice_kinetic += v[vo + r] * pi;
        match r {
            0..=2 => linear[r] += pi,
            3..=5 => h_bar[r - 3] += pi,
            _ => {}
        }
    });
    let a = data.bodies[b].rotation;
    let first_moment = match &model.modal[b] {
        Some(_) => data.modal[b].first_moment,
        None => model.bodies[b].first_moment(),
    };
    let h_origin = a * h_bar;
    let center_offset = a * first_moment / model.bodies[b].mass;
    let r = Vec3::from_column_slice(&q[qo..qo + 3]);
    BodyMomentum {
        kinetic_energy: 0.5 * twice_kinetic,
        linear,
        angular_about_origin: r.cross(&linear) + h_origin,
        angular_about_center_of_mass: h_origin - center_offset.cross(&linear),
    }
}
