//! Every mode set drops the directions that move no mass (reduction/massless_directions.rs), on the
//! peer's steel beam (1 m, 20 mm square, 40 Euler–Bernoulli elements, consistent mass) without rotary
//! inertia, clamped at x = 0: its twist moves no mass.
//!
//! - **A massless combination.** Two static loads at the tip, torques about the oblique axes
//!   `(1, 0, ±1)/√2`: each static mode twists the beam (the torque's x part) and bends it (its z part)
//!   and carries mass; their sum is the pure twist of `√2 t_x` and carries none. `4N2S` keeps five
//!   modes, and its reduced frequencies are those of `4N1S` with the bending torque `t_z` alone (the
//!   kept static mode is the bending one, the twist condensed on it), to 1e-8 relative, raw and
//!   orthonormal.
//! - **Craig–Bampton and free interface.** The clamp is the interface (six dofs): the constraint mode
//!   and the attachment mode of the twist at the clamp move no mass and are dropped with a warning
//!   instead of failing the reduction (before, `8N6C` failed on the free model's held massless spin and
//!   `8F6A` on the dependent direction); the reduced bodies' free-free bending frequencies are the
//!   beam's (Euler–Bernoulli's `(4.7300)² / (2π) √(E I / (ρ A L⁴))` and `7.8532²`) to 3e-3: measured
//!   3.9e-4 and 1.6e-3 with `8N6C` (clamped-interface modes for a free-free body), 1.7e-5 and 2.2e-6
//!   with `8F6A`.
//!
//! About 1 s in release.

use flexmb_fem::mesh::{BeamSection, FeModel, Material, Mesh};
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};
use flexmb_fem::{DofSet, MassModel, StaticLoad, StaticLoadKind, Support};
use nalgebra::Vector3;

const E: f64 = 2.1e11;
const RHO: f64 = 7850.0;
const H: f64 = 0.02;

/// The beam clamped at x = 0, with a static load of a unit torque about each of `torques` at the tip.
fn beam(torques: &[Vector3<f64>]) -> FeModel {
    let i = H.powi(4) / 12.0;
    let mut mesh = Mesh {
        materials: vec![Material { name: "steel".into(), youngs_modulus: E, poisson_ratio: 0.3, density: RHO }],
        beam_sections: vec![BeamSection {
            name: "square".into(),
            material: 0,
            area: H * H,
            iy: i,
            iz: i,
            torsion_constant: 0.1406 * H.powi(4),
            orientation: Vector3::new(0.0, 1.0, 0.0),
            shear_coefficient: None,
            outline: Default::default(),
        }],
        ..Default::default()
    };
    let nodes = mesh.add_beam_line(Vector3::zeros(), Vector3::x(), 40, 0).unwrap();
    let mut model = FeModel { mesh, supports: vec![Support { node: nodes[0], dofs: DofSet::ALL }], ..Default::default() };
    model.options.mass = Some(MassModel::Consistent);
    model.options.rotary_inertia = false;
    let tip = *nodes.last().unwrap();
    for (k, axis) in torques.iter().enumerate() {
        model.static_loads.push(StaticLoad { name: format!("t{}", k + 1), node: tip, kind: StaticLoadKind::Torque(axis.normalize()) });
    }
    model
}

fn settings(set: &str, basis: Basis) -> ReductionSettings {
    ReductionSettings { mode_set: set.parse().unwrap(), basis, eigen: Default::default() }
}

fn relative(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

#[test]
fn two_static_modes_massless_only_in_combination_lose_their_massless_direction() {
    let oblique = beam(&[Vector3::new(1.0, 0.0, 1.0), Vector3::new(1.0, 0.0, -1.0)]);
    let bending = beam(&[Vector3::z()]);
    for basis in [Basis::Raw, Basis::Orthonormal] {
        let reduced = reduce(&oblique, "beam", &settings("4N2S", basis)).unwrap_or_else(|e| panic!("{e}"));
        let reference = reduce(&bending, "beam", &settings("4N1S", basis)).unwrap();
        let body = &reduced.body;
        println!("{basis:?}: {:?}", reduced.warnings);
        assert_eq!(body.mode_count(), 5, "{basis:?}");
        assert!(reduced.warnings.iter().any(|w| w.contains("the combination") && w.contains("moves no mass")), "{:?}", reduced.warnings);
        if basis == Basis::Raw {
            // N1..N4 and the one static mode kept (the pivot is the other).
            assert_eq!(&body.modes[..4].iter().map(|m| m.label.as_str()).collect::<Vec<_>>(), &["N1", "N2", "N3", "N4"]);
        }
        assert!(nalgebra::Cholesky::new(body.modal_mass.clone()).is_some(), "{basis:?}: the kept modal mass is positive definite");
        for (f, r) in body.reduced_frequencies_hz.iter().zip(&reference.body.reduced_frequencies_hz) {
            println!("{basis:?}: {f:.9} Hz against {r:.9} Hz ({:.1e})", relative(*f, *r));
            assert!(relative(*f, *r) < 1e-8, "{basis:?}: {f} Hz against {r} Hz");
        }
    }
}

/// Euler–Bernoulli's free-free bending frequencies of the beam: `β² / (2π) √(E I / (ρ A L⁴))`.
fn free_free_hz(beta: f64) -> f64 {
    beta * beta / (2.0 * std::f64::consts::PI) * (E * H.powi(4) / 12.0 / (RHO * H * H)).sqrt()
}

#[test]
fn interface_sets_drop_the_twist_that_moves_no_mass() {
    let model = beam(&[]);
    let expected = [free_free_hz(4.7300), free_free_hz(7.8532)];
    for set in ["8N6C", "8F6A"] {
        let reduced = reduce(&model, "beam", &settings(set, Basis::Orthonormal)).unwrap_or_else(|e| panic!("{set}: {e}"));
        println!("{set}: {:?}", reduced.warnings);
        assert!(reduced.warnings.iter().any(|w| w.contains("moves no mass")), "{set}: {:?}", reduced.warnings);
        let body = &reduced.body;
        assert!(nalgebra::Cholesky::new(body.modal_mass.clone()).is_some(), "{set}");
        // The bending frequencies come in pairs (y and z); the axial ones lie far above.
        let f = &body.reduced_frequencies_hz;
        println!("{set}: reduced {:?} Hz; Euler–Bernoulli {expected:?} Hz", &f[..4.min(f.len())]);
        for (k, e) in expected.iter().enumerate() {
            for j in [2 * k, 2 * k + 1] {
                println!("{set}: mode {} {:.4} Hz, {:.1e} from Euler–Bernoulli's {e:.4} Hz", j + 1, f[j], relative(f[j], *e));
                assert!(relative(f[j], *e) < 3e-3, "{set}: mode {} at {} Hz against {e} Hz", j + 1, f[j]);
            }
        }
    }
}
