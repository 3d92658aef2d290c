//! `--global-error-control` of `flexmb run` and the `[simulation]` key `global_error_control`: a run whose
//! global error, estimated by reintegration, exceeds 10 of the tolerances asked for is made again from the
//! start at rtol / (its estimate in tolerances); the files written are the run made again, the same numbers
//! as a run asked for at that rtol directly, and its summary names the earlier run. Measured against a
//! reference (Adams at 1e-12), the run kept is within the tolerance asked for, the first was not.

use crate::program;

use crate::vtk_output::read_pvd;
use program::{scratch, succeed, workspace};

fn summary(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("four_bar.json")).unwrap()).unwrap()
}

/// The global error of `run` against `reference` in the norm of the estimate (docs/results.md,
/// `position_outputs`): the coupler point's largest position difference over the output rows, over its
/// largest coordinate in the reference (relative).
fn relative_position_error(run: &std::path::Path, reference: &std::path::Path) -> f64 {
    let read = |p: &std::path::Path| {
        let text = std::fs::read_to_string(p.join("four_bar.csv")).unwrap();
        let mut lines = text.lines();
        let header: Vec<String> = lines.next().unwrap().split(',').map(str::to_string).collect();
        let rows: Vec<Vec<f64>> = lines.map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
        (header, rows)
    };
    let ((header, a), (_, b)) = (read(run), read(reference));
    assert_eq!(a.len(), b.len());
    let columns: Vec<usize> = (0..header.len()).filter(|&c| header[c].starts_with("coupler_point.position.")).collect();
    assert_eq!(columns.len(), 3, "{header:?}");
    let (mut difference, mut scale) = (0.0_f64, 0.0_f64);
    for (x, y) in a.iter().zip(&b) {
        for &c in &columns {
            difference = difference.max((x[c] - y[c]).abs());
            scale = scale.max(y[c].abs());
        }
    }
    difference / scale
}

#[test]
fn a_run_estimated_beyond_ten_tolerances_is_made_again_and_then_keeps_the_tolerance() {
    let out = scratch("global-error-control");
    // The shipped four-bar with the control off in its file, turned on by the option.
    let text = std::fs::read_to_string(workspace().join("models/four_bar.toml")).unwrap();
    assert!(text.contains("global_error_control = true"));
    let file = out.join("four_bar.toml");
    std::fs::write(&file, text.replace("global_error_control = true", "global_error_control = false")).unwrap();
    let controlled = out.join("controlled");
    let vtk = out.join("vtk");
    let vtk_args = ["--vtk", vtk.to_str().unwrap(), "--vtk-step", "0.5"];
    succeed(&[&["run", file.to_str().unwrap(), "--global-error-control", "--quiet", "--out", controlled.to_str().unwrap()], &vtk_args[..]].concat());
    let s = summary(&controlled);
    let control = &s["statistics"]["global_error_control"];
    let earlier = control["earlier_runs"].as_array().unwrap();
    assert_eq!(earlier.len(), 1, "{control}");
    let first = earlier[0]["tolerances"].as_f64().unwrap();
    let (rtol, atol) = (control["rtol"].as_f64().unwrap(), control["atol"].as_f64().unwrap());
    assert!((15.0..25.0).contains(&first) && (rtol - 1e-6 / first).abs() < 1e-18, "{control}");
    assert!(s["warnings"].as_array().unwrap().is_empty(), "{}", s["warnings"]);
    let csv = std::fs::read_to_string(controlled.join("four_bar.csv")).unwrap();
    assert_eq!(csv.lines().count(), 502, "a header and the 501 rows of the run made again, not both runs'");
    // The ParaView series begins anew with the run made again: eleven frames, 0 to 5 s, once.
    let entries = read_pvd(&vtk.join("four_bar.pvd"));
    let times: Vec<f64> = entries.iter().filter(|e| e.part == 0).map(|e| e.time).collect();
    assert_eq!(times, (0..=10).map(|i| 0.5 * i as f64).collect::<Vec<_>>(), "the frames of part 0");

    // The same numbers as the run asked for at that rtol directly.
    let direct = out.join("direct");
    let (r, a) = (format!("{rtol:e}"), format!("{atol:e}"));
    assert_eq!(r.parse::<f64>().unwrap(), rtol);
    succeed(&["run", file.to_str().unwrap(), "--rtol", &r, "--atol", &a, "--quiet", "--out", direct.to_str().unwrap()]);
    assert_eq!(std::fs::read_to_string(direct.join("four_bar.csv")).unwrap(), csv);

    // Against Adams at 1e-12: the first run (at the rtol asked for) off by more than 10 tolerances
    // (measured 1.8e-5, relative), the run kept within one (8.7e-7).
    let reference = out.join("reference");
    succeed(&["run", file.to_str().unwrap(), "--integrator", "adams", "--rtol", "1e-12", "--atol", "1e-12", "--quiet", "--out", reference.to_str().unwrap()]);
    let plain = out.join("plain");
    succeed(&["run", file.to_str().unwrap(), "--quiet", "--out", plain.to_str().unwrap()]);
    let (before, after) = (relative_position_error(&plain, &reference), relative_position_error(&controlled, &reference));
    assert!(before > 10.0 * 1e-6, "first run {before:e}");
    assert!(after < 1e-6, "run kept {after:e}");
}
