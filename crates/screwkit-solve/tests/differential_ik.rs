//! Whole-body differential IK and the centre of mass against independent checks:
//!
//! - the centre of mass against the URDF composed joint by joint with the file's inertials
//!   (`testkit::reference::{tree_world_poses, tree_com}`), its Jacobian against central finite
//!   differences through `integrate` (the floating base's columns too);
//! - every `ik_step`: the QP rebuilt here from the public frame / CoM Jacobians and the
//!   tasks' definitions (H and c equal to the step's), its answer checked by the KKT conditions
//!   and against projected gradient on the same QP, and the limits (q + v·dt within the
//!   bounds, |v| within the speed limits) checked on every step of a control loop;
//! - every `ik_tasks` answer: targets made reachable by construction (FK of a random q* within
//!   limits), the reported errors recomputed from the composition oracle, q within the limits.

use nalgebra::{Matrix4, Vector3};
use screwkit_lie::Se3;
use screwkit_model::{urdf, KinematicTree, Tree};
use screwkit_solve::sample::SplitMix64;
use screwkit_solve::tree::differential_ik::{
    ik_step, ik_tasks, ik_tasks_batch, ik_trajectory, DiffIkWorkspace, Limits, Segments,
    TasksOptions, TasksProblem, TasksStop,
};
use screwkit_solve::tree::tasks::{AxisTask, ComTask, PostureTask, Task, TaskKind};
use screwkit_solve::tree::{com, configuration, fk, jacobian};
use screwkit_solve::{JacobianKind, TreeKinematics, TreeWorkspace};
use screwkit_testkit::reference::{tree_com, tree_world_poses};

