//! `flexmb plot`, `flexmb run --plot` and `flexmb spectrum` as a user runs them: images of the size
//! asked for with something drawn on them, legends that name the runs, clear errors, and spectra that
//! find known frequencies — of a sampled sinusoid, and of an oscillator model run through flexmb.

use crate::program;

use std::f64::consts::TAU;
use std::path::Path;

use program::{fail, scratch, succeed};

/// Width and height from a PNG's IHDR chunk (bytes 16 to 24, after the signature and chunk header).
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

/// The fraction of pixels of a PNG that are not white background.
fn drawn_fraction(path: &Path) -> f64 {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut pixels = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut pixels).unwrap();
    let channels = info.color_type.samples();
    let pixels = &pixels[..info.buffer_size()];
    let drawn = pixels.chunks(channels).filter(|p| p.iter().take(3).any(|c| *c < 250)).count();
    drawn as f64 / (pixels.len() / channels) as f64
}

/// A column to write: name, unit, and its value as a function of time.
type Column<'a> = (&'a str, &'a str, &'a dyn Fn(f64) -> f64);

/// A result file of `columns(t)` sampled every `dt` up to `t_end`, with a summary giving units.
fn write_results(path: &Path, t_end: f64, dt: f64, columns: &[Column]) {
    let names: Vec<&str> = columns.iter().map(|c| c.0).collect();
    let mut csv = format!("t,{}\n", names.join(","));
    let rows = (t_end / dt).round() as usize + 1;
    for k in 0..rows {
        let t = k as f64 * dt;
        let values: Vec<String> = columns.iter().map(|c| format!("{:.10e}", (c.2)(t))).collect();
        csv += &format!("{t:.10e},{}\n", values.join(","));
    }
    std::fs::write(path, csv).unwrap();
    let units: Vec<serde_json::Value> =
        columns.iter().map(|c| serde_json::json!({ "name": c.0, "unit": c.1 })).collect();
    let summary = serde_json::json!({ "output": { "columns": units } });
    std::fs::write(path.with_extension("json"), summary.to_string()).unwrap();
}

/// The rows of the table of peaks `flexmb spectrum` prints: (rank, frequency, amplitude).
fn peak_table(report: &str) -> Vec<(usize, f64, f64)> {
    report
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("rank"))
        .skip(1)
        .map_while(|l| {
            let fields: Vec<&str> = l.split_whitespace().collect();
            match fields[..] {
                [rank, f, a] => Some((rank.parse().ok()?, f.parse().ok()?, a.parse().ok()?)),
                _ => None,
            }
        })
        .collect()
}

#[test]
fn spectrum_finds_a_known_sinusoid_far_finer_than_the_resolution() {
    // 7.3 Hz (1.5 mm) and 19 Hz (0.4 mm) on a linear trend, sampled at 1 kHz for 3 s: 1/T = 0.33 Hz.
    let dir = scratch("spectrum-sine");
    let csv = dir.join("wiper.csv");
    let y = |t: f64| 0.02 + 0.01 * t + 1.5e-3 * (TAU * 7.3 * t + 0.4).sin() + 4e-4 * (TAU * 19.0 * t).cos();
    write_results(&csv, 3.0, 1e-3, &[("tip.y", "m", &y)]);
    let image = dir.join("spectrum.png");
    let report = succeed(&["spectrum", csv.to_str().unwrap(), "--y", "tip.y", "--out", image.to_str().unwrap()]);
    assert!(report.contains("spectrum of tip.y [m]"), "{report}");
    assert!(report.contains("1/T = 0.33322 Hz (T = N Δt = 3.0010 s)"), "{report}");
    assert!(report.contains("Nyquist       500.00 Hz"), "{report}");
    let peaks = peak_table(&report);
    assert_eq!(peaks.len(), 2, "the two components and no side lobes:\n{report}");
    let (rank, f1, a1) = peaks[0];
    let (_, f2, a2) = peaks[1];
    assert_eq!(rank, 1);
    // Frequencies within 0.001 % (a five-thousandth of 1/T at 7.3 Hz), amplitudes within 0.1 %: the
    // printed digits and the CSV's 11 significant digits limit what this test sees.
    assert!((f1 / 7.3 - 1.0).abs() < 1e-5, "{report}");
    assert!((f2 / 19.0 - 1.0).abs() < 1e-5, "{report}");
    assert!((a1 / 1.5e-3 - 1.0).abs() < 1e-3, "{report}");
    assert!((a2 / 4e-4 - 1.0).abs() < 1e-3, "{report}");
    assert!(report.contains(&format!("spectrum plot: {}", image.display())), "{report}");
    let bytes = std::fs::read(&image).unwrap();
    assert_eq!(png_size(&bytes), (1200, 750));
    assert!(drawn_fraction(&image) > 0.01);
}

