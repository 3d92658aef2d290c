//! The `shape` key of `[[body]]`: what each form gives the ParaView output, and every kind of bad input
//! reported with the file, the line and the key path.

use std::path::Path;

use flexmb_files::model_file::{parse_model, ModelFileError};
use flexmb_files::shape::Shape;

/// A model of one body whose `shape` (line 6) is `shape`.
fn body_with(shape: &str) -> String {
    format!("[model]\n[[body]]\nname = \"link\"\nmass = 2.0\ninertia = [0.1, 0.1, 0.02]\nshape = {shape}\n")
}

fn shape_of(text: &str, file: &str) -> Shape {
    let loaded = parse_model(text, file).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.shapes.len(), 1);
    loaded.shapes[0].shape.clone()
}

/// Asserts the error's line and key path, that its display starts with `file:line: key:`, and that it
/// contains every fragment.
fn assert_error(text: &str, file: &str, line: usize, key_path: &str, fragments: &[&str]) -> ModelFileError {
    let e = match parse_model(text, file) {
        Ok(_) => panic!("expected an error for:\n{text}"),
        Err(e) => e,
    };
    let shown = e.to_string();
    assert_eq!((e.line, e.key_path.as_str()), (Some(line), key_path), "{shown}");
    let prefix = format!("{file}:{line}: {key_path}: ");
    assert!(shown.starts_with(&prefix), "`{shown}` should start with `{prefix}`");
    for fragment in fragments {
        assert!(shown.contains(fragment), "`{shown}` should contain `{fragment}`");
    }
    e
}

fn bounds(shape: &Shape) -> ([f64; 3], [f64; 3]) {
    shape.mesh().points.iter().fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
        (std::array::from_fn(|k| lo[k].min(p[k])), std::array::from_fn(|k| hi[k].max(p[k])))
    })
}

fn close(a: [f64; 3], b: [f64; 3]) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
}

#[test]
fn each_form_gives_its_surface_in_the_body_frame() {
    let file = "models/shapes.toml";
    let cuboid = shape_of(&body_with("{ box = [0.4, 0.04, \"0.01*2\"], origin = [0.2, 0, 0] }"), file);
    assert_eq!(bounds(&cuboid), ([0.0, -0.02, -0.01], [0.4, 0.02, 0.01]));
    let cylinder = shape_of(&body_with("{ cylinder = { radius = 0.1, length = 0.6, axis = \"x\" } }"), file);
    let (low, high) = bounds(&cylinder);
    assert!(close(low, [-0.3, -0.1, -0.1]) && close(high, [0.3, 0.1, 0.1]), "{low:?} {high:?}");
    // The cylinder's axis is the shape frame's z unless told, and `orientation` turns the shape frame.
    let turned = "{ cylinder = { radius = 0.1, length = 0.6 }, orientation = { axis = [1, 0, 0], angle_deg = 90 } }";
    let (low, high) = bounds(&shape_of(&body_with(turned), file));
    assert!(close(low, [-0.1, -0.3, -0.1]) && close(high, [0.1, 0.3, 0.1]), "{low:?} {high:?}");
    let sphere = shape_of(&body_with("{ sphere = 0.05, origin = [0, 0, 1] }"), file);
    assert_eq!(bounds(&sphere), ([-0.05, -0.05, 0.95], [0.05, 0.05, 1.05]));
    assert_eq!(shape_of(&body_with("{ frame = 0.3 }"), file), Shape::Frame { size: 0.3 });
    // Without a shape: a frame glyph of half the diagonal of the uniform box with the body's inertia,
    // ½ √(6 tr(J)/m) = ½ √(6 · 0.22 / 2).
    let bare = shape_of("[model]\n[[body]]\nname = \"link\"\nmass = 2.0\ninertia = [0.1, 0.1, 0.02]\n", file);
    let Shape::Frame { size } = bare else { panic!("{bare:?}") };
    assert!((size - 0.5 * 0.66f64.sqrt()).abs() < 1e-15);
}

