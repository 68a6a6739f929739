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
pub mod batch;
mod columns;
mod dls;
pub mod error;
pub mod fk;
pub mod ik;
pub mod jacobian;
mod kinematics;
mod poe;
pub mod sample;
pub mod velocity;
mod workspace;

pub use error::{RowError, SolveError};
pub use kinematics::Kinematics;
pub use screwkit_lie::Frame;
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
