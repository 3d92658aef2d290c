//! Running one `flexmb` command as a new user would, bounded in wall-clock time and in memory, and
//! saying how it ended.

use std::io::Read;
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// How a command ended. Everything but `Success`, `CleanError` and `Known` fails the fuzz test.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// Exit status 0 and nothing suspicious in what it printed and wrote.
    Success,
    /// Exit status 1 (2 for a command line clap refuses) with an `error:` line and no panic.
    CleanError,
    /// A failure the allow-list of `known.rs` names (a finding another branch fixes).
    Known,
    /// Exit status 0, but a result that cannot be right: a non-finite number printed or written, a
    /// run that did not reach its end time, an empty model passed as valid, a plot of non-finite data.
    Suspicious,
    /// Exit status 101 or "panicked" on standard error.
    Panic,
    /// Killed by a signal (abort, segmentation fault) other than the harness's timeout.
    Signal,
    /// An allocation refused by the memory bound (Rust aborts on it).
    OutOfMemory,
    /// Still running at the wall-clock bound: killed.
    Timeout,
    /// Any other exit status, or a failure without an `error:` line.
    UncleanExit,
}

impl Class {
    pub fn fails(self) -> bool {
        !matches!(self, Class::Success | Class::CleanError | Class::Known)
    }

    pub const ALL: [Class; 9] = [
        Class::Success,
        Class::CleanError,
        Class::Known,
        Class::Suspicious,
        Class::Panic,
        Class::Signal,
        Class::OutOfMemory,
        Class::Timeout,
        Class::UncleanExit,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Class::Success => "success",
            Class::CleanError => "clean error",
            Class::Known => "known finding",
            Class::Suspicious => "suspicious success",
            Class::Panic => "panic",
            Class::Signal => "signal",
            Class::OutOfMemory => "out of memory",
            Class::Timeout => "timeout",
            Class::UncleanExit => "unclean exit",
        }
    }
}

/// The wall-clock and memory bounds of one command.
#[derive(Clone, Debug)]
pub struct Bounds {
    pub time: Duration,
    /// The virtual memory the command may map (`ulimit -v`), when `sh` can set it.
    pub memory_bytes: Option<u64>,
}

/// What one command did.
#[derive(Clone, Debug)]
pub struct Ran {
    pub args: Vec<String>,
    pub class: Class,
    /// Why it is in its class (the signal, the suspicious value, …).
    pub detail: String,
    pub stdout: String,
    pub stderr: String,
    pub seconds: f64,
}

/// The memory limit the dense initial-condition analyses are given, so that a large model is refused
/// with what it needs before the harness's harder bound aborts it.
pub const DENSE_ANALYSIS_MEMORY: &str = "512M";

/// Whether `sh -c 'ulimit -v …'` works here (Linux, macOS), so that commands run with a memory bound.
pub fn memory_bound_available() -> bool {
    Command::new("sh")
        .args(["-c", "ulimit -v 4000000 && exec true"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Runs `flexmb ARGS` in `dir` within `bounds`; standard output and error go to files in `dir` (no pipe
/// to fill up), of which the first megabyte is kept.
pub fn run_flexmb(dir: &Path, args: &[String], bounds: &Bounds) -> Ran {
    let flexmb = env!("CARGO_BIN_EXE_flexmb");
    let mut command = match bounds.memory_bytes {
        Some(bytes) => {
            let mut c = Command::new("sh");
            c.args(["-c", "ulimit -v \"$0\" && exec \"$@\""]).arg((bytes / 1024).to_string()).arg(flexmb);
            c
        }
        None => Command::new(flexmb),
    };
    let (out_path, err_path) = (dir.join(".fuzz-stdout"), dir.join(".fuzz-stderr"));
    let start = Instant::now();
    let child = command
        .args(args)
        .current_dir(dir)
        .env("FLEXMB_MEMORY_LIMIT", DENSE_ANALYSIS_MEMORY)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out_path).expect("stdout file"))
        .stderr(std::fs::File::create(&err_path).expect("stderr file"))
        .spawn();
    let mut child = child.unwrap_or_else(|e| panic!("cannot start {flexmb}: {e}"));
    let mut pause = Duration::from_micros(500);
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for flexmb") {
            break Some(status);
        }
        if start.elapsed() > bounds.time {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(pause);
        pause = (pause * 2).min(Duration::from_millis(10));
    };
    let seconds = start.elapsed().as_secs_f64();
    let (stdout, stderr) = (head(&out_path), head(&err_path));
    let (class, detail) = match status {
        None => (Class::Timeout, format!("still running after {:.1} s: killed", bounds.time.as_secs_f64())),
        Some(status) => classify(status, &stderr),
    };
    Ran { args: args.to_vec(), class, detail, stdout, stderr, seconds }
}

/// The first megabyte of a file, as text.
fn head(path: &Path) -> String {
    let mut bytes = Vec::new();
    if let Ok(f) = std::fs::File::open(path) {
        let _ = f.take(1 << 20).read_to_end(&mut bytes);
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

fn classify(status: ExitStatus, stderr: &str) -> (Class, String) {
    if stderr.contains("panicked") {
        return (Class::Panic, first_line_with(stderr, "panicked"));
    }
    match status.code() {
        Some(0) => (Class::Success, String::new()),
        Some(1 | 2) if stderr.lines().any(|l| l.starts_with("error:")) => (Class::CleanError, String::new()),
        Some(101) => (Class::Panic, "exit status 101".into()),
        Some(code) => (Class::UncleanExit, format!("exit status {code} without an error: line")),
        None if stderr.contains("memory allocation of") => {
            (Class::OutOfMemory, first_line_with(stderr, "memory allocation of"))
        }
        None => (Class::Signal, signal_of(status)),
    }
}

fn first_line_with(text: &str, what: &str) -> String {
    text.lines().find(|l| l.contains(what)).unwrap_or_default().to_string()
}

#[cfg(unix)]
fn signal_of(status: ExitStatus) -> String {
    use std::os::unix::process::ExitStatusExt;
    format!("killed by signal {}", status.signal().unwrap_or(0))
}

#[cfg(not(unix))]
fn signal_of(status: ExitStatus) -> String {
    format!("ended without an exit status: {status}")
}
