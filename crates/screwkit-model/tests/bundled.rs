//! The bundled robots: screw axes against independent closed forms, and the
//! product-of-exponentials FK against direct composition of the URDF joint transforms.

mod common;

use common::{asset, poe_space, Sampler};
use nalgebra::{Matrix4, Vector3, Vector6};
use screwkit_model::{load_chain, urdf, ErrorKind, JointKind};

/// (file, base, tip, expected DoF, expected joints on the path)
type ChainCase = (
    &'static str,
    Option<&'static str>,
    Option<&'static str>,
    usize,
    usize,
);

const CHAINS: &[ChainCase] = &[
    ("planar_3r.urdf", None, None, 3, 3),
    ("ur5.urdf", None, None, 6, 6),
    ("panda.urdf", None, None, 7, 7),
    ("iiwa14.urdf", None, None, 7, 7),
    ("scara.urdf", None, None, 4, 4),
    ("tricky.urdf", None, None, 4, 4),
    ("tricky.urdf", Some("base_link"), Some("tool"), 4, 4),
    ("tricky.urdf", Some("l1b"), Some("l3"), 2, 2),
    ("torso_two_arms.urdf", None, Some("left_hand"), 4, 4),
    (
        "torso_two_arms.urdf",
        Some("torso"),
        Some("right_hand"),
        3,
        3,
    ),
    ("gripper_arm.urdf", None, Some("right_finger"), 3, 4),
    (
        "gripper_arm.urdf",
        Some("upper_arm"),
        Some("left_finger"),
        2,
        3,
    ),
];

/// FK by POE (space and body forms) equals direct composition of URDF transforms for 300
/// random configurations on every bundled chain.
#[test]
fn poe_matches_direct_composition_on_every_bundled_chain() {
    let mut rng = Sampler::new(0x9E37_79B9_7F4A_7C15);
    for &(file, base, tip, dof, njoints) in CHAINS {
        let tree = urdf::load_file(asset(file)).unwrap();
        let chain = screwkit_model::Chain::from_tree(&tree, base, tip).unwrap();
        assert_eq!(chain.dof(), dof, "{file} {base:?}→{tip:?}");
        assert_eq!(chain.joints.len(), njoints, "{file}");
        assert_eq!(chain.links.last().unwrap().home, chain.home);
        common::assert_poe_matches_composition(&tree, &chain, &mut rng, 300, file);
    }
}

/// Each link's home pose is the chain to that link's M.
#[test]
fn link_homes_are_the_sub_chain_home_poses() {
    for file in ["panda.urdf", "tricky.urdf", "gripper_arm.urdf"] {
        let tree = urdf::load_file(asset(file)).unwrap();
        let tip = if file == "gripper_arm.urdf" {
            Some("right_finger")
        } else {
            None
        };
        let chain = screwkit_model::Chain::from_tree(&tree, None, tip).unwrap();
        for (k, link) in chain.links.iter().enumerate().skip(1) {
            let sub = screwkit_model::Chain::from_tree(&tree, Some(&chain.base), Some(&link.name))
                .unwrap();
            assert_eq!(sub.home, link.home, "{file}: {}", link.name);
            assert_eq!(
                sub.joints.len(),
                link.joints_before,
                "{file}: {} (#{k})",
                link.name
            );
        }
    }
}

fn s(v: [f64; 6]) -> Vector6<f64> {
    Vector6::from(v)
}

