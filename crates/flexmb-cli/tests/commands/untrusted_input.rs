//! Input that once made a command hang, exhaust memory or pass a wrong answer as success: devices and
//! directories given as files, files over the size limit. Each command must end quickly with an error
//! that names the file and what is wrong, never a panic.

use crate::program;

use program::{fail_within, scratch};

/// A shipped model with `[[flexible_body]] fe_model` pointing at `target`.
fn flexible_body_on(target: &str) -> String {
    format!("[model]\n\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"{target}\"\nmodes = \"1N\"\n")
}

#[cfg(unix)]
#[test]
fn a_device_is_refused_as_model_fe_model_mesh_and_include() {
    let device = "it is a character device, not a regular file";
    for command in ["check", "run"] {
        let e = fail_within(&[command, "/dev/zero"], &[]);
        assert!(e.contains(&format!("/dev/zero: cannot read the model file: {device}")), "{e}");
    }
    let e = fail_within(&["modes", "/dev/zero", "--modes", "1N"], &[]);
    assert!(e.contains(&format!("/dev/zero: cannot read the FE model file: {device}")), "{e}");

    let dir = scratch("device");
    let model = dir.join("arm.toml");
    std::fs::write(&model, flexible_body_on("/dev/zero")).unwrap();
    let e = fail_within(&["check", model.to_str().unwrap()], &[]);
    assert!(e.contains("arm.toml:5: flexible_body[0].fe_model: cannot read the FE model file `/dev/zero`"), "{e}");
    assert!(e.contains(device), "{e}");

    let fe_model = dir.join("fe.toml");
    std::fs::write(&fe_model, "[fe_model]\nmesh = \"/dev/zero\"\n").unwrap();
    let e = fail_within(&["modes", fe_model.to_str().unwrap(), "--modes", "1N"], &[]);
    assert!(e.contains(&format!("fe.toml:2: fe_model.mesh: cannot read the mesh file `/dev/zero`: {device}")), "{e}");

    let deck = dir.join("deck.inp");
    std::fs::write(&deck, "*NODE\n1, 0, 0, 0\n*INCLUDE, INPUT=/dev/zero\n").unwrap();
    let e = fail_within(&["modes", deck.to_str().unwrap(), "--modes", "1N"], &[]);
    assert!(e.contains(&format!("deck.inp:3: *INCLUDE: cannot read /dev/zero: {device}")), "{e}");

    let e = fail_within(&["plot", "/dev/zero", "--y", "x", "--out", dir.join("p.png").to_str().unwrap()], &[]);
    assert!(e.contains(&format!("cannot read /dev/zero: {device}")), "{e}");
    let e = fail_within(&["spectrum", "/dev/zero", "--y", "x"], &[]);
    assert!(e.contains(&format!("cannot read /dev/zero: {device}")), "{e}");
}

#[cfg(unix)]
#[test]
fn a_link_to_a_device_is_followed_and_refused() {
    let dir = scratch("link");
    std::os::unix::fs::symlink("/dev/zero", dir.join("part.stl")).unwrap();
    let model = dir.join("shaped.toml");
    std::fs::write(&model, "[model]\n\n[[body]]\nname = \"b\"\nmass = 1\ninertia = [1, 1, 1]\nshape = { mesh = \"part.stl\" }\n")
        .unwrap();
    let e = fail_within(&["check", model.to_str().unwrap()], &[]);
    assert!(e.contains("shaped.toml:7: body[0].shape.mesh: mesh file"), "{e}");
    assert!(e.contains("part.stl: it is a character device, not a regular file"), "{e}");
}

#[test]
fn a_directory_is_refused_as_a_model() {
    let dir = scratch("directory");
    for command in ["check", "run"] {
        let e = fail_within(&[command, dir.to_str().unwrap()], &[]);
        assert!(e.contains(&format!("{}: cannot read the model file: it is a directory, not a regular file", dir.display())), "{e}");
    }
}

