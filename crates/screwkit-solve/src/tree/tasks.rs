//! Tasks of whole-body differential IK: what each asks, its error and its rows.
//!
//! A task contributes residual rows r = w ⊙ (J Δ − g e) to the step's least-squares problem
//! ([`super::differential_ik`]), with Δ = v·dt the displacement of one step (nv entries, the
//! floating base's body twist first), e the task's error at q, J its Jacobian, g ∈ (0, 1] its
//! gain (the fraction of the error one step removes) and w = weight × the per-axis weights. The
//! errors and Jacobians, in the frames they are stated in:
//!
//! | task | error e | Jacobian J |
//! |---|---|---|
//! | frame F to T* (world) | ξ = log(T_F⁻¹ T*) ∈ se(3), (ω, v) in F's own frame | J_l(ξ)⁻¹ J_b, J_b of F (body form) |
//! | frame A to T* in frame B | ξ = log(T_BA⁻¹ T*), T_BA = T_B⁻¹ T_A, in A's frame | J_l(ξ)⁻¹ J_rel, J_rel the relative Jacobian of A in B, body form |
//! | axis: F's axis a to direction d, F's origin to point p (world) | rotation: θ = ∠(R_F a, d) along b₁ = unit(R_F a × d), 0 along b₂ = R_F a × b₁; position: p − p_F | b₁ᵀ J_ω, b₂ᵀ J_ω; J_v (world-aligned form) |
//! | centre of mass to c* (world) | c* − c(q) | J_c ([`super::com`]) |
//! | posture: q to q_ref | q_ref − q per joint variable (continuous joints wrapped to (−π, π]) | the identity on the joint variables |
//! | damping | 0 | the identity on every velocity entry |
//!
//! The frame task's rows are the error's exact derivative (moving T_F to T_F e^{[δ]} changes ξ by
//! −J_l(ξ)⁻¹ δ, [`screwkit_lie::se3::left_jacobian_inverse`]; pink's `jlog`), so weighting some
//! axes to 0 leaves the others' rows exact. With every axis weighted the rows ask J_b Δ = g J_l(ξ) ξ
//! = g ξ: T_F moves along the geodesic to T*, and a full step (g = 1) of an unconstrained,
//! unconflicted task is the Gauss–Newton step on the log error. Position-only and orientation-only frame tasks are
//! weights (`orientation_weight = 0`, `position_weight = 0`), not other code; per-axis weights
//! are along F's axes for frame tasks, the world's for the axis task's point and the centre of
//! mass. Rotation errors are radians, positions metres: a weight of 1 on both prices 1 rad as
//! 1 m. A floating base's own pose is a frame task on the root link.
//!
//! **Goals and regularisers**: frame, axis and centre-of-mass tasks are goals (each has
//! tolerances and is converged when its weighted axes' errors are within them); posture and
//! damping regularise (their errors are reported, and when a problem has no goal the posture's
//! counts as one).

use nalgebra::Vector3;
use screwkit_lie::{angle, Se3};

use super::com::com_jacobian_unchecked;
use super::jacobian::{pose_jacobian_unchecked, relative_unchecked};
use super::{TreeKinematics, TreeWorkspace};
use crate::error::SolveError;
use crate::jacobian::JacobianKind;

/// What a task asks (frame indices from [`TreeKinematics::frame`]).
#[derive(Debug, Clone, PartialEq)]
pub enum TaskKind {
    /// Frame `frame` to the pose `target`: in the world, or in frame `relative_to` (T_B⁻¹ T_A).
    Frame {
        /// The driven frame (A).
        frame: usize,
        /// The target pose.
        target: Se3,
        /// The frame the target is given in (B); `None` for the world.
        relative_to: Option<usize>,
    },
    /// Frame `frame`'s unit axis `axis` (in its own frame) along the world direction
    /// `direction`, its origin at `point` (world) when given; free about the axis.
    Axis {
        /// The driven frame.
        frame: usize,
        /// The axis in the frame (normalised).
        axis: Vector3<f64>,
        /// The direction in the world (normalised).
        direction: Vector3<f64>,
        /// The origin's target, if any.
        point: Option<Vector3<f64>>,
    },
    /// The centre of mass to `target` (world).
    Com {
        /// The target point.
        target: Vector3<f64>,
    },
    /// q towards `q_ref` (nq values; a floating base's seven are not used).
    Posture {
        /// The reference configuration.
        q_ref: Vec<f64>,
    },
    /// Small steps: ‖Δ‖² weighted.
    Damping,
}

