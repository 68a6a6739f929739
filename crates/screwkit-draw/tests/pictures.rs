//! The SVG drawing and the HTML page: valid XML, deterministic, every joint, axis, link and
//! frame findable with its title, and the geometry where an independent closed form says it
//! must be.

use std::collections::HashSet;

use screwkit_draw::{html, svg, Scene, View};
use screwkit_model::{load_chain, Chain};
use screwkit_service::words::Word;
use screwkit_solve::Kinematics;
use screwkit_testkit::{bundled, Sampler, BUNDLED_CHAINS as CHAINS};

fn load(file: &str, base: Option<&str>, tip: Option<&str>) -> (Chain, Kinematics) {
    let chain = load_chain(bundled(file), base, tip).unwrap();
    let kin = Kinematics::new(&chain);
    (chain, kin)
}

/// The `<g>` with this id, or a panic naming it.
fn group<'a>(doc: &'a roxmltree::Document, id: &str) -> roxmltree::Node<'a, 'a> {
    doc.descendants()
        .find(|n| n.attribute("id") == Some(id))
        .unwrap_or_else(|| panic!("no element with id {id}"))
}

fn title(node: roxmltree::Node) -> String {
    node.children()
        .find(|c| c.has_tag_name("title"))
        .and_then(|t| t.text())
        .unwrap_or_default()
        .to_string()
}

/// A number attribute.
fn num(n: roxmltree::Node, a: &str) -> f64 {
    n.attribute(a)
        .unwrap_or_else(|| panic!("no {a}"))
        .parse()
        .unwrap()
}

/// The boxes of view `v`'s labels (x0, y0, x1, y1): from the baseline's start, as wide as
/// `svg::text_width` says (an upper bound on a browser's, held by the browser test), from
/// 0.95 em above the baseline to 0.25 em below.
fn label_boxes(doc: &roxmltree::Document, v: &str) -> Vec<(String, [f64; 4])> {
    group(doc, &format!("{v}-labels"))
        .children()
        .filter(|n| n.has_tag_name("text") && n.attribute("id").is_some())
        .map(|n| {
            let (x, y, f) = (num(n, "x"), num(n, "y"), num(n, "font-size"));
            let w = svg::text_width(n.text().unwrap_or_default(), f);
            (
                n.attribute("id").unwrap().to_string(),
                [x, y - 0.95 * f, x + w, y + 0.25 * f],
            )
        })
        .collect()
}

/// No two labels of view `v` overlap, and each lies inside its panel.
fn assert_labels_apart(doc: &roxmltree::Document, v: &str) -> usize {
    let panel = group(doc, v)
        .children()
        .find(|n| n.has_tag_name("rect"))
        .unwrap();
    let (x0, y0) = (num(panel, "x"), num(panel, "y"));
    let (x1, y1) = (x0 + num(panel, "width"), y0 + num(panel, "height"));
    let boxes = label_boxes(doc, v);
    for (k, (a, p)) in boxes.iter().enumerate() {
        assert!(
            p[0] >= x0 && p[1] >= y0 && p[2] <= x1 && p[3] <= y1,
            "{a} leaves the panel"
        );
        for (b, q) in &boxes[k + 1..] {
            let apart = p[2] <= q[0] || q[2] <= p[0] || p[3] <= q[1] || q[3] <= p[1];
            assert!(apart, "{a} {p:?} overlaps {b} {q:?}");
        }
    }
    boxes.len()
}

#[test]
fn every_chain_every_view_is_valid_findable_and_deterministic() {
    let mut rng = Sampler::new(3);
    for &(file, base, tip) in CHAINS {
        let (chain, kin) = load(file, base, tip);
        let q = rng.config(&kin);
        let scene = Scene::new(&chain, &kin, Some(&q)).unwrap();
        let text = svg::render(&scene, View::ALL);
        assert_eq!(
            text,
            svg::render(&Scene::new(&chain, &kin, Some(&q)).unwrap(), View::ALL)
        );
        let doc = roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{file}: {e}"));
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        assert_eq!(
            root.tag_name().namespace(),
            Some("http://www.w3.org/2000/svg")
        );
        assert_eq!(root.attribute("version"), Some("1.1"));
        // Only SVG 1.1 elements, and unique ids.
        let allowed = [
            "svg", "title", "desc", "g", "rect", "line", "circle", "text", "polygon",
        ];
        let mut ids = HashSet::new();
        for n in doc.descendants().filter(|n| n.is_element()) {
            assert!(
                allowed.contains(&n.tag_name().name()),
                "{file}: <{}>",
                n.tag_name().name()
            );
            if let Some(id) = n.attribute("id") {
                assert!(ids.insert(id.to_string()), "{file}: duplicate id {id}");
            }
        }
        for &view in View::ALL {
            let v = view.as_str();
            for (j, joint) in chain.joints.iter().enumerate() {
                for what in ["joint", "axis"] {
                    let g = group(&doc, &format!("{v}-{what}-{}", j + 1));
                    assert_eq!(g.attribute("data-joint"), Some(joint.name.as_str()));
                    let t = title(g);
                    assert!(
                        t.contains(&joint.name) && t.contains("S(q) = (ω | v)"),
                        "{t}"
                    );
                }
            }
            for link in chain.links.iter().skip(1) {
                let id = format!("{v}-link-{}", link.name);
                assert!(title(group(&doc, &id)).contains(&link.name));
            }
            for f in ["base", "tip"] {
                assert!(title(group(&doc, &format!("{v}-{f}-frame"))).contains(f));
            }
        }
        assert!(doc
            .descendants()
            .any(|n| n.attribute("id") == Some("legend")));
        // The caption names the chain and q.
        assert!(title(root).contains(&format!("{} → {}", chain.base, chain.tip)));
    }
}

