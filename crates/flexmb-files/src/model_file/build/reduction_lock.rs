//! The lock that lets one process (or thread) reduce an FE model while the others that need the same
//! reduction wait for it and then read it from the cache: a study's workers, a sweep's processes or
//! six `flexmb check` started at once reduce the door once, not six times.
//!
//! The lock is a file `.<cache name>.lock` in the cache directory, created with `create_new` (the
//! file system's atomic "create if absent", on Linux as on Windows) and holding the owner's process
//! id, host and start time; it is removed when the reduction is cached (or has failed). Whoever finds
//! it present polls until it is gone. A lock whose owner is gone (same host, no such process: read
//! from `/proc` where there is one) or that is older than a bound is stale (a process killed while it
//! reduced): it is taken over, with a warning.
//!
//! Correctness never rests on the lock: the cached file is written to a temporary file and renamed
//! into place, so a reader sees a whole file or none. The lock only saves the duplicated work; in the
//! rare races it cannot exclude (two waiters taking over the same stale lock at once) two processes
//! reduce, and both write the same file.

use std::io::{ErrorKind, Write as _};
use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

/// A lock older than this is stale even if its owner seems alive (the owner may be on another host
/// sharing the directory, or its process id reused). A reduction that takes longer than this may be
/// duplicated by a waiter, never corrupted.
pub(crate) const STALE_AFTER: Duration = Duration::from_secs(600);

/// How often a waiter looks whether the lock is gone.
pub(crate) const POLL_EVERY: Duration = Duration::from_millis(50);

/// A held lock: the file is removed when this is dropped, if it is still ours.
#[derive(Debug)]
pub(crate) struct ReductionLock {
    path: PathBuf,
    owner: String,
}

/// How a lock was obtained.
#[derive(Debug)]
pub(crate) struct Acquired {
    pub lock: ReductionLock,
    /// Whether the lock was held by another process (or thread) when first tried. The cache reads its
    /// file again under the lock either way (the other may have released it just before), so only the
    /// tests of the exclusion read this.
    #[cfg_attr(not(test), allow(dead_code))]
    pub waited: bool,
    /// The warning when a stale lock was taken over.
    pub warning: Option<String>,
}

impl ReductionLock {
    /// Takes the lock at `path`, waiting (polling every `poll`) while another live owner holds it,
    /// and taking over a lock whose owner is gone or that is older than `stale_after`. An error other
    /// than "the file exists" (a directory that cannot be written) is returned: reduce without it.
    pub(crate) fn acquire(path: &Path, stale_after: Duration, poll: Duration) -> std::io::Result<Acquired> {
        let owner = owner_line();
        let mut waited = false;
        let mut warning = None;
        loop {
            match std::fs::OpenOptions::new().write(true).create_new(true).open(path) {
                Ok(mut file) => {
                    // The owner's line is written after the creation: a waiter that reads an empty
                    // file judges it by its age alone.
                    if let Err(e) = file.write_all(owner.as_bytes()) {
                        let _ = std::fs::remove_file(path);
                        return Err(e);
                    }
                    let lock = ReductionLock { path: path.to_path_buf(), owner };
                    return Ok(Acquired { lock, waited, warning });
                }
                Err(e) if e.kind() == ErrorKind::AlreadyExists => {}
                Err(e) => return Err(e),
            }
            waited = true;
            if let Some(stale) = stale_reason(path, stale_after) {
                if take_over(path, &stale.held_by) {
                    warning = Some(format!("took over the stale reduction lock {} ({})", path.display(), stale.why));
                }
                continue;
            }
            std::thread::sleep(poll);
        }
    }
}

impl ReductionLock {
    /// Releases the lock: the cache is written (or could not be), the waiters may go on. (Dropping
    /// the lock does the same, on an error's way out.)
    pub(crate) fn release(self) {}
}

