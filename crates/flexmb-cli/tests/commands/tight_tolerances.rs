//! The BDF at tight tolerances over a long run (docs/accuracy.md, *Error per unit step over the run on
//! every case*): the peer's 3-D slider-crank (models/peer/slider_crank_3d.toml, 5 s, error per unit step
//! over the run) and Andrews' squeezer (models/benchmarks/andrews_squeezer.toml, 0.03 s) against the Adams
//! method at the finest tolerance.

use crate::program;

use program::{run_at_tolerance, scratch, workspace, ResultCsv};

/// The global error `E` of docs/accuracy.md on the position outputs of `markers`: for each, the largest
/// difference from the reference over the output times and axes, over the largest coordinate of the
/// reference; the largest of those.
fn global_error(run: &ResultCsv, reference: &ResultCsv, markers: &[&str]) -> f64 {
    let mut error = 0.0_f64;
    for marker in markers {
        let (mut worst, mut scale) = (0.0_f64, 0.0_f64);
        for axis in ["x", "y", "z"] {
            let column = format!("{marker}.position.{axis}");
            let (a, b) = (run.column(&column), reference.column(&column));
            assert_eq!(a.len(), b.len(), "{column}: the runs have different output times");
            worst = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(worst, f64::max);
            scale = b.iter().map(|y| y.abs()).fold(scale, f64::max);
        }
        error = error.max(worst / scale);
    }
    error
}

/// At rtol = atol = 1e-9 the BDF's 27,000 steps are held by the floor of a step's share (1e-13 of the
/// solution), and its Newton increments are resolved to 20 units of rounding, below that floor: the
/// global error stays within 10 tolerances (6.2 measured; 8.0 with the other methods' Newton floor of
/// 100 units) and fewer than 1 % of the steps are rejected (79 of 23,314; 410 of 27,126 with 100 units,
/// whose unresolved part of the corrector was the error estimate's noise). About 3 s in release.
#[test]
fn the_bdf_at_1e_9_over_the_run_stays_within_ten_tolerances_and_rejects_few_steps() {
    let model = workspace().join("models/peer/slider_crank_3d.toml");
    let dir = scratch("tight-tolerances");
    let (adams, bdf) = (dir.join("adams"), dir.join("bdf"));
    run_at_tolerance(&model, "adams", "1e-12", &adams, &[]);
    run_at_tolerance(&model, "bdf", "1e-9", &bdf, &[]);
    let (reference, run) = (ResultCsv::read(&adams.join("slider_crank_3d.csv")), ResultCsv::read(&bdf.join("slider_crank_3d.csv")));
    let error = global_error(&run, &reference, &["slider_guide"]);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(bdf.join("slider_crank_3d.json")).unwrap()).unwrap();
    let statistics = &summary["statistics"];
    let (steps, rejected) = (statistics["steps"].as_u64().unwrap(), statistics["rejected_steps"].as_u64().unwrap());
    eprintln!("E = {error:.3e} ({:.2} tolerances), {steps} steps, {rejected} rejected", error / 1e-9);
    assert!(error <= 10.0 * 1e-9, "global error {error:e} at rtol 1e-9");
    assert!(rejected * 100 < steps, "{rejected} of {steps} steps rejected");
}

