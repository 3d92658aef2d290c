//! `flexmb spectrum`: the dominant frequencies of one result column, e.g. the vibration frequency of
//! a wiper arm, and optionally a plot of its amplitude spectrum.
//!
//! How the peaks are found and how accurate they are: [`estimator`] and docs/results.md.

pub mod estimator;
pub mod samples;

use std::fmt::Write;
use std::path::PathBuf;

use estimator::{dominant_peaks, AmplitudeSpectrum, FrequencyBand, Peak, WindowedRecord};
use samples::UniformSamples;

use crate::plot::{render, Annotation, Figure, ImageFormat, ResultTable, Series, SeriesStyle, Scale};
use crate::run::CliError;

/// What `flexmb spectrum` analyses.
#[derive(Clone, Debug)]
pub struct SpectrumOptions {
    pub file: PathBuf,
    /// The column to analyse.
    pub y: String,
    /// Start and end of the record (s); default the whole file.
    pub from: Option<f64>,
    pub to: Option<f64>,
    /// How many peaks to report, largest first.
    pub peaks: usize,
    /// Only peaks in this band are reported (e.g. a vibration above a slow gross motion).
    pub band: FrequencyBand,
    /// Image of the amplitude spectrum (.png or .svg), if wanted.
    pub out: Option<PathBuf>,
    pub y_scale: Scale,
    pub size: (u32, u32),
}

/// The analysis of one column: what was analysed and what was found.
#[derive(Clone, Debug)]
pub struct SpectrumReport {
    pub samples: UniformSamples,
    pub spectrum: AmplitudeSpectrum,
    pub peaks: Vec<Peak>,
}

impl SpectrumReport {
    /// Frequency resolution `1/T` (Hz).
    pub fn resolution(&self) -> f64 {
        1.0 / self.samples.duration()
    }

    pub fn nyquist(&self) -> f64 {
        0.5 / self.samples.dt
    }
}

/// Analyses the column, writes the plot if asked, and returns the printed report.
pub fn run_spectrum(options: &SpectrumOptions) -> Result<String, CliError> {
    if let Some(out) = &options.out {
        ImageFormat::of(out)?;
    }
    let table = ResultTable::read(&options.file)?;
    let t = table.finite_column("t", "a spectrum")?;
    let report = analyse(t, table.column(&options.y)?, options)
        .map_err(|e| CliError(format!("spectrum of `{}` in {}: {e}", options.y, options.file.display())))?;
    let unit = table.unit(&options.y).map(str::to_string);
    let mut text = describe(&table, &options.y, unit.as_deref(), &report);
    if let Some(out) = &options.out {
        let figure = spectrum_figure(&table, &options.y, unit, &report, options.y_scale);
        render(&figure, out, options.size)?;
        writeln!(text, "\nspectrum plot: {}", out.display()).ok();
        if let Some(note) = hidden_peaks_note(&figure, &report) {
            writeln!(text, "  {note}").ok();
        }
    }
    Ok(text)
}

/// The spectrum and peaks of `y(t)` over the options' time window.
pub fn analyse(t: &[f64], y: &[f64], options: &SpectrumOptions) -> Result<SpectrumReport, CliError> {
    let samples = UniformSamples::select(t, y, options.from, options.to)?;
    let record = WindowedRecord::new(&samples);
    let spectrum = AmplitudeSpectrum::of(&record);
    if spectrum.amplitudes.iter().any(|a| !a.is_finite()) {
        let largest = samples.values.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
        return Err(CliError(format!(
            "the values reach {largest:e}: their amplitudes pass the largest double-precision number, 1.8e308"
        )));
    }
    let peaks = dominant_peaks(&record, &spectrum, options.peaks, options.band);
    Ok(SpectrumReport { samples, spectrum, peaks })
}

