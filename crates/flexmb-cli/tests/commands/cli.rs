//! The `flexmb` program as a new user runs it: shipped models, result files, and errors.


use crate::program;

use program::{flexmb, scratch, text};

#[test]
fn run_writes_csv_and_summary_for_a_shipped_model() {
    let out = scratch("run");
    let o = flexmb(&["run", "models/pendulum.toml", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "stdout:\n{}\nstderr:\n{}", text(&o.stdout), text(&o.stderr));
    let stdout = text(&o.stdout);
    assert!(stdout.contains("degrees of freedom: 1"), "{stdout}");
    assert!(stdout.contains("run completed"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("pendulum.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(header[0], "t");
    let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    // t_end = 5 s, output_step = 0.01 s: 501 rows from 0 to 5 inclusive, evenly spaced.
    assert_eq!(rows.len(), 501);
    for (k, r) in rows.iter().enumerate() {
        assert!((r[0] - 0.01 * k as f64).abs() < 1e-12, "row {k}: t = {}", r[0]);
        assert_eq!(r.len(), header.len());
    }
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("pendulum.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "completed");
    assert_eq!(summary["t_reached"].as_f64().unwrap(), 5.0);
    let stats = &summary["statistics"];
    for key in ["steps", "rejected_steps", "newton_iterations", "matrix_factorizations", "jacobian_evaluations"] {
        assert!(stats[key].as_u64().is_some(), "statistics.{key} missing: {stats}");
    }
    assert!(stats["steps"].as_u64().unwrap() > 10);
    assert!(stats["rms_step_size"].as_f64().unwrap() > 0.0);
    assert!(summary["constraints"]["at_steps"]["position"].as_f64().unwrap() < 1e-6);
    assert!(summary["constraints"]["max_euler_parameter_norm_error"].as_f64().unwrap() < 1e-14);
}

/// The residuals at the accepted steps are those of the states the integrator solved for; the CSV rows
/// hold states interpolated between steps, whose residuals are larger (four-bar: 14 times in position,
/// 28 in velocity). The summary gives both, and the at-outputs ones are the largest of the CSV's.
#[test]
fn constraint_residuals_are_reported_at_the_steps_and_at_the_output_times() {
    let out = scratch("residuals");
    let stdout = program::succeed(&["run", "models/four_bar.toml", "--out", out.to_str().unwrap()]);
    let line = |label: &str| stdout.lines().find(|l| l.contains(label)).unwrap_or_else(|| panic!("{label}: {stdout}")).to_string();
    assert!(line("constraint residual at steps").contains("position"), "{stdout}");
    assert!(line("constraint residual at output times (interpolated)").contains("velocity"), "{stdout}");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("four_bar.json")).unwrap()).unwrap();
    let csv = program::ResultCsv::read(&out.join("four_bar.csv"));
    let constraints = &summary["constraints"];
    for kind in ["position", "velocity"] {
        let at_steps = constraints["at_steps"][kind].as_f64().unwrap();
        let at_outputs = constraints["at_outputs"][kind].as_f64().unwrap();
        let largest_in_csv = csv.column(&format!("constraint_residual.{kind}")).into_iter().fold(0.0, f64::max);
        assert!((at_outputs - largest_in_csv).abs() <= 1e-9 * largest_in_csv, "{kind}: {at_outputs} against the CSV's {largest_in_csv}");
        assert!(at_steps > 0.0 && at_outputs > 3.0 * at_steps, "{kind}: at steps {at_steps:e}, at outputs {at_outputs:e}");
    }
}

#[test]
fn command_line_overrides_the_model_settings() {
    let out = scratch("override");
    let o = flexmb(&["run", "models/slider_crank.toml", "--t-end", "0.5", "--output-step", "0.1", "--rtol", "1e-8", "--atol", "1e-8", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(o.stdout.is_empty(), "--quiet prints nothing: {}", text(&o.stdout));
    let csv = std::fs::read_to_string(out.join("slider_crank.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 6, "header and t = 0, 0.1, …, 0.5");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("slider_crank.json")).unwrap()).unwrap();
    assert_eq!(summary["settings"]["rtol"].as_f64().unwrap(), 1e-8);
}

/// A tolerance below what double precision delivers is raised to 1e-12, and the run says so: in the
/// summary it prints and in the JSON's warnings. `--tolerance-span` is taken.
#[test]
fn a_tolerance_below_double_precision_is_raised_with_a_warning() {
    let out = scratch("finest-tolerance");
    let o = flexmb(&["run", "models/pendulum.toml", "--t-end", "0.2", "--rtol", "1e-15", "--atol", "1e-6", "--tolerance-span", "1", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let printed = text(&o.stdout);
    assert!(printed.contains("warning at t = 0.0000 s: tolerance finer than double precision can deliver: rtol 1e-15 raised to 1e-12"), "{printed}");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("pendulum.json")).unwrap()).unwrap();
    assert_eq!(summary["warnings"][0]["kind"], "tolerance", "{}", summary["warnings"]);
    assert_eq!(summary["status"], "completed");
    let o = flexmb(&["run", "models/pendulum.toml", "--tolerance-span", "0", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success() && text(&o.stderr).contains("--tolerance-span must be a positive number"), "{}", text(&o.stderr));
    // The run's length (the default) and the classical error per step are spelt out; other words are not.
    let steps = |span: &str| {
        let o = flexmb(&["run", "models/pendulum.toml", "--t-end", "0.5", "--tolerance-span", span, "--quiet", "--out", out.to_str().unwrap()]);
        assert!(o.status.success(), "{span}: {}", text(&o.stderr));
        let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("pendulum.json")).unwrap()).unwrap();
        summary["statistics"]["steps"].as_u64().unwrap()
    };
    assert_eq!(steps("run"), steps("0.5"), "the run's span is its length");
    let o = flexmb(&["run", "models/pendulum.toml", "--t-end", "0.5", "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("pendulum.json")).unwrap()).unwrap();
    assert_eq!(summary["statistics"]["steps"].as_u64().unwrap(), steps("run"), "the default is error per unit step over the run");
    assert!(steps("step") < steps("run"), "each step the whole tolerance takes fewer steps");
    let o = flexmb(&["run", "models/pendulum.toml", "--tolerance-span", "steps", "--out", out.to_str().unwrap()]);
    assert!(!o.status.success() && text(&o.stderr).contains("`run`, `step` or a positive number of seconds"), "{}", text(&o.stderr));
}

/// The generalized-α method over the run's span (the default) raises a tolerance below the finest it keeps,
/// 1e-7, to it, and says so in the summary it prints and in the JSON's warnings; with the span given
/// explicitly the tolerance is taken as given, silently.
#[test]
fn generalized_alpha_raises_a_tolerance_finer_than_it_keeps_over_the_run_with_a_warning() {
    let out = scratch("gen-alpha-finest-tolerance");
    let run = |span: &[&str]| {
        let mut args = vec!["run", "models/pendulum.toml", "--integrator", "gen-alpha", "--t-end", "0.1", "--rtol", "1e-9", "--atol", "1e-9"];
        args.extend_from_slice(span);
        args.extend_from_slice(&["--out", out.to_str().unwrap()]);
        let o = flexmb(&args);
        assert!(o.status.success(), "{}", text(&o.stderr));
        let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("pendulum.json")).unwrap()).unwrap();
        assert_eq!(summary["status"], "completed");
        (text(&o.stdout), summary)
    };
    let (printed, summary) = run(&[]);
    assert!(
        printed.contains("warning at t = 0.0000 s: tolerance finer than the generalized-α method keeps over the run: rtol 1e-9 raised to 1e-7, atol 1e-9 raised to 1e-7"),
        "{printed}"
    );
    assert!(printed.contains("use the BDF or the Adams method"), "{printed}");
    assert_eq!(summary["warnings"][0]["kind"], "tolerance", "{}", summary["warnings"]);
    let (printed, summary) = run(&["--tolerance-span", "step"]);
    assert!(!printed.contains("tolerance finer"), "{printed}");
    assert_eq!(summary["warnings"].as_array().map_or(0, Vec::len), 0, "{}", summary["warnings"]);
}

#[test]
fn check_reports_degrees_of_freedom_and_redundant_constraints() {
    let o = flexmb(&["check", "models/slider_crank.toml"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = text(&o.stdout);
    assert!(s.contains("degrees of freedom: 0") && s.contains("redundant constraints: none"), "{s}");

}

/// `flexmb check M | head`: a standard output whose reader has gone ends the program by SIGPIPE, as it
/// ends other Unix tools, not by a panic at the first line printed. The pipe's read end is closed before
/// the program starts, so its first write meets it closed.
#[test]
fn a_closed_standard_output_ends_the_program_by_sigpipe_not_a_panic() {
    use std::os::unix::process::ExitStatusExt;
    let (reader, writer) = std::io::pipe().unwrap();
    drop(reader);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_flexmb"))
        .args(["check", "models/slider_crank.toml"])
        .current_dir(program::workspace())
        .stdout(writer)
        .output()
        .unwrap();
    let e = text(&o.stderr);
    assert!(!e.contains("panicked") && !e.contains("Broken pipe"), "{e}");
    assert_eq!(o.status.signal(), Some(13), "ended by SIGPIPE: {:?}", o.status);
}

#[test]
fn bad_input_names_file_line_and_key() {
    let dir = scratch("bad");
    let model = dir.join("bad_mass.toml");
    std::fs::write(&model, "[model]\n[[body]]\nname = \"b\"\nmass = -1.0\ninertia = [1, 1, 1]\n").unwrap();
    let o = flexmb(&["run", model.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = text(&o.stderr);
    assert!(e.contains("bad_mass.toml:4") && e.contains("body[0].mass"), "{e}");
    assert!(!e.contains("panicked"), "{e}");

    let o = flexmb(&["run", "no/such/model.toml"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("no/such/model.toml"), "{}", text(&o.stderr));

    let o = flexmb(&["run", "models/pendulum.toml", "--t-end=-1"]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("--t-end"), "{}", text(&o.stderr));
}

#[test]
fn a_run_that_fails_midway_says_when_and_why_and_keeps_its_results() {
    let dir = scratch("lock");
    let model = dir.join("lock.toml");
    std::fs::write(&model, LOCKING).unwrap();
    let out = dir.join("out");
    let o = flexmb(&["run", model.to_str().unwrap(), "--out", out.to_str().unwrap()]);
    assert!(!o.status.success(), "the crank cannot follow the driver past t = 1 s");
    let e = text(&o.stderr);
    assert!(e.contains("t = 0.99") || e.contains("t = 1.0"), "the failure time is near 1 s: {e}");
    assert!(e.contains("joint '"), "an equation is named: {e}");
    let csv = std::fs::read_to_string(out.join("lock.csv")).unwrap();
    let rows = csv.lines().count() - 1;
    assert!(rows >= 90, "rows up to the failure are kept: {rows}");
    let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("lock.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    assert!(summary["error"].as_str().unwrap().contains("too small"));
}

/// A bar on a revolute to ground whose tip is pulled by a distance driver `L(t) = 2 + t` from a ground
/// point 2 m away: the tip can be at most 3 m from that point, reached at t = 1 s, after which the
/// constraints cannot all hold.
const LOCKING: &str = r#"[model]
[simulation]
t_end = 2.0
output_step = 0.01

[[body]]
name = "bar"
mass = 1.0
inertia = [0.01, 0.1, 0.1]
center_of_mass = [0.5, 0, 0]
orientation = { axis = [0, 0, 1], angle = 1.5707963267948966 }

[[marker]]
name = "pivot_ground"
body = "ground"

[[marker]]
name = "pivot"
body = "bar"

[[marker]]
name = "tip"
body = "bar"
origin = [1, 0, 0]

[[marker]]
name = "anchor"
body = "ground"
origin = [2, 0, 0]

[[joint]]
name = "hinge"
type = "revolute"
i = "pivot_ground"
j = "pivot"

[[joint]]
name = "pull"
type = "distance"
i = "anchor"
j = "tip"
length = "sqrt(5) + (3 - sqrt(5))*t"
"#;

/// The README's main job, exactly as the README runs it: the seed's door, opened 30° on misaligned
/// hinges and released, swings through the closed position to the other side and back while its
/// energy (kinetic plus strain; no damping, no gravity) stays constant; the CSV holds every output time.
#[test]
fn the_readme_main_job_runs_the_door() {
    let readme = std::fs::read_to_string(program::workspace().join("README.md")).unwrap();
    assert!(readme.contains("cargo run --release -- run models/door/door.toml"), "the README's main job is the door");
    let out = scratch("readme");
    let o = flexmb(&["run", "models/door/door.toml", "--out", out.to_str().unwrap()]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "stdout:\n{stdout}\nstderr:\n{}", text(&o.stderr));
    assert!(stdout.contains("run completed") && stdout.contains("O1 12.56 Hz") && stdout.contains("RMS step size"), "{stdout}");
    let csv = program::ResultCsv::read(&out.join("door.csv"));
    assert_eq!(csv.rows.len(), 401, "2 s at 0.005 s");
    let x = csv.column("door.node11.position.x");
    let (closed_side, open_side) = (x.iter().copied().fold(f64::INFINITY, f64::min), x.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    assert!(closed_side < -0.22 && open_side > 0.22, "the centre swings from {closed_side} m to {open_side} m");
    let energy = csv.column("energy.total");
    let drift = energy.iter().map(|e| (e - energy[0]).abs()).fold(0.0, f64::max);
    assert!(energy[0] > 30.0 && drift < 1e-3 * energy[0], "energy {} J drifts by {drift} J", energy[0]);
}

/// `flexmb compare` prints the seed's columns for each integrator and the reference it measured against.
#[test]
fn compare_prints_a_row_per_integrator_and_the_reference() {
    let o = flexmb(&["compare", "models/slider_crank.toml", "--integrators", "bdf", "--t-end", "0.5"]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "stdout:\n{stdout}\nstderr:\n{}", text(&o.stderr));
    assert!(stdout.contains("T_end [s]") && stdout.contains("CPU [s]") && stdout.contains("RMS step [s]"), "{stdout}");
    let row = stdout.lines().find(|l| l.starts_with("bdf")).expect("a bdf row");
    let error: f64 = row.split_whitespace().nth(7).unwrap().parse().unwrap();
    assert!(error > 0.0 && error < 1e-5, "bdf at rtol 1e-6 is within 1e-5 m of the reference: {row}");
    assert!(stdout.contains("reference: bdf (orders up to 5) at rtol 1e-9"), "{stdout}");
    let o = flexmb(&["compare", "models/slider_crank.toml", "--integrators", "euler"]);
    assert!(!o.status.success() && text(&o.stderr).contains("unknown integrator `euler`"), "{}", text(&o.stderr));
}

/// Every integrator runs a shipped model from the command line and the summary says which one ran.
#[test]
fn run_with_each_integrator() {
    for name in ["bdf", "adams", "gen-alpha"] {
        let out = scratch(&format!("integrator-{name}"));
        let o = flexmb(&["run", "models/pendulum.toml", "--integrator", name, "--t-end", "1", "--quiet", "--out", out.to_str().unwrap()]);
        assert!(o.status.success(), "{name}: {}", text(&o.stderr));
        let summary: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(out.join("pendulum.json")).unwrap()).unwrap();
        let shown = summary.to_string();
        assert!(shown.contains(&format!("\"integrator\":\"{name}\"")), "{name}: {shown}");
    }
    let o = flexmb(&["run", "models/pendulum.toml", "--integrator", "rk4"]);
    assert!(!o.status.success() && text(&o.stderr).contains("--integrator: unknown integrator `rk4`"), "{}", text(&o.stderr));
}
