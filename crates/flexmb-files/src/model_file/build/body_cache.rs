//! The cache of reduced flexible bodies: a reduction of an FE model file is kept in `.flexmb-cache/`
//! next to it, as a flexible-body file named `<fe stem>-<modes>-<basis>-<hash>.json`, where the hash
//! (FNV-1a, 64 bits) covers the bytes of the FE model file and of every file it read (the mesh file and
//! its includes), the mode set, the basis, the flexible-body format version and the program's version.
//! A changed input gives another name, so a stale file is never read; it is removed when the new one
//! is written. A cache that cannot be written only costs the next run a new reduction.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use flexmb_fem::modes::EigenSettings;
use flexmb_fem::reduction::{reduce, Basis, FlexibleBody, ModeSet, ReductionSettings, VERSION};
use flexmb_fem::FemError;

use super::flexible_bodies::FlexibleBodyOrigin;
use crate::fe_model_file::LoadedFeModel;

/// The cache directory's name, next to the FE model file.
pub const CACHE_DIR: &str = ".flexmb-cache";

/// A reduced body and where it came from.
pub(crate) struct Obtained {
    pub body: FlexibleBody,
    pub origin: FlexibleBodyOrigin,
    /// The reduction's warnings (none when the body came from the cache).
    pub warnings: Vec<String>,
}

/// The reduced body of `loaded` (read from `fe_path`) for `set` and `basis`: from the cache if it holds
/// a valid one, else reduced now (and cached if possible) with at most `memory_limit` bytes.
pub(crate) fn reduced_body(
    loaded: &LoadedFeModel,
    fe_path: &Path,
    set: &ModeSet,
    basis: Basis,
    memory_limit: Option<u64>,
) -> Result<Obtained, FemError> {
    let dir = fe_path.parent().unwrap_or(Path::new("")).join(CACHE_DIR);
    let stem = fe_path.file_stem().and_then(|s| s.to_str()).unwrap_or("fe_model");
    let prefix = format!("{stem}-{set}-{}-", basis_name(basis));
    let hash = cache_hash(loaded, set, basis);
    if let Some(hash) = hash {
        let file = dir.join(format!("{prefix}{hash:016x}.json"));
        if let Ok(body) = FlexibleBody::read(&file) {
            if is_valid(&body, loaded, set, basis) {
                let origin = FlexibleBodyOrigin::Cached { fe_model: fe_path.to_path_buf(), cache: file };
                return Ok(Obtained { body, origin, warnings: Vec::new() });
            }
        }
    }
    let started = Instant::now();
    let eigen = EigenSettings { memory_limit, ..Default::default() };
    let settings = ReductionSettings { mode_set: set.clone(), basis, eigen };
    let reduction = reduce(&loaded.model, &loaded.name, &settings)?;
    let seconds = started.elapsed().as_secs_f64();
    let cache = hash.and_then(|hash| store(&dir, &prefix, hash, &reduction.body));
    let origin = FlexibleBodyOrigin::Reduced { fe_model: fe_path.to_path_buf(), cache, seconds };
    Ok(Obtained { body: reduction.body, origin, warnings: reduction.warnings })
}

/// `raw` or `orthonormal`, as in files.
pub fn basis_name(basis: Basis) -> &'static str {
    match basis {
        Basis::Raw => "raw",
        Basis::Orthonormal => "orthonormal",
    }
}

/// A cached body must be what was asked for (the hash makes this all but certain; a file edited or
/// truncated by hand is not).
fn is_valid(body: &FlexibleBody, loaded: &LoadedFeModel, set: &ModeSet, basis: Basis) -> bool {
    body.mode_set == set.to_string()
        && body.basis == basis
        && body.mode_count() == set.len()
        && body.nodes.len() == loaded.model.mesh.nodes.len()
        && body.name == loaded.name
}

/// The hash of everything the reduction depends on; `None` if a source file cannot be read (then
/// nothing is cached).
fn cache_hash(loaded: &LoadedFeModel, set: &ModeSet, basis: Basis) -> Option<u64> {
    let mut hash = Fnv1a::new();
    hash.field(b"flexmb reduced flexible body");
    hash.field(&VERSION.to_le_bytes());
    hash.field(env!("CARGO_PKG_VERSION").as_bytes());
    hash.field(set.to_string().as_bytes());
    hash.field(basis_name(basis).as_bytes());
    hash.field(&(loaded.sources.len() as u64).to_le_bytes());
    for source in &loaded.sources {
        hash.field(&flexmb_fem::input::read_file(source).ok()?);
    }
    Some(hash.finish())
}

/// Writes `body` as `<prefix><hash>.json` in `dir` (through a temporary file, so that a reader never
/// sees half a file), and removes the files of the same prefix with another hash. `None` if the
/// cache cannot be written.
fn store(dir: &Path, prefix: &str, hash: u64, body: &FlexibleBody) -> Option<PathBuf> {
    static TEMPORARY: AtomicU64 = AtomicU64::new(0);
    std::fs::create_dir_all(dir).ok()?;
    let name = format!("{prefix}{hash:016x}.json");
    let file = dir.join(&name);
    let temporary =
        dir.join(format!(".{name}.{}-{}.tmp", std::process::id(), TEMPORARY.fetch_add(1, Ordering::Relaxed)));
    if std::fs::write(&temporary, body.to_json()).and_then(|()| std::fs::rename(&temporary, &file)).is_err() {
        let _ = std::fs::remove_file(&temporary);
        return None;
    }
    remove_stale(dir, prefix, &name);
    Some(file)
}

/// Removes `<prefix><16 hex digits>.json` files other than `keep`: reductions of an earlier version of
/// the same FE model, mode set and basis.
fn remove_stale(dir: &Path, prefix: &str, keep: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let stale = name != keep
            && name
                .strip_prefix(prefix)
                .and_then(|rest| rest.strip_suffix(".json"))
                .is_some_and(|hash| hash.len() == 16 && hash.chars().all(|c| c.is_ascii_hexdigit()));
        if stale {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// FNV-1a, 64 bits: a small, stable hash (the standard library's is neither specified nor stable
/// across versions).
struct Fnv1a(u64);

impl Fnv1a {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    fn write(&mut self, bytes: &[u8]) {
        for byte in bytes {
            self.0 ^= u64::from(*byte);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    /// A length-prefixed field, so that consecutive fields cannot run into each other.
    fn field(&mut self, bytes: &[u8]) {
        self.write(&(bytes.len() as u64).to_le_bytes());
        self.write(bytes);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv1a_matches_the_reference_values() {
        let hash = |text: &str| {
            let mut h = Fnv1a::new();
            h.write(text.as_bytes());
            h.finish()
        };
        assert_eq!(hash(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(hash("a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(hash("foobar"), 0x8594_4171_f739_67e8);
    }
}
