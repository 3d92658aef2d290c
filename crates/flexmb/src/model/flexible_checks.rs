//! Validation of flexible bodies and of markers at their nodes.

use super::{BodyRef, ModelError};
use crate::body::{Marker, ModalBody, RigidBody};

fn bad(name: &str, problem: String) -> ModelError {
    ModelError::BadValue { element: "body", name: name.to_string(), problem }
}

/// Sizes agree, values are finite, and the modal mass is positive definite (the frame's own motions
/// may carry no mass: see [`ModalBody::massless_motions`]).
pub(super) fn check_flexible_body(body: &RigidBody, modal: &ModalBody) -> Result<(), ModelError> {
    let name = &body.name;
    let inv = &modal.invariants;
    let m = modal.modes();
    let sizes = [
        ("C2 columns", inv.c2.ncols()),
        ("C4 entries", inv.c4.len()),
        ("C5 entries", inv.c5.len().checked_div(m).unwrap_or(0)),
        ("C6 columns", inv.c6.ncols()),
        ("C7 entries", inv.c7.len()),
        ("rotary coupling columns", inv.rotary_coupling.ncols()),
        ("modal stiffness size", modal.stiffness.nrows()),
        ("modal damping size", modal.damping.nrows()),
        ("initial modal coordinates", modal.initial_coordinates.len()),
        ("initial modal rates", modal.initial_rates.len()),
        ("mode labels", modal.mode_labels.len()),
    ];
    for (what, n) in sizes {
        if n != m {
            return Err(bad(name, format!("{what}: {n}, expected {m} (one per mode)")));
        }
    }
    if inv.c5.len() != m * m || modal.stiffness.ncols() != m || modal.damping.ncols() != m || inv.rotary_modal_mass.nrows() != m {
        return Err(bad(name, format!("C5, the modal stiffness, damping and rotary modal mass must be {m}×{m}")));
    }
    if let Some(terms) = &modal.geometric_stiffness {
        if terms.inertia_cases.len() != crate::body::INERTIA_CASES || terms.inertia_cases.iter().any(|g| g.shape() != (m, m)) {
            return Err(bad(name, format!("the geometric stiffness must hold {} matrices of {m}×{m}", crate::body::INERTIA_CASES)));
        }
        for i in &terms.interface {
            if i.node >= modal.nodes.len() {
                return Err(bad(name, format!("the geometric stiffness names interface node {} of {}", i.node, modal.nodes.len())));
            }
            if i.loads.len() != crate::body::INTERFACE_CASES || i.loads.iter().any(|g| g.shape() != (m, m)) {
                return Err(bad(
                    name,
                    format!(
                        "the geometric stiffness of interface node {} must hold {} matrices of {m}×{m}",
                        modal.nodes[i.node].label,
                        crate::body::INTERFACE_CASES
                    ),
                ));
            }
        }
        if !terms.cases().all(|g| g.iter().all(|x| x.is_finite())) {
            return Err(bad(name, "the geometric stiffness is not finite".into()));
        }
    }
    if let Some(k) = modal.nodes.iter().position(|n| n.psi.ncols() != m || n.theta.ncols() != m) {
        return Err(bad(name, format!("node {} has mode shapes of the wrong size", modal.nodes[k].label)));
    }
    if !(inv.mass.is_finite() && inv.mass > 0.0) {
        return Err(ModelError::NonPositiveMass { body: name.clone(), mass: inv.mass });
    }
    super::rigid_checks::check_frame(&format!("body '{name}' initial orientation"), &body.initial.orientation.rotation_matrix())?;
    let mass = modal.undeformed_mass_matrix();
    if !mass.iter().all(|x| x.is_finite()) || !modal.stiffness.iter().all(|x| x.is_finite()) {
        return Err(bad(name, "the invariants or the modal stiffness are not finite".into()));
    }
    // The frame may have a motion without mass (a straight beam's spin about its axis) when joints
    // hold it (checked by the assembly); the modes may not: nothing else would give them accelerations.
    if m > 0 && nalgebra::Cholesky::new(inv.modal_mass()).is_none() {
        return Err(bad(
            name,
            "the modal mass is not positive definite: some combination of the modes only turns nodes without \
             rotary inertia (a twist of a beam) and carries no mass; drop those modes or lump rotary inertia in the FE model"
                .into(),
        ));
    }
    Ok(())
}

/// A marker on a flexible body sits at one of its nodes; a marker on a rigid body does not name one.
pub(super) fn check_marker_node(marker: &Marker, node: Option<usize>, modal: &[Option<ModalBody>]) -> Result<(), ModelError> {
    let problem = |p: String| Err(ModelError::BadValue { element: "marker", name: marker.name.clone(), problem: p });
    match (marker.body, node) {
        (BodyRef::Body(b), None) if modal[b.0].is_some() => {
            problem("is on a flexible body: it must sit at one of the body's nodes".into())
        }
        (BodyRef::Body(b), Some(k)) => match &modal[b.0] {
            None => problem("names a node, but its body is rigid".into()),
            Some(m) if k >= m.nodes.len() => problem(format!("node index {k} is beyond the body's {} nodes", m.nodes.len())),
            Some(_) => Ok(()),
        },
        (BodyRef::Ground, Some(_)) => problem("names a node, but is on ground".into()),
        _ => Ok(()),
    }
}
