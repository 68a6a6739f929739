//! FK and Jacobians against independent oracles: direct composition of URDF transforms,
//! central finite differences of FK, and the adjoint relation between J_s and J_b.

mod common;

use common::{fk1, load, Sampler, CHAINS};
use nalgebra::Vector6;
use screwkit_lie::Se3;
use screwkit_solve::fk::fk_all_links;
use screwkit_solve::jacobian::{fk_jacobian, jacobian};
use screwkit_solve::{Frame, SolveError, Workspace};
use screwkit_testkit::reference::{fk_by_composition, poe_body, poe_space};

#[test]
fn fk_matches_composition_and_the_plain_product() {
    let mut rng = Sampler::new(42);
    for &(file, base, tip) in CHAINS {
        let (tree, chain, kin) = load(file, base, tip);
        for _ in 0..200 {
            let q = rng.config(&kin);
            let want = fk_by_composition(&tree, &chain, &q).unwrap();
            let t = fk1(&kin, &q).unwrap();
            assert!((t.to_homogeneous() - want).amax() < 1e-12, "{file}");
            // The fast column kernels equal the product of exponentials written plainly
            // (one Se3::exp per joint), in the space and the body form.
            for (form, plain) in [
                ("space", poe_space(&chain, &q)),
                ("body", poe_body(&chain, &q)),
            ] {
                assert!(
                    t.max_abs_diff(&plain) < 1e-13,
                    "{file}: kernel vs plain {form} form {:e}",
                    t.max_abs_diff(&plain)
                );
            }
        }
    }
}

/// The same on the real files of ../shared/urdf (run by `.ci/run` with `--ignored`), where
/// axes written with a rounded π/2 sit 1e-13–1e-11 off a coordinate axis and take the
/// near-axis update: the kernels (tip FK, FK + space Jacobian) equal the URDF composed joint by
/// joint and the plain product of exponentials to 4e-15 (measured 1.0–3.1e-15 with or without
/// the near-axis update: a few ulps of metre-sized values after six or seven joints).
#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn kernels_match_composition_on_the_real_files() {
    let dir = std::env::var("SCREWKIT_SHARED_URDF")
        .expect("SCREWKIT_SHARED_URDF must name the folder with the shared real-world URDFs");
    let mut rng = Sampler::new(7);
    for &(file, base, tip) in screwkit_testkit::SHARED_CHAINS {
        let tree = screwkit_model::urdf::load_file(format!("{dir}/{file}")).unwrap();
        let chain = screwkit_model::Chain::from_tree(&tree, Some(base), Some(tip)).unwrap();
        let kin = screwkit_solve::Kinematics::new(&chain);
        let mut ws = Workspace::new(&kin);
        let mut worst = 0.0f64;
        for _ in 0..300 {
            let q = rng.config(&kin);
            let t = fk1(&kin, &q).unwrap();
            let by_jacobian = fk_jacobian(&kin, &mut ws, &q, Frame::Space).unwrap().pose;
            let want = fk_by_composition(&tree, &chain, &q).unwrap();
            for got in [t, by_jacobian] {
                worst = worst
                    .max((got.to_homogeneous() - want).amax())
                    .max(got.max_abs_diff(&poe_space(&chain, &q)));
            }
        }
        assert!(worst < 4e-15, "{file} {base}→{tip}: {worst:e}");
    }
}

/// Planar 3R closed form: x = c1 + 0.8 c12 + 0.5 c123, y = s1 + 0.8 s12 + 0.5 s123.
#[test]
fn planar_closed_form() {
    let (_, _, kin) = load("planar_3r.urdf", None, None);
    let q = [0.3, -1.1, 2.0];
    let t = fk1(&kin, &q).unwrap();
    let (a, b, c) = (q[0], q[0] + q[1], q[0] + q[1] + q[2]);
    let x = a.cos() + 0.8 * b.cos() + 0.5 * c.cos();
    let y = a.sin() + 0.8 * b.sin() + 0.5 * c.sin();
    assert!((t.translation().x - x).abs() < 1e-15 && (t.translation().y - y).abs() < 1e-15);
}