/// UR5: Modern Robotics Example 4.5 closed form with the UR5 DH dimensions:
/// S₁ = (0,0,1,0,0,0), S₂ = (0,1,0,−H1,0,0), S₃ = (0,1,0,−H1,0,L1), S₄ = (0,1,0,−H1,0,L1+L2),
/// S₅ = (0,0,−1,−W1,L1+L2,0), S₆ = (0,1,0,H2−H1,0,L1+L2),
/// M = [[−1,0,0,L1+L2],[0,0,1,W1+W2],[0,1,0,H1−H2]].
#[test]
fn ur5_matches_modern_robotics_example_4_5() {
    let (h1, l1, l2, w1, h2, w2) = (0.089159, 0.425, 0.39225, 0.10915, 0.09465, 0.0823);
    let want = [
        s([0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
        s([0.0, 1.0, 0.0, -h1, 0.0, 0.0]),
        s([0.0, 1.0, 0.0, -h1, 0.0, l1]),
        s([0.0, 1.0, 0.0, -h1, 0.0, l1 + l2]),
        s([0.0, 0.0, -1.0, -w1, l1 + l2, 0.0]),
        s([0.0, 1.0, 0.0, h2 - h1, 0.0, l1 + l2]),
    ];
    let chain = load_chain(asset("ur5.urdf"), None, None).unwrap();
    assert_eq!(
        (chain.base.as_str(), chain.tip.as_str()),
        ("base_link", "tool0")
    );
    for (j, w) in chain.joints.iter().zip(want) {
        let got = j.s_space.twist().to_vector();
        assert!((got - w).amax() < 1e-15, "{}: {got:?} vs {w:?}", j.name);
    }
    let m = Matrix4::new(
        -1.0,
        0.0,
        0.0,
        l1 + l2,
        0.0,
        0.0,
        1.0,
        w1 + w2,
        0.0,
        1.0,
        0.0,
        h1 - h2,
        0.0,
        0.0,
        0.0,
        1.0,
    );
    assert!((chain.home.to_homogeneous() - m).amax() < 1e-15);
    // Limits from the data sheet.
    assert!(chain
        .variables
        .iter()
        .all(|v| (v.upper - 2.0 * std::f64::consts::PI).abs() < 1e-15));
    assert_eq!(chain.variables[0].effort, Some(150.0));
    assert_eq!(chain.variables[5].effort, Some(28.0));
}

/// Planar 3R by hand: S_i = (0,0,1, y_i, −x_i, 0) for joint i at (x_i, 0, 0), x = 0, 1, 1.8;
/// FK closed form x = c1 + 0.8 c12 + 0.5 c123, y = s1 + 0.8 s12 + 0.5 s123.
#[test]
fn planar_3r_by_hand() {
    let chain = load_chain(asset("planar_3r.urdf"), None, None).unwrap();
    for (j, x) in chain.joints.iter().zip([0.0, 1.0, 1.8]) {
        assert!((j.s_space.twist().to_vector() - s([0.0, 0.0, 1.0, 0.0, -x, 0.0])).amax() < 1e-15);
    }
    assert_eq!(*chain.home.translation(), Vector3::new(2.3, 0.0, 0.0));
    let mut rng = Sampler::new(7);
    for _ in 0..100 {
        let q = rng.chain_config(&chain);
        let t = poe_space(&chain, &q);
        let (a, b, c) = (q[0], q[0] + q[1], q[0] + q[1] + q[2]);
        let x = a.cos() + 0.8 * b.cos() + 0.5 * c.cos();
        let y = a.sin() + 0.8 * b.sin() + 0.5 * c.sin();
        assert!((t.translation() - Vector3::new(x, y, 0.0)).amax() < 1e-14);
        assert!((t.rpy()[2] - c.sin().atan2(c.cos())).abs() < 1e-13);
    }
}

/// SCARA closed form: x = 0.35 c1 + 0.30 c12, y = 0.35 s1 + 0.30 s12, z = 0.35 − d3,
/// yaw = q1 + q2 + q4; the prismatic axis is S₃ = (0, 0, 0, 0, 0, −1).
#[test]
fn scara_closed_form() {
    let chain = load_chain(asset("scara.urdf"), None, None).unwrap();
    assert_eq!(chain.joints[2].kind, JointKind::Prismatic);
    assert!(chain.joints[2].s_space.is_pure_translation());
    assert!(
        (chain.joints[2].s_space.twist().to_vector() - s([0.0, 0.0, 0.0, 0.0, 0.0, -1.0])).amax()
            < 1e-15
    );
    let mut rng = Sampler::new(11);
    for _ in 0..100 {
        let q = rng.chain_config(&chain);
        let t = poe_space(&chain, &q);
        let x = 0.35 * q[0].cos() + 0.30 * (q[0] + q[1]).cos();
        let y = 0.35 * q[0].sin() + 0.30 * (q[0] + q[1]).sin();
        assert!((t.translation() - Vector3::new(x, y, 0.35 - q[2])).amax() < 1e-14);
        let yaw = q[0] + q[1] + q[3];
        assert!((t.rpy()[2] - yaw.sin().atan2(yaw.cos())).abs() < 1e-12);
    }
}

/// Panda: FK from the published modified-DH table, T = Π Rx(α) Tx(a) Rz(θ) Tz(d) · flange ·
/// Rz(−π/4) · Tz(0.1034), computed here from the table alone.
#[test]
fn panda_matches_its_dh_table() {
    use std::f64::consts::FRAC_PI_2;
    let dh = [
        (0.0, 0.333, 0.0),
        (0.0, 0.0, -FRAC_PI_2),
        (0.0, 0.316, FRAC_PI_2),
        (0.0825, 0.0, FRAC_PI_2),
        (-0.0825, 0.384, -FRAC_PI_2),
        (0.0, 0.0, FRAC_PI_2),
        (0.088, 0.0, FRAC_PI_2),
    ];
    let rx = |a: f64| nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), a).to_homogeneous();
    let rz = |a: f64| nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), a).to_homogeneous();
    let tr = |x: f64, y: f64, z: f64| nalgebra::Translation3::new(x, y, z).to_homogeneous();
    let chain = load_chain(asset("panda.urdf"), None, None).unwrap();
    assert_eq!(chain.tip, "panda_hand_tcp");
    let mut rng = Sampler::new(3);
    for _ in 0..100 {
        let q = rng.chain_config(&chain);
        let mut t = Matrix4::identity();
        for (i, &(a, d, alpha)) in dh.iter().enumerate() {
            t = t * rx(alpha) * tr(a, 0.0, 0.0) * rz(q[i]) * tr(0.0, 0.0, d);
        }
        t = t * tr(0.0, 0.0, 0.107) * rz(-std::f64::consts::FRAC_PI_4) * tr(0.0, 0.0, 0.1034);
        let got = poe_space(&chain, &q).to_homogeneous();
        assert!((got - t).amax() < 1e-12, "{:e}", (got - t).amax());
    }
    assert_eq!(chain.variables[3].upper, -0.0698);
    assert_eq!(chain.variables[5].lower, -0.0175);
}

