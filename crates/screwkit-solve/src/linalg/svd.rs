//! The singular value decomposition J = U Σ Vᵀ: the crate's one SVD, for every Jacobian (the
//! singularity analyses and their ellipsoids, the pseudo-inverse, the check of exact joint
//! velocities), and in its two-column case on the stack ([`svd_2x4`]) for subproblem 6's
//! least-squares system.
//!
//! One-sided Jacobi (Hestenes) on A = Jᵀ, whose six columns are few: plane rotations G_pq
//! applied to pairs of columns until every pair is orthogonal, A G₁ G₂ ⋯ = W, so that
//! J = U Σ Vᵀ with U = G₁ G₂ ⋯ (6 × 6, orthogonal), σ_i = ‖w_i‖ and v_i = w_i / σ_i. It is
//! accurate to ε‖J‖ in every entry of U Σ Vᵀ and to high relative accuracy in the singular
//! values, also at exact rank deficiency (nalgebra's Golub–Kahan SVD was measured 1.4e-9 off
//! in U Σ Vᵀ on a UR5 Jacobian with two zero singular values), and needs no dependency.
//!
//! U is always 6 × 6: for n < 6, or at a singularity, the columns with σ = 0 complete it with
//! the directions J cannot reach. The singular values come sorted, σ₁ ≥ ⋯ ≥ σ_k
//! (k = min(n, 6)), with their columns of U and V; a column of V whose σ is 0 is 0.

use nalgebra::{DMatrix, Matrix6, Matrix6xX};

use crate::error::SolveError;

/// Sweeps over the 15 column pairs before the SVD is declared not converged (quadratic
/// convergence: 6–10 in practice).
const MAX_SWEEPS: usize = 60;

/// J = U Σ Vᵀ, sorted (see the module documentation).
#[derive(Debug, Clone)]
pub(crate) struct JacobianSvd {
    /// Left singular vectors, 6 × 6, column i for σ_i (i < k), then J's unreachable directions.
    pub(crate) u: Matrix6<f64>,
    /// σ₁ ≥ ⋯ ≥ σ_k, k = min(n, 6).
    pub(crate) s: Vec<f64>,
    /// Right singular vectors, n × k, column i for σ_i (0 where σ_i = 0).
    pub(crate) v: DMatrix<f64>,
}

/// The Jacobi rotation (c, s) that makes columns a_p, a_q orthogonal, from α = ‖a_p‖²,
/// β = ‖a_q‖², γ = a_p · a_q ≠ 0: (a_p, a_q) ← (c a_p − s a_q, s a_p + c a_q), the smaller
/// of the two angles (Golub & Van Loan, §8.6.3): ζ = (β − α) / 2γ, t = sign ζ / (|ζ| + √(1 + ζ²)),
/// c = 1 / √(1 + t²), s = c t.
#[inline]
fn rotation(alpha: f64, beta: f64, gamma: f64) -> (f64, f64) {
    let zeta = (beta - alpha) / (2.0 * gamma);
    let t = zeta.signum() / (zeta.abs() + zeta.hypot(1.0));
    let c = 1.0 / t.hypot(1.0);
    (c, c * t)
}

/// A = U diag(σ) Vᵀ of a 2 × 4 matrix ([`svd_2x4`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Svd2x4 {
    /// σ₁ ≥ σ₂ ≥ 0.
    pub(crate) s: [f64; 2],
    /// U's columns (2 × 2, orthogonal).
    pub(crate) u: [[f64; 2]; 2],
    /// V's columns (4 × 2): unit where σ_i > 0, else 0.
    pub(crate) v: [[f64; 4]; 2],
}

