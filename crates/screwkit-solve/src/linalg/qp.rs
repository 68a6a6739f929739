//! Strictly convex quadratic programs with bounds and general inequality rows, small and dense:
//!
//! ```text
//! minimise ½ xᵀ H x + cᵀ x   subject to   l ≤ x ≤ u,   G x ≥ h,
//! ```
//!
//! H symmetric positive definite (n × n, row-major, the lower triangle read), G m × n row-major,
//! l_i ∈ [−∞, ∞), u_i ∈ (−∞, ∞]. This is an IK step that keeps clear of contact: the
//! least-squares step under the joint limits ([`super::box_qp`]'s problem) with one row per
//! close pair of shapes, nᵀ(J_b − J_a) x ≥ −γ (d − margin).
//!
//! **Method**: the dual active-set method of Goldfarb and Idnani ("A numerically stable dual
//! method for solving strictly convex quadratic programs", *Math. Programming* 27, 1983), the
//! method of quadprog and eiquadprog. It starts from the unconstrained minimum x = −H⁻¹c (so it
//! needs no feasible start: a configuration already too close to an obstacle, whose row asks
//! to move away, is a start like any other) and adds one violated constraint at a time (the
//! most violated), dropping active ones whose multiplier would turn negative; the dual
//! objective rises strictly, so no active set repeats and the method ends. It keeps
//! J = L⁻ᵀ Q (L Lᵀ = H; Q orthogonal) and the upper-triangular R with Jᵀ N_A = [R; 0] (N_A
//! the active constraints' normals), updated by Givens rotations as a constraint joins
//! (O(n²)) or leaves (O(n q)). A bound is a constraint whose normal is ±e_i: Jᵀ e_i is row i
//! of J, read, not multiplied.
//!
//! Infeasible constraints (no x meets them all) are reported as such
//! ([`SolveError::Numerical`] naming the constraint), never a silent wrong x. At the end the
//! KKT conditions hold to rounding (tested, with the optimum of every active set enumerated by
//! brute force on small problems as the oracle, and [`super::box_qp`] on bounds only).

// Dense linear algebra on flat row-major buffers: indices read as the formulas do.
#![allow(clippy::needless_range_loop)]

use crate::error::SolveError;

/// Which constraint: the lower or upper bound of a variable, or a general row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Constraint {
    Lower(usize),
    Upper(usize),
    Row(usize),
}

/// Reusable scratch for problems of up to the size it has grown to (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub struct QpWorkspace {
    /// J = L⁻ᵀ Q stored by columns (row a of this buffer is J's column a: every update and
    /// product below then runs over contiguous memory).
    j: Vec<f64>,
    /// R, upper triangular, n × n row-major (its leading q × q block used).
    r: Vec<f64>,
    /// The active constraints, in R's column order.
    active: Vec<Constraint>,
    /// Their multipliers.
    u: Vec<f64>,
    /// Jᵀ n_p, the primal direction z, the dual direction r = R⁻¹ d₁.
    d: Vec<f64>,
    z: Vec<f64>,
    rd: Vec<f64>,
    /// Whether each bound or row is active (lower bounds, upper bounds, rows).
    is_active: Vec<bool>,
}

impl QpWorkspace {
    /// An empty workspace (it grows on first use).
    pub fn new() -> Self {
        Self::default()
    }

    fn fit(&mut self, n: usize, m: usize) {
        self.j.resize(n * n, 0.0);
        self.r.resize(n * n, 0.0);
        self.d.resize(n, 0.0);
        self.z.resize(n, 0.0);
        self.rd.resize(n, 0.0);
        self.active.clear();
        self.u.clear();
        self.is_active.clear();
        self.is_active.resize(2 * n + m, false);
    }

    /// The multipliers of the active constraints of the last solve: (lower bounds, upper
    /// bounds, rows), each ≥ 0 and 0 where the constraint is inactive.
    pub fn multipliers(&self, n: usize, m: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (mut lo, mut up, mut rows) = (vec![0.0; n], vec![0.0; n], vec![0.0; m]);
        for (c, u) in self.active.iter().zip(&self.u) {
            match *c {
                Constraint::Lower(i) => lo[i] = *u,
                Constraint::Upper(i) => up[i] = *u,
                Constraint::Row(k) => rows[k] = *u,
            }
        }
        (lo, up, rows)
    }
}

