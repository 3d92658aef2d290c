//! What error per unit step over the run does with an undamped vibration at BDF order 2
//! (docs/accuracy.md, *Vibrations over the run's span*): the steps resolve its phase so finely that the
//! method damps nothing of it; its errors are carried to the end and add up, so the vibration's
//! velocities are held to the tolerance, and its positions, which a velocity error `δv` moves by only
//! `δv / ω`, far inside it.

mod support;

use flexmb::analysis::SimulationSettings;
use flexmb::integrate::{BdfConfig, Method, ToleranceSpan};
use flexmb::model::OutputKind;

/// The pendulum with a 10 g slider on a spring of 100 N/m (ω = 100 rad/s), started 1 cm from its rest
/// length (velocity amplitude 1 m/s), BDF held to orders 1–2, rtol = atol = 1e-5, error per unit step
/// over the run's 1 s. Against the closed form `z = −(0.1 + x0 cos ωt)`, `ż = x0 ω sin ωt`:
///
/// - the vibration keeps its amplitude to 1e-4: BDF2 damps `1 − |R(iθ)|` ≈ `θ⁴/4` of it per step at
///   `θ = ω h`, nothing measurable at the steps it takes (61,928, `θ` ≈ 1.6e-3: 1e-7 over the run), so
///   its errors are not damped but carried to the end;
/// - its error is BDF2's phase error, `θ³/3` per step, added up: at least `N θ̄³/3` (the mean step's;
///   uneven steps make `Σ θ³` larger: measured 2.4 times), growing in proportion to the time (0.55 of
///   it at half the run);
/// - the velocity error is about the tolerance: 2.0 tolerances in the error test's RMS norm over the 26
///   positions and velocities, of which only this one errs (10 of the slider's weight `atol + rtol |ż|`);
/// - the position error is the same phase times `x0`: the velocity's error over ω.
///
/// So error per unit step holds an undamped vibration's velocities to the tolerance, and its positions
/// to 1/ω s of that: the door's vibration modes over the run (docs/accuracy.md).
/// About 1.5 s in release.
#[test]
fn error_per_unit_step_carries_a_vibrations_phase_error_and_holds_its_velocity_to_the_tolerance() {
    let (x0, omega, t_end, tol) = (1e-2, 100.0_f64, 1.0, 1e-5);
    let mut b = support::pendulum_with_slider(x0, 0.01 * omega * omega);
    let runner = b.find_marker("runner").unwrap();
    b.add_output("slider", OutputKind::MarkerPosition(runner)).unwrap();
    b.add_output("slider_velocity", OutputKind::MarkerVelocity(runner)).unwrap();
    let model = b.build().unwrap();
    let mut settings =
        SimulationSettings { method: Method::Bdf(BdfConfig { max_order: 2, ..Default::default() }), ..support::settings(t_end, 1e-3, tol) };
    settings.tolerances.span = ToleranceSpan::Run;
    let run = support::run(&model, &settings);
    let (z, vz) = (run.col("slider.z"), run.col("slider_velocity.z"));
    let position_error = |k: usize| (z[k] + 0.1 + x0 * (omega * run.t[k]).cos()).abs();
    let velocity_error = |k: usize| (vz[k] - x0 * omega * (omega * run.t[k]).sin()).abs();
    let largest = |error: &dyn Fn(usize) -> f64, from: f64, to: f64| {
        (0..run.t.len()).filter(|&k| run.t[k] >= from && run.t[k] <= to).map(error).fold(0.0, f64::max)
    };
    let (dz, dv) = (largest(&position_error, 0.0, t_end), largest(&velocity_error, 0.0, t_end));
    let dv_half = largest(&velocity_error, 0.45, 0.55);
    let n = run.report.stats.steps as f64;
    let theta = omega * t_end / n;
    let phase = n * theta.powi(3) / 3.0;
    let last = run.t.len() - 1;
    let amplitude = ((z[last] + 0.1).powi(2) + (vz[last] / omega).powi(2)).sqrt();
    eprintln!(
        "{n} steps, RMS step {:.3e}, θ = {theta:.2e}: amplitude {amplitude:.6e} (x0 {x0:e}); velocity error {dv:.3e} m/s (at half the run \
         {dv_half:.3e}), position error {dz:.3e} m; BDF2's phase N θ³/3 = {phase:.3e} rad, times x0 ω {:.3e} m/s",
        (run.report.stats.sum_h_squared / n).sqrt(),
        phase * x0 * omega
    );
    assert!((amplitude / x0 - 1.0).abs() < 1e-4, "the vibration's amplitude {amplitude:e} against {x0:e}");
    // The error test's RMS norm over the 26 positions and velocities, of which this one errs.
    let in_the_norm = dv / (tol * (1.0 + x0 * omega)) / ((model.layout().nq + model.layout().nv) as f64).sqrt();
    assert!((0.3..10.0).contains(&in_the_norm), "velocity error {dv:e}: {in_the_norm} tolerances in the norm");
    assert!((1.0..3.0).contains(&(dv / (phase * x0 * omega))), "velocity error {dv:e} against the phase's {:e}", phase * x0 * omega);
    assert!((0.35..0.65).contains(&(dv_half / dv)), "at half the run {dv_half:e} of {dv:e}");
    assert!((0.8..1.25).contains(&(dz * omega / dv)), "position error {dz:e} against the velocity's over ω {:e}", dv / omega);
}
