//! Inverse kinematics: find q with T(q) = T_sd.
//!
//! Every method is the Newton–Raphson iteration of *Modern Robotics* §6.2.2 on the body twist
//! error V_b = log(T_sb(q)⁻¹ T_sd) with the body Jacobian J_b(q), and stops when ‖ω_b‖ ≤ ε_ω
//! and ‖v_b‖ ≤ ε_v (over the components whose weight is not 0; position-only uses
//! (0, R_sbᵀ(p_d − p))). They differ in the step:
//!
//! - [`IkMethod::NewtonRaphson`]: Δq = J_b⁺ V_b, SVD pseudo-inverse ([`crate::linalg::svd`]).
//! - [`IkMethod::Dls`]: Δq = J_bᵀ (J_b J_bᵀ + λ² I)⁻¹ V_b with a fixed damping λ.
//! - [`IkMethod::LevenbergMarquardt`] (default): Δq = J_bᵀ (J_b J_bᵀ + μ I)⁻¹ V_b with the
//!   adaptive diagonal term μ = 0.05 ‖V_b‖² + μ̄ (after Sugihara, "Solvability-unconcerned
//!   inverse kinematics by the Levenberg–Marquardt method", IEEE T-RO 2011, whose W_N = E + W̄_N
//!   with E = ½‖e‖²; the weight 0.05 instead of ½ damps less far from the target), so steps are
//!   Gauss–Newton near the solution and damped far from it or near singularities.
//!
//! Joint limits: a joint at a bound that the step would push outward is taken out of the step
//! (active set) and the step is solved again without it; then q is projected into the limits
//! (continuous joints wrapped to (−π, π]), so solutions are always within limits. When an
//! attempt stalls (its error norm ‖e‖ does not halve within 5 iterations, unless it is within
//! 1000 tolerances of the target and still closing in by 10 % a window) or reaches 60
//! iterations, it restarts from a random configuration drawn from a seeded generator —
//! reproducible — until the iteration budget or the restart budget runs out (or a wall-time
//! budget, when one is set: none by default, so the same targets give the same answers on an
//! idle and a busy machine). Not converging is an explicit result
//! ([`IkStatus::converged`] = false, with the best q found and why it stopped), never silent
//! garbage.

use std::time::{Duration, Instant};

use nalgebra::{Matrix6xX, Vector6};
use screwkit_lie::Se3;

use screwkit_lie::Frame;

use crate::error::SolveError;
use crate::fk::fk_unchecked;
use crate::jacobian::fk_jacobian_into;
use crate::kinematics::Kinematics;
use crate::sample::{configuration_into, SplitMix64};
use crate::workspace::{ClearScratch, IkScratch, Workspace};

/// The update rule.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkMethod {
    /// Newton–Raphson with the SVD pseudo-inverse.
    NewtonRaphson,
    /// Damped least squares with a fixed damping λ.
    Dls {
        /// Damping λ (same units as the twist error).
        lambda: f64,
    },
    /// Levenberg–Marquardt: J Jᵀ + μ I with the adaptive diagonal term μ = 0.05 ‖e‖² + μ̄.
    LevenbergMarquardt {
        /// The floor μ̄ of the diagonal term (not squared).
        damping_floor: f64,
    },
}

impl IkMethod {
    /// Damped least squares with λ = 0.02.
    pub const DLS: IkMethod = IkMethod::Dls { lambda: 0.02 };
    /// Levenberg–Marquardt with μ̄ = 1e-8.
    pub const LM: IkMethod = IkMethod::LevenbergMarquardt {
        damping_floor: 1e-8,
    };
}

/// Why a solve stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The tolerances were met.
    Converged,
    /// The iteration budget ran out.
    IterationLimit,
    /// The restart budget ran out.
    RestartLimit,
    /// The wall-time budget ran out.
    TimeLimit,
    /// Not solved: the row's input was invalid (batches only; see [`crate::batch::ik_batch`]).
    InvalidInput,
    /// Stopped by the caller's [`IkOptions::interrupt`] check (Ctrl-C in a front end).
    Interrupted,
    /// The budget ran out with only answers that reach the target in collision (or closer than
    /// the margin): [`solve_clear`] only; q is such an answer.
    InCollision,
}

