//! A run that has left physics stops and says so (issue 14): a flexible beam spun up past its first
//! bending frequency, whose linear modal model has no centrifugal stiffening, warns and then stops with
//! a diagnosis long before the step size collapses; an oscillator integrated far too loosely stops on
//! its energy balance; the shipped models run without a warning; the thresholds are `[simulation]`
//! settings.

use crate::program;

use std::path::Path;

use program::{flexmb, scratch, text, workspace, ResultCsv};

/// The spin-up beam (Kane, Ryan and Banerjee 1987): 10 m, hub spun up to 6 rad/s over 15 s, first
/// bending frequency 3.80 rad/s. Without the watchdog its tip deflection grows to 72 m at 10 s and
/// 8e8 m at 14 s, where the step size collapses ("step size too small at t = 14.187101 s").
const SPIN_UP: &str = "crates/flexmb-cli/tests/models/spin_up/spin_up.toml";

fn summary(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

/// Every line of a result CSV is whole: as many values as the header has columns, each a number.
fn complete_rows(csv: &Path) -> ResultCsv {
    let table = ResultCsv::read(csv);
    for (k, row) in table.rows.iter().enumerate() {
        assert_eq!(row.len(), table.header.len(), "row {k} of {}", csv.display());
    }
    table
}

#[test]
fn a_beam_spun_past_its_bending_frequency_warns_then_stops_with_a_diagnosis() {
    let out = scratch("spin-up");
    let o = flexmb(&["run", SPIN_UP, "--out", out.to_str().unwrap()]);
    let (stdout, stderr) = (text(&o.stdout), text(&o.stderr));
    assert!(!o.status.success(), "the run stops: {stdout}");
    assert!(!stderr.contains("panicked"), "{stderr}");
    for part in [
        "simulation failed: the run has left physics",
        "the elastic displacement of flexible body 'beam'",
        "at node 11",
        "of its size 10.000 m ([simulation] elastic_deflection_limit = 0.5)",
        "above its lowest modal frequency 3.798 rad/s",
        "without geometric (centrifugal) stiffening",
        "split it into several flexible bodies",
    ] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    assert!(stdout.contains("run stopped early") && stdout.contains("warning at t = "), "{stdout}");

    // The rows up to the stop are all there; the last one is where the deflection crossed half the
    // beam's length: between 8 and 10 s, well before the step size collapsed (14.2 s; 17 s in the
    // issue's run).
    let csv = complete_rows(&out.join("spin_up.csv"));
    let t_stop = csv.at(-1, "t");
    assert!((8.0..10.0).contains(&t_stop), "stopped at t = {t_stop} s");
    assert_eq!(csv.rows.len(), (t_stop / 0.01).round() as usize + 1, "one row per output time up to the stop");
    let tip = |row: isize| {
        let axis = |a: &str| csv.at(row, &format!("beam.node11.deformation.{a}"));
        (axis("x").powi(2) + axis("y").powi(2) + axis("z").powi(2)).sqrt()
    };
    assert!(tip(-1) >= 5.0 && tip(-2) < 5.0, "the last row crossed 5 m: {} m, before it {} m", tip(-1), tip(-2));

    let s = summary(&out.join("spin_up.json"));
    assert_eq!(s["status"], "failed");
    assert!(s["error"].as_str().unwrap().contains("elastic_deflection_limit"), "{}", s["error"]);
    let warnings = s["warnings"].as_array().unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0]["kind"], "elastic_deflection");
    let t_warning = warnings[0]["t"].as_f64().unwrap();
    assert!((6.0..t_stop - 1.0).contains(&t_warning), "warned at 10 % of the length at t = {t_warning} s");
    assert!(warnings[0]["message"].as_str().unwrap().contains("elastic_deflection_warning = 0.1"));
    let deflection = &s["physics_checks"]["elastic_deflection"];
    assert_eq!(deflection["warning"], 0.1);
    assert_eq!(deflection["limit"], 0.5);
    let largest = deflection["largest"]["deflection"].as_f64().unwrap();
    assert!((largest - tip(-1)).abs() < 1e-9 * largest, "{largest} m is the tip's {} m", tip(-1));
}

/// The spin-up model with `settings` added to its `[simulation]`, in `dir` (its FE model stays where it is).
fn spin_up_with(dir: &Path, settings: &str) -> std::path::PathBuf {
    let fixture = workspace().join(SPIN_UP);
    let fe_model = fixture.with_file_name("spin_up_beam.toml");
    let text = std::fs::read_to_string(&fixture)
        .unwrap()
        .replace("[simulation]\n", &format!("[simulation]\n{settings}\n"))
        .replace("fe_model = \"spin_up_beam.toml\"", &format!("fe_model = {:?}", fe_model.to_str().unwrap()));
    let model = dir.join("spin_up.toml");
    std::fs::write(&model, text).unwrap();
    model
}

