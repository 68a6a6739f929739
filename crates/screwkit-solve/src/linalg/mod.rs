//! The crate's numerics, in one room: each method once, each tested against an independent
//! oracle (faer's SVD and eigenvalues, a dev-dependency; closed forms; KKT conditions).
//!
//! | module | what | used by |
//! |---|---|---|
//! | `svd` | the SVD, one-sided Jacobi (Hestenes): a 6 × n Jacobian, and its two-column case on the stack | analysis (rank, lost directions, the ellipsoids), pseudo-inverses, subproblem 6's least squares |
//! | `eigen` | eigenvalues of a small dense real matrix (balancing, `elmhes`, Francis double-shift QR) | the general 6R's 24 × 24 companion, the subproblems' quartic roots |
//! | `dls` | the damped least-squares step Δq = Jᵀ(JJᵀ + μI)⁻¹e on 6 × 6 arrays | IK (LM, DLS), damped joint velocities |
//! | `newton` | Newton polish of a 6-row residual: J Δ = e, damped when the full step fails | the analytic solvers' postures |
//! | [`box_qp`] | strictly convex QPs under box constraints (primal active set) | whole-body differential IK |
//! | [`qp`] | strictly convex QPs under bounds and general inequality rows (Goldfarb–Idnani dual active set) | IK that keeps clear of contact |

/// aᵀb over the shorter length, eight partial sums: the small dense kernels of the QPs are
/// bound by the sequential sum's dependency chain (one add's latency per term), which eight
/// independent chains (four two-lane vectors on baseline x86-64) shorten eightfold.
#[inline(always)]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let k = a.len().min(b.len());
    let (a, b) = (&a[..k], &b[..k]);
    let (mut ca, mut cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let mut s = [0.0; 8];
    for (x, y) in (&mut ca).zip(&mut cb) {
        for j in 0..8 {
            s[j] += x[j] * y[j];
        }
    }
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7])) + tail
}

pub mod box_qp;
pub(crate) mod dls;
pub(crate) mod eigen;
pub(crate) mod newton;
pub mod qp;
pub(crate) mod svd;