#[test]
fn files_over_the_size_limit_are_refused_unless_the_limit_is_raised() {
    let limit = [("FLEXMB_MAX_FILE_SIZE", "1k")];
    let e = fail_within(&["check", "models/pendulum.toml"], &limit);
    assert!(e.contains("models/pendulum.toml: cannot read the model file: it is larger than 1 kiB (the limit on input files)"), "{e}");
    assert!(e.contains("set FLEXMB_MAX_FILE_SIZE to a larger size"), "{e}");
    // The FE model of a flexible body is read under the same limit (the model file itself is smaller).
    let dir = scratch("size");
    let model = dir.join("arm.toml");
    std::fs::copy(program::workspace().join("models/fe/pendulum_beam.toml"), dir.join("beam.toml")).unwrap();
    std::fs::write(&model, flexible_body_on("beam.toml")).unwrap();
    let e = fail_within(&["check", model.to_str().unwrap()], &[("FLEXMB_MAX_FILE_SIZE", "200")]);
    assert!(e.contains("flexible_body[0].fe_model: cannot read the FE model file") && e.contains("larger than 200 bytes"), "{e}");

    let o = program::flexmb_within(&["check", "models/pendulum.toml"], &[("FLEXMB_MAX_FILE_SIZE", "64k")]);
    assert!(o.status.success(), "{}", program::text(&o.stderr));
    let e = fail_within(&["check", "models/pendulum.toml"], &[("FLEXMB_MAX_FILE_SIZE", "lots")]);
    assert!(e.contains("FLEXMB_MAX_FILE_SIZE=`lots` is not a size"), "{e}");
}