#[test]
fn a_mesh_file_is_read_relative_to_the_model_file_and_scaled() {
    let dir = std::env::temp_dir().join(format!("flexmb-shape-mesh-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(dir.join("parts/tri.obj"), "v 0 0 0\nv 1000 0 0\nv 0 500 0\nf 1 2 3\n").unwrap();
    let file = dir.join("model.toml").display().to_string();
    let shape = shape_of(&body_with("{ mesh = \"parts/tri.obj\", scale = 0.001, origin = [0, 0, 0.1] }"), &file);
    let mesh = shape.mesh();
    assert_eq!(mesh.cells, vec![vec![0, 1, 2]]);
    assert!(close(mesh.points[1].into(), [1.0, 0.0, 0.1]) && close(mesh.points[2].into(), [0.0, 0.5, 0.1]));

    // A problem inside the mesh file is reported at the `mesh` key, with the mesh file's own line.
    std::fs::write(dir.join("parts/bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    let bad = dir.join("parts/bad.obj").display().to_string();
    assert_error(
        &body_with("{ mesh = \"parts/bad.obj\" }"),
        &file,
        6,
        "body[0].shape.mesh",
        &[&format!("mesh file {bad}:3: "), "vertex 7"],
    );
    std::fs::write(dir.join("parts/empty.stl"), "solid nothing\nendsolid nothing\n").unwrap();
    assert_error(&body_with("{ mesh = \"parts/empty.stl\" }"), &file, 6, "body[0].shape.mesh", &["holds no faces"]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_unknown_kind_of_shape_names_the_allowed_keys() {
    assert_error(
        &body_with("{ cone = 0.1 }"),
        "models/bad.toml",
        6,
        "body[0].shape.cone",
        &["unknown key `cone`", "`box`", "`mesh`"],
    );
    assert_error(
        &body_with("{ sphre = 0.1 }"),
        "models/bad.toml",
        6,
        "body[0].shape.sphre",
        &["did you mean `sphere`"],
    );
    assert_error(
        &body_with("{ origin = [0, 0, 0] }"),
        "models/bad.toml",
        6,
        "body[0].shape",
        &["the shape is not given"],
    );
    assert_error(&body_with("{ box = [1, 1, 1], sphere = 1 }"), "models/bad.toml", 6, "body[0].shape", &["gives more"]);
    assert_error(
        &body_with("{ cylinder = { radius = 0.1, length = 1, axis = \"w\" } }"),
        "models/bad.toml",
        6,
        "body[0].shape.cylinder.axis",
        &["unknown axis `w`", "`x`, `y`, `z`"],
    );
    assert_error(
        &body_with("{ cylinder = { radius = 0.1 } }"),
        "models/bad.toml",
        6,
        "body[0].shape.cylinder.length",
        &["missing required key `length`"],
    );
}

#[test]
fn a_missing_or_unknown_mesh_file_is_reported_at_the_mesh_key() {
    let e = assert_error(
        &body_with("{ mesh = \"parts/missing.stl\" }"),
        "models/bad.toml",
        6,
        "body[0].shape.mesh",
        &["mesh file models/parts/missing.stl: "],
    );
    assert!(e.message.to_lowercase().contains("no such file"), "{}", e.message);
    assert_error(
        &body_with("{ mesh = \"parts/link.ply\" }"),
        "models/bad.toml",
        6,
        "body[0].shape.mesh",
        &["ending in `.stl` (ASCII or binary) or `.obj`"],
    );
    assert_error(&body_with("{ mesh = \"\" }"), "models/bad.toml", 6, "body[0].shape.mesh", &["empty string"]);
}

#[test]
fn sizes_must_be_positive() {
    let bad = "models/bad.toml";
    assert_error(
        &body_with("{ box = [0.1, -0.2, 0.3] }"),
        bad,
        6,
        "body[0].shape.box[1]",
        &["a box's edge length must be positive, got -0.2"],
    );
    assert_error(&body_with("{ box = [0.1, 0.2] }"), bad, 6, "body[0].shape.box", &["3 components, got 2"]);
    assert_error(
        &body_with("{ cylinder = { radius = -0.1, length = 1 } }"),
        bad,
        6,
        "body[0].shape.cylinder.radius",
        &["the cylinder's radius must be positive, got -0.1"],
    );
    assert_error(
        &body_with("{ cylinder = { radius = 0.1, length = 0 } }"),
        bad,
        6,
        "body[0].shape.cylinder.length",
        &["must be positive, got 0"],
    );
    assert_error(
        &body_with("{ sphere = \"-r\" }").replace("[model]\n", "[model]\n[parameters]\nr = 0.5\n"),
        bad,
        8,
        "body[0].shape.sphere",
        &["the sphere's radius must be positive, got -0.5"],
    );
    assert_error(&body_with("{ frame = 0 }"), bad, 6, "body[0].shape.frame", &["must be positive"]);
    assert_error(
        &body_with("{ mesh = \"a.stl\", scale = -1 }"),
        bad,
        6,
        "body[0].shape.scale",
        &["the mesh's scale must be positive"],
    );
}

#[test]
fn keys_that_do_not_apply_are_refused() {
    let bad = "models/bad.toml";
    assert_error(
        &body_with("{ box = [1, 1, 1], scale = 2 }"),
        bad,
        6,
        "body[0].shape.scale",
        &["`scale` goes with `mesh` only"],
    );
    assert_error(
        &body_with("{ frame = 0.2, origin = [1, 0, 0] }"),
        bad,
        6,
        "body[0].shape.origin",
        &["does not apply to `frame`"],
    );
    assert_error(
        &body_with("{ sphere = 1, orientation = { axis = [0, 0, 1] } }"),
        bad,
        6,
        "body[0].shape.orientation.angle",
        &["needs `angle`"],
    );
}

#[test]
fn the_shipped_slider_crank_draws_its_links_as_boxes() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models/slider_crank.toml");
    let loaded = flexmb_files::load_model(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.shapes.len(), 3);
    assert!(loaded.shapes.iter().all(|s| matches!(&s.shape, Shape::Surface(m) if m.points.len() == 24)));
}
