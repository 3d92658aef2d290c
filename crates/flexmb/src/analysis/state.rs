//! A mechanism state: positions, velocities, and the set of constraint rows in force.

use crate::math::Vec3;
use crate::model::Model;

/// Positions `q`, velocities `v` and the constraint rows in force (redundant rows are switched off).
#[derive(Clone, Debug)]
pub struct State {
    /// Time (s).
    pub t: f64,
    /// Positions, per body `R, p, a`.
    pub q: Vec<f64>,
    /// Velocities, per body `Ṙ, ω̄, ȧ`.
    pub v: Vec<f64>,
    /// `false` for a constraint row found redundant: its multiplier is held at zero.
    pub active: Vec<bool>,
}

impl State {
    /// The initial state written in the model (before assembly): poses, the given velocities (zero
    /// where none is given), and the initial modal coordinates and rates of flexible bodies.
    pub fn initial(model: &Model) -> Self {
        let l = &model.layout;
        let mut q = vec![0.0; l.nq];
        let mut v = vec![0.0; l.nv];
        for (b, body) in model.bodies.iter().enumerate() {
            let (qo, vo) = (l.q_offset[b], l.v_offset[b]);
            let init = &body.initial;
            q[qo..qo + 3].copy_from_slice(init.position.as_slice());
            let p = init.orientation.normalized();
            q[qo + 3..qo + 7].copy_from_slice(p.as_slice());
            let vel = init.velocity.unwrap_or_else(Vec3::zeros);
            v[vo..vo + 3].copy_from_slice(vel.as_slice());
            let w_bar = init.orientation.rotation_matrix().transpose() * init.angular_velocity.unwrap_or_else(Vec3::zeros);
            v[vo + 3..vo + 6].copy_from_slice(w_bar.as_slice());
            if let Some(modal) = &model.modal[b] {
                let m = modal.modes();
                q[qo + 7..qo + 7 + m].copy_from_slice(modal.initial_coordinates.as_slice());
                v[vo + 6..vo + 6 + m].copy_from_slice(modal.initial_rates.as_slice());
            }
        }
        Self { t: 0.0, q, v, active: vec![true; l.nc] }
    }
}
