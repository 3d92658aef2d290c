//! The normal equations of a minimum-norm correction, `(G W⁻¹ Gᵀ) z = r` for a sparse `G` (by rows) and
//! positive weights `W = diag(w)`: the assembly's Newton step `Δq = −Gᵀ (G Gᵀ)⁻¹ Φ`, the velocity
//! analysis's `Δv = W⁻¹ Bᵀ (B W⁻¹ Bᵀ)⁻¹ r`, and the least-squares combination of rows. `G W⁻¹ Gᵀ` couples
//! two rows only where they share a column (a body), so it is as sparse as the mechanism's joints; it is
//! factored by [`SparseLu`] (dense only when small).

use super::sparse_lu::{SingularMatrix, SparseLu};
use super::sparse_rows::SparseRows;

/// Solves `(G W⁻¹ Gᵀ) z = r` in place (`rhs` holds `r` on entry and `z` on return); `weights` are the
/// `w` of `W = diag(w)`, all ones when `None`. A singular matrix (dependent rows of `G`) is an error.
/// One solve: a sequence of them on one pattern (the assembly's iterations) keeps a [`NormalEquations`].
///
/// # Panics
/// If `rhs` is not of `G`'s rows or `weights` not of its columns (a bug of the caller).
pub(crate) fn solve_normal_equations(g: &SparseRows, weights: Option<&[f64]>, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
    NormalEquations::default().solve(g, weights, rhs)
}

/// The normal matrix `G W⁻¹ Gᵀ` on the pattern of the last `G` it was given: its pattern analysed and
/// its pivots chosen once, then only its numbers formed and refactored, while `G`'s pattern stays.
#[derive(Debug, Default)]
pub(crate) struct NormalEquations {
    /// The pattern of `G` the matrix was built for, by columns (each column's rows), and the matrix.
    built_for: Option<(SparseRows, SparseLu)>,
    /// Pattern analyses made (one per new pattern of `G`).
    analyses: usize,
}

impl NormalEquations {
    /// Solves `(G W⁻¹ Gᵀ) z = r` in place, as [`solve_normal_equations`] does; the pattern of the
    /// previous `G` is reused when `G` has the same.
    ///
    /// # Panics
    /// If `rhs` is not of `G`'s rows or `weights` not of its columns (a bug of the caller).
    pub(crate) fn solve(&mut self, g: &SparseRows, weights: Option<&[f64]>, rhs: &mut [f64]) -> Result<(), SingularMatrix> {
        assert_eq!(rhs.len(), g.nrows(), "a right side per row");
        let weight = |c: usize| weights.map_or(1.0, |w| w[c]);
        let columns = g.transposed();
        let reusable = matches!(&self.built_for, Some((pattern, _)) if pattern.same_pattern(&columns));
        if !reusable {
            let mut entries = Vec::new();
            for c in 0..columns.nrows() {
                let rows = columns.row(c).0;
                for &r1 in rows {
                    entries.extend(rows.iter().map(|&r2| (r1, r2)));
                }
            }
            self.analyses += 1;
            self.built_for = Some((columns.clone(), SparseLu::new(g.nrows(), entries)));
        }
        let (_, a) = self.built_for.as_mut().expect("built above");
        a.clear();
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

    /// Pattern analyses made so far.
    #[cfg(test)]
    pub(crate) fn analyses(&self) -> usize {
        self.analyses
    }
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

    /// Three value sets on one pattern of `G` and then a new pattern: two pattern analyses, and each
    /// solution equal to that of a one-off solve.
    #[test]
    fn the_pattern_is_analysed_once_while_it_stays() {
        let mut normal = NormalEquations::default();
        let pattern = [(0, 0), (0, 1), (1, 1), (1, 2), (1, 3), (2, 3), (2, 4)];
        for (k, shift) in [0.0, 0.5, -0.3].into_iter().enumerate() {
            let entries = pattern.iter().enumerate().map(|(i, &(r, c))| (r, c, 1.0 + shift * i as f64)).collect();
            let g = SparseRows::from_entries(3, 5, entries);
            let mut z = [0.3, -1.0, 2.0];
            let mut once = z;
            normal.solve(&g, None, &mut z).unwrap();
            solve_normal_equations(&g, None, &mut once).unwrap();
            assert!(z.iter().zip(&once).all(|(a, b)| (a - b).abs() <= 1e-14 * b.abs().max(1.0)), "{z:?} {once:?}");
            assert_eq!(normal.analyses(), 1, "value set {k}");
        }
        let g = SparseRows::from_entries(3, 5, vec![(0, 0, 1.0), (1, 1, 2.0), (2, 2, 4.0)]);
        let mut z = [1.0, 1.0, 1.0];
        normal.solve(&g, None, &mut z).unwrap();
        assert_eq!(z, [1.0, 0.25, 0.0625]);
        assert_eq!(normal.analyses(), 2);
    }

    #[test]
    fn dependent_rows_are_singular() {
        let entries = vec![(0, 0, 1.0), (0, 1, 1.0), (1, 0, 2.0), (1, 1, 2.0)];
        let g = SparseRows::from_entries(2, 3, entries);
        let mut z = [1.0, 1.0];
        assert_eq!(solve_normal_equations(&g, None, &mut z), Err(SingularMatrix));
    }
}
