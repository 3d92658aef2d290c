//! The record a spectrum is taken of: the samples of one column between two times, on a uniform
//! time step (resampled by linear interpolation if the file's times are not uniform).

use crate::run::CliError;

/// Samples `values[k]` at times `t0 + k dt`.
#[derive(Clone, Debug)]
pub struct UniformSamples {
    pub t0: f64,
    pub dt: f64,
    pub values: Vec<f64>,
    /// Whether the file's times were not uniform and the values were interpolated.
    pub resampled: bool,
}

/// Fewest samples a spectrum is taken of.
pub const MIN_SAMPLES: usize = 16;

/// Most samples a record resampled onto a uniform step may have (a few rows far apart among many close
/// ones would otherwise make more samples than memory holds).
pub const MAX_RESAMPLED: usize = 10_000_000;

/// Relative spread of the time steps still taken as uniform: the CSV's 11 significant digits, and more.
const UNIFORM_STEP_TOLERANCE: f64 = 1e-6;

impl UniformSamples {
    /// The samples of `y` with `from ≤ t ≤ to`, on a uniform step.
    pub fn select(t: &[f64], y: &[f64], from: Option<f64>, to: Option<f64>) -> Result<Self, CliError> {
        if let Some(k) = t.iter().position(|t| !t.is_finite()) {
            return Err(CliError(format!("time {} (sample {}) is not finite", t[k], k + 1)));
        }
        let (from, to) = (from.unwrap_or(f64::NEG_INFINITY), to.unwrap_or(f64::INFINITY));
        if from >= to {
            return Err(CliError(format!("--from {from} must be before --to {to}")));
        }
        let kept: Vec<(f64, f64)> =
            t.iter().zip(y).map(|(t, y)| (*t, *y)).filter(|(t, _)| (from..=to).contains(t)).collect();
        if kept.len() < MIN_SAMPLES {
            return Err(CliError(format!(
                "{} samples between t = {} s and {} s; a spectrum needs at least {MIN_SAMPLES}",
                kept.len(),
                t.first().map_or(from, |t0| t0.max(from)),
                t.last().map_or(to, |t1| t1.min(to)),
            )));
        }
        check_record(&kept)?;
        Self::uniform(&kept)
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.values.len()
    }

    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Time of the last sample.
    pub fn t_end(&self) -> f64 {
        self.t0 + (self.len() - 1) as f64 * self.dt
    }

    /// The record's length `T = N Δt`: one over the frequency resolution.
    pub fn duration(&self) -> f64 {
        self.len() as f64 * self.dt
    }

    /// Uniform as they are, or interpolated onto the median time step (of at most [`MAX_RESAMPLED`]
    /// samples). The record's length and its step's Nyquist frequency must be finite numbers.
    fn uniform(kept: &[(f64, f64)]) -> Result<Self, CliError> {
        let (t0, t1) = (kept[0].0, kept[kept.len() - 1].0);
        let mean_step = (t1 - t0) / (kept.len() - 1) as f64;
        if !(t1 - t0).is_finite() || !(0.5 / mean_step).is_finite() {
            return Err(CliError(format!(
                "the record from t = {} s to {} s, {} samples, has a length or a time step beyond double precision",
                time(t0),
                time(t1),
                kept.len()
            )));
        }
        let steps: Vec<f64> = kept.windows(2).map(|w| w[1].0 - w[0].0).collect();
        if steps.iter().all(|h| (h - mean_step).abs() <= UNIFORM_STEP_TOLERANCE * mean_step) {
            return Ok(Self { t0, dt: mean_step, values: kept.iter().map(|(_, y)| *y).collect(), resampled: false });
        }
        let dt = median(steps);
        let count = ((t1 - t0) / dt).floor() + 1.0;
        if !count.is_finite() || count > MAX_RESAMPLED as f64 || !(0.5 / dt).is_finite() {
            return Err(CliError(format!(
                "the times are not uniform, and resampling them onto their median step {} s from t = {} s to {} s \
                 would make {count:.3e} samples, more than {MAX_RESAMPLED}; choose a stretch with --from and --to",
                time(dt),
                time(t0),
                time(t1)
            )));
        }
        let values = (0..count as usize).map(|k| interpolate(kept, t0 + k as f64 * dt)).collect();
        Ok(Self { t0, dt, values, resampled: true })
    }
}

