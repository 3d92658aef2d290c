//! The cache of reduced flexible bodies: a reduction of an FE model file is kept in `.flexmb-cache/`
//! next to it, as a flexible-body file named `<fe stem>-<modes>-<basis>-<hash>.json`, where the hash
//! (FNV-1a, 64 bits) covers the bytes of the FE model file and of every file it read (the mesh file and
//! its includes), the mode set, the basis, the flexible-body format version, the terms the reduction
//! computes (the geometric stiffness of the unit inertia and interface loads; the modal stresses, which the FE
//! model file's `[modes] stresses` asks for), the meaning of a model that names no mass model, and the
//! program's version.
//! A changed input gives another name, so a stale file is never read; it is removed when the new one
//! is written. A cache that cannot be written only costs the next run a new reduction. The file is
//! written to a temporary file and renamed into place, so a reader sees all of it or nothing, and
//! the reduction is made under a lock ([`ReductionLock`]), so that many processes loading the same
//! model at once reduce it once.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use flexmb_fem::modes::EigenSettings;
use flexmb_fem::reduction::{add_modal_stresses, reduce, Basis, FlexibleBody, ModeSet, ReductionSettings, VERSION};
use flexmb_fem::FemError;

use super::flexible_bodies::FlexibleBodyOrigin;
use super::reduction_lock::{ReductionLock, POLL_EVERY, STALE_AFTER};
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
/// a valid one, else reduced now (and cached if possible) with at most `memory_limit` bytes. The
/// reduction is made under the cache's [`ReductionLock`]: processes and threads that need the same
/// body at the same time wait for the first one's reduction and read it from the cache.
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
    let reduce_now = |cache: Option<(&Path, &str, u64)>| {
        let started = Instant::now();
        let eigen = EigenSettings { memory_limit, ..Default::default() };
        let settings = ReductionSettings { mode_set: set.clone(), basis, eigen };
        let mut reduction = reduce(&loaded.model, &loaded.name, &settings)?;
        if loaded.defaults.stresses == Some(true) {
            let warning = add_modal_stresses(&loaded.model, &mut reduction.body)?;
            reduction.warnings.extend(warning);
        }
        let seconds = started.elapsed().as_secs_f64();
        let cache = cache.and_then(|(dir, prefix, hash)| store(dir, prefix, hash, &reduction.body));
        let origin = FlexibleBodyOrigin::Reduced { fe_model: fe_path.to_path_buf(), cache, seconds };
        Ok(Obtained { body: reduction.body, origin, warnings: reduction.warnings })
    };
    let Some(hash) = cache_hash(loaded, set, basis) else { return reduce_now(None) };
    let name = format!("{prefix}{hash:016x}.json");
    let file = dir.join(&name);
    if let Some(obtained) = cached(&file, loaded, fe_path, set, basis) {
        return Ok(obtained);
    }
    // A directory where the lock cannot be created cannot hold the cache either: reduce without it.
    let lock_path = dir.join(format!(".{name}.lock"));
    let acquired = std::fs::create_dir_all(&dir)
        .and_then(|()| ReductionLock::acquire(&lock_path, STALE_AFTER, POLL_EVERY))
        .ok();
    let lock_warning = acquired.as_ref().and_then(|a| a.warning.clone());
    // The cache is read again under the lock whether or not another held it: the one that reduced may
    // have written the cache and released the lock between the reading above and this acquisition (six
    // concurrent checks on a loaded machine then reduced the door twice).
    let obtained = match acquired.as_ref().and_then(|_| cached(&file, loaded, fe_path, set, basis)) {
        Some(obtained) => Ok(obtained),
        None => reduce_now(Some((&dir, &prefix, hash))),
    };
    if let Some(acquired) = acquired {
        acquired.lock.release();
    }
    if obtained.is_err() {
        // Nothing was cached: leave no empty cache directory made for the lock (if it is not empty,
        // or another process is using it, it stays).
        let _ = std::fs::remove_dir(&dir);
    }
    obtained.map(|mut obtained| {
        obtained.warnings.extend(lock_warning);
        obtained
    })
}

/// The body cached in `file`, if it is there and valid.
fn cached(file: &Path, loaded: &LoadedFeModel, fe_path: &Path, set: &ModeSet, basis: Basis) -> Option<Obtained> {
    let body = FlexibleBody::read(file).ok().filter(|body| is_valid(body, loaded, set, basis))?;
    let origin = FlexibleBodyOrigin::Cached { fe_model: fe_path.to_path_buf(), cache: file.to_path_buf() };
    Some(Obtained { body, origin, warnings: Vec::new() })
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
        && body.mode_count() <= set.len()
        && body.nodes.len() == loaded.model.mesh.nodes.len()
        && body.name == loaded.name
}

/// The hash of everything the reduction depends on; `None` if a source file cannot be read (then
/// nothing is cached).
fn cache_hash(loaded: &LoadedFeModel, set: &ModeSet, basis: Basis) -> Option<u64> {
    let mut hash = Fnv1a::new();
    hash.field(b"flexmb reduced flexible body");
    hash.field(&VERSION.to_le_bytes());
    // Reductions hold the geometric stiffness of the unit inertia and interface loads, of beams,
    // shells and solids: caches made before do not (or only a beam model's inertia loads).
    hash.field(b"geometric stiffness: inertia loads");
    hash.field(b"geometric stiffness: interface loads; beams, shells and solids");
    // Reductions may hold modal stresses (as the FE model file, hashed below, says).
    hash.field(b"modal stresses");
    // A model that names no mass model has each kind of element's default (consistent beams and
    // solids): caches made before lumped them.
    hash.field(b"mass: each kind of element's default");
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
