//! MuJoCo's `qpos` and screwkit's configuration, both ways, on the model
//! ([`KinematicTree`]): library users and every front end convert with the same code.
//!
//! MuJoCo's `qpos` holds every joint in its order (bodies depth first, joints in order): a
//! free joint's seven numbers (position, then the quaternion **w, x, y, z**), one number per
//! hinge or slide — coupled followers included, as MuJoCo keeps them as degrees of freedom
//! held by an equality. screwkit's q ([`crate::kinematic_tree`]) puts the floating base first
//! as x, y, z, qx, qy, qz, qw, then the independent variables; a follower is not one of them
//! (its value is m q_leader + o). The tree of an MJCF model ([`crate::mjcf`]) has its joints
//! in MuJoCo's order, so the layout is read from it ([`crate::QposLayout`]: the whole model's
//! addresses, props the tree reads past included).

use crate::kinematic_tree::KinematicTree;
use crate::Drive;

/// A `qpos` or q of the wrong length, or a joint with no place in the model's `qpos`.
#[derive(Debug, Clone, PartialEq)]
pub struct QposError {
    /// The argument at fault: `"qpos"` or `"q"`.
    pub argument: &'static str,
    /// What is wrong with it.
    pub message: String,
}

impl std::fmt::Display for QposError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.argument, self.message)
    }
}

impl std::error::Error for QposError {}

fn fail(argument: &'static str, message: impl Into<String>) -> QposError {
    QposError {
        argument,
        message: message.into(),
    }
}

/// For each movable joint of the tree, in MuJoCo's order: its name and drive (variable,
/// multiplier, offset).
fn drives(model: &KinematicTree) -> Vec<(&str, Drive)> {
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
pub fn qpos_len(model: &KinematicTree) -> usize {
    let base = if model.floating_base { 7 } else { 0 };
    base + drives(model).len()
}

/// The length of the whole MuJoCo model's `qpos`, props the tree reads past included (the
/// robot's own length when the file holds nothing else, or is no MJCF file).
pub fn model_qpos_len(model: &KinematicTree) -> usize {
    model
        .tree
        .qpos_layout
        .as_ref()
        .map_or_else(|| qpos_len(model), |l| l.len)
}

/// For each entry of the robot's own `qpos`, its address in the whole model's.
fn addresses(model: &KinematicTree) -> Vec<usize> {
    let Some(layout) = model.tree.qpos_layout.as_ref() else {
        return (0..qpos_len(model)).collect();
    };
    let mut out = Vec::with_capacity(qpos_len(model));
    if model.floating_base {
        let b = layout.base.unwrap_or(0);
        out.extend(b..b + 7);
    }
    for (name, _) in drives(model) {
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
pub fn from_qpos(model: &KinematicTree, qpos: &[f64]) -> Result<Vec<f64>, QposError> {
    let (n, whole) = (qpos_len(model), model_qpos_len(model));
    let own: Vec<f64> = if qpos.len() == n {
        qpos.to_vec()
    } else if qpos.len() == whole {
        addresses(model)
            .iter()
            .map(|&a| {
                qpos.get(a).copied().ok_or_else(|| {
                    fail(
                        "qpos",
                        "a joint of the robot has no place in the model's qpos",
                    )
                })
            })
            .collect::<Result<_, _>>()?
    } else {
        return Err(fail(
            "qpos",
            format!("{}, got {}", expected(n, whole), qpos.len()),
        ));
    };
    let qpos = own.as_slice();
    let mut q = vec![0.0; model.nq()];
    let off = if model.floating_base {
        q[..3].copy_from_slice(&qpos[..3]);
        q[3..6].copy_from_slice(&qpos[4..7]);
        q[6] = qpos[3];
        7
    } else {
        0
    };
    // A variable is named after the joint that owns it; the followers' entries are skipped.
    for (k, (name, d)) in drives(model).iter().enumerate() {
        if model.variables[d.variable].name == *name {
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
/// follower's as its coupling gives it). Without `whole`, the robot's own entries (length
/// [`qpos_len`]); with the whole model's `qpos` (length [`model_qpos_len`]), a copy of it with
/// the robot's entries written at their addresses (the props keep theirs).
pub fn to_qpos(
    model: &KinematicTree,
    q: &[f64],
    whole: Option<&[f64]>,
) -> Result<Vec<f64>, QposError> {
    if q.len() != model.nq() {
        return Err(fail(
            "q",
            format!(
                "expected {} configuration values, got {}",
                model.nq(),
                q.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(qpos_len(model));
    let off = if model.floating_base {
        out.extend_from_slice(&q[..3]);
        out.push(q[6]);
        out.extend_from_slice(&q[3..6]);
        7
    } else {
        0
    };
    for (_, d) in drives(model) {
        out.push(d.theta(&q[off..]));
    }
    let Some(whole) = whole else {
        return Ok(out);
    };
    let len = model_qpos_len(model);
    if whole.len() != len {
        return Err(fail(
            "qpos",
            format!(
                "expected the whole model's {len} MuJoCo qpos values, got {}",
                whole.len()
            ),
        ));
    }
    let mut all = whole.to_vec();
    for (v, a) in out.into_iter().zip(addresses(model)) {
        if let Some(slot) = all.get_mut(a) {
            *slot = v;
        }
    }
    Ok(all)
}
