//! # screwkit-model
//!
//! A robot file (URDF, xacro, MJCF) or a screw table → kinematic tree → serial chain with the
//! screw axes of the product of exponentials,
//! T(q) = e^\[S₁\]θ₁ ⋯ e^\[Sₙ\]θₙ M (space form) = M e^\[B₁\]θ₁ ⋯ e^\[Bₙ\]θₙ (body form).
//!
//! - [`input`]: bounded reads and the XML checks every robot file passes (the stated limits).
//! - [`urdf`]: reading URDF (urdf-rs, with a strict pre-pass for its pitfalls).
//! - [`xacro`]: xacro expanded natively into URDF (ROS's xacro semantics, no ROS).
//! - [`mjcf`]: reading MuJoCo's MJCF (bodies, joints, sites, classes, includes) into the same tree.
//! - [`load`]: any description file, told apart by content ([`load_tree`], [`load_chain`]).
//! - [`mujoco_qpos`]: MuJoCo's `qpos` and screwkit's configuration, both ways.
//! - [`tree`]: links, joints, paths between links.
//! - [`geometry`]: each link's collision and visual shapes as the file describes them.
//! - [`mesh`]: triangle meshes from STL, OBJ and COLLADA files.
//! - [`srdf`]: MoveIt's SRDF: disabled collision pairs, groups, end effectors.
//! - [`kinematic_tree`]: the whole robot: every joint's screw, every link's home pose, frames,
//!   the variable order, the floating base.
//! - [`chain`]: the chain base → tip: S_i, B_i, M, limits, mimic joints, link home poses.
//! - [`digest`]: a stable digest of a model's numbers, for files that name what they came from.
//! - [`table`]: screw-axis tables (Markdown, CSV, JSON), and reading them back.
//! - [`screws`]: robots given by M and screw axes ([`ScrewRobot`]: its exact chain and an
//!   equivalent tree).
//!
//! ```
//! let chain = screwkit_model::load_chain(
//!     concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/planar_3r.urdf"), None, None)?;
//! assert_eq!(chain.dof(), 3);
//! // The tip is 2.3 m out along x at home.
//! assert!((chain.home.translation().x - 2.3).abs() < 1e-15);
//! # Ok::<(), screwkit_model::ModelError>(())
//! ```
//!
//! Conventions: screw axes are (ω, v); the space frame is the base link, the body frame the
//! tip link; URDF rpy is fixed-axis, R = R_z(y) R_y(p) R_x(r).

pub mod chain;
pub mod digest;
pub mod error;
pub mod geometry;
pub mod input;
pub mod kinematic_tree;
pub mod load;
pub mod mesh;
pub mod mjcf;
pub mod mujoco_qpos;
pub mod screws;
pub mod srdf;
pub mod table;
pub mod tree;
pub mod urdf;
pub mod xacro;

pub use chain::{Chain, ChainJoint, ChainLink, Drive, Variable};
pub use error::{ErrorKind, ModelError};
pub use kinematic_tree::{KinematicTree, TreeFrame, TreeLink, TreeScrew};
pub use load::{load_tree, tree_from_str, Format};
pub use screws::{ScrewJoint, ScrewLeader, ScrewRobot};
pub use tree::{Inertial, JointDynamics, JointKind, Limit, Mimic, QposLayout, Tree, TreeJoint};
pub use xacro::XacroOptions;

/// Loads a robot file (URDF, xacro, MJCF or a screw table, told apart by content:
/// [`load::Format`]) and builds the chain from `base` (default: the root link) to `tip`
/// (default: the only leaf below the base).
///
/// ```
/// let ur5 = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/ur5.urdf");
/// let chain = screwkit_model::load_chain(ur5, None, None)?;
/// assert_eq!((chain.base.as_str(), chain.tip.as_str()), ("base_link", "tool0"));
/// assert_eq!(chain.dof(), 6);
/// // The shoulder lift's space screw axis: about y, through (0, 0, 0.089159), pitch 0.
/// let lift = &chain.joints[1];
/// assert_eq!(lift.name, "shoulder_lift_joint");
/// assert_eq!(lift.s_space.direction(), nalgebra::Vector3::y());
/// let q = lift.s_space.point().unwrap();
/// assert!((q - nalgebra::Vector3::new(0.0, 0.0, 0.089159)).norm() < 1e-12);
/// assert_eq!(lift.s_space.pitch(), Some(0.0));
/// # Ok::<(), screwkit_model::ModelError>(())
/// ```
pub fn load_chain(
    path: impl AsRef<std::path::Path>,
    base: Option<&str>,
    tip: Option<&str>,
) -> Result<Chain, ModelError> {
    load::load_chain(path, base, tip, &XacroOptions::default())
}

/// [`load_chain`] with xacro options (package paths, `xacro:arg` values).
pub fn load_chain_with(
    path: impl AsRef<std::path::Path>,
    base: Option<&str>,
    tip: Option<&str>,
    opts: &XacroOptions,
) -> Result<Chain, ModelError> {
    load::load_chain(path, base, tip, opts)
}
