//! Vibration modes of beams against Euler–Bernoulli theory: the cantilever's first five bending
//! frequencies and their convergence with the mesh, the free–free beam's six rigid modes and its
//! elastic frequencies, repeated frequencies of a square section, and the Lanczos path against the
//! dense one (and in its place on a model smaller than its Krylov space).

mod support;

use flexmb_fem::modes::{vibration_modes, EigenSettings, EigenSolver};
use std::f64::consts::PI;

use flexmb_fem::{Dof, DofSet, MassModel, Support};
use support::*;

/// Roots of `cos βL cosh βL = −1` (the 1.8751, 4.6941, 7.8548, 10.9955, 14.1372 to more
/// digits: the consistent mass is accurate to 1e-6, beyond five digits).
const CANTILEVER_BETA_L: [f64; 5] = [1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349, 14.1371683910];
/// Roots of `cos βL cosh βL = 1` (4.7300, 7.8532, 10.9956, 14.1372).
const FREE_FREE_BETA_L: [f64; 4] = [4.7300407449, 7.8532046241, 10.9956078380, 14.1371654913];

fn dense() -> EigenSettings {
    EigenSettings { solver: EigenSolver::Dense, ..Default::default() }
}

/// Relative errors of the five bending frequencies of a cantilever with `n` elements. A square
/// section bends alike in both planes, so the modes come in pairs of equal frequency.
fn cantilever_errors(n: usize, settings: &EigenSettings) -> Vec<f64> {
    cantilever_errors_with(n, settings, MassModel::Lumped)
}

/// [`cantilever_errors`] with the lumped or the consistent mass.
fn cantilever_errors_with(n: usize, settings: &EigenSettings, mass: MassModel) -> Vec<f64> {
    let section = square_section(0.01);
    let mut model = cantilever(1.0, n, section.clone());
    model.options.mass = Some(mass);
    let modes = vibration_modes(&model, 10, settings).unwrap();
    assert_eq!(modes.rigid_modes, 0);
    (0..5)
        .map(|k| {
            let (f1, f2) = (modes.frequencies_hz[2 * k], modes.frequencies_hz[2 * k + 1]);
            assert!(rel(f1, f2) < 1e-9, "pair {k}: {f1} and {f2} should be equal");
            rel(f1, beam_frequency(CANTILEVER_BETA_L[k], 1.0, &section))
        })
        .collect()
}

/// The seed's lumped mass puts half an element's mass at the free tip: the trapezoidal rule on the
/// kinetic energy, whose end error `h²/12 · d(w²)/dx` does not vanish at a free end. The cantilever's
/// frequencies are therefore second-order accurate (the simply supported beam below, where `w = 0`
/// at both ends, is fourth-order). Measured errors at 20 elements: 0.11, 0.40, 0.65, 0.91, 1.18 %;
/// at 32 elements all five are within 0.5 %.
#[test]
fn cantilever_bending_frequencies_against_euler_bernoulli() {
    let errors = cantilever_errors(20, &dense());
    println!("cantilever, 20 elements, relative errors of modes 1-5: {errors:?}");
    let bounds_20 = [2e-3, 5e-3, 7e-3, 1e-2, 1.3e-2];
    for (k, (e, bound)) in errors.iter().zip(bounds_20).enumerate() {
        assert!(*e < bound, "20 elements, mode {}: error {e:.2e}", k + 1);
    }
    let errors = cantilever_errors(32, &dense());
    println!("cantilever, 32 elements, relative errors of modes 1-5: {errors:?}");
    for (k, e) in errors.iter().enumerate() {
        assert!(*e < 5e-3, "32 elements, mode {}: error {e:.2e}", k + 1);
    }
}

