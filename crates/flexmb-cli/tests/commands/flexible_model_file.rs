//! Flexible bodies in model files: `[[flexible_body]]` from an FE model file (reduced through the
//! cache) or from a flexible-body file, markers at nodes, the flexible-body outputs, and every kind of
//! bad input reported with the file, the line and the key path.

use std::path::{Path, PathBuf};
use std::time::SystemTime;

use flexmb::analysis::{output_columns, simulate, SimulationSettings};
use flexmb::body::ModalDamping;
use flexmb::integrate::Tolerances;
use flexmb::model::{BodyId, MarkerId};
use flexmb_files::fe_model_file::load_fe_model;
use flexmb_files::flexible_body::modal_body;
use flexmb_files::model_file::{load_model, ErrorKind, FlexibleBodyOrigin, LoadedModel, ModelFileError, CACHE_DIR};
use flexmb_fem::reduction::{reduce, Basis, ReductionSettings};

fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The shipped cantilever: 21 nodes labelled 1 (x = 0, clamped) to 21 (x = 1), node sets `arm`,
/// `arm.start`, `arm.end`, rotary inertia lumped, `[modes] set = "4N2S"`, orthonormal basis.
fn cantilever_text() -> String {
    std::fs::read_to_string(repository().join("models/fe/cantilever.toml")).expect("the shipped cantilever")
}

/// A directory of its own for each test (removed when dropped), with the cantilever as `fe/arm.toml`.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("flexmb-flexible-model-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("fe")).expect("temp dir");
        let scratch = Self(dir);
        scratch.write("fe/arm.toml", &cantilever_text());
        scratch
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.path(name);
        std::fs::write(&path, text).expect("write temp file");
        path
    }

    /// Writes `text` as `model.toml` and loads it.
    fn load(&self, text: &str) -> Result<LoadedModel, ModelFileError> {
        load_model(&self.write("model.toml", text))
    }

    fn model_file(&self) -> String {
        self.path("model.toml").display().to_string()
    }

    /// Asserts the error of `text`: its line, key path, the display's `file:line: key:` prefix, and
    /// every fragment.
    fn assert_error(&self, text: &str, line: usize, key_path: &str, fragments: &[&str]) -> ModelFileError {
        let e = match self.load(text) {
            Ok(_) => panic!("expected an error for:\n{text}"),
            Err(e) => e,
        };
        let shown = e.to_string();
        assert_eq!(e.line, Some(line), "line of: {shown}");
        assert_eq!(e.key_path, key_path, "key path of: {shown}");
        let prefix = format!("{}:{line}: {key_path}: ", self.model_file());
        assert!(shown.starts_with(&prefix), "`{shown}` should start with `{prefix}`");
        for fragment in fragments {
            assert!(shown.contains(fragment), "`{shown}` should contain `{fragment}`");
        }
        e
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn cache_files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|entries| entries.flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect())
        .unwrap_or_default();
    names.sort();
    names
}

fn modified(path: &Path) -> SystemTime {
    std::fs::metadata(path).and_then(|m| m.modified()).expect("modification time")
}

/// The origin's cache file.
fn cache_of(loaded: &LoadedModel) -> (bool, PathBuf) {
    match &loaded.flexible_bodies[0].origin {
        FlexibleBodyOrigin::Reduced { cache: Some(cache), .. } => (false, cache.clone()),
        FlexibleBodyOrigin::Cached { cache, .. } => (true, cache.clone()),
        other => panic!("expected a reduction with a cache, got {other:?}"),
    }
}

const MECHANISM: &str = r#"[model]
gravity = [0, -9.81, 0]

[[body]]
name = "hub"
mass = 1.0
inertia = [0.01, 0.01, 0.01]

[[flexible_body]]
name = "arm"
fe_model = "fe/arm.toml"
damping = { ratio = 0.02 }
position = [0.1, 0, 0]
modal_coordinates = [0, 0, 0, 0, 0, 0]

[[marker]]
name = "hub_end"
body = "hub"
origin = [0.1, 0, 0]

[[marker]]
name = "root"
body = "arm"
node = 1

[[marker]]
name = "middle"
body = "arm"
node = [0.5, 0, 0]
z_axis = [0, 1, 0]

[[marker]]
name = "tip"
body = "arm"
node = "arm.end"

[[marker]]
name = "base"
body = "ground"

