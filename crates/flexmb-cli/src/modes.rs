//! `flexmb modes`: reduce a flexible body's FE model to a mode set, print the frequencies of the FE
//! model and of the reduced model, the mass properties and the warnings, and write the
//! flexible-body file (and the mode shapes for ParaView).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use flexmb_fem::modes::{EigenSettings, EigenSolver};
use flexmb_fem::reduction::{Basis, BodyMass, ModeKind, ModeSet, Reduction};
use flexmb_fem::{ElementKind, MassModel};

use flexmb_files::fe_model_file::{reduce_fe_model_file, LoadedFeModel, ReduceFileError, ReducedFeModel, ReductionRequest};
use crate::run::CliError;

/// What `flexmb modes` was asked to do.
#[derive(Clone, Debug, Default)]
pub struct ModesOptions {
    /// The mode set (`--modes`), else the file's `[modes] set`.
    pub mode_set: Option<String>,
    /// The basis (`--basis`), else the file's `[modes] basis`, else orthonormal.
    pub basis: Option<Basis>,
    /// The mass model (`--mass`), else the file's `[fe_model] mass`, else each kind of element's
    /// default (consistent for beams and solids, lumped for shells).
    pub mass: Option<MassModel>,
    /// Where to write the flexible-body file; default `out/NAME.json`.
    pub out: Option<PathBuf>,
    /// Directory for the mode shapes as VTK.
    pub vtk: Option<PathBuf>,
    pub solver: EigenSolver,
    /// Store each mode's stresses in the flexible-body file (`--stresses`), else the file's
    /// `[modes] stresses`.
    pub stresses: bool,
}

/// Runs `flexmb modes` on the FE model at `path`; returns the printed report.
pub fn run_modes(path: &Path, options: &ModesOptions) -> Result<String, CliError> {
    let mode_set = match &options.mode_set {
        Some(text) => Some(text.parse::<ModeSet>().map_err(|e| CliError(format!("--modes: {e}")))?),
        None => None,
    };
    let eigen = EigenSettings { solver: options.solver, memory_limit: crate::limits::memory_limit()?.bytes(), ..Default::default() };
    let request = ReductionRequest { mode_set, basis: options.basis, mass: options.mass, eigen, stresses: options.stresses.then_some(true) };
    let ReducedFeModel { loaded, reduction, seconds } = reduce_fe_model_file(path, &request).map_err(|e| match e {
        ReduceFileError::NoModeSet { file } => CliError(format!(
            "{file}: no mode set: give --modes (e.g. 6N, 5S or 4N5S) or `set` in the file's [modes] table"
        )),
        other => CliError(other.to_string()),
    })?;
    let out = options.out.clone().unwrap_or_else(|| PathBuf::from("out").join(format!("{}.json", loaded.name)));
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(|e| CliError(format!("cannot create {}: {e}", dir.display())))?;
    }
    reduction.body.write(&out).map_err(|e| CliError(e.to_string()))?;
    let mut report = describe(path, &loaded, &reduction, seconds);
    if let Some(stresses) = &reduction.body.stresses {
        let _ = writeln!(report, "modal stresses: {} stress points × {} modes", stresses.len(), reduction.body.mode_count());
    }
    let _ = writeln!(report, "wrote {}", out.display());
    if let Some(dir) = &options.vtk {
        let file = flexmb_files::vtk::write_mode_shapes(&reduction.body, dir).map_err(CliError)?;
        let _ = writeln!(report, "wrote {} (mode shapes for ParaView: Warp By Vector on a mode's translation)", file.display());
        let animations = flexmb_files::vtk::write_mode_animations(&reduction.body, dir).map_err(CliError)?;
        report.push_str(&describe_animations(&animations));
    }
    Ok(report)
}

/// One line per mode animation: its `.pvd` file and scale.
fn describe_animations(animations: &[flexmb_files::vtk::ModeAnimation]) -> String {
    let mut s = format!(
        "mode animations for ParaView ({} frames over one period, the largest displacement {}% of the body's size):\n",
        flexmb_files::vtk::FRAMES_PER_PERIOD,
        100.0 * flexmb_files::vtk::AMPLITUDE_FRACTION
    );
    for a in animations {
        let what = match a.rotation_only {
            true => format!(", rotation only: the largest rotation {} rad", flexmb_files::vtk::AMPLITUDE_FRACTION),
            false => String::new(),
        };
        let _ = writeln!(s, "  {}: {} (displacement = {:.4e} x the mode shape{what})", a.label, a.pvd.display(), a.scale);
    }
    s
}

