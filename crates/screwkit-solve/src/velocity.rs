//! Joint velocities from a twist and joint torques from a wrench.
//!
//! The twist/wrench must be expressed in the Jacobian's frame: (J_s, V_s, F_s) or
//! (J_b, V_b, F_b).

use faer::Mat;
use nalgebra::{DVector, Matrix6, Matrix6xX, Vector6};
use screwkit_lie::{Twist, Wrench};

use crate::error::SolveError;

/// q̇ = J⁻¹ V for a square, full-rank J (LU); an error when J is not 6 × 6 or is singular.
pub fn joint_velocities_exact(j: &Matrix6xX<f64>, v: &Twist) -> Result<DVector<f64>, SolveError> {
    if j.ncols() != 6 {
        return Err(SolveError::Numerical(format!(
            "an exact solve needs a square 6 × 6 Jacobian, this one is 6 × {}",
            j.ncols()
        )));
    }
    let sq: Matrix6<f64> = j.fixed_columns::<6>(0).into_owned();
    let x = sq
        .lu()
        .solve(&v.to_vector())
        .ok_or_else(|| SolveError::Numerical("the Jacobian is singular".into()))?;
    Ok(DVector::from_column_slice(x.as_slice()))
}

/// q̇ = J⁺ V with the SVD pseudo-inverse J⁺ = V Σ⁺ Uᵀ (faer), σ_i ≤ `tolerance` treated as 0
/// (default: max(6, n) · ε · σ₁). Least-squares and minimum-norm.
pub fn joint_velocities_pinv(
    j: &Matrix6xX<f64>,
    v: &Twist,
    tolerance: Option<f64>,
) -> Result<DVector<f64>, SolveError> {
    let n = j.ncols();
    let mut out = DVector::zeros(n);
    let default = |s1: f64| 6.max(n) as f64 * f64::EPSILON * s1;
    pinv_into(
        j,
        &v.to_vector(),
        &vec![false; n],
        |s1| tolerance.unwrap_or(default(s1)),
        out.as_mut_slice(),
    )?;
    Ok(out)
}

/// x = J⁺ b = Σ_i (u_iᵀ b / σ_i) v_i over the σ_i > `tolerance(σ₁)` of the faer SVD, with the
/// columns whose `locked` flag is set treated as zero (their x is 0). The one pseudo-inverse of
/// the crate: [`joint_velocities_pinv`] and the Newton–Raphson IK step.
pub(crate) fn pinv_into(
    j: &Matrix6xX<f64>,
    b: &Vector6<f64>,
    locked: &[bool],
    tolerance: impl Fn(f64) -> f64,
    x: &mut [f64],
) -> Result<(), SolveError> {
    let n = j.ncols();
    let m = Mat::<f64>::from_fn(6, n, |r, c| if locked[c] { 0.0 } else { j[(r, c)] });
    let svd = m
        .thin_svd()
        .map_err(|e| SolveError::Numerical(format!("SVD did not converge: {e:?}")))?;
    let (u, s, v) = (svd.U(), svd.S().column_vector(), svd.V());
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

/// Damped least squares q̇ = Jᵀ (J Jᵀ + λ² I)⁻¹ V ([`crate::dls::dls_step`]): bounded near singularities,
/// exact as λ → 0 for full row rank.
pub fn joint_velocities_dls(
    j: &Matrix6xX<f64>,
    v: &Twist,
    lambda: f64,
) -> Result<DVector<f64>, SolveError> {
    if !(lambda.is_finite() && lambda > 0.0) {
        return Err(SolveError::Numerical(format!(
            "damping λ must be positive, got {lambda}"
        )));
    }
    let mut q_dot = DVector::zeros(j.ncols());
    let free = vec![false; j.ncols()];
    crate::dls::dls_step(
        j,
        &v.to_vector(),
        lambda * lambda,
        &free,
        q_dot.as_mut_slice(),
    )?;
    Ok(q_dot)
}

/// Joint torques balancing a tip wrench: τ = Jᵀ F (F in the Jacobian's frame).
pub fn joint_torques(j: &Matrix6xX<f64>, f: &Wrench) -> DVector<f64> {
    j.transpose() * f.to_vector()
}
