//! screwkit side by side with the Rust crate `k` 0.32 on identical inputs, in one run, so every
//! figure is a ratio measured under the same conditions: FK of the tip, FK + Jacobian, and the
//! IK protocol (success at 1e-5 rad / 1e-5 m by independent FK, within limits, 5 ms cap) on the
//! bundled UR5-, Panda- and iiwa-class arms.
//!
//! `k` gets the same URDF, the same joint values, the same targets and the same initial guess;
//! its IK runs with tolerances 1e-5 m / 1e-5 rad, the default step multiplier 0.5 and 100
//! tries per call, called again from random configurations until the 5 ms budget runs out
//! (the same restart policy screwkit applies internally).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{BenchmarkId, Criterion};
use k::InverseKinematicsSolver;
use screwkit_lie::Se3;
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{solve, IkOptions};
use screwkit_solve::jacobian::fk_jacobian;
use screwkit_solve::{Frame, Kinematics, Workspace};

/// The tip pose with a fresh workspace (for checks, not timed).
fn tip_pose(kin: &Kinematics, q: &[f64]) -> Se3 {
    fk(kin, &mut Workspace::new(kin), q).unwrap()
}

const ROBOTS: &[(&str, &str)] = &[
    ("ur5", "tool0"),
    ("panda", "panda_hand_tcp"),
    ("iiwa14", "iiwa_link_ee"),
];

