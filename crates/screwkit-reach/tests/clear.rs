//! Maps clear of contact (`build_clear`), and maps without a body keeping the bytes they had
//! before maps could see one.

use screwkit_collision::CollisionModel;
use screwkit_lie::Se3;
use screwkit_model::digest::Digest;
use screwkit_model::geometry::Shape;
use screwkit_reach::{build, build_clear, merge, Body, Plan, ReachSpec, Shard, SolverChoice};
use screwkit_service::{LoadOptions, Robot, Source};

fn tmp(name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("screwkit-reach-clear-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name).to_string_lossy().into_owned()
}

fn digest_of(path: &str) -> String {
    Digest::new().bytes(&std::fs::read(path).unwrap()).hex()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

/// Maps of robots without geometry are the files they were before `--avoid-collisions`
/// existed, byte for byte: the digests of the maps `screwkit reach` wrote at commit 0f2f705
/// (`reach ur5.urdf --resolution 0.2 --orientations 8`, `reach panda.urdf --resolution 0.25
/// --orientations 4`, and its `--shard 1/3`), on 1 and 2 threads.
#[test]
fn maps_without_a_body_keep_their_bytes() {
    let cases = [
        ("ur5.urdf", 0.2, 8, Shard::WHOLE, "0ec8399bcfbba638"),
        ("panda.urdf", 0.25, 4, Shard::WHOLE, "c43595127be64a2b"),
        (
            "panda.urdf",
            0.25,
            4,
            Shard { index: 1, count: 3 },
            "a228cfbaee5cc8ad",
        ),
    ];
    for (file, resolution, orientations, shard, want) in cases {
        let chain =
            screwkit_model::load_chain(screwkit_testkit::bundled(file), None, None).unwrap();
        let kin = screwkit_solve::Kinematics::new(&chain);
        let spec = ReachSpec {
            resolution,
            orientations,
            ..ReachSpec::default()
        };
        let plan = Plan::new(&chain, &kin, &spec).unwrap();
        for threads in [1, 2] {
            let path = tmp(&format!("pinned-{file}-{}-{threads}.npz", shard.index));
            pool(threads)
                .install(|| build(&plan, &kin, shard, &path, |_, _| {}))
                .unwrap();
            assert_eq!(
                digest_of(&path),
                want,
                "{file} shard {shard:?}, {threads} threads"
            );
        }
    }
}

/// The bundled UR5 with a body: a flat box on the base, a sphere at each moving link's
/// origin (the upper arm's would sit on the shoulder's), `spheres` false: only the tool
/// flange's sphere.
fn ur5_with_body(spheres: bool) -> Robot {
    let text = std::fs::read_to_string(screwkit_testkit::bundled("ur5.urdf")).unwrap();
    let shape = |link: &str, geometry: &str| {
        (
            format!("<link name=\"{link}\"/>"),
            format!("<link name=\"{link}\"><collision>{geometry}</collision></link>"),
        )
    };
    let sphere = |r: f64| format!("<geometry><sphere radius=\"{r}\"/></geometry>");
    let mut edits = vec![shape("wrist_3_link", &sphere(0.04))];
    if spheres {
        edits.extend([
            shape(
                "base_link",
                "<origin xyz=\"0 0 0.01\"/><geometry><box size=\"0.2 0.2 0.02\"/></geometry>",
            ),
            shape("shoulder_link", &sphere(0.06)),
            shape("forearm_link", &sphere(0.05)),
            shape("wrist_1_link", &sphere(0.045)),
            shape("wrist_2_link", &sphere(0.045)),
        ]);
    }
    let mut text = text;
    for (from, to) in edits {
        assert!(text.contains(&from), "{from}");
        text = text.replace(&from, &to);
    }
    let path = tmp(&format!("ur5-body-{spheres}.urdf"));
    std::fs::write(&path, text).unwrap();
    Robot::load(&Source::Path(path.into()), &LoadOptions::default()).unwrap()
}

/// The body's collision model with a box obstacle of `size` centred at `centre`.
fn with_box(robot: &Robot, size: [f64; 3], centre: [f64; 3]) -> CollisionModel {
    let mut model = screwkit_service::body::model(robot.whole().unwrap(), None, None).unwrap();
    let pose = Se3::from_parts_unchecked(
        nalgebra::Matrix3::identity(),
        nalgebra::Vector3::from(centre),
    );
    model
        .add_obstacle("block", &Shape::Box { size }, pose)
        .unwrap();
    model
}

fn read_poses(path: &str) -> Vec<f64> {
    let mut z = screwkit_service::io::npz::NpzReader::open(path).unwrap();
    z.f64_array("pose_manipulability").unwrap().1
}

/// A body that can never touch anything (the flange's sphere against a block 100 m away)
/// changes no pose of the map, for the analytic solver and for numerical IK; the metadata
/// names the margin and the body.
#[test]
fn a_body_far_from_everything_changes_no_pose() {
    let robot = ur5_with_body(false);
    let model = with_box(&robot, [1.0, 1.0, 1.0], [100.0, 0.0, 0.0]);
    let (chain, kin) = robot.chain_parts().unwrap();
    for solver in [SolverChoice::Analytic, SolverChoice::Numerical] {
        let numerical = solver == SolverChoice::Numerical;
        let spec = ReachSpec {
            resolution: if numerical { 0.35 } else { 0.2 },
            orientations: if numerical { 3 } else { 8 },
            solver,
            restarts: 2,
            iterations: 60,
            ..ReachSpec::default()
        };
        let plain = tmp(&format!("far-plain-{numerical}.npz"));
        let plan = Plan::new(chain, kin, &spec).unwrap();
        build(&plan, kin, Shard::WHOLE, &plain, |_, _| {}).unwrap();
        let clear_spec = ReachSpec {
            collision_margin: Some(0.01),
            ..spec
        };
        let plan = Plan::new(chain, kin, &clear_spec).unwrap();
        let clear = tmp(&format!("far-clear-{numerical}.npz"));
        let body = Body {
            robot: &robot,
            tree: robot.whole().unwrap(),
            model: &model,
        };
        let s = build_clear(&plan, kin, body, Shard::WHOLE, &clear, |_, _| {}).unwrap();
        assert_eq!(s.collided, 0);
        let (a, b) = (read_poses(&plain), read_poses(&clear));
        assert!(a.iter().any(|x| !x.is_nan()));
        assert_eq!(a.len(), b.len());
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "{solver:?}: a far body changed the map"
        );
        let meta = screwkit_reach::read(&clear).unwrap().meta;
        assert_eq!(meta["spec"]["collision_margin"], 0.01);
        assert_eq!(meta["body"], model.digest());
        let plain_meta = screwkit_reach::read(&plain).unwrap().meta;
        assert!(
            plain_meta.get("body").is_none()
                && plain_meta["spec"].get("collision_margin").is_none()
        );
    }
}

/// A table under the base (its top 5 cm below it, 1 m thick) and the arm's own links: no
/// tool pose whose flange sphere must be inside the table is reached; every pose the plain
/// map reaches and the clear one does not is counted as reached only in contact (the
/// analytic solver's postures all collide), and none the other way; high poses stay
/// reachable. Threads and shards give the same bytes; a shard of the plain map does not merge
/// with the clear one's.
#[test]
fn a_table_and_the_arm_itself() {
    let robot = ur5_with_body(true);
    let model = with_box(&robot, [3.0, 3.0, 1.0], [0.0, 0.0, -0.55]);
    let (chain, kin) = robot.chain_parts().unwrap();
    let spec = ReachSpec {
        resolution: 0.15,
        orientations: 6,
        solver: SolverChoice::Analytic,
        ..ReachSpec::default()
    };
    let plan = Plan::new(chain, kin, &spec).unwrap();
    let plain = tmp("table-plain.npz");
    let p = build(&plan, kin, Shard::WHOLE, &plain, |_, _| {}).unwrap();
    let clear_plan = Plan::new(
        chain,
        kin,
        &ReachSpec {
            collision_margin: Some(0.0),
            ..spec.clone()
        },
    )
    .unwrap();
    let body = Body {
        robot: &robot,
        tree: robot.whole().unwrap(),
        model: &model,
    };
    let clear = tmp("table-clear.npz");
    let c = pool(1)
        .install(|| build_clear(&clear_plan, kin, body, Shard::WHOLE, &clear, |_, _| {}))
        .unwrap();
    assert_eq!(c.collided, p.reached - c.reached, "{p:?} {c:?}");
    assert!(c.collided > 0 && c.reached > 0, "{c:?}");
    let (a, b) = (read_poses(&plain), read_poses(&clear));
    let k = spec.orientations;
    let (mut deep, mut high) = (0, 0);
    for (v, (pa, pb)) in a.chunks(k).zip(b.chunks(k)).enumerate() {
        let z = plan.grid.centre(v)[2];
        for (x, y) in pa.iter().zip(pb) {
            // Clear ⊆ plain, its best manipulability over fewer postures.
            if !y.is_nan() {
                assert!(!x.is_nan() && *y <= *x, "voxel {v}: {y} > {x}");
            }
            // The flange's sphere reaches 0.0823 + 0.04 m from the tool frame.
            if z < -0.05 - 0.0823 - 0.04 - 1e-9 {
                assert!(y.is_nan(), "voxel {v} at z = {z} reached through the table");
                deep += usize::from(!x.is_nan());
            }
            if z > 0.3 {
                high += usize::from(!y.is_nan());
            }
        }
    }
    assert!(deep > 100 && high > 100, "deep {deep}, high {high}");

    let two = tmp("table-clear-2.npz");
    pool(2)
        .install(|| build_clear(&clear_plan, kin, body, Shard::WHOLE, &two, |_, _| {}))
        .unwrap();
    assert_eq!(digest_of(&two), digest_of(&clear));
    let mut shards = Vec::new();
    for i in [1, 0] {
        let s = tmp(&format!("table-shard{i}.npz"));
        build_clear(
            &clear_plan,
            kin,
            body,
            Shard { index: i, count: 2 },
            &s,
            |_, _| {},
        )
        .unwrap();
        shards.push(s);
    }
    let merged = tmp("table-merged.npz");
    merge(&shards, &merged).unwrap();
    assert_eq!(digest_of(&merged), digest_of(&clear));
    let plain_half = tmp("table-plain-shard0.npz");
    build(
        &plan,
        kin,
        Shard { index: 0, count: 2 },
        &plain_half,
        |_, _| {},
    )
    .unwrap();
    let e = merge(&[plain_half, shards[0].clone()], &merged)
        .unwrap_err()
        .to_string();
    assert!(e.contains("another map"), "{e}");
    // Another body (the table 1 cm lower) is another map too.
    let lower = with_box(&robot, [3.0, 3.0, 1.0], [0.0, 0.0, -0.56]);
    let other = tmp("table-lower-shard1.npz");
    let body = Body {
        model: &lower,
        ..body
    };
    build_clear(
        &clear_plan,
        kin,
        body,
        Shard { index: 1, count: 2 },
        &other,
        |_, _| {},
    )
    .unwrap();
    let half = tmp("table-clear-shard0.npz");
    std::fs::copy(&shards[1], &half).unwrap();
    let e = merge(&[half, other], &merged).unwrap_err().to_string();
    assert!(e.contains("another map"), "{e}");
}

/// A spec clear of contact needs a body, and a body needs two shapes to keep apart.
#[test]
fn a_clear_map_needs_a_body() {
    let bare = Robot::load(
        &Source::Path(screwkit_testkit::bundled("ur5.urdf").into()),
        &LoadOptions::default(),
    )
    .unwrap();
    let (chain, kin) = bare.chain_parts().unwrap();
    let spec = ReachSpec {
        resolution: 0.4,
        orientations: 2,
        collision_margin: Some(0.0),
        ..ReachSpec::default()
    };
    let plan = Plan::new(chain, kin, &spec).unwrap();
    let out = tmp("needs-body.npz");
    let e = build(&plan, kin, Shard::WHOLE, &out, |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("body"), "{e}");
    let model = screwkit_service::body::model(bare.whole().unwrap(), None, None).unwrap();
    let body = Body {
        robot: &bare,
        tree: bare.whole().unwrap(),
        model: &model,
    };
    let e = build_clear(&plan, kin, body, Shard::WHOLE, &out, |_, _| {})
        .unwrap_err()
        .to_string();
    assert!(e.contains("no pair of shapes"), "{e}");
    assert!(!std::path::Path::new(&out).exists());
}
