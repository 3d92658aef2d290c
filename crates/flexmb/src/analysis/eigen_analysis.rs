//! Eigen-analysis of the linearized constrained mechanism (formulation.md §10): the modes of
//! `M_z δz̈ + C_z δż + K_z δz = 0` from the first-order form
//!
//! ```text
//! ẏ = [ 0          I         ] y,     y = [δz; δż]
//!     [ −M_z⁻¹K_z  −M_z⁻¹C_z ]
//! ```
//!
//! solved by faer's dense (complex) eigen-decomposition. An eigenvalue `s = σ + iω_d` gives the
//! undamped natural frequency `|s|/2π` (the reported *frequency*), the damped frequency `ω_d/2π` and the
//! damping ratio `ζ = −σ/|s|`. Each conjugate pair is kept once (`ω_d ≥ 0`); real eigenvalues (an
//! overdamped motion) are kept each; eigenvalues below 10⁻⁶ of the largest (and below 10⁻⁶ s⁻¹) are
//! rigid-body modes, reported once per pair. The shape is the velocity-space displacement
//! `δx = N δz` (translations, rotation vector in body axes, modal coordinates), scaled so that its
//! largest component is 1 (real).
//!
//! **Whirl.** When a body spins (the body of the largest spin angular momentum `|J̄ ω̄₀|`, spin axis
//! `n = A ω̄₀ / |ω̄₀|`), each oscillating mode's orbit is labelled by the sign of its angular momentum
//! about `n`: with the complex displacement `u` of that body's centre of mass and its rotation `θ`
//! about global axes, the orbit `r(t) = Re(r̂ e^{iω_d t})` has `r × ṙ = ω_d Im r̂ × Re r̂`, and
//! `h = n · (m Im û × Re û + I_t Im θ̂ × Re θ̂)` (`I_t` the transverse inertia about the centre of mass)
//! is positive for a **forward** whirl (the orbit turns with the spin), negative for a **backward**
//! one; an orbit with `|h|` below 10⁻⁶ of `m |û|² + I_t |θ̂|²` is a straight line (no whirl).

use faer::Mat;

use super::linearization::ReducedLinearization;
use super::State;
use crate::math::{rotation_matrix, Mat3, Vec3};
use crate::model::Model;

/// The sense of a mode's orbit about the spin axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Whirl {
    /// The orbit turns in the sense of the spin.
    Forward,
    /// The orbit turns against the spin.
    Backward,
    /// No body spins, the mode does not oscillate, or its orbit is a straight line.
    None,
}

impl Whirl {
    /// `forward`, `backward` or `none`.
    pub fn label(self) -> &'static str {
        match self {
            Whirl::Forward => "forward",
            Whirl::Backward => "backward",
            Whirl::None => "none",
        }
    }
}

/// One mode of the linearized mechanism.
#[derive(Clone, Debug)]
pub struct Mode {
    /// Eigenvalue `s = σ + iω_d` (1/s), real and imaginary parts.
    pub eigenvalue: (f64, f64),
    /// Undamped natural frequency `|s|/2π` (Hz).
    pub frequency: f64,
    /// Damped frequency `ω_d/2π` (Hz).
    pub damped_frequency: f64,
    /// Damping ratio `−σ/|s|` (0 for a rigid-body mode).
    pub damping_ratio: f64,
    /// A zero eigenvalue: a motion without restoring force.
    pub rigid_body: bool,
    /// The orbit's sense about the spin axis.
    pub whirl: Whirl,
    /// Real part of the shape `δx = N δz` in velocity coordinates (`nv`).
    pub shape_re: Vec<f64>,
    /// Imaginary part of the shape.
    pub shape_im: Vec<f64>,
    /// The shape in the independent coordinates `δz`, real part.
    pub independent_re: Vec<f64>,
    /// The shape in the independent coordinates, imaginary part.
    pub independent_im: Vec<f64>,
}

/// The spinning body that labels whirl: its index and global spin axis.
#[derive(Clone, Copy, Debug)]
pub struct Spin {
    /// Index of the body in the model.
    pub body: usize,
    /// Unit spin axis, global.
    pub axis: [f64; 3],
    /// Angular speed (rad/s).
    pub speed: f64,
}

