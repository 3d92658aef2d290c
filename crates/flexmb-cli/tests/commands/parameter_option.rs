//! `--parameter NAME=VALUE` (`-p`) of `flexmb run`, `check` and `study`: the command line's values of
//! a model file's `[parameters]` give, to the last digit written, the results of the file edited to
//! those values; unknown names and bad values are refused with messages that say what to write.

use crate::program;

use std::path::Path;

use program::{fail, scratch, succeed, workspace};

/// The shipped pendulum with its `[parameters]` lines edited (`L = 1.0` → `L = 1.7`, …).
fn edited_pendulum(dir: &Path, values: &[(&str, &str)]) -> String {
    let mut text = std::fs::read_to_string(workspace().join("models/pendulum.toml")).unwrap();
    for (name, value) in values {
        let line = text.lines().find(|l| l.starts_with(&format!("{name} = "))).unwrap().to_string();
        text = text.replace(&line, &format!("{name} = {value}"));
    }
    let path = dir.join("pendulum.toml");
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn a_run_with_parameters_equals_the_run_of_the_edited_file() {
    let out = scratch("parameter-run");
    let edited = edited_pendulum(&out, &[("L", "1.7"), ("m_bob", "2.5")]);
    let (given, by_file) = (out.join("given"), out.join("edited"));
    succeed(&["run", "models/pendulum.toml", "-p", "L=1.7", "--parameter", "m_bob=2.5", "--t-end", "2", "--quiet", "--out", given.to_str().unwrap()]);
    succeed(&["run", &edited, "--t-end", "2", "--quiet", "--out", by_file.to_str().unwrap()]);
    let csv = std::fs::read_to_string(given.join("pendulum.csv")).unwrap();
    assert_eq!(csv, std::fs::read_to_string(by_file.join("pendulum.csv")).unwrap());
    // Not the unedited run: the period grows with the rod's length.
    let plain = out.join("plain");
    succeed(&["run", "models/pendulum.toml", "--t-end", "2", "--quiet", "--out", plain.to_str().unwrap()]);
    assert_ne!(csv, std::fs::read_to_string(plain.join("pendulum.csv")).unwrap());
}

#[test]
fn check_reports_the_model_with_the_parameters() {
    let out = scratch("parameter-check");
    let edited = edited_pendulum(&out, &[("L", "3")]);
    let given = succeed(&["check", "models/pendulum.toml", "-p", "L=3"]);
    assert_eq!(given, succeed(&["check", &edited]));
    assert!(given.contains("degrees of freedom: 1"), "{given}");
}

#[test]
fn a_study_with_parameters_runs_each_case_on_the_edited_model_and_the_case_values_win() {
    let out = scratch("parameter-study");
    let edited = edited_pendulum(&out, &[("m_bob", "4")]);
    let study = |model: &str, file: &str| {
        let text = format!(
            "[study]\nname = \"pendulums\"\nmodel = {model:?}\nintegrators = [\"bdf\"]\nt_end = 1.0\n\n\
             [[case]]\nname = \"file_length\"\n\n[[case]]\nname = \"long\"\nparameters = {{ L = 2.0, m_bob = 3.0 }}\n"
        );
        let path = out.join(file);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    let pendulum = workspace().join("models/pendulum.toml").canonicalize().unwrap();
    let given = study(pendulum.to_str().unwrap(), "given.toml");
    let by_file = study(&edited, "edited.toml");
    let (given_out, edited_out) = (out.join("given"), out.join("edited"));
    succeed(&["study", &given, "-p", "m_bob=4", "--quiet", "--out", given_out.to_str().unwrap()]);
    succeed(&["study", &by_file, "--quiet", "--out", edited_out.to_str().unwrap()]);
    for case in ["file_length-bdf.csv", "long-bdf.csv"] {
        let a = std::fs::read_to_string(given_out.join(case)).unwrap();
        assert_eq!(a, std::fs::read_to_string(edited_out.join(case)).unwrap(), "{case}");
    }
    // The case `long` sets m_bob = 3 itself: the same run with or without -p.
    let without = out.join("without");
    succeed(&["study", &given, "--quiet", "--out", without.to_str().unwrap()]);
    let long = std::fs::read_to_string(without.join("long-bdf.csv")).unwrap();
    assert_eq!(long, std::fs::read_to_string(given_out.join("long-bdf.csv")).unwrap());
}

#[test]
fn unknown_names_and_bad_values_are_refused_with_what_to_write() {
    let e = fail(&["run", "models/pendulum.toml", "-p", "LL=2", "--out", "/dev/null"]);
    assert!(e.contains("models/pendulum.toml: the model has no parameter 'LL' (it has: L, m_bob, r_bob); did you mean `L`?"), "{e}");
    let e = fail(&["check", "models/pendulum.toml", "-p", "L=two"]);
    assert!(e.contains("the value of `L` must be a finite number, got `two`"), "{e}");
    let e = fail(&["check", "models/pendulum.toml", "--parameter", "L"]);
    assert!(e.contains("expected NAME=VALUE (e.g. L=2.5), got `L`"), "{e}");
    // A value the model refuses is the model file's error, at the key that uses it.
    let e = fail(&["check", "models/pendulum.toml", "-p", "m_bob=-1"]);
    assert!(e.contains("body[0].mass"), "{e}");
}
