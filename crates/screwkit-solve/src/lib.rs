//! # screwkit-solve
//!
//! Kinematics on a [`screwkit_model::Chain`] with the product of exponentials: forward
//! kinematics, space/body Jacobians, singularity analysis, joint velocities and torques,
//! inverse kinematics, and batches of each.
//!
//! ## The shape of every algorithm
//!
//! Pinocchio's model/data split: [`Kinematics`] is the immutable model (build once, share
//! between threads), [`Workspace`] the per-thread scratch, and every algorithm is
//!
//! ```text
//! algorithm(&kin, &mut ws, inputs…) -> Result<outputs, SolveError>
//! ```
//!
//! checking its inputs (q of the right length and finite, finite targets) and allocating
//! nothing in its hot loop. Bulky outputs (Jacobians, link poses) live in the workspace and
//! are returned by reference. Batch functions take the model and flat row-major buffers —
//! `batch(&kin, inputs, outputs)` — and keep one workspace per worker inside ([`batch`]).
//!
//! | algorithm | returns |
//! |---|---|
//! | [`fk::fk`] | the tip pose T(q) |
//! | [`fk::fk_all_links`] | every link's pose, in the order of [`Kinematics::links`] |
//! | [`jacobian::jacobian`], [`jacobian::fk_jacobian`] | J_s or J_b (6 × n), with the pose |
//! | [`analysis::analyze`] | singular values, rank, manipulability, condition, a verdict |
//! | [`velocity::joint_velocities`], [`velocity::joint_torques`] | q̇ from V, τ from F |
//! | [`ik::solve`], [`ik::solve_into`] | q with T(q) = T_sd, and how the solve ended |
//! | [`batch::fk_batch`], [`batch::jacobian_batch`], [`batch::ik_batch`] | the same for N rows |
//!
//! The whole robot (a tree of frames, a floating base) is [`tree`]: [`TreeKinematics`] +
//! [`TreeWorkspace`], every frame's pose in one sweep, any frame's Jacobian in three forms,
//! relative poses and Jacobians, configurations on SE(3) × ℝⁿ.
//!
//! Errors are [`SolveError`]: bad input (wrong length, NaN, a bad target, bad options) or a
//! numerical failure, told apart by [`SolveError::is_invalid_input`].
//!
//! ```
//! use screwkit_solve::{fk, ik, Kinematics, Workspace};
//! let chain = screwkit_model::load_chain(
//!     concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/ur5.urdf"), None, None)?;
//! let kin = Kinematics::new(&chain);
//! let mut ws = Workspace::new(&kin);
//! let q = [0.1, -0.5, 1.0, 0.2, 0.3, -0.4];
//! let target = fk::fk(&kin, &mut ws, &q)?;
//! let sol = ik::solve(&kin, &mut ws, &target, &kin.midpoint(), &ik::IkOptions::default())?;
//! assert!(sol.status.converged);
//! assert!(fk::fk(&kin, &mut ws, &sol.q)?.max_abs_diff(&target) < 1e-8);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod analysis;
pub mod analytic;
pub mod batch;
pub mod box_qp;
mod columns;
mod dls;
mod eigen;
pub mod error;
pub mod family;
pub mod fk;
pub mod ik;
pub mod jacobian;
mod kinematics;
mod poe;
pub mod sample;
pub mod subproblem;
mod svd;
pub mod tree;
pub mod velocity;
mod workspace;

pub use error::{BadTarget, RowError, SolveError};
pub use kinematics::Kinematics;
pub use screwkit_lie::Frame;
pub use tree::{Form, TreeKinematics, TreeWorkspace};
pub use workspace::Workspace;

/// The bundled chains the unit tests run every kernel on: (file, prepared chain).
#[cfg(test)]
pub(crate) fn test_chains() -> Vec<(&'static str, Kinematics)> {
    [
        ("ur5.urdf", None, None),
        ("panda.urdf", None, None),
        ("iiwa14.urdf", None, None),
        ("scara.urdf", None, None),
        ("tricky.urdf", Some("base_link"), None),
        ("gripper_arm.urdf", None, Some("right_finger")),
    ]
    .into_iter()
    .map(|(file, base, tip)| {
        let path = format!("{}/../../assets/urdf/{file}", env!("CARGO_MANIFEST_DIR"));
        let chain = screwkit_model::load_chain(&path, base, tip).unwrap();
        (file, Kinematics::new(&chain))
    })
    .collect()
}