impl StopReason {
    /// A short lowercase label (`"converged"`, `"iteration limit"`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration limit",
            StopReason::RestartLimit => "restart limit",
            StopReason::TimeLimit => "time limit",
            StopReason::InvalidInput => "invalid input",
            StopReason::Interrupted => "interrupted",
            StopReason::InCollision => "in collision",
        }
    }
}

/// What IK asks of a robot's body to keep its answers clear of contact: the solver knows no
/// shapes (`screwkit_collision::ChainClearance` is the body of a chain in its robot; [`NoBody`]
/// none). `q` is always the chain's joint values.
///
/// [`solve_clear`] iterates as [`solve`] until the pose is reached, then asks
/// [`is_clear`](Clearance::is_clear); an answer that is not clear is not converged.
///
/// - An answer in contact is rejected and the attempt restarts from the next seeded
///   configuration: a collision check (µs) per answer.
/// - On a chain with more joints than the target constrains (the Panda on a full pose, a 6R on
///   a position), from the [`CLEARANCE_STEER_AFTER`]-th such answer on, when the body
///   [`steers`](Clearance::steers), every step is the least-squares step under the joint
///   limits and one inequality row per close pair (pairs closer than
///   [`CLEARANCE_DETECTION`] · L beyond the margin, L the chain's length scale):
///   ∂d/∂q · Δq ≥ −[`CLEARANCE_GAIN`] (d − margin − [`CLEARANCE_BUFFER`] · L), solved by
///   [`crate::linalg::qp`]; so the arm moves along the target's self-motion away from contact
///   instead of restarting blindly.
///
/// Why both (measured on the Panda beside a table and a box, BENCHMARKS.md): steering solves
/// more targets per restart (93 % against 85 % within two restarts, steering from the first
/// contact), but a steered step costs a distance and its row per close pair (~1 ms on exact
/// meshes) where a rejection costs a check; steering from the first contact took 387 µs per
/// target, rejection alone 14 µs, both solving all 200. Rejecting the first answers and
/// steering the hard targets solves as many, and more on a tight budget, at 36 µs. A chain
/// without self-motion (the UR5 on a full pose) only rejects: steering there moves it off the
/// target.
pub trait Clearance: Sync {
    /// One thread's scratch for the body's queries.
    type Scratch: Send;
    /// A new scratch.
    fn scratch(&self) -> Self::Scratch;
    /// True when no checked pair is closer than the margin at q (a query that fails: false).
    fn is_clear(&self, scratch: &mut Self::Scratch, q: &[f64]) -> bool;
    /// True to steer away from contact with distance rows; false to only reject colliding
    /// answers and restart (for measuring the two).
    fn steers(&self) -> bool {
        true
    }
    /// The pairs whose signed distance is within `within` of the margin at q: for each, its
    /// distance less the margin appended to `gaps`, and its gradient ∂d/∂q (one value per
    /// joint variable) appended to `rows`. Pairs the engine cannot measure are left out.
    fn close_rows(
        &self,
        scratch: &mut Self::Scratch,
        q: &[f64],
        within: f64,
        gaps: &mut Vec<f64>,
        rows: &mut Vec<f64>,
    );
}

/// No body: every answer is clear ([`solve`]'s case).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoBody;

impl Clearance for NoBody {
    type Scratch = ();
    fn scratch(&self) {}
    fn is_clear(&self, _: &mut (), _: &[f64]) -> bool {
        true
    }
    fn steers(&self) -> bool {
        false
    }
    fn close_rows(&self, _: &mut (), _: &[f64], _: f64, _: &mut Vec<f64>, _: &mut Vec<f64>) {}
}

/// The pairs a clearance step constrains: those closer than this many length scales beyond
/// the margin.
pub const CLEARANCE_DETECTION: f64 = 0.05;
/// Steering starts after this many answers reached in contact (the first ones are rejected:
/// a restart costs a collision check, a steered step a distance and row per close pair).
pub const CLEARANCE_STEER_AFTER: usize = 3;
/// The fraction of its gap to the margin a close pair may close in one step (and of its
/// shortfall it must recover).
pub const CLEARANCE_GAIN: f64 = 0.5;
/// The rows keep this many length scales beyond the margin, so that the exact check after
/// convergence passes despite the rows' linearisation.
pub const CLEARANCE_BUFFER: f64 = 1e-4;