/// The SVD of a 2 × 4 matrix A (rows `a`), the same one-sided Jacobi on Aᵀ as
/// [`jacobian_svd`], on the stack: two columns need one rotation. None for a non-finite
/// entry. For subproblem 6's least squares.
pub(crate) fn svd_2x4(a: &[[f64; 4]; 2]) -> Option<Svd2x4> {
    if a.iter().flatten().any(|x| !x.is_finite()) {
        return None;
    }
    let m = a.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let inv = if m > 0.0 { 1.0 / m } else { 1.0 };
    // Aᵀ's two columns are A's rows, scaled as in `jacobian_svd`.
    let mut w = [a[0].map(|x| x * inv), a[1].map(|x| x * inv)];
    let dot = |x: &[f64; 4], y: &[f64; 4]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let (alpha, beta, gamma) = (dot(&w[0], &w[0]), dot(&w[1], &w[1]), dot(&w[0], &w[1]));
    let tol = 6.0 * f64::EPSILON;
    let negligible = (tol * (alpha + beta).sqrt()).powi(2);
    let mut g = [[1.0, 0.0], [0.0, 1.0]];
    if alpha > negligible && beta > negligible && gamma.abs() > tol * (alpha * beta).sqrt() {
        let (c, s) = rotation(alpha, beta, gamma);
        let [w0, w1] = &mut w;
        for (x, y) in w0.iter_mut().zip(w1.iter_mut()) {
            (*x, *y) = (c * *x - s * *y, s * *x + c * *y);
        }
        g = [[c, s], [-s, c]];
    }
    let sigma = [dot(&w[0], &w[0]).sqrt(), dot(&w[1], &w[1]).sqrt()];
    // g[i] is row i of G; U's column j is G's column j.
    let order = if sigma[1] > sigma[0] { [1, 0] } else { [0, 1] };
    let scale = if m > 0.0 { m } else { 1.0 };
    let unit = |i: usize| {
        if sigma[i] > 0.0 {
            w[i].map(|x| x / sigma[i])
        } else {
            [0.0; 4]
        }
    };
    Some(Svd2x4 {
        s: order.map(|i| sigma[i] * scale),
        u: order.map(|i| [g[0][i], g[1][i]]),
        v: order.map(unit),
    })
}

