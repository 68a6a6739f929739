//! The library's errors as Python exceptions.
//!
//! | Rust | Python |
//! |---|---|
//! | a file that cannot be read | `FileNotFoundError`, `PermissionError`, `IsADirectoryError` or `OSError` |
//! | `ModelError` (bad URDF, unknown link, no chain) | `ValueError` |
//! | `SolveError` on bad input (shape, NaN, bad target, bad option) | `ValueError` |
//! | `SolveError::Rows` (some rows of a batch) | `screwkit.BatchError` (a `ValueError`) carrying the finished result |
//! | `SolveError::Numerical` | `RuntimeError` |

use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyIsADirectoryError, PyOSError, PyPermissionError, PyRuntimeError,
    PyValueError,
};
use pyo3::prelude::*;
use screwkit_model::ModelError;
use screwkit_solve::SolveError;

create_exception!(
    screwkit,
    BatchError,
    PyValueError,
    "Some rows of a batch had bad input. Every other row was computed: `result` holds the whole \
     result (the bad rows NaN, or not converged for IK), `rows` the bad rows' indices (0-based) \
     and `messages` what was wrong with each."
);

/// A file that could not be read or written, as the matching `OSError` subclass.
pub fn io_error(path: &str, e: &std::io::Error) -> PyErr {
    let msg = format!("{path}: {e}");
    match e.kind() {
        std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err(msg),
        std::io::ErrorKind::PermissionDenied => PyPermissionError::new_err(msg),
        std::io::ErrorKind::IsADirectory => PyIsADirectoryError::new_err(msg),
        std::io::ErrorKind::InvalidData | std::io::ErrorKind::InvalidInput => {
            PyValueError::new_err(msg)
        }
        _ => PyOSError::new_err(msg),
    }
}

/// A floor error: an unreadable file → the matching `OSError` subclass; a bad file, option or
/// word → `ValueError` (an option named by its keyword); a solver error as [`solve_error`].
pub fn service_error(e: screwkit_service::Error) -> PyErr {
    use screwkit_service::Error;
    match e {
        Error::Io { path, source } => io_error(
            &format!("{}: cannot read the file", path.display()),
            &source,
        ),
        Error::Model(m) => model_error(m),
        Error::Solve(s) => solve_error(s),
        Error::File(f) => file_error(f),
        e => PyValueError::new_err(e.to_string()),
    }
}

/// A file that could not be read or written (the matching `OSError`), or is not what it should
/// be (`ValueError`).
pub fn file_error(e: screwkit_service::io::FileError) -> PyErr {
    use screwkit_service::io::FileError;
    match e {
        FileError::Io {
            path,
            doing,
            source,
        } => {
            let label = if doing.is_empty() {
                path
            } else {
                format!("{path}: {doing}")
            };
            io_error(&label, &source)
        }
        e => PyValueError::new_err(e.to_string()),
    }
}

/// A model error (bad file, unknown link, …) as `ValueError` with the library's message (an
/// unreadable include as the matching `OSError`).
pub fn model_error(e: ModelError) -> PyErr {
    match &e.kind {
        screwkit_model::ErrorKind::Io { kind, .. } if *kind != std::io::ErrorKind::InvalidData => {
            io_error(&e.file, &std::io::Error::new(*kind, e.kind.to_string()))
        }
        _ => PyValueError::new_err(e.to_string()),
    }
}

/// A solver error: `ValueError` for bad input, `RuntimeError` for a numerical failure.
/// (`Rows` is handled by the batch calls, which attach their result: [`batch_error`].)
pub fn solve_error(e: SolveError) -> PyErr {
    if e.is_invalid_input() {
        PyValueError::new_err(e.to_string())
    } else {
        PyRuntimeError::new_err(e.to_string())
    }
}

/// A `BatchError` for the bad rows of a stack (row index, message), with the whole result
/// attached (the bad rows NaN).
pub fn rows_error(
    py: Python<'_>,
    what: &str,
    bad: Vec<(usize, String)>,
    result: Bound<'_, PyAny>,
) -> PyErr {
    let more = match bad.len() {
        1 => String::new(),
        n => format!(" (and {} more failed row(s))", n - 1),
    };
    let err = BatchError::new_err(format!("{what}: row {}: {}{more}", bad[0].0, bad[0].1));
    attach(py, err, result, bad)
}

fn attach(
    py: Python<'_>,
    err: PyErr,
    result: Bound<'_, PyAny>,
    bad: Vec<(usize, String)>,
) -> PyErr {
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("result", result)?;
        value.setattr("rows", bad.iter().map(|r| r.0).collect::<Vec<_>>())?;
        value.setattr("messages", bad.into_iter().map(|r| r.1).collect::<Vec<_>>())?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(other) => other,
    }
}

/// The error of a batch call, with its result attached when only some rows failed.
pub fn batch_error(py: Python<'_>, e: SolveError, result: Bound<'_, PyAny>) -> PyErr {
    let SolveError::Rows(rows) = &e else {
        return solve_error(e);
    };
    let err = BatchError::new_err(e.to_string());
    let bad = rows.iter().map(|r| (r.row, r.error.to_string())).collect();
    attach(py, err, result, bad)
}
