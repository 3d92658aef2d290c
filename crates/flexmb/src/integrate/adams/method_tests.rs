//! The Adams stepper alone on ODEs with known solutions: observed order at fixed order and step, error
//! control and order variation on the Kepler and Arenstorf orbits, dense output, a projection hook,
//! and the stiffness signature. Run with `--nocapture` for the tables.

use super::method::*;

/// `y₁' = y₂, y₂' = −y₁`: `y = [cos t, −sin t]` from `[1, 0]`.
struct Oscillator;

impl OdeSystem for Oscillator {
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        dy[0] = y[1];
        dy[1] = -y[0];
        Ok(())
    }
}

/// Global error at `t = n h` of `n` steps of order `k` from the exact constant-step history.
fn fixed_order_error(k: usize, h: f64, n: usize) -> f64 {
    let past: Vec<Vec<f64>> = (0..k)
        .map(|j| {
            let t = -(j as f64) * h;
            vec![-t.sin(), -t.cos()]
        })
        .collect();
    let mut s = AdamsStepper::with_fixed_order_and_step(0.0, &[1.0, 0.0], h, &past);
    for _ in 0..n {
        s.step(&mut Oscillator, f64::INFINITY).unwrap();
    }
    assert_eq!(s.stats.order_counts[k], n, "every step at order {k}");
    let t = s.t();
    assert!((t - n as f64 * h).abs() < 1e-12 * t);
    let y = s.y();
    (y[0] - t.cos()).abs().max((y[1] + t.sin()).abs())
}

/// Least-squares slope of `log err` against `log h`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let xs: Vec<f64> = points.iter().map(|p| p.0.ln()).collect();
    let ys: Vec<f64> = points.iter().map(|p| p.1.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

/// Order `k` (Adams–Bashforth predictor of order k, Adams–Moulton corrector of order k + 1 with local
/// extrapolation) converges with order k + 1 at a fixed step.
#[test]
fn observed_order_at_fixed_order_and_step_is_k_plus_one() {
    let t_end: f64 = 4.0;
    // Step sizes per order: the errors stay well above round-off and the steps inside the stability
    // region of the PECE pair.
    let base = [0.0, 0.02, 0.04, 0.1, 0.1, 0.2, 0.2, 0.25, 0.25, 0.25, 0.25];
    eprintln!("order k   h → error (t = {t_end})                           slope (expected k + 1)");
    for k in 1..=10 {
        let points: Vec<(f64, f64)> = [1.0, 0.5, 0.25]
            .iter()
            .map(|f| {
                let h = base[k] * f;
                let n = (t_end / h).round() as usize;
                (h, fixed_order_error(k, h, n))
            })
            .collect();
        let s = slope(&points);
        eprintln!(
            "  {k:2}   {}   {s:6.3}",
            points.iter().map(|(h, e)| format!("{h:.4}→{e:.2e}")).collect::<Vec<_>>().join("  ")
        );
        assert!((s - (k + 1) as f64).abs() < 0.3, "order {k}: observed {s:.3}, expected {}", k + 1);
    }
}

/// Kepler's problem, eccentricity `e`, from periapsis; period 2π.
struct Kepler;

impl OdeSystem for Kepler {
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let r3 = (y[0] * y[0] + y[1] * y[1]).powf(1.5);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
        Ok(())
    }
}

fn kepler_initial(e: f64) -> [f64; 4] {
    [1.0 - e, 0.0, 0.0, ((1.0 + e) / (1.0 - e)).sqrt()]
}

/// The exact Kepler orbit at `t` (Newton on `E − e sin E = t`).
fn kepler_exact(e: f64, t: f64) -> [f64; 4] {
    let mut big_e = t;
    for _ in 0..50 {
        big_e -= (big_e - e * big_e.sin() - t) / (1.0 - e * big_e.cos());
    }
    let (s, c) = big_e.sin_cos();
    let d = 1.0 - e * c;
    let b = (1.0 - e * e).sqrt();
    [c - e, b * s, -s / d, b * c / d]
}

fn control(tol: f64) -> StepControl {
    StepControl { rtol: tol, atol: tol, ..Default::default() }
}

