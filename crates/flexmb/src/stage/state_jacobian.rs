//! The derivatives of the DAE residual ([`residual`](super::residual)) with respect to the positions and
//! velocities of a rigid body, analytic, for a body that only gravity and point and dot-1 constraints act
//! on (the spherical, revolute and universal joints). With `A = A(p/|p|)`, `S̄` the body's first moment,
//! `J̄` its inertia about the frame origin, `s̄` a constraint marker's origin in the body, `d = ±e_k` the
//! marker's coefficient in point row `k`:
//!
//! ```text
//! F_R = Ṙ − Ṙ − Σ μ d                         ∂/∂Ṙ = −I
//! F_p = ṗ − ½ Gᵀ(p) ω̄ − 2 Gᵀ(p) μ̄_ω − 2 μ_n p  μ̄_ω = Σ μ B_ω̄ᵀ; ∂/∂ω̄ = −½ Gᵀ(p)
//! F_Ṙ = m R̈ − A (S̄ × ω̄̇) + A (ω̄ × (ω̄ × S̄)) − m g + Σ λ d
//! F_ω̄ = S̄ × (Aᵀ (R̈ − g)) + J̄ ω̄̇ + ω̄ × (J̄ ω̄) + Σ λ B_ω̄ᵀ
//! point row:  F_λ = d · (Ṙ + A (ω̄ × s̄)),   F_μ = d · (R + A s̄),   B_ω̄ = (s̄ × Aᵀ d)ᵀ
//! dot-1 row:  F_λ = c · (ω − ω_o),          F_μ = a · a_o,          B_ω̄ = (Aᵀ c)ᵀ,  c = a × a_o
//! F_n = pᵀp − 1
//! ```
//! with `a = A ā` the body's axis of a dot-1 row and `a_o`, `ω_o` the other marker's axis and angular
//! velocity, differentiated in `p` through `∂A/∂p` (of the normalized parameters,
//! [`rotation_derivatives`]) and in `ω̄` through `∂(ω̄ × (ω̄ × S̄))/∂ω̄ = −(ω̄ × S̄)~ − ω̄̃ S̄̃` and
//! `∂(ω̄ × J̄ ω̄)/∂ω̄ = ω̄̃ J̄ − (J̄ ω̄)~`. A dot-1 row's `c` depends on both bodies, so a body's column also
//! holds the other body's constraint-force terms `−λ A_oᵀ ∂c/∂p` (dynamic rows) and
//! `2 Gᵀ(p_o) μ A_oᵀ ∂c/∂p` (kinematic rows). Every entry of a body's columns is thereby analytic whatever
//! its neighbours are; every other body's columns stay finite differences.

use crate::data::Data;
use crate::joint::Equation;
use crate::math::euler_parameters::g_matrix;
use crate::math::{skew, Mat3, Vec3, Vec4};
use crate::model::{bodies_under_force_elements, Model};
use crate::stage::YLayout;

/// One side of a constraint row on an analytic body.
#[derive(Clone, Copy, Debug)]
enum Side {
    /// Point row `k`: the coefficient `d = sign · e_k` and the marker's origin `s̄` in the body.
    Point { row: usize, k: usize, sign: f64, origin: Vec3 },
    /// Dot-1 row `a_iᵀ a_j`: the body's axis `ā` in its frame, the other marker, its axis and its body.
    Dot1 { row: usize, axis: Vec3, other_marker: usize, other_axis: usize, other_body: Option<usize> },
}

/// A body whose positions' and velocities' columns are analytic, and the constraint rows acting on it.
#[derive(Clone, Debug)]
struct AnalyticBody {
    body: usize,
    sides: Vec<Side>,
}

/// The analytic columns of the positions and velocities of the bodies that allow them.
#[derive(Clone, Debug)]
pub(crate) struct StateJacobian {
    bodies: Vec<AnalyticBody>,
    analytic: Vec<bool>,
}

impl StateJacobian {
    /// The rigid bodies that no force element acts on or reads and whose every joint is made of point
    /// and dot-1 equations (spherical, revolute, universal joints).
    pub fn new(model: &Model) -> Self {
        let under = bodies_under_force_elements(model);
        let mut analytic: Vec<bool> = (0..model.bodies.len()).map(|b| model.modal[b].is_none() && !under[b]).collect();
        let mut sides: Vec<Vec<Side>> = vec![Vec::new(); model.bodies.len()];
        for (row, &(j, eq)) in model.layout.equations.iter().enumerate() {
            let joint = &model.joints[j.0];
            let ends = [(joint.marker_i, joint.marker_j, -1.0), (joint.marker_j, joint.marker_i, 1.0)];
            for (own, other, point_sign) in ends {
                let m = &model.markers[own.0];
                let Some(b) = m.body.body() else { continue };
                let other_body = model.markers[other.0].body.body().map(|o| o.0);
                let side = match eq {
                    Equation::Point(k) => Side::Point { row, k, sign: point_sign, origin: m.origin },
                    Equation::Dot1(axis_i, axis_j) => {
                        let (own_axis, other_axis) = if own == joint.marker_i { (axis_i, axis_j) } else { (axis_j, axis_i) };
                        Side::Dot1 {
                            row,
                            axis: m.axes.column(own_axis.index()).into(),
                            other_marker: other.0,
                            other_axis: other_axis.index(),
                            other_body,
                        }
                    }
                    _ => {
                        analytic[b.0] = false;
                        continue;
                    }
                };
                sides[b.0].push(side);
            }
        }
        let bodies = sides
            .into_iter()
            .enumerate()
            .filter(|&(b, _)| analytic[b])
            .map(|(body, sides)| AnalyticBody { body, sides })
            .collect();
        Self { bodies, analytic }
    }

