//! The body's queries per configuration on example-robot-data's Panda and UR5 (collision
//! meshes and SRDFs), with the broad phase's share of a collision check and the pairs it
//! leaves to the narrow phase, and a batch of `min_distance` on 2 threads against 1 (each its
//! own rayon pool; `BATCH_REPEAT=k` repeats the configurations k times in the batch). The robot files come from the Python test venv's
//! example-robot-data (`SCREWKIT_ERD_SHARE`: its `cmeel.prefix/share` folder; default: the one
//! `cargo xtask test` makes under target/xtask-venv). Interleaved rounds, minimum kept.
//!
//! Then IK that keeps clear of contact (`ik::solve_clear` with a `ChainClearance`, margin 1 cm)
//! beside a table and a box: 200 targets FK(q*) with q* clear by the margin (the tool over the
//! table), solved one at a time from the midpoint by plain IK, by rejection alone (`steer =
//! false`) and by the default (steering on a redundant chain); targets solved and µs per
//! target, interleaved rounds, minimum kept.
//!
//! Run: `cargo bench -p screwkit-collision --bench body`.

use std::time::Instant;

use screwkit_collision::{
    broad_phase, distances, in_collision, min_distance, min_distance_batch, ChainClearance,
    CollisionModel, CollisionWorkspace, Options,
};
use screwkit_model::{KinematicTree, XacroOptions};
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{self, Clearance, IkOptions};
use screwkit_solve::TreeKinematics;
use screwkit_solve::{Kinematics, Workspace};

fn main() {
    let Some(share) = screwkit_testkit::example_robot_data() else {
        eprintln!(
            "skipped: no example-robot-data (set SCREWKIT_ERD_SHARE, or run cargo xtask test)"
        );
        return;
    };
    println!("host: {}", screwkit_testkit::protocol::host());
    let robots = share.join("example-robot-data/robots");
    for (name, urdf, srdf, tip) in [
        (
            "panda",
            "panda_description/urdf/panda.urdf",
            "panda_description/srdf/panda.srdf",
            "panda_hand",
        ),
        (
            "ur5",
            "ur_description/urdf/ur5_robot.urdf",
            "ur_description/srdf/ur5.srdf",
            "ee_link",
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
        let chain = screwkit_model::load_chain_with(robots.join(urdf), None, Some(tip), &opts);
        ik_clear(name, &Kinematics::new(&chain.unwrap()), &kin, model);
    }
}

/// IK clear of a table and a box (module documentation).
fn ik_clear(name: &str, chain: &Kinematics, kin: &TreeKinematics, mut model: CollisionModel) {
    for (obstacle, size, centre) in [
        ("table", [0.6, 1.2, 0.05], [0.6, 0.0, 0.1]),
        ("box", [0.15, 0.15, 0.15], [0.45, -0.3, 0.35]),
    ] {
        let pose = screwkit_lie::Se3::from_xyz_rpy(centre, [0.0; 3]).unwrap();
        model
            .add_obstacle(
                obstacle,
                &screwkit_model::geometry::Shape::Box { size },
                pose,
            )
            .unwrap();
    }
    let neutral = screwkit_solve::tree::configuration::neutral(kin);
    let steer = ChainClearance::new(&model, kin, chain.names(), neutral, 0.01).unwrap();
    let mut reject = steer.clone();
    reject.steer = false;
    let mut rng = screwkit_solve::sample::SplitMix64(2);
    let mut ws = Workspace::new(chain);
    let mut scratch = steer.scratch();
    let mut q = vec![0.0; chain.dof()];
    let mut targets = Vec::new();
    while targets.len() < 200 {
        screwkit_solve::sample::configuration_into(chain, &mut rng, &mut q);
        let t = fk(chain, &mut ws, &q).unwrap();
        let p = t.translation();
        let over = (0.3..0.9).contains(&p.x) && p.y.abs() < 0.6 && p.z < 0.375;
        if over && steer.is_clear(&mut scratch, &q) {
            targets.push(t);
        }
    }
    let opts = IkOptions::default();
    let seed = chain.midpoint();
    // (µs per target, solved) of plain, rejection, default.
    let mut best = [(f64::MAX, 0usize); 3];
    for _ in 0..3 {
        for (k, best) in best.iter_mut().enumerate() {
            let t0 = Instant::now();
            let mut solved = 0;
            for t in &targets {
                let r = match k {
                    0 => ik::solve(chain, &mut ws, t, &seed, &opts),
                    1 => ik::solve_clear(chain, &mut ws, t, &seed, &opts, &reject, &mut scratch),
                    _ => ik::solve_clear(chain, &mut ws, t, &seed, &opts, &steer, &mut scratch),
                };
                solved += usize::from(r.unwrap().status.converged);
            }
            let us = t0.elapsed().as_secs_f64() / targets.len() as f64 * 1e6;
            *best = (best.0.min(us), solved);
        }
    }
    println!(
        "{name:<6} IK clear of a table and a box (margin 1 cm), {} targets: plain {:.1} µs ({} solved); \
         rejection {:.1} µs ({} solved, {:.1}x plain); default ({}) {:.1} µs ({} solved, {:.1}x plain)",
        targets.len(),
        best[0].0,
        best[0].1,
        best[1].0,
        best[1].1,
        best[1].0 / best[0].0,
        if chain.dof() > 6 { "steering" } else { "rejection: no self-motion" },
        best[2].0,
        best[2].1,
        best[2].0 / best[0].0,
    );
}
