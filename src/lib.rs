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
