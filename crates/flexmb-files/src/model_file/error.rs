//! The error of the model-file layer: which file, which key, which line, and what was expected.

use std::fmt;

/// What kind of problem a model file has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file could not be read.
    Io,
    /// The text is not valid TOML.
    Syntax,
    /// A key is unknown, missing or holds a value of the wrong type.
    Schema,
    /// A value is out of range, a name refers to nothing, an expression does not parse, or the engine
    /// rejects the model.
    Invalid,
}

/// A problem in a model file, located by file name, TOML key path and 1-based line.
///
/// Displays as `models/x.toml:12: body[2].mass: mass must be positive and finite, got -1`. Arrays of
/// tables are indexed from 0 in the key path (`joint[3]` is the fourth `[[joint]]`).
#[derive(Clone, Debug, PartialEq)]
pub struct ModelFileError {
    /// What kind of problem: unreadable, not TOML, invalid values, …
    pub kind: ErrorKind,
    /// The file name as given to [`load_model`](super::load_model) or [`parse_model`](super::parse_model).
    pub file: String,
    /// 1-based line; `None` only when the file could not be read.
    pub line: Option<usize>,
    /// TOML key path such as `joint[3].i`; empty when the problem concerns the whole file.
    pub key_path: String,
    /// What is wrong and what was expected.
    pub message: String,
}

impl fmt::Display for ModelFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        write!(f, ": ")?;
        if !self.key_path.is_empty() {
            write!(f, "{}: ", self.key_path)?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for ModelFileError {}
