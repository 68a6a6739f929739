//! Fuzz targets of the robot-file parsers — URDF, xacro and xacro's expression language, MJCF —
//! by the seeded mutation fuzzer of `screwkit_testkit::fuzz`, starting from the bundled and
//! shared robot files. Each runs a few seconds here; `SCREWKIT_FUZZ_SECS=600` runs ten
//! minutes. A crash, an abort or a hang fails the run.

use std::path::{Path, PathBuf};

use screwkit_model::{mesh, mjcf, urdf, xacro, Chain, KinematicTree, XacroOptions};
use screwkit_testkit::fuzz;

fn files(dir: &Path, ext: &str, out: &mut Vec<Vec<u8>>) {
    let Ok(rd) = std::fs::read_dir(dir) else {
        return;
    };
    let mut paths: Vec<PathBuf> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    paths.sort();
    for p in paths {
        if p.is_dir() {
            files(&p, ext, out);
        } else if p.extension().is_some_and(|e| e == ext) {
            if let Ok(b) = std::fs::read(&p) {
                if b.len() < 400_000 {
                    out.push(b);
                }
            }
        }
    }
}

fn crate_dir() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

const URDF_TOKENS: &[&[u8]] = &[
    b"<",
    b">",
    b"/>",
    b"\"",
    b"'",
    b"&amp;",
    b"&e;",
    b"<!--",
    b"-->",
    b"<![CDATA[",
    b"]]>",
    b"<joint name=\"j\" type=\"revolute\">",
    b"</joint>",
    b"<link name=\"l\"/>",
    b"<mimic joint=\"j\" multiplier=\"-1e308\"/>",
    b"<limit lower=\"1\" upper=\"-1\"/>",
    b"type=\"continuous\"",
    b"type=\"planar\"",
    b"<axis xyz=\"0 0 0\"/>",
    b"xmlns:u=\"urn:u\"",
    b"<u:origin xyz=\"5 5 5\"/>",
    b"<!DOCTYPE robot [<!ENTITY e \"xxxxxxxx\">]>",
    b"<parent link=\"l\"/>",
    b"<child link=\"l\"/>",
    b"rpy=\"1e300 0 0\"",
    b"<collision><geometry><box size=\"1 1 1\"/></geometry></collision>",
    b"<visual><origin xyz=\"0 0 1e308\"/><geometry><sphere radius=\"0\"/></geometry><material name=\"m\"/></visual>",
    b"<geometry><mesh filename=\"package://p/m.stl\" scale=\"1 1\"/></geometry>",
    b"<capsule radius=\"1\" length=\"-1\"/>",
    b"<cylinder radius=\"nan\" length=\"1\"/>",
];

const XACRO_TOKENS: &[&[u8]] = &[
    b"${",
    b"}",
    b"$(",
    b")",
    b"$(arg x)",
    b"$(find p)",
    b"${pi}",
    b"${1/0}",
    b"${-(-9223372036854775807-1)}",
    b"<xacro:property name=\"p\" value=\"${p}\"/>",
    b"<xacro:macro name=\"m\" params=\"a *b\">",
    b"</xacro:macro>",
    b"<xacro:m a=\"1\"><x/></xacro:m>",
    b"<xacro:if value=\"${1 if x else 0}\">",
    b"</xacro:if>",
    b"<xacro:include filename=\"/dev/zero\"/>",
    b"<xacro:insert_block name=\"b\"/>",
    b"<xacro:element xacro:name=\"a b\"/>",
    b"<xacro:attribute name=\"x\" value=\"y\"/>",
    b"params=\"x:='0 0 0'\"",
    b"**",
    b"//",
    b"%",
    b" and ",
    b" or ",
    b" not ",
    b"((((((((",
];