fn load(path: &str, floating: bool) -> (Tree, TreeKinematics) {
    let tree = urdf::load_file(path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let model = KinematicTree::from_tree(&tree)
        .unwrap()
        .with_floating_base(floating);
    let kin = TreeKinematics::new(&model).unwrap();
    (tree, kin)
}

fn shared(file: &str) -> String {
    let dir = std::env::var("SCREWKIT_SHARED_URDF").expect("SCREWKIT_SHARED_URDF");
    format!("{dir}/trees/{file}")
}

fn se3(m: &Matrix4<f64>) -> Se3 {
    Se3::from_homogeneous_with_tolerance(m, 1e-9).unwrap()
}

/// The centre of mass and its Jacobian against the composition and finite differences.
fn check_com(label: &str, tree: &Tree, kin: &TreeKinematics, samples: usize) {
    let mut ws = TreeWorkspace::new(kin);
    let mut rng = SplitMix64(5);
    for _ in 0..samples {
        let q = configuration::random(kin, &mut rng);
        let want = tree_com(tree, &tree_world_poses(tree, kin, &q));
        let got = com::com(kin, &mut ws, &q).unwrap();
        assert!((got - want).norm() < 1e-12, "{label}: com {got} vs {want}");
        let (c2, jac) = com::com_jacobian(kin, &mut ws, &q).unwrap();
        assert!((c2 - want).norm() < 1e-12, "{label}");
        let jac = jac.clone();
        let h = 1e-6;
        for k in 0..kin.nv() {
            let mut dv = vec![0.0; kin.nv()];
            dv[k] = 1.0;
            let qp = configuration::integrate(kin, &q, &dv, h).unwrap();
            let qm = configuration::integrate(kin, &q, &dv, -h).unwrap();
            let cp = com::com(kin, &mut ws, &qp).unwrap();
            let cm = com::com(kin, &mut ws, &qm).unwrap();
            let fd = (cp - cm) / (2.0 * h);
            let col = jac.column(k);
            assert!(
                (fd - col).norm() < 1e-7,
                "{label}: CoM Jacobian column {k} ({}): {col} vs differences {fd}",
                kin.v_names()[k]
            );
        }
    }
}

#[test]
fn com_of_a_bundled_file_equals_the_composition_and_differences() {
    let path = screwkit_testkit::bundled("tricky.urdf");
    for floating in [false, true] {
        let (tree, kin) = load(&path, floating);
        assert!(com::total_mass(&kin) > 0.0);
        check_com("tricky", &tree, &kin, 20);
    }
    // A file without masses: the centre of mass is an error naming the file.
    let (_, kin) = load(&screwkit_testkit::bundled("ur5.urdf"), false);
    let mut ws = TreeWorkspace::new(&kin);
    let e = com::com(&kin, &mut ws, &vec![0.0; kin.nq()]).unwrap_err();
    assert!(e.to_string().contains("no link has a mass"), "{e}");
}

/// Weighted Jacobian rows, their right-hand sides, and the diagonal terms (index, D, D·r).
type ReferenceRows = (Vec<Vec<f64>>, Vec<f64>, Vec<(usize, f64, f64)>);

/// The rows of one task rebuilt from the public API (frame Jacobians, relative Jacobians, the
/// CoM Jacobian, FK) and the task's definition: (weighted J rows, weighted g·e).
fn reference_rows(kin: &TreeKinematics, q: &[f64], task: &Task) -> ReferenceRows {
    let mut ws = TreeWorkspace::new(kin);
    let nv = kin.nv();
    let (mut rows, mut rhs, mut diag) = (Vec::new(), Vec::new(), Vec::new());
    let w = task.weight;
    let mut push = |wr: f64, row: Vec<f64>, e: f64| {
        if wr != 0.0 {
            rows.push(row.iter().map(|x| wr * x).collect());
            rhs.push(wr * task.gain * e);
        }
    };
    // A world frame task is a relative one without the second frame.
    let frame_like = match &task.kind {
        TaskKind::Frame(f) => Some((f.frame, f.target, None)),
        TaskKind::Relative(r) => Some((r.frame, r.target, Some(r.relative_to))),
        _ => None,
    };
    match &task.kind {
        TaskKind::Frame(_) | TaskKind::Relative(_) => {
            let (frame, target, relative_to) = frame_like.expect("a frame task");
            let (frame, target) = (&frame, &target);
            let (pose, jac) = match relative_to {
                None => {
                    let pj =
                        jacobian::frame_pose_jacobian(kin, &mut ws, q, *frame, JacobianKind::Body)
                            .unwrap();
                    (pj.pose, pj.jacobian.clone())
                }
                Some(b) => {
                    let pj =
                        jacobian::relative_jacobian(kin, &mut ws, q, *frame, b, JacobianKind::Body)
                            .unwrap();
                    (pj.pose, pj.jacobian.clone())
                }
            };
            let xi = pose.inverse_compose(target).log();
            let jac = screwkit_lie::se3::left_jacobian_inverse(&xi) * jac;
            for r in 0..6 {
                let (wr, e) = if r < 3 {
                    (w * task.orientation_weight[r], xi.w[r])
                } else {
                    (w * task.position_weight[r - 3], xi.v[r - 3])
                };
                push(wr, jac.row(r).iter().copied().collect(), e);
            }
        }
        TaskKind::Axis(AxisTask {
            frame,
            axis,
            direction,
            point,
        }) => {
            let pj =
                jacobian::frame_pose_jacobian(kin, &mut ws, q, *frame, JacobianKind::WorldAligned)
                    .unwrap();
            let (pose, jac) = (pj.pose, pj.jacobian.clone());
            let aw = pose.rotation() * axis.normalize();
            let d = direction.normalize();
            let b1 = aw.cross(&d).normalize();
            let b2 = aw.cross(&b1);
            let theta = aw.dot(&d).clamp(-1.0, 1.0).acos();
            for (b, e) in [(b1, theta), (b2, 0.0)] {
                let row = (0..nv)
                    .map(|c| b.dot(&jac.fixed_view::<3, 1>(0, c).into_owned()))
                    .collect();
                push(w * task.orientation_weight[0], row, e);
            }
            if let Some(p) = point {
                let e = p - pose.translation();
                for r in 0..3 {
                    push(
                        w * task.position_weight[r],
                        jac.row(3 + r).iter().copied().collect(),
                        e[r],
                    );
                }
            }
        }
        TaskKind::Com(ComTask { target }) => {
            let (c, jac) = com::com_jacobian(kin, &mut ws, q).unwrap();
            let e = target - c;
            for r in 0..3 {
                push(
                    w * task.position_weight[r],
                    jac.row(r).iter().copied().collect(),
                    e[r],
                );
            }
        }
        TaskKind::Posture(PostureTask { q_ref }) => {
            let (qo, vo) = (
                kin.nq() - kin.model().variables.len(),
                nv - kin.model().variables.len(),
            );
            for j in 0..kin.model().variables.len() {
                let e = q_ref[qo + j] - q[qo + j];
                diag.push((vo + j, w * w, w * w * task.gain * e));
            }
        }
        TaskKind::Damping(_) => {
            for k in 0..nv {
                diag.push((k, w * w, 0.0));
            }
        }
    }
    (rows, rhs, diag)
}

/// Checks one step: H and c against the rebuilt QP (ε aside), KKT of Δ = v·dt, the limits.
fn check_step(
    label: &str,
    kin: &TreeKinematics,
    q: &[f64],
    tasks: &[Task],
    dt: f64,
    v: &[f64],
    ws: &DiffIkWorkspace,
) {
    let nv = kin.nv();
    let (h, c, l, u) = ws.qp();
    let mut h_ref = vec![0.0; nv * nv];
    let mut c_ref = vec![0.0; nv];
    for t in tasks {
        let (rows, rhs, diag) = reference_rows(kin, q, t);
        for (row, b) in rows.iter().zip(&rhs) {
            for i in 0..nv {
                c_ref[i] -= row[i] * b;
                for j in 0..nv {
                    h_ref[i * nv + j] += row[i] * row[j];
                }
            }
        }
        for (k, d, dr) in diag {
            h_ref[k * nv + k] += d;
            c_ref[k] -= dr;
        }
    }
    let scale = h_ref.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for i in 0..nv {
        for j in 0..=i {
            let eps = if i == j { 1e-9 * scale } else { 0.0 };
            assert!(
                (h[i * nv + j] - h_ref[i * nv + j]).abs() <= 1e-10 * scale + eps,
                "{label}: H[{i}][{j}] {} vs {}",
                h[i * nv + j],
                h_ref[i * nv + j]
            );
        }
        assert!(
            (c[i] - c_ref[i]).abs() <= 1e-10 * scale,
            "{label}: c[{i}] {} vs {}",
            c[i],
            c_ref[i]
        );
    }
    // KKT of Δ on the step's own (H, c, l, u).
    let delta: Vec<f64> = v.iter().map(|x| x * dt).collect();
    let gscale = c.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for i in 0..nv {
        assert!(
            delta[i] >= l[i] - 1e-15 && delta[i] <= u[i] + 1e-15,
            "{label}: Δ[{i}] outside the box"
        );
        let g = c[i]
            + (0..nv)
                .map(|j| {
                    let hij = if j <= i { h[i * nv + j] } else { h[j * nv + i] };
                    hij * delta[j]
                })
                .sum::<f64>();
        let tol = 1e-9 * gscale;
        // Δ = v·dt comes back from v = Δ/dt: a variable held at a bound may read a few ulps
        // inside it.
        let ulps = |b: f64| 8.0 * f64::EPSILON * b.abs().max(f64::MIN_POSITIVE);
        let (at_l, at_u) = (delta[i] <= l[i] + ulps(l[i]), delta[i] >= u[i] - ulps(u[i]));
        if !at_l && !at_u {
            assert!(g.abs() <= tol, "{label}: free gradient {i}: {g}");
        } else if at_l {
            assert!(g >= -tol, "{label}: lower multiplier {i}: {g}");
        } else {
            assert!(g <= tol, "{label}: upper multiplier {i}: {g}");
        }
    }
    check_limits(label, kin, q, v, dt);
}

/// q + v·dt within the joints' bounds (their file limits, mimic followers' included) and
/// |v| within the file's velocity limits, read from the file's joints here.
fn check_limits(label: &str, kin: &TreeKinematics, q: &[f64], v: &[f64], dt: f64) {
    let model = kin.model();
    let (qo, vo) = (
        kin.nq() - model.variables.len(),
        kin.nv() - model.variables.len(),
    );
    for j in &model.joints {
        let tj = &model.tree.joints[model.tree.joint(&j.name).unwrap()];
        let Some(limit) = tj.limit else { continue };
        let d = j.drive;
        let theta = d.multiplier * (q[qo + d.variable] + v[vo + d.variable] * dt) + d.offset;
        if tj.kind != screwkit_model::JointKind::Continuous {
            let tol = 1e-12 * limit.lower.abs().max(limit.upper.abs()).max(1.0);
            assert!(
                theta >= limit.lower - tol && theta <= limit.upper + tol,
                "{label}: joint {} at {theta} outside [{}, {}]",
                j.name,
                limit.lower,
                limit.upper
            );
        }
        if let Some(speed) = limit.velocity.filter(|s| *s > 0.0) {
            let rate = (d.multiplier * v[vo + d.variable]).abs();
            assert!(
                rate <= speed * (1.0 + 1e-12),
                "{label}: joint {} at speed {rate} > {speed}",
                j.name
            );
        }
    }
}

/// Independent errors of a frame task from the composition oracle at q.
fn frame_error(tree: &Tree, kin: &TreeKinematics, q: &[f64], task: &Task) -> (f64, f64) {
    let poses = tree_world_poses(tree, kin, q);
    let pose_of = |f: usize| {
        let fr = &kin.model().frames[f];
        se3(&poses[fr.link]).compose(&fr.placement)
    };
    let frame_like = match &task.kind {
        TaskKind::Frame(f) => Some((f.frame, f.target, None)),
        TaskKind::Relative(r) => Some((r.frame, r.target, Some(r.relative_to))),
        _ => None,
    };
    match &task.kind {
        TaskKind::Frame(_) | TaskKind::Relative(_) => {
            let (frame, target, relative_to) = frame_like.expect("a frame task");
            let target = &target;
            let mut t = pose_of(frame);
            if let Some(b) = relative_to {
                t = pose_of(b).inverse_compose(&t);
            }
            let xi = t.inverse_compose(target).log();
            let rot: f64 = (0..3)
                .filter(|&r| task.orientation_weight[r] != 0.0)
                .map(|r| xi.w[r] * xi.w[r])
                .sum();
            let pos: f64 = (0..3)
                .filter(|&r| task.position_weight[r] != 0.0)
                .map(|r| xi.v[r] * xi.v[r])
                .sum();
            (pos.sqrt(), rot.sqrt())
        }
        TaskKind::Axis(AxisTask {
            frame,
            axis,
            direction,
            point,
        }) => {
            let t = pose_of(*frame);
            let aw = t.rotation() * axis.normalize();
            let d = direction.normalize();
            let rot = aw.cross(&d).norm().atan2(aw.dot(&d));
            let pos = point.map_or(0.0, |p| (p - t.translation()).norm());
            (pos, rot)
        }
        TaskKind::Com(ComTask { target }) => ((target - tree_com(tree, &poses)).norm(), 0.0),
        TaskKind::Posture(_) | TaskKind::Damping(_) => (0.0, 0.0),
    }
}

fn position_only(mut t: Task) -> Task {
    t.orientation_weight = [0.0; 3];
    t
}

/// The targets of `frames` at q* (world poses), by the library's FK.
fn frame_targets(kin: &TreeKinematics, q: &[f64], frames: &[usize]) -> Vec<Se3> {
    let mut ws = TreeWorkspace::new(kin);
    frames
        .iter()
        .map(|&f| fk::fk_frame(kin, &mut ws, q, f).unwrap())
        .collect()
}

/// A random configuration strictly inside the bounds (mimic followers' included).
fn inside(kin: &TreeKinematics, rng: &mut SplitMix64) -> Vec<f64> {
    loop {
        let q = configuration::random(kin, rng);
        let v = vec![0.0; kin.nv()];
        let ok = std::panic::catch_unwind(|| check_limits("sample", kin, &q, &v, 0.0)).is_ok();
        if ok {
            return q;
        }
    }
}

/// Solves `count` reachable problems made by `make(q*) -> tasks`; checks every answer
/// independently; returns the converged count.
fn run_reachable(
    label: &str,
    tree: &Tree,
    kin: &TreeKinematics,
    count: usize,
    seed: &dyn Fn(&mut SplitMix64) -> Vec<f64>,
    make: &dyn Fn(&[f64]) -> Vec<Task>,
) -> usize {
    let mut rng = SplitMix64(42);
    let mut ws = DiffIkWorkspace::new(kin);
    let mut converged = 0;
    for i in 0..count {
        let qstar = inside(kin, &mut rng);
        let tasks = make(&qstar);
        let q0 = seed(&mut rng);
        let r = ik_tasks(kin, &mut ws, &tasks, &q0, &TasksOptions::default()).unwrap();
        check_limits(label, kin, &r.q, &vec![0.0; kin.nv()], 0.0);
        for (t, e) in tasks.iter().zip(&r.task_errors) {
            if !t.is_goal() {
                continue;
            }
            let (pos, rot) = frame_error(tree, kin, &r.q, t);
            assert!(
                (pos - e.position).abs() < 1e-9 && (rot - e.rotation).abs() < 1e-9,
                "{label} problem {i}: reported {e:?}, recomputed ({pos}, {rot})"
            );
            if r.converged {
                assert!(
                    pos <= t.tol_pos + 1e-12 && rot <= t.tol_rot + 1e-12,
                    "{label} {i}"
                );
            }
        }
        assert_eq!(
            r.converged,
            r.stop == TasksStop::Converged,
            "{label}: {r:?}"
        );
        converged += r.converged as usize;
        if !r.converged {
            eprintln!(
                "{label} problem {i}: {:?} after {} iterations: {:?}",
                r.stop, r.iterations, r.task_errors
            );
        }
    }
    eprintln!("{label}: {converged} / {count} converged");
    converged
}

#[test]
fn torso_two_arms_reaches_both_hands_and_every_step_is_the_qp_optimum() {
    let path = screwkit_testkit::bundled("torso_two_arms.urdf");
    let (tree, kin) = load(&path, false);
    let l = kin.frame("left_hand").unwrap();
    let r = kin.frame("right_hand").unwrap();
    // 7 joints for two hands: their positions (6 rows) leave one degree of redundancy.
    let make = |qs: &[f64]| {
        let t = frame_targets(&kin, qs, &[l, r]);
        vec![
            position_only(Task::frame(l, t[0])),
            position_only(Task::frame(r, t[1])),
            Task::posture(vec![0.0; kin.nq()]).with_weight(1e-2),
        ]
    };
    let n = run_reachable(
        "torso_two_arms",
        &tree,
        &kin,
        40,
        &|_| vec![0.0; kin.nq()],
        &make,
    );
    assert_eq!(n, 40, "torso_two_arms");
    // A control loop towards out-of-reach targets: every step the QP's optimum, within limits.
    let mut ws = DiffIkWorkspace::new(&kin);
    let mut q = vec![0.0; kin.nq()];
    let far = Se3::from_translation(Vector3::new(2.0, 1.0, 0.5));
    let tasks = vec![
        Task::frame(l, far),
        Task::frame(r, far).with_weight(0.5),
        Task::relative(l, r, Se3::from_translation(Vector3::new(0.0, 0.1, 0.0))),
        Task::damping(1e-3),
    ];
    let limits = Limits::default();
    for step in 0..200 {
        let v = ik_step(&kin, &mut ws, &q, &tasks, 0.02, &limits)
            .unwrap()
            .to_vec();
        check_step(
            &format!("torso step {step}"),
            &kin,
            &q,
            &tasks,
            0.02,
            &v,
            &ws,
        );
        q = configuration::integrate(&kin, &q, &v, 0.02).unwrap();
    }
}

#[test]
fn q_outside_its_limits_is_reported_and_bad_tasks_are_named() {
    let (_, kin) = load(&screwkit_testkit::bundled("torso_two_arms.urdf"), false);
    let mut ws = DiffIkWorkspace::new(&kin);
    let l = kin.frame("left_hand").unwrap();
    let tasks = vec![Task::frame(l, Se3::identity())];
    let mut q = vec![0.0; kin.nq()];
    q[1] = 10.0;
    let e = ik_step(&kin, &mut ws, &q, &tasks, 0.01, &Limits::default()).unwrap_err();
    assert!(
        e.to_string().contains("outside its limits") && e.to_string().contains(&kin.q_names()[1]),
        "{e}"
    );
    let e = ik_tasks(&kin, &mut ws, &tasks, &q, &TasksOptions::default()).unwrap_err();
    assert!(e.to_string().contains("outside its limits"), "{e}");
    q[1] = 0.0;
    for (bad, words) in [
        (Task::frame(999, Se3::identity()), "frame index 999"),
        (Task::frame(l, Se3::identity()).with_gain(0.0), "gain 0"),
        (
            Task::frame(l, Se3::identity()).with_weight(f64::NAN),
            "weight NaN",
        ),
        (Task::posture(vec![0.0; 2]), "q_ref has 2 values"),
        (
            Task::axis(l, Vector3::zeros(), Vector3::z(), None),
            "axis (0, 0, 0) has no direction",
        ),
        (Task::com(Vector3::zeros()), "no link has a mass"),
    ] {
        let e = ik_step(
            &kin,
            &mut ws,
            &q,
            &[Task::damping(1e-3), bad],
            0.01,
            &Limits::default(),
        )
        .unwrap_err();
        let s = e.to_string();
        assert!(
            s.contains("task 1") && s.contains(words),
            "{s} (wanted {words})"
        );
    }
    for dt in [0.0, -1.0, f64::NAN] {
        assert!(ik_step(&kin, &mut ws, &q, &tasks, dt, &Limits::default()).is_err());
    }
    // Finite numbers whose squares overflow (found by the task-JSON fuzzer: a NaN step): an
    // error, never a NaN velocity or configuration.
    let far =
        Se3::from_parts(nalgebra::Matrix3::identity(), Vector3::new(1e300, 0.0, 0.0)).unwrap();
    for (set, what) in [
        (
            vec![Task::frame(l, Se3::identity()), Task::damping(1e308)],
            "a huge weight",
        ),
        (vec![Task::frame(l, far)], "a target at 1e300 m"),
    ] {
        let e = ik_step(&kin, &mut ws, &q, &set, 0.01, &Limits::default()).unwrap_err();
        assert!(e.to_string().contains("overflows"), "{what}: {e}");
        let e = ik_tasks(&kin, &mut ws, &set, &q, &TasksOptions::default()).unwrap_err();
        assert!(e.to_string().contains("overflows"), "{what}: {e}");
    }
}

#[test]
fn batches_and_trajectories_equal_the_single_calls_whatever_the_threads() {
    let (_, kin) = load(&screwkit_testkit::bundled("torso_two_arms.urdf"), false);
    let l = kin.frame("left_hand").unwrap();
    let r = kin.frame("right_hand").unwrap();
    let mut rng = SplitMix64(3);
    let sets: Vec<Vec<Task>> = (0..24)
        .map(|k| {
            let mut q = vec![0.0; kin.nq()];
            for (i, x) in q.iter_mut().enumerate() {
                *x = 0.3 * ((k as f64) * 0.1 + i as f64).sin() + 0.01 * rng.uniform();
            }
            let t = frame_targets(&kin, &q, &[l, r]);
            vec![
                position_only(Task::frame(l, t[0])),
                position_only(Task::frame(r, t[1])),
                Task::posture(vec![0.0; kin.nq()]).with_weight(1e-2),
            ]
        })
        .collect();
    let seed = vec![0.0; kin.nq()];
    let opts = TasksOptions::default();
    let problems: Vec<TasksProblem> = sets
        .iter()
        .enumerate()
        .map(|(row, t)| TasksProblem {
            tasks: t.clone(),
            seed: seed.clone(),
            row,
        })
        .collect();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let batch = ik_tasks_batch(&kin, &problems, &opts);
            let seq = ik_trajectory(&kin, &sets, &seed, &opts, Segments::default()).unwrap();
            let seg = ik_trajectory(
                &kin,
                &sets,
                &seed,
                &opts,
                Segments {
                    length: 5,
                    warm_up: 2,
                },
            )
            .unwrap();
            (batch, seq, seg)
        })
    };
    let (b1, s1, g1) = run(1);
    let (b2, s2, g2) = run(2);
    let mut ws = DiffIkWorkspace::new(&kin);
    let mut q = seed.clone();
    for k in 0..sets.len() {
        let row = TasksOptions {
            seed: screwkit_solve::batch::row_seed(opts.seed, k),
            ..opts.clone()
        };
        let single = ik_tasks(&kin, &mut ws, &sets[k], &seed, &row).unwrap();
        assert_eq!(b1[k].as_ref().unwrap(), &single);
        assert_eq!(b2[k].as_ref().unwrap(), &single);
        let chained = ik_tasks(&kin, &mut ws, &sets[k], &q, &opts).unwrap();
        q = chained.q.clone();
        assert_eq!(
            s1[k].as_ref().unwrap(),
            &chained,
            "the trajectory seeds by the previous answer"
        );
        assert_eq!(s2[k].as_ref().unwrap(), &chained);
        assert_eq!(
            g1[k].as_ref().unwrap(),
            g2[k].as_ref().unwrap(),
            "segments: threads do not matter"
        );
        assert!(g1[k].as_ref().unwrap().converged);
    }
}