    /// Whether body `b`'s positions' and velocities' columns are analytic.
    pub fn is_analytic(&self, b: usize) -> bool {
        self.analytic[b]
    }

    /// Calls `f(row, column, value)` (indices into `y = [q, v, λ, μ]` of `yl`) for every entry of the
    /// analytic bodies' positions' and velocities' columns of `∂F/∂y` at `(y, ẏ)`, whose kinematic stages
    /// `data` holds, with the constraint rows in force `active`. Each `(row, column)` may come more than
    /// once: callers add the values.
    #[allow(clippy::too_many_arguments)]
    pub fn entries(
        &self,
        model: &Model,
        data: &Data,
        yl: &YLayout,
        y: &[f64],
        yp: &[f64],
        active: &[bool],
        mut f: impl FnMut(usize, usize, f64),
    ) {
        let l = &model.layout;
        let (lambda, mu) = (&y[yl.lambda.clone()], &y[yl.mu.clone()]);
        for AnalyticBody { body: b, sides } in &self.bodies {
            let b = *b;
            let body = &model.bodies[b];
            let (qo, vo) = (yl.q.start + l.q_offset[b], yl.v.start + l.v_offset[b]);
            let p = Vec4::new(y[qo + 3], y[qo + 4], y[qo + 5], y[qo + 6]);
            let state = &data.bodies[b];
            let (a, w) = (state.rotation, state.omega_bar);
            let da = rotation_derivatives(&p);
            let rdd = Vec3::new(yp[vo], yp[vo + 1], yp[vo + 2]);
            let wd = Vec3::new(yp[vo + 3], yp[vo + 4], yp[vo + 5]);
            let (s, j) = (body.first_moment(), body.inertia_about_origin());

            // Constraint rows, and the constraint forces' terms of the dynamic and kinematic rows.
            let mut mu_w = Vec3::zeros();
            let mut d_mu_w = [Vec3::zeros(); 4];
            let mut d_lambda_w = [Vec3::zeros(); 4];
            for side in sides {
                match *side {
                    Side::Point { row, k, sign, origin } => {
                        let d = Vec3::ith(k, sign);
                        let turned = origin.cross(&(a.transpose() * d));
                        mu_w += mu[row] * turned;
                        for i in 0..4 {
                            let turned = origin.cross(&(da[i].transpose() * d));
                            d_mu_w[i] += mu[row] * turned;
                            d_lambda_w[i] += lambda[row] * turned;
                        }
                        if !active[row] {
                            continue;
                        }
                        let (velocity_row, position_row) = (yl.lambda.start + row, yl.mu.start + row);
                        f(velocity_row, vo + k, sign);
                        f(position_row, qo + k, sign);
                        let w_cross_s = w.cross(&origin);
                        for c in 0..3 {
                            f(velocity_row, vo + 3 + c, turned[c]);
                        }
                        for i in 0..4 {
                            f(velocity_row, qo + 3 + i, d.dot(&(da[i] * w_cross_s)));
                            f(position_row, qo + 3 + i, d.dot(&(da[i] * origin)));
                        }
                    }
                    Side::Dot1 { row, axis, other_marker, other_axis, other_body } => {
                        // With the body's own axis a first, c = a × a_o on either side: B_ω̄ = Aᵀ c on this
                        // body, −A_oᵀ c on the other, and Φ̇ = c · (ω − ω_o).
                        let other = &data.markers[other_marker];
                        let own_axis = a * axis;
                        let other_axis: Vec3 = other.axes.column(other_axis).into();
                        let c = own_axis.cross(&other_axis);
                        let relative = state.rotation * w - other.angular_velocity;
                        let dc: [Vec3; 4] = std::array::from_fn(|i| (da[i] * axis).cross(&other_axis));
                        mu_w += mu[row] * (a.transpose() * c);
                        for i in 0..4 {
                            let own = da[i].transpose() * c + a.transpose() * dc[i];
                            d_mu_w[i] += mu[row] * own;
                            d_lambda_w[i] += lambda[row] * own;
                        }
                        // The other body's constraint forces −A_oᵀ c (λ) and kinematic terms (μ).
                        if let Some(o) = other_body {
                            let (oq, ov) = (yl.q.start + l.q_offset[o], yl.v.start + l.v_offset[o]);
                            let p_o = Vec4::new(y[oq + 3], y[oq + 4], y[oq + 5], y[oq + 6]);
                            let (a_o, g_o) = (data.bodies[o].rotation, g_matrix(&p_o));
                            for i in 0..4 {
                                let turned = -(a_o.transpose() * dc[i]);
                                let kinematic = -2.0 * mu[row] * (g_o.transpose() * turned);
                                for r in 0..3 {
                                    f(ov + 3 + r, qo + 3 + i, lambda[row] * turned[r]);
                                }
                                for r in 0..4 {
                                    f(oq + 3 + r, qo + 3 + i, kinematic[r]);
                                }
                            }
                        }
                        if !active[row] {
                            continue;
                        }
                        let (velocity_row, position_row) = (yl.lambda.start + row, yl.mu.start + row);
                        let b_w = a.transpose() * c;
                        for k in 0..3 {
                            f(velocity_row, vo + 3 + k, b_w[k]);
                        }
                        for i in 0..4 {
                            f(velocity_row, qo + 3 + i, dc[i].dot(&relative) + c.dot(&(da[i] * w)));
                            f(position_row, qo + 3 + i, (da[i] * axis).dot(&other_axis));
                        }
                    }
                }
            }

            // Kinematic rows.
            let g = g_matrix(&p);
            let mu_n = mu[l.nc + b];
            for c in 0..3 {
                f(qo + c, vo + c, -1.0);
                for r in 0..4 {
                    f(qo + 3 + r, vo + 3 + c, -0.5 * g[(c, r)]);
                }
            }
            for i in 0..4 {
                let gi = g_matrix(&Vec4::ith(i, 1.0)).transpose();
                let column = 0.5 * gi * w + 2.0 * gi * mu_w + 2.0 * g.transpose() * d_mu_w[i] + 2.0 * mu_n * Vec4::ith(i, 1.0);
                for r in 0..4 {
                    f(qo + 3 + r, qo + 3 + i, -column[r]);
                }
            }

            // Dynamic rows: inertia, gravity and the constraint forces.
            let translation_bias = w.cross(&w.cross(&s)) - s.cross(&wd);
            let body_load = rdd - model.gravity;
            for i in 0..4 {
                let translation = da[i] * translation_bias;
                let rotation = s.cross(&(da[i].transpose() * body_load)) + d_lambda_w[i];
                for r in 0..3 {
                    f(vo + r, qo + 3 + i, translation[r]);
                    f(vo + 3 + r, qo + 3 + i, rotation[r]);
                }
            }
            let centrifugal: Mat3 = -a * (skew(&w.cross(&s)) + skew(&w) * skew(&s));
            let gyroscopic: Mat3 = skew(&w) * j - skew(&(j * w));
            for r in 0..3 {
                for c in 0..3 {
                    f(vo + r, vo + 3 + c, centrifugal[(r, c)]);
                    f(vo + 3 + r, vo + 3 + c, gyroscopic[(r, c)]);
                }
            }

            // Normalization.
            for i in 0..4 {
                f(yl.mu.start + l.nc + b, qo + 3 + i, 2.0 * p[i]);
            }
        }
    }
}

