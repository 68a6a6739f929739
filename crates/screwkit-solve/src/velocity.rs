//! Joint velocities from a tip twist and joint torques from a tip wrench:
//! V = J(q) q̇ and τ = J(q)ᵀ F (*Modern Robotics* eqs. 5.1 and 5.26), with the twist or wrench
//! expressed in the Jacobian's frame — (J_s, V_s, F_s) or (J_b, V_b, F_b).

use nalgebra::{DVector, Matrix6, Matrix6xX, Vector6};
use screwkit_lie::{Frame, Twist, Wrench};

use crate::error::SolveError;
use crate::kinematics::Kinematics;
use crate::workspace::Workspace;

/// How [`joint_velocities`] inverts V = J q̇.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VelocitySolver {
    /// q̇ = J⁻¹ V for a square (6-DoF), non-singular J (LU); an error otherwise (rank decided by
    /// the SVD with the analysis's tolerance, 6 ε σ₁).
    Exact,
    /// q̇ = J⁺ V with the SVD pseudo-inverse J⁺ = V Σ⁺ Uᵀ ([`crate::linalg::svd`]): least squares and minimum
    /// norm. σ_i ≤ `tolerance` count as 0 (`None`: max(6, n) · ε · σ₁).
    PseudoInverse {
        /// Singular values at or below this are dropped.
        tolerance: Option<f64>,
    },
    /// Damped least squares q̇ = Jᵀ (J Jᵀ + λ² I)⁻¹ V with damping λ > 0: bounded near
    /// singularities, exact as λ → 0 for full row rank.
    Damped {
        /// The damping λ (same units as the twist).
        lambda: f64,
    },
}

/// The joint velocities q̇ giving the tip twist `twist` (in `frame`) at q. Checks q and the
/// twist.
pub fn joint_velocities(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    twist: &Twist,
    frame: Frame,
    solver: VelocitySolver,
) -> Result<DVector<f64>, SolveError> {
    if !twist.is_finite() {
        return Err(SolveError::InvalidInput("the twist is not finite".into()));
    }
    let j = crate::jacobian::jacobian(kin, ws, q, frame)?;
    let v = twist.to_vector();
    match solver {
        VelocitySolver::Exact => exact(j, &v),
        VelocitySolver::PseudoInverse { tolerance } => {
            let n = j.ncols();
            let mut out = DVector::zeros(n);
            let default = |s1: f64| 6.max(n) as f64 * f64::EPSILON * s1;
            pinv_into(
                j,
                &v,
                &vec![false; n],
                |s1| tolerance.unwrap_or(default(s1)),
                out.as_mut_slice(),
            )?;
            Ok(out)
        }
        VelocitySolver::Damped { lambda } => {
            if !(lambda.is_finite() && lambda > 0.0) {
                return Err(SolveError::InvalidInput(format!(
                    "the damping λ must be positive and finite, got {lambda}"
                )));
            }
            let mut out = DVector::zeros(j.ncols());
            let free = vec![false; j.ncols()];
            crate::linalg::dls::dls_step(j, &v, lambda * lambda, &free, out.as_mut_slice())?;
            Ok(out)
        }
    }
}

/// q̇ = J⁻¹ V for a square, full-rank J (LU).
fn exact(j: &Matrix6xX<f64>, v: &Vector6<f64>) -> Result<DVector<f64>, SolveError> {
    if j.ncols() != 6 {
        return Err(SolveError::InvalidInput(format!(
            "an exact solve needs a square 6 × 6 Jacobian, this one is 6 × {}",
            j.ncols()
        )));
    }
    let sq: Matrix6<f64> = j.fixed_columns::<6>(0).into_owned();
    // Rounding makes a singular J look invertible to LU (pivots of 1e-17, answers of 1e16), so
    // the rank is decided first, with the tolerance of the analysis (6 ε σ₁), by the crate's
    // one SVD.
    let s = crate::linalg::svd::jacobian_svd(j, None)?.s;
    let (s_max, s_min) = (s[0], s[s.len() - 1]);
    let singular = || {
        SolveError::Numerical(format!(
            "the Jacobian is singular (σ_min = {s_min:.3e}, σ_max = {s_max:.3e}): no exact joint velocities; use the pseudo-inverse or damped least squares"
        ))
    };
    if s_min <= 6.0 * f64::EPSILON * s_max {
        return Err(singular());
    }
    let x = sq.lu().solve(v).ok_or_else(singular)?;
    Ok(DVector::from_column_slice(x.as_slice()))
}

/// x = J⁺ b = Σ_i (u_iᵀ b / σ_i) v_i over the σ_i > `tolerance(σ₁)` of the SVD ([`crate::linalg::svd`]), with the
/// columns whose `locked` flag is set treated as zero (their x is 0). The one pseudo-inverse of
/// the crate: [`VelocitySolver::PseudoInverse`] and the Newton–Raphson IK step.
pub(crate) fn pinv_into(
    j: &Matrix6xX<f64>,
    b: &Vector6<f64>,
    locked: &[bool],
    tolerance: impl Fn(f64) -> f64,
    x: &mut [f64],
) -> Result<(), SolveError> {
    let n = j.ncols();
    let svd = crate::linalg::svd::jacobian_svd(j, Some(locked))?;
    let (u, s, v) = (&svd.u, &svd.s, &svd.v);
    let k = n.min(6);
    let tol = if k > 0 { tolerance(s[0]) } else { 0.0 };
    x.iter_mut().for_each(|x| *x = 0.0);
    for i in 0..k {
        if s[i] <= tol {
            continue;
        }
        let c = (0..6).map(|r| u[(r, i)] * b[r]).sum::<f64>() / s[i];
        for (r, x) in x.iter_mut().enumerate() {
            *x += v[(r, i)] * c;
        }
    }
    Ok(())
}

/// The joint torques τ = Jᵀ F that balance the tip wrench `wrench` (in `frame`) at q. Checks q
/// and the wrench.
pub fn joint_torques(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    wrench: &Wrench,
    frame: Frame,
) -> Result<DVector<f64>, SolveError> {
    if !wrench.to_vector().iter().all(|x| x.is_finite()) {
        return Err(SolveError::InvalidInput("the wrench is not finite".into()));
    }
    let j = crate::jacobian::jacobian(kin, ws, q, frame)?;
    Ok(j.transpose() * wrench.to_vector())
}
