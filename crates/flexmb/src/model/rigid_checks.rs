//! Validation of a rigid body's mass properties and initial state, and of frames (marker axes, body
//! orientations).

use super::ModelError;
use crate::body::RigidBody;
use crate::math::{rotation_matrix_defect, Mat3, Vec3, ROTATION_TOLERANCE};

/// Mass, inertia, initial orientation and values of one rigid body.
pub(super) fn check_body(b: &RigidBody) -> Result<(), ModelError> {
    if !(b.mass.is_finite() && b.mass > 0.0) {
        return Err(ModelError::NonPositiveMass { body: b.name.clone(), mass: b.mass });
    }
    check_inertia(&b.inertia).map_err(|problem| ModelError::BadInertia { body: b.name.clone(), problem })?;
    check_frame(&format!("body '{}' initial orientation", b.name), &b.initial.orientation.rotation_matrix())?;
    let finite = |v: &Vec3| v.iter().all(|x| x.is_finite());
    let vel_ok = b.initial.velocity.as_ref().is_none_or(finite)
        && b.initial.angular_velocity.as_ref().is_none_or(finite);
    if !finite(&b.initial.position) || !finite(&b.center_of_mass) || !vel_ok {
        return Err(ModelError::BadValue {
            element: "body",
            name: b.name.clone(),
            problem: "position, centre of mass and velocities must be finite".into(),
        });
    }
    Ok(())
}

/// A physical inertia tensor: symmetric, positive definite, principal moments obeying the triangle
/// inequality `I₁ + I₂ ≥ I₃`.
pub(super) fn check_inertia(j: &Mat3) -> Result<(), String> {
    if !j.iter().all(|x| x.is_finite()) {
        return Err("has a value that is not finite".into());
    }
    let scale = j.abs().max().max(f64::MIN_POSITIVE);
    if (j - j.transpose()).abs().max() > 1e-9 * scale {
        return Err(format!("is not symmetric: {j}"));
    }
    let eig = j.symmetric_eigenvalues();
    let mut m = [eig[0], eig[1], eig[2]];
    m.sort_by(f64::total_cmp);
    if m[0] <= 0.0 {
        return Err(format!("must be positive definite; principal moments are {:.6e}, {:.6e}, {:.6e}", m[0], m[1], m[2]));
    }
    if m[0] + m[1] < m[2] * (1.0 - 1e-9) {
        return Err(format!(
            "principal moments {:.6e}, {:.6e}, {:.6e} violate the triangle inequality I1 + I2 >= I3",
            m[0], m[1], m[2]
        ));
    }
    Ok(())
}

/// `a` is a proper orthonormal frame (a rotation matrix); `what` names it in the error.
pub(super) fn check_frame(what: &str, a: &Mat3) -> Result<(), ModelError> {
    let defect = rotation_matrix_defect(a);
    if defect.is_nan() || defect >= ROTATION_TOLERANCE {
        return Err(ModelError::BadFrame {
            what: what.to_string(),
            problem: format!("axes are not a proper orthonormal frame (defect {defect:.2e})"),
        });
    }
    Ok(())
}
