//! The age of a reused Jacobian: the spinning top (models/spinning_top.toml, BDF at rtol 1e-7, 4 s)
//! converges its reused iterations at rates of 0.05 to 0.14, from which the rate monitor predicted 0.09 to
//! 0.28, yet the slow precession the aging Jacobian resolves worse made 262 of its 4,190 steps (6.3 %) fail
//! their Newton iteration about 11 steps after the Jacobian was evaluated. The BDF now learns an age limit
//! from such a failure (`RateMonitor::age_limit`).

use crate::program;

use program::{scratch, succeed, workspace};

/// Newton failures at most 5 % of the accepted steps (74 of 4,163, 1.8 %, measured), counted in the run's
/// statistics.
#[test]
fn the_spinning_top_fails_few_newton_iterations_with_an_aging_jacobian() {
    let model = workspace().join("models/spinning_top.toml");
    let out = scratch("jacobian-age");
    succeed(&["run", model.to_str().unwrap(), "--integrator", "bdf", "--quiet", "--out", out.to_str().unwrap()]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("spinning_top.json")).unwrap()).unwrap();
    let statistics = &summary["statistics"];
    let (steps, failures) = (statistics["steps"].as_u64().unwrap(), statistics["newton_failures"].as_u64().unwrap());
    assert!(steps > 3000, "{statistics}");
    assert!(failures * 20 <= steps, "{failures} Newton failures in {steps} steps: {statistics}");
}
