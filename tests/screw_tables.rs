//! Snapshots of the screw-axis tables (space and body) and M of every bundled robot.
//!
//! Each snapshot was reviewed by hand once against an independent calculation:
//! - planar_3r: by hand, S_i = (0,0,1, 0,−x_i,0) with x = 0, 1, 1.8; M = Tx(2.3);
//!   B_i = (0,0,1, 0, 2.3 − x_i, 0).
//! - ur5: Modern Robotics Example 4.5 closed form (also asserted in
//!   crates/screwkit-model/tests/bundled.rs).
//! - panda: FK from the Franka modified-DH table (bundled.rs); the table's axes checked by eye
//!   against the DH frames (z₁ up, z₂ = −y, …; M at x = 0.088, z = 0.333 + 0.316 + 0.384 −
//!   0.107 − 0.1034 = 0.8226, rotated π about x then −π/4 about z).
//! - iiwa14: axes on the vertical line (bundled.rs closed form); M = Tz(1.306).
//! - scara: closed form (bundled.rs); prismatic row shows "–" and "∞".
//! - tricky, gripper_arm, torso_two_arms: FK against direct composition of the URDF
//!   transforms (bundled.rs); mimic rows label their leader.
//!
//! CI runs with INSTA_UPDATE=no, so a changed number fails.

use screwkit::lie::Frame;
use screwkit::model::table::{to_csv, to_json, to_markdown};
use screwkit::model::{load_chain, Chain};

fn chain(file: &str, base: Option<&str>, tip: Option<&str>) -> Chain {
    load_chain(
        format!("{}/assets/urdf/{file}", env!("CARGO_MANIFEST_DIR")),
        base,
        tip,
    )
    .unwrap()
}

#[test]
fn planar_3r() {
    insta::assert_snapshot!(to_markdown(
        &chain("planar_3r.urdf", None, None),
        &Frame::ALL
    ));
}

#[test]
fn ur5() {
    insta::assert_snapshot!(to_markdown(&chain("ur5.urdf", None, None), &Frame::ALL));
}

#[test]
fn panda() {
    insta::assert_snapshot!(to_markdown(&chain("panda.urdf", None, None), &Frame::ALL));
}

#[test]
fn iiwa14() {
    insta::assert_snapshot!(to_markdown(&chain("iiwa14.urdf", None, None), &Frame::ALL));
}

#[test]
fn scara() {
    insta::assert_snapshot!(to_markdown(&chain("scara.urdf", None, None), &Frame::ALL));
}

#[test]
fn tricky() {
    insta::assert_snapshot!(to_markdown(
        &chain("tricky.urdf", Some("base_link"), None),
        &Frame::ALL
    ));
}

#[test]
fn torso_left_arm() {
    insta::assert_snapshot!(to_markdown(
        &chain("torso_two_arms.urdf", None, Some("left_hand")),
        &Frame::ALL
    ));
}

#[test]
fn gripper_arm_mimic() {
    insta::assert_snapshot!(to_markdown(
        &chain("gripper_arm.urdf", None, Some("right_finger")),
        &Frame::ALL
    ));
}

#[test]
fn ur5_csv() {
    insta::assert_snapshot!(to_csv(&chain("ur5.urdf", None, None), &[Frame::Space]));
}

#[test]
fn scara_json() {
    let v = to_json(&chain("scara.urdf", None, None));
    insta::assert_snapshot!(serde_json::to_string_pretty(&v).unwrap());
}