#[test]
fn fuzz_urdf() {
    let mut seeds = Vec::new();
    files(&crate_dir().join("../../assets/urdf"), "urdf", &mut seeds);
    if let Some(shared) = std::env::var_os("SCREWKIT_SHARED_URDF") {
        files(Path::new(&shared), "urdf", &mut seeds);
    }
    let n = fuzz::run("urdf", 1, 3.0, &seeds, URDF_TOKENS, |input| {
        let text = String::from_utf8_lossy(input);
        if let Ok(tree) = urdf::load_str(&text, "fuzz.urdf") {
            let _ = Chain::from_tree(&tree, None, None);
            for l in tree.leaves_below(tree.root) {
                let _ = Chain::from_tree(&tree, None, Some(&tree.links[l]));
            }
        }
    });
    assert!(n > 0);
}

#[test]
fn fuzz_xacro() {
    let mut seeds = Vec::new();
    files(&crate_dir().join("tests/xacro_cases"), "xacro", &mut seeds);
    if let Some(shared) = std::env::var_os("SCREWKIT_SHARED_XACRO") {
        files(Path::new(&shared), "xacro", &mut seeds);
    }
    let opts = XacroOptions {
        package_paths: vec![crate_dir().join("tests/xacro_cases/pkgs")],
        args: vec![],
    };
    let dir = crate_dir().join("tests/xacro_cases");
    let n = fuzz::run("xacro", 2, 3.0, &seeds, XACRO_TOKENS, |input| {
        let text = String::from_utf8_lossy(input);
        if let Ok(out) = xacro::expand_str(&text, "fuzz.xacro", &dir, &opts) {
            // What the expander writes is well-formed URDF text (or a clean error).
            let _ = urdf::load_str(&out, "fuzz.urdf");
        }
    });
    assert!(n > 0);
}

#[test]
fn fuzz_expressions() {
    let exprs: &[&str] = &[
        "1 + 2 * 3 - 4 / 5",
        "2 ** -1 ** 2",
        "-7 // 2 % 3",
        "(1/b) if b != 0 else 0",
        "a and b or not c",
        "round(2.675, 2) + int(3.9) - floor(-1.5)",
        "max(1, 2.5, -3) if 'x' else min(4, 5)",
        "radians(90) * sin(pi / 2) + math.atan2(1, 1)",
        "'link_' + str(7 // 2) + 'x'",
        "abs(-9223372036854775807 - 1)",
        "1e308 * 10",
        "float('nan') == float('nan')",
        "((((1))))",
        "not not not True",
        "3 < 4 and 4 <= 4.0",
        "log(100, 10) + sqrt(2) ** 2",
    ];
    let seeds: Vec<Vec<u8>> = exprs.iter().map(|e| e.as_bytes().to_vec()).collect();
    let tokens: &[&[u8]] = &[
        b"(",
        b")",
        b"**",
        b"//",
        b"%",
        b" if ",
        b" else ",
        b" and ",
        b" or ",
        b"not ",
        b"'",
        b"\"",
        b",",
        b".",
        b"math.",
        b"pi",
        b"e",
        b"inf",
        b"nan",
        b"b",
        b"a",
        b"c",
        b"int(",
        b"round(",
        b"9223372036854775807",
        b"-",
        b"1e-7",
        b"str(",
        b"[",
        b"{",
        b":",
    ];
    let props = "<xacro:property name=\"a\" value=\"1\"/><xacro:property name=\"b\" value=\"0\"/><xacro:property name=\"c\" value=\"'s'\"/>";
    let n = fuzz::run("expressions", 3, 3.0, &seeds, tokens, |input| {
        let e = String::from_utf8_lossy(input)
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('"', "&quot;");
        let doc = format!(
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">{props}<link name=\"${{{e}}}\"/></robot>"
        );
        let _ = xacro::expand_str(&doc, "fuzz.xacro", Path::new("."), &XacroOptions::default());
    });
    assert!(n > 0);
}

