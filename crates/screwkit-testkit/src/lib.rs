//! # screwkit-testkit
//!
//! What screwkit's tests and benchmarks share and its users do not need (so it is not part of
//! the library's public API, and not published):
//!
//! - [`reference`](mod@reference): forward kinematics by composing the URDF's joint transforms one by one —
//!   the independent oracle every product-of-exponentials result is checked against.
//! - [`protocol`]: the IK benchmark protocol behind `screwkit bench`, the criterion benches
//!   and BENCHMARKS.md.
//! - [`fuzz`]: the seeded mutation fuzzer the parsers' fuzz tests run.
//! - [`BUNDLED_CHAINS`] and [`SHARED_CHAINS`]: the chains every suite runs on.
//! - [`bundled`]: the path of a robot file in `assets/urdf/`, and [`Sampler`]: random
//!   configurations within a chain's limits (the library's sampler,
//!   [`screwkit_solve::sample`], for tests that hold a [`Chain`]).

pub mod fuzz;
pub mod protocol;
pub mod reference;

use screwkit_model::Chain;
use screwkit_solve::sample::{configuration_into, SplitMix64};
use screwkit_solve::Kinematics;

/// (file, base, tip) of every bundled chain the tests run on: every robot of `assets/urdf/`,
/// with a base or tip where the file needs one.
pub const BUNDLED_CHAINS: &[(&str, Option<&str>, Option<&str>)] = &[
    ("planar_3r.urdf", None, None),
    ("ur5.urdf", None, None),
    ("panda.urdf", None, None),
    ("iiwa14.urdf", None, None),
    ("scara.urdf", None, None),
    ("tricky.urdf", Some("base_link"), None),
    ("torso_two_arms.urdf", None, Some("left_hand")),
    ("gripper_arm.urdf", None, Some("right_finger")),
];

/// (file, base, tip) of the real-world chains `../shared/urdf/README.md` lists to test; the
/// folder is named by the `SCREWKIT_SHARED_URDF` environment variable (`.ci/run` sets it).
pub const SHARED_CHAINS: &[(&str, &str, &str)] = &[
    ("ur5_robot.urdf", "base_link", "tool0"),
    ("panda.urdf", "panda_link0", "panda_hand_tcp"),
    ("panda.urdf", "panda_link0", "panda_leftfinger"),
    ("xarm7.urdf", "link_base", "link_eef"),
    ("z1.urdf", "link00", "gripperMover"),
    ("panda_pybullet.urdf", "panda_link0", "panda_hand"),
];

/// The path of a bundled robot file, `assets/urdf/<file>`.
pub fn bundled(file: &str) -> String {
    format!("{}/../../assets/urdf/{file}", env!("CARGO_MANIFEST_DIR"))
}

/// Reproducible random configurations for tests: the library's sampler
/// ([`screwkit_solve::sample::configuration_into`], uniform within the limits, [−π, π] for
/// unbounded variables) on a seeded SplitMix64.
pub struct Sampler(pub SplitMix64);

impl Sampler {
    /// A sampler seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self(SplitMix64(seed))
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0.uniform()
    }

    /// One configuration of `kin`, within its limits.
    pub fn config(&mut self, kin: &Kinematics) -> Vec<f64> {
        let mut q = vec![0.0; kin.dof()];
        configuration_into(kin, &mut self.0, &mut q);
        q
    }

    /// One configuration of `chain`, within its limits.
    pub fn chain_config(&mut self, chain: &Chain) -> Vec<f64> {
        self.config(&Kinematics::new(chain))
    }
}

/// The `cmeel.prefix/share` folder holding example-robot-data's robots (TALOS, the Panda, the
/// UR5 with meshes and SRDFs), for benches: `SCREWKIT_ERD_SHARE`, else the one the venv of
/// `cargo xtask test` has; None when neither exists.
pub fn example_robot_data() -> Option<std::path::PathBuf> {
    if let Some(s) = std::env::var_os("SCREWKIT_ERD_SHARE") {
        return Some(s.into());
    }
    let venv = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/xtask-venv/lib");
    std::fs::read_dir(venv)
        .ok()?
        .filter_map(|e| e.ok())
        .find_map(|e| {
            let p = e.path().join("site-packages/cmeel.prefix/share");
            p.join("example-robot-data").is_dir().then_some(p)
        })
}

/// A bundled robot with every `<origin xyz>` multiplied by `s` (a robot s times the size):
/// for the scale-free IK test and benchmark.
pub fn scaled_chain(file: &str, s: f64) -> Chain {
    let text = std::fs::read_to_string(bundled(file)).expect("bundled file");
    let doc = roxmltree::Document::parse(&text).expect("bundled files parse");
    let mut out = String::new();
    let mut last = 0;
    for n in doc.descendants().filter(|n| n.has_tag_name("origin")) {
        if let Some(a) = n.attribute_node("xyz") {
            let r = a.range_value();
            out.push_str(&text[last..r.start]);
            let v: Vec<String> = a
                .value()
                .split_whitespace()
                .map(|x| format!("{:?}", x.parse::<f64>().expect("a number") * s))
                .collect();
            out.push_str(&v.join(" "));
            last = r.end;
        }
    }
    out.push_str(&text[last..]);
    let tree = screwkit_model::urdf::load_str(&out, file).expect("scaled file loads");
    Chain::from_tree(&tree, None, None).expect("default chain")
}

/// A serial arm of revolute joints written as URDF, one joint per (origin xyz, origin rpy,
/// axis), limits ±3 rad, and a fixed tool frame after the last (xyz 0.05 0.02 0.1, rpy
/// 0.3 0.2 0.1): random and constructed arms for the analytic-IK tests and benchmark.
pub fn serial_arm(joints: &[([f64; 3], [f64; 3], [f64; 3])]) -> Kinematics {
    let mut s = String::from(r#"<robot name="random"><link name="l0"/>"#);
    for (i, (xyz, rpy, axis)) in joints.iter().enumerate() {
        s.push_str(&format!(
            r#"<link name="l{n}"/><joint name="j{n}" type="revolute"><parent link="l{i}"/><child link="l{n}"/><origin xyz="{} {} {}" rpy="{} {} {}"/><axis xyz="{} {} {}"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>"#,
            xyz[0], xyz[1], xyz[2], rpy[0], rpy[1], rpy[2], axis[0], axis[1], axis[2],
            n = i + 1
        ));
    }
    s.push_str(&format!(
        r#"<link name="tool"/><joint name="t" type="fixed"><parent link="l{}"/><child link="tool"/><origin xyz="0.05 0.02 0.1" rpy="0.3 0.2 0.1"/></joint></robot>"#,
        joints.len()
    ));
    let tree = screwkit_model::urdf::load_str(&s, "random.urdf").expect("the arm parses");
    Kinematics::new(&Chain::from_tree(&tree, None, Some("tool")).expect("a serial chain"))
}

/// A float64 `.npy` file's bytes written by hand (format 1.0), independent of the code under
/// test: `shape` is the header's Python tuple as text (`"(3, 6)"`, `"(7,)"`), so a test can
/// also write a header that lies about its data.
pub fn npy_bytes(descr: &str, fortran: bool, shape: &str, data: &[f64]) -> Vec<u8> {
    let mut h = format!(
        "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}",
        if fortran { "True" } else { "False" }
    );
    while (10 + h.len() + 1) % 64 != 0 {
        h.push(' ');
    }
    h.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(h.len() as u16).to_le_bytes());
    bytes.extend_from_slice(h.as_bytes());
    for x in data {
        bytes.extend_from_slice(&x.to_le_bytes());
    }
    bytes
}
