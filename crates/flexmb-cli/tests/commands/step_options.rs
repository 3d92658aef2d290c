//! `--fixed-step H` and `--max-step H` of `flexmb run`, and the `[simulation]` keys `fixed_step` and
//! `max_step`: a fixed-step generalized-α run takes exactly `t_end / H` steps (as the peer's fixed-step
//! generalized-α), a largest step is never exceeded, and a fixed step with a method that has none is
//! refused with a message naming the key.

use crate::program;

use program::{fail, scratch, succeed, workspace};

/// The number of steps in the summary JSON of a run into `dir` of the shipped pendulum.
fn steps(dir: &std::path::Path) -> u64 {
    let text = std::fs::read_to_string(dir.join("pendulum.json")).unwrap();
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    json["statistics"]["steps"].as_u64().unwrap()
}

#[test]
fn a_fixed_step_run_takes_t_end_over_h_steps() {
    let out = scratch("fixed-step");
    for (h, expected) in [("0.01", 200), ("0.004", 500), ("0.0025", 800)] {
        let dir = out.join(h);
        succeed(&["run", "models/pendulum.toml", "--integrator", "gen-alpha", "--fixed-step", h, "--t-end", "2", "--quiet", "--out", dir.to_str().unwrap()]);
        assert_eq!(steps(&dir), expected, "--fixed-step {h}");
    }
    // The model file's key gives the same run.
    let text = std::fs::read_to_string(workspace().join("models/pendulum.toml")).unwrap();
    let text = text.replace("[simulation]\n", "[simulation]\nintegrator = \"gen-alpha\"\nfixed_step = 0.004\n");
    let file = out.join("pendulum.toml");
    std::fs::write(&file, text).unwrap();
    let by_key = out.join("key");
    succeed(&["run", file.to_str().unwrap(), "--t-end", "2", "--quiet", "--out", by_key.to_str().unwrap()]);
    assert_eq!(steps(&by_key), 500);
    let by_option = std::fs::read_to_string(out.join("0.004/pendulum.csv")).unwrap();
    assert_eq!(std::fs::read_to_string(by_key.join("pendulum.csv")).unwrap(), by_option);
}

#[test]
fn a_largest_step_is_never_exceeded() {
    let out = scratch("max-step");
    for integrator in ["gen-alpha", "bdf", "adams"] {
        let free = out.join(format!("{integrator}-free"));
        succeed(&["run", "models/pendulum.toml", "--integrator", integrator, "--t-end", "2", "--quiet", "--out", free.to_str().unwrap()]);
        let capped = out.join(format!("{integrator}-capped"));
        succeed(&["run", "models/pendulum.toml", "--integrator", integrator, "--max-step", "0.0002", "--t-end", "2", "--quiet", "--out", capped.to_str().unwrap()]);
        // 2 s in steps of at most 0.2 ms: at least 10,000 steps, where error control alone takes far fewer
        // (generalized-α the most: 2,392 with the error per unit step over the run, its steps growing as
        // `tol^(-1/2)`).
        assert!(steps(&free) < 5000, "{integrator}: {} steps without the limit", steps(&free));
        assert!(steps(&capped) >= 10_000, "{integrator}: {} steps with --max-step 0.0002", steps(&capped));
    }
}

#[test]
fn a_fixed_step_needs_the_generalized_alpha_method() {
    let out = scratch("fixed-step-refused");
    let e = fail(&["run", "models/pendulum.toml", "--integrator", "bdf", "--fixed-step", "0.01", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(e.contains("generalized-α method only"), "{e}");
    let e = fail(&["run", "models/pendulum.toml", "--integrator", "gen-alpha", "--fixed-step=0", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(e.contains("--fixed-step must be a positive number"), "{e}");
    let text = std::fs::read_to_string(workspace().join("models/pendulum.toml")).unwrap();
    let file = out.join("pendulum.toml");
    std::fs::write(&file, text.replace("[simulation]\n", "[simulation]\nfixed_step = 0.01\n")).unwrap();
    let e = fail(&["check", file.to_str().unwrap()]);
    assert!(e.contains("simulation.fixed_step") && e.contains("integrator = \"gen-alpha\""), "{e}");
    std::fs::write(&file, text.replace("[simulation]\n", "[simulation]\nmax_step = 0\n")).unwrap();
    let e = fail(&["check", file.to_str().unwrap()]);
    assert!(e.contains("simulation.max_step") && e.contains("must be positive"), "{e}");
}

/// `--spectral-radius` alone selects the generalized-α method with that radius (the same run as with
/// `--integrator gen-alpha`, and another run than with another radius); beside another `--integrator` it
/// is refused, as is a radius outside 0 to 1; a radius of 1 under error control runs with a warning.
#[test]
fn a_spectral_radius_selects_the_generalized_alpha_method() {
    let out = scratch("spectral-radius");
    let run = |name: &str, args: &[&str]| {
        let dir = out.join(name);
        let mut all = vec!["run", "models/pendulum.toml", "--t-end", "1", "--quiet", "--out", dir.to_str().unwrap()];
        all.extend_from_slice(args);
        succeed(&all);
        let text = std::fs::read_to_string(dir.join("pendulum.json")).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(json["settings"]["integrator"], "gen-alpha", "{args:?}");
        std::fs::read_to_string(dir.join("pendulum.csv")).unwrap()
    };
    let alone = run("alone", &["--spectral-radius", "0.5"]);
    let named = run("named", &["--integrator", "gen-alpha", "--spectral-radius", "0.5"]);
    let other = run("other", &["--spectral-radius", "1"]);
    assert_eq!(alone, named, "--spectral-radius alone is the generalized-α method with that radius");
    assert_ne!(alone, other, "the radius changes the run");
    // Near 1 under error control the run warns at its start that the steps can collapse
    // (`GeneralizedAlphaConfig::undamped_warning`); at 0.5, or at a fixed step, it does not.
    let undamped = |name: &str| -> usize {
        let text = std::fs::read_to_string(out.join(name).join("pendulum.json")).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        let warnings = json["warnings"].as_array().unwrap();
        warnings.iter().filter(|w| w["t"] == 0.0 && w["message"].as_str().unwrap().contains("ρ∞ = 1 of the generalized-α method under error control")).count()
    };
    run("fixed", &["--spectral-radius", "1", "--fixed-step", "0.01"]);
    assert_eq!((undamped("other"), undamped("alone"), undamped("fixed")), (1, 0, 0));
    let e = fail(&["run", "models/pendulum.toml", "--integrator", "bdf", "--spectral-radius", "0.5", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(e.contains("--spectral-radius is a setting of the generalized-α method") && e.contains("--integrator bdf"), "{e}");
    let e = fail(&["run", "models/pendulum.toml", "--spectral-radius", "1.5", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(e.contains("between 0 and 1"), "{e}");
}
