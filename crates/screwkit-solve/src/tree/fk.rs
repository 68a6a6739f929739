//! Forward kinematics of a tree's frames: T_F(q) = T_base · Π_{j on the path to F}
//! e^{[S_j]θ_j} · M_F (the formula of [`screwkit_model::kinematic_tree`]).
//!
//! One frame runs the chain kernels of its path ([`crate::fk`]) on the space screws. Every
//! frame at once ([`fk_frames`]) sweeps the tree in each joint's own frame instead (Pinocchio's
//! form), which the same product gives: with H_k the joint frame at home and a_k its axis
//! there, S_k = Ad_{H_k}(a_k, 0) (prismatic: (0, a_k)), so e^{[S_k]θ} H_k = H_k e^{[a_k]θ} and
//! the joint frame's pose J_k(q) = T_base Π_{j ≤ k} e^{[S_j]θ_j} H_k is
//!
//! J_k = J_parent(k) · X_k · e^{[a_k]θ_k},  X_k = H_parent(k)⁻¹ H_k (the file's origins),
//! T_F = J_support(F) · P_F,  P_F = H_support(F)⁻¹ M_F (the identity for a joint's child link),
//!
//! with J of "no joint" = T_base. Each joint's motion is then a rotation about (or a
//! translation along) a coordinate axis of its own frame in most files ([`PoeJoint::apply`]
//! takes the two-column update), and most links' frames are a joint frame itself (no product).
//! The tests hold it equal to the chain kernels and to the URDF composed joint by joint.

use nalgebra::Matrix3;
use screwkit_lie::fma::{dispatch, Kernel, MulAdd};
use screwkit_lie::{trig, Se3};

use super::{TreeKinematics, TreeWorkspace, View, NONE};
use crate::columns::Columns;
use crate::error::SolveError;
use crate::fk::fk_unchecked;
use crate::poe::PoeJoint;

/// A fixed transform X applied on the right in the sweep (T ← T X), in its cheapest form.
#[derive(Debug, Clone)]
pub(crate) enum Placement {
    Identity,
    /// A pure translation (the rotation exactly the identity, as most origins write it).
    Translation([f64; 3]),
    General(Matrix3<f64>, [f64; 3]),
}

impl Placement {
    pub(crate) fn of(x: &Se3) -> Placement {
        let t = (*x.translation()).into();
        match (*x.rotation() == Matrix3::identity(), t == [0.0; 3]) {
            (true, true) => Placement::Identity,
            (true, false) => Placement::Translation(t),
            _ => Placement::General(*x.rotation(), t),
        }
    }

    /// T · X.
    #[inline(always)]
    pub(crate) fn apply<A: MulAdd>(&self, g: &Columns) -> Columns {
        match self {
            Placement::Identity => *g,
            Placement::Translation(t) => {
                let mut out = *g;
                out.translate::<A>(t);
                out
            }
            Placement::General(e, t) => g.compose::<A>(e, t),
        }
    }
}

/// One joint of the sweep: X_k, then the motion e^{[a_k]θ} in the joint's own frame.
#[derive(Debug, Clone)]
pub(crate) struct SweepJoint {
    pub(crate) fixed: Placement,
    pub(crate) motion: PoeJoint,
}

/// Every frame's pose in one sweep, in frame order (the links in the file's order, then the
/// extra frames), written into the workspace. Checks q.
///
/// Per joint, parents first: J_k = J_parent(k) · X_k · e^{[a_k]θ_k} (J of "no parent" = T_base);
/// per frame: T_F = J_support(F) · P_F (the module's formulas). Pinocchio's
/// `forwardKinematics` + `updateFramePlacements`.
///
/// ```
/// use screwkit_model::{urdf, KinematicTree};
/// use screwkit_solve::tree::fk::fk_frames;
/// use screwkit_solve::{TreeKinematics, TreeWorkspace};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/torso_two_arms.urdf");
/// let model = KinematicTree::from_tree(&urdf::load_file(path)?)?;
/// let kin = TreeKinematics::new(&model)?;
/// let mut ws = TreeWorkspace::new(&kin);
/// let head = kin.frame("head")?;
/// // The waist turns the head about z; nothing else moves it.
/// let q = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7];
/// let frames = fk_frames(&kin, &mut ws, &q)?;
/// assert!((frames[head].translation() - nalgebra::Vector3::new(0.0, 0.0, 1.4)).norm() < 1e-12);
/// let r = frames[head].rotation();
/// assert!((r[(1, 0)] - 0.1f64.sin()).abs() < 1e-15 && (r[(0, 0)] - 0.1f64.cos()).abs() < 1e-15);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fk_frames<'w>(
    kin: &TreeKinematics,
    ws: &'w mut TreeWorkspace,
    q: &[f64],
) -> Result<&'w [Se3], SolveError> {
    let base = kin.check_q(q)?;
    ws.fit(kin);
    frames_unchecked(kin, ws, q, &base);
    Ok(&ws.frames)
}

