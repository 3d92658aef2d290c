//! Euler parameters `p = [e0, e]`, `e0 = cos(χ/2)`, `e = u sin(χ/2)` (Haug 1989, ch. 6; the seed's
//! "Euler parameters" chart), and the matrices `A(p)`, `E(p)`, `G(p)` with `A = E Gᵀ`.
//!
//! All functions normalize `p` first, so a parameter vector that has drifted off the unit sphere inside a
//! Newton iteration still describes a proper rotation.

use super::{Mat3, Mat3x4, Vec3, Vec4};

/// The largest [`rotation_matrix_defect`] of a matrix taken as a rotation.
pub const ROTATION_TOLERANCE: f64 = 1e-6;

/// Why an orientation cannot be made.
#[derive(Clone, Copy, Debug, thiserror::Error, PartialEq)]
pub enum OrientationError {
    /// The axis of an axis–angle rotation has zero length or is not finite.
    #[error("the rotation axis must be a finite, non-zero vector, got [{}, {}, {}]", axis[0], axis[1], axis[2])]
    ZeroAxis {
        /// The axis given.
        axis: [f64; 3],
    },
    /// The angle of an axis–angle rotation is not finite.
    #[error("the rotation angle must be finite, got {angle}")]
    NonFiniteAngle {
        /// The angle given (rad).
        angle: f64,
    },
    /// A matrix that is not a proper rotation.
    #[error("the matrix is not a proper rotation: defect {defect:.2e} (max(|AᵀA − I|, |det A − 1|)), allowed {ROTATION_TOLERANCE:.0e}")]
    NotARotation {
        /// Its [`rotation_matrix_defect`].
        defect: f64,
    },
}

/// Orientation of a body reference frame, `s = A(p) s̄`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerParameters(pub Vec4);

impl EulerParameters {
    /// The identity orientation `[1, 0, 0, 0]`.
    pub fn identity() -> Self {
        Self(Vec4::new(1.0, 0.0, 0.0, 0.0))
    }

    /// Rotation by `angle` (rad) about `axis` (need not be unit, but finite and not zero).
    pub fn from_axis_angle(axis: &Vec3, angle: f64) -> Result<Self, OrientationError> {
        let n = axis.norm();
        if !(n > 0.0 && n.is_finite()) {
            return Err(OrientationError::ZeroAxis { axis: [axis.x, axis.y, axis.z] });
        }
        if !angle.is_finite() {
            return Err(OrientationError::NonFiniteAngle { angle });
        }
        if angle == 0.0 {
            return Ok(Self::identity());
        }
        let (s, c) = (0.5 * angle).sin_cos();
        let e = axis * (s / n);
        Ok(Self(Vec4::new(c, e.x, e.y, e.z)))
    }

    /// Euler parameters of a proper rotation matrix (Shepperd's method, stable for every angle); a
    /// matrix whose [`rotation_matrix_defect`] reaches [`ROTATION_TOLERANCE`] (or is NaN) is refused.
    pub fn from_rotation_matrix(a: &Mat3) -> Result<Self, OrientationError> {
        let defect = rotation_matrix_defect(a);
        if defect.is_nan() || defect >= ROTATION_TOLERANCE {
            return Err(OrientationError::NotARotation { defect });
        }
        let tr = a.trace();
        let (e0, e1, e2, e3);
        if tr >= a[(0, 0)] && tr >= a[(1, 1)] && tr >= a[(2, 2)] {
            let s = (1.0 + tr).max(0.0).sqrt() * 2.0; // 4 e0
            e0 = 0.25 * s;
            e1 = (a[(2, 1)] - a[(1, 2)]) / s;
            e2 = (a[(0, 2)] - a[(2, 0)]) / s;
            e3 = (a[(1, 0)] - a[(0, 1)]) / s;
        } else if a[(0, 0)] >= a[(1, 1)] && a[(0, 0)] >= a[(2, 2)] {
            let s = (1.0 + a[(0, 0)] - a[(1, 1)] - a[(2, 2)]).max(0.0).sqrt() * 2.0; // 4 e1
            e0 = (a[(2, 1)] - a[(1, 2)]) / s;
            e1 = 0.25 * s;
            e2 = (a[(0, 1)] + a[(1, 0)]) / s;
            e3 = (a[(0, 2)] + a[(2, 0)]) / s;
        } else if a[(1, 1)] >= a[(2, 2)] {
            let s = (1.0 + a[(1, 1)] - a[(0, 0)] - a[(2, 2)]).max(0.0).sqrt() * 2.0; // 4 e2
            e0 = (a[(0, 2)] - a[(2, 0)]) / s;
            e1 = (a[(0, 1)] + a[(1, 0)]) / s;
            e2 = 0.25 * s;
            e3 = (a[(1, 2)] + a[(2, 1)]) / s;
        } else {
            let s = (1.0 + a[(2, 2)] - a[(0, 0)] - a[(1, 1)]).max(0.0).sqrt() * 2.0; // 4 e3
            e0 = (a[(1, 0)] - a[(0, 1)]) / s;
            e1 = (a[(0, 2)] + a[(2, 0)]) / s;
            e2 = (a[(1, 2)] + a[(2, 1)]) / s;
            e3 = 0.25 * s;
        }
        let p = Vec4::new(e0, e1, e2, e3);
        let p = if e0 < 0.0 { -p } else { p };
        Ok(Self(p / p.norm()))
    }

    /// The unit-norm copy of these parameters.
    #[inline]
    pub fn normalized(&self) -> Vec4 {
        self.0 / self.0.norm()
    }

    /// Direction-cosine matrix `A(p) = (2e0² − 1) I + 2(e eᵀ + e0 ẽ)` of the normalized parameters.
    #[inline]
    pub fn rotation_matrix(&self) -> Mat3 {
        rotation_matrix(&self.0)
    }
}

