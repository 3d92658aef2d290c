//! Reduction of an FE model to a flexible body: the mode set's basis (vibration and static correction
//! modes, raw or mass-orthonormalized), the frequencies of the reduced model, the modal mass and
//! stiffness, the inertia invariants, and the flexible-body file that holds them.

mod flexible_body;
mod geometric_stiffness;
mod interface_modes;
mod invariants;
mod massless_directions;
mod modal_stress;
mod mode_set;
mod serde_matrix;

use faer::{Mat, Side};
use nalgebra::{DMatrix, Matrix3, Vector3};

pub use flexible_body::{
    Basis, BodyElement, BodyFileError, BodyMass, BodyMassProperties, BodyNode, FlexibleBody, ModeInfo, ModeKind, ModeShape,
    FORMAT, VERSION,
};
pub use geometric_stiffness::{GeometricStiffness, InterfaceStiffness, CENTRIFUGAL_CASES, INTERFACE_CASES};
pub use interface_modes::interface_dofs;
pub use invariants::InertiaInvariants;
pub use modal_stress::{add_modal_stresses, von_mises, ModalStresses};
pub use mode_set::{ModeGroup, ModeSet};

use crate::assembly::{AssembledModel, MassProperties};
use crate::error::FemError;
use crate::mesh::FeModel;
use crate::modes::{check_memory, prepare, prepare_supported, vibration_modes_of, EigenSettings, PreparedModel, VibrationModes};
use crate::static_correction::{static_correction_modes, StaticModes};
use crate::symmetric_product::{symmetric_projection, symmetrized};
use massless_directions::drop_massless_directions;

/// What to reduce to.
#[derive(Clone, Debug, PartialEq)]
pub struct ReductionSettings {
    /// The vibration and static correction modes of the basis, such as `4N2S`.
    pub mode_set: ModeSet,
    /// Default [`Basis::Orthonormal`].
    pub basis: Basis,
    /// How the vibration modes are found.
    pub eigen: EigenSettings,
}

/// A reduced body and how it was obtained.
#[derive(Clone, Debug)]
pub struct Reduction {
    /// The flexible body: nodes, modes, modal mass and stiffness, invariants.
    pub body: FlexibleBody,
    /// The FE vibration modes computed (at least as many as the basis has modes, for comparison).
    pub fe_modes: VibrationModes,
    /// The static correction modes (all the model's loads), if the mode set has any.
    pub static_modes: Option<StaticModes>,
    /// Smallest eigenvalue of the raw basis' Gram matrix `ΦᵀMΦ` scaled to unit diagonal: near 0, the
    /// basis is nearly dependent.
    pub basis_independence: f64,
    /// Things the user should know: rigid modes found, loads balanced by inertia relief, a nearly
    /// dependent basis.
    pub warnings: Vec<String>,
}

/// Below this, the scaled Gram matrix's smallest eigenvalue makes the basis a warning.
const NEARLY_DEPENDENT: f64 = 1e-6;
/// Below this, the basis is singular.
const DEPENDENT: f64 = 1e-12;

