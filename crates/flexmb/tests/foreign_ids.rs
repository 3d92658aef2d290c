//! A library that says what is wrong: ids, states, workspaces and solvers of one model handed to
//! another model's functions are `None` or an error that names what does not fit, never a panic.
//! The small model is a rigid pendulum (1 body, 3 markers, 1 joint of 5 rows); the large one a
//! flexible pendulum (1 body with 3 modes) and a slider-crank added to it, so that every size differs.

mod support;

use std::sync::Arc;

use flexmb::analysis::{
    assemble, displaced_positions, linearize, velocity_analysis, AccelerationError, AccelerationSolver, AssemblyError,
    OperatingPoint, OutputFrame, OutputSink, OutputTable, Simulation, SparseLinearization, State,
};
use flexmb::model::{BodyId, BodyRef, JointId, MarkerId, Model, SizeMismatch};
use flexmb::stage::{force_stages, forward, kinematic_stages};
use flexmb::Data;
use support::{consistent_start, lumped_flexible_pendulum, pendulum, settings, slider_crank_linkage};

fn small() -> Model {
    pendulum(1.0, 1.0, 1e-3, 0.3, 9.81).build().unwrap()
}

fn large() -> Model {
    let (mut b, _, _) = lumped_flexible_pendulum([50.0, 400.0, 2000.0], [0.0; 3]);
    slider_crank_linkage(&mut b, 0.1, 0.4, None);
    b.build().unwrap()
}

/// The error says which argument does not fit, its size and the model's.
fn names(error: &SizeMismatch, what: &str, found: usize, expected: usize) {
    assert_eq!((error.what, error.found, error.expected), (what, found, expected), "{error}");
    assert!(error.to_string().contains("made for another model"), "{error}");
}

#[test]
fn lookups_by_an_id_the_model_does_not_have_are_none() {
    let model = small();
    let beyond = model.bodies().len();
    assert!(model.body(BodyId(0)).is_some());
    assert!(model.body(BodyId(beyond)).is_none());
    assert!(model.modal_body(BodyId(beyond)).is_none());
    assert!(model.marker(MarkerId(model.markers().len())).is_none());
    assert!(model.marker_node(MarkerId(model.markers().len())).is_none());
    assert!(model.joint(JointId(model.joints().len())).is_none());
    assert_eq!(model.body_name(BodyRef::Ground), Some("ground"));
    assert!(model.body_name(BodyRef::Body(BodyId(beyond))).is_none());
    let layout = model.layout();
    assert_eq!(layout.modes(BodyId(0)), Some(0));
    assert!(layout.modes(BodyId(beyond)).is_none());
    assert!(layout.modal_q_range(BodyId(beyond)).is_none() && layout.modal_v_range(BodyId(beyond)).is_none());
    assert_eq!(layout.joint_rows(JointId(0)), Some(0..5));
    assert_eq!((layout.q_range(BodyId(0)), layout.v_range(BodyId(0))), (Some(0..7), Some(0..6)));
    assert!(layout.q_range(BodyId(beyond)).is_none() && layout.v_range(BodyId(beyond)).is_none());
    assert_eq!((layout.body_of_position(6), layout.body_of_velocity(5)), (Some(BodyId(0)), Some(BodyId(0))));
    assert!(layout.body_of_position(7).is_none() && layout.body_of_velocity(6).is_none());
    assert!(layout.joint_rows(JointId(1)).is_none());
    let text = model.describe_constraint_row(layout.nc);
    assert!(text.contains("does not have (it has 5)"), "{text}");
    let text = model.describe_velocity_row(layout.nv + 3);
    assert!(text.contains("does not have (it has 6)"), "{text}");
    let data = Data::new(&model);
    assert!(data.marker_position(MarkerId(0)).is_some() && data.marker_position(MarkerId(99)).is_none());
    assert!(data.marker_axes(MarkerId(99)).is_none());
}

#[test]
fn the_forward_stages_refuse_a_workspace_or_a_state_of_another_model() {
    let (model, other) = (small(), large());
    let (state, acc) = consistent_start(&model);
    let mut data = Data::new(&model);
    forward(&model, &mut data, 0.0, &state.q, &state.v, &acc.vdot).expect("its own sizes");
    let mut foreign = Data::new(&other);
    let error = forward(&model, &mut foreign, 0.0, &state.q, &state.v, &acc.vdot).unwrap_err();
    names(&error, "the workspace Data (bodies)", other.bodies().len(), model.bodies().len());
    let other_state = State::initial(&other);
    let error = kinematic_stages(&model, &mut data, 0.0, &other_state.q, &state.v).unwrap_err();
    names(&error, "positions q", other.layout().nq, 7);
    let error = kinematic_stages(&model, &mut data, 0.0, &state.q, &other_state.v).unwrap_err();
    names(&error, "velocities v", other.layout().nv, 6);
    let error = force_stages(&model, &mut data, 0.0, &[0.0; 2]).unwrap_err();
    names(&error, "accelerations v̇", 2, 6);
}

