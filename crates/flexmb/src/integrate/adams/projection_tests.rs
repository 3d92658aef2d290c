//! The drift the projection removes: the index-1 ODE integrated by the same stepper without projection
//! leaves the constraints at a rate set by the local error, and the violation grows along the run;
//! with projection it stays at the projection's tolerance.

use std::sync::Arc;
use super::kkt::{constraint_rate, position_residual};
use crate::stage::position_rates;
use super::method::{AdamsStepper, EvaluationFailure, OdeSystem, StepControl};
use super::projection::ProjectedMechanism;
use crate::analysis::test_models::double_pendulum_with_spring;
use crate::analysis::{assemble, velocity_analysis, AccelerationSolver, State};
use crate::data::Data;
use crate::model::Model;
use crate::stage::{constraint_equations, kinematics};

/// The same system with the projection switched off (the accepted solution is only evaluated).
struct Unprojected(ProjectedMechanism);

impl OdeSystem for Unprojected {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        self.0.rhs(t, y, dy)
    }
}

/// Largest `|Φ|`, `|B v + Φ_t|` and `|pᵀp − 1|` at `(t, y)`.
fn violations(model: &Model, data: &mut Data, active: &[bool], t: f64, y: &[f64]) -> (f64, f64, f64) {
    let (q, v) = y.split_at(model.layout.nq);
    kinematics(model, data, q, v);
    constraint_equations(model, data, t);
    let position = position_residual(data, active);
    let velocity =
        (0..active.len()).filter(|r| active[*r]).map(|r| constraint_rate(model, data, r).abs()).fold(0.0, f64::max);
    let norm = (0..model.bodies.len())
        .map(|b| {
            let qo = model.layout.q_offset[b];
            ((3..7).map(|k| q[qo + k].powi(2)).sum::<f64>() - 1.0).abs()
        })
        .fold(0.0, f64::max);
    (position, velocity, norm)
}

#[test]
fn projection_removes_the_drift_of_the_index_one_equations() {
    let model = double_pendulum_with_spring();
    let mut data = Data::new(&model);
    let mut state = State::initial(&model);
    assemble(&model, &mut data, &mut state, Default::default()).unwrap();
    velocity_analysis(&model, &mut data, &mut state).unwrap();
    let mut solver = AccelerationSolver::new(&model);
    let acc = solver.solve(&model, &mut data, 0.0, &state.q, &state.v, &state.active).unwrap().clone();
    let (nq, nv) = (model.layout.nq, model.layout.nv);
    let mut y0 = state.q.clone();
    y0.extend_from_slice(&state.v);
    let mut yp0 = vec![0.0; nq + nv];
    yp0[nq..].copy_from_slice(&acc.vdot);
    position_rates(&model, &state.q, &state.v, &mut yp0[..nq]);
    let t_end = 5.0;
    eprintln!("spatial double pendulum, {t_end} s: largest |Φ|, |Bv + Φ_t|, |pᵀp − 1| along the run");
    for tol in [1e-6, 1e-9] {
        let control = StepControl { rtol: tol, atol: tol, ..Default::default() };
        let mut worst = [(0.0_f64, 0.0_f64, 0.0_f64); 2];
        let mut steps = [0; 2];
        for (k, worst) in worst.iter_mut().enumerate() {
            let system = ProjectedMechanism::new(Arc::new(model.clone()), state.active.clone(), tol, tol);
            let mut stepper = AdamsStepper::new(control, 0.0, &y0, &yp0);
            let mut projected = system;
            let mut unprojected = Unprojected(ProjectedMechanism::new(Arc::new(model.clone()), state.active.clone(), tol, tol));
            while stepper.t() < t_end {
                if k == 0 {
                    stepper.step(&mut unprojected, t_end).unwrap();
                } else {
                    stepper.step(&mut projected, t_end).unwrap();
                }
                let v = violations(&model, &mut data, &state.active, stepper.t(), stepper.y());
                *worst = (worst.0.max(v.0), worst.1.max(v.1), worst.2.max(v.2));
            }
            steps[k] = stepper.stats.steps;
        }
        let [free, kept] = worst;
        eprintln!(
            "  tol {tol:.0e}: without projection {:.1e} m, {:.1e} m/s, {:.1e} ({} steps); with projection {:.1e} m, \
             {:.1e} m/s, {:.1e} ({} steps)",
            free.0, free.1, free.2, steps[0], kept.0, kept.1, kept.2, steps[1]
        );
        assert!(kept.0 <= 1e-2 * tol && kept.1 < 1e-12 && kept.2 < 1e-14, "{kept:?}");
        assert!(free.0 > 10.0 * tol && free.1 > 10.0 * tol, "the index-1 equations drift: {free:?}");
    }
}