/// IK settings. `Default` gives LM, 1e-9 rad / 1e-9 m, 2000 iterations, 200 restarts, no
/// wall-time budget (reproducible), seed 0.
#[derive(Debug, Clone, PartialEq)]
pub struct IkOptions {
    /// The update rule.
    pub method: IkMethod,
    /// ε_ω: converged when ‖ω_b‖ ≤ this (rad).
    pub tol_rot: f64,
    /// ε_v: converged when ‖v_b‖ ≤ this (m).
    pub tol_pos: f64,
    /// Total iterations over all attempts.
    pub max_iterations: usize,
    /// Random restarts allowed.
    pub max_restarts: usize,
    /// Wall-time budget (`None`: iterations and restarts only, fully deterministic).
    pub timeout: Option<Duration>,
    /// Seed of the restart generator.
    pub seed: u64,
    /// Solve for the tip position only (orientation free).
    pub position_only: bool,
    /// Weights on the six twist-error components (ω₁, ω₂, ω₃, v₁, v₂, v₃); 0 masks one out.
    pub weights: [f64; 6],
    /// Largest change of any joint in one iteration (rad or m).
    pub max_step: f64,
    /// Called every 64 iterations when set: `true` stops the solve with
    /// [`StopReason::Interrupted`] (a front end's Ctrl-C check). `None` by default.
    pub interrupt: Option<Interrupt>,
}

/// A caller's check for "stop now" ([`IkOptions::interrupt`]): a plain function, so options
/// stay `Copy`-cheap and `Send`. Two checks compare equal (options are compared by their
/// settings, not by which function polls for Ctrl-C).
#[derive(Debug, Clone, Copy)]
pub struct Interrupt(pub fn() -> bool);

impl PartialEq for Interrupt {
    fn eq(&self, _: &Self) -> bool {
        true
    }
}

/// A wall-time budget given in milliseconds, as every front end takes it: 0 is no budget
/// (the default: answers then depend on iterations and restarts only), a positive number is
/// the budget (one beyond what a [`Duration`] holds, 1e300 say, is no budget either);
/// negative, NaN and infinite values are refused.
pub fn timeout_from_ms(ms: f64) -> Result<Option<Duration>, SolveError> {
    if !ms.is_finite() || ms < 0.0 {
        return Err(SolveError::InvalidInput(format!(
            "expected a finite number of milliseconds ≥ 0 (0: none), got {ms}"
        )));
    }
    if ms == 0.0 {
        return Ok(None);
    }
    Ok(Duration::try_from_secs_f64(ms / 1e3).ok())
}

impl Default for IkOptions {
    fn default() -> Self {
        Self {
            method: IkMethod::LM,
            tol_rot: 1e-9,
            tol_pos: 1e-9,
            max_iterations: 2000,
            max_restarts: 200,
            timeout: None,
            seed: 0,
            position_only: false,
            weights: [1.0; 6],
            max_step: 1.0,
            interrupt: None,
        }
    }
}

/// How a solve ended, without the solution vector (which [`solve_into`] writes into the
/// caller's buffer and [`IkResult`] carries).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IkStatus {
    /// True when the tolerances were met.
    pub converged: bool,
    /// Iterations used (all attempts).
    pub iterations: usize,
    /// Random restarts used.
    pub restarts: usize,
    /// Final rotation error: the angle of R_sbᵀ R_sd (rad), reported also for position-only.
    pub error_rot: f64,
    /// Final position error ‖p_d − p‖ (m).
    pub error_pos: f64,
    /// Why it stopped.
    pub stop: StopReason,
}

impl IkStatus {
    /// The status of a row that was not solved because its input was invalid: not converged,
    /// no iterations, NaN errors, stop [`StopReason::InvalidInput`].
    pub fn unsolved() -> Self {
        Self {
            converged: false,
            iterations: 0,
            restarts: 0,
            error_rot: f64::NAN,
            error_pos: f64::NAN,
            stop: StopReason::InvalidInput,
        }
    }
}

impl Default for IkStatus {
    /// [`IkStatus::unsolved`]: what an output buffer holds before a batch fills it.
    fn default() -> Self {
        Self::unsolved()
    }
}

