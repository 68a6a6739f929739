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

/// The length of the robot's own `qpos`: 7 for a floating base, one per movable joint.
pub fn qpos_len(kin: &TreeKinematics) -> usize {
    let base = if kin.floating_base() { 7 } else { 0 };
    base + drives(kin).len()
}

/// The length of the whole MuJoCo model's `qpos`, props the tree reads past included (the
/// robot's own length when the file holds nothing else, or is no MJCF file).
pub fn model_qpos_len(kin: &TreeKinematics) -> usize {
    kin.model()
        .tree
        .qpos_layout
        .as_ref()
        .map_or_else(|| qpos_len(kin), |l| l.len)
}

/// For each entry of the robot's own `qpos`, its address in the whole model's.
fn addresses(kin: &TreeKinematics) -> Vec<usize> {
    let Some(layout) = kin.model().tree.qpos_layout.as_ref() else {
        return (0..qpos_len(kin)).collect();
    };
    let mut out = Vec::with_capacity(qpos_len(kin));
    if kin.floating_base() {
        let b = layout.base.unwrap_or(0);
        out.extend(b..b + 7);
    }
    for (name, _) in drives(kin) {
        let a = layout
            .joints
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, a)| *a);
        out.push(a.unwrap_or(usize::MAX));
    }
    out
}

/// screwkit's q (nq) of MuJoCo's `qpos` — the robot's own (length [`qpos_len`]) or the whole
/// model's (length [`model_qpos_len`], props included: the robot's entries are read at their
/// addresses): the base's quaternion reordered to x, y, z, w, each variable its own joint's
/// entry (a follower's entry is not read).
pub fn from_qpos(kin: &TreeKinematics, qpos: &[f64]) -> Result<Vec<f64>> {
    let (n, whole) = (qpos_len(kin), model_qpos_len(kin));
    let own: Vec<f64> = if qpos.len() == n {
        qpos.to_vec()
    } else if qpos.len() == whole {
        addresses(kin)
            .iter()
            .map(|&a| {
                qpos.get(a).copied().ok_or_else(|| {
                    Error::option(
                        "qpos",
                        "a joint of the robot has no place in the model's qpos",
                    )
                })
            })
            .collect::<Result<_>>()?
    } else {
        return Err(Error::option(
            "qpos",
            format!("{}, got {}", expected(n, whole), qpos.len()),
        ));
    };
    let qpos = own.as_slice();
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

/// What a `qpos` may hold, for messages.
fn expected(n: usize, whole: usize) -> String {
    if n == whole {
        format!("expected {n} MuJoCo qpos values")
    } else {
        format!("expected {n} MuJoCo qpos values (the robot's) or {whole} (the whole model's, props included)")
    }
}

/// MuJoCo's `qpos` of screwkit's q: the base's quaternion w first, every joint's value (a
/// follower's as its coupling gives it). Without `model`, the robot's own entries (length
/// [`qpos_len`]); with the whole model's `qpos` (length [`model_qpos_len`]), a copy of it with
/// the robot's entries written at their addresses (the props keep theirs).
pub fn to_qpos(kin: &TreeKinematics, q: &[f64], model: Option<&[f64]>) -> Result<Vec<f64>> {
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
    let Some(model) = model else {
        return Ok(out);
    };
    let whole = model_qpos_len(kin);
    if model.len() != whole {
        return Err(Error::option(
            "qpos",
            format!(
                "expected the whole model's {whole} MuJoCo qpos values, got {}",
                model.len()
            ),
        ));
    }
    let mut all = model.to_vec();
    for (v, a) in out.into_iter().zip(addresses(kin)) {
        if let Some(slot) = all.get_mut(a) {
            *slot = v;
        }
    }
    Ok(all)
}