/// The whole robots of ../shared/urdf/trees (run by `.ci/run` with `--ignored`).
#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn shared_trees_com_equals_the_composition_and_differences() {
    for file in [
        "talos_full_v2.urdf",
        "baxter.urdf",
        "allegro_right_hand.urdf",
        "so101.urdf",
    ] {
        for floating in [false, true] {
            let (tree, kin) = load(&shared(file), floating);
            check_com(file, &tree, &kin, 2);
        }
    }
}

#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn talos_floating_feet_hands_posture_and_com() {
    let (tree, kin) = load(&shared("talos_full_v2.urdf"), true);
    let names = [
        "left_sole_link",
        "right_sole_link",
        "gripper_left_base_link",
        "gripper_right_base_link",
    ];
    let frames: Vec<usize> = names.iter().map(|n| kin.frame(n).unwrap()).collect();
    // The neutral configuration with its joints brought within their limits.
    let mut neutral = configuration::neutral(&kin);
    for (x, (l, u)) in neutral
        .iter_mut()
        .zip(kin.lower().into_iter().zip(kin.upper()))
        .skip(7)
    {
        *x = x.clamp(l, u);
    }
    let make = |qs: &[f64]| {
        let t = frame_targets(&kin, qs, &frames);
        let mut tasks: Vec<Task> = frames
            .iter()
            .zip(&t)
            .map(|(&f, t)| Task::frame(f, *t))
            .collect();
        tasks.push(Task::posture(neutral.clone()).with_weight(1e-2));
        tasks
    };
    let n = run_reachable("talos", &tree, &kin, 30, &|_| neutral.clone(), &make);
    assert_eq!(n, 30, "{n} / 30");
    // A control loop: feet held where they are, hands reaching, the CoM over the feet, posture.
    let mut ws = DiffIkWorkspace::new(&kin);
    let mut q = neutral.clone();
    let feet = frame_targets(&kin, &q, &frames[..2]);
    let mut tws = TreeWorkspace::new(&kin);
    let c0 = com::com(&kin, &mut tws, &q).unwrap();
    // The feet weigh 100× the hands (the weights decide between the conflicting tasks).
    let mut tasks = vec![
        Task::frame(frames[0], feet[0]).with_weight(100.0),
        Task::frame(frames[1], feet[1]).with_weight(100.0),
    ];
    tasks.push(
        Task::frame(
            frames[2],
            Se3::from_translation(Vector3::new(0.6, 0.4, 1.2)),
        )
        .with_gain(0.5),
    );
    let mut hand = Task::frame(
        frames[3],
        Se3::from_translation(Vector3::new(0.5, -0.5, 0.2)),
    );
    hand.orientation_weight = [0.0; 3];
    tasks.push(hand);
    let mut ctask = Task::com(c0);
    ctask.position_weight = [1.0, 1.0, 0.0];
    tasks.push(ctask);
    tasks.push(Task::posture(neutral.clone()).with_weight(1e-2));
    tasks.push(Task::damping(1e-3));
    for step in 0..60 {
        let v = ik_step(&kin, &mut ws, &q, &tasks, 0.01, &Limits::default())
            .unwrap()
            .to_vec();
        if step % 6 == 0 {
            check_step(
                &format!("talos step {step}"),
                &kin,
                &q,
                &tasks,
                0.01,
                &v,
                &ws,
            );
        }
        check_limits("talos", &kin, &q, &v, 0.01);
        q = configuration::integrate(&kin, &q, &v, 0.01).unwrap();
    }
    let feet_now = frame_targets(&kin, &q, &frames[..2]);
    for (a, b) in feet.iter().zip(&feet_now) {
        assert!(
            a.max_abs_diff(b) < 1e-3,
            "the feet stay: {}",
            a.max_abs_diff(b)
        );
    }
}