/// The outcome of [`solve`]: the solution and how the solve ended.
#[derive(Debug, Clone, PartialEq)]
pub struct IkResult {
    /// The solution (or, if not converged, the best configuration found); always within limits.
    pub q: Vec<f64>,
    /// Converged or not, iterations, errors, why it stopped.
    pub status: IkStatus,
}

/// Projects q into the limits; continuous variables are wrapped to (−π, π].
fn project(kin: &Kinematics, q: &mut [f64]) {
    for (k, x) in q.iter_mut().enumerate() {
        if kin.continuous[k] {
            *x = screwkit_lie::angle::wrap(*x);
        } else {
            *x = x.clamp(kin.lower[k], kin.upper[k]);
        }
    }
}

/// Error twist (weighted), the norms that decide convergence (over the components that are
/// not masked out) and the true rotation/position errors for reporting.
struct ErrorState {
    e: Vector6<f64>,
    check_rot: f64,
    check_lin: f64,
    rot: f64,
    pos: f64,
}

fn error_state(t: &Se3, target: &Se3, opts: &IkOptions, weights: &[f64; 6]) -> ErrorState {
    let t_bd = t.inverse_compose(target);
    let (mut e, rot) = if opts.position_only {
        let d = t_bd.translation();
        let rot = screwkit_lie::so3::log(t_bd.rotation()).norm();
        (Vector6::new(0.0, 0.0, 0.0, d.x, d.y, d.z), rot)
    } else {
        let v_b = t_bd.log();
        (v_b.to_vector(), v_b.w.norm())
    };
    let (mut check_rot, mut check_lin) = (0.0, 0.0);
    for i in 0..6 {
        let w = weights[i];
        if w != 0.0 {
            if i < 3 {
                check_rot += e[i] * e[i];
            } else {
                check_lin += e[i] * e[i];
            }
        }
        e[i] *= w;
    }
    ErrorState {
        e,
        check_rot: check_rot.sqrt(),
        check_lin: check_lin.sqrt(),
        rot,
        pos: (target.translation() - t.translation()).norm(),
    }
}

/// The weight w of the LM diagonal term μ = w ‖e‖² + μ̄: Sugihara's ½ (μ = E = ½‖e‖²) damps
/// too much far from the target on these arms (26 → 17 iterations per solve on the UR5
/// benchmark protocol of BENCHMARKS.md with 0.05).
const LM_ERROR_WEIGHT: f64 = 0.05;

/// Scales the rows of J by the weights (skipped when all are 1).
fn weight_rows(jac: &mut Matrix6xX<f64>, weights: &[f64; 6]) {
    if weights.iter().all(|&w| w == 1.0) {
        return;
    }
    for mut c in jac.column_iter_mut() {
        for i in 0..6 {
            c[i] *= weights[i];
        }
    }
}

/// Δq for one iteration into `dq`, from the (already weighted) J and e. Columns whose
/// `locked` flag is set are left out (their Δq is 0).
fn step(
    method: IkMethod,
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    locked: &[bool],
    dq: &mut [f64],
) -> Result<(), SolveError> {
    let mu = match method {
        // Δq = J⁺ e with the SVD; σ ≤ 1e-10 σ₁ dropped.
        IkMethod::NewtonRaphson => {
            return crate::velocity::pinv_into(jac, e, locked, |s1| 1e-10 * s1, dq);
        }
        IkMethod::Dls { lambda } => lambda * lambda,
        IkMethod::LevenbergMarquardt { damping_floor } => lm_diagonal(e, damping_floor),
    };
    crate::linalg::dls::dls_step(jac, e, mu, locked, dq)
}

/// The LM diagonal term μ = 0.05 ‖e‖² + μ̄ (see the module documentation).
#[inline]
fn lm_diagonal(e: &Vector6<f64>, damping_floor: f64) -> f64 {
    LM_ERROR_WEIGHT * e.norm_squared() + damping_floor
}

