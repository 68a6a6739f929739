//! MJCF input (`screwkit_model::mjcf`): what is read from the bundled construct model, and
//! every refusal as one message naming the file, the line and the element. (The poses are
//! checked against MuJoCo itself in `crates/screwkit-py/tests/test_mjcf.py`.)

use std::path::{Path, PathBuf};

use screwkit_model::{mjcf, JointKind, KinematicTree};

fn asset() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/mjcf/two_arm_constructs.xml")
}

fn error_of(xml: &str) -> String {
    mjcf::load_str(xml, "m.xml", Path::new("."))
        .map(|t| format!("loaded {} links", t.links.len()))
        .unwrap_or_else(|e| e.to_string())
}

fn body(inner: &str) -> String {
    format!("<mujoco>\n<worldbody>\n<body name=\"b\">\n{inner}\n</body>\n</worldbody>\n</mujoco>")
}

#[test]
fn the_construct_model_reads_as_mujoco_orders_it() {
    let text = std::fs::read_to_string(asset()).unwrap();
    assert!(mjcf::is_mjcf(&text));
    assert!(!mjcf::is_mjcf("<?xml version=\"1.0\"?><robot name=\"r\"/>"));
    assert!(mjcf::is_mjcf(
        "<?xml version=\"1.0\"?>\n<!-- c -->\n<mujoco model=\"m\"/>"
    ));
    let tree = mjcf::load_file(asset()).unwrap();
    assert_eq!(tree.name, "two_arm_constructs");
    assert!(!tree.floating_root);
    let kt = KinematicTree::from_tree(&tree).unwrap();
    let names: Vec<&str> = kt.variables.iter().map(|v| v.name.as_str()).collect();
    // MuJoCo's joint order (bodies depth first), the coupled follower excluded.
    assert_eq!(
        names,
        [
            "waist",
            "left_shoulder",
            "left_shoulder_roll",
            "left_elbow",
            "left_slide",
            "right_shoulder",
            "right_elbow"
        ]
    );
    let roll = &tree.joints[tree.joint("right_shoulder_roll").unwrap()];
    let m = roll.mimic.as_ref().unwrap();
    assert_eq!(
        (m.leader.as_str(), m.multiplier, m.offset),
        ("left_shoulder_roll", -1.0, 0.0)
    );
    // Degrees: the elbow's range is [−150°, 0], the slide's in metres.
    let elbow = &tree.joints[tree.joint("left_elbow").unwrap()];
    assert_eq!(elbow.limit.unwrap().lower, (-150.0_f64).to_radians());
    let slide = &tree.joints[tree.joint("left_slide").unwrap()];
    assert_eq!(slide.kind, JointKind::Prismatic);
    assert_eq!(
        (slide.limit.unwrap().lower, slide.limit.unwrap().upper),
        (0.0, 0.1)
    );
    // Sites are links; the inertials are kept.
    assert!(tree.link("left_hand").is_ok() && tree.link("right_hand").is_ok());
    let torso = tree.link("torso").unwrap();
    assert_eq!(tree.inertials[torso].unwrap().mass, 5.0);
    assert!(tree.warnings.is_empty(), "{:?}", tree.warnings);
}