/// The modes of a linearized mechanism, by increasing frequency.
#[derive(Clone, Debug)]
pub struct EigenAnalysis {
    /// The modes, rigid-body modes first, then by increasing undamped frequency.
    pub modes: Vec<Mode>,
    /// The body whose spin labels whirl, if any body spins.
    pub spin: Option<Spin>,
}

/// Eigen-analysis failed: the mass matrix is singular or the eigensolver did not converge.
#[derive(Clone, Debug, PartialEq)]
pub struct EigenAnalysisError(pub String);

impl std::fmt::Display for EigenAnalysisError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for EigenAnalysisError {}

/// The first-order state matrix `[0 I; −M_z⁻¹K_z −M_z⁻¹C_z]` of `reduced`.
pub fn state_matrix(reduced: &ReducedLinearization) -> Mat<f64> {
    use faer::linalg::solvers::Solve;
    let n = reduced.degrees_of_freedom();
    let lu = reduced.mass.partial_piv_lu();
    let mk = lu.solve(&reduced.stiffness);
    let mc = lu.solve(&reduced.damping);
    Mat::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
        (true, true) => 0.0,
        (true, false) => f64::from(u8::from(j - n == i)),
        (false, true) => -mk[(i - n, j)],
        (false, false) => -mc[(i - n, j - n)],
    })
}

/// The modes of `reduced`, linearized at `state` of `model`.
pub fn eigen_analysis(model: &Model, state: &State, reduced: &ReducedLinearization) -> Result<EigenAnalysis, EigenAnalysisError> {
    let n = reduced.degrees_of_freedom();
    let spin = spinning_body(model, state);
    if n == 0 {
        return Ok(EigenAnalysis { modes: Vec::new(), spin });
    }
    let a = state_matrix(reduced);
    if (0..2 * n).any(|i| (0..2 * n).any(|j| !a[(i, j)].is_finite())) {
        return Err(EigenAnalysisError("the reduced mass matrix is singular (a coordinate without inertia)".into()));
    }
    let evd = a.eigen().map_err(|e| EigenAnalysisError(format!("the eigensolver did not converge: {e:?}")))?;
    let (s, u) = (evd.S(), evd.U());
    let values: Vec<(f64, f64)> = (0..2 * n).map(|k| (s[k].re, s[k].im)).collect();
    let largest = values.iter().map(|&(re, im)| re.hypot(im)).fold(0.0, f64::max);
    let zero = 1e-6 * largest.max(1.0);
    let mut modes = Vec::new();
    let mut zeros_seen = 0;
    for (k, &(re, im)) in values.iter().enumerate() {
        let magnitude = re.hypot(im);
        let rigid_body = magnitude < zero;
        if rigid_body {
            zeros_seen += 1;
            if zeros_seen % 2 == 0 {
                continue;
            }
        } else if im < 0.0 {
            continue;
        }
        let z: Vec<(f64, f64)> = (0..n).map(|i| (u[(i, k)].re, u[(i, k)].im)).collect();
        modes.push(mode(model, state, reduced, spin.as_ref(), (re, im), rigid_body, &z));
    }
    modes.sort_by(|a, b| (!a.rigid_body, a.frequency).partial_cmp(&(!b.rigid_body, b.frequency)).unwrap_or(std::cmp::Ordering::Equal));
    Ok(EigenAnalysis { modes, spin })
}

fn mode(
    model: &Model,
    state: &State,
    reduced: &ReducedLinearization,
    spin: Option<&Spin>,
    (re, im): (f64, f64),
    rigid_body: bool,
    z: &[(f64, f64)],
) -> Mode {
    let basis = &reduced.independent.basis;
    let nv = basis.nrows();
    let mut x: Vec<(f64, f64)> = (0..nv)
        .map(|r| z.iter().enumerate().fold((0.0, 0.0), |(a, b), (k, &(zr, zi))| (a + basis[(r, k)] * zr, b + basis[(r, k)] * zi)))
        .collect();
    let scale = normalize(&mut x);
    let zs: Vec<(f64, f64)> = z.iter().map(|&(a, b)| (a * scale.0 - b * scale.1, a * scale.1 + b * scale.0)).collect();
    let magnitude = re.hypot(im);
    let (frequency, damping_ratio) = if rigid_body { (0.0, 0.0) } else { (magnitude / std::f64::consts::TAU, -re / magnitude) };
    let whirl = match spin {
        Some(spin) if !rigid_body && im > 0.0 => whirl_of(model, state, spin, &x),
        _ => Whirl::None,
    };
    Mode {
        eigenvalue: (re, im),
        frequency,
        damped_frequency: if rigid_body { 0.0 } else { im / std::f64::consts::TAU },
        damping_ratio,
        rigid_body,
        whirl,
        shape_re: x.iter().map(|c| c.0).collect(),
        shape_im: x.iter().map(|c| c.1).collect(),
        independent_re: zs.iter().map(|c| c.0).collect(),
        independent_im: zs.iter().map(|c| c.1).collect(),
    }
}

