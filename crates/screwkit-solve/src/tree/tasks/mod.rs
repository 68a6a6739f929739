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
//!
//! **One file per task type** (mink's shape): each implements `Objective` — its check against
//! the model, whether it is a goal, its description, the velocity entries it depends on, which
//! errors it reports and its rows — and [`TaskKind`] lists them, the one place a new type is
//! registered (with its arm in the `each_type` macro, the one match over the types: it has no
//! catch-all arm, so the compiler names every place a new type must be handled).

use nalgebra::Vector3;
use screwkit_lie::Se3;

use super::{TreeKinematics, TreeWorkspace};
use crate::error::SolveError;

mod axis;
mod com;
mod damping;
mod frame;
mod posture;
mod relative;
mod set;

pub use axis::AxisTask;
pub use com::ComTask;
pub use damping::DampingTask;
pub use frame::FrameTask;
pub use posture::PostureTask;
pub use relative::RelativeTask;
pub use set::{Target, TaskSet};

/// What a task asks (frame indices from [`TreeKinematics::frame`]): one variant per task
/// type, each type in its own file.
#[derive(Debug, Clone, PartialEq)]
pub enum TaskKind {
    /// A frame to a pose in the world.
    Frame(FrameTask),
    /// A frame to a pose given in another frame (T_B⁻¹ T_A).
    Relative(RelativeTask),
    /// A frame's axis along a world direction, its origin at a point when given.
    Axis(AxisTask),
    /// The centre of mass to a point.
    Com(ComTask),
    /// q towards a reference configuration.
    Posture(PostureTask),
    /// Small steps.
    Damping(DampingTask),
}

/// The one list of the task types: `$t` bound to the task inside `$kind` in every arm (the
/// registration; no catch-all arm, so a new variant that is not listed here does not compile).
macro_rules! each_type {
    ($kind:expr, $t:ident => $e:expr) => {
        match $kind {
            TaskKind::Frame($t) => $e,
            TaskKind::Relative($t) => $e,
            TaskKind::Axis($t) => $e,
            TaskKind::Com($t) => $e,
            TaskKind::Posture($t) => $e,
            TaskKind::Damping($t) => $e,
        }
    };
}

impl TaskKind {
    /// The task type's behaviour (`each_type`).
    pub(crate) fn objective(&self) -> &dyn Objective {
        each_type!(self, t => t)
    }

    /// The same, to change its target ([`TaskSet::set_target`]).
    pub(crate) fn objective_mut(&mut self) -> &mut dyn Objective {
        each_type!(self, t => t)
    }

    /// Which errors the task reports ([`TaskError`]'s meaningful fields).
    pub fn measures(&self) -> Measures {
        self.objective().measures()
    }
}

/// Which of a [`TaskError`]'s fields a task type reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measures {
    /// None: a damping task has no error.
    Nothing,
    /// ‖q_ref − q‖ over the joints (`position`).
    Configuration,
    /// A position error (m).
    Position,
    /// A position (m) and a rotation (rad) error.
    PositionAndRotation,
}

/// A task type's behaviour (one implementation per file of this module).
pub(crate) trait Objective {
    /// The task's values against the model (indices, finite values, lengths), the message
    /// naming what is wrong.
    fn check(&self, kin: &TreeKinematics) -> Result<(), String>;
    /// True for a goal (tolerances; converged when within them), false for a regulariser.
    fn is_goal(&self) -> bool;
    /// A short description for messages (`frame task on "gripper"`).
    fn describe(&self, kin: &TreeKinematics) -> String;
    /// The velocity entries the task's rows depend on (appended to `out`): a goal's frames'
    /// path variables and a floating base's six; nothing for a regulariser.
    fn dependence(&self, kin: &TreeKinematics, out: &mut Vec<usize>);
    /// Which errors it reports.
    fn measures(&self) -> Measures;
    /// Takes `target` as its new target (the message when the type takes no such target;
    /// [`TaskSet::set_target`] then checks the task).
    fn set_target(&mut self, target: Target) -> Result<(), String>;
    /// Its rows (or a regulariser's diagonal terms) at the evaluation's q, weighted by `task`'s
    /// weights and gain, into `rows`; returns its error (`converged` is set by the caller).
    fn rows(&self, at: &mut At<'_>, task: &Task, rows: &mut Rows) -> TaskError;
}

/// The message of a target a task type does not take.
pub(crate) fn wrong_target(task: &str, takes: &str, target: &Target) -> String {
    format!(
        "a {task} takes {takes} as its target, not {}",
        target.what()
    )
}

/// Where a task set is evaluated: the model, its scratch, q and the base pose, and whether any
/// task is a goal.
pub(crate) struct At<'a> {
    pub(crate) kin: &'a TreeKinematics,
    pub(crate) ws: &'a mut TreeWorkspace,
    pub(crate) q: &'a [f64],
    pub(crate) base: &'a Se3,
    pub(crate) has_goal: bool,
}

