//! Reading an input file: a regular file (after following symbolic links) of at most
//! [`max_file_size`] bytes. A device such as `/dev/zero`, a directory or a named pipe is refused
//! before it is read, and no more than the limit plus one byte is ever read, so even a file that
//! grows while it is read, or reports a size it does not have, cannot exhaust memory.

use std::fs::{File, FileType};
use std::io::Read;
use std::path::Path;

/// The largest file read when [`MAX_FILE_SIZE_VARIABLE`] is not set: 1 GiB.
pub const DEFAULT_MAX_FILE_SIZE: u64 = 1 << 30;

/// The environment variable that sets the largest file read, in bytes, optionally with the suffix
/// `k`, `M` or `G` (times 1024, 1024², 1024³): `FLEXMB_MAX_FILE_SIZE=4G`.
pub const MAX_FILE_SIZE_VARIABLE: &str = "FLEXMB_MAX_FILE_SIZE";

/// Why an input file was not read. The message says what the file is or what went wrong, without
/// its path: the caller names the file (and what it is for) in its own error.
#[derive(Debug, thiserror::Error)]
pub enum InputFileError {
    /// The operating system's error: no such file, no permission, …
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The path names something that is not a regular file.
    #[error("it is {kind}, not a regular file")]
    NotRegular {
        /// What it is: a directory, a device, ….
        kind: &'static str,
    },
    /// The file is larger than the limit.
    #[error(
        "it is larger than {} (the limit on input files); set {MAX_FILE_SIZE_VARIABLE} to a larger size \
         in bytes, or with k, M or G (e.g. {MAX_FILE_SIZE_VARIABLE}=4G), to read it",
        size_text(*limit)
    )]
    TooLarge {
        /// The limit (bytes).
        limit: u64,
    },
    /// [`MAX_FILE_SIZE_VARIABLE`] does not hold a size.
    #[error(
        "{MAX_FILE_SIZE_VARIABLE}=`{value}` is not a size: expected a whole number of bytes, optionally \
         followed by k, M or G (times 1024, 1024², 1024³), e.g. 2G"
    )]
    BadLimit {
        /// The variable's value.
        value: String,
    },
    /// The file is not UTF-8 text (from [`read_text`]).
    #[error("it is not UTF-8 text: {0}")]
    NotText(std::str::Utf8Error),
}

/// The bytes of the input file at `path`: a regular file (symbolic links are followed) of at most
/// [`max_file_size`] bytes.
pub fn read_file(path: &Path) -> Result<Vec<u8>, InputFileError> {
    read_file_within(path, max_file_size()?)
}

/// Whether [`read_file`] would read the file at `path`: whether it is a regular file within the
/// size limit. Nothing is opened, so a named pipe does not block.
pub fn check_file(path: &Path) -> Result<(), InputFileError> {
    let limit = max_file_size()?;
    let metadata = std::fs::metadata(path)?;
    check_regular(metadata.file_type())?;
    if metadata.len() > limit {
        return Err(InputFileError::TooLarge { limit });
    }
    Ok(())
}

/// [`read_file`] with the limit `limit` (bytes).
fn read_file_within(path: &Path, limit: u64) -> Result<Vec<u8>, InputFileError> {
    // The type is checked before the file is opened: opening a named pipe would wait for a writer.
    check_regular(std::fs::metadata(path)?.file_type())?;
    let file = File::open(path)?;
    let metadata = file.metadata()?;
    check_regular(metadata.file_type())?;
    if metadata.len() > limit {
        return Err(InputFileError::TooLarge { limit });
    }
    let mut bytes = Vec::with_capacity(usize::try_from(metadata.len()).unwrap_or(0));
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(InputFileError::TooLarge { limit });
    }
    Ok(bytes)
}

/// The text of the input file at `path`, as [`read_file`] reads it; it must be UTF-8.
pub fn read_text(path: &Path) -> Result<String, InputFileError> {
    String::from_utf8(read_file(path)?).map_err(|e| InputFileError::NotText(e.utf8_error()))
}

