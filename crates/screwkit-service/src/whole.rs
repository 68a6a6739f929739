//! Requests on the whole tree ([`screwkit_solve::tree`]): which frames a front end answers and
//! when it answers for the tree rather than the chain — written once for the CLI and Python.
//!
//! The rule: a request is about the whole tree when it names frames (`--frames`, `--of`,
//! `link=`), asks for a floating base, or the robot has no chain (a file with several leaves
//! and no tip). Otherwise the chain `base → tip` answers, as before. In the whole tree, q is
//! the tree's configuration ([`screwkit_model::kinematic_tree`]: the file's joint order,
//! after the floating base's seven values).

use screwkit_solve::TreeKinematics;

use crate::load::Robot;

/// True when a request goes to the whole tree (module documentation); `names_frames`: the
/// request names frames.
pub fn wants_tree(robot: &Robot, names_frames: bool) -> bool {
    names_frames
        || robot.options().floating_base
        || robot.tree().floating_root
        || !robot.has_chain()
}

/// The leaf links: links with no joint below them, in the file's link order.
pub fn leaf_frames(kin: &TreeKinematics) -> Vec<usize> {
    let tree = &kin.model().tree;
    (0..tree.links.len())
        .filter(|&l| tree.child_joints[l].is_empty())
        .collect()
}