/// With the consistent mass (Hermite cubics) the free end's kinetic energy is integrated exactly:
/// all five frequencies are within 0.5 % at 20 elements (measured 5e-8, 2e-6, 1.6e-5, 6e-5, 1.7e-4)
/// and converge at fourth order, from above (Rayleigh–Ritz with a conforming field).
#[test]
fn consistent_mass_cantilever_within_half_a_percent_at_twenty_elements() {
    let coarse = cantilever_errors_with(10, &dense(), MassModel::Consistent);
    let fine = cantilever_errors_with(20, &dense(), MassModel::Consistent);
    println!("consistent mass, 20 elements, relative errors of modes 1-5: {fine:?}");
    for k in 0..5 {
        assert!(fine[k] < 5e-3, "20 elements, mode {}: error {:.2e}", k + 1, fine[k]);
        let order = (coarse[k] / fine[k]).log2();
        println!("consistent mode {}: errors {:.2e} {:.2e}, observed order {order:.2}", k + 1, coarse[k], fine[k]);
        assert!(order > 3.5, "mode {}: order {order:.2}", k + 1);
    }
    // From above: every frequency exceeds Euler–Bernoulli's.
    let section = square_section(0.01);
    let mut model = cantilever(1.0, 20, section.clone());
    model.options.mass = Some(MassModel::Consistent);
    let modes = vibration_modes(&model, 10, &dense()).unwrap();
    for k in 0..5 {
        assert!(modes.frequencies_hz[2 * k] > beam_frequency(CANTILEVER_BETA_L[k], 1.0, &section) * (1.0 - 1e-5));
    }
}

/// Pinned at both ends, the lumped-mass beam's frequencies converge at fourth order: the second-order
/// error of the cantilever comes from its free end only.
#[test]
fn simply_supported_beam_converges_at_fourth_order() {
    let section = square_section(0.01);
    let errors = |n: usize| -> Vec<f64> {
        let mut model = beam(1.0, n, section.clone());
        let last = model.mesh.nodes.len() - 1;
        model.supports.push(Support { node: 0, dofs: DofSet::TRANSLATIONS.with(Dof::Rx) });
        model.supports.push(Support { node: last, dofs: DofSet::EMPTY.with(Dof::Uy).with(Dof::Uz) });
        let modes = vibration_modes(&model, 6, &dense()).unwrap();
        (0..3).map(|k| rel(modes.frequencies_hz[2 * k], beam_frequency(PI * (k + 1) as f64, 1.0, &section))).collect()
    };
    let (coarse, fine) = (errors(10), errors(20));
    for k in 0..3 {
        let order = (coarse[k] / fine[k]).log2();
        println!("simply supported mode {}: errors {:.2e} {:.2e}, observed order {order:.2}", k + 1, coarse[k], fine[k]);
        assert!(order > 3.8, "mode {}: order {order:.2}", k + 1);
        assert!(fine[k] < 5e-5);
    }
}

#[test]
fn cantilever_frequencies_converge_at_second_order() {
    let coarse = cantilever_errors(10, &dense());
    let fine = cantilever_errors(20, &dense());
    let finer = cantilever_errors(40, &dense());
    for k in 0..5 {
        let order = (coarse[k] / fine[k]).log2();
        let order_fine = (fine[k] / finer[k]).log2();
        println!("mode {}: errors {:.2e} {:.2e} {:.2e}, observed orders {order:.2} {order_fine:.2}", k + 1, coarse[k], fine[k], finer[k]);
        assert!(fine[k] < coarse[k] && finer[k] < fine[k]);
        assert!(order_fine > 1.8, "mode {}: observed order {order_fine:.2}", k + 1);
    }
}

#[test]
fn free_free_beam_has_six_rigid_modes_and_beam_theory_frequencies() {
    let section = square_section(0.01);
    // Free ends: second-order like the cantilever; 60 elements put mode 4 within 0.3 %.
    let model = beam(1.0, 60, section.clone());
    let modes = vibration_modes(&model, 8, &dense()).unwrap();
    assert_eq!(modes.rigid_modes, 6);
    for (k, beta_l) in FREE_FREE_BETA_L.iter().enumerate() {
        let reference = beam_frequency(*beta_l, 1.0, &section);
        for f in [modes.frequencies_hz[2 * k], modes.frequencies_hz[2 * k + 1]] {
            assert!(rel(f, reference) < 5e-3, "free-free mode {}: {f} Hz vs {reference} Hz", k + 1);
        }
    }
    assert!(modes.max_orthogonality_error < 1e-9);
    // With rotary inertia the spin about the beam's axis has mass: six rigid modes all the same.
    let mut model = beam(1.0, 40, section);
    model.options.rotary_inertia = true;
    assert_eq!(vibration_modes(&model, 8, &dense()).unwrap().rigid_modes, 6);
}

