//! The Campbell diagram: a mechanism's natural frequencies (Hz) against a swept parameter, such as a
//! rotor's spin speed, one curve per mode (column `k` of the frequencies at each value, as the caller
//! followed the mode; a dot where it was computed), and the 1× line `f = s x` of a once-per-revolution excitation (`s = 1/2π` for a spin in
//! rad/s, `1/60` for one in rpm). Where a mode's curve crosses the 1× line the excitation meets that
//! mode's frequency: a critical speed, marked and labelled on the diagram and returned by
//! [`critical_speeds`].

use std::path::Path;

use super::figure::{render, Annotation, Figure, Series, SeriesStyle, Scale};
use super::DEFAULT_SIZE;

/// Where a mode's frequency curve crosses the 1× line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CriticalSpeed {
    /// The mode's index (0 for the lowest frequency).
    pub mode: usize,
    /// The parameter's value at the crossing.
    pub value: f64,
    /// The frequency there (Hz): `s × value`.
    pub frequency_hz: f64,
}

/// Writes the Campbell diagram of `frequencies_hz[i]` (the frequencies of the modes at `values[i]`,
/// mode `k` in column `k`; their number may differ from value to value, and NaN marks a mode absent
/// at a value) against the parameter named `parameter` (with its unit in
/// the name, e.g. `spin [rad/s]`) to `path` (`.png` or `.svg`, 1200 × 750 pixels), with the 1× line
/// `f = s x` and its crossings if `one_per_rev_hz_per_unit` is `Some(s)`.
pub fn write_campbell(
    path: &Path,
    parameter: &str,
    values: &[f64],
    frequencies_hz: &[Vec<f64>],
    one_per_rev_hz_per_unit: Option<f64>,
) -> Result<(), String> {
    let figure = campbell_figure(parameter, values, frequencies_hz, one_per_rev_hz_per_unit)?;
    render(&figure, path, DEFAULT_SIZE).map_err(|e| e.0)
}

/// The diagram [`write_campbell`] draws: the modes' curves, the 1× line (from the smallest value to
/// the largest, or to where it leaves the frequency axis), the critical speeds marked; the frequency
/// axis from 0 to a tenth above the highest frequency.
pub fn campbell_figure(
    parameter: &str,
    values: &[f64],
    frequencies_hz: &[Vec<f64>],
    one_per_rev_hz_per_unit: Option<f64>,
) -> Result<Figure, String> {
    check(values, frequencies_hz, one_per_rev_hz_per_unit)?;
    let order = sorted_order(values);
    let modes = frequencies_hz.iter().map(Vec::len).max().unwrap_or(0);
    let mut series: Vec<Series> = (0..modes)
        .map(|mode| Series {
            label: format!("mode {}", mode + 1),
            points: mode_curve(values, frequencies_hz, &order, mode),
            style: SeriesStyle::LineAndPoints,
        })
        .collect();
    let highest = frequencies_hz.iter().flatten().copied().filter(|f| !f.is_nan()).fold(0.0, f64::max);
    let top = if highest > 0.0 { 1.1 * highest } else { 1.0 };
    let (first, last) = (values[order[0]], values[order[order.len() - 1]]);
    let mut annotations = Vec::new();
    if let Some(s) = one_per_rev_hz_per_unit {
        let end = if s * last > top { top / s } else { last };
        let start = first.min(end);
        series.push(Series {
            label: format!("1× line, f = {} × {parameter}", significant(s)),
            points: vec![(start, s * start), (end, s * end)],
            style: SeriesStyle::Reference,
        });
        annotations = critical_speeds(values, frequencies_hz, s)
            .iter()
            .map(|c| Annotation {
                x: c.value,
                y: c.frequency_hz,
                text: format!("mode {} at {}", c.mode + 1, significant(c.value)),
            })
            .collect();
    }
    Ok(Figure {
        title: format!("Campbell diagram: natural frequencies against {parameter}"),
        x_quantity: (parameter.to_string(), None),
        y_quantity: ("frequency".into(), Some("Hz".into())),
        series,
        annotations,
        y_scale: Scale::Linear,
        x_scale: Scale::Linear,
        x_range: Some(if last > first { (first, last) } else { (first - 0.5, first + 0.5) }),
        y_range: Some((0.0, top)),
    })
}

/// Where each mode's curve (straight between the values it was computed at, in increasing order)
/// crosses the 1× line `f = s x`, by mode and then by value.
pub fn critical_speeds(values: &[f64], frequencies_hz: &[Vec<f64>], s: f64) -> Vec<CriticalSpeed> {
    let order = sorted_order(values);
    let modes = frequencies_hz.iter().map(Vec::len).max().unwrap_or(0);
    let mut crossings = Vec::new();
    for mode in 0..modes {
        let curve = mode_curve(values, frequencies_hz, &order, mode);
        let above = |(x, f): (f64, f64)| f - s * x;
        for (k, &point) in curve.iter().enumerate() {
            let g = above(point);
            let crossing_value = if g == 0.0 {
                Some(point.0)
            } else {
                curve.get(k + 1).map(|&next| (next, above(next))).filter(|(_, h)| g * h < 0.0).map(|(next, h)| {
                    // The straight piece between the two points meets the line where `g` changes sign.
                    point.0 + (next.0 - point.0) * g / (g - h)
                })
            };
            if let Some(value) = crossing_value {
                crossings.push(CriticalSpeed { mode, value, frequency_hz: s * value });
            }
        }
    }
    crossings
}