#[test]
#[ignore = "needs the CI data's URDFs: SCREWKIT_SHARED_URDF (.ci/run's conformance stage sets it)"]
fn baxter_allegro_so101_reach_their_targets() {
    // Baxter: both grippers, fixed base.
    let (tree, kin) = load(&shared("baxter.urdf"), false);
    let frames = [
        kin.frame("left_gripper").unwrap(),
        kin.frame("right_gripper").unwrap(),
    ];
    let zero = configuration::neutral(&kin);
    let make = |qs: &[f64]| {
        let t = frame_targets(&kin, qs, &frames);
        vec![
            Task::frame(frames[0], t[0]),
            Task::frame(frames[1], t[1]),
            Task::posture(zero.clone()).with_weight(1e-2),
        ]
    };
    let n = run_reachable("baxter", &tree, &kin, 30, &|_| zero.clone(), &make);
    assert_eq!(n, 30, "baxter");
    // Allegro: four fingertips, position only.
    let (tree, kin) = load(&shared("allegro_right_hand.urdf"), false);
    let tips: Vec<usize> = [
        "link_3.0_tip",
        "link_7.0_tip",
        "link_11.0_tip",
        "link_15.0_tip",
    ]
    .iter()
    .map(|n| kin.frame(n).unwrap())
    .collect();
    let mid: Vec<f64> = kin
        .lower()
        .iter()
        .zip(kin.upper())
        .map(|(l, u)| 0.5 * (l + u))
        .collect();
    let make = |qs: &[f64]| {
        let t = frame_targets(&kin, qs, &tips);
        tips.iter()
            .zip(&t)
            .map(|(&f, t)| position_only(Task::frame(f, *t)))
            .chain([Task::posture(mid.clone()).with_weight(1e-3)])
            .collect()
    };
    let n = run_reachable("allegro", &tree, &kin, 30, &|_| mid.clone(), &make);
    assert_eq!(n, 30, "allegro");
    // SO-101: the gripper's z axis along a direction, its origin at a point (5 DoF).
    let (tree, kin) = load(&shared("so101.urdf"), false);
    let g = kin.frame("gripper_frame_link").unwrap();
    let mid: Vec<f64> = kin
        .lower()
        .iter()
        .zip(kin.upper())
        .map(|(l, u)| 0.5 * (l + u))
        .collect();
    let make = |qs: &[f64]| {
        let t = frame_targets(&kin, qs, &[g])[0];
        let d = t.rotation() * Vector3::z();
        vec![Task::axis(g, Vector3::z(), d, Some(*t.translation()))]
    };
    let n = run_reachable("so101", &tree, &kin, 30, &|_| mid.clone(), &make);
    assert_eq!(n, 30, "so101");
}

