//! Running the `flexmb` program from the workspace root, as a new user would, for the command tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Runs `flexmb ARGS` in the workspace root.
pub fn flexmb(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_flexmb")).args(args).current_dir(workspace()).output().expect("flexmb runs")
}

pub fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An empty scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("flexmb-cli-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Runs flexmb and returns its standard output, failing the test with both streams if it fails.
pub fn succeed(args: &[&str]) -> String {
    let o = flexmb(args);
    assert!(o.status.success(), "flexmb {args:?}\nstdout:\n{}\nstderr:\n{}", text(&o.stdout), text(&o.stderr));
    text(&o.stdout)
}

/// Runs `flexmb run MODEL --integrator I --rtol T --atol T --quiet --out OUT` and any `extra` arguments;
/// it must succeed.
pub fn run_at_tolerance(model: &Path, integrator: &str, tolerance: &str, out: &Path, extra: &[&str]) -> String {
    let (model, out) = (model.to_str().unwrap(), out.to_str().unwrap());
    let mut args = vec!["run", model, "--integrator", integrator, "--rtol", tolerance, "--atol", tolerance, "--quiet", "--out", out];
    args.extend_from_slice(extra);
    succeed(&args)
}

/// Runs flexmb, which must fail without panicking, and returns its error message.
pub fn fail(args: &[&str]) -> String {
    let o = flexmb(args);
    assert!(!o.status.success(), "flexmb {args:?} should fail:\n{}", text(&o.stdout));
    let e = text(&o.stderr);
    assert!(!e.contains("panicked"), "{e}");
    e
}

/// A result CSV written by `flexmb run`: its header and rows.
pub struct ResultCsv {
    pub header: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl ResultCsv {
    pub fn read(path: &Path) -> Self {
        let csv = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut lines = csv.lines();
        let header = lines.next().unwrap().split(',').map(str::to_string).collect();
        let rows = lines.map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
        Self { header, rows }
    }

    /// The value of column `name` in row `row` (negative: counted from the end, −1 the last).
    pub fn at(&self, row: isize, name: &str) -> f64 {
        let k = self.header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {:?}", self.header));
        let r = if row < 0 { (self.rows.len() as isize + row) as usize } else { row as usize };
        self.rows[r][k]
    }

    /// The values of column `name`, one per row.
    pub fn column(&self, name: &str) -> Vec<f64> {
        let k = self.header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name} in {:?}", self.header));
        self.rows.iter().map(|r| r[k]).collect()
    }
}

/// The largest difference between two equally long series.
pub fn largest_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len(), "series of different lengths");
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// How long a command given hostile input may take before it counts as hanging.
pub const HANG_LIMIT: std::time::Duration = std::time::Duration::from_secs(30);

/// Runs `flexmb ARGS` with the extra environment `env`, as [`flexmb`] does, but kills it and fails the
/// test if it has not ended within [`HANG_LIMIT`] (polling `try_wait`). On Unix its address space is
/// limited to 4 GB (`ulimit -v`), so that a command that reads without bound fails instead of
/// exhausting the machine.
pub fn flexmb_within(args: &[&str], env: &[(&str, &str)]) -> Output {
    use std::io::Read;
    use std::process::Stdio;
    let binary = env!("CARGO_BIN_EXE_flexmb");
    let mut command = if cfg!(unix) {
        let mut c = Command::new("sh");
        c.arg("-c").arg("ulimit -v 4000000; exec \"$0\" \"$@\"").arg(binary);
        c
    } else {
        Command::new(binary)
    };
    let mut child = command
        .args(args)
        .envs(env.iter().copied())
        .current_dir(workspace())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("flexmb starts");
    // Read both streams as they come, so that a full pipe never stops the program.
    let drain = |mut pipe: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            let _ = pipe.read_to_end(&mut bytes);
            bytes
        })
    };
    let stdout = drain(Box::new(child.stdout.take().unwrap()));
    let stderr = drain(Box::new(child.stderr.take().unwrap()));
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("flexmb can be waited for") {
            break status;
        }
        if start.elapsed() > HANG_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            panic!("flexmb {args:?} did not end within {HANG_LIMIT:?}");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    };
    Output { status, stdout: stdout.join().unwrap(), stderr: stderr.join().unwrap() }
}

/// Runs flexmb as [`flexmb_within`] does; it must fail, without panicking (exit code 101), and end in
/// time. Returns its error message.
pub fn fail_within(args: &[&str], env: &[(&str, &str)]) -> String {
    let o = flexmb_within(args, env);
    let e = text(&o.stderr);
    assert!(!o.status.success(), "flexmb {args:?} should fail:\n{}", text(&o.stdout));
    assert_ne!(o.status.code(), Some(101), "flexmb {args:?} panicked: {e}");
    assert!(!e.contains("panicked"), "{e}");
    e
}
