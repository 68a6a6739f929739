//! The floor's errors: typed, so each front end decides how to show them (the CLI one line,
//! Python the matching exception) without reading messages.

use std::path::PathBuf;

use screwkit_model::ModelError;
use screwkit_solve::SolveError;

use crate::io::FileError;
use crate::words::WordError;

/// What went wrong in a floor call.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A robot file (or standard input) that could not be read; `source` is the operating
    /// system's error (Python raises the matching `OSError` subclass).
    #[error("{}: cannot read the file: {source}", .path.display())]
    Io {
        /// The file (`<stdin>` for standard input).
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A bad robot file, link or chain request.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// A solver refused its input (or failed numerically).
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// An input or output file (`.npy`, `.npz`, a picture) that could not be read or written,
    /// or is not what it should be.
    #[error(transparent)]
    File(#[from] FileError),
    /// A body query that cannot run (a geometry problem, a mesh, an unknown link).
    #[error(transparent)]
    Collision(screwkit_collision::CollisionError),
    /// An option word that is not one of its family's.
    #[error(transparent)]
    Word(#[from] WordError),
    /// An option's value that cannot be used; `name` is the option's neutral name (`tool`,
    /// `lock`, `weights`), which the CLI shows as `--tool` and Python as the keyword.
    #[error("{name}: {message}")]
    Option {
        /// The option.
        name: &'static str,
        /// What is wrong with its value.
        message: String,
    },
}

impl From<screwkit_collision::CollisionError> for Error {
    fn from(e: screwkit_collision::CollisionError) -> Error {
        match e {
            screwkit_collision::CollisionError::Solve(s) => Error::Solve(s),
            e => Error::Collision(e),
        }
    }
}

impl Error {
    /// A bad value of option `name`.
    pub fn option(name: &'static str, message: impl Into<String>) -> Error {
        Error::Option {
            name,
            message: message.into(),
        }
    }

    /// True when the caller's input is at fault (everything but a numerical failure and an
    /// I/O error).
    pub fn is_invalid_input(&self) -> bool {
        match self {
            Error::Solve(e) => e.is_invalid_input(),
            Error::Io { .. } => false,
            Error::File(FileError::Io { .. }) => false,
            _ => true,
        }
    }
}

/// A floor result.
pub type Result<T, E = Error> = std::result::Result<T, E>;
