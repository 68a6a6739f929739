//! Space and body Jacobians, computed with the pose in one O(n) pass.
//!
//! Space: J_s column i = \[Ad_{e^[S₁]θ₁ ⋯ e^[S_{i−1}]θ_{i−1}}\] S_i, so V_s = J_s q̇.
//! Body: J_b = \[Ad_{T⁻¹}\] J_s, so V_b = J_b q̇. Rows are (ω, v). With mimic joints, the
//! column of a variable is Σ multiplier_j · (column of joint j) over the joints it drives.

use nalgebra::Matrix6xX;
use screwkit_lie::fma::{MulAdd, Plain};
use screwkit_lie::Se3;

use crate::columns::{Columns, Lane};

use crate::error::SolveError;
use crate::kinematics::{JointConst, Kinematics, Workspace};

/// Pose and Jacobian in `frame` in one pass, unchecked (q must have `dof` finite entries).
#[inline]
pub(crate) fn fk_jacobian_into(
    kin: &Kinematics,
    jac: &mut Matrix6xX<f64>,
    q: &[f64],
    frame: Frame,
) -> Se3 {
    #[cfg(target_arch = "x86_64")]
    if screwkit_lie::fma::fused_available() {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        return unsafe { fk_jacobian_fused(kin, jac, q, frame) };
    }
    fk_jacobian_with::<Plain>(kin, jac, q, frame)
}

/// [`fk_jacobian_with`] compiled for AVX2 + FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn fk_jacobian_fused(kin: &Kinematics, jac: &mut Matrix6xX<f64>, q: &[f64], frame: Frame) -> Se3 {
    fk_jacobian_with::<screwkit_lie::fma::Fused>(kin, jac, q, frame)
}

/// One pass for the pose and the Jacobian, mimic columns summed with their multipliers
/// (column of a variable = Σ m_j · column of joint j).
///
/// Space: left to right, column j = \[Ad_{T_j}\] S_j with T_j = e^[S₁]θ₁ ⋯ e^[S_{j−1}]θ_{j−1};
/// then T = T_n M.
/// Body: right to left with the body screws, column j = \[Ad_{V_j}\] B_j with
/// V_j = e^{−[B_n]θ_n} ⋯ e^{−[B_{j+1}]θ_{j+1}} (Modern Robotics eq. 5.18), accumulated as
/// V ← V e^{−[B_j]θ_j}; at the end V = (e^[B₁]θ₁ ⋯ e^[Bₙ]θₙ)⁻¹, so T = M V⁻¹. Both passes use
/// the same kernels and cost the same.
#[inline(always)]
fn fk_jacobian_with<A: MulAdd>(
    kin: &Kinematics,
    jac: &mut Matrix6xX<f64>,
    q: &[f64],
    frame: Frame,
) -> Se3 {
    if !kin.identity_map {
        jac.fill(0.0);
    }
    let mut store = |j: usize, jc: &JointConst, w: Lane, v: Lane| {
        if kin.identity_map {
            let mut dst = jac.column_mut(j);
            dst[0] = w[0];
            dst[1] = w[1];
            dst[2] = w[2];
            dst[3] = v[0];
            dst[4] = v[1];
            dst[5] = v[2];
        } else {
            let m = jc.multiplier;
            let mut dst = jac.column_mut(jc.variable);
            for i in 0..3 {
                dst[i] = A::madd(m, w[i], dst[i]);
                dst[i + 3] = A::madd(m, v[i], dst[i + 3]);
            }
        }
    };
    let mut t = Columns::identity();
    match frame {
        Frame::Space => {
            kin.walk::<A>(q, |j, jc, theta, s, c| {
                let (w, v) = jc.adjoint_column::<A>(&t);
                store(j, jc, w, v);
                jc.apply::<A>(&mut t, theta, s, c);
            });
            t.compose::<A>(kin.home.rotation(), &(*kin.home.translation()).into())
                .to_se3()
        }
        Frame::Body => {
            kin.walk_rev::<A>(q, |j, jb, theta, s, c| {
                let (w, v) = jb.adjoint_column::<A>(&t);
                store(j, jb, w, v);
                jb.apply::<A>(&mut t, -theta, -s, c);
            });
            kin.home_columns.then::<A>(&t.inverse::<A>()).to_se3()
        }
    }
}

