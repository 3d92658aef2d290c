//! Random FE model files that are valid by construction: materials, beam sections of every form,
//! shell sections, beam lines and plates that share their end points and corners, listed nodes and
//! elements, point masses, supports and the static loads of correction modes. They exercise the
//! elements, the assembly, the mode analysis and the reduction of the preprocessor.

use std::fmt::Write;

use nalgebra::Vector3;

use super::mechanism::{num, vector};
use super::rng::Rng;

fn direction(rng: &mut Rng) -> Vector3<f64> {
    if rng.chance(0.5) {
        let mut v = Vector3::zeros();
        v[rng.below(3)] = 1.0;
        v
    } else {
        Vector3::new(rng.normal(), rng.normal(), rng.normal()).normalize()
    }
}

/// A direction that is not within about 10° of `avoid` (nor of its opposite).
fn direction_away_from(rng: &mut Rng, avoid: &Vector3<f64>) -> Vector3<f64> {
    loop {
        let d = direction(rng);
        if d.cross(avoid).norm() > 0.2 * avoid.norm() {
            return d;
        }
    }
}

/// An FE model file.
pub fn fe_model(rng: &mut Rng) -> String {
    let mut t = String::from("# An FE model made by the fuzz harness.\n[fe_model]\nname = \"generated\"\n");
    if rng.chance(0.5) {
        let _ = writeln!(t, "rotary_inertia = {}", rng.chance(0.7));
    }
    if rng.chance(0.3) {
        let _ = writeln!(t, "mass = \"{}\"", rng.pick(&["lumped", "consistent"]));
    }
    if rng.chance(0.2) {
        let _ = writeln!(t, "drilling_stiffness = {}", num(rng.log_range(1e-6, 1.0)));
    }
    let _ = writeln!(t, "\n[parameters]\nL = {}\n", num(rng.log_range(0.1, 3.0)));
    let _ = writeln!(
        t,
        "[[material]]\nname = \"m\"\nE = {}\nnu = {}\nrho = {}\n",
        num(rng.log_range(1e9, 3e11)),
        num(rng.range(0.0, 0.45)),
        num(rng.log_range(500.0, 20000.0))
    );
    let orientations: Vec<Vector3<f64>> = (0..2).map(|_| direction(rng) * rng.range(0.5, 2.0)).collect();
    for (k, o) in orientations.iter().enumerate() {
        beam_section(rng, &mut t, k, o);
    }
    let _ = writeln!(t, "[[shell_section]]\nname = \"sheet\"\nmaterial = \"m\"\nthickness = {}\n", num(rng.log_range(1e-3, 2e-2)));

    // Points parts may start from, so that they connect; single-node sets that loads may act on.
    let mut points: Vec<Vector3<f64>> = vec![Vector3::zeros()];
    let mut ends: Vec<String> = Vec::new();
    let mut sets: Vec<String> = Vec::new();
    for part in 0..rng.between(1, 4) {
        let from = *rng.pick(&points);
        if rng.chance(0.6) {
            let s = rng.below(orientations.len());
            let d = direction_away_from(rng, &orientations[s]) * rng.log_range(0.05, 2.0);
            let to = from + d;
            let _ = writeln!(
                t,
                "[[beam_line]]\nname = \"p{part}\"\nsection = \"s{s}\"\nfrom = {}\nto = {}\nelements = {}\n",
                vector(&from),
                vector(&to),
                rng.between(1, 12)
            );
            points.push(to);
            ends.extend([format!("p{part}.start"), format!("p{part}.end")]);
            sets.push(format!("p{part}"));
        } else {
            // Edges within a factor 4 of each other, elements of about equal sides: slender shells
            // are a conditioning limit of the eigensolver's residual check, not of the input.
            let a = direction(rng) * rng.log_range(0.05, 2.0);
            let b = direction_away_from(rng, &a) * a.norm() * rng.log_range(0.25, 4.0);
            let h = a.norm().min(b.norm()) / rng.between(1, 3) as f64;
            let (na, nb) = ((a.norm() / h).round().clamp(1.0, 8.0), (b.norm() / h).round().clamp(1.0, 8.0));
            let _ = writeln!(
                t,
                "[[plate]]\nname = \"p{part}\"\nsection = \"sheet\"\ncorner = {}\nedge_a = {}\nedge_b = {}\nelements = [{}, {}]",
                vector(&from),
                vector(&a),
                vector(&b),
                na,
                nb
            );
            if rng.chance(0.3) {
                let _ = writeln!(t, "shape = \"triangle\"");
            }
            t.push('\n');
            points.extend([from + a, from + b, from + a + b]);
            sets.extend([format!("p{part}"), format!("p{part}.boundary")]);
        }
    }
    if rng.chance(0.3) {
        listed_elements(rng, &mut t, &points, &orientations);
    }
    let supported: Vec<String> = (0..rng.below(3))
        .map(|_| {
            let at = if rng.chance(0.5) && !ends.is_empty() { rng.pick(&ends).clone() } else { rng.pick(&sets).clone() };
            let dofs = match rng.below(4) {
                0 => "\"all\"".to_string(),
                1 => format!("\"{}\"", rng.pick(&["translations", "rotations"])),
                _ => {
                    let all = ["x", "y", "z", "rx", "ry", "rz"];
                    let some: Vec<String> = all.iter().filter(|_| rng.chance(0.5)).map(|d| format!("\"{d}\"")).collect();
                    format!("[{}]", if some.is_empty() { "\"z\"".to_string() } else { some.join(", ") })
                }
            };
            let _ = writeln!(t, "[[support]]\nat = \"{at}\"\ndofs = {dofs}\n");
            at
        })
        .collect();
    for _ in 0..rng.below(3) {
        let at = if !ends.is_empty() && rng.chance(0.7) { format!("\"{}\"", rng.pick(&ends)) } else { vector(rng.pick(&points)) };
        let mass = rng.log_range(0.01, 10.0);
        let _ = writeln!(t, "[[mass]]\nat = {at}\nmass = {}", num(mass));
        if rng.chance(0.3) {
            let j = mass * 1e-3;
            let _ = writeln!(t, "rotary_inertia = [{}, {}, {}]", num(rng.range(0.0, j)), num(rng.range(0.0, j)), num(rng.range(0.0, j)));
        }
        t.push('\n');
    }
    // Loads act where no support of the same part holds (a node shared with another part may still be
    // held: a clean error).
    let part_of = |set: &str| set.split('.').next().unwrap_or_default().to_string();
    let free_ends: Vec<&String> =
        ends.iter().filter(|e| !supported.iter().any(|s| s == *e || (!s.ends_with(".start") && !s.ends_with(".end") && part_of(s) == part_of(e)))).collect();
    let mut loads = 0;
    for k in 0..rng.below(3) {
        if free_ends.is_empty() {
            break;
        }
        let kind = rng.pick(&["force", "torque"]);
        let _ = writeln!(t, "[[static_load]]\nname = \"l{k}\"\nat = \"{}\"\n{kind} = {}\n", rng.pick(&free_ends), vector(&direction(rng)));
        loads += 1;
    }
    let statics = rng.between(0, loads);
    let vibration = rng.between(if statics == 0 { 1 } else { 0 }, 6);
    let set = match (vibration, statics) {
        (n, 0) => format!("{n}N"),
        (0, s) => format!("{s}S"),
        (n, s) => format!("{n}N{s}S"),
    };
    let _ = writeln!(t, "[modes]\nset = \"{set}\"");
    if rng.chance(0.3) {
        let _ = writeln!(t, "basis = \"{}\"", rng.pick(&["raw", "orthonormal"]));
    }
    t
}

