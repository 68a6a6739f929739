//! Whole-body differential IK: several tasks at once under hard joint limits (mink's and
//! pink's job), one velocity step for a control loop ([`ik_step`]) or iterated to convergence
//! ([`ik_tasks`]), batches and trajectories on all cores.
//!
//! **The step.** With the tasks' rows ([`super::tasks`]: r = w ⊙ (J Δ − g e)) stacked into
//! A Δ − b and the regularisers' diagonal D (posture, damping), the displacement Δ = v·dt of one
//! step solves
//!
//! ```text
//! minimise ½‖A Δ − b‖² + ½ Σ_i D_i (Δ_i − r_i)² + ½ ε ‖Δ‖²   subject to   l ≤ Δ ≤ u,
//! ```
//!
//! a box-constrained least-squares problem, solved exactly by [`crate::linalg::box_qp`] (H = AᵀA + D +
//! εI, c = −(Aᵀb + D r)). ε = 1e-10 (1 + max_i (AᵀA + D)_ii) keeps H positive definite when
//! the tasks leave directions free (no damping or posture task); it changes the answer by
//! rounding-level amounts. The box, per joint variable j (the floating base is unbounded):
//!
//! - position: q_j + Δ_j within the variable's bounds — its joint's `<limit>` and, for a
//!   variable driving mimic joints, theirs mapped through θ = m q + o; continuous joints have
//!   none;
//! - velocity: |Δ_j| ≤ dt · min(the file's `velocity`, the caller's cap for j).
//!
//! A configuration already outside its bounds (beyond 1e-9 relative) is an error naming the
//! joint, never clipped silently. The weights decide between conflicting tasks.
//!
//! **To convergence** ([`ik_tasks`]): from the seed (and, when that descent stalls, from up to
//! `restarts` random joint values with the seed's base: a local method's answer to local
//! minima, as the chain IK's restarts), steps with dt = 1 (position limits only),
//! Levenberg–Marquardt style: the merit is the goals' weighted squared error E; velocity entry
//! i gets the damping λ·E_i, E_i the merit of the goals that entry moves (λ divided by 3 on a
//! step that lowers E, multiplied by 10 and the step retried otherwise), and its regularisers'
//! squared weights are multiplied by min(1, E_i), so that they choose among solutions while the
//! goals are far and vanish as they are met (the goals then
//! converge to their tolerances, as a posture task would otherwise hold them off). A descent
//! stalls when neither E nor any unmet goal's own error fell by 0.1 % in five steps. It stops when
//! every goal is within its tolerances ([`TasksStop::Converged`]), at the iteration budget, or
//! when E no longer decreases: [`TasksStop::Conflicting`] when two or more goals remain unmet
//! (the weights decide between them), [`TasksStop::Stalled`] for one (out of reach, a
//! singularity or a joint limit). Each task's final error is reported.
//!
//! **Batches and trajectories**: independent problems on all cores ([`ik_tasks_batch`], one
//! workspace per worker; row k is the single call on problem k); a trajectory
//! ([`ik_trajectory`]) solves N target sets in order, each seeded by the previous answer, on one
//! core, or in fixed segments on all cores, each segment warmed up from the seed over the target
//! sets before it — the segments depend on the options only, never on the thread count, so the
//! answers do not either.
//!
//! **Limits are types** ([`super::limits`]: position, velocity, one file each, behind the
//! [`super::limits::Limit`] trait). A limit may also give general inequality rows G Δ ≥ h
//! beside the box (collision avoidance, `screwkit_collision::CollisionAvoidance`: one row per
//! close pair); a step with rows is solved by the dual active-set QP
//! [`crate::linalg::qp`] (exact too; no feasible start needed, so a pair already closer than
//! its margin is a row like any other), one without by [`crate::linalg::box_qp`].

use rayon::prelude::*;
use screwkit_lie::Se3;

use super::tasks::{check_tasks, evaluate, Rows, Task, TaskError, TaskSet};
use super::{TreeKinematics, TreeWorkspace};
use crate::error::SolveError;
use crate::ik::Interrupt;
use crate::linalg::box_qp::{self, BoxQpWorkspace};
use crate::linalg::qp::{self, QpWorkspace};

