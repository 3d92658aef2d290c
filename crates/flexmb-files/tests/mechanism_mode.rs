//! The animation of a mode of the whole mechanism, read back with `vtkio` as ParaView reads it: frame
//! `k` draws every body at `q ⊕ c Re(ψ e^{2πik/N})` — at φ = 0 exactly the positions
//! `displaced_positions(q, c ψ_re)` drawn, at φ = π their mirror image about `q` to first order in `c`, a
//! complex shape a quarter period later at `displaced_positions(q, −c ψ_im)` — and a zero shape stays
//! at `q`.

use std::path::{Path, PathBuf};

use flexmb::analysis::{displaced_positions, State};
use flexmb::math::{rotation_matrix, Mat3, Vec3, Vec4};
use flexmb::model::BodyId;
use flexmb::Model;
use flexmb_files::shape::frame_size;
use flexmb_files::vtk::mechanism_mode::{
    loaded_mechanism_mode_animation, mechanism_mode_animation,
};
use flexmb_files::vtk::{AMPLITUDE_FRACTION, FRAMES_PER_PERIOD};
use flexmb_files::{load_model, LoadedModel};
use vtkio::model::{Attribute, DataSet, Piece, UnstructuredGridPiece, VertexNumbers};

fn model_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../models").join(name)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmb-files-mechanism-mode-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn read_vtu(path: &Path) -> UnstructuredGridPiece {
    let vtk = vtkio::Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let DataSet::UnstructuredGrid { mut pieces, .. } = vtk.data else { panic!("{}: not a grid", path.display()) };
    match pieces.remove(0) {
        Piece::Inline(piece) => *piece,
        _ => panic!("{}: the piece is inline", path.display()),
    }
}

fn points(grid: &UnstructuredGridPiece) -> Vec<Vec3> {
    grid.points.cast_into::<f64>().unwrap().chunks(3).map(Vec3::from_column_slice).collect()
}

fn point_vectors(grid: &UnstructuredGridPiece, name: &str) -> Vec<Vec3> {
    let array = grid.data.point.iter().find(|a| a.name() == name).unwrap_or_else(|| panic!("point data {name}"));
    let Attribute::DataArray(array) = array else { panic!("{name} is a data array") };
    array.data.cast_into::<f64>().unwrap().chunks(3).map(Vec3::from_column_slice).collect()
}

/// The `.pvd` file's entries: (time, block name, file).
fn pvd_entries(pvd: &Path) -> Vec<(f64, String, PathBuf)> {
    let text = std::fs::read_to_string(pvd).unwrap();
    let attribute = |line: &str, key: &str| {
        let start = line.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        line[start..start + line[start..].find('"').unwrap()].to_string()
    };
    text.lines()
        .filter(|l| l.contains("<DataSet "))
        .map(|l| {
            let file = pvd.parent().unwrap().join(attribute(l, "file"));
            (attribute(l, "timestep").parse().unwrap(), attribute(l, "name"), file)
        })
        .collect()
}

/// The grid of block `name` in frame `k`.
fn frame(pvd: &Path, k: usize, name: &str) -> UnstructuredGridPiece {
    let entries = pvd_entries(pvd);
    let time = k as f64 / FRAMES_PER_PERIOD as f64;
    let (_, _, file) = entries.iter().find(|(t, n, _)| (t - time).abs() < 1e-12 && n == name).unwrap();
    read_vtu(file)
}

fn pose(model: &Model, body: usize, q: &[f64]) -> (Vec3, Mat3) {
    let range = model.layout().q_range(BodyId(body)).unwrap();
    let qb = &q[range];
    (Vec3::from_column_slice(&qb[0..3]), rotation_matrix(&Vec4::from_column_slice(&qb[3..7])))
}

/// A rigid body as a model alone draws it: its frame glyph, the origin and one axis end per axis.
fn glyph(model: &Model, body: usize, q: &[f64]) -> Vec<Vec3> {
    let (origin, rotation) = pose(model, body, q);
    let b = &model.bodies()[body];
    let size = frame_size(b.mass, &b.inertia);
    (0..3).flat_map(|k| [origin, origin + rotation * (size * Vec3::ith(k, 1.0))]).collect()
}

/// A flexible body's nodes at `R + A (s̄ + Ψ a)`.
fn nodes(model: &Model, body: usize, q: &[f64]) -> Vec<Vec3> {
    let (origin, rotation) = pose(model, body, q);
    let a = &q[model.layout().modal_q_range(BodyId(body)).unwrap()];
    let modal = model.modal_body(BodyId(body)).unwrap();
    let a = nalgebra::DVector::from_column_slice(a);
    modal.nodes.iter().map(|n| origin + rotation * (n.position + &n.psi * &a)).collect()
}

