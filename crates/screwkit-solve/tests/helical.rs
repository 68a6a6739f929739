//! A helical joint written as a continuous joint with a prismatic mimic follower (the
//! textbook's screw joint in URDF): IK must not wrap its variable into (−π, π], since a full
//! turn also advances it by 2π × the pitch. Before the fix: "not converged", 0.628 m off.

use screwkit_model::{urdf, Chain};
use screwkit_solve::ik::{self, IkOptions};
use screwkit_solve::{fk, Kinematics, Workspace};

const HELICAL: &str = r#"<robot name="screw">
  <link name="base"/><link name="nut"/><link name="slider"/><link name="arm"/><link name="tip"/>
  <joint name="turn" type="continuous"><parent link="base"/><child link="nut"/><axis xyz="0 0 1"/></joint>
  <joint name="advance" type="prismatic"><parent link="nut"/><child link="slider"/><axis xyz="0 0 1"/>
    <limit lower="-100" upper="100" effort="1" velocity="1"/><mimic joint="turn" multiplier="0.1" offset="0"/></joint>
  <joint name="j2" type="revolute"><parent link="slider"/><child link="arm"/><origin xyz="0.3 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="j3" type="fixed"><parent link="arm"/><child link="tip"/><origin xyz="0.2 0 0"/></joint>
</robot>"#;

#[test]
fn a_helical_mimic_pair_is_solved_beyond_pi() {
    let tree = urdf::load_str(HELICAL, "screw.urdf").unwrap();
    let chain = Chain::from_tree(&tree, None, Some("tip")).unwrap();
    let kin = Kinematics::new(&chain);
    let mut ws = Workspace::new(&kin);
    assert_eq!(kin.dof(), 2);
    // (Restarts sample an unbounded variable in [−π, π]: far beyond that, several turns
    // away, a seed near the answer is needed.)
    for q_star in [[4.0, 0.3], [-5.5, -0.7], [-4.4, 1.1], [1.0, 0.2]] {
        let target = fk::fk(&kin, &mut ws, &q_star).unwrap();
        let opts = IkOptions {
            position_only: true, // 2 variables: the tip point (x, y, z) is reachable exactly
            ..IkOptions::default()
        };
        let r = ik::solve(&kin, &mut ws, &target, &[0.0, 0.0], &opts).unwrap();
        assert!(r.status.converged, "q* = {q_star:?}: {:?}", r.status);
        let got = fk::fk(&kin, &mut ws, &r.q).unwrap();
        let d = (got.translation() - target.translation()).norm();
        assert!(d < 1e-8, "q* = {q_star:?}: {d} m off at {:?}", r.q);
        // The height pins the turn: q1 = q1* exactly (no 2π representative reaches it).
        assert!((r.q[0] - q_star[0]).abs() < 1e-6, "{:?} vs {q_star:?}", r.q);
    }
}
