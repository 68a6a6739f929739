//! The map builder against the raw batched IK it calls, in one process (interleaved rounds,
//! minimum kept): the same in-reach poses of a UR5 map (0.1 m, 20 orientations) solved by
//! `AnalyticIk::solve_batch` alone (2048 targets a call, as the map), and the whole `build` (targets, solve, one Jacobian and
//! manipulability per posture, .npz streaming); the same for numerical IK (`ik_batch_from`)
//! on the UR5 and the Panda. Prints solves/s on the current pool and the ratio.
//! Run: `cargo bench -p screwkit-reach --bench map_vs_ik [-- THREADS]`.

use std::time::Instant;

use screwkit_reach::{build, Plan, ReachSpec, Shard, SolverChoice};
use screwkit_solve::analytic::AnalyticIk;
use screwkit_solve::batch::ik_batch_from;
use screwkit_solve::ik::{IkOptions, IkStatus};
use screwkit_solve::Kinematics;

fn targets(plan: &Plan) -> Vec<f64> {
    let mut t = Vec::new();
    for v in (0..plan.grid.len()).filter(|&v| plan.in_reach(v)) {
        let c = plan.grid.centre(v);
        for r in &plan.rotations {
            for i in 0..3 {
                t.extend_from_slice(&[r[(i, 0)], r[(i, 1)], r[(i, 2)], c[i]]);
            }
            t.extend_from_slice(&[0.0, 0.0, 0.0, 1.0]);
        }
    }
    t
}

fn case(name: &str, file: &str, solver: SolverChoice) {
    let chain = screwkit_model::load_chain(
        format!("{}/../../assets/urdf/{file}", env!("CARGO_MANIFEST_DIR")),
        None,
        None,
    )
    .unwrap();
    let kin = Kinematics::new(&chain);
    let spec = ReachSpec {
        resolution: 0.1,
        orientations: 20,
        solver,
        ..ReachSpec::default()
    };
    let plan = Plan::new(&chain, &kin, &spec).unwrap();
    let t = targets(&plan);
    let poses = t.len() / 16;
    let path = std::env::temp_dir().join("screwkit-map-bench.npz");
    let path = path.to_string_lossy();
    let n = kin.dof();
    let opts = IkOptions {
        max_iterations: spec.iterations,
        max_restarts: spec.restarts,
        timeout: None,
        ..IkOptions::default()
    };
    let ik = AnalyticIk::new(&kin).ok();
    let (mut raw, mut map) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..5 {
        let t0 = Instant::now();
        match (&ik, plan.solver_name()) {
            (Some(ik), "analytic") => {
                // In batches of 2048 targets, as the map does: one call on all of them would
                // hold every solution list at once (up to 24 KB a pose) and measure the memory.
                for chunk in t.chunks(2048 * 16) {
                    std::hint::black_box(ik.solve_batch(&kin, chunk, None).unwrap());
                }
            }
            _ => {
                let mut q = vec![0.0; poses * n];
                let mut st = vec![IkStatus::unsolved(); poses];
                ik_batch_from(&kin, 0, &t, None, &opts, &mut q, &mut st, None).unwrap();
            }
        }
        raw = raw.min(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        build(&plan, &kin, Shard::WHOLE, &path, |_, _| {}).unwrap();
        map = map.min(t0.elapsed().as_secs_f64());
    }
    println!(
        "{name:<22} {poses} poses on {} threads: raw batched IK {:.0} solves/s, map {:.0} solves/s ({:.0} % of raw)",
        rayon::current_num_threads(),
        poses as f64 / raw,
        poses as f64 / map,
        100.0 * raw / map
    );
}

fn main() {
    let threads: usize = std::env::args()
        .skip(1)
        .find_map(|a| a.parse().ok())
        .unwrap_or(1);
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build_global()
        .unwrap();
    case("ur5 analytic", "ur5.urdf", SolverChoice::Auto);
    case("ur5 numerical", "ur5.urdf", SolverChoice::Numerical);
    case("panda numerical", "panda.urdf", SolverChoice::Numerical);
}