pub use super::limits::{Limits, LIMIT_TOLERANCE};

/// The most velocity variables (nv) a whole-body IK problem may have. Its QP is dense: H is
/// nv × nv (32 MiB of f64 at this limit, and the active set's factor as much again); whole
/// robots have fewer than 100 (TALOS 38 with its floating base). A larger tree is refused with
/// an error naming this limit, before anything of that size is allocated (a 30,000-joint tree
/// asked for 7.2 GB and aborted).
pub const MAX_NV: usize = 2048;

/// The most draws of a restart point that keeps the extra limits.
const RESTART_DRAWS: usize = 20;

/// The most times a step's rows are tightened and its QP solved again
/// ([`super::limits::Limit::tighten`]).
pub const TIGHTEN_ROUNDS: usize = 4;

/// Refuses a tree whose whole-body QP would exceed [`MAX_NV`].
fn check_size(kin: &TreeKinematics) -> Result<(), SolveError> {
    if kin.nv() > MAX_NV {
        return Err(SolveError::InvalidInput(format!(
            "whole-body IK takes trees of at most {MAX_NV} velocity variables (its QP is a \
             dense nv x nv matrix); this one has {}",
            kin.nv()
        )));
    }
    Ok(())
}

/// Reusable scratch of the differential IK (grows to the largest task set, then no allocation).
#[derive(Debug, Clone)]
pub struct DiffIkWorkspace {
    pub(crate) tree: TreeWorkspace,
    rows: Rows,
    next: Rows,
    h: Vec<f64>,
    c: Vec<f64>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    delta: Vec<f64>,
    v: Vec<f64>,
    q: Vec<f64>,
    q_try: Vec<f64>,
    qp: BoxQpWorkspace,
    /// The limits' general rows G Δ ≥ h and their QP.
    limit_rows: super::limits::LimitRows,
    rows_qp: QpWorkspace,
}

impl DiffIkWorkspace {
    /// Scratch for `kin` (H, nv × nv, only for a tree within [`MAX_NV`]: the algorithms refuse
    /// a larger one before they use it).
    pub fn new(kin: &TreeKinematics) -> Self {
        let nv = kin.nv();
        Self {
            tree: TreeWorkspace::new(kin),
            rows: Rows::default(),
            next: Rows::default(),
            h: if nv <= MAX_NV {
                vec![0.0; nv * nv]
            } else {
                Vec::new()
            },
            c: vec![0.0; nv],
            lo: vec![0.0; nv],
            hi: vec![0.0; nv],
            delta: vec![0.0; nv],
            v: vec![0.0; nv],
            q: vec![0.0; kin.nq()],
            q_try: vec![0.0; kin.nq()],
            qp: BoxQpWorkspace::new(),
            limit_rows: Default::default(),
            rows_qp: QpWorkspace::new(),
        }
    }

    fn fit(&mut self, kin: &TreeKinematics) {
        if self.c.len() != kin.nv() || self.q.len() != kin.nq() {
            *self = DiffIkWorkspace::new(kin);
        }
        self.tree.fit(kin);
    }

    /// Each task's error at the configuration of the last step (its q, not after it).
    pub fn task_errors(&self) -> &[TaskError] {
        &self.rows.errors
    }

    /// The QP of the last step or iteration (H n × n row-major, c, l, u, n = nv), for
    /// inspection and reference solves: its solution is that step's Δ = v·dt.
    pub fn qp(&self) -> (&[f64], &[f64], &[f64], &[f64]) {
        (&self.h, &self.c, &self.lo, &self.hi)
    }

    /// The general rows of the last step or iteration (G row-major, nv per row; h): with
    /// [`DiffIkWorkspace::qp`], the whole problem, G Δ ≥ h beside the box.
    pub fn rows(&self) -> (&[f64], &[f64]) {
        (&self.limit_rows.g, &self.limit_rows.h)
    }