#[test]
fn an_interrupt_stops_a_solve_and_every_set_of_a_trajectory() {
    let (_, kin) = load(&screwkit_testkit::bundled("torso_two_arms.urdf"), false);
    let l = kin.frame("left_hand").unwrap();
    // Out of reach: without the interrupt every descent runs and 10⁶ restarts would follow.
    let far = Se3::from_parts(nalgebra::Matrix3::identity(), Vector3::new(5.0, 0.0, 0.0)).unwrap();
    let tasks = vec![Task::frame(l, far)];
    let stop = TasksOptions {
        restarts: 1_000_000,
        interrupt: Some(screwkit_solve::ik::Interrupt(|| true)),
        ..TasksOptions::default()
    };
    let mut ws = DiffIkWorkspace::new(&kin);
    let seed = vec![0.0; kin.nq()];
    let r = ik_tasks(&kin, &mut ws, &tasks, &seed, &stop).unwrap();
    assert_eq!(r.stop, TasksStop::Interrupted);
    assert_eq!(r.iterations, 0, "polled before the first step");
    assert!(!r.converged);
    let sets = vec![tasks; 1000];
    for length in [0, 100] {
        let segments = Segments { length, warm_up: 5 };
        let out = ik_trajectory(&kin, &sets, &seed, &stop, segments).unwrap();
        assert_eq!(out.len(), 1000);
        assert!(out.iter().all(|r| {
            let r = r.as_ref().unwrap();
            r.stop == TasksStop::Interrupted && r.iterations == 0
        }));
    }
}

