//! Generators of regular meshes: straight lines of beams and rectangular plates of shells, added to a
//! [`Mesh`] one after another.
//!
//! Generated nodes that coincide with nodes already in the mesh are reused rather than duplicated,
//! so a beam line that ends on a plate edge, or two plates sharing an edge, are connected. "Coincide"
//! means closer than a tolerance relative to the size of the model: `1e-9 × max(size of the new
//! line or plate, size of the mesh before the call)` (see [`REUSE_TOLERANCE`]). The nearest existing
//! node within the tolerance is taken. The search uses a hash grid with cells of the tolerance's size,
//! built once per generator call, so a plate of 10⁴ nodes generated into a mesh of 10⁴ nodes costs
//! O(n) rather than O(n²).
//!
//! New nodes get labels `max_node_label() + 1, + 2, …`, new elements `max_element_label() + 1, …`.

use std::collections::HashMap;

use nalgebra::Vector3;

use super::{Element, ElementKind, Mesh, Node};
use crate::error::FemError;

/// The element shape of a generated plate.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShellShape {
    /// 4-node quadrilaterals.
    #[default]
    Quadrilateral,
    /// 3-node triangles, two per grid cell, the diagonal alternating from cell to cell in a
    /// checkerboard (so the mesh has no preferred direction).
    Triangle,
}

/// The relative tolerance of node reuse by the generators: new nodes closer than
/// `REUSE_TOLERANCE × max(size of the new part, size of the mesh)` to an existing node are merged
/// with it.
pub const REUSE_TOLERANCE: f64 = 1e-9;

impl Mesh {
    /// The index of the node nearest to `position` if it is within `tolerance` (m) of it; otherwise a
    /// new node at `position`, labelled `max_node_label() + 1`.
    ///
    /// One call scans the nodes once (O(n)); the generators below use a hash grid instead, for many
    /// points at a time.
    pub fn find_or_add_node(&mut self, position: Vector3<f64>, tolerance: f64) -> usize {
        match self.nearest_node(&position) {
            Some((index, distance)) if distance <= tolerance => index,
            _ => {
                let label = self.max_node_label() + 1;
                self.add_node(label, position)
            }
        }
    }

    /// Adds `elements` equal 2-node beam elements (section `section`, an index into
    /// [`beam_sections`](Self::beam_sections)) along the straight line from `a` to `b`, and returns the
    /// `elements + 1` node indices along the line, from `a` to `b`.
    ///
    /// Nodes closer than `1e-9 × max(|b − a|, mesh size)` to existing nodes are reused (the nearest
    /// one), so a line can start or end on nodes of earlier lines and plates. A zero-length line gives
    /// degenerate elements that the element matrices reject.
    ///
    /// # Errors
    /// [`FemError::Generator`] if `elements` is 0; the mesh is then unchanged. (A section index is
    /// checked when the model is assembled, so sections may be added after the geometry.)
    pub fn add_beam_line(
        &mut self,
        a: Vector3<f64>,
        b: Vector3<f64>,
        elements: usize,
        section: usize,
    ) -> Result<Vec<usize>, FemError> {
        if elements == 0 {
            return Err(FemError::Generator { generator: "beam line", problem: "a line needs at least one element" });
        }
        let tolerance = REUSE_TOLERANCE * (b - a).norm().max(self.size());
        let mut locator = NodeLocator::new(self, tolerance);
        let nodes: Vec<usize> = (0..=elements)
            .map(|i| {
                let s = i as f64 / elements as f64;
                locator.find_or_add(self, a + (b - a) * s)
            })
            .collect();
        let first_label = self.max_element_label() + 1;
        for (label, pair) in (first_label..).zip(nodes.windows(2)) {
            self.elements.push(Element {
                label,
                kind: ElementKind::Beam { section },
                nodes: vec![pair[0], pair[1]],
            });
        }
        Ok(nodes)
    }