/// At rtol = atol = 1e-10 the BDF's steps are held by the floor under a step's share, which it makes of
/// its error estimate's measured noise (`integrate/noise_floor.rs`): three times the leftover of one
/// Newton iteration more, carried into the estimate, down to 1.5e-14 of the solution instead of the fixed
/// 1e-13; and a step the estimate lets grow above the recent mean of the steps it chose there is held to
/// that mean (`integrate/floor_step_cap.rs`), since the longest of the held steps made the error. Against
/// the Adams method at 1e-12: the 3-D slider-crank 4.3 to 5.6 tolerances over rtol × 0.97 … 1.03 in about
/// 35,600 steps (25 to 27 in 29,500 without the bound, 59 to 62 with the fixed floor; bound 10), the heavy
/// top 0.31 (0.36 to 0.44 without; bound 1); the floor the held steps were held to, on average, below
/// 1e-13 in both. About 1.5 s in release.
#[test]
fn the_bdf_at_1e_10_over_the_run_holds_its_steps_to_the_measured_noise_and_its_longest_to_their_mean() {
    let dir = scratch("measured-noise-floor");
    for (name, markers, bound) in [("slider_crank_3d", &["slider_guide"][..], 10.0), ("heavy_top", &["com", "ex", "ey"][..], 1.0)] {
        let model = workspace().join(format!("models/peer/{name}.toml"));
        let (adams, bdf) = (dir.join(format!("{name}_adams")), dir.join(format!("{name}_bdf")));
        run_at_tolerance(&model, "adams", "1e-12", &adams, &[]);
        run_at_tolerance(&model, "bdf", "1e-10", &bdf, &[]);
        let csv = format!("{name}.csv");
        let error = global_error(&ResultCsv::read(&bdf.join(&csv)), &ResultCsv::read(&adams.join(&csv)), markers);
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(bdf.join(format!("{name}.json"))).unwrap()).unwrap();
        let statistics = &summary["statistics"];
        let (held, floor) = (statistics["share_floor_steps"].as_u64().unwrap(), statistics["share_floor"].as_f64().unwrap());
        let steps = statistics["steps"].as_u64().unwrap();
        eprintln!("{name}: E = {error:.3e} ({:.2} tolerances), {steps} steps, {held} held to {floor:.2e} on average", error / 1e-10);
        assert!(error <= bound * 1e-10, "{name}: global error {error:e} at rtol 1e-10");
        assert!(held * 2 > steps, "{name}: the floor holds most steps ({held} of {steps})");
        assert!((1.5e-14..0.5e-13).contains(&floor), "{name}: the mean floor {floor:e}");
    }
}

