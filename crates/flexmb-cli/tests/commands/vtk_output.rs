//! ParaView output as a user gets it: `flexmb run --vtk` writes a `.pvd` series of `.vtu` files whose
//! points are where the engine says the bodies are, rigid bodies drawn as their shapes, joints at their
//! markers; `flexmb modes --vtk` adds an animation of each mode. The files are read back with `vtkio`
//! and, when `meshio` is installed, by an independent reader (`tests/vtk/check_vtk.py`).

use crate::program;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use program::{flexmb, scratch, text, workspace, ResultCsv};
use vtkio::model::{Attribute, DataSet, Piece, UnstructuredGridPiece, VertexNumbers};

/// One `<DataSet …/>` of a `.pvd` file.
#[derive(Debug)]
pub(crate) struct Entry {
    pub time: f64,
    pub part: usize,
    pub name: String,
    pub file: String,
}

/// The entries of a `.pvd` file, in order.
pub(crate) fn read_pvd(path: &Path) -> Vec<Entry> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(text.trim_end().ends_with("</VTKFile>"), "the index is complete: {text}");
    let attribute = |line: &str, name: &str| -> String {
        let start = line.find(&format!(" {name}=\"")).unwrap_or_else(|| panic!("{name} in {line}")) + name.len() + 3;
        line[start..].split('"').next().unwrap().to_string()
    };
    text.lines()
        .filter(|l| l.trim_start().starts_with("<DataSet "))
        .map(|l| Entry {
            time: attribute(l, "timestep").parse().unwrap(),
            part: attribute(l, "part").parse().unwrap(),
            name: attribute(l, "name"),
            file: attribute(l, "file"),
        })
        .collect()
}

/// The grid of a `.vtu` file.
pub(crate) fn read_vtu(path: &Path) -> UnstructuredGridPiece {
    let vtk = vtkio::Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else { panic!("{}: not a grid", path.display()) };
    assert_eq!(pieces.len(), 1);
    match pieces.remove(0) {
        Piece::Inline(piece) => *piece,
        _ => panic!("{}: the piece is inline", path.display()),
    }
}

pub(crate) fn points(grid: &UnstructuredGridPiece) -> Vec<[f64; 3]> {
    grid.points.cast_into::<f64>().unwrap().chunks(3).map(|p| [p[0], p[1], p[2]]).collect()
}

/// A point data array (`components` per point) as numbers.
pub(crate) fn point_data(grid: &UnstructuredGridPiece, name: &str) -> Vec<f64> {
    let array = grid.data.point.iter().find(|a| a.name() == name).unwrap_or_else(|| panic!("point data {name}"));
    let Attribute::DataArray(array) = array else { panic!("{name} is a data array") };
    array.data.cast_into::<f64>().unwrap()
}

fn cell_data(grid: &UnstructuredGridPiece, name: &str) -> Vec<f64> {
    let array = grid.data.cell.iter().find(|a| a.name() == name).unwrap_or_else(|| panic!("cell data {name}"));
    let Attribute::DataArray(array) = array else { panic!("{name} is a data array") };
    array.data.cast_into::<f64>().unwrap()
}

/// The cells' point lists.
fn cells(grid: &UnstructuredGridPiece) -> Vec<Vec<u64>> {
    let VertexNumbers::XML { connectivity, offsets } = &grid.cells.cell_verts else { panic!("XML cells") };
    let mut start = 0;
    offsets
        .iter()
        .map(|&end| {
            let cell = connectivity[start as usize..end as usize].to_vec();
            start = end;
            cell
        })
        .collect()
}

fn close(a: [f64; 3], b: [f64; 3], tolerance: f64) -> bool {
    (0..3).all(|k| (a[k] - b[k]).abs() <= tolerance)
}

