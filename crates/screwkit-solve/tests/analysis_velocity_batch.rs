//! Singularity analysis against nalgebra's SVD and known singular configurations; joint
//! velocities and torques; batches equal single calls and do not depend on the thread count.

mod common;

use common::{fk1, load, Sampler};
use nalgebra::{DVector, Matrix6xX, Vector6};
use screwkit_lie::{Twist, Wrench};
use screwkit_solve::analysis::{analyze, analyze_jacobian};
use screwkit_solve::batch::{
    fk_all_links_batch, fk_batch, ik_batch, ik_path, jacobian_batch, row_seed,
};
use screwkit_solve::fk::fk_all_links;
use screwkit_solve::ik::{solve, IkOptions, IkStatus, StopReason};
use screwkit_solve::jacobian::{fk_jacobian, jacobian};
use screwkit_solve::velocity::{joint_torques, joint_velocities, VelocitySolver};
use screwkit_solve::{Frame, Kinematics, SolveError, Workspace};

/// J with a fresh workspace, owned.
fn jac(kin: &Kinematics, q: &[f64], frame: Frame) -> Matrix6xX<f64> {
    jacobian(kin, &mut Workspace::new(kin), q, frame)
        .unwrap()
        .clone()
}

#[test]
fn analysis_matches_nalgebra_svd() {
    let mut rng = Sampler::new(21);
    for file in ["ur5.urdf", "panda.urdf", "planar_3r.urdf"] {
        let (_, _, kin) = load(file, None, None);
        for _ in 0..20 {
            let q = rng.config(&kin);
            let j = jac(&kin, &q, Frame::Space);
            let a = analyze(&kin, &mut Workspace::new(&kin), &q, Frame::Space).unwrap();
            assert_eq!(a, analyze_jacobian(&j).unwrap());
            let mut sv: Vec<f64> = j
                .clone()
                .svd(false, false)
                .singular_values
                .iter()
                .copied()
                .collect();
            sv.sort_by(|x, y| y.total_cmp(x));
            assert_eq!(a.singular_values.len(), sv.len());
            for (x, y) in a.singular_values.iter().zip(&sv) {
                assert!((x - y).abs() < 1e-12, "{file}");
            }
            let jjt = &j * j.transpose();
            let det = jjt.determinant();
            assert!(
                (a.manipulability - det.max(0.0).sqrt()).abs() < 1e-10,
                "{file}"
            );
            // The SVD-free form (row-major J), in the space and the body frame.
            let row_major = |j: &nalgebra::Matrix6xX<f64>| {
                let mut v = vec![0.0; 6 * j.ncols()];
                screwkit_solve::batch::write_jacobian(j, &mut v);
                v
            };
            let n = kin.dof();
            for frame_j in [j.clone(), jac(&kin, &q, Frame::Body)] {
                let w = screwkit_solve::analysis::manipulability(&row_major(&frame_j), n);
                assert!(
                    (w - a.manipulability).abs() <= 1e-9 * a.manipulability.max(1e-3),
                    "{file}: {w} vs {}",
                    a.manipulability
                );
            }
            if kin.dof() == 6 {
                let dj = nalgebra::Matrix6::from_iterator(j.iter().copied()).determinant();
                assert!((a.determinant.unwrap() - dj).abs() < 1e-12);
            }
            // Ellipsoid lengths² are the eigenvalues of J_ω J_ωᵀ / J_v J_vᵀ: their sum is the trace.
            let tr_w: f64 = (0..3).map(|r| j.row(r).norm_squared()).sum();
            let sum: f64 = a.angular.lengths.iter().map(|l| l * l).sum();
            assert!((tr_w - sum).abs() < 1e-10);
        }
    }
}