fn beam_section(rng: &mut Rng, t: &mut String, k: usize, orientation: &Vector3<f64>) {
    let _ = writeln!(t, "[[beam_section]]\nname = \"s{k}\"\nmaterial = \"m\"\norientation = {}", vector(orientation));
    let size = rng.log_range(2e-3, 5e-2);
    match rng.below(4) {
        0 => {
            let _ = writeln!(t, "shape = \"rectangle\"\nwidth = {}\nheight = {}", num(size), num(size * rng.range(0.2, 5.0)));
        }
        1 => {
            let _ = writeln!(t, "shape = \"circle\"\nradius = {}", num(size));
        }
        2 => {
            let _ = writeln!(t, "shape = \"tube\"\nradius = {}\nthickness = {}", num(size), num(size * rng.range(0.05, 1.0)));
        }
        _ => {
            let (a, iy, iz) = (size * size, size.powi(4) / 12.0, size.powi(4) / 12.0 * rng.range(0.2, 5.0));
            let _ = writeln!(t, "A = {}\nIy = {}\nIz = {}\nJ = {}", num(a), num(iy), num(iz), num((iy + iz) * 0.5));
        }
    }
    if rng.chance(0.3) {
        let _ = writeln!(t, "shear_coefficient = {}", num(rng.range(0.5, 1.0)));
    }
    t.push('\n');
}

/// A few `[[node]]`s and the `[[beam]]`s and `[[shell]]` between them, hung from a point of the parts.
fn listed_elements(rng: &mut Rng, t: &mut String, points: &[Vector3<f64>], orientations: &[Vector3<f64>]) {
    let start = *rng.pick(points);
    let s = rng.below(orientations.len());
    let a = direction_away_from(rng, &orientations[s]) * rng.log_range(0.05, 1.0);
    let b = direction_away_from(rng, &a).cross(&a).normalize() * a.norm();
    let corners = [start, start + a, start + a + b, start + b];
    for (k, p) in corners.iter().enumerate() {
        let _ = writeln!(t, "[[node]]\nlabel = {}\nposition = {}\n", 1000 + k, vector(p));
    }
    let _ = writeln!(t, "[[beam]]\nsection = \"s{s}\"\nnodes = [[1000, 1001]]\n");
    let shell = if rng.chance(0.5) { "[1000, 1001, 1002, 1003]" } else { "[1000, 1001, 1002], [1000, 1002, 1003]" };
    let _ = writeln!(t, "[[shell]]\nsection = \"sheet\"\nnodes = [{shell}]\n");
}