/// [`fk_frames`] without the checks (q has nq finite values; `base` is its base pose).
pub(crate) fn frames_unchecked(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    base: &Se3,
) {
    let TreeWorkspace {
        joint_poses,
        theta,
        sin,
        cos,
        frame_columns,
        frames,
        ..
    } = ws;
    dispatch(AllFrames {
        kin,
        q: &q[kin.q_offset()..],
        base: Columns::from_se3(base),
        joint_poses,
        theta,
        sin,
        cos,
        out: frame_columns,
    });
    // Converted outside the AVX2 clone (see `crate::fk::fk_unchecked`).
    for (o, c) in frames.iter_mut().zip(frame_columns.iter()) {
        *o = c.to_se3();
    }
}

/// The sweep kernel of [`fk_frames`].
struct AllFrames<'a> {
    kin: &'a TreeKinematics,
    /// The joint variables.
    q: &'a [f64],
    base: Columns,
    joint_poses: &'a mut [Columns],
    theta: &'a mut [f64],
    sin: &'a mut [f64],
    cos: &'a mut [f64],
    out: &'a mut [Columns],
}

impl Kernel for AllFrames<'_> {
    type Output = ();
    #[inline(always)]
    fn run<A: MulAdd>(self) {
        let kin = self.kin;
        for (t, j) in self.theta.iter_mut().zip(&kin.sweep) {
            *t = j.motion.drive.theta(self.q);
        }
        sin_cos_lanes::<A>(self.theta, self.sin, self.cos);
        for (k, j) in kin.sweep.iter().enumerate() {
            let p = kin.parent[k];
            let parent = if p == NONE {
                &self.base
            } else {
                &self.joint_poses[p]
            };
            let mut g = j.fixed.apply::<A>(parent);
            j.motion
                .apply::<A>(&mut g, self.theta[k], self.sin[k], self.cos[k]);
            self.joint_poses[k] = g;
        }
        for (o, f) in self.out.iter_mut().zip(&kin.frames) {
            let g = if f.support == NONE {
                &self.base
            } else {
                &self.joint_poses[f.support]
            };
            *o = f.placement.apply::<A>(g);
        }
    }
}

/// sin θ and cos θ of every angle of `theta` (whole lanes of [`trig::LANES`]), into `sin` and
/// `cos`: the lane sin/cos of the sweeps.
#[inline(always)]
pub(crate) fn sin_cos_lanes<A: MulAdd>(theta: &[f64], sin: &mut [f64], cos: &mut [f64]) {
    const L: usize = trig::LANES;
    for ((t, s), c) in theta
        .chunks_exact(L)
        .zip(sin.chunks_exact_mut(L))
        .zip(cos.chunks_exact_mut(L))
    {
        let (mut ls, mut lc) = ([0.0; L], [0.0; L]);
        let lt: &[f64; L] = t.try_into().expect("whole lanes");
        trig::sin_cos_lanes_with::<A>(lt, &mut ls, &mut lc);
        s.copy_from_slice(&ls);
        c.copy_from_slice(&lc);
    }
}

/// One frame's pose T_F(q) (frame index from [`TreeKinematics::frame`]). Checks q and the
/// index. Runs the chain kernel of the frame's path ([`crate::fk::fk`]) on its variables.
pub fn fk_frame(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    frame: usize,
) -> Result<Se3, SolveError> {
    kin.check_frame(frame)?;
    let base = kin.check_q(q)?;
    ws.fit(kin);
    Ok(frame_unchecked(kin, ws, q, &base, frame))
}

/// [`fk_frame`] without the checks.
#[inline]
pub(crate) fn frame_unchecked(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    base: &Se3,
    frame: usize,
) -> Se3 {
    let f = &kin.frames[frame];
    let local = match kin.view(frame) {
        None => f.home,
        Some(view) => {
            let vq = gather(kin, view, q, &mut ws.view_q);
            fk_unchecked(&view.kin, vq)
        }
    };
    if kin.floating {
        base.compose(&local)
    } else {
        local
    }
}

/// The chain's variables of `view` gathered from q into `buf`.
#[inline(always)]
pub(crate) fn gather<'b>(
    kin: &TreeKinematics,
    view: &View,
    q: &[f64],
    buf: &'b mut [f64],
) -> &'b [f64] {
    let joints = &q[kin.q_offset()..];
    let out = &mut buf[..view.variables.len()];
    for (o, &v) in out.iter_mut().zip(&view.variables) {
        *o = joints[v];
    }
    out
}

/// The pose of frame `a` in frame `b`: T_B⁻¹ T_A (a hand relative to the head, one hand
/// relative to the other). Checks q and the indices.
pub fn relative_pose(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    a: usize,
    b: usize,
) -> Result<Se3, SolveError> {
    kin.check_frame(a)?;
    kin.check_frame(b)?;
    let base = kin.check_q(q)?;
    ws.fit(kin);
    let ta = frame_unchecked(kin, ws, q, &base, a);
    let tb = frame_unchecked(kin, ws, q, &base, b);
    Ok(tb.inverse_compose(&ta))
}