/// The tip pose and the space Jacobian J_s(q) (6 × dof, in the workspace).
pub fn fk_jacobian_space<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<(Se3, &'w Matrix6xX<f64>), SolveError> {
    kin.check_q(q)?;
    let t = fk_jacobian_into(kin, &mut ws.jacobian, q, Frame::Space);
    Ok((t, &ws.jacobian))
}

/// The tip pose and the body Jacobian J_b(q) = \[Ad_{T⁻¹}\] J_s(q) (6 × dof, in the workspace).
pub fn fk_jacobian_body<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<(Se3, &'w Matrix6xX<f64>), SolveError> {
    kin.check_q(q)?;
    let t = fk_jacobian_into(kin, &mut ws.jacobian, q, Frame::Body);
    Ok((t, &ws.jacobian))
}

/// Which frame a Jacobian or twist is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    /// The base (space) frame.
    Space,
    /// The tip (body) frame.
    Body,
}

/// The Jacobian in the chosen frame, as an owned matrix (allocates; for one-off use).
pub fn jacobian(kin: &Kinematics, q: &[f64], frame: Frame) -> Result<Matrix6xX<f64>, SolveError> {
    let mut ws = Workspace::new(kin);
    match frame {
        Frame::Space => fk_jacobian_space(kin, &mut ws, q)?,
        Frame::Body => fk_jacobian_body(kin, &mut ws, q)?,
    };
    Ok(ws.jacobian)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fk::{fk_all_links_with, fk_with};
    use screwkit_lie::fma::Fused;

    /// The portable and the fused instantiations of every hot path agree (the public functions
    /// run only one of them on a given CPU; the integration tests check that one against the
    /// oracles). `Fused` outside an `fma` function is slow but computes the same values.
    #[test]
    fn portable_and_fused_paths_agree() {
        let chains = [
            ("ur5.urdf", None, None),
            ("panda.urdf", None, None),
            ("iiwa14.urdf", None, None),
            ("scara.urdf", None, None),
            ("tricky.urdf", Some("base_link"), None),
            ("gripper_arm.urdf", None, Some("right_finger")),
        ];
        for (file, base, tip) in chains {
            let path = format!("{}/../../assets/urdf/{file}", env!("CARGO_MANIFEST_DIR"));
            let kin = Kinematics::new(&screwkit_model::load_chain(&path, base, tip).unwrap());
            let n = kin.dof();
            let qs = crate::protocol::sample_configurations(&kin, 50, 99);
            let ws = Workspace::new(&kin);
            let (mut jp, mut jf) = (ws.jacobian.clone(), ws.jacobian.clone());
            let (mut lp, mut lf) = (ws.links.clone(), ws.links.clone());
            for q in qs.chunks(n) {
                let t = crate::fk::fk_unchecked(&kin, q);
                for other in [fk_with::<Plain>(&kin, q), fk_with::<Fused>(&kin, q)] {
                    assert!(t.max_abs_diff(&other) < 1e-14, "{file}");
                }
                fk_all_links_with::<Plain>(&kin, &mut lp, q);
                fk_all_links_with::<Fused>(&kin, &mut lf, q);
                for (a, b) in lp.iter().zip(&lf) {
                    assert!(a.max_abs_diff(b) < 1e-14, "{file}");
                }
                for frame in [Frame::Space, Frame::Body] {
                    let tp = fk_jacobian_with::<Plain>(&kin, &mut jp, q, frame);
                    let tf = fk_jacobian_with::<Fused>(&kin, &mut jf, q, frame);
                    assert!(tp.max_abs_diff(&tf) < 1e-14, "{file}");
                    assert!((&jp - &jf).amax() < 1e-14, "{file} {frame:?}");
                }
            }
        }
    }
}
