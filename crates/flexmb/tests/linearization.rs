//! The linearized equations of motion against finite differences of the forward dynamics: moving the
//! velocities or the positions of a state by a small `δ` along one direction changes the accelerations
//! and multipliers by `δv̇`, `δλ` that satisfy `M δv̇ + C δv + K δq + Bᵀ δλ = 0` to second order in `δ`.

mod support;

use faer::Mat;
use flexmb::analysis::{
    assemble, displaced_positions, linearize, velocity_analysis, AccelerationSolver, Accelerations, Linearization, State,
};
use flexmb::math::Vec3;
use flexmb::model::{Model, OutputKind};
use flexmb::Data;
use support::{lumped_flexible_pendulum, slider_crank_linkage};

/// A consistent moving state of `model` (assembled, velocity-analysed), with its accelerations.
fn moving_state(model: &Model) -> (State, Accelerations) {
    let mut data = Data::new(model);
    let mut state = State::initial(model);
    assemble(model, &mut data, &mut state, Default::default()).unwrap();
    velocity_analysis(model, &mut data, &mut state).unwrap();
    let acc = AccelerationSolver::new(model).solve(model, &mut data, 0.0, &state.q, &state.v, &state.active).unwrap().clone();
    (state, acc)
}

/// `|M δv̇ + (C or K) δ e_k + Bᵀ δλ|` (largest row) for the forward dynamics moved along direction `k`,
/// and the largest of its three terms.
fn residual(lin: &Linearization, column: &Mat<f64>, k: usize, delta: f64, (dvdot, dlambda): (&[f64], &[f64])) -> (f64, f64) {
    let (nv, nc) = (dvdot.len(), dlambda.len());
    let (mut worst, mut scale) = (0.0_f64, 0.0_f64);
    for r in 0..nv {
        let inertia: f64 = (0..nv).map(|c| lin.mass[(r, c)] * dvdot[c]).sum();
        let reaction: f64 = (0..nc).map(|i| lin.constraint_jacobian[(i, r)] * dlambda[i]).sum();
        let direct = column[(r, k)] * delta;
        worst = worst.max((inertia + direct + reaction).abs());
        scale = scale.max(inertia.abs()).max(direct.abs()).max(reaction.abs());
    }
    (worst, scale)
}

/// Every velocity and every position direction of `model` at a moving state: the largest residual of the
/// linearized dynamic equations over the directions, relative to the largest term over them (directions
/// that barely change the forces, such as the spin of a slender rod about its axis, are measured on
/// the scale of the others: their own terms are at the round-off of the accelerations' differences).
fn check(name: &str, model: &Model) {
    let (state, acc) = moving_state(model);
    let (nv, nc) = (model.layout().nv, model.layout().nc);
    let mut data = Data::new(model);
    let lin = linearize(model, &mut data, &state, &acc).unwrap();
    assert_eq!((lin.mass.nrows(), lin.stiffness.ncols(), lin.constraint_jacobian.nrows()), (nv, nv, nc));
    let mut solver = AccelerationSolver::new(model);
    let delta = 1e-6;
    let (mut worst_v, mut worst_q, mut scale_v, mut scale_q) = (0.0_f64, 0.0_f64, 0.0_f64, 0.0_f64);
    for k in 0..nv {
        let mut v = state.v.clone();
        v[k] += delta;
        let moved = solver.solve(model, &mut data, 0.0, &state.q, &v, &state.active).unwrap();
        let dvdot: Vec<f64> = moved.vdot.iter().zip(&acc.vdot).map(|(a, b)| a - b).collect();
        let dlambda: Vec<f64> = moved.lambda.iter().zip(&acc.lambda).map(|(a, b)| a - b).collect();
        let (worst, scale) = residual(&lin, &lin.damping, k, delta, (&dvdot, &dlambda));
        (worst_v, scale_v) = (worst_v.max(worst), scale_v.max(scale));

        let mut d = vec![0.0; nv];
        d[k] = delta;
        let q = displaced_positions(model, &state.q, &d).unwrap();
        let moved = solver.solve(model, &mut data, 0.0, &q, &state.v, &state.active).unwrap();
        let dvdot: Vec<f64> = moved.vdot.iter().zip(&acc.vdot).map(|(a, b)| a - b).collect();
        let dlambda: Vec<f64> = moved.lambda.iter().zip(&acc.lambda).map(|(a, b)| a - b).collect();
        let (worst, scale) = residual(&lin, &lin.stiffness, k, delta, (&dvdot, &dlambda));
        (worst_q, scale_q) = (worst_q.max(worst), scale_q.max(scale));
    }
    let (worst_v, worst_q) = (worst_v / scale_v, worst_q / scale_q);
    eprintln!("{name}: largest relative residual {worst_v:.1e} along velocities, {worst_q:.1e} along positions");
    // Second order in δ = 1e-6 and the finite differences' own error (steps of 1.5e-8): about 1e-6
    // relative; a wrong sign or a missing term is of order one.
    assert!(worst_v < 1e-4 && worst_q < 1e-4, "{name}: {worst_v:.1e}, {worst_q:.1e}");
}