/// Known singularities: UR5 wrist (q5 = 0: joints 4 and 6 aligned) and elbow (q3 = 0);
/// the lost twist direction is orthogonal to every column.
#[test]
fn known_singularities() {
    let (_, _, kin) = load("ur5.urdf", None, None);
    for q in [
        [0.3, -0.7, 1.2, 0.4, 0.0, 0.2],
        [0.3, -0.7, 0.0, 0.4, 0.5, 0.2],
    ] {
        let j = jac(&kin, &q, Frame::Space);
        let a = analyze_jacobian(&j).unwrap();
        assert_eq!(a.rank, 5, "{:?}", a.singular_values);
        assert!(
            a.verdict().starts_with("singular (rank 5 of 6)"),
            "{}",
            a.verdict()
        );
        assert_eq!(a.lost_directions.len(), 1);
        assert!(a.manipulability < 1e-12);
        // Rank deficient: σ_min is rounding noise, so the condition number is ∞, not 1e16-ish.
        assert_eq!(a.condition_number, f64::INFINITY);
        let u = a.lost_directions[0];
        // Canonical sign: the first component above 1e-9 is positive (the SVD's sign is not).
        assert!(*u.iter().find(|x| x.abs() > 1e-9).unwrap() > 0.0, "{u}");
        for c in j.column_iter() {
            assert!(u.dot(&c).abs() < 1e-12);
        }
    }
    // Generic configuration: full rank.
    let a = analyze_jacobian(&jac(&kin, &[0.3, -0.7, 1.2, 0.4, 0.5, 0.2], Frame::Space)).unwrap();
    assert_eq!(a.rank, 6);
    assert!(
        a.verdict().starts_with("well-conditioned"),
        "{}",
        a.verdict()
    );
    assert!(a.lost_directions.is_empty());
    let s = &a.singular_values;
    assert_eq!(a.condition_number, s[0] / s[5]);
    // Planar 3R: rank 3 of 6 at most (min(6, n)), three lost directions.
    let (_, _, kin3) = load("planar_3r.urdf", None, None);
    let a = analyze_jacobian(&jac(&kin3, &[0.1, 0.5, -0.3], Frame::Space)).unwrap();
    assert!(
        a.verdict().contains("3-joint chain can never produce 3"),
        "{}",
        a.verdict()
    );
    assert_eq!(
        (a.rank, a.lost_directions.len(), a.manipulability),
        (3, 3, 0.0)
    );
}

#[test]
fn joint_velocities_and_torques() {
    let (_, _, kin) = load("ur5.urdf", None, None);
    let mut ws = Workspace::new(&kin);
    let q = [0.3, -0.7, 1.2, 0.4, 0.5, 0.2];
    let j = jac(&kin, &q, Frame::Body);
    let v = Twist::from_vector(&Vector6::new(0.1, -0.2, 0.3, 0.05, 0.02, -0.04));
    let qd = |kin: &Kinematics, q: &[f64], solver| {
        joint_velocities(kin, &mut Workspace::new(kin), q, &v, Frame::Body, solver)
    };
    let exact = qd(&kin, &q, VelocitySolver::Exact).unwrap();
    assert!((&j * &exact - v.to_vector()).amax() < 1e-12);
    let pinv = qd(&kin, &q, VelocitySolver::PseudoInverse { tolerance: None }).unwrap();
    assert!((&pinv - &exact).amax() < 1e-10);
    let dls = qd(&kin, &q, VelocitySolver::Damped { lambda: 1e-6 }).unwrap();
    assert!((&dls - &exact).amax() < 1e-6);
    // Power balance: q̇ᵀτ = Vᵀ F for τ = Jᵀ F.
    let f = Wrench::from_vector(&Vector6::new(1.0, 2.0, -1.0, 10.0, -5.0, 3.0));
    let tau = joint_torques(&kin, &mut ws, &q, &f, Frame::Body).unwrap();
    assert!((exact.dot(&tau) - f.power(&v)).abs() < 1e-12);
    // Redundant arm: pinv gives the minimum-norm solution; exact is refused as bad input.
    let (_, _, panda) = load("panda.urdf", None, None);
    let q7 = [0.1, 0.2, -0.1, -1.5, 0.3, 1.6, 0.2];
    let j7 = jac(&panda, &q7, Frame::Body);
    let e = qd(&panda, &q7, VelocitySolver::Exact).unwrap_err();
    assert!(
        e.is_invalid_input() && e.to_string().contains("6 × 7"),
        "{e}"
    );
    let qd7 = qd(
        &panda,
        &q7,
        VelocitySolver::PseudoInverse { tolerance: None },
    )
    .unwrap();
    assert!((&j7 * &qd7 - v.to_vector()).amax() < 1e-12);
    // The null-space direction: pad J to 7 × 7 with a zero row so nalgebra's (thin) SVD
    // returns a full V, and take the right singular vector of the zero singular value.
    let mut padded = nalgebra::DMatrix::<f64>::zeros(7, 7);
    padded.view_mut((0, 0), (6, 7)).copy_from(&j7);
    let svd = padded.svd(false, true);
    let k = svd.singular_values.imin();
    let n7: DVector<f64> = svd.v_t.unwrap().row(k).transpose().into_owned();
    assert!((&j7 * &n7).amax() < 1e-12);
    assert!(
        qd7.dot(&n7).abs() < 1e-10,
        "minimum norm: no null-space component"
    );
    let e = qd(&panda, &q7, VelocitySolver::Damped { lambda: 0.0 }).unwrap_err();
    assert!(e.is_invalid_input(), "{e}");
    // A singular square Jacobian is a numerical failure, not bad input.
    let wrist = [0.3, -0.7, 1.2, 0.4, 0.0, 0.2];
    let e = qd(&kin, &wrist, VelocitySolver::Exact).unwrap_err();
    assert!(!e.is_invalid_input(), "{e}");
}