/// Every link's pose equals direct composition to that link.
#[test]
fn all_links_match_composition() {
    let mut rng = Sampler::new(5);
    for &(file, base, tip) in CHAINS {
        let (tree, chain, kin) = load(file, base, tip);
        let mut ws = Workspace::new(&kin);
        let q = rng.config(&kin);
        let poses = fk_all_links(&kin, &mut ws, &q).unwrap().to_vec();
        assert_eq!(poses.len(), chain.links.len());
        assert!(poses[0].max_abs_diff(&Se3::identity()) == 0.0);
        for (link, pose) in chain.links.iter().zip(&poses).skip(1) {
            let sub = screwkit_model::Chain::from_tree(&tree, Some(&chain.base), Some(&link.name))
                .unwrap();
            // The sub-chain's variables are a prefix subset of the chain's, by name.
            let qs: Vec<f64> = sub
                .variables
                .iter()
                .map(|v| {
                    q[chain
                        .variables
                        .iter()
                        .position(|w| w.name == v.name)
                        .unwrap()]
                })
                .collect();
            let want = fk_by_composition(&tree, &sub, &qs).unwrap();
            assert!(
                (pose.to_homogeneous() - want).amax() < 1e-12,
                "{file}: {}",
                link.name
            );
        }
        assert!(poses.last().unwrap().max_abs_diff(&fk1(&kin, &q).unwrap()) < 1e-15);
    }
}

/// Body twist of a relative motion: log(T(q)⁻¹ T(q')).
fn body_delta(t: &Se3, t2: &Se3) -> Vector6<f64> {
    t.inverse_compose(t2).log().to_vector()
}

/// Space twist of a relative motion: log(T(q') T(q)⁻¹).
fn space_delta(t: &Se3, t2: &Se3) -> Vector6<f64> {
    (*t2 * t.inverse()).log().to_vector()
}

/// Central differences: J_b column k ≈ [log(T⁻¹T(q + h e_k)) − log(T⁻¹T(q − h e_k))]/2h, and
/// J_s column k ≈ the same with T(q ± h e_k) T⁻¹ (i.e. [V_s] = Ṫ T⁻¹). Includes mimic and
/// prismatic joints.
#[test]
fn jacobians_match_finite_differences() {
    let mut rng = Sampler::new(77);
    let h = 1e-6;
    for &(file, base, tip) in CHAINS {
        let (_, _, kin) = load(file, base, tip);
        let mut ws = Workspace::new(&kin);
        for _ in 0..50 {
            let q = rng.config(&kin);
            let t = fk1(&kin, &q).unwrap();
            let space = fk_jacobian(&kin, &mut ws, &q, Frame::Space).unwrap();
            let (ts, js) = (space.pose, space.jacobian.clone());
            assert!(ts.max_abs_diff(&t) < 1e-14);
            let body = fk_jacobian(&kin, &mut ws, &q, Frame::Body).unwrap();
            assert!(body.pose.max_abs_diff(&t) < 1e-14);
            let jb = body.jacobian.clone();
            for k in 0..kin.dof() {
                let mut qp = q.clone();
                let mut qm = q.clone();
                qp[k] += h;
                qm[k] -= h;
                let (tp, tm) = (fk1(&kin, &qp).unwrap(), fk1(&kin, &qm).unwrap());
                let fd_b = (body_delta(&t, &tp) - body_delta(&t, &tm)) / (2.0 * h);
                let fd_s = (space_delta(&t, &tp) - space_delta(&t, &tm)) / (2.0 * h);
                let eb = (jb.column(k) - fd_b).amax();
                let es = (js.column(k) - fd_s).amax();
                assert!(eb < 1e-8, "{file} body col {k}: {eb:e}");
                assert!(es < 1e-8, "{file} space col {k}: {es:e}");
            }
            // J_b = Ad_{T⁻¹} J_s.
            let adinv = t.inverse().adjoint();
            assert!((adinv * &js - &jb).amax() < 1e-12);
        }
    }
}