#[test]
fn the_analyses_refuse_a_state_a_workspace_or_a_solver_of_another_model() {
    let (model, other) = (small(), large());
    let (state, acc) = consistent_start(&model);
    let mut data = Data::new(&model);
    let mut other_state = State::initial(&other);
    let error = assemble(&model, &mut data, &mut other_state, Default::default()).unwrap_err();
    assert!(matches!(&error, AssemblyError::SizeMismatch(e) if e.what == "positions q"), "{error}");
    let error = velocity_analysis(&other, &mut data, &mut other_state).unwrap_err();
    assert!(matches!(&error, AssemblyError::SizeMismatch(e) if e.what.starts_with("the workspace Data")), "{error}");

    let mut foreign_solver = AccelerationSolver::new(&other);
    let error = foreign_solver.solve(&model, &mut data, 0.0, &state.q, &state.v, &state.active).unwrap_err();
    assert!(matches!(&error, AccelerationError::SizeMismatch(e) if e.what.starts_with("the acceleration solver")), "{error}");
    let error = AccelerationSolver::new(&model).solve(&model, &mut data, 0.0, &state.q, &state.v, &[true; 2]).unwrap_err();
    assert!(matches!(&error, AccelerationError::SizeMismatch(e) if e.found == 2 && e.expected == 5), "{error}");

    let error = linearize(&model, &mut data, &other_state, &acc).unwrap_err();
    names(&error, "positions q", other.layout().nq, 7);
    let mut foreign_evaluator = SparseLinearization::new(&other);
    let error = foreign_evaluator.evaluate(&model, &mut data, &state.active, &OperatingPoint::new(&state, &acc)).unwrap_err();
    assert!(error.what.starts_with("the linearization's workspace"), "{error}");
    let error = displaced_positions(&model, &state.q, &[0.0; 5]).unwrap_err();
    names(&error, "the increment d", 5, 6);
    // An integrator started from another model's state.
    use flexmb::integrate::{Adams, Bdf, GeneralizedAlpha, IntegrationError};
    let (other_start, other_acc) = consistent_start(&other);
    let model = Arc::new(model);
    let starts = [
        Bdf::new(model.clone(), &other_start, &other_acc, Default::default(), Default::default()).err(),
        Adams::new(model.clone(), &other_start, &other_acc, Default::default(), Default::default()).err(),
        GeneralizedAlpha::new(model.clone(), &other_start, &other_acc, Default::default(), Default::default()).err(),
    ];
    for error in starts {
        let error = error.expect("refused");
        assert!(matches!(&error, IntegrationError::InitialConditions { .. }), "{error}");
        let expected = format!("positions q has {} entries where model 'pendulum' needs 7", other.layout().nq);
        assert!(error.to_string().contains(&expected), "{error}");
    }
    // The same calls with the model's own arguments work.
    assert!(linearize(&model, &mut data, &state, &acc).is_ok());
    assert_eq!(displaced_positions(&model, &state.q, &[0.0; 6]).unwrap(), state.q);
}

#[test]
fn a_simulation_and_its_table_answer_none_or_an_error_for_what_they_do_not_have() {
    let model = Arc::new(small());
    let mut table = OutputTable::with_states(&model);
    let mut simulation = Simulation::new(model.clone(), settings(0.05, 0.01, 1e-8)).unwrap();
    simulation.run(&mut table, &|| None).unwrap();
    assert_eq!(simulation.modal_coordinates(BodyId(0)), Some(&[][..]), "a rigid body has no modal coordinates");
    assert!(simulation.modal_coordinates(BodyId(1)).is_none() && simulation.modal_rates(BodyId(1)).is_none());
    let rows = table.len();
    assert!(table.row(rows - 1).is_some() && table.row(rows).is_none());
    assert!(table.positions(rows).is_none() && table.velocities(rows).is_none());
    let values = vec![0.0; table.columns().len() - 1];
    let frame = OutputFrame { t: 1.0, values: &values, q: &[0.0; 3], v: &[0.0; 6] };
    let error = table.write_frame(&frame).unwrap_err();
    assert!(error.contains("7 positions and 6 velocities per row, the frame has 3 and 6"), "{error}");
    assert_eq!(table.len(), rows, "a refused frame adds no row");
}
