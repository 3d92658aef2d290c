//! Assembly of the global stiffness and mass: equation numbers for the free degrees of freedom
//! (supports removed), element matrices added at their rows, sparse storage. The mass is held as
//! mass points (one per node for the lumped mass, the elements' Gauss points for the consistent
//! one), from which the mass matrix and its square-root factor follow.

use faer::sparse::{SparseColMat, SymbolicSparseColMat, Triplet};
use nalgebra::{Matrix3, Vector3};

use crate::element::{element_matrices, MassPoint, NodalMass};
use crate::error::FemError;
use std::collections::{BTreeMap, HashSet};

use crate::mesh::{dependent_dofs, DependentDof, Dof, DofSet, FeModel, ImportedMatrices, MassModel, Mesh, NodeShare, SplitMass};

/// Equation numbers of the nodal degrees of freedom: up to 6 per node; supported ones have none, and
/// neither have the rotations of nodes that only solid elements touch (absent: the node has
/// translations only, see [`present_dofs`]) nor the dofs of nodes rigidly coupled to a reference
/// node (dependent: combinations of the reference node's equations, see
/// [`RigidCoupling`](crate::mesh::RigidCoupling)).
#[derive(Clone, Debug, PartialEq)]
pub struct DofMap {
    /// Per node and dof (`6 node + dof`), the equation number, or `None` where supported, absent or
    /// dependent.
    equations: Vec<Option<usize>>,
    /// Per node and dof, whether the node has it.
    present: Vec<bool>,
    /// The dependent dofs and their combinations of equations.
    dependent: BTreeMap<usize, Vec<(usize, f64)>>,
    n_free: usize,
}

impl DofMap {
    /// Numbers the free degrees of freedom node by node, every node having all six; a node beyond
    /// `supported` is free.
    pub fn new(n_nodes: usize, supported: &[DofSet]) -> DofMap {
        DofMap::with_present(n_nodes, supported, &[])
    }

    /// Numbers the free degrees of freedom node by node: those in `present` (all six for a node
    /// beyond it) and not in `supported` (none for a node beyond it). A support of an absent dof is
    /// without effect.
    pub fn with_present(n_nodes: usize, supported: &[DofSet], present: &[DofSet]) -> DofMap {
        DofMap::with_couplings(n_nodes, supported, present, &[])
    }

    /// [`with_present`](Self::with_present), with `dependent` global dofs that are combinations of
    /// other global dofs (those of rigid couplings' reference nodes): they get no equation, and their
    /// combination is over the equations of the dofs they depend on (a supported one is zero).
    pub(crate) fn with_couplings(n_nodes: usize, supported: &[DofSet], present: &[DofSet], dependent: &[DependentDof]) -> DofMap {
        let mut equations = vec![None; 6 * n_nodes];
        let mut has = vec![true; 6 * n_nodes];
        let is_dependent: HashSet<usize> = dependent.iter().map(|(g, _)| *g).collect();
        let mut n_free = 0;
        for node in 0..n_nodes {
            for dof in Dof::ALL {
                let global = 6 * node + dof.index();
                if !present.get(node).is_none_or(|p| p.contains(dof)) {
                    has[global] = false;
                } else if !supported.get(node).is_some_and(|s| s.contains(dof)) && !is_dependent.contains(&global) {
                    equations[global] = Some(n_free);
                    n_free += 1;
                }
            }
        }
        let dependent = dependent
            .iter()
            .map(|(g, terms)| {
                let on_equations = terms.iter().filter_map(|&(rg, c)| equations.get(rg).copied().flatten().map(|e| (e, c))).collect();
                (*g, on_equations)
            })
            .collect();
        DofMap { equations, present: has, dependent, n_free }
    }

    /// The combination of equations global dof `6 node + dof` is: itself, the combination of a
    /// dependent dof, or nothing (supported, absent).
    pub fn terms(&self, global: usize) -> Vec<(usize, f64)> {
        match (self.equation_of(global), self.dependent.get(&global)) {
            (Some(e), _) => vec![(e, 1.0)],
            (None, Some(terms)) => terms.clone(),
            (None, None) => Vec::new(),
        }
    }