/// A result file `t,x` of 64 rows every 0.01 s, `x` a 5 Hz sinusoid except where `special` says.
fn results_with(dir: &std::path::Path, name: &str, special: impl Fn(usize) -> Option<String>) -> String {
    let mut csv = String::from("t,x\n");
    for k in 0..64 {
        let t = k as f64 * 0.01;
        let x = special(k).unwrap_or_else(|| format!("{}", (std::f64::consts::TAU * 5.0 * t).sin()));
        csv += &format!("{t},{x}\n");
    }
    let path = dir.join(name);
    std::fs::write(&path, csv).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn plot_and_spectrum_of_huge_or_non_finite_columns_end_with_an_error() {
    let dir = scratch("plot");
    let image = dir.join("out.png");
    let image = image.to_str().unwrap();
    // The span of ±1.7e308 overflows: plotters' tick computation never ended on it.
    let huge = results_with(&dir, "huge.csv", |k| Some(if k % 2 == 0 { "1.7e308" } else { "-1.7e308" }.to_string()));
    let e = fail_within(&["plot", &huge, "--y", "x", "--out", image], &[]);
    assert!(e.contains("cannot plot: the values along the y axis run from -1.7e308 (column `x`, "), "{e}");
    assert!(e.contains("huge.csv:3) to 1.7e308 (column `x`, ") && e.contains("more than the largest double-precision number"), "{e}");
    let e = fail_within(&["plot", &huge, "--x", "x", "--y", "t", "--out", image], &[]);
    assert!(e.contains("the values along the x axis run from -1.7e308"), "{e}");
    let e = fail_within(&["spectrum", &huge, "--y", "x", "--out", image], &[]);
    assert!(e.contains("huge.csv: the values reach 1.7e308: their amplitudes pass the largest double-precision number"), "{e}");

    for (value, name) in [("inf", "inf.csv"), ("-inf", "minus_inf.csv"), ("NaN", "nan.csv")] {
        let file = results_with(&dir, name, |k| (k == 12).then(|| value.to_string()));
        let e = fail_within(&["plot", &file, "--y", "x", "--out", image], &[]);
        assert!(e.contains(&format!("{name}:14: column `x` holds {value}; a plot needs finite values")), "{e}");
        let e = fail_within(&["spectrum", &file, "--y", "x", "--out", image], &[]);
        assert!(e.contains(&format!("spectrum of `x` in {file}: the value at t = 0.12 s is {value}")), "{e}");
    }
    // A spectrum of values near the largest double is computed (scaled), but its plot cannot hold them.
    let near = results_with(&dir, "near.csv", |k| Some(format!("{:e}", 1.75e308 * (std::f64::consts::TAU * 0.05 * k as f64).sin())));
    let e = fail_within(&["spectrum", &near, "--y", "x", "--out", image, "--scale", "linear"], &[]);
    assert!(e.contains("cannot draw the y axis (amplitude)"), "{e}");
}

#[test]
fn a_spectrum_refuses_times_it_cannot_resample() {
    let dir = scratch("times");
    let mut csv = String::from("t,x\n");
    for k in 0..64 {
        let t = if k == 63 { 1e8 } else { k as f64 * 0.01 };
        csv += &format!("{t},{}\n", (k as f64).sin());
    }
    std::fs::write(dir.join("late.csv"), csv).unwrap();
    let e = fail_within(&["spectrum", dir.join("late.csv").to_str().unwrap(), "--y", "x"], &[]);
    assert!(e.contains("would make 1.000e10 samples, more than 10000000; choose a stretch with --from and --to"), "{e}");
}

#[test]
fn output_grids_beyond_the_row_limit_are_refused_before_the_run() {
    let dir = scratch("rows");
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let e = fail_within(&["run", "models/pendulum.toml", "--output-step", "1e-9", "--out", out], &[]);
    assert!(
        e.contains(
            "models/pendulum.toml: an output step of 1e-9 s up to t_end = 5 s would write 5000000001 output \
             rows, more than the limit of 10000000"
        ),
        "{e}"
    );
    assert!(e.contains("--max-output-rows 5000000001 (or max_output_rows = 5000000001 in the model's [simulation])"), "{e}");
    assert!(!dir.join("out/pendulum.csv").exists(), "nothing is written");
    let e = fail_within(&["compare", "models/pendulum.toml", "--integrators", "bdf", "--t-end", "1e6"], &[]);
    assert!(e.contains("would write 100000001 output rows") && e.contains("max_output_rows = 100000001 in the model's"), "{e}");

    // The limit is the user's to raise, on the command line or in the file.
    let args = ["run", "models/pendulum.toml", "--t-end", "0.1", "--quiet", "--out", out];
    let e = fail_within(&[&args[..], &["--max-output-rows", "10"]].concat(), &[]);
    assert!(e.contains("would write 11 output rows, more than the limit of 10"), "{e}");
    let o = program::flexmb_within(&[&args[..], &["--max-output-rows", "11"]].concat(), &[]);
    assert!(o.status.success(), "{}", program::text(&o.stderr));
    let model = dir.join("limited.toml");
    let pendulum = std::fs::read_to_string(program::workspace().join("models/pendulum.toml")).unwrap();
    std::fs::write(&model, pendulum.replace("[simulation]\n", "[simulation]\nmax_output_rows = 10\n")).unwrap();
    let e = fail_within(&["run", model.to_str().unwrap(), "--t-end", "0.1", "--out", out], &[]);
    assert!(e.contains("would write 11 output rows, more than the limit of 10"), "{e}");
    std::fs::write(&model, pendulum.replace("[simulation]\n", "[simulation]\nmax_output_rows = 0.5\n")).unwrap();
    let e = fail_within(&["check", model.to_str().unwrap()], &[]);
    assert!(e.contains("simulation.max_output_rows: max_output_rows must be a whole number of at least 1, got 0.5"), "{e}");
}

#[test]
fn paraview_series_beyond_the_frame_limit_are_refused_before_the_run() {
    let dir = scratch("frames");
    let vtk = dir.join("vtk");
    let (out, vtk) = (dir.to_str().unwrap(), vtk.to_str().unwrap());
    let run = ["run", "models/pendulum.toml", "--t-end", "1000", "--output-step", "1e-3", "--out", out, "--vtk", vtk];
    let e = fail_within(&run, &[]);
    assert!(
        e.contains(
            "ParaView frames every 0.001 s up to t_end = 1000 s would be 1000001 frames (a file per body and joint \
             each), more than the limit of 100000"
        ),
        "{e}"
    );
    assert!(e.contains("--max-vtk-frames 1000001"), "{e}");
    assert!(!dir.join("vtk/pendulum").exists(), "no frame is written");
    let short = ["run", "models/pendulum.toml", "--t-end", "0.05", "--quiet", "--out", out, "--vtk", vtk];
    let e = fail_within(&[&short[..], &["--max-vtk-frames", "5"]].concat(), &[]);
    assert!(e.contains("would be 6 frames"), "{e}");
    let o = program::flexmb_within(&[&short[..], &["--max-vtk-frames", "6"]].concat(), &[]);
    assert!(o.status.success(), "{}", program::text(&o.stderr));
}

#[test]
fn an_empty_truncated_or_bodiless_model_fails_check_and_run() {
    let dir = scratch("empty");
    let cases = [
        ("empty.toml", "", "empty.toml:1: no [model] table: a model file must have one"),
        ("headless.toml", "[[body]]\nname = \"b\"\nmass = 1\ninertia = [1, 1, 1]\n", "headless.toml:1: no [model] table"),
        (
            "cut.toml",
            "# cut short after its first table\n[model]\nname = \"cut\"\n",
            "cut.toml:2: the model has no bodies: it needs at least one [[body]] or [[flexible_body]] table",
        ),
    ];
    for (name, text, message) in cases {
        let model = dir.join(name);
        std::fs::write(&model, text).unwrap();
        let (path, out) = (model.to_str().unwrap(), dir.to_str().unwrap());
        for args in [&["check", path][..], &["run", path, "--out", out]] {
            let e = fail_within(args, &[]);
            assert!(e.contains(message), "{args:?}: {e}");
            assert!(!e.contains("degrees of freedom"), "{e}");
        }
    }
}

#[test]
fn absurd_magnitudes_are_refused_at_their_key_not_reported_as_a_singular_matrix() {
    let dir = scratch("magnitudes");
    let pendulum = std::fs::read_to_string(program::workspace().join("models/pendulum.toml")).unwrap();
    let heavy = dir.join("heavy.toml");
    std::fs::write(&heavy, pendulum.replace("mass = \"m_bob\"", "mass = 1e308")).unwrap();
    let (heavy, out) = (heavy.to_str().unwrap(), dir.to_str().unwrap());
    for args in [&["check", heavy][..], &["run", heavy, "--out", out]] {
        let e = fail_within(args, &[]);
        assert!(e.contains("heavy.toml:31: body[0].mass: 1e308 kg is outside the range of a mass, |x| ≤ 1e12 kg"), "{e}");
        assert!(!e.contains("singular"), "{e}");
    }

    let cantilever = std::fs::read_to_string(program::workspace().join("models/fe/cantilever.toml")).unwrap();
    let stiff = dir.join("stiff.toml");
    std::fs::write(&stiff, cantilever.replace("E = 210e9", "E = 1e308")).unwrap();
    let e = fail_within(&["modes", stiff.to_str().unwrap()], &[]);
    assert!(e.contains("material[0].E: 1e308 Pa is outside the range of an elastic modulus, |x| ≤ 1e15 Pa"), "{e}");

    let deck = dir.join("dense.inp");
    let text = "*NODE\n1, 0, 0, 0\n2, 0.5, 0, 0\n3, 1, 0, 0\n*ELEMENT, TYPE=B31, ELSET=BEAM\n1, 1, 2\n2, 2, 3\n\
                *MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n*DENSITY\n1e300\n\
                *BEAM SECTION, ELSET=BEAM, MATERIAL=STEEL, SECTION=RECT\n0.02, 0.01\n0, 1, 0\n*BOUNDARY\n1, 1, 6\n";
    std::fs::write(&deck, text).unwrap();
    let e = fail_within(&["modes", deck.to_str().unwrap(), "--modes", "2N"], &[]);
    assert!(e.contains("dense.inp:12: *DENSITY: the density (field 1): 1e300 kg/m³ is outside the range of a density"), "{e}");
    assert!(!e.contains("mechanism"), "{e}");
}
