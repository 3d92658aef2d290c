//! Restart through the program (issue 15): `flexmb run --save-state FILE` at a pause or an
//! interruption, then `flexmb run --resume FILE`, gives the rows of one uninterrupted run — the first
//! part's CSV followed by the second's — and the counters of the whole run; a checkpoint that is not
//! one, or of another model or method, is a clean error naming the file.

use crate::program;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use program::{fail, scratch, succeed, text, workspace, ResultCsv};

/// Relative agreement of a split run with one run: the same steps, so equal to round-off (the CSV's
/// 10 decimals make them equal digit for digit in practice).
const TOLERANCE: f64 = 1e-12;

fn path(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `flexmb run MODEL` with `args`, quiet, into `out`; returns the CSV and the JSON summary.
fn run(model: &str, out: &Path, args: &[&str]) -> (ResultCsv, serde_json::Value) {
    succeed(&[&["run", model, "--quiet", "--out", path(out)], args].concat());
    let stem = Path::new(model).file_stem().unwrap().to_str().unwrap();
    let summary = std::fs::read_to_string(out.join(format!("{stem}.json"))).unwrap();
    (ResultCsv::read(&out.join(format!("{stem}.csv"))), serde_json::from_str(&summary).unwrap())
}

/// The rows of `first` followed by those of `second` equal `whole`'s, within [`TOLERANCE`].
fn assert_continues(name: &str, first: &ResultCsv, second: &ResultCsv, whole: &ResultCsv) {
    assert_eq!(first.header, whole.header);
    assert_eq!(second.header, whole.header);
    let rows: Vec<&Vec<f64>> = first.rows.iter().chain(&second.rows).collect();
    assert_eq!(rows.len(), whole.rows.len(), "{name}: rows");
    assert!(!first.rows.is_empty() && !second.rows.is_empty(), "{name}: both parts have rows");
    for (k, (split, one)) in rows.iter().zip(&whole.rows).enumerate() {
        for (c, (a, b)) in split.iter().zip(one).enumerate() {
            let scale = a.abs().max(b.abs()).max(1e-8);
            assert!((a - b).abs() <= TOLERANCE * scale, "{name}: row {k}, column {}: {a} vs {b}", whole.header[c]);
        }
    }
}

/// One run to `t_end`, and a run paused at `t_end / 2` with `--save-state` and resumed to `t_end`.
fn check_split(model: &str, integrator: &str, t_end: f64) {
    let name = format!("{model} {integrator}");
    let dir = scratch(&format!("restart-{}-{integrator}", Path::new(model).file_stem().unwrap().to_str().unwrap()));
    let (t, pause) = (t_end.to_string(), (t_end / 2.0).to_string());
    let common = ["--t-end", &t, "--integrator", integrator];
    let (whole, whole_summary) = run(model, &dir.join("whole"), &common);
    let state = dir.join("state.json");
    let (first, first_summary) = run(model, &dir.join("first"), &[&common[..], &["--pause-at", &pause, "--save-state", path(&state)]].concat());
    assert_eq!(first_summary["status"], "interrupted", "{name}: {first_summary}");
    assert!(first_summary["interrupted_at"].as_f64().unwrap() >= t_end / 2.0);
    let (second, summary) = run(model, &dir.join("second"), &[&common[..], &["--resume", path(&state)]].concat());
    assert_continues(&name, &first, &second, &whole);
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["resumed_from"]["checkpoint"], path(&state));
    assert_eq!(summary["resumed_from"]["t"], first_summary["interrupted_at"]);
    assert!(whole_summary.get("resumed_from").is_none());
    for counter in ["steps", "rejected_steps", "newton_iterations", "jacobian_evaluations"] {
        assert_eq!(summary["statistics"][counter], whole_summary["statistics"][counter], "{name}: {counter}");
    }
    assert_eq!(summary["output"]["rows"], whole_summary["output"]["rows"], "{name}: the summary counts the whole run's rows");
}

#[test]
fn slider_crank_split_with_bdf_and_generalized_alpha_equals_one_run() {
    check_split("models/slider_crank.toml", "bdf", 1.0);
    check_split("models/slider_crank.toml", "gen-alpha", 1.0);
}

#[test]
fn flexible_pendulum_split_with_bdf_and_adams_equals_one_run() {
    check_split("models/flexible_pendulum.toml", "bdf", 0.5);
    check_split("models/flexible_pendulum.toml", "adams", 0.5);
}

