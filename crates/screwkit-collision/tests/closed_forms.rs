//! The body's queries against closed forms: a three-link robot (base —revolute— arm
//! —prismatic x— slider, so base and slider are not adjacent) carrying primitives and meshes,
//! whose distances are known by hand; the pair rules; obstacles; batches equal single calls
//! whatever the thread count; geometry problems and bad meshes named.

use screwkit_collision::{
    collisions, distances, in_collision, in_collision_batch, min_distance, min_distance_batch,
    CollisionError, CollisionModel, CollisionWorkspace, MeshMode, Options,
};
use screwkit_lie::Se3;
use screwkit_model::geometry::Shape;
use screwkit_model::{KinematicTree, XacroOptions};
use screwkit_solve::TreeKinematics;

/// base (shape `base`) —revolute z— arm (a small box) —prismatic x— slider (shape `slider`,
/// at x = q[1]); a fixed `tool` link on the slider with its own shape.
fn robot(base: &str, slider: &str, tool: &str, dir: &std::path::Path) -> TreeKinematics {
    let urdf = format!(
        r#"<robot name="t">
  <link name="base"><collision>{base}</collision></link>
  <link name="arm"><collision><geometry><box size="0.01 0.01 0.01"/></geometry></collision></link>
  <link name="slider"><collision>{slider}</collision></link>
  <link name="tool"><collision>{tool}</collision></link>
  <joint name="turn" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
  <joint name="slide" type="prismatic"><parent link="arm"/><child link="slider"/>
    <axis xyz="1 0 0"/><limit lower="-5" upper="5" effort="1" velocity="1"/></joint>
  <joint name="mount" type="fixed"><parent link="slider"/><child link="tool"/>
    <origin xyz="0 0 3"/></joint>
</robot>"#
    );
    let path = dir.join("t.urdf");
    std::fs::write(&path, urdf).unwrap();
    let tree = screwkit_model::load_tree(&path, &XacroOptions::default()).unwrap();
    TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap()
}