/// Reduces `model` to the mode set of `settings`; `name` names the body.
///
/// A steel cantilever 1 m long, 10 mm square, in 20 beam elements, reduced to its four lowest
/// vibration modes: the first frequency is Euler–Bernoulli's `(1.8751)² / (2π) √(E I / (ρ A L⁴))`
/// and the mass is `ρ A L`.
///
/// ```
/// use flexmb_fem::mesh::{BeamSection, FeModel, Material, Mesh};
/// use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
/// use flexmb_fem::{DofSet, Support};
/// use nalgebra::Vector3;
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let (e, rho, h, length): (f64, f64, f64, f64) = (2.1e11, 7850.0, 0.01, 1.0);
/// let (area, i) = (h * h, h.powi(4) / 12.0);
/// let mut mesh = Mesh {
///     materials: vec![Material { name: "steel".into(), youngs_modulus: e, poisson_ratio: 0.3, density: rho }],
///     beam_sections: vec![BeamSection {
///         name: "square".into(),
///         material: 0,
///         area,
///         iy: i,
///         iz: i,
///         torsion_constant: 0.1406 * h.powi(4),
///         orientation: Vector3::new(0.0, 1.0, 0.0),
///         shear_coefficient: None,
///         outline: Default::default(),
///     }],
///     ..Default::default()
/// };
/// let nodes = mesh.add_beam_line(Vector3::zeros(), Vector3::new(length, 0.0, 0.0), 20, 0)?;
/// let clamp = Support { node: nodes[0], dofs: DofSet::ALL };
/// let model = FeModel { mesh, supports: vec![clamp], ..Default::default() };
///
/// let settings = ReductionSettings { mode_set: "4N".parse()?, basis: Basis::Raw, eigen: Default::default() };
/// let reduction = reduce(&model, "cantilever", &settings)?;
/// let body = &reduction.body;
///
/// let euler_bernoulli = 1.8751_f64.powi(2) / (2.0 * std::f64::consts::PI) * (e * i / (rho * area)).sqrt();
/// assert!((body.fe_frequencies_hz[0] / euler_bernoulli - 1.0).abs() < 2e-3);
/// assert_eq!(body.mode_count(), 4);
/// assert!((body.mass_properties.mass - rho * area * length).abs() < 1e-12);
/// assert!((body.mass_properties.center_of_mass.x - length / 2.0).abs() < 1e-12);
/// # Ok(())
/// # }
/// ```
pub fn reduce(model: &FeModel, name: &str, settings: &ReductionSettings) -> Result<Reduction, FemError> {
    let set = &settings.mode_set;
    if set.statics() > model.static_loads.len() {
        return Err(FemError::ModeSet {
            text: set.to_string(),
            message: format!(
                "asks for {} static correction modes but the model defines {} static loads",
                set.statics(),
                model.static_loads.len()
            ),
        });
    }
    model.check_references()?;
    check_memory(model, &settings.eigen)?;
    // An interface set reduces the unsupported model: assembled once, the supported model's
    // matrices taken from it.
    let free = if set.uses_interface() { Some(prepare(&FeModel { supports: Vec::new(), ..model.clone() })?) } else { None };
    let prepared = match &free {
        Some(free) => prepare_supported(model, free)?,
        None => prepare(model)?,
    };
    let (model, assembled, rigid) = (&prepared.model, &prepared.assembled, &prepared.rigid);
    let mut warnings = Vec::new();
    for &(node, dof) in &prepared.held_massless {
        warnings.push(format!(
            "node {} dof {} held: the rigid motion through it has no mass (lump rotary inertia to keep it)",
            model.mesh.nodes[node].label,
            dof.name()
        ));
    }
    let rigid_count = rigid.ncols() + prepared.held_massless.len();
    if rigid_count > 0 {
        warnings.push(format!(
            "the supports leave {rigid_count} rigid motion(s) (zero-frequency mechanisms); they are excluded from the vibration modes"
        ));
    }
    if let Some(free) = free {
        return reduce_on_interface(model, &prepared, free, name, settings, warnings);
    }
    let fe_count = set.len().max(set.vibration());
    let mut fe_modes = vibration_modes_of(assembled, rigid, fe_count, &settings.eigen)?;
    fe_modes.rigid_modes = rigid_count;
    let static_modes = if set.statics() > 0 { Some(static_correction_modes(model, assembled, rigid)?) } else { None };
    if let Some(statics) = &static_modes {
        for (name, fraction) in statics.names.iter().zip(&statics.rigid_load_fractions).take(set.statics()) {
            if *fraction > 1e-8 {
                warnings.push(format!(
                    "static load {name} moves the rigid mechanism ({:.1} % of it); it was balanced by rigid-body inertia forces (inertia relief)",
                    100.0 * fraction
                ));
            }
        }
    }
    let (mut basis, modes) = raw_basis(set, &fe_modes, static_modes.as_ref());
    let names: Vec<String> =
        modes.iter().map(|m| m.load.as_ref().map_or(m.label.clone(), |l| format!("{} ({l})", m.label))).collect();
    let (mut modal_mass, kept) = drop_massless_directions(model, assembled, &mut basis, &names, &mut warnings);
    let mut modes: Vec<ModeInfo> = kept.iter().map(|&j| modes[j].clone()).collect();
    let mut modal_stiffness = symmetric_projection(&assembled.stiffness, basis.as_ref());
    let basis_independence = scaled_gram_minimum(&modal_mass)?;
    if basis_independence < DEPENDENT {
        return Err(FemError::SingularBasis {
            message: format!("the modes of {set} are linearly dependent (scaled Gram eigenvalue {basis_independence:.1e}); drop a static mode or use fewer modes"),
        });
    }
    if basis_independence < NEARLY_DEPENDENT {
        warnings.push(format!(
            "the modes of {set} are nearly dependent (scaled Gram eigenvalue {basis_independence:.1e}): a static mode is almost in the span of the others"
        ));
    }
    let (reduced_eigenvalues, ritz) = reduced_eigenproblem(&modal_mass, &modal_stiffness)?;
    let reduced_frequencies_hz: Vec<f64> = reduced_eigenvalues.iter().map(|l| hz(*l)).collect();
    if settings.basis == Basis::Orthonormal {
        basis = &basis * &ritz;
        modal_mass = symmetric_projection(&assembled.mass, basis.as_ref());
        modal_stiffness = symmetric_projection(&assembled.stiffness, basis.as_ref());
        modes = orthonormal_modes(&reduced_frequencies_hz);
    }
    let mut body = flexible_body(
        model,
        assembled,
        name,
        settings,
        &basis,
        modes,
        (&modal_mass, &modal_stiffness),
        reduced_frequencies_hz,
        &fe_modes,
    )?;
    body.geometric_stiffness = Some(geometric_stiffness::geometric_stiffness(model, assembled, rigid, &nodal_modes(assembled, &basis))?);
    Ok(Reduction { body, fe_modes, static_modes, basis_independence, warnings })
}

