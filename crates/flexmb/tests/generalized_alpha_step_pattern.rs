//! The generalized-α method with a varying step: a step pattern alternating `h` and `2h` keeps second
//! order and is about as accurate as a uniform step of the same number of steps, so that a change of
//! step size costs no first-order error (`ã_n` is moved to the new step size, see `predict` in
//! `integrate/generalized_alpha`). Run with `--nocapture` for the measured numbers.

mod support;

use std::sync::Arc;
use flexmb::integrate::{Bdf, BdfConfig, GeneralizedAlpha, GeneralizedAlphaConfig, Tolerances};
use flexmb::model::Model;
use support::*;

const G: f64 = 9.81;

/// Generalized-α through the steps `steps` (no error control: each step ends where the pattern says),
/// Newton tolerance `tol`.
fn pattern_run(model: &Model, rho: f64, steps: &[f64], tol: f64) -> GeneralizedAlpha {
    let (state, acc) = consistent_start(model);
    let longest = steps.iter().copied().fold(0.0, f64::max);
    // A fixed step longer than every step of the pattern: each step ends on the `t_stop` it is given.
    let alpha = GeneralizedAlphaConfig { spectral_radius: rho, fixed_step: Some(2.0 * longest) };
    let mut ga = GeneralizedAlpha::new(Arc::new(model.clone()), &state, &acc, Tolerances::new(tol, tol), alpha).unwrap();
    let mut t = 0.0;
    for &h in steps {
        t += h;
        ga.step(t).unwrap();
        assert!((ga.t() - t).abs() < 1e-12, "the step ends on the pattern's time");
    }
    assert_eq!(ga.stats.steps, steps.len());
    ga
}

/// Positions and velocities at `t_end` from the BDF at tolerance `tol`.
fn bdf_reference(model: &Model, t_end: f64, tol: f64) -> (Vec<f64>, Vec<f64>) {
    let (state, acc) = consistent_start(model);
    let mut bdf = Bdf::new(Arc::new(model.clone()), &state, &acc, Tolerances::new(tol, tol), BdfConfig::default()).unwrap();
    while bdf.t() < t_end {
        bdf.step(t_end).unwrap();
    }
    let l = model.layout();
    let y = bdf.y();
    (y[..l.nq].to_vec(), y[l.nq..l.nq + l.nv].to_vec())
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// A pendulum swinging 1 rad over 1.5 s with `n` uniform steps and with `n` steps alternating `h` and
/// `2h` (`h = 2 t_end / 3n`). The local error grows as `h³`, so the alternating pattern, whose steps
/// are 2/3 and 4/3 of the uniform one, is expected to be `(8 + 64)/(2 · 27) = 1.33` times less accurate:
/// measured 1.21–1.35 (positions and velocities, ρ∞ = 0.9 and 0.5, n = 60 … 480). Without the shift of
/// `ã_n` to the new step size the change would cost an `O(h)` error in `ã`, and the pattern would
/// converge at first order.
#[test]
fn alternating_steps_keep_second_order_and_the_accuracy_of_a_uniform_step() {
    let model = pendulum(1.0, 1.0, 1e-3, 1.0, G).build().unwrap();
    let t_end = 1.5;
    let (q_ref, v_ref) = bdf_reference(&model, t_end, 1e-12);
    for rho in [0.9, 0.5] {
        eprintln!("ρ∞ = {rho}:\n      n   uniform q   alternating q  ratio   uniform v   alternating v  ratio");
        let mut previous: Option<(f64, f64)> = None;
        for n in [60, 120, 240, 480] {
            let uniform = vec![t_end / n as f64; n];
            let h = 2.0 * t_end / (3.0 * n as f64);
            let alternating: Vec<f64> = (0..n).map(|k| if k % 2 == 0 { h } else { 2.0 * h }).collect();
            let (u, a) = (pattern_run(&model, rho, &uniform, 1e-12), pattern_run(&model, rho, &alternating, 1e-12));
            let (uq, uv) = (max_difference(u.q(), &q_ref), max_difference(u.v(), &v_ref));
            let (aq, av) = (max_difference(a.q(), &q_ref), max_difference(a.v(), &v_ref));
            eprintln!("  {n:5} {uq:11.3e} {aq:13.3e} {:7.2} {uv:11.3e} {av:13.3e} {:7.2}", aq / uq, av / uv);
            for (what, ratio) in [("positions", aq / uq), ("velocities", av / uv)] {
                assert!((1.0..1.6).contains(&ratio), "ρ∞ = {rho}, n = {n}: alternating/uniform error of the {what} {ratio:.2}, expected 1.33");
            }
            if let Some((pq, pv)) = previous {
                // Halving the steps of the pattern divides its error by 4 (second order).
                for (what, factor) in [("positions", pq / aq), ("velocities", pv / av)] {
                    assert!((3.5..4.5).contains(&factor), "ρ∞ = {rho}, n = {n}: the alternating pattern's {what} error fell by {factor:.2} per halving, expected 4");
                }
            }
            previous = Some((aq, av));
        }
    }
}
