//! `flexmb study --jobs N` runs the study's (case, integrator) pairs on N threads: the runs are the
//! same computations as one after the other, so every CSV is the same to the last digit, and the
//! printed lines and the table come in the study's order; only the CPU column (each run's own
//! integration time) may differ.

use crate::program;

use program::{scratch, succeed};

/// The printed lines and the table with the CPU times (the `N.NNN s` of a run line, the table's
/// fourth column) replaced by `*`.
fn without_times(printed: &str, out: &std::path::Path) -> String {
    let cells = |line: &str| -> String {
        if line.starts_with('|') && !line.starts_with("|---") && !line.starts_with("| type") {
            let mut cells: Vec<&str> = line.split('|').collect();
            cells[4] = " * ";
            cells.join("|")
        } else if let Some((head, tail)) = line.split_once(" s, ").and_then(|(h, t)| Some((h, t.split_once(" s: ")?.1))) {
            format!("{head} s, * s: {tail}")
        } else {
            line.to_string()
        }
    };
    let out = out.display().to_string();
    printed.lines().map(|l| cells(&l.replace(&out, "OUT"))).collect::<Vec<_>>().join("\n")
}

#[test]
fn a_study_on_three_jobs_prints_and_writes_what_one_job_does() {
    let dir = scratch("parallel-study");
    let (one, three) = (dir.join("one"), dir.join("three"));
    let run = |out: &std::path::Path, jobs: &str| {
        succeed(&["study", "models/door/study.toml", "--t-end", "0.2", "--out", out.to_str().unwrap(), "--jobs", jobs])
    };
    let (printed_one, printed_three) = (run(&one, "1"), run(&three, "3"));
    assert_eq!(without_times(&printed_one, &one), without_times(&printed_three, &three));
    // 4 cases × 3 integrators, each with its CSV and JSON summary, in the same order as the table.
    let lines: Vec<&str> = printed_three.lines().take(12).collect();
    let order: Vec<String> = lines.iter().map(|l| l.split_whitespace().take(2).collect::<Vec<_>>().join(" ")).collect();
    assert_eq!(order[..4], ["5S bdf", "5S bdf:2", "5S adams", "5N bdf"]);
    assert_eq!(order[11], "4N5S adams");
    let mut csvs = 0;
    for entry in std::fs::read_dir(&one).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "csv") {
            let other = three.join(path.file_name().unwrap());
            assert!(std::fs::read(&path).unwrap() == std::fs::read(&other).unwrap(), "{} differs", other.display());
            csvs += 1;
        }
    }
    assert_eq!(csvs, 12);
}

#[test]
fn jobs_must_be_a_whole_number_of_at_least_one() {
    let e = program::fail(&["study", "models/door/study.toml", "--jobs", "0"]);
    assert!(e.contains("--jobs"), "{e}");
}