[[joint]]
name = "weld"
type = "fixed"
i = "hub_end"
j = "root"

[[joint]]
name = "bearing"
type = "revolute"
i = "base"
j = "hub_end"

[[output]]
type = "node_position"
body = "arm"
node = 21

[[output]]
type = "node_velocity"
body = "arm"
node = [1, 0, 0]

[[output]]
type = "node_acceleration"
body = "arm"
node = "arm.end"

[[output]]
name = "middle_bending"
type = "node_deformation"
body = "arm"
node = 11

[[output]]
type = "modal_coordinates"
body = "arm"

[[output]]
type = "strain_energy"
body = "arm"

[[output]]
type = "energy"

[[output]]
type = "marker_position"
marker = "tip"
"#;

#[test]
fn a_flexible_body_from_an_fe_model_with_markers_at_nodes_and_outputs() {
    let scratch = Scratch::new("mechanism");
    let loaded = scratch.load(MECHANISM).unwrap_or_else(|e| panic!("{e}"));
    let model = &loaded.model;
    assert_eq!(model.bodies().len(), 2);
    assert!(model.modal_body(BodyId(0)).is_none(), "the hub is rigid");
    let modal = model.modal_body(BodyId(1)).expect("the arm is flexible");
    assert_eq!(modal.modes(), 6, "4N2S from the FE file's [modes]");
    assert_eq!(modal.mode_labels, ["O1", "O2", "O3", "O4", "O5", "O6"]);
    assert_eq!(modal.nodes.len(), 21);
    assert!((model.bodies()[1].mass - 1.57).abs() < 1e-9, "the lumped mass of the FE model");
    assert_eq!(model.bodies()[1].initial.position, flexmb::math::Vec3::new(0.1, 0.0, 0.0));
    assert!(modal.damping.iter().any(|d| *d != 0.0), "damping ratio 0.02");

    // Markers at nodes by label, position and node set: node index = position of the label.
    assert_eq!(model.marker_node(MarkerId(0)), None, "hub_end is on the rigid hub");
    assert_eq!(model.marker_node(MarkerId(1)), Some(0));
    assert_eq!(model.marker_node(MarkerId(2)), Some(10));
    assert_eq!(model.marker_node(MarkerId(3)), Some(20));
    assert_eq!(model.marker(MarkerId(2)).unwrap().origin, flexmb::math::Vec3::new(0.5, 0.0, 0.0));
    let z = model.marker(MarkerId(2)).unwrap().axes.column(2).into_owned();
    assert!((z - flexmb::math::Vec3::y()).norm() < 1e-12, "axes in the body frame");

    let columns: Vec<String> = output_columns(model).into_iter().map(|c| c.name).collect();
    let expected = [
        "arm.node21.position.x",
        "arm.node21.position.y",
        "arm.node21.position.z",
        "arm.node21.velocity.x",
        "arm.node21.velocity.y",
        "arm.node21.velocity.z",
        "arm.node21.acceleration.x",
        "arm.node21.acceleration.y",
        "arm.node21.acceleration.z",
        "middle_bending.x",
        "middle_bending.y",
        "middle_bending.z",
        "arm.modal_coordinates.O1",
        "arm.modal_coordinates.O2",
        "arm.modal_coordinates.O3",
        "arm.modal_coordinates.O4",
        "arm.modal_coordinates.O5",
        "arm.modal_coordinates.O6",
        "arm.strain_energy",
        "energy.kinetic",
        "energy.potential",
        "energy.strain",
        "energy.total",
        "tip.position.x",
        "tip.position.y",
        "tip.position.z",
    ];
    assert_eq!(columns, expected);

    let info = &loaded.flexible_bodies[0];
    assert_eq!(info.name, "arm");
    assert_eq!(info.mode_set, "4N2S");
    assert_eq!(info.basis, Basis::Orthonormal);
    assert_eq!(info.nodes, 21);
    assert_eq!(info.frequencies_hz.len(), 6);
    assert!(info.frequencies_hz.windows(2).all(|w| w[0] <= w[1]));
    assert!(matches!(info.origin, FlexibleBodyOrigin::Reduced { cache: Some(_), .. }));

    let check = flexmb_cli::check::check_model(model, Default::default()).unwrap_or_else(|e| panic!("{e}"));
    let text = flexmb_cli::check::describe(model, &check);
    assert!(text.contains("flexible body 'arm': 6 modes (O1 "), "{text}");
    assert!(text.contains("degrees of freedom: 7"), "the bearing's rotation and 6 modes: {text}");
    let sources = flexmb_cli::check::describe_flexible_bodies(&loaded);
    assert!(sources.contains("flexible body 'arm' (4N2S orthonormal): reduced from"), "{sources}");
}

