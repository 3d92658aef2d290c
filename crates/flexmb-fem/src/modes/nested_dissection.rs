//! A nested-dissection ordering of a sparse symmetric matrix's graph for its Cholesky factor: the
//! graph is split by a separator into two parts that share no edge, the parts are ordered first
//! (recursively, the same way) and the separator last, so that eliminating one part never fills the
//! other.
//!
//! Where the vertices (the equations) have positions (their nodes'), a set is cut across its longest
//! extent at the median coordinate (coordinate bisection): the vertices below the median form one
//! part, and those at or above it that have a neighbour below form the separator — on a structured
//! mesh, one plane of nodes, the shortest cut there is. Without positions, or where that leaves a
//! part empty, the separator is a level of a breadth-first search from a pseudo-peripheral vertex
//! (the level that halves the vertices; a level's neighbours lie only in the levels next to it), as
//! in George and Liu, *Computer Solution of Large Sparse Positive Definite Systems*, 1981, ch. 8.
//! On a square patch of a grid whose elements couple diagonal neighbours, those levels are L-shaped
//! (distance from a corner counts diagonal steps as one): √2 times longer than a straight cut. On the
//! 220,515-dof solid of the `solid-reduction` benchmark the coordinate cuts give a factor of
//! 108.1 million nonzeros against 159.0 million with the levels (docs/preprocessor.md, "Cost").

use faer::sparse::SparseColMat;
use nalgebra::Vector3;

/// Parts this small are ordered as they are.
const LEAF: usize = 96;

/// The elimination order (`order[k]` is the vertex eliminated `k`-th) and its inverse.
/// `positions` (one per vertex), where given, are where the vertices are (coordinate bisection).
pub fn nested_dissection(a: &SparseColMat<usize, f64>, positions: Option<&[Vector3<f64>]>) -> (Vec<usize>, Vec<usize>) {
    let n = a.ncols();
    let positions = positions.filter(|p| p.len() == n && p.iter().all(|x| x.iter().all(|c| c.is_finite())));
    let mut graph = Graph { col_ptr: a.col_ptr(), row_idx: a.row_idx(), positions, mark: vec![0; n], level: vec![0; n], next_mark: 1, queue: Vec::new() };
    let mut order = Vec::with_capacity(n);
    let mut stack = vec![Task::Dissect((0..n).collect())];
    while let Some(task) = stack.pop() {
        match task {
            Task::Append(vertices) => order.extend(vertices),
            Task::Dissect(vertices) if vertices.len() <= LEAF => order.extend(vertices),
            Task::Dissect(vertices) => match graph.split(&vertices) {
                Split::Components(reached, rest) => {
                    stack.push(Task::Dissect(rest));
                    stack.push(Task::Dissect(reached));
                }
                Split::Separated(first, second, separator) => {
                    stack.push(Task::Append(separator));
                    stack.push(Task::Dissect(second));
                    stack.push(Task::Dissect(first));
                }
                Split::None => order.extend(vertices),
            },
        }
    }
    let mut inverse = vec![0; n];
    for (k, &v) in order.iter().enumerate() {
        inverse[v] = k;
    }
    (order, inverse)
}

enum Task {
    Dissect(Vec<usize>),
    Append(Vec<usize>),
}

enum Split {
    /// The vertices reached from the first one and the others (not connected to them).
    Components(Vec<usize>, Vec<usize>),
    /// Two parts and the separator between them.
    Separated(Vec<usize>, Vec<usize>, Vec<usize>),
    /// Too few levels to split.
    None,
}

struct Graph<'a> {
    col_ptr: &'a [usize],
    row_idx: &'a [usize],
    positions: Option<&'a [Vector3<f64>]>,
    /// The set a vertex is in (a vertex is in the current set when its mark is the set's).
    mark: Vec<usize>,
    level: Vec<usize>,
    next_mark: usize,
    queue: Vec<usize>,
}

