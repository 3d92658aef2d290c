//! Guards on what users give flexmb, shared by the `.inp` reader of this crate and the model-file
//! readers of the `flexmb` program (which depends on this crate, not the other way round):
//!
//! * [`mod@file`]: every input file is read by [`read_file`] or [`read_text`], which refuse what is not
//!   a regular file (a directory, `/dev/zero`, a pipe) and stop at a size limit, so that no path
//!   makes a command hang or exhaust memory;
//! * [`magnitude`]: the windows of physical magnitudes a value read from a file must lie in (a mass,
//!   a length, Young's modulus …), so that an absurd number is refused at its key or line instead of
//!   surfacing later as a singular matrix.

pub mod file;
pub mod magnitude;

pub use file::{check_file, max_file_size, parse_size, read_file, read_text, InputFileError, DEFAULT_MAX_FILE_SIZE, MAX_FILE_SIZE_VARIABLE};
pub use magnitude::Quantity;