fn largest_difference(a: &[Vec3], b: &[Vec3]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).map(|(x, y)| (x - y).norm()).fold(0.0, f64::max)
}

/// A shape of the double pendulum: both links turned about z (rotation vectors in body axes), the
/// second also moved along its own axis.
fn double_pendulum_shape(model: &Model, turn: [f64; 2], slide: f64) -> Vec<f64> {
    let mut d = vec![0.0; model.layout().nv];
    for (b, angle) in turn.iter().enumerate() {
        let v = model.layout().v_range(BodyId(b)).unwrap();
        d[v.start + 5] = *angle;
    }
    let v = model.layout().v_range(BodyId(1)).unwrap();
    d[v.start] = slide;
    d
}

#[test]
fn a_real_mode_swings_through_the_operating_point_and_frame_zero_is_its_displaced_positions() {
    let loaded = load_model(&model_file("double_pendulum.toml")).unwrap();
    let model = &loaded.model;
    let q = State::initial(model).q;
    let shape = double_pendulum_shape(model, [1.0, -0.6], 0.3);
    let zeros = vec![0.0; shape.len()];
    let dir = scratch("real");
    let animation = mechanism_mode_animation(model, &q, &shape, &zeros, "1 (0.62 Hz)", &dir).unwrap();
    assert_eq!(animation.pvd, dir.join("double-pendulum_mode_1__0.62_Hz_.pvd"));
    assert_eq!((animation.frames, animation.blocks), (FRAMES_PER_PERIOD, 4), "two links, two revolutes");
    let entries = pvd_entries(&animation.pvd);
    assert_eq!(entries.len(), FRAMES_PER_PERIOD * 4);
    for (_, _, file) in &entries {
        read_vtu(file);
    }
    let c = animation.scale;
    let half = FRAMES_PER_PERIOD / 2;
    let plus = displaced_positions(model, &q, &shape.iter().map(|x| c * x).collect::<Vec<_>>()).unwrap();
    let mut largest_displacement: f64 = 0.0;
    for (b, name) in [(0, "link1"), (1, "link2")] {
        let (at_zero, at_pi) = (frame(&animation.pvd, 0, name), frame(&animation.pvd, half, name));
        // φ = 0: exactly the displaced positions, drawn.
        assert!(largest_difference(&points(&at_zero), &glyph(model, b, &plus)) < 1e-14);
        // φ = π: the mirror image about q. Turning by ±θ moves a point at r from the axis by
        // ±r sin θ + r (1 − cos θ) (towards the axis), so the two displacements cancel but for r θ²,
        // θ times the first-order displacement r θ.
        let theta = c * shape.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        let (u0, u_pi) = (point_vectors(&at_zero, "displacement"), point_vectors(&at_pi, "displacement"));
        for (a, b) in u0.iter().zip(&u_pi) {
            assert!((a + b).norm() <= theta * a.norm().max(b.norm()) + 1e-15, "{a} and {b} are not mirror images");
            largest_displacement = largest_displacement.max(a.norm());
        }
        // `displacement` is from q.
        let drawn_at_q = glyph(model, b, &q);
        let moved: Vec<Vec3> = drawn_at_q.iter().zip(&u0).map(|(p, u)| p + u).collect();
        assert!(largest_difference(&moved, &points(&at_zero)) < 1e-14);
    }
    assert!(largest_displacement > 0.0);
    // The largest displacement of any point drawn (the glyphs and the joints' markers) is a tenth of the
    // mechanism's size (the box around them at q), to first order in c: within θ of it.
    let zeros_shape = vec![0.0; shape.len()];
    let still = mechanism_mode_animation(model, &q, &zeros_shape, &zeros_shape, "still", &dir).unwrap().pvd;
    let (mut low, mut high) = (Vec3::repeat(f64::MAX), Vec3::repeat(f64::MIN));
    let mut largest: f64 = 0.0;
    for (_, name, _) in entries.iter().filter(|(t, ..)| *t == 0.0) {
        let (at_q, at_zero) = (points(&frame(&still, 0, name)), points(&frame(&animation.pvd, 0, name)));
        for (p, p0) in at_q.iter().zip(&at_zero) {
            (low, high) = (low.inf(p), high.sup(p));
            largest = largest.max((p0 - p).norm());
        }
    }
    let size = (high - low).norm();
    let theta = c * 1.0;
    assert!(
        (largest / (AMPLITUDE_FRACTION * size) - 1.0).abs() < theta,
        "largest displacement {largest} m, size {size} m, θ = {theta}"
    );
}

