//! An interrupted run keeps its summary (issue 14): SIGINT or SIGTERM during `flexmb run` ends the run
//! after its current step with whole CSV rows, a JSON summary that says `"status": "interrupted"`, when
//! and why, a ParaView series that is complete up to its last frame, and the conventional exit status.

use crate::program;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use program::{scratch, text, workspace, ResultCsv};

/// Starts the door for 400 s (80,001 output times, within the default limit of ParaView frames), sends `signal` with the `kill` program once the CSV has 50 rows, and
/// returns the exit status, the standard error and the output directory.
fn interrupt_the_door(name: &str, signal: &str, vtk: bool) -> (Option<i32>, String, std::path::PathBuf) {
    let out = scratch(name);
    let mut command = Command::new(env!("CARGO_BIN_EXE_flexmb"));
    command.args(["run", "models/door/door.toml", "--t-end", "400", "--quiet", "--out", out.to_str().unwrap()]);
    if vtk {
        command.args(["--vtk", out.join("vtk").to_str().unwrap()]);
    }
    let mut child = command.current_dir(workspace()).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("flexmb starts");
    let csv = out.join("door.csv");
    let started = Instant::now();
    while std::fs::read_to_string(&csv).map_or(0, |t| t.lines().count()) < 51 {
        assert!(started.elapsed() < Duration::from_secs(120), "no rows written");
        if let Some(status) = child.try_wait().unwrap() {
            let mut stderr = String::new();
            std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut stderr).unwrap();
            panic!("flexmb ended before it was interrupted ({status}): {stderr}");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let kill = Command::new("kill").args([signal, &child.id().to_string()]).status().expect("kill runs");
    assert!(kill.success());
    let output = child.wait_with_output().unwrap();
    (output.status.code(), text(&output.stderr), out)
}

/// The CSV's rows, each whole, at the output times 0, 0.005 s, … in order.
fn check_rows(csv: &Path) -> ResultCsv {
    let raw = std::fs::read_to_string(csv).unwrap();
    assert!(raw.ends_with('\n'), "the last line is whole");
    let table = ResultCsv::read(csv);
    for (k, row) in table.rows.iter().enumerate() {
        assert_eq!(row.len(), table.header.len(), "row {k}");
        assert!((row[0] - 0.005 * k as f64).abs() < 1e-9, "row {k} at t = {}", row[0]);
    }
    table
}

/// The summary of an interrupted run: status, when and why, and the statistics so far.
fn check_summary(path: &Path, reason: &str, csv: &ResultCsv) -> f64 {
    let s: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    assert_eq!(s["status"], "interrupted", "{s}");
    assert_eq!(s["reason"], reason);
    assert!(s["error"].is_null());
    let at = s["interrupted_at"].as_f64().unwrap();
    let last = csv.at(-1, "t");
    assert!(last <= at && at < last + 0.005, "interrupted at t = {at} s, last row at {last} s");
    assert_eq!(s["t_reached"].as_f64().unwrap(), at);
    assert!(s["statistics"]["steps"].as_u64().unwrap() > 10, "{}", s["statistics"]);
    assert_eq!(s["output"]["rows"].as_u64().unwrap() as usize, csv.rows.len());
    assert!(s["energy"]["final"].as_f64().unwrap() > 30.0, "{}", s["energy"]);
    at
}

/// The `file` and `timestep` of every `DataSet` of a `.pvd`, which must be well-formed XML.
fn read_pvd(path: &Path) -> Vec<(String, f64)> {
    use quick_xml::events::Event;
    let text = std::fs::read_to_string(path).unwrap();
    let mut reader = quick_xml::Reader::from_str(&text);
    let (mut depth, mut entries) = (0_i32, Vec::new());
    loop {
        match reader.read_event().unwrap_or_else(|e| panic!("{}: not XML: {e}", path.display())) {
            Event::Start(_) => depth += 1,
            Event::End(_) => depth -= 1,
            Event::Empty(e) if e.name().as_ref() == b"DataSet" => {
                let attribute = |name: &str| {
                    let a = e.try_get_attribute(name).unwrap().unwrap_or_else(|| panic!("{name} of a DataSet"));
                    a.unescape_value().unwrap().into_owned()
                };
                entries.push((attribute("file"), attribute("timestep").parse().unwrap()));
            }
            Event::Eof => break,
            _ => {}
        }
    }
    assert_eq!(depth, 0, "{}: every element is closed", path.display());
    entries
}

#[test]
fn sigint_ends_the_run_with_its_rows_summary_and_paraview_series() {
    let (status, stderr, out) = interrupt_the_door("sigint", "-INT", true);
    assert_eq!(status, Some(130), "128 + SIGINT: {stderr}");
    assert!(stderr.contains("interrupted by SIGINT") && !stderr.contains("panicked"), "{stderr}");
    let csv = check_rows(&out.join("door.csv"));
    let at = check_summary(&out.join("door.json"), "SIGINT", &csv);
    let entries = read_pvd(&out.join("vtk/door.pvd"));
    assert!(entries.len() >= 50, "{} entries", entries.len());
    for (file, time) in &entries {
        assert!(out.join("vtk").join(file).is_file(), "{file}");
        assert!(*time <= at + 1e-9, "a frame at {time} s after the interruption at {at} s");
    }
    let last_frame = entries.iter().map(|e| e.1).fold(0.0, f64::max);
    assert!((last_frame - csv.at(-1, "t")).abs() < 1e-3, "the series ends with the CSV: {last_frame} s");
}

#[test]
fn sigterm_ends_the_run_with_its_rows_and_summary() {
    let (status, stderr, out) = interrupt_the_door("sigterm", "-TERM", false);
    assert_eq!(status, Some(143), "128 + SIGTERM: {stderr}");
    assert!(stderr.contains("interrupted by SIGTERM"), "{stderr}");
    let csv = check_rows(&out.join("door.csv"));
    check_summary(&out.join("door.json"), "SIGTERM", &csv);
}