    /// After the QP: while the step to q ⊕ Δ breaks a limit its rows linearise (a pair closer
    /// than its margin), the broken rows' bounds are raised by the shortfall and the QP solved
    /// again (at most [`TIGHTEN_ROUNDS`] times: sequential linearisation, as an SQP's).
    fn keep_limits(
        &mut self,
        kin: &TreeKinematics,
        q: &[f64],
        limits: &Limits,
    ) -> Result<(), SolveError> {
        for _ in 0..TIGHTEN_ROUNDS {
            if self.limit_rows.h.is_empty() {
                return Ok(());
            }
            step_into(kin, q, &self.delta, limits.position, &mut self.q_try);
            if !limits.tighten(kin, &self.q_try, &self.delta, &mut self.limit_rows)? {
                return Ok(());
            }
            // Tightened rows the box cannot meet: the last step stands.
            self.v.copy_from_slice(&self.delta);
            if self.solve_qp().is_err() {
                self.delta.copy_from_slice(&self.v);
                return Ok(());
            }
        }
        Ok(())
    }

    /// The step's QP solved into `delta`: the box alone by [`box_qp`]; with rows, by [`qp`]
    /// (bounds and rows together: measured on TALOS against a table, solving the box first
    /// and then both only when the box's answer breaks a row cost 2 µs more a step, the rows
    /// being broken on nearly every step in contact).
    fn solve_qp(&mut self) -> Result<(), SolveError> {
        if self.limit_rows.h.is_empty() {
            box_qp::solve(
                &mut self.qp,
                &self.h,
                &self.c,
                &self.lo,
                &self.hi,
                &mut self.delta,
            )?;
        } else {
            qp::solve(
                &mut self.rows_qp,
                &self.h,
                &self.c,
                &self.lo,
                &self.hi,
                &self.limit_rows.g,
                &self.limit_rows.h,
                &mut self.delta,
            )?;
        }
        Ok(())
    }
}

fn check_dt(dt: f64) -> Result<(), SolveError> {
    if dt.is_finite() && dt > 0.0 {
        Ok(())
    } else {
        Err(SolveError::InvalidInput(format!(
            "dt must be a finite number > 0, got {dt}"
        )))
    }
}

/// Per velocity entry, the merit of the goals it moves ([`Damping::merit`]) and whether any
/// goal depends on it: the scales of [`ik_tasks`]' damping and regularisers.
#[derive(Debug, Clone, Default)]
struct Damping {
    merit: Vec<f64>,
    touched: Vec<bool>,
    lambda: f64,
}

/// H = AᵀA + D' + εI, c = −(Aᵀb + D' r) from `rows`. Without `damping` (a control step),
/// D' = D. With it (an iteration of [`ik_tasks`]), entry i's regularisers are scaled by
/// min(1, E_i) (E_i the merit of the goals entry i moves; 1 for an entry no goal depends on,
/// or when there is no goal) and λ E_i is added: Levenberg–Marquardt damping per entry, so that
/// a goal met or converging beside a stuck one is neither damped nor held off by it.
///
/// Errors (`InvalidInput`) when the numbers overflow f64 — a weight or a target so large that
/// its square is infinite: a diagonal of H or an entry of c that is not finite (H's
/// off-diagonal entries are then finite too, |H_ij| ≤ √(H_ii H_jj)).
fn normal_equations(
    rows: &Rows,
    nv: usize,
    damping: Option<&Damping>,
    h: &mut [f64],
    c: &mut [f64],
) -> Result<(), SolveError> {
    let scale = |i: usize| match damping {
        Some(d) if rows.has_goal && d.touched[i] => (d.merit[i].min(1.0), d.lambda * d.merit[i]),
        _ => (1.0, 0.0),
    };
    h.fill(0.0);
    for (k, ck) in c.iter_mut().enumerate() {
        *ck = -scale(k).0 * rows.diag_rhs[k];
    }
    for r in 0..rows.m {
        let row = &rows.a[r * nv..r * nv + nv];
        let br = rows.b[r];
        for i in 0..nv {
            let ai = row[i];
            if ai == 0.0 {
                continue;
            }
            c[i] -= ai * br;
            let hrow = &mut h[i * nv..i * nv + i + 1];
            for (hij, aj) in hrow.iter_mut().zip(&row[..=i]) {
                *hij += ai * aj;
            }
        }
    }
    let mut max_diag = 0.0_f64;
    for i in 0..nv {
        h[i * nv + i] += scale(i).0 * rows.diag[i];
        max_diag = max_diag.max(h[i * nv + i]);
    }
    let eps = 1e-10 * (1.0 + max_diag);
    for i in 0..nv {
        h[i * nv + i] += eps + scale(i).1;
    }
    match (0..nv).find(|&i| !h[i * nv + i].is_finite() || !c[i].is_finite()) {
        None => Ok(()),
        Some(i) => Err(SolveError::InvalidInput(format!(
            "the step's least-squares problem overflows at velocity entry {i} (H = {:e}, c = {:e}): a task's weight or target is too large for f64 (weights above about 1e150 square to infinity)",
            h[i * nv + i],
            c[i]
        ))),
    }
}

