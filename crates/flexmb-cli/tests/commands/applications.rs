//! The seed's two applications, as a user runs them (`flexmb study`), at reduced end times: the
//! flexible hinged door with its four mode sets and two integrators, and the windshield wiper with
//! flexible and rigid arms. What the seed observed, checked on the whole trajectories:
//!
//! - door: 4N5S follows 5S closely while 5N (and 9N) swing at a far higher frequency; the Adams and
//!   BDF runs of each set agree; with neither damping nor gravity the energy stays constant;
//! - wiper: the flexible and rigid mechanisms make the same gross motion, and the flexible arm's tip
//!   velocity carries a vibration near the arm's first in-plane bending frequency that the rigid one
//!   lacks.

use crate::program;

use program::{largest_difference, scratch, succeed, ResultCsv};

#[test]
fn door_mode_sets_reproduce_the_seeds_observations() {
    let out = scratch("door-study");
    let out_text = out.to_str().unwrap();
    let table = succeed(&["study", "models/door/study.toml", "--t-end", "0.6", "--out", out_text, "--quiet"]);
    for case in ["5S", "5N", "9N", "4N5S"] {
        for integrator in ["bdf", "adams"] {
            assert!(table.contains(&format!("| {case} | {integrator} | 0.6 |")), "{case} {integrator} completed:\n{table}");
        }
    }
    assert!(out.join("table.md").is_file() && out.join("door.node11.position.x-bdf.png").is_file());
    let x = |run: &str| ResultCsv::read(&out.join(format!("{run}.csv"))).column("door.node11.position.x");
    let s5 = x("5S-bdf");
    // The door starts opened by 30°: its centre (0.45 m from the hinge line) at x = −0.45 sin 30°,
    // less the small static deflection that fits it to the misaligned hinges.
    assert!((s5[0] + 0.225).abs() < 2e-3, "x(0) = {}", s5[0]);
    // Static correction modes dominate: adding four vibration modes changes the swing by little (the
    // measured 1.2 mm of a 0.45 m swing), while vibration modes alone make the door far stiffer.
    let with_vibration = largest_difference(&s5, &x("4N5S-bdf"));
    let vibration_only = largest_difference(&s5, &x("5N-bdf"));
    println!("door: |5S − 4N5S| = {with_vibration:.2e} m, |5S − 5N| = {vibration_only:.2e} m");
    assert!(with_vibration < 5e-3, "4N5S differs from 5S by {with_vibration} m");
    assert!(vibration_only > 0.2, "5N differs from 5S by only {vibration_only} m");
    assert!(largest_difference(&s5, &x("9N-bdf")) > 0.2);
    // 5S swings back through the closed position once in 0.6 s; 5N swings several times.
    let crossings = |x: &[f64]| x.windows(2).filter(|w| w[0] < 0.0 && w[1] >= 0.0 || w[0] > 0.0 && w[1] <= 0.0).count();
    assert_eq!(crossings(&s5), 1);
    assert!(crossings(&x("5N-bdf")) >= 8, "5N crossings {}", crossings(&x("5N-bdf")));
    // The two integrators agree on every set (tolerance 1e-6 on both).
    for case in ["5S", "5N", "9N", "4N5S"] {
        let d = largest_difference(&x(&format!("{case}-bdf")), &x(&format!("{case}-adams")));
        assert!(d < 1e-3, "{case}: BDF and Adams differ by {d} m");
    }
    // The seed's cost signature: keeping the vibration modes (4N5S) over 5S, the same motion, costs the
    // non-stiff Adams method many times the steps, its step limited by stability; the BDF on its
    // A-stable orders (bdf:2) follows the motion and hardly needs more.
    let steps = |case: &str, integrator: &str| -> f64 {
        let row = table.lines().find(|l| l.starts_with(&format!("| {case} | {integrator} |"))).unwrap();
        row.split('|').nth(6).unwrap().trim().parse().unwrap()
    };
    let adams_growth = steps("4N5S", "adams") / steps("5S", "adams");
    let bdf_growth = steps("4N5S", "bdf:2") / steps("5S", "bdf:2");
    println!("door: steps 4N5S / 5S: Adams {adams_growth:.1}, BDF (orders 1-2) {bdf_growth:.1}");
    assert!(adams_growth > 8.0 && bdf_growth < 3.0, "Adams ×{adams_growth}, BDF ×{bdf_growth}");
    // No damping and no gravity: kinetic plus strain energy is constant.
    for case in ["5S", "4N5S"] {
        let e = ResultCsv::read(&out.join(format!("{case}-adams.csv"))).column("energy.total");
        let drift = e.iter().map(|v| (v - e[0]).abs()).fold(0.0, f64::max) / e[0];
        assert!(drift < 1e-4, "{case}: energy drifts by {drift:e} of {} J", e[0]);
    }
}

