//! The text of a model file and its name: turns byte offsets into lines and makes located errors.

use std::ops::Range;

use super::error::{ErrorKind, ModelFileError};
use super::key_path::KeyPath;

/// Reads the text of the `what` file ("model", "FE model", "study") at `path` as every input file is
/// read ([`flexmb_fem::input::read_text`]: a regular file within the size limit, UTF-8), with an I/O
/// error that names the file when it cannot be read.
pub(crate) fn read_text_file(path: &std::path::Path, what: &str) -> Result<String, ModelFileError> {
    flexmb_fem::input::read_text(path).map_err(|e| ModelFileError {
        kind: ErrorKind::Io,
        file: path.display().to_string(),
        line: None,
        key_path: String::new(),
        message: format!("cannot read the {what} file: {e}"),
    })
}

/// A model file's name and text, with the byte offset at which each line starts.
pub(crate) struct Source<'a> {
    file: &'a str,
    text: &'a str,
    line_starts: Vec<usize>,
}

impl<'a> Source<'a> {
    pub(crate) fn new(file: &'a str, text: &'a str) -> Self {
        let line_starts = std::iter::once(0).chain(text.match_indices('\n').map(|(i, _)| i + 1)).collect();
        Self { file, text, line_starts }
    }

    /// The file name as shown in messages.
    pub(crate) fn file(&self) -> &'a str {
        self.file
    }

    pub(crate) fn text(&self) -> &'a str {
        self.text
    }

    /// The 1-based line holding byte `offset` (offsets past the end fall on the last line).
    pub(crate) fn line(&self, offset: usize) -> usize {
        self.line_starts.partition_point(|&start| start <= offset).max(1)
    }

    /// An error at the start of `span`.
    pub(crate) fn error(
        &self,
        kind: ErrorKind,
        span: &Range<usize>,
        key: &KeyPath,
        message: impl Into<String>,
    ) -> ModelFileError {
        ModelFileError {
            kind,
            file: self.file.to_string(),
            line: Some(self.line(span.start)),
            key_path: key.as_str().to_string(),
            message: message.into(),
        }
    }

    /// A semantic error (a value out of range, an unknown name, an engine rejection).
    pub(crate) fn invalid(&self, span: &Range<usize>, key: &KeyPath, message: impl Into<String>) -> ModelFileError {
        self.error(ErrorKind::Invalid, span, key, message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_map_to_one_based_lines() {
        let s = Source::new("f.toml", "a = 1\nb = 2\n\nc = 3");
        assert_eq!(s.line(0), 1);
        assert_eq!(s.line(5), 1); // the newline ends line 1
        assert_eq!(s.line(6), 2);
        assert_eq!(s.line(12), 3);
        assert_eq!(s.line(13), 4);
        assert_eq!(s.line(100), 4);
    }
}
