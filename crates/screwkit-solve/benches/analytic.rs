//! All IK solutions of a pose with the analytic solver, per pose, next to one numerical (LM)
//! solve of the same poses in the same run: the UR5 and the Panda with joint 7 locked
//! (bundled) and, when ../shared/xacro is beside the clone, a KUKA KR 16 (spherical wrist).
//! Three figures per arm: `postures` (the kernel: every posture, exact or least squares, as
//! IK-Geo and EAIK return them), `solve` (postures deduplicated, each checked by FK, every 2π
//! shift within the limits listed) and one LM solve. Interleaved rounds, minimum kept.
//! Run: `cargo bench -p screwkit-solve --bench analytic`.

use std::time::Instant;

use screwkit_solve::analytic::{AnalyticIk, Postures, Solutions};
use screwkit_solve::ik::{solve, IkOptions};
use screwkit_solve::{fk::fk, Kinematics, Workspace};
use screwkit_testkit::Sampler;

fn bench(name: &str, kin: &Kinematics, solver: &AnalyticIk) {
    let mut ws = Workspace::new(kin);
    let mut rng = Sampler::new(42);
    let lock = solver.locked_joint();
    let cases: Vec<_> = (0..2000)
        .map(|_| {
            let q = rng.config(kin);
            (fk(kin, &mut ws, &q).unwrap(), lock.map_or(0.0, |j| q[j]))
        })
        .collect();
    let (mut best_p, mut best_s, mut best_lm) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let (mut postures, mut solutions) = (0usize, 0usize);
    let mut raw = Postures::default();
    let mut sols = Solutions::default();
    let per = |t0: Instant| t0.elapsed().as_secs_f64() / cases.len() as f64;
    for _ in 0..7 {
        let t0 = Instant::now();
        for (t, v) in &cases {
            solver.postures(t, *v, &mut raw);
            postures += raw.as_slice().len();
        }
        best_p = best_p.min(per(t0));
        let t0 = Instant::now();
        for (t, v) in &cases {
            solver.solve(kin, &mut ws, t, *v, &mut sols).unwrap();
            solutions += sols.len();
        }
        best_s = best_s.min(per(t0));
        let t0 = Instant::now();
        for (t, _) in &cases {
            std::hint::black_box(
                solve(kin, &mut ws, t, &kin.midpoint(), &IkOptions::default()).unwrap(),
            );
        }
        best_lm = best_lm.min(per(t0));
    }
    let rounds = 7.0 * cases.len() as f64;
    println!(
        "{name:<14} postures {:6.3} µs ({:.1}/pose)   solve {:6.3} µs ({:.1} solutions/pose)   LM, one solution {:6.2} µs",
        best_p * 1e6,
        postures as f64 / rounds,
        best_s * 1e6,
        solutions as f64 / rounds,
        best_lm * 1e6
    );
}

fn main() {
    let load = |f: &str| {
        Kinematics::new(
            &screwkit_model::load_chain(screwkit_testkit::bundled(f), None, None).unwrap(),
        )
    };
    let ur5 = load("ur5.urdf");
    bench("ur5", &ur5, &AnalyticIk::new(&ur5).unwrap());
    let panda = load("panda.urdf");
    bench(
        "panda, j7 lock",
        &panda,
        &AnalyticIk::locked(&panda, 6).unwrap(),
    );
    // Joint 5 locked: a spherical wrist only, by subproblem 5 (a quartic).
    bench(
        "panda, j5 lock",
        &panda,
        &AnalyticIk::locked(&panda, 4).unwrap(),
    );
    let kr16 = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/xacro/expanded/kr16_2.urdf"
    );
    if let Ok(chain) = screwkit_model::load_chain(kr16, Some("base_link"), Some("tool0")) {
        let kin = Kinematics::new(&chain);
        bench("kr16_2", &kin, &AnalyticIk::new(&kin).unwrap());
    }
}