/// Solves T(q) = `target` from `seed` (one value per variable). Checks the seed, the target
/// and the options; a solve that does not converge is an `Ok` result with
/// `status.converged == false`.
///
/// ```
/// use screwkit_solve::{fk::fk, ik, Kinematics, Workspace};
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/panda.urdf");
/// let kin = Kinematics::new(&screwkit_model::load_chain(path, None, None)?);
/// let mut ws = Workspace::new(&kin);
/// let target = fk(&kin, &mut ws, &[0.1, -0.4, 0.2, -2.0, 0.3, 1.8, 0.5])?;
/// let sol = ik::solve(&kin, &mut ws, &target, &kin.midpoint(), &ik::IkOptions::default())?;
/// assert!(sol.status.converged);
/// // Checked by an independent FK call, and within the joint limits.
/// assert!(fk(&kin, &mut ws, &sol.q)?.max_abs_diff(&target) < 1e-8);
/// let (lower, upper) = (kin.lower(), kin.upper());
/// assert!((0..7).all(|i| lower[i] <= sol.q[i] && sol.q[i] <= upper[i]));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn solve(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
) -> Result<IkResult, SolveError> {
    let mut q = vec![0.0; kin.dof()];
    let status = solve_into(kin, ws, target, seed, opts, &mut q)?;
    Ok(IkResult { q, status })
}

/// [`solve`] keeping clear of contact: an answer is converged when it reaches the target
/// within the tolerances and `body` finds it clear (see [`Clearance`]); when the budget ends
/// with only colliding answers, the status says [`StopReason::InCollision`] and q is one of
/// them. `scratch` is the body's (from [`Clearance::scratch`]), reused across calls.
pub fn solve_clear<B: Clearance>(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
    body: &B,
    scratch: &mut B::Scratch,
) -> Result<IkResult, SolveError> {
    kin.check_q(seed)?;
    check_target(target)?;
    check_options(opts)?;
    ws.fit(kin);
    let mut q = vec![0.0; kin.dof()];
    let status = solve_unchecked(kin, ws, target, seed, opts, (body, scratch), &mut q);
    Ok(IkResult { q, status })
}

/// [`solve`] writing the solution into `q` (one value per variable) instead of allocating it:
/// nothing is allocated once the workspace has been used for this chain.
pub fn solve_into(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
    q: &mut [f64],
) -> Result<IkStatus, SolveError> {
    kin.check_q(seed)?;
    check_target(target)?;
    check_options(opts)?;
    kin.check_len("solution values", q.len())?;
    ws.fit(kin);
    Ok(solve_unchecked(
        kin,
        ws,
        target,
        seed,
        opts,
        (&NoBody, &mut ()),
        q,
    ))
}

/// A target must be finite (its rotation is trusted to be one: [`Se3`]'s checked constructors
/// validate user input).
pub(crate) fn check_target(target: &Se3) -> Result<(), SolveError> {
    if target.is_finite() {
        Ok(())
    } else {
        Err(SolveError::BadTarget(crate::BadTarget::NonFinite))
    }
}

/// Tolerances ≥ 0, a positive step cap, finite weights and damping.
pub(crate) fn check_options(o: &IkOptions) -> Result<(), SolveError> {
    let bad = |what: &str, x: f64| {
        Err(SolveError::InvalidInput(format!(
            "IK option {what} must be finite and non-negative, got {x}"
        )))
    };
    for (what, x) in [("tol_rot", o.tol_rot), ("tol_pos", o.tol_pos)] {
        if !(x.is_finite() && x >= 0.0) {
            return bad(what, x);
        }
    }
    if o.max_step.is_nan() || o.max_step <= 0.0 {
        return bad("max_step (> 0)", o.max_step);
    }
    if let Some(w) = o.weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
        return bad("weights", *w);
    }
    match o.method {
        IkMethod::Dls { lambda: x } | IkMethod::LevenbergMarquardt { damping_floor: x }
            if !(x.is_finite() && x >= 0.0) =>
        {
            bad("damping", x)
        }
        _ => Ok(()),
    }
}

/// The solve on checked input (with a body and its scratch), writing the solution into `q_out`.
pub(crate) fn solve_unchecked<B: Clearance>(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
    body: (&B, &mut B::Scratch),
    q_out: &mut [f64],
) -> IkStatus {
    let start = opts.timeout.map(|d| (Instant::now(), d));
    let mut scratch = std::mem::take(&mut ws.ik);
    let status = iterate(kin, ws, target, seed, opts, start, &mut scratch, body);
    q_out.copy_from_slice(&scratch.best_q);
    ws.ik = scratch;
    status
}

