//! The rigid motions a set of supports leaves free: the zero-frequency mechanisms of an
//! under-determined boundary set (the seed's door turns about its hinge line).
//!
//! A connected beam/shell mesh has exactly six rigid motions: the translations, and the rotations
//! `u = θ × (x − x₀)` with nodal rotations `θ`. Those that satisfy every support (zero at every held
//! dof) are the mechanisms of the supported model; they are found here from geometry, exactly, so
//! they need not be told apart from low elastic frequencies by a threshold.

use faer::Mat;
use nalgebra::{Matrix6, SymmetricEigen, Vector3};

use crate::assembly::DofMap;
use crate::mesh::Mesh;

/// The six rigid motions of the whole mesh as nodal vectors (`6 n_nodes × 6`): columns are
/// translations along x, y, z and rotations about axes through the mesh centre, the rotation
/// columns scaled by the mesh size so that all columns have comparable size.
fn all_rigid_motions(mesh: &Mesh) -> Mat<f64> {
    let n = mesh.nodes.len();
    let center: Vector3<f64> =
        mesh.nodes.iter().map(|node| node.position).sum::<Vector3<f64>>() / n.max(1) as f64;
    let scale = mesh.size().max(f64::MIN_POSITIVE);
    let mut r = Mat::zeros(6 * n, 6);
    for (i, node) in mesh.nodes.iter().enumerate() {
        let x = (node.position - center) / scale;
        for k in 0..3 {
            r[(6 * i + k, k)] = 1.0;
            let mut axis = Vector3::zeros();
            axis[k] = 1.0;
            let u = axis.cross(&x);
            for d in 0..3 {
                r[(6 * i + d, 3 + k)] = u[d];
            }
            r[(6 * i + 3 + k, 3 + k)] = 1.0 / scale;
        }
    }
    r
}

/// The rigid motions left free by the supports, over the free dofs (`n_free × r`, r ≤ 6), with
/// orthonormal columns in the Euclidean inner product of the free dofs.
pub fn free_rigid_motions(mesh: &Mesh, dofs: &DofMap) -> Mat<f64> {
    let all = all_rigid_motions(mesh);
    // Gram matrix of the motions at the supported dofs: its null space is the admissible set.
    let mut held = Matrix6::<f64>::zeros();
    let mut free = Matrix6::<f64>::zeros();
    for g in 0..all.nrows() {
        let row = |a: usize| all[(g, a)];
        let target = if dofs.equation_of(g).is_some() {
            &mut free
        } else if dofs.is_held(g) {
            &mut held
        } else {
            continue;
        };
        for a in 0..6 {
            for b in 0..6 {
                target[(a, b)] += row(a) * row(b);
            }
        }
    }
    let eigen = SymmetricEigen::new(held);
    let scale = free.trace().max(f64::MIN_POSITIVE);
    let null: Vec<usize> =
        (0..6).filter(|&k| eigen.eigenvalues[k].abs() <= 1e-10 * scale).collect();
    let mut motions = Mat::zeros(dofs.n_free(), null.len());
    for (c, &k) in null.iter().enumerate() {
        let combination = eigen.eigenvectors.column(k);
        for g in 0..all.nrows() {
            if let Some(e) = dofs.equation_of(g) {
                motions[(e, c)] = (0..6).map(|a| all[(g, a)] * combination[a]).sum();
            }
        }
    }
    orthonormalize_columns(&mut motions);
    motions
}

/// Free dofs, as many as the columns of `motions`, whose values fix those motions: rows of the
/// matrix chosen by Gram–Schmidt, the largest remaining norm first. Holding them at zero is a
/// statically determinate extra support (Nastran's SUPORT).
pub fn pivot_dofs(motions: &Mat<f64>) -> Vec<usize> {
    let (n, r) = (motions.nrows(), motions.ncols());
    let mut rows: Vec<Vec<f64>> = (0..n).map(|i| (0..r).map(|k| motions[(i, k)]).collect()).collect();
    let norm2 = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>();
    let mut chosen = Vec::with_capacity(r);
    for _ in 0..r {
        // As many pivots as motions, at most one per dof.
        let Some(best) = (0..n)
            .filter(|i| !chosen.contains(i))
            .max_by(|&a, &b| norm2(&rows[a]).total_cmp(&norm2(&rows[b])))
        else {
            break;
        };
        let norm = norm2(&rows[best]).sqrt();
        let pivot: Vec<f64> = rows[best].iter().map(|x| x / norm).collect();
        for row in rows.iter_mut() {
            let dot: f64 = row.iter().zip(&pivot).map(|(a, b)| a * b).sum();
            for (x, p) in row.iter_mut().zip(&pivot) {
                *x -= dot * p;
            }
        }
        chosen.push(best);
    }
    chosen
}

/// The combinations of the rigid motions that carry no mass (`M R c = 0`): a straight line of beams
/// without rotary inertia spinning about its own axis. They are neither vibration modes nor
/// mechanisms the model can move in, and they make `K + σM` singular.
pub fn massless_rigid_motions(mass: &faer::sparse::SparseColMat<usize, f64>, rigid: &Mat<f64>) -> Mat<f64> {
    let r = rigid.ncols();
    if r == 0 {
        return Mat::zeros(rigid.nrows(), 0);
    }
    let gram = rigid.transpose() * (mass * rigid);
    let eigen = gram.self_adjoint_eigen(faer::Side::Lower).expect("small symmetric eigenproblem");
    let largest = (0..r).map(|k| eigen.S()[k]).fold(0.0_f64, f64::max);
    let massless: Vec<usize> = (0..r).filter(|&k| eigen.S()[k] <= 1e-12 * largest.max(f64::MIN_POSITIVE)).collect();
    let mut motions = Mat::zeros(rigid.nrows(), massless.len());
    for (c, &k) in massless.iter().enumerate() {
        let combination = eigen.U().col(k);
        let column = rigid * combination;
        for i in 0..rigid.nrows() {
            motions[(i, c)] = column[i];
        }
    }
    motions
}

/// Modified Gram–Schmidt, twice, on the columns of `m` (Euclidean inner product).
pub(crate) fn orthonormalize_columns(m: &mut Mat<f64>) {
    for _pass in 0..2 {
        for j in 0..m.ncols() {
            for i in 0..j {
                let dot: f64 = (0..m.nrows()).map(|r| m[(r, i)] * m[(r, j)]).sum();
                for r in 0..m.nrows() {
                    m[(r, j)] -= dot * m[(r, i)];
                }
            }
            let norm = (0..m.nrows()).map(|r| m[(r, j)].powi(2)).sum::<f64>().sqrt();
            for r in 0..m.nrows() {
                m[(r, j)] /= norm;
            }
        }
    }
}
