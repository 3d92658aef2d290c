//! The steps of forward-difference derivatives: `(f(x + h) − f(x)) / h` with `h ≈ √ε · max(|x|, 1)`, which
//! balances the truncation error `O(h)` against the round-off `O(ε/h)` of a unit-scaled function.

/// Relative step of a forward difference (`≈ √ε`), and the step of a rotation in radians.
pub const RELATIVE_STEP: f64 = 1.5e-8;

/// Forward-difference step for a coordinate of value `x`: [`RELATIVE_STEP`]`· max(|x|, 1)`, rounded so
/// that it is exactly representable at `x`, `(x + h) − x == h`.
#[inline]
pub fn perturbation(x: f64) -> f64 {
    let h = RELATIVE_STEP * x.abs().max(1.0);
    (x + h) - x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The step moves `x` by exactly itself, relative to `x`'s size, at every magnitude.
    #[test]
    fn the_step_is_exact_and_relative() {
        for x in [0.0, 1e-300, -0.3, 1.0, 7.25, -1e3, 123456.789, 1e12] {
            let h = perturbation(x);
            assert_eq!((x + h) - x, h, "x = {x}");
            let size = RELATIVE_STEP * f64::abs(x).max(1.0);
            assert!((h - size).abs() <= 4.0 * f64::EPSILON * f64::abs(x).max(1.0), "x = {x}: h = {h}");
        }
    }

    /// A forward difference with the step is first-order accurate: on `sin` its error is about `h/2 · sin`,
    /// well below `1e-7`, while a step 1000 times smaller loses digits to round-off.
    #[test]
    fn forward_differences_of_sine_match_cosine() {
        for x in [0.1, 1.0, 2.5, 40.0] {
            let h = perturbation(x);
            let derivative = (f64::sin(x + h) - f64::sin(x)) / h;
            assert!((derivative - x.cos()).abs() < 1e-7 * x.abs().max(1.0), "x = {x}");
        }
    }
}