/// The velocity entries each goal depends on ([`Task`]'s dependence: the variables of its
/// frames' paths and a floating base's six, every entry for a centre-of-mass task); empty for
/// regularisers.
fn dependence(kin: &TreeKinematics, tasks: &[Task]) -> Vec<Vec<usize>> {
    tasks.iter().map(|t| t.dependence(kin)).collect()
}

impl Damping {
    fn new(nv: usize, deps: &[Vec<usize>]) -> Damping {
        let mut touched = vec![false; nv];
        for d in deps {
            for &i in d {
                touched[i] = true;
            }
        }
        Damping {
            merit: vec![0.0; nv],
            touched,
            lambda: 1e-3,
        }
    }

    /// E_i from the tasks' merits.
    fn update(&mut self, deps: &[Vec<usize>], rows: &Rows) {
        self.merit.fill(0.0);
        for (d, m) in deps.iter().zip(&rows.task_merit) {
            for &i in d {
                self.merit[i] += m;
            }
        }
    }
}

/// One control step: the velocity v (nv) that moves the tasks by their gains in time `dt`
/// within `limits` (module documentation), in the workspace. Checks q, the tasks and dt.
pub fn ik_step<'w>(
    kin: &TreeKinematics,
    ws: &'w mut DiffIkWorkspace,
    q: &[f64],
    tasks: &[Task],
    dt: f64,
    limits: &Limits,
) -> Result<&'w [f64], SolveError> {
    check_size(kin)?;
    let base = kin.check_q(q)?;
    check_tasks(kin, tasks)?;
    check_dt(dt)?;
    step(kin, ws, q, &base, tasks, dt, limits)
}

/// [`ik_step`] with a prepared task set (checked once; its targets updated in place by
/// [`TaskSet::set_target`]): the same step, without checking the tasks again. Checks q, dt
/// and that the set was prepared for this model.
pub fn ik_step_set<'w>(
    kin: &TreeKinematics,
    ws: &'w mut DiffIkWorkspace,
    q: &[f64],
    tasks: &TaskSet,
    dt: f64,
    limits: &Limits,
) -> Result<&'w [f64], SolveError> {
    check_size(kin)?;
    let base = kin.check_q(q)?;
    tasks.check_model(kin)?;
    check_dt(dt)?;
    step(kin, ws, q, &base, tasks.tasks(), dt, limits)
}

/// The step of [`ik_step`] on checked inputs.
fn step<'w>(
    kin: &TreeKinematics,
    ws: &'w mut DiffIkWorkspace,
    q: &[f64],
    base: &Se3,
    tasks: &[Task],
    dt: f64,
    limits: &Limits,
) -> Result<&'w [f64], SolveError> {
    ws.fit(kin);
    let nv = kin.nv();
    limits.bounds(kin, q, Some(dt), &mut ws.lo, &mut ws.hi)?;
    limits.rows(kin, q, &mut ws.limit_rows)?;
    evaluate(kin, &mut ws.tree, q, base, tasks, &mut ws.rows);
    normal_equations(&ws.rows, nv, None, &mut ws.h, &mut ws.c)?;
    ws.solve_qp()?;
    ws.keep_limits(kin, q, limits)?;
    for (v, d) in ws.v.iter_mut().zip(&ws.delta) {
        *v = d / dt;
    }
    Ok(&ws.v)
}

