//! The damped least-squares step of a 6-row Jacobian, Δq = Jᵀ (J Jᵀ + λ² I)⁻¹ e, on fixed-size
//! 6×6 arrays: A = Σ_k c_k c_kᵀ + λ² I over the free columns c_k (lower triangle only, 21
//! entries), A = L Lᵀ (Cholesky), L z = e, Lᵀ y = z, Δq_k = c_k · y (0 for locked columns).
//!
//! It equals the SVD form Δq = Σ_i σ_i / (σ_i² + λ²) v_i (u_iᵀ e) that faer computes (tested in
//! `tests/ik.rs`), at a fraction of the cost: everything is unrolled and stays in registers.

use nalgebra::{Matrix6xX, Vector6};

use screwkit_lie::fma::{MulAdd, Plain};

use crate::error::SolveError;

/// Writes Δq = J_freeᵀ (J_free J_freeᵀ + λ² I)⁻¹ e into `dq` (`lambda2` = λ² ≥ 0; columns with
/// `locked[k]` set are left out and get Δq_k = 0). Fails when the 6×6 system is not positive
/// definite (λ = 0 and J_free without full row rank) or not finite. Panics if `locked` or `dq`
/// is shorter than the number of columns.
pub fn dls_step(
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    lambda2: f64,
    locked: &[bool],
    dq: &mut [f64],
) -> Result<(), SolveError> {
    assert!(locked.len() >= jac.ncols() && dq.len() >= jac.ncols());
    #[cfg(target_arch = "x86_64")]
    if screwkit_lie::fma::fused_available() {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        return unsafe { dls_step_fused(jac, e, lambda2, locked, dq) };
    }
    dls_step_with::<Plain>(jac, e, lambda2, locked, dq)
}

/// [`dls_step_with`] compiled for AVX2 + FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn dls_step_fused(
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    lambda2: f64,
    locked: &[bool],
    dq: &mut [f64],
) -> Result<(), SolveError> {
    dls_step_with::<screwkit_lie::fma::Fused>(jac, e, lambda2, locked, dq)
}

/// The step with the multiply-add policy `A` (see [`screwkit_lie::fma`]).
#[inline(always)]
fn dls_step_with<A: MulAdd>(
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    lambda2: f64,
    locked: &[bool],
    dq: &mut [f64],
) -> Result<(), SolveError> {
    // A = Σ c cᵀ + λ² I (both triangles: whole columns vectorise; 36 multiply-adds per column).
    let mut a = [[0.0f64; 6]; 6];
    for (k, col) in jac.column_iter().enumerate() {
        if locked[k] {
            continue;
        }
        let c: [f64; 6] = std::array::from_fn(|i| col[i]);
        for (j, a_j) in a.iter_mut().enumerate() {
            for i in 0..6 {
                a_j[i] = A::madd(c[i], c[j], a_j[i]);
            }
        }
    }
    for (i, row) in a.iter_mut().enumerate() {
        row[i] += lambda2;
    }
    // Cholesky A = L Lᵀ in place (L_ij at a[i][j], i ≥ j), one const-generic step per column
    // so every loop has a fixed trip count and unrolls; keep 1 / L_jj for the solves.
    let mut inv = [0.0f64; 6];
    let ok = cholesky_column::<0>(&mut a, &mut inv)
        && cholesky_column::<1>(&mut a, &mut inv)
        && cholesky_column::<2>(&mut a, &mut inv)
        && cholesky_column::<3>(&mut a, &mut inv)
        && cholesky_column::<4>(&mut a, &mut inv)
        && cholesky_column::<5>(&mut a, &mut inv);
    if !ok {
        return Err(SolveError::Numerical(
            "J Jᵀ + λ²I is not positive definite".into(),
        ));
    }
    // L z = e, then Lᵀ y = z.
    let mut y: [f64; 6] = (*e).into();
    forward::<0>(&a, &inv, &mut y);
    forward::<1>(&a, &inv, &mut y);
    forward::<2>(&a, &inv, &mut y);
    forward::<3>(&a, &inv, &mut y);
    forward::<4>(&a, &inv, &mut y);
    forward::<5>(&a, &inv, &mut y);
    backward::<5>(&a, &inv, &mut y);
    backward::<4>(&a, &inv, &mut y);
    backward::<3>(&a, &inv, &mut y);
    backward::<2>(&a, &inv, &mut y);
    backward::<1>(&a, &inv, &mut y);
    backward::<0>(&a, &inv, &mut y);
    for (k, c) in jac.column_iter().enumerate() {
        dq[k] = if locked[k] {
            0.0
        } else {
            c[0] * y[0] + c[1] * y[1] + c[2] * y[2] + c[3] * y[3] + c[4] * y[4] + c[5] * y[5]
        };
    }
    Ok(())
}

/// Column J of the Cholesky factor: L_JJ = √(A_JJ − Σ_{k<J} L_Jk²),
/// L_iJ = (A_iJ − Σ_{k<J} L_ik L_Jk) / L_JJ for i > J. False unless the pivot is positive
/// and finite.
#[inline(always)]
fn cholesky_column<const J: usize>(a: &mut [[f64; 6]; 6], inv: &mut [f64; 6]) -> bool {
    let mut d = a[J][J];
    for x in &a[J][..J] {
        d -= x * x;
    }
    if !(d > 0.0 && d.is_finite()) {
        return false;
    }
    let l = d.sqrt();
    a[J][J] = l;
    inv[J] = 1.0 / l;
    for i in J + 1..6 {
        let mut s = a[i][J];
        for (x, y) in a[i][..J].iter().zip(&a[J][..J]) {
            s -= x * y;
        }
        a[i][J] = s * inv[J];
    }
    true
}

/// Row I of L z = e (in place in `y`): z_I = (e_I − Σ_{k<I} L_Ik z_k) / L_II.
#[inline(always)]
fn forward<const I: usize>(a: &[[f64; 6]; 6], inv: &[f64; 6], y: &mut [f64; 6]) {
    let mut s = y[I];
    for k in 0..I {
        s -= a[I][k] * y[k];
    }
    y[I] = s * inv[I];
}

/// Row I of Lᵀ y = z (in place): y_I = (z_I − Σ_{k>I} L_kI y_k) / L_II.
#[inline(always)]
fn backward<const I: usize>(a: &[[f64; 6]; 6], inv: &[f64; 6], y: &mut [f64; 6]) {
    let mut s = y[I];
    for k in I + 1..6 {
        s -= a[k][I] * y[k];
    }
    y[I] = s * inv[I];
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The portable and fused instantiations agree (the public function runs one of them;
    /// `tests/ik.rs` checks that one against faer's SVD).
    #[test]
    fn portable_and_fused_agree() {
        let mut s = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in [3, 6, 7, 9] {
            for _ in 0..50 {
                let j = Matrix6xX::from_fn(n, |_, _| next());
                let e = Vector6::from_fn(|_, _| next());
                let locked: Vec<bool> = (0..n).map(|k| k == 1).collect();
                let (mut a, mut b) = (vec![0.0; n], vec![0.0; n]);
                dls_step_with::<Plain>(&j, &e, 1e-3, &locked, &mut a).unwrap();
                dls_step_with::<screwkit_lie::fma::Fused>(&j, &e, 1e-3, &locked, &mut b).unwrap();
                let scale = a.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                for k in 0..n {
                    assert!((a[k] - b[k]).abs() < 1e-9 * scale, "{a:?} {b:?}");
                }
            }
        }
    }
}
