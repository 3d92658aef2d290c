//! Tests of the flat shell: rigid motions and zero-energy modes, invariance under rotation, the
//! membrane and bending patch tests, a thin cantilever strip against beam theory, the effect of the
//! drilling stiffness on bending frequencies, the lumped mass, and the errors.

use nalgebra::{DMatrix, DVector, Matrix3, Vector2, Vector3};

use super::*;
use crate::element::test_support::{
    assert_rigid_body_modes, block_rotation, oblique, relative_eigenvalues, rotation, DenseModel,
};

const RHO: f64 = 7800.0;

fn material(poisson_ratio: f64) -> Material {
    Material {
        name: "m".into(),
        youngs_modulus: 210e9,
        poisson_ratio,
        density: RHO,
    }
}

fn section(thickness: f64) -> ShellSection {
    ShellSection {
        name: "s".into(),
        material: 0,
        thickness,
    }
}

fn options(rotary_inertia: bool, drilling_stiffness: f64) -> ModelOptions {
    ModelOptions {
        rotary_inertia,
        drilling_stiffness,
        ..Default::default()
    }
}

/// Points of the plane (x, y) placed in space: origin + q (x, y, 0).
fn place(plane: &[[f64; 2]], q: &Matrix3<f64>, origin: Vector3<f64>) -> Vec<Vector3<f64>> {
    plane
        .iter()
        .map(|[x, y]| origin + q * Vector3::new(*x, *y, 0.0))
        .collect()
}

/// Assembles the elements (node lists) on `nodes` into a dense stiffness and a diagonal mass.
fn assemble(
    nodes: &[Vector3<f64>],
    elements: &[Vec<usize>],
    thickness: f64,
    material: &Material,
    options: &ModelOptions,
) -> (DenseModel, DVector<f64>) {
    let mut model = DenseModel::new(nodes.len());
    let mut mass = DVector::zeros(6 * nodes.len());
    for element in elements {
        let points: Vec<_> = element.iter().map(|&i| nodes[i]).collect();
        let m = shell_matrices(&points, &section(thickness), material, options).unwrap();
        model.add(element, &m.stiffness);
        for (&node, nodal) in element.iter().zip(&m.lumped_mass) {
            for d in 0..3 {
                mass[6 * node + d] += nodal.mass;
                mass[6 * node + 3 + d] += nodal.rotary_inertia[(d, d)];
            }
        }
    }
    (model, mass)
}

/// The lowest `count` natural frequencies (rad/s) with the nodes `fixed` clamped, the mass on the
/// translations only: the rotations are condensed out statically (K* = K_tt − K_tr K_rr⁻¹ K_rt).
fn frequencies(model: &DenseModel, mass: &DVector<f64>, fixed: &[usize], count: usize) -> Vec<f64> {
    let free = |rotation: bool| -> Vec<usize> {
        (0..mass.len())
            .filter(|d| !fixed.contains(&(d / 6)) && (d % 6 >= 3) == rotation)
            .collect()
    };
    let (t, r) = (free(false), free(true));
    let pick = |rows: &[usize], cols: &[usize]| {
        DMatrix::from_fn(rows.len(), cols.len(), |i, j| model.k[(rows[i], cols[j])])
    };
    let k_rr = pick(&r, &r)
        .cholesky()
        .expect("rotational stiffness not positive definite");
    let k_rt = pick(&r, &t);
    let condensed = pick(&t, &t) - k_rt.transpose() * k_rr.solve(&k_rt);
    let scale: Vec<f64> = t.iter().map(|&d| 1.0 / mass[d].sqrt()).collect();
    let a = DMatrix::from_fn(t.len(), t.len(), |i, j| {
        condensed[(i, j)] * scale[i] * scale[j]
    });
    let a = (&a + a.transpose()) * 0.5;
    let mut values: Vec<f64> = a.symmetric_eigen().eigenvalues.iter().copied().collect();
    values.sort_by(f64::total_cmp);
    values
        .iter()
        .take(count)
        .map(|v| v.max(0.0).sqrt())
        .collect()
}

/// Nodes, elements (node lists) and the clamped nodes of a test structure.
type Structure = (Vec<Vector3<f64>>, Vec<Vec<usize>>, Vec<usize>);