/// Why [`ik_tasks`] stopped (its best descent's reason).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TasksStop {
    /// Every goal within its tolerances.
    Converged,
    /// The iteration budget ran out.
    Iterations,
    /// One goal remains unmet and no step lowers its error (out of reach, a singularity, a
    /// joint limit).
    Stalled,
    /// Two or more goals remain unmet and no step lowers their weighted error: they conflict
    /// and the weights decide.
    Conflicting,
    /// The caller's interrupt check said stop.
    Interrupted,
}

impl TasksStop {
    /// The word (`converged`, `iterations`, `stalled`, `conflicting`, `interrupted`).
    pub fn word(self) -> &'static str {
        match self {
            TasksStop::Converged => "converged",
            TasksStop::Iterations => "iterations",
            TasksStop::Stalled => "stalled",
            TasksStop::Conflicting => "conflicting",
            TasksStop::Interrupted => "interrupted",
        }
    }
}

/// Settings of [`ik_tasks`].
#[derive(Debug, Clone)]
pub struct TasksOptions {
    /// Iteration budget of each descent (default 100).
    pub max_iterations: usize,
    /// Descents from random joint values after the first stalls (default 50).
    pub restarts: usize,
    /// The restarts' random seed (default 0; batch row k uses `batch::row_seed(seed, k)`).
    pub seed: u64,
    /// Keep q within the position bounds (default true).
    pub position_limits: bool,
    /// A stop check polled every 16 iterations, from the first (so a trajectory of short
    /// solves polls it once per set).
    pub interrupt: Option<Interrupt>,
    /// Further limits every iteration respects (collision avoidance; none by default).
    pub limits: Vec<std::sync::Arc<dyn super::limits::Limit>>,
}

impl PartialEq for TasksOptions {
    /// Equal settings and the same limit objects.
    fn eq(&self, o: &TasksOptions) -> bool {
        self.max_iterations == o.max_iterations
            && self.restarts == o.restarts
            && self.seed == o.seed
            && self.position_limits == o.position_limits
            && self.interrupt == o.interrupt
            && self.limits.len() == o.limits.len()
            && self
                .limits
                .iter()
                .zip(&o.limits)
                .all(|(a, b)| std::sync::Arc::ptr_eq(a, b))
    }
}

impl Default for TasksOptions {
    fn default() -> Self {
        TasksOptions {
            max_iterations: 100,
            restarts: 50,
            seed: 0,
            position_limits: true,
            interrupt: None,
            limits: Vec::new(),
        }
    }
}

/// The outcome of [`ik_tasks`].
#[derive(Debug, Clone, PartialEq)]
pub struct TasksResult {
    /// The final configuration (nq).
    pub q: Vec<f64>,
    /// Every goal within its tolerances.
    pub converged: bool,
    /// Steps taken, over every descent.
    pub iterations: usize,
    /// Why it stopped.
    pub stop: TasksStop,
    /// Each task's error at `q`, in the tasks' order.
    pub task_errors: Vec<TaskError>,
}

/// q ⊕ Δ (the base by the exponential map), the joints clamped into `bounds` when `limits`
/// (rounding only: Δ is within the box).
fn step_into(kin: &TreeKinematics, q: &[f64], delta: &[f64], limits: bool, out: &mut [f64]) {
    let (qo, vo) = (kin.q_offset(), kin.v_offset());
    for (j, &(bl, bu)) in kin.variable_bounds.iter().enumerate() {
        let x = q[qo + j] + delta[vo + j];
        out[qo + j] = if limits {
            x.clamp(bl.min(q[qo + j]), bu.max(q[qo + j]))
        } else {
            x
        };
    }
    if kin.floating {
        let base = super::base_pose(q).unwrap_or_else(|_| Se3::identity());
        let step = Se3::exp(&screwkit_lie::Twist::new(
            nalgebra::Vector3::new(delta[0], delta[1], delta[2]),
            nalgebra::Vector3::new(delta[3], delta[4], delta[5]),
        ));
        let t = base.compose(&step);
        out[..3].copy_from_slice(t.translation().as_slice());
        out[3..7].copy_from_slice(&t.quaternion());
    }
}

