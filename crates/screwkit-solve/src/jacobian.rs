//! Space and body Jacobians, computed with the tip pose in one O(n) pass.
//!
//! Space: J_s column i = \[Ad_{e^\[S₁\]θ₁ ⋯ e^[S_{i−1}]θ_{i−1}}\] S_i, so V_s = J_s q̇ (*Modern
//! Robotics* eq. 5.11). Body: J_b = \[Ad_{T⁻¹}\] J_s, so V_b = J_b q̇ (eq. 5.18). Rows are
//! (ω, v). With mimic joints, the column of a variable is Σ multiplier_j · (column of joint j)
//! over the joints it drives.

use nalgebra::Matrix6xX;
use screwkit_lie::fma::{dispatch, Kernel, MulAdd};
use screwkit_lie::{Frame, Se3};

use crate::columns::{Columns, Lane};
use crate::error::SolveError;
use crate::kinematics::Kinematics;
use crate::poe::{walk, walk_rev, PoeJoint};
use crate::workspace::Workspace;

/// Which Jacobian of a frame: the one kind for a chain's tip and for any frame of a tree (the
/// rows are (ω, v) in each; `From<Frame>` gives the space and body kinds).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum JacobianKind {
    /// J_s: the frame's spatial twist, in the world (base) frame: V_s = J_s q̇. Column j is
    /// joint j's screw axis at q (*Modern Robotics* eq. 5.11).
    Space,
    /// J_b = \[Ad_{T⁻¹}\] J_s: the frame's body twist, in the frame itself (eq. 5.18).
    Body,
    /// The frame's angular velocity and its origin's linear velocity, both in the world's
    /// axes (Pinocchio's `LOCAL_WORLD_ALIGNED`, Robotics Toolbox's `jacob0`): (ω, v_s + ω × p)
    /// ([`space_to_world_aligned`]).
    WorldAligned,
}

impl From<Frame> for JacobianKind {
    fn from(f: Frame) -> JacobianKind {
        match f {
            Frame::Space => JacobianKind::Space,
            Frame::Body => JacobianKind::Body,
        }
    }
}

impl JacobianKind {
    /// The frame of the screw pass that makes this kind (the world-aligned one comes from the
    /// space pass).
    #[inline]
    pub fn pass(self) -> Frame {
        match self {
            JacobianKind::Body => Frame::Body,
            JacobianKind::Space | JacobianKind::WorldAligned => Frame::Space,
        }
    }
}

/// The tip pose and the Jacobian of one pass (see [`fk_jacobian`]).
///
/// `repr(C)` with the pose first: the kernel then writes the pose straight into the caller's
/// result (as it did when this was a tuple), with no copy between the AVX2 clone's stores and
/// the caller's loads (measured: the copy stalled on store-to-load forwarding, 10–20 ns).
#[derive(Debug, Clone, Copy)]
#[repr(C)]
pub struct PoseJacobian<'w> {
    /// T(q): the tip pose in the base frame.
    pub pose: Se3,
    /// J(q) in the requested frame, 6 × dof, rows (ω, v); it lives in the workspace.
    pub jacobian: &'w Matrix6xX<f64>,
}