/// A cantilevered L-section (two flanges of width 0.1 folded at 90°) of length 1 and thickness t,
/// in quads or triangles.
fn folded_plate(triangles: bool) -> Structure {
    let section = [[0.1, 0.0], [0.05, 0.0], [0.0, 0.0], [0.0, 0.05], [0.0, 0.1]];
    let stations = 10;
    let mut nodes = Vec::new();
    for i in 0..=stations {
        for [y, z] in section {
            nodes.push(Vector3::new(i as f64 / stations as f64, y, z));
        }
    }
    let m = section.len();
    let mut elements = Vec::new();
    for i in 0..stations {
        for j in 0..m - 1 {
            let (a, b, c, d) = (
                i * m + j,
                (i + 1) * m + j,
                (i + 1) * m + j + 1,
                i * m + j + 1,
            );
            if triangles {
                elements.push(vec![a, b, c]);
                elements.push(vec![a, c, d]);
            } else {
                elements.push(vec![a, b, c, d]);
            }
        }
    }
    (nodes, elements, (0..m).collect())
}

/// A cantilevered cylindrical panel: radius 1, 90° of arc in 8 facets, length 1 in 8, clamped at
/// x = 0.
fn cylindrical_panel(triangles: bool) -> Structure {
    let (around, along) = (8, 8);
    let mut nodes = Vec::new();
    for i in 0..=along {
        for j in 0..=around {
            let phi = std::f64::consts::FRAC_PI_2 * j as f64 / around as f64;
            nodes.push(Vector3::new(i as f64 / along as f64, phi.cos(), phi.sin()));
        }
    }
    let m = around + 1;
    let mut elements = Vec::new();
    for i in 0..along {
        for j in 0..around {
            let (a, b, c, d) = (
                i * m + j,
                (i + 1) * m + j,
                (i + 1) * m + j + 1,
                i * m + j + 1,
            );
            if triangles {
                elements.push(vec![a, b, c]);
                elements.push(vec![a, c, d]);
            } else {
                elements.push(vec![a, b, c, d]);
            }
        }
    }
    (nodes, elements, (0..m).collect())
}

fn default_options() -> ModelOptions {
    ModelOptions::default()
}

/// A distorted quadrilateral and a triangle in plane coordinates.
const QUAD: [[f64; 2]; 4] = [[0.0, 0.0], [1.1, 0.1], [1.2, 0.9], [-0.1, 0.8]];
const TRIANGLE: [[f64; 2]; 3] = [[0.0, 0.0], [1.0, 0.2], [0.3, 0.9]];

/// The test elements placed at a general orientation in space: the distorted quadrilateral, the
/// triangle, and the quadrilateral warped by ±0.02 out of its plane (warp 0.013).
fn elements_in_space() -> Vec<(&'static str, Vec<Vector3<f64>>)> {
    let (q, origin) = (oblique(), Vector3::new(0.4, -1.2, 0.7));
    let normal = q * Vector3::z();
    let warped: Vec<_> = place(&QUAD, &q, origin)
        .iter()
        .enumerate()
        .map(|(i, p)| p + normal * if i % 2 == 0 { 0.02 } else { -0.02 })
        .collect();
    vec![
        ("quadrilateral", place(&QUAD, &q, origin)),
        ("triangle", place(&TRIANGLE, &q, origin)),
        ("warped quadrilateral", warped),
    ]
}

#[test]
fn elements_in_space_have_exactly_six_rigid_body_modes() {
    for (name, points) in elements_in_space() {
        let k = shell_matrices(&points, &section(0.05), &material(0.3), &default_options())
            .unwrap()
            .stiffness;
        // The drilling spring, α D against membrane stiffnesses ~E t, is the smallest stiffness:
        // about 1e-3 (0.05)² / 12 ≈ 2e-7 of the largest.
        let seventh = assert_rigid_body_modes(&k, &points, 1e-8);
        println!("{name}: seventh eigenvalue {seventh:.2e} of the largest");
        // Without drilling stiffness, each node's drilling rotation adds one zero-energy mode, and
        // nothing else does.
        let free = options(false, 0.0);
        let k = shell_matrices(&points, &section(0.05), &material(0.3), &free)
            .unwrap()
            .stiffness;
        let zeros = relative_eigenvalues(&k)
            .iter()
            .filter(|v| v.abs() < 1e-10)
            .count();
        assert_eq!(zeros, 6 + points.len(), "{name}");
    }
}

