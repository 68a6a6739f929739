//! The whole tree, next to Pinocchio's C++ (`benches/peer/run_pinocchio.sh`, same protocol):
//! every frame's pose (`tree::fk::fk_frames`, Pinocchio's `forwardKinematics` +
//! `updateFramePlacements`) and one frame's world-aligned Jacobian
//! (`tree::jacobian::frame_jacobian`, Pinocchio's `computeFrameJacobian(…,
//! LOCAL_WORLD_ALIGNED)`), in ns per call: the minimum over 30 rounds of 20,000 calls on 256
//! random configurations, one thread. Then one whole-body control step (`differential_ik::ik_step`,
//! the problem of `benchmarks/whole_body_bench.py`) and its box-constrained QP alone.
//!
//! `cargo bench -p screwkit-solve --bench tree -- URDF FRAME` (default: TALOS from the CI data,
//! `$SCREWKIT_SHARED_URDF/trees`, and its left gripper's base link; example-robot-data's
//! `talos_full_v2.urdf` is the same file).

use std::hint::black_box;
use std::time::Instant;

use screwkit_model::{urdf, KinematicTree};
use screwkit_solve::linalg::box_qp::{self, BoxQpWorkspace};
use screwkit_solve::sample::SplitMix64;
use screwkit_solve::tree::differential_ik::{self, DiffIkWorkspace, Limits};
use screwkit_solve::tree::tasks::Task;
use screwkit_solve::tree::{configuration, fk, jacobian};
use screwkit_solve::{JacobianKind, TreeKinematics, TreeWorkspace};

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    // TALOS: a path given, or the CI data's copy (SCREWKIT_SHARED_URDF).
    let Some(path) = args.first().cloned().or_else(|| {
        std::env::var("SCREWKIT_SHARED_URDF")
            .ok()
            .map(|d| format!("{d}/trees/talos_full_v2.urdf"))
    }) else {
        eprintln!(
            "tree bench: give a whole-robot URDF (TALOS: pip install example-robot-data) after \
             `--`, or set SCREWKIT_SHARED_URDF; nothing measured"
        );
        return;
    };
    let frame = args
        .get(1)
        .cloned()
        .unwrap_or_else(|| "gripper_left_base_link".into());
    let tree = urdf::load_file(&path).expect("the URDF");
    let model = KinematicTree::from_tree(&tree).expect("a tree");
    let kin = TreeKinematics::new(&model).expect("prepared");
    let f = kin.frame(&frame).expect("the frame");
    let mut ws = TreeWorkspace::new(&kin);
    let mut rng = SplitMix64(1);
    let qs: Vec<Vec<f64>> = (0..256)
        .map(|_| configuration::random(&kin, &mut rng))
        .collect();
    let (mut best_fk, mut best_j) = (f64::INFINITY, f64::INFINITY);
    let calls = 20_000;
    for _ in 0..30 {
        let t0 = Instant::now();
        for k in 0..calls {
            let p = fk::fk_frames(&kin, &mut ws, &qs[k % 256]).unwrap();
            black_box(p[f].translation()[0]);
        }
        let t1 = Instant::now();
        for k in 0..calls {
            let j = jacobian::frame_jacobian(
                &kin,
                &mut ws,
                &qs[k % 256],
                f,
                JacobianKind::WorldAligned,
            )
            .unwrap();
            black_box(j[(0, 0)]);
        }
        let t2 = Instant::now();
        best_fk = best_fk.min((t1 - t0).as_nanos() as f64 / calls as f64);
        best_j = best_j.min((t2 - t1).as_nanos() as f64 / calls as f64);
    }
    // The same frame's chain alone (root → frame), the kernel the tree's Jacobian runs.
    let chain = model.chain_to(f).expect("a chain").expect("not the root");
    let ck = screwkit_solve::Kinematics::new(&chain);
    let mut cws = screwkit_solve::Workspace::new(&ck);
    let cqs: Vec<Vec<f64>> = (0..256)
        .map(|_| screwkit_solve::sample::configurations(&ck, 1, rng.next_u64()))
        .collect();
    let mut best_chain = f64::INFINITY;
    for _ in 0..30 {
        let t0 = Instant::now();
        for k in 0..calls {
            let j = screwkit_solve::jacobian::jacobian(
                &ck,
                &mut cws,
                &cqs[k % 256],
                screwkit_solve::Frame::Space,
            )
            .unwrap();
            black_box(j[(0, 0)]);
        }
        best_chain = best_chain.min(t0.elapsed().as_nanos() as f64 / calls as f64);
    }
    println!(
        "CHAIN root→{frame}: {} variables, {} joints, space Jacobian {best_chain:.1} ns",
        ck.dof(),
        chain.joints.len()
    );
    println!(
        "SCREWKIT joints={} frames={} nq={} all_frames_fk_ns={best_fk:.1} frame_jacobian_ns={best_j:.1}",
        model.joints.len(),
        kin.frame_count(),
        kin.nq()
    );
    dynamics_calls(&kin, &qs);
    whole_body_step(&kin, &mut rng);
}