#[test]
fn bad_joint_vectors_are_errors() {
    let (_, _, kin) = load("ur5.urdf", None, None);
    let e = fk1(&kin, &[0.0; 5]).unwrap_err();
    assert!(matches!(
        e,
        SolveError::WrongLength {
            expected: 6,
            got: 5,
            ..
        }
    ));
    assert!(e.to_string().contains("shoulder_pan_joint"), "{e}");
    let e = fk1(&kin, &[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0]).unwrap_err();
    assert!(
        e.to_string().contains("#2 (elbow_joint) is not finite"),
        "{e}"
    );
    let mut ws = Workspace::new(&kin);
    assert!(jacobian(&kin, &mut ws, &[0.0; 7], Frame::Space).is_err());
    assert!(fk_all_links(&kin, &mut ws, &[f64::INFINITY; 6]).is_err());
}

/// A workspace made for another chain is refitted, never a panic or a wrongly sized result;
/// `within_limits` is false for a q of the wrong length.
#[test]
fn workspaces_and_limits_check_their_sizes() {
    let (_, _, ur5) = load("ur5.urdf", None, None);
    let (_, _, panda) = load("panda.urdf", None, None);
    let mut ws = Workspace::new(&ur5);
    let q7 = [0.1, 0.2, -0.1, -1.5, 0.3, 1.6, 0.2];
    let j = jacobian(&panda, &mut ws, &q7, Frame::Body).unwrap();
    assert_eq!(j.ncols(), 7);
    assert_eq!(
        fk_all_links(&panda, &mut ws, &q7).unwrap().len(),
        panda.links().len()
    );
    assert_eq!(
        jacobian(&ur5, &mut ws, &[0.0; 6], Frame::Space)
            .unwrap()
            .ncols(),
        6
    );
    assert!(ur5.within_limits(&[0.0; 6], 0.0));
    assert!(!ur5.within_limits(&[0.0; 5], 0.0));
    assert!(!ur5.within_limits(&[0.0; 7], 0.0));
    assert!(!ur5.within_limits(&[0.0, 0.0, f64::NAN, 0.0, 0.0, 0.0], 0.0));
}

/// Each joint's screw at q recombines into the space Jacobian by the mimic rule (column k =
/// Σ m_j S_j(q) over the joints q_k drives); at q = 0 the joints before any offset mimic joint
/// have their home screws.
#[test]
fn joint_screws_recombine_into_the_space_jacobian() {
    use screwkit_solve::jacobian::joint_screws;
    let mut rng = Sampler::new(9);
    for &(file, base, tip) in CHAINS {
        let (_, chain, kin) = load(file, base, tip);
        let mut ws = Workspace::new(&kin);
        for _ in 0..5 {
            let q = rng.config(&kin);
            let screws = joint_screws(&kin, &mut ws, &q).unwrap();
            assert_eq!(screws.len(), chain.joints.len());
            let js = jacobian(&kin, &mut ws, &q, Frame::Space).unwrap().clone();
            for k in 0..kin.dof() {
                let mut col = Vector6::zeros();
                for (j, s) in chain.joints.iter().zip(&screws) {
                    if j.drive.variable == k {
                        col += s.to_vector() * j.drive.multiplier;
                    }
                }
                let diff = (col - js.column(k)).amax();
                assert!(diff < 1e-12, "{file}: variable {k}: {diff:e}");
            }
        }
    }
    // The space screws at q = 0 are the home screws S_j.
    let (_, chain, kin) = load("gripper_arm.urdf", None, Some("right_finger"));
    let offsets: Vec<f64> = vec![0.0; kin.dof()];
    let screws = joint_screws(&kin, &mut Workspace::new(&kin), &offsets).unwrap();
    // The coupled joint has a mimic offset: joints after it see it turned, so compare only up
    // to and including it.
    for (j, s) in chain.joints.iter().zip(&screws).take(3) {
        assert!(
            (s.to_vector() - j.s_space.twist().to_vector()).amax() < 1e-15,
            "{}",
            j.name
        );
    }
}

