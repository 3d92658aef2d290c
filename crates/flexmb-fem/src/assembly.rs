//! Assembly of the global stiffness and lumped mass: equation numbers for the free degrees of
//! freedom (supports removed), element matrices added at their rows, sparse storage.

use faer::sparse::{SparseColMat, Triplet};
use nalgebra::{Matrix3, Vector3};

use crate::element::{element_matrices, NodalMass};
use crate::error::FemError;
use crate::mesh::{Dof, DofSet, FeModel};

/// Equation numbers of the nodal degrees of freedom: 6 per node, supported ones have none.
#[derive(Clone, Debug, PartialEq)]
pub struct DofMap {
    /// Per node and dof (`6 node + dof`), the equation number, or `None` where supported.
    equations: Vec<Option<usize>>,
    n_free: usize,
}

impl DofMap {
    /// Numbers the free degrees of freedom node by node.
    pub fn new(n_nodes: usize, supported: &[DofSet]) -> DofMap {
        let mut equations = vec![None; 6 * n_nodes];
        let mut n_free = 0;
        for node in 0..n_nodes {
            for dof in Dof::ALL {
                if !supported[node].contains(dof) {
                    equations[6 * node + dof.index()] = Some(n_free);
                    n_free += 1;
                }
            }
        }
        DofMap { equations, n_free }
    }

    /// The equation of `dof` of `node`, `None` if supported.
    pub fn equation(&self, node: usize, dof: Dof) -> Option<usize> {
        self.equations[6 * node + dof.index()]
    }

    /// The equation of global dof index `6 node + dof`.
    pub fn equation_of(&self, global: usize) -> Option<usize> {
        self.equations[global]
    }

    /// Number of free degrees of freedom (the size of the assembled matrices).
    pub fn n_free(&self) -> usize {
        self.n_free
    }

    /// The node and dof of equation `equation`.
    pub fn node_dof(&self, equation: usize) -> (usize, Dof) {
        let global = self.equations.iter().position(|e| *e == Some(equation)).expect("equation exists");
        (global / 6, Dof::ALL[global % 6])
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.equations.len() / 6
    }

    /// Scatters a vector over the free dofs into all `6 n_nodes` nodal dofs (zeros at supports).
    pub fn expand(&self, free: &[f64]) -> Vec<f64> {
        self.equations.iter().map(|e| e.map_or(0.0, |k| free[k])).collect()
    }
}

/// The assembled model: equation numbers, sparse stiffness and mass over the free dofs (both
/// triangles stored), and the lumped mass per node (for the inertia invariants).
#[derive(Clone, Debug)]
pub struct AssembledModel {
    pub dofs: DofMap,
    pub stiffness: SparseColMat<usize, f64>,
    pub mass: SparseColMat<usize, f64>,
    /// Lumped mass and rotary inertia at each node, elements and point masses together.
    pub nodal_masses: Vec<NodalMass>,
}

/// The supported dofs of every node.
pub fn supported_dofs(model: &FeModel) -> Vec<DofSet> {
    let mut supported = vec![DofSet::EMPTY; model.mesh.nodes.len()];
    for s in &model.supports {
        supported[s.node] = supported[s.node].union(s.dofs);
    }
    supported
}