/// The Jacobian J_s(q) or J_b(q) (6 × dof, rows (ω, v)), in the workspace. Checks q.
///
/// ```
/// use screwkit_solve::{fk::fk, jacobian::jacobian, Frame, Kinematics, Workspace};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/ur5.urdf");
/// let kin = Kinematics::new(&screwkit_model::load_chain(path, None, None)?);
/// let mut ws = Workspace::new(&kin);
/// let q = [0.1, -0.5, 1.0, 0.2, 0.3, -0.4];
/// let j_s = jacobian(&kin, &mut ws, &q, Frame::Space)?.clone();
/// // Column 3 is the elbow's screw at q: its linear part is the velocity of the point at the
/// // base origin, so moving the elbow by h moves the tip by ≈ h (ω × p + v).
/// let h = 1e-6;
/// let (mut lo, mut hi) = (q, q);
/// lo[2] -= h;
/// hi[2] += h;
/// let (t0, t1, t) = (fk(&kin, &mut ws, &lo)?, fk(&kin, &mut ws, &hi)?, fk(&kin, &mut ws, &q)?);
/// let dp = (t1.translation() - t0.translation()) / (2.0 * h);
/// let (w, v) = (j_s.fixed_view::<3, 1>(0, 2), j_s.fixed_view::<3, 1>(3, 2));
/// assert!((dp - (w.cross(t.translation()) + v)).norm() < 1e-8);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn jacobian<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
    kind: impl Into<JacobianKind>,
) -> Result<&'w Matrix6xX<f64>, SolveError> {
    Ok(fk_jacobian(kin, ws, q, kind)?.jacobian)
}

/// The tip-point Jacobian in base axes: [`jacobian`] with [`JacobianKind::WorldAligned`].
#[deprecated(note = "use `jacobian(kin, ws, q, JacobianKind::WorldAligned)`")]
pub fn jacobian_world_aligned<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<&'w Matrix6xX<f64>, SolveError> {
    jacobian(kin, ws, q, JacobianKind::WorldAligned)
}

/// Every column of a space Jacobian made world-aligned at p ([`space_to_world_aligned`]).
pub(crate) fn world_aligned_columns(jac: &mut Matrix6xX<f64>, p: &nalgebra::Vector3<f64>) {
    for c in 0..jac.ncols() {
        let mut col = [0.0; 6];
        for (r, x) in col.iter_mut().enumerate() {
            *x = jac[(r, c)];
        }
        space_to_world_aligned(&mut col, p);
        for (r, x) in col.iter().enumerate() {
            jac[(r, c)] = *x;
        }
    }
}

/// One column of J_s, (ω, v) with v the velocity of the body point at the base origin, made a
/// column of J_wa: (ω, v + ω × p), the velocity of the point at p (the tip) instead.
#[inline]
pub fn space_to_world_aligned(column: &mut [f64; 6], p: &nalgebra::Vector3<f64>) {
    let (w0, w1, w2) = (column[0], column[1], column[2]);
    column[3] += w1 * p[2] - w2 * p[1];
    column[4] += w2 * p[0] - w0 * p[2];
    column[5] += w0 * p[1] - w1 * p[0];
}

/// Every chain joint's screw axis at q in the space frame, one per joint of the chain in chain
/// order (mimic joints included: `kin.links()` and the model's `Chain::joints` order):
/// S_j(q) = \[Ad_{e^\[S₁\]θ₁ ⋯ e^\[S_{j−1}\]θ_{j−1}}\] S_j, the axis the joint turns about (or
/// slides along) at this configuration. Without mimic joints these are the columns of J_s(q);
/// with them, column k of J_s is Σ m_j S_j(q) over the joints driven by q_k. For pictures and
/// analysis, not a hot path (it uses the general `Se3::exp`). Checks q.
pub fn joint_screws(
    kin: &Kinematics,
    _ws: &mut Workspace,
    q: &[f64],
) -> Result<Vec<screwkit_lie::Twist>, SolveError> {
    kin.check_q(q)?;
    let mut t = Se3::identity();
    let mut out = Vec::with_capacity(kin.space.len());
    for joint in &kin.space {
        let s = joint.twist();
        out.push(t.adjoint_apply(&s));
        let theta = joint.drive.theta(q);
        t = t.compose(&Se3::exp(&screwkit_lie::Twist::new(
            s.w * theta,
            s.v * theta,
        )));
    }
    Ok(out)
}

