//! The one home of file formats and output rules shared by the front ends and the maps:
//! numpy's `.npy`/`.npz` ([`npz`]), outputs written whole or not at all ([`atomic`]), and the
//! JSON number rule ([`json`]).

pub mod atomic;
pub mod json;
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