/// Issue 44, item 5: whole-body IK on a tree beyond `MAX_NV` velocity variables is refused
/// with an error naming the limit, before its dense nv × nv QP is allocated (a 30,000-joint
/// star asked for 7.2 GB and aborted); FK on the same tree still works.
#[test]
fn a_tree_too_large_for_the_dense_qp_is_refused_by_name() {
    use screwkit_solve::tree::differential_ik::MAX_NV;
    let n = MAX_NV + 1000;
    let mut t = String::from("<robot name=\"star\"><link name=\"hub\"/>");
    for i in 0..n {
        t.push_str(&format!(
            "<link name=\"s{i}\"/><joint name=\"j{i}\" type=\"revolute\"><parent link=\"hub\"/><child link=\"s{i}\"/><origin xyz=\"0.1 0 0\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\"/></joint>"
        ));
    }
    t.push_str("</robot>");
    let tree = urdf::load_str(&t, "star.urdf").unwrap();
    let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    assert_eq!(kin.nv(), n);
    let q = vec![0.0; n];
    let mut tws = TreeWorkspace::new(&kin);
    assert_eq!(fk::fk_frames(&kin, &mut tws, &q).unwrap().len(), n + 1);
    let tasks = [Task::posture(vec![0.5; n])];
    let mut ws = DiffIkWorkspace::new(&kin);
    let e = ik_step(&kin, &mut ws, &q, &tasks, 0.01, &Limits::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&format!("at most {MAX_NV} velocity variables")) && e.contains(&n.to_string()),
        "{e}"
    );
    let e = ik_tasks(&kin, &mut ws, &tasks, &q, &TasksOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("at most"), "{e}");
    let e = ik_trajectory(
        &kin,
        &[tasks.to_vec()],
        &q,
        &TasksOptions::default(),
        Segments::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("at most"), "{e}");
}

