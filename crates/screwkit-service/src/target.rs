//! IK targets as front ends take them — 16 numbers of the 4 × 4 matrix (row-major), or
//! x, y, z with a quaternion or URDF rpy — read once into an [`Se3`] under one tolerance:
//! max |RᵀR − I| ≤ [`TARGET_ROTATION_TOLERANCE`] (typed or rounded matrices), re-orthonormalised
//! ([`Se3::from_row_major`]).

use screwkit_lie::so3::TARGET_ROTATION_TOLERANCE;
use screwkit_lie::Se3;
use screwkit_solve::{BadTarget, SolveError};

use crate::error::{Error, Result};

/// A target from 16 numbers (row-major 4 × 4).
pub fn from_row_major(values: &[f64]) -> Result<Se3, SolveError> {
    Se3::from_row_major(values, TARGET_ROTATION_TOLERANCE)
        .map_err(|e| SolveError::BadTarget(BadTarget::NotRigid(e)))
}

/// A target from x, y, z, qx, qy, qz, qw (the quaternion normalised).
pub fn from_xyz_quat(values: &[f64]) -> Result<Se3> {
    let [x, y, z, qx, qy, qz, qw] = values else {
        return Err(count("target_xyz_quat", 7, values.len()));
    };
    Se3::from_translation_quaternion([*x, *y, *z], [*qx, *qy, *qz, *qw])
        .map_err(|e| Error::option("target_xyz_quat", e.to_string()))
}

/// A target from x, y, z, roll, pitch, yaw (URDF fixed-axis rpy).
pub fn from_xyz_rpy(values: &[f64]) -> Result<Se3> {
    let [x, y, z, r, p, w] = values else {
        return Err(count("target_xyz_rpy", 6, values.len()));
    };
    Se3::from_xyz_rpy([*x, *y, *z], [*r, *p, *w])
        .map_err(|e| Error::option("target_xyz_rpy", e.to_string()))
}

fn count(name: &'static str, n: usize, got: usize) -> Error {
    Error::option(name, format!("needs {n} numbers, got {got}"))
}

/// A pose's 16 numbers, row-major.
pub fn row_major(t: &Se3) -> [f64; 16] {
    let mut out = [0.0; 16];
    t.write_row_major(&mut out);
    out
}
