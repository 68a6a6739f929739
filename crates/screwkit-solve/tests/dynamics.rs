//! Dynamics against closed forms: the two-link planar arm with point masses (*Modern
//! Robotics*, Example 8.1), whose mass matrix, Coriolis and gravity terms are written out by
//! hand; forward dynamics inverting inverse dynamics; the energy's rate equal to vᵀτ along a
//! simulated motion.

use nalgebra::Vector3;
use screwkit_model::{urdf, KinematicTree};
use screwkit_solve::tree::dynamics::{self, Dynamics, DynamicsWorkspace};
use screwkit_solve::TreeKinematics;

const L1: f64 = 0.7;
const L2: f64 = 0.45;
const M1: f64 = 1.3;
const M2: f64 = 0.8;
const G: f64 = 9.81;

/// The arm in the xy-plane, joints about z, a point mass at each link's end; gravity along −y.
fn arm() -> Dynamics {
    let text = format!(
        r#"<robot name="two_link">
  <link name="base"/>
  <link name="l1"><inertial><origin xyz="{L1} 0 0"/><mass value="{M1}"/>
    <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
  <link name="l2"><inertial><origin xyz="{L2} 0 0"/><mass value="{M2}"/>
    <inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial></link>
  <joint name="j1" type="continuous"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/></joint>
  <joint name="j2" type="continuous"><parent link="l1"/><child link="l2"/>
    <origin xyz="{L1} 0 0"/><axis xyz="0 0 1"/></joint>
</robot>"#
    );
    let tree = urdf::load_str(&text, "two_link.urdf").unwrap();
    let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    Dynamics::new(&kin, false)
        .unwrap()
        .with_gravity(Vector3::new(0.0, -G, 0.0))
}

/// MR Example 8.1: τ = M(θ) θ̈ + c(θ, θ̇) + g(θ).
fn closed_form(q: [f64; 2], v: [f64; 2], a: [f64; 2]) -> ([[f64; 2]; 2], [f64; 2]) {
    let (c1, c2, s2) = (q[0].cos(), q[1].cos(), q[1].sin());
    let c12 = (q[0] + q[1]).cos();
    let m11 = M1 * L1 * L1 + M2 * (L1 * L1 + 2.0 * L1 * L2 * c2 + L2 * L2);
    let m12 = M2 * (L1 * L2 * c2 + L2 * L2);
    let m22 = M2 * L2 * L2;
    let c = [
        -M2 * L1 * L2 * s2 * (2.0 * v[0] * v[1] + v[1] * v[1]),
        M2 * L1 * L2 * v[0] * v[0] * s2,
    ];
    let g = [
        (M1 + M2) * L1 * G * c1 + M2 * G * L2 * c12,
        M2 * G * L2 * c12,
    ];
    let tau = [
        m11 * a[0] + m12 * a[1] + c[0] + g[0],
        m12 * a[0] + m22 * a[1] + c[1] + g[1],
    ];
    ([[m11, m12], [m12, m22]], tau)
}

#[test]
fn the_two_link_arm_follows_its_closed_form() {
    let d = arm();
    let mut ws = DynamicsWorkspace::new(&d);
    let mut rng = screwkit_solve::sample::SplitMix64(3);
    let mut r = || 4.0 * rng.uniform() - 2.0;
    for _ in 0..50 {
        let (q, v, a) = ([r(), r()], [r(), r()], [r(), r()]);
        let (m, tau) = closed_form(q, v, a);
        let got = dynamics::inverse_dynamics(&d, &mut ws, &q, &v, &a)
            .unwrap()
            .to_vec();
        for k in 0..2 {
            assert!((got[k] - tau[k]).abs() < 1e-12, "τ {got:?} vs {tau:?}");
        }
        let mass = dynamics::mass_matrix(&d, &mut ws, &q).unwrap().clone();
        for i in 0..2 {
            for j in 0..2 {
                assert!((mass[(i, j)] - m[i][j]).abs() < 1e-13, "M {mass} vs {m:?}");
            }
        }
        let (_, g) = closed_form(q, [0.0; 2], [0.0; 2]);
        let got = dynamics::gravity(&d, &mut ws, &q).unwrap().to_vec();
        assert!((got[0] - g[0]).abs() < 1e-12 && (got[1] - g[1]).abs() < 1e-12);
        let back = dynamics::forward_dynamics(&d, &mut ws, &q, &v, &tau)
            .unwrap()
            .to_vec();
        assert!(
            (back[0] - a[0]).abs() < 1e-10 && (back[1] - a[1]).abs() < 1e-10,
            "{back:?}"
        );
    }
}

