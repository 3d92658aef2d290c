//! `flexmb eigen`: the modes of a model linearized at an operating point (frequencies, damping
//! ratios, whirl, the coordinates that dominate each shape) as a table and `eigen.json`; with
//! `--sweep NAME=START:STOP:COUNT`, one eigen-analysis per value of a model parameter and the
//! frequencies against it, each mode followed by its shape (`sweep.json`, `sweep.csv`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use flexmb::analysis::{eigen_analysis, track_modes, EigenAnalysis, LinearModel, OperatingPointChoice};
use flexmb::Model;
use serde_json::{json, Value};

use flexmb_files::vtk::mechanism_mode::loaded_mechanism_mode_animation;

use crate::linear_analysis::{choice_kind, describe_choice, load_and_linearize};
use crate::plot::campbell::{critical_speeds, write_campbell};
use crate::run::CliError;

/// What `flexmb eigen` is asked for.
pub struct EigenOptions {
    /// Where to linearize.
    pub choice: OperatingPointChoice,
    /// Directory of the files.
    pub out: PathBuf,
    /// `--parameter` values.
    pub parameters: Vec<(String, f64)>,
    /// `--sweep`: a parameter and its values.
    pub sweep: Option<Sweep>,
    /// `--vtk`: a ParaView animation of every oscillating mode of the whole mechanism
    /// (`OUT/MODEL_mode_K.pvd`).
    pub vtk: bool,
    /// `--plot` (with `--sweep`): the Campbell diagram `OUT/campbell.png`.
    pub plot: bool,
    /// `--one-per-rev S`: the Campbell diagram's 1× line `f = S × parameter` (Hz per unit of the
    /// swept parameter: 1/(2π) for a spin in rad/s, 1/60 for rpm).
    pub one_per_rev: Option<f64>,
}

/// A parameter swept over `count` values from `start` to `stop`.
#[derive(Clone, Debug, PartialEq)]
pub struct Sweep {
    /// The parameter of the model's `[parameters]`.
    pub parameter: String,
    /// The values, evenly spaced, ends included.
    pub values: Vec<f64>,
}

/// Parses `NAME=START:STOP:COUNT`.
pub fn parse_sweep(text: &str) -> Result<Sweep, String> {
    let usage = || format!("expected NAME=START:STOP:COUNT (e.g. spin=0:500:11), got `{text}`");
    let (name, range) = text.split_once('=').ok_or_else(usage)?;
    let parts: Vec<&str> = range.split(':').collect();
    let [start, stop, count] = parts[..] else { return Err(usage()) };
    let (start, stop): (f64, f64) = (start.trim().parse().map_err(|_| usage())?, stop.trim().parse().map_err(|_| usage())?);
    let count: usize = count.trim().parse().map_err(|_| usage())?;
    if name.trim().is_empty() || count == 0 || !start.is_finite() || !stop.is_finite() {
        return Err(usage());
    }
    let values = (0..count).map(|k| if count == 1 { start } else { start + (stop - start) * k as f64 / (count - 1) as f64 }).collect();
    Ok(Sweep { parameter: name.trim().to_string(), values })
}

/// Runs `flexmb eigen`; returns the report to print.
pub fn run_eigen(path: &Path, options: &EigenOptions) -> Result<String, CliError> {
    std::fs::create_dir_all(&options.out).map_err(|e| CliError(format!("cannot create output directory {}: {e}", options.out.display())))?;
    match &options.sweep {
        None => {
            let (loaded, linear) = load_and_linearize(path, &options.parameters, options.choice)?;
            let modes = analyse(path, &loaded.model, &linear)?;
            let file = options.out.join("eigen.json");
            write_json(&file, &eigen_json(&loaded.model, &linear, &modes, options.choice))?;
            let mut report = table(&loaded.model, &linear, &modes, options.choice);
            let _ = writeln!(report, "written: {}", file.display());
            if options.vtk {
                for (k, mode) in modes.modes.iter().enumerate().filter(|(_, m)| !m.rigid_body) {
                    let label = (k + 1).to_string();
                    let animation = loaded_mechanism_mode_animation(&loaded, &linear.point.state.q, &mode.shape_re, &mode.shape_im, &label, &options.out)
                        .map_err(|e| CliError(format!("{}: mode {label}: {e}", path.display())))?;
                    let _ = writeln!(report, "written: {} (mode {label}, {:.6e} Hz)", animation.pvd.display(), mode.frequency);
                }
            }
            Ok(report)
        }
        Some(sweep) => run_sweep(path, options, sweep),
    }
}

