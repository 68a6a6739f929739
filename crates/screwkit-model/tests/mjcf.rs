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
        ("<robot name=\"x\"/>".to_string(), "the root element is not <mujoco>"),
        (body("<joint name=\"j\" type=\"spin\"/>"), "m.xml:4: <joint name=\"j\">: unknown joint type \"spin\""),
        (body("<joint name=\"j\" type=\"ball\"/>"), "ball joints"),
        (body("<replicate count=\"3\"><body name=\"r\"/></replicate>"), "m.xml:4: <replicate>: <replicate> (bodies MuJoCo generates when compiling) is not read"),
        (body("<attach model=\"arm\" prefix=\"a_\"/>"), "<attach>: <attach> (bodies MuJoCo generates"),
        (body("<joint name=\"j\" ref=\"x\"/>"), "ref=\"x\": not 1 numbers"),
        (body("<joint name=\"j\" range=\"1 2 3\"/>"), "range=\"1 2 3\": expected 2 numbers"),
        (body("<joint name=\"j\" limited=\"true\" range=\"10 -10\"/>"), "range [10, -10] is empty"),
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
            "m.xml:1: <include>: cannot read the included file \"/nonexistent/part.xml\"",
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

/// Issue 44, item 2: the nesting limit holds across includes. 16 files of 250 nested bodies,
/// each including the next inside its innermost body (4,000 levels), aborted the process on
/// a stack overflow; now one error naming the file and line.
#[test]
fn nesting_through_includes_is_bounded() {
    let dir = std::env::temp_dir().join(format!("sk-mjcf-nest-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (k, tag) in (0..16)
        .map(|k| (k, "body"))
        .chain((16..47).map(|k| (k, "frame")))
    {
        let mut t = String::from("<mujoco>");
        if k == 0 || k == 16 {
            t.push_str("<worldbody>");
        }
        for i in 0..250 {
            t.push_str(&format!("<{tag} name=\"{tag}{k}_{i}\">"));
        }
        if k != 15 && k != 46 {
            t.push_str(&format!("<include file=\"n{}.xml\"/>", k + 1));
        }
        for _ in 0..250 {
            t.push_str(&format!("</{tag}>"));
        }
        if k == 0 || k == 16 {
            t.push_str("</worldbody>");
        }
        t.push_str("</mujoco>");
        std::fs::write(dir.join(format!("n{k}.xml")), t).unwrap();
    }
    for first in ["n0.xml", "n16.xml"] {
        let e = mjcf::load_file(dir.join(first)).unwrap_err().to_string();
        assert!(e.contains("nested more than 256 levels deep"), "{e}");
        assert!(e.contains("n1.xml:1") || e.contains("n17.xml:1"), "{e}");
        assert_eq!(e.lines().count(), 1);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 44, item 4: one byte budget (64 MiB) for every file a model reads, summed over its
/// includes: a small file including a 3 MB file 40 times is refused before it is all read.
#[test]
fn includes_share_one_byte_budget() {
    let dir = std::env::temp_dir().join(format!("sk-mjcf-bytes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let big = format!("<mujoco><!--{}--></mujoco>", "x".repeat(3 << 20));
    std::fs::write(dir.join("big.xml"), big).unwrap();
    let mut main = String::from("<mujoco>");
    for _ in 0..40 {
        main.push_str("<include file=\"big.xml\"/>\n");
    }
    main.push_str("</mujoco>");
    std::fs::write(dir.join("main.xml"), main).unwrap();
    let e = mjcf::load_file(dir.join("main.xml"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("exceed 64 MiB"), "{e}");
    // The include that crosses the budget: the 22nd (22 × 3 MiB > 64 MiB), on line 22.
    assert!(e.contains("main.xml:22: <include>"), "{e}");
    // Errors about an included file say where, not what its attributes hold (item 22).
    std::fs::write(dir.join("bad.xml"), "<robot name=\"SECRET\"/>").unwrap();
    std::fs::write(
        dir.join("main2.xml"),
        "<mujoco><include file=\"bad.xml\"/></mujoco>",
    )
    .unwrap();
    let e = mjcf::load_file(dir.join("main2.xml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.xml") && e.contains("is not <mujoco>"),
        "{e}"
    );
    assert!(!e.contains("SECRET") && !e.contains("<robot"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 44, item 17: line numbers come from an index of line starts (each was searched from
/// the start of the file: 30,000 bodies took 43 s). 200,000 elements load, and every error
/// still names the right line.
#[test]
fn large_models_read_in_linear_time_with_right_lines() {
    let mut t = String::from("<mujoco>\n<worldbody>\n<body name=\"b\">\n<joint name=\"j\"/>\n");
    for i in 0..200_000 {
        t.push_str(&format!("<geom name=\"g{i}\" size=\"0.1\"/>\n"));
    }
    t.push_str("<joint name=\"k\" type=\"spin\"/>\n</body>\n</worldbody>\n</mujoco>\n");
    let e = mjcf::load_str(&t, "big.xml", Path::new("."))
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("big.xml:200005: <joint name=\"k\">"), "{e}");
}

/// Issue 44, item 3: a class inherits its parents' attributes without copying them. One 1 MiB
/// attribute under 10,000 child classes asked for 10 GB and aborted; it now loads, and the
/// classes still inherit (a joint of the last class takes the top class's axis and range).
#[test]
fn default_classes_share_what_they_inherit() {
    let mut t = format!(
        "<mujoco><compiler angle=\"radian\"/><default><joint axis=\"0 1 0\" range=\"-0.5 0.25\" user=\"{}\"/>",
        "1 ".repeat(1 << 19)
    );
    for i in 0..10_000 {
        t.push_str(&format!("<default class=\"c{i}\"/>"));
    }
    t.push_str("</default><worldbody><body name=\"b\"><joint name=\"j\" class=\"c9999\"/></body></worldbody></mujoco>");
    assert!(t.len() > 1 << 20);
    let tree = mjcf::load_str(&t, "m.xml", Path::new(".")).unwrap();
    let j = &tree.joints[0];
    assert_eq!(j.name, "j");
    assert_eq!(j.axis, [0.0, 1.0, 0.0]);
    let limit = j.limit.unwrap();
    assert_eq!((limit.lower, limit.upper), (-0.5, 0.25));
}

/// Issue 44, item 10: MuJoCo's semantics, checked against MuJoCo 4 by hand (`jnt_limited` and
/// its errors): `range="0 0"` (or any lower ≥ upper) with limited="auto" leaves a joint
/// unlimited, `limited="true"` on such a range is refused, `coordinate="global"` is refused,
/// elements of another XML namespace are refused, and `xyaxes` of 1e154 and more give the
/// right rotation.
#[test]
fn mujoco_semantics_of_ranges_coordinates_namespaces_and_huge_axes() {
    for range in ["0 0", "0.5 0.5", "1 -1"] {
        let tree = mjcf::load_str(
            &body(&format!("<joint name=\"j\" range=\"{range}\"/>")),
            "m.xml",
            Path::new("."),
        )
        .unwrap();
        let j = &tree.joints[0];
        assert_eq!(j.kind, JointKind::Continuous, "{range}: unlimited");
        assert!(j.limit.is_none(), "{range}");
        let e = error_of(&body(&format!(
            "<joint name=\"j\" limited=\"true\" range=\"{range}\"/>"
        )));
        assert!(
            e.contains("is empty (a limited joint needs lower < upper)"),
            "{e}"
        );
    }
    let e = error_of("<mujoco><compiler coordinate=\"global\"/><worldbody/></mujoco>");
    assert!(e.contains("coordinate=\"global\" is not read"), "{e}");
    assert!(mjcf::load_str(
        "<mujoco><compiler coordinate=\"local\"/><worldbody/></mujoco>",
        "m.xml",
        Path::new(".")
    )
    .is_ok());
    let e = error_of(
        "<mujoco xmlns:u=\"http://example.com/u\"><worldbody><u:body name=\"b\"><joint name=\"j\"/></u:body></worldbody></mujoco>",
    );
    assert!(
        e.contains("m.xml:1: <body> is an element of another XML namespace"),
        "{e}"
    );
    // xyaxes scaled by 1e154 and 1e300: the same frame as unscaled.
    let site = |xy: &str| {
        let tree = mjcf::load_str(
            &body(&format!(
                "<joint name=\"j\"/><site name=\"s\" xyaxes=\"{xy}\"/>"
            )),
            "m.xml",
            Path::new("."),
        )
        .unwrap();
        let k = tree
            .joints
            .iter()
            .position(|j| tree.links[j.child] == "s")
            .unwrap();
        tree.joints[k].origin_rpy
    };
    let want = site("0 1 0 -1 0 0");
    for scale in ["1e154", "1e300"] {
        let got = site(&format!("0 {scale} 0 -{scale} 0 0"));
        for k in 0..3 {
            assert!(
                (got[k] - want[k]).abs() < 1e-12,
                "{scale}: {got:?} vs {want:?}"
            );
        }
    }
    assert!(
        (want[2] - std::f64::consts::FRAC_PI_2).abs() < 1e-12,
        "{want:?}"
    );
}

/// MuJoCo takes a body's mass from its geoms (inertiafromgeom "auto" without `<inertial>`, or
/// "true"): screwkit weighs its solid primitives the same way (density 1000, or the geom's
/// `mass`; MuJoCo itself is the oracle in the Python suite); a body with a geom it cannot weigh
/// (a mesh) is named in a warning and left massless, never guessed.
#[test]
fn masses_from_geoms_are_weighed() {
    let model = |compiler: &str, inner: &str| {
        format!("<mujoco>{compiler}<worldbody><body name=\"b\"><joint name=\"j\"/>{inner}</body></worldbody></mujoco>")
    };
    let load = |xml: String| mjcf::load_str(&xml, "m.xml", Path::new(".")).unwrap();
    let warned = |xml: String| {
        load(xml)
            .warnings
            .iter()
            .any(|w| w.contains("inertiafromgeom"))
    };
    let mass = |xml: String| {
        let tree = load(xml);
        let b = tree.link("b").unwrap();
        tree.inertials[b].map(|i| (i.mass, i.com, i.inertia))
    };
    let geom = "<geom size=\"0.1\"/>";
    let inertial = "<inertial pos=\"0 0 0\" mass=\"1\" diaginertia=\"0.1 0.2 0.3\"/>";
    // A sphere of radius 0.1 at density 1000: m = 4/3 π r³ ρ, I = 2/5 m r².
    let m = 4.0 / 3.0 * std::f64::consts::PI * 1e-3 * 1000.0;
    let (got, com, i) = mass(model("", geom)).unwrap();
    assert!((got - m).abs() < 1e-12 && com == [0.0; 3]);
    assert!((i[0] - 0.4 * m * 0.01).abs() < 1e-15 && i[1] == 0.0 && (i[5] - i[0]).abs() < 1e-18);
    // In a frame 1 m up: the centre moves, the moments about it do not.
    let (_, com, _) = mass(model("", &format!("<frame pos=\"0 0 1\">{geom}</frame>"))).unwrap();
    assert!((com[2] - 1.0).abs() < 1e-15, "{com:?}");
    // `mass` on the geom wins over density.
    let (got, _, _) = mass(model("", "<geom size=\"0.1\" mass=\"2.5\"/>")).unwrap();
    assert_eq!(got, 2.5);
    // "auto" keeps an <inertial>; "true" weighs the geoms over it; "false" keeps it.
    assert_eq!(
        mass(model("", &format!("{geom}{inertial}"))).unwrap().0,
        1.0
    );
    let (got, _, _) = mass(model(
        "<compiler inertiafromgeom=\"true\"/>",
        &format!("{geom}{inertial}"),
    ))
    .unwrap();
    assert!((got - m).abs() < 1e-12);
    assert!(mass(model("<compiler inertiafromgeom=\"false\"/>", geom)).is_none());
    for xml in [
        model("", geom),
        model("", ""),
        model("", &format!("{geom}{inertial}")),
    ] {
        assert!(!warned(xml));
    }
    // A mesh geom: not weighed, the body named, massless.
    let mesh = r#"<asset><mesh name="m" vertex="0 0 0 1 0 0 0 1 0 0 0 1"/></asset>"#;
    let xml = format!(
        "<mujoco>{mesh}<worldbody><body name=\"b\"><joint name=\"j\"/>{geom}<geom type=\"mesh\" mesh=\"m\"/></body></worldbody></mujoco>"
    );
    assert!(warned(xml.clone()));
    assert!(mass(xml).is_none());
}

/// Issue 44, item 21: names screwkit makes (`b_weld`, `s_site`, `a/j`, `c_joint0`) never take
/// one the file gives (a valid model was refused with a joint it does not have); `name=""` is
/// no name, as in MuJoCo; a free root whose type comes from its childclass is the floating
/// base.
#[test]
fn made_names_never_collide_with_the_files_own() {
    let xml = r#"<mujoco><worldbody>
      <body name="b"><geom size="0.1"/></body>
      <body name="a" pos="1 0 0"><joint name="j" pos="0 0 0.1"/>
        <body name="a/j" pos="0 0 1"><joint name="b_weld"/></body>
        <site name="s"/>
      </body>
      <body name="c" pos="2 0 0"><joint/><joint name="s_site" axis="1 0 0"/>
        <body name="c_joint0"><joint name="k"/></body>
      </body>
      <body name="" pos="3 0 0"><joint name="e"/></body>
    </worldbody></mujoco>"#;
    let tree = mjcf::load_str(xml, "m.xml", Path::new(".")).unwrap();
    let names: Vec<&str> = tree.joints.iter().map(|j| j.name.as_str()).collect();
    // The file's own names, each once, as the file gives them.
    for own in ["j", "b_weld", "s_site", "k", "e"] {
        assert_eq!(
            names.iter().filter(|n| **n == own).count(),
            1,
            "{own}: {names:?}"
        );
    }
    for own in ["b", "a", "a/j", "c", "c_joint0", "s"] {
        assert_eq!(
            tree.links.iter().filter(|l| *l == own).count(),
            1,
            "{own}: {:?}",
            tree.links
        );
    }
    // Made names took a suffix where the file had them.
    assert!(names.contains(&"b_weld~1"), "{names:?}");
    assert!(names.contains(&"s_site~1"), "{names:?}");
    assert!(tree.links.iter().any(|l| l == "a/j~1"), "{:?}", tree.links);
    assert!(names.contains(&"c_joint0"), "{names:?}"); // joints and links are apart
    assert!(!tree.links.iter().any(|l| l.is_empty()), "{:?}", tree.links);
    // A free joint given by the body's childclass.
    let xml = r#"<mujoco><default><default class="free"><joint type="free"/></default></default>
      <worldbody><body name="base" childclass="free" pos="0 0 1"><joint name="root"/>
        <body name="arm"><joint name="h" type="hinge"/></body></body></worldbody></mujoco>"#;
    let tree = mjcf::load_str(xml, "m.xml", Path::new(".")).unwrap();
    assert!(tree.floating_root);
    assert_eq!(
        tree.joints
            .iter()
            .filter(|j| j.kind != JointKind::Fixed)
            .count(),
        1
    );
}

/// Review of issue 44: the nesting limit across includes is the parser's own (255 element
/// levels), so a model accepted through includes is also accepted as its spliced text (what
/// a pickled robot reloads); repeated site names are refused as MuJoCo does (making `~k`
/// names for them was quadratic).
#[test]
fn the_limit_across_includes_is_the_parsers_and_sites_are_unique() {
    let dir = std::env::temp_dir().join(format!("sk-mjcf-edge-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let main = "<mujoco><worldbody><include file=\"deep.xml\"/></worldbody></mujoco>";
    for (k, ok) in [(253, true), (254, false)] {
        let body = format!(
            "<mujoco>{}{}</mujoco>",
            (0..k)
                .map(|i| format!("<body name=\"b{i}\">"))
                .collect::<String>(),
            "</body>".repeat(k)
        );
        std::fs::write(dir.join("deep.xml"), body).unwrap();
        let r = mjcf::read_str(main, "m.xml", &dir);
        assert_eq!(r.is_ok(), ok, "{k}: {:?}", r.as_ref().err());
        if let Ok((_, text)) = r {
            assert!(mjcf::load_str(&text, "spliced.xml", &dir).is_ok(), "{k}");
        }
    }
    let e = error_of(&body("<site name=\"s\"/><site name=\"s\"/>"));
    assert!(
        e.contains("m.xml:4: <site name=\"s\">: this site name is given twice"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
