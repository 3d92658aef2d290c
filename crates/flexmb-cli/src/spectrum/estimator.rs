//! The amplitude spectrum of a uniformly sampled record and its dominant frequencies.
//!
//! 1. The linear trend (least-squares line) is removed, then a Hann window `w_k = ½(1 − cos 2πk/(N−1))`
//!    applied: its side lobes fall to −31 dB and on at 18 dB per octave, so a strong component
//!    hardly biases a weaker one a few bins away.
//! 2. The windowed record is zero-padded to at least [`PADDING`] times its length (and a power of
//!    two of at least [`MIN_FFT_POINTS`]) and Fourier transformed; `A(f) = 2 |Σ x_k w_k e^{−2πi f k Δt}| / Σ w_k` is then the amplitude of a sinusoid
//!    at `f` (dividing by `Σ w_k = N × coherent gain` undoes the window's attenuation).
//! 3. A peak is a local maximum of `A` on that grid that is the largest within the window's main lobe
//!    (±2/T), at least [`FLOOR`] times the largest, and at a frequency of at least 2/T: two periods in
//!    the record (below that, the main lobe around zero frequency — what is left of the mean and the
//!    trend — is what shows).
//! 4. Each peak's frequency is refined to the maximum of `A(f)`, evaluated directly from the record,
//!    by golden-section search between the grid points either side of it. For a single sinusoid in
//!    white noise the maximum of the periodogram is the maximum-likelihood frequency estimate
//!    (Rife and Boorstyn, IEEE Trans. Inf. Theory 20(5), 1974); the window trades a little of that
//!    noise optimality for immunity to leakage from other components. The amplitude is `A` there, so
//!    it has no scalloping loss.

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

use super::samples::UniformSamples;

/// Zero-padding: the FFT grid is at least this many times finer than 1/T …
pub const PADDING: usize = 4;

/// … and has at least this many points, so that plotted spectra of short records are smooth.
pub const MIN_FFT_POINTS: usize = 8192;

/// Peaks smaller than this fraction of the largest are not reported (−80 dB).
pub const FLOOR: f64 = 1e-4;

/// Half-width of the Hann window's main lobe, in units of 1/T.
const MAIN_LOBE_HALF_WIDTH: f64 = 2.0;

/// A detrended, Hann-windowed record.
#[derive(Clone, Debug)]
pub struct WindowedRecord {
    /// `x_k w_k / scale`.
    weighted: Vec<f64>,
    window_sum: f64,
    dt: f64,
    /// A power of two near the largest `|x_k|`: the record is held divided by it (exactly), so that
    /// the sums of the trend and the transform cannot overflow for values up to 1.8e308, and the
    /// amplitudes are multiplied by it.
    scale: f64,
}

impl WindowedRecord {
    pub fn new(samples: &UniformSamples) -> Self {
        let scale = power_of_two_below(samples.values.iter().fold(0.0, |m: f64, x| m.max(x.abs())));
        let scaled: Vec<f64> = samples.values.iter().map(|x| x / scale).collect();
        let detrended = remove_linear_trend(&scaled);
        let window = hann(detrended.len());
        let weighted = detrended.iter().zip(&window).map(|(x, w)| x * w).collect();
        Self { weighted, window_sum: window.iter().sum(), dt: samples.dt, scale }
    }

    /// `T = N Δt`.
    pub fn duration(&self) -> f64 {
        self.weighted.len() as f64 * self.dt
    }

    /// The amplitude `A(f)` of a sinusoid at frequency `f`, from the windowed record directly.
    pub fn amplitude_at(&self, f: f64) -> f64 {
        let step = -2.0 * std::f64::consts::PI * f * self.dt;
        let mut sum = Complex::new(0.0, 0.0);
        for (start, chunk) in (0..).step_by(1024).zip(self.weighted.chunks(1024)) {
            // Rotate by e^{iΔ} from an exact phase at the start of each chunk, so errors do not pile up.
            let rotation = Complex::from_polar(1.0, step);
            let mut phasor = Complex::from_polar(1.0, step * start as f64);
            for x in chunk {
                sum += phasor * x;
                phasor *= rotation;
            }
        }
        2.0 * sum.norm() / self.window_sum * self.scale
    }
}

/// The largest power of two not above `x` (1 for zero and for what is not finite).
fn power_of_two_below(x: f64) -> f64 {
    if !(x.is_finite() && x > 0.0) {
        return 1.0;
    }
    2f64.powi(x.log2().floor() as i32)
}

/// `A(f)` on the grid `f_k = k × bin`, `k = 0 … n/2`, of the zero-padded FFT.
#[derive(Clone, Debug)]
pub struct AmplitudeSpectrum {
    pub bin: f64,
    pub amplitudes: Vec<f64>,
}