fn analyse(path: &Path, model: &Model, linear: &LinearModel) -> Result<EigenAnalysis, CliError> {
    eigen_analysis(model, &linear.point.state, &linear.reduced).map_err(|e| CliError(format!("{}: {e}", path.display())))
}

/// A followed mode at one value of a sweep: frequency (Hz), damping ratio, whirl.
type TrackedMode = (f64, f64, &'static str);

/// One eigen-analysis per value of the swept parameter. Modes are tracked by their shapes
/// ([`track_modes`]: the modal assurance criterion between consecutive values), so that a mode keeps
/// its column (and its whirl) where curves cross; column `k` starts as the `k`-th oscillating mode of
/// the first value.
fn run_sweep(path: &Path, options: &EigenOptions, sweep: &Sweep) -> Result<String, CliError> {
    let mut analyses = Vec::new();
    let mut model_name = String::new();
    for &value in &sweep.values {
        let mut parameters = options.parameters.clone();
        parameters.push((sweep.parameter.clone(), value));
        let (loaded, linear) = load_and_linearize(path, &parameters, options.choice)?;
        if !loaded.parameters.contains_key(&sweep.parameter) {
            return Err(CliError(format!("--sweep: the model has no parameter '{}'", sweep.parameter)));
        }
        analyses.push(analyse(path, &loaded.model, &linear)?);
        model_name = loaded.model.name().to_string();
    }
    let tracks = track_modes(&analyses);
    // rows[i].1[k]: track k at value i.
    let rows: Vec<(f64, Vec<Option<TrackedMode>>)> = sweep
        .values
        .iter()
        .enumerate()
        .map(|(i, &value)| {
            let at = |m: Option<usize>| m.map(|m| &analyses[i].modes[m]).map(|m| (m.frequency, m.damping_ratio, m.whirl.label()));
            (value, tracks.iter().map(|t| at(t[i])).collect())
        })
        .collect();
    let columns = tracks.len();
    let mut csv = sweep.parameter.clone();
    for k in 1..=columns {
        let _ = write!(csv, ",mode{k}_hz,mode{k}_damping_ratio,mode{k}_whirl");
    }
    csv.push('\n');
    let mut report = format!("eigen-analysis of '{model_name}' against {} ({} values); modes followed by their shapes\n", sweep.parameter, rows.len());
    let _ = write!(report, "{:>14}", sweep.parameter);
    for k in 1..=columns {
        let _ = write!(report, " {:>22}", format!("mode {k} Hz (whirl)"));
    }
    report.push('\n');
    for (value, modes) in &rows {
        let _ = write!(csv, "{value:e}");
        let _ = write!(report, "{value:>14.6e}");
        for mode in modes {
            match mode {
                Some((f, z, w)) => {
                    let _ = write!(csv, ",{f:e},{z:e},{w}");
                    let _ = write!(report, " {:>22}", format!("{f:.6e} ({w})"));
                }
                None => {
                    csv.push_str(",,,");
                    let _ = write!(report, " {:>22}", "-");
                }
            }
        }
        csv.push('\n');
        report.push('\n');
    }
    let column = |pick: &dyn Fn(&TrackedMode) -> Value| -> Vec<Vec<Value>> {
        rows.iter().map(|(_, m)| m.iter().map(|x| x.as_ref().map_or(Value::Null, pick)).collect()).collect()
    };
    let json = json!({
        "model": model_name,
        "parameter": sweep.parameter,
        "tracking": "mode k follows its shape from value to value (the modal assurance criterion of complex shapes between consecutive values); null where the mode is absent",
        "values": rows.iter().map(|(v, _)| *v).collect::<Vec<_>>(),
        "frequencies_hz": column(&|x| json!(x.0)),
        "damping_ratios": column(&|x| json!(x.1)),
        "whirl": column(&|x| json!(x.2)),
    });
    let (json_file, csv_file) = (options.out.join("sweep.json"), options.out.join("sweep.csv"));
    write_json(&json_file, &json)?;
    std::fs::write(&csv_file, csv).map_err(|e| CliError(format!("cannot write {}: {e}", csv_file.display())))?;
    let _ = writeln!(report, "written: {}, {}", json_file.display(), csv_file.display());
    if options.plot {
        let png = options.out.join("campbell.png");
        let values: Vec<f64> = rows.iter().map(|(v, _)| *v).collect();
        let frequencies: Vec<Vec<f64>> = rows.iter().map(|(_, m)| m.iter().map(|x| x.map_or(f64::NAN, |x| x.0)).collect()).collect();
        write_campbell(&png, &sweep.parameter, &values, &frequencies, options.one_per_rev).map_err(|e| CliError(format!("{}: {e}", png.display())))?;
        let _ = writeln!(report, "written: {} (Campbell diagram)", png.display());
        if let Some(s) = options.one_per_rev {
            for c in critical_speeds(&values, &frequencies, s) {
                let _ = writeln!(report, "critical speed: the 1x line crosses mode {} at {} = {:.6e} ({:.6e} Hz)", c.mode + 1, sweep.parameter, c.value, c.frequency_hz);
            }
        }
    }
    Ok(report)
}

fn write_json(file: &Path, value: &Value) -> Result<(), CliError> {
    let text = serde_json::to_string_pretty(value).map_err(|e| CliError(e.to_string()))?;
    std::fs::write(file, text).map_err(|e| CliError(format!("cannot write {}: {e}", file.display())))
}

/// The two independent coordinates of largest amplitude in a mode's shape.
fn dominant(linear: &LinearModel, re: &[f64], im: &[f64]) -> String {
    let mut k: Vec<usize> = (0..re.len()).collect();
    k.sort_by(|&a, &b| re[b].hypot(im[b]).total_cmp(&re[a].hypot(im[a])));
    k.iter().take(2).map(|&i| linear.reduced.independent.names[i].clone()).collect::<Vec<_>>().join(", ")
}

/// The printed table.
pub fn table(model: &Model, linear: &LinearModel, modes: &EigenAnalysis, choice: OperatingPointChoice) -> String {
    let mut s = format!(
        "eigen-analysis of '{}' at {}: {} degrees of freedom\n",
        model.name(),
        describe_choice(choice, linear.point.state.t),
        linear.reduced.degrees_of_freedom()
    );
    if let Some(spin) = &modes.spin {
        let a = spin.axis;
        let _ = writeln!(s, "spin: body '{}', {:.6e} rad/s about ({:.3}, {:.3}, {:.3})", model.bodies()[spin.body].name, spin.speed, a[0], a[1], a[2]);
    }
    let _ = writeln!(s, "{:>5} {:>16} {:>16} {:>14} {:>9}  dominant coordinates", "mode", "frequency Hz", "damped Hz", "damping ratio", "whirl");
    for (k, m) in modes.modes.iter().enumerate() {
        let kind = if m.rigid_body { "rigid".to_string() } else { m.whirl.label().to_string() };
        let _ = writeln!(
            s,
            "{:>5} {:>16.9e} {:>16.9e} {:>14.6e} {:>9}  {}",
            k + 1,
            m.frequency,
            m.damped_frequency,
            m.damping_ratio,
            kind,
            dominant(linear, &m.independent_re, &m.independent_im)
        );
    }
    s
}

/// `eigen.json`.
pub fn eigen_json(model: &Model, linear: &LinearModel, modes: &EigenAnalysis, choice: OperatingPointChoice) -> Value {
    json!({
        "model": model.name(),
        "operating_point": { "kind": choice_kind(choice), "t": linear.point.state.t },
        "degrees_of_freedom": linear.reduced.degrees_of_freedom(),
        "coordinates": linear.reduced.independent.names,
        "velocity_names": model.velocity_names(),
        "frequency": "undamped natural frequency |s|/2π (Hz); damped_frequency_hz is Im(s)/2π",
        "spin": modes.spin.map(|s| json!({ "body": model.bodies()[s.body].name, "axis": s.axis, "speed": s.speed })),
        "modes": modes.modes.iter().map(|m| json!({
            "eigenvalue": [m.eigenvalue.0, m.eigenvalue.1],
            "frequency_hz": m.frequency,
            "damped_frequency_hz": m.damped_frequency,
            "damping_ratio": m.damping_ratio,
            "rigid_body": m.rigid_body,
            "whirl": m.whirl.label(),
            "shape": m.shape_re.iter().zip(&m.shape_im).map(|(a, b)| [*a, *b]).collect::<Vec<_>>(),
            "independent_shape": m.independent_re.iter().zip(&m.independent_im).map(|(a, b)| [*a, *b]).collect::<Vec<_>>(),
        })).collect::<Vec<_>>(),
    })
}