/// The consistent mass's free–free beam: six rigid modes, elastic frequencies within 3e-4 at 20
/// elements (the lumped mass needs 60 for 5e-3); with rotary inertia (Rayleigh's beam, 2e-4 lower here)
/// the Lanczos path, whose operator acts on the mass points' motions (more rows than free dofs),
/// agrees with the dense one.
#[test]
fn consistent_mass_free_free_beam_and_lanczos() {
    let section = square_section(0.01);
    let mut model = beam(1.0, 20, section.clone());
    model.options.mass = Some(MassModel::Consistent);
    let modes = vibration_modes(&model, 8, &dense()).unwrap();
    assert_eq!(modes.rigid_modes, 6);
    for (k, beta_l) in FREE_FREE_BETA_L.iter().enumerate() {
        let reference = beam_frequency(*beta_l, 1.0, &section);
        for f in [modes.frequencies_hz[2 * k], modes.frequencies_hz[2 * k + 1]] {
            assert!(rel(f, reference) < 3e-4, "free-free mode {}: {f} Hz vs {reference} Hz", k + 1);
        }
    }
    model.options.rotary_inertia = true;
    let dense_modes = vibration_modes(&model, 8, &dense()).unwrap();
    assert_eq!(dense_modes.rigid_modes, 6);
    let lanczos = EigenSettings { solver: EigenSolver::Lanczos, ..Default::default() };
    let sparse_modes = vibration_modes(&model, 8, &lanczos).unwrap();
    for (k, (a, b)) in dense_modes.frequencies_hz.iter().zip(&sparse_modes.frequencies_hz).enumerate() {
        assert!(rel(*b, *a) < 1e-9, "{a} vs {b}");
        assert!(*a < modes.frequencies_hz[k] && rel(*a, modes.frequencies_hz[k]) < 3e-3, "rotary inertia lowers mode {}", k + 1);
    }
    assert!(sparse_modes.max_residual < 1e-8 && sparse_modes.max_orthogonality_error < 1e-9);
}

#[test]
fn lanczos_agrees_with_dense() {
    let model = cantilever(1.0, 60, square_section(0.01));
    let dense_modes = vibration_modes(&model, 12, &dense()).unwrap();
    let lanczos = EigenSettings { solver: EigenSolver::Lanczos, ..Default::default() };
    let sparse_modes = vibration_modes(&model, 12, &lanczos).unwrap();
    assert_eq!(sparse_modes.solver, EigenSolver::Lanczos);
    for (a, b) in dense_modes.frequencies_hz.iter().zip(&sparse_modes.frequencies_hz) {
        assert!(rel(*b, *a) < 1e-9, "{a} vs {b}");
    }
    assert!(sparse_modes.max_residual < 1e-8, "residual {}", sparse_modes.max_residual);
    assert!(sparse_modes.max_orthogonality_error < 1e-9);
}

/// A model no larger than the Lanczos method's Krylov space (64 vectors) is solved densely when
/// Lanczos is asked for: faer's iteration panicked on it (`flexmb modes --solver lanczos` on an 18-dof
/// cantilever, or 30 modes of a 20-element one, found by the fuzz test).
#[test]
fn lanczos_on_a_model_smaller_than_its_krylov_space_is_solved_densely() {
    let lanczos = EigenSettings { solver: EigenSolver::Lanczos, ..Default::default() };
    // The lumped mass without rotary inertia: the operator acts on the 3 translations of each free node.
    for (elements, count) in [(3, 4), (7, 6), (20, 30)] {
        let model = cantilever(1.0, elements, square_section(0.01));
        let dense_modes = vibration_modes(&model, count, &dense()).unwrap();
        let modes = vibration_modes(&model, count, &lanczos).unwrap();
        assert_eq!(modes.solver, EigenSolver::Dense, "{elements} elements, {count} modes");
        assert_eq!(modes.frequencies_hz, dense_modes.frequencies_hz);
    }
    let larger = vibration_modes(&cantilever(1.0, 30, square_section(0.01)), 4, &lanczos).unwrap();
    assert_eq!(larger.solver, EigenSolver::Lanczos, "90 translations: more than the 64 vectors of the Krylov space");
}