#[test]
fn the_flexible_pendulum_series_puts_the_nodes_where_the_engine_does() {
    let dir = scratch("vtk-flexible");
    let out = dir.join("out");
    let vtk = dir.join("vtk");
    let args = ["run", "models/flexible_pendulum.toml", "--t-end", "0.2", "--vtk", vtk.to_str().unwrap()];
    let o = flexmb(&[&args[..], &["--out", out.to_str().unwrap()]].concat());
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "stdout:\n{stdout}\nstderr:\n{}", text(&o.stderr));
    let pvd = vtk.join("flexible_pendulum.pvd");
    assert!(stdout.contains(&format!("ParaView: {} (101 frames of 2 blocks)", pvd.display())), "{stdout}");

    // Every output time (output_step 0.002 s, 0 to 0.2 s), one block for the strip and one for the hinge.
    let entries = read_pvd(&pvd);
    assert_eq!(entries.len(), 2 * 101);
    for (k, pair) in entries.chunks(2).enumerate() {
        assert!((pair[0].time - 0.002 * k as f64).abs() < 1e-12 && pair[1].time == pair[0].time);
        assert_eq!((pair[0].part, pair[0].name.as_str(), pair[1].part, pair[1].name.as_str()), (0, "beam", 1, "hinge"));
    }

    // At t = 0.1 s the tip (node 21) is where the engine's node outputs put it, and moves as they say.
    let csv = ResultCsv::read(&out.join("flexible_pendulum.csv"));
    assert!((csv.at(50, "t") - 0.1).abs() < 1e-12 && (entries[100].time - 0.1).abs() < 1e-12);
    let beam = read_vtu(&vtk.join(&entries[100].file));
    assert_eq!((points(&beam).len(), cells(&beam).len()), (21, 20));
    assert!(cells(&beam).iter().all(|c| c.len() == 2), "beam elements are lines");
    let tip = point_data(&beam, "node").iter().position(|&label| label == 21.0).expect("node 21");
    let csv3 = |what: &str| ["x", "y", "z"].map(|c| csv.at(50, &format!("beam.node21.{what}.{c}")));
    assert!(close(points(&beam)[tip], csv3("position"), 1e-9), "{:?} vs {:?}", points(&beam)[tip], csv3("position"));
    let velocity = point_data(&beam, "velocity");
    assert!(close([velocity[3 * tip], velocity[3 * tip + 1], velocity[3 * tip + 2]], csv3("velocity"), 1e-8));
    // The elastic displacement is the node's deformation (body frame in the CSV) turned to global axes.
    let elastic = point_data(&beam, "elastic_displacement");
    let deformation = csv3("deformation");
    let norm = |v: [f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!(norm(deformation) > 1e-5, "the strip bends: {deformation:?}");
    assert!((norm([elastic[3 * tip], elastic[3 * tip + 1], elastic[3 * tip + 2]]) - norm(deformation)).abs() < 1e-12);
    // The displacement is measured from the first frame.
    let first = read_vtu(&vtk.join(&entries[0].file));
    let displacement = point_data(&beam, "displacement");
    for (k, (p, p0)) in points(&beam).iter().zip(points(&first)).enumerate() {
        let d = [displacement[3 * k], displacement[3 * k + 1], displacement[3 * k + 2]];
        assert!(close(d, [p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]], 1e-15));
    }
    assert!(point_data(&first, "displacement").iter().all(|&x| x == 0.0));

    // The hinge: a vertex at each marker, both at the pivot.
    let hinge = read_vtu(&vtk.join(&entries[101].file));
    assert_eq!(cells(&hinge), vec![vec![0], vec![1]]);
    assert_eq!(point_data(&hinge, "marker"), vec![0.0, 1.0]);
    assert!(points(&hinge).iter().all(|p| close(*p, [0.0; 3], 1e-9)), "{:?}", points(&hinge));

    check_with_meshio(&pvd, &out.join("flexible_pendulum.csv"), &["beam=21:20", "hinge=2:2"], Some(("beam", 21, 0.1)));
}

