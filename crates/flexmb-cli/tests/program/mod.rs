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
