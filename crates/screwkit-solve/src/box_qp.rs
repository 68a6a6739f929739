//! Strictly convex quadratic programs with box constraints, small and dense:
//!
//! ```text
//! minimise ½ xᵀ H x + cᵀ x   subject to   l ≤ x ≤ u,
//! ```
//!
//! H symmetric positive definite (n × n, row-major), l_i ∈ [−∞, ∞), u_i ∈ (−∞, ∞], l ≤ u. This
//! is the step of whole-body differential IK ([`crate::tree::differential_ik`]): a weighted
//! least-squares problem ‖A x − b‖² + damping (H = AᵀA + D, c = −Aᵀb) under joint limits.
//!
//! **Method**: the primal active-set method (Nocedal & Wright, *Numerical Optimization*, 2nd
//! ed., §16.5) specialised to bounds, where the working set is a set of variables held at one
//! of their bounds. From a feasible start (0 clamped into the box), each iteration solves the
//! equality-constrained subproblem on the free variables F, H_FF y_F = −(c_F + H_FA x_A), by a
//! Cholesky factorisation of H_FF; if y is feasible it is taken and the multipliers of the held
//! variables, g_i = (H x + c)_i, are checked (held at l_i: g_i ≥ 0; at u_i: g_i ≤ 0) and the most
//! negative one released; if not, x moves towards y as far as the box allows and the blocking
//! variable is held. H being positive definite, the objective decreases strictly on every move
//! and no working set repeats, so the method ends. The first working set holds every variable
//! the unconstrained minimiser puts beyond a bound (at that bound, the rest at the minimiser's
//! values: a feasible start), so that the bounds a step hits come in one factorisation rather
//! than one each; the iterations then release the ones that should not be held.
//!
//! At the end the KKT conditions hold to rounding: with g = H x + c, g_i = 0 where l_i < x_i < u_i,
//! g_i ≥ 0 where x_i = l_i and g_i ≤ 0 where x_i = u_i (the tests check them, and compare with a
//! reference solver). Why this and not a general QP crate (measured, BENCHMARKS.md, TALOS
//! n = 32): an interior-point solver (Clarabel, OSQP through qpsolvers) takes over 1 ms for the
//! QP alone and answers to its tolerance (2e-3 off the exact optimum here); a dense active set
//! in C (DAQP) takes 43 µs for the QP alone from Python, while the whole step here (Jacobians
//! included) takes 33 µs and is exact. A general inequality row (self-collision avoidance: a
//! distance's gradient times v above a bound) needs a
//! general QP; it would enter here as a new constraint kind beside the box.

use crate::error::SolveError;

/// Which bound a variable is held at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Held {
    /// Not held: l < x < u, or at a bound with its gradient pointing inside.
    Free,
    /// Held at its lower bound.
    Lower,
    /// Held at its upper bound.
    Upper,
}

/// Reusable scratch for problems of up to the size it has grown to (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub struct BoxQpWorkspace {
    chol: Vec<f64>,
    rhs: Vec<f64>,
    y: Vec<f64>,
    free: Vec<usize>,
    held: Vec<Held>,
}

impl BoxQpWorkspace {
    /// An empty workspace (it grows on first use).
    pub fn new() -> Self {
        Self::default()
    }

    fn fit(&mut self, n: usize) {
        if self.held.len() != n {
            self.chol.resize(n * n, 0.0);
            self.rhs.resize(n, 0.0);
            self.y.resize(n, 0.0);
            self.free.resize(n, 0);
            self.held.resize(n, Held::Free);
        }
    }

    /// Which bound each variable was held at in the last solve.
    pub fn held(&self) -> &[Held] {
        &self.held
    }
}

/// What a solve did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoxQpInfo {
    /// Active-set iterations (one factorisation each).
    pub iterations: usize,
    /// Variables held at a bound at the solution.
    pub active: usize,
}

