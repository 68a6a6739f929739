//! Test helpers shared by the solver tests.

#![allow(dead_code)]

use screwkit_lie::Se3;
use screwkit_model::{urdf, Chain, Tree};
use screwkit_solve::{Kinematics, SolveError, Workspace};
pub use screwkit_testkit::Sampler;

/// (file, base, tip) of every bundled chain the solver is tested on.
#[allow(unused_imports)]
pub use screwkit_testkit::BUNDLED_CHAINS as CHAINS;

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

/// A serial arm from per-joint (origin xyz, origin rpy, axis), limits ±3, a tool frame.
#[allow(unused_imports)]
pub use screwkit_testkit::serial_arm as arm;
