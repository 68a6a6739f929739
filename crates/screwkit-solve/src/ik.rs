//! Inverse kinematics: find q with T(q) = T_sd.
//!
//! Every method iterates on the body twist error V_b = log(T_sb(q)⁻¹ T_sd) (the seeds'
//! algorithm) with the body Jacobian J_b(q), and stops when ‖ω_b‖ ≤ ε_ω and ‖v_b‖ ≤ ε_v
//! (over the components whose weight is not 0; position-only uses (0, R_sbᵀ(p_d − p))):
//!
//! - [`IkMethod::NewtonRaphson`]: Δq = J_b⁺ V_b, SVD pseudo-inverse (faer).
//! - [`IkMethod::Dls`]: Δq = J_bᵀ (J_b J_bᵀ + λ² I)⁻¹ V_b with a fixed λ (6 × 6 Cholesky).
//! - [`IkMethod::LevenbergMarquardt`] (default): the same with adaptive damping
//!   λ = w ‖V_b‖² + λ̄ (after Sugihara 2011, with w = 0.05), so steps are Gauss–Newton near the
//!   solution and damped far from it or near singularities.
//!
//! Joint limits: a joint at a bound that the step would push outward is taken out of the step
//! (active set) and the step is solved again without it; then q is projected into the limits
//! (continuous joints wrapped to (−π, π]), so solutions are always within limits. When an
//! attempt stalls (less than quartering the error in 5 iterations) or hits 60 iterations, it
//! restarts from a random
//! configuration drawn from a seeded generator — reproducible — until the iteration budget,
//! the restart budget or the wall-time budget (default 5 ms, like TRAC-IK) runs out.
//! Not converging is an explicit result ([`IkResult::converged`] = false, with the best q
//! found and why it stopped), never silent garbage.

use std::time::{Duration, Instant};

use nalgebra::{Matrix6xX, Vector6};
use screwkit_lie::Se3;

use crate::error::SolveError;
use crate::jacobian::{fk_jacobian_into, Frame};
use crate::kinematics::{Kinematics, Workspace};

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
    /// Levenberg–Marquardt with adaptive damping λ = 0.05 ‖e‖² + λ̄.
    LevenbergMarquardt {
        /// The floor λ̄ of the damping.
        lambda_min: f64,
    },
}

impl IkMethod {
    /// Damped least squares with λ = 0.02.
    pub const DLS: IkMethod = IkMethod::Dls { lambda: 0.02 };
    /// Levenberg–Marquardt with λ̄ = 1e-8.
    pub const LM: IkMethod = IkMethod::LevenbergMarquardt { lambda_min: 1e-8 };
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
}

impl StopReason {
    /// A short lowercase label (`"converged"`, `"iteration limit"`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            StopReason::Converged => "converged",
            StopReason::IterationLimit => "iteration limit",
            StopReason::RestartLimit => "restart limit",
            StopReason::TimeLimit => "time limit",
        }
    }
}

/// IK settings. `Default` gives LM, 1e-9 rad / 1e-9 m, 5 ms, seed 0.
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
}

impl Default for IkOptions {
    fn default() -> Self {
        Self {
            method: IkMethod::LM,
            tol_rot: 1e-9,
            tol_pos: 1e-9,
            max_iterations: 2000,
            max_restarts: 200,
            timeout: Some(Duration::from_millis(5)),
            seed: 0,
            position_only: false,
            weights: [1.0; 6],
            max_step: 1.0,
        }
    }
}