/// What a solve did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct QpInfo {
    /// Constraints added or dropped.
    pub iterations: usize,
    /// Constraints active at the solution.
    pub active: usize,
}

/// The problem's data, borrowed.
struct Problem<'a> {
    n: usize,
    l: &'a [f64],
    u: &'a [f64],
    g: &'a [f64],
    h: &'a [f64],
}

impl Problem<'_> {
    /// The constraint's slack at x: nᵀx − b (≥ 0 when met).
    fn slack(&self, c: Constraint, x: &[f64]) -> f64 {
        match c {
            Constraint::Lower(i) => x[i] - self.l[i],
            Constraint::Upper(i) => self.u[i] - x[i],
            Constraint::Row(k) => dot(&self.g[k * self.n..(k + 1) * self.n], x) - self.h[k],
        }
    }

    /// nᵀ v.
    fn normal_dot(&self, c: Constraint, v: &[f64]) -> f64 {
        match c {
            Constraint::Lower(i) => v[i],
            Constraint::Upper(i) => -v[i],
            Constraint::Row(k) => dot(&self.g[k * self.n..(k + 1) * self.n], v),
        }
    }

    fn index(&self, c: Constraint) -> usize {
        match c {
            Constraint::Lower(i) => i,
            Constraint::Upper(i) => self.n + i,
            Constraint::Row(k) => 2 * self.n + k,
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves the QP of the module documentation into `x` (length n). `hm` is H (n × n row-major,
/// lower triangle read), `c`, `l`, `u` of length n, `g` the m rows of G (m × n row-major) and
/// `h` their bounds (length m).
///
/// Errors: bad bounds (l_i > u_i, NaN, l_i = +∞ or u_i = −∞) or a non-finite row
/// (`InvalidInput`, naming it); H not positive definite or constraints that no x meets
/// (`Numerical`, naming the constraint that could not be met).
#[allow(clippy::too_many_arguments)]
pub fn solve(
    ws: &mut QpWorkspace,
    hm: &[f64],
    c: &[f64],
    l: &[f64],
    u: &[f64],
    g: &[f64],
    h: &[f64],
    x: &mut [f64],
) -> Result<QpInfo, SolveError> {
    let n = c.len();
    let m = h.len();
    debug_assert!(hm.len() == n * n && l.len() == n && u.len() == n && x.len() == n);
    debug_assert!(g.len() == m * n);
    super::box_qp::check_bounds(l, u)?;
    if let Some(k) =
        (0..m).find(|&k| !h[k].is_finite() || g[k * n..(k + 1) * n].iter().any(|v| !v.is_finite()))
    {
        return Err(SolveError::InvalidInput(format!(
            "inequality row {k} is not finite"
        )));
    }
    ws.fit(n, m);
    factor(ws, hm, n)?;
    // x = −H⁻¹ c = −J Jᵀ c.
    for a in 0..n {
        ws.d[a] = dot(&ws.j[a * n..(a + 1) * n], c);
    }
    for i in 0..n {
        x[i] = -(0..n).map(|a| ws.j[a * n + i] * ws.d[a]).sum::<f64>();
    }
    let p = Problem { n, l, u, g, h };
    // Tolerance of a slack: rounding of the constraints' terms.
    let scale = x.iter().fold(1.0_f64, |s, v| s.max(v.abs()))
        + l.iter()
            .chain(u)
            .chain(h)
            .filter(|v| v.is_finite())
            .fold(0.0_f64, |s, v| s.max(v.abs()));
    let tol = 1e-12 * scale;
    let cap = 10 * (2 * n + m) + 100;
    let mut iterations = 0;
    loop {
        // Step 1: the most violated constraint, if any.
        let mut worst: Option<(Constraint, f64)> = None;
        let candidates = (0..n)
            .flat_map(|i| [Constraint::Lower(i), Constraint::Upper(i)])
            .chain((0..m).map(Constraint::Row));
        for cst in candidates {
            if ws.is_active[p.index(cst)] {
                continue;
            }
            if let Constraint::Lower(i) = cst {
                if l[i] == f64::NEG_INFINITY {
                    continue;
                }
            }
            if let Constraint::Upper(i) = cst {
                if u[i] == f64::INFINITY {
                    continue;
                }
            }
            let s = p.slack(cst, x);
            if s < -tol && worst.is_none_or(|w| s < w.1) {
                worst = Some((cst, s));
            }
        }
        let Some((np, mut s)) = worst else {
            return Ok(QpInfo {
                iterations,
                active: ws.active.len(),
            });
        };
        let mut u_plus = 0.0;
        // Step 2: move until np is met, dropping constraints whose multipliers reach 0.
        loop {
            iterations += 1;
            if iterations > cap {
                return Err(SolveError::Numerical(format!(
                    "the QP did not finish in {cap} active-set changes"
                )));
            }
            let q = ws.active.len();
            // d = Jᵀ n_p.
            match np {
                Constraint::Lower(i) => {
                    for a in 0..n {
                        ws.d[a] = ws.j[a * n + i];
                    }
                }
                Constraint::Upper(i) => {
                    for a in 0..n {
                        ws.d[a] = -ws.j[a * n + i];
                    }
                }
                Constraint::Row(k) => {
                    let row = &g[k * n..(k + 1) * n];
                    for a in 0..n {
                        ws.d[a] = dot(&ws.j[a * n..(a + 1) * n], row);
                    }
                }
            }
            // z = J₂ d₂, r = R⁻¹ d₁.
            ws.z.fill(0.0);
            for a in q..n {
                let da = ws.d[a];
                for (z, j) in ws.z.iter_mut().zip(&ws.j[a * n..(a + 1) * n]) {
                    *z += da * j;
                }
            }
            for a in (0..q).rev() {
                let mut v = ws.d[a];
                for b in a + 1..q {
                    v -= ws.r[a * n + b] * ws.rd[b];
                }
                ws.rd[a] = v / ws.r[a * n + a];
            }
            // Step lengths: t1 (partial: an active multiplier reaches 0), t2 (full: np met).
            let mut t1 = f64::INFINITY;
            let mut k_drop = usize::MAX;
            for a in 0..q {
                if ws.rd[a] > 0.0 {
                    let t = ws.u[a] / ws.rd[a];
                    if t < t1 {
                        t1 = t;
                        k_drop = a;
                    }
                }
            }
            let zn = p.normal_dot(np, &ws.z);
            let z_norm = ws.z.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            let d_norm = ws.d.iter().fold(0.0_f64, |s, v| s.max(v.abs()));
            let t2 = if z_norm > 1e-14 * d_norm.max(f64::MIN_POSITIVE) && zn > 0.0 {
                -s / zn
            } else {
                f64::INFINITY
            };
            let t = t1.min(t2);
            if t == f64::INFINITY {
                return Err(SolveError::Numerical(format!(
                    "the constraints cannot all be met ({})",
                    describe(np)
                )));
            }
            for a in 0..q {
                ws.u[a] -= t * ws.rd[a];
            }
            u_plus += t;
            if t2.is_finite() {
                for i in 0..n {
                    x[i] += t * ws.z[i];
                }
            }
            if t == t2 {
                add(ws, n, np, u_plus)?;
                let idx = p.index(np);
                ws.is_active[idx] = true;
                break;
            }
            // Partial step: drop the constraint whose multiplier reached 0.
            let dropped = ws.active[k_drop];
            ws.is_active[p.index(dropped)] = false;
            drop_active(ws, n, k_drop);
            s = p.slack(np, x);
        }
    }
}

/// What a constraint is, in words.
fn describe(c: Constraint) -> String {
    match c {
        Constraint::Lower(i) => format!("the lower bound of variable {i}"),
        Constraint::Upper(i) => format!("the upper bound of variable {i}"),
        Constraint::Row(k) => format!("inequality row {k}"),
    }
}

/// L Lᵀ = H (lower triangle of `hm`), then J = L⁻ᵀ into `ws.j` (by columns: row a of the
/// buffer is row a of L⁻¹).
fn factor(ws: &mut QpWorkspace, hm: &[f64], n: usize) -> Result<(), SolveError> {
    // L into ws.r (row-major, lower triangle) as scratch.
    let lm = &mut ws.r;
    lm.fill(0.0);
    for i in 0..n {
        for k in 0..=i {
            let (row_i, row_k) = (&lm[i * n..i * n + k], &lm[k * n..k * n + k]);
            let v = hm[i * n + k] - dot(row_i, row_k);
            if i == k {
                if v.is_nan() || v <= 0.0 {
                    return Err(SolveError::Numerical(format!(
                        "the QP's matrix is not positive definite (pivot {v:e} at variable {i})"
                    )));
                }
                lm[i * n + i] = v.sqrt();
            } else {
                lm[i * n + k] = v / lm[k * n + k];
            }
        }
    }
    // Row i of L⁻¹ = (e_i − Σ_{a<i} L_ia (row a of L⁻¹)) / L_ii: contiguous row updates.
    let j = &mut ws.j;
    j.fill(0.0);
    for i in 0..n {
        let (done, rest) = j.split_at_mut(i * n);
        let row = &mut rest[..n];
        row[i] = 1.0;
        for a in 0..i {
            let f = lm[i * n + a];
            if f != 0.0 {
                for (x, y) in row[..=a].iter_mut().zip(&done[a * n..a * n + a + 1]) {
                    *x -= f * y;
                }
            }
        }
        let inv = 1.0 / lm[i * n + i];
        for x in row[..=i].iter_mut() {
            *x *= inv;
        }
    }
    lm.fill(0.0);
    Ok(())
}

/// A Givens rotation (c, s) taking (a, b) to (√(a² + b²), 0).
fn givens(a: f64, b: f64) -> (f64, f64, f64) {
    let h = a.hypot(b);
    if h == 0.0 {
        (1.0, 0.0, 0.0)
    } else {
        (a / h, b / h, h)
    }
}

/// Rotates columns a < b of J (rows of the buffer): J_a ← c J_a + s J_b, J_b ← −s J_a + c J_b.
fn rotate_columns(j: &mut [f64], n: usize, a: usize, b: usize, c: f64, s: f64) {
    let (first, second) = j.split_at_mut(b * n);
    let (ja, jb) = (&mut first[a * n..(a + 1) * n], &mut second[..n]);
    for (x, y) in ja.iter_mut().zip(jb.iter_mut()) {
        let (u, v) = (*x, *y);
        *x = c * u + s * v;
        *y = -s * u + c * v;
    }
}

/// Adds constraint `np` (with `ws.d` = Jᵀ n_p) to the active set with multiplier `mult`: a
/// reflection zeroes d below position q, and d's first q + 1 entries become R's new column.
/// (`ws.z` and `ws.rd` are scratch here: the step's directions are recomputed after.)
fn add(ws: &mut QpWorkspace, n: usize, np: Constraint, mult: f64) -> Result<(), SolveError> {
    let q = ws.active.len();
    // One Householder reflection H = I − β v vᵀ takes d[q..n] to (α, 0, …, 0); J's columns
    // q..n become J₂ H (each column a: J_a − β v_a Σ_b v_b J_b).
    let tail = &ws.d[q..n];
    let norm = tail.iter().map(|x| x * x).sum::<f64>().sqrt();
    if n - q > 1 && norm > 0.0 {
        let alpha = if tail[0] > 0.0 { -norm } else { norm };
        ws.z[..n - q].copy_from_slice(tail);
        ws.z[0] -= alpha;
        let vv: f64 = ws.z[..n - q].iter().map(|x| x * x).sum();
        if vv > 0.0 {
            let beta = 2.0 / vv;
            ws.rd.iter_mut().for_each(|x| *x = 0.0);
            for (b, &vb) in ws.z[..n - q].iter().enumerate() {
                let col = &ws.j[(q + b) * n..(q + b + 1) * n];
                for (w, c) in ws.rd.iter_mut().zip(col) {
                    *w += vb * c;
                }
            }
            for (b, &vb) in ws.z[..n - q].iter().enumerate() {
                let f = beta * vb;
                let col = &mut ws.j[(q + b) * n..(q + b + 1) * n];
                for (c, w) in col.iter_mut().zip(&ws.rd) {
                    *c -= f * w;
                }
            }
            ws.d[q] = alpha;
            ws.d[q + 1..n].iter_mut().for_each(|x| *x = 0.0);
        }
    }
    if ws.d[q].abs() <= 1e-14 * ws.d.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs())) {
        return Err(SolveError::Numerical(format!(
            "the active constraints are dependent at {}",
            describe(np)
        )));
    }
    for a in 0..=q {
        ws.r[a * n + q] = ws.d[a];
    }
    ws.active.push(np);
    ws.u.push(mult);
    Ok(())
}

/// Drops active constraint `k` (its column of R): the columns after it move left, and
/// rotations of rows (a, a + 1) of R, and of columns (a, a + 1) of J, make R triangular again.
fn drop_active(ws: &mut QpWorkspace, n: usize, k: usize) {
    let q = ws.active.len();
    for col in k..q - 1 {
        for a in 0..=col + 1 {
            ws.r[a * n + col] = ws.r[a * n + col + 1];
        }
    }
    for a in 0..q {
        ws.r[a * n + q - 1] = 0.0;
    }
    for a in k..q - 1 {
        let (c, s, h) = givens(ws.r[a * n + a], ws.r[(a + 1) * n + a]);
        ws.r[a * n + a] = h;
        ws.r[(a + 1) * n + a] = 0.0;
        for col in a + 1..q - 1 {
            let (x, y) = (ws.r[a * n + col], ws.r[(a + 1) * n + col]);
            ws.r[a * n + col] = c * x + s * y;
            ws.r[(a + 1) * n + col] = -s * x + c * y;
        }
        rotate_columns(&mut ws.j, n, a, a + 1, c, s);
    }
    ws.active.remove(k);
    ws.u.remove(k);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::SplitMix64;

    fn uni(rng: &mut SplitMix64, a: f64, b: f64) -> f64 {
        a + (b - a) * rng.uniform()
    }

    /// A random SPD matrix AᵀA + δI (n × n) and vector.
    fn problem(rng: &mut SplitMix64, n: usize) -> (Vec<f64>, Vec<f64>) {
        let mut a = vec![0.0; (n + 2) * n];
        for v in &mut a {
            *v = uni(rng, -1.0, 1.0);
        }
        let mut h = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                h[i * n + j] = (0..n + 2).map(|k| a[k * n + i] * a[k * n + j]).sum::<f64>()
                    + if i == j { 0.05 } else { 0.0 };
            }
        }
        let c = (0..n).map(|_| uni(rng, -2.0, 2.0)).collect();
        (h, c)
    }

    /// Solves H_AA-type equality QPs by Gaussian elimination: the KKT system
    /// [H −Nᵀ; N 0] [x; λ] = [−c; b] for the constraints in `set` (normals N, bounds b).
    fn equality_qp(
        h: &[f64],
        c: &[f64],
        normals: &[Vec<f64>],
        b: &[f64],
    ) -> Option<(Vec<f64>, Vec<f64>)> {
        let n = c.len();
        let k = normals.len();
        let size = n + k;
        let mut m = vec![0.0; size * (size + 1)];
        let w = size + 1;
        for i in 0..n {
            for j in 0..n {
                m[i * w + j] = h[i * n + j];
            }
            for (a, nr) in normals.iter().enumerate() {
                m[i * w + n + a] = -nr[i];
                m[(n + a) * w + i] = nr[i];
            }
            m[i * w + size] = -c[i];
        }
        for a in 0..k {
            m[(n + a) * w + size] = b[a];
        }
        for col in 0..size {
            let piv = (col..size)
                .max_by(|&x, &y| m[x * w + col].abs().total_cmp(&m[y * w + col].abs()))?;
            if m[piv * w + col].abs() < 1e-12 {
                return None;
            }
            for j in 0..w {
                m.swap(col * w + j, piv * w + j);
            }
            for r in 0..size {
                if r != col {
                    let f = m[r * w + col] / m[col * w + col];
                    for j in col..w {
                        m[r * w + j] -= f * m[col * w + j];
                    }
                }
            }
        }
        let sol: Vec<f64> = (0..size).map(|r| m[r * w + size] / m[r * w + r]).collect();
        Some((sol[..n].to_vec(), sol[n..].to_vec()))
    }

    /// The optimum by brute force: every subset of the constraints taken as equalities; the
    /// one whose x is feasible and whose multipliers are ≥ 0 is the KKT point (unique for a
    /// strictly convex QP).
    fn brute_force(h: &[f64], c: &[f64], cons: &[(Vec<f64>, f64)]) -> Option<Vec<f64>> {
        let k = cons.len();
        for mask in 0u32..(1 << k) {
            let set: Vec<usize> = (0..k).filter(|i| mask & (1 << i) != 0).collect();
            let normals: Vec<Vec<f64>> = set.iter().map(|&i| cons[i].0.clone()).collect();
            let b: Vec<f64> = set.iter().map(|&i| cons[i].1).collect();
            let Some((x, lambda)) = equality_qp(h, c, &normals, &b) else {
                continue;
            };
            let feasible = cons.iter().all(|(nr, bb)| dot(nr, &x) - bb >= -1e-9);
            if feasible && lambda.iter().all(|&v| v >= -1e-9) {
                return Some(x);
            }
        }
        None
    }

    #[test]
    fn equals_the_enumerated_optimum() {
        let mut rng = SplitMix64(7);
        let (mut infeasible, mut rows_active) = (0, 0);
        for trial in 0..400 {
            let n = 1 + trial % 4;
            let m = trial % 3;
            let (hm, c) = problem(&mut rng, n);
            let mut l = vec![f64::NEG_INFINITY; n];
            let mut u = vec![f64::INFINITY; n];
            for i in 0..n {
                if uni(&mut rng, 0.0, 1.0) < 0.6 {
                    l[i] = uni(&mut rng, -1.0, 0.2);
                }
                if uni(&mut rng, 0.0, 1.0) < 0.6 {
                    u[i] = l[i].max(-1.0) + uni(&mut rng, 0.0, 1.5);
                }
            }
            let g: Vec<f64> = (0..m * n).map(|_| uni(&mut rng, -1.0, 1.0)).collect();
            let hv: Vec<f64> = (0..m).map(|_| uni(&mut rng, -0.5, 0.8)).collect();
            let mut cons: Vec<(Vec<f64>, f64)> = Vec::new();
            for i in 0..n {
                let mut e = vec![0.0; n];
                e[i] = 1.0;
                if l[i].is_finite() {
                    cons.push((e.clone(), l[i]));
                }
                if u[i].is_finite() {
                    cons.push((e.iter().map(|v| -v).collect(), -u[i]));
                }
            }
            for k in 0..m {
                cons.push((g[k * n..(k + 1) * n].to_vec(), hv[k]));
            }
            let oracle = brute_force(&hm, &c, &cons);
            let mut ws = QpWorkspace::new();
            let mut x = vec![0.0; n];
            let got = solve(&mut ws, &hm, &c, &l, &u, &g, &hv, &mut x);
            match (oracle, got) {
                (Some(want), Ok(_)) => {
                    for i in 0..n {
                        assert!(
                            (x[i] - want[i]).abs() < 1e-9,
                            "trial {trial}: {x:?} vs {want:?}"
                        );
                    }
                    // KKT: H x + c = Σ λ n with λ ≥ 0 on active constraints.
                    let (lo, up, rows) = ws.multipliers(n, m);
                    for i in 0..n {
                        let grad: f64 = (0..n).map(|j| hm[i * n + j] * x[j]).sum::<f64>() + c[i];
                        let pull =
                            lo[i] - up[i] + (0..m).map(|k| rows[k] * g[k * n + i]).sum::<f64>();
                        assert!((grad - pull).abs() < 1e-9, "trial {trial}: stationarity");
                    }
                    assert!(lo.iter().chain(&up).chain(&rows).all(|&v| v >= -1e-12));
                    rows_active += usize::from(rows.iter().any(|&v| v > 0.0));
                }
                (None, Err(SolveError::Numerical(_))) => infeasible += 1,
                (want, got) => panic!("trial {trial}: oracle {want:?}, solver {got:?} {x:?}"),
            }
        }
        // Both kinds occur.
        assert!(infeasible > 5 && infeasible < 200, "{infeasible}");
        assert!(rows_active > 50, "{rows_active}");
    }

    /// Larger problems (whole-body sized, n up to 40 with 12 rows): the KKT conditions hold
    /// at the answer — feasible, H x + c = Σ λ n, λ ≥ 0, λ = 0 on every slack constraint.
    #[test]
    fn large_problems_meet_the_kkt_conditions() {
        let mut rng = SplitMix64(5);
        let mut solved = 0;
        for trial in 0..60 {
            let n = 10 + trial % 31;
            let m = trial % 13;
            let (hm, c) = problem(&mut rng, n);
            let l: Vec<f64> = (0..n).map(|_| uni(&mut rng, -1.0, -0.05)).collect();
            let u: Vec<f64> = (0..n).map(|_| uni(&mut rng, 0.05, 1.0)).collect();
            let g: Vec<f64> = (0..m * n).map(|_| uni(&mut rng, -1.0, 1.0)).collect();
            // Bounds the origin meets: a feasible problem.
            let hv: Vec<f64> = (0..m).map(|_| uni(&mut rng, -0.5, 0.0)).collect();
            let mut ws = QpWorkspace::new();
            let mut x = vec![0.0; n];
            solve(&mut ws, &hm, &c, &l, &u, &g, &hv, &mut x).unwrap();
            let (lo, up, rows) = ws.multipliers(n, m);
            for i in 0..n {
                assert!(x[i] >= l[i] - 1e-12 && x[i] <= u[i] + 1e-12);
                let grad: f64 = (0..n).map(|j| hm[i * n + j] * x[j]).sum::<f64>() + c[i];
                let pull = lo[i] - up[i] + (0..m).map(|k| rows[k] * g[k * n + i]).sum::<f64>();
                assert!(
                    (grad - pull).abs() < 1e-9,
                    "trial {trial}: stationarity {grad} {pull}"
                );
                assert!(lo[i] == 0.0 || (x[i] - l[i]).abs() < 1e-12);
                assert!(up[i] == 0.0 || (x[i] - u[i]).abs() < 1e-12);
            }
            for k in 0..m {
                let slack = dot(&g[k * n..(k + 1) * n], &x) - hv[k];
                assert!(slack >= -1e-12 && (rows[k] == 0.0 || slack.abs() < 1e-10));
            }
            assert!(lo.iter().chain(&up).chain(&rows).all(|&v| v >= 0.0));
            solved += usize::from(rows.iter().any(|&v| v > 0.0));
        }
        assert!(solved > 10, "{solved}");
    }

    #[test]
    fn bounds_alone_equal_the_box_qp() {
        let mut rng = SplitMix64(11);
        for _ in 0..200 {
            let n = 6;
            let (hm, c) = problem(&mut rng, n);
            let l: Vec<f64> = (0..n).map(|_| uni(&mut rng, -1.0, 0.0)).collect();
            let u: Vec<f64> = l.iter().map(|v| v + uni(&mut rng, 0.0, 1.0)).collect();
            let (mut x, mut y) = (vec![0.0; n], vec![0.0; n]);
            solve(&mut QpWorkspace::new(), &hm, &c, &l, &u, &[], &[], &mut x).unwrap();
            crate::linalg::box_qp::solve(&mut Default::default(), &hm, &c, &l, &u, &mut y).unwrap();
            for i in 0..n {
                assert!((x[i] - y[i]).abs() < 1e-10, "{x:?} vs {y:?}");
            }
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let h = [1.0];
        let mut x = [0.0];
        let mut ws = QpWorkspace::new();
        assert!(matches!(
            solve(&mut ws, &h, &[0.0], &[1.0], &[0.0], &[], &[], &mut x),
            Err(SolveError::InvalidInput(_))
        ));
        assert!(matches!(
            solve(
                &mut ws,
                &h,
                &[0.0],
                &[0.0],
                &[1.0],
                &[f64::NAN],
                &[0.0],
                &mut x
            ),
            Err(SolveError::InvalidInput(_))
        ));
        assert!(matches!(
            solve(&mut ws, &[-1.0], &[0.0], &[0.0], &[1.0], &[], &[], &mut x),
            Err(SolveError::Numerical(_))
        ));
        // x ≥ 2 under x ≤ 1: infeasible, named.
        let e = solve(&mut ws, &h, &[0.0], &[0.0], &[1.0], &[1.0], &[2.0], &mut x).unwrap_err();
        assert!(e.to_string().contains("cannot all be met"), "{e}");
    }
}