#[test]
fn rotating_the_element_rotates_its_stiffness() {
    let q = rotation(Vector3::new(-0.4, 0.9, 0.2), 2.3);
    for (name, points) in elements_in_space() {
        let k =
            shell_matrices(&points, &section(0.05), &material(0.3), &default_options()).unwrap();
        let turned: Vec<_> = points.iter().map(|p| q * p).collect();
        let k_turned =
            shell_matrices(&turned, &section(0.05), &material(0.3), &default_options()).unwrap();
        let t = block_rotation(points.len(), &q);
        let expected = &t * &k.stiffness * t.transpose();
        let error = (&k_turned.stiffness - &expected).amax() / expected.amax();
        assert!(error < 1e-12, "{name}: relative difference {error:e}");
    }
}

/// The patch of MacNeal & Harder ("A proposed standard set of problems to test finite element
/// accuracy", Finite Elements in Analysis and Design 1, 1985): a 0.24 × 0.12 rectangle, 4 boundary
/// nodes (0–3) and 4 interior nodes (4–7), 5 distorted quadrilaterals or 10 triangles.
fn patch(triangles: bool) -> (Vec<[f64; 2]>, Vec<Vec<usize>>) {
    let nodes = vec![
        [0.0, 0.0],
        [0.24, 0.0],
        [0.24, 0.12],
        [0.0, 0.12],
        [0.04, 0.02],
        [0.18, 0.03],
        [0.16, 0.08],
        [0.08, 0.08],
    ];
    let quads = [
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
        [4, 5, 6, 7],
    ];
    let elements = if triangles {
        quads
            .iter()
            .flat_map(|[a, b, c, d]| [vec![*a, *b, *c], vec![*a, *c, *d]])
            .collect()
    } else {
        quads.iter().map(|q| q.to_vec()).collect()
    };
    (nodes, elements)
}

/// Runs a patch test in a plane at a general orientation: the boundary nodes get the exact field
/// (translation and rotation in the patch's plane coordinates, `field(x, y)`), the interior nodes
/// are solved for without loads. Returns the largest errors of the translations and of the
/// rotations at the interior nodes, each relative to the largest translation or rotation of the
/// field there.
fn patch_test(
    triangles: bool,
    thickness: f64,
    alpha: f64,
    field: impl Fn(f64, f64) -> [Vector3<f64>; 2],
) -> [f64; 2] {
    let (q, origin) = (oblique(), Vector3::new(1.0, 0.5, -0.3));
    let (plane, elements) = patch(triangles);
    let nodes = place(&plane, &q, origin);
    let (model, _) = assemble(
        &nodes,
        &elements,
        thickness,
        &material(0.25),
        &options(false, alpha),
    );
    let exact: Vec<DVector<f64>> = plane
        .iter()
        .map(|[x, y]| {
            let [u, r] = field(*x, *y);
            let (u, r) = (q * u, q * r);
            DVector::from_column_slice(&[u.x, u.y, u.z, r.x, r.y, r.z])
        })
        .collect();
    let prescribed: Vec<(usize, f64)> = (0..4)
        .flat_map(|n| (0..6).map(move |d| (6 * n + d, 0.0)))
        .collect();
    let prescribed: Vec<(usize, f64)> = prescribed
        .iter()
        .map(|&(dof, _)| (dof, exact[dof / 6][dof % 6]))
        .collect();
    let u = model.solve(&prescribed, &DVector::zeros(6 * nodes.len()));
    let mut errors = [0.0f64; 2];
    let mut sizes = [0.0f64; 2];
    for (n, exact) in exact.iter().enumerate().skip(4) {
        for part in 0..2 {
            let computed = u.fixed_rows::<3>(6 * n + 3 * part);
            let expected = exact.fixed_rows::<3>(3 * part);
            errors[part] = errors[part].max((computed - expected).amax());
            sizes[part] = sizes[part].max(expected.amax());
        }
    }
    [errors[0] / sizes[0], errors[1] / sizes[1]]
}