/// The screw axes in the titles are the columns of the space Jacobian at q (one per joint
/// without mimic joints), printed to 6 decimals.
#[test]
fn titles_carry_the_space_jacobian_columns() {
    let (chain, kin) = load("ur5.urdf", None, None);
    let q = [0.3, -1.0, 1.4, -0.8, -1.2, 0.4];
    let js = screwkit_solve::jacobian::jacobian(
        &kin,
        &mut screwkit_solve::Workspace::new(&kin),
        &q,
        screwkit_solve::Frame::Space,
    )
    .unwrap()
    .clone();
    let text = svg::render(&Scene::new(&chain, &kin, Some(&q)).unwrap(), &[View::Iso]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    for k in 0..6 {
        let t = title(group(&doc, &format!("iso-axis-{}", k + 1)));
        let c = js.column(k);
        let f = |x: f64| format!("{:.6}", if x.abs() < 5e-7 { 0.0 } else { x });
        let want = format!(
            "({}, {}, {}) | ({}, {}, {})",
            f(c[0]),
            f(c[1]),
            f(c[2]),
            f(c[3]),
            f(c[4]),
            f(c[5])
        );
        assert!(t.contains(&want), "{t} vs {want}");
    }
}

/// The planar 3R arm from above: the joint marks sit where the closed form puts the joints,
/// (0, 0), L1 (cos q1, sin q1), + L2 (cos(q1 + q2), sin(q1 + q2)), under one scale and offset;
/// the three axes point at the viewer (rings).
#[test]
fn planar_arm_from_above_matches_the_closed_form() {
    let (chain, kin) = load("planar_3r.urdf", None, None);
    let q = [0.4, 0.6, -0.9];
    let text = svg::render(&Scene::new(&chain, &kin, Some(&q)).unwrap(), &[View::Top]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let centre = |i: usize| {
        let c = group(&doc, &format!("top-joint-{i}"))
            .children()
            .find(|n| n.has_tag_name("circle"))
            .unwrap();
        let num = |a| c.attribute(a).unwrap().parse::<f64>().unwrap();
        (num("cx"), num("cy"))
    };
    let (l1, l2) = (1.0, 0.8);
    let world = [
        (0.0, 0.0),
        (l1 * q[0].cos(), l1 * q[0].sin()),
        (
            l1 * q[0].cos() + l2 * (q[0] + q[1]).cos(),
            l1 * q[0].sin() + l2 * (q[0] + q[1]).sin(),
        ),
    ];
    let (p0, p1) = (centre(1), centre(2));
    let scale = (p1.0 - p0.0) / world[1].0;
    for (i, w) in world.iter().enumerate() {
        let p = centre(i + 1);
        assert!(
            (p.0 - (p0.0 + scale * w.0)).abs() < 0.02,
            "joint {}: x",
            i + 1
        );
        assert!(
            (p.1 - (p0.1 - scale * w.1)).abs() < 0.02,
            "joint {}: y",
            i + 1
        );
    }
    for i in 1..=3 {
        let axis = group(&doc, &format!("top-axis-{i}"));
        assert!(
            axis.children().any(|n| n.has_tag_name("circle")),
            "axis {i} end-on"
        );
    }
}

#[test]
fn the_page_embeds_the_chain_and_runs_offline() {
    for &(file, base, tip) in CHAINS {
        let (chain, kin) = load(file, base, tip);
        let page = html::page(&chain, &kin, None).unwrap();
        assert!(page.starts_with("<!DOCTYPE html>"));
        // Nothing fetched: no address but the XHTML namespace three.js creates its canvas in
        // (and three.js's home in its licence comment).
        let addresses = page
            .replace("http://www.w3.org/1999/xhtml", "")
            .replace("https://threejs.org", "");
        assert!(
            !addresses.contains("http://") && !addresses.contains("https://"),
            "{file}: a URL"
        );
        assert!(
            !page.contains(" src=\"") && !page.contains("fetch("),
            "{file}: a load"
        );
        // three.js and its licence are inlined.
        assert!(page.contains("Copyright © 2010-2026 three.js authors"));
        assert!(page.contains("WebGLRenderer"));
        let start = page.find("id=\"model\">").unwrap() + "id=\"model\">".len();
        let end = start + page[start..].find("</script>").unwrap();
        let model: serde_json::Value = serde_json::from_str(&page[start..end]).unwrap();
        assert_eq!(
            model["joints"].as_array().unwrap().len(),
            chain.joints.len()
        );
        assert_eq!(model["variables"].as_array().unwrap().len(), kin.dof());
        assert_eq!(model["links"].as_array().unwrap().len(), chain.links.len());
        for (j, joint) in chain.joints.iter().enumerate() {
            let s: Vec<f64> = serde_json::from_value(model["joints"][j]["S"].clone()).unwrap();
            assert_eq!(s.as_slice(), joint.s_space.twist().to_vector().as_slice());
        }
    }
    let (chain, kin) = load("ur5.urdf", None, None);
    assert!(html::page(&chain, &kin, Some(&[0.0; 5])).is_err());
}

/// A 2 mm gripper-scale arm and a 6 m arm both fill their panel: every mark inside it, and the
/// drawing spans most of it.
#[test]
fn any_size_is_fitted_to_the_page() {
    for scale in [1e-3, 3.0] {
        let urdf = format!(
            r#"<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
            <joint name="j1" type="revolute"><parent link="a"/><child link="b"/>
              <origin xyz="0 0 {s}"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
            <joint name="j2" type="revolute"><parent link="b"/><child link="c"/>
              <origin xyz="{s} 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
            </robot>"#,
            s = 2.0 * scale
        );
        let tree = screwkit_model::urdf::load_str(&urdf, "sized.urdf").unwrap();
        let chain = Chain::from_tree(&tree, None, None).unwrap();
        let kin = Kinematics::new(&chain);
        let text = svg::render(
            &Scene::new(&chain, &kin, Some(&[0.3, 0.5])).unwrap(),
            &[View::Side],
        );
        let doc = roxmltree::Document::parse(&text).unwrap();
        let panel = group(&doc, "side")
            .children()
            .find(|n| n.has_tag_name("rect"))
            .unwrap();
        let (x0, y0) = (num(panel, "x"), num(panel, "y"));
        let (x1, y1) = (x0 + num(panel, "width"), y0 + num(panel, "height"));
        let mut xs = Vec::new();
        for n in doc.descendants().filter(|n| n.has_tag_name("line")) {
            if n.ancestors().any(|a| a.attribute("id") == Some("legend")) {
                continue;
            }
            for (ax, ay) in [("x1", "y1"), ("x2", "y2")] {
                let (x, y) = (num(n, ax), num(n, ay));
                assert!(
                    x0 <= x && x <= x1 && y0 <= y && y <= y1,
                    "scale {scale}: ({x}, {y})"
                );
                xs.push(x);
            }
        }
        let span = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - xs.iter().cloned().fold(f64::INFINITY, f64::min);
        assert!(
            span > 0.5 * (x1 - x0),
            "scale {scale}: the drawing spans {span} px"
        );
        assert!(text.contains(if scale < 1.0 {
            " mm</text>"
        } else {
            " m</text>"
        }));
    }
}

/// A single view is 580 px wide: a 7-joint caption wraps onto a second line (it was cut at
/// the sheet's edge) and the panel moves down to make room; every line fits the width.
#[test]
fn long_captions_wrap_within_the_sheet() {
    let (chain, kin) = load("panda.urdf", None, None);
    let q = [0.2, -0.4, 0.1, -2.0, 0.1, 1.8, 0.6];
    let scene = Scene::new(&chain, &kin, Some(&q)).unwrap();
    let text = svg::render(&scene, &[View::Iso]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let width: f64 = doc
        .root_element()
        .attribute("width")
        .unwrap()
        .parse()
        .unwrap();
    let caption: Vec<roxmltree::Node> = doc
        .root_element()
        .children()
        .filter(|n| n.has_tag_name("text"))
        .collect();
    assert_eq!(caption.len(), 2, "{text}");
    let joined: Vec<&str> = caption.iter().filter_map(|n| n.text()).collect();
    assert_eq!(
        joined.join(" "),
        "panda: chain panda_link0 → panda_hand_tcp, q = [0.200000, -0.400000, 0.100000, -2.000000, 0.100000, 1.800000, 0.600000]"
    );
    for l in &joined {
        // 8 px per character at 15 px is wider than Helvetica's widest digits and letters.
        assert!(10.0 + 8.0 * l.chars().count() as f64 <= width, "{l}");
    }
    let panel = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("iso"))
        .unwrap();
    let rect = panel.children().find(|n| n.has_tag_name("rect")).unwrap();
    assert_eq!(rect.attribute("y"), Some("56.00"));
}

/// The page starts at each joint's 0, or at the limit nearest 0 when 0 is outside the
/// limits (the Panda's joint 4: [−3.07, −0.07]).
#[test]
fn the_page_starts_within_the_limits() {
    let (chain, kin) = load("panda.urdf", None, None);
    let page = html::page(&chain, &kin, None).unwrap();
    let start = page.find("\"q\":[").expect("the page's q") + 5;
    let end = start + page[start..].find(']').unwrap();
    let q: Vec<f64> = page[start..end]
        .split(',')
        .map(|x| x.parse().unwrap())
        .collect();
    assert_eq!(q.len(), 7);
    assert!(kin.within_limits(&q, 0.0), "{q:?}");
    assert_eq!(q[3], kin.upper()[3]);
    assert_eq!(q[0], 0.0);
}

/// A whole tree (the two-armed torso: three branches): every link's segment from its parent
/// with its origin from the file composed joint by joint, every joint and axis, every leaf's
/// triad with its name written, no two names on top of each other, and the page with the tree
/// embedded (leaves as frames, the floating base's seven values first).
#[test]
fn a_whole_tree_draws_every_branch_and_names_its_leaves() {
    use screwkit_model::{urdf, KinematicTree};
    use screwkit_solve::tree::configuration;
    use screwkit_solve::{sample::SplitMix64, TreeKinematics};
    use screwkit_testkit::reference::{tree_fk_by_composition, tree_joint_positions};
    let tree = urdf::load_file(bundled("torso_two_arms.urdf")).unwrap();
    let model = KinematicTree::from_tree(&tree).unwrap();
    let kin = TreeKinematics::new(&model).unwrap();
    let mut rng = SplitMix64(9);
    let q = configuration::random(&kin, &mut rng);
    let names: Vec<String> = model.variables.iter().map(|v| v.name.clone()).collect();
    let positions = tree_joint_positions(&tree, &names, &q);
    let want = tree_fk_by_composition(&tree, &|j| positions[j]);
    let scene = Scene::tree(&kin, Some(&q)).unwrap();
    assert_eq!(scene.links.len(), model.links.len());
    assert_eq!(scene.joints.len(), model.joints.len());
    let text = svg::render(&scene, View::ALL);
    assert_eq!(
        text,
        svg::render(&Scene::tree(&kin, Some(&q)).unwrap(), View::ALL)
    );
    let doc = roxmltree::Document::parse(&text).unwrap();
    let mut ids = HashSet::new();
    for id in doc.descendants().filter_map(|n| n.attribute("id")) {
        assert!(ids.insert(id), "duplicate id {id}");
    }
    assert!(
        title(doc.root_element()).contains("whole tree from pelvis, 11 links, 7 joints, 3 leaves")
    );
    for &view in View::ALL {
        let v = view.as_str();
        for (l, link) in model.links.iter().enumerate() {
            if link.parent.is_none() {
                continue;
            }
            let p = want[l];
            let origin = format!(
                "origin ({:.6}, {:.6}, {:.6})",
                p[(0, 3)],
                p[(1, 3)],
                p[(2, 3)]
            );
            let t = title(group(&doc, &format!("{v}-link-{}", link.name)));
            assert!(t.contains(&origin), "{t} vs {origin}");
        }
        for (k, j) in model.joints.iter().enumerate() {
            for what in ["joint", "axis"] {
                let g = group(&doc, &format!("{v}-{what}-{}", k + 1));
                assert_eq!(g.attribute("data-joint"), Some(j.name.as_str()));
            }
        }
        for leaf in ["head", "left_hand", "right_hand"] {
            let g = group(&doc, &format!("{v}-leaf-{leaf}"));
            assert!(title(g).contains(&format!("leaf frame: link {leaf}")));
            let label = group(&doc, &format!("{v}-label-{leaf}"));
            assert_eq!(label.text(), Some(leaf));
        }
        assert_labels_apart(&doc, v);
        assert!(group(&doc, &format!("{v}-base-frame")).has_tag_name("g"));
    }
    for floating in [false, true] {
        let kin = TreeKinematics::new(&model.clone().with_floating_base(floating)).unwrap();
        let page = html::tree_page(&kin, None).unwrap();
        let start = page.find("id=\"model\">").unwrap() + "id=\"model\">".len();
        let end = start + page[start..].find("</script>").unwrap();
        let json: serde_json::Value = serde_json::from_str(&page[start..end]).unwrap();
        let frames: Vec<&str> = json["frames"]
            .as_array()
            .unwrap()
            .iter()
            .map(|f| f["name"].as_str().unwrap())
            .collect();
        assert_eq!(frames, ["head", "left_hand", "right_hand"]);
        assert_eq!(json["joints"].as_array().unwrap().len(), 7);
        let vars = json["variables"].as_array().unwrap();
        assert_eq!(vars.len(), if floating { 14 } else { 7 });
        assert_eq!(
            vars[0]["name"],
            if floating { "floating_base.x" } else { "waist" }
        );
        assert_eq!(json["q"].as_array().unwrap().len(), kin.nq());
        assert!(html::tree_page(&kin, Some(&[0.0; 3])).is_err());
    }
}

/// The page's body: every visual and collision shape of the drawn links with its link,
/// origin, dimensions and colour; a mesh embedded once however many shapes use it, its
/// vertices (float32) and triangles (uint32) decoding to the file's; a mesh that cannot be
/// read named in `problems`, the page made all the same.
#[test]
fn the_page_embeds_the_body() {
    let dir = std::env::temp_dir().join(format!("screwkit-draw-body-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("tet.stl"),
        "solid t\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n vertex 0 1 0\n endloop\n endfacet\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 0 1 0\n vertex 0 0 1\n endloop\n endfacet\nendsolid t\n",
    )
    .unwrap();
    let urdf = r#"<robot name="r">
      <material name="red"><color rgba="1 0 0 1"/></material>
      <link name="a"><visual><origin xyz="0 0 0.1"/><geometry><box size="0.1 0.2 0.3"/></geometry><material name="red"/></visual>
        <collision><geometry><cylinder radius="0.05" length="0.2"/></geometry></collision></link>
      <link name="b"><visual><geometry><mesh filename="tet.stl" scale="2 2 2"/></geometry></visual>
        <collision><geometry><mesh filename="tet.stl" scale="2 2 2"/></geometry></collision>
        <visual><geometry><mesh filename="missing.stl"/></geometry></visual></link>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 0.5"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#;
    let path = dir.join("r.urdf");
    std::fs::write(&path, urdf).unwrap();
    let tree = screwkit_model::load_tree(&path, &Default::default()).unwrap();
    let chain = screwkit_model::load_chain(&path, None, None).unwrap();
    let kin = screwkit_solve::Kinematics::new(&chain);
    let page = html::page_with_body(&chain, &kin, None, Some(&tree), &Default::default()).unwrap();
    let start = page.find("id=\"model\">").unwrap() + "id=\"model\">".len();
    let end = start + page[start..].find("</script>").unwrap();
    let model: serde_json::Value = serde_json::from_str(&page[start..end]).unwrap();
    let body = &model["body"];
    let shapes = body["shapes"].as_array().unwrap();
    let link = |name: &str| {
        model["links"]
            .as_array()
            .unwrap()
            .iter()
            .position(|l| l["name"] == name)
            .unwrap()
    };
    let kinds: Vec<(&str, &str, usize)> = shapes
        .iter()
        .map(|s| {
            (
                s["kind"].as_str().unwrap(),
                s["role"].as_str().unwrap(),
                s["link"].as_u64().unwrap() as usize,
            )
        })
        .collect();
    let mut sorted = kinds.clone();
    sorted.sort();
    assert_eq!(
        sorted,
        [
            ("box", "visual", link("a")),
            ("cylinder", "collision", link("a")),
            ("mesh", "collision", link("b")),
            ("mesh", "visual", link("b")),
        ]
    );
    let of = |kind: &str, role: &str| {
        &shapes[kinds
            .iter()
            .position(|k| k.0 == kind && k.1 == role)
            .unwrap()]
    };
    let bx = of("box", "visual");
    assert_eq!(bx["size"], serde_json::json!([0.1, 0.2, 0.3]));
    assert_eq!(bx["rgba"], serde_json::json!([1.0, 0.0, 0.0, 1.0]));
    assert_eq!(bx["origin"][11], 0.1);
    assert_eq!(of("cylinder", "collision")["radius"], 0.05);
    // One mesh for both shapes of the same file and scale.
    assert_eq!(of("mesh", "visual")["mesh"], 0);
    assert_eq!(of("mesh", "collision")["mesh"], 0);
    let meshes = body["meshes"].as_array().unwrap();
    assert_eq!(meshes.len(), 1);
    let decode = |b64: &str| -> Vec<u8> {
        let abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        let mut bits = 0u32;
        let mut n = 0;
        let mut out = Vec::new();
        for c in b64.chars().filter(|&c| c != '=') {
            bits = bits << 6 | abc.find(c).unwrap() as u32;
            n += 6;
            if n >= 8 {
                n -= 8;
                out.push((bits >> n) as u8);
            }
        }
        out
    };
    let v: Vec<f32> = decode(meshes[0]["positions"].as_str().unwrap())
        .chunks(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let t: Vec<u32> = decode(meshes[0]["indices"].as_str().unwrap())
        .chunks(4)
        .map(|b| u32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    let file = screwkit_model::mesh::read_mesh(&dir.join("tet.stl"), [2.0; 3]).unwrap();
    // The same triangles, corner by corner (the vertices welded and reordered).
    let corners: Vec<[f32; 3]> = t
        .iter()
        .map(|&i| {
            [
                v[3 * i as usize],
                v[3 * i as usize + 1],
                v[3 * i as usize + 2],
            ]
        })
        .collect();
    let want: Vec<[f32; 3]> = file
        .triangles
        .iter()
        .flatten()
        .map(|&i| file.vertices[i as usize].map(|x| x as f32))
        .collect();
    assert!(want.iter().any(|p| p.contains(&2.0)), "scaled");
    assert_eq!(corners, want);
    assert_eq!(v.len(), 3 * 4, "welded: a tetrahedron's 4 corners");
    assert_eq!(meshes[0]["triangles"], 2);
    // Obstacles stand in the world (no link).
    let table = screwkit_service::body::Obstacle {
        name: "table".into(),
        shape: screwkit_model::geometry::Shape::Box {
            size: [1.0, 2.0, 0.05],
        },
        pose: screwkit_lie::Se3::from_parts_unchecked(
            nalgebra::Matrix3::identity(),
            nalgebra::Vector3::new(0.5, 0.0, 0.2),
        ),
    };
    let options = html::PageOptions {
        obstacles: std::slice::from_ref(&table),
        ..Default::default()
    };
    let with = html::page_with_body(&chain, &kin, None, Some(&tree), &options).unwrap();
    let start = with.find("id=\"model\">").unwrap() + "id=\"model\">".len();
    let end = start + with[start..].find("</script>").unwrap();
    let m: serde_json::Value = serde_json::from_str(&with[start..end]).unwrap();
    let last = m["body"]["shapes"]
        .as_array()
        .unwrap()
        .last()
        .unwrap()
        .clone();
    assert_eq!(last["role"], "obstacle");
    assert!(last["link"].is_null());
    assert_eq!(last["size"], serde_json::json!([1.0, 2.0, 0.05]));
    assert_eq!(last["origin"][3], 0.5);
    let problems = body["problems"].as_array().unwrap();
    assert!(
        problems
            .iter()
            .any(|p| p.as_str().unwrap().contains("missing.stl")),
        "{problems:?}"
    );
    let _ = std::fs::remove_dir_all(dir);
}

/// A fine mesh (a sphere of 20,000 triangles) is drawn with about `MESH_TRIANGLES`, its
/// vertices still on the sphere (to 1 % of its radius) and its extent kept; a coarse one is
/// drawn as it is.
#[test]
fn fine_meshes_are_decimated() {
    let (rings, segments) = (100, 100);
    let mut vertices = Vec::new();
    for i in 0..=rings {
        let th = std::f64::consts::PI * i as f64 / rings as f64;
        for j in 0..segments {
            let ph = 2.0 * std::f64::consts::PI * j as f64 / segments as f64;
            vertices.push([th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()]);
        }
    }
    let mut triangles = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let a = (i * segments + j) as u32;
            let b = (i * segments + (j + 1) % segments) as u32;
            let (c, d) = (a + segments as u32, b + segments as u32);
            triangles.push([a, c, b]);
            triangles.push([b, c, d]);
        }
    }
    assert_eq!(triangles.len(), 20_000);
    let (points, indices) = html::decimate(&vertices, &triangles);
    let n = indices.len() / 3;
    assert!(
        (html::MESH_TRIANGLES / 2..=html::MESH_TRIANGLES * 11 / 10).contains(&n),
        "{n} triangles"
    );
    for p in &points {
        let r = p.iter().map(|x| f64::from(*x).powi(2)).sum::<f64>().sqrt();
        assert!((r - 1.0).abs() < 0.01, "a vertex off the sphere: {r}");
    }
    let top = points.iter().map(|p| p[2]).fold(f32::MIN, f32::max);
    assert!(top > 0.99, "{top}");
    let quad = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    let (few, idx) = html::decimate(&quad, &[[0, 1, 2], [1, 3, 2]]);
    assert_eq!((few.len(), idx.len()), (4, 6));
}

/// A motion rides in the page (frames and rate, the first frame shown first); a frame of the
/// wrong length or a value that is not finite is an error naming the frame, a bad rate too.
#[test]
fn the_page_embeds_a_motion() {
    let (chain, kin) = load("ur5.urdf", None, None);
    let frames: Vec<Vec<f64>> = (0..5).map(|k| vec![0.1 * k as f64; 6]).collect();
    let motion = html::Motion {
        frames: &frames,
        fps: 50.0,
    };
    let options = html::PageOptions {
        motion: Some(motion),
        ..Default::default()
    };
    let page = html::page_with_body(&chain, &kin, None, None, &options).unwrap();
    let start = page.find("id=\"model\">").unwrap() + "id=\"model\">".len();
    let end = start + page[start..].find("</script>").unwrap();
    let model: serde_json::Value = serde_json::from_str(&page[start..end]).unwrap();
    assert_eq!(model["motion"]["fps"], 50.0);
    let got: Vec<Vec<f64>> = serde_json::from_value(model["motion"]["frames"].clone()).unwrap();
    assert_eq!(got, frames);
    assert_eq!(model["q"], serde_json::json!(frames[0]));
    let error = |frames: &[Vec<f64>], fps: f64| {
        let options = html::PageOptions {
            motion: Some(html::Motion { frames, fps }),
            ..Default::default()
        };
        html::page_with_body(&chain, &kin, None, None, &options)
            .unwrap_err()
            .to_string()
    };
    let mut bad = frames.clone();
    bad[3].pop();
    let e = error(&bad, 50.0);
    assert!(e.contains("frame 3"), "{e}");
    bad[3] = vec![f64::NAN; 6];
    let e = error(&bad, 50.0);
    assert!(e.contains("frame 3"), "{e}");
    for fps in [0.0, -1.0, f64::NAN, 1e6] {
        let e = error(&frames, fps);
        assert!(e.contains("fps"), "{e}");
    }
}

/// Issue 49, item 4, on the bundled humanoid (23 joints, a capsule or sphere on every link):
/// every link's name asked (`Labels::All`) in the four views: no two labels overlap, each
/// inside its panel, and the names left out for room are counted in the panel's note; the
/// axes of a tree of more than 12 joints are left out unless asked, by name or number; an
/// unknown joint is refused by name.
#[test]
fn dense_names_never_overlap_and_axes_are_chosen() {
    use screwkit_model::KinematicTree;
    use screwkit_solve::TreeKinematics;
    use svg::{Axes, Labels, Options};
    let tree = screwkit_model::urdf::load_file(bundled("humanoid.urdf")).unwrap();
    let model = KinematicTree::from_tree(&tree).unwrap();
    let kin = TreeKinematics::new(&model).unwrap();
    let scene = Scene::tree(&kin, None).unwrap().with_body(&tree);
    assert!(!scene.outlines.is_empty() && scene.problems.is_empty());
    for labels in [Labels::None, Labels::Leaves, Labels::All] {
        let options = Options {
            views: View::ALL.to_vec(),
            labels,
            axes: Axes::Auto,
        };
        let text = svg::render_with(&scene, &options).unwrap();
        let doc = roxmltree::Document::parse(&text).unwrap();
        for &view in View::ALL {
            let v = view.as_str();
            let placed = assert_labels_apart(&doc, v);
            let dropped: usize = group(&doc, &format!("{v}-labels"))
                .children()
                .find(|n| n.attribute("class") == Some("dropped"))
                .map_or(0, |n| {
                    n.text()
                        .unwrap()
                        .split(' ')
                        .next()
                        .unwrap()
                        .parse()
                        .unwrap()
                });
            let asked = match labels {
                Labels::None => 0,
                Labels::Leaves => 5, // two soles, two hands, the head
                Labels::All => model.links.len(),
            };
            assert_eq!(placed + dropped, asked, "{v} {labels}");
            if labels == Labels::Leaves {
                assert_eq!(dropped, 0, "{v}: a leaf's name left out");
            }
            // No axis (23 joints), every joint mark.
            assert!(!text.contains(&format!("id=\"{v}-axis-")));
            assert!(text.contains(&format!("id=\"{v}-joint-23\"")));
        }
    }
    let options = Options {
        axes: "3,left_knee".parse().unwrap(),
        ..Options::default()
    };
    let text = svg::render_with(&scene, &options).unwrap();
    let knee = model
        .joints
        .iter()
        .position(|j| j.name == "left_knee")
        .unwrap()
        + 1;
    let mut drawn: Vec<usize> = text
        .match_indices("id=\"iso-axis-")
        .map(|(k, m)| {
            let rest = &text[k + m.len()..];
            rest[..rest.find('"').unwrap()].parse().unwrap()
        })
        .collect();
    drawn.sort();
    let mut want = vec![3, knee];
    want.sort();
    assert_eq!(drawn, want);
    let options = Options {
        axes: "left_knee,elbow".parse().unwrap(),
        ..Options::default()
    };
    let e = svg::render_with(&scene, &options).unwrap_err().to_string();
    assert!(e.starts_with("axes: no joint \"elbow\""), "{e}");
}

/// The body's silhouettes, against closed forms: a 0.2 × 0.4 × 0.1 m box seen from above is
/// a 0.2 × 0.4 rectangle at its place, a sphere a circle (every vertex at one radius, within
/// the ring's spacing) at its centre, both in the scale of the drawing's scale bar; painter's
/// order puts the farther shape first in the document, whatever the file's order; a colour
/// from the file is kept; a mesh that cannot be read is named in the caption, the rest drawn.
#[test]
fn silhouettes_are_the_shapes_projected_in_painters_order() {
    let urdf = r#"<robot name="shapes">
      <link name="base"/>
      <link name="arm">
        <visual><origin xyz="0.5 0.2 0.3"/><geometry><box size="0.2 0.4 0.1"/></geometry>
          <material name="red"><color rgba="1 0 0 1"/></material></visual>
        <visual><origin xyz="-0.3 -0.1 0.0"/><geometry><sphere radius="0.15"/></geometry></visual>
        <visual><geometry><mesh filename="missing.stl"/></geometry></visual>
      </link>
      <link name="tip"/>
      <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
        <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <joint name="j2" type="revolute"><parent link="arm"/><child link="tip"/>
        <origin xyz="1 0 0"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    </robot>"#;
    let tree = screwkit_model::urdf::load_str(urdf, "shapes.urdf").unwrap();
    let chain = Chain::from_tree(&tree, None, None).unwrap();
    let kin = Kinematics::new(&chain);
    let scene = Scene::new(&chain, &kin, Some(&[0.0, 0.0]))
        .unwrap()
        .with_body(&tree);
    assert_eq!(scene.outlines.len(), 2);
    assert!(
        scene.problems[0].contains("missing.stl"),
        "{:?}",
        scene.problems
    );
    let text = svg::render(&scene, &[View::Top]);
    let doc = roxmltree::Document::parse(&text).unwrap();
    assert!(
        doc.root_element()
            .children()
            .filter_map(|n| n.text())
            .any(|t| t.starts_with("not drawn: \"arm\": ") && t.contains("missing.stl")),
        "the caption names the mesh"
    );
    let shapes: Vec<roxmltree::Node> = group(&doc, "top-body")
        .children()
        .filter(|n| n.has_tag_name("polygon"))
        .collect();
    assert_eq!(shapes.len(), 2);
    // The box (z = 0.3) is nearer to a viewer above than the sphere (z = 0): drawn last.
    assert_eq!(shapes[1].attribute("fill"), Some("#ff0000"));
    let points = |n: roxmltree::Node| -> Vec<(f64, f64)> {
        n.attribute("points")
            .unwrap()
            .split(' ')
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect()
    };
    // Pixels per metre: the scale bar's length over its label.
    let bar = group(&doc, "top-scale");
    let line = bar.children().find(|n| n.has_tag_name("line")).unwrap();
    let label = bar
        .children()
        .find(|n| n.has_tag_name("text"))
        .unwrap()
        .text()
        .unwrap();
    let metres: f64 = match label.strip_suffix(" mm") {
        Some(mm) => mm.parse::<f64>().unwrap() / 1e3,
        None => label.strip_suffix(" m").unwrap().parse().unwrap(),
    };
    let ppm = (num(line, "x2") - num(line, "x1")) / metres;
    let rect = points(shapes[1]);
    assert_eq!(rect.len(), 4, "{rect:?}");
    let span = |k: usize, pts: &[(f64, f64)]| {
        let v: Vec<f64> = pts.iter().map(|p| if k == 0 { p.0 } else { p.1 }).collect();
        v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
    };
    assert!((span(0, &rect) - 0.2 * ppm).abs() < 0.02, "{rect:?}");
    assert!((span(1, &rect) - 0.4 * ppm).abs() < 0.02, "{rect:?}");
    let circle = points(shapes[0]);
    let n = circle.len() as f64;
    let c = (
        circle.iter().map(|p| p.0).sum::<f64>() / n,
        circle.iter().map(|p| p.1).sum::<f64>() / n,
    );
    for p in &circle {
        let r = (p.0 - c.0).hypot(p.1 - c.1) / ppm;
        assert!((r - 0.15).abs() < 0.15 * 0.01, "radius {r}");
    }
    // The box's centre is 0.8 m right of and 0.3 m above (y) the sphere's (y up, page down).
    let rc = (
        rect.iter().map(|p| p.0).sum::<f64>() / 4.0,
        rect.iter().map(|p| p.1).sum::<f64>() / 4.0,
    );
    assert!(((rc.0 - c.0) / ppm - 0.8).abs() < 1e-3 && ((c.1 - rc.1) / ppm - 0.3).abs() < 1e-3);
}
