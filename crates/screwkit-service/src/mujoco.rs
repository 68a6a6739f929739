//! MuJoCo's `qpos` and screwkit's configuration, both ways — written once for every front end.
//!
//! MuJoCo's `qpos` holds every joint in its order (bodies depth first, joints in order): a
//! free joint's seven numbers (position, then the quaternion **w, x, y, z**), one number per
//! hinge or slide — coupled followers included, as MuJoCo keeps them as degrees of freedom
//! held by an equality. screwkit's q ([`screwkit_model::kinematic_tree`]) puts the floating
//! base first as x, y, z, qx, qy, qz, qw, then the independent variables; a follower is not
//! one of them (its value is m q_leader + o). The tree of an MJCF model
//! ([`screwkit_model::mjcf`]) has its joints in MuJoCo's order, so the layout is read from it.

use screwkit_solve::TreeKinematics;

use crate::error::{Error, Result};

/// For each movable joint of the tree, in MuJoCo's order: its name and drive (variable,
/// multiplier, offset).
fn drives(kin: &TreeKinematics) -> Vec<(&str, screwkit_model::Drive)> {
    let model = kin.model();
    model
        .tree
        .joints
        .iter()
        .filter(|j| j.kind.is_movable())
        .filter_map(|j| {
            model
                .joints
                .iter()
                .find(|s| s.name == j.name)
                .map(|s| (j.name.as_str(), s.drive))
        })
        .collect()
}

/// The length of MuJoCo's `qpos` for this tree: 7 for a floating base, one per movable joint.
pub fn qpos_len(kin: &TreeKinematics) -> usize {
    let base = if kin.floating_base() { 7 } else { 0 };
    base + drives(kin).len()
}

/// screwkit's q (nq) of MuJoCo's `qpos`: the base's quaternion reordered to x, y, z, w, each
/// variable its own joint's entry (a follower's entry is not read).
pub fn from_qpos(kin: &TreeKinematics, qpos: &[f64]) -> Result<Vec<f64>> {
    let n = qpos_len(kin);
    if qpos.len() != n {
        return Err(Error::option(
            "qpos",
            format!("expected {n} MuJoCo qpos values, got {}", qpos.len()),
        ));
    }
    let mut q = vec![0.0; kin.nq()];
    let off = if kin.floating_base() {
        q[..3].copy_from_slice(&qpos[..3]);
        q[3..6].copy_from_slice(&qpos[4..7]);
        q[6] = qpos[3];
        7
    } else {
        0
    };
    // A variable is named after the joint that owns it; the followers' entries are skipped.
    for (k, (name, d)) in drives(kin).iter().enumerate() {
        if kin.q_names()[off + d.variable] == *name {
            q[off + d.variable] = qpos[off + k];
        }
    }
    Ok(q)
}

/// MuJoCo's `qpos` of screwkit's q: the base's quaternion w first, every joint's value (a
/// follower's as its coupling gives it).
pub fn to_qpos(kin: &TreeKinematics, q: &[f64]) -> Result<Vec<f64>> {
    if q.len() != kin.nq() {
        return Err(Error::option(
            "q",
            format!(
                "expected {} configuration values, got {}",
                kin.nq(),
                q.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(qpos_len(kin));
    let off = if kin.floating_base() {
        out.extend_from_slice(&q[..3]);
        out.push(q[6]);
        out.extend_from_slice(&q[3..6]);
        7
    } else {
        0
    };
    for (_, d) in drives(kin) {
        out.push(d.theta(&q[off..]));
    }
    Ok(out)
}
