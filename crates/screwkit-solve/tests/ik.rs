//! IK: solve rates on every bundled robot (1,000 reachable targets each: q* uniform in
//! limits, target FK(q*), seed at the limit midpoints), FK(q_sol) = target checked with an
//! independent FK call, solutions within limits, unreachable targets, singular targets.

mod common;

use common::{load, Rng, CHAINS};
use nalgebra::Vector3;
use screwkit_lie::Se3;
use screwkit_solve::fk::fk;
use screwkit_solve::ik::{solve, IkMethod, IkOptions, StopReason};
use screwkit_solve::Workspace;

fn options(method: IkMethod) -> IkOptions {
    // No wall-time budget in tests: a debug build is slow and results must be reproducible.
    IkOptions {
        method,
        timeout: None,
        ..IkOptions::default()
    }
}

/// Returns the solve rate; asserts every reported success independently.
fn solve_rate(
    file: &str,
    base: Option<&str>,
    tip: Option<&str>,
    opts: &IkOptions,
    count: usize,
) -> f64 {
    let (_, _, kin) = load(file, base, tip);
    let mut ws = Workspace::new(&kin);
    let mut rng = Rng(0xABCD_EF01_2345_6789);
    let seed = kin.midpoint();
    let mut ok = 0;
    for _ in 0..count {
        let q_star = rng.config(&kin);
        let target = fk(&kin, &q_star).unwrap();
        let r = solve(&kin, &mut ws, &target, &seed, opts).unwrap();
        assert!(
            kin.within_limits(&r.q, 0.0),
            "{file}: solution outside limits {:?}",
            r.q
        );
        if r.converged {
            // Independent check: a fresh FK call, rotation angle and position distance.
            let t = fk(&kin, &r.q).unwrap();
            let d = t.inverse_compose(&target);
            let rot = screwkit_lie::so3::log(d.rotation()).norm();
            let pos = (t.translation() - target.translation()).norm();
            assert!(
                rot < 1e-8 && pos < 1e-8,
                "{file}: claimed success with {rot:e} rad, {pos:e} m"
            );
            ok += 1;
        } else {
            assert_ne!(r.stop, StopReason::Converged);
        }
    }
    ok as f64 / count as f64
}

/// The default method (LM) solves ≥ 99.5% on every bundled chain.
#[test]
fn default_method_solve_rate() {
    for &(file, base, tip) in CHAINS {
        let rate = solve_rate(file, base, tip, &options(IkOptions::default().method), 1000);
        println!("LM  {file:<22} {:.1}%", rate * 100.0);
        assert!(rate >= 0.995, "{file}: LM solved only {:.1}%", rate * 100.0);
    }
}

/// The other methods, reported (and held to a lower bar: they exist for comparison).
#[test]
fn other_methods_solve_rate() {
    for &(file, base, tip) in CHAINS {
        for (name, m) in [("NR ", IkMethod::NewtonRaphson), ("DLS", IkMethod::DLS)] {
            let rate = solve_rate(file, base, tip, &options(m), 1000);
            println!("{name} {file:<22} {:.1}%", rate * 100.0);
            assert!(
                rate >= 0.9,
                "{file}: {name} solved only {:.1}%",
                rate * 100.0
            );
        }
    }
}

#[test]
fn unreachable_target_is_reported() {
    let (_, _, kin) = load("ur5.urdf", None, None);
    let mut ws = Workspace::new(&kin);
    let target = Se3::from_translation(Vector3::new(5.0, 0.0, 0.0));
    let opts = IkOptions {
        max_iterations: 3000,
        ..options(IkMethod::LM)
    };
    let r = solve(&kin, &mut ws, &target, &kin.midpoint(), &opts).unwrap();
    assert!(!r.converged);
    assert!(matches!(
        r.stop,
        StopReason::IterationLimit | StopReason::RestartLimit
    ));
    assert!(r.error_pos > 4.0, "{}", r.error_pos);
    assert!(kin.within_limits(&r.q, 0.0));
    assert!(r.q.iter().all(|x| x.is_finite()));
}

