//! Haug's primitive constraint equations (Haug 1989, §9.2), written on the global kinematics of the two
//! markers so that the same code serves rigid bodies, ground and (later) nodes of flexible bodies.
//!
//! For a vector `a` fixed in marker `i`: `δa = δθ_i × a`, `ȧ = ω_i × a`,
//! `ä = α_i × a + ω_i × (ω_i × a)`. Each equation returns its value `Φ`, its partial time derivative
//! `Φ_t`, its coefficients on the variations `δr_i, δθ_i, δr_j, δθ_j` of the two markers, and the part of
//! `Φ̈` that does not multiply generalized accelerations (`γ = −accel_bias`).

use super::Axis;
use crate::math::Vec3;
use crate::stage::MarkerState;

/// One primitive equation of a joint.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Equation {
    /// Component `k` of `r_j − r_i = 0`.
    Point(usize),
    /// `a_iᵀ a_j = 0` (dot-1).
    Dot1(Axis, Axis),
    /// `a_iᵀ (r_j − r_i) = 0` (dot-2).
    Dot2(Axis),
    /// `½ (dᵀd − L(t)²) = 0`.
    Distance,
    /// `θ_ij − f(t) = 0`, the angle from `x_i` to `x_j` about `z_i`.
    Angle,
    /// `z_iᵀ d − f(t) = 0`.
    Displacement,
}

/// Value and derivatives of one constraint equation (see the module docs).
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct EquationTerms {
    pub phi: f64,
    pub phi_t: f64,
    pub d_point_i: Vec3,
    pub d_rot_i: Vec3,
    pub d_point_j: Vec3,
    pub d_rot_j: Vec3,
    /// `Φ̈ − (Φ_q q̈)`: velocity-squared and time terms; `γ = −accel_bias`.
    pub accel_bias: f64,
}

impl EquationTerms {
    /// `Φ̇ = Φ_q q̇ + Φ_t` from the marker velocities.
    pub fn rate(&self, mi: &MarkerState, mj: &MarkerState) -> f64 {
        self.d_point_i.dot(&mi.velocity)
            + self.d_rot_i.dot(&mi.angular_velocity)
            + self.d_point_j.dot(&mj.velocity)
            + self.d_rot_j.dot(&mj.angular_velocity)
            + self.phi_t
    }
}

/// A unit vector fixed in a marker and its first and (bias) second derivatives.
struct MovingVector {
    a: Vec3,
    rate: Vec3,
    accel_bias: Vec3,
}

fn axis_of(m: &MarkerState, axis: Axis) -> MovingVector {
    let a: Vec3 = m.axes.column(axis.index()).into();
    let rate = m.angular_velocity.cross(&a);
    let accel_bias = m.angular_accel_bias.cross(&a) + m.angular_velocity.cross(&rate);
    MovingVector { a, rate, accel_bias }
}

/// `f(t), f'(t), f''(t)` of a driver or distance law; zero for the other equations.
pub(crate) type TimeLaw = [f64; 3];

impl Equation {
    /// Evaluates the equation on the two markers' current kinematics.
    /// `angle_reference` is the last accepted angle (for unwrapping `Angle` past ±π).
    pub fn evaluate(
        &self,
        mi: &MarkerState,
        mj: &MarkerState,
        law: TimeLaw,
        angle_reference: f64,
    ) -> EquationTerms {
        let d = mj.position - mi.position;
        let d_rate = mj.velocity - mi.velocity;
        let d_bias = mj.accel_bias - mi.accel_bias;
        match *self {
            Equation::Point(k) => {
                let e = Vec3::ith(k, 1.0);
                EquationTerms {
                    phi: d[k],
                    d_point_i: -e,
                    d_point_j: e,
                    accel_bias: d_bias[k],
                    ..Default::default()
                }
            }
            Equation::Dot1(ai, aj) => dot1(&axis_of(mi, ai), &axis_of(mj, aj)),
            Equation::Dot2(ai) => dot2(&axis_of(mi, ai), &d, &d_rate, &d_bias),
            Equation::Distance => {
                let [l, dl, ddl] = law;
                EquationTerms {
                    phi: 0.5 * (d.dot(&d) - l * l),
                    phi_t: -l * dl,
                    d_point_i: -d,
                    d_point_j: d,
                    accel_bias: d_rate.dot(&d_rate) + d.dot(&d_bias) - dl * dl - l * ddl,
                    ..Default::default()
                }
            }
            Equation::Displacement => {
                let [f, df, ddf] = law;
                let mut terms = dot2(&axis_of(mi, Axis::Z), &d, &d_rate, &d_bias);
                terms.phi -= f;
                terms.phi_t -= df;
                terms.accel_bias -= ddf;
                terms
            }
            Equation::Angle => {
                let [f, df, ddf] = law;
                let mut terms = relative_angle(mi, mj, angle_reference);
                terms.phi -= f;
                terms.phi_t -= df;
                terms.accel_bias -= ddf;
                terms
            }
        }
    }
}