/// Moves `q` by a whole turn (±2π) of the one screw variable ([`Kinematics::turns`]) that
/// lowers the weighted error most, if one lowers it below `err2` (`trial`: scratch of q's
/// length). Returns whether it moved.
fn turn_hop(
    kin: &Kinematics,
    target: &Se3,
    opts: &IkOptions,
    weights: &[f64; 6],
    err2: f64,
    q: &mut [f64],
    trial: &mut [f64],
) -> bool {
    let mut best: Option<(usize, f64, f64)> = None;
    for k in (0..q.len()).filter(|&k| kin.turns[k]) {
        for turn in [std::f64::consts::TAU, -std::f64::consts::TAU] {
            let x = q[k] + turn;
            if x < kin.lower[k] || x > kin.upper[k] {
                continue;
            }
            trial.copy_from_slice(q);
            trial[k] = x;
            let e2 = error_state(&fk_unchecked(kin, trial), target, opts, weights)
                .e
                .norm_squared();
            if e2 < best.map_or(err2, |b| b.2) {
                best = Some((k, x, e2));
            }
        }
    }
    match best {
        Some((k, x, _)) => {
            q[k] = x;
            true
        }
        None => false,
    }
}

/// The step of [`Clearance`]: min ‖J Δ − e‖² + μ ‖Δ‖² (μ the method's diagonal term) with
/// every joint inside its limits and within `max_step`, and each close pair's row
/// ∂d/∂q · Δ ≥ −γ (gap − buffer), by [`crate::linalg::qp`], into `clear.step`. An error when no
/// step meets them all.
#[allow(clippy::needless_range_loop)]
fn clearance_step(
    kin: &Kinematics,
    opts: &IkOptions,
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    q: &[f64],
    clear: &mut ClearScratch,
) -> Result<(), SolveError> {
    let n = q.len();
    let mu = match opts.method {
        IkMethod::NewtonRaphson => 0.0,
        IkMethod::Dls { lambda } => lambda * lambda,
        IkMethod::LevenbergMarquardt { damping_floor } => lm_diagonal(e, damping_floor),
    };
    clear.h.resize(n * n, 0.0);
    clear.c.resize(n, 0.0);
    clear.lower.resize(n, 0.0);
    clear.upper.resize(n, 0.0);
    clear.step.resize(n, 0.0);
    let mut largest = 0.0_f64;
    for i in 0..n {
        for j in 0..=i {
            let v = jac.column(i).dot(&jac.column(j));
            clear.h[i * n + j] = v;
            largest = largest.max(v.abs());
        }
        clear.c[i] = -jac.column(i).dot(e);
    }
    // Positive definite whatever the method (Newton–Raphson's μ = 0 on a redundant arm).
    let mu = mu.max(1e-12 * largest.max(1e-12));
    for i in 0..n {
        clear.h[i * n + i] += mu;
        let (lo, hi) = if kin.continuous[i] {
            (-opts.max_step, opts.max_step)
        } else {
            (
                (kin.lower[i] - q[i]).max(-opts.max_step),
                (kin.upper[i] - q[i]).min(opts.max_step),
            )
        };
        clear.lower[i] = lo.min(0.0);
        clear.upper[i] = hi.max(0.0);
    }
    let buffer = CLEARANCE_BUFFER * kin.length_scale;
    for g in &mut clear.gaps {
        *g = -CLEARANCE_GAIN * (*g - buffer);
    }
    crate::linalg::qp::solve(
        &mut clear.qp,
        &clear.h,
        &clear.c,
        &clear.lower,
        &clear.upper,
        &clear.rows,
        &clear.gaps,
        &mut clear.step,
    )
    .map(|_| ())
}

/// The best iterate's error so far.
#[derive(Debug, Clone, Copy)]
struct Best {
    /// ‖e‖² of the weighted error twist: what "best" minimises.
    err2: f64,
    error_rot: f64,
    error_pos: f64,
}

