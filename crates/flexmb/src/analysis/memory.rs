//! Memory of the initial-condition analyses (redundancy check, assembly, velocity analysis), which hold
//! the constraint Jacobians as sparse matrices and factor their sparse normal matrices: estimated from the
//! model's joints and bodies and checked against the memory the machine has before anything is
//! allocated, so that a model too large ends with an error that says how much it needed instead of an
//! aborted allocation or the system's out-of-memory killer. The estimate grows with the bodies for
//! chains and trees (linearly), and with the square of the joints on one body (a hub), as the normal
//! matrix does.

use crate::model::Model;

/// How much memory the initial-condition analyses may use.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MemoryLimit {
    /// The memory available on this machine when the analysis starts (`MemAvailable` of
    /// `/proc/meminfo`; no check where the system does not say).
    #[default]
    Available,
    /// At most this many bytes.
    Bytes(u64),
}

impl MemoryLimit {
    /// The limit in bytes, if one is known.
    pub fn bytes(self) -> Option<u64> {
        match self {
            MemoryLimit::Available => available_memory(),
            MemoryLimit::Bytes(n) => Some(n),
        }
    }
}

/// Bytes of the largest working set of the initial-condition analyses, an upper estimate from the
/// model's structure. Per body `b` with `k_b` rows touching it (its joints' constraint rows and its
/// normalization row) and `s_b` positions: the entries of `Φ̂_q` and `B`, `Σ k_b (s_b + v_b)`, each held
/// as an entry list, compressed, transposed and in the triangular factor of the redundancy check (at most
/// 64 bytes an entry); the normal matrix `Φ̂_q Φ̂_qᵀ`, whose entries are the pairs of rows that share a
/// position, `Σ s_b k_b²`, with its pattern, values and LU factors (at most 48 bytes a pair); and the
/// vectors of positions, velocities and rows (64 bytes each).
pub fn analysis_bytes(model: &Model) -> u64 {
    let l = &model.layout;
    let nb = model.bodies.len();
    let mut rows_touching = vec![1u64; nb];
    for (j, joint) in model.joints.iter().enumerate() {
        let rows = l.joint_rows[j].len() as u64;
        let [i, k] = model.joint_bodies(joint);
        for b in [i, k.filter(|k| Some(*k) != i)].into_iter().flatten() {
            rows_touching[b.0] += rows;
        }
    }
    let (mut entries, mut pairs) = (0u64, 0u64);
    for (b, &k) in rows_touching.iter().enumerate() {
        let (s, v) = (7 + l.modes[b] as u64, 6 + l.modes[b] as u64);
        entries = entries.saturating_add(k.saturating_mul(s + v));
        pairs = pairs.saturating_add(s.saturating_mul(k).saturating_mul(k));
    }
    let vectors = (l.nq + l.nv + l.nc + nb) as u64;
    entries.saturating_mul(64).saturating_add(pairs.saturating_mul(48)).saturating_add(vectors.saturating_mul(64))
}

/// `MemAvailable` of `/proc/meminfo` in bytes, where there is one.
fn available_memory() -> Option<u64> {
    let text = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kb: u64 = line.trim_start_matches("MemAvailable:").trim().trim_end_matches("kB").trim().parse().ok()?;
    Some(kb * 1024)
}

/// `184.8 GiB`, `473.0 MiB`: a byte count for messages, in binary multiples.
pub fn format_bytes(bytes: u64) -> String {
    const UNITS: [&str; 5] = ["B", "kiB", "MiB", "GiB", "TiB"];
    let mut x = bytes as f64;
    let mut unit = 0;
    while x >= 1024.0 && unit < UNITS.len() - 1 {
        x /= 1024.0;
        unit += 1;
    }
    if unit == 0 {
        format!("{bytes} B")
    } else {
        format!("{x:.1} {}", UNITS[unit])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::test_models::{spherical_chain, spherical_pendulums};

    #[test]
    fn the_estimate_grows_linearly_with_the_bodies_of_a_chain_and_of_independent_pendulums() {
        // Each body of a chain has the 3 rows of the joint above and the 3 of the joint below and its
        // normalization: 7 rows, 7 positions, 6 velocities, 7·13·64 + 7·7²·48 + (7 + 6 + 3 + 1)·64 bytes.
        let per_body = 7 * 13 * 64 + 7 * 49 * 48 + 17 * 64;
        let chain = |n| analysis_bytes(&spherical_chain(n));
        assert_eq!(chain(2000) - chain(1000), 1000 * per_body);
        assert_eq!(chain(20_000) - chain(10_000), 10_000 * per_body);
        assert_eq!(format_bytes(chain(20_000)), "445.8 MiB");
        // A pendulum's bob has the 3 rows of its one joint and its normalization.
        let per_pendulum = 4 * 13 * 64 + 7 * 16 * 48 + 17 * 64;
        assert_eq!(analysis_bytes(&spherical_pendulums(1000)), 1000 * per_pendulum);
        assert_eq!(format_bytes(999), "999 B");
        assert_eq!(format_bytes(3 << 19), "1.5 MiB");
    }
}
