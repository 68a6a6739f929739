//! The whole tree against independent oracles: the URDF composed joint by joint through the
//! tree (every link), central finite differences of FK for every Jacobian form (through
//! `integrate`, so the floating base's columns too), the relative pose and Jacobian by their
//! definition, and the chain kernels where a frame's path is the chain.

use nalgebra::{Matrix4, Vector6};
use screwkit_lie::Se3;
use screwkit_model::{urdf, KinematicTree, Tree};
use screwkit_solve::sample::SplitMix64;
use screwkit_solve::tree::{batch, configuration, fk, jacobian};
use screwkit_solve::{JacobianKind, Kinematics, TreeKinematics, TreeWorkspace, Workspace};
use screwkit_testkit::reference::tree_world_poses;

/// The bundled files (all of them are trees; most are single chains).
const BUNDLED: &[&str] = &[
    "torso_two_arms.urdf",
    "ur5.urdf",
    "panda.urdf",
    "iiwa14.urdf",
    "scara.urdf",
    "tricky.urdf",
    "gripper_arm.urdf",
    "planar_3r.urdf",
];

/// The whole robots of ../shared/urdf/trees.
const SHARED_TREES: &[&str] = &[
    "talos_full_v2.urdf",
    "baxter.urdf",
    "allegro_right_hand.urdf",
    "so101.urdf",
];

