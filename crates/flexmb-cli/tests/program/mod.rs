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
