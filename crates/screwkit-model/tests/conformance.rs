//! Real-world URDFs from ../shared/urdf (see its README): load, build each listed chain, check
//! the product-of-exponentials FK against direct composition for random q.
//!
//! These files are not in the repository. The test is ignored by default and says why; `.ci/run`
//! sets `SCREWKIT_SHARED_URDF` to the folder and runs it with `--ignored`.

mod common;

use common::{fk_by_composition, poe_space, Sampler};
use screwkit_model::{urdf, Chain, JointKind};

/// (file, base, tip, revolute count, prismatic count)
const CHAINS: &[(&str, &str, &str, usize, usize)] = &[
    ("ur5_robot.urdf", "base_link", "tool0", 6, 0),
    ("panda.urdf", "panda_link0", "panda_hand_tcp", 7, 0),
    ("panda.urdf", "panda_link0", "panda_leftfinger", 7, 1),
    ("xarm7.urdf", "link_base", "link_eef", 7, 0),
    ("z1.urdf", "link00", "gripperMover", 7, 0),
];

#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn real_world_urdfs_conform() {
    let dir = std::env::var("SCREWKIT_SHARED_URDF")
        .expect("SCREWKIT_SHARED_URDF must name the folder with the shared real-world URDFs");
    let mut rng = Sampler::new(0xC0FF_EE00_1234_5678);
    for &(file, base, tip, revolute, prismatic) in CHAINS {
        let path = format!("{dir}/{file}");
        let tree = urdf::load_file(&path).unwrap_or_else(|e| panic!("{e}"));
        let chain =
            Chain::from_tree(&tree, Some(base), Some(tip)).unwrap_or_else(|e| panic!("{e}"));
        let count = |k: JointKind| chain.variables.iter().filter(|v| v.kind == k).count();
        assert_eq!(
            (
                count(JointKind::Revolute) + count(JointKind::Continuous),
                count(JointKind::Prismatic)
            ),
            (revolute, prismatic),
            "{file} {base}→{tip}: {:?}",
            chain.variable_names()
        );
        common::assert_poe_matches_composition(&tree, &chain, &mut rng, 500, file);
    }
}

/// The Panda's right finger is a mimic of the left one: a chain to it has one variable for
/// the fingers, driven by panda_finger_joint1.
#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn panda_mimic_finger() {
    let dir = std::env::var("SCREWKIT_SHARED_URDF")
        .expect("SCREWKIT_SHARED_URDF must name the folder with the shared real-world URDFs");
    let tree = urdf::load_file(format!("{dir}/panda.urdf")).unwrap();
    let chain = Chain::from_tree(&tree, Some("panda_link0"), Some("panda_rightfinger")).unwrap();
    assert_eq!(chain.dof(), 8);
    assert_eq!(chain.variables[7].name, "panda_finger_joint1");
    assert_eq!(chain.joints[7].name, "panda_finger_joint2");
    let mut rng = Sampler::new(99);
    for _ in 0..100 {
        let q = rng.chain_config(&chain);
        let want = fk_by_composition(&tree, &chain, &q).unwrap();
        assert!((poe_space(&chain, &q).to_homogeneous() - want).amax() < 1e-12);
    }
}