fn dir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("screwkit-collide-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

const SPHERE: &str = r#"<geometry><sphere radius="0.1"/></geometry>"#;
/// Far from everything: the tool's shape, 3 m up.
const SMALL: &str = r#"<geometry><sphere radius="0.01"/></geometry>"#;

/// The pair of the base's and the slider's shapes.
fn base_slider(model: &CollisionModel) -> usize {
    (0..model.pair_count())
        .find(|&k| model.pair_names(k) == ("base", "slider"))
        .expect("the base–slider pair is checked")
}

#[test]
fn pair_rules() {
    let d = dir("rules");
    let kin = robot(SPHERE, SPHERE, SMALL, &d);
    let mut model = CollisionModel::new(&kin, Options::default()).unwrap();
    let names: Vec<_> = (0..model.pair_count())
        .map(|k| model.pair_names(k))
        .collect();
    // base–arm and arm–slider are adjacent; slider–tool one rigid body.
    assert_eq!(names, [("base", "slider"), ("base", "tool")], "{names:?}");
    let keep = CollisionModel::new(
        &kin,
        Options {
            keep_adjacent: true,
            ..Options::default()
        },
    )
    .unwrap();
    assert_eq!(keep.pair_count(), 5, "every pair of two bodies");
    model.disable("tool", "base").unwrap();
    assert_eq!(model.pair_count(), 1);
    assert_eq!(model.disabled(), [("base".to_string(), "tool".to_string())]);
    assert!(matches!(
        model.disable("base", "nope"),
        Err(CollisionError::Unknown(m)) if m.contains("\"nope\"")
    ));
    // Obstacles: checked against every robot shape, never against each other.
    let table = Shape::Box {
        size: [1.0, 1.0, 0.1],
    };
    model
        .add_obstacle(
            "table",
            &table,
            Se3::from_translation([0.0, 0.0, -1.0].into()),
        )
        .unwrap();
    model
        .add_obstacle(
            "wall",
            &table,
            Se3::from_translation([9.0, 0.0, 0.0].into()),
        )
        .unwrap();
    assert_eq!(model.pair_count(), 1 + 4 * 2);
    assert_eq!(model.obstacles(), ["table", "wall"]);
    assert!(model.remove_obstacle("wall") && !model.remove_obstacle("wall"));
    assert_eq!(model.pair_count(), 1 + 4);
    std::fs::remove_dir_all(&d).unwrap();
}

/// Two spheres of radius 0.1, the slider's at x = s: distance s − 0.2, negative when they
/// overlap, witness points on the x axis, normal +x; `in_collision` and `collisions` agree.
#[test]
fn sphere_sphere() {
    let d = dir("spheres");
    let kin = robot(SPHERE, SPHERE, SMALL, &d);
    let model = CollisionModel::new(&kin, Options::default()).unwrap();
    let mut ws = CollisionWorkspace::new(&kin, &model);
    let k = base_slider(&model);
    let mut out = Vec::new();
    let mut hits = Vec::new();
    for s in [0.5, 0.25, 0.2001, 0.15, 0.05] {
        let q = [0.3, s];
        distances(&model, &mut ws, &kin, &q, &mut out).unwrap();
        let p = out[k];
        assert!((p.distance - (s - 0.2)).abs() < 1e-9, "{s}: {p:?}");
        // The slider's axis turned 0.3 rad about z by the first joint.
        let u = [0.3f64.cos(), 0.3f64.sin(), 0.0];
        for (i, &ui) in u.iter().enumerate() {
            if s > 0.2 {
                assert!((p.point_a[i] - 0.1 * ui).abs() < 1e-9, "{s}: {p:?}");
                assert!((p.point_b[i] - (s - 0.1) * ui).abs() < 1e-9, "{s}: {p:?}");
            }
            assert!((p.normal[i] - ui).abs() < 1e-9, "{s}: {p:?}");
        }
        let colliding = s < 0.2;
        assert_eq!(in_collision(&model, &mut ws, &kin, &q).unwrap(), colliding);
        collisions(&model, &mut ws, &kin, &q, &mut hits).unwrap();
        assert_eq!(hits, if colliding { vec![k] } else { vec![] });
        let m = min_distance(&model, &mut ws, &kin, &q).unwrap().unwrap();
        assert_eq!(m.pair, k);
        assert_eq!(m.distance, p.distance);
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// Each primitive's placement and axis: a box, a cylinder and a capsule along z (URDF's axis,
/// not the engine's y), at an origin with a rotation, against the slider's sphere.
#[test]
fn primitives_keep_urdfs_axes() {
    let d = dir("axes");
    let cases: [(&str, f64, f64); 4] = [
        // (shape, its half extent along x, along z)
        (
            r#"<geometry><box size="0.4 0.6 1.0"/></geometry>"#,
            0.2,
            0.5,
        ),
        (
            r#"<geometry><cylinder radius="0.2" length="1.0"/></geometry>"#,
            0.2,
            0.5,
        ),
        (
            r#"<geometry><capsule radius="0.2" length="1.0"/></geometry>"#,
            0.2,
            0.7,
        ),
        // The same box turned 90° about z, origin shifted 0.1 along x.
        (
            r#"<origin xyz="0.1 0 0" rpy="0 0 1.5707963267948966"/><geometry><box size="0.6 0.4 1.0"/></geometry>"#,
            0.3,
            0.5,
        ),
    ];
    for (base, x_extent, _) in cases {
        let kin = robot(base, SPHERE, SMALL, &d);
        let model = CollisionModel::new(&kin, Options::default()).unwrap();
        let mut ws = CollisionWorkspace::new(&kin, &model);
        let k = base_slider(&model);
        let mut out = Vec::new();
        for s in [0.9, 1.7] {
            distances(&model, &mut ws, &kin, &[0.0, s], &mut out).unwrap();
            let want = s - x_extent - 0.1;
            assert!(
                (out[k].distance - want).abs() < 1e-9,
                "{base} {s}: {:?}",
                out[k]
            );
        }
        // The slider's sphere at the shape's centre: inside.
        distances(&model, &mut ws, &kin, &[0.0, 0.0], &mut out).unwrap();
        assert!(
            out[k].distance < 0.0,
            "{base}: the sphere at the centre is inside"
        );
    }
    // The z extents: the base shape against an obstacle sphere on the z axis, 2 m up.
    for (base, _, z_extent) in cases {
        let kin = robot(base, SPHERE, SMALL, &d);
        let mut model = CollisionModel::new(&kin, Options::default()).unwrap();
        model
            .add_obstacle(
                "ball",
                &Shape::Sphere { radius: 0.25 },
                Se3::from_translation([0.0, 0.0, 2.0].into()),
            )
            .unwrap();
        let mut ws = CollisionWorkspace::new(&kin, &model);
        let mut out = Vec::new();
        distances(&model, &mut ws, &kin, &[0.4, 3.0], &mut out).unwrap();
        let k = (0..model.pair_count())
            .find(|&k| model.pair_names(k) == ("base", "ball"))
            .unwrap();
        assert!(
            (out[k].distance - (2.0 - 0.25 - z_extent)).abs() < 1e-9,
            "{base}: {:?}",
            out[k]
        );
        assert!((out[k].normal[2] - 1.0).abs() < 1e-9);
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// A 0.4 m cube as a binary STL on the base, read exactly and as its hull: the distances of
/// the box primitive.
#[test]
fn a_mesh_is_its_shape() {
    let d = dir("mesh");
    let v = |i: u32| {
        [
            if i & 1 == 0 { -0.2f32 } else { 0.2 },
            if i & 2 == 0 { -0.2 } else { 0.2 },
            if i & 4 == 0 { -0.2 } else { 0.2 },
        ]
    };
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let mut stl = vec![0u8; 80];
    stl.extend_from_slice(&12u32.to_le_bytes());
    for q in quads {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            stl.extend_from_slice(&[0u8; 12]);
            for i in t {
                for x in v(i) {
                    stl.extend_from_slice(&x.to_le_bytes());
                }
            }
            stl.extend_from_slice(&[0u8; 2]);
        }
    }
    std::fs::write(d.join("cube.stl"), &stl).unwrap();
    let kin = robot(
        r#"<geometry><mesh filename="cube.stl"/></geometry>"#,
        SPHERE,
        SMALL,
        &d,
    );
    for mode in [MeshMode::Exact, MeshMode::ConvexHull] {
        let model = CollisionModel::new(
            &kin,
            Options {
                mesh_mode: mode,
                ..Options::default()
            },
        )
        .unwrap();
        let mut ws = CollisionWorkspace::new(&kin, &model);
        let k = base_slider(&model);
        let mut out = Vec::new();
        for s in [0.35, 0.8, -1.3] {
            distances(&model, &mut ws, &kin, &[0.0, s], &mut out).unwrap();
            let want = s.abs() - 0.2 - 0.1;
            assert!(
                (out[k].distance - want).abs() < 1e-6,
                "{mode:?} {s}: {:?}",
                out[k]
            );
        }
        assert!(in_collision(&model, &mut ws, &kin, &[0.0, 0.25]).unwrap());
    }
    std::fs::remove_dir_all(&d).unwrap();
}

/// Batches answer each row as the single call, with 1 and 2 threads alike; a bad row is named
/// and the others answered.
#[test]
fn batches_equal_single_calls() {
    let d = dir("batch");
    let kin = robot(SPHERE, SPHERE, SMALL, &d);
    let model = CollisionModel::new(&kin, Options::default()).unwrap();
    let rows: Vec<[f64; 2]> = (0..200)
        .map(|i| [0.01 * i as f64 - 1.0, 0.004 * i as f64 - 0.4])
        .collect();
    let qs: Vec<f64> = rows.iter().flatten().copied().collect();
    let mut ws = CollisionWorkspace::new(&kin, &model);
    let single: Vec<(bool, f64)> = rows
        .iter()
        .map(|q| {
            (
                in_collision(&model, &mut ws, &kin, q).unwrap(),
                min_distance(&model, &mut ws, &kin, q)
                    .unwrap()
                    .unwrap()
                    .distance,
            )
        })
        .collect();
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (mut hit, mut dist) = (vec![false; rows.len()], vec![0.0; rows.len()]);
        pool.install(|| {
            in_collision_batch(&model, &kin, &qs, &mut hit).unwrap();
            min_distance_batch(&model, &kin, &qs, &mut dist).unwrap();
        });
        for (k, s) in single.iter().enumerate() {
            assert_eq!((hit[k], dist[k].to_bits()), (s.0, s.1.to_bits()), "row {k}");
        }
    }
    assert!(single.iter().any(|s| s.0) && single.iter().any(|s| !s.0));
    let mut bad = qs.clone();
    bad[2 * 7 + 1] = f64::NAN;
    let mut hit = vec![false; rows.len()];
    match in_collision_batch(&model, &kin, &bad, &mut hit) {
        Err(CollisionError::Solve(screwkit_solve::SolveError::Rows(r))) => {
            assert_eq!(r.iter().map(|e| e.row).collect::<Vec<_>>(), [7]);
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(hit[8], single[8].0);
    std::fs::remove_dir_all(&d).unwrap();
}

/// A geometry problem of the file, a missing mesh and an unreadable one: errors naming the
/// link and the file; the kinematics loaded all the same.
#[test]
fn problems_are_named() {
    let d = dir("problems");
    let kin = robot(
        r#"<geometry><box size="1 1"/></geometry>"#,
        SPHERE,
        SMALL,
        &d,
    );
    let e = CollisionModel::new(&kin, Options::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("link \"base\"") && e.contains("<box size>"),
        "{e}"
    );
    let kin = robot(
        r#"<geometry><mesh filename="gone.stl"/></geometry>"#,
        SPHERE,
        SMALL,
        &d,
    );
    let e = CollisionModel::new(&kin, Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("link \"base\"") && e.contains("gone.stl"), "{e}");
    std::fs::write(d.join("junk.stl"), b"solid x\nfacet\n").unwrap();
    let kin = robot(
        r#"<geometry><mesh filename="junk.stl"/></geometry>"#,
        SPHERE,
        SMALL,
        &d,
    );
    let e = CollisionModel::new(&kin, Options::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("link \"base\"") && e.contains("junk.stl"), "{e}");
    // A robot without collision shapes: an empty model, every query answered.
    let tree = screwkit_model::load_tree(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/urdf/ur5.urdf"),
        &XacroOptions::default(),
    )
    .unwrap();
    let ur5 = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    let empty = CollisionModel::new(&ur5, Options::default()).unwrap();
    let mut ws = CollisionWorkspace::new(&ur5, &empty);
    assert_eq!(empty.pair_count(), 0);
    assert!(!in_collision(&empty, &mut ws, &ur5, &[0.0; 6]).unwrap());
    assert!(min_distance(&empty, &mut ws, &ur5, &[0.0; 6])
        .unwrap()
        .is_none());
    std::fs::remove_dir_all(&d).unwrap();
}

/// `min_distance` is the minimum over `distances` (the same pair, the same bits), on the bundled
/// humanoid's primitives at random configurations, most of them with several overlapping pairs
/// (the branch and bound must not stop at the first penetration it meets).
#[test]
fn min_distance_is_the_minimum_of_distances() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/urdf/humanoid.urdf");
    let tree = screwkit_model::load_tree(&path, &XacroOptions::default()).unwrap();
    let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    let model = CollisionModel::new(&kin, Options::default()).unwrap();
    let mut ws = CollisionWorkspace::new(&kin, &model);
    let mut rng = screwkit_solve::sample::SplitMix64(0xB0D1_0001);
    let mut out = Vec::new();
    let mut overlapping = 0;
    for _ in 0..200 {
        let q = screwkit_solve::tree::configuration::random(&kin, &mut rng);
        distances(&model, &mut ws, &kin, &q, &mut out).unwrap();
        let best = out
            .iter()
            .min_by(|a, b| a.distance.total_cmp(&b.distance).then(a.pair.cmp(&b.pair)))
            .unwrap();
        let m = min_distance(&model, &mut ws, &kin, &q).unwrap().unwrap();
        assert_eq!(
            (m.pair, m.distance.to_bits()),
            (best.pair, best.distance.to_bits())
        );
        overlapping += usize::from(out.iter().filter(|d| d.distance < 0.0).count() > 1);
    }
    assert!(overlapping > 50, "{overlapping}");
}
