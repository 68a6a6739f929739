//! # screwkit-collision
//!
//! The robot's body: the collision shapes its file gives each link
//! ([`screwkit_model::geometry`]), placed by the whole tree's forward kinematics, and the
//! questions asked of them — is a configuration in collision with itself or with obstacles,
//! which pairs, how far apart is each pair (signed: negative when they overlap) with its
//! witness points and normal, and the minimum distance; one configuration at a time or a
//! batch on all cores.
//!
//! The engine is parry (`parry3d-f64`, dimforge): GJK/EPA between convex shapes, bounding-volume
//! trees for triangle meshes. Its glam types stay inside this crate ([`convert`]); the API
//! speaks screwkit's `Se3` and arrays.
//!
//! - [`model`]: the [`CollisionModel`] built once from a tree (shapes, meshes read as exact
//!   triangle meshes or as convex hulls, the pairs a query checks, obstacles).
//! - [`acm`]: the allowed-collision matrix generated as MoveIt's setup assistant does.
//! - [`avoidance`]: collision avoidance as a limit of whole-body differential IK
//!   ([`CollisionAvoidance`]: one velocity-damper row per close pair).
//! - [`clearance`]: a chain's body as IK asks for it ([`ChainClearance`]: IK answers clear of
//!   contact, with distance rows that steer its steps).
//! - [`query`]: the algorithms, Pinocchio style: `algorithm(&model, &mut ws, &kin, q)` with a
//!   reusable [`CollisionWorkspace`]; a broad phase (each shape's bounding box at q) prunes
//!   pairs before any narrow-phase call.
//!
//! Conventions: metres; a pair (a, b) has `a < b` in the model's shape order; its normal
//! points from a to b, and its signed distance is the separation (≥ 0) or minus the
//! penetration depth.

pub mod acm;
pub mod avoidance;
pub mod clearance;
mod closed_forms;
pub mod convert;
pub mod ellipsoid;
pub mod hull;
mod mesh_distance;
pub mod model;
pub mod query;
mod triangles;

pub use avoidance::CollisionAvoidance;
pub use clearance::{ChainClearance, ClearanceScratch};
pub use model::{Attach, CollisionError, CollisionModel, MeshMode, Object, Options};
pub use query::{
    broad_phase, clear, close_pairs, collisions, collisions_batch, distance_jacobians,
    distance_jacobians_batch, distances, distances_batch, in_collision, in_collision_batch,
    min_distance, min_distance_batch, CollisionWorkspace, PairDistance,
};
