//! The memory the mode analysis of a mesh needs, estimated from its elements and nodes before anything
//! is assembled, so that a mesh too large for the machine is refused with what it needs instead of
//! ending in an aborted allocation (a beam line of 10⁶ elements, found by the fuzz test, asked for
//! 3.2 GB of stiffness triplets at once), and the dense eigensolver's, checked once the operator's
//! dimension is known (`--solver dense` on a plate of 1600 × 12 shells asked for 28 GB).

use crate::mesh::Mesh;

/// Bytes of one stiffness triplet of the assembly (row, column, value).
const TRIPLET_BYTES: u64 = 24;
/// The Lanczos method's Krylov space: at least 64 vectors of all the degrees of freedom.
const KRYLOV_VECTORS: u64 = 64;

/// About the peak memory of the assembly and mode analysis of `mesh`, in bytes: the triplets of every
/// element's stiffness (`(6k)²` for an element of `k` nodes) and the Krylov space of its degrees of
/// freedom. A plate of 300 × 300 shells: 1.52 GB, where the analysis measured 1.5 GB.
pub fn mode_analysis_bytes(mesh: &Mesh) -> u64 {
    let entries: u64 = mesh.elements.iter().map(|e| (6 * e.nodes.len() as u64).pow(2)).sum();
    let dofs = 6 * mesh.nodes.len() as u64;
    entries * TRIPLET_BYTES + dofs * KRYLOV_VECTORS * 8
}

/// The dense eigensolver's matrices for an operator of dimension `n`: the identity it is applied to, the
/// operator, its symmetric part, the eigenvectors and the solver's workspace, about six `n × n` in all.
pub fn dense_eigensolver_bytes(n: usize) -> u64 {
    6 * 8 * (n as u64).pow(2)
}
