//! Reachability maps: the same bytes whatever the thread count or sharding, agreement with an
//! independent IK (numerical, checked by FK) pose by pose, and errors that name the file.

use screwkit_lie::Se3;
use screwkit_reach::{build, merge, OrientationMode, Plan, ReachSpec, Shard, SolverChoice};
use screwkit_service::io::npz::NpzReader;
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{solve, IkOptions};
use screwkit_solve::jacobian::jacobian;
use screwkit_solve::{Frame, Kinematics, Workspace};

fn load(file: &str) -> (screwkit_model::Chain, Kinematics) {
    let chain = screwkit_model::load_chain(screwkit_testkit::bundled(file), None, None).unwrap();
    let kin = Kinematics::new(&chain);
    (chain, kin)
}

fn tmp(name: &str) -> String {
    let dir = std::env::temp_dir().join(format!("screwkit-reach-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name).to_string_lossy().into_owned()
}

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

/// Builds `shard` of `plan` on `threads` threads into `name`; its bytes.
fn bytes_of(plan: &Plan, kin: &Kinematics, shard: Shard, threads: usize, name: &str) -> Vec<u8> {
    let path = tmp(name);
    pool(threads)
        .install(|| build(plan, kin, shard, &path, |_, _| {}))
        .unwrap();
    std::fs::read(&path).unwrap()
}

/// The unsharded map is the same file on 1 and 2 threads, and 3 shards (merged in any order)
/// give that file byte for byte — for the analytic solver (UR5) and numerical IK (Panda).
#[test]
fn shards_and_threads_give_the_same_file() {
    for (file, spec) in [
        (
            "ur5.urdf",
            ReachSpec {
                resolution: 0.2,
                orientations: 12,
                ..ReachSpec::default()
            },
        ),
        (
            "panda.urdf",
            ReachSpec {
                resolution: 0.35,
                orientations: 4,
                restarts: 1,
                iterations: 60,
                ..ReachSpec::default()
            },
        ),
    ] {
        let (chain, kin) = load(file);
        let plan = Plan::new(&chain, &kin, &spec).unwrap();
        let one = bytes_of(&plan, &kin, Shard::WHOLE, 1, &format!("{file}-1.npz"));
        let two = bytes_of(&plan, &kin, Shard::WHOLE, 2, &format!("{file}-2.npz"));
        assert!(one == two, "{file}: 1 and 2 threads differ");
        let mut shards = Vec::new();
        for i in [2, 0, 1] {
            let name = format!("{file}-shard{i}.npz");
            bytes_of(&plan, &kin, Shard { index: i, count: 3 }, 2, &name);
            shards.push(tmp(&name));
        }
        let merged = tmp(&format!("{file}-merged.npz"));
        let s = merge(&shards, &merged).unwrap();
        assert_eq!(s.voxels, plan.grid.len());
        assert!(
            std::fs::read(&merged).unwrap() == one,
            "{file}: merged ≠ unsharded"
        );
        let map = screwkit_reach::read(&merged).unwrap();
        assert!(map.index.iter().all(|x| (0.0..=1.0).contains(x)));
        assert!(
            map.index.iter().any(|&x| x > 0.0),
            "{file}: nothing reached"
        );
        assert_eq!(
            plan.solver_name(),
            if file == "ur5.urdf" {
                "analytic"
            } else {
                "numerical"
            }
        );
    }
}

/// Pose by pose against numerical IK (many restarts, every answer checked by FK and the
/// limits): a pose numerical IK reaches is reached in the map, and its manipulability is at
/// most the map's best for that pose (the map takes the best of every posture); a pose
/// the map reaches is reached by numerical IK in most cases (it finds one posture of several).
#[test]
fn the_map_agrees_with_numerical_ik() {
    let (chain, kin) = load("ur5.urdf");
    let spec = ReachSpec {
        resolution: 0.15,
        orientations: 10,
        ..ReachSpec::default()
    };
    let plan = Plan::new(&chain, &kin, &spec).unwrap();
    let path = tmp("agree.npz");
    build(&plan, &kin, Shard::WHOLE, &path, |_, _| {}).unwrap();
    let mut z = NpzReader::open(&path).unwrap();
    let (shape, pose) = z.f64_array("pose_manipulability").unwrap();
    assert_eq!(shape, vec![plan.grid.len(), 10]);
    let (_, rot) = z.f64_array("orientations").unwrap();
    let opts = IkOptions {
        max_restarts: 30,
        ..IkOptions::default()
    };
    let mut ws = Workspace::new(&kin);
    let (mut both, mut map_only, mut checked) = (0, 0, 0);
    for v in (0..plan.grid.len()).step_by(37) {
        for k in (v % 3..10).step_by(3) {
            let c = plan.grid.centre(v);
            let r = &rot[9 * k..9 * k + 9];
            let mut m = [0.0; 16];
            for i in 0..3 {
                m[4 * i..4 * i + 3].copy_from_slice(&r[3 * i..3 * i + 3]);
                m[4 * i + 3] = c[i];
            }
            m[15] = 1.0;
            let target = Se3::from_row_major(&m, 1e-9).unwrap();
            let o = IkOptions {
                seed: (v * 10 + k) as u64,
                ..opts.clone()
            };
            let got = solve(&kin, &mut ws, &target, &kin.midpoint(), &o).unwrap();
            let in_map = pose[v * 10 + k];
            checked += 1;
            if got.status.converged {
                let t = fk(&kin, &mut ws, &got.q).unwrap();
                assert!(t.max_abs_diff(&target) < 1e-7 && kin.within_limits(&got.q, 1e-9));
                assert!(
                    !in_map.is_nan(),
                    "voxel {v} orientation {k}: numerical IK reaches it, the map does not"
                );
                let j = jacobian(&kin, &mut ws, &got.q, Frame::Space).unwrap();
                let mut row_major = vec![0.0; 36];
                screwkit_solve::batch::write_jacobian(j, &mut row_major);
                let w = screwkit_solve::analysis::manipulability(&row_major, 6);
                assert!(w <= in_map + 1e-9, "{w} > {in_map}");
                both += 1;
            } else if !in_map.is_nan() {
                map_only += 1;
            }
        }
    }
    assert!(checked > 400 && both > 50, "{checked} {both}");
    assert!(
        map_only * 10 <= both,
        "numerical IK missed {map_only} of {} reached poses",
        both + map_only
    );
}

/// Capability-map orientations: the tool's z axis points at the voxel centre from K
/// directions; the orientations entry holds them.
#[test]
fn directions_mode() {
    let (chain, kin) = load("ur5.urdf");
    let spec = ReachSpec {
        resolution: 0.3,
        orientations: 16,
        mode: OrientationMode::Directions,
        solver: SolverChoice::Analytic,
        ..ReachSpec::default()
    };
    let plan = Plan::new(&chain, &kin, &spec).unwrap();
    let path = tmp("dirs.npz");
    build(&plan, &kin, Shard::WHOLE, &path, |_, _| {}).unwrap();
    let map = screwkit_reach::read(&path).unwrap();
    assert_eq!(map.meta["spec"]["mode"], "Directions");
    let (_, rot) = NpzReader::open(&path)
        .unwrap()
        .f64_array("orientations")
        .unwrap();
    let mut mean = [0.0; 3];
    for r in rot.chunks(9) {
        for i in 0..3 {
            mean[i] += r[3 * i + 2] / 16.0;
        }
    }
    assert!(mean.iter().all(|m| m.abs() < 0.1), "{mean:?}");
}

/// Bad shards, merges of the wrong files, a chain without a closed form for `analytic`.
#[test]
fn errors_name_what_is_wrong() {
    for bad in ["3/3", "1", "a/b", "0/0", "-1/2"] {
        assert!(Shard::parse(bad).is_err(), "{bad}");
    }
    assert_eq!(Shard::parse("2/5").unwrap(), Shard { index: 2, count: 5 });
    // Voxel ranges of shards cover every voxel once.
    let total = 1001;
    let mut next = 0;
    for i in 0..7 {
        let r = Shard { index: i, count: 7 }.voxels(total);
        assert_eq!(r.start, next);
        next = r.end;
    }
    assert_eq!(next, total);

    let (chain, kin) = load("ur5.urdf");
    let spec = ReachSpec {
        resolution: 0.4,
        orientations: 3,
        ..ReachSpec::default()
    };
    let plan = Plan::new(&chain, &kin, &spec).unwrap();
    let (a, b) = (tmp("e0.npz"), tmp("e1.npz"));
    build(&plan, &kin, Shard { index: 0, count: 2 }, &a, |_, _| {}).unwrap();
    build(&plan, &kin, Shard { index: 1, count: 2 }, &b, |_, _| {}).unwrap();
    let out = tmp("e-out.npz");
    let e = merge(std::slice::from_ref(&a), &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains("1 of 2 shards"), "{e}");
    let e = merge(&[a.clone(), a.clone(), b.clone()], &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains(&a) && e.contains("missing or twice"), "{e}");
    let other = Plan::new(
        &chain,
        &kin,
        &ReachSpec {
            orientations: 4,
            ..spec.clone()
        },
    )
    .unwrap();
    let c = tmp("e-other.npz");
    build(&other, &kin, Shard { index: 1, count: 2 }, &c, |_, _| {}).unwrap();
    let e = merge(&[a.clone(), c.clone()], &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains(&c) && e.contains("another map"), "{e}");
    let not_a_map = tmp("e-text.npz");
    std::fs::write(&not_a_map, "hello").unwrap();
    let e = merge(std::slice::from_ref(&not_a_map), &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains(&not_a_map), "{e}");
    assert!(merge(&[], &out).is_err());

    let (pchain, pkin) = load("panda.urdf");
    let e = Plan::new(
        &pchain,
        &pkin,
        &ReachSpec {
            solver: SolverChoice::Analytic,
            ..spec.clone()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("numerical"), "{e}");
    for bad in [
        ReachSpec {
            resolution: 0.0,
            ..spec.clone()
        },
        ReachSpec {
            orientations: 0,
            ..spec.clone()
        },
        ReachSpec {
            bounds: Some(([0.0, 0.0, 0.0], [-1.0, 1.0, 1.0])),
            ..spec.clone()
        },
    ] {
        assert!(Plan::new(&chain, &kin, &bad).is_err());
    }
}
