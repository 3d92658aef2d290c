//! The model-file layer: every shipped model builds, and every kind of bad input gives an error that
//! names the file, the line and the key path (never a panic).

use std::path::{Path, PathBuf};

use flexmb_cli::model_file::{load_model, parse_model, ErrorKind, ModelFileError};

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
    let prefix = format!("models/bad.toml:{line}: {key_path}: ");
    assert!(shown.starts_with(&prefix), "`{shown}` should start with `{prefix}`");
    for fragment in fragments {
        assert!(shown.contains(fragment), "`{shown}` should contain `{fragment}`");
    }
    e
}

/// Lines 1-13 of most test files: line 1 is empty, `[[body]]` is line 2, `mass` line 4, `inertia` line 5,
/// the first marker's `body` line 9, the ground marker ends on line 13.
const BODY: &str = r#"
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
    assert_eq!(loaded.simulation, flexmb_cli::SimulationDefaults::default());
    assert_eq!(loaded.simulation.t_end, 1.0);
    assert_eq!(loaded.model.markers().len(), 2);
}

#[test]
fn unknown_key_names_key_line_and_allowed_keys() {
    let text = format!("{BODY}\n[[joint]]\nname = \"j\"\ntype = \"revolute\"\ni = \"base\"\nj = \"pin\"\nlenght = 2\n");
    // BODY fills lines 1-13 (line 1 is empty); then blank 14, [[joint]] 15, name 16, type 17, i 18, j 19
    assert_error(&text, 20, "joint[0].lenght", &["unknown key `lenght`", "did you mean `length`?", "`axis_i`"]);
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
    assert_error(&text, 17, "joint[0].type", &["unknown joint type `revolut`", "did you mean `revolute`?", "`point-on-line`"]);
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