    /// Whether global dof `6 node + dof` is tied to a reference node by a rigid coupling.
    pub fn is_dependent(&self, global: usize) -> bool {
        self.dependent.contains_key(&global)
    }

    /// Whether global dof `6 node + dof` exists (false for the rotations of solid-only nodes and
    /// beyond the nodes).
    pub fn is_present(&self, global: usize) -> bool {
        self.present.get(global).copied().unwrap_or(false)
    }

    /// Whether global dof `6 node + dof` exists and is supported.
    pub fn is_held(&self, global: usize) -> bool {
        self.is_present(global) && self.equation_of(global).is_none() && !self.is_dependent(global)
    }

    /// The equation of `dof` of `node`, `None` if supported or beyond the nodes.
    pub fn equation(&self, node: usize, dof: Dof) -> Option<usize> {
        self.equation_of(6 * node + dof.index())
    }

    /// The equation of global dof index `6 node + dof`, `None` if supported or beyond the nodes.
    pub fn equation_of(&self, global: usize) -> Option<usize> {
        self.equations.get(global).copied().flatten()
    }

    /// Whether every equation is a translation (a mesh of solid elements, whose nodes have no
    /// rotations, with any reference node held).
    pub fn only_translations(&self) -> bool {
        self.equations.iter().enumerate().all(|(global, e)| e.is_none() || global % 6 < 3)
    }

    /// Number of free degrees of freedom (the size of the assembled matrices).
    pub fn n_free(&self) -> usize {
        self.n_free
    }

    /// The node and dof of equation `equation`, `None` beyond [`n_free`](Self::n_free).
    pub fn node_dof(&self, equation: usize) -> Option<(usize, Dof)> {
        let global = self.equations.iter().position(|e| *e == Some(equation))?;
        Some((global / 6, Dof::ALL[global % 6]))
    }

    /// Number of nodes.
    pub fn n_nodes(&self) -> usize {
        self.equations.len() / 6
    }

    /// Scatters a vector over the free dofs into all `6 n_nodes` nodal dofs (zeros at supports, and
    /// where `free` is shorter than [`n_free`](Self::n_free)).
    pub fn expand(&self, free: &[f64]) -> Vec<f64> {
        let value = |e: usize| free.get(e).copied().unwrap_or(0.0);
        (0..self.equations.len())
            .map(|g| match (self.equations[g], self.dependent.get(&g)) {
                (Some(e), _) => value(e),
                (None, Some(terms)) => terms.iter().map(|&(e, c)| c * value(e)).sum(),
                (None, None) => 0.0,
            })
            .collect()
    }

    /// The map of `self`, the equations of a model, to those of `supported`, the same model with
    /// more dofs held: for each equation of `self`, its equation in `supported` (`None` where held).
    /// `None` if `supported` is not `self` with equations removed: an equation of its own, a dof
    /// present in one and absent in the other, or a dependent dof that depends on other equations
    /// (a support on a node of a distributing coupling changes what the coupling eliminates).
    fn restriction_to(&self, supported: &DofMap) -> Option<Vec<Option<usize>>> {
        if self.present != supported.present || self.dependent.len() != supported.dependent.len() {
            return None;
        }
        let mut kept = vec![None; self.n_free];
        for (own, &restricted) in self.equations.iter().zip(&supported.equations) {
            match (own, restricted) {
                (Some(f), Some(e)) => kept[*f] = Some(e),
                (None, Some(_)) => return None,
                _ => {}
            }
        }
        for (global, terms) in &self.dependent {
            let restricted: Vec<(usize, f64)> = terms.iter().filter_map(|&(f, c)| kept[f].map(|e| (e, c))).collect();
            if supported.dependent.get(global) != Some(&restricted) {
                return None;
            }
        }
        Some(kept)
    }
}

