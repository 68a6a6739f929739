//! Configurations of a tree on SE(3) × ℝⁿ (the floating base's q = (x, y, z, qx, qy, qz, qw),
//! v = (ω, v_b) in the base frame; see [`screwkit_model::kinematic_tree`]).
//!
//! - `integrate(q, v, dt)`: the base moves by the exponential map, T ← T e^{[V_b] dt} (its
//!   quaternion is composed with the rotation's, never added to), the joints by q + q̇ dt;
//! - `difference(q0, q1)`: the v for which `integrate(q0, v, 1) = q1`: V_b = log(T₀⁻¹ T₁), the
//!   joints q₁ − q₀;
//! - `neutral`: the base at the world's origin with the identity quaternion, the joints at
//!   zero (the file's home);
//! - `random`: joints uniform within their limits ([−π, π] when unbounded), the base's
//!   orientation uniform on SO(3) and its position uniform in the cube [−1, 1]³ m (the base is
//!   unbounded; the cube only places samples).

use screwkit_lie::{so3, Se3, Twist};

use super::{base_pose, TreeKinematics};
use crate::error::SolveError;
use crate::sample::{range, SplitMix64};

fn check_v(kin: &TreeKinematics, v: &[f64]) -> Result<(), SolveError> {
    if v.len() != kin.nv() {
        return Err(SolveError::WrongLength {
            what: "velocity values",
            expected: kin.nv(),
            got: v.len(),
            names: kin.v_names().join(", "),
        });
    }
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(SolveError::NonFinite {
            what: "velocity value",
            index: i,
            name: kin.v_names()[i].clone(),
            value: v[i],
        }),
    }
}

/// Writes the base pose `t` into q\[0..7\] (quaternion x, y, z, w with w ≥ 0).
fn write_base(t: &Se3, q: &mut [f64]) {
    q[..3].copy_from_slice(t.translation().as_slice());
    q[3..7].copy_from_slice(&t.quaternion());
}

/// q ⊕ v·dt (module documentation). Checks q, v and dt (finite).
pub fn integrate(
    kin: &TreeKinematics,
    q: &[f64],
    v: &[f64],
    dt: f64,
) -> Result<Vec<f64>, SolveError> {
    let base = kin.check_q(q)?;
    check_v(kin, v)?;
    if !dt.is_finite() {
        return Err(SolveError::InvalidInput(format!(
            "dt must be finite, got {dt}"
        )));
    }
    let mut out = q.to_vec();
    let (qo, vo) = (kin.q_offset(), kin.v_offset());
    for (o, x) in out[qo..].iter_mut().zip(&v[vo..]) {
        *o += x * dt;
    }
    if kin.floating {
        let step = Se3::exp(&Twist::new(
            nalgebra::Vector3::new(v[0], v[1], v[2]) * dt,
            nalgebra::Vector3::new(v[3], v[4], v[5]) * dt,
        ));
        write_base(&base.compose(&step), &mut out);
        if !out.iter().all(|x| x.is_finite()) {
            return Err(SolveError::InvalidInput(
                "the integrated configuration is not finite (v · dt overflows)".into(),
            ));
        }
    }
    Ok(out)
}

/// The velocity v with `integrate(q0, v, 1) = q1` (module documentation). Checks both.
pub fn difference(kin: &TreeKinematics, q0: &[f64], q1: &[f64]) -> Result<Vec<f64>, SolveError> {
    let b0 = kin.check_q(q0)?;
    let b1 = kin.check_q(q1)?;
    let (qo, vo) = (kin.q_offset(), kin.v_offset());
    let mut v = vec![0.0; kin.nv()];
    for ((o, a), b) in v[vo..].iter_mut().zip(&q0[qo..]).zip(&q1[qo..]) {
        *o = b - a;
    }
    if kin.floating {
        let xi = b0.inverse_compose(&b1).log();
        v[..3].copy_from_slice(xi.w.as_slice());
        v[3..6].copy_from_slice(xi.v.as_slice());
    }
    Ok(v)
}

/// The neutral configuration (module documentation).
pub fn neutral(kin: &TreeKinematics) -> Vec<f64> {
    let mut q = vec![0.0; kin.nq()];
    if kin.floating {
        q[6] = 1.0;
    }
    q
}

/// A random configuration (module documentation) from `rng`.
pub fn random(kin: &TreeKinematics, rng: &mut SplitMix64) -> Vec<f64> {
    let mut q = neutral(kin);
    let qo = kin.q_offset();
    for (k, x) in q[qo..].iter_mut().enumerate() {
        let (l, u) = range(kin.lower[k], kin.upper[k]);
        *x = l + (u - l) * rng.uniform();
    }
    if kin.floating {
        for x in &mut q[..3] {
            *x = 2.0 * rng.uniform() - 1.0;
        }
        // Shoemake's uniform unit quaternion.
        let (u1, u2, u3) = (rng.uniform(), rng.uniform(), rng.uniform());
        let tau = std::f64::consts::TAU;
        let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
        let quat = [
            a * (tau * u2).sin(),
            a * (tau * u2).cos(),
            b * (tau * u3).sin(),
            b * (tau * u3).cos(),
        ];
        // Through the rotation matrix, so that w ≥ 0 as everywhere else.
        let r = so3::from_quaternion(quat).expect("a unit quaternion");
        q[3..7].copy_from_slice(&so3::to_quaternion(&r));
        debug_assert!(base_pose(&q).is_ok());
    }
    q
}
