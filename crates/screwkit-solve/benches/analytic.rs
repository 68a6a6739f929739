//! All IK solutions of a pose with the analytic solver, per pose, next to one numerical (LM)
//! solve of the same poses in the same run: the UR5 and the Panda with joint 7 locked
//! (bundled), a general 6R (no special geometry: the algebraic elimination), the iiwa by its
//! arm angle and, when `SCREWKIT_SHARED_XACRO` names the CI data, a KUKA KR 16 (spherical wrist).
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
            let value = match lock {
                Some(j) => q[j],
                None => solver.arm_angle_of(&q).unwrap_or(0.0),
            };
            (fk(kin, &mut ws, &q).unwrap(), value)
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

/// Does the analytic solver help a 7R arm's IK? Same targets (random configurations within
/// the limits), one thread: LM from the midpoint; the analytic solver with joint 7 locked at
/// the seed's (midpoint's) value, nearest solution; the same swept over 8 values of joint 7;
/// and "analytic, else LM" (the locked solve first, LM when it has no solution in limits).
fn seven_r_strategies(kin: &Kinematics, solver: &AnalyticIk) {
    let mut ws = Workspace::new(kin);
    let mut rng = Sampler::new(7);
    let targets: Vec<_> = (0..2000)
        .map(|_| fk(kin, &mut ws, &rng.config(kin)).unwrap())
        .collect();
    let mid = kin.midpoint();
    let j = solver.locked_joint().unwrap();
    let sweep = solver.sweep(kin, 8);
    let mut sols = Solutions::default();
    let opts = IkOptions::default();
    let mut rows: Vec<(&str, f64, usize)> = Vec::new();
    for (name, mode) in [
        ("LM from the midpoint", 0),
        ("analytic, lock at seed", 1),
        ("analytic, 8-value sweep", 2),
        ("analytic, else LM", 3),
    ] {
        let mut best = f64::INFINITY;
        let mut solved = 0;
        for _ in 0..3 {
            solved = 0;
            let t0 = Instant::now();
            for t in &targets {
                let ok = match mode {
                    0 => {
                        solve(kin, &mut ws, t, &mid, &opts)
                            .unwrap()
                            .status
                            .converged
                    }
                    1 | 3 => {
                        solver.solve(kin, &mut ws, t, mid[j], &mut sols).unwrap();
                        let hit = sols.is_exact() && sols.nearest(&mid, None).is_some();
                        hit || (mode == 3
                            && solve(kin, &mut ws, t, &mid, &opts)
                                .unwrap()
                                .status
                                .converged)
                    }
                    _ => {
                        solver
                            .solve_swept(kin, &mut ws, t, &sweep, &mut sols)
                            .unwrap();
                        sols.is_exact()
                    }
                };
                solved += usize::from(ok);
            }
            best = best.min(t0.elapsed().as_secs_f64() / targets.len() as f64);
        }
        rows.push((name, best, solved));
    }
    for (name, t, solved) in rows {
        println!(
            "  panda 7R, {name:<26} {:7.2} µs/target, solved {:5.1} %",
            t * 1e6,
            100.0 * solved as f64 / targets.len() as f64
        );
    }
}

fn main() {
    let load = |f: &str| {
        Kinematics::new(
            &screwkit_model::load_chain(screwkit_testkit::bundled(f), None, None).unwrap(),
        )
    };
    // The general 6R (no two consecutive axes parallel or meeting): a fixed arm of
    // cobot-like offsets, every axis turned off the last.
    let z = [0.0, 0.0, 1.0];
    let general = screwkit_testkit::serial_arm(&[
        ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], z),
        ([0.05, 0.02, 0.27], [1.2, 0.1, 0.0], z),
        ([0.29, 0.03, 0.01], [0.1, 0.3, 0.2], z),
        ([0.08, -0.04, 0.34], [-1.1, 0.2, 0.1], z),
        ([0.02, 0.03, 0.09], [1.3, -0.2, 0.3], z),
        ([0.01, 0.07, 0.05], [-1.2, 0.1, 0.2], z),
    ]);
    bench("general 6R", &general, &AnalyticIk::new(&general).unwrap());
    let ur5 = load("ur5.urdf");
    bench("ur5", &ur5, &AnalyticIk::new(&ur5).unwrap());
    let panda = load("panda.urdf");
    bench(
        "panda, j7 lock",
        &panda,
        &AnalyticIk::locked(&panda, 6).unwrap(),
    );
    seven_r_strategies(&panda, &AnalyticIk::locked(&panda, 6).unwrap());
    // The iiwa by its arm angle (each pose at its own configuration's ψ).
    let iiwa = load("iiwa14.urdf");
    bench(
        "iiwa, arm angle",
        &iiwa,
        &AnalyticIk::arm_angle(&iiwa).unwrap(),
    );
    // Joint 5 locked: a spherical wrist only, by subproblem 5 (a quartic).
    bench(
        "panda, j5 lock",
        &panda,
        &AnalyticIk::locked(&panda, 4).unwrap(),
    );
    // A KUKA KR 16 from the CI data, when SCREWKIT_SHARED_XACRO names it.
    let kr16 = std::env::var_os("SCREWKIT_SHARED_XACRO")
        .map(|d| std::path::Path::new(&d).join("expanded/kr16_2.urdf"));
    if let Some(Ok(chain)) =
        kr16.map(|p| screwkit_model::load_chain(p, Some("base_link"), Some("tool0")))
    {
        let kin = Kinematics::new(&chain);
        bench("kr16_2", &kin, &AnalyticIk::new(&kin).unwrap());
    }
}