/// A row-major 4 × 4 from 16 values.
fn pose_rows(v: &[f64]) -> nalgebra::Matrix4<f64> {
    nalgebra::Matrix4::from_row_slice(v)
}

#[test]
fn batches_equal_single_calls_and_ignore_thread_count() {
    let (_, chain, kin) = load("panda.urdf", None, None);
    let n = kin.dof();
    let mut ws = Workspace::new(&kin);
    let rows = 600;
    let qs = screwkit_solve::sample::configurations(&kin, rows, 4);
    // FK, all-link FK and Jacobians with poses: 1 thread = 2 threads = single calls, bit for bit.
    let links = chain.links.len();
    let run_all = |threads: usize| {
        let (mut p, mut l) = (vec![0.0; rows * 16], vec![0.0; rows * links * 16]);
        let (mut js, mut jp) = (vec![0.0; rows * 6 * n], vec![0.0; rows * 16]);
        let mut jb = vec![0.0; rows * 6 * n];
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                fk_batch(&kin, &qs, &mut p).unwrap();
                fk_all_links_batch(&kin, &qs, &mut l).unwrap();
                jacobian_batch(&kin, &qs, Frame::Space, &mut js, Some(&mut jp)).unwrap();
                jacobian_batch(&kin, &qs, Frame::Body, &mut jb, None).unwrap();
            });
        (p, l, js, jp, jb)
    };
    let one = run_all(1);
    assert_eq!(one, run_all(2));
    let (poses, all, js, jp, jb) = one;
    for k in 0..rows {
        let q = &qs[k * n..(k + 1) * n];
        let t = fk1(&kin, q).unwrap();
        assert_eq!(pose_rows(&poses[16 * k..16 * (k + 1)]), t.to_homogeneous());
        assert_eq!(pose_rows(&jp[16 * k..16 * (k + 1)]), t.to_homogeneous());
        let each = fk_all_links(&kin, &mut ws, q).unwrap();
        for (i, p) in each.iter().enumerate() {
            let o = 16 * (k * links + i);
            assert_eq!(pose_rows(&all[o..o + 16]), p.to_homogeneous());
        }
        let single = fk_jacobian(&kin, &mut ws, q, Frame::Space).unwrap();
        assert_eq!(
            Matrix6xX::from_row_slice(&js[6 * n * k..6 * n * (k + 1)]),
            *single.jacobian
        );
        let body = jac(&kin, q, Frame::Body);
        assert_eq!(
            Matrix6xX::from_row_slice(&jb[6 * n * k..6 * n * (k + 1)]),
            body
        );
    }
    // IK: batch = single calls with the row seeds; 1 thread = 2 threads, bit for bit.
    let targets = poses[..200 * 16].to_vec();
    let opts = IkOptions {
        timeout: None,
        seed: 7,
        ..IkOptions::default()
    };
    let run_ik = |threads: usize| {
        let (mut q, mut st) = (vec![0.0; 200 * n], vec![IkStatus::default(); 200]);
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| ik_batch(&kin, &targets, None, &opts, &mut q, &mut st, None).unwrap());
        (q, st)
    };
    let (q1, st1) = run_ik(1);
    assert_eq!((q1.clone(), st1.clone()), run_ik(2));
    // A batch small enough to be solved in turn on the calling thread gives the same rows.
    let few = screwkit_solve::batch::IK_INLINE_ROWS;
    let (mut q, mut st) = (vec![0.0; few * n], vec![IkStatus::default(); few]);
    ik_batch(
        &kin,
        &targets[..16 * few],
        None,
        &opts,
        &mut q,
        &mut st,
        None,
    )
    .unwrap();
    assert_eq!((&q[..], &st[..]), (&q1[..few * n], &st1[..few]));
    for k in 0..200 {
        let t = screwkit_lie::Se3::from_row_major(&targets[16 * k..16 * (k + 1)], 1e-6).unwrap();
        let single = solve(
            &kin,
            &mut ws,
            &t,
            &kin.midpoint(),
            &IkOptions {
                seed: row_seed(7, k),
                ..opts.clone()
            },
        )
        .unwrap();
        assert_eq!(single.q, q1[k * n..(k + 1) * n]);
        assert_eq!(single.status, st1[k]);
        assert!(st1[k].converged);
    }
}

