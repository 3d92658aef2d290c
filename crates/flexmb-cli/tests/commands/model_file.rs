//! The model-file layer: every shipped model builds, and every kind of bad input gives an error that
//! names the file, the line and the key path (never a panic).

use std::path::{Path, PathBuf};

use flexmb_files::model_file::{load_model, parse_model, ErrorKind, ModelFileError};

fn models_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models")
}

fn shipped_models() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(models_dir())
        .expect("models/ exists")
        .map(|entry| entry.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    paths
}

#[test]
fn every_shipped_model_parses_and_builds() {
    let paths = shipped_models();
    assert!(!paths.is_empty());
    for path in paths {
        let loaded = load_model(&path).unwrap_or_else(|e| panic!("{e}"));
        let stem = path.file_stem().and_then(|s| s.to_str()).expect("file stem");
        assert!(!loaded.model.bodies().is_empty(), "{stem} has bodies");
        assert!(!loaded.model.outputs().is_empty(), "{stem} requests outputs");
        assert!(loaded.simulation.t_end > 0.0);
    }
}

/// The error `text` gives, with its display.
fn error_of(text: &str) -> (ModelFileError, String) {
    match parse_model(text, "models/bad.toml") {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => {
            let shown = e.to_string();
            (e, shown)
        }
    }
}

/// Asserts the error's line, key path and that its display starts with `file:line: key:` and
/// contains every fragment.
fn assert_error(text: &str, line: usize, key_path: &str, fragments: &[&str]) -> ModelFileError {
    let (e, shown) = error_of(text);
    assert_eq!(e.line, Some(line), "line of: {shown}");
    assert_eq!(e.key_path, key_path, "key path of: {shown}");
    let prefix = match key_path {
        "" => format!("models/bad.toml:{line}: "),
        key_path => format!("models/bad.toml:{line}: {key_path}: "),
    };
    assert!(shown.starts_with(&prefix), "`{shown}` should start with `{prefix}`");
    for fragment in fragments {
        assert!(shown.contains(fragment), "`{shown}` should contain `{fragment}`");
    }
    e
}

/// Lines 1-13 of most test files: line 1 is `[model]`, `[[body]]` is line 2, `mass` line 4, `inertia`
/// line 5, the first marker's `body` line 9, the ground marker ends on line 13.
const BODY: &str = r#"[model]
[[body]]
name = "link"
mass = 2.0
inertia = [0.1, 0.1, 0.02]

[[marker]]
name = "pin"
body = "link"

[[marker]]
name = "base"
body = "ground"
"#;

