//! Stiffness and mass matrices exported by another FE program (CalculiX's `*FREQUENCY,
//! SOLVER=MATRIXSTORAGE`, Abaqus' `*MATRIX GENERATE`, Ansys' `*SMAT`/`*EXPORT`) as a part of the
//! model: a superelement over the degrees of freedom of the mesh's nodes, assembled next to the
//! elements (if any) and reduced like any other model.
//!
//! **Mass.** The engine's inertia invariants are sums over mass points (see
//! [`MassPoint`](crate::element::MassPoint)), which a matrix alone does not give. flexmb takes the
//! mass matrices that solid elements make, lumped or consistent: the translations of two nodes coupled
//! by one scalar `m_ab`, equal in x, y and z (`M = M_s ⊗ I₃`), and not coupled with rotations;
//! rotations (if any) with a rotary inertia block per node. `M_s` is then written exactly as mass
//! points that interpolate linearly between nodes:
//!
//! - for every coupled pair `a ≠ b`, a point at the midpoint moving with `(u_a + u_b) / 2`, of mass
//!   `4 m_ab` (its `m N Nᵀ` is `m_ab` on the pair's off-diagonal, and `m_ab` on their diagonals);
//! - at every node, a point of mass `m_aa − Σ_{b≠a} m_ab` (what is left of the diagonal).
//!
//! `Σ_g m_g N_gᵀ N_g = M_s` holds exactly, and every interpolation is a partition of unity that
//! reproduces linear fields, so the mass, its first and second moments (`1ᵀ M_s x`, `xᵀ M_s x`) and
//! every invariant (bilinear in the undeformed positions and the mode shapes) are those of the matrix:
//! the exact integrals when the exporting program's elements reproduce linear fields (isoparametric
//! elements do). Some of these masses are negative (a consistent mass's off-diagonal terms of
//! quadratic elements, a diagonal smaller than its row); sums need no sign. The square-root factor
//! of the mass that the mode analysis needs is the Cholesky factor of `M_s` instead
//! ([`ImportedMatrices::mass_root_rows`]).

use std::collections::BTreeMap;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::{LltError, LltRegularization};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholeskyRaw, SymmetricOrdering};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Par, Side};
use nalgebra::{Matrix3, Matrix6};

use super::{Dof, DofSet, Mesh};
use crate::element::MassPoint;
use crate::error::FemError;

/// A symmetric stiffness and mass over the nodes' degrees of freedom, as another program exported
/// them. A degree of freedom is `6 node + dof` (node an index into [`Mesh::nodes`], dof the index of
/// `x y z rx ry rz`); each matrix is its upper triangle (`row ≤ column`), one entry per position.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ImportedMatrices {
    /// Where they came from (the stiffness file), for messages.
    pub origin: String,
    /// The stiffness's upper triangle, `(row, column, value)` with `row ≤ column`.
    pub stiffness: Vec<(usize, usize, f64)>,
    /// The mass's upper triangle, `(row, column, value)` with `row ≤ column`.
    pub mass: Vec<(usize, usize, f64)>,
}

/// The mass of [`ImportedMatrices`] split as flexmb holds it.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct SplitMass {
    /// `m_ab` (`a ≤ b`, node indices): the coupling of the translations of a and b, the same in x, y, z.
    pub translational: BTreeMap<(usize, usize), f64>,
    /// Rotary inertia blocks, by node.
    pub rotary: BTreeMap<usize, Matrix3<f64>>,
}

/// A node's share of a mass: (node index, mass, rotary inertia).
pub(crate) type NodeShare = (usize, f64, Matrix3<f64>);

impl ImportedMatrices {
    /// The dofs each of `n_nodes` nodes has in the matrices (empty for a node they do not mention).
    pub fn present_dofs(&self, n_nodes: usize) -> Vec<DofSet> {
        let mut present = vec![DofSet::EMPTY; n_nodes];
        for &(a, b, _) in self.stiffness.iter().chain(&self.mass) {
            for g in [a, b] {
                if let Some(set) = present.get_mut(g / 6) {
                    *set = set.with(Dof::ALL[g % 6]);
                }
            }
        }
        present
    }

    fn error(&self, message: String) -> FemError {
        FemError::ImportedMatrices { origin: self.origin.clone(), message }
    }

    /// Checks that every mentioned node has all three translations or none, and all three
    /// rotations or none, and that every dof lies on a node of `mesh`.
    pub(crate) fn check_dofs(&self, mesh: &Mesh) -> Result<(), FemError> {
        let n = mesh.nodes.len();
        if let Some(&(_, b, _)) = self.stiffness.iter().chain(&self.mass).find(|&&(a, b, _)| a.max(b) >= 6 * n) {
            return Err(self.error(format!("a degree of freedom of node index {} beyond the model's {n} nodes", b / 6)));
        }
        for (node, set) in self.present_dofs(n).into_iter().enumerate() {
            for (group, name) in [(DofSet::TRANSLATIONS, "translations"), (DofSet::ROTATIONS, "rotations")] {
                let has: Vec<Dof> = group.iter().filter(|&d| set.contains(d)).collect();
                if !has.is_empty() && has.len() < 3 {
                    let names: Vec<&str> = has.iter().map(|d| d.name()).collect();
                    return Err(self.error(format!(
                        "node {} has {} of its {name} in the matrices, not all three: export the matrices of the \
                         structure without boundary conditions and give the supports as [[support]] tables",
                        mesh.nodes[node].label,
                        names.join(", ")
                    )));
                }
            }
        }
        Ok(())
    }

