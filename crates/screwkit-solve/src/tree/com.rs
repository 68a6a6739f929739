//! The centre of mass of a tree and its Jacobian (Pinocchio's `centerOfMass`,
//! `jacobianCenterOfMass`).
//!
//! Every link L with an `<inertial>` of mass m_L > 0 and centre c_L (in the link's frame,
//! [`screwkit_model::Inertial`]) counts, the root link included:
//!
//! ```text
//! c(q) = (1/M) Σ_L m_L T_L(q) c_L,        M = Σ_L m_L,
//! ```
//!
//! in the world frame (metres). Its Jacobian J_c (3 × nv, ċ = J_c v) has, for a joint k with
//! world axis w_k through the point p_k (read off the joint's pose in the all-frame sweep), the
//! column
//!
//! ```text
//! revolute:  w_k × (s_k − M_k p_k) / M,      prismatic:  M_k w_k / M,
//! ```
//!
//! where M_k and s_k = Σ m_L c_L (world) sum over the links that joint k carries (its subtree:
//! one pass from the leaves); a variable driving several joints (mimic) gets Σ m_j · column j. A
//! floating base's six columns (its twist (ω, v) in its own frame, R and p its pose) are
//! (−[c − p]× R, R): every link moves with the base.
//!
//! Note: Pinocchio's fixed-base model leaves the root link's mass out (it is the "universe");
//! its free-flyer model counts it, as here.

use nalgebra::{Matrix3xX, Vector3};

use super::fk::frames_unchecked;
use super::{TreeKinematics, TreeWorkspace, NONE};
use crate::error::SolveError;

/// The total mass M of the links that have one (kg; 0 when the file gives none).
pub fn total_mass(kin: &TreeKinematics) -> f64 {
    kin.total_mass
}

fn check_mass(kin: &TreeKinematics) -> Result<(), SolveError> {
    if kin.total_mass > 0.0 {
        Ok(())
    } else {
        Err(SolveError::InvalidInput(format!(
            "{}: no link has a mass (<inertial><mass value> > 0): the centre of mass is undefined",
            kin.model.source
        )))
    }
}

/// The centre of mass c(q) in the world frame (module documentation). Checks q; an error when
/// no link has a mass.
pub fn com(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
) -> Result<Vector3<f64>, SolveError> {
    check_mass(kin)?;
    let base = kin.check_q(q)?;
    ws.fit(kin);
    frames_unchecked(kin, ws, q, &base);
    Ok(com_of_frames(kin, ws))
}

/// c from the link poses of the last sweep.
pub(crate) fn com_of_frames(kin: &TreeKinematics, ws: &TreeWorkspace) -> Vector3<f64> {
    let mut s = Vector3::zeros();
    for (l, m, c) in &kin.masses {
        s += *m * ws.frames[*l].transform_point(c);
    }
    s / kin.total_mass
}

/// The centre of mass and its Jacobian J_c (3 × nv, in the workspace; module documentation).
/// Checks q; an error when no link has a mass.
pub fn com_jacobian<'w>(
    kin: &TreeKinematics,
    ws: &'w mut TreeWorkspace,
    q: &[f64],
) -> Result<(Vector3<f64>, &'w Matrix3xX<f64>), SolveError> {
    check_mass(kin)?;
    let base = kin.check_q(q)?;
    ws.fit(kin);
    let c = com_jacobian_unchecked(kin, ws, q, &base);
    Ok((c, &ws.com_jacobian))
}

/// [`com_jacobian`] without the checks (a mass exists, q checked, `base` its base pose).
pub(crate) fn com_jacobian_unchecked(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    base: &screwkit_lie::Se3,
) -> Vector3<f64> {
    frames_unchecked(kin, ws, q, base);
    for s in ws.subtree.iter_mut() {
        *s = (0.0, Vector3::zeros());
    }
    let mut total = Vector3::zeros();
    for (l, m, c) in &kin.masses {
        let cw = *m * ws.frames[*l].transform_point(c);
        total += cw;
        let support = kin.frames[*l].support;
        if support != NONE {
            let s = &mut ws.subtree[support];
            s.0 += m;
            s.1 += cw;
        }
    }
    // Children come after their parents: one pass backwards carries each subtree up.
    for k in (0..kin.joints.len()).rev() {
        let p = kin.parent[k];
        if p != NONE {
            let (m, s) = ws.subtree[k];
            ws.subtree[p].0 += m;
            ws.subtree[p].1 += s;
        }
    }
    let mass = kin.total_mass;
    let jac = &mut ws.com_jacobian;
    jac.as_mut_slice().fill(0.0);
    let vo = kin.v_offset();
    for (k, joint) in kin.model.joints.iter().enumerate() {
        let g = ws.joint_poses[k].to_se3();
        let w = g.rotation() * joint.axis;
        let (mk, sk) = ws.subtree[k];
        // The subtree's centre of mass moves with the joint's twist (ω, v) at its points:
        // ṁc = ω × (s − m p) + m h ω for a rotating joint of pitch h, m a for a prismatic one.
        let col = match joint.kind {
            screwkit_model::JointKind::Prismatic => w * (mk / mass),
            screwkit_model::JointKind::Helical => {
                let h = joint.s_space.pitch().unwrap_or(0.0);
                (w.cross(&(sk - mk * g.translation())) + w * (mk * h)) / mass
            }
            _ => w.cross(&(sk - mk * g.translation())) / mass,
        };
        let d = joint.drive;
        let mut dst = jac.column_mut(vo + d.variable);
        dst += col * d.multiplier;
    }
    let c = total / mass;
    if kin.floating {
        let r = base.rotation();
        let arm = c - base.translation();
        // ω_b = e_i turns every point x about the base's origin: ẋ = (R e_i) × (x − p);
        // v_b = e_i moves it by R e_i.
        for i in 0..3 {
            let ri = r.column(i).into_owned();
            jac.column_mut(i).copy_from(&ri.cross(&arm));
            jac.column_mut(3 + i).copy_from(&ri);
        }
    }
    c
}
