//! Numbers and points in messages: six significant digits, no trailing noise (`0.05`, not
//! `0.04999999999999993`), exponents for very small and very large magnitudes (`1e-9`).

use nalgebra::Vector3;

/// `x` rounded to six significant digits and written as short as possible.
pub(crate) fn number(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    let rounded: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    if (1e-4..1e9).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// `[x, y, z]` with [`number`]'s rounding.
pub(crate) fn point(p: &Vector3<f64>) -> String {
    format!("[{}, {}, {}]", number(p.x), number(p.y), number(p.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rounds_to_six_digits() {
        assert_eq!(number(0.04999999999999993), "0.05");
        assert_eq!(number(1e-6), "1e-6");
        assert_eq!(number(2.5e-3), "0.0025");
        assert_eq!(number(-2.5), "-2.5");
        assert_eq!(number(0.0), "0");
        assert_eq!(point(&Vector3::new(1.0, 0.1 + 0.2, 0.0)), "[1, 0.3, 0]");
    }
}
