//! Test helpers shared by the solver tests.

#![allow(dead_code)]

use screwkit_model::{urdf, Chain, Tree};
use screwkit_solve::Kinematics;

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
    let tree = urdf::load_file(format!(
        "{}/../../assets/urdf/{file}",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let chain = Chain::from_tree(&tree, base, tip).unwrap();
    let kin = Kinematics::new(&chain);
    (tree, chain, kin)
}

/// xorshift64: reproducible test randomness.
pub struct Rng(pub u64);

impl Rng {
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform within limits ([−π, π] when unbounded).
    pub fn config(&mut self, kin: &Kinematics) -> Vec<f64> {
        (0..kin.dof())
            .map(|k| {
                let (l, u) = (kin.lower()[k], kin.upper()[k]);
                let (l, u) = if l.is_finite() && u.is_finite() {
                    (l, u)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                };
                l + (u - l) * self.uniform()
            })
            .collect()
    }
}