impl AmplitudeSpectrum {
    pub fn of(record: &WindowedRecord) -> Self {
        let size = (PADDING * record.weighted.len()).next_power_of_two().max(MIN_FFT_POINTS);
        let mut buffer: Vec<Complex<f64>> = record.weighted.iter().map(|x| Complex::new(*x, 0.0)).collect();
        buffer.resize(size, Complex::new(0.0, 0.0));
        FftPlanner::new().plan_fft_forward(size).process(&mut buffer);
        let amplitudes =
            buffer[..=size / 2].iter().map(|c| 2.0 * c.norm() / record.window_sum * record.scale).collect();
        Self { bin: 1.0 / (size as f64 * record.dt), amplitudes }
    }

    pub fn frequency(&self, k: usize) -> f64 {
        k as f64 * self.bin
    }
}

/// A spectral peak: frequency (Hz) and amplitude (the column's unit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Peak {
    pub frequency: f64,
    pub amplitude: f64,
}

/// The `count` largest peaks, largest first, each refined to the maximum of `A(f)`.
pub fn dominant_peaks(record: &WindowedRecord, spectrum: &AmplitudeSpectrum, count: usize, band: FrequencyBand) -> Vec<Peak> {
    let mut grid_peaks = peak_bins(spectrum, record.duration());
    grid_peaks.retain(|&k| band.contains(spectrum.frequency(k)));
    grid_peaks.sort_by(|a, b| spectrum.amplitudes[*b].total_cmp(&spectrum.amplitudes[*a]));
    grid_peaks.truncate(count);
    let mut peaks: Vec<Peak> = grid_peaks.into_iter().map(|k| refine(record, spectrum, k)).collect();
    peaks.sort_by(|a, b| b.amplitude.total_cmp(&a.amplitude));
    peaks
}

/// The frequencies a peak may have (Hz); `None` leaves that side open.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FrequencyBand {
    pub min: Option<f64>,
    pub max: Option<f64>,
}

impl FrequencyBand {
    pub fn contains(&self, f: f64) -> bool {
        self.min.is_none_or(|min| f >= min) && self.max.is_none_or(|max| f <= max)
    }
}

/// Grid indices of the peaks: local maxima, largest within the main lobe, above 2/T and the floor.
fn peak_bins(spectrum: &AmplitudeSpectrum, duration: f64) -> Vec<usize> {
    let a = &spectrum.amplitudes;
    let first = (MAIN_LOBE_HALF_WIDTH / duration / spectrum.bin).ceil() as usize;
    let lobe = (MAIN_LOBE_HALF_WIDTH / duration / spectrum.bin).round() as usize;
    let largest = a.iter().skip(first).copied().fold(0.0, f64::max);
    (first.max(1)..a.len().saturating_sub(1))
        .filter(|&k| a[k] > a[k - 1] && a[k] >= a[k + 1] && a[k] >= FLOOR * largest && a[k] > 0.0)
        .filter(|&k| a[k.saturating_sub(lobe)..=(k + lobe).min(a.len() - 1)].iter().all(|v| *v <= a[k]))
        .collect()
}

/// The maximum of `A(f)` between the grid points either side of bin `k`, by golden-section search.
fn refine(record: &WindowedRecord, spectrum: &AmplitudeSpectrum, k: usize) -> Peak {
    let inverse_golden = (5f64.sqrt() - 1.0) / 2.0;
    let (mut lo, mut hi) = (spectrum.frequency(k - 1), spectrum.frequency(k + 1));
    let mut c = hi - inverse_golden * (hi - lo);
    let mut d = lo + inverse_golden * (hi - lo);
    let (mut ac, mut ad) = (record.amplitude_at(c), record.amplitude_at(d));
    while hi - lo > 1e-9 * spectrum.bin {
        if ac > ad {
            (hi, d, ad) = (d, c, ac);
            c = hi - inverse_golden * (hi - lo);
            ac = record.amplitude_at(c);
        } else {
            (lo, c, ac) = (c, d, ad);
            d = lo + inverse_golden * (hi - lo);
            ad = record.amplitude_at(d);
        }
    }
    let frequency = 0.5 * (lo + hi);
    Peak { frequency, amplitude: record.amplitude_at(frequency) }
}

/// `x_k − (a + b k)` with `a + b k` the least-squares line through the samples.
fn remove_linear_trend(x: &[f64]) -> Vec<f64> {
    let n = x.len() as f64;
    let k_mean = (n - 1.0) / 2.0;
    let x_mean = x.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (k, v) in x.iter().enumerate() {
        let dk = k as f64 - k_mean;
        sxy += dk * (v - x_mean);
        sxx += dk * dk;
    }
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    x.iter().enumerate().map(|(k, v)| v - x_mean - slope * (k as f64 - k_mean)).collect()
}

