//! Singularity analysis against nalgebra's SVD and known singular configurations; joint
//! velocities and torques; batches equal single calls and do not depend on the thread count.

mod common;

use common::{load, Rng};
use nalgebra::{DVector, Vector6};
use screwkit_lie::{Twist, Wrench};
use screwkit_solve::analysis::analyze;
use screwkit_solve::batch::{fk_batch, ik_batch, ik_path, jacobian_batch, row_seed};
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{solve, IkOptions};
use screwkit_solve::jacobian::jacobian;
use screwkit_solve::velocity::{
    joint_torques, joint_velocities_dls, joint_velocities_exact, joint_velocities_pinv,
};
use screwkit_solve::{Frame, Workspace};

#[test]
fn analysis_matches_nalgebra_svd() {
    let mut rng = Rng(21);
    for file in ["ur5.urdf", "panda.urdf", "planar_3r.urdf"] {
        let (_, _, kin) = load(file, None, None);
        for _ in 0..20 {
            let q = rng.config(&kin);
            let j = jacobian(&kin, &q, Frame::Space).unwrap();
            let a = analyze(&j).unwrap();
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
        let j = jacobian(&kin, &q, Frame::Space).unwrap();
        let a = analyze(&j).unwrap();
        assert_eq!(a.rank, 5, "{:?}", a.singular_values);
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
    let j = jacobian(&kin, &[0.3, -0.7, 1.2, 0.4, 0.5, 0.2], Frame::Space).unwrap();
    let a = analyze(&j).unwrap();
    assert_eq!(a.rank, 6);
    assert!(a.lost_directions.is_empty());
    let s = &a.singular_values;
    assert_eq!(a.condition_number, s[0] / s[5]);
    // Planar 3R: rank 3 of 6 at most (min(6, n)), three lost directions.
    let (_, _, kin3) = load("planar_3r.urdf", None, None);
    let a = analyze(&jacobian(&kin3, &[0.1, 0.5, -0.3], Frame::Space).unwrap()).unwrap();
    assert_eq!(
        (a.rank, a.lost_directions.len(), a.manipulability),
        (3, 3, 0.0)
    );
}

#[test]
fn joint_velocities_and_torques() {
    let (_, _, kin) = load("ur5.urdf", None, None);
    let q = [0.3, -0.7, 1.2, 0.4, 0.5, 0.2];
    let j = jacobian(&kin, &q, Frame::Body).unwrap();
    let v = Twist::from_vector(&Vector6::new(0.1, -0.2, 0.3, 0.05, 0.02, -0.04));
    let exact = joint_velocities_exact(&j, &v).unwrap();
    assert!((&j * &exact - v.to_vector()).amax() < 1e-12);
    let pinv = joint_velocities_pinv(&j, &v, None).unwrap();
    assert!((&pinv - &exact).amax() < 1e-10);
    let dls = joint_velocities_dls(&j, &v, 1e-6).unwrap();
    assert!((&dls - &exact).amax() < 1e-6);
    // Power balance: q̇ᵀτ = Vᵀ F for τ = Jᵀ F.
    let f = Wrench::from_vector(&Vector6::new(1.0, 2.0, -1.0, 10.0, -5.0, 3.0));
    let tau = joint_torques(&j, &f);
    assert!((exact.dot(&tau) - v.power(&f)).abs() < 1e-12);
    // Redundant arm: pinv gives the minimum-norm solution; exact is refused.
    let (_, _, panda) = load("panda.urdf", None, None);
    let j7 = jacobian(&panda, &[0.1, 0.2, -0.1, -1.5, 0.3, 1.6, 0.2], Frame::Space).unwrap();
    assert!(joint_velocities_exact(&j7, &v).is_err());
    let qd = joint_velocities_pinv(&j7, &v, None).unwrap();
    assert!((&j7 * &qd - v.to_vector()).amax() < 1e-12);
    // The null-space direction: pad J to 7 × 7 with a zero row so nalgebra's (thin) SVD
    // returns a full V, and take the right singular vector of the zero singular value.
    let mut padded = nalgebra::DMatrix::<f64>::zeros(7, 7);
    padded.view_mut((0, 0), (6, 7)).copy_from(&j7);
    let svd = padded.svd(false, true);
    let k = svd.singular_values.imin();
    let n7: DVector<f64> = svd.v_t.unwrap().row(k).transpose().into_owned();
    assert!((&j7 * &n7).amax() < 1e-12);
    assert!(
        qd.dot(&n7).abs() < 1e-10,
        "minimum norm: no null-space component"
    );
    assert!(joint_velocities_dls(&j7, &v, 0.0).is_err());
}

#[test]
fn batches_equal_single_calls_and_ignore_thread_count() {
    let (_, _, kin) = load("panda.urdf", None, None);
    let n = kin.dof();
    let mut rng = Rng(4);
    let rows = 600;
    let qs: Vec<f64> = (0..rows).flat_map(|_| rng.config(&kin)).collect();
    let mut out = vec![screwkit_lie::Se3::identity(); rows];
    fk_batch(&kin, &qs, &mut out).unwrap();
    for (k, t) in out.iter().enumerate() {
        assert_eq!(*t, fk(&kin, &qs[k * n..(k + 1) * n]).unwrap());
    }
    let js = jacobian_batch(&kin, &qs[..10 * n], Frame::Body).unwrap();
    for (k, (_, jk)) in js.iter().enumerate() {
        assert_eq!(
            *jk,
            jacobian(&kin, &qs[k * n..(k + 1) * n], Frame::Body).unwrap()
        );
    }
    // IK: batch = single calls with the row seeds; 1 thread = 2 threads, bit for bit.
    let targets: Vec<_> = out[..200].to_vec();
    let opts = IkOptions {
        timeout: None,
        seed: 7,
        ..IkOptions::default()
    };
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| ik_batch(&kin, &targets, None, &opts).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let mut ws = Workspace::new(&kin);
    for (k, (a, b)) in one.iter().zip(&two).enumerate() {
        let (a, b) = (a.as_ref().unwrap(), b.as_ref().unwrap());
        assert_eq!(a, b);
        let single = solve(
            &kin,
            &mut ws,
            &targets[k],
            &kin.midpoint(),
            &IkOptions {
                seed: row_seed(7, k),
                ..opts.clone()
            },
        )
        .unwrap();
        assert_eq!(*a, single);
    }
    // Wrong shapes are errors.
    assert!(fk_batch(&kin, &qs[..n + 1], &mut out[..1]).is_err());
    assert!(fk_batch(&kin, &qs[..2 * n], &mut out[..3]).is_err());
    // Non-finite values anywhere in a large batch (checked in parallel): an error naming the
    // joint of the first bad row in input order.
    let rows = qs.len() / n;
    let mut bad = qs.clone();
    bad[(rows - 3) * n + 2] = f64::INFINITY;
    bad[(rows / 2) * n + 1] = f64::NAN;
    let err = fk_batch(&kin, &bad, &mut out).unwrap_err().to_string();
    assert!(
        err.contains(&kin.names()[1]) && err.contains("NaN"),
        "{err}"
    );
    assert!(jacobian_batch(&kin, &bad, Frame::Space).is_err());
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
            fk(&kin, &q).unwrap()
        })
        .collect();
    let opts = IkOptions {
        timeout: None,
        ..IkOptions::default()
    };
    let res = ik_path(&kin, &targets, &q0, &opts).unwrap();
    assert!(res.iter().all(|r| r.converged));
    let mean: f64 = res.iter().map(|r| r.iterations as f64).sum::<f64>() / res.len() as f64;
    assert!(
        mean < 8.0,
        "warm start should need few iterations, mean {mean}"
    );
    assert!(res.iter().all(|r| r.restarts == 0));
}