#[test]
fn wiper_arms_vibrate_over_the_rigid_gross_motion() {
    let out = scratch("wiper-study");
    let out_text = out.to_str().unwrap();
    succeed(&["study", "models/wiper/study.toml", "--t-end", "1.0", "--out", out_text, "--quiet"]);
    let flexible = ResultCsv::read(&out.join("flexible-bdf.csv"));
    let rigid = ResultCsv::read(&out.join("rigid-bdf.csv"));
    // The same gross motion: the arm swings ±0.8 rad in both, within 0.03 rad of each other.
    let angle = flexible.column("left_arm_angle");
    let swing = angle.iter().fold(0.0_f64, |m, a| m.max(a.abs()));
    let gross = largest_difference(&angle, &rigid.column("left_arm_angle"));
    println!("wiper: swing {swing:.3} rad, flexible − rigid arm angle {gross:.2e} rad");
    assert!(swing > 0.7, "the arm swings {swing} rad");
    assert!(gross < 0.03, "flexible and rigid arm angles differ by {gross} rad");
    // The flexible tip velocity carries a vibration above 5 Hz near the arm's first in-plane bending
    // frequency (14.28 Hz clamped at the pivot; the linkage's compliance and the coupling of the two
    // arms through the crank shift it); the rigid one has none.
    let dominant = |run: &str| {
        let csv = out.join(format!("{run}-bdf.csv"));
        let report = succeed(&["spectrum", csv.to_str().unwrap(), "--y", "left_arm.node21.velocity.x", "--from", "0.3", "--min-frequency", "5", "--peaks", "1"]);
        let line = report.lines().last().unwrap().to_string();
        let fields: Vec<f64> = line.split_whitespace().filter_map(|w| w.parse().ok()).collect();
        (fields[1], fields[2])
    };
    let (f, amplitude) = dominant("flexible");
    let (_, rigid_amplitude) = dominant("rigid");
    println!("wiper: flexible tip vibration {f:.3} Hz, {amplitude:.3} m/s; rigid {rigid_amplitude:.2e} m/s");
    assert!((12.0..16.0).contains(&f), "vibration at {f} Hz");
    assert!(amplitude > 0.3, "vibration amplitude {amplitude} m/s");
    assert!(rigid_amplitude < 1e-2 * amplitude, "rigid arm vibrates with {rigid_amplitude} m/s");
}

/// A study file's mistakes are reported with the file, the key path and the line.
#[test]
fn study_file_errors_name_file_key_and_line() {
    let dir = scratch("study-errors");
    let model = program::workspace().join("models/door/door.toml");
    let write = |name: &str, body: &str| {
        let path = dir.join(name);
        std::fs::write(&path, format!("[study]\nmodel = {:?}\n{body}", model.display().to_string())).unwrap();
        path.display().to_string()
    };
    let cases = [
        ("integrator.toml", "integrators = [\"bdf\", \"rk4\"]\n[[case]]\nname = \"a\"\n", ":3: study.integrators[1]"),
        ("key.toml", "[[case]]\nname = \"a\"\nmode = { door = \"5S\" }\n", ":5: case[0]"),
        ("none.toml", "", "at least one [[case]]"),
        ("order.toml", "integrators = [\"bdf:7\"]\n[[case]]\nname = \"a\"\n", ":3: study.integrators[0]: `bdf:7`"),
        ("twice.toml", "[[case]]\nname = \"a\"\n[[case]]\nname = \"a\"\n", ":6: case[1].name: case 'a' is named twice"),
        // Published figures are positive numbers (an infinite CPU time was printed as `inf`).
        ("published.toml", "[[case]]\nname = \"a\"\npublished = { cpu = inf }\n", ":5: case[0].published.cpu: cpu must be a positive number, got inf"),
        ("again.toml", "integrators = [\"bdf\", \"adams\", \"bdf\"]\n[[case]]\nname = \"a\"\n", ":3: study.integrators[2]: integrator 'bdf' is listed twice"),
        ("plot.toml", "plot = [\"x\", \"y\", \"x\"]\n[[case]]\nname = \"a\"\n", ":3: study.plot[2]: column 'x' is listed twice"),
        ("step.toml", "[[case]]\nname = \"a\"\npublished = { rms_step = -1e-3 }\n", ":5: case[0].published.rms_step: rms_step must be a positive number, got -0.001"),
    ];
    for (name, body, expected) in cases {
        let path = write(name, body);
        let e = program::fail(&["study", &path]);
        assert!(e.contains(&path) && e.contains(expected), "{name}: {e}");
    }
    // A case that names a body the model does not have: the study file's line, and the model's bodies.
    let path = write("body.toml", "[[case]]\nname = \"a\"\nmodes = { doors = \"5S\" }\n");
    let e = program::fail(&["study", &path, "--out", dir.join("out").to_str().unwrap()]);
    assert!(e.contains(&format!("{path}:3: case[0]")) && e.contains("no flexible body 'doors' (it has: door)"), "{e}");
}

/// The table prints the end time in full: with one decimal a run to 0.02 s read 0.0.
#[test]
fn study_table_prints_short_end_times_in_full() {
    let out = scratch("short-study");
    let table = succeed(&["study", "models/wiper/study.toml", "--t-end", "0.02", "--out", out.to_str().unwrap(), "--quiet"]);
    assert!(table.contains("| flexible | bdf | 0.02 |") && table.contains("| rigid | bdf | 0.02 |"), "{table}");
}