/// Assembles the stiffness and lumped mass of `model`.
pub fn assemble(model: &FeModel) -> Result<AssembledModel, FemError> {
    let mesh = &model.mesh;
    let n_nodes = mesh.nodes.len();
    let dofs = DofMap::new(n_nodes, &supported_dofs(model));
    if dofs.n_free() == 0 {
        return Err(FemError::NoFreeDofs);
    }
    let mut nodal_masses = vec![NodalMass { mass: 0.0, rotary_inertia: Matrix3::zeros() }; n_nodes];
    let mut stiffness_triplets = Vec::new();
    // Every nodal dof, supported or not, must be resisted by some element.
    let mut stiff_dof = vec![false; 6 * n_nodes];
    for element in &mesh.elements {
        let matrices = element_matrices(mesh, element, &model.options)
            .map_err(|source| FemError::Element { label: element.label, source })?;
        let globals: Vec<usize> =
            element.nodes.iter().flat_map(|&n| (0..6).map(move |d| 6 * n + d)).collect();
        for (a, &ga) in globals.iter().enumerate() {
            if matrices.stiffness[(a, a)] > 0.0 {
                stiff_dof[ga] = true;
            }
            let Some(row) = dofs.equation_of(ga) else { continue };
            for (b, &gb) in globals.iter().enumerate() {
                let Some(col) = dofs.equation_of(gb) else { continue };
                let value = matrices.stiffness[(a, b)];
                if value != 0.0 {
                    stiffness_triplets.push(Triplet::new(row, col, value));
                }
            }
        }
        for (&node, lumped) in element.nodes.iter().zip(&matrices.lumped_mass) {
            nodal_masses[node].mass += lumped.mass;
            nodal_masses[node].rotary_inertia += lumped.rotary_inertia;
        }
    }
    for pm in &mesh.point_masses {
        let label = mesh.nodes[pm.node].label;
        if !(pm.mass.is_finite() && pm.mass >= 0.0) {
            return Err(FemError::InvalidPointMass { label, mass: pm.mass });
        }
        nodal_masses[pm.node].mass += pm.mass;
        nodal_masses[pm.node].rotary_inertia += Matrix3::from_diagonal(&pm.rotary_inertia);
    }
    for (global, stiff) in stiff_dof.iter().enumerate() {
        if !stiff && dofs.equation_of(global).is_some() {
            let node = global / 6;
            return Err(FemError::NoStiffness {
                label: mesh.nodes[node].label,
                dof: Dof::ALL[global % 6].name(),
            });
        }
    }
    if nodal_masses.iter().all(|m| m.mass == 0.0) {
        return Err(FemError::NoMass);
    }
    let n = dofs.n_free();
    let stiffness = SparseColMat::try_new_from_triplets(n, n, &stiffness_triplets)
        .map_err(|e| FemError::LinearAlgebra(format!("stiffness assembly: {e:?}")))?;
    let mass = mass_matrix(&dofs, &nodal_masses)?;
    Ok(AssembledModel { dofs, stiffness, mass, nodal_masses })
}

/// The lumped mass matrix over the free dofs: `m I` on the translations of each node, the rotary
/// inertia on its rotations.
fn mass_matrix(dofs: &DofMap, nodal: &[NodalMass]) -> Result<SparseColMat<usize, f64>, FemError> {
    let mut triplets = Vec::new();
    for (node, m) in nodal.iter().enumerate() {
        for dof in [Dof::Ux, Dof::Uy, Dof::Uz] {
            if let Some(e) = dofs.equation(node, dof) {
                triplets.push(Triplet::new(e, e, m.mass));
            }
        }
        let rot = [Dof::Rx, Dof::Ry, Dof::Rz];
        for (a, da) in rot.into_iter().enumerate() {
            for (b, db) in rot.into_iter().enumerate() {
                let value = m.rotary_inertia[(a, b)];
                if let (Some(r), Some(c)) = (dofs.equation(node, da), dofs.equation(node, db)) {
                    if value != 0.0 || a == b {
                        triplets.push(Triplet::new(r, c, value));
                    }
                }
            }
        }
    }
    let n = dofs.n_free();
    SparseColMat::try_new_from_triplets(n, n, &triplets)
        .map_err(|e| FemError::LinearAlgebra(format!("mass assembly: {e:?}")))
}

/// Total mass, centre of mass and inertia about the centre of mass of the lumped model (rotary
/// inertia included): the rigid-body properties a flexible body must reproduce.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    pub mass: f64,
    pub center_of_mass: Vector3<f64>,
    /// Inertia tensor about the centre of mass, body axes (kg m²).
    pub inertia: Matrix3<f64>,
}

impl MassProperties {
    /// The mass properties of nodes at `positions` with lumped `masses`.
    pub fn of_lumped(positions: &[Vector3<f64>], masses: &[NodalMass]) -> MassProperties {
        let mass: f64 = masses.iter().map(|m| m.mass).sum();
        let first: Vector3<f64> = positions.iter().zip(masses).map(|(x, m)| m.mass * x).sum();
        let com = if mass > 0.0 { first / mass } else { Vector3::zeros() };
        let mut inertia = Matrix3::zeros();
        for (x, m) in positions.iter().zip(masses) {
            let r = x - com;
            inertia += m.mass * (Matrix3::identity() * r.norm_squared() - r * r.transpose());
            inertia += m.rotary_inertia;
        }
        MassProperties { mass, center_of_mass: com, inertia }
    }
}