fn run_to<S: OdeSystem>(s: &mut AdamsStepper, sys: &mut S, t_end: f64) {
    while s.t() < t_end {
        s.step(sys, t_end).unwrap();
    }
    assert_eq!(s.t(), t_end);
}

fn order_histogram(st: &StepperStats) -> String {
    st.order_counts
        .iter()
        .enumerate()
        .filter(|(_, c)| **c > 0)
        .map(|(k, c)| format!("{k}:{c}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Error control: the global error over three orbits follows the tolerance, the order rises as the
/// tolerance tightens (few steps per orbit at high order), and every step ends on the requested end time.
#[test]
fn kepler_orbit_error_follows_tolerance_and_order_rises() {
    let e = 0.5;
    let t_end = 3.0 * std::f64::consts::TAU;
    let exact = kepler_exact(e, t_end);
    eprintln!(
        "Kepler e = {e}, three orbits:\n       tol   steps  rejected  f evals   global error   mean order   orders"
    );
    let mut last_steps = 0;
    let mut mean_orders = Vec::new();
    let mut errors = Vec::new();
    for tol in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        let mut s = AdamsStepper::start(control(tol), &mut Kepler, 0.0, &kepler_initial(e)).unwrap();
        run_to(&mut s, &mut Kepler, t_end);
        let err = (0..4).map(|l| (s.y()[l] - exact[l]).abs()).fold(0.0, f64::max);
        let st = s.stats;
        let mean = st.order_counts.iter().enumerate().map(|(k, c)| k * c).sum::<usize>() as f64 / st.steps as f64;
        eprintln!(
            "  {tol:8.0e} {:7} {:9} {:8} {err:14.3e} {mean:12.2}   {}",
            st.steps,
            st.error_test_failures,
            st.evaluations,
            order_histogram(&st)
        );
        // The tolerance bounds the local error per unit step; over three orbits (whose phase error
        // grows with time) the global error is measured at 760–3300 times the tolerance.
        assert!(err < 1e4 * tol, "tol {tol:e}: global error {err:e}");
        errors.push(err);
        assert!(st.steps > last_steps, "more steps at a tighter tolerance");
        last_steps = st.steps;
        mean_orders.push(mean);
        // PECE: one evaluation at the start, two per accepted step, one per rejected attempt.
        assert_eq!(st.evaluations, 1 + 2 * st.steps + st.error_test_failures);
    }
    // Tolerance proportionality: 100 times tighter, at least 10 times smaller.
    assert!(errors.windows(2).all(|w| w[1] < w[0] / 10.0), "{errors:?}");
    assert!(mean_orders.windows(2).all(|w| w[1] > w[0]), "the order rises as the tolerance tightens: {mean_orders:?}");
    assert!(mean_orders[4] > 9.0, "high orders at tol 1e-12: {mean_orders:?}");
    assert!(mean_orders[0] < 7.0, "lower orders at tol 1e-4: {mean_orders:?}");
}

/// The restricted three-body problem (Arenstorf orbit): periodic with period `T`; the orbit passes close
/// to the moon, so the step varies over orders of magnitude along it.
struct Arenstorf;

const ARENSTORF_MU: f64 = 0.012277471;
const ARENSTORF_T: f64 = 17.065_216_560_157_963;
const ARENSTORF_Y0: [f64; 4] = [0.994, 0.0, 0.0, -2.001_585_106_379_082_5];

impl OdeSystem for Arenstorf {
    fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let (mu, mu1) = (ARENSTORF_MU, 1.0 - ARENSTORF_MU);
        let d1 = ((y[0] + mu).powi(2) + y[1] * y[1]).powf(1.5);
        let d2 = ((y[0] - mu1).powi(2) + y[1] * y[1]).powf(1.5);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = y[0] + 2.0 * y[3] - mu1 * (y[0] + mu) / d1 - mu * (y[0] - mu1) / d2;
        dy[3] = y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - mu * y[1] / d2;
        Ok(())
    }
}

#[test]
fn arenstorf_orbit_closes() {
    eprintln!("Arenstorf orbit, one period:\n       tol   steps  rejected  f evals   error at T   min h      max h     orders");
    for (tol, bound) in [(1e-6, 5e-2), (1e-9, 1e-4), (1e-12, 1e-7)] {
        let mut s = AdamsStepper::start(control(tol), &mut Arenstorf, 0.0, &ARENSTORF_Y0).unwrap();
        let (mut h_min, mut h_max) = (f64::INFINITY, 0.0_f64);
        while s.t() < ARENSTORF_T {
            let t0 = s.t();
            s.step(&mut Arenstorf, ARENSTORF_T).unwrap();
            if s.t() < ARENSTORF_T {
                h_min = h_min.min(s.t() - t0);
            }
            h_max = h_max.max(s.t() - t0);
        }
        let err = (0..2).map(|l| (s.y()[l] - ARENSTORF_Y0[l]).abs()).fold(0.0, f64::max);
        let st = s.stats;
        eprintln!(
            "  {tol:8.0e} {:7} {:9} {:8} {err:12.3e} {h_min:10.2e} {h_max:10.2e}   {}",
            st.steps,
            st.error_test_failures,
            st.evaluations,
            order_histogram(&st)
        );
        assert!(err < bound, "tol {tol:e}: the orbit misses its start by {err:e}");
        assert!(h_max / h_min > 30.0, "the step varies along the orbit");
    }
}

/// INTRP: the interpolant of each step matches the exact solution and its derivative inside the step,
/// to about the tolerance.
#[test]
fn dense_output_follows_the_exact_solution() {
    let e = 0.3;
    let tol = 1e-10;
    let mut s = AdamsStepper::start(control(tol), &mut Kepler, 0.0, &kepler_initial(e)).unwrap();
    let (mut y, mut yp) = ([0.0; 4], [0.0; 4]);
    let mut f = [0.0; 4];
    let (mut worst_y, mut worst_yp) = (0.0_f64, 0.0_f64);
    let mut points = 0;
    while s.t() < 10.0 {
        s.step(&mut Kepler, 10.0).unwrap();
        for j in 1..=4 {
            let t = s.t_old() + (s.t() - s.t_old()) * j as f64 / 5.0;
            s.interpolate(t, &mut y, &mut yp);
            let ex = kepler_exact(e, t);
            Kepler.rhs(t, &ex, &mut f).unwrap();
            for l in 0..4 {
                worst_y = worst_y.max((y[l] - ex[l]).abs());
                worst_yp = worst_yp.max((yp[l] - f[l]).abs());
            }
            points += 1;
        }
        // At the step's end the interpolant is the solution itself.
        s.interpolate(s.t(), &mut y, &mut yp);
        assert!((0..4).all(|l| (y[l] - s.y()[l]).abs() <= 1e-15 * (1.0 + s.y()[l].abs())));
    }
    eprintln!("dense output at {points} points inside steps: largest error {worst_y:.2e} (y), {worst_yp:.2e} (y')");
    assert!(worst_y < 1e-7, "{worst_y:e}");
    assert!(worst_yp < 1e-6, "{worst_yp:e}");
}

/// The oscillator projected onto its invariant circle after every step: the invariant holds to
/// round-off, and the solution stays as accurate as without projection.
struct ProjectedOscillator;

impl OdeSystem for ProjectedOscillator {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        Oscillator.rhs(t, y, dy)
    }
    fn accept(&mut self, t: f64, y: &mut [f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        let r = (y[0] * y[0] + y[1] * y[1]).sqrt();
        y[0] /= r;
        y[1] /= r;
        self.rhs(t, y, dy)
    }
}

#[test]
fn projection_hook_keeps_the_invariant() {
    let t_end = 100.0;
    let tol = 1e-8;
    let mut plain = AdamsStepper::start(control(tol), &mut Oscillator, 0.0, &[1.0, 0.0]).unwrap();
    run_to(&mut plain, &mut Oscillator, t_end);
    let mut projected = AdamsStepper::start(control(tol), &mut ProjectedOscillator, 0.0, &[1.0, 0.0]).unwrap();
    let mut worst_invariant = 0.0_f64;
    while projected.t() < t_end {
        projected.step(&mut ProjectedOscillator, t_end).unwrap();
        let y = projected.y();
        worst_invariant = worst_invariant.max((y[0] * y[0] + y[1] * y[1] - 1.0).abs());
    }
    let err = |s: &AdamsStepper| (s.y()[0] - t_end.cos()).abs().max((s.y()[1] + t_end.sin()).abs());
    let y = plain.y();
    let drift_plain = (y[0] * y[0] + y[1] * y[1] - 1.0).abs();
    eprintln!(
        "oscillator to t = {t_end}: plain {} steps, error {:.2e}, |r² − 1| {drift_plain:.2e}; projected {} steps, error {:.2e}, |r² − 1| ≤ {worst_invariant:.2e}",
        plain.stats.steps,
        err(&plain),
        projected.stats.steps,
        err(&projected)
    );
    assert!(worst_invariant < 1e-14);
    assert!(err(&projected) <= 1.5 * err(&plain) + 1e-9);
}

/// `y' = −λ (y − cos t) − sin t` (solution `cos t` after a transient of rate λ): the Adams method's
/// step is bounded by stability, `h λ ≲ 1`, whatever the tolerance — the stiffness signature.
struct StiffRelaxation(f64);

impl OdeSystem for StiffRelaxation {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        dy[0] = -self.0 * (y[0] - t.cos()) - t.sin();
        Ok(())
    }
}

