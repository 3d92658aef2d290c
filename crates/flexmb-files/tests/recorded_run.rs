//! A model file loaded, run and recorded through the library alone, as a binding would: the CSV, the
//! summary and the ParaView series agree with the frames the caller saw, and a stop predicate ends the
//! run with every file complete up to that point.

use std::cell::Cell;
use std::path::{Path, PathBuf};

use flexmb_files::model_file::{LoadOptions, ModelOverrides};
use flexmb_files::results::ParaViewSeries;
use flexmb_files::vtk::SeriesTimes;
use flexmb_files::{load_model_with, record_model_run, Restart, ResultTable, RunOutputs};

fn pendulum() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/pendulum.toml")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmb-files-recorded-run-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn summary(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_stopped_run_keeps_every_frame_it_reported_in_the_csv_the_summary_and_the_paraview_series() {
    let overrides = ModelOverrides { parameters: vec![("L".into(), 2.0)], ..Default::default() };
    let loaded = load_model_with(&pendulum(), &LoadOptions { overrides, ..Default::default() }).unwrap();
    let mut defaults = loaded.simulation;
    defaults.t_end = 1.0;
    let settings = defaults.settings(&loaded.model, defaults.assembly());
    let dir = scratch("stopped");
    let mut outputs = RunOutputs::in_directory(&dir, "pendulum");
    let times = SeriesTimes { step: Some(2.0 * settings.output_step), output_step: settings.output_step, t_end: 1.0 };
    outputs.paraview = Some(ParaViewSeries { dir: dir.join("vtk"), name: "pendulum".into(), times, max_frames: 1000 });

    let mut seen = Vec::new();
    let frames = Cell::new(0);
    let stop = || (frames.get() >= 10).then(|| "enough".to_string());
    let observe = &mut |frame: &flexmb::analysis::OutputFrame| {
        seen.push((frame.t, frame.values.to_vec()));
        frames.set(frames.get() + 1);
    };
    let run = record_model_run(&loaded, &settings, "pendulum.toml", &outputs, Restart::default(), observe, &stop).unwrap();

    assert!(run.error.is_none());
    let interrupted = run.report.interrupted.as_ref().expect("stopped by the predicate");
    assert_eq!(interrupted.reason, "enough");
    assert!(seen.len() >= 10 && seen.len() < 51, "{} frames", seen.len());
    assert_eq!(run.rows, seen.len());

    // The CSV holds exactly the frames the caller saw, to the 11 digits it writes.
    let table = ResultTable::read(&outputs.csv).unwrap();
    assert_eq!(table.rows(), seen.len());
    let t = table.column("t").unwrap();
    for (row, (time, values)) in seen.iter().enumerate() {
        assert!((t[row] - time).abs() <= 1e-10 * time.abs().max(1.0));
        for (name, value) in table.names()[1..].iter().zip(values) {
            let written = table.column(name).unwrap()[row];
            assert!((written - value).abs() <= 1e-10 * value.abs().max(1e-300), "{name} at row {row}: {written} vs {value}");
        }
    }

    // The summary says the run was interrupted, where, and how many rows it wrote.
    let s = summary(&outputs.summary);
    assert_eq!(s["status"], "interrupted");
    assert_eq!(s["reason"], "enough");
    assert_eq!(s["interrupted_at"].as_f64().unwrap(), interrupted.t);
    assert_eq!(s["output"]["rows"].as_u64().unwrap() as usize, seen.len());
    assert_eq!(s["settings"]["t_end"].as_f64().unwrap(), 1.0);

    // The ParaView series has a frame at every second output time it reached: a body and a joint each.
    let written = run.paraview.expect("a ParaView series");
    assert_eq!(written.pvd, dir.join("vtk/pendulum.pvd"));
    assert_eq!(written.frames, seen.len().div_ceil(2));
    assert_eq!(written.blocks, 2);
    let pvd = std::fs::read_to_string(&written.pvd).unwrap();
    assert_eq!(pvd.matches("<DataSet ").count(), written.frames * written.blocks);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn too_many_paraview_frames_are_refused_before_any_result_file_is_written() {
    let loaded = flexmb_files::load_model(&pendulum()).unwrap();
    let settings = loaded.simulation.settings(&loaded.model, loaded.simulation.assembly());
    let dir = scratch("refused");
    let mut outputs = RunOutputs::in_directory(&dir, "pendulum");
    let times = SeriesTimes { step: None, output_step: settings.output_step, t_end: settings.t_end };
    outputs.paraview = Some(ParaViewSeries { dir: dir.join("vtk"), name: "pendulum".into(), times, max_frames: 10 });
    let e = record_model_run(&loaded, &settings, "pendulum.toml", &outputs, Restart::default(), &mut |_| {}, &|| None).err().unwrap();
    assert!(e.to_string().contains("more than the limit of 10"), "{e}");
    assert!(!outputs.csv.exists() && !outputs.summary.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_memory_limit_a_caller_gives_bounds_the_reduction_of_a_flexible_body() {
    // The flexible pendulum and its FE model in a fresh directory, so that the body is reduced now.
    let dir = scratch("memory");
    let models = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models");
    std::fs::create_dir_all(dir.join("fe")).unwrap();
    std::fs::copy(models.join("fe/pendulum_beam.toml"), dir.join("fe/pendulum_beam.toml")).unwrap();
    std::fs::copy(models.join("flexible_pendulum.toml"), dir.join("flexible_pendulum.toml")).unwrap();
    let path = dir.join("flexible_pendulum.toml");

    let small = LoadOptions { memory_limit: Some(1024), ..Default::default() };
    let e = load_model_with(&path, &small).unwrap_err().to_string();
    assert!(e.contains("flexible_body[0].fe_model: cannot reduce the FE model"), "{e}");
    assert!(e.contains("the mesh is too large for the mode analysis: 20 elements and 21 nodes"), "{e}");
    assert!(!dir.join(".flexmb-cache").exists() && !dir.join("fe/.flexmb-cache").exists(), "nothing reduced, nothing cached");

    let loaded = load_model_with(&path, &LoadOptions { memory_limit: None, ..Default::default() }).unwrap();
    assert_eq!(loaded.flexible_bodies.len(), 1);
    assert_eq!(loaded.flexible_bodies[0].mode_set, "4N");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Records the pendulum to 1 s with `restart`, returning every frame it reported (time and values).
fn record_frames(dir: &Path, restart: Restart) -> (Vec<(f64, Vec<f64>)>, serde_json::Value) {
    let loaded = load_model_with(&pendulum(), &LoadOptions::default()).unwrap();
    let mut defaults = loaded.simulation;
    defaults.t_end = 1.0;
    let settings = defaults.settings(&loaded.model, defaults.assembly());
    std::fs::create_dir_all(dir).unwrap();
    let outputs = RunOutputs::in_directory(dir, "pendulum");
    let mut frames = Vec::new();
    let observe = &mut |frame: &flexmb::analysis::OutputFrame| frames.push((frame.t, frame.values.to_vec()));
    let run = record_model_run(&loaded, &settings, "pendulum.toml", &outputs, restart, observe, &|| None).unwrap();
    assert!(run.error.is_none());
    (frames, summary(&outputs.summary))
}

#[test]
fn a_run_paused_saved_and_resumed_through_the_library_reports_the_frames_of_one_run_bit_for_bit() {
    let dir = scratch("restart");
    let state = dir.join("state.json");
    let (whole, whole_summary) = record_frames(&dir.join("whole"), Restart::default());
    let pause = Restart { save_state: Some(&state), pause_at: Some(0.5), ..Default::default() };
    let (mut split, first_summary) = record_frames(&dir.join("first"), pause);
    assert_eq!(first_summary["status"], "interrupted");
    let (second, summary) = record_frames(&dir.join("second"), Restart { resume: Some(&state), ..Default::default() });
    assert!(split.len() > 10 && second.len() > 10, "{} and {} frames", split.len(), second.len());
    split.extend(second);
    // The same steps from the same state: the same numbers, not merely close ones.
    assert_eq!(split, whole);
    assert_eq!(summary["statistics"]["steps"], whole_summary["statistics"]["steps"]);
    assert_eq!(summary["energy"]["final"], whole_summary["energy"]["final"]);
}