/// Solves the box-constrained QP of the module documentation into `x` (length n). `h` is
/// n × n row-major (only its lower triangle is read), `c`, `l`, `u` of length n.
///
/// Errors: a bound with l_i > u_i or NaN (`InvalidInput`, naming the index), H not positive
/// definite on the free variables (`Numerical`).
pub fn solve(
    ws: &mut BoxQpWorkspace,
    h: &[f64],
    c: &[f64],
    l: &[f64],
    u: &[f64],
    x: &mut [f64],
) -> Result<BoxQpInfo, SolveError> {
    let n = c.len();
    debug_assert!(h.len() == n * n && l.len() == n && u.len() == n && x.len() == n);
    ws.fit(n);
    for i in 0..n {
        if l[i].is_nan()
            || u[i].is_nan()
            || l[i] > u[i]
            || l[i] == f64::INFINITY
            || u[i] == f64::NEG_INFINITY
        {
            return Err(SolveError::InvalidInput(format!(
                "box constraint {i}: the bounds [{}, {}] are empty",
                l[i], u[i]
            )));
        }
        x[i] = 0.0_f64.clamp(l[i], u[i]);
        ws.held[i] = if l[i] == u[i] {
            Held::Lower
        } else {
            Held::Free
        };
    }
    // The multipliers' tolerance: rounding of the gradient's largest terms.
    let scale = c.iter().fold(0.0_f64, |m, v| m.max(v.abs()))
        + (0..n).fold(0.0_f64, |m, i| m.max(h[i * n + i].abs()))
            * l.iter()
                .chain(u)
                .filter(|v| v.is_finite())
                .fold(1.0_f64, |m, v| m.max(v.abs()));
    let tol = 1e-12 * scale.max(f64::MIN_POSITIVE);
    // The first working set from the unconstrained minimiser: every variable it puts beyond a
    // bound held there, the others at its values (a feasible start, so the method below stays
    // exact; it then releases what should not be held). One factorisation instead of one per
    // bound when many bounds are active, as under a control step's velocity limits.
    subproblem(ws, h, c, x)?;
    for i in 0..n {
        if ws.held[i] != Held::Free {
            continue;
        }
        let y = ws.y[i];
        if y < l[i] {
            ws.held[i] = Held::Lower;
            x[i] = l[i];
        } else if y > u[i] {
            ws.held[i] = Held::Upper;
            x[i] = u[i];
        } else {
            x[i] = y;
        }
    }
    let max_iterations = 4 * n + 20;
    for iteration in 1..=max_iterations {
        subproblem(ws, h, c, x)?;
        let BoxQpWorkspace { y, held, .. } = ws;
        // The largest step towards y within the box.
        let (mut alpha, mut block) = (1.0_f64, None);
        for i in 0..n {
            if held[i] != Held::Free {
                continue;
            }
            let d = y[i] - x[i];
            let (bound, side) = if y[i] < l[i] {
                (l[i], Held::Lower)
            } else if y[i] > u[i] {
                (u[i], Held::Upper)
            } else {
                continue;
            };
            let a = ((bound - x[i]) / d).clamp(0.0, 1.0);
            if a < alpha || block.is_none() {
                alpha = a;
                block = Some((i, side, bound));
            }
        }
        match block {
            Some((b, side, bound)) => {
                for i in 0..n {
                    if held[i] == Held::Free {
                        x[i] += alpha * (y[i] - x[i]);
                        x[i] = x[i].clamp(l[i], u[i]);
                    }
                }
                x[b] = bound;
                held[b] = side;
            }
            None => {
                for i in 0..n {
                    if held[i] == Held::Free {
                        x[i] = y[i];
                    }
                }
                // The held variables' multipliers; release the most violated.
                let mut worst = (tol, None);
                for i in 0..n {
                    if held[i] == Held::Free || l[i] == u[i] {
                        continue;
                    }
                    let g = gradient(h, c, x, i);
                    let violation = if held[i] == Held::Lower { -g } else { g };
                    if violation > worst.0 {
                        worst = (violation, Some(i));
                    }
                }
                match worst.1 {
                    Some(i) => held[i] = Held::Free,
                    None => {
                        return Ok(BoxQpInfo {
                            iterations: iteration,
                            active: held.iter().filter(|s| **s != Held::Free).count(),
                        })
                    }
                }
            }
        }
    }
    Err(SolveError::Numerical(format!(
        "the box-constrained QP did not finish in {max_iterations} active-set iterations"
    )))
}