/// [`reduce`] for a Craig–Bampton or free-interface set ([`interface_modes`]).
fn reduce_on_interface(
    model: &FeModel,
    supported: &PreparedModel,
    free: PreparedModel,
    name: &str,
    settings: &ReductionSettings,
    warnings: Vec<String>,
) -> Result<Reduction, FemError> {
    let set = &settings.mode_set;
    if settings.basis == Basis::Raw {
        return Err(FemError::ModeSet {
            text: set.to_string(),
            message: "Craig–Bampton and free-interface sets are orthonormalized (their span holds rigid motions, which the floating frame carries): use the orthonormal basis".into(),
        });
    }
    let mut raw = interface_modes::interface_basis(model, supported, free, set, &settings.eigen)?;
    let mut warnings = warnings;
    let names: Vec<String> =
        set.groups.iter().flat_map(|g| (1..=g.count()).map(move |j| format!("{}{j}", g.letter()))).collect();
    drop_massless_directions(&raw.free.model, &raw.free.assembled, &mut raw.basis, &names, &mut warnings);
    let free = &raw.free;
    let (eigenvalues, basis, basis_independence) = interface_modes::orthonormal_elastic_span(free, &raw.basis, raw.rigid_in_span, set)?;
    if basis_independence < NEARLY_DEPENDENT {
        warnings.push(format!(
            "the modes of {set} are nearly dependent (scaled Gram eigenvalue {basis_independence:.1e}) once their rigid motions are removed"
        ));
    }
    let modal_mass = symmetric_projection(&free.assembled.mass, basis.as_ref());
    let modal_stiffness = symmetric_projection(&free.assembled.stiffness, basis.as_ref());
    let reduced_frequencies_hz: Vec<f64> = eigenvalues.iter().map(|l| hz(*l)).collect();
    let modes = orthonormal_modes(&reduced_frequencies_hz);
    // The geometric stiffness of the unit inertia and interface loads is that of the supported body's
    // statics; an interface set's body is free, so it has none (the field stays absent, and a model
    // asking for stiffening gets the warning of a body without the terms).
    let body = flexible_body(
        &free.model,
        &free.assembled,
        name,
        settings,
        &basis,
        modes,
        (&modal_mass, &modal_stiffness),
        reduced_frequencies_hz,
        &raw.fe_modes,
    )?;
    Ok(Reduction { body, fe_modes: raw.fe_modes, static_modes: raw.static_modes, basis_independence, warnings })
}