/// The slider-crank, spinning under gravity: a closed loop whose multipliers change with the state.
#[test]
fn the_linearized_slider_crank_matches_finite_differences_of_its_forward_dynamics() {
    let mut b = flexmb::ModelBuilder::new("slider-crank").gravity(Vec3::new(0.0, -9.81, 0.0));
    slider_crank_linkage(&mut b, 0.1, 0.3, Some(Vec3::new(0.0, 0.0, 12.0)));
    check("slider-crank", &b.build().unwrap());
}

/// The flexible pendulum, its modes excited: modal stiffness and damping, gravity, a revolute joint.
#[test]
fn the_linearized_flexible_pendulum_matches_finite_differences_of_its_forward_dynamics() {
    let (mut b, _, tip) = lumped_flexible_pendulum([400.0, 3000.0, 9000.0], [0.3, -0.2, 0.1]);
    b.add_output("tip", OutputKind::MarkerPosition(tip)).unwrap();
    check("flexible pendulum", &b.build().unwrap());
}

/// A free flexible body's modal block: the stiffness is the modal stiffness where nothing else acts on
/// the modal coordinates (the body at rest, no gravity, no joint).
#[test]
fn the_modal_stiffness_of_a_flexible_pendulum_is_in_its_linearization() {
    let (b, beam, _) = lumped_flexible_pendulum([400.0, 3000.0, 9000.0], [0.0; 3]);
    let model = b.gravity(Vec3::zeros()).build().unwrap();
    let (state, acc) = moving_state(&model);
    let mut data = Data::new(&model);
    let lin = linearize(&model, &mut data, &state, &acc).unwrap();
    let vo = model.layout().v_range(beam).unwrap().start + 6;
    for (i, k) in [400.0, 3000.0, 9000.0].into_iter().enumerate() {
        let found = lin.stiffness[(vo + i, vo + i)];
        assert!((found - k).abs() < 1e-5 * k, "mode {i}: {found} against {k}");
    }
}

/// A running simulation linearizes at its last step: the same matrices as `linearize` at that state.
#[test]
fn a_simulation_linearizes_at_its_current_state() {
    use std::sync::Arc;
    let (mut b, _, tip) = lumped_flexible_pendulum([400.0, 3000.0, 9000.0], [0.3, -0.2, 0.1]);
    b.add_output("tip", OutputKind::MarkerPosition(tip)).unwrap();
    let model = Arc::new(b.build().unwrap());
    let settings = support::settings(0.2, 0.05, 1e-7);
    let mut simulation = flexmb::analysis::Simulation::new(model.clone(), settings).unwrap();
    simulation.advance_to(0.1, &mut |_: &flexmb::analysis::OutputFrame| {}).unwrap();
    let from_simulation = simulation.linearize().unwrap();
    let (q, v) = (simulation.positions().to_vec(), simulation.velocities().to_vec());
    let mut data = Data::new(&model);
    let active = vec![true; model.layout().nc];
    let acc = AccelerationSolver::new(&model).solve(&model, &mut data, simulation.time(), &q, &v, &active).unwrap().clone();
    let state = State { t: simulation.time(), q, v, active };
    let direct = linearize(&model, &mut data, &state, &acc).unwrap();
    assert!(from_simulation.stiffness == direct.stiffness && from_simulation.damping == direct.damping);
    assert!(from_simulation.mass == direct.mass && from_simulation.constraint_jacobian == direct.constraint_jacobian);
}
