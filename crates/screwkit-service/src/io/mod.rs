//! The one home of file formats and output rules shared by the front ends and the maps:
//! numpy's `.npy`/`.npz` ([`npz`]), outputs written whole or not at all ([`atomic`]), and the
//! JSON number rule ([`json`]), motions to play back ([`motion`]).

pub mod atomic;
pub mod json;
pub mod motion;
pub mod npy;
pub mod npz;

/// A file that could not be read or written, or that is not what it should be.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The operating system refused (`source` keeps its kind).
    #[error("{path}: {}{source}", if .doing.is_empty() { String::new() } else { format!("{}: ", .doing) })]
    Io {
        /// The file.
        path: String,
        /// What was being done ("cannot read the file", "cannot write"; may be empty).
        doing: &'static str,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The file's contents are not what they should be (not an `.npy`, a damaged archive, a
    /// shard of another map, …), said with the file's name.
    #[error("{0}")]
    Format(String),
}

/// Values as their little-endian bytes (the `.npy` data of `<f8` / `<i8`).
pub(crate) fn le_bytes<const N: usize, T: Copy>(
    values: &[T],
    to: impl Fn(T) -> [u8; N],
) -> Vec<u8> {
    let mut bytes = Vec::with_capacity(values.len() * N);
    for &v in values {
        bytes.extend_from_slice(&to(v));
    }
    bytes
}

/// Little-endian 8-byte values from bytes (a trailing partial value is dropped).
pub(crate) fn from_le8<T>(bytes: &[u8], from: impl Fn([u8; 8]) -> T) -> Vec<T> {
    bytes
        .chunks_exact(8)
        .map(|b| from(b.try_into().unwrap_or([0; 8])))
        .collect()
}

impl FileError {
    /// An I/O error on `path`.
    pub fn io(path: &str, source: std::io::Error) -> FileError {
        FileError::Io {
            path: path.to_string(),
            doing: "",
            source,
        }
    }

    /// An I/O error on `path` while `doing` something ("cannot write").
    pub fn io_doing(path: &str, doing: &'static str, source: std::io::Error) -> FileError {
        FileError::Io {
            path: path.to_string(),
            doing,
            source,
        }
    }
}
