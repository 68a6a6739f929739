//! Newton polish of a six-row residual: the crate's one Newton iteration, for the analytic
//! solvers' postures (the general 6R's roots, and a closed form's rare ill-conditioned
//! posture).
//!
//! At an iterate x with error twist e (J Δ = e moves x towards the goal) and Jacobian J
//! (6 × M, M ≥ 6):
//! - the full step solves J Δ = e: Δ = J⁻¹ e for M = 6 (LU of J, so the conditioning is κ(J),
//!   not κ(J)²), the least-norm Δ = Jᵀ (J Jᵀ)⁻¹ e for M > 6;
//! - a damped step, for each damping d asked, Δ = Jᵀ (J Jᵀ + λ I)⁻¹ e = (JᵀJ + λ I)⁻¹ Jᵀ e
//!   with λ = d · max(‖J‖²_F, 10⁻¹²), the damped least-squares step on the 6 × 6 system.
//!
//! The trial x_i ← wrap(x_i + Δ_i) is taken when its residual is below the current one; the
//! full step is tried first, then the dampings in order. It stops at the step budget, at the
//! residual floor, or when no trial improves: the residual never grows.

use nalgebra::{Matrix6, SMatrix, SVector, Vector6};

/// A linearisation at an iterate: the error twist e (so that J Δ = e heads for the goal), the
/// Jacobian J, and the residual that decides whether a step is taken.
#[derive(Debug, Clone)]
pub(crate) struct Linear<const M: usize> {
    /// The error twist e, ordered (ω, v) as J's rows.
    pub(crate) error: Vector6<f64>,
    /// J, 6 × M.
    pub(crate) jacobian: SMatrix<f64, 6, M>,
    /// The residual of the iterate (smaller is better).
    pub(crate) residual: f64,
}

/// The iteration's budget.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Newton<'a> {
    /// At most this many steps taken.
    pub(crate) steps: usize,
    /// No step once the residual is at or below this.
    pub(crate) floor: f64,
    /// The dampings d tried, in order, when the full step does not improve.
    pub(crate) dampings: &'a [f64],
}

/// The step Δ of J Δ = e with damping d (0 for the full step); see the module documentation.
/// None when the system is singular.
pub(crate) fn step<const M: usize>(
    j: &SMatrix<f64, 6, M>,
    e: &Vector6<f64>,
    damping: f64,
) -> Option<SVector<f64, M>> {
    if M == 6 && damping == 0.0 {
        let square: Matrix6<f64> = j.fixed_view::<6, 6>(0, 0).into_owned();
        let d = square.lu().solve(e)?;
        return Some(SVector::from_fn(|i, _| d[i]));
    }
    let mut a: Matrix6<f64> = j * j.transpose();
    if damping > 0.0 {
        let lambda = damping * a.trace().max(1e-12);
        for i in 0..6 {
            a[(i, i)] += lambda;
        }
    }
    let y = a.lu().solve(e)?;
    Some(j.transpose() * y)
}