    /// The mass as flexmb holds it: the translational couplings (checked equal in x, y, z and not
    /// across directions) and the nodes' rotary inertia blocks (checked not coupled to anything else).
    pub(crate) fn split_mass(&self, mesh: &Mesh) -> Result<SplitMass, FemError> {
        let scale = self.mass.iter().filter(|(a, b, _)| a == b).map(|(_, _, v)| v.abs()).fold(0.0, f64::max);
        let negligible = 1e-9 * scale;
        let label = |g: usize| format!("{} of node {}", Dof::ALL[g % 6].name(), mesh.nodes[g / 6].label);
        let mut directions: BTreeMap<(usize, usize), [f64; 3]> = BTreeMap::new();
        let mut split = SplitMass::default();
        for &(ga, gb, value) in &self.mass {
            if !value.is_finite() {
                return Err(self.error(format!("the mass entry of {} and {} is {value}", label(ga), label(gb))));
            }
            let (a, i, b, j) = (ga / 6, ga % 6, gb / 6, gb % 6);
            if i < 3 && j < 3 && i == j {
                directions.entry((a.min(b), a.max(b))).or_insert([0.0; 3])[i] += value;
            } else if i >= 3 && j >= 3 && a == b {
                let block = split.rotary.entry(a).or_insert_with(Matrix3::zeros);
                block[(i - 3, j - 3)] = value;
                block[(j - 3, i - 3)] = value;
            } else if value.abs() > negligible {
                return Err(self.error(format!(
                    "the mass couples {} with {} ({value:e}); flexmb takes the mass of solid elements, lumped or \
                     consistent: translations coupled equally in x, y and z and not across directions or with \
                     rotations, and each node's rotations with its own only",
                    label(ga),
                    label(gb)
                )));
            }
        }
        for ((a, b), values) in directions {
            let largest = values.iter().map(|v| v.abs()).fold(0.0, f64::max);
            let spread = values.iter().fold(f64::NEG_INFINITY, |m, v| m.max(*v)) - values.iter().fold(f64::INFINITY, |m, v| m.min(*v));
            if spread > 1e-6 * largest + negligible {
                return Err(self.error(format!(
                    "the mass couples the translations of nodes {} and {} differently in x, y and z ({:e}, {:e}, {:e}); \
                     flexmb takes masses that are the same in every direction, as solid elements' are",
                    mesh.nodes[a].label, mesh.nodes[b].label, values[0], values[1], values[2]
                )));
            }
            // Explicit zeros (CalculiX writes the stiffness's pattern) make no mass point.
            if largest > 0.0 {
                split.translational.insert((a, b), values.iter().sum::<f64>() / 3.0);
            }
        }
        Ok(split)
    }

    /// The mass as mass points (the pair decomposition of the module's documentation) and each
    /// node's share of it (the diagonal of `M_s`, scaled to the total mass, and the rotary blocks).
    pub(crate) fn mass_points(split: &SplitMass, mesh: &Mesh) -> (Vec<MassPoint>, Vec<NodeShare>) {
        let mut translation = Matrix6::zeros();
        translation.fixed_view_mut::<3, 3>(0, 0).fill_with_identity();
        let mut residual: BTreeMap<usize, f64> = BTreeMap::new();
        let mut points = Vec::new();
        for (&(a, b), &m) in &split.translational {
            if a == b {
                *residual.entry(a).or_insert(0.0) += m;
                continue;
            }
            *residual.entry(a).or_insert(0.0) -= m;
            *residual.entry(b).or_insert(0.0) -= m;
            let position = 0.5 * (mesh.nodes[a].position + mesh.nodes[b].position);
            points.push(MassPoint {
                position,
                mass: 4.0 * m,
                rotary_inertia: Matrix3::zeros(),
                interpolation: vec![(a, 0.5 * translation), (b, 0.5 * translation)],
            });
        }
        for (&node, &m) in &residual {
            if m != 0.0 {
                points.push(MassPoint::at_node(node, mesh.nodes[node].position, m, Matrix3::zeros()));
            }
        }
        for (&node, &j) in &split.rotary {
            points.push(MassPoint::at_node(node, mesh.nodes[node].position, 0.0, j));
        }
        // Each node's share: HRZ (the diagonal scaled to the total mass), positive for a positive
        // definite mass.
        let total: f64 = split.translational.iter().map(|(&(a, b), &m)| if a == b { m } else { 2.0 * m }).sum();
        let diagonal: f64 = split.translational.iter().filter(|((a, b), _)| a == b).map(|(_, m)| m).sum();
        let factor = if diagonal != 0.0 { total / diagonal } else { 0.0 };
        let mut shares: BTreeMap<usize, (f64, Matrix3<f64>)> = BTreeMap::new();
        for (&(a, b), &m) in &split.translational {
            if a == b {
                shares.entry(a).or_insert((0.0, Matrix3::zeros())).0 += factor * m;
            }
        }
        for (&node, &j) in &split.rotary {
            shares.entry(node).or_insert((0.0, Matrix3::zeros())).1 += j;
        }
        (points, shares.into_iter().map(|(n, (m, j))| (n, m, j)).collect())
    }

