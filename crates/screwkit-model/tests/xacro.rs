//! xacro expansion: the nine real xacro files of the CI data (`SCREWKIT_SHARED_XACRO`) against the expansions ROS's
//! own `xacro` made of them (same robot: links, joints, types, origins, axes, limits to 1e-12),
//! and cases built here for what those files do not use, each against the URDF it must give.

use std::path::PathBuf;

use screwkit_model::urdf::{load_file, load_file_with, load_str};
use screwkit_model::xacro::{expand_str, XacroOptions};
use screwkit_model::{ErrorKind, Tree};

/// The CI data's xacro folder, named by `SCREWKIT_SHARED_XACRO` (set by `.ci/run`'s
/// conformance stage; the tests that need it are ignored otherwise).
fn shared_xacro() -> PathBuf {
    PathBuf::from(
        std::env::var("SCREWKIT_SHARED_XACRO")
            .expect("SCREWKIT_SHARED_XACRO must name the CI data's xacro folder"),
    )
}

/// Same links, and the same joints with the same numbers (to `tol`).
fn assert_same_robot(a: &Tree, b: &Tree, tol: f64, what: &str) {
    let mut la = a.links.clone();
    let mut lb = b.links.clone();
    la.sort();
    lb.sort();
    assert_eq!(la, lb, "{what}: links");
    assert_eq!(a.joints.len(), b.joints.len(), "{what}: joint count");
    for ja in &a.joints {
        let jb = &b.joints[b
            .joint(&ja.name)
            .unwrap_or_else(|| panic!("{what}: joint {} missing", ja.name))];
        assert_eq!(ja.kind, jb.kind, "{what}: {} type", ja.name);
        assert_eq!(
            a.links[ja.parent], b.links[jb.parent],
            "{what}: {} parent",
            ja.name
        );
        assert_eq!(
            a.links[ja.child], b.links[jb.child],
            "{what}: {} child",
            ja.name
        );
        let close = |x: &[f64; 3], y: &[f64; 3]| x.iter().zip(y).all(|(p, q)| (p - q).abs() <= tol);
        assert!(
            close(&ja.origin_xyz, &jb.origin_xyz),
            "{what}: {} xyz {:?} vs {:?}",
            ja.name,
            ja.origin_xyz,
            jb.origin_xyz
        );
        assert!(
            close(&ja.origin_rpy, &jb.origin_rpy),
            "{what}: {} rpy {:?} vs {:?}",
            ja.name,
            ja.origin_rpy,
            jb.origin_rpy
        );
        assert!(close(&ja.axis, &jb.axis), "{what}: {} axis", ja.name);
        match (&ja.limit, &jb.limit) {
            (Some(x), Some(y)) => {
                assert!(
                    (x.lower - y.lower).abs() <= tol && (x.upper - y.upper).abs() <= tol,
                    "{what}: {} limits {x:?} vs {y:?}",
                    ja.name
                );
                assert_eq!(x.velocity.is_some(), y.velocity.is_some());
                if let (Some(p), Some(q)) = (x.velocity, y.velocity) {
                    assert!((p - q).abs() <= tol, "{what}: {} velocity", ja.name);
                }
                if let (Some(p), Some(q)) = (x.effort, y.effort) {
                    assert!((p - q).abs() <= tol, "{what}: {} effort", ja.name);
                }
            }
            (None, None) => {}
            _ => panic!("{what}: {} limit presence differs", ja.name),
        }
        assert_eq!(ja.mimic, jb.mimic, "{what}: {} mimic", ja.name);
    }
}

const SHARED: &[&str] = &[
    "kuka_kr3_support/urdf/kr3r540.xacro",
    "kuka_kr5_support/urdf/kr5_arc.xacro",
    "kuka_kr6_support/urdf/kr6r700sixx.xacro",
    "kuka_kr6_support/urdf/kr6r900sixx.xacro",
    "kuka_kr10_support/urdf/kr10r1100sixx.xacro",
    "kuka_kr16_support/urdf/kr16_2.xacro",
    "kuka_kr120_support/urdf/kr120r2500pro.xacro",
    "kuka_kr150_support/urdf/kr150_2.xacro",
    "abb_irb140/urdf/irb140.xacro",
];

#[test]
#[ignore = "needs the CI data's xacro files: SCREWKIT_SHARED_XACRO (.ci/run's conformance stage sets it)"]
fn real_xacro_files_match_ros_xacro() {
    let dir = shared_xacro();
    let opts = XacroOptions {
        package_paths: vec![dir.clone()],
        args: Vec::new(),
    };
    for file in SHARED {
        let stem = std::path::Path::new(file)
            .file_stem()
            .unwrap()
            .to_str()
            .unwrap();
        let ours = load_file_with(dir.join(file), &opts).unwrap_or_else(|e| panic!("{e}"));
        let reference = load_file(dir.join("expanded").join(format!("{stem}.urdf"))).unwrap();
        assert_same_robot(&ours, &reference, 1e-12, file);
        let chain =
            screwkit_model::Chain::from_tree(&ours, Some("base_link"), Some("tool0")).unwrap();
        assert_eq!(chain.dof(), 6, "{file}");
    }
}

fn cases() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/xacro_cases"))
}