// The patch tests are passed to round-off. Round-off grows with the spread of the stiffnesses: the
// drilling stiffness α D against the membrane's E t makes the condition number about 12 A / (α t²),
// so with the default α and a thin patch the (fictitious) drilling rotations carry round-off errors
// of 1e-6 to 1e-5 while the translations stay exact; with α = 1 the rotations are exact too.

#[test]
fn membrane_patch_test() {
    // u, v linear in the patch plane; the drilling rotation is the field's rotation ½(v_x − u_y).
    let field = |x: f64, y: f64| {
        let (u, v) = (1e-3 + 2e-3 * x + 1.5e-3 * y, -5e-4 + 1e-3 * x - 3e-3 * y);
        [
            Vector3::new(u, v, 0.0),
            Vector3::new(0.0, 0.0, 0.5 * (1e-3 - 1.5e-3)),
        ]
    };
    for triangles in [false, true] {
        for (thickness, alpha, rotation_tolerance) in [(0.01, 1.0, 1e-9), (0.001, 1e-3, 1e-4)] {
            let [translation, rotation] = patch_test(triangles, thickness, alpha, field);
            println!(
                "membrane patch, triangles {triangles}, t {thickness}, alpha {alpha}: errors \
                 {translation:.1e} (translations), {rotation:.1e} (rotations)"
            );
            assert!(
                translation < 1e-9,
                "triangles {triangles}, t {thickness}: {translation:e}"
            );
            assert!(
                rotation < rotation_tolerance,
                "triangles {triangles}, t {thickness}: {rotation:e}"
            );
        }
    }
}

#[test]
fn bending_patch_test() {
    // Constant curvature: w = ½(a x² + 2 b x y + c y²) plus a rigid part, with the Kirchhoff
    // rotations θx = ∂w/∂y, θy = −∂w/∂x (no transverse shear).
    let (a, b, c) = (0.02, -0.01, 0.03);
    let field = |x: f64, y: f64| {
        let w = 1e-3 * (1.0 + x + 2.0 * y) + 0.5 * (a * x * x + 2.0 * b * x * y + c * y * y);
        let (w_x, w_y) = (1e-3 + a * x + b * y, 2e-3 + b * x + c * y);
        [Vector3::new(0.0, 0.0, w), Vector3::new(w_y, -w_x, 0.0)]
    };
    for triangles in [false, true] {
        for (thickness, alpha, rotation_tolerance) in
            [(0.01, 1.0, 1e-9), (0.001, 1.0, 1e-8), (0.0001, 1e-3, 1e-3)]
        {
            let [translation, rotation] = patch_test(triangles, thickness, alpha, field);
            println!(
                "bending patch, triangles {triangles}, t {thickness}, alpha {alpha}: errors \
                 {translation:.1e} (translations), {rotation:.1e} (rotations)"
            );
            assert!(
                translation < 1e-8,
                "triangles {triangles}, t {thickness}: {translation:e}"
            );
            assert!(
                rotation < rotation_tolerance,
                "triangles {triangles}, t {thickness}: {rotation:e}"
            );
        }
    }
}

#[test]
fn discrete_kirchhoff_rotations_are_exact_for_quadratic_deflections() {
    // For w quadratic and corner rotations θx = ∂w/∂y, θy = −∂w/∂x, the DKT's β is −∇w exactly.
    let xy: Vec<_> = [[0.1, -0.2], [1.3, 0.1], [0.4, 0.8]]
        .iter()
        .map(|[x, y]| Vector2::new(*x, *y))
        .collect();
    let (a, b, c, d, e) = (0.3, -0.7, 1.1, 0.2, -0.4);
    let gradient = |p: &Vector2<f64>| Vector2::new(d + a * p.x + b * p.y, e + b * p.x + c * p.y);
    let w = |p: &Vector2<f64>| {
        d * p.x + e * p.y + 0.5 * (a * p.x * p.x + 2.0 * b * p.x * p.y + c * p.y * p.y)
    };
    let mut u = nalgebra::SVector::<f64, 9>::zeros();
    for (i, p) in xy.iter().enumerate() {
        let g = gradient(p);
        u[3 * i] = w(p);
        u[3 * i + 1] = g.y;
        u[3 * i + 2] = -g.x;
    }
    let shape = dkt::DktShape::new(&xy);
    for [xi, eta] in [[0.2, 0.3], [0.5, 0.5], [0.0, 0.7], [0.6, 0.1]] {
        let p = xy[0] * (1.0 - xi - eta) + xy[1] * xi + xy[2] * eta;
        let beta = shape.rotations(xi, eta) * u;
        let expected = -gradient(&p);
        assert!(
            (beta - expected).norm() < 1e-13,
            "at ({xi}, {eta}): {beta:?} vs {expected:?}"
        );
        // Constant curvature: κ = [−a, −c, −2b].
        let kappa = shape.curvature(xi, eta) * u;
        assert!((kappa - Vector3::new(-a, -c, -2.0 * b)).norm() < 1e-12);
    }
}

