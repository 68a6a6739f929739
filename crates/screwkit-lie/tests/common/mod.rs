//! Shared helpers for the property and corner tests (an independent matrix exponential).

#![allow(dead_code)]

use nalgebra::{Matrix3, Matrix4, UnitQuaternion, Vector3};
use proptest::prelude::*;
use screwkit_lie::{Se3, Twist};

/// e^M for a 4x4 matrix by scaling and squaring with a 30-term Taylor series: an oracle that
/// shares no code with the closed forms.
pub fn expm_series(m: &Matrix4<f64>) -> Matrix4<f64> {
    let norm = m.abs().row_sum().max();
    let mut squarings = 0;
    let mut scale = 1.0;
    while norm * scale > 0.25 {
        scale *= 0.5;
        squarings += 1;
    }
    let a = m * scale;
    let mut term = Matrix4::identity();
    let mut sum = Matrix4::identity();
    for k in 1..30 {
        term = term * a / k as f64;
        sum += term;
    }
    for _ in 0..squarings {
        sum = sum * sum;
    }
    sum
}

/// A rotation from a non-zero 4-vector (normalised to a unit quaternion: uniform on SO(3)
/// when the vector is Gaussian; near-uniform for the box used here).
pub fn rotation_from(q: [f64; 4]) -> Matrix3<f64> {
    let uq = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]));
    *uq.to_rotation_matrix().matrix()
}

/// Random rigid transforms (rotation from a random quaternion, translation in [−5, 5]³).
pub fn arb_se3() -> impl Strategy<Value = Se3> {
    (
        prop::array::uniform4(-1.0f64..1.0),
        prop::array::uniform3(-5.0f64..5.0),
    )
        .prop_filter("quaternion away from zero", |(q, _)| {
            q.iter().map(|x| x * x).sum::<f64>() > 1e-3
        })
        .prop_map(|(q, p)| Se3::from_parts_unchecked(rotation_from(q), Vector3::from(p)))
}

/// Random twists with ‖ω‖ ≤ `max_angle` and ‖v‖ components in [−5, 5].
pub fn arb_twist(max_angle: f64) -> impl Strategy<Value = Twist> {
    (
        prop::array::uniform3(-1.0f64..1.0),
        0.0..max_angle,
        prop::array::uniform3(-5.0f64..5.0),
    )
        .prop_filter("axis away from zero", |(a, _, _)| {
            a.iter().map(|x| x * x).sum::<f64>() > 1e-4
        })
        .prop_map(|(a, angle, v)| {
            let axis = Vector3::from(a).normalize();
            Twist::new(axis * angle, Vector3::from(v))
        })
}
