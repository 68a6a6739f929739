//! Errors of the solver crate.

use thiserror::Error;

/// What is wrong with a solver call's input.
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
        /// The expected entries' names.
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
    #[error("the target pose is not finite")]
    BadTarget,
    /// A linear-algebra failure (SVD did not converge, singular square Jacobian, …).
    #[error("{0}")]
    Numerical(String),
}
