//! The normal equations of a minimum-norm correction, `(G W⁻¹ Gᵀ) z = r` for a sparse `G` (by rows) and
//! positive weights `W = diag(w)`: the assembly's Newton step `Δq = −Gᵀ (G Gᵀ)⁻¹ Φ`, the velocity
//! analysis's `Δv = W⁻¹ Bᵀ (B W⁻¹ Bᵀ)⁻¹ r`, and the least-squares combination of rows. `G W⁻¹ Gᵀ` couples
//! two rows only where they share a column (a body), so it is as sparse as the mechanism's joints; it is
//! factored by [`SparseLu`] (dense only when small).

use super::sparse_lu::{SingularMatrix, SparseLu};
use super::sparse_rows::SparseRows;

/// Solves `(G W⁻¹ Gᵀ) z = r` in place (`rhs` holds `r` on entry and `z` on return); `weights` are the
/// `w` of `W = diag(w)`, all ones when `None`. A singular matrix (dependent rows of `G`) is an error.
///
/// # Panics
/// If `rhs` is not of `G`'s rows or `weights` not of its columns (a bug of the caller).
pub(crate) fn solve_normal_equations(g: &SparseRows, weights: Option<&[f64]>, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
    assert_eq!(rhs.len(), g.nrows(), "a right side per row");
    let weight = |c: usize| weights.map_or(1.0, |w| w[c]);
    let columns = g.transposed();
    let mut entries = Vec::new();
    for c in 0..columns.nrows() {
        let rows = columns.row(c).0;
        for &r1 in rows {
            entries.extend(rows.iter().map(|&r2| (r1, r2)));
        }
    }
    let mut a = SparseLu::new(g.nrows(), entries);
    for c in 0..columns.nrows() {
        let (rows, values) = columns.row(c);
        let w = weight(c);
        for (r1, x1) in rows.iter().zip(values) {
            for (r2, x2) in rows.iter().zip(values) {
                a.add(*r1, *r2, x1 * x2 / w);
            }
        }
    }
    a.factor()?;
    a.solve_in_place(rhs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_minimum_norm_correction_satisfies_the_rows_and_is_orthogonal_to_their_null_space() {
        // Three rows of five columns (a path of couplings); weights unequal.
        let entries = vec![(0, 0, 1.0), (0, 1, -1.0), (1, 1, 2.0), (1, 2, 0.5), (1, 3, 1.0), (2, 3, -1.0), (2, 4, 3.0)];
        let g = SparseRows::from_entries(3, 5, entries);
        let w = [1.0, 1e3, 2.0, 1.0, 0.5];
        let r = [0.3, -1.0, 2.0];
        let mut z = r;
        solve_normal_equations(&g, Some(&w), &mut z).unwrap();
        // Δ = W⁻¹ Gᵀ z solves G Δ = r …
        let mut delta = [0.0; 5];
        g.multiply_transposed(&z, &mut delta);
        delta.iter_mut().zip(&w).for_each(|(d, w)| *d /= w);
        let mut g_delta = [0.0; 3];
        g.multiply(&delta, &mut g_delta);
        for k in 0..3 {
            assert!((g_delta[k] - r[k]).abs() < 1e-13, "{g_delta:?}");
        }
        // … and W Δ lies in the row space of G: it is W-orthogonal to any null vector n of G.
        let null = [1.0, 1.0, -4.0, 0.0, 0.0]; // G null: row 1: 2·1 + 0.5·(−4) = 0
        let mut gnull = [0.0; 3];
        g.multiply(&null, &mut gnull);
        assert_eq!(gnull, [0.0; 3]);
        let product: f64 = null.iter().zip(&delta).zip(&w).map(|((n, d), w)| n * d * w).sum();
        assert!(product.abs() < 1e-13, "{product:e}");
    }

    #[test]
    fn dependent_rows_are_singular() {
        let entries = vec![(0, 0, 1.0), (0, 1, 1.0), (1, 0, 2.0), (1, 1, 2.0)];
        let g = SparseRows::from_entries(2, 3, entries);
        let mut z = [1.0, 1.0];
        assert_eq!(solve_normal_equations(&g, None, &mut z), Err(SingularMatrix));
    }
}
