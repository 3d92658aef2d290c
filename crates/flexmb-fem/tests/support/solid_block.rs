//! `.inp` decks of a rectangular block `lx × ly × lz` (from the origin) meshed with `nx × ny × nz`
//! cells of one solid element type: bricks (C3D8, C3D8I, C3D20, C3D20R), each cell split into two
//! wedges along z (C3D6, C3D15) or into six tetrahedra around its diagonal (C3D4, C3D10). Nodes sit
//! on a lattice of twice the cells (mid-edge nodes between corners); only the nodes the elements use
//! are written. Node set `ROOT`: the nodes on x = 0; `TIP`: those on x = lx.
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::fmt::Write as _;

/// A block and its mesh.
#[derive(Clone, Debug)]
pub struct SolidBlock {
    pub element: &'static str,
    pub lx: f64,
    pub ly: f64,
    pub lz: f64,
    pub nx: usize,
    pub ny: usize,
    pub nz: usize,
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    pub density: f64,
    /// Clamp (`*BOUNDARY ROOT, 1, 3`) the face x = 0; free-free otherwise.
    pub clamped: bool,
    /// Modes asked of ccx (`*FREQUENCY`).
    pub modes: usize,
}

impl SolidBlock {
    /// A steel cantilever 1 m × 0.1 m × 0.1 m of `element`, `nx × 2 × 2` cells, 10 modes.
    pub fn cantilever(element: &'static str, nx: usize) -> SolidBlock {
        SolidBlock {
            element,
            lx: 1.0,
            ly: 0.1,
            lz: 0.1,
            nx,
            ny: 2,
            nz: 2,
            youngs_modulus: 210e9,
            poisson_ratio: 0.3,
            density: 7850.0,
            clamped: true,
            modes: 10,
        }
    }