/// The restart rule: an attempt whose error norm has not halved since the start of the
/// window (‖e‖ > ½ ‖e₀‖, compared as squares: ‖e‖² > ¼ ‖e₀‖²) has stalled.
#[inline]
fn stalled(err2: f64, window_start_err2: f64) -> bool {
    const NORM_FACTOR: f64 = 0.5;
    err2 > NORM_FACTOR * NORM_FACTOR * window_start_err2
}

/// The IK loop proper, on the workspace's scratch buffers (no allocation); the answer is left
/// in `scratch.best_q`.
#[allow(clippy::too_many_arguments)]
fn iterate<B: Clearance>(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
    start: Option<(Instant, Duration)>,
    scratch: &mut IkScratch,
    (body, body_scratch): (&B, &mut B::Scratch),
) -> IkStatus {
    // Tuned on the benchmark protocol of BENCHMARKS.md: an attempt that does not halve its
    // error norm within 5 iterations, or reaches 60, restarts.
    const WINDOW: usize = 5;
    const ATTEMPT_CAP: usize = 60;
    let n = kin.dof();
    let mut rng = SplitMix64(opts.seed ^ 0x5C7E_3B1D_0000_0001);
    let IkScratch {
        q,
        dq,
        best_q,
        locked,
        clear,
    } = scratch;
    q.resize(n, 0.0);
    dq.resize(n, 0.0);
    best_q.resize(n, 0.0);
    locked.resize(n, false);
    q.copy_from_slice(seed);
    project(kin, q);
    best_q.copy_from_slice(q);
    let mut best = Best {
        err2: f64::INFINITY,
        error_rot: f64::INFINITY,
        error_pos: f64::INFINITY,
    };
    let (mut iterations, mut restarts, mut attempt_iter) = (0usize, 0usize, 0usize);
    let mut window_start_err2 = f64::INFINITY;
    // Clearance: an answer reached in contact was seen; steps steer away from contact.
    // (Once per attempt: a fresh window to move away in; the stall rule then applies.)
    let (mut reached_in_contact, mut steering, mut steered_this_attempt) = (false, false, false);
    let mut contacts = 0usize;
    // Scale-free: the linear rows and errors in units of the chain's length scale L, so the
    // damping and the step see the same numbers for a 1 cm and a 10 m arm (the tolerances stay
    // in metres and radians).
    let mut row_weights = opts.weights;
    for w in &mut row_weights[3..] {
        *w /= kin.length_scale;
    }
    if opts.position_only {
        row_weights[..3].fill(0.0);
    }
    // Steering moves along the target's self-motion: a chain with more joints than the
    // target's constrained components. Without one, rejection and a restart (a few µs of
    // collision check) beats steering (a distance and its row per close pair each step, ~1 ms
    // on exact meshes) at the same success: measured, BENCHMARKS.md.
    let redundant = row_weights.iter().filter(|w| **w != 0.0).count() < n;
    let stop = loop {
        let t = fk_jacobian_into(kin, &mut ws.jacobian, q, Frame::Body);
        let es = error_state(&t, target, opts, &row_weights);
        let err2 = es.e.norm_squared();
        let reached = es.check_rot <= opts.tol_rot && es.check_lin <= opts.tol_pos;
        let converged = reached && body.is_clear(body_scratch, q);
        if reached && !converged {
            // The target reached in contact: not an answer. Steer away from here (a fresh
            // window), or, rejecting only, restart.
            reached_in_contact = true;
            contacts += 1;
            if !(body.steers() && redundant && contacts >= CLEARANCE_STEER_AFTER) {
                attempt_iter = ATTEMPT_CAP;
            } else if !steered_this_attempt {
                steering = true;
                steered_this_attempt = true;
                attempt_iter = 1;
                window_start_err2 = f64::INFINITY;
            }
        }
        if err2 < best.err2 || converged {
            best = Best {
                err2,
                error_rot: es.rot,
                error_pos: es.pos,
            };
            best_q.copy_from_slice(q);
        }
        if converged {
            break StopReason::Converged;
        }
        if iterations >= opts.max_iterations {
            break StopReason::IterationLimit;
        }
        if let Some((t0, budget)) = start {
            if iterations.is_multiple_of(4) && t0.elapsed() >= budget {
                break StopReason::TimeLimit;
            }
        }
        if let Some(Interrupt(stop)) = opts.interrupt {
            if iterations.is_multiple_of(64) && stop() {
                break StopReason::Interrupted;
            }
        }
        // Stall detection and restarts.
        if attempt_iter.is_multiple_of(WINDOW) {
            // Close to the target (within 1000 tolerances) and still getting closer (by 10 %
            // a window), an attempt goes on rather than restarting far away: slow, linear
            // convergence there (a joint at its limit, a helical joint's coupled rotation and
            // advance) otherwise ended budgets a few 1e-9 short.
            let closing = es.check_rot <= 1e3 * opts.tol_rot
                && es.check_lin <= 1e3 * opts.tol_pos
                && err2 < 0.81 * window_start_err2;
            if (attempt_iter > 0 && stalled(err2, window_start_err2) && !closing)
                || attempt_iter >= ATTEMPT_CAP
            {
                if restarts >= opts.max_restarts {
                    break StopReason::RestartLimit;
                }
                restarts += 1;
                // A screw joint (helical, or revolute with a prismatic follower) stalls where
                // the rotation is right a whole turn away: the rotation error's minimum, with
                // the position off by 2π h. Try the next turn before a random restart.
                if !turn_hop(kin, target, opts, &row_weights, err2, q, dq) {
                    configuration_into(kin, &mut rng, q);
                }
                attempt_iter = 0;
                window_start_err2 = f64::INFINITY;
                steered_this_attempt = false;
                continue;
            }
            window_start_err2 = err2;
        }
        weight_rows(&mut ws.jacobian, &row_weights);
        if steering {
            clear.gaps.clear();
            clear.rows.clear();
            body.close_rows(
                body_scratch,
                q,
                CLEARANCE_DETECTION * kin.length_scale,
                &mut clear.gaps,
                &mut clear.rows,
            );
            if !clear.gaps.is_empty() {
                if clearance_step(kin, opts, &ws.jacobian, &es.e, q, clear).is_err() {
                    // No step meets the rows within the limits: a stall of this attempt.
                    attempt_iter = ATTEMPT_CAP;
                    continue;
                }
                for (x, d) in q.iter_mut().zip(&clear.step) {
                    *x += d;
                }
                project(kin, q);
                iterations += 1;
                attempt_iter += 1;
                continue;
            }
        }
        locked.iter_mut().for_each(|l| *l = false);
        // A numerical failure of the step (not possible with a positive damping) counts as a
        // stall of this attempt.
        let mut ok = step(opts.method, &ws.jacobian, &es.e, locked, dq).is_ok();
        // Active set: a joint at a bound that the step pushes outward is left out and the
        // step is solved again with the others, so the clamp does not distort the direction.
        let mut any = false;
        for k in 0..n {
            if (q[k] <= kin.lower[k] && dq[k] < 0.0) || (q[k] >= kin.upper[k] && dq[k] > 0.0) {
                locked[k] = true;
                any = true;
            }
        }
        if ok && any && locked.iter().any(|l| !l) {
            ok = step(opts.method, &ws.jacobian, &es.e, locked, dq).is_ok();
        }
        let largest = dq.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        if !ok || !largest.is_finite() {
            // A numerical blow-up: treat as a stall.
            attempt_iter = ATTEMPT_CAP;
            continue;
        }
        let scale = if largest > opts.max_step {
            opts.max_step / largest
        } else {
            1.0
        };
        for (x, d) in q.iter_mut().zip(dq.iter()) {
            *x += d * scale;
        }
        project(kin, q);
        iterations += 1;
        attempt_iter += 1;
    };
    let stop = match stop {
        StopReason::IterationLimit | StopReason::RestartLimit | StopReason::TimeLimit
            if reached_in_contact =>
        {
            StopReason::InCollision
        }
        s => s,
    };
    IkStatus {
        converged: stop == StopReason::Converged,
        iterations,
        restarts,
        error_rot: best.error_rot,
        error_pos: best.error_pos,
        stop,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stall rule halves the error norm: ‖e‖ = 0.6 ‖e₀‖ has stalled, 0.4 ‖e₀‖ has not.
    #[test]
    fn stall_means_the_norm_did_not_halve() {
        let e0 = 2.0f64;
        assert!(stalled((0.6 * e0).powi(2), e0 * e0));
        assert!(!stalled((0.4 * e0).powi(2), e0 * e0));
    }
}