impl Graph<'_> {
    fn split(&mut self, vertices: &[usize]) -> Split {
        if let Some(split) = self.positions.and_then(|positions| self.bisect(positions, vertices)) {
            return split;
        }
        let set = self.next_mark;
        self.next_mark += 3;
        for &v in vertices {
            self.mark[v] = set;
        }
        // A pseudo-peripheral start: the last vertex reached from the first, then from that one.
        let far = *self.search(vertices[0], set).last().expect("the start is reached");
        self.search(far, set + 1);
        // The second search relabelled its vertices `set + 1`; the rest are another component.
        let reached = self.queue.clone();
        if reached.len() < vertices.len() {
            let rest = vertices.iter().copied().filter(|&v| self.mark[v] == set).collect();
            return Split::Components(reached, rest);
        }
        let levels = self.level[*reached.last().expect("the start is reached")] + 1;
        if levels < 3 {
            return Split::None;
        }
        let mut counts = vec![0usize; levels];
        for &v in &reached {
            counts[self.level[v]] += 1;
        }
        let (mut middle, mut below) = (0, 0);
        while below + counts[middle] < reached.len() / 2 {
            below += counts[middle];
            middle += 1;
        }
        middle = middle.clamp(1, levels - 2);
        let part = |pick: &dyn Fn(usize) -> bool| reached.iter().copied().filter(|&v| pick(self.level[v])).collect::<Vec<usize>>();
        Split::Separated(part(&|l| l < middle), part(&|l| l > middle), part(&|l| l == middle))
    }

    /// Coordinate bisection of `vertices` across their longest extent at the median coordinate:
    /// the vertices below it, those at or above it with no neighbour below, and the separator,
    /// those at or above it with one. `None` if a part is empty.
    fn bisect(&mut self, positions: &[Vector3<f64>], vertices: &[usize]) -> Option<Split> {
        let (mut low, mut high) = (positions[vertices[0]], positions[vertices[0]]);
        for &v in vertices {
            low = low.inf(&positions[v]);
            high = high.sup(&positions[v]);
        }
        let axis = (high - low).imax();
        let mut coordinates: Vec<f64> = vertices.iter().map(|&v| positions[v][axis]).collect();
        let half = coordinates.len() / 2;
        let median = *coordinates.select_nth_unstable_by(half, f64::total_cmp).1;
        let below = self.next_mark;
        self.next_mark += 3;
        for &v in vertices {
            self.mark[v] = if positions[v][axis] < median { below } else { below + 1 };
        }
        let (mut first, mut second, mut separator) = (Vec::new(), Vec::new(), Vec::new());
        for &v in vertices {
            if self.mark[v] == below {
                first.push(v);
            } else if self.row_idx[self.col_ptr[v]..self.col_ptr[v + 1]].iter().any(|&w| self.mark[w] == below) {
                separator.push(v);
            } else {
                second.push(v);
            }
        }
        (!first.is_empty() && !second.is_empty()).then_some(Split::Separated(first, second, separator))
    }

    /// Breadth-first search from `start` over the vertices marked `set`, which it marks `set + 1`;
    /// leaves the vertices reached in `queue`, in order, and their levels in `level`.
    fn search(&mut self, start: usize, set: usize) -> &[usize] {
        self.queue.clear();
        self.queue.push(start);
        self.mark[start] = set + 1;
        self.level[start] = 0;
        let mut head = 0;
        while head < self.queue.len() {
            let v = self.queue[head];
            head += 1;
            for &w in &self.row_idx[self.col_ptr[v]..self.col_ptr[v + 1]] {
                if self.mark[w] == set {
                    self.mark[w] = set + 1;
                    self.level[w] = self.level[v] + 1;
                    self.queue.push(w);
                }
            }
        }
        &self.queue
    }
}