/// The assembled model: equation numbers, sparse stiffness and mass over the free dofs (both
/// triangles stored), the mass points the mass is made of, and the lumped mass per node.
#[derive(Clone, Debug)]
pub struct AssembledModel {
    /// The equation number of every free dof.
    pub dofs: DofMap,
    /// `K` over the free dofs.
    pub stiffness: SparseColMat<usize, f64>,
    /// `M = Σ_g G_gᵀ diag(m_g I, J_g) G_g` over the mass points.
    pub mass: SparseColMat<usize, f64>,
    /// A square-root factor `F` of the mass, `Fᵀ F = M`: rows `√m_g G_g` (translations) and
    /// `J_g^{1/2} G_g` (rotations) of every mass point with mass or rotary inertia.
    pub mass_root: SparseColMat<usize, f64>,
    /// The mass points (interpolation indices are mesh node indices): what the inertia invariants
    /// and the mass properties sum over.
    pub mass_points: Vec<MassPoint>,
    /// Lumped mass and rotary inertia at each node, elements and point masses together: the mass
    /// points of the lumped mass, and each node's share of the mass with the consistent one.
    pub nodal_masses: Vec<NodalMass>,
    /// The undeformed position of every equation's node (m): where the fill-reducing ordering of
    /// the factorizations cuts the mesh.
    pub equation_positions: Vec<Vector3<f64>>,
}

impl AssembledModel {
    /// The assembly of `supported`, the model `self` was assembled from with more supports, taken
    /// from `self`: the stiffness and mass less the rows and columns of the newly held equations, the
    /// mass factor less their columns (and the rows left empty). That is what [`assemble`] gives (the
    /// same element matrices at the same places; the held dofs' terms dropped), but without computing
    /// the element matrices and sorting their entries again. `None` where the supports change more
    /// than which equations there are (a support on a node of a distributing coupling changes what the
    /// coupling eliminates): assemble `supported` then.
    pub fn with_supports(&self, supported: &FeModel) -> Result<Option<AssembledModel>, FemError> {
        supported.check_references()?;
        let mesh = &supported.mesh;
        let present = present_dofs(mesh);
        let held = supported_dofs(supported);
        let dependent = dependent_dofs(supported, &present, &held)?;
        let dofs = DofMap::with_couplings(mesh.nodes.len(), &held, &present, &dependent);
        if dofs.n_free() == 0 {
            return Err(FemError::NoFreeDofs);
        }
        let Some(kept) = self.dofs.restriction_to(&dofs) else {
            return Ok(None);
        };
        let n = dofs.n_free();
        Ok(Some(AssembledModel {
            stiffness: principal_submatrix(&self.stiffness, &kept, n),
            mass: principal_submatrix(&self.mass, &kept, n),
            mass_root: without_columns(&self.mass_root, &kept, n),
            dofs,
            mass_points: self.mass_points.clone(),
            nodal_masses: self.nodal_masses.clone(),
            equation_positions: (0..self.dofs.n_free()).filter(|&f| kept[f].is_some()).map(|f| self.equation_positions[f]).collect(),
        }))
    }
}

/// The rows and columns `i` of `a` with `kept[i]` some, at `kept[i]` (increasing with `i`) of an
/// `n × n` matrix.
fn principal_submatrix(a: &SparseColMat<usize, f64>, kept: &[Option<usize>], n: usize) -> SparseColMat<usize, f64> {
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let (mut row_idx, mut values) = (Vec::with_capacity(a.compute_nnz()), Vec::with_capacity(a.compute_nnz()));
    for column in (0..a.ncols()).filter(|&j| kept[j].is_some()) {
        for (i, v) in a.row_idx_of_col(column).zip(a.val_of_col(column)) {
            if let Some(row) = kept[i] {
                row_idx.push(row);
                values.push(*v);
            }
        }
        col_ptr.push(row_idx.len());
    }
    SparseColMat::new(SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx), values)
}