/// Below 1e-10 over the run the BDF's steps ask nothing finer (they are held to the floor under a step's
/// share already at 1e-10), and a finer tolerance only lets more estimates pass as rounding where the
/// constraint Jacobian's condition number dips: before the raise the slider-crank was 2.4e-8 off at 1e-11
/// and 4.8e-8 at 1e-12, against 2.6e-9 at 1e-10 (docs/accuracy.md, *The finest tolerance*). Now a run at
/// 1e-12 says at t = 0 that rtol and atol were raised to 1e-10 and names the Adams method, and it is the
/// run at 1e-10, to the last digit. With a span given explicitly the tolerance is taken as given (the run
/// differs and does not warn). About 3 s in release.
#[test]
fn the_bdf_over_the_run_raises_a_tolerance_below_1e_10_to_it_and_says_so() {
    let model = workspace().join("models/peer/slider_crank_3d.toml");
    let dir = scratch("bdf-finest-tolerance");
    let read = |out: &std::path::Path| -> (ResultCsv, serde_json::Value) {
        let summary = serde_json::from_str(&std::fs::read_to_string(out.join("slider_crank_3d.json")).unwrap()).unwrap();
        (ResultCsv::read(&out.join("slider_crank_3d.csv")), summary)
    };
    let raised_by = |summary: &serde_json::Value| -> Vec<String> {
        summary["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "tolerance" && w["message"].as_str().unwrap().contains("tolerance finer than the BDF keeps over the run:"))
            .map(|w| {
                assert_eq!(w["t"].as_f64(), Some(0.0), "{w}");
                w["message"].as_str().unwrap().to_string()
            })
            .collect()
    };
    let (at_finest, at_finer, given) = (dir.join("1e-10"), dir.join("1e-12"), dir.join("1e-12-step"));
    run_at_tolerance(&model, "bdf", "1e-10", &at_finest, &[]);
    run_at_tolerance(&model, "bdf", "1e-12", &at_finer, &[]);
    run_at_tolerance(&model, "bdf", "1e-12", &given, &["--tolerance-span", "step", "--t-end", "0.2"]);
    let ((finest, finest_summary), (finer, finer_summary)) = (read(&at_finest), read(&at_finer));
    assert!(raised_by(&finest_summary).is_empty());
    let messages = raised_by(&finer_summary);
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!(
        messages[0].contains("rtol 1e-12 raised to 1e-10, atol 1e-12 raised to 1e-10") && messages[0].contains("integrator = \"adams\""),
        "{}",
        messages[0]
    );
    assert_eq!(finer.header, finest.header);
    assert!(finer.rows == finest.rows, "the raised run is the run at 1e-10");
    assert_eq!(finer_summary["statistics"]["steps"], finest_summary["statistics"]["steps"]);
    let (_, given_summary) = read(&given);
    assert!(raised_by(&given_summary).is_empty(), "a span given explicitly takes the tolerance as given");
}

/// The warning of a run whose steps the share's floor holds: each BDF step is then held to the floor
/// (1e-13 of the solution, or three times the estimate's measured noise down to 1.5e-14,
/// `integrate/noise_floor.rs`) however short it is, and those local errors add up. On the slider-crank
/// at rtol 1e-10 nearly every step of 35,600 is held (at 1.5e-14 to 3e-14 on average, 5e-10 to 1e-9 of
/// the solution; 5.6 tolerances measured, the warning is a bound): the run warns, at the step
/// that makes their number times the floor exceed rtol, and names the floor, the steps and the Adams
/// method. At rtol 1e-8 some 20 of 17,900 steps are held (2e-12) and it does not. About 2 s in release.
#[test]
fn the_bdf_warns_when_the_steps_held_to_the_share_floor_add_up_to_more_than_rtol() {
    let model = workspace().join("models/peer/slider_crank_3d.toml");
    let dir = scratch("share-floor-warning");
    for (rtol, warns) in [(1e-10, true), (1e-8, false)] {
        let out = dir.join(format!("bdf_{rtol:e}"));
        run_at_tolerance(&model, "bdf", &format!("{rtol:e}"), &out, &[]);
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("slider_crank_3d.json")).unwrap()).unwrap();
        let statistics = &summary["statistics"];
        let (held, floor) = (statistics["share_floor_steps"].as_u64().unwrap(), statistics["share_floor"].as_f64().unwrap());
        let steps = statistics["steps"].as_u64().unwrap();
        let warnings: Vec<&serde_json::Value> = summary["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "tolerance" && w["message"].as_str().unwrap().contains("held to what one step resolves"))
            .collect();
        eprintln!("rtol {rtol:e}: {held} of {steps} steps held to {floor:e}, {} warnings", warnings.len());
        assert_eq!(held as f64 * floor > rtol, warns, "rtol {rtol:e}: {held} steps held to {floor:e}");
        assert_eq!(warnings.len(), usize::from(warns), "rtol {rtol:e}: {warnings:?}");
        if let Some(warning) = warnings.first() {
            let message = warning["message"].as_str().unwrap();
            assert!(message.contains("adams") && message.contains("share_floor_steps"), "{message}");
            // The floor it names is the measured noise's, between 1.5e-14 and 1e-13 (printed to one digit).
            let number_before = |marker: &str| -> f64 {
                let head = &message[..message.find(marker).unwrap_or_else(|| panic!("{marker:?} in {message}"))];
                head.rsplit(' ').find_map(|word| word.trim_end_matches(',').parse().ok()).unwrap()
            };
            let named_floor = number_before(" of the solution (the floor");
            assert!((1e-14..=1e-13).contains(&named_floor), "{message}");
            // Issued at the step that crossed rtol: what the held steps add up to is just above it (the
            // steps before it spent at most rtol, the last one adds at most 1e-13).
            let sum = number_before(" of the solution, more than rtol");
            assert!(sum >= rtol * 0.999 && sum <= rtol * 1.05, "{message}");
            assert!(warning["t"].as_f64().unwrap() < 5.0);
        }
    }
}

