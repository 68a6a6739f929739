//! Reference forward kinematics by direct composition of URDF joint transforms.
//!
//! T_base_tip = Π_j origin_j · motion_j(θ_j) along the path, where origin_j is the joint's
//! `<origin>` (R = R_z(y) R_y(p) R_x(r), built with nalgebra's Euler angles) and motion_j is a
//! rotation about the unit axis by θ (nalgebra's axis-angle) or a translation along it. It
//! uses none of the screw machinery, so it is the independent oracle for the
//! product-of-exponentials FK: slow (allocates, looks names up), exact, URDF-literal.
//!
//! [`poe_space`] and [`poe_body`] are the product of exponentials written plainly, joint by
//! joint with `Se3::exp` — the reference the fast column kernels of `screwkit-solve` are
//! checked against, and (against [`fk_by_composition`]) the check of the extracted screws.

use nalgebra::{Matrix4, Rotation3, Translation3, Unit, Vector3};

use screwkit_lie::Se3;
use screwkit_model::Chain;
use screwkit_model::{ErrorKind, ModelError};
use screwkit_model::{JointKind, Tree, TreeJoint};

/// The tip pose (4x4) of `chain` for variables `q`, composing the URDF transforms of `tree`
/// along the chain's path; mimic joints follow `<mimic>` (θ = multiplier · θ_leader + offset).
pub fn fk_by_composition(
    tree: &Tree,
    chain: &Chain,
    q: &[f64],
) -> Result<Matrix4<f64>, ModelError> {
    let err = |k| ModelError::new(tree.source.clone(), k);
    let base = tree.link(&chain.base)?;
    let tip = tree.link(&chain.tip)?;
    let path = tree.path(base, tip)?;
    let position = |name: &str| -> Option<f64> {
        chain
            .variables
            .iter()
            .position(|v| v.name == name)
            .map(|k| q[k])
    };
    let mut t = Matrix4::identity();
    for j in path {
        let joint = &tree.joints[j];
        t *= origin(joint);
        if !joint.kind.is_movable() {
            continue;
        }
        let mut theta = position(&joint.name);
        if theta.is_none() {
            // Follow the mimic chain to a variable of the chain.
            let (mut cur, mut m, mut o) = (j, 1.0, 0.0);
            while let Some(mimic) = &tree.joints[cur].mimic {
                o += m * mimic.offset;
                m *= mimic.multiplier;
                cur = tree.joint(&mimic.leader).ok_or_else(|| {
                    err(ErrorKind::Mimic {
                        joint: joint.name.clone(),
                        problem: format!("unknown joint \"{}\"", mimic.leader),
                    })
                })?;
                if let Some(x) = position(&tree.joints[cur].name) {
                    theta = Some(m * x + o);
                    break;
                }
            }
        }
        let theta = theta.ok_or_else(|| {
            err(ErrorKind::Mimic {
                joint: joint.name.clone(),
                problem: "a joint that is not a variable of the chain".into(),
            })
        })?;
        t *= motion(joint, theta);
    }
    Ok(t)
}

/// A joint's `<origin>` as a 4x4: translation xyz, then R = R_z(y) R_y(p) R_x(r) (nalgebra's
/// Euler angles), or the exact quaternion where the format gave one (nalgebra's
/// `UnitQuaternion`).
fn origin(joint: &TreeJoint) -> Matrix4<f64> {
    let rotation = match joint.origin_quat {
        Some([w, x, y, z]) => {
            nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
                .to_homogeneous()
        }
        None => Rotation3::from_euler_angles(
            joint.origin_rpy[0],
            joint.origin_rpy[1],
            joint.origin_rpy[2],
        )
        .to_homogeneous(),
    };
    Translation3::from(Vector3::from(joint.origin_xyz)).to_homogeneous() * rotation
}

/// A movable joint's motion at θ as a 4x4: a translation along the unit axis (prismatic) or a
/// rotation about it (nalgebra's axis-angle).
fn motion(joint: &TreeJoint, theta: f64) -> Matrix4<f64> {
    let axis = Unit::new_normalize(Vector3::from(joint.axis));
    if joint.kind == JointKind::Prismatic {
        Translation3::from(axis.into_inner() * theta).to_homogeneous()
    } else {
        Rotation3::from_axis_angle(&axis, theta).to_homogeneous()
    }
}

/// θ_j of every chain joint for variables q (each joint's [`screwkit_model::Drive`]).
pub fn joint_positions(chain: &Chain, q: &[f64]) -> Vec<f64> {
    chain.joints.iter().map(|j| j.drive.theta(q)).collect()
}