#[test]
fn modes_basis_and_initial_modal_state_from_the_table() {
    let scratch = Scratch::new("table");
    let text = r#"[model]
[[flexible_body]]
name = "arm"
fe_model = "fe/arm.toml"
modes = "3N"
basis = "raw"
damping = { rayleigh = [0.5, 1e-4] }
orientation = { axis = [0, 0, 1], angle_deg = 90 }
modal_coordinates = [1e-3, 0, "2e-4"]
modal_rates = [0, 0.5, 0]

[[marker]]
name = "root"
body = "arm"
node = 1
"#;
    let loaded = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    let modal = loaded.model.modal_body(BodyId(0)).expect("flexible");
    assert_eq!(modal.mode_labels, ["N1", "N2", "N3"]);
    assert_eq!(modal.initial_coordinates.as_slice(), [1e-3, 0.0, 2e-4]);
    assert_eq!(modal.initial_rates.as_slice(), [0.0, 0.5, 0.0]);
    let expected = 0.5 * modal.invariants.modal_mass() + 1e-4 * &modal.stiffness;
    assert!((&modal.damping - expected).abs().max() < 1e-9 * modal.stiffness.abs().max());
    assert_eq!(loaded.flexible_bodies[0].basis, Basis::Raw);
    assert_eq!(loaded.flexible_bodies[0].mode_set, "3N");
}

/// Ignored until the engine sorts the natural modes: `ModalBody::damping_matrix` pairs the k-th ratio
/// with the k-th eigenpair of `nalgebra::SymmetricEigen`, whose eigenvalues are not sorted (here the
/// ratios land on O3, O1, O4, O2).
#[test]
fn per_mode_damping_ratios_follow_the_orthonormal_modes() {
    let scratch = Scratch::new("ratios");
    let text = "[model]\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"fe/arm.toml\"\nmodes = \"4N\"\n\
                damping = { ratios = [0.01, 0.02, 0.03, 0.5] }\n\n[[marker]]\nname = \"root\"\nbody = \"arm\"\nnode = 1\n";
    let loaded = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    let modal = loaded.model.modal_body(BodyId(0)).expect("flexible");
    // Orthonormal basis: M = I, K = diag(ω²), so D = diag(2 ζ_k ω_k) in the order O1 … O4.
    for (k, zeta) in [0.01, 0.02, 0.03, 0.5].into_iter().enumerate() {
        let omega = modal.stiffness[(k, k)].sqrt();
        let d = modal.damping[(k, k)];
        assert!(
            (d - 2.0 * zeta * omega).abs() < 1e-6 * (2.0 * zeta * omega),
            "mode O{}: damping ratio {} instead of {zeta}",
            k + 1,
            d / (2.0 * omega)
        );
    }
}

#[test]
fn the_cache_is_created_reused_and_rebuilt_when_the_fe_model_changes() {
    let scratch = Scratch::new("cache");
    let text = "[model]\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"fe/arm.toml\"\n\n[[marker]]\nname = \"root\"\nbody = \"arm\"\nnode = 1\n";
    let cache_dir = scratch.path("fe").join(CACHE_DIR);
    assert!(!cache_dir.exists());

    let first = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    let (cached, file) = cache_of(&first);
    assert!(!cached, "the first load reduces");
    assert_eq!(file.parent(), Some(cache_dir.as_path()));
    let name = file.file_name().and_then(|n| n.to_str()).expect("file name").to_string();
    assert!(name.starts_with("arm-4N2S-orthonormal-") && name.ends_with(".json"), "{name}");
    assert_eq!(name.len(), "arm-4N2S-orthonormal-".len() + 16 + ".json".len(), "a 16-digit hash: {name}");
    let written = modified(&file);

    let second = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cache_of(&second), (true, file.clone()), "the second load reads the cache");
    assert_eq!(modified(&file), written, "and does not write it");
    assert_eq!(first.model.modal_body(BodyId(0)), second.model.modal_body(BodyId(0)), "the same body");

    // Another mode set is another file; the first stays.
    let other = scratch.load(&text.replace("fe/arm.toml\"\n", "fe/arm.toml\"\nmodes = \"4N\"\n")).unwrap();
    let (cached, other_file) = cache_of(&other);
    assert!(!cached);
    assert!(other_file.file_name().unwrap().to_str().unwrap().starts_with("arm-4N-orthonormal-"));
    assert!(file.exists());

    // A changed FE model file (even a comment) gives a new hash: reduced again, the stale file removed.
    scratch.write("fe/arm.toml", &(cantilever_text() + "\n# changed\n"));
    let third = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    let (cached, new_file) = cache_of(&third);
    assert!(!cached, "a changed FE model is reduced again");
    assert_ne!(new_file, file);
    assert!(!file.exists(), "the stale reduction is removed");
    assert!(other_file.exists(), "another mode set is not stale");
    assert_eq!(cache_files(&cache_dir).len(), 2, "{:?}", cache_files(&cache_dir));
    let fourth = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cache_of(&fourth), (true, new_file));

    // A cache file that is not a valid body is replaced.
    let (_, current) = cache_of(&fourth);
    std::fs::write(&current, "{ not a body").unwrap();
    let fifth = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cache_of(&fifth), (false, current.clone()));
    assert!(flexmb_fem::reduction::FlexibleBody::read(&current).is_ok());
}