fn tree_of(path: &str) -> Tree {
    urdf::load_file(path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn prepared(tree: &Tree, floating: bool) -> (KinematicTree, TreeKinematics) {
    let mut model = KinematicTree::from_tree(tree)
        .unwrap()
        .with_floating_base(floating);
    // An extra frame on the last link, like a tool: pose in the link's frame.
    let last = model.links.last().unwrap().name.clone();
    let tool = Se3::from_xyz_rpy([0.01, -0.02, 0.05], [0.3, -0.2, 0.1]).unwrap();
    model.add_frame("extra_tool", &last, tool).unwrap();
    let kin = TreeKinematics::new(&model).unwrap();
    (model, kin)
}

/// Every link's pose by composition, T_base applied (q is the tree's configuration).
fn oracle(
    tree: &Tree,
    _model: &KinematicTree,
    kin: &TreeKinematics,
    q: &[f64],
) -> Vec<Matrix4<f64>> {
    tree_world_poses(tree, kin, q)
}

fn check_fk(label: &str, tree: &Tree, floating: bool, samples: usize) {
    let (model, kin) = prepared(tree, floating);
    let mut ws = TreeWorkspace::new(&kin);
    let mut rng = SplitMix64(11);
    let links = model.links.len();
    let mut worst = 0.0f64;
    for _ in 0..samples {
        let q = configuration::random(&kin, &mut rng);
        let want = oracle(tree, &model, &kin, &q);
        let all = fk::fk_frames(&kin, &mut ws, &q).unwrap().to_vec();
        assert_eq!(all.len(), links + 1);
        for (i, t) in all.iter().enumerate() {
            let w = if i < links {
                want[i]
            } else {
                want[model.frames[i].link] * model.frames[i].placement.to_homogeneous()
            };
            let one = fk::fk_frame(&kin, &mut ws, &q, i).unwrap();
            let scale = 1.0 + w.fixed_view::<3, 1>(0, 3).norm();
            for got in [t, &one] {
                let e = (got.to_homogeneous() - w).amax() / scale;
                worst = worst.max(e);
            }
        }
    }
    assert!(
        worst < 1e-13,
        "{label} floating={floating}: FK vs composition {worst:e}"
    );
}

/// The body twist of T(q)⁻¹ T(q ⊕ ε eᵢ) by central differences: column i of J_b.
fn fd_body(
    kin: &TreeKinematics,
    pose: &dyn Fn(&[f64]) -> Se3,
    q: &[f64],
    i: usize,
) -> Vector6<f64> {
    let h = 1e-6;
    let mut e = vec![0.0; kin.nv()];
    e[i] = 1.0;
    let plus = configuration::integrate(kin, q, &e, h).unwrap();
    let minus = configuration::integrate(kin, q, &e, -h).unwrap();
    let t = pose(q);
    let dp = t.inverse_compose(&pose(&plus)).log();
    let dm = t.inverse_compose(&pose(&minus)).log();
    let d = |a: f64, b: f64| (a - b) / (2.0 * h);
    Vector6::new(
        d(dp.w[0], dm.w[0]),
        d(dp.w[1], dm.w[1]),
        d(dp.w[2], dm.w[2]),
        d(dp.v[0], dm.v[0]),
        d(dp.v[1], dm.v[1]),
        d(dp.v[2], dm.v[2]),
    )
}

/// The three forms of a Jacobian from its body form and the pose.
fn forms_from_body(jb: &Vector6<f64>, t: &Se3) -> [(JacobianKind, Vector6<f64>); 3] {
    let tw = screwkit_lie::Twist::new(jb.fixed_rows::<3>(0).into(), jb.fixed_rows::<3>(3).into());
    let s = t.adjoint_apply(&tw);
    let r = t.rotation();
    let wa_w = r * tw.w;
    let wa_v = r * tw.v;
    [
        (JacobianKind::Body, *jb),
        (
            JacobianKind::Space,
            Vector6::new(s.w[0], s.w[1], s.w[2], s.v[0], s.v[1], s.v[2]),
        ),
        (
            JacobianKind::WorldAligned,
            Vector6::new(wa_w[0], wa_w[1], wa_w[2], wa_v[0], wa_v[1], wa_v[2]),
        ),
    ]
}

fn check_jacobians(label: &str, tree: &Tree, floating: bool, samples: usize) {
    let (model, kin) = prepared(tree, floating);
    let mut ws = TreeWorkspace::new(&kin);
    let mut rng = SplitMix64(5);
    let frames = model.frames.len();
    let mut worst = 0.0f64;
    for s in 0..samples {
        let q = configuration::random(&kin, &mut rng);
        // A few frames per sample, the extra frame always.
        let picks = [frames - 1, (s * 7 + 3) % frames, (s * 13 + 1) % frames];
        for &f in &picks {
            let pose = |q: &[f64]| fk::fk_frame(&kin, &mut TreeWorkspace::new(&kin), q, f).unwrap();
            let t = pose(&q);
            let fd: Vec<_> = (0..kin.nv()).map(|i| fd_body(&kin, &pose, &q, i)).collect();
            for form in [
                JacobianKind::Space,
                JacobianKind::Body,
                JacobianKind::WorldAligned,
            ] {
                let got = jacobian::frame_pose_jacobian(&kin, &mut ws, &q, f, form).unwrap();
                assert!(
                    got.pose.max_abs_diff(&t) < 1e-14,
                    "{label}: pose with the Jacobian {:e}",
                    got.pose.max_abs_diff(&t)
                );
                let j = got.jacobian.clone();
                assert_eq!(j.ncols(), kin.nv());
                for (i, col) in fd.iter().enumerate() {
                    let want = forms_from_body(col, &t)
                        .into_iter()
                        .find(|(k, _)| *k == form)
                        .unwrap()
                        .1;
                    let e = (j.column(i) - want).amax();
                    worst = worst.max(e);
                    assert!(
                        e < 1e-6,
                        "{label} floating={floating} frame {} {form:?} column {i} ({}): {e:e}",
                        model.frames[f].name,
                        kin.v_names()[i]
                    );
                }
            }
            // Relative to another frame: T_BA = T_B⁻¹ T_A by its definition and its body
            // Jacobian by differences.
            let b = (f * 5 + 2) % frames;
            let rel_pose = |q: &[f64]| {
                fk::relative_pose(&kin, &mut TreeWorkspace::new(&kin), q, f, b).unwrap()
            };
            let tb = fk::fk_frame(&kin, &mut ws, &q, b).unwrap();
            let trel = rel_pose(&q);
            assert!(trel.max_abs_diff(&tb.inverse_compose(&t)) < 1e-14);
            for form in [
                JacobianKind::Space,
                JacobianKind::Body,
                JacobianKind::WorldAligned,
            ] {
                let got = jacobian::relative_jacobian(&kin, &mut ws, &q, f, b, form).unwrap();
                assert!(got.pose.max_abs_diff(&trel) < 1e-14);
                let j = got.jacobian.clone();
                for i in 0..kin.nv() {
                    let col = fd_body(&kin, &rel_pose, &q, i);
                    let want = forms_from_body(&col, &trel)
                        .into_iter()
                        .find(|(k, _)| *k == form)
                        .unwrap()
                        .1;
                    let e = (j.column(i) - want).amax();
                    assert!(e < 1e-6, "{label}: relative {form:?} column {i}: {e:e}");
                }
            }
        }
    }
    assert!(worst > 0.0 || kin.nv() == 0);
}

/// Every joint's frame and screw at q (`jacobian::joint_screws`, the space form with the
/// general exponential): the frame equals its child link composed from the file, the screw's
/// direction is the file's axis turned by that frame and its line passes through the frame's
/// origin, and every link's space Jacobian column is Σ m_j S_j(q) over the path's joints its
/// variable drives.
fn check_joint_screws(label: &str, tree: &Tree, floating: bool, samples: usize) {
    let (model, kin) = prepared(tree, floating);
    let mut ws = TreeWorkspace::new(&kin);
    let mut rng = SplitMix64(5);
    let off = if floating { 6 } else { 0 };
    for _ in 0..samples {
        let q = configuration::random(&kin, &mut rng);
        let want = oracle(tree, &model, &kin, &q);
        let screws = jacobian::joint_screws(&kin, &mut ws, &q).unwrap();
        assert_eq!(screws.len(), model.joints.len());
        for (k, (js, j)) in screws.iter().zip(&model.joints).enumerate() {
            let child = (0..model.links.len())
                .find(|&l| {
                    model.links[l].support == Some(k)
                        && model.links[l]
                            .parent
                            .is_none_or(|p| model.links[p].support != Some(k))
                })
                .unwrap_or_else(|| panic!("{label}: joint {} has no child", j.name));
            let d = (js.frame.to_homogeneous() - want[child]).abs().max();
            assert!(d < 1e-12, "{label}: joint {} frame off by {d:e}", j.name);
            let dir = js.frame.rotation() * j.axis;
            let p = js.frame.translation();
            let (w, v) = (js.screw.w, js.screw.v);
            if j.kind == screwkit_model::JointKind::Prismatic {
                assert!(
                    w.norm() == 0.0 && (v - dir).norm() < 1e-12,
                    "{label}: {}",
                    j.name
                );
            } else {
                assert!((w - dir).norm() < 1e-12, "{label}: {} direction", j.name);
                assert!((w.cross(p) + v).norm() < 1e-12, "{label}: {} line", j.name);
            }
        }
        for l in 0..model.links.len() {
            let jac = jacobian::frame_jacobian(&kin, &mut ws, &q, l, JacobianKind::Space)
                .unwrap()
                .clone();
            for var in 0..model.variables.len() {
                let mut col = Vector6::zeros();
                for k in model.path(l) {
                    let j = &model.joints[k];
                    if j.drive.variable == var {
                        col += screws[k].screw.to_vector() * j.drive.multiplier;
                    }
                }
                let d = (jac.column(off + var) - col).abs().max();
                assert!(d < 1e-12, "{label}: link {l} column {var} off by {d:e}");
            }
        }
    }
}

#[test]
fn bundled_trees_joint_screws_are_the_jacobian_columns() {
    for file in BUNDLED {
        let tree = tree_of(&screwkit_testkit::bundled(file));
        check_joint_screws(file, &tree, false, 5);
        check_joint_screws(file, &tree, true, 3);
    }
}

#[test]
fn bundled_trees_fk_equals_the_composition() {
    for file in BUNDLED {
        let tree = tree_of(&screwkit_testkit::bundled(file));
        check_fk(file, &tree, false, 100);
        check_fk(file, &tree, true, 30);
    }
}

#[test]
fn bundled_trees_jacobians_equal_finite_differences() {
    for file in BUNDLED {
        let tree = tree_of(&screwkit_testkit::bundled(file));
        check_jacobians(file, &tree, false, 4);
        check_jacobians(file, &tree, true, 3);
    }
}

/// The whole robots of ../shared/urdf/trees (run by `.ci/run` with `--ignored`).
#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn shared_trees_against_the_composition_and_differences() {
    let dir = std::env::var("SCREWKIT_SHARED_URDF").expect("SCREWKIT_SHARED_URDF");
    for file in SHARED_TREES {
        let tree = tree_of(&format!("{dir}/trees/{file}"));
        check_fk(file, &tree, false, 100);
        check_fk(file, &tree, true, 30);
        check_jacobians(file, &tree, false, 2);
        check_jacobians(file, &tree, true, 2);
        check_joint_screws(file, &tree, false, 3);
    }
}

/// A chain (root → tip) is a view of the tree: the sweep's tip pose equals the chain kernel,
/// and the tip's tree Jacobian is the chain's with its columns in the tree's variable order
/// (both to 1e-14).
#[test]
fn the_chain_is_a_view_of_the_tree() {
    for file in [
        "ur5.urdf",
        "panda.urdf",
        "iiwa14.urdf",
        "scara.urdf",
        "planar_3r.urdf",
    ] {
        let tree = tree_of(&screwkit_testkit::bundled(file));
        let chain = screwkit_model::Chain::from_tree(&tree, None, None).unwrap();
        let ck = Kinematics::new(&chain);
        let mut cws = Workspace::new(&ck);
        let (model, kin) = prepared(&tree, false);
        let mut ws = TreeWorkspace::new(&kin);
        let tip = kin.frame(&chain.tip).unwrap();
        let order: Vec<usize> = chain
            .variables
            .iter()
            .map(|v| {
                model
                    .variables
                    .iter()
                    .position(|w| w.name == v.name)
                    .unwrap()
            })
            .collect();
        let mut rng = SplitMix64(3);
        for _ in 0..50 {
            let q = configuration::random(&kin, &mut rng);
            let cq: Vec<f64> = order.iter().map(|&k| q[k]).collect();
            let t = screwkit_solve::fk::fk(&ck, &mut cws, &cq).unwrap();
            let sweep = fk::fk_frames(&kin, &mut ws, &q).unwrap()[tip];
            assert!(sweep.max_abs_diff(&t) < 1e-14, "{file}");
            let cj = screwkit_solve::jacobian::jacobian(
                &ck,
                &mut cws,
                &cq,
                screwkit_solve::Frame::Space,
            )
            .unwrap()
            .clone();
            let tj = jacobian::frame_jacobian(&kin, &mut ws, &q, tip, JacobianKind::Space).unwrap();
            // The tree's frame Jacobian runs its own chain root → frame (`chain_to`), the
            // same chain as `Chain::from_tree` to rounding.
            for (c, &k) in order.iter().enumerate() {
                let d = (cj.column(c) - tj.column(k)).amax();
                assert!(d < 1e-14, "{file}: column {c} differs by {d:e}");
            }
        }
    }
}

/// A frame can take a chain known more exactly than its tree (a robot from screws): its pose
/// and Jacobians are then that chain's bit for bit; a chain that does not fit is refused and
/// changes nothing.
#[test]
fn a_frame_answers_with_the_chain_it_is_given() {
    let tree = tree_of(&screwkit_testkit::bundled("ur5.urdf"));
    let chain = screwkit_model::Chain::from_tree(&tree, None, None).unwrap();
    let (_, kin) = prepared(&tree, false);
    let tip = kin.frame(&chain.tip).unwrap();
    // The same chain, its home moved by 1e-12 (as screws given to rounding would be).
    let mut exact = chain.clone();
    let m = *exact.home.translation() + nalgebra::Vector3::new(1e-12, 0.0, 0.0);
    exact.home = Se3::from_parts_unchecked(*exact.home.rotation(), m);
    // Refused: a variable the tree does not have, a home elsewhere, a bad index.
    let mut renamed = exact.clone();
    renamed.variables[0].name = "elsewhere".into();
    let e = kin.set_chain(tip, &renamed, 1e-9).unwrap_err().to_string();
    assert!(e.contains("\"elsewhere\" is not the tree's"), "{e}");
    let e = kin.set_chain(tip, &exact, 1e-13).unwrap_err().to_string();
    assert!(e.contains("home is not frame"), "{e}");
    assert!(kin.set_chain(999, &exact, 1e-9).is_err());
    kin.set_chain(tip, &exact, 1e-9).unwrap();
    let e = kin.set_chain(tip, &exact, 1e-9).unwrap_err().to_string();
    assert!(e.contains("built already"), "{e}");
    let ck = Kinematics::new(&exact);
    let (mut cws, mut ws) = (Workspace::new(&ck), TreeWorkspace::new(&kin));
    let mut rng = SplitMix64(5);
    for _ in 0..20 {
        let q = configuration::random(&kin, &mut rng);
        let t = screwkit_solve::fk::fk(&ck, &mut cws, &q).unwrap();
        assert_eq!(fk::fk_frame(&kin, &mut ws, &q, tip).unwrap(), t);
        for kind in [
            JacobianKind::Space,
            JacobianKind::Body,
            JacobianKind::WorldAligned,
        ] {
            let cj = screwkit_solve::jacobian::jacobian(&ck, &mut cws, &q, kind)
                .unwrap()
                .clone();
            let tj = jacobian::frame_jacobian(&kin, &mut ws, &q, tip, kind).unwrap();
            assert_eq!(&cj, tj, "{kind:?}");
        }
    }
}

#[test]
fn torso_two_arms_is_one_tree_with_two_hands() {
    let tree = tree_of(&screwkit_testkit::bundled("torso_two_arms.urdf"));
    let model = KinematicTree::from_tree(&tree).unwrap();
    assert_eq!(model.variables.len(), 7);
    // Variables in the file's joint order.
    let file_order: Vec<&str> = tree
        .joints
        .iter()
        .filter(|j| j.kind.is_movable() && j.mimic.is_none())
        .map(|j| j.name.as_str())
        .collect();
    let names: Vec<&str> = model.variables.iter().map(|v| v.name.as_str()).collect();
    assert_eq!(names, file_order);
    assert_eq!(model.frames.len(), tree.links.len());
    // Joints off a hand's path give zero columns.
    let kin = TreeKinematics::new(&model).unwrap();
    let mut ws = TreeWorkspace::new(&kin);
    let leaves = tree.leaves_below(tree.root);
    assert!(leaves.len() >= 2);
    let q: Vec<f64> = (0..kin.nq()).map(|k| 0.1 * k as f64 - 0.2).collect();
    for &leaf in &leaves {
        let f = kin.frame(&tree.links[leaf]).unwrap();
        let path = model.path(f);
        let j = jacobian::frame_jacobian(&kin, &mut ws, &q, f, JacobianKind::Space)
            .unwrap()
            .clone();
        for v in 0..kin.nv() {
            let on = path.iter().any(|&p| model.joints[p].drive.variable == v);
            assert_eq!(
                j.column(v).amax() > 0.0,
                on,
                "{} column {v}",
                tree.links[leaf]
            );
        }
    }
}

#[test]
fn floating_base_configuration_and_integration() {
    let tree = tree_of(&screwkit_testkit::bundled("torso_two_arms.urdf"));
    let model = KinematicTree::from_tree(&tree)
        .unwrap()
        .with_floating_base(true);
    let kin = TreeKinematics::new(&model).unwrap();
    assert_eq!((kin.nq(), kin.nv()), (14, 13));
    assert_eq!(
        &kin.q_names()[..7],
        [
            "floating_base.x",
            "floating_base.y",
            "floating_base.z",
            "floating_base.qx",
            "floating_base.qy",
            "floating_base.qz",
            "floating_base.qw"
        ]
    );
    assert_eq!(kin.v_names()[0], "floating_base.wx");
    let q0 = configuration::neutral(&kin);
    assert_eq!(&q0[..7], [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]);
    // A pure rotation about z at 1 rad/s for π/2 s: the quaternion (0, 0, sin π/4, cos π/4).
    let mut v = vec![0.0; 13];
    v[2] = 1.0;
    v[3] = 2.0; // and 2 m/s along the base's x: a helix piece, p = (2 sin t, 2 (1 − cos t), 0)
    let q1 = configuration::integrate(&kin, &q0, &v, std::f64::consts::FRAC_PI_2).unwrap();
    let h = std::f64::consts::FRAC_1_SQRT_2;
    for (got, want) in q1[..7].iter().zip([2.0, 2.0, 0.0, 0.0, 0.0, h, h]) {
        assert!((got - want).abs() < 1e-15, "{q1:?}");
    }
    // difference inverts integrate.
    let mut rng = SplitMix64(9);
    for _ in 0..100 {
        let a = configuration::random(&kin, &mut rng);
        let v: Vec<f64> = (0..13).map(|_| 2.0 * rng.uniform() - 1.0).collect();
        let b = configuration::integrate(&kin, &a, &v, 0.7).unwrap();
        let d = configuration::difference(&kin, &a, &b).unwrap();
        for (x, y) in d.iter().zip(&v) {
            assert!((x - 0.7 * y).abs() < 1e-12);
        }
        let qn: f64 = b[3..7].iter().map(|x| x * x).sum();
        assert!((qn - 1.0).abs() < 1e-15);
    }
    // A quaternion far from unit length is refused, naming it; near unit length accepted.
    let mut bad = q0.clone();
    bad[6] = 0.5;
    let e = kin.check_q(&bad).unwrap_err().to_string();
    assert!(e.contains("quaternion") && e.contains("norm 0.5"), "{e}");
    bad[6] = 1.0 + 1e-7;
    assert!(kin.check_q(&bad).is_ok());
    assert!(configuration::integrate(&kin, &q0, &v[..12], 0.1).is_err());
}

#[test]
fn batches_equal_single_calls_and_report_bad_rows() {
    let tree = tree_of(&screwkit_testkit::bundled("torso_two_arms.urdf"));
    for floating in [false, true] {
        let (_, kin) = prepared(&tree, floating);
        let mut ws = TreeWorkspace::new(&kin);
        let mut rng = SplitMix64(1);
        let n = 600;
        let mut qs: Vec<f64> = (0..n)
            .flat_map(|_| configuration::random(&kin, &mut rng))
            .collect();
        qs[17 * kin.nq() + 2] = f64::NAN;
        let frames = kin.frame_count();
        let mut all = vec![0.0; n * frames * 16];
        let e = batch::fk_frames_batch(&kin, &qs, &mut all).unwrap_err();
        assert!(e.to_string().starts_with("row 17:"), "{e}");
        let f = frames - 1;
        let mut one = vec![0.0; n * 16];
        assert!(batch::fk_frame_batch(&kin, f, &qs, &mut one).is_err());
        let nv = kin.nv();
        let mut jac = vec![0.0; n * 6 * nv];
        let mut poses = vec![0.0; n * 16];
        assert!(batch::frame_jacobian_batch(
            &kin,
            f,
            JacobianKind::Body,
            &qs,
            &mut jac,
            Some(&mut poses)
        )
        .is_err());
        let mut rel = vec![0.0; n * 6 * nv];
        assert!(batch::relative_jacobian_batch(
            &kin,
            (f, 1),
            JacobianKind::Space,
            &qs,
            &mut rel,
            None
        )
        .is_err());
        for k in 0..n {
            let q = &qs[k * kin.nq()..(k + 1) * kin.nq()];
            if k == 17 {
                assert!(all[k * frames * 16..(k + 1) * frames * 16]
                    .iter()
                    .all(|x| x.is_nan()));
                assert!(jac[k * 6 * nv..(k + 1) * 6 * nv].iter().all(|x| x.is_nan()));
                continue;
            }
            let single = fk::fk_frames(&kin, &mut ws, q).unwrap().to_vec();
            for (i, t) in single.iter().enumerate() {
                let mut m = [0.0; 16];
                t.write_row_major(&mut m);
                assert_eq!(&all[(k * frames + i) * 16..(k * frames + i + 1) * 16], &m);
            }
            let mut m = [0.0; 16];
            fk::fk_frame(&kin, &mut ws, q, f)
                .unwrap()
                .write_row_major(&mut m);
            assert_eq!(&one[k * 16..(k + 1) * 16], &m);
            let pj =
                jacobian::frame_pose_jacobian(&kin, &mut ws, q, f, JacobianKind::Body).unwrap();
            pj.pose.write_row_major(&mut m);
            assert_eq!(&poses[k * 16..(k + 1) * 16], &m);
            let j = pj.jacobian;
            for r in 0..6 {
                for c in 0..nv {
                    assert_eq!(jac[k * 6 * nv + r * nv + c], j[(r, c)]);
                }
            }
            let j = jacobian::relative_jacobian(&kin, &mut ws, q, f, 1, JacobianKind::Space)
                .unwrap()
                .jacobian;
            for r in 0..6 {
                for c in 0..nv {
                    assert_eq!(rel[k * 6 * nv + r * nv + c], j[(r, c)]);
                }
            }
        }
    }
}

#[test]
fn frames_errors_name_what_is_wrong() {
    let tree = tree_of(&screwkit_testkit::bundled("torso_two_arms.urdf"));
    let mut model = KinematicTree::from_tree(&tree).unwrap();
    let e = model.frame("no_such_hand").unwrap_err().to_string();
    assert!(e.contains("unknown frame \"no_such_hand\""), "{e}");
    let link = model.links[1].name.clone();
    let e = model
        .add_frame(&link, &link, Se3::identity())
        .unwrap_err()
        .to_string();
    assert!(e.contains("duplicate frame"), "{e}");
    let e = model
        .add_frame("tcp", "nowhere", Se3::identity())
        .unwrap_err()
        .to_string();
    assert!(e.contains("nowhere"), "{e}");
    let kin = TreeKinematics::new(&model).unwrap();
    let mut ws = TreeWorkspace::new(&kin);
    let e = fk::fk_frame(&kin, &mut ws, &[0.0; 7], 999)
        .unwrap_err()
        .to_string();
    assert!(e.contains("out of range"), "{e}");
    let e = fk::fk_frames(&kin, &mut ws, &[0.0; 6])
        .unwrap_err()
        .to_string();
    assert!(e.contains("expected 7"), "{e}");
}

/// A 20,000-link chain (hostile depth): preparing the tree is linear — the chains of the frames
/// are built on first use, not one per frame up front (which took 25 s and 3 GB at 3,000 links,
/// and would not fit in memory here).
#[test]
fn a_deep_tree_prepares_in_linear_work() {
    let n = 20_000;
    let mut xml = String::from("<robot name=\"deep\">");
    for i in 0..=n {
        xml.push_str(&format!("<link name=\"l{i}\"/>"));
    }
    for i in 0..n {
        xml.push_str(&format!(
            "<joint name=\"j{i}\" type=\"revolute\"><parent link=\"l{i}\"/><child link=\"l{}\"/><origin xyz=\"0 0 0.001\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>",
            i + 1
        ));
    }
    xml.push_str("</robot>");
    let tree = urdf::load_str(&xml, "deep").unwrap();
    let model = KinematicTree::from_tree(&tree).unwrap();
    let kin = TreeKinematics::new(&model).unwrap();
    let mut ws = TreeWorkspace::new(&kin);
    let q = vec![0.0; n];
    let tip = kin.frame(&format!("l{n}")).unwrap();
    let t = fk::fk_frame(&kin, &mut ws, &q, tip).unwrap();
    assert!((t.translation().z - 0.001 * n as f64).abs() < 1e-9);
    let all = fk::fk_frames(&kin, &mut ws, &q).unwrap();
    assert!((all[tip].translation().z - 0.001 * n as f64).abs() < 1e-9);
}