#[cfg(test)]
mod tests {
    use faer::perm::PermRef;
    use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, SymmetricOrdering};
    use faer::sparse::{SparseColMat, Triplet};
    use faer::Side;
    use nalgebra::Vector3;

    use super::nested_dissection;

    /// The 5-point Laplacian of a `k × k` grid, two components side by side (the ordering must
    /// handle disconnected graphs).
    fn two_grids(k: usize) -> SparseColMat<usize, f64> {
        let n = 2 * k * k;
        let index = |g: usize, i: usize, j: usize| g * k * k + j * k + i;
        let mut triplets = Vec::new();
        for g in 0..2 {
            for j in 0..k {
                for i in 0..k {
                    let a = index(g, i, j);
                    triplets.push(Triplet::new(a, a, 4.0));
                    for (di, dj) in [(1, 0), (0, 1)] {
                        if i + di < k && j + dj < k {
                            let b = index(g, i + di, j + dj);
                            triplets.push(Triplet::new(a, b, -1.0));
                            triplets.push(Triplet::new(b, a, -1.0));
                        }
                    }
                }
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &triplets).unwrap()
    }

    /// The 9-point Laplacian of a `k × k` grid (each vertex coupled to its diagonal neighbours, as
    /// the nodes of quadrilateral elements are) and the vertices' positions.
    fn nine_point_grid(k: usize) -> (SparseColMat<usize, f64>, Vec<Vector3<f64>>) {
        let index = |i: usize, j: usize| j * k + i;
        let mut triplets = Vec::new();
        for j in 0..k {
            for i in 0..k {
                triplets.push(Triplet::new(index(i, j), index(i, j), 8.0));
                for (di, dj) in [(1, 0), (0, 1), (1, 1), (-1, 1)] {
                    let (p, q) = (i as i64 + di, j as i64 + dj);
                    if (0..k as i64).contains(&p) && (0..k as i64).contains(&q) {
                        let (a, b) = (index(i, j), index(p as usize, q as usize));
                        triplets.push(Triplet::new(a, b, -1.0));
                        triplets.push(Triplet::new(b, a, -1.0));
                    }
                }
            }
        }
        let positions = (0..k * k).map(|v| Vector3::new((v % k) as f64, (v / k) as f64, 0.0)).collect();
        (SparseColMat::try_new_from_triplets(k * k, k * k, &triplets).unwrap(), positions)
    }

    /// On a square grid whose vertices couple diagonally, the coordinate cuts (straight lines of
    /// the grid) give a sparser factor than the breadth-first levels (L-shaped, √2 times longer),
    /// and the order is a permutation.
    #[test]
    fn coordinate_cuts_beat_the_levels_on_a_square_grid() {
        let (a, positions) = nine_point_grid(80);
        let n = a.ncols();
        let fill = |positions: Option<&[Vector3<f64>]>| {
            let (order, inverse) = nested_dissection(&a, positions);
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert!(sorted.iter().enumerate().all(|(k, &v)| k == v), "not a permutation");
            let ordering = SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, n));
            factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, Default::default()).unwrap().len_val()
        };
        let (levels, cuts) = (fill(None), fill(Some(&positions)));
        assert!((cuts as f64) < 0.9 * levels as f64, "coordinate cuts {cuts} nonzeros, levels {levels}");
    }

    /// The order is a permutation, and on a 2-D grid its factor is far sparser than that of the
    /// natural (banded) order: nested dissection's `O(n log n)` fill against the band's `O(n^1.5)`.
    #[test]
    fn orders_every_vertex_once_and_cuts_the_fill_of_a_grid() {
        let a = two_grids(60);
        let n = a.ncols();
        let (order, inverse) = nested_dissection(&a, None);
        let mut seen = vec![false; n];
        for (k, &v) in order.iter().enumerate() {
            assert!(!seen[v], "vertex {v} ordered twice");
            seen[v] = true;
            assert_eq!(inverse[v], k);
        }
        assert!(seen.iter().all(|&s| s));
        let fill = |ordering| factorize_symbolic_cholesky(a.symbolic(), Side::Lower, ordering, Default::default()).unwrap().len_val();
        let natural = fill(SymmetricOrdering::Identity);
        let dissected = fill(SymmetricOrdering::Custom(PermRef::new_checked(&order, &inverse, n)));
        assert!((dissected as f64) < 0.5 * natural as f64, "nested dissection {dissected} nonzeros, natural order {natural}");
    }
}