/// Iterates steps to convergence from `seed` (module documentation), restarting from random
/// joint values (`opts.restarts`, seeded by `opts.seed`) when a descent stalls. Checks the seed
/// (within the limits when `opts.position_limits`) and the tasks.
pub fn ik_tasks(
    kin: &TreeKinematics,
    ws: &mut DiffIkWorkspace,
    tasks: &[Task],
    seed: &[f64],
    opts: &TasksOptions,
) -> Result<TasksResult, SolveError> {
    check_size(kin)?;
    kin.check_q(seed)?;
    check_tasks(kin, tasks)?;
    ws.fit(kin);
    let limits = Limits {
        position: opts.position_limits,
        velocity: false,
        extra: opts.limits.clone(),
        ..Limits::default()
    };
    limits.bounds(kin, seed, None, &mut ws.lo, &mut ws.hi)?;
    // Which velocity entries each goal moves: once per call (descents and restarts share it).
    let deps = dependence(kin, tasks);
    let mut rng = crate::sample::SplitMix64(opts.seed);
    let mut start = seed.to_vec();
    // (keeps the extra limits, merit, result) of the best descent.
    let mut best: Option<(bool, f64, TasksResult)> = None;
    let (mut iterations, mut interrupted) = (0, false);
    for attempt in 0..=opts.restarts {
        if attempt > 0 {
            // Odd restarts keep the best answer's met goals and redraw the variables of the
            // unmet ones; even restarts redraw every joint from the seed. A draw that breaks
            // an extra limit (a configuration in contact) is drawn again, a few times.
            for _ in 0..RESTART_DRAWS {
                match (&best, attempt % 2) {
                    (Some((_, _, b)), 1) => {
                        let mask = unmet_variables(kin, &deps, tasks, &b.task_errors);
                        restart_point(kin, &b.q, Some(&mask), &mut rng, &mut start);
                    }
                    _ => restart_point(kin, seed, None, &mut rng, &mut start),
                }
                if limits.extra.is_empty() || limits.satisfied(kin, &start)? {
                    break;
                }
            }
        }
        let (stop, used) = descend(kin, ws, tasks, &deps, &start, &limits, opts)?;
        iterations += used;
        let merit = ws.rows.merit;
        // An answer that keeps the extra limits beats one that does not, then the lower merit.
        let kept = limits.extra.is_empty() || limits.satisfied(kin, &ws.q)?;
        let converged = stop == TasksStop::Converged && kept;
        if best
            .as_ref()
            .is_none_or(|(k, m, _)| (kept && !k) || (kept == *k && (merit < *m || converged)))
        {
            best = Some((
                kept,
                merit,
                TasksResult {
                    q: ws.q.clone(),
                    converged: ws.rows.converged && kept,
                    iterations,
                    stop: if stop == TasksStop::Converged && !kept {
                        TasksStop::Stalled
                    } else {
                        stop
                    },
                    task_errors: ws.rows.errors.clone(),
                },
            ));
        }
        if stop == TasksStop::Interrupted {
            interrupted = true;
        }
        if converged || stop == TasksStop::Interrupted {
            break;
        }
    }
    let mut result = best.expect("at least one descent").2;
    result.iterations = iterations;
    if interrupted && !result.converged {
        // The best answer so far, and the reason the search ended.
        result.stop = TasksStop::Interrupted;
    }
    Ok(result)
}

/// A restart: `from` with its joints (those of `mask`, or all) drawn uniformly within their
/// bounds ([−π, π] where unbounded); the floating base kept.
fn restart_point(
    kin: &TreeKinematics,
    from: &[f64],
    mask: Option<&[bool]>,
    rng: &mut crate::sample::SplitMix64,
    out: &mut [f64],
) {
    out.copy_from_slice(from);
    let qo = kin.q_offset();
    for (j, &(l, u)) in kin.variable_bounds.iter().enumerate() {
        let (l, u) = crate::sample::range(l, u);
        let x = l + (u - l) * rng.uniform();
        if mask.is_none_or(|m| m[j]) {
            out[qo + j] = x;
        }
    }
}