#[test]
fn spectrum_of_an_oscillator_run_through_flexmb_is_its_damped_natural_frequency() {
    // models/oscillator.toml: m = 2 kg, k = 2000 N/m, ζ = 0.05 → f_d = √(k/m) √(1 − ζ²) / 2π.
    let (m, k, zeta) = (2.0f64, 2000.0f64, 0.05f64);
    let f_natural = (k / m).sqrt() / TAU;
    let f_damped = f_natural * (1.0 - zeta * zeta).sqrt();
    let dir = scratch("spectrum-oscillator");
    succeed(&["run", "models/oscillator.toml", "--out", dir.to_str().unwrap(), "--quiet"]);
    let csv = dir.join("oscillator.csv");
    let report = succeed(&["spectrum", csv.to_str().unwrap(), "--y", "x", "--peaks", "3"]);
    let peaks = peak_table(&report);
    assert_eq!(peaks.len(), 1, "one mode, one peak:\n{report}");
    // f_d and f_n differ by 0.125 %; the spectrum tells them apart: within 0.002 % of f_d (0.0003 % is
    // reached; the record holds 20 periods, 1/T = 0.25 Hz).
    let f = peaks[0].1;
    assert!((f / f_damped - 1.0).abs() < 2e-5, "f = {f} Hz, f_d = {f_damped} Hz, f_n = {f_natural} Hz\n{report}");
    assert!(report.contains("spectrum of x [m]"), "the unit from the run's summary: {report}");

    // Over the last two seconds only: the same frequency, from the smaller, later oscillation.
    let report = succeed(&["spectrum", csv.to_str().unwrap(), "--y", "x", "--from", "2", "--to", "4"]);
    assert!(report.contains("t = 2 s to 4 s: 2001 samples"), "{report}");
    assert!((peak_table(&report)[0].1 / f_damped - 1.0).abs() < 2e-5, "{report}");
}

#[test]
fn plot_writes_a_png_of_the_requested_size_with_the_lines_on_it() {
    let dir = scratch("plot-png");
    succeed(&["run", "models/pendulum.toml", "--out", dir.to_str().unwrap(), "--quiet"]);
    let csv = dir.join("pendulum.csv");
    let stdout =
        succeed(&["plot", csv.to_str().unwrap(), "--y", "bob.position.y", "--width", "800", "--height", "500"]);
    let image = dir.join("pendulum_bob.position.y.png");
    assert_eq!(stdout.trim(), format!("plot: {}", image.display()), "the default image sits next to the CSV");
    assert_eq!(png_size(&std::fs::read(&image).unwrap()), (800, 500));
    let drawn = drawn_fraction(&image);
    assert!(drawn > 0.02 && drawn < 0.5, "text, grid and a line on a white background: {drawn}");
}

#[test]
fn plot_writes_svg_with_title_axis_labels_units_and_legend() {
    let dir = scratch("plot-svg");
    succeed(&["run", "models/pendulum.toml", "--out", dir.to_str().unwrap(), "--quiet"]);
    let image = dir.join("angle.svg");
    let csv = dir.join("pendulum.csv");
    let args = ["plot", csv.to_str().unwrap(), "--y", "pivot_angle", "--out", image.to_str().unwrap()];
    succeed(&[&args[..], &["--title", "Swing of the pendulum"]].concat());
    let svg = std::fs::read_to_string(&image).unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"), "{}", &svg[..200.min(svg.len())]);
    for expected in ["Swing of the pendulum", "pivot_angle [rad]", "t [s]", "<polyline"] {
        assert!(svg.contains(expected), "{expected} missing from the SVG");
    }
}

#[test]
fn overlays_name_each_file_in_the_legend() {
    let dir = scratch("plot-overlay");
    let (a, b) = (dir.join("door_4N.csv"), dir.join("door_8N.csv"));
    write_results(&a, 1.0, 0.01, &[("latch.y", "m", &|t| (TAU * 2.0 * t).sin())]);
    write_results(&b, 1.0, 0.01, &[("latch.y", "m", &|t| 0.9 * (TAU * 2.1 * t).sin())]);
    let image = dir.join("overlay.svg");
    succeed(&["plot", a.to_str().unwrap(), b.to_str().unwrap(), "--y", "latch.y", "--out", image.to_str().unwrap()]);
    let svg = std::fs::read_to_string(&image).unwrap();
    assert!(svg.contains("door_4N: latch.y") && svg.contains("door_8N: latch.y"), "legend names both runs");
    // One line of 101 points per file, in the palette's first two colours.
    let data_lines: Vec<&str> = svg.split("<polyline").filter(|p| p.matches(',').count() >= 101).collect();
    assert_eq!(data_lines.len(), 2, "one line per file");
    assert!(data_lines[0].contains("#1F77B4") && data_lines[1].contains("#FF7F0E"), "{data_lines:?}");
    assert!(svg.contains("latch.y [m]"), "the unit from the summaries");
}