/// Targets at singular configurations (UR5 outstretched elbow q3 = 0, wrist q5 = 0; the Panda
/// and iiwa straight up) are solved by DLS and LM without blow-up.
#[test]
fn singular_targets() {
    let cases: &[(&str, Vec<f64>)] = &[
        ("ur5.urdf", vec![0.3, -0.7, 0.0, 0.4, 0.5, 0.2]),
        ("ur5.urdf", vec![0.3, -0.7, 1.2, 0.4, 0.0, 0.2]),
        ("iiwa14.urdf", vec![0.0; 7]),
        ("panda.urdf", vec![0.0, 0.0, 0.0, -0.0698, 0.0, 0.0, 0.0]),
    ];
    for (file, q_star) in cases {
        let (_, _, kin) = load(file, None, None);
        let mut ws = Workspace::new(&kin);
        let target = fk(&kin, q_star).unwrap();
        for m in [IkMethod::LM, IkMethod::DLS] {
            let r = solve(&kin, &mut ws, &target, &kin.midpoint(), &options(m)).unwrap();
            assert!(r.q.iter().all(|x| x.is_finite()));
            assert!(r.converged, "{file} {m:?}: {r:?}");
        }
    }
}

#[test]
fn position_only_and_masks() {
    let (_, _, kin) = load("panda.urdf", None, None);
    let mut ws = Workspace::new(&kin);
    let mut rng = Rng(3);
    for _ in 0..50 {
        let q_star = rng.config(&kin);
        let p = *fk(&kin, &q_star).unwrap().translation();
        // Any orientation: only the position matters.
        let target = Se3::from_translation(p);
        let opts = IkOptions {
            position_only: true,
            ..options(IkMethod::LM)
        };
        let r = solve(&kin, &mut ws, &target, &kin.midpoint(), &opts).unwrap();
        assert!(r.converged);
        assert!((fk(&kin, &r.q).unwrap().translation() - p).norm() < 1e-8);
    }
    // Masking rotation about the tool z: a 5-D task.
    let q_star = rng.config(&kin);
    let t = fk(&kin, &q_star).unwrap();
    let spun = t * Se3::exp(&screwkit_lie::Twist::new(
        Vector3::z() * 0.7,
        Vector3::zeros(),
    ));
    let opts = IkOptions {
        weights: [1.0, 1.0, 0.0, 1.0, 1.0, 1.0],
        ..options(IkMethod::LM)
    };
    let r = solve(&kin, &mut ws, &spun, &kin.midpoint(), &opts).unwrap();
    assert!(r.converged);
    let got = fk(&kin, &r.q).unwrap();
    assert!((got.translation() - spun.translation()).norm() < 1e-8);
    // The tool z axis matches; rotation about it is free.
    let (za, zb) = (got.rotation().column(2), spun.rotation().column(2));
    assert!((za - zb).norm() < 1e-8);
}

#[test]
fn bad_input() {
    let (_, _, kin) = load("ur5.urdf", None, None);
    let mut ws = Workspace::new(&kin);
    let t = fk(&kin, &[0.0; 6]).unwrap();
    assert!(solve(&kin, &mut ws, &t, &[0.0; 5], &IkOptions::default()).is_err());
    let nan = Se3::from_translation(Vector3::new(f64::NAN, 0.0, 0.0));
    assert!(solve(&kin, &mut ws, &nan, &[0.0; 6], &IkOptions::default()).is_err());
}