const MJCF_TOKENS: &[&[u8]] = &[
    b"<body name=\"x\">",
    b"</body>",
    b"<joint type=\"slide\"/>",
    b"<joint type=\"ball\"/>",
    b"<freejoint/>",
    b"<frame euler=\"1 2 3\">",
    b"</frame>",
    b"<site quat=\"0 0 0 0\"/>",
    b"childclass=\"main\"",
    b"class=\"nope\"",
    b"<default class=\"c\"><joint range=\"0 1\"/></default>",
    b"<compiler angle=\"radian\" eulerseq=\"ZyX\" autolimits=\"false\"/>",
    b"<include file=\"fuzz.xml\"/>",
    b"<equality><joint joint1=\"a\" joint2=\"b\" polycoef=\"0 1 0 0 0\"/></equality>",
    b"ref=\"1e308\"",
    b"range=\"-1e999 nan\"",
    b"xyaxes=\"1 0 0 1 0 0\"",
    b"zaxis=\"0 0 -1\"",
    b"axisangle=\"0 0 0 90\"",
    b"limited=\"auto\"",
    b"<geom type=\"capsule\" fromto=\"0 0 0 0 0 1\" size=\"0.1\"/>",
    b"<geom type=\"box\" size=\"1e308 1 1\" contype=\"-1\"/>",
    b"<geom type=\"ellipsoid\" size=\"0 1\"/>",
    b"<geom type=\"plane\" size=\"nan\"/>",
    b"<geom type=\"mesh\" mesh=\"m\"/>",
    b"<geom type=\"hfield\"/>",
    b"<asset><mesh name=\"m\" file=\"../m.stl\" scale=\"1 1\"/></asset>",
    b"<contact><exclude body1=\"world\" body2=\"x\"/><pair geom1=\"a\" geom2=\"\"/></contact>",
    b"<option><flag filterparent=\"disable\"/></option>",
];

#[test]
fn fuzz_mjcf() {
    let mut seeds = Vec::new();
    files(&crate_dir().join("../../assets/mjcf"), "xml", &mut seeds);
    if let Some(shared) = std::env::var_os("SCREWKIT_SHARED_MJCF") {
        files(Path::new(&shared), "xml", &mut seeds);
    }
    let dir = std::env::temp_dir();
    let n = fuzz::run("mjcf", 4, 3.0, &seeds, MJCF_TOKENS, |input| {
        let text = String::from_utf8_lossy(input);
        if let Ok(tree) = mjcf::load_str(&text, "fuzz.xml", &dir) {
            if let Ok(kt) = KinematicTree::from_tree(&tree) {
                let _ = kt.with_floating_base(tree.floating_root);
            }
            for l in tree.leaves_below(tree.root) {
                let _ = Chain::from_tree(&tree, None, Some(&tree.links[l]));
            }
        }
    });
    assert!(n > 0);
}

/// Where the fuzzer's input splits into the files of an MJCF model.
const FILE_BREAK: &str = "\n<!--FILE-->\n";

const INCLUDE_TOKENS: &[&[u8]] = &[
    b"<include file=\"a.xml\"/>",
    b"<include file=\"b.xml\"/>",
    b"<include file=\"main.xml\"/>",
    b"<include file=\"missing.xml\"/>",
    b"<include/>",
    b"\n<!--FILE-->\n",
    b"<body name=\"n\"><body name=\"m\">",
    b"</body></body>",
    b"<default class=\"k\"><default class=\"k2\"><joint axis=\"1 0 0\"/></default></default>",
    b"<joint class=\"k2\"/>",
    b"<mujoco>",
    b"</mujoco>",
    b"<worldbody>",
    b"</worldbody>",
    b"<frame pos=\"0 0 1\">",
    b"</frame>",
    b"range=\"0 0\"",
    b"limited=\"true\"",
    b"<compiler coordinate=\"global\"/>",
    b"xmlns:u=\"u\"",
    b"<u:body>",
];

