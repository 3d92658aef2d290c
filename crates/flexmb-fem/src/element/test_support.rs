//! Helpers of the element tests: rotations, rigid motions, eigenvalues, a small dense assembly.

use nalgebra::{DMatrix, DVector, Matrix3, Rotation3, Unit, Vector3};

/// The rotation by `angle` about `axis`.
pub(crate) fn rotation(axis: Vector3<f64>, angle: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Unit::new_normalize(axis), angle).into_inner()
}

/// An oblique rotation used to place elements at a general orientation in space.
pub(crate) fn oblique() -> Matrix3<f64> {
    rotation(Vector3::new(0.3, -0.7, 0.5), 1.1)
}

/// `diag(q, q, …)` over the 2 blocks (translation, rotation) of each of `nodes` nodes.
pub(crate) fn block_rotation(nodes: usize, q: &Matrix3<f64>) -> DMatrix<f64> {
    let mut t = DMatrix::zeros(6 * nodes, 6 * nodes);
    for block in 0..2 * nodes {
        t.fixed_view_mut::<3, 3>(3 * block, 3 * block).copy_from(q);
    }
    t
}

/// The six rigid motions of nodes at `points`: unit translations along x, y, z, then unit rotations
/// ω about x, y, z about the origin (nodal translations ω × p, nodal rotations ω).
pub(crate) fn rigid_motions(points: &[Vector3<f64>]) -> Vec<DVector<f64>> {
    let mut motions = Vec::new();
    for k in 0..6 {
        let mut d = DVector::zeros(6 * points.len());
        let e = Vector3::ith(k % 3, 1.0);
        for (i, p) in points.iter().enumerate() {
            if k < 3 {
                d.fixed_rows_mut::<3>(6 * i).copy_from(&e);
            } else {
                d.fixed_rows_mut::<3>(6 * i).copy_from(&e.cross(p));
                d.fixed_rows_mut::<3>(6 * i + 3).copy_from(&e);
            }
        }
        motions.push(d);
    }
    motions
}

/// The eigenvalues of the symmetric `k` divided by the largest magnitude, ascending.
pub(crate) fn relative_eigenvalues(k: &DMatrix<f64>) -> Vec<f64> {
    let eigen = k.clone().symmetric_eigen();
    let largest = eigen.eigenvalues.amax();
    let mut values: Vec<f64> = eigen.eigenvalues.iter().map(|v| v / largest).collect();
    values.sort_by(f64::total_cmp);
    values
}

/// Largest |K − Kᵀ| relative to the largest |K|.
pub(crate) fn asymmetry(k: &DMatrix<f64>) -> f64 {
    (k - k.transpose()).amax() / k.amax()
}

/// Checks that `k` (of nodes at `points`) is symmetric, has exactly six eigenvalues below 1e-10 of
/// the largest and the seventh above `seventh_at_least`, and gives forces below 1e-10 (relative to
/// the largest stiffness times the motion's size) for each rigid motion. Returns the seventh
/// relative eigenvalue.
pub(crate) fn assert_rigid_body_modes(
    k: &DMatrix<f64>,
    points: &[Vector3<f64>],
    seventh_at_least: f64,
) -> f64 {
    assert!(asymmetry(k) < 1e-13, "asymmetry {:e}", asymmetry(k));
    let values = relative_eigenvalues(k);
    for v in &values[..6] {
        assert!(v.abs() < 1e-10, "rigid-body eigenvalue {v:e} of {values:?}");
    }
    assert!(
        values[6] > seventh_at_least,
        "seventh eigenvalue {:e} (expected > {seventh_at_least:e})",
        values[6]
    );
    for (i, d) in rigid_motions(points).iter().enumerate() {
        let force = (k * d).amax() / (k.amax() * d.amax());
        assert!(force < 1e-10, "rigid motion {i}: relative force {force:e}");
    }
    values[6]
}

/// A dense stiffness of `nodes` nodes with 6 degrees of freedom each.
pub(crate) struct DenseModel {
    pub k: DMatrix<f64>,
}

impl DenseModel {
    pub(crate) fn new(nodes: usize) -> Self {
        Self {
            k: DMatrix::zeros(6 * nodes, 6 * nodes),
        }
    }

    /// Adds an element stiffness whose nodes are `nodes`.
    pub(crate) fn add(&mut self, nodes: &[usize], ke: &DMatrix<f64>) {
        for (a, &na) in nodes.iter().enumerate() {
            for (b, &nb) in nodes.iter().enumerate() {
                let mut block = self.k.view_mut((6 * na, 6 * nb), (6, 6));
                block += ke.view((6 * a, 6 * b), (6, 6));
            }
        }
    }

    /// Solves `K u = f` with the degrees of freedom in `prescribed` held at their values; returns all
    /// of u.
    pub(crate) fn solve(&self, prescribed: &[(usize, f64)], loads: &DVector<f64>) -> DVector<f64> {
        let n = self.k.nrows();
        let mut u = DVector::zeros(n);
        let mut is_fixed = vec![false; n];
        for &(dof, value) in prescribed {
            u[dof] = value;
            is_fixed[dof] = true;
        }
        let free: Vec<usize> = (0..n).filter(|&i| !is_fixed[i]).collect();
        let rhs = loads - &self.k * &u;
        let k_ff = DMatrix::from_fn(free.len(), free.len(), |r, c| self.k[(free[r], free[c])]);
        let f_f = DVector::from_fn(free.len(), |r, _| rhs[free[r]]);
        let u_f = k_ff
            .lu()
            .solve(&f_f)
            .expect("the constrained stiffness is singular");
        for (r, &dof) in free.iter().enumerate() {
            u[dof] = u_f[r];
        }
        u
    }
}

/// The element mass matrix (6n × 6n, element node order) of mass points: `Σ_g G_gᵀ diag(m I, J) G_g`.
pub(super) fn mass_matrix_of_points(points: &[super::MassPoint], nodes: usize) -> DMatrix<f64> {
    let mut m = DMatrix::zeros(6 * nodes, 6 * nodes);
    for p in points {
        let d = p.inertia_block();
        for (a, ga) in &p.interpolation {
            for (b, gb) in &p.interpolation {
                let block = ga.transpose() * d * gb;
                let mut view = m.view_mut((6 * a, 6 * b), (6, 6));
                view += block;
            }
        }
    }
    m
}