/// The weight of a damping task given none (every front end's default): small next to the
/// goals' weight 1, so it only settles what they leave free and slows the steps near
/// singularities, as a regulariser should.
pub const DAMPING_WEIGHT: f64 = 1e-3;

/// A task: what it asks, its gain, weights and tolerances (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    /// What it asks.
    pub kind: TaskKind,
    /// The fraction of the error one step removes, in (0, 1]; default 1.
    pub gain: f64,
    /// The task's weight (its rows' scale), ≥ 0; default 1.
    pub weight: f64,
    /// Per-axis weights of the rotation rows (frame: F's x, y, z; axis: the first entry for
    /// both rows); default 1.
    pub orientation_weight: [f64; 3],
    /// Per-axis weights of the position rows (frame: F's x, y, z; axis and centre of mass: the
    /// world's); default 1.
    pub position_weight: [f64; 3],
    /// Converged when the weighted rotation error is at most this (rad); default 1e-9.
    pub tol_rot: f64,
    /// Converged when the weighted position error is at most this (m); default 1e-9.
    pub tol_pos: f64,
}

impl Task {
    fn new(kind: TaskKind) -> Task {
        Task {
            kind,
            gain: 1.0,
            weight: 1.0,
            orientation_weight: [1.0; 3],
            position_weight: [1.0; 3],
            tol_rot: 1e-9,
            tol_pos: 1e-9,
        }
    }

    /// Frame `frame` to `target` in the world.
    pub fn frame(frame: usize, target: Se3) -> Task {
        Task::new(TaskKind::Frame {
            frame,
            target,
            relative_to: None,
        })
    }

    /// Frame `frame` to `target` given in frame `relative_to`.
    pub fn relative(frame: usize, relative_to: usize, target: Se3) -> Task {
        Task::new(TaskKind::Frame {
            frame,
            target,
            relative_to: Some(relative_to),
        })
    }

    /// Frame `frame`'s `axis` along `direction`, its origin at `point` if given.
    pub fn axis(
        frame: usize,
        axis: Vector3<f64>,
        direction: Vector3<f64>,
        point: Option<Vector3<f64>>,
    ) -> Task {
        Task::new(TaskKind::Axis {
            frame,
            axis,
            direction,
            point,
        })
    }

    /// The centre of mass to `target`.
    pub fn com(target: Vector3<f64>) -> Task {
        Task::new(TaskKind::Com { target })
    }

    /// q towards `q_ref`.
    pub fn posture(q_ref: Vec<f64>) -> Task {
        Task::new(TaskKind::Posture { q_ref })
    }

    /// Damping of weight `weight` (the front ends' default: [`DAMPING_WEIGHT`]).
    pub fn damping(weight: f64) -> Task {
        Task::new(TaskKind::Damping).with_weight(weight)
    }

    /// The same task with weight `w`.
    pub fn with_weight(mut self, w: f64) -> Task {
        self.weight = w;
        self
    }

    /// The same task with gain `g`.
    pub fn with_gain(mut self, g: f64) -> Task {
        self.gain = g;
        self
    }

    /// True for goals (frame, axis, centre of mass): module documentation.
    pub fn is_goal(&self) -> bool {
        matches!(
            self.kind,
            TaskKind::Frame { .. } | TaskKind::Axis { .. } | TaskKind::Com { .. }
        )
    }