#[test]
fn an_unwritable_cache_only_means_reducing_again() {
    let scratch = Scratch::new("no-cache");
    // A file where the cache directory should be: it cannot be created.
    scratch.write(&format!("fe/{CACHE_DIR}"), "in the way");
    let text = "[model]\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"fe/arm.toml\"\n\n[[marker]]\nname = \"root\"\nbody = \"arm\"\nnode = 1\n";
    for _ in 0..2 {
        let loaded = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
        assert!(matches!(loaded.flexible_bodies[0].origin, FlexibleBodyOrigin::Reduced { cache: None, .. }));
        assert_eq!(loaded.model.modal_body(BodyId(0)).map(|m| m.modes()), Some(6));
        let sources = flexmb_cli::check::describe_flexible_bodies(&loaded);
        assert!(sources.contains("could not be written"), "{sources}");
    }
}

const DECK: &str = "\
** a beam of four B31 elements along x; the nodes are in nodes.inp
*INCLUDE, INPUT=nodes.inp
*ELEMENT, TYPE=B31, ELSET=BEAMS
1, 1, 2
2, 2, 3
3, 3, 4
4, 4, 5
*MATERIAL, NAME=STEEL
*ELASTIC
2.1E11, 0.3
*DENSITY
7850.
*BEAM SECTION, ELSET=BEAMS, MATERIAL=STEEL, SECTION=RECT
0.02, 0.01
0., 1., 0.
*BOUNDARY
1, 1, 6
";

const NODES: &str = "*NODE, NSET=ALL\n1, 0., 0., 0.\n2, 0.25, 0., 0.\n3, 0.5, 0., 0.\n4, 0.75, 0., 0.\n5, 1., 0., 0.\n*NSET, NSET=TIP\n5\n";