    /// Adds a flat rectangular (parallelogram) plate of shell elements (section `section`, an index
    /// into [`shell_sections`](Self::shell_sections)) and returns its grid of node indices:
    /// `grid[i][j]` is the node at `corner + i/na · edge_a + j/nb · edge_b`, `i` in `0..=na`, `j` in
    /// `0..=nb`.
    ///
    /// Each of the `na × nb` cells is one quadrilateral or two triangles (`shape`); their nodes go
    /// counter-clockwise about `edge_a × edge_b`, which is the shell normal. Triangles split the cells
    /// along alternating diagonals (checkerboard): cells with `i + j` even along
    /// `grid[i][j]–grid[i+1][j+1]`, the others along `grid[i+1][j]–grid[i][j+1]`.
    ///
    /// Nodes closer than `1e-9 × max(|edge_a| + |edge_b|, mesh size)` to existing nodes are reused (the
    /// nearest one), so plates and beam lines generated one after another connect.
    ///
    /// # Errors
    /// [`FemError::Generator`] if `na` or `nb` is 0; the mesh is then unchanged.
    #[allow(clippy::too_many_arguments)]
    pub fn add_rectangular_plate(
        &mut self,
        corner: Vector3<f64>,
        edge_a: Vector3<f64>,
        edge_b: Vector3<f64>,
        na: usize,
        nb: usize,
        section: usize,
        shape: ShellShape,
    ) -> Result<Vec<Vec<usize>>, FemError> {
        if na == 0 || nb == 0 {
            return Err(FemError::Generator { generator: "plate", problem: "a plate needs at least one cell each way" });
        }
        let tolerance = REUSE_TOLERANCE * (edge_a.norm() + edge_b.norm()).max(self.size());
        let mut locator = NodeLocator::new(self, tolerance);
        let grid: Vec<Vec<usize>> = (0..=na)
            .map(|i| {
                (0..=nb)
                    .map(|j| {
                        let p = corner
                            + edge_a * (i as f64 / na as f64)
                            + edge_b * (j as f64 / nb as f64);
                        locator.find_or_add(self, p)
                    })
                    .collect()
            })
            .collect();
        let mut label = self.max_element_label();
        let kind = ElementKind::Shell { section };
        let mut push = |mesh: &mut Mesh, nodes: Vec<usize>| {
            label += 1;
            mesh.elements.push(Element { label, kind, nodes });
        };
        for i in 0..na {
            for j in 0..nb {
                let (n00, n10, n11, n01) = (
                    grid[i][j],
                    grid[i + 1][j],
                    grid[i + 1][j + 1],
                    grid[i][j + 1],
                );
                match shape {
                    ShellShape::Quadrilateral => push(self, vec![n00, n10, n11, n01]),
                    ShellShape::Triangle if (i + j) % 2 == 0 => {
                        push(self, vec![n00, n10, n11]);
                        push(self, vec![n00, n11, n01]);
                    }
                    ShellShape::Triangle => {
                        push(self, vec![n00, n10, n01]);
                        push(self, vec![n10, n11, n01]);
                    }
                }
            }
        }
        Ok(grid)
    }
}

/// Finds nodes near a point with a hash grid of cubic cells whose edge is the tolerance (or larger),
/// so that all nodes within the tolerance lie in the 27 cells around the point's cell.
struct NodeLocator {
    tolerance: f64,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
    next_label: u64,
}

impl NodeLocator {
    fn new(mesh: &Mesh, tolerance: f64) -> Self {
        let tolerance = if tolerance.is_finite() {
            tolerance.max(0.0)
        } else {
            0.0
        };
        // Any cell edge ≥ tolerance is correct; a zero tolerance (exact coincidence) still needs a
        // positive edge, and one far below the coordinates' resolution only makes cell keys saturate.
        let cell = if tolerance > 0.0 { tolerance } else { 1.0 };
        let mut locator = NodeLocator {
            tolerance,
            cell,
            cells: HashMap::new(),
            next_label: mesh.max_node_label() + 1,
        };
        for (index, node) in mesh.nodes.iter().enumerate() {
            locator.insert(index, &node.position);
        }
        locator
    }