/// Issue 44, item 15: one rule for a mimic follower's limits — the leader's own limits, as ROS
/// does — in `lower`/`upper` and the whole-body IK, and a warning naming a follower that
/// cannot hold its own over the leader's range. The PR2's gripper (a follower of multiplier −1
/// given the leader's [0, 0.548]) locked the leader at [0, −0] and refused its midpoint.
#[test]
fn a_follower_that_cannot_follow_is_named_and_does_not_lock_its_leader() {
    let text = r#"<robot name="gripper">
      <link name="palm"/><link name="l"/><link name="r"/>
      <joint name="l_finger" type="revolute"><parent link="palm"/><child link="l"/>
        <origin xyz="0 0.02 0"/><axis xyz="0 0 1"/><limit lower="0" upper="0.548"/></joint>
      <joint name="r_finger" type="revolute"><parent link="palm"/><child link="r"/>
        <origin xyz="0 -0.02 0"/><axis xyz="0 0 1"/><limit lower="0" upper="0.548"/>
        <mimic joint="l_finger" multiplier="-1"/></joint>
    </robot>"#;
    let tree = urdf::load_str(text, "gripper.urdf").unwrap();
    assert_eq!(tree.warnings.len(), 1, "{:?}", tree.warnings);
    assert!(
        tree.warnings[0].contains("joint \"r_finger\" mimics \"l_finger\"")
            && tree.warnings[0].contains("the leader's limits are kept"),
        "{}",
        tree.warnings[0]
    );
    let kin = TreeKinematics::new(&KinematicTree::from_tree(&tree).unwrap()).unwrap();
    assert_eq!((kin.lower(), kin.upper()), (vec![0.0], vec![0.548]));
    let mut ws = DiffIkWorkspace::new(&kin);
    let r = ik_tasks(
        &kin,
        &mut ws,
        &[Task::posture(vec![0.4])],
        &[0.274],
        &TasksOptions::default(),
    )
    .unwrap();
    assert!(r.converged && (r.q[0] - 0.4).abs() < 1e-9, "{r:?}");
    // A follower whose limits do hold (the bundled gripper's coupled joint): no warning.
    let ok = urdf::load_file(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../assets/urdf/gripper_arm.urdf"
    ))
    .unwrap();
    assert!(ok.warnings.is_empty(), "{:?}", ok.warnings);
}

