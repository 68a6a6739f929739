//! Formatting shared by the subcommands: numbers, matrices, JSON values, the failure type.

use std::fmt;

use nalgebra::Vector3;
use screwkit_lie::display::{fixed, fixed_list};
use screwkit_lie::Se3;
use serde_json::Value;

/// Decimals in human-readable output.
pub const PREC: usize = 6;

/// A failed operation: printed as one line on stderr, exit code 1.
#[derive(Debug)]
pub struct Failure(pub String);

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// Errors shown as their message.
macro_rules! shown_as_message {
    ($($t:ty),+) => {
        $(impl From<$t> for Failure {
            fn from(e: $t) -> Self {
                Failure(e.to_string())
            }
        })+
    };
}
shown_as_message!(
    screwkit_model::ModelError,
    screwkit_solve::SolveError,
    screwkit_lie::LieError,
    screwkit_reach::ReachError,
    screwkit_service::io::FileError,
    screwkit_service::WordError
);

impl From<screwkit_service::Error> for Failure {
    /// The floor's errors, an option named as its flag (`tool` → `--tool`).
    fn from(e: screwkit_service::Error) -> Self {
        match e {
            screwkit_service::Error::Option { name, message } => {
                Failure(format!("--{}: {message}", name.replace('_', "-")))
            }
            e => Failure(e.to_string()),
        }
    }
}

/// Result of a subcommand.
pub type CliResult<T = ()> = Result<T, Failure>;

pub use screwkit_service::io::json::{num, nums};

/// A pose as a JSON 4x4 array of rows.
pub fn pose_json(t: &Se3) -> Value {
    let m = t.to_homogeneous();
    Value::Array(
        (0..4)
            .map(|i| nums(&[m[(i, 0)], m[(i, 1)], m[(i, 2)], m[(i, 3)]]))
            .collect(),
    )
}

/// `(a, b, c)` with [`PREC`] decimals.
pub fn tuple(xs: &[f64]) -> String {
    format!("({})", fixed_list(xs, PREC))
}

/// A 4x4 pose, one bracketed row per line, columns aligned.
pub fn matrix_text(t: &Se3) -> String {
    let m = t.to_homogeneous();
    let cells: Vec<Vec<String>> = (0..4)
        .map(|i| (0..4).map(|j| fixed(m[(i, j)], PREC)).collect())
        .collect();
    let w = cells.iter().flatten().map(String::len).max().unwrap_or(1);
    cells
        .iter()
        .map(|r| {
            format!(
                "[{}]\n",
                r.iter()
                    .map(|c| format!("{c:>w$}"))
                    .collect::<Vec<_>>()
                    .join("  ")
            )
        })
        .collect()
}

/// Position, quaternion (x, y, z, w) and URDF rpy of a pose, one per line.
pub fn pose_summary(t: &Se3) -> String {
    let p: &Vector3<f64> = t.translation();
    format!(
        "position (m)          {}\nquaternion (x,y,z,w)  {}\nrpy (rad)             {}\n",
        tuple(p.as_slice()),
        tuple(&t.quaternion()),
        tuple(&t.rpy())
    )
}

/// Prints a JSON value on one line.
pub fn print_json(v: &Value) -> CliResult {
    emit(&format!("{v}\n"))
}

/// The failure message of a closed standard output (`screwkit info … | head -1`): `main` ends
/// quietly with exit code 0 on it, as other Unix tools end quietly.
pub const CLOSED_PIPE: &str = "standard output closed";

/// A write error on standard output as a failure: a closed pipe is [`CLOSED_PIPE`], anything
/// else (a full disk: `> /dev/full`) names the error.
pub fn write_error(e: std::io::Error) -> Failure {
    if e.kind() == std::io::ErrorKind::BrokenPipe {
        Failure(CLOSED_PIPE.into())
    } else {
        Failure(format!("cannot write the output: {e}"))
    }
}

/// Writes `s` to standard output and flushes it (every non-batch result goes through here).
pub fn emit(s: &str) -> CliResult {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    out.write_all(s.as_bytes())
        .and_then(|()| out.flush())
        .map_err(write_error)
}