/// iiwa14: every axis passes through the vertical line, so S = (ω, −ω × (0, 0, h)):
/// joints 2, 4, 6 at h = 0.36, 0.78, 1.18 about y, −y, y; M = Tz(1.306).
#[test]
fn iiwa14_closed_form() {
    let chain = load_chain(asset("iiwa14.urdf"), None, None).unwrap();
    let want = [
        s([0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
        s([0.0, 1.0, 0.0, -0.36, 0.0, 0.0]),
        s([0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
        s([0.0, -1.0, 0.0, 0.78, 0.0, 0.0]),
        s([0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
        s([0.0, 1.0, 0.0, -1.18, 0.0, 0.0]),
        s([0.0, 0.0, 1.0, 0.0, 0.0, 0.0]),
    ];
    for (j, w) in chain.joints.iter().zip(want) {
        assert!(
            (j.s_space.twist().to_vector() - w).amax() < 1e-14,
            "{}",
            j.name
        );
    }
    assert!((chain.home.translation() - Vector3::new(0.0, 0.0, 1.306)).amax() < 1e-15);
    assert!((chain.variables[6].upper - 175f64.to_radians()).abs() < 1e-15);
}

/// Mimic joints: the coupled joint and the right finger follow their leaders' variables.
#[test]
fn mimic_joints_fold_into_their_leaders() {
    let chain = load_chain(asset("gripper_arm.urdf"), None, Some("right_finger")).unwrap();
    assert_eq!(
        chain.variable_names(),
        ["shoulder_joint", "elbow_joint", "left_finger_joint"]
    );
    let names: Vec<_> = chain
        .joints
        .iter()
        .map(|j| {
            (
                j.name.as_str(),
                j.drive.variable,
                j.drive.multiplier,
                j.drive.offset,
            )
        })
        .collect();
    assert_eq!(
        names,
        [
            ("shoulder_joint", 0, 1.0, 0.0),
            ("elbow_joint", 1, 1.0, 0.0),
            ("coupled_joint", 1, -1.0, 0.1),
            ("right_finger_joint", 2, 1.0, 0.0),
        ]
    );
    assert!(chain.has_mimic());
    // The finger variable takes the leader's limits.
    assert_eq!(
        (chain.variables[2].lower, chain.variables[2].upper),
        (0.0, 0.04)
    );
    // With the elbow at e and the coupled joint at −e + 0.1, the palm pitch is 0.1 total.
    let t = common::poe_space(&chain, &[0.0, 0.7, 0.02]);
    let pitch = t.rpy()[1];
    assert!((pitch - 0.1).abs() < 1e-14, "{pitch}");
}

/// What real files do (tricky.urdf): world above the base, out-of-order joints, transmission
/// joints ignored, inexact rpy kept, continuous joint limit ignored, missing velocity/effort.
#[test]
fn real_world_quirks_load() {
    let tree = urdf::load_file(asset("tricky.urdf")).unwrap();
    assert_eq!(tree.links[tree.root], "world");
    assert_eq!(
        tree.joints.len(),
        7,
        "the <joint> inside <transmission> is not a tree joint"
    );
    let mid = &tree.joints[tree.joint("mid_fixed").unwrap()];
    assert_eq!(mid.origin_rpy, [1.570796325, 0.0, 0.0]);
    let world = &tree.joints[tree.joint("world_joint").unwrap()];
    assert_eq!(world.origin_xyz, [0.0, 0.0, 0.649]);
    let j2 = &tree.joints[tree.joint("j2").unwrap()];
    assert_eq!(j2.origin_xyz, [0.3, -9.8483e-05, 0.0]);
    let chain = screwkit_model::Chain::from_tree(&tree, Some("base_link"), None).unwrap();
    assert_eq!(chain.tip, "tool");
    let v = &chain.variables;
    assert_eq!(v[1].kind, JointKind::Continuous);
    assert_eq!((v[1].lower, v[1].upper), (f64::NEG_INFINITY, f64::INFINITY));
    assert_eq!(
        (v[2].lower, v[2].upper, v[2].velocity, v[2].effort),
        (-0.1, 0.15, None, None)
    );
    assert_eq!((v[0].lower, v[0].upper), (-4.5, 4.5));
    assert!(
        v[3].lower > 0.0,
        "q = 0 outside the limits is allowed; M is the pose at q = 0"
    );
    // Non-unit axes are normalised.
    for j in &chain.joints {
        assert!((j.s_space.direction().norm() - 1.0).abs() < 1e-15);
    }
    // The root chain starts at world and includes the 0.649 m offset.
    let from_world = screwkit_model::Chain::from_tree(&tree, None, None).unwrap();
    assert_eq!(from_world.base, "world");
    let d =
        from_world.home.translation() - (chain.home.translation() + Vector3::new(0.0, 0.0, 0.649));
    assert!(d.amax() < 1e-15);
}

/// Base/tip selection on a tree: no default tip when there are several leaves.
#[test]
fn tree_needs_a_tip() {
    let tree = urdf::load_file(asset("torso_two_arms.urdf")).unwrap();
    let err = screwkit_model::Chain::from_tree(&tree, None, None).unwrap_err();
    match &err.kind {
        ErrorKind::AmbiguousTip { count, leaves, .. } => {
            assert_eq!(*count, 3);
            for l in ["head", "left_hand", "right_hand"] {
                assert!(leaves.contains(l), "{leaves}");
            }
        }
        k => panic!("unexpected {k:?}"),
    }
    let msg = err.to_string();
    assert!(
        msg.contains("torso_two_arms.urdf") && msg.contains("pick one of them as the tip"),
        "{msg}"
    );
    // A base below a movable joint is fine.
    let c =
        screwkit_model::Chain::from_tree(&tree, Some("left_shoulder"), Some("left_hand")).unwrap();
    assert_eq!(c.variable_names(), ["left_shoulder_roll", "left_elbow"]);
    // Sibling links are not a chain.
    let e =
        screwkit_model::Chain::from_tree(&tree, Some("left_hand"), Some("right_hand")).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::NotAncestor { .. }), "{e}");
}
