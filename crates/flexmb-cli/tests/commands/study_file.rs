//! The study file of docs/study-file.md (`models/studies/pendulum_lengths.toml`) as a user runs it: its cases'
//! parameters, numbers and expressions of the model's parameters, reach the model, and the study
//! writes a run, a table row and a curve for every case.

use crate::program;

use std::f64::consts::PI;
use std::path::Path;

use flexmb_files::model_file::LoadOptions;
use flexmb_files::study_file::load_study;
use program::{fail, scratch, succeed, workspace};

#[test]
fn a_case_parameter_is_a_number_or_an_expression_of_the_models_parameters() {
    let study = load_study(&workspace().join("models/studies/pendulum_lengths.toml")).unwrap();
    let names: Vec<&str> = study.cases.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["L1", "L2", "half_hertz"]);
    let parameter = |case: usize, name: &str| {
        let options = LoadOptions { overrides: study.cases[case].overrides.clone(), ..Default::default() };
        flexmb_files::load_model_with(&study.model, &options).unwrap().parameters[name]
    };
    assert_eq!((parameter(0, "L"), parameter(0, "r_bob")), (1.0, 0.02));
    assert_eq!((parameter(1, "L"), parameter(1, "r_bob")), (2.0, 0.02));
    // The length whose small swings have 0.5 Hz, and a bob a twentieth of it: 0.99396 m, 49.7 mm.
    let length = 9.81 / (2.0 * PI * 0.5f64).powi(2);
    assert!((parameter(2, "L") - length).abs() < 1e-15);
    assert!((parameter(2, "r_bob") - length / 20.0).abs() < 1e-15);
}

#[test]
fn the_example_study_runs_every_case_and_writes_its_table_and_plot() {
    let dir = scratch("example-study");
    let out = dir.to_str().unwrap();
    let printed = succeed(&["study", "models/studies/pendulum_lengths.toml", "--t-end", "0.5", "--out", out, "--jobs", "2"]);
    for case in ["L1", "L2", "half_hertz"] {
        for integrator in ["bdf", "adams"] {
            assert!(dir.join(format!("{case}-{integrator}.csv")).is_file(), "{case}-{integrator}\n{printed}");
        }
    }
    let table = std::fs::read_to_string(dir.join("table.md")).unwrap();
    assert_eq!(table.lines().filter(|l| l.starts_with("| half_hertz") || l.starts_with("| L")).count(), 6, "{table}");
    assert!(dir.join("bob.position.y-bdf.png").is_file());
}

#[test]
fn a_bad_case_parameter_is_an_error_at_its_case() {
    let dir = scratch("bad-study");
    let model = workspace().join("models/pendulum.toml");
    let write = |parameters: &str| {
        let path = dir.join("study.toml");
        let text = format!(
            "[study]\nmodel = \"{}\"\n\n[[case]]\nname = \"a\"\nparameters = {{ {parameters} }}\n",
            model.display()
        );
        std::fs::write(&path, text).unwrap();
        path
    };
    let study = write("L = \"2*LL\"");
    let e = fail(&["study", study.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(e.contains("study.toml:4: case[0]") && e.contains("LL"), "{e}");
    let study = write("L = true");
    let e = fail(&["study", study.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    assert!(e.contains("study.toml:6") && e.contains("case[0].parameters"), "{e}");
    assert!(Path::new(&dir).is_dir());
}
