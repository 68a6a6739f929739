//! Errors of the solver crate: bad input (the caller's to fix) or a numerical failure.

use thiserror::Error;

/// What went wrong in a solver call.
///
/// [`SolveError::is_invalid_input`] sorts the variants: everything but
/// [`SolveError::Numerical`] is a problem with the input (a binding maps it to `ValueError`).
/// An IK solve that does not converge is not an error but a result with `converged = false`.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolveError {
    /// A slice of the wrong length.
    #[error("expected {expected} {what} ({names}), got {got}")]
    WrongLength {
        /// What the slice holds ("joint values", …).
        what: &'static str,
        /// Expected count.
        expected: usize,
        /// Given count.
        got: usize,
        /// The expected entries' names (or the shape expected).
        names: String,
    },
    /// A NaN or infinity in the input.
    #[error("{what} #{index} ({name}) is not finite: {value}")]
    NonFinite {
        /// What the slice holds.
        what: &'static str,
        /// Index of the bad entry.
        index: usize,
        /// Its name.
        name: String,
        /// The value.
        value: f64,
    },
    /// A target pose that is not a finite rigid transform.
    #[error("the target pose is not a finite rigid transform: {0}")]
    BadTarget(BadTarget),
    /// Any other input the call cannot take (a non-square Jacobian for an exact solve, a
    /// damping that is not positive, …), said in words.
    #[error("{0}")]
    InvalidInput(String),
    /// A numerical failure on valid input: an SVD that did not converge, a singular square
    /// Jacobian, a system that is not positive definite.
    #[error("{0}")]
    Numerical(String),
    /// Rows of a batch that failed, in row order (0-based); every other row was computed.
    #[error("{}", rows_message(.0))]
    Rows(Vec<RowError>),
}

/// Why a target pose is refused ([`SolveError::BadTarget`]).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BadTarget {
    /// It holds NaN or infinity.
    #[error("it holds NaN or infinity")]
    NonFinite,
    /// Its numbers are not a rigid transform (the checked constructor's reason: not a rotation
    /// within the tolerance, a last row other than (0, 0, 0, 1), a wrong count).
    #[error("{0}")]
    NotRigid(#[from] screwkit_lie::LieError),
}

/// One failed row of a batch.
#[derive(Debug, Clone, PartialEq)]
pub struct RowError {
    /// The row's index (0-based) in the batch.
    pub row: usize,
    /// What was wrong with it.
    pub error: SolveError,
}

fn rows_message(rows: &[RowError]) -> String {
    match rows {
        [] => "no failed rows".into(),
        [one] => format!("row {}: {}", one.row, one.error),
        [first, rest @ ..] => format!(
            "row {}: {} (and {} more failed row(s))",
            first.row,
            first.error,
            rest.len()
        ),
    }
}

impl SolveError {
    /// True when the input was at fault (wrong length, NaN, a bad target, failed batch rows that
    /// were all bad input), false for a numerical failure.
    pub fn is_invalid_input(&self) -> bool {
        match self {
            SolveError::Numerical(_) => false,
            SolveError::Rows(rows) => rows.iter().all(|r| r.error.is_invalid_input()),
            _ => true,
        }
    }
}
