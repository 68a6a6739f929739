//! Jacobians of a tree's frames, one column per velocity entry (nv: the floating base's six,
//! then one per joint variable), rows (ω, v).
//!
//! - **Space** (world): column of joint j on the path to F = \[Ad_{T_base G_{j−1}}\] S_j with
//!   G_{j−1} the product of the joints above j (*Modern Robotics* eq. 5.11 along the path);
//!   joints off the path: zero; a variable driving several joints (mimic): Σ m_j · column j.
//!   The base's six columns: \[Ad_{T_base}\] (the base's body twist seen in the world).
//! - **Body**: J_b = \[Ad_{T_F⁻¹}\] J_s; the joint columns do not depend on the base's pose,
//!   the base's columns are \[Ad_{(T_base⁻¹ T_F)⁻¹}\].
//! - **World-aligned**: (ω, v_s + ω × p_F): the frame's angular velocity and its origin's
//!   velocity in world axes (Pinocchio's `LOCAL_WORLD_ALIGNED`).
//!
//! **Relative** (frame A seen from frame B, T_BA = T_B⁻¹ T_A): the twist of T_BA is
//! V = \[Ad_{T_B⁻¹}\](J_s,A − J_s,B) v in B's frame (space form, B as the base), \[Ad_{T_A⁻¹}\]
//! (J_s,A − J_s,B) v in A's frame (body form), and (ω, v + ω × p_BA) in B's axes at A's origin
//! (world-aligned). When B is an ancestor of A this is the chain B → A's Jacobian.

use nalgebra::Matrix6xX;
use screwkit_lie::{Se3, Twist};

use super::{TreeKinematics, TreeWorkspace};
use crate::error::SolveError;
use crate::jacobian::JacobianKind;
use crate::jacobian::{fk_jacobian_into, space_to_world_aligned, PoseJacobian};

/// The Jacobian of `frame` in `form` (6 × nv), in the workspace. Checks q and the index.
pub fn frame_jacobian<'w>(
    kin: &TreeKinematics,
    ws: &'w mut TreeWorkspace,
    q: &[f64],
    frame: usize,
    form: JacobianKind,
) -> Result<&'w Matrix6xX<f64>, SolveError> {
    Ok(frame_pose_jacobian(kin, ws, q, frame, form)?.jacobian)
}

/// The pose and the Jacobian of `frame` from one pass. Checks q and the index.
pub fn frame_pose_jacobian<'w>(
    kin: &TreeKinematics,
    ws: &'w mut TreeWorkspace,
    q: &[f64],
    frame: usize,
    form: JacobianKind,
) -> Result<PoseJacobian<'w>, SolveError> {
    kin.check_frame(frame)?;
    let base = kin.check_q(q)?;
    ws.fit(kin);
    let pose = pose_jacobian_unchecked(kin, ws, q, &base, frame, form, false);
    Ok(PoseJacobian {
        pose,
        jacobian: &ws.jacobian,
    })
}

/// Pose and Jacobian of one frame into `ws.jacobian` (or `ws.other` when `other`), unchecked.
///
/// A frame's Jacobian is its chain's: the chain root → frame ([`TreeKinematics::view`], the
/// chain kernels' one pass, mimic columns summed with their multipliers), its columns moved
/// to the tree's variables, every other column zero. Space and world-aligned columns are
/// seen from the world (\[Ad_{T_base}\] of the chain's with a floating base), the world-aligned
/// ones moved to the frame's origin ([`space_to_world_aligned`]); body columns do not depend on
/// the base. With a floating base, its six columns (module documentation).
pub(crate) fn pose_jacobian_unchecked(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    base: &Se3,
    frame: usize,
    form: JacobianKind,
    other: bool,
) -> Se3 {
    let TreeWorkspace {
        view_q,
        view_jacobian,
        jacobian,
        other: second,
        ..
    } = ws;
    let jac = if other { second } else { jacobian };
    let view = kin.view(frame);
    let vq = view.map(|view| super::fk::gather(kin, view, q, view_q));
    let out = jac.as_mut_slice();
    out.fill(0.0);
    let vo = kin.v_offset();
    let place = |local: Se3| {
        if kin.floating {
            base.compose(&local)
        } else {
            local
        }
    };
    let pose = match (view, vq) {
        (Some(view), Some(vq)) => {
            let local = fk_jacobian_into(&view.kin, view_jacobian, vq, form.pass());
            let pose = place(local);
            let p = *pose.translation();
            let columns = view_jacobian.as_slice().chunks_exact(6);
            for (&v, c) in view.variables.iter().zip(columns) {
                let mut col = [c[0], c[1], c[2], c[3], c[4], c[5]];
                if form != JacobianKind::Body {
                    if kin.floating {
                        let t = base.adjoint_apply(&Twist::new(
                            nalgebra::Vector3::new(col[0], col[1], col[2]),
                            nalgebra::Vector3::new(col[3], col[4], col[5]),
                        ));
                        col = [t.w[0], t.w[1], t.w[2], t.v[0], t.v[1], t.v[2]];
                    }
                    if form == JacobianKind::WorldAligned {
                        space_to_world_aligned(&mut col, &p);
                    }
                }
                if let Some(o) = out.get_mut(6 * (vo + v)..6 * (vo + v) + 6) {
                    o.copy_from_slice(&col);
                }
            }
            pose
        }
        _ => place(kin.frames[frame].home),
    };
    if kin.floating {
        let ad = match form {
            JacobianKind::Body => base.inverse_compose(&pose).inverse().adjoint(),
            _ => base.adjoint(),
        };
        for i in 0..6 {
            let mut col: [f64; 6] = ad.column(i).into();
            if form == JacobianKind::WorldAligned {
                space_to_world_aligned(&mut col, pose.translation());
            }
            out[6 * i..6 * i + 6].copy_from_slice(&col);
        }
    }
    pose
}