/// The report of a reduction: model size, mass properties, eigensolver checks, the frequency table and
/// the warnings.
pub fn describe(path: &Path, loaded: &LoadedFeModel, reduction: &Reduction, seconds: f64) -> String {
    let mesh = &loaded.model.mesh;
    let body = &reduction.body;
    let count = |kind: fn(&ElementKind) -> bool| mesh.elements.iter().filter(|e| kind(&e.kind)).count();
    let beams = count(|k| matches!(k, ElementKind::Beam { .. }));
    let shells = count(|k| matches!(k, ElementKind::Shell { .. }));
    let solids = count(|k| matches!(k, ElementKind::Solid { .. }));
    let present = flexmb_fem::assembly::present_dofs(mesh);
    let dofs: usize = present.iter().map(|p| p.iter().count()).sum();
    let supported: usize = loaded
        .model
        .supports
        .iter()
        .map(|s| s.dofs.iter().filter(|d| present.get(s.node).is_some_and(|p| p.contains(*d))).count())
        .sum();
    let mut s = String::new();
    let _ = writeln!(s, "FE model {} ({})", loaded.name, path.display());
    let _ = writeln!(
        s,
        "  {} nodes, {} elements ({beams} beam, {shells} shell, {solids} solid), {} point masses, {dofs} dofs of which {supported} supported",
        mesh.nodes.len(),
        mesh.elements.len(),
        mesh.point_masses.len(),
    );
    if let Some(imported) = &mesh.imported {
        let _ = writeln!(
            s,
            "  stiffness and mass matrices imported from {} ({} and {} stored entries)",
            imported.origin,
            imported.stiffness.len(),
            imported.mass.len()
        );
    }
    if !mesh.elements.is_empty() || mesh.imported.is_none() {
        let _ = writeln!(s, "  mass matrix: {} ({})", body.mass.name(), mass_model_description(body.mass));
    }
    let p = &body.mass_properties;
    let c = p.center_of_mass;
    let _ = writeln!(s, "  mass {:.6e} kg, centre of mass [{:.6}, {:.6}, {:.6}] m", p.mass, c.x, c.y, c.z);
    let i = p.inertia;
    let _ = writeln!(
        s,
        "  inertia about the centre of mass [kg m²]: Ixx {:.6e}, Iyy {:.6e}, Izz {:.6e}, Ixy {:.3e}, Iyz {:.3e}, Izx {:.3e}",
        i[(0, 0)],
        i[(1, 1)],
        i[(2, 2)],
        i[(0, 1)],
        i[(1, 2)],
        i[(2, 0)]
    );
    let fe = &reduction.fe_modes;
    let _ = writeln!(
        s,
        "  eigensolver {:?}: {} modes, largest residual {:.1e}, largest M-orthogonality error {:.1e}; {} rigid motion(s) left by the supports; {:.3} s",
        fe.solver,
        fe.frequencies_hz.len(),
        fe.max_residual,
        fe.max_orthogonality_error,
        body.rigid_modes,
        seconds
    );
    let _ = writeln!(s, "mode set {} ({} basis), {} modes", body.mode_set, basis_name(body.basis), body.mode_count());
    let _ = writeln!(s, "  {:>4}  {:<6} {:<12} {:<18} {:>14}  {:>14}", "k", "mode", "kind", "load", "FE f [Hz]", "reduced f [Hz]");
    for k in 0..body.mode_count() {
        let mode = &body.modes[k];
        let kind = match mode.kind {
            ModeKind::Vibration => "vibration",
            ModeKind::Static => "static",
            ModeKind::Orthonormal => "orthonormal",
        };
        let fe_f = body.fe_frequencies_hz.get(k).map_or(String::from("-"), |f| format!("{f:.6}"));
        let _ = writeln!(
            s,
            "  {:>4}  {:<6} {:<12} {:<18} {:>14}  {:>14.6}",
            k + 1,
            mode.label,
            kind,
            mode.load.as_deref().unwrap_or("-"),
            fe_f,
            body.reduced_frequencies_hz[k]
        );
    }
    if let Some(statics) = &reduction.static_modes {
        let _ = writeln!(s, "  static modes solved with relative residual {:.1e}", statics.max_residual);
    }
    let _ = writeln!(s, "  basis independence (smallest scaled Gram eigenvalue) {:.2e}", reduction.basis_independence);
    for w in loaded.warnings.iter().chain(&reduction.warnings) {
        let _ = writeln!(s, "warning: {w}");
    }
    s
}

/// Where the elements' mass is, in a few words.
fn mass_model_description(mass: BodyMass) -> &'static str {
    match mass {
        BodyMass::Lumped => "at the nodes",
        BodyMass::Consistent => "beams' Hermite cubics, shells' bilinear/linear fields, solids' shape functions",
        BodyMass::Mixed => "consistent for the beams and solids, at the nodes for the shells",
    }
}

fn basis_name(basis: Basis) -> &'static str {
    match basis {
        Basis::Raw => "raw",
        Basis::Orthonormal => "orthonormalized",
    }
}