#[test]
fn stiff_problem_takes_stability_limited_steps() {
    let t_end = 10.0;
    eprintln!("y' = −λ (y − cos t) − sin t to t = {t_end}:\n      λ      tol   steps  rejected    error");
    for lambda in [1e2, 1e3] {
        let mut counts = Vec::new();
        for tol in [1e-3, 1e-6] {
            let mut sys = StiffRelaxation(lambda);
            let mut s = AdamsStepper::start(control(tol), &mut sys, 0.0, &[1.0]).unwrap();
            run_to(&mut s, &mut sys, t_end);
            let err = (s.y()[0] - t_end.cos()).abs();
            eprintln!("  {lambda:6.0e} {tol:8.0e} {:7} {:9} {err:9.2e}", s.stats.steps, s.stats.error_test_failures);
            assert!(err < 100.0 * tol);
            counts.push(s.stats.steps as f64);
        }
        // Stability, not accuracy, sets the step: at least λ t_end / 4 steps at either tolerance.
        assert!(counts.iter().all(|&c| c > lambda * t_end / 4.0), "λ = {lambda}: {counts:?}");
    }
}

/// With `max_order` the order never exceeds the limit.
#[test]
fn order_limit_is_respected() {
    for max_order in [1, 2, 5] {
        let c = StepControl { max_order, ..control(1e-8) };
        let mut s = AdamsStepper::start(c, &mut Kepler, 0.0, &kepler_initial(0.2)).unwrap();
        run_to(&mut s, &mut Kepler, 5.0);
        assert!(s.stats.order_counts[max_order + 1..].iter().all(|&c| c == 0), "{:?}", s.stats.order_counts);
        assert!(s.stats.order_counts[max_order] > 0);
        let err = (0..4).map(|l| (s.y()[l] - kepler_exact(0.2, 5.0)[l]).abs()).fold(0.0, f64::max);
        assert!(err < 1e-5, "max order {max_order}: {err:e}");
    }
}

/// Failures are reported with the time: an `f` that fails beyond `t = 1` drives the step to zero there.
struct FailsBeyond(f64);

impl OdeSystem for FailsBeyond {
    fn rhs(&mut self, t: f64, _y: &[f64], dy: &mut [f64]) -> Result<(), EvaluationFailure> {
        if t > self.0 {
            return Err(EvaluationFailure("beyond the end of the world"));
        }
        dy[0] = 1.0;
        Ok(())
    }
}

#[test]
fn evaluation_failures_shrink_the_step_then_stop_with_the_cause() {
    let mut sys = FailsBeyond(1.0);
    let mut s = AdamsStepper::start(control(1e-6), &mut sys, 0.0, &[0.0]).unwrap();
    let result = loop {
        match s.step(&mut sys, 2.0) {
            Ok(()) => assert!(s.t() <= 1.0),
            Err(e) => break e,
        }
    };
    match result {
        StepFailure::StepSizeTooSmall {
            t, last: Some(AttemptFailure::Evaluation(EvaluationFailure(what))), ..
        } => {
            assert!((t - 1.0).abs() < 1e-12, "stopped at {t}");
            assert_eq!(what, "beyond the end of the world");
        }
        other => panic!("unexpected {other:?}"),
    }
}