/// The outcome of a solve.
#[derive(Debug, Clone, PartialEq)]
pub struct IkResult {
    /// The solution (or, if not converged, the best configuration found); always within limits.
    pub q: Vec<f64>,
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

/// SplitMix64: a small, well-distributed, seedable generator (reproducible restarts).
#[derive(Debug, Clone)]
pub(crate) struct SplitMix(pub(crate) u64);

impl SplitMix {
    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    pub(crate) fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Uniform within the limits ([−π, π] for unbounded variables).
pub(crate) fn random_config(kin: &Kinematics, rng: &mut SplitMix, q: &mut [f64]) {
    for (k, x) in q.iter_mut().enumerate() {
        let (l, u) = (kin.lower[k], kin.upper[k]);
        let (l, u) = if l.is_finite() && u.is_finite() {
            (l, u)
        } else {
            (-std::f64::consts::PI, std::f64::consts::PI)
        };
        *x = l + (u - l) * rng.uniform();
    }
}

/// Projects q into the limits; continuous variables are wrapped to (−π, π].
pub(crate) fn project(kin: &Kinematics, q: &mut [f64]) {
    use std::f64::consts::PI;
    for (k, x) in q.iter_mut().enumerate() {
        if kin.continuous[k] {
            let mut y = (*x + PI).rem_euclid(2.0 * PI) - PI;
            if y <= -PI {
                y += 2.0 * PI;
            }
            *x = y;
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

fn error_state(t: &Se3, target: &Se3, opts: &IkOptions) -> ErrorState {
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
        let w = if opts.position_only && i < 3 {
            0.0
        } else {
            opts.weights[i]
        };
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

/// LM damping λ = w ‖e‖² + λ̄: w = 0.05 (Sugihara's λ = E = ½‖e‖² damps too much far from the
/// target on these arms: 26 → 17 iterations per solve on the UR5 protocol).
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
    let lambda2 = match method {
        IkMethod::NewtonRaphson => {
            return pinv_step(jac, e, locked, dq);
        }
        IkMethod::Dls { lambda } => lambda * lambda,
        IkMethod::LevenbergMarquardt { lambda_min } => {
            LM_ERROR_WEIGHT * e.norm_squared() + lambda_min
        }
    };
    crate::dls::dls_step(jac, e, lambda2, locked, dq)
}

/// Δq = J⁺ e with the faer SVD; σ ≤ 1e-10 σ₁ dropped; locked columns left out.
fn pinv_step(
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    locked: &[bool],
    dq: &mut [f64],
) -> Result<(), SolveError> {
    crate::velocity::pinv_into(jac, e, locked, |s1| 1e-10 * s1, dq)
}

/// Solves T(q) = `target` from `seed`, checking the input (q length, finite values, target).
pub fn solve(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
) -> Result<IkResult, SolveError> {
    kin.check_q(seed)?;
    if !target.is_finite() {
        return Err(SolveError::BadTarget);
    }
    solve_unchecked(kin, ws, target, seed, opts)
}

pub(crate) fn solve_unchecked(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
) -> Result<IkResult, SolveError> {
    let start = opts.timeout.map(|d| (Instant::now(), d));
    let mut scratch = std::mem::take(&mut ws.ik);
    let result = iterate(kin, ws, target, seed, opts, start, &mut scratch);
    ws.ik = scratch;
    result
}

/// The IK loop proper, on the workspace's scratch buffers (no allocation but the result's q).
fn iterate(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
    opts: &IkOptions,
    start: Option<(Instant, Duration)>,
    scratch: &mut crate::kinematics::IkScratch,
) -> Result<IkResult, SolveError> {
    // Tuned on the IK protocol (see BENCHMARKS.md): an attempt that does not quarter its error
    // in 5 iterations, or reaches 60, restarts.
    const WINDOW: usize = 5;
    const ATTEMPT_CAP: usize = 60;
    const STALL_FACTOR: f64 = 0.25;
    let n = kin.dof();
    let mut rng = SplitMix(opts.seed ^ 0x5C7E_3B1D_0000_0001);
    let crate::kinematics::IkScratch {
        q,
        dq,
        best_q,
        locked,
    } = scratch;
    q.resize(n, 0.0);
    dq.resize(n, 0.0);
    best_q.resize(n, 0.0);
    locked.resize(n, false);
    q.copy_from_slice(seed);
    project(kin, q);
    best_q.copy_from_slice(q);
    let mut best = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let (mut iterations, mut restarts, mut attempt_iter) = (0usize, 0usize, 0usize);
    let mut window_start_err = f64::INFINITY;
    let mut row_weights = opts.weights;
    if opts.position_only {
        row_weights[..3].fill(0.0);
    }
    let stop = loop {
        let t = fk_jacobian_into(kin, &mut ws.jacobian, q, Frame::Body);
        let es = error_state(&t, target, opts);
        let err2 = es.e.norm_squared();
        if err2 < best.0 {
            best = (err2, es.rot, es.pos);
            best_q.copy_from_slice(q);
        }
        if es.check_rot <= opts.tol_rot && es.check_lin <= opts.tol_pos {
            best = (err2, es.rot, es.pos);
            best_q.copy_from_slice(q);
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
        // Stall detection and restarts.
        if attempt_iter.is_multiple_of(WINDOW) {
            let stalled = attempt_iter > 0 && err2 > STALL_FACTOR * window_start_err;
            if stalled || attempt_iter >= ATTEMPT_CAP {
                if restarts >= opts.max_restarts {
                    break StopReason::RestartLimit;
                }
                restarts += 1;
                random_config(kin, &mut rng, q);
                attempt_iter = 0;
                window_start_err = f64::INFINITY;
                continue;
            }
            window_start_err = err2;
        }
        weight_rows(&mut ws.jacobian, &row_weights);
        locked.iter_mut().for_each(|l| *l = false);
        step(opts.method, &ws.jacobian, &es.e, locked, dq)?;
        // Active set: a joint at a bound that the step pushes outward is left out and the
        // step is solved again with the others, so the clamp does not distort the direction.
        let mut any = false;
        for k in 0..n {
            if (q[k] <= kin.lower[k] && dq[k] < 0.0) || (q[k] >= kin.upper[k] && dq[k] > 0.0) {
                locked[k] = true;
                any = true;
            }
        }
        if any && locked.iter().any(|l| !l) {
            step(opts.method, &ws.jacobian, &es.e, locked, dq)?;
        }
        let largest = dq.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let scale = if largest > opts.max_step {
            opts.max_step / largest
        } else {
            1.0
        };
        if !largest.is_finite() {
            // A numerical blow-up: treat as a stall.
            attempt_iter = ATTEMPT_CAP;
            continue;
        }
        for (x, d) in q.iter_mut().zip(dq.iter()) {
            *x += d * scale;
        }
        project(kin, q);
        iterations += 1;
        attempt_iter += 1;
    };
    Ok(IkResult {
        q: best_q.clone(),
        converged: stop == StopReason::Converged,
        iterations,
        restarts,
        error_rot: best.1,
        error_pos: best.2,
        stop,
    })
}
