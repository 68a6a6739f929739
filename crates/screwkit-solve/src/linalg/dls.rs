//! The damped least-squares step of a 6-row Jacobian, Δq = Jᵀ (J Jᵀ + μ I)⁻¹ e (μ = λ² for a
//! damping λ), on fixed-size 6×6 arrays: A = Σ_k c_k c_kᵀ + μ I over the free columns c_k,
//! A = L Lᵀ (Cholesky), L z = e, Lᵀ y = z, Δq_k = c_k · y (0 for locked columns).
//!
//! It equals the SVD form Δq = Σ_i σ_i / (σ_i² + μ) v_i (u_iᵀ e) that an SVD gives ([`crate::linalg::svd`], tested
//! below on every bundled chain), at a fraction of the cost: everything is unrolled and stays
//! in registers. Used by the LM and DLS IK steps and by damped joint velocities.

use nalgebra::{Matrix6xX, Vector6};

use screwkit_lie::fma::{dispatch, Kernel, MulAdd};

use crate::error::SolveError;

/// Writes Δq = J_freeᵀ (J_free J_freeᵀ + μ I)⁻¹ e into `dq` (`mu` = μ ≥ 0 is the term added
/// to the diagonal: λ² for damped least squares with damping λ); columns with `locked[k]` set
/// are left out and get Δq_k = 0. Fails when the 6×6 system is not positive definite (μ = 0 and
/// J_free without full row rank) or not finite. Panics if `locked` or `dq` is shorter than the
/// number of columns.
pub(crate) fn dls_step(
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    mu: f64,
    locked: &[bool],
    dq: &mut [f64],
) -> Result<(), SolveError> {
    assert!(locked.len() >= jac.ncols() && dq.len() >= jac.ncols());
    dispatch(DlsStep {
        jac,
        e,
        mu,
        locked,
        dq,
    })
}

/// The step's kernel (see [`screwkit_lie::fma::Kernel`]).
struct DlsStep<'a> {
    jac: &'a Matrix6xX<f64>,
    e: &'a Vector6<f64>,
    mu: f64,
    locked: &'a [bool],
    dq: &'a mut [f64],
}

impl Kernel for DlsStep<'_> {
    type Output = Result<(), SolveError>;
    #[inline(always)]
    fn run<A: MulAdd>(self) -> Self::Output {
        dls_step_with::<A>(self.jac, self.e, self.mu, self.locked, self.dq)
    }
}

/// The step with the multiply-add policy `A` (see [`screwkit_lie::fma`]).
#[inline(always)]
fn dls_step_with<A: MulAdd>(
    jac: &Matrix6xX<f64>,
    e: &Vector6<f64>,
    mu: f64,
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
        row[i] += mu;
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
    use crate::test_chains;
    use screwkit_lie::fma::{Fused, Plain};
    use screwkit_lie::Frame;

    /// The fixed-size step equals the SVD form computed from the crate's SVD (a different
    /// route: Jacobi rotations, no normal equations),
    /// Δq = Σ_i σ_i / (σ_i² + μ) v_i (u_iᵀ e) over the free columns, on every bundled chain at
    /// random and singular configurations, for small to large μ and with locked columns; the
    /// portable and the fused instantiation both.
    #[test]
    fn step_equals_the_svd_form() {
        let mut rng = crate::sample::SplitMix64(0x0D15_C0DE_5EED_0001);
        let mut checked = 0;
        for (file, kin) in test_chains() {
            let n = kin.dof();
            let mut ws = crate::Workspace::new(&kin);
            let mut configs: Vec<Vec<f64>> = crate::sample::configurations(&kin, 20, 3)
                .chunks(n)
                .map(<[f64]>::to_vec)
                .collect();
            if file == "ur5.urdf" {
                configs.push(vec![0.3, -0.7, 1.2, 0.4, 0.0, 0.2]); // wrist singular
                configs.push(vec![0.3, -0.7, 0.0, 0.4, 0.5, 0.2]); // elbow singular
            }
            for (c, q) in configs.iter().enumerate() {
                for frame in Frame::ALL {
                    let j = crate::jacobian::jacobian(&kin, &mut ws, q, frame)
                        .unwrap()
                        .clone();
                    let e = Vector6::from_fn(|_, _| rng.uniform() - 0.5);
                    let locked: Vec<bool> = (0..n).map(|k| c % 3 == 1 && k % 3 == 0).collect();
                    for mu in [1e-6, 1e-3, 0.5] {
                        let svd = crate::linalg::svd::jacobian_svd(&j, Some(&locked)).unwrap();
                        let (u, s, v) = (&svd.u, &svd.s, &svd.v);
                        let mut oracle = vec![0.0; n];
                        for i in 0..n.min(6) {
                            let ute: f64 = (0..6).map(|r| u[(r, i)] * e[r]).sum();
                            let g = s[i] / (s[i] * s[i] + mu) * ute;
                            for (k, x) in oracle.iter_mut().enumerate() {
                                *x += v[(k, i)] * g;
                            }
                        }
                        // Rounding grows with the condition number of J Jᵀ + μI.
                        let cond = (s[0] * s[0] + mu) / mu;
                        let scale = oracle.iter().fold(1.0f64, |m, x| m.max(x.abs()));
                        let mut dispatched = vec![f64::NAN; n];
                        dls_step(&j, &e, mu, &locked, &mut dispatched).unwrap();
                        let (mut plain, mut fused) = (vec![f64::NAN; n], vec![f64::NAN; n]);
                        dls_step_with::<Plain>(&j, &e, mu, &locked, &mut plain).unwrap();
                        dls_step_with::<Fused>(&j, &e, mu, &locked, &mut fused).unwrap();
                        for dq in [&dispatched, &plain, &fused] {
                            for k in 0..n {
                                assert!(
                                    (dq[k] - oracle[k]).abs() <= 1e-14 * cond * scale,
                                    "{file} {frame:?} μ={mu}: Δq_{k} {} vs {}",
                                    dq[k],
                                    oracle[k]
                                );
                                if locked[k] {
                                    assert_eq!(dq[k], 0.0);
                                }
                            }
                        }
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked >= 700, "{checked}");
    }

    /// Not positive definite (μ = 0, fewer than 6 free columns): a numerical error, not garbage.
    #[test]
    fn singular_system_is_an_error() {
        let j = Matrix6xX::from_fn(3, |r, c| (r + c) as f64);
        let mut dq = [0.0; 3];
        let e = Vector6::repeat(0.1);
        let err = dls_step(&j, &e, 0.0, &[false; 3], &mut dq).unwrap_err();
        assert!(!err.is_invalid_input(), "{err}");
    }
}
