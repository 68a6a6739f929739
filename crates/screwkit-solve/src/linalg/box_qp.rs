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
//! Cholesky factorisation of H_FF (factored once, then updated as one variable joins or leaves
//! F: O(n²) per iteration); if y is feasible it is taken and the multipliers of the held
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
//! reference solver). Two reductions keep it fast on whole-body steps: a variable whose row of
//! H has no off-diagonal entry (a joint no task moves) is a 1-D problem, clamp(−c_i / H_ii),
//! solved apart; and the Cholesky factor is updated, not rebuilt, as the working set changes
//! (a Givens sweep when a variable is held, one triangular solve when it is released).
//! Why this and not a general QP crate (measured, BENCHMARKS.md, TALOS n = 32): an
//! interior-point solver (Clarabel, OSQP through qpsolvers) takes about 1 ms for the QP alone
//! and answers to its tolerance (2e-3 off the exact optimum here); a dense active set in C
//! (DAQP) takes 40–59 µs for the QP alone from Python, while the whole step here (Jacobians
//! included) takes 9–10 µs and is exact. A general inequality row (self-collision avoidance: a
//! distance's gradient times v above a bound) needs a
//! general QP; it would enter here as a new constraint kind beside the box.

use super::dot;
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
    /// H with both triangles (from the caller's lower one): contiguous rows.
    full: Vec<f64>,
    /// x on the held variables, 0 on the free ones.
    held_x: Vec<f64>,
    /// L with L Lᵀ = H_FF, the free variables in the order of `order` (row stride n).
    chol: Vec<f64>,
    /// The free variables, in the factor's order.
    order: Vec<usize>,
    /// Whether a variable's row of H has an off-diagonal entry (the others are 1-D problems).
    coupled: Vec<bool>,
    /// 1 / L_aa (multiplications in place of divisions on the factor's dependency chains).
    inv: Vec<f64>,
    rhs: Vec<f64>,
    y: Vec<f64>,
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
            self.full.resize(n * n, 0.0);
            self.held_x.resize(n, 0.0);
            self.inv.resize(n, 0.0);
            self.coupled.resize(n, false);
            self.rhs.resize(n, 0.0);
            self.y.resize(n, 0.0);
            self.held.resize(n, Held::Free);
        }
        self.order.clear();
    }

    /// Which bound each variable was held at in the last solve.
    pub fn held(&self) -> &[Held] {
        &self.held
    }
}

/// What a solve did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoxQpInfo {
    /// Active-set iterations (one solve with the factor each).
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
    let mut full = std::mem::take(&mut ws.full);
    ws.coupled.fill(false);
    for i in 0..n {
        for j in 0..i {
            let v = h[i * n + j];
            full[i * n + j] = v;
            full[j * n + i] = v;
            if v != 0.0 {
                ws.coupled[i] = true;
                ws.coupled[j] = true;
            }
        }
        full[i * n + i] = h[i * n + i];
    }
    let result = solve_symmetric(ws, &full, c, l, u, x);
    ws.full = full;
    result
}

