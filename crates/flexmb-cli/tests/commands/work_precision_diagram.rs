//! `flexmb compare --tolerances`: the work-precision diagram of a shipped model. Each method's global
//! error (docs/accuracy.md's norm, against the Adams method at 1e-12) stays within 10 tolerances and
//! falls with the tolerance; the table's error is the one a user computes from the two runs' CSV files;
//! the diagram holds one line per method; a reference run's file serves as the reference; bad tolerances
//! and references are refused.

use std::path::Path;

use super::program::{fail, run_at_tolerance, scratch, succeed, workspace, ResultCsv};

/// One row of the table's CSV.
struct Row {
    method: String,
    tol: f64,
    error: f64,
    error_over_tol: f64,
    steps: usize,
    completed: bool,
}

fn rows(path: &Path) -> Vec<Row> {
    let csv = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no column {name}: {header:?}"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            Row {
                method: f[at("method")].to_string(),
                tol: f[at("tol")].parse().unwrap(),
                error: f[at("error")].parse().unwrap(),
                error_over_tol: f[at("error_over_tol")].parse().unwrap(),
                steps: f[at("steps")].parse().unwrap(),
                completed: f[at("completed")] == "true",
            }
        })
        .collect()
}

/// The docs' global error of `run` against `reference`, computed here from the two CSV files: per
/// `….position` output, its largest difference over its largest reference value.
fn global_error_of_files(run: &ResultCsv, reference: &ResultCsv) -> f64 {
    let stems: Vec<&str> = reference.header.iter().filter_map(|h| h.strip_suffix(".position.x")).collect();
    assert!(!stems.is_empty(), "{:?}", reference.header);
    stems
        .iter()
        .map(|stem| {
            let columns: Vec<String> = ["x", "y", "z"].iter().map(|a| format!("{stem}.position.{a}")).collect();
            let scale = columns.iter().flat_map(|c| reference.column(c)).map(f64::abs).fold(0.0, f64::max);
            let difference = columns
                .iter()
                .flat_map(|c| run.column(c).into_iter().zip(reference.column(c)).map(|(a, b)| (a - b).abs()))
                .fold(0.0, f64::max);
            difference / scale
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_work_precision_diagram_of_the_3d_pendulum_keeps_each_methods_promise() {
    let out = scratch("work-precision");
    let model = workspace().join("models/peer/rigid_pendulum_3d.toml");
    let stdout = succeed(&[
        "compare",
        model.to_str().unwrap(),
        "--integrators",
        "bdf,adams,gen-alpha",
        "--tolerances",
        "1e-3,1e-4,1e-5,1e-6",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(stdout.contains("reference: adams at 1e-12"), "{stdout}");
    assert!(stdout.contains("rtol = atol = tol over the run (the promise of docs/accuracy.md"), "{stdout}");
    let table = rows(&out.join("rigid_pendulum_3d_work_precision.csv"));
    assert_eq!(table.len(), 12, "three methods at four tolerances");
    for method in ["bdf", "adams", "gen-alpha"] {
        let mine: Vec<&Row> = table.iter().filter(|r| r.method == method).collect();
        assert_eq!(mine.iter().map(|r| r.tol).collect::<Vec<_>>(), [1e-3, 1e-4, 1e-5, 1e-6]);
        for r in &mine {
            // The promise of docs/accuracy.md: within 10 tolerances.
            assert!(r.completed && r.error > 0.0 && r.error <= 10.0 * r.tol, "{method} at {}: E = {}", r.tol, r.error);
            assert!((r.error_over_tol - r.error / r.tol).abs() <= 1e-12 * r.error_over_tol, "{method} at {}", r.tol);
            // The table printed says the same.
            let printed = stdout.lines().find(|l| l.starts_with(method) && l.contains(&format!("{:.0e}", r.tol))).unwrap();
            let e: f64 = printed.split_whitespace().nth(2).unwrap().parse().unwrap();
            assert!((e - r.error).abs() <= 1e-3 * r.error, "{printed} against {}", r.error);
        }
        // Falling with the tolerance (at least threefold per decade), in more steps.
        for pair in mine.windows(2) {
            assert!(pair[1].error < pair[0].error / 3.0, "{method}: {} at {} after {} at {}", pair[1].error, pair[1].tol, pair[0].error, pair[0].tol);
            assert!(pair[1].steps > pair[0].steps, "{method}: {} steps at {} after {}", pair[1].steps, pair[1].tol, pair[0].steps);
        }
    }

    // The error of the BDF at 1e-4 is the one computed from its run's CSV and the reference's.
    let (bdf, reference) = (out.join("bdf"), out.join("reference"));
    run_at_tolerance(&model, "bdf", "1e-4", &bdf, &[]);
    run_at_tolerance(&model, "adams", "1e-12", &reference, &[]);
    let from_files = global_error_of_files(
        &ResultCsv::read(&bdf.join("rigid_pendulum_3d.csv")),
        &ResultCsv::read(&reference.join("rigid_pendulum_3d.csv")),
    );
    let tabled = table.iter().find(|r| r.method == "bdf" && r.tol == 1e-4).unwrap().error;
    assert!((from_files - tabled).abs() <= 1e-9 * tabled, "from the files {from_files}, in the table {tabled}");
    // The reference run's file as the reference (`--reference FILE.csv`): the same error, without the run.
    let again = out.join("again");
    let reference_file = reference.join("rigid_pendulum_3d.csv");
    let stdout = succeed(&[
        "compare",
        model.to_str().unwrap(),
        "--tolerances",
        "1e-4",
        "--reference",
        reference_file.to_str().unwrap(),
        "--out",
        again.to_str().unwrap(),
    ]);
    assert!(stdout.contains(&format!("reference: {}", reference_file.display())), "{stdout}");
    let from_file = rows(&again.join("rigid_pendulum_3d_work_precision.csv"))[0].error;
    assert!((from_file - tabled).abs() <= 1e-12 * tabled, "against the file {from_file}, against the run {tabled}");
    // A solution that gives only the positions (as a published one may) serves as well.
    let positions_only = out.join("positions_only.csv");
    let full = ResultCsv::read(&reference_file);
    let kept: Vec<usize> = (0..full.header.len()).filter(|&k| full.header[k] == "t" || full.header[k].contains(".position.")).collect();
    let mut text = kept.iter().map(|&k| full.header[k].clone()).collect::<Vec<_>>().join(",") + "\n";
    for row in &full.rows {
        text += &(kept.iter().map(|&k| format!("{:?}", row[k])).collect::<Vec<_>>().join(",") + "\n");
    }
    std::fs::write(&positions_only, text).unwrap();
    let third = out.join("third");
    succeed(&["compare", model.to_str().unwrap(), "--tolerances", "1e-4", "--reference", positions_only.to_str().unwrap(), "--out", third.to_str().unwrap()]);
    let from_positions = rows(&third.join("rigid_pendulum_3d_work_precision.csv"))[0].error;
    assert_eq!(from_positions, from_file, "the positions alone give the same error");

    // The diagram: one line per method, labelled with its tolerances.
    let svg = std::fs::read_to_string(out.join("rigid_pendulum_3d_work_precision.svg")).unwrap();
    for method in ["bdf", "adams", "gen-alpha"] {
        assert!(svg.contains(&format!("{method}, tol 1e-3 … 1e-6")), "legend of {method}");
    }
    assert!(svg.contains("global error against steps"), "title");
}

#[test]
fn the_work_precision_diagram_refuses_what_it_cannot_run() {
    let model = "models/peer/rigid_pendulum_3d.toml";
    let e = fail(&["compare", model, "--tolerances", "1e-3,-1e-4"]);
    assert!(e.contains("--tolerances") && e.contains("positive"), "{e}");
    let e = fail(&["compare", model, "--tolerances", "1e-3", "--reference", "adams"]);
    assert!(e.contains("METHOD:TOL"), "{e}");
    let e = fail(&["compare", model, "--tolerances", "1e-3", "--reference", "rk4:1e-12"]);
    assert!(e.contains("--reference") && e.contains("rk4"), "{e}");
    let e = fail(&["compare", model, "--tolerances", "1e-3", "--reference", "bdf:1e-12"]);
    assert!(e.contains("bdf keeps 1e-10 over the run") && e.contains("adams:1e-12"), "{e}");
    let e = fail(&["compare", model, "--tolerances", "1e-3", "--reference", "models/no_such_reference.csv"]);
    assert!(e.contains("--reference models/no_such_reference.csv: cannot read"), "{e}");
    // A result file of another model lacks this model's columns.
    let other = scratch("work-precision-other-model");
    run_at_tolerance(&workspace().join("models/pendulum.toml"), "bdf", "1e-6", &other, &["--t-end", "0.1"]);
    let other_csv = other.join("pendulum.csv");
    let e = fail(&["compare", model, "--tolerances", "1e-3", "--reference", other_csv.to_str().unwrap()]);
    assert!(e.contains("it has no column cm.position.x of the model's position outputs"), "{e}");
    let e = fail(&["compare", model, "--tolerances", "1e-3", "--rtol", "1e-5"]);
    assert!(e.contains("cannot be used with"), "{e}");
    // Finer than generalized-α keeps over the run: left out, and with nothing else to run, refused.
    let e = fail(&["compare", model, "--integrators", "gen-alpha", "--tolerances", "1e-8,1e-9"]);
    assert!(e.contains("nothing to run") && e.contains("gen-alpha at 1e-8 (it keeps 1e-7 over the run"), "{e}");
    let out = scratch("work-precision-left-out");
    let stdout = succeed(&["compare", model, "--integrators", "bdf,gen-alpha", "--tolerances", "1e-7,1e-8", "--out", out.to_str().unwrap()]);
    assert!(stdout.contains("not run: gen-alpha at 1e-8 (it keeps 1e-7 over the run and raises a finer one to it)"), "{stdout}");
    let table = rows(&out.join("rigid_pendulum_3d_work_precision.csv"));
    let run: Vec<(&str, f64)> = table.iter().map(|r| (r.method.as_str(), r.tol)).collect();
    assert_eq!(run, [("bdf", 1e-7), ("bdf", 1e-8), ("gen-alpha", 1e-7)]);
}