/// A strip of `cells` × 1 cells (length 1, width 0.1) along plane x at a general orientation,
/// clamped at x = 0, with a tip force of 1 along `direction` (plane components) shared by the two
/// tip nodes; returns the mean tip displacement along that direction.
fn cantilever_strip(triangles: bool, cells: usize, thickness: f64, direction: Vector3<f64>) -> f64 {
    let (q, origin) = (oblique(), Vector3::new(-0.5, 0.2, 0.3));
    let plane: Vec<[f64; 2]> = (0..=cells)
        .flat_map(|i| {
            [
                [i as f64 / cells as f64, 0.0],
                [i as f64 / cells as f64, 0.1],
            ]
        })
        .collect();
    let nodes = place(&plane, &q, origin);
    let mut elements = Vec::new();
    for i in 0..cells {
        let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
        if triangles {
            elements.push(vec![a, b, c]);
            elements.push(vec![a, c, d]);
        } else {
            elements.push(vec![a, b, c, d]);
        }
    }
    let (model, _) = assemble(
        &nodes,
        &elements,
        thickness,
        &material(0.0),
        &default_options(),
    );
    let force = q * direction;
    let mut loads = DVector::zeros(6 * nodes.len());
    for tip in [2 * cells, 2 * cells + 1] {
        loads.fixed_rows_mut::<3>(6 * tip).copy_from(&(force * 0.5));
    }
    let clamped: Vec<(usize, f64)> = (0..12).map(|d| (d, 0.0)).collect();
    let u = model.solve(&clamped, &loads);
    let tip = |n: usize| u.fixed_rows::<3>(6 * n).dot(&force);
    0.5 * (tip(2 * cells) + tip(2 * cells + 1))
}

#[test]
fn thin_cantilever_strip_matches_beam_theory() {
    // ν = 0, so the strip bends as a beam: δ = P L³ / (3 E I), I = b t³ / 12, plus the shear
    // deflection P L / (k G b t), 5e-5 of it here (MITC4; the DKT has none).
    let (b, t): (f64, f64) = (0.1, 0.002);
    let youngs = material(0.0).youngs_modulus;
    let bending = 1.0 / (3.0 * youngs * b * t.powi(3) / 12.0);
    let shear = 1.0 / (5.0 / 6.0 * youngs / 2.0 * b * t);
    for (triangles, expected, name) in [(false, bending + shear, "MITC4"), (true, bending, "DKT")] {
        let deflection = cantilever_strip(triangles, 10, t, Vector3::z());
        let error = deflection / expected - 1.0;
        println!("{name} strip, 10 cells, L/t = 500: tip deflection error {error:+.2e}");
        assert!(error.abs() < 0.01, "{name}: relative error {error:e}");
    }
}

#[test]
fn in_plane_cantilever_strip_with_incompatible_modes() {
    // In-plane tip load on 10 square QM6 elements against the Timoshenko beam,
    // δ = P L³ / (3 E I) + P L / (k G A)
    // with I = t b³ / 12, A = b t, k = 5/6 (ν = 0).
    let (b, t): (f64, f64) = (0.1, 0.01);
    let youngs = material(0.0).youngs_modulus;
    let expected =
        1.0 / (3.0 * youngs * t * b.powi(3) / 12.0) + 1.0 / (5.0 / 6.0 * youngs / 2.0 * b * t);
    let deflection = cantilever_strip(false, 10, t, Vector3::y());
    let error = deflection / expected - 1.0;
    println!("QM6 in-plane strip, 10 cells: tip deflection error {error:+.2e}");
    assert!(error.abs() < 0.02, "relative error {error:e}");
}