/// Applies \[Ad_T\] to every column.
fn adjoint_columns(jac: &mut Matrix6xX<f64>, t: &Se3) {
    for c in 0..jac.ncols() {
        let col = jac.column(c);
        let tw = t.adjoint_apply(&Twist::new(
            col.fixed_rows::<3>(0).into(),
            col.fixed_rows::<3>(3).into(),
        ));
        let mut dst = jac.column_mut(c);
        dst.fixed_rows_mut::<3>(0).copy_from(&tw.w);
        dst.fixed_rows_mut::<3>(3).copy_from(&tw.v);
    }
}

/// The pose of frame `a` in frame `b` (T_B⁻¹ T_A) and the Jacobian of that relative motion in
/// `form` (module documentation), 6 × nv, in the workspace. Checks q and the indices.
pub fn relative_jacobian<'w>(
    kin: &TreeKinematics,
    ws: &'w mut TreeWorkspace,
    q: &[f64],
    a: usize,
    b: usize,
    form: JacobianKind,
) -> Result<PoseJacobian<'w>, SolveError> {
    kin.check_frame(a)?;
    kin.check_frame(b)?;
    let base = kin.check_q(q)?;
    ws.fit(kin);
    let pose = relative_unchecked(kin, ws, q, &base, a, b, form);
    Ok(PoseJacobian {
        pose,
        jacobian: &ws.jacobian,
    })
}

/// [`relative_jacobian`] without the checks; the Jacobian in `ws.jacobian`.
pub(crate) fn relative_unchecked(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    base: &Se3,
    a: usize,
    b: usize,
    form: JacobianKind,
) -> Se3 {
    let ta = pose_jacobian_unchecked(kin, ws, q, base, a, JacobianKind::Space, false);
    let tb = pose_jacobian_unchecked(kin, ws, q, base, b, JacobianKind::Space, true);
    ws.jacobian -= &ws.other;
    let rel = tb.inverse_compose(&ta);
    match form {
        JacobianKind::Space | JacobianKind::WorldAligned => {
            adjoint_columns(&mut ws.jacobian, &tb.inverse());
            if form == JacobianKind::WorldAligned {
                crate::jacobian::world_aligned_columns(&mut ws.jacobian, rel.translation());
            }
        }
        JacobianKind::Body => adjoint_columns(&mut ws.jacobian, &ta.inverse()),
    }
    rel
}

/// A movable joint of the tree at q: its frame and its screw axis in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointScrew {
    /// The joint's frame at q: T_base G_k(q) H_k, with G_k the product of the exponentials of
    /// the path down to and including joint k and H_k its frame at home
    /// (`TreeScrew::home`). Its origin lies on the axis.
    pub frame: Se3,
    /// Its screw axis at q in the world: S_k(q) = \[Ad_{T_base G_parent(k)(q)}\] S_k, the axis
    /// the joint turns about (or slides along) at this configuration. Without mimic joints the
    /// column of its variable in the space Jacobian of any frame below it; with them that
    /// column is Σ m_j S_j(q) over the joints the variable drives.
    pub screw: Twist,
}

/// Every movable joint's frame and space screw axis at q, in the order of
/// `KinematicTree::joints` (parents first, mimic joints included). For pictures and
/// analysis, not a hot path: the space form with the general `Se3::exp`, independent of the
/// sweep and chain kernels. Checks q.
pub fn joint_screws(
    kin: &TreeKinematics,
    _ws: &mut TreeWorkspace,
    q: &[f64],
) -> Result<Vec<JointScrew>, SolveError> {
    let base = kin.check_q(q)?;
    let joints_q = &q[kin.q_offset()..];
    let model = &kin.model;
    // G_k = G_parent(k) e^{[S_k]θ_k}, with T_base in front.
    let mut g: Vec<Se3> = Vec::with_capacity(model.joints.len());
    let mut out = Vec::with_capacity(model.joints.len());
    for j in &model.joints {
        let above = j.parent.map_or(base, |p| g[p]);
        let s = *j.s_space.twist();
        let theta = j.drive.theta(joints_q);
        let gk = above.compose(&Se3::exp(&Twist::new(s.w * theta, s.v * theta)));
        out.push(JointScrew {
            frame: gk.compose(&j.home),
            screw: above.adjoint_apply(&s),
        });
        g.push(gk);
    }
    Ok(out)
}