/// MJCF models of several files (a virtual file set: the input split at [`FILE_BREAK`] into
/// main.xml, a.xml and b.xml, which include each other), so that includes — nesting across
/// files, cycles, budgets, defaults split over files — are fuzzed too.
#[test]
fn fuzz_mjcf_includes() {
    let seeds = vec![
        [
            "<mujoco model=\"m\"><include file=\"a.xml\"/><worldbody><body name=\"b0\"><joint name=\"j0\"/><include file=\"b.xml\"/></body></worldbody></mujoco>",
            "<mujoco><default><joint axis=\"0 1 0\" range=\"-1 1\"/><default class=\"c\"><joint axis=\"1 0 0\"/></default></default></mujoco>",
            "<mujoco><body name=\"b1\" pos=\"0 0 0.3\"><joint name=\"j1\" class=\"c\"/><site name=\"tip\" pos=\"0 0 0.2\"/></body></mujoco>",
        ]
        .join(FILE_BREAK)
        .into_bytes(),
        [
            "<mujoco><worldbody><include file=\"a.xml\"/></worldbody></mujoco>",
            "<mujoco><body name=\"p\"><freejoint/><include file=\"b.xml\"/></body></mujoco>",
            "<mujoco><body name=\"q\"><joint name=\"k\" type=\"slide\"/></body></mujoco>",
        ]
        .join(FILE_BREAK)
        .into_bytes(),
    ];
    let dir = std::env::temp_dir().join(format!("sk-fuzz-inc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let n = fuzz::run("mjcf-includes", 5, 3.0, &seeds, INCLUDE_TOKENS, |input| {
        let text = String::from_utf8_lossy(input);
        let mut parts = text.splitn(3, FILE_BREAK);
        for name in ["main.xml", "a.xml", "b.xml"] {
            std::fs::write(dir.join(name), parts.next().unwrap_or("")).unwrap();
        }
        if let Ok(tree) = mjcf::load_file(dir.join("main.xml")) {
            if let Ok(kt) = KinematicTree::from_tree(&tree) {
                let _ = kt.with_floating_base(tree.floating_root);
            }
            for l in tree.leaves_below(tree.root) {
                let _ = Chain::from_tree(&tree, None, Some(&tree.links[l]));
            }
        }
    });
    let _ = std::fs::remove_dir_all(&dir);
    assert!(n > 0);
}

const SCREW_TOKENS: &[&[u8]] = &[
    b"\"screw\": [0, 0, 1, 0, 0, 0.1]",
    b"\"screw_space\": [0, 0, 0, 0, 0, 1]",
    b"\"frame\": \"body\"",
    b"\"lower\": null",
    b"\"upper\": 1e308",
    b"\"mimic\": {\"leader\": \"joint1\", \"multiplier\": -1}",
    b"\"mimic\": {\"leader\": \"joint2\"}",
    b"NaN",
    b"1e999",
    b"-0",
    b"[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]",
    b"space,1,a,helical,0,0,1,0,0,0.1,,,,0.1\n",
    b"M,1,1,0,0,0,,,,,,,,\n",
    b"\"x,\"\"y\"\"\"",
];

/// Screw tables as `screwkit table --format json|csv` and `ScrewRobot::to_json` write them,
/// mutated: the reader, then the chain and the tree of whatever it accepts, never panic.
#[test]
fn fuzz_screw_tables() {
    let robot = screwkit_model::ScrewRobot::new(
        "seed",
        [
            -1., 0., 0., 0., 0., 1., 0., 6., 0., 0., -1., 2., 0., 0., 0., 1.,
        ],
        vec![
            [0., 0., 1., 4., 0., 0.],
            [0., 0., 0., 0., 1., 0.],
            [0., 0., -1., -6., 0., -0.1],
        ],
        screwkit_lie::Frame::Space,
        Some(vec![
            (-1.0, 1.0),
            (0.0, 2.0),
            (f64::NEG_INFINITY, f64::INFINITY),
        ]),
        None,
    )
    .unwrap();
    let chain = robot.chain().unwrap();
    let seeds = vec![
        robot.to_json().to_string().into_bytes(),
        screwkit_model::table::to_json(&chain)
            .to_string()
            .into_bytes(),
        screwkit_model::table::to_csv(
            &chain,
            &[screwkit_lie::Frame::Space, screwkit_lie::Frame::Body],
        )
        .into_bytes(),
    ];
    let n = fuzz::run("screw-tables", 5, 3.0, &seeds, SCREW_TOKENS, |input| {
        let text = String::from_utf8_lossy(input);
        if screwkit_model::table::is_screw_table(&text) {
            if let Ok(r) = screwkit_model::table::read_screw_table(&text, "fuzz") {
                if r.chain().is_ok() {
                    let tree = r
                        .tree()
                        .expect("a description whose chain builds has a tree");
                    KinematicTree::from_tree(&tree).expect("and its whole tree builds");
                }
            }
        }
    });
    assert!(n > 0);
}

