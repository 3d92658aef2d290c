//! `flexmb check`: validate a model, assemble it, and report degrees of freedom and redundancy, and
//! the flexible bodies: their modes, and whether each was reduced, read from the cache or from a file.

use flexmb::body::ModalBody;
use flexmb::model::BodyId;
use flexmb::Model;

use flexmb_files::model_file::{FlexibleBodyOrigin, LoadedModel};

/// The engine's check of a model (assembly and velocity analysis), which the program prints.
pub use flexmb::analysis::{check_model, CheckReport};

/// Text for the assembly part of a check or run.
pub fn describe(model: &Model, report: &CheckReport) -> String {
    let a = &report.assembly;
    let l = model.layout();
    let mut s = format!(
        "model '{}': {} bodies, {} markers, {} joints ({} constraint equations), {} force elements\n\
         assembly: {} iterations, residual {:.2e} -> {:.2e}\n\
         degrees of freedom: {}\n",
        model.name(),
        model.bodies().len(),
        model.markers().len(),
        model.joints().len(),
        l.nc,
        model.forces().len(),
        a.iterations,
        a.initial_residual,
        a.residual,
        a.degrees_of_freedom,
    );
    for b in 0..model.bodies().len() {
        if let Some(modal) = model.modal_body(BodyId(b)) {
            s.push_str(&describe_modal(&model.bodies()[b].name, modal));
        }
    }
    if a.redundant.is_empty() {
        s.push_str("redundant constraints: none\n");
    } else {
        s.push_str(&format!(
            "redundant constraints: {} (removed; their reaction forces are reported as zero):\n",
            a.redundant.len()
        ));
        for r in &a.redundant {
            s.push_str(&format!("  - {}\n", r.description));
        }
    }
    for adj in &report.velocity.adjusted {
        s.push_str(&format!("warning: {adj}\n"));
    }
    s
}

/// The columns `flexmb run` writes into the model's CSV, in order, each with its unit:
/// `output columns (4):` and one `  name [unit]` line per column, `t` first.
pub fn describe_columns(model: &Model) -> String {
    let columns = flexmb::analysis::OutputTable::new(model).columns().to_vec();
    let mut s = format!("output columns ({}):\n", columns.len());
    for c in columns {
        s.push_str(&format!("  {} [{}]\n", c.name, c.unit));
    }
    s
}

/// `flexible body 'beam': 4 modes (O1 18.2 Hz, …), 21 nodes, 1.57 kg`.
fn describe_modal(name: &str, modal: &ModalBody) -> String {
    let frequencies = modal_frequencies(modal);
    let modes: Vec<String> = modal
        .mode_labels
        .iter()
        .enumerate()
        .map(|(k, label)| match frequencies.as_ref().and_then(|f| f.get(k)) {
            Some(f) => format!("{label} {}", hz(*f)),
            None => label.clone(),
        })
        .collect();
    let listed = if modes.len() > 8 {
        format!("{}, …, {}", modes[..6].join(", "), modes[modes.len() - 1])
    } else {
        modes.join(", ")
    };
    let (count, plural) = (modal.modes(), if modal.modes() == 1 { "" } else { "s" });
    let modes = if count == 0 { "no modes (rigid)".to_string() } else { format!("{count} mode{plural} ({listed})") };
    format!(
        "flexible body '{name}': {modes}, {} nodes, mass {:.6} kg\n",
        modal.nodes.len(),
        modal.invariants.mass
    )
}

/// The natural frequencies (Hz) of the body's modal mass and stiffness, ascending (the mode labels
/// name the basis; with the orthonormal basis the k-th frequency is the k-th mode's own).
fn modal_frequencies(modal: &ModalBody) -> Option<Vec<f64>> {
    if modal.modes() == 0 {
        return Some(Vec::new());
    }
    let mass = modal.invariants.modal_mass();
    let l_inv = nalgebra::Cholesky::new(mass)?.l().try_inverse()?;
    let reduced = &l_inv * &modal.stiffness * l_inv.transpose();
    let reduced = 0.5 * (&reduced + reduced.transpose());
    let mut eigenvalues: Vec<f64> = nalgebra::SymmetricEigen::new(reduced).eigenvalues.iter().copied().collect();
    eigenvalues.sort_by(f64::total_cmp);
    Some(eigenvalues.iter().map(|l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)).collect())
}

/// A frequency with four significant digits.
fn hz(f: f64) -> String {
    if f >= 1000.0 {
        format!("{f:.0} Hz")
    } else if f >= 100.0 {
        format!("{f:.1} Hz")
    } else if f >= 10.0 {
        format!("{f:.2} Hz")
    } else {
        format!("{f:.3} Hz")
    }
}

/// Where each flexible body of a loaded model came from (reduced now, from the cache, from a
/// flexible-body file), the natural modes its `high_mode_damping` damps, and the FE model's, the
/// reduction's and the table's warnings.
pub fn describe_flexible_bodies(loaded: &LoadedModel) -> String {
    let mut s = String::new();
    for info in &loaded.flexible_bodies {
        let basis = flexmb_files::model_file::basis_name(info.basis);
        let what = format!("flexible body '{}' ({} {basis})", info.name, info.mode_set);
        let line = match &info.origin {
            FlexibleBodyOrigin::Reduced { fe_model, cache: Some(cache), seconds } => {
                format!("{what}: reduced from {} in {seconds:.3} s, cached in {}", fe_model.display(), cache.display())
            }
            FlexibleBodyOrigin::Reduced { fe_model, cache: None, seconds } => format!(
                "{what}: reduced from {} in {seconds:.3} s (the cache directory could not be written)",
                fe_model.display()
            ),
            FlexibleBodyOrigin::Cached { fe_model, cache } => {
                format!("{what}: reduction of {} read from the cache {}", fe_model.display(), cache.display())
            }
            FlexibleBodyOrigin::BodyFile { path } => format!("{what}: read from {}", path.display()),
        };
        s.push_str(&line);
        s.push('\n');
        if let Some(high) = &info.high_mode_damping {
            let damped: Vec<f64> = info.frequencies_hz.iter().copied().filter(|&f| f > high.above_hz).collect();
            if let (Some(first), Some(last)) = (damped.first(), damped.last()) {
                s.push_str(&format!(
                    "flexible body '{}': damping ratio {} on the {} natural mode(s) above {} Hz ({} to {})\n",
                    info.name,
                    high.ratio,
                    damped.len(),
                    high.above_hz,
                    hz(*first),
                    hz(*last)
                ));
            }
        }
        for warning in &info.warnings {
            s.push_str(&format!("warning: {}: {warning}\n", info.name));
        }
    }
    s
}