/// Bad rows fail alone: NaN output, the others computed, an error listing them in order.
#[test]
fn batches_report_bad_rows_and_finish_the_rest() {
    let (_, _, kin) = load("panda.urdf", None, None);
    let n = kin.dof();
    let rows = 700;
    let mut qs = screwkit_solve::sample::configurations(&kin, rows, 9);
    qs[(rows - 3) * n + 2] = f64::INFINITY;
    qs[(rows / 2) * n + 1] = f64::NAN;
    let mut out = vec![0.0; rows * 16];
    let err = fk_batch(&kin, &qs, &mut out).unwrap_err();
    let SolveError::Rows(bad) = &err else {
        panic!("{err}")
    };
    assert_eq!(
        bad.iter().map(|r| r.row).collect::<Vec<_>>(),
        [rows / 2, rows - 3]
    );
    assert!(err.is_invalid_input());
    let msg = err.to_string();
    assert!(
        msg.starts_with(&format!("row {}:", rows / 2))
            && msg.contains(&kin.names()[1])
            && msg.contains("NaN"),
        "{msg}"
    );
    for k in 0..rows {
        let row = &out[16 * k..16 * (k + 1)];
        if k == rows / 2 || k == rows - 3 {
            assert!(row.iter().all(|x| x.is_nan()));
        } else {
            let t = fk1(&kin, &qs[k * n..(k + 1) * n]).unwrap();
            assert_eq!(pose_rows(row), t.to_homogeneous());
        }
    }
    let mut js = vec![0.0; rows * 6 * n];
    assert!(matches!(
        jacobian_batch(&kin, &qs, Frame::Space, &mut js, None),
        Err(SolveError::Rows(r)) if r.len() == 2
    ));
    // Wrong shapes are errors before any work.
    assert!(matches!(
        fk_batch(&kin, &qs[..n + 1], &mut out[..16]),
        Err(SolveError::WrongLength { .. })
    ));
    assert!(matches!(
        fk_batch(&kin, &qs[..2 * n], &mut out[..3 * 16]),
        Err(SolveError::WrongLength { .. })
    ));
    // IK: a target that is not a rigid transform and one with NaN fail alone.
    let good = {
        let t = fk1(&kin, &qs[..n]).unwrap().to_homogeneous();
        (0..16).map(|i| t[(i / 4, i % 4)]).collect::<Vec<f64>>()
    };
    // A batch run in turn on the calling thread and one run on the pool.
    for rows in [3, screwkit_solve::batch::IK_INLINE_ROWS + 5] {
        let mut targets = good.repeat(rows);
        targets[16] = 3.0; // R no longer orthonormal
        targets[32 + 3] = f64::NAN;
        let last = 16 * (rows - 1);
        if rows > 3 {
            targets[last + 15] = 0.5; // bottom row not (0, 0, 0, 1)
        }
        let (mut q, mut st) = (vec![0.0; rows * n], vec![IkStatus::default(); rows]);
        let opts = IkOptions {
            timeout: None,
            ..IkOptions::default()
        };
        let err = ik_batch(&kin, &targets, None, &opts, &mut q, &mut st, None).unwrap_err();
        let SolveError::Rows(bad) = &err else {
            panic!("{err}")
        };
        let want: Vec<usize> = if rows > 3 {
            vec![1, 2, rows - 1]
        } else {
            vec![1, 2]
        };
        assert_eq!(bad.iter().map(|r| r.row).collect::<Vec<_>>(), want);
        assert!(st[0].converged && st[3..rows.max(4) - 1].iter().all(|s| s.converged));
        assert_eq!(st[1].stop, StopReason::InvalidInput);
        assert!(q[n..3 * n].iter().all(|x| x.is_nan()));
        assert!(q[(rows - 1) * n..].iter().all(|x| x.is_nan()) || rows == 3);
    }
}