/// The modes of an orthonormalized basis, `O1`, `O2`, …, with their reduced frequencies (Hz).
fn orthonormal_modes(frequencies_hz: &[f64]) -> Vec<ModeInfo> {
    frequencies_hz
        .iter()
        .enumerate()
        .map(|(j, f)| ModeInfo { label: format!("O{}", j + 1), kind: ModeKind::Orthonormal, frequency_hz: Some(*f), load: None })
        .collect()
}

fn hz(eigenvalue: f64) -> f64 {
    eigenvalue.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)
}

/// The raw basis over the free dofs, in the order of the mode set's groups, and its mode labels.
fn raw_basis(set: &ModeSet, fe: &VibrationModes, statics: Option<&StaticModes>) -> (Mat<f64>, Vec<ModeInfo>) {
    let n = fe.shapes.nrows();
    let mut columns: Vec<Vec<f64>> = Vec::new();
    let mut modes = Vec::new();
    for group in &set.groups {
        match *group {
            ModeGroup::Vibration(count) => {
                for j in 0..count {
                    columns.push((0..n).map(|i| fe.shapes[(i, j)]).collect());
                    modes.push(ModeInfo { label: format!("N{}", j + 1), kind: ModeKind::Vibration, frequency_hz: Some(fe.frequencies_hz[j]), load: None });
                }
            }
            ModeGroup::Constraint(_) | ModeGroup::FreeVibration(_) | ModeGroup::Attachment(_) => {
                unreachable!("interface sets are reduced by reduce_on_interface")
            }
            ModeGroup::Static(count) => {
                let statics = statics.expect("static modes computed when the set has any");
                for j in 0..count {
                    columns.push((0..n).map(|i| statics.shapes[(i, j)]).collect());
                    modes.push(ModeInfo { label: format!("S{}", j + 1), kind: ModeKind::Static, frequency_hz: None, load: Some(statics.names[j].clone()) });
                }
            }
        }
    }
    (Mat::from_fn(n, columns.len(), |i, j| columns[j][i]), modes)
}

/// Smallest eigenvalue of `D^{-1/2} G D^{-1/2}` (`D` the diagonal of `G`).
fn scaled_gram_minimum(gram: &Mat<f64>) -> Result<f64, FemError> {
    let m = gram.nrows();
    let scaled = Mat::from_fn(m, m, |i, j| gram[(i, j)] / (gram[(i, i)] * gram[(j, j)]).sqrt());
    let values = scaled
        .self_adjoint_eigenvalues(Side::Lower)
        .map_err(|e| FemError::LinearAlgebra(format!("basis Gram matrix: {e:?}")))?;
    Ok(values.first().copied().unwrap_or(1.0))
}

/// The eigenvalues ω² (ascending) and M-orthonormal eigenvectors `X` of the reduced pair
/// `(ΦᵀKΦ) x = ω² (ΦᵀMΦ) x`.
fn reduced_eigenproblem(mass: &Mat<f64>, stiffness: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>), FemError> {
    let m = mass.nrows();
    let factor = mass
        .llt(Side::Lower)
        .map_err(|e| FemError::SingularBasis { message: format!("the modal mass is not positive definite: {e:?}") })?;
    let l = factor.L();
    // A = L⁻¹ K L⁻ᵀ
    let mut a = stiffness.clone();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, a.as_mut(), faer::Par::Seq);
    let mut a = a.transpose().to_owned();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(l, a.as_mut(), faer::Par::Seq);
    let a = symmetrized(&a);
    let eigen = a
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| FemError::LinearAlgebra(format!("reduced eigenproblem: {e:?}")))?;
    let values: Vec<f64> = (0..m).map(|k| eigen.S()[k]).collect();
    // X = L⁻ᵀ Y
    let mut x = eigen.U().to_owned();
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(l.transpose(), x.as_mut(), faer::Par::Seq);
    Ok((values, x))
}