/// Space form T = e^\[S₁\]θ₁ ⋯ e^\[Sₙ\]θₙ M, one `Se3::exp` per joint.
pub fn poe_space(chain: &Chain, q: &[f64]) -> Se3 {
    let theta = joint_positions(chain, q);
    let mut t = Se3::identity();
    for (j, th) in chain.joints.iter().zip(theta) {
        t = t * Se3::exp_screw(&j.s_space, th);
    }
    t * chain.home
}

/// Body form T = M e^\[B₁\]θ₁ ⋯ e^\[Bₙ\]θₙ, one `Se3::exp` per joint.
pub fn poe_body(chain: &Chain, q: &[f64]) -> Se3 {
    let theta = joint_positions(chain, q);
    let mut t = chain.home;
    for (j, th) in chain.joints.iter().zip(theta) {
        t = t * Se3::exp_screw(&j.b_body, th);
    }
    t
}

/// Every link's pose (4x4, in the root link's frame, in `tree.links` order) for joint
/// positions given by name (`position(joint) -> θ` for every movable joint, mimic followers
/// included), composing the URDF transforms of `tree` from the root down: T_child =
/// T_parent · origin_j · motion_j(θ_j). The independent oracle for the whole-tree FK.
pub fn tree_fk_by_composition(tree: &Tree, position: &dyn Fn(&str) -> f64) -> Vec<Matrix4<f64>> {
    let mut out = vec![Matrix4::identity(); tree.links.len()];
    let mut stack = vec![tree.root];
    while let Some(l) = stack.pop() {
        for &j in &tree.child_joints[l] {
            let joint = &tree.joints[j];
            let mut t = out[l] * origin(joint);
            if joint.kind.is_movable() {
                t *= motion(joint, position(&joint.name));
            }
            out[joint.child] = t;
            stack.push(joint.child);
        }
    }
    out
}

/// The position of every movable joint of `tree` (by name) for the tree's variables
/// `q_joints` (named `variables`, the mimic rule followed from `<mimic>` as written):
/// θ = multiplier · θ_leader + offset.
pub fn tree_joint_positions(
    tree: &Tree,
    variables: &[String],
    q_joints: &[f64],
) -> std::collections::HashMap<String, f64> {
    let mut out = std::collections::HashMap::new();
    for joint in tree.joints.iter().filter(|j| j.kind.is_movable()) {
        let (mut cur, mut m, mut o) = (joint, 1.0, 0.0);
        while let Some(mimic) = &cur.mimic {
            o += m * mimic.offset;
            m *= mimic.multiplier;
            cur = &tree.joints[tree.joint(&mimic.leader).expect("a mimic leader")];
        }
        let k = variables
            .iter()
            .position(|v| *v == cur.name)
            .expect("the leader is a variable");
        out.insert(joint.name.clone(), m * q_joints[k] + o);
    }
    out
}

/// Every link's world pose (4x4, `tree.links` order) at the whole-tree configuration `q` of
/// `kin` (nq values; a floating base's seven first: x y z qx qy qz qw), by
/// [`tree_fk_by_composition`] and the base's pose built here from its quaternion with
/// nalgebra. The oracle of every whole-tree algorithm's poses.
pub fn tree_world_poses(
    tree: &Tree,
    kin: &screwkit_solve::TreeKinematics,
    q: &[f64],
) -> Vec<Matrix4<f64>> {
    let model = kin.model();
    let off = if kin.floating_base() { 7 } else { 0 };
    let names: Vec<String> = model.variables.iter().map(|v| v.name.clone()).collect();
    let positions = tree_joint_positions(tree, &names, &q[off..]);
    let base = if kin.floating_base() {
        let quat = nalgebra::UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            q[6], q[3], q[4], q[5],
        ));
        nalgebra::Isometry3::from_parts(Translation3::new(q[0], q[1], q[2]), quat).to_homogeneous()
    } else {
        Matrix4::identity()
    };
    tree_fk_by_composition(tree, &|j| positions[j])
        .into_iter()
        .map(|t| base * t)
        .collect()
}

/// The centre of mass Σ m_L T_L c_L / Σ m_L of the links with a mass (> 0), from the link
/// poses `poses` (world, 4x4) and the tree's `<inertial>` values.
pub fn tree_com(tree: &Tree, poses: &[Matrix4<f64>]) -> Vector3<f64> {
    let (mut s, mut m) = (Vector3::zeros(), 0.0);
    for (l, i) in tree.inertials.iter().enumerate() {
        if let Some(i) = i.filter(|i| i.mass > 0.0) {
            let c = poses[l] * nalgebra::Vector4::new(i.com[0], i.com[1], i.com[2], 1.0);
            s += i.mass * c.xyz();
            m += i.mass;
        }
    }
    s / m
}
