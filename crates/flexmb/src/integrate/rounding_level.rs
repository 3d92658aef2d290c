//! The rounding level of the Newton increments, estimated a priori from the iteration matrix: the
//! increment that the rounding of the residual at the iterate produces, below which the increments of a
//! simplified Newton iteration are no longer a correction and their rate says nothing.
//!
//! The rounding of evaluating row `i` of a residual whose derivative is `J` at `y` is about
//! `ε Σⱼ |Jᵢⱼ| |yⱼ|` (the componentwise backward error of Oettli and Prager: `y` itself is known to
//! `ε |y|`, and each term of the row to `ε` of its size). The increment that rounding produces is then
//! about `J⁻¹ (ε |J| |y|)`, with the signs of the rows' rounding unknown: [`rounding_residual`] draws
//! them from a fixed sequence, so that they neither cancel nor add up by the matrix's structure.
//!
//! Where it matters: the hanging chain of n rods (`flexmb bench --case chain`, rtol = atol = 3e-10, 0.1 s
//! from the horizontal). Its rods' positions reach `n/2` m from the origin, and the top joints carry the
//! weight of the whole chain, `λ ≈ 10 n` N. The increments, traced block by block, stall in the
//! multipliers of the position constraints, `μ` (zero at the solution, so weighed at `atol`; their
//! impulse `c μ` moves the positions onto the constraints), at 6.0e-4 to 2.2e-3 tolerances in 21 of the 23
//! failed iterations of the chain of 512 rods, at rates of 0.4 to 1, against a Newton tolerance of 7.4e-5,
//! while the positions', the velocities' and the multipliers `λ`'s parts of the same increments were at
//! most 1.5e-4; the estimate below gives 7.25e-3 there, 99.9 % of it in `μ`. Such an iteration fails, or converges at a slow rate that
//! the rate monitor ([`RateMonitor`](super::convergence_rate::RateMonitor)) answers with a new Jacobian
//! at the next step: measured against the rate alone, the chain of 512 rods failed 23 iterations in 127
//! steps and evaluated 94 Jacobians, that of 1,024 rods 17 in 136 and 134.
//!
//! The level is estimated once per factorization of the iteration matrix, by the first iteration that
//! needs it: an increment after the first that converges neither outright nor by its rate
//! ([`ConvergenceTest::needs_rounding_level`](super::newton::ConvergenceTest::needs_rounding_level)); one
//! product with `|J|` and one solve more. The next iterations with the same factors start with it, so
//! that an increment at the level converges before its rate, which says nothing, is measured. It is
//! bounded as the learnt rounding floor is ([`NOISE_CEILING`](super::newton_rounding::NOISE_CEILING) of
//! the solution, [`CHANGE_RATIO`](super::newton_rounding::CHANGE_RATIO) of the step's change of it), so
//! that a motion that runs away, whose iteration matrix grows ill-conditioned with it, is not passed; and
//! it is not used where it exceeds the step's share of the tolerance: that tolerance is finer than the
//! arithmetic resolves the model, and the floor learnt from failures, which also covers the error
//! estimates, takes over (the chain of 1,024 rods at rtol 1e-12, a level of 15 tolerances).

/// The rounding of the residual of a system `J x = b` at `y`, row by row: `ε Σⱼ |Jᵢⱼ| |yⱼ|` (given in
/// `out`, from [`IterationMatrix::absolute_product`](super::iteration_matrix::IterationMatrix::absolute_product))
/// with a sign from a fixed pseudo-random sequence of the row.
pub(crate) fn rounding_residual(out: &mut [f64]) {
    for (i, x) in out.iter_mut().enumerate() {
        // The top bit of a multiplicative hash of the row (Knuth's golden-ratio constant).
        let negative = (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 63 == 1;
        *x *= if negative { -f64::EPSILON } else { f64::EPSILON };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each row's rounding is `ε` times its magnitude, of either sign, and the signs are mixed: on a
    /// thousand rows about as many of each, and no long run of one.
    #[test]
    fn each_row_rounds_by_epsilon_of_its_magnitude_with_mixed_signs() {
        let magnitudes: Vec<f64> = (0..1000).map(|i| 1.0 + i as f64).collect();
        let mut rows = magnitudes.clone();
        rounding_residual(&mut rows);
        for (x, m) in rows.iter().zip(&magnitudes) {
            assert_eq!(x.abs(), f64::EPSILON * m);
        }
        let negative = rows.iter().filter(|x| **x < 0.0).count();
        assert!((400..=600).contains(&negative), "{negative} negative rows of 1000");
        let longest_run = rows.windows(2).fold((1, 1), |(run, longest), w| {
            let run = if (w[0] < 0.0) == (w[1] < 0.0) { run + 1 } else { 1 };
            (run, longest.max(run))
        });
        assert!(longest_run.1 <= 12, "a run of {} rows of one sign", longest_run.1);
    }
}