/// The printed report: the record, resolution, Nyquist frequency, and the table of peaks.
fn describe(table: &ResultTable, column: &str, unit: Option<&str>, report: &SpectrumReport) -> String {
    let s = &report.samples;
    let mut text = String::new();
    let unit_text = unit.map(|u| format!(" [{u}]")).unwrap_or_default();
    writeln!(text, "spectrum of {column}{unit_text} in {}", table.path().display()).ok();
    let step = if s.resampled { "resampled by linear interpolation from non-uniform times" } else { "uniform" };
    writeln!(text, "  record        t = {} s to {} s: {} samples, Δt = {} s ({step})", s.t0, s.t_end(), s.len(), s.dt)
        .ok();
    writeln!(
        text,
        "  resolution    1/T = {} Hz (T = N Δt = {} s)",
        significant(report.resolution()),
        significant(s.duration())
    )
    .ok();
    writeln!(text, "  Nyquist       {} Hz", significant(report.nyquist())).ok();
    writeln!(
        text,
        "  method        linear trend removed, Hann window, zero-padded FFT ({} points), peaks refined to the maximum of the windowed spectrum",
        2 * (report.spectrum.amplitudes.len() - 1)
    )
    .ok();
    if report.peaks.is_empty() {
        writeln!(text, "\nno peak above 2/T: the column holds no oscillation this record can resolve").ok();
        return text;
    }
    let decimals = frequency_decimals(report.resolution());
    let amplitude_header = format!("amplitude{}", unit.map(|u| format!(" ({u})")).unwrap_or_default());
    writeln!(text, "\n  rank  {:>16}  {amplitude_header:>16}", "frequency (Hz)").ok();
    for (rank, peak) in report.peaks.iter().enumerate() {
        writeln!(text, "  {:>4}  {:>16.decimals$}  {:>16}", rank + 1, peak.frequency, significant(peak.amplitude)).ok();
    }
    text
}

/// Decimals that show the frequency to about 1/10 000 of the resolution.
fn frequency_decimals(resolution: f64) -> usize {
    (4.0 - resolution.log10().floor()).clamp(0.0, 12.0) as usize
}

/// Five significant digits: plain from 0.001 to 100 000, else scientific.
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i32;
    if (-3..5).contains(&magnitude) {
        let decimals = (4 - magnitude).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        format!("{x:.4e}")
    }
}

/// The amplitude spectrum with every reported peak marked and labelled with its frequency: from 0 to
/// twice the highest peak (at least 20/T, at most the Nyquist frequency), so that every peak lies
/// inside the frequency axis with room after it; the amplitude axis holds every peak (on a log axis
/// at least a decade above its floor: [`axis_ranges`](crate::plot::axis_ranges)).
pub fn spectrum_figure(
    table: &ResultTable,
    column: &str,
    unit: Option<String>,
    report: &SpectrumReport,
    y_scale: Scale,
) -> Figure {
    let highest = report.peaks.iter().map(|p| p.frequency).fold(0.0, f64::max);
    let f_max = (2.0 * highest).max(20.0 * report.resolution()).min(report.nyquist());
    let spectrum = &report.spectrum;
    let shown = ((f_max / spectrum.bin).ceil() as usize + 1).min(spectrum.amplitudes.len());
    let decimals = frequency_decimals(report.resolution()).min(4);
    Figure {
        title: format!("Amplitude spectrum of {column} — {}", table.stem()),
        x_quantity: ("frequency".into(), Some("Hz".into())),
        y_quantity: ("amplitude".into(), unit),
        series: vec![Series {
            label: format!("{column}, t = {} to {} s, Hann window", report.samples.t0, report.samples.t_end()),
            points: (0..shown).map(|k| (spectrum.frequency(k), spectrum.amplitudes[k])).collect(),
            style: SeriesStyle::Line,
        }],
        annotations: report
            .peaks
            .iter()
            .map(|p| Annotation { x: p.frequency, y: p.amplitude, text: format!("{:.decimals$} Hz", p.frequency) })
            .collect(),
        y_scale,
        x_scale: Scale::Linear,
        x_range: Some((0.0, f_max)),
        y_range: None,
    }
}

/// On a linear amplitude axis a peak below this fraction of the axis's height is a flat line at the
/// bottom: only its marker shows it.
const LINEAR_VISIBLE: f64 = 0.01;

/// A note for the report if some peaks are too small to see on the figure's linear amplitude axis.
fn hidden_peaks_note(figure: &Figure, report: &SpectrumReport) -> Option<String> {
    let (_, (lo, hi)) = crate::plot::axis_ranges(figure).ok()?;
    if figure.y_scale != Scale::Linear {
        return None;
    }
    let small: Vec<String> = report
        .peaks
        .iter()
        .filter(|p| p.amplitude - lo.max(0.0) < LINEAR_VISIBLE * (hi - lo))
        .map(|p| format!("{} Hz", significant(p.frequency)))
        .collect();
    (!small.is_empty()).then(|| {
        format!(
            "on the linear amplitude axis the peaks at {} are below 1 % of its height and show only as their \
             markers; --scale log shows them",
            small.join(", ")
        )
    })
}
