//! From the preprocessor's flexible-body file to the engine's modal body: the invariants, modal
//! stiffness and damping, the geometric stiffness of the unit inertia and interface loads (when the file has it),
//! and the nodes where markers attach.

use flexmb::body::{InterfaceGeometricStiffness, ModalBody, ModalDamping, ModalGeometricStiffness, ModalInvariants, ModalNode};
use flexmb_fem::reduction::FlexibleBody;
use nalgebra::{DMatrix, DVector, Matrix3xX};

/// The engine's modal body of a reduced flexible body, with `damping`; initial modal coordinates and
/// rates zero.
pub fn modal_body(body: &FlexibleBody, damping: &ModalDamping) -> Result<ModalBody, String> {
    let inv = &body.invariants;
    let m = body.mode_count();
    let to3 = |a: &DMatrix<f64>| Matrix3xX::from_fn(m, |r, c| a[(r, c)]);
    let invariants = ModalInvariants {
        mass: inv.mass,
        c1: inv.c1,
        c2: to3(&inv.c2),
        c3: inv.c3,
        c4: inv.c4.clone(),
        c5: inv.c5.iter().flatten().copied().collect(),
        c6: to3(&inv.c6),
        c7: inv.c7.iter().map(to3).collect(),
        c9: inv.c9.clone(),
        rotary_inertia: inv.rotary_inertia,
        rotary_coupling: to3(&inv.rotary_coupling),
        rotary_modal_mass: inv.rotary_modal_mass.clone(),
    };
    let nodes = body
        .nodes
        .iter()
        .enumerate()
        .map(|(i, n)| ModalNode {
            label: n.label,
            position: n.position,
            psi: Matrix3xX::from_fn(m, |r, j| body.shapes[j].translation[i][r]),
            theta: Matrix3xX::from_fn(m, |r, j| body.shapes[j].rotation[i][r]),
        })
        .collect();
    let mut modal = ModalBody {
        invariants,
        stiffness: body.modal_stiffness.clone(),
        damping: DMatrix::zeros(m, m),
        nodes,
        mode_labels: body.modes.iter().map(|mode| mode.label.clone()).collect(),
        initial_coordinates: DVector::zeros(m),
        initial_rates: DVector::zeros(m),
        geometric_stiffness: None,
    };
    if let Some(g) = &body.geometric_stiffness {
        let interface = g
            .interface
            .iter()
            .map(|case| {
                let node = body.nodes.iter().position(|n| n.label == case.node).ok_or_else(|| {
                    format!("the geometric stiffness names interface node {}, which is not a node of the body", case.node)
                })?;
                Ok(InterfaceGeometricStiffness { node, loads: case.loads.clone() })
            })
            .collect::<Result<Vec<_>, String>>()?;
        modal.geometric_stiffness = Some(ModalGeometricStiffness {
            inertia_cases: g.acceleration.iter().chain(&g.angular_acceleration).chain(&g.centrifugal).cloned().collect(),
            interface,
        });
    }
    modal.damping = modal.damping_matrix(damping).map_err(|e| e.to_string())?;
    Ok(modal)
}
