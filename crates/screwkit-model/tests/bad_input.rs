//! Bad input: each case gives a clear error naming the file and the joint or link, never a
//! panic.

use screwkit_model::{urdf, Chain, ErrorKind, ModelError};

/// A two-joint arm; `{J1}`/`{J2}` are replaced to inject faults.
const ARM: &str = r#"<robot name="arm">
  <link name="base"/><link name="a"/><link name="b"/>
  <joint name="j1" type="revolute">
    <origin xyz="0 0 0.1" rpy="0 0 0"/><parent link="base"/><child link="a"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <origin xyz="0.5 0 0"/><parent link="a"/><child link="b"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>"#;

fn chain_of(text: &str) -> Result<Chain, ModelError> {
    let tree = urdf::load_str(text, "test.urdf")?;
    Chain::from_tree(&tree, None, None)
}

fn expect_err(text: &str, check: impl Fn(&ErrorKind) -> bool, words: &[&str]) {
    let err = chain_of(text).expect_err("must fail");
    assert!(check(&err.kind), "unexpected error kind: {:?}", err.kind);
    let msg = err.to_string();
    assert!(msg.starts_with("test.urdf: "), "{msg}");
    for w in words {
        assert!(msg.contains(w), "message {msg:?} should mention {w:?}");
    }
}

#[test]
fn the_unmodified_arm_loads() {
    let c = chain_of(ARM).unwrap();
    assert_eq!(c.dof(), 2);
}

#[test]
fn malformed_xml() {
    expect_err(
        "<robot name=\"x\"><link name=\"a\"></robot>",
        |k| matches!(k, ErrorKind::Xml(_)),
        &["malformed XML"],
    );
    expect_err("not xml at all", |k| matches!(k, ErrorKind::Xml(_)), &[]);
    expect_err(
        "<model name=\"x\"/>",
        |k| matches!(k, ErrorKind::NotARobot(_)),
        &["<model>"],
    );
}

#[test]
fn empty_and_missing_files() {
    expect_err("", |k| *k == ErrorKind::Empty, &["empty"]);
    expect_err("  \n\t ", |k| *k == ErrorKind::Empty, &["empty"]);
    let err = urdf::load_file("/definitely/not/here.urdf").unwrap_err();
    assert!(matches!(
        err.kind,
        ErrorKind::Io {
            kind: std::io::ErrorKind::NotFound,
            ..
        }
    ));
    assert!(
        err.to_string()
            .starts_with("/definitely/not/here.urdf: cannot read"),
        "{err}"
    );
}

#[test]
fn unknown_base_or_tip_and_non_ancestor() {
    let tree = urdf::load_str(ARM, "test.urdf").unwrap();
    let e = Chain::from_tree(&tree, Some("nope"), None).unwrap_err();
    assert!(
        matches!(&e.kind, ErrorKind::UnknownLink { link, available } if link == "nope" && available.contains("\"base\"")),
        "{e}"
    );
    let e = Chain::from_tree(&tree, None, Some("hand")).unwrap_err();
    assert!(e.to_string().contains("unknown link \"hand\""), "{e}");
    let e = Chain::from_tree(&tree, Some("b"), Some("a")).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::NotAncestor { .. }));
    assert!(
        e.to_string()
            .contains("\"b\" is not an ancestor of tip link \"a\""),
        "{e}"
    );
    let e = Chain::from_tree(&tree, Some("a"), Some("a")).unwrap_err();
    assert!(matches!(e.kind, ErrorKind::SameLink(_)));
}

