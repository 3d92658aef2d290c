//! Memory of the dense initial-condition analyses (redundancy check, assembly, velocity analysis), which
//! hold the constraint Jacobian as dense matrices: checked against the memory the machine has before
//! anything is allocated, so that a model too large ends with an error that says how much it needed
//! instead of an aborted allocation or the system's out-of-memory killer.

/// How much memory the dense analyses may use.
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

/// Bytes of the largest dense working set of the initial-condition analyses for `nc` constraint rows,
/// `nb` bodies, `nq` positions and `nv` velocities, in `f64`: the redundancy check's `Bᵀ` and its
/// orthonormal basis (`2 · nv × nc`), or the assembly's velocity Jacobian `B` (`nc × nv`), position
/// Jacobian `Φ_q` (`(nc + nb) × nq`) and normal matrix `Φ_q Φ_qᵀ` (`(nc + nb)²`), whichever is larger.
pub fn dense_analysis_bytes(nc: usize, nb: usize, nq: usize, nv: usize) -> u64 {
    let (nc, nb, nq, nv) = (nc as u64, nb as u64, nq as u64, nv as u64);
    let m = nc + nb;
    8 * (2 * nc * nv).max(nc * nv + m * nq + m * m)
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

    #[test]
    fn a_chain_of_20000_bodies_needs_tens_of_gigabytes() {
        // 20,000 rigid bodies on spherical joints: nc = 60,000, nq = 140,000, nv = 120,000.
        let bytes = dense_analysis_bytes(60_000, 20_000, 140_000, 120_000);
        assert_eq!(bytes, 198_400_000_000);
        assert_eq!(format_bytes(bytes), "184.8 GiB");
        assert_eq!(format_bytes(999), "999 B");
        assert_eq!(format_bytes(3 << 19), "1.5 MiB");
    }
}
