//! ParaView's `.pvd` index of a time series: a `Collection` of `DataSet` entries, each naming a file,
//! its time (`timestep`), its block (`part`) and the block's `name`, which ParaView shows as the block's
//! name when several parts share a time. Entries are added as frames are written; each addition
//! writes the new entries and the closing tags over the old closing tags in one write, so that the file
//! is a complete index after every frame and a run that stops leaves a series ParaView opens.

use std::fmt::Write as _;
use std::fs::File;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

const HEADER: &str = "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
                      byte_order=\"LittleEndian\">\n  <Collection>\n";
const TRAILER: &str = "  </Collection>\n</VTKFile>\n";

/// One file of the series.
#[derive(Clone, Copy, Debug)]
pub struct PvdEntry<'a> {
    /// The frame's time (s).
    pub time: f64,
    /// The block's index within the frame.
    pub part: usize,
    /// The block's name, shown by ParaView.
    pub name: &'a str,
    /// Relative to the `.pvd` file's directory, with `/` separators.
    pub file: &'a str,
}

/// A `.pvd` file being written.
pub struct PvdFile {
    path: PathBuf,
    file: File,
    /// Where the closing tags start.
    end: u64,
}

impl PvdFile {
    /// Creates an empty collection at `path`.
    pub fn create(path: &Path) -> std::io::Result<Self> {
        let mut file = File::create(path)?;
        file.write_all(format!("{HEADER}{TRAILER}").as_bytes())?;
        Ok(Self { path: path.to_path_buf(), file, end: HEADER.len() as u64 })
    }

    /// Adds `entries` at the end of the collection.
    pub fn append(&mut self, entries: &[PvdEntry]) -> std::io::Result<()> {
        let mut text = String::new();
        for e in entries {
            let _ = writeln!(
                text,
                "    <DataSet timestep=\"{}\" part=\"{}\" name=\"{}\" file=\"{}\"/>",
                e.time,
                e.part,
                escaped(e.name),
                escaped(e.file)
            );
        }
        let added = text.len() as u64;
        text.push_str(TRAILER);
        self.file.seek(SeekFrom::Start(self.end))?;
        self.file.write_all(text.as_bytes())?;
        self.file.flush()?;
        self.end += added;
        Ok(())
    }

    /// The `.pvd` file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// `text` as an XML attribute value.
fn escaped(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

/// `name` reduced to letters, digits, `-`, `_` and `.`, for a file name.
pub fn file_safe(name: &str) -> String {
    name.chars().map(|c| if c.is_ascii_alphanumeric() || "-_.".contains(c) { c } else { '_' }).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_index_is_complete_after_every_append() {
        let dir = std::env::temp_dir().join(format!("flexmb-pvd-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("series.pvd");
        let mut pvd = PvdFile::create(&path).unwrap();
        let read = || std::fs::read_to_string(&path).unwrap();
        assert_eq!(read(), format!("{HEADER}{TRAILER}"));
        pvd.append(&[PvdEntry { time: 0.0, part: 0, name: "a<b", file: "s/a_000000.vtu" }]).unwrap();
        pvd.append(&[
            PvdEntry { time: 0.5, part: 0, name: "a<b", file: "s/a_000001.vtu" },
            PvdEntry { time: 0.5, part: 1, name: "j \"1\"", file: "s/j_000001.vtu" },
        ])
        .unwrap();
        let text = read();
        assert!(text.ends_with(TRAILER) && text.starts_with(HEADER));
        assert_eq!(text.matches("<DataSet ").count(), 3);
        assert!(
            text.contains("<DataSet timestep=\"0.5\" part=\"1\" name=\"j &quot;1&quot;\" file=\"s/j_000001.vtu\"/>")
        );
        assert!(text.contains("name=\"a&lt;b\""));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn file_names_keep_only_safe_characters() {
        assert_eq!(file_safe("crank pin/2"), "crank_pin_2");
        assert_eq!(file_safe("rod-1.a_b"), "rod-1.a_b");
    }
}