#[test]
fn a_minimal_model_builds_with_defaults() {
    let loaded = parse_model(BODY, "dir/minimal.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.model.name(), "minimal");
    assert_eq!(loaded.simulation, flexmb_files::SimulationDefaults::default());
    assert_eq!(loaded.simulation.t_end, 1.0);
    assert_eq!(loaded.model.markers().len(), 2);
}

#[test]
fn unknown_key_names_key_line_and_allowed_keys() {
    let text = format!("{BODY}\n[[joint]]\nname = \"j\"\ntype = \"revolute\"\ni = \"base\"\nj = \"pin\"\nlenght = 2\n");
    // BODY fills lines 1-13 (line 1 is `[model]`); then blank 14, [[joint]] 15, name 16, type 17, i 18, j 19
    assert_error(&text, 20, "joint[0].lenght", &["unknown key `lenght`", "did you mean `length`?", "`axis_i`"]);
}

#[test]
fn an_unknown_key_ending_in_a_digit_keeps_its_digit() {
    let text = format!("{BODY}\n[[joint]]\nname = \"j\"\ntype = \"revolute\"\ni = \"base\"\nj = \"pin\"\naxis2 = [0, 0, 1]\n");
    assert_error(&text, 20, "joint[0].axis2", &["unknown key `axis2`"]);
}

#[test]
fn missing_required_key_is_reported_at_its_table() {
    let text = "[model]\nname = \"m\"\n\n[[body]]\nname = \"a\"\nmass = 1.0\ninertia = [1, 1, 1]\n\n[[body]]\nname = \"b\"\ninertia = [1, 1, 1]\n";
    let e = assert_error(text, 9, "body[1].mass", &["missing required key `mass`"]);
    assert_eq!(e.kind, ErrorKind::Schema);
}

#[test]
fn marker_on_a_body_that_does_not_exist() {
    let text = BODY.replace("name = \"pin\"\nbody = \"link\"", "name = \"pin\"\nbody = \"lnik\"");
    assert_error(&text, 9, "marker[0].body", &["no body named `lnik`", "did you mean `link`?"]);
}

#[test]
fn negative_mass() {
    let text = BODY.replace("mass = 2.0", "mass = -1");
    assert_error(&text, 4, "body[0].mass", &["mass must be positive and finite, got -1"]);
}

#[test]
fn non_physical_inertia() {
    let text = BODY.replace("inertia = [0.1, 0.1, 0.02]", "inertia = [0.1, 0.1, 0.5]");
    assert_error(&text, 5, "body[0].inertia", &["triangle inequality"]);
    let text = BODY.replace("inertia = [0.1, 0.1, 0.02]", "inertia = { xx = 0.1, yy = -0.1, zz = 0.02 }");
    assert_error(&text, 5, "body[0].inertia", &["positive definite"]);
}

#[test]
fn unknown_joint_type() {
    let text = format!("{BODY}\n[[joint]]\nname = \"j\"\ntype = \"revolut\"\ni = \"base\"\nj = \"pin\"\n");
    assert_error(
        &text,
        17,
        "joint[0].type",
        &["unknown joint type `revolut`", "did you mean `revolute`?", "`point-on-line`"],
    );
}

/// Lines 14-24 after [`BODY`]: line 14 is empty, `[[joint]]` 15, `[[measure]]` 21.
const DRIVEN: &str = r#"
[[joint]]
name = "hinge"
type = "revolute"
i = "base"
j = "pin"

[[measure]]
name = "hinge_rate"
type = "joint_rate"
joint = "hinge"
"#;

#[test]
fn bad_expression() {
    let text = format!("{BODY}{DRIVEN}\n[[force]]\nname = \"motor\"\ntype = \"rotational_spring_damper\"\njoint = \"hinge\"\nactuator = \"2*(1 - hinge_rate\"\n");
    // BODY lines 1-13, DRIVEN lines 14-24, blank 25, [[force]] 26, name 27, type 28, joint 29, actuator 30
    assert_error(&text, 30, "force[0].actuator", &["`2*(1 - hinge_rate`", "never closed"]);
}

#[test]
fn unknown_measure_in_an_expression() {
    let text = format!("{BODY}{DRIVEN}\n[[force]]\nname = \"motor\"\ntype = \"rotational_spring_damper\"\njoint = \"hinge\"\nactuator = \"2*(1 - hinge_rat/10)\"\n");
    assert_error(&text, 30, "force[0].actuator", &["names `hinge_rat`", "did you mean `hinge_rate`?"]);
}

#[test]
fn wrong_vector_length() {
    let text = BODY.replace("name = \"pin\"\nbody = \"link\"", "name = \"pin\"\nbody = \"link\"\norigin = [0.1, 0.0]");
    assert_error(&text, 10, "marker[0].origin", &["expected a vector [x, y, z] with 3 components, got 2"]);
}

#[test]
fn toml_syntax_error() {
    let text = BODY.replace("mass = 2.0", "mass = = 2.0");
    let e = assert_error(&text, 4, "body[0].mass", &["TOML syntax error"]);
    assert_eq!(e.kind, ErrorKind::Syntax);
}

#[test]
fn unreadable_file_names_the_file() {
    let e = load_model(Path::new("models/does-not-exist.toml")).expect_err("missing file");
    assert_eq!(e.kind, ErrorKind::Io);
    assert!(e.to_string().starts_with("models/does-not-exist.toml: cannot read"), "{e}");
}

#[test]
fn inertia_of_the_wrong_shape_names_the_forms() {
    let text = BODY.replace("inertia = [0.1, 0.1, 0.02]", "inertia = [0.1, 0.1]");
    assert_error(&text, 5, "body[0].inertia", &["principal moments [Ixx, Iyy, Izz]", "3x3 matrix"]);
}

#[test]
fn duplicate_names_point_at_the_first_definition() {
    let text = BODY.replace("name = \"base\"", "name = \"pin\"");
    assert_error(&text, 12, "marker[1].name", &["marker name `pin` is already used by marker[0] on line 8"]);
}

#[test]
fn a_joint_with_both_markers_on_one_body() {
    let text = format!("{BODY}\n[[marker]]\nname = \"pin2\"\nbody = \"link\"\n\n[[joint]]\nname = \"j\"\ntype = \"spherical\"\ni = \"pin\"\nj = \"pin2\"\n");
    // lines 14-17: the third marker; blank 18, [[joint]] 19, name 20, type 21, i 22, j 23
    assert_error(&text, 23, "joint[0].j", &["both on body `link`"]);
}

#[test]
fn parameters_are_substituted_and_checked() {
    let text = format!("[parameters]\nm = \"2*half\"\nhalf = 0.5\n{BODY}").replace("mass = 2.0", "mass = \"m\"");
    let loaded = parse_model(&text, "p.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.model.bodies()[0].mass, 1.0);

    let cyclic = "[parameters]\na = \"b + 1\"\nb = \"2*a\"\n";
    assert_error(cyclic, 2, "parameters.a", &["cycle: a -> b -> a"]);

    let timed = "[parameters]\nk = \"3*t\"\n";
    assert_error(timed, 2, "parameters.k", &["depends on time `t`"]);

    let reserved = "[parameters]\nsin = 2\n";
    assert_error(reserved, 2, "parameters.sin", &["cannot name a parameter"]);
}

#[test]
fn exponent_literals_work_in_expressions() {
    let text = format!("[parameters]\nk = \"1.5e3\"\n{BODY}").replace("mass = 2.0", "mass = \"2e-3*k\"");
    let loaded = parse_model(&text, "p.toml").unwrap_or_else(|e| panic!("{e}"));
    assert!((loaded.model.bodies()[0].mass - 3.0).abs() < 1e-12);
}

#[test]
fn measure_names_must_suit_expressions() {
    let text = format!("{BODY}{DRIVEN}").replace("name = \"hinge_rate\"", "name = \"max_rate\"");
    assert_error(&text, 22, "measure[0].name", &["cannot begin with `max`"]);
    let text = format!("{BODY}{DRIVEN}").replace("name = \"hinge_rate\"", "name = \"e\"");
    assert_error(&text, 22, "measure[0].name", &["constant or function"]);
}

#[test]
fn a_measure_needs_a_suitable_joint() {
    let text = format!("{BODY}{DRIVEN}").replace("type = \"joint_rate\"", "type = \"joint_velocity\"");
    assert_error(&text, 24, "measure[0].joint", &["needs a translational", "`hinge` is revolute"]);
}

#[test]
fn a_key_that_does_not_apply_to_the_type() {
    let text = format!("{BODY}{DRIVEN}").replace("joint = \"hinge\"\n", "joint = \"hinge\"\nmarker = \"pin\"\n");
    assert_error(&text, 25, "measure[0].marker", &["does not apply to a joint_rate measure", "`joint`"]);
}

#[test]
fn a_key_the_type_requires() {
    let text = format!("{BODY}{DRIVEN}\n[[force]]\nname = \"push\"\ntype = \"force\"\nmarker = \"pin\"\n");
    // blank 25, [[force]] 26
    assert_error(&text, 26, "force[0].components", &["missing required key `components` for a force force"]);
}

#[test]
fn drivers_follow_their_joint() {
    let driver = "\n[[driver]]\nname = \"motion\"\njoint = \"hinge\"\nfunction = \"0.5*t^2\"\n";
    let text = format!("{BODY}{DRIVEN}{driver}");
    let loaded = parse_model(&text, "d.toml").unwrap_or_else(|e| panic!("{e}"));
    let joint = loaded.model.joints().iter().find(|j| j.name == "motion").expect("driver joint");
    assert_eq!(joint.kind.keyword(), "angle driver");

    let constant = format!("{BODY}{DRIVEN}{}", driver.replace("\"0.5*t^2\"", "0.25"));
    parse_model(&constant, "d.toml").unwrap_or_else(|e| panic!("{e}"));

    let wrong = format!("{BODY}{DRIVEN}{}", driver.replace("function", "type = \"displacement\"\nfunction"));
    // blank 25, [[driver]] 26, name 27, joint 28, type 29
    assert_error(&wrong, 29, "driver[0].type", &["needs a translational or cylindrical joint"]);

    let reads_measure = format!("{BODY}{DRIVEN}{}", driver.replace("0.5*t^2", "hinge_rate*t"));
    assert_error(&reads_measure, 29, "driver[0].function", &["may depend on time `t` only"]);
}

#[test]
fn orientation_forms_agree() {
    let with = |orientation: &str| {
        let text = BODY
            .replace("inertia = [0.1, 0.1, 0.02]", &format!("inertia = [0.1, 0.1, 0.02]\norientation = {orientation}"));
        let loaded = parse_model(&text, "o.toml").unwrap_or_else(|e| panic!("{e}"));
        loaded.model.bodies()[0].initial.orientation.rotation_matrix()
    };
    let by_angle = with("{ axis = [0, 0, 1], angle = 0.5 }");
    let by_degrees = with("{ axis = [0, 0, 2], angle_deg = 28.64788975654116 }");
    let (c, s) = (0.5f64.cos(), 0.5f64.sin());
    let by_matrix = with(&format!("{{ matrix = [[{c}, {}, 0], [{s}, {c}, 0], [0, 0, 1]] }}", -s));
    let by_parameters = with(&format!("{{ euler_parameters = [{}, 0, 0, {}] }}", 0.25f64.cos(), 0.25f64.sin()));
    for other in [by_degrees, by_matrix, by_parameters] {
        assert!((other - by_angle).abs().max() < 1e-12, "{other} vs {by_angle}");
    }
    let text = BODY.replace(
        "inertia = [0.1, 0.1, 0.02]",
        "inertia = [0.1, 0.1, 0.02]\norientation = { matrix = [[1, 0, 0], [0, 1, 0], [0, 0, -1]] }",
    );
    assert_error(&text, 6, "body[0].orientation.matrix", &["not a proper rotation"]);
}

#[test]
fn marker_z_axis_sets_the_marker_frame() {
    let text = BODY.replace(
        "name = \"pin\"\nbody = \"link\"",
        "name = \"pin\"\nbody = \"link\"\nz_axis = [1, 0, 0]\nx_axis = [0, 1, 1]",
    );
    let loaded = parse_model(&text, "m.toml").unwrap_or_else(|e| panic!("{e}"));
    let axes = loaded.model.markers()[0].axes;
    let expected_x = nalgebra::Vector3::new(0.0, 1.0, 1.0).normalize();
    assert!((axes.column(2) - nalgebra::Vector3::x()).norm() < 1e-12);
    assert!((axes.column(0) - expected_x).norm() < 1e-12);
    assert!((axes.determinant() - 1.0).abs() < 1e-12);
}

#[test]
fn outputs_get_default_names_and_must_be_unique() {
    let outputs = "\n[[output]]\ntype = \"marker_position\"\nmarker = \"pin\"\n\n[[output]]\ntype = \"energy\"\n";
    let loaded = parse_model(&format!("{BODY}{outputs}"), "o.toml").unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<&str> = loaded.model.outputs().iter().map(|o| o.name.as_str()).collect();
    assert_eq!(names, ["pin.position", "energy"]);
    let twice = format!("{BODY}{outputs}{}", "\n[[output]]\ntype = \"energy\"\n");
    // blank 14, output 15-17, blank 18, output 19-20, blank 21, [[output]] 22, type 23
    assert_error(
        &twice,
        23,
        "output[2].name",
        &["already used by output[1] on line 20", "give this output its own `name`"],
    );
}

#[test]
fn simulation_defaults_come_from_the_file() {
    let text = format!("[simulation]\nt_end = 2\noutput_step = \"1/200\"\n{BODY}");
    let loaded = parse_model(&text, "s.toml").unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.simulation.t_end, 2.0);
    assert_eq!(loaded.simulation.output_step, 0.005);
    assert_eq!(loaded.simulation.rtol, 1e-6);
    assert_error(&format!("[simulation]\nrtol = 0\n{BODY}"), 2, "simulation.rtol", &["must be positive"]);
}

#[test]
fn an_empty_or_truncated_file_is_not_a_model() {
    for text in ["", "# nothing but a comment\n", "[simulation]\nt_end = 2\n", &BODY.replacen("[model]", "", 1)] {
        let e = assert_error(text, 1, "", &["no [model] table: a model file must have one", "empty or truncated"]);
        assert_eq!(e.kind, ErrorKind::Schema);
    }
    // Cut after its first table: a [model] and no body.
    let e = error_of("# a model\n\n[model]\nname = \"cut\"\n\n[simulation]\nt_end = 2\n").1;
    assert_eq!(e, "models/bad.toml:3: the model has no bodies: it needs at least one [[body]] or [[flexible_body]] table");
}

#[test]
fn absurd_magnitudes_are_named_with_their_window() {
    // Finite but absurd: once accepted and reported later as "a singular matrix".
    let text = BODY.replace("mass = 2.0", "mass = 1e308");
    assert_error(&text, 4, "body[0].mass", &["1e308 kg is outside the range of a mass, |x| ≤ 1e12 kg"]);
    let text = BODY.replace("mass = 2.0", "mass = 2.0\nposition = [0, 1e300, 0]");
    assert_error(&text, 5, "body[0].position[1]", &["1e300 m is outside the range of a length, |x| ≤ 1e12 m"]);
    let text = BODY.replace("inertia = [0.1, 0.1, 0.02]", "inertia = { xx = 1e300, yy = 1e300, zz = 1e300 }");
    assert_error(&text, 5, "body[0].inertia.xx", &["outside the range of an inertia, |x| ≤ 1e18 kg m²"]);
    let text = BODY.replace("name = \"pin\"\nbody = \"link\"", "name = \"pin\"\nbody = \"link\"\norigin = [\"1e13\", 0, 0]");
    assert_error(&text, 10, "marker[0].origin[0]", &["1e13 m is outside the range of a length"]);
    let text = BODY.replace("[model]", "[model]\ngravity = [0, -1e20, 0]");
    assert_error(&text, 2, "model.gravity[1]", &["-1e20 m/s² is outside the range of an acceleration"]);
    let text = format!("[simulation]\nt_end = 1e15\n{BODY}");
    assert_error(&text, 2, "simulation.t_end", &["1e15 s is outside the range of a time, |x| ≤ 1e12 s"]);
    let spring = "\n[[force]]\nname = \"s\"\ntype = \"translational_spring_damper\"\ni = \"base\"\nj = \"pin\"\nstiffness = 1e300\n";
    // blank 14, [[force]] 15, name 16, type 17, i 18, j 19, stiffness 20
    assert_error(&format!("{BODY}{spring}"), 20, "force[0].stiffness", &["1e300 (N/m or N m/rad) is outside the range of a stiffness, |x| ≤ 1e15 (N/m or N m/rad)"]);
}

#[test]
fn a_wrong_value_type_is_located() {
    let text = BODY.replace("name = \"link\"", "name = 3");
    assert_error(&text, 3, "body[0].name", &["invalid type: integer `3`, expected a string"]);
    let text = BODY.replace("mass = 2.0", "mass = true");
    assert_error(&text, 4, "body[0].mass", &["expected a number or an expression string"]);
}

#[test]
fn unknown_top_level_table() {
    assert_error("[modle]\nname = \"x\"\n", 1, "modle", &["unknown key `modle`", "did you mean `model`?", "`body`"]);
}

/// Random edits of a shipped model never panic (a small, deterministic fuzz).
#[test]
fn garbled_models_give_errors_not_panics() {
    let text = std::fs::read_to_string(models_dir().join("motor_friction.toml")).expect("model");
    let pieces = [
        "", "=", "[", "]", "\"", "x", "-1", "(", ")", "e", "1e", "{", "}", "\n", "[[body]]", "nan", "inf", "max_",
        "t*", ",", "π", "ü", "0", "#",
    ];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    for _ in 0..400 {
        let mut garbled = text.clone();
        for _ in 0..1 + next(3) {
            let mut at = next(garbled.len());
            while !garbled.is_char_boundary(at) {
                at -= 1;
            }
            let cut = (at + next(4)).min(garbled.len());
            let cut = (at..=cut).rev().find(|c| garbled.is_char_boundary(*c)).unwrap_or(at);
            garbled.replace_range(at..cut, pieces[next(pieces.len())]);
        }
        let outcome = std::panic::catch_unwind(|| parse_model(&garbled, "fuzz.toml").map(|_| ()));
        match outcome {
            Ok(Ok(())) => {}
            Ok(Err(e)) => {
                let shown = e.to_string();
                assert!(shown.starts_with("fuzz.toml:"), "{shown}");
                assert!(e.line.is_some_and(|l| l >= 1 && l <= garbled.lines().count() + 1), "{shown}");
            }
            Err(_) => panic!("parse_model panicked on:\n{garbled}"),
        }
    }
}

#[test]
fn deeply_nested_input_is_refused_not_overflowed() {
    let deep = format!("mass = \"{}2{}\"", "(".repeat(5000), ")".repeat(5000));
    let text = BODY.replace("mass = 2.0", &deep);
    assert_error(&text, 4, "body[0].mass", &["nests parentheses more than 100 deep"]);
    let deep_toml = format!("[model]\ngravity = {}1{}\n", "[".repeat(5000), "]".repeat(5000));
    let (e, _) = error_of(&deep_toml);
    assert_eq!(e.line, Some(2));
}

#[test]
fn an_unknown_integrator_and_a_spectral_radius_out_of_range_are_named() {
    let text = format!("[simulation]\nintegrator = \"eulr\"\n{BODY}");
    assert_error(&text, 2, "simulation.integrator", &["unknown integrator `eulr`", "bdf"]);
    let text = format!("[simulation]\nspectral_radius = 1.5\n{BODY}");
    assert_error(&text, 2, "simulation.spectral_radius", &["between 0 and 1, got 1.5"]);
    let loaded = flexmb_files::parse_model(&format!("[simulation]\nintegrator = \"bdf\"\n{BODY}"), "models/ok.toml").unwrap();
    assert_eq!(loaded.simulation.method, flexmb::integrate::Method::default());
}