/// Warm start along a path: each solve starts at the previous solution and takes few
/// iterations.
#[test]
fn warm_started_path() {
    let (_, _, kin) = load("ur5.urdf", None, None);
    let q0 = [0.3, -0.9, 1.2, -0.4, 0.5, 0.2];
    let targets: Vec<_> = (0..50)
        .map(|k| {
            let mut q = q0;
            q[0] += 0.01 * k as f64;
            q[2] -= 0.005 * k as f64;
            fk1(&kin, &q).unwrap()
        })
        .collect();
    let opts = IkOptions {
        timeout: None,
        ..IkOptions::default()
    };
    let res = ik_path(&kin, &mut Workspace::new(&kin), &targets, &q0, &opts).unwrap();
    assert!(res.iter().all(|r| r.status.converged));
    let mean: f64 = res.iter().map(|r| r.status.iterations as f64).sum::<f64>() / res.len() as f64;
    assert!(
        mean < 8.0,
        "warm start should need few iterations, mean {mean}"
    );
    assert!(res.iter().all(|r| r.status.restarts == 0));
}

/// A chain without joints has an empty Jacobian: its verdict says it cannot move.
#[test]
fn a_chain_without_joints_cannot_move() {
    let j = nalgebra::Matrix6xX::<f64>::zeros(0);
    let a = screwkit_solve::analysis::analyze_jacobian(&j).unwrap();
    assert_eq!(a.rank, 0);
    assert_eq!(a.verdict(), "no joints: the tip cannot move");
}

/// The position-only analysis is the SVD of the tip point's velocity Jacobian, checked against
/// central differences of the tip position: manipulability = √det(J_v J_vᵀ); a planar arm
/// has position rank 2 (it cannot leave its plane); a wrist singularity keeps rank 3.
#[test]
fn position_analysis_from_finite_differences() {
    use screwkit_solve::analysis::analyze_position;
    let (_, _, kin) = load("ur5.urdf", None, None);
    let mut ws = Workspace::new(&kin);
    let q = [0.3, -1.0, 1.4, -0.8, -1.2, 0.4];
    let h = 1e-6;
    let mut jv = nalgebra::Matrix3xX::<f64>::zeros(6);
    for k in 0..6 {
        let (mut a, mut b) = (q, q);
        a[k] += h;
        b[k] -= h;
        let d = (fk1(&kin, &a).unwrap().translation() - fk1(&kin, &b).unwrap().translation())
            / (2.0 * h);
        jv.set_column(k, &d);
    }
    let want = (&jv * jv.transpose()).determinant().sqrt();
    let p = analyze_position(&kin, &mut ws, &q).unwrap();
    assert_eq!(p.rank, 3);
    assert!(
        (p.manipulability - want).abs() < 1e-7 * want.max(1.0),
        "{} vs {want}",
        p.manipulability
    );
    assert!(p.condition_number >= 1.0 && p.condition_number.is_finite());
    // The wrist singularity of the CLI snapshot (q5 = 0: axes 4 and 6 parallel).
    let wrist = analyze_position(
        &kin,
        &mut ws,
        &[
            0.0,
            -std::f64::consts::FRAC_PI_2,
            std::f64::consts::FRAC_PI_2,
            0.0,
            0.0,
            0.0,
        ],
    )
    .unwrap();
    assert_eq!(wrist.rank, 3);
    let (_, _, planar) = load("planar_3r.urdf", None, None);
    let pl = analyze_position(&planar, &mut Workspace::new(&planar), &[0.3, 0.6, -0.4]).unwrap();
    assert_eq!((pl.rank, pl.manipulability), (2, 0.0));
    assert!(pl.condition_number.is_infinite());
}