/// The columns `j` of `a` with `kept[j]` some, at `kept[j]` (increasing with `j`) of `n` columns,
/// and the rows that have an entry in them, in their order.
fn without_columns(a: &SparseColMat<usize, f64>, kept: &[Option<usize>], n: usize) -> SparseColMat<usize, f64> {
    let columns = || (0..a.ncols()).filter(|&j| kept[j].is_some());
    let mut row_of = vec![None; a.nrows()];
    for column in columns() {
        a.row_idx_of_col(column).for_each(|i| row_of[i] = Some(0));
    }
    let mut rows = 0;
    for row in row_of.iter_mut().flatten() {
        *row = rows;
        rows += 1;
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0);
    let (mut row_idx, mut values) = (Vec::new(), Vec::new());
    for column in columns() {
        for (i, v) in a.row_idx_of_col(column).zip(a.val_of_col(column)) {
            row_idx.push(row_of[i].expect("a row with an entry in a kept column"));
            values.push(*v);
        }
        col_ptr.push(row_idx.len());
    }
    SparseColMat::new(SymbolicSparseColMat::new_checked(rows, n, col_ptr, None, row_idx), values)
}

/// The supported dofs of every node. A support at a node the mesh does not have is left out here;
/// [`FeModel::check_references`] reports it.
pub fn supported_dofs(model: &FeModel) -> Vec<DofSet> {
    let mut supported = vec![DofSet::EMPTY; model.mesh.nodes.len()];
    for s in &model.supports {
        if let Some(set) = supported.get_mut(s.node) {
            *set = set.union(s.dofs);
        }
    }
    supported
}

/// The dofs every node has: the three translations at nodes that solid elements touch and no beam or
/// shell does, all six elsewhere; with imported matrices, a node they mention and no element touches
/// has the dofs they give it, and one nothing mentions has all six.
pub fn present_dofs(mesh: &Mesh) -> Vec<DofSet> {
    let n = mesh.nodes.len();
    let (mut solid, mut rotational) = (vec![false; n], vec![false; n]);
    for element in &mesh.elements {
        let touched = if element.kind.has_rotations() { &mut rotational } else { &mut solid };
        for &node in &element.nodes {
            if let Some(t) = touched.get_mut(node) {
                *t = true;
            }
        }
    }
    let imported = mesh.imported.as_ref().map(|m| m.present_dofs(n)).unwrap_or_default();
    (0..n)
        .map(|i| {
            let from_matrices = imported.get(i).copied().unwrap_or(DofSet::EMPTY);
            match (solid[i], rotational[i]) {
                (_, true) => DofSet::ALL,
                (true, false) => DofSet::TRANSLATIONS.union(from_matrices),
                (false, false) if !from_matrices.is_empty() => from_matrices,
                (false, false) => DofSet::ALL,
            }
        })
        .collect()
}