#[test]
fn default_drilling_stiffness_barely_changes_bending_frequencies() {
    // Folded and curved shells are where drilling rotations of one element are bending rotations of
    // its neighbours; against α → 0 (1e-7), the default α = 1e-3 may change the lowest frequencies
    // by ~α only. (Scaled by G t A instead of D, it changed them by 1e-3 to 2e-3.)
    for (name, build) in [
        ("folded plate", folded_plate as fn(bool) -> Structure),
        (
            "cylindrical panel",
            cylindrical_panel as fn(bool) -> Structure,
        ),
    ] {
        for triangles in [false, true] {
            let (nodes, elements, fixed) = build(triangles);
            let at = |alpha: f64| {
                let (model, mass) = assemble(
                    &nodes,
                    &elements,
                    0.002,
                    &material(0.3),
                    &options(false, alpha),
                );
                frequencies(&model, &mass, &fixed, 6)
            };
            let (reference, default) = (at(1e-7), at(default_options().drilling_stiffness));
            let change = default
                .iter()
                .zip(&reference)
                .map(|(a, b)| (a / b - 1.0).abs())
                .fold(0.0, f64::max);
            println!(
                "{name}, triangles {triangles}: lowest frequencies {reference:.1?}, \
                 change {change:.1e}"
            );
            assert!(
                change < 1e-4,
                "{name}, triangles {triangles}: change {change:e}"
            );
        }
    }
}

#[test]
fn lumped_mass_shares_rho_t_a_equally() {
    let t = 0.05;
    for (name, points) in elements_in_space() {
        let area = if points.len() == 3 {
            0.5 * (points[1] - points[0])
                .cross(&(points[2] - points[0]))
                .norm()
        } else {
            // Of the quadrilateral projected on its mean plane: half the diagonals' cross product.
            0.5 * (points[2] - points[0])
                .cross(&(points[3] - points[1]))
                .norm()
        };
        let n = points.len() as f64;
        let without =
            shell_matrices(&points, &section(t), &material(0.3), &default_options()).unwrap();
        let total: f64 = without.lumped_mass.iter().map(|m| m.mass).sum();
        assert!((total / (RHO * t * area) - 1.0).abs() < 1e-14, "{name}");
        assert!(without
            .lumped_mass
            .iter()
            .all(|m| m.rotary_inertia == Matrix3::zeros()));
        let with =
            shell_matrices(&points, &section(t), &material(0.3), &options(true, 1e-3)).unwrap();
        for m in &with.lumped_mass {
            assert!(
                (m.mass / (RHO * t * area / n) - 1.0).abs() < 1e-14,
                "{name}"
            );
            let expected = Matrix3::identity() * (RHO * t.powi(3) / 12.0 * area / n);
            assert!(
                (m.rotary_inertia - expected).amax() < 1e-14 * expected.amax(),
                "{name}"
            );
        }
    }
}

/// The consistent mass of a rectangle `a × b` is `ρ t a b / 36 · [4 2 1 2; 2 4 2 1; 1 2 4 2; 2 1 2 4]`
/// on each translation (bilinear fields), that of a triangle `ρ t A / 12 · [2 1 1; 1 2 1; 1 1 2]`;
/// rotary inertia follows the same pattern with `ρ t³ / 12`. Checked on elements placed obliquely.
#[test]
fn consistent_mass_of_rectangle_and_triangle() {
    let (t, q, origin) = (0.02, oblique(), Vector3::new(0.4, -0.3, 1.2));
    let rectangle = place(&[[0.0, 0.0], [0.6, 0.0], [0.6, 0.4], [0.0, 0.4]], &q, origin);
    let triangle = place(&[[0.0, 0.0], [0.7, 0.1], [0.2, 0.5]], &q, origin);
    let rectangle_pattern = [[4.0, 2.0, 1.0, 2.0], [2.0, 4.0, 2.0, 1.0], [1.0, 2.0, 4.0, 2.0], [2.0, 1.0, 2.0, 4.0]];
    let triangle_pattern = vec![vec![2.0, 1.0, 1.0], vec![1.0, 2.0, 1.0], vec![1.0, 1.0, 2.0]];
    let cases = [
        (rectangle, 0.24 / 36.0, rectangle_pattern.iter().map(|r| r.to_vec()).collect::<Vec<_>>()),
        (triangle, 0.5 * (0.7 * 0.5 - 0.1 * 0.2) / 12.0, triangle_pattern),
    ];
    for (points, scale, pattern) in &cases {
        let (points, scale) = (points.as_slice(), *scale);
        for rotary in [false, true] {
            let options = ModelOptions { mass: Some(crate::mesh::MassModel::Consistent), ..options(rotary, 1e-3) };
            let m = shell_matrices(points, &section(t), &material(0.3), &options).unwrap();
            let matrix = crate::element::test_support::mass_matrix_of_points(&m.consistent_mass, points.len());
            let n = points.len();
            let mut expected = DMatrix::zeros(6 * n, 6 * n);
            for a in 0..n {
                for b in 0..n {
                    for k in 0..3 {
                        expected[(6 * a + k, 6 * b + k)] = RHO * t * scale * pattern[a][b];
                        if rotary {
                            expected[(6 * a + 3 + k, 6 * b + 3 + k)] = RHO * t.powi(3) / 12.0 * scale * pattern[a][b];
                        }
                    }
                }
            }
            let error = (&matrix - &expected).amax() / expected.amax();
            assert!(error < 1e-13, "{n} nodes, rotary {rotary}: relative error {error:.2e}");
        }
    }
}

