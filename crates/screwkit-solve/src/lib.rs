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
mod block;
mod columns;
pub mod error;
pub mod family;
pub mod fk;
pub mod ik;
pub mod jacobian;
mod kinematics;
pub mod linalg;
pub mod path;
mod poe;
pub mod sample;
pub mod subproblem;
pub mod timing;
pub mod tree;
pub mod velocity;
mod workspace;

pub use error::{BadTarget, RowError, SolveError};
pub use jacobian::JacobianKind;
pub use kinematics::Kinematics;
/// The box QP's old path; it lives in [`linalg`] now.
pub use linalg::box_qp;
pub use screwkit_lie::Frame;
#[allow(deprecated)]
pub use tree::Form;
pub use tree::{TreeKinematics, TreeWorkspace};
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
    .chain([("every update", every_update())])
    .collect()
}

/// A chain with a joint for every update of [`poe::PoeJoint::apply`]: axes near a coordinate
/// axis (1e-11 off, as rounded π/2 puts them), helical joints about exact and near axes, a
/// general axis, a prismatic joint, and ten joints in all (blocks of four and a remainder).
#[cfg(test)]
fn every_update() -> Kinematics {
    use nalgebra::Vector3;
    let revolute = |w: Vector3<f64>, at: Vector3<f64>, pitch: f64| {
        let w = w.normalize();
        let v = -w.cross(&at) + pitch * w;
        [w.x, w.y, w.z, v.x, v.y, v.z]
    };
    let screws = vec![
        revolute(
            Vector3::new(3e-11, -2e-12, 1.0),
            Vector3::new(0.1, 0.2, 0.0),
            0.0,
        ),
        revolute(Vector3::x(), Vector3::new(0.0, 0.1, 0.3), 0.05),
        revolute(
            Vector3::new(0.3, -0.5, 0.8),
            Vector3::new(0.2, 0.0, 0.4),
            0.0,
        ),
        [0.0, 0.0, 0.0, 0.0, 0.6, 0.8],
        revolute(
            Vector3::new(1e-10, -1.0, 4e-11),
            Vector3::new(0.3, 0.0, 0.5),
            0.0,
        ),
        revolute(Vector3::x(), Vector3::new(0.0, 0.2, 0.6), 0.0),
        revolute(
            Vector3::new(1.0, 2e-11, 0.0),
            Vector3::new(0.0, 0.1, 0.7),
            0.1,
        ),
        revolute(Vector3::y(), Vector3::new(0.4, 0.0, 0.8), -0.02),
        revolute(
            Vector3::new(0.0, 0.6, -0.8),
            Vector3::new(0.1, 0.1, 0.9),
            0.0,
        ),
        revolute(-Vector3::z(), Vector3::new(0.2, 0.3, 0.0), 0.03),
    ];
    let home = [
        0.0, -1.0, 0.0, 0.3, 1.0, 0.0, 0.0, 0.1, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0,
    ];
    let limits = vec![(-3.0, 3.0); screws.len()];
    let robot = screwkit_model::screws::ScrewRobot::new(
        "every update",
        home,
        screws,
        screwkit_lie::Frame::Space,
        Some(limits),
        None,
    )
    .unwrap();
    Kinematics::new(&robot.chain().unwrap())
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

    /// The block kernels on every lane path this CPU has equal the single-pose kernels with
    /// that path's multiply-add policy, bit for bit (the dispatched batch tests cover only the
    /// path this process runs).
    #[test]
    fn block_kernels_equal_single_kernels_on_every_path() {
        use crate::block::{SpaceJacobianBlock, TipBlock, W};
        use screwkit_lie::fma::{KernelPath, MulAdd};
        use screwkit_lie::lanes::dispatch_lanes_on;
        fn check<A: MulAdd>(path: KernelPath, file: &str, kin: &crate::Kinematics) -> bool {
            let n = kin.dof();
            let mut qs = crate::sample::configurations(kin, W, 5);
            // Angles past the vector sine's reduction range in one lane: its joint's eight
            // angles take the scalar path, each with the value the single call gives it.
            qs[3 * n] = 1e6;
            let (mut poses, mut jac, mut jposes) =
                (vec![0.0; 16 * W], vec![0.0; 6 * n * W], vec![0.0; 16 * W]);
            let tip = TipBlock {
                kin,
                qs: &qs,
                out: &mut poses,
            };
            match dispatch_lanes_on(path, tip) {
                Err(_) => return false,
                Ok(done) => assert!(done, "{file} {path:?}"),
            }
            // A value that is not finite anywhere in the block: refused, nothing written (the
            // batch then goes row by row).
            for bad in [f64::NAN, f64::INFINITY] {
                let mut qs = qs.clone();
                qs[W * n - 1] = bad;
                let mut untouched = vec![7.0; 16 * W];
                let tip = TipBlock {
                    kin,
                    qs: &qs,
                    out: &mut untouched,
                };
                assert_eq!(dispatch_lanes_on(path, tip).ok(), Some(false));
                assert!(untouched.iter().all(|x| *x == 7.0));
            }
            if kin.identity_map {
                let block = SpaceJacobianBlock {
                    kin,
                    qs: &qs,
                    jac: &mut jac,
                    poses: Some(&mut jposes),
                };
                assert_eq!(dispatch_lanes_on(path, block).ok(), Some(true));
            }
            let mut j1 = Matrix6xX::zeros(n);
            for (l, q) in qs.chunks(n).enumerate() {
                let mut want = [0.0; 16];
                TipPose { kin, q }
                    .run::<A>()
                    .to_se3()
                    .write_row_major(&mut want);
                assert_eq!(&poses[16 * l..16 * (l + 1)], &want, "{file} {path:?}");
                if !kin.identity_map {
                    continue;
                }
                assert_eq!(&jposes[16 * l..16 * (l + 1)], &want, "{file} {path:?}");
                PoseAndJacobian {
                    kin,
                    jac: &mut j1,
                    q,
                    frame: Frame::Space,
                }
                .run::<A>();
                let mut row_major = vec![0.0; 6 * n];
                crate::batch::write_jacobian(&j1, &mut row_major);
                assert_eq!(
                    &jac[6 * n * l..6 * n * (l + 1)],
                    &row_major[..],
                    "{file} {path:?}"
                );
            }
            true
        }
        let mut paths = 0;
        for (file, kin) in test_chains() {
            if kin.dof() == 0 {
                continue;
            }
            paths = 0;
            for path in KernelPath::ALL {
                let ran = if path == KernelPath::Portable {
                    check::<Plain>(path, file, &kin)
                } else {
                    check::<Fused>(path, file, &kin)
                };
                paths += ran as usize;
            }
        }
        let have = KernelPath::ALL.iter().filter(|p| p.available()).count();
        assert_eq!(paths, have);
    }
}