    /// A short description for messages (`frame task on "gripper"`).
    pub fn describe(&self, kin: &TreeKinematics) -> String {
        let name = |f: usize| {
            if f < kin.frame_count() {
                format!("\"{}\"", kin.frame_name(f))
            } else {
                format!("index {f}")
            }
        };
        match &self.kind {
            TaskKind::Frame {
                frame,
                relative_to: None,
                ..
            } => format!("frame task on {}", name(*frame)),
            TaskKind::Frame {
                frame,
                relative_to: Some(b),
                ..
            } => format!("relative frame task on {} in {}", name(*frame), name(*b)),
            TaskKind::Axis { frame, .. } => format!("axis task on {}", name(*frame)),
            TaskKind::Com { .. } => "centre-of-mass task".into(),
            TaskKind::Posture { .. } => "posture task".into(),
            TaskKind::Damping => "damping task".into(),
        }
    }
}

/// A task's error after an evaluation: the norms of its weighted axes' errors.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TaskError {
    /// Position error (m): ‖ξ_v‖ (frame), ‖p − p_F‖ (axis), ‖c* − c‖ (centre of mass),
    /// ‖q_ref − q‖ over the joints (posture), over the axes whose weight is not 0.
    pub position: f64,
    /// Rotation error (rad): ‖ξ_ω‖ (frame), the angle between axis and direction (axis).
    pub rotation: f64,
    /// Within both tolerances (always true for a regulariser).
    pub converged: bool,
}

/// Checks every task against the model: indices, finite values, unit-able vectors, gains in
/// (0, 1], weights ≥ 0, tolerances > 0, q_ref's length. The error names the task.
pub fn check_tasks(kin: &TreeKinematics, tasks: &[Task]) -> Result<(), SolveError> {
    for (i, t) in tasks.iter().enumerate() {
        check_task(kin, t).map_err(|m| {
            SolveError::InvalidInput(format!("task {i} ({}): {m}", t.describe(kin)))
        })?;
    }
    Ok(())
}

fn check_task(kin: &TreeKinematics, t: &Task) -> Result<(), String> {
    if !(t.gain > 0.0 && t.gain <= 1.0) {
        return Err(format!("gain {} is not in (0, 1]", t.gain));
    }
    let weights = std::iter::once(t.weight)
        .chain(t.orientation_weight)
        .chain(t.position_weight);
    for w in weights {
        if !(w.is_finite() && w >= 0.0) {
            return Err(format!("weight {w} is not a finite number ≥ 0"));
        }
    }
    for (what, tol) in [("tol_rot", t.tol_rot), ("tol_pos", t.tol_pos)] {
        if !(tol.is_finite() && tol > 0.0) {
            return Err(format!("{what} {tol} is not a finite number > 0"));
        }
    }
    let frame = |f: usize| {
        if f < kin.frame_count() {
            Ok(())
        } else {
            Err(format!(
                "frame index {f} is out of range: the model has {} frames",
                kin.frame_count()
            ))
        }
    };
    let unit = |what: &str, x: &Vector3<f64>| {
        let n = x.norm();
        if n.is_finite() && n > 1e-12 {
            Ok(())
        } else {
            Err(format!(
                "the {what} ({}, {}, {}) has no direction",
                x[0], x[1], x[2]
            ))
        }
    };
    match &t.kind {
        TaskKind::Frame {
            frame: a,
            target,
            relative_to,
        } => {
            frame(*a)?;
            if let Some(b) = relative_to {
                frame(*b)?;
                if a == b {
                    return Err("a frame relative to itself".into());
                }
            }
            if !target.is_finite() {
                return Err("the target pose is not finite".into());
            }
        }
        TaskKind::Axis {
            frame: f,
            axis,
            direction,
            point,
        } => {
            frame(*f)?;
            unit("axis", axis)?;
            unit("direction", direction)?;
            if point.is_some_and(|p| !p.iter().all(|x| x.is_finite())) {
                return Err("the point is not finite".into());
            }
        }
        TaskKind::Com { target } => {
            if kin.total_mass <= 0.0 {
                return Err("no link has a mass (<inertial><mass value> > 0)".into());
            }
            if !target.iter().all(|x| x.is_finite()) {
                return Err("the target is not finite".into());
            }
        }
        TaskKind::Posture { q_ref } => {
            if q_ref.len() != kin.nq() {
                return Err(format!(
                    "q_ref has {} values, the model has nq = {}",
                    q_ref.len(),
                    kin.nq()
                ));
            }
            let qo = kin.q_offset();
            if let Some(i) = q_ref[qo..].iter().position(|x| !x.is_finite()) {
                return Err(format!(
                    "q_ref[{}] ({}) is not finite",
                    qo + i,
                    kin.q_names()[qo + i]
                ));
            }
        }
        TaskKind::Damping => {}
    }
    Ok(())
}