#[test]
fn run_plot_writes_one_image_per_output_and_prints_their_paths() {
    let dir = scratch("run-plot");
    let stdout = succeed(&["run", "models/pendulum.toml", "--out", dir.to_str().unwrap(), "--plot"]);
    let line = stdout.lines().find(|l| l.starts_with("plots: ")).unwrap_or_else(|| panic!("{stdout}"));
    let images: Vec<&str> = line["plots: ".len()..].split(", ").collect();
    // marker_position, joint_reaction (forces and torques), measure, energy, constraint_residual.
    assert_eq!(images.len(), 6, "{line}");
    for name in ["pendulum_bob.position.png", "pendulum_pivot.reaction.f.png", "pendulum_pivot_angle.png"] {
        assert!(images.iter().any(|i| i.ends_with(name)), "{name} not in {line}");
    }
    for image in &images {
        assert_eq!(png_size(&std::fs::read(image).unwrap()), (1200, 750));
    }

    let stdout =
        succeed(&["run", "models/pendulum.toml", "--out", dir.to_str().unwrap(), "--quiet", "--plot", "energy.total"]);
    assert!(stdout.is_empty(), "--quiet prints nothing: {stdout}");
    assert!(dir.join("pendulum_energy.total.png").is_file());
}

#[test]
fn errors_say_what_is_wrong() {
    let dir = scratch("plot-errors");
    let csv = dir.join("r.csv");
    write_results(&csv, 1.0, 0.01, &[("bob.position.y", "m", &|t| t)]);
    let csv = csv.to_str().unwrap();

    let e = fail(&["plot", "no/such/file.csv", "--y", "x"]);
    assert!(e.contains("cannot read no/such/file.csv"), "{e}");

    let e = fail(&["plot", csv, "--y", "bob.postion.y"]);
    assert!(e.contains("has no column `bob.postion.y`; did you mean `bob.position.y`?"), "{e}");
    assert!(e.contains("available columns: t, bob.position.y"), "{e}");

    let empty = dir.join("empty.csv");
    std::fs::write(&empty, "").unwrap();
    let e = fail(&["plot", empty.to_str().unwrap(), "--y", "x"]);
    assert!(e.contains("is empty"), "{e}");

    let e = fail(&["plot", csv, "--y", "bob.position.y", "--out", "plot.jpg"]);
    assert!(e.contains("cannot write .jpg images; use a .png or .svg file name"), "{e}");

    let e = fail(&["plot", csv, "--y", "bob.position.y", "--width", "10"]);
    assert!(e.contains("width and height must be 200 to 8000 pixels"), "{e}");

    let e = fail(&["spectrum", csv, "--y", "bob.position.y", "--from", "0.5", "--to", "0.55"]);
    assert!(e.contains("6 samples between t = 0.5 s and 0.55 s; a spectrum needs at least 16"), "{e}");

    let e = fail(&["spectrum", csv, "--y", "z"]);
    assert!(e.contains("has no column `z`"), "{e}");
}

