//! The boundary between screwkit's nalgebra types and parry's glam types: poses and points
//! cross here, nowhere else.

use nalgebra::Vector3;
use parry3d_f64::math::{Pose, Vector};
use screwkit_lie::Se3;

/// A screwkit pose as parry's (rotation as a unit quaternion, translation).
pub fn pose(t: &Se3) -> Pose {
    let r = t.rotation();
    let m = parry3d_f64::glamx::DMat3::from_cols_array(&[
        r[(0, 0)],
        r[(1, 0)],
        r[(2, 0)],
        r[(0, 1)],
        r[(1, 1)],
        r[(2, 1)],
        r[(0, 2)],
        r[(1, 2)],
        r[(2, 2)],
    ]);
    let p = t.translation();
    Pose::from_parts(
        Vector::new(p.x, p.y, p.z),
        parry3d_f64::glamx::DQuat::from_mat3(&m),
    )
}

/// A parry point or vector as an array.
pub fn array(v: Vector) -> [f64; 3] {
    [v.x, v.y, v.z]
}

/// An array as a parry vector.
pub fn vector(v: [f64; 3]) -> Vector {
    Vector::new(v[0], v[1], v[2])
}

/// A nalgebra vector as a parry vector.
pub fn from_nalgebra(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}
