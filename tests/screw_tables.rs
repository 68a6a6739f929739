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

/// Issue 44, item 12: a CSV table prints a mimic's multiplier and offset to six decimals, as
/// every other number (three moved a tip 0.87 mm on a round trip).
#[test]
fn csv_mimic_drives_round_trip_to_six_decimals() {
    use screwkit::model::table::read_screw_table;
    let text = std::fs::read_to_string(format!(
        "{}/assets/urdf/gripper_arm.urdf",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
    .replace("multiplier=\"-1\"", "multiplier=\"-1.23456789\"")
    .replace("offset=\"0.1\"", "offset=\"0.0987654\"");
    assert!(text.contains("-1.23456789") && text.contains("0.0987654"));
    let tree = screwkit::model::urdf::load_str(&text, "g.urdf").unwrap();
    let chain = Chain::from_tree(&tree, None, Some("right_finger")).unwrap();
    let csv = to_csv(&chain, &[Frame::Space]);
    assert!(csv.contains("-1.234568 × elbow_joint + 0.098765"), "{csv}");
    let back = read_screw_table(&csv, "g.csv").unwrap().chain().unwrap();
    let coupled = back
        .joints
        .iter()
        .find(|j| j.name == "coupled_joint")
        .unwrap();
    assert!((coupled.drive.multiplier + 1.23456789).abs() < 5e-7);
    assert!((coupled.drive.offset - 0.0987654).abs() < 5e-7);
}
