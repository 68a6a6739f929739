//! The body's queries per configuration on example-robot-data's Panda and UR5 (collision
//! meshes and SRDFs), with the broad phase's share of a collision check and the pairs it
//! leaves to the narrow phase, and a batch of `min_distance` on 2 threads against 1 (each its
//! own rayon pool; `BATCH_REPEAT=k` repeats the configurations k times in the batch). The robot files come from the Python test venv's
//! example-robot-data (`SCREWKIT_ERD_SHARE`: its `cmeel.prefix/share` folder; default: the one
//! `cargo xtask test` makes under target/xtask-venv). Interleaved rounds, minimum kept.
//! Run: `cargo bench -p screwkit-collision --bench body`.

use std::path::PathBuf;
use std::time::Instant;

use screwkit_collision::{
    broad_phase, distances, in_collision, min_distance, min_distance_batch, CollisionModel,
    CollisionWorkspace, Options,
};
use screwkit_model::{KinematicTree, XacroOptions};
use screwkit_solve::TreeKinematics;

fn share() -> Option<PathBuf> {
    if let Some(s) = std::env::var_os("SCREWKIT_ERD_SHARE") {
        return Some(PathBuf::from(s));
    }
    let venv = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../target/xtask-venv/lib");
    std::fs::read_dir(venv)
        .ok()?
        .filter_map(|e| e.ok())
        .find_map(|e| {
            let p = e.path().join("site-packages/cmeel.prefix/share");
            p.join("example-robot-data").is_dir().then_some(p)
        })
}

fn main() {
    let Some(share) = share() else {
        eprintln!(
            "skipped: no example-robot-data (set SCREWKIT_ERD_SHARE, or run cargo xtask test)"
        );
        return;
    };
    println!("host: {}", screwkit_testkit::protocol::host());
    let robots = share.join("example-robot-data/robots");
    for (name, urdf, srdf) in [
        (
            "panda",
            "panda_description/urdf/panda.urdf",
            "panda_description/srdf/panda.srdf",
        ),
        (
            "ur5",
            "ur_description/urdf/ur5_robot.urdf",
            "ur_description/srdf/ur5.srdf",
        ),
    ] {
        let opts = XacroOptions {
            package_paths: vec![share.clone()],
            ..Default::default()
        };
        let tree = screwkit_model::load_tree(robots.join(urdf), &opts).unwrap();
        let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
        let mut model = CollisionModel::new(&kin, Options::default()).unwrap();
        model
            .apply_srdf(&screwkit_model::srdf::read_file(&robots.join(srdf)).unwrap())
            .unwrap();
        let mut ws = CollisionWorkspace::new(&kin, &model);
        let mut rng = screwkit_solve::sample::SplitMix64(1);
        let qs: Vec<Vec<f64>> = (0..200)
            .map(|_| screwkit_solve::tree::configuration::random(&kin, &mut rng))
            .collect();
        let survivors: usize = qs
            .iter()
            .map(|q| broad_phase(&model, &mut ws, &kin, q).unwrap())
            .sum();
        let per = |t0: Instant| t0.elapsed().as_secs_f64() / qs.len() as f64 * 1e6;
        let (mut broad, mut check, mut dist, mut min) = (f64::MAX, f64::MAX, f64::MAX, f64::MAX);
        let mut out = Vec::new();
        for _ in 0..5 {
            let t0 = Instant::now();
            for q in &qs {
                std::hint::black_box(broad_phase(&model, &mut ws, &kin, q).unwrap());
            }
            broad = broad.min(per(t0));
            let t0 = Instant::now();
            for q in &qs {
                std::hint::black_box(in_collision(&model, &mut ws, &kin, q).unwrap());
            }
            check = check.min(per(t0));
            let t0 = Instant::now();
            for q in &qs {
                distances(&model, &mut ws, &kin, q, &mut out).unwrap();
            }
            dist = dist.min(per(t0));
            let t0 = Instant::now();
            for q in &qs {
                std::hint::black_box(min_distance(&model, &mut ws, &kin, q).unwrap());
            }
            min = min.min(per(t0));
        }
        // The batch on 2 threads against 1 (per row).
        let repeat: usize = std::env::var("BATCH_REPEAT")
            .ok()
            .and_then(|r| r.parse().ok())
            .unwrap_or(1);
        let flat: Vec<f64> = (0..repeat)
            .flat_map(|_| qs.iter().flatten().copied())
            .collect();
        let mut rows = vec![0.0; qs.len() * repeat];
        let mut per_threads = [f64::MAX; 2];
        for _ in 0..5 {
            for (k, threads) in [1usize, 2].into_iter().enumerate() {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let t0 = Instant::now();
                pool.install(|| min_distance_batch(&model, &kin, &flat, &mut rows).unwrap());
                per_threads[k] = per_threads[k].min(per(t0) / repeat as f64);
            }
        }
        println!(
            "{name:<6} batch of {} min_distance, per row: 1 thread {:.1} µs, 2 threads {:.1} µs ({:.2}x)",
            rows.len(),
            per_threads[0],
            per_threads[1],
            per_threads[0] / per_threads[1]
        );
        println!(
            "{name:<6} {} pairs, {:.1} left by the broad phase on average ({:.0} % pruned); \
             check {check:.2} µs (broad phase {broad:.2} µs, {:.0} %), distances {dist:.0} µs, \
             min_distance {min:.0} µs",
            model.pair_count(),
            survivors as f64 / qs.len() as f64,
            100.0 * (1.0 - survivors as f64 / (qs.len() * model.pair_count()) as f64),
            100.0 * broad / check,
        );
    }
}