/// The world-aligned Jacobian: its linear rows are the derivative of the tip position (central
/// differences), its angular rows those of J_s; the batch equals the single call bit for bit.
#[test]
fn world_aligned_jacobian_is_the_tip_point_velocity() {
    use screwkit_solve::batch::jacobian_batch;
    use screwkit_solve::JacobianKind;
    let mut rng = Sampler::new(21);
    for &(file, base, tip) in CHAINS {
        let (_, _, kin) = load(file, base, tip);
        let n = kin.dof();
        let mut ws = Workspace::new(&kin);
        let mut qs = Vec::new();
        for _ in 0..4 {
            let q = rng.config(&kin);
            let jwa = jacobian(&kin, &mut ws, &q, JacobianKind::WorldAligned)
                .unwrap()
                .clone();
            // The deprecated name of one release answers the same.
            #[allow(deprecated)]
            let old = screwkit_solve::jacobian::jacobian_world_aligned(&kin, &mut ws, &q)
                .unwrap()
                .clone();
            assert_eq!(old, jwa, "{file}");
            let js = jacobian(&kin, &mut ws, &q, Frame::Space).unwrap().clone();
            let h = 1e-6;
            for k in 0..n {
                let (mut qp, mut qm) = (q.clone(), q.clone());
                qp[k] += h;
                qm[k] -= h;
                let dp = (fk1(&kin, &qp).unwrap().translation()
                    - fk1(&kin, &qm).unwrap().translation())
                    / (2.0 * h);
                for r in 0..3 {
                    assert_eq!(jwa[(r, k)], js[(r, k)], "{file}: ω row {r}");
                    assert!(
                        (jwa[(3 + r, k)] - dp[r]).abs() < 1e-8,
                        "{file}: col {k} row {r}"
                    );
                }
            }
            qs.extend_from_slice(&q);
        }
        let rows = qs.len() / n.max(1);
        let mut batch = vec![0.0; rows * 6 * n];
        jacobian_batch(&kin, &qs, JacobianKind::WorldAligned, &mut batch, None).unwrap();
        for k in 0..rows {
            let j = jacobian(
                &kin,
                &mut ws,
                &qs[k * n..(k + 1) * n],
                JacobianKind::WorldAligned,
            )
            .unwrap();
            for r in 0..6 {
                for c in 0..n {
                    assert_eq!(batch[k * 6 * n + r * n + c], j[(r, c)], "{file}: row {k}");
                }
            }
        }
    }
}

/// A tool frame: FK of the tool chain = FK · T_tool; its body Jacobian = Ad_{T_tool⁻¹} J_b; the
/// space Jacobian is unchanged.
#[test]
fn tool_frame_is_composed_at_the_tip() {
    let tool = Se3::from_xyz_rpy([0.01, -0.02, 0.15], [0.3, -0.2, 0.1]).unwrap();
    let mut rng = Sampler::new(31);
    for &(file, base, tip) in CHAINS {
        let (_, chain, kin) = load(file, base, tip);
        let with = chain.with_tool(&tool);
        let kt = screwkit_solve::Kinematics::new(&with);
        assert_eq!(with.tip, format!("{}+tool", chain.tip));
        let mut ws = Workspace::new(&kin);
        let mut wt = Workspace::new(&kt);
        let q = rng.config(&kin);
        let want = fk1(&kin, &q).unwrap().compose(&tool);
        assert!(fk1(&kt, &q).unwrap().max_abs_diff(&want) < 1e-14, "{file}");
        let js = jacobian(&kin, &mut ws, &q, Frame::Space).unwrap().clone();
        assert!((jacobian(&kt, &mut wt, &q, Frame::Space).unwrap() - &js).amax() < 1e-14);
        let jb = jacobian(&kin, &mut ws, &q, Frame::Body).unwrap().clone();
        let jbt = jacobian(&kt, &mut wt, &q, Frame::Body).unwrap().clone();
        let ad = tool.inverse().adjoint();
        assert!((ad * jb - jbt).amax() < 1e-13, "{file}");
        let links = fk_all_links(&kt, &mut wt, &q).unwrap();
        assert!(links.last().unwrap().max_abs_diff(&want) < 1e-14);
    }
}