/// Cases built for what the real files do not use (macros with block, default and inherited
/// parameters, xacro:call, scoped and lazy properties; expressions, conditions, args, $(eval),
/// escapes; includes through $(find) and relative paths, xacro:element/attribute), each against
/// the expansion ROS's xacro 2.1.1 made of it (`NAME.expected.urdf`; the Python suite re-makes
/// them with the real xacro and compares again).
#[test]
fn built_cases_match_ros_xacro() {
    let opts = XacroOptions {
        package_paths: vec![cases().join("pkgs")],
        args: Vec::new(),
    };
    for case in ["macros", "expressions", "includes", "substitutions"] {
        let ours = load_file_with(cases().join(format!("{case}.xacro")), &opts)
            .unwrap_or_else(|e| panic!("{case}: {e}"));
        let reference = load_file(cases().join(format!("{case}.expected.urdf"))).unwrap();
        assert_same_robot(&ours, &reference, 0.0, case);
    }
}

/// xacro:arg values from the caller change the robot.
#[test]
fn arguments_override_defaults() {
    let file = cases().join("expressions.xacro");
    let with = |args: &[(&str, &str)]| {
        let opts = XacroOptions {
            package_paths: Vec::new(),
            args: args
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
        };
        load_file_with(&file, &opts).unwrap()
    };
    let default = with(&[]);
    assert!(default.joint("tool_joint").is_some() && default.joint("j2").is_some());
    let no_tool = with(&[("with_tool", "false")]);
    assert!(no_tool.joint("tool_joint").is_none());
    let scaled = with(&[("scale", "1.5")]);
    assert!(scaled.joint("j2").is_none(), "j2 needs scale == 2");
    assert!((scaled.joints[scaled.joint("j1").unwrap()].origin_xyz[0] - 0.15).abs() < 1e-15);
    assert_eq!(
        XacroOptions::parse_arg("scale:=5"),
        Ok(("scale".to_string(), "5".to_string()))
    );
    assert!(XacroOptions::parse_arg("scale=5").is_err());
}

/// The three namespace spellings, and the prefix used without a declaration.
#[test]
fn every_namespace_spelling_and_an_undeclared_prefix() {
    for ns in screwkit_model::xacro::XACRO_NAMESPACES {
        let text = format!(
            r#"<robot name="r" xmlns:xacro="{ns}"><xacro:property name="n" value="b"/>
            <link name="a"/><link name="${{n}}"/>
            <joint name="j" type="fixed"><parent link="a"/><child link="${{n}}"/></joint></robot>"#
        );
        let tree = load_str(&text, "ns.xacro").unwrap();
        assert_eq!(tree.links, ["a", "b"], "{ns}");
    }
    let undeclared = r#"<robot name="r"><xacro:property name="n" value="b"/>
        <link name="a"/><link name="${n}"/>
        <joint name="j" type="fixed"><parent link="a"/><child link="${n}"/></joint></robot>"#;
    assert_eq!(load_str(undeclared, "u.xacro").unwrap().links, ["a", "b"]);
}

/// What cannot be expanded fails in one line naming the file, the line and the construct.
#[test]
fn errors_name_file_line_and_construct() {
    let dir = std::path::Path::new(".");
    let opts = XacroOptions::default();
    let cases: &[(&str, &[&str])] = &[
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<link name=\"${nope}\"/></robot>",
            &["bad.xacro:2", "unknown property or name \"nope\""],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:macro name=\"m\" params=\"a\"/>\n<xacro:m/></robot>",
            &["bad.xacro:3", "<xacro:m>: missing parameter a"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:macro name=\"m\" params=\"a\"/>\n<xacro:m a=\"1\" b=\"2\"/></robot>",
            &["bad.xacro:3", "unknown parameter b"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n\n<xacro:frobnicate/></robot>",
            &["bad.xacro:3", "<xacro:frobnicate>: no such macro"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:property name=\"a\" value=\"${b}\"/>\n<xacro:property name=\"b\" value=\"${a}\"/>\n<link name=\"${a}\"/></robot>",
            &["defined in terms of itself"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:include filename=\"$(find no_such_pkg)/x.xacro\"/></robot>",
            &["bad.xacro:2", "$(find no_such_pkg): package not found", "package paths"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:include filename=\"missing.xacro\"/></robot>",
            &["bad.xacro:2", "<xacro:include filename=\"missing.xacro\">: cannot read"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:macro name=\"m\" params=\"\"><xacro:m/></xacro:macro>\n<xacro:m/></robot>",
            &["nested more than 200 deep"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<link name=\"${1 +}\"/></robot>",
            &["bad.xacro:2", "${1 +}"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<link name=\"$(arg x)\"/></robot>",
            &["bad.xacro:2", "$(arg x): no such argument"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<xacro:if value=\"maybe\"><link name=\"a\"/></xacro:if></robot>",
            &["bad.xacro:2", "\"maybe\" is not a boolean"],
        ),
        (
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n<link name=\"${1/0}\"/></robot>",
            &["bad.xacro:2", "division by zero"],
        ),
    ];
    for (text, want) in cases {
        let e = expand_str(text, "bad.xacro", dir, &opts).unwrap_err();
        assert!(matches!(e.kind, ErrorKind::XacroExpand(_)), "{e}");
        let msg = e.to_string();
        assert_eq!(msg.lines().count(), 1, "{msg}");
        for w in *want {
            assert!(msg.contains(w), "{msg:?} lacks {w:?}");
        }
    }
}