#[test]
fn the_thresholds_are_settings_of_the_model_file() {
    // Stricter: stop at 20 % of the length, warn (by default at 10 %) before.
    let dir = scratch("spin-up-strict");
    let model = spin_up_with(&dir, "elastic_deflection_limit = 0.2");
    let o = flexmb(&["run", model.to_str().unwrap(), "--quiet", "--out", dir.to_str().unwrap()]);
    assert!(!o.status.success());
    assert!(text(&o.stderr).contains("elastic_deflection_limit = 0.2"), "{}", text(&o.stderr));
    let strict_stop = complete_rows(&dir.join("spin_up.csv")).at(-1, "t");
    assert!((7.0..8.5).contains(&strict_stop), "stopped at t = {strict_stop} s");

    // Out of the way: the run goes on to the failure it had before the watchdog, each step its whole
    // tolerance as that failure was found (over the run's span the diverging beam is followed past 14 s
    // with ever shorter steps for minutes before it fails).
    let dir = scratch("spin-up-off");
    let model = spin_up_with(&dir, "elastic_deflection_warning = 1e9\ntolerance_span = \"step\"");
    let o = flexmb(&["run", model.to_str().unwrap(), "--quiet", "--out", dir.to_str().unwrap()]);
    let stderr = text(&o.stderr);
    assert!(!o.status.success() && stderr.contains("too small at t = 1"), "{stderr}");
    let s = summary(&dir.join("spin_up.json"));
    assert!(s["t_reached"].as_f64().unwrap() > 12.0, "{}", s["t_reached"]);
    assert_eq!(s["physics_checks"]["elastic_deflection"]["limit"], 1e9, "a limit not given is at least the warning");
    // No warning of the watchdog's; on the approach to the failure the integrator may say its Newton
    // increments reached the residual's rounding (a `tolerance` warning, not a physics check).
    let watchdog_warnings: Vec<_> = s["warnings"].as_array().unwrap().iter().filter(|w| w["kind"] != "tolerance").collect();
    assert!(watchdog_warnings.is_empty(), "{}", s["warnings"]);

    // A warning above its limit is a located error.
    let dir = scratch("spin-up-inconsistent");
    let model = spin_up_with(&dir, "energy_balance_warning = 0.3\nenergy_balance_limit = 0.2");
    let o = flexmb(&["run", model.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    let stderr = text(&o.stderr);
    assert!(!o.status.success(), "{stderr}");
    assert!(
        stderr.contains("spin_up.toml:") && stderr.contains("simulation.energy_balance_warning: energy_balance_warning (0.3) must not exceed energy_balance_limit (0.2)"),
        "{stderr}"
    );
    let model = spin_up_with(&dir, "elastic_deflection_warning = -0.1");
    let stderr = text(&flexmb(&["check", model.to_str().unwrap()]).stderr);
    assert!(stderr.contains("simulation.elastic_deflection_warning: elastic_deflection_warning must be positive"), "{stderr}");
}

/// The shipped oscillator (m = 2 kg, k = 2000 N/m, 5 % damping) at a tolerance of 3e-3 instead of its
/// 1e-8, each step its whole tolerance: the BDF's orders 3–5 amplify the lightly damped vibration, the
/// damper dissipates five times the energy the block ever had, and the balance says so. (Over the run's
/// span the same tolerance is accurate, 313 steps with the balance within 0.4 %: a run that loose must
/// ask for the error per step.)
#[test]
fn an_oscillator_integrated_far_too_loosely_stops_on_its_energy_balance() {
    let out = scratch("loose-oscillator");
    let args = ["run", "models/oscillator.toml", "--rtol", "3e-3", "--atol", "3e-3", "--tolerance-span", "step", "--out", out.to_str().unwrap()];
    let o = flexmb(&args);
    let stderr = text(&o.stderr);
    assert!(!o.status.success(), "{}", text(&o.stdout));
    for part in ["the run has left physics", "the energy balance is off by", "energy_balance_limit = 0.5", "tighten rtol and atol"] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    let s = summary(&out.join("oscillator.json"));
    let warnings = s["warnings"].as_array().unwrap();
    assert!(warnings.iter().any(|w| w["kind"] == "energy_balance"), "{warnings:?}");
    assert!(s["physics_checks"]["energy_balance"]["largest_fraction"].as_f64().unwrap() >= 0.5);
    complete_rows(&out.join("oscillator.csv"));
}

/// The model files shipped in `models/` (not the FE models nor the studies).
fn shipped_models() -> Vec<String> {
    let mut models = Vec::new();
    let mut dirs = vec![workspace().join("models")];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "toml") {
                let text = std::fs::read_to_string(&path).unwrap();
                let mechanism = text.contains("\n[[body]]") || text.contains("\n[[flexible_body]]");
                if mechanism && !text.contains("\n[fe_model]") {
                    models.push(path.strip_prefix(workspace()).unwrap().display().to_string());
                }
            }
        }
    }
    models.sort();
    models
}