#[test]
fn refusals_name_the_file_line_and_element() {
    for (xml, words) in [
        ("<mujoco><worldbody><body>".to_string(), "malformed XML"),
        ("<robot name=\"x\"/>".to_string(), "expected <mujoco>"),
        (body("<joint name=\"j\" type=\"spin\"/>"), "m.xml:4: <joint name=\"j\">: unknown joint type \"spin\""),
        (body("<joint name=\"j\" type=\"ball\"/>"), "ball joints"),
        (body("<replicate count=\"3\"><body name=\"r\"/></replicate>"), "m.xml:4: <replicate>: <replicate> (bodies MuJoCo generates when compiling) is not read"),
        (body("<attach model=\"arm\" prefix=\"a_\"/>"), "<attach>: <attach> (bodies MuJoCo generates"),
        (body("<joint name=\"j\" ref=\"x\"/>"), "ref=\"x\": not 1 numbers"),
        (body("<joint name=\"j\" range=\"1 2 3\"/>"), "range=\"1 2 3\": expected 2 numbers"),
        (body("<joint name=\"j\" range=\"10 -10\"/>"), "range [10, -10] is empty"),
        (body("<joint name=\"j\" axis=\"0 0 0\"/>"), "axis is zero"),
        (body("<joint name=\"j\" class=\"nope\"/>"), "class \"nope\" is not defined"),
        (body("<joint name=\"j\" pos=\"nan 0 0\"/>"), "not finite"),
        (body("<site name=\"s\" quat=\"0 0 0 0\"/>"), "a zero quaternion"),
        (body("<site name=\"s\" quat=\"1 0 0 0\" euler=\"0 0 0\"/>"), "more than one orientation"),
        (
            "<mujoco><worldbody><body name=\"a\"><joint name=\"h\"/><body name=\"b\"><freejoint/></body></body></worldbody></mujoco>".into(),
            "a free joint is read only on the file's single top-level body",
        ),
        (
            "<mujoco><compiler angle=\"gradian\"/><worldbody/></mujoco>".into(),
            "angle=\"gradian\"",
        ),
        (
            "<mujoco><compiler autolimits=\"false\"/><worldbody><body><joint range=\"0 1\"/></body></worldbody></mujoco>".into(),
            "has a range but no limited",
        ),
        (
            format!(
                "{}<equality><joint joint1=\"j1\" joint2=\"j2\" polycoef=\"0 1 0.5 0 0\"/></equality></mujoco>",
                body("<joint name=\"j1\"/><body name=\"c\"><joint name=\"j2\"/></body>")
                    .trim_end_matches("</mujoco>")
            ),
            "terms above the linear",
        ),
        (
            "<mujoco><include file=\"/nonexistent/part.xml\"/></mujoco>".into(),
            "m.xml:1: <include>: cannot read \"/nonexistent/part.xml\"",
        ),
        (
            "<mujoco><worldbody><joint name=\"j\"/></worldbody></mujoco>".into(),
            "a joint belongs in a <body>",
        ),
    ] {
        let e = error_of(&xml);
        assert!(e.contains(words), "{e}\n  (wanted {words})");
        assert_eq!(e.lines().count(), 1, "{e}");
    }
}

