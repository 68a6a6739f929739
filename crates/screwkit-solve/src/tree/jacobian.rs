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
use screwkit_lie::fma::{dispatch, Kernel, MulAdd};
use screwkit_lie::{trig, Se3, Twist};

use super::fk::sin_cos_lanes;
use super::{TreeKinematics, TreeWorkspace, NONE};
use crate::columns::{add, cross, sub, Columns, Lane};
use crate::error::SolveError;
use crate::jacobian::JacobianKind;
use crate::jacobian::{space_to_world_aligned, PoseJacobian};

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
/// The path's joints are swept in their own frames as in [`super::fk::fk_frames`] (from the
/// base's pose: G_k = G_parent X_k e^{[a_k]θ_k}), and joint k's world column is
/// \[Ad_{G_k}\](a_k, 0) = (R_k a_k, p_k × R_k a_k) (prismatic (0, R_k a_k)) — the space column of
/// the module's formula, since S_k = Ad_{H_k}(a_k, 0) — with the axis-aligned a_k of most files
/// a column of R_k. Then each form from the world column, each added (× its mimic multiplier)
/// into its variable's column; columns off the path stay zero.
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
        theta,
        sin,
        cos,
        path,
        path_columns,
        jacobian,
        other: second,
        ..
    } = ws;
    let jac = if other { second } else { jacobian };
    jac.as_mut_slice().fill(0.0);
    // The path root → the frame's support joint, parents first.
    let mut n = 0;
    let mut j = kin.frames[frame].support;
    while j != NONE {
        path[n] = j;
        n += 1;
        j = kin.parent[j];
    }
    path[..n].reverse();
    let vo = kin.v_offset();
    let pose = dispatch(PathColumns {
        kin,
        q: &q[kin.q_offset()..],
        base: Columns::from_se3(base),
        frame,
        form,
        path: &path[..n],
        theta,
        sin,
        cos,
        columns: path_columns,
        out: &mut jac.as_mut_slice()[6 * vo..],
    })
    .to_se3();
    let out = jac.as_mut_slice();
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

/// The kernel of [`pose_jacobian_unchecked`]: the frame's pose, its path joints' world
/// columns, each in `form` and added into its variable's column of `out` (the joint columns).
struct PathColumns<'a> {
    kin: &'a TreeKinematics,
    /// The joint variables.
    q: &'a [f64],
    base: Columns,
    frame: usize,
    form: JacobianKind,
    /// Joint indices, parents first.
    path: &'a [usize],
    theta: &'a mut [f64],
    sin: &'a mut [f64],
    cos: &'a mut [f64],
    columns: &'a mut [[Lane; 3]],
    out: &'a mut [f64],
}

impl Kernel for PathColumns<'_> {
    type Output = Columns;
    #[inline(always)]
    fn run<A: MulAdd>(self) -> Columns {
        const L: usize = trig::LANES;
        let kin = self.kin;
        let n = self.path.len();
        let lanes = n.div_ceil(L) * L;
        for (t, &k) in self.theta.iter_mut().zip(self.path) {
            *t = kin.sweep[k].motion.drive.theta(self.q);
        }
        self.theta[n..lanes].fill(0.0);
        sin_cos_lanes::<A>(&self.theta[..lanes], self.sin, self.cos);
        let mut g = self.base;
        for (i, (&k, col)) in self.path.iter().zip(self.columns.iter_mut()).enumerate() {
            let j = &kin.sweep[k];
            g = j.fixed.apply::<A>(&g);
            j.motion
                .apply::<A>(&mut g, self.theta[i], self.sin[i], self.cos[i]);
            // [Ad_G](w, v) = (R w, p × R w + R v); the joint's own motion leaves its axis.
            // Kept as (R w, R v, p); the cross product is taken below, once per form.
            let (w, v) = j.motion.axis();
            let rv = if j.motion.prismatic || *v != [0.0; 3] {
                g.rotate::<A>(v)
            } else {
                [0.0; 4]
            };
            *col = [g.rotate::<A>(w), rv, g.p()];
        }
        let t = kin.frames[self.frame].placement.apply::<A>(&g);
        let inv = (self.form == JacobianKind::Body).then(|| t.inverse::<A>());
        for (&k, &[w, rv, p]) in self.path.iter().zip(self.columns.iter()) {
            let (w, v) = match (self.form, &inv) {
                (JacobianKind::Space, _) => (w, add(cross(p, w), rv)),
                // (ω, v + ω × p_F) (`jacobian::space_to_world_aligned`) = (ω, (p − p_F) × ω + R v).
                (JacobianKind::WorldAligned, _) => (w, add(cross(sub(p, t.p()), w), rv)),
                // [Ad_{T_F⁻¹}](ω, v) = (Rᵀω, Rᵀv + (−Rᵀp) × Rᵀω).
                (JacobianKind::Body, Some(inv)) => {
                    let v = add(cross(p, w), rv);
                    let (w, v) = ([w[0], w[1], w[2]], [v[0], v[1], v[2]]);
                    let bw = inv.rotate::<A>(&w);
                    (bw, add(inv.rotate::<A>(&v), cross(inv.p(), bw)))
                }
                (JacobianKind::Body, None) => unreachable!("the inverse is made for the body form"),
            };
            let drive = &kin.sweep[k].motion.drive;
            let o = &mut self.out[6 * drive.variable..6 * drive.variable + 6];
            let m = drive.multiplier;
            for (r, x) in [w[0], w[1], w[2], v[0], v[1], v[2]].into_iter().enumerate() {
                o[r] = A::madd(m, x, o[r]);
            }
        }
        t
    }
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