/// dot-1: `Φ = a_iᵀ a_j`.
fn dot1(ai: &MovingVector, aj: &MovingVector) -> EquationTerms {
    let c = ai.a.cross(&aj.a);
    EquationTerms {
        phi: ai.a.dot(&aj.a),
        d_rot_i: c,
        d_rot_j: -c,
        accel_bias: ai.accel_bias.dot(&aj.a) + ai.a.dot(&aj.accel_bias) + 2.0 * ai.rate.dot(&aj.rate),
        ..Default::default()
    }
}

/// dot-2: `Φ = a_iᵀ d`, `d = r_j − r_i`.
fn dot2(ai: &MovingVector, d: &Vec3, d_rate: &Vec3, d_bias: &Vec3) -> EquationTerms {
    EquationTerms {
        phi: ai.a.dot(d),
        d_point_i: -ai.a,
        d_rot_i: ai.a.cross(d),
        d_point_j: ai.a,
        accel_bias: ai.accel_bias.dot(d) + 2.0 * ai.rate.dot(d_rate) + ai.a.dot(d_bias),
        ..Default::default()
    }
}

/// Wraps an angle difference into `(−π, π]`.
fn wrap(x: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    x - two_pi * ((x + std::f64::consts::PI) / two_pi).floor()
}

/// The angle `θ = atan2(y_iᵀ x_j, x_iᵀ x_j)` from `x_i` to `x_j` about `z_i`, continued from `reference`
/// so that it runs past ±π, with its exact first and second derivatives:
/// `θ̇ = (c ṡ − s ċ)/ρ²`, `θ̈ = (c s̈ − s c̈)/ρ² − 2 θ̇ (c ċ + s ṡ)/ρ²`.
pub(crate) fn relative_angle(mi: &MarkerState, mj: &MarkerState, reference: f64) -> EquationTerms {
    let xj = axis_of(mj, Axis::X);
    let c_terms = dot1(&axis_of(mi, Axis::X), &xj);
    let s_terms = dot1(&axis_of(mi, Axis::Y), &xj);
    let (c, s) = (c_terms.phi, s_terms.phi);
    let rho2 = c * c + s * s;
    let raw = s.atan2(c);
    let theta = reference + wrap(raw - reference);
    let c_rate = c_terms.rate(mi, mj);
    let s_rate = s_terms.rate(mi, mj);
    let theta_rate = (c * s_rate - s * c_rate) / rho2;
    EquationTerms {
        phi: theta,
        phi_t: 0.0,
        d_point_i: Vec3::zeros(),
        d_rot_i: (c * s_terms.d_rot_i - s * c_terms.d_rot_i) / rho2,
        d_point_j: Vec3::zeros(),
        d_rot_j: (c * s_terms.d_rot_j - s * c_terms.d_rot_j) / rho2,
        accel_bias: (c * s_terms.accel_bias - s * c_terms.accel_bias) / rho2
            - 2.0 * theta_rate * (c * c_rate + s * s_rate) / rho2,
    }
}