/// The tip pose and the Jacobian of `kind`, from the same pass (the cost of the Jacobian
/// alone). Checks q.
pub fn fk_jacobian<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
    kind: impl Into<JacobianKind>,
) -> Result<PoseJacobian<'w>, SolveError> {
    kin.check_q(q)?;
    ws.fit(kin);
    let kind = kind.into();
    let pose = fk_jacobian_into(kin, &mut ws.jacobian, q, kind.pass());
    if kind == JacobianKind::WorldAligned {
        world_aligned_columns(&mut ws.jacobian, pose.translation());
    }
    Ok(PoseJacobian {
        pose,
        jacobian: &ws.jacobian,
    })
}

/// Pose and Jacobian in `frame` in one pass, unchecked (q must have `dof` finite entries and
/// `jac` `dof` columns).
#[inline]
pub(crate) fn fk_jacobian_into(
    kin: &Kinematics,
    jac: &mut Matrix6xX<f64>,
    q: &[f64],
    frame: Frame,
) -> Se3 {
    dispatch(PoseAndJacobian { kin, jac, q, frame })
}

/// The one-pass kernel for the pose and the Jacobian, mimic columns summed with their
/// multipliers (column of a variable = Σ m_j · column of joint j).
///
/// Space: left to right, column j = \[Ad_{T_j}\] S_j with T_j = e^[S₁]θ₁ ⋯ e^[S_{j−1}]θ_{j−1};
/// then T = T_n M.
/// Body: right to left with the body screws, column j = \[Ad_{V_j}\] B_j with
/// V_j = e^{−[B_n]θ_n} ⋯ e^{−[B_{j+1}]θ_{j+1}} (*Modern Robotics* eq. 5.18), accumulated as
/// V ← V e^{−[B_j]θ_j}; at the end V = (e^[B₁]θ₁ ⋯ e^[Bₙ]θₙ)⁻¹, so T = M V⁻¹. Both passes use
/// the same kernels and cost the same.
pub(crate) struct PoseAndJacobian<'a> {
    pub(crate) kin: &'a Kinematics,
    pub(crate) jac: &'a mut Matrix6xX<f64>,
    pub(crate) q: &'a [f64],
    pub(crate) frame: Frame,
}

impl Kernel for PoseAndJacobian<'_> {
    type Output = Se3;
    #[inline(always)]
    fn run<A: MulAdd>(self) -> Se3 {
        let Self { kin, jac, q, frame } = self;
        if !kin.identity_map {
            jac.as_mut_slice().fill(0.0);
        }
        let mut store = |j: usize, jc: &PoeJoint, w: Lane, v: Lane| {
            if kin.identity_map {
                let mut dst = jac.column_mut(j);
                dst[0] = w[0];
                dst[1] = w[1];
                dst[2] = w[2];
                dst[3] = v[0];
                dst[4] = v[1];
                dst[5] = v[2];
            } else {
                let m = jc.drive.multiplier;
                let mut dst = jac.column_mut(jc.drive.variable);
                for i in 0..3 {
                    dst[i] = A::madd(m, w[i], dst[i]);
                    dst[i + 3] = A::madd(m, v[i], dst[i + 3]);
                }
            }
        };
        let mut t = Columns::identity();
        match frame {
            Frame::Space => {
                walk::<A>(&kin.space, kin.identity_map, q, |j, jc, theta, s, c| {
                    let (w, v) = jc.adjoint_column::<A>(&t);
                    store(j, jc, w, v);
                    jc.apply::<A>(&mut t, theta, s, c);
                });
                t.compose::<A>(kin.home.rotation(), &(*kin.home.translation()).into())
                    .to_se3()
            }
            Frame::Body => {
                walk_rev::<A>(&kin.body, kin.identity_map, q, |j, jb, theta, s, c| {
                    let (w, v) = jb.adjoint_column::<A>(&t);
                    store(j, jb, w, v);
                    jb.apply::<A>(&mut t, -theta, -s, c);
                });
                kin.home_columns.then::<A>(&t.inverse::<A>()).to_se3()
            }
        }
    }
}