impl Drop for ReductionLock {
    fn drop(&mut self) {
        // A lock taken over by another (ours judged stale) is theirs now: leave it.
        if std::fs::read_to_string(&self.path).is_ok_and(|held| held == self.owner) {
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

/// `pid host seconds.nanoseconds`: the owner of a lock, unique per acquisition.
fn owner_line() -> String {
    let since = SystemTime::now().duration_since(UNIX_EPOCH).unwrap_or_default();
    format!("{} {} {}.{:09}\n", std::process::id(), host_name(), since.as_secs(), since.subsec_nanos())
}

/// The host's name where the system tells it without a dependency (Linux), else empty.
fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname").map(|h| h.trim().replace(' ', "_")).unwrap_or_default()
}

/// A lock found stale: what it held and why it is stale.
struct Stale {
    held_by: String,
    why: String,
}

/// Whether the lock at `path` is stale: its owner process is gone (on this host, where `/proc` tells)
/// or the file is older than `stale_after`. `None` also when the lock is already gone.
fn stale_reason(path: &Path, stale_after: Duration) -> Option<Stale> {
    let held_by = std::fs::read_to_string(path).ok()?;
    let mut fields = held_by.split_whitespace();
    let (pid, host) = (fields.next().and_then(|p| p.parse::<u32>().ok()), fields.next().unwrap_or(""));
    if let Some(pid) = pid {
        if host == host_name() && process_is_gone(pid) {
            return Some(Stale { why: format!("its process {pid} is gone"), held_by });
        }
    }
    let age = std::fs::metadata(path).and_then(|m| m.modified()).ok()?.elapsed().ok()?;
    (age > stale_after).then(|| Stale {
        why: format!("held for {:.0} s, longer than {:.0} s", age.as_secs_f64(), stale_after.as_secs_f64()),
        held_by,
    })
}

/// Whether process `pid` is known not to exist: `/proc` is there and has no such entry. Where there
/// is no `/proc` (Windows, macOS) nothing is known, and only the age of a lock makes it stale.
fn process_is_gone(pid: u32) -> bool {
    Path::new("/proc/self").exists() && !Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes the stale lock at `path` if it still holds `held_by`: renamed aside first (only one of
/// several waiters can rename the file), then checked, then deleted. Whether it was removed.
fn take_over(path: &Path, held_by: &str) -> bool {
    let aside = path.with_extension(format!("stale-{}", std::process::id()));
    if std::fs::rename(path, &aside).is_err() {
        return false;
    }
    let ours = std::fs::read_to_string(&aside).is_ok_and(|held| held == held_by);
    if !ours {
        // A fresh lock taken between our reading and our renaming: put it back, unless yet another
        // was created meanwhile (then two reduce, which is only duplicated work).
        let _ = std::fs::hard_link(&aside, path);
    }
    let _ = std::fs::remove_file(&aside);
    ours
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicBool, Ordering};

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("flexmb-reduction-lock-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    const LONG: Duration = Duration::from_secs(3600);

    #[test]
    fn a_free_lock_is_taken_and_removed_when_dropped() {
        let path = scratch("free").join("x.lock");
        let acquired = ReductionLock::acquire(&path, LONG, POLL_EVERY).unwrap();
        assert!(!acquired.waited && acquired.warning.is_none());
        let held = std::fs::read_to_string(&path).unwrap();
        assert!(held.starts_with(&format!("{} ", std::process::id())), "{held}");
        drop(acquired);
        assert!(!path.exists());
    }

    #[test]
    fn a_held_lock_is_waited_for_and_excludes_the_others() {
        // Four threads each take the lock and, holding it, mark a critical section: never two inside.
        let path = scratch("held").join("x.lock");
        let inside = AtomicBool::new(false);
        let waited: Vec<bool> = std::thread::scope(|s| {
            let workers: Vec<_> = (0..4)
                .map(|_| {
                    s.spawn(|| {
                        let acquired = ReductionLock::acquire(&path, LONG, Duration::from_millis(2)).unwrap();
                        assert!(!inside.swap(true, Ordering::SeqCst), "two holders of the lock at once");
                        std::thread::sleep(Duration::from_millis(30));
                        inside.store(false, Ordering::SeqCst);
                        acquired.waited
                    })
                })
                .collect();
            workers.into_iter().map(|w| w.join().unwrap()).collect()
        });
        assert!(waited.iter().filter(|&&w| w).count() >= 3, "{waited:?}");
        assert!(!path.exists());
    }

    #[test]
    fn a_lock_of_a_process_that_is_gone_is_taken_over_with_a_warning() {
        if !Path::new("/proc/self").exists() {
            return; // no process table to read: only the age decides (the next test)
        }
        let path = scratch("gone").join("x.lock");
        // A process that has exited: its id is not in /proc (reaped, and not reused this soon).
        let mut child = std::process::Command::new(std::env::current_exe().unwrap()).arg("--help").stdout(std::process::Stdio::null()).spawn().unwrap();
        let pid = child.id();
        child.wait().unwrap();
        std::fs::write(&path, format!("{pid} {} 0.0\n", host_name())).unwrap();
        let acquired = ReductionLock::acquire(&path, LONG, POLL_EVERY).unwrap();
        let warning = acquired.warning.clone().expect("a warning");
        assert!(warning.contains(&format!("its process {pid} is gone")), "{warning}");
        assert!(acquired.waited);
    }

    #[test]
    fn a_lock_older_than_the_bound_is_taken_over_even_if_its_owner_lives() {
        let path = scratch("old").join("x.lock");
        // Held by this very process (alive), on another host: only its age can make it stale.
        std::fs::write(&path, format!("{} another-host 0.0\n", std::process::id())).unwrap();
        std::thread::sleep(Duration::from_millis(30));
        let acquired = ReductionLock::acquire(&path, Duration::from_millis(10), POLL_EVERY).unwrap();
        let warning = acquired.warning.clone().expect("a warning");
        assert!(warning.contains("longer than"), "{warning}");
        // A lock younger than the bound of a live owner is waited for: released by another thread.
        drop(acquired);
        std::fs::write(&path, format!("{} {} 0.0\n", std::process::id(), host_name())).unwrap();
        let path_again = path.clone();
        let release = std::thread::spawn(move || {
            std::thread::sleep(Duration::from_millis(100));
            std::fs::remove_file(&path_again).unwrap();
        });
        let acquired = ReductionLock::acquire(&path, LONG, Duration::from_millis(5)).unwrap();
        release.join().unwrap();
        assert!(acquired.waited && acquired.warning.is_none());
    }
}
