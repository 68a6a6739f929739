//! Analytic IK (spherical wrist, 2 ∥ 3): every returned solution reaches the target (FK, an
//! independent call) and lies within the limits, and the configuration the target came from is
//! among them; on the nine industrial arms of ../shared/xacro/expanded (ignored without it;
//! `.ci/run` runs it) and on a PUMA-type arm built here.

mod common;

use common::{fk1, Sampler};
use screwkit_model::Chain;
use screwkit_solve::analytic::solve_all;
use screwkit_solve::family::{classify, Family};
use screwkit_solve::Kinematics;

fn check(kin: &Kinematics, name: &str, trials: usize) {
    let mut rng = Sampler::new(11);
    let mut counts = Vec::new();
    for _ in 0..trials {
        let q_star = rng.config(kin);
        let target = fk1(kin, &q_star).unwrap();
        let sols = solve_all(kin, &target).unwrap();
        assert!(sols.exact, "{name}: {q_star:?}");
        assert!(!sols.q.is_empty());
        for q in &sols.q {
            assert!(kin.within_limits(q, 0.0), "{name}: {q:?}");
            let d = fk1(kin, q).unwrap().max_abs_diff(&target);
            assert!(d < 1e-10, "{name}: a solution misses by {d:e}");
        }
        assert!(
            sols.q
                .iter()
                .any(|q| q.iter().zip(&q_star).all(|(a, b)| (a - b).abs() < 1e-7)),
            "{name}: q* = {q_star:?} not among {} solutions",
            sols.q.len()
        );
        assert!(
            sols.branches >= 1 && sols.branches <= 8,
            "{name}: {} branches",
            sols.branches
        );
        counts.push(sols.branches);
    }
    eprintln!(
        "{name}: distinct solutions (mod 2π) per pose: min {} max {}",
        counts.iter().min().unwrap(),
        counts.iter().max().unwrap()
    );
}

/// A PUMA-type arm: axis 1 vertical, 2 ∥ 3 horizontal with an offset, a spherical wrist.
const PUMA: &str = r#"<robot name="puma"><link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/><link name="l5"/><link name="l6"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.6"/><axis xyz="0 0 1"/><limit lower="-2.8" upper="2.8" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.05 0.15 0"/><axis xyz="0 1 0"/><limit lower="-2.0" upper="2.0" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.43 0 0"/><axis xyz="0 1 0"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/><origin xyz="0.1 -0.02 0.3"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j5" type="revolute"><parent link="l4"/><child link="l5"/><origin xyz="0.2 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="j6" type="revolute"><parent link="l5"/><child link="l6"/><origin xyz="0 0 0"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>"#;

#[test]
fn puma_type_arm_all_solutions() {
    let tree = screwkit_model::urdf::load_str(PUMA, "puma.urdf").unwrap();
    let kin = Kinematics::new(&Chain::from_tree(&tree, None, None).unwrap());
    assert_eq!(classify(&kin).family, Family::SphericalWristTwoParallel);
    check(&kin, "puma", 300);
}

#[test]
fn ur5_all_solutions() {
    let (_, _, kin) = common::load("ur5.urdf", None, None);
    assert_eq!(classify(&kin).family, Family::ThreeParallelTwoIntersecting);
    check(&kin, "ur5", 500);
}

#[test]
fn other_families_are_refused_by_name() {
    let (_, _, kin) = common::load("iiwa14.urdf", None, None);
    let e = solve_all(&kin, kin.home()).unwrap_err();
    assert!(e.to_string().contains("7R (redundant)"), "{e}");
}

#[test]
#[ignore = "needs ../shared/xacro (SCREWKIT_SHARED_XACRO); .ci/run runs it with --ignored"]
fn industrial_arms_all_solutions() {
    let dir = std::env::var("SCREWKIT_SHARED_XACRO")
        .unwrap_or_else(|_| concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/xacro").into());
    for f in [
        "irb140",
        "kr10r1100sixx",
        "kr120r2500pro",
        "kr150_2",
        "kr16_2",
        "kr3r540",
        "kr5_arc",
        "kr6r700sixx",
        "kr6r900sixx",
    ] {
        let chain = screwkit_model::load_chain(
            format!("{dir}/expanded/{f}.urdf"),
            Some("base_link"),
            Some("tool0"),
        )
        .unwrap();
        let kin = Kinematics::new(&chain);
        assert_eq!(
            classify(&kin).family,
            Family::SphericalWristTwoParallel,
            "{f}"
        );
        check(&kin, f, 200);
    }
}
