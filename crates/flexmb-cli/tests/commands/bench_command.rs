//! `flexmb bench`: its arguments, and one small case measured (counts, never times, are checked).

use crate::program;

use program::{fail, scratch, succeed};

#[test]
fn unknown_cases_and_integrators_are_refused_with_the_names_it_knows() {
    let e = fail(&["bench", "--case", "pendulum-of-doom"]);
    assert!(e.contains("peer") && e.contains("chain") && e.contains("pendulums"), "{e}");
    let e = fail(&["bench", "--case", "peer", "--integrator", "rk4"]);
    assert!(e.contains("bdf") && e.contains("adams") && e.contains("gen-alpha"), "{e}");
    let e = fail(&["bench", "--case", "peer", "--repeat", "many"]);
    assert!(e.contains("--repeat"), "{e}");
    let e = fail(&["bench", "--case", "chain", "--links", "0"]);
    assert!(e.contains("--links") && e.contains('0'), "{e}");
}

/// `--links N` makes the chain group one chain of N rods, any N: one row, that chain's.
#[test]
fn the_chain_group_runs_one_chain_of_the_rods_asked_for() {
    let stdout = succeed(&["bench", "--case", "chain", "--links", "6", "--integrator", "bdf", "--repeat", "1"]);
    let rows: Vec<&str> = stdout.lines().filter(|l| l.starts_with("chain-")).collect();
    assert_eq!(rows.len(), 1, "{stdout}");
    assert!(rows[0].starts_with("chain-6 "), "{stdout}");
}

/// The rigid 3-D pendulum with two integrators, once each: a table row per integrator and a JSON
/// record with the counts, consistent with one another.
#[test]
fn a_peer_case_is_measured_with_its_counts_in_the_table_and_the_json_file() {
    let out = scratch("bench");
    let json = out.join("bench.json");
    let stdout = succeed(&[
        "bench",
        "--case",
        "peer-rigid-pendulum-3d",
        "--integrator",
        "bdf,adams",
        "--repeat",
        "1",
        "--json",
        json.to_str().unwrap(),
    ]);
    for column in ["steps", "rej.N", "rej.E", "Newton", "Jac.", "LU", "us/step", "us/Newton", "s/sim.s"] {
        assert!(stdout.contains(column), "{column}: {stdout}");
    }
    assert_eq!(stdout.lines().filter(|l| l.starts_with("rigid-pendulum-3d")).count(), 2, "{stdout}");
    let document: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let records = document["measurements"].as_array().unwrap();
    assert_eq!(records.len(), 2);
    assert_eq!(records[0]["integrator"], "bdf");
    assert_eq!(records[1]["integrator"], "adams");
    for r in records {
        assert_eq!(r["group"], "peer");
        assert_eq!(r["case"], "rigid-pendulum-3d");
        // The peer's accuracy for this case: rtol = atol = 3e-5 with both integrators over the run's span, 5 s.
        assert_eq!(r["rtol"].as_f64(), Some(3e-5));
        assert_eq!(r["t_end"].as_f64(), Some(5.0));
        assert!(r["failure"].is_null(), "{r}");
        let count = |key: &str| r[key].as_u64().unwrap_or_else(|| panic!("{key} missing: {r}"));
        assert!(count("steps") > 10, "{r}");
        let rejected = count("newton_failures") + count("error_test_failures");
        assert!(rejected <= count("steps"), "{r}");
        assert!(count("factorizations") >= 1, "{r}");
        // Accepted steps by order add up to the steps.
        let by_order: u64 = r["order_counts"].as_array().unwrap().iter().map(|c| c.as_u64().unwrap()).sum();
        assert_eq!(by_order, count("steps"), "{r}");
        for key in ["us_per_step", "time_per_simulated_second", "integration_wall_s", "whole_wall_s", "setup_s"] {
            assert!(r[key].as_f64().is_some(), "{key} missing: {r}");
        }
    }
    // The BDF evaluates Jacobians; the Adams method has none.
    assert!(records[0]["jacobian_evaluations"].as_u64().unwrap() >= 1);
    assert_eq!(records[1]["jacobian_evaluations"].as_u64(), Some(0));
}