/// The door run for 400 s, stopped by SIGINT once its CSV has 50 rows, with `--save-state`: returns the
/// output directory and the time it stopped at.
fn interrupt_the_door(out: &Path, state: &Path) -> f64 {
    let mut child = Command::new(env!("CARGO_BIN_EXE_flexmb"))
        .args(["run", "models/door/door.toml", "--t-end", "400", "--tolerance-span", "step", "--quiet", "--out", path(out), "--save-state", path(state)])
        .current_dir(workspace())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("flexmb starts");
    let csv = out.join("door.csv");
    let started = Instant::now();
    while std::fs::read_to_string(&csv).map_or(0, |t| t.lines().count()) < 51 {
        assert!(started.elapsed() < Duration::from_secs(120), "no rows written");
        assert!(child.try_wait().unwrap().is_none(), "flexmb ended before it was interrupted");
        std::thread::sleep(Duration::from_millis(5));
    }
    assert!(Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill runs").success());
    let output = child.wait_with_output().unwrap();
    assert_eq!(output.status.code(), Some(130), "{}", text(&output.stderr));
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("door.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "interrupted");
    summary["interrupted_at"].as_f64().unwrap()
}

#[test]
fn run_interrupted_by_sigint_resumes_to_the_end_of_one_run() {
    let dir = scratch("restart-interrupted");
    let state = dir.join("state.json");
    let at = interrupt_the_door(&dir.join("first"), &state);
    let first = ResultCsv::read(&dir.join("first").join("door.csv"));
    // The end a little after the interruption: the steps before it are those of a run to that end, with
    // each step its whole tolerance (over the run's span the steps depend on the end time: 400 s for the
    // interrupted run, a fraction of a second for the others).
    let t_end = format!("{:.3}", at + 0.1);
    let per_step = ["--tolerance-span", "step"];
    let (second, summary) = run("models/door/door.toml", &dir.join("second"), &[&["--t-end", &t_end, "--resume", path(&state)][..], &per_step].concat());
    let (whole, _) = run("models/door/door.toml", &dir.join("whole"), &[&["--t-end", &t_end][..], &per_step].concat());
    assert_continues("door interrupted", &first, &second, &whole);
    assert_eq!(summary["status"], "completed");
}

/// A checkpoint of the slider-crank to resume from in the tests of bad checkpoints.
fn slider_crank_state(dir: &Path) -> PathBuf {
    let state = dir.join("state.json");
    succeed(&["run", "models/slider_crank.toml", "--t-end", "0.2", "--quiet", "--out", path(dir), "--save-state", path(&state)]);
    state
}

#[test]
fn corrupt_missing_or_foreign_checkpoints_are_clean_errors_naming_the_file() {
    let dir = scratch("restart-bad");
    let out = path(&dir);
    let state = slider_crank_state(&dir);
    let corrupt = dir.join("corrupt.json");
    std::fs::write(&corrupt, "{\"version\": 1, \"t\": ").unwrap();
    let e = fail(&["run", "models/slider_crank.toml", "--quiet", "--out", out, "--resume", path(&corrupt)]);
    assert!(e.contains(&format!("{}: not a simulation checkpoint written by `flexmb run --save-state`", corrupt.display())), "{e}");
    let missing = dir.join("missing.json");
    let e = fail(&["run", "models/slider_crank.toml", "--quiet", "--out", out, "--resume", path(&missing)]);
    assert!(e.contains(&format!("cannot read {}", missing.display())), "{e}");
    let e = fail(&["run", "models/pendulum.toml", "--quiet", "--out", out, "--resume", path(&state)]);
    assert!(e.contains(&format!("{}: the checkpoint does not fit the model", state.display())), "{e}");
    let e = fail(&["run", "models/slider_crank.toml", "--integrator", "adams", "--quiet", "--out", out, "--resume", path(&state)]);
    assert!(e.contains(&format!("{}: the checkpoint is of the bdf method, the simulation uses adams", state.display())), "{e}");
    let e = fail(&["run", "models/slider_crank.toml", "--t-end", "0.1", "--quiet", "--out", out, "--resume", path(&state)]);
    assert!(e.contains(&format!("{}: the checkpoint is at t = 0.2 s, after the end time 0.1 s", state.display())), "{e}");
    assert!(!e.contains("panicked"), "{e}");
}