    fn key(&self, p: &Vector3<f64>) -> [i64; 3] {
        // `as` saturates (and maps NaN to 0): far-away or non-finite points share edge cells, which is
        // slower but still correct since candidates are checked by distance.
        [
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
            (p.z / self.cell).floor() as i64,
        ]
    }

    fn insert(&mut self, index: usize, p: &Vector3<f64>) {
        let key = self.key(p);
        self.cells.entry(key).or_default().push(index);
    }

    /// The nearest node within the tolerance (lowest index on ties), else a new node.
    fn find_or_add(&mut self, mesh: &mut Mesh, p: Vector3<f64>) -> usize {
        let [kx, ky, kz] = self.key(&p);
        let mut best: Option<(usize, f64)> = None;
        for dx in -1..=1_i64 {
            for dy in -1..=1_i64 {
                for dz in -1..=1_i64 {
                    let key = [
                        kx.saturating_add(dx),
                        ky.saturating_add(dy),
                        kz.saturating_add(dz),
                    ];
                    let Some(candidates) = self.cells.get(&key) else {
                        continue;
                    };
                    for &index in candidates {
                        let distance = (mesh.nodes[index].position - p).norm();
                        let better = match best {
                            None => true,
                            Some((b, d)) => distance < d || (distance == d && index < b),
                        };
                        if distance <= self.tolerance && better {
                            best = Some((index, distance));
                        }
                    }
                }
            }
        }
        if let Some((index, _)) = best {
            return index;
        }
        let label = self.next_label;
        self.next_label += 1;
        mesh.nodes.push(Node { label, position: p });
        let index = mesh.nodes.len() - 1;
        self.insert(index, &p);
        index
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

    fn v(x: f64, y: f64, z: f64) -> Vector3<f64> {
        Vector3::new(x, y, z)
    }

    #[test]
    fn beam_line_counts_positions_and_labels() {
        let mut mesh = Mesh::default();
        let nodes = mesh.add_beam_line(v(0.0, 0.0, 0.0), v(2.0, 0.0, 0.0), 4, 0).unwrap();
        assert_eq!(nodes, vec![0, 1, 2, 3, 4]);
        assert_eq!(mesh.nodes.len(), 5);
        assert_eq!(mesh.elements.len(), 4);
        for (k, &n) in nodes.iter().enumerate() {
            assert!((mesh.nodes[n].position - v(0.5 * k as f64, 0.0, 0.0)).norm() < 1e-15);
            assert_eq!(mesh.nodes[n].label, k as u64 + 1);
        }
        for (k, e) in mesh.elements.iter().enumerate() {
            assert_eq!(e.label, k as u64 + 1);
            assert_eq!(e.kind, ElementKind::Beam { section: 0 });
            assert_eq!(e.nodes, vec![nodes[k], nodes[k + 1]]);
        }
        // A second line continuing from the end reuses the end node; labels continue.
        let more = mesh.add_beam_line(v(2.0, 0.0, 0.0), v(2.0, 1.0, 0.0), 2, 1).unwrap();
        assert_eq!(more[0], nodes[4]);
        assert_eq!(mesh.nodes.len(), 7);
        assert_eq!(mesh.nodes[more[2]].label, 7);
        assert_eq!(mesh.elements.last().unwrap().label, 6);
        assert_eq!(
            mesh.elements.last().unwrap().kind,
            ElementKind::Beam { section: 1 }
        );
    }

    #[test]
    fn plate_grid_counts_and_positions() {
        let mut mesh = Mesh::default();
        let corner = v(1.0, 2.0, 3.0);
        let (ea, eb) = (v(2.0, 0.0, 0.0), v(0.0, 1.0, 0.5));
        let grid = mesh.add_rectangular_plate(corner, ea, eb, 4, 3, 0, ShellShape::Quadrilateral).unwrap();
        assert_eq!(grid.len(), 5);
        assert!(grid.iter().all(|row| row.len() == 4));
        assert_eq!(mesh.nodes.len(), 20);
        assert_eq!(mesh.elements.len(), 12);
        for (i, row) in grid.iter().enumerate() {
            for (j, &n) in row.iter().enumerate() {
                let expected = corner + ea * (i as f64 / 4.0) + eb * (j as f64 / 3.0);
                assert!((mesh.nodes[n].position - expected).norm() < 1e-14);
            }
        }
        let mut tri = Mesh::default();
        let grid = tri.add_rectangular_plate(corner, ea, eb, 4, 3, 2, ShellShape::Triangle).unwrap();
        assert_eq!(tri.nodes.len(), 20);
        assert_eq!(tri.elements.len(), 24);
        assert!(tri
            .elements
            .iter()
            .all(|e| e.nodes.len() == 3 && e.kind == ElementKind::Shell { section: 2 }));
        // Checkerboard: cell (0,0) is split along grid[0][0]–grid[1][1], cell (1,0) along the other diagonal.
        assert_eq!(
            tri.elements[0].nodes,
            vec![grid[0][0], grid[1][0], grid[1][1]]
        );
        assert_eq!(
            tri.elements[2 * 3].nodes,
            vec![grid[1][0], grid[2][0], grid[1][1]]
        );
    }

    /// The normal of a polygon (Newell's method), counter-clockwise nodes giving a positive normal.
    fn polygon_normal(mesh: &Mesh, nodes: &[usize]) -> Vector3<f64> {
        let mut n = Vector3::zeros();
        for k in 0..nodes.len() {
            let p = mesh.nodes[nodes[k]].position;
            let q = mesh.nodes[nodes[(k + 1) % nodes.len()]].position;
            n += p.cross(&q);
        }
        n / 2.0
    }

    #[test]
    fn elements_are_counter_clockwise_about_edge_a_cross_edge_b() {
        let (ea, eb) = (v(0.0, 1.0, 1.0), v(-2.0, 0.0, 0.0));
        let normal = ea.cross(&eb).normalize();
        for shape in [ShellShape::Quadrilateral, ShellShape::Triangle] {
            let mut mesh = Mesh::default();
            mesh.add_rectangular_plate(v(0.3, 0.0, -1.0), ea, eb, 3, 2, 0, shape).unwrap();
            let total_area: f64 = mesh
                .elements
                .iter()
                .map(|e| polygon_normal(&mesh, &e.nodes).dot(&normal))
                .sum();
            for e in &mesh.elements {
                let n = polygon_normal(&mesh, &e.nodes);
                assert!(
                    n.normalize().dot(&normal) > 1.0 - 1e-12,
                    "{shape:?} element {} is reversed",
                    e.label
                );
            }
            assert!((total_area - ea.cross(&eb).norm()).abs() < 1e-12);
        }
    }

    #[test]
    fn beam_line_attached_to_plate_edge_shares_nodes() {
        let mut mesh = Mesh::default();
        let grid = mesh.add_rectangular_plate(
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            4,
            4,
            0,
            ShellShape::Quadrilateral,
        ).unwrap();
        let before = mesh.nodes.len();
        // A stiffener along the edge j = 4, with 2 elements: its 3 nodes are plate nodes 0, 2, 4 of that edge.
        let line = mesh.add_beam_line(v(0.0, 1.0, 0.0), v(1.0, 1.0, 0.0), 2, 0).unwrap();
        assert_eq!(line, vec![grid[0][4], grid[2][4], grid[4][4]]);
        assert_eq!(mesh.nodes.len(), before);
        // A post standing on the plate's centre shares one node and adds the others.
        let post = mesh.add_beam_line(v(0.5, 0.5, 0.0), v(0.5, 0.5, 1.0), 5, 0).unwrap();
        assert_eq!(post[0], grid[2][2]);
        assert_eq!(mesh.nodes.len(), before + 5);
        // A second plate sharing the edge i = 4 of the first one.
        let second = mesh.add_rectangular_plate(
            v(1.0, 0.0, 0.0),
            v(0.0, 0.0, 1.0),
            v(0.0, 1.0, 0.0),
            2,
            4,
            0,
            ShellShape::Triangle,
        ).unwrap();
        for j in 0..=4 {
            assert_eq!(second[0][j], grid[4][j]);
        }
        assert_eq!(mesh.nodes.len(), before + 5 + 2 * 5);
    }

    #[test]
    fn reuse_tolerance() {
        let mut mesh = Mesh::default();
        let a = mesh.find_or_add_node(v(0.0, 0.0, 0.0), 1e-6);
        let b = mesh.find_or_add_node(v(1.0, 0.0, 0.0), 1e-6);
        assert_eq!((a, b), (0, 1));
        assert_eq!(mesh.nodes[1].label, 2);
        // Within the tolerance: the nearest existing node.
        assert_eq!(mesh.find_or_add_node(v(1.0 + 5e-7, 0.0, 0.0), 1e-6), 1);
        assert_eq!(mesh.find_or_add_node(v(0.4, 0.0, 0.0), 0.7), 0);
        assert_eq!(mesh.find_or_add_node(v(0.6, 0.0, 0.0), 0.7), 1);
        // Outside: a new node labelled after the largest label.
        mesh.nodes[1].label = 40;
        let c = mesh.find_or_add_node(v(1.0 + 2e-6, 0.0, 0.0), 1e-6);
        assert_eq!(c, 2);
        assert_eq!(mesh.nodes[2].label, 41);

        // The generators' tolerance is 1e-9 of the larger of the new part's and the mesh's sizes:
        // a line of length 1 reuses a node 0.5e-9 away but not one 2e-9 away.
        let mut mesh = Mesh::default();
        mesh.add_node(7, v(0.0, 0.0, 0.5e-9));
        mesh.add_node(8, v(1.0, 0.0, 2e-9));
        let line = mesh.add_beam_line(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), 1, 0).unwrap();
        assert_eq!(line[0], 0);
        assert_eq!(line[1], 2);
        assert_eq!(mesh.nodes[2].label, 9);
        // Nearest of several candidates within the tolerance.
        let mut mesh = Mesh::default();
        mesh.add_node(1, v(10.0, 0.0, 0.0));
        mesh.add_node(2, v(0.0, 0.0, 8e-9));
        mesh.add_node(3, v(0.0, 0.0, -3e-9));
        let line = mesh.add_beam_line(v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0), 1, 0).unwrap();
        assert_eq!(line[0], 2);
    }

    #[test]
    fn large_plate_into_large_mesh_is_fast() {
        let mut mesh = Mesh::default();
        mesh.add_rectangular_plate(
            v(0.0, 0.0, 0.0),
            v(1.0, 0.0, 0.0),
            v(0.0, 1.0, 0.0),
            99,
            99,
            0,
            ShellShape::Quadrilateral,
        ).unwrap();
        assert_eq!(mesh.nodes.len(), 10_000);
        let start = Instant::now();
        // A second plate of 10⁴ nodes sharing one edge (100 nodes) with the first.
        let grid = mesh.add_rectangular_plate(
            v(1.0, 0.0, 0.0),
            v(0.0, 0.0, 1.0),
            v(0.0, 1.0, 0.0),
            99,
            99,
            0,
            ShellShape::Triangle,
        ).unwrap();
        let elapsed = start.elapsed();
        assert_eq!(mesh.nodes.len(), 20_000 - 100);
        assert_eq!(grid[0][50], 99 * 100 + 50);
        assert!(elapsed.as_secs_f64() < 0.5, "took {elapsed:?}");
    }
}
