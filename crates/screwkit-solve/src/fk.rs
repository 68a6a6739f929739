//! Forward kinematics: T(q) = e^\[S₁\]θ₁ ⋯ e^\[Sₙ\]θₙ M (*Modern Robotics* eq. 4.14), for the tip
//! and for every link of the chain.
//!
//! θ_j follows from q by each joint's [`screwkit_model::Drive`] (θ_j = q_j for ordinary joints,
//! m q_leader + o for mimic joints). The kernels run on the column form of the pose
//! (`columns.rs`) through the one dispatch of [`screwkit_lie::fma`] (portable, or AVX2 + FMA
//! chosen at run time; the two agree to the last bit or so).

use screwkit_lie::fma::{dispatch, Kernel, MulAdd};
use screwkit_lie::Se3;

use crate::columns::Columns;
use crate::error::SolveError;
use crate::kinematics::Kinematics;
use crate::poe::walk;
use crate::workspace::Workspace;

/// The tip pose T(q) = e^\[S₁\]θ₁ ⋯ e^\[Sₙ\]θₙ M. Checks q (length, finite).
///
/// The workspace is not used by the tip pose (it needs no scratch) but is taken like in every
/// algorithm, so that callers hold one shape: `algorithm(&kin, &mut ws, inputs)`.
///
/// ```
/// use screwkit_solve::{fk::fk, Kinematics, Workspace};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/planar_3r.urdf");
/// let chain = screwkit_model::load_chain(path, None, None)?;
/// let kin = Kinematics::new(&chain);
/// let mut ws = Workspace::new(&kin);
/// // Links of 1.0, 0.8 and 0.5 m in the plane: the closed form x = Σ L_i cos(θ_1 + … + θ_i).
/// let q = [0.3, 0.6, -0.4];
/// let t = fk(&kin, &mut ws, &q)?;
/// let (a1, a2, a3) = (0.3f64, 0.9f64, 0.5f64);
/// let x = a1.cos() + 0.8 * a2.cos() + 0.5 * a3.cos();
/// let y = a1.sin() + 0.8 * a2.sin() + 0.5 * a3.sin();
/// assert!((t.translation() - nalgebra::Vector3::new(x, y, 0.0)).norm() < 1e-14);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[inline]
pub fn fk(kin: &Kinematics, _ws: &mut Workspace, q: &[f64]) -> Result<Se3, SolveError> {
    kin.check_q(q)?;
    Ok(fk_unchecked(kin, q))
}

/// [`fk`] without the checks: q must have `dof` finite entries (panics if shorter).
#[inline]
pub(crate) fn fk_unchecked(kin: &Kinematics, q: &[f64]) -> Se3 {
    // The kernel returns the pose as columns and the conversion happens here, outside the
    // AVX2 clone: the clone's 32-byte column stores forward to the loads below, whereas an
    // `Se3` written field by field inside the clone and copied out here stalled on
    // store-to-load forwarding (≈ 15 ns per call, measured).
    dispatch(TipPose { kin, q }).to_se3()
}

/// The tip-pose kernel: T = (Π_j e^[S_j]θ_j) M on columns (returned as columns; see
/// [`fk_unchecked`]).
pub(crate) struct TipPose<'a> {
    pub(crate) kin: &'a Kinematics,
    pub(crate) q: &'a [f64],
}

impl Kernel for TipPose<'_> {
    type Output = Columns;
    #[inline(always)]
    fn run<A: MulAdd>(self) -> Columns {
        let kin = self.kin;
        let mut t = Columns::identity();
        walk::<A>(
            &kin.space,
            kin.identity_map,
            self.q,
            |_, jc, theta, s, c| jc.apply::<A>(&mut t, theta, s, c),
        );
        t.compose::<A>(kin.home.rotation(), &(*kin.home.translation()).into())
    }
}

/// The poses of every link on the chain, base first, tip last (the order of
/// [`Kinematics::links`]), written into the workspace: link k is e^\[S₁\]θ₁ ⋯ e^\[S_m\]θ_m · home_k
/// with m the joints before it. Checks q.
pub fn fk_all_links<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<&'w [Se3], SolveError> {
    kin.check_q(q)?;
    ws.fit(kin);
    link_poses_unchecked(kin, &mut ws.link_columns, &mut ws.links, q);
    Ok(&ws.links)
}

/// [`fk_all_links`] without the checks: the kernel writes each link's pose as columns into
/// `columns` and the conversion to `Se3` into `out` happens here, outside the AVX2 clone (see
/// [`fk_unchecked`]).
#[inline]
pub(crate) fn link_poses_unchecked(
    kin: &Kinematics,
    columns: &mut [Columns],
    out: &mut [Se3],
    q: &[f64],
) {
    dispatch(LinkPoses {
        kin,
        out: columns,
        q,
    });
    for (o, c) in out.iter_mut().zip(columns.iter()) {
        *o = c.to_se3();
    }
}

/// The all-link kernel: the links before the first joint are their home poses; after joint j,
/// the links with j + 1 joints before them are (prefix through j) · home.
pub(crate) struct LinkPoses<'a> {
    pub(crate) kin: &'a Kinematics,
    pub(crate) out: &'a mut [Columns],
    pub(crate) q: &'a [f64],
}

impl Kernel for LinkPoses<'_> {
    type Output = ();
    #[inline(always)]
    fn run<A: MulAdd>(self) {
        let (kin, out) = (self.kin, self.out);
        let links = &kin.links;
        let mut prefix = Columns::identity();
        let mut k = 0;
        while k < links.len() && links[k].joints_before == 0 {
            out[k] = kin.link_columns[k];
            k += 1;
        }
        walk::<A>(
            &kin.space,
            kin.identity_map,
            self.q,
            |j, jc, theta, s, c| {
                jc.apply::<A>(&mut prefix, theta, s, c);
                while k < links.len() && links[k].joints_before == j + 1 {
                    let home = &links[k].home;
                    out[k] = prefix.compose::<A>(home.rotation(), &(*home.translation()).into());
                    k += 1;
                }
            },
        );
    }
}