#[test]
fn every_reported_peak_lies_inside_the_spectrum_plot_and_above_its_floor() {
    // A large 2 Hz swing and a small 112 Hz vibration, a thousandth of it: on a linear amplitude axis
    // the small peak is a flat line under a pixel high, which is how a user's 112 Hz peak was hidden.
    use flexmb_cli::plot::{axis_ranges, ResultTable, Scale};
    use flexmb_cli::spectrum::{analyse, spectrum_figure, SpectrumOptions};
    let dir = scratch("spectrum-small-peak");
    let csv = dir.join("arm.csv");
    let y = |t: f64| 0.3 * (TAU * 2.0 * t).sin() + 3e-4 * (TAU * 112.0 * t).sin();
    write_results(&csv, 4.0, 1e-3, &[("tip.x", "m", &y)]);
    let table = ResultTable::read(&csv).unwrap();
    let options = SpectrumOptions {
        file: csv.clone(),
        y: "tip.x".into(),
        from: None,
        to: None,
        peaks: 5,
        band: Default::default(),
        out: None,
        y_scale: Scale::Log,
        size: (1200, 750),
    };
    let report = analyse(table.column("t").unwrap(), table.column("tip.x").unwrap(), &options).unwrap();
    let frequencies: Vec<f64> = report.peaks.iter().map(|p| p.frequency).collect();
    assert_eq!(frequencies.len(), 2, "{frequencies:?}");
    assert!((frequencies[0] - 2.0).abs() < 1e-4 && (frequencies[1] - 112.0).abs() < 1e-3, "{frequencies:?}");
    for scale in [Scale::Log, Scale::Linear] {
        let figure = spectrum_figure(&table, "tip.x", Some("m".into()), &report, scale);
        let ((f0, f1), (a0, a1)) = axis_ranges(&figure).unwrap();
        assert!(f0 <= 0.0 && f1 >= 1.5 * 112.0, "{scale:?}: the frequency axis {f0} to {f1} Hz");
        assert_eq!(figure.annotations.len(), 2, "{scale:?}: both peaks marked");
        for peak in &report.peaks {
            assert!(peak.amplitude < a1, "{scale:?}: {peak:?} under the top {a1}");
            match scale {
                Scale::Log => assert!(peak.amplitude >= 10.0 * a0, "a decade above the floor {a0}: {peak:?}"),
                Scale::Linear => assert!(peak.amplitude > a0, "above the floor {a0}: {peak:?}"),
            }
        }
    }
    // On the linear axis the report says which peak shows only as its marker.
    let image = dir.join("linear.png");
    let printed =
        succeed(&["spectrum", csv.to_str().unwrap(), "--y", "tip.x", "--scale", "linear", "--out", image.to_str().unwrap()]);
    assert!(printed.contains("the peaks at 112.00 Hz are below 1 % of its height"), "{printed}");
    let printed = succeed(&["spectrum", csv.to_str().unwrap(), "--y", "tip.x", "--out", image.to_str().unwrap()]);
    assert!(!printed.contains("below 1 %"), "the log axis shows both: {printed}");
}

#[test]
fn campbell_diagram_is_written_at_its_size_with_the_critical_speed_of_a_constant_mode() {
    use flexmb_cli::plot::campbell::{critical_speeds, write_campbell, CriticalSpeed};
    let dir = scratch("campbell");
    let values: Vec<f64> = (0..=20).map(|k| k as f64).collect();
    let frequencies: Vec<Vec<f64>> = values.iter().map(|x| vec![10.0, 12.0 + 0.5 * x]).collect();
    let image = dir.join("campbell.png");
    write_campbell(&image, "spin [rev/s]", &values, &frequencies, Some(1.0)).unwrap();
    assert_eq!(png_size(&std::fs::read(&image).unwrap()), (1200, 750));
    assert!(drawn_fraction(&image) > 0.01);
    let found = critical_speeds(&values, &frequencies, 1.0);
    assert_eq!(found[0], CriticalSpeed { mode: 0, value: 10.0, frequency_hz: 10.0 });
    assert_eq!(found.len(), 1, "mode 2 meets the 1× line at 24 rev/s, past the sweep: {found:?}");
    let svg = dir.join("campbell.svg");
    write_campbell(&svg, "spin [rev/s]", &values, &frequencies, None).unwrap();
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("Campbell diagram") && text.contains("mode 2") && !text.contains("1×"), "no 1× line asked");
    let e = write_campbell(&dir.join("campbell.jpg"), "spin", &values, &frequencies, None).unwrap_err();
    assert!(e.contains("use a .png or .svg"), "{e}");
}

#[test]
fn plot_draws_a_time_window_and_refuses_an_empty_one() {
    let dir = scratch("plot-window");
    let csv = dir.join("swing.csv");
    write_results(&csv, 5.0, 0.01, &[("x", "m", &|t: f64| t.sin())]);
    let image = dir.join("window.svg");
    let csv_arg = csv.to_str().unwrap();
    succeed(&["plot", csv_arg, "--y", "x", "--from", "1", "--to", "2", "--out", image.to_str().unwrap()]);
    assert!(std::fs::read_to_string(&image).unwrap().contains("<svg"));
    let e = fail(&["plot", csv_arg, "--y", "x", "--from", "2", "--to", "1"]);
    assert!(e.contains("--from 2 s is not before --to 1 s"), "{e}");
    let e = fail(&["plot", csv_arg, "--y", "x", "--from", "6"]);
    assert!(e.contains("no row has 6 ≤ t ≤ ∞ s; its times run from 0 to 5 s"), "{e}");
}