/// Along a motion driven by forces τ(t) (semi-implicit Euler of FD, 10 µs steps), the total
/// energy's rate equals the power vᵀτ: E(T) − E(0) = ∫ vᵀτ dt within the integrator's error.
#[test]
fn energy_changes_by_the_work_of_the_forces() {
    let d = arm();
    let mut ws = DynamicsWorkspace::new(&d);
    let (mut q, mut v) = ([0.3, -0.4], [0.5, -1.0]);
    let energy = |ws: &mut DynamicsWorkspace, q: &[f64; 2], v: &[f64; 2]| {
        dynamics::kinetic_energy(&d, ws, q, v).unwrap()
            + dynamics::potential_energy(&d, ws, q).unwrap()
    };
    let start = energy(&mut ws, &q, &v);
    let (dt, steps) = (1e-5, 50_000);
    let mut work = 0.0;
    for k in 0..steps {
        let t = k as f64 * dt;
        let tau = [2.0 * (3.0 * t).sin(), -1.0 + t];
        let a = dynamics::forward_dynamics(&d, &mut ws, &q, &v, &tau)
            .unwrap()
            .to_vec();
        let v_next = [v[0] + a[0] * dt, v[1] + a[1] * dt];
        // The power at the step's mean velocity (trapezoid).
        work += dt * (tau[0] * (v[0] + v_next[0]) + tau[1] * (v[1] + v_next[1])) / 2.0;
        v = v_next;
        q = [q[0] + v[0] * dt, q[1] + v[1] * dt];
    }
    let end = energy(&mut ws, &q, &v);
    let change = end - start;
    assert!(work.abs() > 0.1, "the forces did work: {work}");
    assert!(
        (change - work).abs() < 2e-3 * work.abs().max(1.0),
        "ΔE {change} vs work {work}"
    );
}

/// The articulated-body algorithm and M⁻¹ (τ − h) (the factorised mass matrix) give the same
/// accelerations on the bundled humanoid, fixed and floating (Pinocchio's `aba` is the
/// independent oracle of both, in the Python suite).
#[test]
fn the_articulated_body_algorithm_equals_the_mass_matrix_solve() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/urdf/humanoid.urdf"
    );
    let tree = urdf::load_file(path).unwrap();
    for floating in [false, true] {
        let model = KinematicTree::from_tree(&tree)
            .unwrap()
            .with_floating_base(floating);
        let kin = TreeKinematics::new(&model).unwrap();
        let d = Dynamics::new(&kin, false).unwrap();
        let mut ws = DynamicsWorkspace::new(&d);
        let mut rng = screwkit_solve::sample::SplitMix64(11);
        for _ in 0..20 {
            let q = screwkit_solve::tree::configuration::random(&kin, &mut rng);
            let v: Vec<f64> = (0..kin.nv()).map(|_| rng.uniform() - 0.5).collect();
            let tau: Vec<f64> = (0..kin.nv()).map(|_| 10.0 * rng.uniform() - 5.0).collect();
            let a = dynamics::aba(&d, &mut ws, &q, &v, &tau).unwrap().to_vec();
            let b = dynamics::forward_dynamics_tip(&d, &mut ws, &q, &v, &tau, &[0.0; 6])
                .unwrap()
                .to_vec();
            let worst = a
                .iter()
                .zip(&b)
                .map(|(x, y)| (x - y).abs() / (1.0 + y.abs()))
                .fold(0.0, f64::max);
            assert!(worst < 1e-9, "floating {floating}: {worst:e}");
        }
    }
}