#[test]
fn circular_and_deep_includes_are_refused() {
    let dir = std::env::temp_dir().join(format!("sk-mjcf-inc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("a.xml"),
        "<mujoco><include file=\"b.xml\"/></mujoco>",
    )
    .unwrap();
    std::fs::write(
        dir.join("b.xml"),
        "<mujoco><include file=\"a.xml\"/></mujoco>",
    )
    .unwrap();
    let e = mjcf::load_file(dir.join("a.xml")).unwrap_err().to_string();
    assert!(
        e.contains("circular include") && e.contains("b.xml:1"),
        "{e}"
    );
    // A diamond that doubles at every level: bounded by the element count, never a hang.
    for k in 0..30 {
        std::fs::write(
            dir.join(format!("d{k}.xml")),
            format!(
                "<mujoco><include file=\"d{n}.xml\"/><include file=\"d{n}.xml\"/></mujoco>",
                n = k + 1
            ),
        )
        .unwrap();
    }
    std::fs::write(dir.join("d30.xml"), "<mujoco><worldbody/></mujoco>").unwrap();
    let e = mjcf::load_file(dir.join("d0.xml")).unwrap_err().to_string();
    assert!(e.contains("more than 10000 included files"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn tendons_and_loop_closures_are_warnings() {
    let xml = format!(
        "{}<tendon><fixed name=\"t\"><joint joint=\"j\" coef=\"1\"/></fixed></tendon><equality><connect body1=\"b\" body2=\"world\" anchor=\"0 0 0\"/></equality></mujoco>",
        body("<joint name=\"j\"/>").trim_end_matches("</mujoco>")
    );
    let tree = mjcf::load_str(&xml, "m.xml", Path::new(".")).unwrap();
    assert_eq!(tree.warnings.len(), 2, "{:?}", tree.warnings);
    assert!(tree.warnings[0].contains("connect"), "{:?}", tree.warnings);
    assert!(tree.warnings[1].contains("tendon"), "{:?}", tree.warnings);
    let tree = mjcf::load_str(
        &body("<composite type=\"rope\" count=\"5 1 1\"/>"),
        "m.xml",
        Path::new("."),
    )
    .unwrap();
    assert_eq!(
        tree.warnings,
        ["line 4: <composite> read past (the soft body's generated bodies and joints are not in the tree)"]
    );
}

#[test]
fn free_floating_props_beside_the_robot_are_read_past_with_a_warning() {
    // Two free bodies (a legged robot and a ball, as dm_control's quadruped): the larger is the
    // floating root.
    let robot =
        "<body name=\"torso\"><freejoint/><body name=\"leg\"><joint name=\"hip\"/></body></body>";
    let ball = "<body name=\"ball\"><freejoint/></body>";
    let xml = format!("<mujoco><worldbody>{ball}{robot}</worldbody></mujoco>");
    let tree = mjcf::load_str(&xml, "m.xml", Path::new(".")).unwrap();
    assert!(tree.floating_root);
    assert_eq!(tree.links[tree.root], "torso");
    assert!(tree.link("ball").is_err());
    assert_eq!(tree.warnings.len(), 1, "{:?}", tree.warnings);
    assert!(
        tree.warnings[0].contains("top-level body ball read past"),
        "{:?}",
        tree.warnings
    );
    // A fixed-base arm beside a free box: the world is the root, the box a prop.
    let arm = "<body name=\"link1\"><joint name=\"j1\"/><body name=\"link2\"><joint name=\"j2\"/></body></body>";
    let xml = format!(
        "<mujoco><worldbody>{arm}<body name=\"box\"><freejoint/></body></worldbody></mujoco>"
    );
    let tree = mjcf::load_str(&xml, "m.xml", Path::new(".")).unwrap();
    assert!(!tree.floating_root);
    assert_eq!(tree.links[tree.root], "world");
    assert!(tree.link("link2").is_ok() && tree.link("box").is_err());
    assert!(
        tree.warnings[0].contains("beside the fixed-base mechanism"),
        "{:?}",
        tree.warnings
    );
}

#[test]
fn the_qpos_layout_counts_the_props_as_mujoco_does() {
    // MuJoCo's qpos: bodies depth first, each body's joints before its children; a free
    // joint 7 entries, a ball 4 (a type a class gives too), a hinge or slide 1.
    let xml = "<mujoco><default><default class=\"b\"><joint type=\"ball\"/></default></default>\
        <worldbody>\
        <body name=\"prop\"><freejoint/><frame><body name=\"swing\" childclass=\"b\"><joint name=\"s\"/></body></frame></body>\
        <body name=\"arm\"><joint name=\"a\"/><body name=\"fore\"><joint name=\"b\" type=\"slide\"/></body></body>\
        <frame><body name=\"arm2\"><joint name=\"c\"/></body></frame>\
        </worldbody></mujoco>";
    let tree = mjcf::load_str(xml, "m.xml", Path::new(".")).unwrap();
    let layout = tree.qpos_layout.as_ref().unwrap();
    assert_eq!(layout.len, 7 + 4 + 1 + 1 + 1);
    assert_eq!(layout.base, None);
    let want: Vec<(String, usize)> = vec![("a".into(), 11), ("b".into(), 12), ("c".into(), 13)];
    assert_eq!(layout.joints, want);
}

#[test]
fn the_text_kept_is_self_contained() {
    // Without includes the text is the file's own; with includes, every include spliced in
    // (attribute values escaped), and it reads to the same tree where the parts are gone.
    let text = std::fs::read_to_string(asset()).unwrap();
    let (tree, kept) = mjcf::read_str(&text, "m.xml", Path::new(".")).unwrap();
    assert_eq!(kept, text);
    let dir = std::env::temp_dir().join(format!("sk-mjcf-flat-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("parts")).unwrap();
    let (head, rest) = text.split_once("<worldbody>").unwrap();
    let head = head.replacen("<mujoco model=\"two_arm_constructs\">", "", 1);
    assert_ne!(
        head,
        text.split_once("<worldbody>").unwrap().0,
        "the model tag is as written"
    );
    std::fs::write(
        dir.join("parts/head.xml"),
        format!("<mujoco>{head}</mujoco>"),
    )
    .unwrap();
    let main = format!(
        "<mujoco model=\"two_arm_constructs\"><include file=\"parts/head.xml\"/><worldbody>{rest}"
    );
    let (from_parts, flat) = mjcf::read_str(&main, "main.xml", &dir).unwrap();
    assert!(!flat.contains("<include"), "{flat}");
    std::fs::remove_dir_all(&dir).unwrap();
    let again = mjcf::load_str(&flat, "flat.xml", &dir).unwrap();
    for t in [&from_parts, &again] {
        assert_eq!(t.links, tree.links);
        assert_eq!(t.joints, tree.joints);
        assert_eq!(t.inertials, tree.inertials);
    }
    let escaped =
        "<mujoco model=\"a &amp; &quot;b&quot; &lt;c&gt;\"><include file=\"x.xml\"/></mujoco>";
    let dir = std::env::temp_dir().join(format!("sk-mjcf-esc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("x.xml"), "<mujoco><worldbody/></mujoco>").unwrap();
    let (_, flat) = mjcf::read_str(escaped, "e.xml", &dir).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        mjcf::load_str(&flat, "f.xml", &dir).unwrap().name,
        "a & \"b\" <c>"
    );
}