/// The joint variables the goals not met depend on ([`dependence`] without the floating base's
/// entries: every variable for an unmet centre-of-mass task).
fn unmet_variables(
    kin: &TreeKinematics,
    deps: &[Vec<usize>],
    tasks: &[Task],
    errors: &[TaskError],
) -> Vec<bool> {
    let vo = kin.v_offset();
    let mut mask = vec![false; kin.variable_bounds.len()];
    for ((t, e), d) in tasks.iter().zip(errors).zip(deps) {
        if t.is_goal() && !e.converged {
            for &i in d.iter().filter(|&&i| i >= vo) {
                mask[i - vo] = true;
            }
        }
    }
    mask
}

/// True when the total merit or some unmet goal's own error fell by more than 0.1 % (a goal
/// converging beside a stuck one is progress though the total hardly moves).
fn progress(tasks: &[Task], before: &Rows, after: &Rows) -> bool {
    const RATE: f64 = 1.0 - 1e-3;
    if after.merit < before.merit * RATE {
        return true;
    }
    let size = |e: &TaskError| e.position * e.position + e.rotation * e.rotation;
    tasks
        .iter()
        .zip(before.errors.iter().zip(&after.errors))
        .any(|(t, (b, a))| t.is_goal() && !b.converged && size(a) < size(b) * RATE)
}

/// One Levenberg–Marquardt descent from `start` (module documentation) of at most
/// `opts.max_iterations` steps; leaves the final q and its evaluation in `ws.q` / `ws.rows`.
fn descend(
    kin: &TreeKinematics,
    ws: &mut DiffIkWorkspace,
    tasks: &[Task],
    deps: &[Vec<usize>],
    start: &[f64],
    limits: &Limits,
    opts: &TasksOptions,
) -> Result<(TasksStop, usize), SolveError> {
    let nv = kin.nv();
    let budget = opts.max_iterations;
    ws.q.copy_from_slice(start);
    let base = kin.check_q(&ws.q)?;
    evaluate(kin, &mut ws.tree, &ws.q, &base, tasks, &mut ws.rows);
    let mut damping = Damping::new(nv, deps);
    let mut iterations = 0;
    let mut slow = 0;
    loop {
        if ws.rows.converged {
            return Ok((TasksStop::Converged, iterations));
        }
        if iterations >= budget {
            return Ok((TasksStop::Iterations, iterations));
        }
        if iterations % 16 == 0 && opts.interrupt.as_ref().is_some_and(|i| (i.0)()) {
            return Ok((TasksStop::Interrupted, iterations));
        }
        let e = ws.rows.merit;
        damping.update(deps, &ws.rows);
        limits.bounds(kin, &ws.q, None, &mut ws.lo, &mut ws.hi)?;
        limits.rows(kin, &ws.q, &mut ws.limit_rows)?;
        let mut accepted = false;
        while damping.lambda < 1e10 {
            normal_equations(&ws.rows, nv, Some(&damping), &mut ws.h, &mut ws.c)?;
            match ws.solve_qp() {
                // Rows the box cannot meet (a restart drawn in contact, held by a joint
                // limit): this descent ends there, the next restarts elsewhere.
                Err(SolveError::Numerical(_)) if !ws.limit_rows.h.is_empty() => {
                    return Ok((TasksStop::Stalled, iterations));
                }
                r => r?,
            }
            let q = std::mem::take(&mut ws.q);
            let kept = ws.keep_limits(kin, &q, limits);
            ws.q = q;
            kept?;
            step_into(kin, &ws.q, &ws.delta, limits.position, &mut ws.q_try);
            let base = kin.check_q(&ws.q_try)?;
            evaluate(kin, &mut ws.tree, &ws.q_try, &base, tasks, &mut ws.next);
            // A step is taken when it lowers the merit and keeps the extra limits (their rows
            // are linear, an iteration's step is not small: a step into contact is retried
            // with more damping), or when q breaks them already (its rows move it out).
            if ws.next.merit < e
                && (limits.extra.is_empty()
                    || limits.satisfied(kin, &ws.q_try)?
                    || !limits.satisfied(kin, &ws.q)?)
            {
                accepted = true;
                damping.lambda = (damping.lambda / 3.0).max(1e-12);
                slow = if progress(tasks, &ws.rows, &ws.next) {
                    0
                } else {
                    slow + 1
                };
                std::mem::swap(&mut ws.rows, &mut ws.next);
                std::mem::swap(&mut ws.q, &mut ws.q_try);
                break;
            }
            damping.lambda *= 10.0;
        }
        iterations += 1;
        if !accepted || slow >= 5 {
            if ws.rows.converged {
                return Ok((TasksStop::Converged, iterations));
            }
            let unmet = ws
                .rows
                .errors
                .iter()
                .zip(tasks)
                .filter(|(e, t)| t.is_goal() && !e.converged)
                .count();
            let stop = if unmet >= 2 {
                TasksStop::Conflicting
            } else {
                TasksStop::Stalled
            };
            return Ok((stop, iterations));
        }
    }
}