/// The SVD of `j` with the columns whose `locked` flag is set taken as zero. A non-finite
/// entry, or rotations that do not converge, is a [`SolveError::Numerical`].
pub(crate) fn jacobian_svd(
    j: &Matrix6xX<f64>,
    locked: Option<&[bool]>,
) -> Result<JacobianSvd, SolveError> {
    if j.iter().any(|x| !x.is_finite()) {
        return Err(SolveError::Numerical(
            "the Jacobian has non-finite entries".into(),
        ));
    }
    let n = j.ncols();
    // A = Jᵀ / m (n × 6, column-major: column p is row p of J, contiguous), m the largest
    // |entry|: the squared norms below neither overflow nor underflow whatever J's scale (a
    // robot file with 1e200 m links); σ is scaled back at the end.
    let free = |c: usize| !locked.is_some_and(|l| l[c]);
    let m = (0..n)
        .filter(|&c| free(c))
        .map(|c| j.column(c).amax())
        .fold(0.0, f64::max);
    let inv = if m > 0.0 { 1.0 / m } else { 1.0 };
    let mut a = DMatrix::from_fn(n, 6, |r, c| if free(r) { j[(c, r)] * inv } else { 0.0 });
    // A pair counts as orthogonal at |a_p · a_q| ≤ tol ‖a_p‖ ‖a_q‖, the rounding level of the
    // inner product of n-vectors (LAPACK's one-sided Jacobi uses √m ε; this is tighter).
    let tol = n.max(6) as f64 * f64::EPSILON;
    // A column below tol ‖A‖ is rounding (J's rank is below 6 there): rotating it against the
    // others only moves that rounding around, so it takes part in no rotation.
    let negligible = (tol * a.norm()).powi(2);
    let mut g = Matrix6::<f64>::identity();
    let mut converged = false;
    for _ in 0..MAX_SWEEPS {
        let mut rotated = false;
        for p in 0..5 {
            for q in p + 1..6 {
                let (ap, aq) = (a.column(p), a.column(q));
                let (alpha, beta, gamma) = (ap.norm_squared(), aq.norm_squared(), ap.dot(&aq));
                if alpha <= negligible
                    || beta <= negligible
                    || gamma.abs() <= tol * (alpha * beta).sqrt()
                {
                    continue;
                }
                rotated = true;
                let (c, s) = rotation(alpha, beta, gamma);
                for r in 0..n {
                    let (x, y) = (a[(r, p)], a[(r, q)]);
                    a[(r, p)] = c * x - s * y;
                    a[(r, q)] = s * x + c * y;
                }
                for r in 0..6 {
                    let (x, y) = (g[(r, p)], g[(r, q)]);
                    g[(r, p)] = c * x - s * y;
                    g[(r, q)] = s * x + c * y;
                }
            }
        }
        if !rotated {
            converged = true;
            break;
        }
    }
    if !converged {
        return Err(SolveError::Numerical(
            "the SVD's Jacobi rotations did not converge".into(),
        ));
    }
    let sigma: Vec<f64> = (0..6).map(|c| a.column(c).norm()).collect();
    let scale = if m > 0.0 { m } else { 1.0 };
    let mut order: Vec<usize> = (0..6).collect();
    order.sort_by(|&x, &y| sigma[y].total_cmp(&sigma[x]));
    let k = n.min(6);
    Ok(JacobianSvd {
        u: Matrix6::from_fn(|r, c| g[(r, order[c])]),
        s: order[..k].iter().map(|&i| sigma[i] * scale).collect(),
        v: DMatrix::from_fn(n, k, |r, c| {
            let (i, s) = (order[c], sigma[order[c]]);
            if s > 0.0 {
                a[(r, i)] / s
            } else {
                0.0
            }
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// J = U Σ Vᵀ with orthogonal U (6 × 6), orthonormal V where σ > 0, sorted σ, for wide,
    /// square and narrow (n < 6) matrices, rank-deficient ones and with a locked column; the
    /// singular values against the eigenvalues of J Jᵀ (an independent route: σ² = λ), and the
    /// columns of U past the rank orthogonal to J's range.
    /// The singular values equal faer's (an independent SVD, not nalgebra's) to 1e-14 σ₁, on
    /// wide, square and narrow Jacobians, rank-deficient ones, and at extreme scales.
    #[test]
    fn singular_values_equal_faer() {
        let mut rng = crate::sample::SplitMix64(0x0FAE_0000_0000_0001);
        for n in 1..=12 {
            for case in 0..8 {
                let scale = [1.0, 1e-150, 1e150, 1.0][case % 4];
                let mut j = Matrix6xX::from_fn(n, |_, _| (rng.uniform() - 0.5) * scale);
                if case >= 4 && n >= 3 {
                    // Rank-deficient: a column made of two others, another zeroed.
                    let c = j.column(0) * 0.3 + j.column(1) * -1.7;
                    j.set_column(n - 1, &c);
                    j.column_mut(n / 2).fill(0.0);
                }
                let ours = jacobian_svd(&j, None).unwrap().s;
                let m = faer::Mat::<f64>::from_fn(6, n, |r, c| j[(r, c)]);
                let mut theirs: Vec<f64> = m.singular_values().unwrap();
                theirs.sort_by(|a, b| b.total_cmp(a));
                assert_eq!(ours.len(), n.min(6));
                for (a, b) in ours.iter().zip(&theirs) {
                    assert!(
                        (a - b).abs() <= 1e-14 * theirs[0].max(f64::MIN_POSITIVE),
                        "n = {n}, case {case}: {ours:?} against {theirs:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn decomposes_and_sorts() {
        let mut rng = crate::sample::SplitMix64(0x5EED_0000_0000_0042);
        for n in [1, 3, 5, 6, 7, 12] {
            for rank_deficient in [false, true] {
                let mut j = Matrix6xX::from_fn(n, |_, _| rng.uniform() - 0.5);
                if rank_deficient && n >= 3 {
                    let c = j.column(0) * 0.3 + j.column(1) * -1.7;
                    j.set_column(n - 1, &c);
                }
                for locked in [None, Some((0..n).map(|c| c == 0).collect::<Vec<_>>())] {
                    let svd = jacobian_svd(&j, locked.as_deref()).unwrap();
                    let k = n.min(6);
                    assert_eq!((svd.s.len(), svd.v.shape()), (k, (n, k)));
                    assert!(svd.s.windows(2).all(|w| w[0] >= w[1]));
                    assert!((svd.u.transpose() * svd.u - Matrix6::identity()).norm() < 1e-14);
                    let mut jl = DMatrix::from_fn(6, n, |r, c| j[(r, c)]);
                    for c in 0..n {
                        if locked.as_ref().is_some_and(|l| l[c]) {
                            jl.column_mut(c).fill(0.0);
                        }
                    }
                    let us = DMatrix::from_fn(6, k, |r, c| svd.u[(r, c)] * svd.s[c]);
                    assert!((us * svd.v.transpose() - &jl).norm() < 1e-14);
                    let tol = 1e-12 * svd.s[0];
                    let live: Vec<usize> = (0..k).filter(|&i| svd.s[i] > tol).collect();
                    for &a in &live {
                        for &b in &live {
                            let d = svd.v.column(a).dot(&svd.v.column(b));
                            assert!((d - f64::from(u8::from(a == b))).abs() < 1e-14);
                        }
                    }
                    let mut eig: Vec<f64> = (jl.clone() * jl.transpose())
                        .symmetric_eigenvalues()
                        .iter()
                        .map(|x| x.max(0.0).sqrt())
                        .collect();
                    eig.sort_by(|a, b| b.total_cmp(a));
                    for i in 0..k {
                        assert!((eig[i] - svd.s[i]).abs() < 1e-7, "{n}: {eig:?} {:?}", svd.s);
                    }
                    for c in live.len()..6 {
                        assert!((jl.transpose() * svd.u.column(c)).norm() < 1e-14);
                    }
                }
            }
        }
        // Any scale: the same decomposition of J · 1e±200 (no overflow or underflow in the
        // squared norms), and the zero matrix.
        let j = Matrix6xX::from_fn(7, |r, c| ((r * 7 + c) as f64 * 0.37).sin());
        let base = jacobian_svd(&j, None).unwrap();
        for scale in [1e200, 1e-200] {
            let scaled = jacobian_svd(&(j.clone() * scale), None).unwrap();
            for (x, y) in base.s.iter().zip(&scaled.s) {
                assert!(
                    (y / scale - x).abs() <= 1e-14 * base.s[0],
                    "{scale}: {x} {y}"
                );
            }
            assert!((scaled.u.transpose() * scaled.u - Matrix6::identity()).norm() < 1e-14);
        }
        let zero = jacobian_svd(&Matrix6xX::zeros(4), None).unwrap();
        assert_eq!(zero.s, vec![0.0; 4]);
        assert_eq!(zero.u, Matrix6::identity());
        let mut bad = Matrix6xX::<f64>::zeros(3);
        bad[(2, 1)] = f64::NAN;
        assert!(matches!(
            jacobian_svd(&bad, None),
            Err(SolveError::Numerical(_))
        ));
    }

    /// The two-column case on the stack: A = U diag(σ) Vᵀ, U orthogonal, V orthonormal where
    /// σ > 0; σ equal to faer's and to [`jacobian_svd`]'s of A padded to six rows (the
    /// general kernel it specialises), on random, rank-one, zero-row and extreme-scale
    /// matrices; None on NaN.
    #[test]
    fn two_by_four_equals_the_general_kernel_and_faer() {
        let mut rng = crate::sample::SplitMix64(0x2040_0000_0000_0001);
        for case in 0..64 {
            let scale = [1.0, 1e-150, 1e150, 3.0][case % 4];
            let mut a = [[0.0; 4]; 2];
            for x in a.iter_mut().flatten() {
                *x = (rng.uniform() - 0.5) * scale;
            }
            match case / 4 % 4 {
                1 => a[1] = a[0].map(|x| -2.5 * x),
                2 => a[case % 2] = [0.0; 4],
                3 => a[1] = [a[0][0], a[0][1], 0.0, 0.0],
                _ => {}
            }
            let Svd2x4 { s: sigma, u, v } = svd_2x4(&a).unwrap();
            let s1 = sigma[0].max(f64::MIN_POSITIVE);
            assert!(sigma[0] >= sigma[1] && sigma[1] >= 0.0, "{sigma:?}");
            for r in 0..2 {
                for c in 0..4 {
                    let usv: f64 = (0..2).map(|i| u[i][r] * sigma[i] * v[i][c]).sum();
                    assert!((usv - a[r][c]).abs() <= 1e-14 * s1, "case {case}: {a:?}");
                }
            }
            let utu = u[0][0] * u[1][0] + u[0][1] * u[1][1];
            assert!(utu.abs() < 1e-15 && (u[0][0].hypot(u[0][1]) - 1.0).abs() < 1e-15);
            for i in 0..2 {
                let norm = v[i].iter().map(|x| x * x).sum::<f64>().sqrt();
                assert!(if sigma[i] > 0.0 {
                    (norm - 1.0).abs() < 1e-14
                } else {
                    norm == 0.0
                });
            }
            let padded = Matrix6xX::from_fn(4, |r, c| if r < 2 { a[r][c] } else { 0.0 });
            let general = jacobian_svd(&padded, None).unwrap().s;
            let m = faer::Mat::<f64>::from_fn(2, 4, |r, c| a[r][c]);
            let mut faer_s: Vec<f64> = m.singular_values().unwrap();
            faer_s.sort_by(|x, y| y.total_cmp(x));
            for i in 0..2 {
                assert!(
                    (sigma[i] - general[i]).abs() <= 1e-14 * s1,
                    "{sigma:?} {general:?}"
                );
                assert!(
                    (sigma[i] - faer_s[i]).abs() <= 1e-14 * s1,
                    "{sigma:?} {faer_s:?}"
                );
            }
        }
        assert!(svd_2x4(&[[0.0, f64::NAN, 0.0, 0.0], [0.0; 4]]).is_none());
        assert_eq!(svd_2x4(&[[0.0; 4]; 2]).unwrap().s, [0.0, 0.0]);
    }
}