/// The rows of one evaluation: A (m × nv, row-major), b, the diagonal terms D and D·r of the
/// regularisers, each task's error, and the goals' merit Σ (w e)².
#[derive(Debug, Clone, Default)]
pub(crate) struct Rows {
    pub(crate) a: Vec<f64>,
    pub(crate) b: Vec<f64>,
    pub(crate) m: usize,
    pub(crate) diag: Vec<f64>,
    pub(crate) diag_rhs: Vec<f64>,
    pub(crate) errors: Vec<TaskError>,
    /// Σ over goal rows of (w e)² (the posture's when there is no goal).
    pub(crate) merit: f64,
    /// Each task's share of `merit`.
    pub(crate) task_merit: Vec<f64>,
    pub(crate) converged: bool,
    /// Some task is a goal (the regularisers then scale in [`super::differential_ik`]).
    pub(crate) has_goal: bool,
}

impl Rows {
    /// The three rows of a point's error `e` (world axes) with Jacobian rows `jac(r, c)`,
    /// weighted per axis; returns the weighted axes' error norm.
    fn push_point(
        &mut self,
        nv: usize,
        pw: &[f64; 3],
        g: f64,
        e: &Vector3<f64>,
        jac: impl Fn(usize, usize) -> f64,
    ) -> f64 {
        let mut pos = 0.0;
        for r in 0..3 {
            let w = pw[r];
            if w == 0.0 {
                continue;
            }
            pos += e[r] * e[r];
            self.merit += (w * e[r]) * (w * e[r]);
            self.push(nv, w, (0..nv).map(|c| jac(r, c)), g * e[r]);
        }
        pos.sqrt()
    }

    fn push(&mut self, nv: usize, w: f64, jrow: impl Iterator<Item = f64>, rhs: f64) {
        let start = self.m * nv;
        if self.a.len() < start + nv {
            self.a.resize(start + nv, 0.0);
        }
        for (dst, j) in self.a[start..start + nv].iter_mut().zip(jrow) {
            *dst = w * j;
        }
        if self.b.len() <= self.m {
            self.b.resize(self.m + 1, 0.0);
        }
        self.b[self.m] = w * rhs;
        self.m += 1;
    }
}