/// The block (structure-of-arrays) FK kernel gives every row bit for bit the single call, on
/// every bundled chain (mimic joints, prismatic joints, general and axis-aligned revolute axes);
/// with a row count that is not a multiple of the block and a bad row inside a block.
#[test]
fn block_fk_equals_single_calls_on_every_chain() {
    let chains: Vec<Kinematics> = common::CHAINS
        .iter()
        .map(|(f, b, t)| load(f, *b, *t).2)
        .collect();
    block_kernels_equal_single_calls(&chains);
}

/// The same on the real chains of the CI data (`SCREWKIT_SHARED_URDF`).
#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn block_fk_equals_single_calls_on_the_real_chains() {
    let dir = std::env::var("SCREWKIT_SHARED_URDF").expect("SCREWKIT_SHARED_URDF");
    let chains: Vec<Kinematics> = screwkit_testkit::SHARED_CHAINS
        .iter()
        .map(|(f, b, t)| {
            let chain = screwkit_model::load_chain(format!("{dir}/{f}"), Some(b), Some(t)).unwrap();
            Kinematics::new(&chain)
        })
        .collect();
    assert!(!chains.is_empty());
    block_kernels_equal_single_calls(&chains);
}

/// Block FK and FK + J of 325 rows (one NaN row) equal the single calls, bit for bit.
fn block_kernels_equal_single_calls(chains: &[Kinematics]) {
    for kin in chains {
        let n = kin.dof();
        let rows = 8 * 40 + 5;
        let mut qs = screwkit_solve::sample::configurations(kin, rows, 9);
        if n > 0 {
            qs[13 * n] = f64::NAN;
        }
        let mut poses = vec![0.0; rows * 16];
        let r = fk_batch(kin, &qs, &mut poses);
        if n > 0 {
            assert!(matches!(r, Err(SolveError::Rows(ref e)) if e.len() == 1 && e[0].row == 13));
        }
        // The space Jacobian's block kernel too (with poses), row by row against single calls.
        let (mut js, mut jp) = (vec![0.0; rows * 6 * n], vec![0.0; rows * 16]);
        if n > 0 {
            let r = jacobian_batch(kin, &qs, Frame::Space, &mut js, Some(&mut jp));
            assert!(matches!(r, Err(SolveError::Rows(ref e)) if e.len() == 1 && e[0].row == 13));
            assert_eq!(
                poses.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                jp.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
            );
            let mut ws = Workspace::new(kin);
            for k in (0..rows).filter(|&k| k != 13) {
                let single = fk_jacobian(kin, &mut ws, &qs[k * n..(k + 1) * n], Frame::Space)
                    .unwrap()
                    .jacobian
                    .clone();
                let got = Matrix6xX::from_row_slice(&js[6 * n * k..6 * n * (k + 1)]);
                assert!(
                    got.iter()
                        .zip(single.iter())
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "row {k}"
                );
            }
        }
        for k in 0..rows {
            let got = &poses[16 * k..16 * (k + 1)];
            match fk1(kin, &qs[k * n..(k + 1) * n]) {
                Ok(t) => {
                    let mut want = [0.0; 16];
                    t.write_row_major(&mut want);
                    assert_eq!(
                        got.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                        want.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
                        "row {k}"
                    );
                }
                Err(_) => assert!(got.iter().all(|x| x.is_nan())),
            }
        }
    }
}