fn path(name: &str) -> String {
    format!(
        "{}/../../assets/urdf/{name}.urdf",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn ours(name: &str) -> Kinematics {
    Kinematics::new(&screwkit_model::load_chain(path(name), None, None).unwrap())
}

fn theirs(name: &str, tip: &str) -> k::SerialChain<f64> {
    let chain = k::Chain::<f64>::from_urdf_file(path(name)).unwrap();
    let node = chain.find_link(tip).unwrap();
    k::SerialChain::from_end(node)
}

fn configs(kin: &Kinematics, rows: usize, seed: u64) -> Vec<Vec<f64>> {
    screwkit_solve::sample::configurations(kin, rows, seed)
        .chunks(kin.dof())
        .map(<[f64]>::to_vec)
        .collect()
}

fn k_pose(arm: &k::SerialChain<f64>) -> Se3 {
    let t = arm.end_transform();
    let m = t.to_homogeneous();
    let mut v = [0.0; 16];
    for i in 0..4 {
        for j in 0..4 {
            v[4 * i + j] = m[(i, j)];
        }
    }
    Se3::from_row_major(&v, 1e-9).unwrap()
}

fn to_k(t: &Se3) -> k::Isometry3<f64> {
    let q = t.quaternion();
    let p = t.translation();
    k::Isometry3::from_parts(
        k::Translation3::new(p.x, p.y, p.z),
        k::UnitQuaternion::from_quaternion(k::nalgebra::Quaternion::new(q[3], q[0], q[1], q[2])),
    )
}

fn errors(t: &Se3, target: &Se3) -> (f64, f64) {
    let d = t.inverse_compose(target);
    (
        screwkit_lie::so3::log(d.rotation()).norm(),
        (t.translation() - target.translation()).norm(),
    )
}

struct Stats {
    rate: f64,
    mean: f64,
    median: f64,
    p99: f64,
}

fn stats(mut times: Vec<f64>, ok: usize) -> Stats {
    let n = times.len();
    times.sort_by(f64::total_cmp);
    Stats {
        rate: 100.0 * ok as f64 / n as f64,
        mean: times.iter().sum::<f64>() / n as f64,
        median: times[n / 2],
        p99: times[(n * 99) / 100],
    }
}

/// The IK protocol for both libraries on the same targets; prints one table.
fn ik_protocol_side_by_side(queries: usize) {
    println!("IK protocol, {queries} targets per robot, same targets and seeds for both (µs):");
    println!("| robot | library | solved | within limits | mean | median | p99 |");
    println!("|---|---|---|---|---|---|---|");
    for &(name, tip) in ROBOTS {
        let kin = ours(name);
        let arm = theirs(name, tip);
        let mid = kin.midpoint();
        let targets: Vec<Se3> = configs(&kin, queries, 0xC0FF_EE12_3456_789A)
            .iter()
            .map(|q| tip_pose(&kin, q))
            .collect();
        // screwkit
        let mut ws = Workspace::new(&kin);
        let (mut times, mut ok) = (Vec::new(), 0);
        for (i, t) in targets.iter().enumerate() {
            let opts = IkOptions {
                seed: screwkit_solve::batch::row_seed(42, i),
                ..IkOptions::default()
            };
            let t0 = Instant::now();
            let r = solve(&kin, &mut ws, t, &mid, &opts).unwrap();
            times.push(t0.elapsed().as_secs_f64() * 1e6);
            let (er, ep) = errors(&tip_pose(&kin, &r.q), t);
            if er <= 1e-5 && ep <= 1e-5 && kin.within_limits(&r.q, 0.0) {
                ok += 1;
            }
        }
        let s = stats(times, ok);
        println!(
            "| {name} | screwkit (LM) | {:.2} % | always | {:.1} | {:.1} | {:.1} |",
            s.rate, s.mean, s.median, s.p99
        );
        // k: same targets, same initial guess, restarts from random configurations until 5 ms.
        let solver = k::JacobianIkSolver::new(1e-5, 1e-5, 0.5, 100);
        let (mut times, mut ok, mut in_limits) = (Vec::new(), 0, 0);
        let mut restart = configs(&kin, 64, 0x5151_5151_0000_0001).into_iter().cycle();
        for t in &targets {
            let target_k = to_k(t);
            let t0 = Instant::now();
            arm.set_joint_positions_unchecked(&mid);
            let mut solved = solver.solve(&arm, &target_k).is_ok();
            while !solved && t0.elapsed() < Duration::from_millis(5) {
                arm.set_joint_positions_unchecked(&restart.next().unwrap());
                solved = solver.solve(&arm, &target_k).is_ok();
            }
            times.push(t0.elapsed().as_secs_f64() * 1e6);
            let q = arm.joint_positions();
            let (er, ep) = errors(&tip_pose(&kin, &q), t);
            let lim = kin.within_limits(&q, 0.0);
            if er <= 1e-5 && ep <= 1e-5 {
                in_limits += usize::from(lim);
                if lim {
                    ok += 1;
                }
            }
        }
        let s = stats(times, ok);
        println!(
            "| {name} | k 0.32 (JacobianIkSolver) | {:.2} % | {:.2} % of its successes | {:.1} | {:.1} | {:.1} |",
            s.rate,
            100.0 * in_limits as f64 / ok.max(1) as f64,
            s.mean,
            s.median,
            s.p99
        );
    }
    println!();
}

fn benches(c: &mut Criterion) {
    for &(name, tip) in ROBOTS {
        let kin = ours(name);
        let arm = theirs(name, tip);
        let q = configs(&kin, 1, 0x1234_5678_9ABC_DEF1).remove(0);
        // Same answer first: the two libraries agree on FK.
        arm.set_joint_positions_unchecked(&q);
        let diff = k_pose(&arm).max_abs_diff(&tip_pose(&kin, &q));
        assert!(
            diff < 1e-12,
            "{name}: screwkit and k disagree on FK by {diff:e}"
        );
        let mut g = c.benchmark_group(format!("vs_k/{name}"));
        let mut ws = Workspace::new(&kin);
        g.bench_function(BenchmarkId::new("fk_tip", "screwkit"), |b| {
            b.iter(|| fk(&kin, &mut ws, black_box(&q)).unwrap())
        });
        g.bench_function(BenchmarkId::new("fk_tip", "k"), |b| {
            b.iter(|| {
                arm.set_joint_positions_unchecked(black_box(&q));
                arm.end_transform()
            })
        });
        g.bench_function(BenchmarkId::new("fk_and_jacobian", "screwkit"), |b| {
            b.iter(|| {
                fk_jacobian(&kin, &mut ws, black_box(&q), Frame::Space)
                    .unwrap()
                    .pose
            })
        });
        g.bench_function(BenchmarkId::new("fk_and_jacobian", "k"), |b| {
            b.iter(|| {
                arm.set_joint_positions_unchecked(black_box(&q));
                k::jacobian(&arm)
            })
        });
        g.finish();
    }
}

fn main() {
    let queries: usize = std::env::var("SCREWKIT_IK_QUERIES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1000);
    ik_protocol_side_by_side(queries);
    let mut c = Criterion::default().configure_from_args();
    benches(&mut c);
    c.final_summary();
}
