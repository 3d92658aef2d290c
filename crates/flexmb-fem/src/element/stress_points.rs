//! Stress recovery: the linear map from an element's nodal displacements to the stress at its
//! stress points, each at one of its nodes — a solid's node, a shell's top or bottom surface there,
//! a beam section's extreme fibres there. The flexible-body file stores, for each mode, these
//! stresses averaged over the elements that share a point (`reduction::ModalStresses`).

use nalgebra::DMatrix;
use serde::{Deserialize, Serialize};

use super::{beam, element_points, lookup, shell, solid, ElementError};
use crate::mesh::{Element, ElementKind, Mesh};

/// Where at a node a recovered stress is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StressPlace {
    /// In a solid.
    Solid,
    /// On a shell's top surface (the side its normal points to).
    Top,
    /// On a shell's bottom surface.
    Bottom,
    /// At extreme fibre k of a beam's section (see `element::beam::beam_stress_matrix`).
    Fibre(u8),
}

impl std::fmt::Display for StressPlace {
    /// `solid`, `fibre 1`, … (fibres counted from 1).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StressPlace::Solid => write!(f, "solid"),
            StressPlace::Top => write!(f, "top"),
            StressPlace::Bottom => write!(f, "bottom"),
            StressPlace::Fibre(k) => write!(f, "fibre {}", k + 1),
        }
    }
}

/// The stress at an element's stress points from its nodal displacements.
#[derive(Clone, Debug, PartialEq)]
pub struct ElementStress {
    /// The stress points: the element's node (position 0..n in its node list) and the place there;
    /// point p has rows `6p..6p+6` of `matrix`.
    pub points: Vec<(usize, StressPlace)>,
    /// `6 p × 6 n`: the stress σxx σyy σzz σxy σyz σzx (Pa, body axes) at each point from
    /// `ux uy uz rx ry rz` of each node (body frame).
    pub matrix: DMatrix<f64>,
    /// Whether the points are shared with the neighbouring elements at the node, and the stress
    /// there their mean (a solid's nodes), or the element's alone (a beam's end sections).
    pub shared: bool,
}

/// The stress recovery of `element` of `mesh` (every kind has one; `None` is kept for kinds that
/// may come without).
pub fn element_stress(mesh: &Mesh, element: &Element) -> Result<Option<ElementStress>, ElementError> {
    let points = element_points(mesh, element)?;
    match element.kind {
        ElementKind::Solid { section, formulation } => {
            let section = lookup(&mesh.solid_sections, "solid section", section)?;
            let material = lookup(&mesh.materials, "material", section.material)?;
            if points.len() != formulation.node_count() {
                return Err(ElementError::NodeCount { kind: formulation.abaqus_name(), expected: "as many as its type", found: points.len() });
            }
            solid::solid_stress_matrix(&points, formulation, material).map(Some)
        }
        ElementKind::Beam { section } => {
            let section = lookup(&mesh.beam_sections, "beam section", section)?;
            let material = lookup(&mesh.materials, "material", section.material)?;
            if points.len() != 2 {
                return Err(ElementError::NodeCount { kind: "beam", expected: "2", found: points.len() });
            }
            beam::beam_stress_matrix(&points[0], &points[1], section, material).map(Some)
        }
        ElementKind::Shell { section } => {
            let section = lookup(&mesh.shell_sections, "shell section", section)?;
            let material = lookup(&mesh.materials, "material", section.material)?;
            shell::shell_stress_matrix(&points, section, material).map(Some)
        }
    }
}
