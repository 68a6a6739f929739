//! Loading any description by content (`screwkit_model::load`) and MuJoCo's qpos layout
//! (`screwkit_model::mujoco_qpos`), as a library user reaches them, on the bundled models.

use screwkit_model::{load, mujoco_qpos, Format, KinematicTree, XacroOptions};

fn asset(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets")
        .join(path)
}

/// The format is told by content, whatever the file is called; each format's tree is the one
/// its own reader gives.
#[test]
fn formats_are_told_apart_by_content() {
    let mjcf = std::fs::read_to_string(asset("mjcf/humanoid.xml")).unwrap();
    let urdf = std::fs::read_to_string(asset("urdf/ur5.urdf")).unwrap();
    let chain = screwkit_model::load_chain(asset("urdf/ur5.urdf"), None, None).unwrap();
    let table = screwkit_model::table::to_csv(&chain, &[screwkit_lie::Frame::Space]);
    assert_eq!(Format::of(&mjcf), Format::Mjcf);
    assert_eq!(Format::of(&urdf), Format::Urdf);
    assert_eq!(Format::of(&table), Format::ScrewTable);
    // The MJCF humanoid is the URDF humanoid joint for joint (its file says so), plus the
    // free joint: the same joint names in the same order.
    let from_mjcf = load::load_tree(asset("mjcf/humanoid.xml"), &XacroOptions::default()).unwrap();
    let from_urdf = load::load_tree(asset("urdf/humanoid.urdf"), &XacroOptions::default()).unwrap();
    let movable = |t: &screwkit_model::Tree| -> Vec<String> {
        t.joints
            .iter()
            .filter(|j| j.kind.is_movable())
            .map(|j| j.name.clone())
            .collect()
    };
    let mut a = movable(&from_mjcf);
    let mut b = movable(&from_urdf);
    a.sort();
    b.sort();
    assert_eq!(a, b);
    assert!(from_mjcf.floating_root && !from_urdf.floating_root);
}

/// `load_chain` reads a screw table file too, as its exact chain: the screws bit for bit as
/// the table gives them (the CSV prints 17 significant digits).
#[test]
fn load_chain_reads_a_screw_table_exactly() {
    let ur5 = screwkit_model::load_chain(asset("urdf/ur5.urdf"), None, None).unwrap();
    let dir = std::env::temp_dir().join(format!("screwkit-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("ur5_screws.txt");
    std::fs::write(
        &path,
        screwkit_model::table::to_csv(&ur5, &[screwkit_lie::Frame::Space]),
    )
    .unwrap();
    let table = screwkit_model::load_chain(&path, None, None).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(table.dof(), 6);
    for (a, b) in table.joints.iter().zip(&ur5.joints) {
        let (sa, sb) = (a.s_space.twist(), b.s_space.twist());
        let d = (sa.w - sb.w).amax().max((sa.v - sb.v).amax());
        assert!(d < 1e-15, "{}: {sa:?} against {sb:?}", b.name);
    }
    assert!(table.home.max_abs_diff(&ur5.home) < 1e-15);
}

/// MuJoCo's qpos of the floating humanoid: the free joint's quaternion w first in qpos, last
/// in q; both ways round trip; the whole-model form writes into a given qpos; wrong lengths
/// name the argument.
#[test]
fn qpos_layout_round_trips_on_the_floating_humanoid() {
    let tree = load::load_tree(asset("mjcf/humanoid.xml"), &XacroOptions::default()).unwrap();
    let model = KinematicTree::from_tree(&tree)
        .unwrap()
        .with_floating_base(true);
    let n = model.nq();
    assert_eq!(mujoco_qpos::qpos_len(&model), n);
    let q: Vec<f64> = (0..n)
        .map(|i| match i {
            3..=5 => 0.0,
            6 => 1.0,
            _ => 0.01 * i as f64,
        })
        .collect();
    let qpos = mujoco_qpos::to_qpos(&model, &q, None).unwrap();
    assert_eq!(qpos[3], 1.0, "w first");
    assert_eq!(&qpos[..3], &q[..3]);
    assert_eq!(&qpos[7..], &q[7..], "the file's joints in MuJoCo's order");
    assert_eq!(mujoco_qpos::from_qpos(&model, &qpos).unwrap(), q);
    let whole = vec![9.0; mujoco_qpos::model_qpos_len(&model)];
    assert_eq!(
        mujoco_qpos::to_qpos(&model, &q, Some(&whole)).unwrap(),
        qpos
    );
    let short = mujoco_qpos::from_qpos(&model, &qpos[1..]).unwrap_err();
    assert_eq!(short.argument, "qpos");
    assert!(short
        .message
        .contains(&format!("expected {n} MuJoCo qpos values")));
    assert_eq!(
        mujoco_qpos::to_qpos(&model, &q[1..], None)
            .unwrap_err()
            .argument,
        "q"
    );
}