/// Assembles the stiffness and lumped mass of `model`.
pub fn assemble(model: &FeModel) -> Result<AssembledModel, FemError> {
    model.check_references()?;
    let mesh = &model.mesh;
    let n_nodes = mesh.nodes.len();
    let present = present_dofs(mesh);
    let supported = supported_dofs(model);
    let dependent = dependent_dofs(model, &present, &supported)?;
    let dofs = DofMap::with_couplings(n_nodes, &supported, &present, &dependent);
    if dofs.n_free() == 0 {
        return Err(FemError::NoFreeDofs);
    }
    let mut nodal_masses = vec![NodalMass { mass: 0.0, rotary_inertia: Matrix3::zeros() }; n_nodes];
    let mut mass_points = Vec::new();
    // The mass of the elements whose mass is lumped, and the point masses, node by node.
    let mut lumped = nodal_masses.clone();
    let mut stiffness_triplets = Vec::new();
    // Every nodal dof, supported or not, must be resisted by some element.
    let mut stiff_dof = vec![false; 6 * n_nodes];
    for element in &mesh.elements {
        let matrices = element_matrices(mesh, element, &model.options)
            .map_err(|source| FemError::Element { label: element.label, source })?;
        let globals: Vec<usize> =
            element.nodes.iter().flat_map(|&n| (0..6).map(move |d| 6 * n + d)).collect();
        let terms: Vec<Vec<(usize, f64)>> = globals.iter().map(|&g| dofs.terms(g)).collect();
        for (a, &ga) in globals.iter().enumerate() {
            if matrices.stiffness[(a, a)] > 0.0 {
                stiff_dof[ga] = true;
            }
            for &(row, ca) in &terms[a] {
                for (b, column_terms) in terms.iter().enumerate() {
                    let value = matrices.stiffness[(a, b)];
                    if value == 0.0 {
                        continue;
                    }
                    for &(col, cb) in column_terms {
                        stiffness_triplets.push(Triplet::new(row, col, ca * value * cb));
                    }
                }
            }
        }
        let consistent = model.options.mass_of(element.kind) == MassModel::Consistent;
        for (&node, share) in element.nodes.iter().zip(&matrices.lumped_mass) {
            nodal_masses[node].mass += share.mass;
            nodal_masses[node].rotary_inertia += share.rotary_inertia;
            if !consistent {
                lumped[node].mass += share.mass;
                lumped[node].rotary_inertia += share.rotary_inertia;
            }
        }
        for mut point in matrices.consistent_mass {
            for (node, _) in point.interpolation.iter_mut() {
                *node = element.nodes[*node];
            }
            mass_points.push(point);
        }
    }
    for pm in &mesh.point_masses {
        let label = mesh.nodes[pm.node].label;
        if !(pm.mass.is_finite() && pm.mass >= 0.0) {
            return Err(FemError::InvalidPointMass { label, mass: pm.mass });
        }
        if pm.rotary_inertia != Vector3::zeros() && !present[pm.node].contains(Dof::Rx) {
            return Err(FemError::RotaryInertiaWithoutRotations { label });
        }
        for masses in [&mut nodal_masses, &mut lumped] {
            masses[pm.node].mass += pm.mass;
            masses[pm.node].rotary_inertia += Matrix3::from_diagonal(&pm.rotary_inertia);
        }
    }
    // The consistent elements' points, then a point at each node that has lumped mass.
    mass_points.extend(
        lumped
            .iter()
            .enumerate()
            .filter(|(_, m)| m.mass != 0.0 || m.rotary_inertia != Matrix3::zeros())
            .map(|(node, m)| MassPoint::at_node(node, mesh.nodes[node].position, m.mass, m.rotary_inertia)),
    );
    let (mut root_rows, mut imported_points) = (Vec::new(), 0);
    if let Some(imported) = &mesh.imported {
        let matrices = imported_matrices(mesh, imported, &dofs, &mut stiffness_triplets, &mut stiff_dof)?;
        for (node, mass, rotary) in matrices.shares {
            nodal_masses[node].mass += mass;
            nodal_masses[node].rotary_inertia += rotary;
        }
        root_rows = matrices.root_rows;
        imported_points = matrices.points.len();
        // The mass root is built from the elements' points and the factor's rows, the mass matrix and
        // the invariants from all points.
        mass_points.extend(matrices.points);
    }
    // A coupled dof's stiffness acts on the reference node's dofs it depends on.
    for (global, terms) in &dependent {
        if stiff_dof[*global] {
            terms.iter().for_each(|&(reference, _)| stiff_dof[reference] = true);
        }
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
    let stiffness = compressed_columns(n, &stiffness_triplets).map_err(|e| FemError::LinearAlgebra(format!("stiffness assembly: {e}")))?;
    drop(stiffness_triplets);
    let mass = mass_matrix(&dofs, &mass_points)?;
    let element_points = mass_points.len() - imported_points;
    let mass_root = mass_root(&dofs, &mass_points[..element_points], &root_rows)?;
    let mut equation_positions = vec![Vector3::zeros(); n];
    for (global, node) in (0..6 * n_nodes).map(|g| (g, &mesh.nodes[g / 6])) {
        if let Some(e) = dofs.equation_of(global) {
            equation_positions[e] = node.position;
        }
    }
    Ok(AssembledModel { dofs, stiffness, mass, mass_root, mass_points, nodal_masses, equation_positions })
}

/// What imported matrices add to the assembly besides their stiffness.
struct ImportedMass {
    /// Mass points that make up their mass (some of negative mass).
    points: Vec<MassPoint>,
    /// Each node's share of the mass: (node, mass, rotary inertia).
    shares: Vec<NodeShare>,
    /// Rows of a square-root factor of their mass, over global dofs `6 node + dof`.
    root_rows: Vec<Vec<(usize, f64)>>,
}

/// Adds the stiffness of `imported` to `triplets` (and marks the dofs it resists), and returns its
/// mass as mass points, nodal shares and factor rows.
fn imported_matrices(
    mesh: &Mesh,
    imported: &ImportedMatrices,
    dofs: &DofMap,
    triplets: &mut Vec<Triplet<usize, usize, f64>>,
    stiff_dof: &mut [bool],
) -> Result<ImportedMass, FemError> {
    imported.check_dofs(mesh)?;
    for &(a, b, value) in &imported.stiffness {
        if !value.is_finite() {
            return Err(FemError::ImportedMatrices {
                origin: imported.origin.clone(),
                message: format!("the stiffness entry of dofs {a} and {b} is {value}"),
            });
        }
        if value == 0.0 {
            continue;
        }
        if a == b && value > 0.0 {
            stiff_dof[a] = true;
        }
        let (ta, tb) = (dofs.terms(a), dofs.terms(b));
        for &(row, ca) in &ta {
            for &(col, cb) in &tb {
                triplets.push(Triplet::new(row, col, ca * value * cb));
                if a != b {
                    triplets.push(Triplet::new(col, row, ca * value * cb));
                }
            }
        }
    }
    let split: SplitMass = imported.split_mass(mesh)?;
    let (points, shares) = ImportedMatrices::mass_points(&split, mesh);
    let root_rows = imported.mass_root_rows(&split, mesh)?;
    Ok(ImportedMass { points, shares, root_rows })
}

/// The rows of `G` of `point` over the free dofs: for each of its 6 rows, (equation, value) pairs.
fn free_rows(dofs: &DofMap, point: &MassPoint) -> [Vec<(usize, f64)>; 6] {
    let mut rows: [Vec<(usize, f64)>; 6] = Default::default();
    for (node, block) in &point.interpolation {
        for dof in Dof::ALL {
            for (e, c) in dofs.terms(6 * node + dof.index()) {
                for (r, row) in rows.iter_mut().enumerate() {
                    let value = block[(r, dof.index())];
                    if value != 0.0 {
                        row.push((e, c * value));
                    }
                }
            }
        }
    }
    rows
}

/// The mass matrix over the free dofs, `Σ_g G_gᵀ diag(m_g I, J_g) G_g`, with the whole diagonal
/// stored.
fn mass_matrix(dofs: &DofMap, points: &[MassPoint]) -> Result<SparseColMat<usize, f64>, FemError> {
    let mut triplets: Vec<Triplet<usize, usize, f64>> = (0..dofs.n_free()).map(|e| Triplet::new(e, e, 0.0)).collect();
    for point in points {
        let rows = free_rows(dofs, point);
        let inertia = point.inertia_block();
        for a in 0..6 {
            for b in 0..6 {
                let d = inertia[(a, b)];
                if d == 0.0 {
                    continue;
                }
                for &(ea, ga) in &rows[a] {
                    for &(eb, gb) in &rows[b] {
                        triplets.push(Triplet::new(ea, eb, ga * d * gb));
                    }
                }
            }
        }
    }
    let n = dofs.n_free();
    compressed_columns(n, &triplets).map_err(|e| FemError::LinearAlgebra(format!("mass assembly: {e}")))
}

/// The `n × n` compressed-column matrix of the sum of `triplets` (the duplicates added), built by a
/// counting sort on the columns and a sort of each column's few rows. faer's general conversion
/// sorts all the triplets at once, which took a quarter of the reduction of a 220,515-dof solid
/// (33 million stiffness triplets, assembled twice).
fn compressed_columns(n: usize, triplets: &[Triplet<usize, usize, f64>]) -> Result<SparseColMat<usize, f64>, String> {
    if let Some(t) = triplets.iter().find(|t| t.row >= n || t.col >= n) {
        return Err(format!("entry ({}, {}) outside the {n} equations", t.row, t.col));
    }
    let mut start = vec![0usize; n + 1];
    for t in triplets {
        start[t.col + 1] += 1;
    }
    for j in 0..n {
        start[j + 1] += start[j];
    }
    let mut next = start.clone();
    let mut entries = vec![(0usize, 0.0f64); triplets.len()];
    for t in triplets {
        entries[next[t.col]] = (t.row, t.val);
        next[t.col] += 1;
    }
    let mut col_ptr = Vec::with_capacity(n + 1);
    let (mut row_idx, mut values) = (Vec::new(), Vec::new());
    col_ptr.push(0);
    for j in 0..n {
        let column = &mut entries[start[j]..start[j + 1]];
        column.sort_unstable_by_key(|&(row, _)| row);
        let first = row_idx.len();
        for &(row, value) in column.iter() {
            if row_idx.len() > first && row_idx.last() == Some(&row) {
                *values.last_mut().expect("a value per row index") += value;
            } else {
                row_idx.push(row);
                values.push(value);
            }
        }
        col_ptr.push(row_idx.len());
    }
    let symbolic = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
    Ok(SparseColMat::new(symbolic, values))
}

/// The square-root factor `F` of the mass (`Fᵀ F = M`), one row per massive translation or rotation
/// of every mass point, then `global_rows` (rows over global dofs `6 node + dof`, of imported
/// matrices); rows of supported motions that vanish are dropped.
fn mass_root(dofs: &DofMap, points: &[MassPoint], global_rows: &[Vec<(usize, f64)>]) -> Result<SparseColMat<usize, f64>, FemError> {
    let mut triplets = Vec::new();
    let mut row_count = 0;
    for row in global_rows {
        let entries: Vec<(usize, f64)> =
            row.iter().flat_map(|&(g, v)| dofs.terms(g).into_iter().map(move |(e, c)| (e, c * v))).collect();
        if entries.is_empty() {
            continue;
        }
        triplets.extend(entries.into_iter().map(|(e, v)| Triplet::new(row_count, e, v)));
        row_count += 1;
    }
    for point in points {
        let rows = free_rows(dofs, point);
        for root in point.inertia_root_rows() {
            let mut entries: Vec<(usize, f64)> = Vec::new();
            for (k, r) in root.iter().enumerate() {
                if *r != 0.0 {
                    entries.extend(rows[k].iter().map(|&(e, g)| (e, r * g)));
                }
            }
            if entries.is_empty() {
                continue;
            }
            triplets.extend(entries.into_iter().map(|(e, v)| Triplet::new(row_count, e, v)));
            row_count += 1;
        }
    }
    SparseColMat::try_new_from_triplets(row_count, dofs.n_free(), &triplets)
        .map_err(|e| FemError::LinearAlgebra(format!("mass factor: {e:?}")))
}

/// Total mass, centre of mass and inertia about the centre of mass of the lumped model (rotary
/// inertia included): the rigid-body properties a flexible body must reproduce.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MassProperties {
    /// Total mass (kg).
    pub mass: f64,
    /// Centre of mass in the body frame (m).
    pub center_of_mass: Vector3<f64>,
    /// Inertia tensor about the centre of mass, body axes (kg m²).
    pub inertia: Matrix3<f64>,
}

impl MassProperties {
    /// The mass properties of mass points.
    pub fn of_points(points: &[MassPoint]) -> MassProperties {
        let mass: f64 = points.iter().map(|p| p.mass).sum();
        let first: Vector3<f64> = points.iter().map(|p| p.mass * p.position).sum();
        let com = if mass > 0.0 { first / mass } else { Vector3::zeros() };
        let mut inertia = Matrix3::zeros();
        for p in points {
            let r = p.position - com;
            inertia += p.mass * (Matrix3::identity() * r.norm_squared() - r * r.transpose());
            inertia += p.rotary_inertia;
        }
        MassProperties { mass, center_of_mass: com, inertia }
    }
}