#[test]
fn a_complex_mode_moves_round_an_orbit_and_a_zero_shape_stays_at_the_operating_point() {
    let loaded = load_model(&model_file("double_pendulum.toml")).unwrap();
    let model = &loaded.model;
    let q = State::initial(model).q;
    let (re, im) = (double_pendulum_shape(model, [1.0, 0.0], 0.0), double_pendulum_shape(model, [0.0, 1.0], 0.2));
    let dir = scratch("complex");
    let animation = mechanism_mode_animation(model, &q, &re, &im, "whirl", &dir).unwrap();
    let c = animation.scale;
    // A quarter period on, φ = π/2: Re(ψ e^{iπ/2}) = −ψ_im.
    let quarter = displaced_positions(model, &q, &im.iter().map(|x| -c * x).collect::<Vec<_>>()).unwrap();
    for (b, name) in [(0, "link1"), (1, "link2")] {
        let drawn = points(&frame(&animation.pvd, FRAMES_PER_PERIOD / 4, name));
        assert!(largest_difference(&drawn, &glyph(model, b, &quarter)) < 1e-14);
    }

    let zeros = vec![0.0; re.len()];
    let path = mechanism_mode_animation(model, &q, &zeros, &zeros, "still", &dir).unwrap().pvd;
    for k in [0, 5, FRAMES_PER_PERIOD / 2] {
        for (b, name) in [(0, "link1"), (1, "link2")] {
            let grid = frame(&path, k, name);
            assert_eq!(points(&grid), glyph(model, b, &q));
            assert!(point_vectors(&grid, "displacement").iter().all(|u| *u == Vec3::zeros()));
        }
    }
}

#[test]
fn a_flexible_body_is_drawn_as_its_deformed_mesh_and_bad_shapes_are_errors_naming_the_mode() {
    let loaded: LoadedModel = load_model(&model_file("flexible_pendulum.toml")).unwrap();
    let model = &loaded.model;
    let q = State::initial(model).q;
    let nv = model.layout().nv;
    // The first modal coordinate and a turn of the beam about z.
    let mut shape = vec![0.0; nv];
    let modal = model.layout().modal_v_range(BodyId(0)).unwrap();
    shape[modal.start] = 1.0;
    shape[5] = 0.5;
    let zeros = vec![0.0; nv];
    let dir = scratch("flexible");
    let animation = loaded_mechanism_mode_animation(&loaded, &q, &shape, &zeros, "1", &dir).unwrap();
    let c = animation.scale;
    assert!(c > 0.0);
    let displaced = displaced_positions(model, &q, &shape.iter().map(|x| c * x).collect::<Vec<_>>()).unwrap();
    let grid = frame(&animation.pvd, 0, "beam");
    assert!(largest_difference(&points(&grid), &nodes(model, 0, &displaced)) < 1e-14);
    let VertexNumbers::XML { offsets, .. } = &grid.cells.cell_verts else { panic!("XML cells") };
    assert_eq!(offsets.len(), 20, "the FE model's 20 beam elements, as lines");
    let elastic = point_vectors(&grid, "elastic_displacement");
    assert!(elastic.iter().any(|u| u.norm() > 0.0), "the mode deforms the beam");

    // A model alone draws the beam's nodes as vertices.
    let bare = mechanism_mode_animation(model, &q, &shape, &zeros, "1", &scratch("bare")).unwrap();
    let grid = frame(&bare.pvd, 0, "beam");
    assert!(largest_difference(&points(&grid), &nodes(model, 0, &displaced)) < 1e-14);

    let e = mechanism_mode_animation(model, &q, &shape[1..], &zeros, "3", &dir).unwrap_err();
    assert_eq!(
        e,
        format!("mode 3: the real part of the shape has {} entries; the model has {nv} velocity coordinates", nv - 1)
    );
    let mut bad = zeros.clone();
    bad[2] = f64::NAN;
    let e = mechanism_mode_animation(model, &q, &shape, &bad, "3", &dir).unwrap_err();
    assert_eq!(e, "mode 3: entry 2 of the imaginary part of the shape is NaN");
    let e = mechanism_mode_animation(model, &q[1..], &shape, &zeros, "3", &dir).unwrap_err();
    assert_eq!(e, format!("mode 3: the operating point has {} positions; the model has {}", q.len() - 1, q.len()));
}
