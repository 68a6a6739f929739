//! Errors of the Lie-group crate.

use thiserror::Error;

/// What can be wrong with the input of a checked constructor.
///
/// The hot-path functions (`exp`, `log`, composition) never return errors: given finite input
/// they return finite output, given non-finite input they return non-finite output and never
/// panic. Validation happens once, at the boundary, through the constructors that return
/// `Result<_, LieError>`.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LieError {
    /// A NaN or infinity where a finite number is required.
    #[error("{what} contains a non-finite number (NaN or infinity)")]
    NonFinite {
        /// Which input (e.g. "rotation matrix", "twist").
        what: &'static str,
    },
    /// The 3x3 block is not a rotation: not orthonormal within the tolerance, or det ≠ +1.
    #[error(
        "not a rotation matrix: max |RᵀR − I| = {orthogonality_error:.3e} (tolerance {tolerance:.1e}), det R = {det:.6}"
    )]
    NotARotation {
        /// Largest entry of |RᵀR − I|.
        orthogonality_error: f64,
        /// Determinant of R (must be +1).
        det: f64,
        /// The tolerance that was applied.
        tolerance: f64,
    },
    /// The last row of a homogeneous transform is not `[0, 0, 0, 1]`.
    #[error("the last row of a homogeneous transform must be [0, 0, 0, 1], got {row:?}")]
    BadLastRow {
        /// The row that was found.
        row: [f64; 4],
    },
    /// A vector that must have a direction has (numerically) zero length.
    #[error("{what} has zero length")]
    ZeroVector {
        /// Which input (e.g. "screw direction", "quaternion").
        what: &'static str,
    },
    /// A slice has the wrong number of entries.
    #[error("{what} needs {expected} numbers, got {got}")]
    WrongLength {
        /// Which input.
        what: &'static str,
        /// How many numbers it needs.
        expected: usize,
        /// How many it got.
        got: usize,
    },
    /// An argument outside the values it may take (a trajectory's duration, sample count or
    /// time-scaling method).
    #[error("{what}")]
    OutOfRange {
        /// What is wrong, naming the argument.
        what: String,
    },
}
