#![doc = include_str!("../README.md")]
//!
//! ## Crates
//!
//! This facade re-exports the workspace crates:
//! - [`lie`]: SO(3)/SE(3), twists, wrenches and screw axes ([`screwkit_lie`]).
//! - [`model`]: URDF → screw model ([`screwkit_model`]).
//! - [`solve`]: FK, Jacobians, IK ([`screwkit_solve`]).

/// The linear algebra crate of the API's vectors and matrices (`Vector3`, `Matrix6xX`, …), so
/// that a program needs no other dependency than `screwkit`.
pub use nalgebra;
pub use screwkit_lie as lie;
pub use screwkit_model as model;
pub use screwkit_solve as solve;

/// The names most programs need: `use screwkit::prelude::*;`.
pub mod prelude {
    pub use nalgebra::{Matrix4, Matrix6xX, Vector3, Vector6};
    pub use screwkit_lie::{ScrewAxis, Se3, Twist, Wrench};
    pub use screwkit_model::{load_chain, Chain, ModelError};
    pub use screwkit_solve::fk::{fk, fk_all_links};
    pub use screwkit_solve::ik::{IkMethod, IkOptions, IkResult, IkStatus};
    pub use screwkit_solve::jacobian::{fk_jacobian, jacobian};
    pub use screwkit_solve::{Frame, Kinematics, SolveError, Workspace};
}