/// A prepared task set steps exactly as the task list does; its targets change in place, each
/// checked alone, a refused one leaving the task as it was.
#[test]
fn a_prepared_task_set_steps_as_the_list_and_takes_new_targets() {
    use screwkit_solve::tree::differential_ik::ik_step_set;
    use screwkit_solve::tree::tasks::{Target, TaskSet};
    let path = screwkit_testkit::bundled("humanoid.urdf");
    let (_, kin) = load(&path, false);
    let (l, r) = (
        kin.frame("left_hand").unwrap(),
        kin.frame("right_hand").unwrap(),
    );
    let a = Se3::from_translation(Vector3::new(0.3, 0.4, 1.1));
    let b = Se3::from_translation(Vector3::new(0.2, -0.3, 1.0));
    let list = |ta: Se3, c: Vector3<f64>| {
        vec![
            Task::frame(l, ta),
            Task::relative(r, l, b).with_weight(0.5),
            Task::com(c).with_weight(0.1),
            Task::posture(vec![0.1; kin.nq()]).with_weight(1e-2),
            Task::damping(1e-3),
        ]
    };
    let c0 = Vector3::new(0.0, 0.0, 0.5);
    let mut set = TaskSet::new(&kin, list(a, c0)).unwrap();
    let (mut ws1, mut ws2) = (DiffIkWorkspace::new(&kin), DiffIkWorkspace::new(&kin));
    let limits = Limits::default();
    // Mid-range within every joint's limits.
    let mut q: Vec<f64> = kin
        .lower()
        .iter()
        .zip(kin.upper())
        .map(|(lo, hi)| 0.5 * (lo.max(-3.0) + hi.min(3.0)))
        .collect();
    for k in 0..20 {
        let ta = Se3::from_translation(Vector3::new(0.3, 0.4 - 0.01 * k as f64, 1.1));
        let c = Vector3::new(0.01 * k as f64, 0.0, 0.5);
        set.set_target(&kin, 0, Target::Pose(ta)).unwrap();
        set.set_target(&kin, 2, Target::Point(c)).unwrap();
        let v_set = ik_step_set(&kin, &mut ws1, &q, &set, 0.01, &limits)
            .unwrap()
            .to_vec();
        let v_list = ik_step(&kin, &mut ws2, &q, &list(ta, c), 0.01, &limits)
            .unwrap()
            .to_vec();
        assert_eq!(v_set, v_list, "step {k}");
        assert!(v_set.iter().any(|x| *x != 0.0));
        for (qi, vi) in q.iter_mut().zip(&v_set) {
            *qi += 0.01 * vi;
        }
    }
    // Refused targets name the task and leave it unchanged.
    let before = set.clone();
    let mut bad = Se3::identity();
    bad = Se3::from_parts_unchecked(*bad.rotation(), Vector3::new(f64::NAN, 0.0, 0.0));
    for (i, t, words) in [
        (0, Target::Pose(bad), "not finite"),
        (0, Target::Point(c0), "takes a pose"),
        (4, Target::Point(c0), "takes nothing"),
        (3, Target::Configuration(vec![0.0; 2]), "q_ref has 2 values"),
        (9, Target::Point(c0), "out of range"),
    ] {
        let e = set.set_target(&kin, i, t).unwrap_err().to_string();
        assert!(e.contains(words), "{e}");
        if i < 9 {
            assert!(e.starts_with(&format!("task {i} (")), "{e}");
        }
    }
    assert_eq!(set, before);
    // Another model: refused.
    let other = screwkit_testkit::bundled("torso_two_arms.urdf");
    let (_, kin2) = load(&other, false);
    let e = ik_step_set(
        &kin2,
        &mut DiffIkWorkspace::new(&kin2),
        &vec![0.0; kin2.nq()],
        &set,
        0.01,
        &limits,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("another model"), "{e}");
}

/// A limit of the caller's own kind (a joint held still) joins the built-in ones through
/// `Limits::extra`: the step's box and answer respect it, and the other joints still move.
#[test]
fn an_extra_limit_narrows_the_step_box() {
    use screwkit_solve::tree::limits::Limit;
    use screwkit_solve::SolveError;
    #[derive(Debug)]
    struct Hold(usize);
    impl Limit for Hold {
        fn check(&self, kin: &TreeKinematics) -> Result<(), SolveError> {
            if self.0 < kin.nv() {
                Ok(())
            } else {
                Err(SolveError::InvalidInput(format!(
                    "no velocity entry {}",
                    self.0
                )))
            }
        }
        fn narrow(
            &self,
            _kin: &TreeKinematics,
            _q: &[f64],
            _dt: Option<f64>,
            lo: &mut [f64],
            hi: &mut [f64],
        ) -> Result<(), SolveError> {
            lo[self.0] = lo[self.0].max(0.0);
            hi[self.0] = hi[self.0].min(0.0);
            Ok(())
        }
    }
    let path = screwkit_testkit::bundled("torso_two_arms.urdf");
    let (_, kin) = load(&path, false);
    let l = kin.frame("left_hand").unwrap();
    let far = Se3::from_translation(Vector3::new(0.5, 0.5, 1.0));
    let tasks = [Task::frame(l, far), Task::damping(1e-3)];
    let q = vec![0.0; kin.nq()];
    let mut ws = DiffIkWorkspace::new(&kin);
    let free = ik_step(&kin, &mut ws, &q, &tasks, 0.01, &Limits::default())
        .unwrap()
        .to_vec();
    assert!(free[0] != 0.0, "the waist moves without the hold");
    let held = Limits {
        extra: vec![std::sync::Arc::new(Hold(0))],
        ..Limits::default()
    };
    let v = ik_step(&kin, &mut ws, &q, &tasks, 0.01, &held)
        .unwrap()
        .to_vec();
    let (_, _, lo, hi) = ws.qp();
    assert_eq!((lo[0], hi[0]), (0.0, 0.0));
    assert_eq!(v[0], 0.0);
    assert!(v[1..].iter().any(|x| *x != 0.0));
    let bad = Limits {
        extra: vec![std::sync::Arc::new(Hold(99))],
        ..Limits::default()
    };
    let e = ik_step(&kin, &mut ws, &q, &tasks, 0.01, &bad).unwrap_err();
    assert!(e.to_string().contains("no velocity entry 99"), "{e}");
}