/// [`solve`] with both triangles of H.
fn solve_symmetric(
    ws: &mut BoxQpWorkspace,
    h: &[f64],
    c: &[f64],
    l: &[f64],
    u: &[f64],
    x: &mut [f64],
) -> Result<BoxQpInfo, SolveError> {
    let n = c.len();
    check_bounds(l, u)?;
    for i in 0..n {
        x[i] = 0.0_f64.clamp(l[i], u[i]);
        ws.held[i] = if l[i] == u[i] {
            Held::Lower
        } else {
            Held::Free
        };
    }
    // A variable no other one is coupled to (a joint no task moves: only its posture and
    // damping terms) is a 1-D problem, x_i = clamp(−c_i / H_ii); the active set works on the
    // rest (their rows of H do not see these).
    for i in 0..n {
        if ws.coupled[i] || l[i] == u[i] {
            continue;
        }
        let d = h[i * n + i];
        if d.is_nan() || d <= 0.0 {
            return Err(SolveError::Numerical(format!(
                "the QP's matrix is not positive definite (pivot {d:e} at variable {i})"
            )));
        }
        let y = -c[i] / d;
        (x[i], ws.held[i]) = if y < l[i] {
            (l[i], Held::Lower)
        } else if y > u[i] {
            (u[i], Held::Upper)
        } else {
            (y, Held::Free)
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
    refactor(ws, h, n)?;
    solve_free(ws, h, c, x);
    let mut changed = 0;
    for i in 0..n {
        if ws.held[i] != Held::Free || !ws.coupled[i] {
            continue;
        }
        let y = ws.y[i];
        if y < l[i] {
            ws.held[i] = Held::Lower;
            x[i] = l[i];
            changed += 1;
        } else if y > u[i] {
            ws.held[i] = Held::Upper;
            x[i] = u[i];
            changed += 1;
        } else {
            x[i] = y;
        }
    }
    if changed > 0 {
        refactor(ws, h, n)?;
    }
    let max_iterations = 4 * n + 20;
    for iteration in 1..=max_iterations {
        solve_free(ws, h, c, x);
        // The largest step towards y within the box.
        let (mut alpha, mut block) = (1.0_f64, None);
        for &i in &ws.order {
            let (y, d) = (ws.y[i], ws.y[i] - x[i]);
            let (bound, side) = if y < l[i] {
                (l[i], Held::Lower)
            } else if y > u[i] {
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
                for &i in &ws.order {
                    x[i] += alpha * (ws.y[i] - x[i]);
                    x[i] = x[i].clamp(l[i], u[i]);
                }
                x[b] = bound;
                ws.held[b] = side;
                hold(ws, h, n, b)?;
            }
            None => {
                for &i in &ws.order {
                    x[i] = ws.y[i];
                }
                // The held variables' multipliers; release the most violated.
                let mut worst = (tol, None);
                for i in 0..n {
                    if ws.held[i] == Held::Free || l[i] == u[i] || !ws.coupled[i] {
                        continue;
                    }
                    let g = gradient(h, c, x, i);
                    let violation = if ws.held[i] == Held::Lower { -g } else { g };
                    if violation > worst.0 {
                        worst = (violation, Some(i));
                    }
                }
                match worst.1 {
                    Some(i) => {
                        ws.held[i] = Held::Free;
                        release(ws, h, n, i)?;
                    }
                    None => {
                        return Ok(BoxQpInfo {
                            iterations: iteration,
                            active: ws.held.iter().filter(|s| **s != Held::Free).count(),
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

/// (H x + c)_i (H with both triangles).
#[inline]
/// Bounds l ≤ u, none NaN, l < +∞, u > −∞: an error naming the first empty one.
pub(crate) fn check_bounds(l: &[f64], u: &[f64]) -> Result<(), SolveError> {
    for (i, (&lo, &hi)) in l.iter().zip(u).enumerate() {
        if lo.is_nan() || hi.is_nan() || lo > hi || lo == f64::INFINITY || hi == f64::NEG_INFINITY {
            return Err(SolveError::InvalidInput(format!(
                "box constraint {i}: the bounds [{lo}, {hi}] are empty"
            )));
        }
    }
    Ok(())
}

fn gradient(h: &[f64], c: &[f64], x: &[f64], i: usize) -> f64 {
    let n = c.len();
    c[i] + dot(&h[i * n..i * n + n], x)
}

/// The factor from scratch: `order` = the free variables, L Lᵀ = H_FF row by row.
fn refactor(ws: &mut BoxQpWorkspace, h: &[f64], n: usize) -> Result<(), SolveError> {
    let BoxQpWorkspace {
        chol,
        order,
        held,
        inv,
        coupled,
        ..
    } = ws;
    order.clear();
    order.extend((0..n).filter(|&i| held[i] == Held::Free && coupled[i]));
    for a in 0..order.len() {
        for b in 0..=a {
            let s =
                h[order[a] * n + order[b]] - dot(&chol[a * n..a * n + b], &chol[b * n..b * n + b]);
            if a == b {
                if s.is_nan() || s <= 0.0 {
                    return Err(SolveError::Numerical(format!(
                        "the QP's matrix is not positive definite (pivot {s:e} at variable {})",
                        order[a]
                    )));
                }
                chol[a * n + a] = s.sqrt();
                inv[a] = 1.0 / chol[a * n + a];
            } else {
                chol[a * n + b] = s * inv[b];
            }
        }
    }
    Ok(())
}

/// y_F = H_FF⁻¹ (−c_F − H_FA x_A) with the factor (y is only written on F).
fn solve_free(ws: &mut BoxQpWorkspace, h: &[f64], c: &[f64], x: &[f64]) {
    let n = c.len();
    let BoxQpWorkspace {
        chol,
        order,
        rhs,
        y,
        held,
        held_x,
        inv,
        ..
    } = ws;
    let m = order.len();
    for j in 0..n {
        held_x[j] = if held[j] == Held::Free { 0.0 } else { x[j] };
    }
    for (a, &i) in order.iter().enumerate() {
        rhs[a] = -c[i] - dot(&h[i * n..i * n + n], held_x);
    }
    // L z = rhs by rows, then Lᵀ y = z by columns of Lᵀ (rows of L): contiguous both ways.
    for a in 0..m {
        rhs[a] = (rhs[a] - dot(&chol[a * n..a * n + a], &rhs[..a])) * inv[a];
    }
    for a in (0..m).rev() {
        let ya = rhs[a] * inv[a];
        rhs[a] = ya;
        for (r, l) in rhs[..a].iter_mut().zip(&chol[a * n..a * n + a]) {
            *r -= l * ya;
        }
    }
    for (a, &i) in order.iter().enumerate() {
        y[i] = rhs[a];
    }
}

/// Variable `i` leaves the free set: its row of L is deleted and the rows below, each with
/// one entry right of its diagonal, are made triangular again by Givens rotations of column
/// pairs (L Q Qᵀ Lᵀ = H_FF with i's row and column gone): O(m²) instead of a refactorisation
/// (which it falls back to if a pivot vanishes, reporting an H that is not positive definite).
fn hold(ws: &mut BoxQpWorkspace, h: &[f64], n: usize, i: usize) -> Result<(), SolveError> {
    let BoxQpWorkspace {
        chol, order, inv, ..
    } = &mut *ws;
    let m = order.len();
    let Some(p) = order.iter().position(|&v| v == i) else {
        return Ok(());
    };
    order.remove(p);
    for a in p..m - 1 {
        let (dst, src) = (a * n, (a + 1) * n);
        chol.copy_within(src..src + a + 2, dst);
    }
    for k in p..m - 1 {
        let (x, y) = (chol[k * n + k], chol[k * n + k + 1]);
        let r = x.hypot(y);
        if r.is_nan() || r <= 0.0 {
            return refactor(ws, h, n);
        }
        let (cs, sn) = (x / r, y / r);
        chol[k * n + k] = r;
        inv[k] = 1.0 / r;
        chol[k * n + k + 1] = 0.0;
        for a in k + 1..m - 1 {
            let (x, y) = (chol[a * n + k], chol[a * n + k + 1]);
            chol[a * n + k] = cs * x + sn * y;
            chol[a * n + k + 1] = cs * y - sn * x;
        }
    }
    Ok(())
}

/// Variable `i` joins the free set, last in the factor's order: its row of L solves
/// L z = H_F,i and its diagonal is √(H_ii − zᵀz). Where that pivot has lost most of H_ii to
/// cancellation, the factor is rebuilt from scratch instead (which reports an H that is not
/// positive definite).
fn release(ws: &mut BoxQpWorkspace, h: &[f64], n: usize, i: usize) -> Result<(), SolveError> {
    let m = ws.order.len();
    {
        let BoxQpWorkspace {
            chol, order, inv, ..
        } = &mut *ws;
        let mut zz = 0.0;
        for a in 0..m {
            let (done, new) = chol.split_at_mut(m * n);
            let z = (h[i * n + order[a]] - dot(&done[a * n..a * n + a], &new[..a])) * inv[a];
            new[a] = z;
            zz += z * z;
        }
        let d = h[i * n + i] - zz;
        if d > 1e-8 * h[i * n + i] {
            chol[m * n + m] = d.sqrt();
            inv[m] = 1.0 / chol[m * n + m];
            order.push(i);
            return Ok(());
        }
    }
    refactor(ws, h, n)
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

    /// Bounds in [−scale, 0] and [0, scale]; every `lower_free`-th lower bound (from the last of
    /// each run) and every `upper_free`-th upper bound infinite.
    fn random_bounds(
        n: usize,
        rng: &mut SplitMix64,
        scale: f64,
        lower_free: usize,
        upper_free: usize,
    ) -> (Vec<f64>, Vec<f64>) {
        let mut pick = |i: usize, every: usize, sign: f64| {
            if every != usize::MAX && i % every == every - 1 {
                sign * f64::INFINITY
            } else {
                sign * scale * rng.uniform()
            }
        };
        let l = (0..n).map(|i| pick(i, lower_free, -1.0)).collect();
        let u = (0..n).map(|i| pick(i, upper_free, 1.0)).collect();
        (l, u)
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
            let (l, u) = random_bounds(n, &mut rng, 0.5, 4, 5);
            let mut x = vec![0.0; n];
            let info = solve(&mut ws, &h, &c, &l, &u, &mut x).unwrap();
            active_seen += info.active;
            assert_kkt(&h, &c, &l, &u, &x, 1e-9, &format!("trial {trial}"));
            if n <= 4 {
                let r = reference(&h, &c, &l, &u);
                let (fx, fr) = (objective(&h, &c, &x), objective(&h, &c, &r));
                assert!(fx <= fr + 1e-9, "trial {trial}: {fx} vs reference {fr}");
            }
        }
        assert!(active_seen > 20, "the trials exercise active bounds");
    }

    /// The KKT conditions of the box QP at x, to `tol`.
    fn assert_kkt(h: &[f64], c: &[f64], l: &[f64], u: &[f64], x: &[f64], tol: f64, what: &str) {
        let n = c.len();
        for i in 0..n {
            assert!(x[i] >= l[i] && x[i] <= u[i], "{what}: x[{i}] outside");
            let g = c[i] + (0..n).map(|j| h[i * n + j] * x[j]).sum::<f64>();
            if x[i] > l[i] && x[i] < u[i] {
                assert!(g.abs() < tol, "{what}: free gradient {g} at {i}");
            } else if x[i] == l[i] && l[i] < u[i] {
                assert!(g > -tol, "{what}: lower multiplier {g} at {i}");
            } else if x[i] == u[i] && l[i] < u[i] {
                assert!(g < tol, "{what}: upper multiplier {g} at {i}");
            }
        }
    }

    /// Problems of a whole-body step's size (n up to 48) with many bounds active and
    /// ill-conditioned H: many factor updates per solve (variables joining and leaving the free
    /// set in every order), some with uncoupled variables; the answer satisfies the KKT
    /// conditions, and the objective is no worse than projected gradient descent's.
    #[test]
    fn factor_updates_on_large_problems_keep_kkt() {
        let mut rng = SplitMix64(11);
        let mut ws = BoxQpWorkspace::new();
        let mut iterations = 0;
        for trial in 0..40 {
            let n = 12 + trial % 37;
            // H = AᵀA + D with A of rank < n (a task stack) and a small D (posture, damping).
            let rank = 1 + n / 3;
            let a: Vec<f64> = (0..rank * n).map(|_| 2.0 * rng.uniform() - 1.0).collect();
            let mut h = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    h[i * n + j] = (0..rank).map(|k| a[k * n + i] * a[k * n + j]).sum::<f64>();
                }
                h[i * n + i] += 1e-4 * (1.0 + rng.uniform());
            }
            // Every third trial, some variables no task moves (no off-diagonal entries): the
            // 1-D problems solved apart from the active set.
            if trial % 3 == 0 {
                for i in (0..n).step_by(4) {
                    for j in 0..n {
                        if j != i {
                            h[i * n + j] = 0.0;
                            h[j * n + i] = 0.0;
                        }
                    }
                }
            }
            let c: Vec<f64> = (0..n).map(|_| 20.0 * rng.uniform() - 10.0).collect();
            let (l, u) = random_bounds(n, &mut rng, 0.1, usize::MAX, 7);
            let mut x = vec![0.0; n];
            let info = solve(&mut ws, &h, &c, &l, &u, &mut x).unwrap();
            iterations += info.iterations;
            assert_kkt(
                &h,
                &c,
                &l,
                &u,
                &x,
                1e-8,
                &format!("trial {trial} (n = {n})"),
            );
            if n <= 16 {
                let r = reference(&h, &c, &l, &u);
                let (fx, fr) = (objective(&h, &c, &x), objective(&h, &c, &r));
                assert!(
                    fx <= fr + 1e-9 * fr.abs().max(1.0),
                    "trial {trial}: {fx} vs {fr}"
                );
            }
        }
        assert!(
            iterations > 200,
            "the trials exercise the updates: {iterations}"
        );
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
