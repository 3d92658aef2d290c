//! Input that once made a command hang, exhaust memory or pass a wrong answer as success: devices and
//! directories given as files, files over the size limit. Each command must end quickly with an error
//! that names the file and what is wrong, never a panic.

mod program;

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