/// Every shipped model, with its own end time, tolerances and thresholds, completes without a warning
/// but the chaotic double pendulum's, whose file turns on the divergence check: one `tolerance` warning,
/// neighbouring trajectories separating exponentially (docs/accuracy.md, *Chaotic motion: the divergence
/// check*), and the four-bar's, whose file turns on global error control: its first run's global
/// error is estimated at 18 tolerances (1.8e-5 against the 1.8e-5 of a run of Adams at 1e-12), the run
/// made again at the rtol that estimate asks for keeps the tolerance and passes without a warning
/// (docs/accuracy.md, *Global error control*) (the A01 pendulum
/// over 2,000 s at rtol 1e-8 runs the Adams method, which its file sets: with the BDF its steps held to the
/// share floor add up to more than rtol and the run warns); the largest deflection is the wiper
/// arm's 5.6 % of its length (warning at 10 %), the largest
/// energy-balance error 8e-4 of the energy that flowed (the double pendulum's first output step; warning at 5 %).
#[test]
fn the_shipped_models_run_without_warnings() {
    let models = shipped_models();
    assert!(models.len() >= 11 && models.iter().any(|m| m.ends_with("door.toml")), "{models:?}");
    for model in &models {
        let out = scratch(&format!("shipped-{}", model.replace('/', "-")));
        let o = flexmb(&["run", model, "--quiet", "--out", out.to_str().unwrap()]);
        assert!(o.status.success(), "{model}: {}", text(&o.stderr));
        let stem = Path::new(model).file_stem().unwrap().to_str().unwrap();
        let s = summary(&out.join(format!("{stem}.json")));
        assert_eq!(s["status"], "completed", "{model}");
        let warnings = s["warnings"].as_array().unwrap();
        if model.ends_with("double_pendulum.toml") {
            let chaotic = |w: &serde_json::Value| w["kind"] == "tolerance" && w["message"].as_str().unwrap().contains("separate exponentially");
            assert!(warnings.len() == 1 && chaotic(&warnings[0]), "{model}: {}", s["warnings"]);
        } else if model.ends_with("/four_bar.toml") {
            // Global error control: the first run at rtol 1e-6 is estimated 15 to 25 tolerances off, the
            // run made again finer is estimated within 10 and passes without a warning.
            let control = &s["statistics"]["global_error_control"];
            let earlier = control["earlier_runs"].as_array().unwrap();
            assert!(earlier.len() == 1, "{model}: {control}");
            let first = earlier[0]["tolerances"].as_f64().unwrap();
            assert!((15.0..25.0).contains(&first), "{model}: {control}");
            let last = s["statistics"]["global_error_estimate"]["tolerances"].as_f64().unwrap();
            assert!(last < 10.0 && control["rtol"].as_f64().unwrap() < 1e-7, "{model}: {control}");
            assert!(warnings.is_empty(), "{model}: {}", s["warnings"]);
        } else {
            assert!(warnings.is_empty(), "{model}: {}", s["warnings"]);
        }
        let checks = &s["physics_checks"];
        let deflection = checks["elastic_deflection"]["largest_fraction"].as_f64().unwrap_or(0.0);
        let balance = checks["energy_balance"]["largest_fraction"].as_f64().unwrap();
        assert!(deflection < 0.07 && balance < 2e-3, "{model}: deflection {deflection}, energy balance {balance}");
    }
}