/// The symmetric Hann window of `n` points.
fn hann(n: usize) -> Vec<f64> {
    let denominator = (n.max(2) - 1) as f64;
    (0..n).map(|k| 0.5 * (1.0 - (2.0 * std::f64::consts::PI * k as f64 / denominator).cos())).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `y(t)` sampled every `dt` from 0 to `t_end`.
    fn sampled(t_end: f64, dt: f64, y: impl Fn(f64) -> f64) -> UniformSamples {
        let count = (t_end / dt).round() as usize + 1;
        UniformSamples { t0: 0.0, dt, values: (0..count).map(|k| y(k as f64 * dt)).collect(), resampled: false }
    }

    fn peaks_of(samples: &UniformSamples, count: usize) -> Vec<Peak> {
        let record = WindowedRecord::new(samples);
        dominant_peaks(&record, &AmplitudeSpectrum::of(&record), count, FrequencyBand::default())
    }

    #[test]
    fn finds_two_sinusoids_on_a_trend_far_finer_than_the_resolution() {
        // 7.3 Hz (amplitude 1) and 19 Hz (0.25) on a linear trend, 1 kHz for 3 s: 1/T = 0.333 Hz.
        let tau = 2.0 * std::f64::consts::PI;
        let y = |t: f64| 0.4 + 2.0 * t + (tau * 7.3 * t + 0.3).sin() + 0.25 * (tau * 19.0 * t + 1.1).cos();
        let peaks = peaks_of(&sampled(3.0, 1e-3, y), 5);
        assert_eq!(peaks.len(), 2, "two peaks and no side lobes: {peaks:?}");
        // Frequencies to 1e-5 relative (2e-4 of 1/T at 7.3 Hz; 2e-7 and 1e-6 are reached), amplitudes
        // to 1e-4 (6e-7 and 8e-6 are reached): what is left is leakage from the other component.
        assert!((peaks[0].frequency / 7.3 - 1.0).abs() < 1e-5, "{peaks:?}");
        assert!((peaks[1].frequency / 19.0 - 1.0).abs() < 1e-5, "{peaks:?}");
        assert!((peaks[0].amplitude / 1.0 - 1.0).abs() < 1e-4, "{peaks:?}");
        assert!((peaks[1].amplitude / 0.25 - 1.0).abs() < 1e-4, "{peaks:?}");
    }

    #[test]
    fn a_sinusoid_between_grid_points_loses_no_amplitude() {
        // 12.345 Hz in 2 s: 24.69 periods, far from a whole number of bins.
        let y = |t: f64| 3e-3 * (2.0 * std::f64::consts::PI * 12.345 * t).sin();
        let peaks = peaks_of(&sampled(2.0, 2e-3, y), 3);
        assert_eq!(peaks.len(), 1, "{peaks:?}");
        assert!((peaks[0].frequency / 12.345 - 1.0).abs() < 1e-6, "{peaks:?}");
        assert!((peaks[0].amplitude / 3e-3 - 1.0).abs() < 1e-3, "{peaks:?}");
    }

    #[test]
    fn huge_values_give_the_same_peaks_scaled() {
        // 2e306 times the sinusoid of the test above: the sums of the trend overflowed before scaling.
        let y = |t: f64| 2e306 * (2.0 * std::f64::consts::PI * 12.345 * t).sin() + 1e307 * t;
        let peaks = peaks_of(&sampled(2.0, 2e-3, y), 3);
        assert_eq!(peaks.len(), 1, "{peaks:?}");
        assert!((peaks[0].frequency / 12.345 - 1.0).abs() < 1e-6, "{peaks:?}");
        assert!((peaks[0].amplitude / 2e306 - 1.0).abs() < 1e-3, "{peaks:?}");
        assert_eq!(power_of_two_below(1.7e308), 2f64.powi(1023));
        assert_eq!(power_of_two_below(3.0), 2.0);
        assert_eq!(power_of_two_below(0.0), 1.0);
    }

    #[test]
    fn the_trend_is_removed_and_the_window_tapers_to_zero() {
        let detrended = remove_linear_trend(&[1.0, 3.0, 5.0, 7.0]);
        assert!(detrended.iter().all(|v| v.abs() < 1e-12), "{detrended:?}");
        let w = hann(5);
        assert_eq!(w[0], 0.0);
        assert!((w[2] - 1.0).abs() < 1e-15 && w[4].abs() < 1e-15);
    }
}