#[test]
fn structural_errors() {
    // Cycle: b → base closes the loop, so no link is a root.
    let cyc = ARM.replace(
        "</robot>",
        r#"<joint name="j3" type="fixed"><parent link="b"/><child link="base"/></joint></robot>"#,
    );
    expect_err(&cyc, |k| matches!(k, ErrorKind::NoRoot(_)), &["cycle"]);
    // A cycle beside a valid root.
    let cyc2 = ARM.replace(
        "</robot>",
        r#"<link name="c"/><link name="d"/>
           <joint name="k1" type="fixed"><parent link="c"/><child link="d"/></joint>
           <joint name="k2" type="fixed"><parent link="d"/><child link="c"/></joint></robot>"#,
    );
    expect_err(
        &cyc2,
        |k| matches!(k, ErrorKind::Cycle(_)),
        &["\"c\"", "\"d\""],
    );
    // Two parents.
    let two = ARM.replace(
        "</robot>",
        r#"<joint name="j3" type="fixed"><parent link="base"/><child link="b"/></joint></robot>"#,
    );
    expect_err(
        &two,
        |k| matches!(k, ErrorKind::TwoParents { .. }),
        &["\"b\"", "\"j2\"", "\"j3\""],
    );
    // Missing link.
    let missing = ARM.replace(r#"<child link="b"/>"#, r#"<child link="ghost"/>"#);
    expect_err(
        &missing,
        |k| matches!(k, ErrorKind::MissingLink { .. }),
        &["\"j2\"", "child link \"ghost\""],
    );
    // Several roots.
    let roots = ARM.replace("</robot>", r#"<link name="floating_thing"/></robot>"#);
    expect_err(
        &roots,
        |k| matches!(k, ErrorKind::SeveralRoots(_)),
        &["\"base\"", "\"floating_thing\""],
    );
    // Duplicates.
    let dup = ARM.replace(r#"<link name="b"/>"#, r#"<link name="b"/><link name="b"/>"#);
    expect_err(
        &dup,
        |k| matches!(k, ErrorKind::Duplicate { what: "link", .. }),
        &["duplicate link name \"b\""],
    );
    let dupj = ARM.replace(r#"joint name="j2""#, r#"joint name="j1""#);
    expect_err(
        &dupj,
        |k| matches!(k, ErrorKind::Duplicate { what: "joint", .. }),
        &["\"j1\""],
    );
}

#[test]
fn joint_errors() {
    let zero = ARM.replace(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 0 0"/>"#);
    expect_err(
        &zero,
        |k| *k == ErrorKind::ZeroAxis("j2".into()),
        &["joint \"j2\" has a zero axis"],
    );
    let nan = ARM.replace(r#"<origin xyz="0.5 0 0"/>"#, r#"<origin xyz="0.5 NaN 0"/>"#);
    expect_err(
        &nan,
        |k| matches!(k, ErrorKind::NonFinite { joint, .. } if joint == "j2"),
        &["\"j2\"", "<origin>"],
    );
    let inf_axis = ARM.replace(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 inf 0"/>"#);
    expect_err(
        &inf_axis,
        |k| matches!(k, ErrorKind::NonFinite { .. }),
        &["\"j2\"", "<axis>"],
    );
    let order = ARM.replace(
        r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>"#,
        r#"<limit lower="1" upper="-1" effort="1" velocity="1"/>
  </joint>
</robot>"#,
    );
    // urdf-rs does not check the order for URDF < 1.2; we do.
    expect_err(
        &order,
        |k| matches!(k, ErrorKind::LimitOrder { joint, .. } if joint == "j2"),
        &["lower limit 1 is greater than upper limit -1"],
    );
    let floating = ARM.replace(
        r#"name="j2" type="revolute""#,
        r#"name="j2" type="floating""#,
    );
    expect_err(
        &floating,
        |k| matches!(k, ErrorKind::UnsupportedJoint { .. }),
        &["unsupported joint type in chain", "\"j2\"", "floating"],
    );
    let no_limit = ARM.replace(
        r#"<axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
        r#"<axis xyz="0 1 0"/>"#,
    );
    expect_err(
        &no_limit,
        |k| *k == ErrorKind::MissingLimit("j2".into()),
        &["\"j2\"", "no <limit>"],
    );
    let bad_mimic = ARM.replace(
        r#"<axis xyz="0 1 0"/>"#,
        r#"<axis xyz="0 1 0"/><mimic joint="nobody"/>"#,
    );
    expect_err(
        &bad_mimic,
        |k| matches!(k, ErrorKind::Mimic { .. }),
        &["\"j2\" mimics joint \"nobody\""],
    );
    let bad_type = ARM.replace(r#"type="revolute""#, r#"type="revolving""#);
    expect_err(
        &bad_type,
        |k| matches!(k, ErrorKind::Urdf(_)),
        &["URDF parser"],
    );
}

/// A floating or planar joint off the chain is fine.
#[test]
fn unsupported_joints_off_the_path_are_fine() {
    let text = ARM.replace(
        "</robot>",
        r#"<link name="marker"/><joint name="free" type="floating"><parent link="base"/><child link="marker"/></joint></robot>"#,
    );
    let tree = urdf::load_str(&text, "test.urdf").unwrap();
    let c = Chain::from_tree(&tree, None, Some("b")).unwrap();
    assert_eq!(c.dof(), 2);
}

/// urdf-rs pitfalls, each guarded.
#[test]
fn urdf_rs_pitfalls() {
    // 1. A non-numeric token would be silently dropped by urdf-rs ("0.5 x 0 0" -> 0.5 0 0).
    let token = ARM.replace(r#"<origin xyz="0.5 0 0"/>"#, r#"<origin xyz="0.5 x 0 0"/>"#);
    expect_err(
        &token,
        |k| matches!(k, ErrorKind::BadNumber { .. }),
        &["joint \"j2\" <origin>", "\"x\" is not a number"],
    );
    let short = ARM.replace(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 1"/>"#);
    expect_err(
        &short,
        |k| matches!(k, ErrorKind::BadNumber { .. }),
        &["joint \"j2\" <axis>", "expected 3"],
    );
    let lim = ARM.replace(
        r#"lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
</robot>"#,
        r#"lower="-1" upper="1 2" effort="1" velocity="1"/>
  </joint>
</robot>"#,
    );
    expect_err(
        &lim,
        |k| matches!(k, ErrorKind::BadNumber { .. }),
        &["<limit>", "upper"],
    );
    // 2. A missing <limit> on a revolute joint must not become [0, 0]: covered by
    //    joint_errors (MissingLimit). 3. <limit> without velocity/effort loads; the model
    //    records them as absent.
    let no_vel = ARM.replace(
        r#"effort="1" velocity="1"/>
  </joint>
</robot>"#,
        r#"/>
  </joint>
</robot>"#,
    );
    let c = chain_of(&no_vel).unwrap();
    assert_eq!(
        (c.variables[1].velocity, c.variables[1].effort),
        (None, None)
    );
    assert_eq!(c.variables[0].velocity, Some(1.0));
}

/// xacro is expanded, not refused: a property becomes its value; `${…}` naming nothing is an
/// expansion error naming the file, line and name.
#[test]
fn xacro_is_expanded() {
    let x = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
        <xacro:property name="l" value="0.5"/>"#;
    let with_l = ARM
        .replace("<robot name=\"arm\">", x)
        .replace(r#"<origin xyz="0.5 0 0"/>"#, r#"<origin xyz="${l} 0 0"/>"#);
    let plain = chain_of(ARM).unwrap();
    assert_eq!(chain_of(&with_l).unwrap().home, plain.home);
    // ${l} with no property l (and no namespace: still xacro, it is in an <origin>).
    let expr = ARM.replace(r#"<origin xyz="0.5 0 0"/>"#, r#"<origin xyz="${l} 0 0"/>"#);
    let err = chain_of(&expr).unwrap_err();
    assert!(matches!(err.kind, ErrorKind::XacroExpand(_)), "{err}");
    let msg = err.to_string();
    assert!(
        msg.starts_with("test.urdf:") && msg.contains("unknown property or name \"l\""),
        "{msg}"
    );
    // Undeclared prefix: read as xacro (an empty macro definition, then no links at all).
    let undeclared = r#"<robot name="r"><xacro:macro name="m"/><link name="a"/></robot>"#;
    assert_eq!(
        urdf::load_str(undeclared, "test.urdf").unwrap().links,
        ["a"]
    );
    // The namespace declaration alone (left by xacro in its output) and ${...} in comments
    // are fine.
    let ok = ARM.replace(
        "<robot name=\"arm\">",
        "<robot name=\"arm\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\"><!-- ${prefix}j1 -->",
    );
    assert_eq!(chain_of(&ok).unwrap().dof(), 2);
}

/// URDF defaults: no <axis> means (1, 0, 0); no <origin> means identity.
#[test]
fn urdf_defaults() {
    let text = ARM
        .replace(r#"<axis xyz="0 1 0"/>"#, "")
        .replace(r#"<origin xyz="0.5 0 0"/>"#, "");
    let c = chain_of(&text).unwrap();
    let s2 = c.joints[1].s_space.twist().to_vector();
    // Axis x through (0, 0, 0.1): S = (1, 0, 0, 0, 0.1, 0).
    assert_eq!(s2.as_slice(), &[1.0, 0.0, 0.0, 0.0, 0.1, 0.0]);
    assert_eq!(*c.home.translation(), nalgebra::Vector3::new(0.0, 0.0, 0.1));
}

/// What urdfdom accepts is accepted: blank lines before the XML declaration, NUL bytes at the
/// end, a byte-order mark, a declared Latin-1 encoding (with a Latin-1 byte in a name).
#[test]
fn tolerated_like_urdfdom() {
    let decl = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    let plain = chain_of(ARM).unwrap();
    for text in [
        format!("\n\n  \n{decl}{ARM}"),
        format!("{decl}{ARM}\0\0"),
        format!("\u{feff}{decl}{ARM}"),
    ] {
        let dir = std::env::temp_dir().join(format!("screwkit-tolerate-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let f = dir.join("t.urdf");
        std::fs::write(&f, text.as_bytes()).unwrap();
        let tree = urdf::load_file(&f).unwrap_or_else(|e| panic!("{text:?}: {e}"));
        assert_eq!(
            Chain::from_tree(&tree, None, None).unwrap().home,
            plain.home
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
    // Latin-1: "é" as the single byte 0xE9 in a link name.
    let latin = ARM
        .replace("name=\"b\"", "name=\"b\u{e9}\"")
        .replace("link=\"b\"", "link=\"b\u{e9}\"");
    let mut bytes = b"<?xml version=\"1.0\" encoding=\"ISO-8859-1\"?>\n".to_vec();
    bytes.extend(latin.chars().map(|c| c as u32 as u8));
    let dir = std::env::temp_dir().join(format!("screwkit-latin1-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("latin1.urdf");
    std::fs::write(&f, &bytes).unwrap();
    let tree = urdf::load_file(&f).unwrap();
    assert!(
        tree.links.iter().any(|l| l == "b\u{e9}"),
        "{:?}",
        tree.links
    );
    // The same bytes without the declaration: not UTF-8, said so.
    std::fs::write(
        &f,
        &bytes[bytes.iter().position(|&b| b == b'\n').unwrap() + 1..],
    )
    .unwrap();
    let e = urdf::load_file(&f).unwrap_err();
    assert!(
        e.to_string().contains("not UTF-8") && e.to_string().contains("ISO-8859-1"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// An axis shorter than 1e-9 is refused like a zero one.
#[test]
fn near_zero_axis_is_refused() {
    let tiny = ARM.replacen("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 1e-10\"/>", 1);
    assert_ne!(tiny, ARM);
    expect_err(
        &tiny,
        |k| matches!(k, ErrorKind::ZeroAxis(_)),
        &["zero axis", "1e-9"],
    );
    let small = ARM.replacen("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"0 0 1e-6\"/>", 1);
    assert!(chain_of(&small).is_ok());
}

/// The pose of one link in another through fixed joints, both ways; a movable joint between
/// them is named.
#[test]
fn fixed_transforms_between_links() {
    let text = r#"<robot name="r"><link name="world"/><link name="base"/><link name="a"/><link name="cam"/>
      <joint name="mount" type="fixed"><parent link="world"/><child link="base"/><origin xyz="1 2 3" rpy="0 0 1.5707963267948966"/></joint>
      <joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="c" type="fixed"><parent link="base"/><child link="cam"/><origin xyz="0 0 0.5"/></joint></robot>"#;
    let tree = urdf::load_str(text, "t.urdf").unwrap();
    let t = tree.fixed_transform("base", "world").unwrap();
    let w = tree.fixed_transform("world", "base").unwrap();
    assert!(t.compose(&w).max_abs_diff(&screwkit_lie::Se3::identity()) < 1e-15);
    assert!((w.translation() - nalgebra::Vector3::new(1.0, 2.0, 3.0)).norm() < 1e-15);
    // world origin seen from base: R_z(90°)ᵀ (−(1, 2, 3)) = (−2, 1, −3).
    assert!((t.translation() - nalgebra::Vector3::new(-2.0, 1.0, -3.0)).norm() < 1e-14);
    let cam = tree.fixed_transform("world", "cam").unwrap();
    assert!((cam.translation() - nalgebra::Vector3::new(1.0, 2.0, 3.5)).norm() < 1e-15);
    let e = tree.fixed_transform("cam", "a").unwrap_err();
    assert!(
        e.to_string().contains("joint \"j1\" between them moves"),
        "{e}"
    );
}