/// A body welded to ground in zero gravity, given an initial angular velocity that the velocity
/// analysis removes: its energy stays at round-off (about 1e-32 J), which is then the whole of the
/// energy that flowed. The energy balance must not call that a departure from physics (found by the
/// fuzz test, seed 7 case 33: "off by -3.960e-32 J, 100.0 % of the 3.960e-32 J of energy that flowed").
#[test]
fn a_body_held_at_rest_runs_through_the_round_off_of_its_zero_energy() {
    let dir = scratch("held-at-rest");
    let model = dir.join("held.toml");
    std::fs::write(
        &model,
        r#"[model]
name = "held"
gravity = [0.0, 0.0, 0.0]

[simulation]
t_end = 0.05
output_step = 0.025
max_order = 4

[[body]]
name = "b0"
mass = 4.113127631074436
inertia = { xx = 0.04828546833206117, yy = 0.05278151945595155, zz = 0.040661646464409174, xy = 0.013675342707786201, xz = -0.00268651004659126, yz = 0.0009450002946651973 }
position = [0.09417998576179709, -0.40576505056582124, 0.8489585665900636]
orientation = { euler_parameters = [0.6645696871216381, -0.638030644827833, -0.3038662512551447, -0.24275363759946617] }
angular_velocity = [-0.8847151006259586, 0.18658561641615923, 0.4655763229817371]

[[marker]]
name = "k0"
body = "ground"
origin = [0.17122340600992736, -0.6097105256750491, 0.4445113544682123]
z_axis = [-1.9867522395599388, 0.7857065118508901, -2.1060581226164383]
x_axis = [0.3128615234647771, -0.754684344151108, -0.5766881374092161]

[[marker]]
name = "k1"
body = "b0"
origin = [-0.24817432553959784, 0.3241850720319041, -0.2107617992636031]
orientation = { matrix = [[-0.2424696965269243, -0.21582675843003996, -0.9458473749034368], [0.574930149171068, -0.8172675887144534, 0.03910258317549742], [-0.781449787152236, -0.5343149808703145, 0.32224793463617557]] }

[[joint]]
name = "j0"
type = "fixed"
i = "k0"
j = "k1"

[[output]]
name = "velocity"
type = "marker_velocity"
marker = "k1"
"#,
    )
    .unwrap();
    let out = dir.join("out");
    let o = flexmb(&["run", model.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = summary(&out.join("held.json"));
    assert_eq!(s["status"], "completed");
    assert!(s["warnings"].as_array().unwrap().is_empty(), "{}", s["warnings"]);
    // The marker stays at rest: every velocity component in the CSV is round-off.
    let table = complete_rows(&out.join("held.csv"));
    for row in &table.rows {
        assert!(row[1..].iter().all(|x| x.abs() < 1e-12), "{row:?}");
    }
}

/// The shipped oscillator made heavily damped (ζ = 2) and released 0.4 m from its free length, with
/// output every 0.1 s: the damper takes the 160 J of the spring within the first 0.05 s, between the
/// first two output times. The balance integrates the dampers' power over the steps as well as the
/// output times, so it sees that work; over the output times alone it saw half of it, and the run
/// warned at t = 0.1 s that the balance was off by 92 J, 58 % of the energy (found by the fuzz test,
/// seed 7 case 1381: a spring released far from its length stopped as having "left physics", "off by
/// -1.690e3 J, 92.0 % of the 1.836e3 J of energy that flowed", whatever the tolerance).
#[test]
fn a_transient_shorter_than_the_output_step_keeps_the_energy_balance() {
    let dir = scratch("fast-transient");
    let text_of = std::fs::read_to_string(workspace().join("models/oscillator.toml")).unwrap();
    let model = dir.join("oscillator.toml");
    let changed = text_of
        .replace("zeta = 0.05 ", "zeta = 2.0  ")
        .replace("x0 = 0.01 ", "x0 = 0.4  ")
        .replace("t_end = 4.0 ", "t_end = 1.0 ")
        .replace("output_step = 0.001 ", "output_step = 0.1   ");
    assert!(changed.contains("zeta = 2.0") && changed.contains("x0 = 0.4") && changed.contains("output_step = 0.1 "));
    std::fs::write(&model, changed).unwrap();
    let out = dir.join("out");
    let o = flexmb(&["run", model.to_str().unwrap(), "--quiet", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let s = summary(&out.join("oscillator.json"));
    assert!(s["warnings"].as_array().unwrap().is_empty(), "{}", s["warnings"]);
    // The spring's 160 J (k x0² / 2) are dissipated: the work of the non-conservative forces is −160 J
    // to 1e-3 (the trapezoidal rule over the steps: −160.023 J), and the energy change matches it to
    // the same.
    let energy = &s["energy"];
    let work = energy["nonconservative_work"].as_f64().unwrap();
    let change = energy["final"].as_f64().unwrap() - energy["initial"].as_f64().unwrap();
    assert!((work + 160.0).abs() < 0.16, "work {work} J");
    assert!((change - work).abs() < 0.16, "change {change} J, work {work} J");
}