/// The mesh parsers (STL ASCII and binary, OBJ, COLLADA) from a triangle in each format: every
/// answer is a clean mesh (finite vertices, indices in range) or an error.
#[test]
fn fuzz_meshes() {
    let mut binary = vec![0u8; 80];
    binary.extend_from_slice(&1u32.to_le_bytes());
    binary.extend_from_slice(&[0u8; 12]);
    for x in [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0] {
        binary.extend_from_slice(&x.to_le_bytes());
    }
    binary.extend_from_slice(&[0u8; 2]);
    let seeds: Vec<(&str, Vec<u8>)> = vec![
        ("m.stl", b"solid t\n facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\nendsolid t\n".to_vec()),
        ("m.stl", binary),
        ("m.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/1\nf -1 -2 -3\n".to_vec()),
        ("m.dae", br##"<COLLADA version="1.4.1"><asset><unit meter="0.001"/></asset><library_geometries><geometry id="g"><mesh><source id="p"><float_array id="a" count="9">0 0 0 1 0 0 0 1 0</float_array><technique_common><accessor source="#a" count="3" stride="3"><param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/></accessor></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="1"><input semantic="VERTEX" source="#v" offset="0"/><p>0 1 2</p></triangles></mesh></geometry></library_geometries><library_visual_scenes><visual_scene id="s"><node><matrix>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</matrix><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>"##.to_vec()),
    ];
    let tokens: &[&[u8]] = &[
        b"vertex ",
        b"facet",
        b"endloop",
        b"1e39",
        b"nan",
        b"-0",
        b"\xff\xff\xff\x7f",
        b"f 1 2 99",
        b"f 0 0 0",
        b"count=\"99999999\"",
        b"<p>0 1 7</p>",
        b"stride=\"0\"",
        b"offset=\"5\"",
        b"meter=\"1e300\"",
    ];
    for (k, (name, seed)) in seeds.into_iter().enumerate() {
        let path = Path::new(name);
        let n = fuzz::run(name, 10 + k as u64, 1.5, &[seed], tokens, |input| {
            if let Ok(m) = mesh::parse_mesh(input, path, [1.0, 2.0, 3.0]) {
                assert!(m.vertices.iter().flatten().all(|x| x.is_finite()));
                assert!(m
                    .triangles
                    .iter()
                    .flatten()
                    .all(|&i| (i as usize) < m.vertices.len()));
            }
        });
        assert!(n > 0);
    }
}

/// The SRDF reader from a small MoveIt file: every answer is a clean `Srdf` or an error, and
/// what it writes back parses to the same disabled pairs.
#[test]
fn fuzz_srdf() {
    let seed = br#"<?xml version="1.0"?>
<robot name="r">
  <group name="arm"><chain base_link="a" tip_link="b"/><joint name="j"/><link name="l"/><group name="g"/></group>
  <end_effector name="e" parent_link="b" group="hand" parent_group="arm"/>
  <disable_collisions link1="a" link2="b" reason="Adjacent"/>
  <disable_collisions link1="c&amp;d" link2="a" reason="Never"/>
</robot>"#;
    let tokens: &[&[u8]] = &[
        b"<disable_collisions link1=\"x\" link2=\"y\"/>",
        b"<group name=\"g\">",
        b"</group>",
        b"<end_effector/>",
        b"link1=\"",
        b"&amp;",
        b"<!--",
        b"-->",
        b"\"",
        b"<",
        b">",
    ];
    let n = fuzz::run("srdf", 20, 2.0, &[seed.to_vec()], tokens, |input| {
        let text = String::from_utf8_lossy(input);
        if let Ok(s) = screwkit_model::srdf::parse(&text, "fuzz.srdf") {
            let back = screwkit_model::srdf::parse(
                &screwkit_model::srdf::write(&s.robot, &s.disabled),
                "back.srdf",
            )
            .expect("what srdf::write writes parses");
            assert!(back.disabled.len() <= s.disabled.len());
        }
    });
    assert!(n > 0);
}