/// Andrews' squeezer over the run: every step is near a singular position (κ about 200), where the BDF
/// passes local error estimates up to `50 · gain · 10 ε κ` of the solution as rounding (2.3e-10 at order
/// 5), far above the steps' shares at rtol 1e-9 (1e-13 to 3.5e-13). The step chosen after such an estimate
/// aims at the rounding itself, `gain · 10 ε κ` (`SingularPassage::estimate_for_selection`); before, it grew
/// until the truncation error reached the fifty times, and those truncation errors added up to `E` = 4.4e-8
/// (44 tolerances, 2,454 steps; 9 to 75 at rtol × 0.97 … 1.03). Now `E` is 7.7e-10, 0.77 tolerances, in
/// 4,801 steps (0.5 to 3.4 over the same tolerances). What passed beyond the shares (statistic
/// `rounding_passed`) still adds up to more than rtol, 1.9e-8 of the solution: the estimates passed are now
/// at the rounding, which does not add up as a truncation error does, so the run's warning is an upper
/// measure of the error (`E` at most twice rtol plus it), not an estimate. At rtol 1e-6 (the model's own)
/// what passed is 4e-11, 4e-5 tolerances, `E` 0.11 tolerances, and there is no such warning. About 1 s in
/// release.
#[test]
fn the_bdf_on_andrews_squeezer_keeps_ten_tolerances_at_1e_9_and_says_what_passed_as_rounding() {
    let model = workspace().join("models/benchmarks/andrews_squeezer.toml");
    let dir = scratch("andrews-passed-rounding");
    let adams = dir.join("adams");
    run_at_tolerance(&model, "adams", "1e-12", &adams, &[]);
    let reference = ResultCsv::read(&adams.join("andrews_squeezer.csv"));
    for (rtol, warns) in [(1e-9, true), (1e-6, false)] {
        let out = dir.join(format!("bdf_{rtol:e}"));
        run_at_tolerance(&model, "bdf", &format!("{rtol:e}"), &out, &[]);
        let run = ResultCsv::read(&out.join("andrews_squeezer.csv"));
        let error = global_error(&run, &reference, &["f_crank", "e_body2"]);
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("andrews_squeezer.json")).unwrap()).unwrap();
        let passed = summary["statistics"]["rounding_passed"].as_f64().unwrap();
        let warnings: Vec<&serde_json::Value> = summary["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "tolerance" && w["message"].as_str().unwrap().contains("pass as the rounding"))
            .collect();
        eprintln!(
            "rtol {rtol:e}: E = {error:.2e} ({:.2} tolerances), passed as rounding {passed:.2e} ({:.2} tolerances), {} warnings",
            error / rtol,
            passed / rtol,
            warnings.len()
        );
        assert_eq!(warnings.len(), usize::from(warns), "rtol {rtol:e}: {warnings:?}");
        assert_eq!(passed > rtol, warns, "rtol {rtol:e}: passed {passed:e}");
        assert!(error <= 2.0 * (rtol + passed), "rtol {rtol:e}: E {error:e} beyond twice the tolerance and what passed, {passed:e}");
        if let Some(warning) = warnings.first() {
            let message = warning["message"].as_str().unwrap();
            assert!(message.contains(&format!("{passed:.1e} of the solution")), "{message}");
            // Its condition number, about 200 at every step, names the amplification; the run passes no
            // singular position (`singular_positions` 0), so the message does not say it is near one.
            assert!(message.contains("condition number (up to") && message.contains("rounding_passed"), "{message}");
            assert_eq!(warning["t"], 0.03, "at the end of the run");
        }
        assert!(error < 10.0 * rtol, "rtol {rtol:e}: E = {error:e}");
    }
}
