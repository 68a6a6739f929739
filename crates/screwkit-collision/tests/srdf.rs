//! SRDF read and written (`screwkit_model::srdf`), applied to a collision model, and the
//! allowed-collision matrix generated as MoveIt's setup assistant does (`acm::generate`): its
//! reasons on a robot whose collisions are known by hand, its bytes the same on every run and
//! thread count, its "never" pairs free on a fresh sample.

use screwkit_collision::acm::{generate, Generate};
use screwkit_collision::{collisions, CollisionModel, CollisionWorkspace, MeshMode, Options};
use screwkit_model::srdf;
use screwkit_model::{KinematicTree, XacroOptions};
use screwkit_solve::TreeKinematics;

/// base (sphere 0.1) —revolute— arm (no shape) —prismatic x ∈ [−5, 5]— slider (sphere 0.1)
/// —fixed, 3 m up— tool (sphere 0.01); and a `fin` on the base, fixed, always inside the base's
/// sphere.
fn robot(dir: &std::path::Path) -> TreeKinematics {
    let urdf = r#"<robot name="t">
  <link name="base"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
  <link name="arm"/>
  <link name="slider"><collision><geometry><sphere radius="0.1"/></geometry></collision></link>
  <link name="tool"><collision><geometry><sphere radius="0.01"/></geometry></collision></link>
  <link name="fin"><collision><geometry><box size="0.05 0.05 0.05"/></geometry></collision></link>
  <joint name="turn" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="slide" type="prismatic"><parent link="arm"/><child link="slider"/>
    <axis xyz="1 0 0"/><limit lower="-5" upper="5" effort="1" velocity="1"/></joint>
  <joint name="mount" type="fixed"><parent link="slider"/><child link="tool"/>
    <origin xyz="0 0 3"/></joint>
  <joint name="weld" type="fixed"><parent link="base"/><child link="fin"/>
    <origin xyz="0.05 0 0"/></joint>
</robot>"#;
    let path = dir.join("t.urdf");
    std::fs::write(&path, urdf).unwrap();
    let tree = screwkit_model::load_tree(&path, &XacroOptions::default()).unwrap();
    TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap()
}

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("screwkit-srdf-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn read_and_write() {
    let text = r#"<?xml version="1.0"?>
<robot name="panda">
  <group name="arm"><chain base_link="panda_link0" tip_link="panda_link8"/></group>
  <group name="hand"><link name="panda_hand"/><joint name="panda_finger_joint1"/></group>
  <group name="both"><group name="arm"/><group name="hand"/></group>
  <end_effector name="eef" parent_link="panda_link8" group="hand" parent_group="arm"/>
  <disable_collisions link1="panda_link0" link2="panda_link1" reason="Adjacent"/>
  <disable_collisions link1="b" link2="a" reason="Never"/>
  <virtual_joint name="v" type="fixed" parent_frame="world" child_link="panda_link0"/>
</robot>"#;
    let s = srdf::parse(text, "panda.srdf").unwrap();
    assert_eq!(s.robot, "panda");
    assert_eq!(s.groups.len(), 3);
    assert_eq!(
        s.groups[0].chains,
        [("panda_link0".into(), "panda_link8".into())]
    );
    assert_eq!(s.groups[1].links, ["panda_hand"]);
    assert_eq!(s.groups[1].joints, ["panda_finger_joint1"]);
    assert_eq!(s.groups[2].subgroups, ["arm", "hand"]);
    assert_eq!(s.end_effectors[0].parent_group.as_deref(), Some("arm"));
    assert_eq!(s.disabled.len(), 2);
    assert_eq!(s.disabled[1].reason, "Never");
    // Written sorted, each pair once and link1 < link2: the same bytes from any order.
    let out = srdf::write("panda", &s.disabled);
    let mut reversed = s.disabled.clone();
    reversed.reverse();
    assert_eq!(out, srdf::write("panda", &reversed));
    let back = srdf::parse(&out, "out.srdf").unwrap();
    assert_eq!(back.disabled[0].link1, "a");
    assert_eq!(back.disabled.len(), 2);
    // Errors name the element and its line.
    let e = srdf::parse(
        "<robot>\n<disable_collisions link1=\"a\"/></robot>",
        "x.srdf",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("x.srdf") && e.contains("line 2") && e.contains("link2"),
        "{e}"
    );
    let e = srdf::parse("<robot><group/></robot>", "x.srdf")
        .unwrap_err()
        .to_string();
    assert!(e.contains("<group> has no name"), "{e}");
    assert!(srdf::parse("<mujoco/>", "x.srdf").is_err());
    assert!(srdf::parse("<robot", "x.srdf").is_err());
}

#[test]
fn a_generated_matrix_has_its_reasons() {
    let d = dir("generate");
    let kin = robot(&d);
    let g = Generate {
        samples: 2000,
        seed: 7,
        never: true,
        ..Generate::default()
    };
    let pairs = generate(&kin, MeshMode::Exact, &g).unwrap();
    let reasons: Vec<(&str, &str, &str)> = pairs
        .iter()
        .map(|p| (p.link1.as_str(), p.link2.as_str(), p.reason.as_str()))
        .collect();
    // base–fin: welded, the nearest ancestor with shapes (Adjacent). base–slider: through the
    // shapeless arm (Adjacent). slider–tool: welded (Adjacent). fin–tool, base–tool: never.
    // fin–slider: the spheres at the default q = 0 overlap the fin (Default).
    assert_eq!(
        reasons,
        [
            ("base", "fin", "Adjacent"),
            ("base", "slider", "Adjacent"),
            ("base", "tool", "Never"),
            ("fin", "slider", "Default"),
            ("fin", "tool", "Never"),
            ("slider", "tool", "Adjacent"),
        ]
    );
    // The same bytes on 1 and 2 threads.
    let text = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| srdf::write("t", &generate(&kin, MeshMode::Exact, &g).unwrap()))
    };
    assert_eq!(text(1), text(2));
    // Applied: the model checks only the pairs not listed; a "never" pair never collides on a
    // fresh sample.
    let mut model = CollisionModel::new(&kin, Options::default()).unwrap();
    let parsed = srdf::parse(&text(2), "t.srdf").unwrap();
    model.apply_srdf(&parsed).unwrap();
    assert_eq!(
        model.pair_count(),
        0,
        "every pair of this robot is disabled"
    );
    let all = CollisionModel::new(
        &kin,
        Options {
            all_pairs: true,
            ..Options::default()
        },
    )
    .unwrap();
    let mut ws = CollisionWorkspace::new(&kin, &all);
    let mut hits = Vec::new();
    let mut rng = screwkit_solve::sample::SplitMix64(99);
    for _ in 0..2000 {
        let q = screwkit_solve::tree::configuration::random(&kin, &mut rng);
        collisions(&all, &mut ws, &kin, &q, &mut hits).unwrap();
        for &k in &hits {
            let (a, b) = all.pair_names(k);
            let never = pairs.iter().any(|p| {
                p.reason == "Never"
                    && ((p.link1 == a && p.link2 == b) || (p.link1 == b && p.link2 == a))
            });
            assert!(!never, "{a}–{b} was generated as never colliding");
        }
    }
    // An SRDF naming a link the robot lacks is an error naming it.
    let bad = srdf::parse(
        r#"<robot><disable_collisions link1="base" link2="ghost"/></robot>"#,
        "b.srdf",
    )
    .unwrap();
    let e = model.apply_srdf(&bad).unwrap_err().to_string();
    assert!(e.contains("\"ghost\""), "{e}");
    std::fs::remove_dir_all(&d).unwrap();
}