#[test]
fn the_cache_follows_the_mesh_file_and_its_includes() {
    let scratch = Scratch::new("mesh-cache");
    scratch.write("fe/beam.inp", DECK);
    scratch.write("fe/nodes.inp", NODES);
    scratch.write("fe/post.toml", "[fe_model]\nmesh = \"beam.inp\"\nrotary_inertia = true\n\n[modes]\nset = \"2N\"\n");
    let fe = load_fe_model(&scratch.path("fe/post.toml")).unwrap_or_else(|e| panic!("{e}"));
    let expected = [scratch.path("fe/post.toml"), scratch.path("fe/beam.inp"), scratch.path("fe/nodes.inp")];
    assert_eq!(fe.sources, expected, "the FE model file, its mesh file and the mesh's include");

    let text = "[model]\n[[flexible_body]]\nname = \"post\"\nfe_model = \"fe/post.toml\"\n\n[[marker]]\nname = \"tip\"\nbody = \"post\"\nnode = \"tip\"\n";
    let first = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(first.model.marker_node(MarkerId(0)), Some(4), "the deck's node set, case-insensitive");
    let (cached, file) = cache_of(&first);
    assert!(!cached);
    assert!(cache_of(&scratch.load(text).unwrap()).0, "unchanged: from the cache");
    // Only the included file changes.
    scratch.write("fe/nodes.inp", &NODES.replace("0.75", "0.76"));
    let changed = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    let (cached, new_file) = cache_of(&changed);
    assert!(!cached, "an included file changed: reduced again");
    assert_ne!(new_file, file);
    let node = &changed.model.modal_body(BodyId(0)).unwrap().nodes[3];
    assert_eq!(node.position.x, 0.76);

    // An .inp deck given directly as the FE model needs the mode set in the table.
    let direct = "[model]\n[[flexible_body]]\nname = \"post\"\nfe_model = \"fe/beam.inp\"\n";
    let e = scratch.assert_error(direct, 2, "flexible_body[0].modes", &["missing required key `modes`", "beam.inp"]);
    assert_eq!(e.kind, ErrorKind::Schema);
    let direct = format!("{direct}modes = \"2N\"\n");
    // Without rotary inertia (a deck's default), the strip's spin about its axis has no mass: the
    // model loads, and with no joint holding that spin, the gauge does (the check passes).
    let loaded = scratch.load(&direct).unwrap_or_else(|e| panic!("{e}"));
    flexmb::analysis::check_model(&loaded.model, Default::default()).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn a_flexible_body_from_a_body_file() {
    let scratch = Scratch::new("body-file");
    let fe = load_fe_model(&scratch.path("fe/arm.toml")).unwrap_or_else(|e| panic!("{e}"));
    let settings =
        ReductionSettings { mode_set: "3N1S".parse().unwrap(), basis: Basis::Raw, eigen: Default::default() };
    let reduction = reduce(&fe.model, &fe.name, &settings).unwrap_or_else(|e| panic!("{e}"));
    reduction.body.write(&scratch.path("arm.json")).unwrap();
    let text = r#"[model]
[[flexible_body]]
name = "arm"
body_file = "arm.json"
damping = { ratio = 0.05 }

[[marker]]
name = "tip"
body = "arm"
node = [1, 0, 0]

[[output]]
type = "modal_coordinates"
body = "arm"
"#;
    let loaded = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    let expected = modal_body(&reduction.body, &ModalDamping::Ratios(vec![0.05])).unwrap();
    assert_eq!(loaded.model.modal_body(BodyId(0)), Some(&expected));
    assert_eq!(loaded.model.marker_node(MarkerId(0)), Some(20));
    assert_eq!(loaded.flexible_bodies[0].origin, FlexibleBodyOrigin::BodyFile { path: scratch.path("arm.json") });
    assert_eq!(loaded.flexible_bodies[0].mode_labels, ["N1", "N2", "N3", "S1"]);
    let columns: Vec<String> = output_columns(&loaded.model).into_iter().map(|c| c.name).collect();
    assert_eq!(
        columns,
        [
            "arm.modal_coordinates.N1",
            "arm.modal_coordinates.N2",
            "arm.modal_coordinates.N3",
            "arm.modal_coordinates.S1"
        ]
    );

    // A body file has its own mode set and basis, and no node sets.
    let with_modes = text.replace("body_file = \"arm.json\"\n", "body_file = \"arm.json\"\nmodes = \"4N\"\n");
    scratch.assert_error(&with_modes, 5, "flexible_body[0].modes", &["goes with `fe_model` only"]);
    let with_basis = text.replace("body_file = \"arm.json\"\n", "body_file = \"arm.json\"\nbasis = \"raw\"\n");
    scratch.assert_error(&with_basis, 5, "flexible_body[0].basis", &["goes with `fe_model` only"]);
    let by_set = text.replace("node = [1, 0, 0]", "node = \"arm.end\"");
    scratch.assert_error(&by_set, 10, "marker[0].node", &["has no node sets", "node label"]);
    scratch.write("broken.json", "{ \"format\": 3 }");
    let broken = text.replace("arm.json", "broken.json");
    scratch.assert_error(
        &broken,
        4,
        "flexible_body[0].body_file",
        &["cannot read the flexible-body file", "broken.json:1:"],
    );
    let missing = text.replace("arm.json", "nowhere.json");
    scratch.assert_error(
        &missing,
        4,
        "flexible_body[0].body_file",
        &["cannot read the flexible-body file", "nowhere.json"],
    );
}

#[test]
fn the_shipped_flexible_pendulum_swings_and_bends() {
    let path = repository().join("models/flexible_pendulum.toml");
    let loaded = load_model(&path).unwrap_or_else(|e| panic!("{e}"));
    let model = &loaded.model;
    let modal = model.modal_body(BodyId(0)).expect("the beam is flexible");
    assert_eq!(modal.modes(), 4);
    let f = &loaded.flexible_bodies[0].frequencies_hz;
    assert!(f[0] > 15.0 && f[0] < 22.0, "first in-plane bending near 18 Hz: {f:?}");
    let columns: Vec<String> = output_columns(model).into_iter().map(|c| c.name).collect();
    let column = |name: &str| columns.iter().position(|c| c == name).unwrap_or_else(|| panic!("{name} in {columns:?}"));
    let (x, y, o1) =
        (column("beam.node21.position.x"), column("beam.node21.position.y"), column("beam.modal_coordinates.O1"));
    let total = column("energy.total");
    let settings = SimulationSettings {
        t_end: 0.3,
        output_step: 0.1,
        tolerances: Tolerances::new(1e-6, 1e-6),
        ..Default::default()
    };
    let mut rows = Vec::new();
    simulate(model, &settings, &mut |frame| rows.push((frame.t, frame.values.to_vec())))
        .unwrap_or_else(|e| panic!("{e}"));
    let (t0, first) = &rows[0];
    assert_eq!(*t0, 0.0);
    assert!((first[x] - 1.0).abs() < 1e-12 && first[y].abs() < 1e-12, "released horizontal");
    let (t_end, last) = rows.last().unwrap();
    assert!((t_end - 0.3).abs() < 1e-12);
    assert!(last[y] < -0.3, "the tip falls: y = {}", last[y]);
    assert!(((last[x].powi(2) + last[y].powi(2)).sqrt() - 1.0).abs() < 1e-2, "a nearly rigid swing");
    assert!(rows.iter().any(|(_, r)| r[o1].abs() > 1e-5), "the fall bends the strip");
    assert!(last[total].abs() < 1e-2, "energy is nearly conserved (2 % damping): {}", last[total]);
}

#[test]
fn errors_of_the_flexible_body_table() {
    let scratch = Scratch::new("errors");
    let body = "[model]\n[[flexible_body]]\nname = \"arm\"\n";
    let fe = "fe_model = \"fe/arm.toml\"\n";
    // Lines: 1 [model], 2 [[flexible_body]], 3 name, 4 fe_model, 5 the key under test.
    scratch.assert_error(
        &format!("{body}{fe}body_file = \"arm.json\"\n"),
        5,
        "flexible_body[0].body_file",
        &["give either `fe_model`", "not both"],
    );
    let e = scratch.assert_error(body, 2, "flexible_body[0]", &["needs `fe_model", "or `body_file"]);
    assert_eq!(e.kind, ErrorKind::Schema);
    scratch.assert_error(
        &format!("{body}fe_model = \"fe/nowhere.toml\"\n"),
        4,
        "flexible_body[0].fe_model",
        &["cannot read the FE model file", "nowhere.toml"],
    );
    scratch.assert_error(&format!("{body}fe_model = \"\"\n"), 4, "flexible_body[0].fe_model", &["empty"]);
    scratch.assert_error(
        &format!("{body}{fe}modes = \"4X\"\n"),
        5,
        "flexible_body[0].modes",
        &["mode set `4X`", "4N5S"],
    );
    scratch.assert_error(
        &format!("{body}{fe}modes = \"4N3S\"\n"),
        5,
        "flexible_body[0].modes",
        &["3 static correction mode(s)", "2 static load(s)"],
    );
    scratch.assert_error(
        &format!("{body}{fe}basis = \"orthonormel\"\n"),
        5,
        "flexible_body[0].basis",
        &["did you mean `orthonormal`?"],
    );
    scratch.assert_error(
        &format!("{body}{fe}damping = {{ ratios = [0.01, 0.02] }}\n"),
        5,
        "flexible_body[0].damping.ratios",
        &["expected 6 damping ratios, one per mode (O1, O2, O3, O4, O5, O6), got 2"],
    );
    scratch.assert_error(
        &format!("{body}{fe}damping = {{ ratio = -0.1 }}\n"),
        5,
        "flexible_body[0].damping.ratio",
        &["must not be negative"],
    );
    scratch.assert_error(
        &format!("{body}{fe}damping = {{ ratio = 0.1, rayleigh = [0, 1] }}\n"),
        5,
        "flexible_body[0].damping",
        &["more than one form"],
    );
    scratch.assert_error(
        &format!("{body}{fe}damping = {{ ratoi = 0.1 }}\n"),
        5,
        "flexible_body[0].damping.ratoi",
        &["unknown key `ratoi`; did you mean `ratio`?"],
    );
    scratch.assert_error(
        &format!("{body}{fe}damping = {{ rayleigh = [0, -1] }}\n"),
        5,
        "flexible_body[0].damping.rayleigh[1]",
        &["beta must not be negative"],
    );
    scratch.assert_error(
        &format!("{body}{fe}modal_coordinates = [0, 0, 0]\n"),
        5,
        "flexible_body[0].modal_coordinates",
        &["expected 6 modal coordinates, one per mode", "got 3"],
    );
    scratch.assert_error(
        &format!("{body}{fe}modal_rates = [0, 0, 0, 0, 0, 0, 0]\n"),
        5,
        "flexible_body[0].modal_rates",
        &["expected 6 modal rates"],
    );
    scratch.assert_error(
        &format!("{body}{fe}modal_coordinates = [0, 0, \"q\", 0, 0, 0]\n"),
        5,
        "flexible_body[0].modal_coordinates[2]",
        &["`q`"],
    );
    scratch.assert_error(
        &format!("{body}{fe}mode = \"4N\"\n"),
        5,
        "flexible_body[0].mode",
        &["unknown key `mode`; did you mean `modes`?"],
    );
    scratch.assert_error(
        &format!("{body}{fe}orientation = {{ axis = [0, 0, 0], angle = 1 }}\n"),
        5,
        "flexible_body[0].orientation.axis",
        &["must not be the zero vector"],
    );
    scratch.assert_error(
        "[model]\n[[flexible_body]]\nname = \"ground\"\nfe_model = \"fe/arm.toml\"\n",
        3,
        "flexible_body[0].name",
        &["inertial frame"],
    );
    let twice = format!("[[body]]\nname = \"arm\"\nmass = 1\ninertia = [1, 1, 1]\n\n{body}{fe}");
    scratch.assert_error(&twice, 8, "flexible_body[0].name", &["body name `arm` is already used by body[0] on line 2"]);
}

#[test]
fn errors_of_the_fe_model_file_name_its_file_and_line_and_the_reference() {
    let scratch = Scratch::new("fe-errors");
    let bad = cantilever_text().replace("width = \"w\"", "width = \"-w\"");
    let line = bad.lines().position(|l| l.starts_with("width = ")).unwrap() + 1;
    scratch.write("fe/bad.toml", &bad);
    let text = "[model]\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"fe/bad.toml\"\n";
    let e = scratch.load(text).expect_err("a bad FE model");
    let fe_file = scratch.path("fe/bad.toml").display().to_string();
    assert_eq!(e.file, fe_file);
    assert_eq!(e.line, Some(line));
    assert_eq!(e.key_path, "beam_section[0].width");
    let shown = e.to_string();
    let prefix = format!("{fe_file}:{line}: beam_section[0].width: ");
    assert!(shown.starts_with(&prefix), "`{shown}` should start with `{prefix}`");
    let reference = format!("(in the FE model of flexible_body[0].fe_model, {}:4)", scratch.model_file());
    assert!(shown.ends_with(&reference), "`{shown}` should end with `{reference}`");

    // The FE model file has no [modes] set: the table must give one.
    let no_set: String =
        cantilever_text().lines().filter(|l| !l.starts_with("set = ")).map(|l| format!("{l}\n")).collect();
    scratch.write("fe/no_set.toml", &no_set);
    let text = "[model]\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"fe/no_set.toml\"\n";
    scratch.assert_error(text, 2, "flexible_body[0].modes", &["missing required key `modes`", "no `[modes] set`"]);
    scratch
        .load(&format!("{text}modes = \"2N\"\n\n[[marker]]\nname = \"m\"\nbody = \"arm\"\nnode = 1\n"))
        .unwrap_or_else(|e| panic!("{e}"));

    // Without rotary inertia the torque's static mode only twists the arm and moves no mass: the
    // reduction drops it (4N2S gives five modes). The arm's spin about its own axis carries no mass
    // either; with no joint to hold it, the gauge holds it (ω̄ · e = 0) and the check passes.
    let no_rotary = cantilever_text().replace("rotary_inertia = true", "rotary_inertia = false");
    scratch.write("fe/no_rotary.toml", &no_rotary);
    let text = "[model]\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"fe/no_rotary.toml\"\n";
    let loaded = scratch.load(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.flexible_bodies[0].mode_labels.len(), 5);
    flexmb::analysis::check_model(&loaded.model, Default::default()).unwrap_or_else(|e| panic!("{e}"));
}

#[test]
fn errors_of_markers_and_outputs_at_nodes() {
    let scratch = Scratch::new("node-errors");
    // Lines 1-4: a rigid body; 6: [model]; 7-9: the flexible arm; 11: the [[marker]] or [[output]]
    // header, 12-13 its name (type) and body, 14 and 15 the keys under test.
    let head = "[[body]]\nname = \"hub\"\nmass = 1\ninertia = [1, 1, 1]\n\n\
                [model]\n[[flexible_body]]\nname = \"arm\"\nfe_model = \"fe/arm.toml\"\n\n";
    let marker = |body: &str, rest: &str| format!("{head}[[marker]]\nname = \"m\"\nbody = \"{body}\"\n{rest}");
    scratch.assert_error(
        &marker("arm", "node = 99\n"),
        14,
        "marker[0].node",
        &["flexible body `arm` has no node labelled 99 (it has 21 nodes, labelled 1 to 21)"],
    );
    scratch.assert_error(
        &marker("hub", "node = 3\n"),
        14,
        "marker[0].node",
        &["`node` applies to markers on flexible bodies only", "`hub`, a rigid body"],
    );
    scratch.assert_error(&marker("ground", "node = 3\n"), 14, "marker[0].node", &["on ground"]);
    let e = scratch.assert_error(
        &marker("arm", "origin = [1, 0, 0]\n"),
        11,
        "marker[0].node",
        &["missing required key `node`", "`arm` is a flexible body"],
    );
    assert_eq!(e.kind, ErrorKind::Schema);
    scratch.assert_error(
        &marker("arm", "node = 21\norigin = [1, 0, 0]\n"),
        15,
        "marker[0].origin",
        &["`origin` does not go with `node`"],
    );
    scratch.assert_error(
        &marker("arm", "node = [0.51, 0, 0]\n"),
        14,
        "marker[0].node",
        &["no node at [0.51, 0, 0]", "the nearest is node 11 at [0.5, 0, 0], 0.01 m away"],
    );
    scratch.assert_error(&marker("arm", "node = [0.5, 0]\n"), 14, "marker[0].node", &["3 components"]);
    scratch.assert_error(&marker("arm", "node = \"arm.ends\"\n"), 14, "marker[0].node", &["did you mean `arm.end`?"]);
    scratch.assert_error(&marker("arm", "node = \"arm\"\n"), 14, "marker[0].node", &["holds 21 nodes"]);
    scratch.assert_error(&marker("arm", "node = 0\n"), 14, "marker[0].node", &["positive integer"]);
    scratch.assert_error(&marker("armm", "node = 1\n"), 13, "marker[0].body", &["did you mean `arm`?"]);

    let output = |rest: &str| format!("{head}[[output]]\n{rest}");
    scratch.assert_error(
        &output("type = \"modal_coordinates\"\nbody = \"hub\"\n"),
        13,
        "output[0].body",
        &["`hub` is a rigid body"],
    );
    scratch.assert_error(
        &output("type = \"strain_energy\"\nbody = \"arn\"\n"),
        13,
        "output[0].body",
        &["no body named `arn`; did you mean `arm`?"],
    );
    scratch.assert_error(
        &output("type = \"node_position\"\nbody = \"arm\"\n"),
        11,
        "output[0].node",
        &["missing required key `node`"],
    );
    scratch.assert_error(
        &output("type = \"node_velocity\"\nnode = 3\n"),
        11,
        "output[0].body",
        &["missing required key `body`"],
    );
    scratch.assert_error(
        &output("type = \"node_deformation\"\nbody = \"arm\"\nnode = 22\n"),
        14,
        "output[0].node",
        &["no node labelled 22"],
    );
    scratch.assert_error(
        &output("type = \"modal_coordinates\"\nbody = \"arm\"\nnode = 3\n"),
        14,
        "output[0].node",
        &["does not apply to a modal_coordinates output"],
    );
    scratch.assert_error(
        &output("type = \"node_positon\"\nbody = \"arm\"\nnode = 3\n"),
        12,
        "output[0].type",
        &["did you mean `node_position`?"],
    );
}
