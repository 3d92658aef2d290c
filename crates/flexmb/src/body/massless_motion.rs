//! Motions of a flexible body that carry no mass: the null space of the mass matrix of the undeformed
//! body, `(6 + m)`-square in the body frame. A straight line of point masses without rotary inertia
//! (a beam of Euler–Bernoulli elements, as ANCF cables are) has no inertia about its own axis: the
//! frame's spin about it moves no mass. Such a body is simulated: where the joints hold that motion the
//! matrix `[M Bᵀ; B 0]` of the accelerations stays regular (no solve inverts `M` alone), and where none
//! holds it a gauge fixes the frame's spin about the axis, which moves no mass point (the module
//! `analysis::massless_motions`); the assembly checks that one or the other does. Modes and
//! combinations of modes that carry no mass (a twist without polar inertia) are dropped by the
//! reduction, so the modal block itself is positive definite.

use nalgebra::{DMatrix, DVector};

use super::ModalBody;
use crate::math::{skew, Vec3};

/// Below this eigenvalue of the scaled mass matrix (translation in units of the body's mass, rotation
/// in units of its mass times its size squared, each mode in units of its modal mass) a direction
/// carries no mass.
const MASSLESS: f64 = 1e-10;

/// A motion of a flexible body that carries no mass, in its velocity coordinates `[Ṙ, ω̄, ȧ]` with `Ṙ`
/// in body axes (at `A = I`), of unit norm.
#[derive(Clone, Debug, PartialEq)]
pub struct MasslessMotion {
    /// `[Ṙ, ω̄, ȧ]`, `6 + m` entries, body axes.
    pub velocity: DVector<f64>,
}

impl MasslessMotion {
    /// What the motion is, in words: a rotation about an axis through a point (body frame), or a
    /// combination of the frame's motion and the modes.
    pub fn describe(&self) -> String {
        let v = &self.velocity;
        let translation = Vec3::new(v[0], v[1], v[2]);
        let omega = Vec3::new(v[3], v[4], v[5]);
        let modal = v.rows(6, v.len() - 6).norm();
        if omega.norm() > 1e-6 && modal < 1e-6 * omega.norm() {
            // Ṙ = −ω × p: the point p on the axis nearest the origin is ω × Ṙ / |ω|².
            let point = omega.cross(&translation) / omega.norm_squared();
            let axis = omega.normalize();
            let axis = if axis.iter().fold(0.0_f64, |a, &x| if x.abs() > a.abs() { x } else { a }) < 0.0 { -axis } else { axis };
            let along = translation.dot(&axis);
            if along.abs() < 1e-6 * (translation.norm() + omega.norm()) {
                return format!("the rotation about the axis {} through {} m (body frame)", vector(&axis), vector(&point));
            }
        }
        let frame: Vec<String> = v.iter().take(6).map(|x| format!("{x:.3}")).collect();
        let modes: Vec<String> = v.iter().skip(6).map(|x| format!("{x:.3}")).collect();
        format!("the motion [Ṙ, ω̄] = [{}] with modal rates [{}] (body frame)", frame.join(", "), modes.join(", "))
    }
}

fn vector(v: &Vec3) -> String {
    let round = |x: f64| if x.abs() < 1e-12 { 0.0 } else { x };
    format!("[{:.4}, {:.4}, {:.4}]", round(v.x), round(v.y), round(v.z))
}

impl ModalBody {
    /// The motions of the undeformed body that carry no mass (none for a body with rotary inertia or
    /// with mass off a line). Each is of unit norm; together they span the null space of
    /// [`undeformed_mass_matrix`](Self::undeformed_mass_matrix).
    pub fn massless_motions(&self) -> Vec<MasslessMotion> {
        let mass = self.undeformed_mass_matrix();
        let n = mass.nrows();
        let total = self.invariants.mass.max(f64::MIN_POSITIVE);
        let com = self.invariants.c1 / total;
        let size = self.nodes.iter().map(|node| (node.position - com).norm()).fold(0.0, f64::max).max(1e-9);
        let scale = DVector::from_fn(n, |k, _| match k {
            0..=2 => 1.0 / total.sqrt(),
            3..=5 => 1.0 / (total.sqrt() * size),
            _ => 1.0 / mass[(k, k)].max(f64::MIN_POSITIVE).sqrt(),
        });
        let scaled = DMatrix::from_fn(n, n, |r, c| scale[r] * mass[(r, c)] * scale[c]);
        let eigen = nalgebra::SymmetricEigen::new(scaled);
        (0..n)
            .filter(|&k| eigen.eigenvalues[k] < MASSLESS)
            .map(|k| {
                let velocity = eigen.eigenvectors.column(k).component_mul(&scale);
                MasslessMotion { velocity: velocity.normalize() }
            })
            .collect()
    }

    /// The `(6 + m)`-square mass matrix at `a = 0` in the body frame (`A = I`), in the velocity
    /// coordinates `[Ṙ, ω̄, ȧ]`.
    pub fn undeformed_mass_matrix(&self) -> DMatrix<f64> {
        let inv = &self.invariants;
        let m = self.modes();
        let n = 6 + m;
        let mut mass = DMatrix::zeros(n, n);
        let s_tilde = skew(&inv.c1);
        let j = inv.undeformed_inertia();
        let coupling = &inv.c6 + &inv.rotary_coupling;
        let modal_mass = inv.modal_mass();
        for r in 0..3 {
            mass[(r, r)] = inv.mass;
            for c in 0..3 {
                mass[(r, 3 + c)] = -s_tilde[(r, c)];
                mass[(3 + c, r)] = -s_tilde[(r, c)];
                mass[(3 + r, 3 + c)] = j[(r, c)];
            }
            for k in 0..m {
                mass[(r, 6 + k)] = inv.c2[(r, k)];
                mass[(6 + k, r)] = inv.c2[(r, k)];
                mass[(3 + r, 6 + k)] = coupling[(r, k)];
                mass[(6 + k, 3 + r)] = coupling[(r, k)];
            }
        }
        for a in 0..m {
            for b in 0..m {
                mass[(6 + a, 6 + b)] = modal_mass[(a, b)];
            }
        }
        mass
    }
}