    /// The elements as lattice points (`[i, j, k]` on the lattice of twice the cells), in the
    /// Abaqus node order of the element type.
    pub fn elements(&self) -> Vec<Vec<[usize; 3]>> {
        let corner = |c: [usize; 3], d: [usize; 3]| [2 * c[0] + 2 * d[0], 2 * c[1] + 2 * d[1], 2 * c[2] + 2 * d[2]];
        let mid = |a: [usize; 3], b: [usize; 3]| [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2];
        let mut elements = Vec::new();
        for k in 0..self.nz {
            for j in 0..self.ny {
                for i in 0..self.nx {
                    let c = [i, j, k];
                    let brick: Vec<[usize; 3]> = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]]
                        .into_iter()
                        .map(|d| corner(c, d))
                        .collect();
                    match self.element {
                        "C3D8" | "C3D8I" => elements.push(brick),
                        "C3D20" | "C3D20R" => {
                            let mut nodes = brick.clone();
                            for (a, b) in [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)] {
                                nodes.push(mid(brick[a], brick[b]));
                            }
                            elements.push(nodes);
                        }
                        "C3D6" | "C3D15" => {
                            for triangle in [[0, 1, 2], [0, 2, 3]] {
                                let mut nodes: Vec<[usize; 3]> = triangle.iter().map(|&t| brick[t]).collect();
                                nodes.extend(triangle.iter().map(|&t| brick[t + 4]));
                                if self.element == "C3D15" {
                                    let corners = nodes.clone();
                                    for (a, b) in [(0, 1), (1, 2), (2, 0), (3, 4), (4, 5), (5, 3), (0, 3), (1, 4), (2, 5)] {
                                        nodes.push(mid(corners[a], corners[b]));
                                    }
                                }
                                elements.push(nodes);
                            }
                        }
                        "C3D4" | "C3D10" => {
                            for axes in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
                                let mut d = [0, 0, 0];
                                let mut corners = vec![corner(c, d)];
                                for axis in axes {
                                    d[axis] = 1;
                                    corners.push(corner(c, d));
                                }
                                if orientation(&corners) < 0 {
                                    corners.swap(1, 2);
                                }
                                let mut nodes = corners.clone();
                                if self.element == "C3D10" {
                                    for (a, b) in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)] {
                                        nodes.push(mid(corners[a], corners[b]));
                                    }
                                }
                                elements.push(nodes);
                            }
                        }
                        other => panic!("no mesh of {other}"),
                    }
                }
            }
        }
        elements
    }

    /// The `.inp` deck, with a `*FREQUENCY` step of `modes` modes.
    pub fn deck(&self) -> String {
        let step = format!("*STEP\n*FREQUENCY\n{}\n*END STEP\n", self.modes);
        self.deck_with_step(&step)
    }

    /// The `.inp` deck with a `*STATIC` step: a force `force_per_node` along y at every node of
    /// `TIP`, and the displacements of `TIP` printed.
    pub fn static_deck(&self, force_per_node: f64) -> String {
        let step = format!("*STEP\n*STATIC\n*CLOAD\nTIP, 2, {force_per_node}\n*NODE PRINT, NSET=TIP\nU\n*END STEP\n");
        self.deck_with_step(&step)
    }

    /// The deck of [`deck`](Self::deck) with `extra` cards (elements, sections) before the step.
    pub fn deck_with(&self, extra: &str) -> String {
        let deck = self.deck();
        let at = deck.find("*STEP").unwrap();
        format!("{}{extra}{}", &deck[..at], &deck[at..])
    }

    /// The labels of the corner nodes of the top face z = lz as a grid `[i][j]` (i along x), for
    /// meshes of corner nodes only.
    pub fn top_face_labels(&self) -> Vec<Vec<usize>> {
        let labels = self.labels();
        (0..=self.nx).map(|i| (0..=self.ny).map(|j| labels[&[2 * i, 2 * j, 2 * self.nz]]).collect()).collect()
    }

    /// The label of every lattice point the elements use, numbered in order of first use.
    fn labels(&self) -> BTreeMap<[usize; 3], usize> {
        let mut labels: BTreeMap<[usize; 3], usize> = BTreeMap::new();
        for nodes in &self.elements() {
            for p in nodes {
                let next = labels.len() + 1;
                labels.entry(*p).or_insert(next);
            }
        }
        labels
    }

    fn deck_with_step(&self, step: &str) -> String {
        let elements = self.elements();
        let labels = self.labels();
        let position = |p: &[usize; 3]| {
            [
                self.lx * p[0] as f64 / (2 * self.nx) as f64,
                self.ly * p[1] as f64 / (2 * self.ny) as f64,
                self.lz * p[2] as f64 / (2 * self.nz) as f64,
            ]
        };
        let mut s = format!("** flexmb test deck: block of {} elements\n*NODE\n", self.element);
        let mut by_label: Vec<(&usize, &[usize; 3])> = labels.iter().map(|(p, l)| (l, p)).collect();
        by_label.sort();
        for (label, p) in &by_label {
            let [x, y, z] = position(p);
            // Shortest round-trip decimals: ccx reads at most 20 characters of a number.
            let _ = writeln!(s, "{label}, {x}, {y}, {z}");
        }
        let _ = writeln!(s, "*ELEMENT, TYPE={}, ELSET=BLOCK", self.element);
        for (e, nodes) in elements.iter().enumerate() {
            let list: Vec<String> = nodes.iter().map(|p| labels[p].to_string()).collect();
            // At most 16 entries per line; a trailing comma continues the line.
            let mut line = format!("{}", e + 1);
            for (k, l) in list.iter().enumerate() {
                line += ", ";
                line += l;
                if k == 14 && list.len() > 15 {
                    line += ",\n";
                    line += &list[15..].join(", ");
                    break;
                }
            }
            let _ = writeln!(s, "{line}");
        }
        for (name, at) in [("ROOT", 0), ("TIP", 2 * self.nx)] {
            let _ = writeln!(s, "*NSET, NSET={name}");
            for (label, p) in &by_label {
                if p[0] == at {
                    let _ = writeln!(s, "{label},");
                }
            }
        }
        let _ = writeln!(
            s,
            "*MATERIAL, NAME=STEEL\n*ELASTIC\n{:e}, {}\n*DENSITY\n{}\n*SOLID SECTION, ELSET=BLOCK, MATERIAL=STEEL",
            self.youngs_modulus, self.poisson_ratio, self.density
        );
        if self.clamped {
            s += "*BOUNDARY\nROOT, 1, 3\n";
        }
        s += step;
        s
    }
}

/// The sign of the volume of the tetrahedron of lattice points `c` (1-2-3 counter-clockwise seen
/// from 4 is positive).
fn orientation(c: &[[usize; 3]]) -> i64 {
    let v = |a: usize| [0, 1, 2].map(|k| c[a][k] as i64 - c[0][k] as i64);
    let (a, b, d) = (v(1), v(2), v(3));
    let cross = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    cross[0] * d[0] + cross[1] * d[1] + cross[2] * d[2]
}