/// Times must increase and values be finite.
fn check_record(kept: &[(f64, f64)]) -> Result<(), CliError> {
    if let Some(w) = kept.windows(2).find(|w| w[1].0 <= w[0].0) {
        return Err(CliError(format!("time does not increase from t = {} s to {} s", w[0].0, w[1].0)));
    }
    if let Some((t, y)) = kept.iter().find(|(_, y)| !y.is_finite()) {
        return Err(CliError(format!("the value at t = {t} s is {y}; a spectrum needs finite values")));
    }
    Ok(())
}

/// A time for messages: as written if it is of ordinary size, else in scientific notation.
fn time(t: f64) -> String {
    if t == 0.0 || (1e-3..1e6).contains(&t.abs()) {
        format!("{}", (t * 1e9).round() / 1e9)
    } else {
        format!("{t:.6e}")
    }
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Linear interpolation in `(t, y)` pairs of increasing `t`, at `t` within their range.
fn interpolate(points: &[(f64, f64)], t: f64) -> f64 {
    let i = points.partition_point(|(ti, _)| *ti <= t).clamp(1, points.len() - 1);
    let ((ta, ya), (tb, yb)) = (points[i - 1], points[i]);
    ya + (yb - ya) * (t - ta) / (tb - ta)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selects_the_window_and_keeps_a_uniform_step() {
        let t: Vec<f64> = (0..101).map(|k| k as f64 * 0.01).collect();
        let s = UniformSamples::select(&t, &t, Some(0.2), Some(0.6)).unwrap();
        assert!(!s.resampled);
        assert_eq!(s.len(), 41);
        assert!((s.dt - 0.01).abs() < 1e-15 && (s.t0 - 0.2).abs() < 1e-15);
    }

    #[test]
    fn resamples_uneven_times_onto_the_median_step() {
        let t: Vec<f64> = (0..40).map(|k| k as f64 * 0.1 + if k % 3 == 1 { 0.03 } else { 0.0 }).collect();
        let y: Vec<f64> = t.iter().map(|t| 2.0 * t + 1.0).collect();
        let s = UniformSamples::select(&t, &y, None, None).unwrap();
        assert!(s.resampled);
        for (k, v) in s.values.iter().enumerate() {
            let tk = s.t0 + k as f64 * s.dt;
            assert!((v - (2.0 * tk + 1.0)).abs() < 1e-12, "a straight line stays straight");
        }
    }

    #[test]
    fn too_few_samples_and_bad_values_are_errors() {
        let t: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
        let e = UniformSamples::select(&t, &t, Some(0.5), Some(0.55)).unwrap_err().to_string();
        assert!(e.contains("6 samples between t = 0.5 s and 0.55 s; a spectrum needs at least 16"), "{e}");
        let mut y = t.clone();
        y[50] = f64::NAN;
        assert!(UniformSamples::select(&t, &y, None, None).unwrap_err().to_string().contains("t = 0.5 s is NaN"));
        assert!(UniformSamples::select(&t, &t, Some(1.0), Some(0.5)).is_err());
    }

    #[test]
    fn records_beyond_double_precision_or_memory_are_errors() {
        let mut t: Vec<f64> = (0..64).map(|k| k as f64 * 0.01).collect();
        let y = vec![0.0; t.len()];
        t[5] = f64::NAN;
        assert_eq!(UniformSamples::select(&t, &y, None, None).unwrap_err().to_string(), "time NaN (sample 6) is not finite");
        t[5] = 0.05;
        t[0] = -1.7e308;
        t[63] = 1.7e308;
        let e = UniformSamples::select(&t, &y, None, None).unwrap_err().to_string();
        assert!(e.contains("beyond double precision"), "{e}");
        // One late row among many close ones: 1e8 s on a median step of 0.01 s is 1e10 samples.
        t[0] = 0.0;
        t[63] = 1e8;
        let e = UniformSamples::select(&t, &y, None, None).unwrap_err().to_string();
        assert!(e.contains("would make 1.000e10 samples, more than 10000000"), "{e}");
    }
}