/// The largest input file read, in bytes: [`MAX_FILE_SIZE_VARIABLE`] if set, else
/// [`DEFAULT_MAX_FILE_SIZE`].
pub fn max_file_size() -> Result<u64, InputFileError> {
    match std::env::var(MAX_FILE_SIZE_VARIABLE) {
        Ok(value) => parse_size(&value).ok_or(InputFileError::BadLimit { value }),
        Err(std::env::VarError::NotPresent) => Ok(DEFAULT_MAX_FILE_SIZE),
        Err(std::env::VarError::NotUnicode(value)) => {
            Err(InputFileError::BadLimit { value: value.to_string_lossy().into_owned() })
        }
    }
}

/// `"1500"`, `"64k"`, `"512M"`, `"4G"` (binary multiples; the suffix in either case): the sizes
/// flexmb's environment variables take.
pub fn parse_size(text: &str) -> Option<u64> {
    let text = text.trim();
    let (digits, factor) = match text.char_indices().last()? {
        (i, 'k' | 'K') => (&text[..i], 1 << 10),
        (i, 'm' | 'M') => (&text[..i], 1 << 20),
        (i, 'g' | 'G') => (&text[..i], 1 << 30),
        _ => (text, 1),
    };
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse::<u64>().ok()?.checked_mul(factor)
}

/// A size as the user would write it: `1 GiB`, `64 kiB`, or bytes.
fn size_text(bytes: u64) -> String {
    let units = [(1 << 30, "GiB"), (1 << 20, "MiB"), (1 << 10, "kiB")];
    match units.iter().find(|(size, _)| bytes >= *size && bytes % size == 0) {
        Some((size, unit)) => format!("{} {unit}", bytes / size),
        None => format!("{bytes} bytes"),
    }
}

fn check_regular(file_type: FileType) -> Result<(), InputFileError> {
    if file_type.is_file() {
        return Ok(());
    }
    Err(InputFileError::NotRegular { kind: kind_of(file_type) })
}

/// What a file that is not a regular file is, in words.
#[cfg(unix)]
fn kind_of(file_type: FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt;
    if file_type.is_dir() {
        "a directory"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_fifo() {
        "a named pipe (FIFO)"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "a special file"
    }
}

#[cfg(not(unix))]
fn kind_of(file_type: FileType) -> &'static str {
    if file_type.is_dir() {
        "a directory"
    } else {
        "a special file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_bytes_or_binary_multiples() {
        assert_eq!(parse_size("1500"), Some(1500));
        assert_eq!(parse_size("64k"), Some(64 << 10));
        assert_eq!(parse_size(" 512M "), Some(512 << 20));
        assert_eq!(parse_size("4G"), Some(4 << 30));
        for bad in ["", "G", "1.5G", "-1", "12T", "1 G", "0x10"] {
            assert_eq!(parse_size(bad), None, "{bad}");
        }
        assert_eq!(parse_size("99999999999999G"), None, "overflow");
        assert_eq!(size_text(DEFAULT_MAX_FILE_SIZE), "1 GiB");
        assert_eq!(size_text(100), "100 bytes");
    }

    #[test]
    fn directories_and_devices_are_refused_by_kind() {
        let e = read_file(Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap_err().to_string();
        assert_eq!(e, "it is a directory, not a regular file");
        #[cfg(unix)]
        {
            let e = read_file(Path::new("/dev/zero")).unwrap_err().to_string();
            assert_eq!(e, "it is a character device, not a regular file");
        }
        let e = read_file(Path::new("no/such/file.inp")).unwrap_err();
        assert!(matches!(e, InputFileError::Io(_)), "{e}");
    }

    #[test]
    fn no_more_than_the_limit_is_read() {
        let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("Cargo.toml");
        let size = std::fs::metadata(&manifest).unwrap().len();
        assert_eq!(read_file_within(&manifest, size).unwrap().len() as u64, size, "a file of the limit's size is read");
        let e = read_file_within(&manifest, size - 1).unwrap_err().to_string();
        assert!(e.starts_with(&format!("it is larger than {} bytes (the limit", size - 1)), "{e}");
        #[cfg(target_os = "linux")]
        {
            // A regular file that reports a size of 0 and holds more: only the limit and a byte are read.
            let e = read_file_within(Path::new("/proc/self/status"), 10).unwrap_err();
            assert!(matches!(e, InputFileError::TooLarge { limit: 10 }), "{e}");
        }
    }
}