    /// The rows of a square-root factor `F` of the mass (`Fᵀ F = M`) over the nodes' global dofs
    /// (`6 node + dof`): `Lᵀ ⊗ I₃` of the sparse Cholesky factor `M_s = L Lᵀ` (in a fill-reducing
    /// order) on the translations, and `J^{1/2}` of each rotary block on the rotations.
    ///
    /// # Errors
    /// [`FemError::ImportedMatrices`] if `M_s` is not positive definite.
    pub(crate) fn mass_root_rows(&self, split: &SplitMass, mesh: &Mesh) -> Result<Vec<Vec<(usize, f64)>>, FemError> {
        let mut nodes: Vec<usize> = split.translational.keys().flat_map(|&(a, b)| [a, b]).collect();
        nodes.sort_unstable();
        nodes.dedup();
        let mut rows = Vec::new();
        if !nodes.is_empty() {
            let factor = self.scalar_cholesky(split, &nodes, mesh)?;
            for column in factor {
                for d in 0..3 {
                    rows.push(column.iter().map(|&(node, v)| (6 * node + d, v)).collect());
                }
            }
        }
        for (&node, &j) in &split.rotary {
            for row in MassPoint::at_node(node, mesh.nodes[node].position, 0.0, j).inertia_root_rows() {
                rows.push((0..3).map(|c| (6 * node + 3 + c, row[3 + c])).filter(|&(_, v)| v != 0.0).collect());
            }
        }
        Ok(rows)
    }

    /// The columns of the Cholesky factor of `M_s` over `nodes` (in a fill-reducing order: `P M_s Pᵀ
    /// = L Lᵀ`, so that `Fᵀ F = M_s` for the rows `F = Lᵀ P`), each as (node, value) pairs.
    fn scalar_cholesky(&self, split: &SplitMass, nodes: &[usize], mesh: &Mesh) -> Result<Vec<Vec<(usize, f64)>>, FemError> {
        let n = nodes.len();
        let index: BTreeMap<usize, usize> = nodes.iter().enumerate().map(|(k, &node)| (node, k)).collect();
        let mut columns = vec![Vec::new(); n];
        for (&(a, b), &m) in &split.translational {
            let (i, j) = (index[&a], index[&b]);
            columns[i.max(j)].push((i.min(j), m));
        }
        let (mut pointers, mut rows, mut values) = (vec![0], Vec::new(), Vec::new());
        for column in &mut columns {
            column.sort_by_key(|&(row, _)| row);
            rows.extend(column.iter().map(|(r, _)| *r));
            values.extend(column.iter().map(|(_, v)| *v));
            pointers.push(rows.len());
        }
        let linear = |e: String| FemError::LinearAlgebra(format!("the imported mass's factor: {e}"));
        let pattern = SymbolicSparseColMat::new_checked(n, n, pointers, None, rows);
        let upper = SparseColMatRef::new(pattern.as_ref(), &values);
        let params = CholeskySymbolicParams { supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL, ..Default::default() };
        let symbolic = factorize_symbolic_cholesky(pattern.as_ref(), Side::Upper, SymmetricOrdering::Amd, params)
            .map_err(|e| linear(format!("{e:?}")))?;
        let mut l_values = vec![0.0; symbolic.len_val()];
        let mut memory = MemBuffer::try_new(symbolic.factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default()))
            .map_err(|e| linear(format!("{e:?}")))?;
        let factored = symbolic.factorize_numeric_llt(
            &mut l_values,
            upper,
            Side::Upper,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut memory),
            Default::default(),
        );
        let forward: Vec<usize> = match symbolic.perm() {
            Some(perm) => perm.arrays().0.to_vec(),
            None => (0..n).collect(),
        };
        if let Err(e) = factored {
            let LltError::NonPositivePivot { index } = e;
            let node = forward.get(index).map(|&old| format!(" (at node {})", mesh.nodes[nodes[old]].label)).unwrap_or_default();
            return Err(self.error(format!(
                "the mass matrix is not positive definite{node}: every node of the matrices must carry mass in every \
                 translation"
            )));
        }
        let SymbolicCholeskyRaw::Simplicial(factor) = symbolic.raw() else {
            return Err(linear("expected a simplicial factor".into()));
        };
        let (col_ptr, row_idx) = (factor.col_ptr(), factor.row_idx());
        Ok((0..n)
            .map(|c| {
                (col_ptr[c]..col_ptr[c + 1])
                    .map(|k| (nodes[forward[row_idx[k]]], l_values[k]))
                    .filter(|&(_, v)| v != 0.0)
                    .collect()
            })
            .collect())
    }
}