/// Newton from `x`: `linearise` gives the error, Jacobian and residual at an iterate (None
/// where it cannot be evaluated, which ends the iteration). `x` is left at the best iterate;
/// returns its linearisation (None when `x` itself could not be linearised).
pub(crate) fn polish<const M: usize>(
    x: &mut [f64; M],
    newton: Newton<'_>,
    wrap: impl Fn(f64) -> f64,
    mut linearise: impl FnMut(&[f64; M]) -> Option<Linear<M>>,
) -> Option<Linear<M>> {
    let mut at = linearise(x)?;
    for _ in 0..newton.steps {
        if at.residual <= newton.floor {
            break;
        }
        let mut improved = false;
        for &damping in std::iter::once(&0.0).chain(newton.dampings) {
            let Some(d) = step(&at.jacobian, &at.error, damping) else {
                continue;
            };
            let trial: [f64; M] = std::array::from_fn(|i| wrap(x[i] + d[i]));
            let Some(next) = linearise(&trial) else {
                continue;
            };
            if next.residual < at.residual {
                (*x, at) = (trial, next);
                improved = true;
                break;
            }
        }
        if !improved {
            break;
        }
    }
    Some(at)
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::prelude::Solve;

    fn random_j<const M: usize>(rng: &mut crate::sample::SplitMix64) -> SMatrix<f64, 6, M> {
        SMatrix::from_fn(|_, _| rng.uniform() - 0.5)
    }

    /// The steps against their defining equations: J Δ = e (square), the least-norm solution
    /// (J Δ = e and Δ in J's row space), and the damped normal equations
    /// (JᵀJ + λ I) Δ = Jᵀ e, each from an independent solve (faer's LU on the M × M system).
    #[test]
    fn steps_solve_their_equations() {
        let mut rng = crate::sample::SplitMix64(0x4E57_0000_0000_0001);
        for _ in 0..50 {
            let e = Vector6::from_fn(|_, _| rng.uniform() - 0.5);
            let j6 = random_j::<6>(&mut rng);
            let d = step(&j6, &e, 0.0).unwrap();
            assert!((j6 * d - e).norm() < 1e-10 * (1.0 + d.norm()));
            let j7 = random_j::<7>(&mut rng);
            let d = step(&j7, &e, 0.0).unwrap();
            assert!((j7 * d - e).norm() < 1e-10 * (1.0 + d.norm()));
            // Least norm: Δ = Jᵀ y for some y, so Δ ⊥ null(J).
            let svd = faer::Mat::<f64>::from_fn(6, 7, |r, c| j7[(r, c)])
                .svd()
                .unwrap();
            let null = svd.V().col(6);
            let along: f64 = (0..7).map(|i| null[i] * d[i]).sum();
            assert!(along.abs() < 1e-12, "{along}");
            for damping in [1e-6, 1e-3, 1e-1] {
                let d = step(&j7, &e, damping).unwrap();
                let lambda = damping * j7.norm_squared();
                let h = faer::Mat::<f64>::from_fn(7, 7, |r, c| {
                    (j7.column(r).dot(&j7.column(c))) + if r == c { lambda } else { 0.0 }
                });
                let g = faer::Mat::<f64>::from_fn(7, 1, |r, _| j7.column(r).dot(&e));
                let theirs = h.partial_piv_lu().solve(&g);
                for i in 0..7 {
                    assert!((d[i] - theirs[(i, 0)]).abs() < 1e-10, "{damping}");
                }
            }
        }
        assert!(step(&SMatrix::<f64, 6, 6>::zeros(), &Vector6::repeat(1.0), 0.0).is_none());
    }

    /// Newton on a linear map converges in one full step; on a map whose full step overshoots
    /// (x ↦ sin x per coordinate near a fold) the residual never grows, and the iterate the
    /// polish leaves is the one its linearisation describes.
    #[test]
    fn polish_never_increases_the_residual() {
        let mut rng = crate::sample::SplitMix64(0x4E57_0000_0000_0002);
        let a = random_j::<6>(&mut rng);
        let goal = Vector6::from_fn(|_, _| rng.uniform() - 0.5);
        let lin = |x: &[f64; 6]| {
            let v = a * Vector6::from_column_slice(x);
            Some(Linear {
                error: goal - v,
                jacobian: a,
                residual: (goal - v).amax(),
            })
        };
        let mut x = [0.0; 6];
        let at = polish(
            &mut x,
            Newton {
                steps: 2,
                floor: 0.0,
                dampings: &[],
            },
            |v| v,
            lin,
        )
        .unwrap();
        assert!(at.residual < 1e-12, "{}", at.residual);
        let fold = |x: &[f64; 6]| {
            let v = Vector6::from_fn(|i, _| x[i].sin());
            let err = Vector6::repeat(0.999) - v;
            Some(Linear {
                error: err,
                jacobian: SMatrix::from_fn(|r, c| if r == c { x[r].cos() } else { 0.0 }),
                residual: err.amax(),
            })
        };
        let mut x = [1.2; 6];
        let start = fold(&x).unwrap().residual;
        let newton = Newton {
            steps: 8,
            floor: 0.0,
            dampings: &[1e-6, 1e-3, 1e-1],
        };
        let at = polish(&mut x, newton, |v| v, fold).unwrap();
        assert!(at.residual <= start);
        assert_eq!(at.residual, fold(&x).unwrap().residual);
    }
}