/// `A(p)` for a parameter vector that may be slightly off the unit sphere (it is normalized first).
#[inline]
pub fn rotation_matrix(p: &Vec4) -> Mat3 {
    let p = p / p.norm();
    let (e0, e1, e2, e3) = (p[0], p[1], p[2], p[3]);
    Mat3::new(
        2.0 * (e0 * e0 + e1 * e1) - 1.0,
        2.0 * (e1 * e2 - e0 * e3),
        2.0 * (e1 * e3 + e0 * e2),
        2.0 * (e1 * e2 + e0 * e3),
        2.0 * (e0 * e0 + e2 * e2) - 1.0,
        2.0 * (e2 * e3 - e0 * e1),
        2.0 * (e1 * e3 - e0 * e2),
        2.0 * (e2 * e3 + e0 * e1),
        2.0 * (e0 * e0 + e3 * e3) - 1.0,
    )
}

/// `G(p) = [−e, −ẽ + e0 I]`: body angular velocity `ω̄ = 2 G ṗ`, and `ṗ = ½ Gᵀ ω̄` on the unit sphere.
#[inline]
pub fn g_matrix(p: &Vec4) -> Mat3x4 {
    let (e0, e1, e2, e3) = (p[0], p[1], p[2], p[3]);
    Mat3x4::new(-e1, e0, e3, -e2, -e2, -e3, e0, e1, -e3, e2, -e1, e0)
}

/// `E(p) = [−e, ẽ + e0 I]`: global angular velocity `ω = 2 E ṗ`.
#[inline]
pub fn e_matrix(p: &Vec4) -> Mat3x4 {
    let (e0, e1, e2, e3) = (p[0], p[1], p[2], p[3]);
    Mat3x4::new(-e1, e0, -e3, e2, -e2, e3, e0, -e1, -e3, -e2, e1, e0)
}

/// How far `a` is from a proper rotation: `max(‖AᵀA − I‖∞, |det A − 1|)`.
pub fn rotation_matrix_defect(a: &Mat3) -> f64 {
    let ortho = (a.transpose() * a - Mat3::identity()).abs().max();
    ortho.max((a.determinant() - 1.0).abs())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_equals_e_g_transpose_and_is_orthogonal() {
        let p = EulerParameters::from_axis_angle(&Vec3::new(0.3, -1.2, 0.7), 2.1).unwrap().0;
        let a = rotation_matrix(&p);
        let eg = e_matrix(&p) * g_matrix(&p).transpose();
        assert!((a - eg).abs().max() < 1e-14);
        assert!(rotation_matrix_defect(&a) < 1e-14);
        assert!((g_matrix(&p) * p).norm() < 1e-15);
    }

    #[test]
    fn rotation_matrix_round_trip_for_all_branches() {
        for (axis, angle) in [
            (Vec3::new(0.0, 0.0, 1.0), 0.3),
            (Vec3::new(1.0, 0.0, 0.0), 3.1),
            (Vec3::new(0.0, 1.0, 0.0), 3.0),
            (Vec3::new(0.2, 0.1, 1.0), 3.0),
            (Vec3::new(1.0, 1.0, 1.0), -2.0),
        ] {
            let p = EulerParameters::from_axis_angle(&axis, angle).unwrap();
            let back = EulerParameters::from_rotation_matrix(&p.rotation_matrix()).unwrap();
            let same = (back.0 - p.0).norm().min((back.0 + p.0).norm());
            assert!(same < 1e-12, "axis {axis:?} angle {angle}: {same}");
        }
    }

    #[test]
    fn angular_velocity_from_parameter_rates() {
        // ω̄ = 2 G ṗ and ω = 2 E ṗ = A ω̄ for ṗ = ½ Gᵀ ω̄.
        let p = EulerParameters::from_axis_angle(&Vec3::new(0.5, 0.2, -0.4), 0.9).unwrap().0;
        let wbar = Vec3::new(0.7, -1.1, 2.3);
        let pdot = 0.5 * g_matrix(&p).transpose() * wbar;
        assert!((2.0 * g_matrix(&p) * pdot - wbar).norm() < 1e-14);
        let w = rotation_matrix(&p) * wbar;
        assert!((2.0 * e_matrix(&p) * pdot - w).norm() < 1e-14);
    }

    #[test]
    fn a_zero_axis_a_non_finite_angle_and_a_matrix_that_is_not_a_rotation_are_refused() {
        let zero = EulerParameters::from_axis_angle(&Vec3::zeros(), 0.5).unwrap_err();
        assert_eq!(zero, OrientationError::ZeroAxis { axis: [0.0, 0.0, 0.0] });
        assert_eq!(zero.to_string(), "the rotation axis must be a finite, non-zero vector, got [0, 0, 0]");
        let nan = EulerParameters::from_axis_angle(&Vec3::z(), f64::NAN).unwrap_err();
        assert_eq!(nan.to_string(), "the rotation angle must be finite, got NaN");
        assert_eq!(EulerParameters::from_axis_angle(&Vec3::x(), 0.0), Ok(EulerParameters::identity()));
        let stretched = Mat3::from_diagonal(&Vec3::new(1.0, 1.0, 2.0));
        let error = EulerParameters::from_rotation_matrix(&stretched).unwrap_err();
        assert_eq!(error, OrientationError::NotARotation { defect: 3.0 });
        let mirror = Mat3::from_diagonal(&Vec3::new(1.0, 1.0, -1.0));
        assert!(matches!(EulerParameters::from_rotation_matrix(&mirror), Err(OrientationError::NotARotation { .. })));
    }
}