/// `∂A(p/|p|)/∂pᵢ`, `i = 0..4`, of the rotation matrix of Euler parameters `p` that may be off the unit
/// sphere ([`rotation_matrix`](crate::math::euler_parameters::rotation_matrix) normalizes them first).
pub(crate) fn rotation_derivatives(p: &Vec4) -> [Mat3; 4] {
    let norm = p.norm();
    let u = p / norm;
    let (e0, e1, e2, e3) = (u[0], u[1], u[2], u[3]);
    // Derivatives of A in the normalized parameters.
    let unit = [
        Mat3::new(2.0 * e0, -e3, e2, e3, 2.0 * e0, -e1, -e2, e1, 2.0 * e0) * 2.0,
        Mat3::new(2.0 * e1, e2, e3, e2, 0.0, -e0, e3, e0, 0.0) * 2.0,
        Mat3::new(0.0, e1, e0, e1, 2.0 * e2, e3, -e0, e3, 0.0) * 2.0,
        Mat3::new(0.0, -e0, e1, e0, 0.0, e2, e1, e2, 2.0 * e3) * 2.0,
    ];
    // Chain rule through u = p/|p|: ∂u/∂p = (I − u uᵀ)/|p|.
    let radial: Mat3 = (0..4).map(|i| unit[i] * u[i]).sum();
    std::array::from_fn(|k| (unit[k] - radial * u[k]) / norm)
}