/// Runs `tests/vtk/check_vtk.py` (an independent reader, meshio) on a series, if meshio is installed.
fn check_with_meshio(pvd: &Path, csv: &Path, blocks: &[&str], node: Option<(&str, u64, f64)>) {
    let has_meshio = Command::new("python3").args(["-c", "import meshio"]).output().is_ok_and(|o| o.status.success());
    if !has_meshio {
        println!("skipped: meshio not installed (python3 -m pip install meshio)");
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/vtk/check_vtk.py");
    let mut args: Vec<String> =
        vec![script.display().to_string(), pvd.display().to_string(), csv.display().to_string()];
    args.extend(blocks.iter().map(|b| format!("--block={b}")));
    if let Some((body, label, time)) = node {
        args.push(format!("--node={body}:{label}:{time}"));
    }
    let o = Command::new("python3").args(&args).output().expect("python3 runs");
    assert!(o.status.success(), "check_vtk.py failed:\nstdout:\n{}\nstderr:\n{}", text(&o.stdout), text(&o.stderr));
    println!("{}", text(&o.stdout));
}

/// A model with one rigid body of every shape; the arm swings on a hinge, the others fall.
const SHAPES: &str = r#"
[model]
name = "shapes"
gravity = [0.0, -9.81, 0.0]

[simulation]
t_end = 0.1
output_step = 0.01
vtk_step = 0.05

[[body]]
name = "arm"
mass = 1.0
inertia = [1e-4, 0.013, 0.013]
center_of_mass = [0.2, 0.0, 0.0]
velocity = [0, 0, 0]
angular_velocity = [0, 0, 0]
shape = { box = [0.4, 0.04, 0.02], origin = [0.2, 0.0, 0.0] }

[[body]]
name = "drum"
mass = 2.0
inertia = [0.01, 0.01, 0.02]
position = [1.0, 0.0, 0.0]
velocity = [0, 0, 0]
angular_velocity = [0, 3, 0]
shape = { cylinder = { radius = 0.1, length = 0.05, axis = "y" } }

[[body]]
name = "ball"
mass = 0.5
inertia = [5e-4, 5e-4, 5e-4]
position = [1.5, 0.0, 0.0]
velocity = [0, 0, 0]
angular_velocity = [0, 0, 0]
shape = { sphere = 0.05 }

[[body]]
name = "cube"
mass = 0.1
inertia = [1e-5, 1e-5, 1e-5]
position = [2.0, 0.0, 0.0]
velocity = [0, 0, 0]
angular_velocity = [0, 0, 0]
shape = { mesh = "parts/cube_mm.stl", scale = 0.001, origin = [0.0, 0.5, 0.0], orientation = { axis = [0, 0, 1], angle_deg = 90 } }

[[body]]
name = "plate"
mass = 0.1
inertia = [1e-5, 1e-5, 1e-5]
position = [2.5, 0.0, 0.0]
velocity = [0, 0, 0]
angular_velocity = [0, 0, 0]
shape = { mesh = "parts/plate.stl" }

[[body]]
name = "bracket"
mass = 0.1
inertia = [1e-5, 1e-5, 1e-5]
position = [3.0, 0.0, 0.0]
velocity = [0, 0, 0]
angular_velocity = [0, 0, 0]
shape = { mesh = "parts/bracket.obj" }

[[body]]
name = "bare"
mass = 1.0
inertia = [0.01, 0.02, 0.03]
position = [3.5, 0.0, 0.0]
velocity = [0, 0, 0]
angular_velocity = [0, 0, 0]

[[marker]]
name = "pivot"
body = "ground"

[[marker]]
name = "arm_pivot"
body = "arm"

[[marker]]
name = "arm_corner"
body = "arm"
origin = [0.4, 0.02, 0.01]

[[marker]]
name = "floor"
body = "ground"

[[marker]]
name = "ball_centre"
body = "ball"

[[joint]]
name = "hinge"
type = "revolute"
i = "pivot"
j = "arm_pivot"

[[joint]]
name = "ball_plane"
type = "point-in-plane"
i = "floor"
j = "ball_centre"

[[output]]
type = "marker_position"
marker = "arm_corner"

[[output]]
type = "marker_position"
marker = "ball_centre"
"#;

/// The twelve triangles of a cube of 10 mm edge from the origin, as ASCII STL.
fn cube_mm_stl() -> String {
    let corner = |k: usize| [(k & 1) as f64 * 10.0, ((k >> 1) & 1) as f64 * 10.0, ((k >> 2) & 1) as f64 * 10.0];
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    let mut s = String::from("solid cube\n");
    for f in faces {
        for tri in [[f[0], f[1], f[2]], [f[0], f[2], f[3]]] {
            s.push_str("  facet normal 0 0 0\n    outer loop\n");
            for k in tri {
                let [x, y, z] = corner(k);
                s.push_str(&format!("      vertex {x} {y} {z}\n"));
            }
            s.push_str("    endloop\n  endfacet\n");
        }
    }
    s + "endsolid cube\n"
}

/// Two triangles of a 0.2 m square plate, as binary STL.
fn plate_stl() -> Vec<u8> {
    let mut bytes = vec![b' '; 80];
    bytes.extend(2u32.to_le_bytes());
    for tri in
        [[[0.0f32, 0.0, 0.0], [0.2, 0.0, 0.0], [0.2, 0.2, 0.0]], [[0.0, 0.0, 0.0], [0.2, 0.2, 0.0], [0.0, 0.2, 0.0]]]
    {
        bytes.extend([0.0f32; 3].iter().flat_map(|x| x.to_le_bytes()));
        bytes.extend(tri.iter().flatten().flat_map(|x| x.to_le_bytes()));
        bytes.extend([0, 0]);
    }
    bytes
}

/// An L-shaped bracket of two quadrilaterals and a triangle, as OBJ.
const BRACKET_OBJ: &str = "# bracket\nv 0 0 0\nv 0.1 0 0\nv 0.1 0.1 0\nv 0 0.1 0\nv 0 0 0.1\nv 0.1 0 0.1\n\
                           f 1 2 3 4\nf 1/1 5/2 6/3 2/4\nf -2 -1 -5\n";

fn shapes_model(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    std::fs::write(dir.join("parts/cube_mm.stl"), cube_mm_stl()).unwrap();
    std::fs::write(dir.join("parts/plate.stl"), plate_stl()).unwrap();
    std::fs::write(dir.join("parts/bracket.obj"), BRACKET_OBJ).unwrap();
    let path = dir.join("shapes.toml");
    std::fs::write(&path, SHAPES).unwrap();
    path
}

#[test]
fn rigid_bodies_are_drawn_as_their_shapes_and_move_with_them() {
    let dir = scratch("vtk-shapes");
    let model = shapes_model(&dir);
    let vtk = dir.join("vtk");
    let o = flexmb(&["run", model.to_str().unwrap(), "--vtk", vtk.to_str().unwrap(), "--out", dir.to_str().unwrap()]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "stdout:\n{stdout}\nstderr:\n{}", text(&o.stderr));

    // vtk_step = 0.05 s of 0.1 s: three frames of seven bodies and two joints.
    let entries = read_pvd(&vtk.join("shapes.pvd"));
    assert_eq!(entries.len(), 3 * 9);
    let times: Vec<f64> = entries.iter().step_by(9).map(|e| e.time).collect();
    assert!(times.iter().zip([0.0, 0.05, 0.1]).all(|(t, expected)| (t - expected).abs() < 1e-12), "{times:?}");
    let names: Vec<&str> = entries[..9].iter().map(|e| e.name.as_str()).collect();
    assert_eq!(names, ["arm", "drum", "ball", "cube", "plate", "bracket", "bare", "hinge", "ball_plane"]);

    let grids: BTreeMap<&str, UnstructuredGridPiece> =
        entries[18..].iter().map(|e| (e.name.as_str(), read_vtu(&vtk.join(&e.file)))).collect();
    let size = |name: &str| (points(&grids[name]).len(), cells(&grids[name]).len());
    assert_eq!(size("arm"), (24, 6), "a box: four points per face");
    assert_eq!(size("drum"), (4 * 32, 32 + 2), "a cylinder: 32 side quadrilaterals and two caps");
    assert_eq!(size("ball"), (2 + 15 * 32, 16 * 32), "a sphere: 16 bands of 32");
    assert_eq!(size("cube"), (36, 12), "ASCII STL: three points per triangle");
    assert_eq!(size("plate"), (6, 2), "binary STL");
    assert_eq!(size("bracket"), (6, 3), "OBJ: shared vertices");
    assert_eq!(size("bare"), (6, 3), "no shape: the frame glyph");
    assert_eq!(cell_data(&grids["bare"], "axis"), vec![0.0, 1.0, 2.0]);
    assert_eq!(cells(&grids["bracket"]), vec![vec![0, 1, 2, 3], vec![0, 4, 5, 1], vec![4, 5, 1]]);

    // The box's corner is where the engine puts a marker at that corner of the swinging arm.
    let csv = ResultCsv::read(&dir.join("shapes.csv"));
    assert!((csv.at(-1, "t") - 0.1).abs() < 1e-12);
    let corner = ["x", "y", "z"].map(|c| csv.at(-1, &format!("arm_corner.position.{c}")));
    assert!(corner[1] < -0.01, "the arm has swung down: {corner:?}");
    let on_box = points(&grids["arm"]).iter().filter(|p| close(**p, corner, 1e-9)).count();
    assert_eq!(on_box, 3, "three faces meet at the corner {corner:?}");
    // The joint's points are its markers: the ground's at the origin, the ball's centre falling.
    let centre = ["x", "y", "z"].map(|c| csv.at(-1, &format!("ball_centre.position.{c}")));
    assert!(centre[1] < -0.04, "the ball falls: {centre:?}");
    let joint = points(&grids["ball_plane"]);
    assert!(close(joint[0], [0.0; 3], 0.0) && close(joint[1], centre, 1e-9), "{joint:?} vs {centre:?}");
    let fall = point_data(&grids["ball_plane"], "velocity")[4];
    assert!((fall + 9.81 * 0.1).abs() < 1e-6, "the ball's centre falls at g t: {fall}");

    // The cube in millimetres, scaled to metres, turned 90° about z and placed 0.5 m up the body's y
    // axis, at the first frame (the body frame at [2, 0, 0], unturned).
    let cube0 = read_vtu(&vtk.join(&entries[3].file));
    let (low, high) = points(&cube0).iter().fold(([f64::MAX; 3], [f64::MIN; 3]), |(lo, hi), p| {
        (std::array::from_fn(|k| lo[k].min(p[k])), std::array::from_fn(|k| hi[k].max(p[k])))
    });
    assert!(close(low, [1.99, 0.5, 0.0], 1e-12) && close(high, [2.0, 0.51, 0.01], 1e-12), "{low:?} {high:?}");

    let csv = dir.join("shapes.csv");
    let blocks = [
        "arm=24:6",
        "drum=128:34",
        "ball=482:512",
        "cube=36:12",
        "plate=6:2",
        "bracket=6:3",
        "bare=6:3",
        "hinge=2:2",
        "ball_plane=2:2",
    ];
    check_with_meshio(&vtk.join("shapes.pvd"), &csv, &blocks, None);
}

#[test]
fn the_frame_interval_must_be_a_multiple_of_the_output_step() {
    let dir = scratch("vtk-step");
    let model = shapes_model(&dir);
    let vtk = dir.join("vtk");
    let args = ["run", model.to_str().unwrap(), "--vtk", vtk.to_str().unwrap(), "--out", dir.to_str().unwrap()];
    let o = flexmb(&[&args[..], &["--vtk-step", "0.015"]].concat());
    assert!(!o.status.success());
    let stderr = text(&o.stderr);
    assert!(stderr.contains("--vtk-step") && stderr.contains("multiple of the output step 0.01"), "{stderr}");
    // Without --vtk there is nothing to space.
    let o = flexmb(&["run", model.to_str().unwrap(), "--vtk-step", "0.05", "--out", dir.to_str().unwrap()]);
    let stderr = text(&o.stderr);
    assert!(!o.status.success() && stderr.contains("--vtk <DIR>"), "{stderr}");
}

/// Every file a `.pvd` names exists and reads as a grid; returns the entries.
fn check_series(pvd: &Path) -> Vec<Entry> {
    let entries = read_pvd(pvd);
    for e in &entries {
        read_vtu(&pvd.parent().unwrap().join(&e.file));
    }
    entries
}

#[test]
fn a_run_that_fails_leaves_a_complete_series_up_to_its_last_frame() {
    // The hinge driven by sqrt(0.05 − t), whose rate is infinite at t = 0.05 s: the run stops there.
    // (A driver tan(π t / 0.1), whose angle grows without bound, made the same point but spun the arm
    // through 754,000 steps and 78 s of the suite before the step size collapsed.)
    let dir = scratch("vtk-failed");
    shapes_model(&dir);
    let model = dir.join("runaway.toml");
    let driver = "[[driver]]\nname = \"runaway\"\njoint = \"hinge\"\nfunction = \"sqrt(0.05 - t)\"\n\n[[output]]";
    std::fs::write(&model, SHAPES.replacen("[[output]]", driver, 1)).unwrap();
    let vtk = dir.join("vtk");
    let args = ["run", model.to_str().unwrap(), "--vtk", vtk.to_str().unwrap(), "--vtk-step", "0.01"];
    let o = flexmb(&[&args[..], &["--out", dir.to_str().unwrap()]].concat());
    assert!(!o.status.success(), "the run fails: {}", text(&o.stdout));
    let stderr = text(&o.stderr);
    // The failure names the driver and its infinite rate (not "a singular mass matrix"), whether a step
    // ended past t = 0.05 s or the steps shrank to nothing before it (the rate, −inf there, found ahead).
    for part in ["simulation failed: at t = 0.05 s joint 'runaway' (angle driver)", "is not finite (its time derivative is"] {
        assert!(stderr.contains(part), "{part}: {stderr}");
    }
    let entries = check_series(&vtk.join("runaway.pvd"));
    let last = entries.last().expect("frames before the failure").time;
    assert!(
        entries.len() >= 3 * 9 && entries.len() % 9 == 0 && last < 0.05,
        "{} entries up to t = {last}",
        entries.len()
    );
}

#[test]
fn a_run_that_is_killed_leaves_a_complete_series() {
    let dir = scratch("vtk-killed");
    let vtk = dir.join("vtk");
    let pvd = vtk.join("flexible_pendulum.pvd");
    let mut child = Command::new(env!("CARGO_BIN_EXE_flexmb"))
        .args(["run", "models/flexible_pendulum.toml", "--quiet", "--vtk", vtk.to_str().unwrap()])
        .args(["--out", dir.to_str().unwrap()])
        .current_dir(workspace())
        .spawn()
        .expect("flexmb starts");
    // Killed (SIGKILL: no chance to tidy up) once some frames are written.
    let started = std::time::Instant::now();
    while std::fs::read_to_string(&pvd).map_or(0, |t| t.matches("<DataSet ").count()) < 20 {
        assert!(started.elapsed().as_secs() < 120, "no frames written");
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    child.kill().expect("kill");
    child.wait().unwrap();
    let entries = check_series(&pvd);
    assert!(entries.len() >= 20 && entries.len() % 2 == 0, "{} entries", entries.len());
}

#[test]
fn each_mode_of_the_cantilever_plays_as_an_animation() {
    let dir = scratch("vtk-modes");
    let o = flexmb(&[
        "modes",
        "models/fe/cantilever.toml",
        "--out",
        dir.join("arm.json").to_str().unwrap(),
        "--vtk",
        dir.to_str().unwrap(),
    ]);
    let stdout = text(&o.stdout);
    assert!(o.status.success(), "stdout:\n{stdout}\nstderr:\n{}", text(&o.stderr));
    assert!(dir.join("cantilever_modes.vtu").exists(), "the mode shapes file is still written");
    let pvd = dir.join("cantilever_mode_O1.pvd");
    assert!(stdout.contains(&pvd.display().to_string()), "{stdout}");
    for label in ["O1", "O2", "O3", "O4", "O5", "O6"] {
        assert_eq!(read_pvd(&dir.join(format!("cantilever_mode_{label}.pvd"))).len(), 24, "{label}");
    }
    let entries = read_pvd(&pvd);
    assert!(entries.iter().enumerate().all(|(k, e)| (e.time - k as f64 / 24.0).abs() < 1e-12));
    assert!(entries[0].name.starts_with("O1 mode ("), "{}", entries[0].name);
    // Frame 0 is the undeformed bar along x (1 m); a quarter period later (frame 6) the largest
    // displacement is a tenth of the bar's size, and the points are the undeformed ones plus it.
    let rest = read_vtu(&dir.join(&entries[0].file));
    let peak = read_vtu(&dir.join(&entries[6].file));
    assert!(point_data(&rest, "displacement").iter().all(|&x| x == 0.0));
    let u = point_data(&peak, "displacement");
    let largest = u.chunks(3).map(|d| d.iter().map(|x| x * x).sum::<f64>().sqrt()).fold(0.0, f64::max);
    let rest_points = points(&rest);
    let (x_min, x_max) = rest_points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p[0]), hi.max(p[0])));
    assert!((x_max - x_min - 1.0).abs() < 1e-12);
    assert!((largest - 0.1).abs() < 1e-12, "{largest}");
    for (k, (p, p0)) in points(&peak).iter().zip(&rest_points).enumerate() {
        assert!(close(*p, [p0[0] + u[3 * k], p0[1] + u[3 * k + 1], p0[2] + u[3 * k + 2]], 1e-15));
    }
    // Half a period on, the shape is back at rest (sin π = 0, to round-off).
    let half = read_vtu(&dir.join(&entries[12].file));
    assert!(point_data(&half, "displacement").iter().all(|x| x.abs() < 1e-15));

    // O6 twists the bar about its axis, where the nodes are: it turns them without moving them, so its
    // largest rotation is scaled to 0.1 rad rather than its round-off translations to a tenth of the bar.
    assert!(stdout.contains("rotation only"), "{stdout}");
    let twist = read_pvd(&dir.join("cantilever_mode_O6.pvd"));
    let peak = read_vtu(&dir.join(&twist[6].file));
    let largest = |v: Vec<f64>| v.chunks(3).map(|d| d.iter().map(|x| x * x).sum::<f64>().sqrt()).fold(0.0, f64::max);
    assert!((largest(point_data(&peak, "rotation")) - 0.1).abs() < 1e-12);
    assert!(largest(point_data(&peak, "displacement")) < 1e-12);
}

#[test]
fn the_model_files_frame_interval_must_be_positive() {
    let text =
        "[simulation]\noutput_step = 0.01\nvtk_step = -0.05\n[model]\n[[body]]\nname = \"b\"\nmass = 1\ninertia = [1, 1, 1]\n";
    let e = flexmb_files::parse_model(text, "models/bad.toml").expect_err("an error");
    assert_eq!((e.line, e.key_path.as_str()), (Some(3), "simulation.vtk_step"));
    assert!(e.to_string().contains("vtk_step must be positive, got -0.05"), "{e}");
    let loaded = flexmb_files::parse_model(&text.replace("-0.05", "0.05"), "models/good.toml").unwrap();
    assert_eq!(loaded.simulation.vtk_step, Some(0.05));
}
