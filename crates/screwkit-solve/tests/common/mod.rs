//! Test helpers shared by the solver tests.

#![allow(dead_code)]

use screwkit_lie::Se3;
use screwkit_model::{urdf, Chain, Tree};
use screwkit_solve::{Kinematics, SolveError, Workspace};
pub use screwkit_testkit::Sampler;

/// (file, base, tip) of every bundled chain the solver is tested on.
pub const CHAINS: &[(&str, Option<&str>, Option<&str>)] = &[
    ("planar_3r.urdf", None, None),
    ("ur5.urdf", None, None),
    ("panda.urdf", None, None),
    ("iiwa14.urdf", None, None),
    ("scara.urdf", None, None),
    ("tricky.urdf", Some("base_link"), None),
    ("torso_two_arms.urdf", None, Some("left_hand")),
    ("gripper_arm.urdf", None, Some("right_finger")),
];

/// Loads a bundled chain with its tree.
pub fn load(file: &str, base: Option<&str>, tip: Option<&str>) -> (Tree, Chain, Kinematics) {
    let tree = urdf::load_file(screwkit_testkit::bundled(file)).unwrap();
    let chain = Chain::from_tree(&tree, base, tip).unwrap();
    let kin = Kinematics::new(&chain);
    (tree, chain, kin)
}

/// The tip pose with a fresh workspace: a call independent of any solver's state.
pub fn fk1(kin: &Kinematics, q: &[f64]) -> Result<Se3, SolveError> {
    screwkit_solve::fk::fk(kin, &mut Workspace::new(kin), q)
}
