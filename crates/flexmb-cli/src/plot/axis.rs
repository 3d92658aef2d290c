//! Axis labels and tick labels: `name [unit]`, with very large or small values shown in a power of
//! ten of the unit taken into the label (`[10⁻³ m]`), as engineering plots do.

/// How one axis writes its numbers.
#[derive(Clone, Debug)]
pub enum AxisScale {
    /// Values shown divided by `10^exponent` (a multiple of 3), each with `decimals` decimals.
    Linear { exponent: i32, decimals: usize, range: (f64, f64) },
    /// A logarithmic axis: decades, in plain or scientific notation.
    Log,
}

/// The scale of a linear axis over `(lo, hi)` with at most `max_ticks` ticks (plotters picks the
/// smallest step of 1, 2 or 5 times a power of ten that gives no more).
pub fn linear_axis((lo, hi): (f64, f64), max_ticks: usize) -> AxisScale {
    let largest = lo.abs().max(hi.abs());
    let magnitude = if largest > 0.0 { largest.log10().floor() as i32 } else { 0 };
    let exponent = if (-2..=3).contains(&magnitude) { 0 } else { 3 * magnitude.div_euclid(3) };
    let step = nice_step((hi - lo) / (max_ticks.max(2) - 1) as f64) / 10f64.powi(exponent);
    let decimals = if step > 0.0 { (-step.log10().floor()).clamp(0.0, 12.0) as usize } else { 0 };
    AxisScale::Linear { exponent, decimals, range: (lo, hi) }
}

pub fn log_axis() -> AxisScale {
    AxisScale::Log
}

impl AxisScale {
    /// The label of one tick at `value`.
    pub fn tick(&self, value: f64) -> String {
        match self {
            Self::Linear { exponent, decimals, .. } => {
                let shown = value / 10f64.powi(*exponent);
                // No "-0.0": a tick at zero reads 0.
                let shown = if shown.abs() < 0.5 * 10f64.powi(-(*decimals as i32)) { 0.0 } else { shown };
                format!("{shown:.decimals$}")
            }
            Self::Log => log_tick(value),
        }
    }

    /// The axis label, `name [unit]`, with the power of ten of the ticks in the unit.
    pub fn label(&self, (name, unit): &(String, Option<String>)) -> String {
        let power = match self {
            Self::Linear { exponent, .. } if *exponent != 0 => Some(format!("10{}", superscript(*exponent))),
            _ => None,
        };
        match (power, unit.as_deref()) {
            (Some(p), Some(u)) => format!("{name} [{p} {u}]"),
            (Some(p), None) => format!("{name} [{p}]"),
            (None, Some(u)) => format!("{name} [{u}]"),
            (None, None) => name.clone(),
        }
    }

    /// Labels as wide as this axis's widest: to size the space beside it.
    pub fn sample_ticks(&self) -> Vec<String> {
        match self {
            Self::Linear { range: (lo, hi), .. } => vec![self.tick(*lo), self.tick(*hi), self.tick(0.5 * (lo + hi))],
            Self::Log => vec![log_tick(1e-10), log_tick(2.5e-5)],
        }
    }
}

/// The round step (1, 2 or 5 times a power of ten) at least `raw`.
fn nice_step(raw: f64) -> f64 {
    if !(raw > 0.0 && raw.is_finite()) {
        return 0.0;
    }
    let power = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0].into_iter().map(|m| m * power).find(|s| *s >= raw * (1.0 - 1e-12)).unwrap_or(10.0 * power)
}

/// A tick of a logarithmic axis: a decade as `10⁻³`, anything else as `2e-3`.
fn log_tick(value: f64) -> String {
    let exponent = value.log10().round();
    if (value / 10f64.powf(exponent) - 1.0).abs() < 1e-9 {
        format!("10{}", superscript(exponent as i32))
    } else {
        let rounded: f64 = format!("{value:.2e}").parse().unwrap_or(value);
        format!("{rounded:e}")
    }
}

/// `-3` → `⁻³`.
fn superscript(n: i32) -> String {
    n.to_string()
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            _ => '⁹',
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quantity(name: &str, unit: Option<&str>) -> (String, Option<String>) {
        (name.to_string(), unit.map(str::to_string))
    }

    #[test]
    fn ordinary_ranges_keep_the_unit_and_enough_decimals() {
        let axis = linear_axis((-1.2, 0.8), 11);
        assert_eq!(axis.label(&quantity("bob.position.y", Some("m"))), "bob.position.y [m]");
        assert_eq!(axis.tick(0.4), "0.4");
        assert_eq!(axis.tick(-1e-17), "0.0");
        assert_eq!(linear_axis((0.0, 5.0), 11).tick(2.0), "2.0");
        assert_eq!(linear_axis((0.0, 50.0), 11).tick(20.0), "20");
        assert_eq!(
            linear_axis((0.0, 5.0), 10).tick(2.0),
            "2",
            "plotters steps by 1 here: 11 ticks of 0.5 are too many"
        );
    }

    #[test]
    fn tiny_and_huge_values_move_a_power_of_ten_into_the_label() {
        let axis = linear_axis((-2e-5, 3e-5), 11);
        assert_eq!(axis.label(&quantity("tip.deformation.y", Some("m"))), "tip.deformation.y [10⁻⁶ m]");
        assert_eq!(axis.tick(1.5e-5), "15");
        let axis = linear_axis((0.0, 2.5e5), 11);
        assert_eq!(axis.label(&quantity("f", None)), "f [10³]");
        assert_eq!(axis.tick(1e5), "100");
    }

    #[test]
    fn log_ticks_are_powers_of_ten() {
        assert_eq!(log_tick(0.01), "10⁻²");
        assert_eq!(log_tick(1.0), "10⁰");
        assert_eq!(log_tick(1e-5 * (1.0 + 1e-15)), "10⁻⁵");
        assert_eq!(log_tick(2e-5 * (1.0 + 1e-15)), "2e-5");
        assert_eq!(log_axis().label(&quantity("amplitude", Some("m"))), "amplitude [m]");
    }
}