/// Evaluates every task at q (checked; `base` its base pose) into `rows`: the errors, the
/// goals' rows and the regularisers' diagonal.
pub(crate) fn evaluate(
    kin: &TreeKinematics,
    ws: &mut TreeWorkspace,
    q: &[f64],
    base: &Se3,
    tasks: &[Task],
    rows: &mut Rows,
) {
    let nv = kin.nv();
    rows.m = 0;
    rows.diag.clear();
    rows.diag.resize(nv, 0.0);
    rows.diag_rhs.clear();
    rows.diag_rhs.resize(nv, 0.0);
    rows.errors.clear();
    rows.merit = 0.0;
    rows.task_merit.clear();
    let has_goal = tasks.iter().any(Task::is_goal);
    let mut converged = true;
    let (qo, vo) = (kin.q_offset(), kin.v_offset());
    for t in tasks {
        let merit_before = rows.merit;
        let g = t.gain;
        let ow = t.orientation_weight.map(|x| x * t.weight);
        let pw = t.position_weight.map(|x| x * t.weight);
        let mut error = TaskError::default();
        match &t.kind {
            TaskKind::Frame {
                frame,
                target,
                relative_to,
            } => {
                let pose = match relative_to {
                    None => {
                        pose_jacobian_unchecked(kin, ws, q, base, *frame, JacobianKind::Body, false)
                    }
                    Some(b) => relative_unchecked(kin, ws, q, base, *frame, *b, JacobianKind::Body),
                };
                let xi = pose.inverse_compose(target).log();
                let e = [xi.w[0], xi.w[1], xi.w[2], xi.v[0], xi.v[1], xi.v[2]];
                // The error's own derivative: T_F exp(δ) changes ξ by −J_l(ξ)⁻¹ δ, δ = J_b Δ.
                let jinv = screwkit_lie::se3::left_jacobian_inverse(&xi);
                let (mut rot, mut pos) = (0.0, 0.0);
                for (r, &er) in e.iter().enumerate() {
                    let w = if r < 3 { ow[r] } else { pw[r - 3] };
                    if w == 0.0 {
                        continue;
                    }
                    if r < 3 {
                        rot += er * er;
                    } else {
                        pos += er * er;
                    }
                    rows.merit += (w * er) * (w * er);
                    let jac = &ws.jacobian;
                    let jrow = (0..nv).map(|c| (0..6).map(|k| jinv[(r, k)] * jac[(k, c)]).sum());
                    rows.push(nv, w, jrow, g * er);
                }
                error.rotation = rot.sqrt();
                error.position = pos.sqrt();
            }
            TaskKind::Axis {
                frame,
                axis,
                direction,
                point,
            } => {
                let pose = pose_jacobian_unchecked(
                    kin,
                    ws,
                    q,
                    base,
                    *frame,
                    JacobianKind::WorldAligned,
                    false,
                );
                let aw = pose.rotation() * axis.normalize();
                let d = direction.normalize();
                let cross = aw.cross(&d);
                let theta = cross.norm().atan2(aw.dot(&d));
                let b1 = if cross.norm() > 1e-12 {
                    cross.normalize()
                } else {
                    any_perpendicular(&aw)
                };
                let b2 = aw.cross(&b1);
                let w = ow[0];
                if w != 0.0 {
                    error.rotation = theta;
                    rows.merit += (w * theta) * (w * theta);
                    for (bi, ei) in [(b1, theta), (b2, 0.0)] {
                        let jac = &ws.jacobian;
                        let jrow = (0..nv).map(|c| {
                            bi[0] * jac[(0, c)] + bi[1] * jac[(1, c)] + bi[2] * jac[(2, c)]
                        });
                        rows.push(nv, w, jrow, g * ei);
                    }
                }
                if let Some(p) = point {
                    let e = p - pose.translation();
                    let jac = &ws.jacobian;
                    error.position = rows.push_point(nv, &pw, g, &e, |r, c| jac[(3 + r, c)]);
                }
            }
            TaskKind::Com { target } => {
                let c = com_jacobian_unchecked(kin, ws, q, base);
                let e = target - c;
                let jac = &ws.com_jacobian;
                error.position = rows.push_point(nv, &pw, g, &e, |r, c| jac[(r, c)]);
            }
            TaskKind::Posture { q_ref } => {
                let w2 = t.weight * t.weight;
                let mut pos = 0.0;
                for j in 0..kin.variable_bounds.len() {
                    let mut e = q_ref[qo + j] - q[qo + j];
                    if kin.continuous[j] {
                        e = angle::wrap(e);
                    }
                    pos += e * e;
                    rows.diag[vo + j] += w2;
                    rows.diag_rhs[vo + j] += w2 * g * e;
                    if !has_goal {
                        rows.merit += t.weight * t.weight * e * e;
                    }
                }
                error.position = pos.sqrt();
            }
            TaskKind::Damping => {
                let w2 = t.weight * t.weight;
                for d in rows.diag.iter_mut() {
                    *d += w2;
                }
            }
        }
        let counts = t.is_goal() || (!has_goal && matches!(t.kind, TaskKind::Posture { .. }));
        error.converged = !counts || (error.rotation <= t.tol_rot && error.position <= t.tol_pos);
        converged &= error.converged;
        rows.errors.push(error);
        rows.task_merit.push(rows.merit - merit_before);
    }
    rows.converged = converged;
    rows.has_goal = has_goal;
}

/// A unit vector perpendicular to the unit vector `a`.
fn any_perpendicular(a: &Vector3<f64>) -> Vector3<f64> {
    let e = if a[0].abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    a.cross(&e).normalize()
}