/// The mass matrix (the composite-rigid-body pass in the root link's frame) has for columns
/// the inverse dynamics (Newton–Euler in each joint's own frame) of unit accelerations at rest,
/// less gravity: M e_i = ID(q, 0, e_i) − g(q). On files with mimic (coupled) and prismatic
/// joints, fixed and floating, and a textbook chain with helical joints and unnormalised axes.
#[test]
fn the_mass_matrix_columns_are_inverse_dynamics_of_unit_accelerations() {
    let asset = |f: &str| format!("{}/../../assets/{f}", env!("CARGO_MANIFEST_DIR"));
    let mut models = Vec::new();
    for (file, floating) in [
        ("urdf/gripper_arm.urdf", false),
        ("urdf/tricky.urdf", false),
        ("urdf/humanoid.urdf", true),
        ("mjcf/humanoid.xml", true),
        ("urdf/torso_two_arms.urdf", true),
    ] {
        let tree = screwkit_model::load_tree(asset(file), &Default::default()).unwrap();
        let model = KinematicTree::from_tree(&tree)
            .unwrap()
            .with_floating_base(floating);
        let kin = TreeKinematics::new(&model).unwrap();
        models.push((file.to_string(), Dynamics::new(&kin, true).unwrap()));
    }
    models.push(("helical chain".into(), helical_chain()));
    for (name, d) in &models {
        let mut ws = DynamicsWorkspace::new(d);
        let nv = d.nv();
        let mut rng = screwkit_solve::sample::SplitMix64(5);
        for _ in 0..10 {
            let q = match d.kinematics() {
                Some(kin) => screwkit_solve::tree::configuration::random(kin, &mut rng),
                None => (0..nv).map(|_| 4.0 * rng.uniform() - 2.0).collect(),
            };
            let m = dynamics::mass_matrix(d, &mut ws, &q).unwrap().clone();
            let g = dynamics::gravity(d, &mut ws, &q).unwrap().to_vec();
            let zero = vec![0.0; nv];
            let scale = m.amax().max(1.0);
            for i in 0..nv {
                let mut e = zero.clone();
                e[i] = 1.0;
                let col = dynamics::inverse_dynamics(d, &mut ws, &q, &zero, &e).unwrap();
                for r in 0..nv {
                    let want = col[r] - g[r];
                    assert!(
                        (m[(r, i)] - want).abs() < 1e-10 * scale,
                        "{name}: M({r}, {i}) = {} but ID − g = {want}",
                        m[(r, i)]
                    );
                }
            }
            assert!(m.iter().all(|x| x.is_finite()), "{name}");
            assert_eq!(m, m.transpose(), "{name}: M exactly symmetric");
        }
    }
}

/// A textbook (M, G, S) chain of four joints: revolute, helical (pitch 0.05), prismatic, and a
/// revolute whose axis is given with |ω| = 2 (taken as 2 θ about the unit axis).
fn helical_chain() -> Dynamics {
    use nalgebra::{Matrix3, Matrix6};
    use screwkit_lie::{Se3, Twist};
    let at = |x: f64, y: f64, z: f64| {
        Se3::from_parts_unchecked(Matrix3::identity(), Vector3::new(x, y, z))
    };
    let m_list = [
        at(0.0, 0.0, 0.2),
        at(0.3, 0.0, 0.0),
        at(0.0, 0.25, 0.1),
        at(0.2, 0.0, 0.0),
        at(0.1, 0.0, 0.0),
    ];
    let body = |m: f64, c: Vector3<f64>| {
        let s = dynamics::SpatialInertia::from_com(
            m,
            c,
            Matrix3::from_diagonal(&(Vector3::new(0.01, 0.02, 0.015) * m)),
        );
        s.matrix()
    };
    let g_list: Vec<Matrix6<f64>> = vec![
        body(1.5, Vector3::new(0.1, 0.0, 0.0)),
        body(1.0, Vector3::new(0.0, 0.1, 0.05)),
        body(0.7, Vector3::new(0.05, 0.0, -0.02)),
        body(0.4, Vector3::new(0.02, 0.01, 0.0)),
    ];
    // Space screws at home: joint frames at z 0.2, then (0.3, 0, 0.2), (0.3, 0.25, 0.3),
    // (0.5, 0.25, 0.3).
    let revolute = |w: Vector3<f64>, q: Vector3<f64>| Twist::new(w, -w.cross(&q));
    let s_list = [
        revolute(Vector3::z(), Vector3::new(0.0, 0.0, 0.2)),
        {
            let (w, q) = (Vector3::x(), Vector3::new(0.3, 0.0, 0.2));
            Twist::new(w, -w.cross(&q) + w * 0.05)
        },
        Twist::new(Vector3::zeros(), Vector3::new(0.0, 0.6, 0.8)),
        revolute(Vector3::y() * 2.0, Vector3::new(0.5, 0.25, 0.3)),
    ];
    Dynamics::from_screws(&m_list, &g_list, &s_list).unwrap()
}