/// Continuous joints come back wrapped to (−π, π].
#[test]
fn continuous_joints_are_wrapped() {
    let (_, _, kin) = load("tricky.urdf", Some("base_link"), None);
    let mut ws = Workspace::new(&kin);
    let mut rng = Rng(8);
    for _ in 0..50 {
        let q_star = rng.config(&kin);
        let target = fk(&kin, &q_star).unwrap();
        let r = solve(
            &kin,
            &mut ws,
            &target,
            &kin.midpoint(),
            &options(IkMethod::LM),
        )
        .unwrap();
        assert!(r.q[1] > -std::f64::consts::PI && r.q[1] <= std::f64::consts::PI);
    }
}

/// The fixed-size damped least-squares step (6×6 Cholesky) equals the SVD form computed with
/// faer, Δq = Σ_i σ_i / (σ_i² + λ²) v_i (u_iᵀ e) over the free columns, on every bundled chain
/// at random and singular configurations, for small to large damping and with locked columns.
#[test]
fn fixed_size_dls_step_equals_the_faer_svd_form() {
    use screwkit_solve::dls::dls_step;
    use screwkit_solve::jacobian::jacobian;
    use screwkit_solve::Frame;
    let mut rng = Rng(0x0D15_C0DE_5EED_0001);
    let mut checked = 0;
    for (file, base, tip) in CHAINS {
        let (_, _, kin) = load(file, *base, *tip);
        let n = kin.dof();
        let mut configs: Vec<Vec<f64>> = (0..20).map(|_| rng.config(&kin)).collect();
        if *file == "ur5.urdf" {
            configs.push(vec![0.3, -0.7, 1.2, 0.4, 0.0, 0.2]); // wrist singular
            configs.push(vec![0.3, -0.7, 0.0, 0.4, 0.5, 0.2]); // elbow singular
        }
        for (c, q) in configs.iter().enumerate() {
            for frame in [Frame::Space, Frame::Body] {
                let j = jacobian(&kin, q, frame).unwrap();
                let e = nalgebra::Vector6::from_fn(|_, _| rng.uniform() - 0.5);
                let locked: Vec<bool> = (0..n).map(|k| c % 3 == 1 && k % 3 == 0).collect();
                for lambda2 in [1e-6, 1e-3, 0.5] {
                    let mut dq = vec![f64::NAN; n];
                    dls_step(&j, &e, lambda2, &locked, &mut dq).unwrap();
                    // Oracle: faer's SVD of J with the locked columns zeroed.
                    let m =
                        faer::Mat::<f64>::from_fn(
                            6,
                            n,
                            |r, k| {
                                if locked[k] {
                                    0.0
                                } else {
                                    j[(r, k)]
                                }
                            },
                        );
                    let svd = m.thin_svd().unwrap();
                    let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
                    let mut oracle = vec![0.0; n];
                    for i in 0..n.min(6) {
                        let ute: f64 = (0..6).map(|r| u[(r, i)] * e[r]).sum();
                        let g = s[i] / (s[i] * s[i] + lambda2) * ute;
                        for (k, x) in oracle.iter_mut().enumerate() {
                            *x += v[(k, i)] * g;
                        }
                    }
                    // Rounding grows with the condition number of J Jᵀ + λ²I.
                    let cond = (s[0] * s[0] + lambda2) / lambda2;
                    let scale = oracle.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                    for k in 0..n {
                        assert!(
                            (dq[k] - oracle[k]).abs() <= 1e-14 * cond * scale,
                            "{file} {frame:?} λ²={lambda2}: Δq_{k} {} vs {}",
                            dq[k],
                            oracle[k]
                        );
                        if locked[k] {
                            assert_eq!(dq[k], 0.0);
                        }
                    }
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 900, "{checked}");
    // Not positive definite (λ = 0, fewer than 6 free columns): an error, not garbage.
    let (_, _, kin) = load("planar_3r.urdf", None, None);
    let j = jacobian(&kin, &[0.1, 0.2, 0.3], Frame::Space).unwrap();
    let mut dq = [0.0; 3];
    let e = nalgebra::Vector6::repeat(0.1);
    assert!(dls_step(&j, &e, 0.0, &[false; 3], &mut dq).is_err());
}
