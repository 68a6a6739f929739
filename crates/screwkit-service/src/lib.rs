//! screwkit's front-end floor: what every front end (the CLI, the Python package, pictures,
//! maps; a C API or a ROS node later) needs between the library and its users, written once.
//!
//! - [`whole`]: the whole tree's requests: which frames to answer, frame names to indices.
//! - [`load`]: [`Robot::load`] from a path, text or standard input ([`Source`]): URDF, xacro,
//!   MJCF or a screw table, told apart by content, one decoding rule, package paths, xacro
//!   arguments, base, tip, tool frame and floating base ([`LoadOptions`]).
//! - [`words`]: the option words (`lm`/`dls`/`nr`, `space`/`body`/`world-aligned`, map modes,
//!   views, …): `FromStr` + `Display` + one `ALL` list each.
//! - [`request`]: requests with their one set of defaults ([`IkSettings`], [`ReachSpec`],
//!   [`Shard`]); [`target`]: IK targets under one tolerance; [`joint`]: joints by name or
//!   0-based index ([`JointRef`], [`Lock`]).
//! - [`report`]: the serde structs of the JSON contract; [`solutions`]: every analytic
//!   solution, single and batched.
//! - [`body`]: the robot's body (collision model, SRDF, the `collide` report).
//! - [`mujoco`]: MuJoCo's `qpos` and screwkit's q, both ways.
//! - [`io`]: `.npy`/`.npz`, outputs written whole or not at all, the JSON number rule.
//! - [`Error`]: typed errors (`Io { path, source }`, model, solver, file, word, option).
//!
//! The floor holds no kinematics: every answer comes from `screwkit_solve`.

pub mod body;
pub mod dynamics;
pub mod error;
pub mod info;
pub mod io;
pub mod joint;
pub mod load;
pub mod mujoco;
pub mod path;
pub mod query;
pub mod report;
pub mod request;
pub mod solutions;
pub mod target;
pub mod tasks;
pub mod whole;
pub mod words;

pub use error::{Error, Result};
pub use joint::{JointRef, Lock};
pub use load::{LoadOptions, Robot, Source};
pub use request::{IkSettings, ReachSpec, Shard};
pub use solutions::AllSolutions;
pub use words::{Word, WordError};