/// Every kernel's portable and fused instantiations agree (the public functions run only one
/// of them on a given CPU; the integration tests check that one against the oracles). `Fused`
/// outside the dispatched clone is slow but computes the same values.
#[cfg(test)]
mod kernels_agree {
    use crate::fk::{LinkPoses, TipPose};
    use crate::jacobian::PoseAndJacobian;
    use crate::{test_chains, Frame, Workspace};
    use nalgebra::Matrix6xX;
    use screwkit_lie::fma::{Fused, Kernel, Plain};

    #[test]
    fn portable_and_fused_kernels_agree() {
        for (file, kin) in test_chains() {
            let n = kin.dof();
            let mut ws = Workspace::new(&kin);
            let (mut lp, mut lf) = (ws.link_columns.clone(), ws.link_columns.clone());
            let (mut jp, mut jf) = (Matrix6xX::zeros(n), Matrix6xX::zeros(n));
            for q in crate::sample::configurations(&kin, 50, 99).chunks(n) {
                let t = crate::fk::fk(&kin, &mut ws, q).unwrap();
                for other in [
                    TipPose { kin: &kin, q }.run::<Plain>().to_se3(),
                    TipPose { kin: &kin, q }.run::<Fused>().to_se3(),
                ] {
                    assert!(t.max_abs_diff(&other) < 1e-14, "{file}");
                }
                LinkPoses {
                    kin: &kin,
                    out: &mut lp,
                    q,
                }
                .run::<Plain>();
                LinkPoses {
                    kin: &kin,
                    out: &mut lf,
                    q,
                }
                .run::<Fused>();
                for (a, b) in lp.iter().zip(&lf) {
                    assert!(a.to_se3().max_abs_diff(&b.to_se3()) < 1e-14, "{file}");
                }
                for frame in Frame::ALL {
                    let tp = PoseAndJacobian {
                        kin: &kin,
                        jac: &mut jp,
                        q,
                        frame,
                    }
                    .run::<Plain>();
                    let tf = PoseAndJacobian {
                        kin: &kin,
                        jac: &mut jf,
                        q,
                        frame,
                    }
                    .run::<Fused>();
                    assert!(
                        tp.max_abs_diff(&tf) < 1e-14 && tp.max_abs_diff(&t) < 1e-14,
                        "{file}"
                    );
                    assert!((&jp - &jf).amax() < 1e-14, "{file} {frame:?}");
                }
            }
        }
    }

    /// The block kernels with each policy equal the single-pose kernels with the same policy,
    /// bit for bit (the dispatched batch tests cover only the policy this CPU runs).
    #[test]
    fn block_kernels_equal_single_kernels_under_both_policies() {
        use crate::columns::W;
        use crate::fk::TipBlock;
        use crate::jacobian::SpaceJacobianBlock;
        use screwkit_lie::fma::MulAdd;
        fn check<A: MulAdd>(file: &str, kin: &crate::Kinematics) {
            let n = kin.dof();
            let qs = crate::sample::configurations(kin, W, 5);
            let (mut poses, mut jac, mut jposes) =
                (vec![0.0; 16 * W], vec![0.0; 6 * n * W], vec![0.0; 16 * W]);
            TipBlock {
                kin,
                qs: &qs,
                out: &mut poses,
            }
            .run::<A>();
            SpaceJacobianBlock {
                kin,
                qs: &qs,
                jac: &mut jac,
                poses: Some(&mut jposes),
            }
            .run::<A>();
            let mut j1 = Matrix6xX::zeros(n);
            for (l, q) in qs.chunks(n).enumerate() {
                let mut want = [0.0; 16];
                TipPose { kin, q }
                    .run::<A>()
                    .to_se3()
                    .write_row_major(&mut want);
                assert_eq!(&poses[16 * l..16 * (l + 1)], &want, "{file}");
                assert_eq!(&jposes[16 * l..16 * (l + 1)], &want, "{file}");
                PoseAndJacobian {
                    kin,
                    jac: &mut j1,
                    q,
                    frame: Frame::Space,
                }
                .run::<A>();
                let mut row_major = vec![0.0; 6 * n];
                crate::batch::write_jacobian(&j1, &mut row_major);
                assert_eq!(&jac[6 * n * l..6 * n * (l + 1)], &row_major[..], "{file}");
            }
        }
        for (file, kin) in test_chains() {
            if kin.dof() > 0 && kin.identity_map {
                check::<Plain>(file, &kin);
                check::<Fused>(file, &kin);
            }
        }
    }
}