/// Scales `x` so that its largest component is 1; returns the complex factor.
fn normalize(x: &mut [(f64, f64)]) -> (f64, f64) {
    let big = x.iter().copied().fold((0.0_f64, 0.0_f64), |best, c| if c.0.hypot(c.1) > best.0.hypot(best.1) { c } else { best });
    let norm2 = big.0 * big.0 + big.1 * big.1;
    let factor = if norm2 > 0.0 { (big.0 / norm2, -big.1 / norm2) } else { (1.0, 0.0) };
    for c in x.iter_mut() {
        *c = (c.0 * factor.0 - c.1 * factor.1, c.0 * factor.1 + c.1 * factor.0);
    }
    factor
}

/// The body of the largest spin angular momentum `|J̄ ω̄₀|`, if any body turns.
fn spinning_body(model: &Model, state: &State) -> Option<Spin> {
    let l = &model.layout;
    let mut best: Option<(f64, Spin)> = None;
    for (b, body) in model.bodies.iter().enumerate() {
        let vo = l.v_offset[b];
        let w = Vec3::new(state.v[vo + 3], state.v[vo + 4], state.v[vo + 5]);
        let momentum = (body.inertia * w).norm();
        if w.norm() > 0.0 && best.as_ref().is_none_or(|(m, _)| momentum > *m) {
            let axis = attitude(model, state, b) * w / w.norm();
            best = Some((momentum, Spin { body: b, axis: [axis[0], axis[1], axis[2]], speed: w.norm() }));
        }
    }
    best.map(|(_, spin)| spin)
}

fn attitude(model: &Model, state: &State, b: usize) -> Mat3 {
    let qo = model.layout.q_offset[b];
    let q = &state.q;
    rotation_matrix(&nalgebra::Vector4::new(q[qo + 3], q[qo + 4], q[qo + 5], q[qo + 6]))
}

/// The whirl rule of the module docs, for the spinning body of `spin` in the shape `x`.
fn whirl_of(model: &Model, state: &State, spin: &Spin, x: &[(f64, f64)]) -> Whirl {
    let b = spin.body;
    let body = &model.bodies[b];
    let a = attitude(model, state, b);
    let vo = model.layout.v_offset[b];
    let part = |im: bool| {
        let pick = |c: &(f64, f64)| if im { c.1 } else { c.0 };
        let r = Vec3::new(pick(&x[vo]), pick(&x[vo + 1]), pick(&x[vo + 2]));
        let theta = a * Vec3::new(pick(&x[vo + 3]), pick(&x[vo + 4]), pick(&x[vo + 5]));
        (r + theta.cross(&(a * body.center_of_mass)), theta)
    };
    let ((u_re, th_re), (u_im, th_im)) = (part(false), part(true));
    let n = Vec3::new(spin.axis[0], spin.axis[1], spin.axis[2]);
    let inertia = a * body.inertia * a.transpose();
    let transverse = 0.5 * (inertia.trace() - n.dot(&(inertia * n)));
    let h = body.mass * n.dot(&u_im.cross(&u_re)) + transverse * n.dot(&th_im.cross(&th_re));
    let size = body.mass * (u_re.norm_squared() + u_im.norm_squared()) + transverse * (th_re.norm_squared() + th_im.norm_squared());
    if h.abs() <= 1e-6 * size {
        Whirl::None
    } else if h > 0.0 {
        Whirl::Forward
    } else {
        Whirl::Backward
    }
}