/// The velocity entries of a floating base (its six) and of the path to `frame`.
pub(crate) fn base_and_path(kin: &TreeKinematics, frame: usize, out: &mut Vec<usize>) {
    let model = kin.model();
    let vo = kin.v_offset();
    out.extend(0..vo);
    out.extend(
        model
            .path(frame)
            .into_iter()
            .map(|j| vo + model.joints[j].drive.variable),
    );
}

/// A frame's name for messages (its index when out of range).
pub(crate) fn frame_name(kin: &TreeKinematics, f: usize) -> String {
    if f < kin.frame_count() {
        format!("\"{}\"", kin.frame_name(f))
    } else {
        format!("index {f}")
    }
}

/// A frame index within the model, or the message.
pub(crate) fn check_frame(kin: &TreeKinematics, f: usize) -> Result<(), String> {
    if f < kin.frame_count() {
        Ok(())
    } else {
        Err(format!(
            "frame index {f} is out of range: the model has {} frames",
            kin.frame_count()
        ))
    }
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
        Task::new(TaskKind::Frame(FrameTask { frame, target }))
    }

    /// Frame `frame` to `target` given in frame `relative_to`.
    pub fn relative(frame: usize, relative_to: usize, target: Se3) -> Task {
        Task::new(TaskKind::Relative(RelativeTask {
            frame,
            relative_to,
            target,
        }))
    }

    /// Frame `frame`'s `axis` along `direction`, its origin at `point` if given.
    pub fn axis(
        frame: usize,
        axis: Vector3<f64>,
        direction: Vector3<f64>,
        point: Option<Vector3<f64>>,
    ) -> Task {
        Task::new(TaskKind::Axis(AxisTask {
            frame,
            axis,
            direction,
            point,
        }))
    }

    /// The centre of mass to `target`.
    pub fn com(target: Vector3<f64>) -> Task {
        Task::new(TaskKind::Com(ComTask { target }))
    }

    /// q towards `q_ref`.
    pub fn posture(q_ref: Vec<f64>) -> Task {
        Task::new(TaskKind::Posture(PostureTask { q_ref }))
    }

    /// Damping of weight `weight` (the front ends' default: [`DAMPING_WEIGHT`]).
    pub fn damping(weight: f64) -> Task {
        Task::new(TaskKind::Damping(DampingTask)).with_weight(weight)
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

    /// True for goals (frame, relative, axis, centre of mass): module documentation.
    pub fn is_goal(&self) -> bool {
        self.kind.objective().is_goal()
    }

    /// A short description for messages (`frame task on "gripper"`).
    pub fn describe(&self, kin: &TreeKinematics) -> String {
        self.kind.objective().describe(kin)
    }

    /// The velocity entries the task depends on, sorted, once each (empty for a regulariser).
    pub(crate) fn dependence(&self, kin: &TreeKinematics) -> Vec<usize> {
        let mut out = Vec::new();
        self.kind.objective().dependence(kin, &mut out);
        out.sort_unstable();
        out.dedup();
        out
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
    t.kind.objective().check(kin)
}

/// A vector with a direction (finite, not 0), or the message naming it.
pub(crate) fn check_unit(what: &str, x: &Vector3<f64>) -> Result<(), String> {
    let n = x.norm();
    if n.is_finite() && n > 1e-12 {
        Ok(())
    } else {
        Err(format!(
            "the {what} ({}, {}, {}) has no direction",
            x[0], x[1], x[2]
        ))
    }
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
    pub(crate) fn push_point(
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

    pub(crate) fn push(&mut self, nv: usize, w: f64, jrow: impl Iterator<Item = f64>, rhs: f64) {
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
    let mut at = At {
        kin,
        ws,
        q,
        base,
        has_goal,
    };
    for t in tasks {
        let merit_before = rows.merit;
        let objective = t.kind.objective();
        let mut error = objective.rows(&mut at, t, rows);
        let counts = objective.is_goal() || (!has_goal && matches!(t.kind, TaskKind::Posture(_)));
        error.converged = !counts || (error.rotation <= t.tol_rot && error.position <= t.tol_pos);
        converged &= error.converged;
        rows.errors.push(error);
        rows.task_merit.push(rows.merit - merit_before);
    }
    rows.converged = converged;
    rows.has_goal = has_goal;
}