#[test]
fn bad_shapes_and_properties_are_reported() {
    let q = oblique();
    let origin = Vector3::new(0.1, 0.2, 0.3);
    let check = |plane: &[[f64; 2]]| {
        shell_matrices(
            &place(plane, &q, origin),
            &section(0.01),
            &material(0.3),
            &default_options(),
        )
    };
    // Collinear triangle, coincident nodes, a non-convex (dart) and a crossed (bow-tie)
    // quadrilateral.
    assert_eq!(
        check(&[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]).unwrap_err(),
        ElementError::DegenerateShape
    );
    assert_eq!(
        check(&[[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]).unwrap_err(),
        ElementError::DegenerateShape
    );
    assert_eq!(
        check(&[[0.0, 0.0], [1.0, 0.0], [0.3, 0.3], [0.0, 1.0]]).unwrap_err(),
        ElementError::DegenerateShape
    );
    assert_eq!(
        check(&[[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]]).unwrap_err(),
        ElementError::DegenerateShape
    );
    // Clockwise order is fine (the normal flips).
    assert!(check(&[[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]).is_ok());
    // Warp: the unit square with nodes at ±h; the mean diagonal is √2.
    let square = place(
        &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        &q,
        origin,
    );
    let warped = |h: f64| -> Vec<Vector3<f64>> {
        square
            .iter()
            .enumerate()
            .map(|(i, p)| p + q * Vector3::z() * if i % 2 == 0 { h } else { -h })
            .collect()
    };
    let run = |points: &[Vector3<f64>]| {
        shell_matrices(points, &section(0.01), &material(0.3), &default_options())
    };
    assert!(run(&warped(0.9 * WARP_TOLERANCE * 2f64.sqrt())).is_ok());
    match run(&warped(1.1 * WARP_TOLERANCE * 2f64.sqrt())) {
        Err(ElementError::Warped { warp }) => {
            assert!((warp / (1.1 * WARP_TOLERANCE) - 1.0).abs() < 1e-12)
        }
        other => panic!("expected a warp error, got {other:?}"),
    }
    // Properties and node count.
    let points = place(&TRIANGLE, &q, origin);
    let bad_thickness = shell_matrices(&points, &section(0.0), &material(0.3), &default_options());
    assert!(matches!(
        bad_thickness,
        Err(ElementError::InvalidProperty { .. })
    ));
    let bad_alpha = shell_matrices(
        &points,
        &section(0.01),
        &material(0.3),
        &options(false, -1.0),
    );
    assert!(matches!(bad_alpha, Err(ElementError::OutOfRange { .. })));
    let bad_modulus = Material {
        youngs_modulus: f64::NAN,
        ..material(0.3)
    };
    assert!(matches!(
        shell_matrices(&points, &section(0.01), &bad_modulus, &default_options()),
        Err(ElementError::InvalidProperty { .. })
    ));
    assert!(matches!(
        shell_matrices(
            &points[..2],
            &section(0.01),
            &material(0.3),
            &default_options()
        ),
        Err(ElementError::NodeCount { found: 2, .. })
    ));
}
