//! Limits a user can set for the machine a command runs on, through environment variables:
//! `FLEXMB_MEMORY_LIMIT`, the memory the dense initial-condition analyses and the FE mode analysis
//! may use (default: what the machine has available).

use flexmb::analysis::{AssemblySettings, MemoryLimit};

use crate::run::CliError;
use crate::SimulationDefaults;

/// The environment variable that caps the memory of the dense analyses.
pub const MEMORY_LIMIT_VARIABLE: &str = "FLEXMB_MEMORY_LIMIT";

/// The memory limit `FLEXMB_MEMORY_LIMIT` sets (bytes, or with a suffix k, M, G, T in powers of 1000),
/// else the memory the machine has available.
pub fn memory_limit() -> Result<MemoryLimit, CliError> {
    match std::env::var(MEMORY_LIMIT_VARIABLE) {
        Ok(text) => parse_byte_size(&text)
            .map(MemoryLimit::Bytes)
            .ok_or_else(|| CliError(format!("{MEMORY_LIMIT_VARIABLE}={text:?}: expected a number of bytes such as 8000000000 or 8G"))),
        Err(_) => Ok(MemoryLimit::Available),
    }
}

/// The memory limit in bytes, if one is known; a malformed `FLEXMB_MEMORY_LIMIT` counts as none here
/// (the commands that read [`memory_limit`] report it).
pub fn memory_limit_bytes() -> Option<u64> {
    memory_limit().ok().and_then(MemoryLimit::bytes)
}

/// The assembly settings of a model's `[simulation]` with the memory limit of this machine.
pub fn assembly_settings(defaults: &SimulationDefaults) -> Result<AssemblySettings, CliError> {
    Ok(AssemblySettings { memory_limit: memory_limit()?, ..defaults.assembly() })
}

/// `"512"`, `"64k"`, `"1.5M"`, `"8G"`, `"2T"` in bytes (powers of 1000; a trailing `B` is allowed).
pub fn parse_byte_size(text: &str) -> Option<u64> {
    let t = text.trim().trim_end_matches(['B', 'b']);
    let (number, factor) = match t.chars().last()? {
        'k' | 'K' => (&t[..t.len() - 1], 1e3),
        'M' | 'm' => (&t[..t.len() - 1], 1e6),
        'G' | 'g' => (&t[..t.len() - 1], 1e9),
        'T' | 't' => (&t[..t.len() - 1], 1e12),
        _ => (t, 1.0),
    };
    let x: f64 = number.trim().parse().ok()?;
    (x.is_finite() && x >= 0.0 && x * factor < u64::MAX as f64).then_some((x * factor) as u64)
}

#[cfg(test)]
mod tests {
    use super::parse_byte_size;

    #[test]
    fn byte_sizes_read_with_decimal_suffixes() {
        assert_eq!(parse_byte_size("512"), Some(512));
        assert_eq!(parse_byte_size("64k"), Some(64_000));
        assert_eq!(parse_byte_size("1.5M"), Some(1_500_000));
        assert_eq!(parse_byte_size(" 8G "), Some(8_000_000_000));
        assert_eq!(parse_byte_size("8GB"), Some(8_000_000_000));
        assert_eq!(parse_byte_size("2T"), Some(2_000_000_000_000));
        for bad in ["", "G", "-1", "lots", "1e400", "nan"] {
            assert_eq!(parse_byte_size(bad), None, "{bad:?}");
        }
    }
}