/// Mode `mode`'s points, `(value, frequency)`, in the order `order` of the values, where it was found.
fn mode_curve(values: &[f64], frequencies_hz: &[Vec<f64>], order: &[usize], mode: usize) -> Vec<(f64, f64)> {
    order.iter().filter_map(|&i| frequencies_hz[i].get(mode).filter(|f| !f.is_nan()).map(|f| (values[i], *f))).collect()
}

/// The indices of `values` in increasing order of value.
fn sorted_order(values: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|a, b| values[*a].total_cmp(&values[*b]));
    order
}

/// An error unless there is a list of frequencies per value, at least one value, and every number is
/// finite (frequencies also not negative, or NaN for an absent mode; the 1× slope positive).
fn check(values: &[f64], frequencies_hz: &[Vec<f64>], s: Option<f64>) -> Result<(), String> {
    if values.is_empty() || values.len() != frequencies_hz.len() {
        return Err(format!(
            "a Campbell diagram needs one list of frequencies per parameter value: {} values, {} lists",
            values.len(),
            frequencies_hz.len()
        ));
    }
    if let Some(k) = values.iter().position(|v| !v.is_finite()) {
        return Err(format!("parameter value {} is {}", k + 1, values[k]));
    }
    for (k, list) in frequencies_hz.iter().enumerate() {
        if let Some(f) = list.iter().find(|f| !(f.is_nan() || (f.is_finite() && **f >= 0.0))) {
            return Err(format!("a frequency at parameter value {} is {f} Hz", values[k]));
        }
    }
    match s {
        Some(s) if !(s.is_finite() && s > 0.0) => Err(format!("the 1× line's slope must be positive, got {s}")),
        _ => Ok(()),
    }
}

/// Four significant digits.
fn significant(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let decimals = (3 - x.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{x:.decimals$}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::axis_ranges;

    #[test]
    fn a_constant_mode_crosses_the_one_per_rev_line_where_the_speed_equals_its_frequency() {
        let values: Vec<f64> = (0..=20).map(|k| k as f64).collect();
        let frequencies: Vec<Vec<f64>> = values.iter().map(|_| vec![10.0]).collect();
        assert_eq!(
            critical_speeds(&values, &frequencies, 1.0),
            [CriticalSpeed { mode: 0, value: 10.0, frequency_hz: 10.0 }]
        );
        // Between computed values the crossing is where the straight pieces meet the line.
        let values = [0.0, 7.0, 13.0, 20.0];
        let frequencies = vec![vec![10.0, 15.0, 30.0]; 4];
        let found = critical_speeds(&values, &frequencies, 1.0);
        let at: Vec<(usize, f64)> = found.iter().map(|c| (c.mode, c.value)).collect();
        assert_eq!(at.len(), 2, "mode 3 at 30 Hz stays above a 1× line that ends at 20 Hz: {at:?}");
        assert!(at[0].0 == 0 && (at[0].1 - 10.0).abs() < 1e-12, "{at:?}");
        assert!(at[1].0 == 1 && (at[1].1 - 15.0).abs() < 1e-12, "{at:?}");
    }

    #[test]
    fn forward_and_backward_whirl_curves_each_cross_once_and_the_axes_hold_them() {
        // A Jeffcott-like pair splitting with speed: f = 8 ± 0.05 Ω (Hz, Ω in rad/s), 1× = Ω/2π.
        let values: Vec<f64> = (0..=30).map(|k| 4.0 * k as f64).collect();
        let frequencies: Vec<Vec<f64>> = values.iter().map(|w| vec![8.0 - 0.05 * w, 8.0 + 0.05 * w]).collect();
        let s = 1.0 / std::f64::consts::TAU;
        let found = critical_speeds(&values, &frequencies, s);
        assert_eq!(found.len(), 2);
        for (c, sign) in found.iter().zip([-1.0, 1.0]) {
            let exact = 8.0 / (s - sign * 0.05);
            assert!((c.value - exact).abs() < 1e-9 * exact, "{c:?} against {exact}");
        }
        let figure = campbell_figure("spin [rad/s]", &values, &frequencies, Some(s)).unwrap();
        let ((x0, x1), (y0, y1)) = axis_ranges(&figure).unwrap();
        assert_eq!((x0, x1), (0.0, 120.0));
        assert!(y0 == 0.0 && (y1 - 1.1 * 14.0).abs() < 1e-12);
        assert_eq!(figure.annotations.len(), 2);
        assert_eq!(figure.series.len(), 3);
        assert_eq!(figure.series[2].style, SeriesStyle::Reference);
    }

    #[test]
    fn bad_input_is_an_error_that_says_what() {
        let e = campbell_figure("spin", &[1.0, 2.0], &[vec![1.0]], None).unwrap_err();
        assert_eq!(e, "a Campbell diagram needs one list of frequencies per parameter value: 2 values, 1 lists");
        let e = campbell_figure("spin", &[1.0], &[vec![f64::INFINITY]], None).unwrap_err();
        assert_eq!(e, "a frequency at parameter value 1 is inf Hz");
        let e = campbell_figure("spin", &[1.0], &[vec![-2.0]], None).unwrap_err();
        assert_eq!(e, "a frequency at parameter value 1 is -2 Hz");
        // NaN marks a mode absent at a value: its curve skips the value.
        let figure = campbell_figure("spin", &[1.0, 2.0], &[vec![3.0, f64::NAN], vec![3.5, 4.0]], None).unwrap();
        assert_eq!(figure.series[1].points, vec![(2.0, 4.0)]);
        let e = campbell_figure("spin", &[1.0], &[vec![1.0]], Some(0.0)).unwrap_err();
        assert_eq!(e, "the 1× line's slope must be positive, got 0");
    }
}