/// (H x + c)_i.
#[inline]
fn gradient(h: &[f64], c: &[f64], x: &[f64], i: usize) -> f64 {
    let n = c.len();
    let row = &h[i * n..i * n + n];
    // The lower triangle only: H[i][j] for j ≤ i, H[j][i] for j > i.
    let mut g = c[i];
    for j in 0..=i {
        g += row[j] * x[j];
    }
    for j in i + 1..n {
        g += h[j * n + i] * x[j];
    }
    g
}

/// y_F = H_FF⁻¹ (−c_F − H_FA x_A) by Cholesky (H_FF = L Lᵀ, L packed in `ws.chol`, |F| × |F|).
fn subproblem(ws: &mut BoxQpWorkspace, h: &[f64], c: &[f64], x: &[f64]) -> Result<(), SolveError> {
    let n = c.len();
    let BoxQpWorkspace {
        chol,
        rhs,
        y,
        free,
        held,
    } = ws;
    let mut m = 0;
    for (i, _) in held.iter().enumerate().filter(|(_, h)| **h == Held::Free) {
        free[m] = i;
        m += 1;
    }
    let free = &free[..m];
    let hl = |i: usize, j: usize| if j <= i { h[i * n + j] } else { h[j * n + i] };
    for (a, &i) in free.iter().enumerate() {
        let mut r = -c[i];
        for j in 0..n {
            if held[j] != Held::Free {
                r -= hl(i, j) * x[j];
            }
        }
        rhs[a] = r;
    }
    // L Lᵀ = H_FF, row by row.
    for a in 0..m {
        for b in 0..=a {
            let mut s = hl(free[a], free[b]);
            for k in 0..b {
                s -= chol[a * m + k] * chol[b * m + k];
            }
            if a == b {
                if s.is_nan() || s <= 0.0 {
                    return Err(SolveError::Numerical(format!(
                        "the QP's matrix is not positive definite (pivot {s:e} at variable {})",
                        free[a]
                    )));
                }
                chol[a * m + a] = s.sqrt();
            } else {
                chol[a * m + b] = s / chol[b * m + b];
            }
        }
    }
    // L z = rhs, then Lᵀ y = z.
    for a in 0..m {
        let mut s = rhs[a];
        for k in 0..a {
            s -= chol[a * m + k] * rhs[k];
        }
        rhs[a] = s / chol[a * m + a];
    }
    for a in (0..m).rev() {
        let mut s = rhs[a];
        for k in a + 1..m {
            s -= chol[k * m + a] * rhs[k];
        }
        rhs[a] = s / chol[a * m + a];
    }
    for (a, &i) in free.iter().enumerate() {
        y[i] = rhs[a];
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::SplitMix64;

    /// A random SPD matrix A Aᵀ + εI (row-major).
    fn spd(n: usize, rng: &mut SplitMix64) -> Vec<f64> {
        let a: Vec<f64> = (0..n * n).map(|_| 2.0 * rng.uniform() - 1.0).collect();
        let mut h = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                h[i * n + j] = (0..n).map(|k| a[i * n + k] * a[j * n + k]).sum::<f64>()
                    + if i == j { 1e-3 } else { 0.0 };
            }
        }
        h
    }

    /// The objective ½xᵀHx + cᵀx.
    fn objective(h: &[f64], c: &[f64], x: &[f64]) -> f64 {
        let n = c.len();
        let mut f = 0.0;
        for i in 0..n {
            f += c[i] * x[i];
            for j in 0..n {
                f += 0.5 * x[i] * h[i * n + j] * x[j];
            }
        }
        f
    }

    /// Projected gradient descent with a fixed step 1/‖H‖_F, many iterations: an independent,
    /// slow reference.
    fn reference(h: &[f64], c: &[f64], l: &[f64], u: &[f64]) -> Vec<f64> {
        let n = c.len();
        let step = 1.0 / h.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut x: Vec<f64> = (0..n).map(|i| 0.0_f64.clamp(l[i], u[i])).collect();
        for _ in 0..200_000 {
            let g: Vec<f64> = (0..n)
                .map(|i| c[i] + (0..n).map(|j| h[i * n + j] * x[j]).sum::<f64>())
                .collect();
            for i in 0..n {
                x[i] = (x[i] - step * g[i]).clamp(l[i], u[i]);
            }
        }
        x
    }

    #[test]
    fn kkt_holds_and_matches_projected_gradient() {
        let mut rng = SplitMix64(7);
        let mut ws = BoxQpWorkspace::new();
        let mut active_seen = 0;
        for trial in 0..60 {
            let n = 1 + trial % 9;
            let h = spd(n, &mut rng);
            let c: Vec<f64> = (0..n).map(|_| 4.0 * rng.uniform() - 2.0).collect();
            let l: Vec<f64> = (0..n)
                .map(|i| {
                    if i % 4 == 3 {
                        f64::NEG_INFINITY
                    } else {
                        -0.5 * rng.uniform()
                    }
                })
                .collect();
            let u: Vec<f64> = (0..n)
                .map(|i| {
                    if i % 5 == 4 {
                        f64::INFINITY
                    } else {
                        0.5 * rng.uniform()
                    }
                })
                .collect();
            let mut x = vec![0.0; n];
            let info = solve(&mut ws, &h, &c, &l, &u, &mut x).unwrap();
            active_seen += info.active;
            for i in 0..n {
                assert!(
                    x[i] >= l[i] && x[i] <= u[i],
                    "trial {trial}: x[{i}] outside"
                );
                let g = c[i] + (0..n).map(|j| h[i * n + j] * x[j]).sum::<f64>();
                if x[i] > l[i] && x[i] < u[i] {
                    assert!(g.abs() < 1e-9, "trial {trial}: free gradient {g}");
                } else if x[i] == l[i] && l[i] < u[i] {
                    assert!(g > -1e-9, "trial {trial}: lower multiplier {g}");
                } else if x[i] == u[i] && l[i] < u[i] {
                    assert!(g < 1e-9, "trial {trial}: upper multiplier {g}");
                }
            }
            if n <= 4 {
                let r = reference(&h, &c, &l, &u);
                let (fx, fr) = (objective(&h, &c, &x), objective(&h, &c, &r));
                assert!(fx <= fr + 1e-9, "trial {trial}: {fx} vs reference {fr}");
            }
        }
        assert!(active_seen > 20, "the trials exercise active bounds");
    }

    #[test]
    fn unconstrained_is_the_newton_step_and_fixed_variables_stay() {
        let h = [2.0, 0.0, 0.0, 4.0];
        let c = [-2.0, -8.0];
        let mut x = [0.0; 2];
        let mut ws = BoxQpWorkspace::new();
        let info = solve(&mut ws, &h, &c, &[-10.0; 2], &[10.0; 2], &mut x).unwrap();
        let close = |x: [f64; 2], y: [f64; 2]| (x[0] - y[0]).abs() + (x[1] - y[1]).abs() < 1e-15;
        assert!(close(x, [1.0, 2.0]), "{x:?}");
        assert_eq!(info.active, 0);
        solve(&mut ws, &h, &c, &[-10.0, 0.5], &[10.0, 0.5], &mut x).unwrap();
        assert!(close(x, [1.0, 0.5]), "{x:?}");
        assert_eq!(x[1], 0.5, "a fixed variable is exactly its value");
        let info = solve(&mut ws, &h, &c, &[-10.0, -1.0], &[0.25, 1.0], &mut x).unwrap();
        assert_eq!(x, [0.25, 1.0], "both held exactly at their bounds");
        assert_eq!(info.active, 2);
    }

    #[test]
    fn bad_bounds_and_indefinite_matrices_are_errors() {
        let mut ws = BoxQpWorkspace::new();
        let mut x = [0.0; 2];
        let h = [1.0, 0.0, 0.0, 1.0];
        let e = solve(&mut ws, &h, &[0.0; 2], &[0.0, 1.0], &[1.0, 0.0], &mut x).unwrap_err();
        assert!(e.to_string().contains("box constraint 1"), "{e}");
        let e = solve(&mut ws, &h, &[0.0; 2], &[f64::NAN, 0.0], &[1.0; 2], &mut x).unwrap_err();
        assert!(e.is_invalid_input(), "{e}");
        let h = [1.0, 0.0, 0.0, -1.0];
        let e = solve(&mut ws, &h, &[0.0; 2], &[-1.0; 2], &[1.0; 2], &mut x).unwrap_err();
        assert!(matches!(e, SolveError::Numerical(_)), "{e}");
    }
}