/// Every mode of `basis` (over the free dofs) over all `6 n_nodes` nodal dofs.
fn nodal_modes(assembled: &AssembledModel, basis: &Mat<f64>) -> Vec<Vec<f64>> {
    (0..basis.ncols()).map(|j| assembled.dofs.expand(&(0..basis.nrows()).map(|i| basis[(i, j)]).collect::<Vec<_>>())).collect()
}

fn to_nalgebra(m: &Mat<f64>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

#[allow(clippy::too_many_arguments)]
fn flexible_body(
    model: &FeModel,
    assembled: &AssembledModel,
    name: &str,
    settings: &ReductionSettings,
    basis: &Mat<f64>,
    modes: Vec<ModeInfo>,
    (modal_mass, modal_stiffness): (&Mat<f64>, &Mat<f64>),
    reduced_frequencies_hz: Vec<f64>,
    fe_modes: &VibrationModes,
) -> Result<FlexibleBody, FemError> {
    let mesh = &model.mesh;
    let m = basis.ncols();
    let nodal = nodal_modes(assembled, basis);
    let shapes: Vec<ModeShape> = nodal
        .iter()
        .map(|v| ModeShape {
            translation: (0..mesh.nodes.len()).map(|i| [v[6 * i], v[6 * i + 1], v[6 * i + 2]]).collect(),
            rotation: (0..mesh.nodes.len()).map(|i| [v[6 * i + 3], v[6 * i + 4], v[6 * i + 5]]).collect(),
        })
        .collect();
    let points = &assembled.mass_points;
    let positions: Vec<Vector3<f64>> = points.iter().map(|p| p.position).collect();
    let masses: Vec<f64> = points.iter().map(|p| p.mass).collect();
    let rotary: Vec<Matrix3<f64>> = points.iter().map(|p| p.rotary_inertia).collect();
    // Ψ and Θ of each mass point: its interpolation applied to the nodal mode shapes.
    let (psi, theta): (Vec<DMatrix<f64>>, Vec<DMatrix<f64>>) = points
        .iter()
        .map(|p| {
            let motion = DMatrix::from_fn(6, m, |r, j| {
                p.interpolation
                    .iter()
                    .map(|(node, g)| (0..6).map(|c| g[(r, c)] * nodal[j][6 * node + c]).sum::<f64>())
                    .sum()
            });
            (motion.rows(0, 3).into_owned(), motion.rows(3, 3).into_owned())
        })
        .unzip();
    let invariants = InertiaInvariants::new(&positions, &masses, &rotary, &psi, &theta, m)?;
    let properties = MassProperties::of_points(points);
    Ok(FlexibleBody {
        format: FORMAT.to_string(),
        version: VERSION,
        name: name.to_string(),
        mode_set: settings.mode_set.to_string(),
        basis: settings.basis,
        mass: BodyMass::of(model),
        nodes: mesh
            .nodes
            .iter()
            .zip(&assembled.nodal_masses)
            .map(|(n, lumped)| BodyNode { label: n.label, position: n.position, mass: lumped.mass, rotary_inertia: lumped.rotary_inertia })
            .collect(),
        elements: mesh
            .elements
            .iter()
            .map(|e| BodyElement {
                label: e.label,
                kind: e.kind.name().to_string(),
                nodes: e.nodes.clone(),
            })
            .collect(),
        modes,
        shapes,
        modal_stiffness: to_nalgebra(modal_stiffness),
        modal_mass: to_nalgebra(modal_mass),
        invariants,
        reduced_frequencies_hz,
        fe_frequencies_hz: fe_modes.frequencies_hz.clone(),
        rigid_modes: fe_modes.rigid_modes,
        mass_properties: BodyMassProperties {
            mass: properties.mass,
            center_of_mass: properties.center_of_mass,
            inertia: properties.inertia,
        },
        geometric_stiffness: None,
        stresses: None,
    })
}
