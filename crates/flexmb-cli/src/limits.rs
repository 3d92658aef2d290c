//! Limits a user can set for the machine a command runs on, through environment variables:
//! `FLEXMB_MEMORY_LIMIT`, the memory the initial-condition analyses and the FE mode analysis
//! may use (default: what the machine has available). (`FLEXMB_MAX_FILE_SIZE`, the largest input
//! file, is read where files are read: `flexmb_fem::input`.) The program reads the variable; the
//! libraries take the value.

use flexmb::analysis::{AssemblySettings, MemoryLimit};
use flexmb_fem::input::parse_size;

use crate::run::CliError;
use flexmb_files::model_file::LoadOptions;
use flexmb_files::SimulationDefaults;

/// The environment variable that caps the memory of the initial-condition analyses.
pub const MEMORY_LIMIT_VARIABLE: &str = "FLEXMB_MEMORY_LIMIT";

/// The memory limit `FLEXMB_MEMORY_LIMIT` sets (bytes, or with a suffix k, M, G: times 1024, 1024²,
/// 1024³), else the memory the machine has available.
pub fn memory_limit() -> Result<MemoryLimit, CliError> {
    match std::env::var(MEMORY_LIMIT_VARIABLE) {
        Ok(text) => parse_size(&text).map(MemoryLimit::Bytes).ok_or_else(|| {
            CliError(format!(
                "{MEMORY_LIMIT_VARIABLE}={text:?}: expected a whole number of bytes, optionally followed by k, M \
                 or G (times 1024, 1024², 1024³), e.g. 8G"
            ))
        }),
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
    Ok(defaults.with_memory_limit(memory_limit()?))
}

/// How the commands load model files: the file as it is, with the memory limit of this machine for
/// the mode analysis of its flexible bodies.
pub fn load_options() -> LoadOptions {
    LoadOptions { memory_limit: memory_limit_bytes(), ..Default::default() }
}
