#![doc = include_str!("../README.md")]
//!
//! ## Crates
//!
//! This facade re-exports the workspace crates:
//! - [`lie`]: SO(3)/SE(3), twists, wrenches and screw axes ([`screwkit_lie`]).
//! - [`model`]: URDF → screw model ([`screwkit_model`]).
//! - [`solve`]: FK, Jacobians, IK ([`screwkit_solve`]).

pub use screwkit_lie as lie;
pub use screwkit_model as model;
pub use screwkit_solve as solve;

/// The names most programs need: `use screwkit::prelude::*;`.
pub mod prelude {
    pub use screwkit_lie::{ScrewAxis, Se3, Twist, Wrench};
    pub use screwkit_model::{load_chain, Chain, ModelError};
    pub use screwkit_solve::fk::{fk, fk_all_links};
    pub use screwkit_solve::ik::{IkMethod, IkOptions, IkResult, IkStatus};
    pub use screwkit_solve::jacobian::{fk_jacobian, jacobian};
    pub use screwkit_solve::{Frame, Kinematics, SolveError, Workspace};
}
