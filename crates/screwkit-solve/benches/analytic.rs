//! All IK solutions of a pose with the analytic solver, per pose, next to one numerical (LM)
//! solve of the same poses in the same run: the UR5 (bundled) and, when ../shared/xacro is
//! beside the clone, a KUKA KR 16 (spherical wrist). Interleaved rounds, minimum kept.
//! Run: `cargo bench -p screwkit-solve --bench analytic`.

use std::time::Instant;

use screwkit_solve::analytic::solve_all;
use screwkit_solve::ik::{solve, IkOptions};
use screwkit_solve::{fk::fk, Kinematics, Workspace};
use screwkit_testkit::Sampler;

fn bench(name: &str, kin: &Kinematics) {
    let mut ws = Workspace::new(kin);
    let mut rng = Sampler::new(42);
    let targets: Vec<_> = (0..2000)
        .map(|_| fk(kin, &mut ws, &rng.config(kin)).unwrap())
        .collect();
    let (mut best_all, mut best_lm) = (f64::INFINITY, f64::INFINITY);
    let mut branches = 0;
    for _ in 0..5 {
        let t0 = Instant::now();
        for t in &targets {
            let s = solve_all(kin, t).unwrap();
            branches += s.branches;
            std::hint::black_box(&s);
        }
        best_all = best_all.min(t0.elapsed().as_secs_f64() / targets.len() as f64);
        let t0 = Instant::now();
        for t in &targets {
            std::hint::black_box(
                solve(kin, &mut ws, t, &kin.midpoint(), &IkOptions::default()).unwrap(),
            );
        }
        best_lm = best_lm.min(t0.elapsed().as_secs_f64() / targets.len() as f64);
    }
    println!(
        "{name:<8} analytic, all solutions {:7.2} µs/pose ({:.1} postures on average)   numerical LM, one solution {:7.2} µs/pose",
        best_all * 1e6,
        branches as f64 / (5.0 * targets.len() as f64),
        best_lm * 1e6
    );
}

fn main() {
    let ur5 =
        screwkit_model::load_chain(screwkit_testkit::bundled("ur5.urdf"), None, None).unwrap();
    bench("ur5", &Kinematics::new(&ur5));
    let kr16 = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/xacro/expanded/kr16_2.urdf"
    );
    if let Ok(chain) = screwkit_model::load_chain(kr16, Some("base_link"), Some("tool0")) {
        bench("kr16_2", &Kinematics::new(&chain));
    }
}