/// Inverse dynamics, gravity, the mass matrix and forward dynamics (Pinocchio's `rnea`,
/// `computeGeneralizedGravity`, `crba`, `aba`) on the same configurations, v and a (or τ) of
/// 0.1 and 0.2 rad/s(²) in every entry.
fn dynamics_calls(kin: &TreeKinematics, qs: &[Vec<f64>]) {
    use screwkit_solve::tree::dynamics::{self, Dynamics, DynamicsWorkspace};
    let d = Dynamics::new(kin, true).expect("the inertias");
    let mut ws = DynamicsWorkspace::new(&d);
    let (v, a) = (vec![0.1; kin.nv()], vec![0.2; kin.nv()]);
    let mut best = [f64::INFINITY; 6];
    let calls = 20_000;
    for _ in 0..30 {
        let mut t = Instant::now();
        let mut lap = |k: usize, t: &mut Instant| {
            let now = Instant::now();
            best[k] = best[k].min((now - *t).as_nanos() as f64 / calls as f64);
            *t = now;
        };
        for k in 0..calls {
            black_box(dynamics::inverse_dynamics(&d, &mut ws, &qs[k % 256], &v, &a).unwrap()[0]);
        }
        lap(0, &mut t);
        for k in 0..calls {
            black_box(dynamics::gravity(&d, &mut ws, &qs[k % 256]).unwrap()[0]);
        }
        lap(1, &mut t);
        for k in 0..calls {
            black_box(dynamics::mass_matrix(&d, &mut ws, &qs[k % 256]).unwrap()[(0, 0)]);
        }
        lap(2, &mut t);
        for k in 0..calls {
            black_box(dynamics::forward_dynamics(&d, &mut ws, &qs[k % 256], &v, &a).unwrap()[0]);
        }
        lap(3, &mut t);
        for k in 0..calls {
            black_box(dynamics::aba(&d, &mut ws, &qs[k % 256], &v, &a).map_or(0.0, |x| x[0]));
        }
        lap(4, &mut t);
        for k in 0..calls {
            let fd = dynamics::forward_dynamics_tip(&d, &mut ws, &qs[k % 256], &v, &a, &[0.0; 6]);
            black_box(fd.unwrap()[0]);
        }
        lap(5, &mut t);
    }
    println!(
        "SCREWKIT dynamics nv={} rnea_ns={:.1} gravity_ns={:.1} crba_ns={:.1} aba_ns={:.1} (articulated-body {:.1}, M + Cholesky {:.1})",
        kin.nv(),
        best[0],
        best[1],
        best[2],
        best[3],
        best[4],
        best[5]
    );
}

/// One whole-body control step (`differential_ik::ik_step`: two grippers' poses + posture +
/// damping, position and velocity limits, dt = 0.01, as `benchmarks/whole_body_bench.py` in
/// Python) from the middle of the limits, and its box-constrained QP alone.
fn whole_body_step(kin: &TreeKinematics, rng: &mut SplitMix64) {
    let hands = ["gripper_left_base_link", "gripper_right_base_link"];
    let Ok(frames) = hands
        .iter()
        .map(|h| kin.frame(h))
        .collect::<Result<Vec<_>, _>>()
    else {
        return;
    };
    let mut ws = TreeWorkspace::new(kin);
    let (lower, upper) = (kin.lower(), kin.upper());
    let mid: Vec<f64> = configuration::neutral(kin)
        .iter()
        .enumerate()
        .map(|(i, x)| x.clamp(lower[i], upper[i]))
        .collect();
    // Targets: FK of q* at 0.3–0.7 of every joint's range (reachable, away from the limits).
    let star: Vec<f64> = (0..kin.nq())
        .map(|i| lower[i] + (upper[i] - lower[i]) * (0.3 + 0.4 * rng.uniform()))
        .collect();
    let poses = fk::fk_frames(kin, &mut ws, &star).unwrap().to_vec();
    let mut tasks: Vec<Task> = frames.iter().map(|&f| Task::frame(f, poses[f])).collect();
    tasks.push(Task::posture(mid.clone()).with_weight(1e-2));
    tasks.push(Task::damping(1e-6));
    let limits = Limits::default();
    let mut dws = DiffIkWorkspace::new(kin);
    let (mut best_step, mut best_qp) = (f64::INFINITY, f64::INFINITY);
    let calls = 2_000;
    let mut qp = BoxQpWorkspace::new();
    let mut x = vec![0.0; kin.nv()];
    for _ in 0..30 {
        let t0 = Instant::now();
        for _ in 0..calls {
            let v = differential_ik::ik_step(kin, &mut dws, &mid, &tasks, 0.01, &limits).unwrap();
            black_box(v[0]);
        }
        let t1 = Instant::now();
        let (h, c, l, u) = dws.qp();
        for _ in 0..calls {
            box_qp::solve(&mut qp, h, c, l, u, &mut x).unwrap();
            black_box(x[0]);
        }
        let t2 = Instant::now();
        best_step = best_step.min((t1 - t0).as_nanos() as f64 / calls as f64);
        best_qp = best_qp.min((t2 - t1).as_nanos() as f64 / calls as f64);
    }
    let (h, c, l, u) = dws.qp();
    let info = box_qp::solve(&mut qp, h, c, l, u, &mut x).unwrap();
    println!(
        "SCREWKIT whole_body ik_step_ns={best_step:.0} box_qp_ns={best_qp:.0} nv={} qp_iterations={} active={}",
        kin.nv(),
        info.iterations,
        info.active
    );
}
