//! Simple pendulum: period against the elliptic-integral value, energy conservation over many periods.

mod support;

use flexmb::analysis::{simulate, SimulationSettings};
use flexmb::integrate::Tolerances;
use flexmb::model::OutputKind;

#[test]
fn period_matches_elliptic_integral_and_energy_is_conserved() {
    let (l, m, ic, g, theta0) = (1.0, 1.0, 1e-3, 9.81, 1.0_f64);
    let mut b = support::pendulum(l, m, ic, theta0, g);
    let bob = b.find_marker("bob_centre").unwrap();
    b.add_output("bob", OutputKind::MarkerPosition(bob)).unwrap();
    b.add_output("energy", OutputKind::Energy).unwrap();
    let model = b.build().unwrap();
    // Physical pendulum: T = 4 sqrt(I_O / (m g l)) K(sin(θ0/2)).
    let i_pivot = ic + m * l * l;
    let period = 4.0 * (i_pivot / (m * g * l)).sqrt() * support::elliptic_k((theta0 / 2.0).sin());
    let settings = SimulationSettings {
        t_end: 10.0 * period,
        output_step: 1e-3,
        tolerances: Tolerances::new(1e-9, 1e-9),
        ..Default::default()
    };
    let mut t = Vec::new();
    let mut x = Vec::new();
    let mut e = Vec::new();
    let report = simulate(&model, &settings, &mut |f| {
        t.push(f.t);
        x.push(f.values[0]);
        e.push(f.values[6]);
    })
    .unwrap();
    // Zero crossings of x going downward-to-upward: successive crossings in the same direction are one period apart.
    let mut crossings = Vec::new();
    for k in 1..t.len() {
        if x[k - 1] < 0.0 && x[k] >= 0.0 {
            let s = x[k - 1] / (x[k - 1] - x[k]);
            crossings.push(t[k - 1] + s * (t[k] - t[k - 1]));
        }
    }
    assert!(crossings.len() >= 9, "crossings: {crossings:?}");
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let rel = (measured - period).abs() / period;
    assert!(rel < 1e-5, "period {measured} vs {period}: rel {rel:e}");
    let e0 = e[0];
    let drift = e.iter().map(|x| (x - e0).abs()).fold(0.0, f64::max) / (m * g * l);
    assert!(drift < 1e-5, "energy drift {drift:e}");
    assert!(report.max_position_residual < 1e-8, "{:?}", report.max_position_residual);
    assert!(report.max_normalization_error < 1e-14, "{:?}", report.max_normalization_error);
    eprintln!("steps {} rms h {:.3e} jac {} fact {}", report.stats.steps, report.stats.rms_step(), report.stats.jacobian_evaluations, report.stats.factorizations);
}
