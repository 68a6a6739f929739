//! # screwkit-solve
//!
//! Kinematics on a [`screwkit_model::Chain`] with the product of exponentials: forward
//! kinematics, space/body Jacobians, singularity analysis, joint velocities, inverse
//! kinematics, and batches of each.
//!
//! The design follows Pinocchio's model/data split: [`Kinematics`] is immutable and shared,
//! [`Workspace`] is per-thread scratch, and the hot paths allocate nothing:
//! `algorithm(&kin, &mut ws, q)`.
//!
//! ```
//! use screwkit_solve::{fk, ik, Kinematics, Workspace};
//! let chain = screwkit_model::load_chain(
//!     concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/ur5.urdf"), None, None)?;
//! let kin = Kinematics::new(&chain);
//! let mut ws = Workspace::new(&kin);
//! let q = [0.1, -0.5, 1.0, 0.2, 0.3, -0.4];
//! let target = fk::fk(&kin, &q)?;
//! let sol = ik::solve(&kin, &mut ws, &target, &kin.midpoint(), &ik::IkOptions::default())?;
//! assert!(sol.converged);
//! assert!(fk::fk(&kin, &sol.q)?.max_abs_diff(&target) < 1e-8);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod analysis;
pub mod batch;
mod columns;
pub mod dls;
pub mod error;
pub mod fk;
pub mod ik;
pub mod jacobian;
pub mod kinematics;
pub mod protocol;
pub mod velocity;

pub use error::SolveError;
pub use jacobian::Frame;
pub use kinematics::{Kinematics, Workspace};