/// One problem of a batch: its tasks, seed and row.
#[derive(Debug, Clone, PartialEq)]
pub struct TasksProblem {
    /// The tasks.
    pub tasks: Vec<Task>,
    /// The seed (nq).
    pub seed: Vec<f64>,
    /// Its row in the caller's numbering (a line of a stream read in chunks): its restarts'
    /// random seed is `batch::row_seed(opts.seed, row)`, so an answer does not depend on how
    /// the rows were chunked.
    pub row: usize,
}

/// Independent problems on all cores (one workspace per worker): entry k is
/// `ik_tasks(problems[k])` with restart seed `batch::row_seed(opts.seed, problems[k].row)`,
/// whatever the thread count.
pub fn ik_tasks_batch(
    kin: &TreeKinematics,
    problems: &[TasksProblem],
    opts: &TasksOptions,
) -> Vec<Result<TasksResult, SolveError>> {
    problems
        .par_iter()
        .map_init(
            || DiffIkWorkspace::new(kin),
            |ws, p| {
                let opts = TasksOptions {
                    seed: crate::batch::row_seed(opts.seed, p.row),
                    ..opts.clone()
                };
                ik_tasks(kin, ws, &p.tasks, &p.seed, &opts)
            },
        )
        .collect()
}

/// How [`ik_trajectory`] splits a trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Segments {
    /// Target sets per segment; 0 (the default): one segment, solved in order on one core.
    pub length: usize,
    /// Target sets before each segment solved first (from the seed) and discarded, so that a
    /// segment starts from an answer of the trajectory rather than from the seed.
    pub warm_up: usize,
}

/// N target sets solved in order, each seeded by the previous answer (the first by `seed`); a
/// set that fails (bad input) is reported and the next one seeded by the last answer. With
/// `segments.length > 0`, segment s (sets s·length …) runs on its own core after solving the
/// `warm_up` sets before it from `seed`; the answers depend on `segments`, not on the threads.
pub fn ik_trajectory(
    kin: &TreeKinematics,
    sets: &[Vec<Task>],
    seed: &[f64],
    opts: &TasksOptions,
    segments: Segments,
) -> Result<Vec<Result<TasksResult, SolveError>>, SolveError> {
    check_size(kin)?;
    kin.check_q(seed)?;
    let n = sets.len();
    let length = if segments.length == 0 {
        n.max(1)
    } else {
        segments.length
    };
    let starts: Vec<usize> = (0..n).step_by(length).collect();
    let parts: Vec<Vec<Result<TasksResult, SolveError>>> = starts
        .par_iter()
        .map(|&start| {
            let mut ws = DiffIkWorkspace::new(kin);
            let end = (start + length).min(n);
            let first = start.saturating_sub(segments.warm_up);
            let mut q = seed.to_vec();
            let mut out = Vec::with_capacity(end - start);
            for (i, set) in sets.iter().enumerate().take(end).skip(first) {
                let r = ik_tasks(kin, &mut ws, set, &q, opts);
                if let Ok(res) = &r {
                    q.copy_from_slice(&res.q);
                }
                if i >= start {
                    out.push(r);
                }
            }
            out
        })
        .collect();
    Ok(parts.into_iter().flatten().collect())
}
