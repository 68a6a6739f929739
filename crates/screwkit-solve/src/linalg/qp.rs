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
//! **Split**: a variable nothing couples to another (no off-diagonal entry in its row of H, no
//! row of G using it) is its own 1-D problem, x_i = clamp(−c_i / H_ii, l_i, u_i), and the
//! method runs on the coupled rest only. A whole-body step is mostly such variables (its
//! posture and damping terms are diagonal; a frame task and the collision rows couple one
//! limb's joints): on TALOS 38 variables become about 10.
//!
//! Infeasible constraints (no x meets them all) are reported as such
//! ([`SolveError::Numerical`] naming the constraint), never a silent wrong x. At the end the
//! KKT conditions hold to rounding (tested, with the optimum of every active set enumerated by
//! brute force on small problems as the oracle, and [`super::box_qp`] on bounds only).

// Dense linear algebra on flat row-major buffers: indices read as the formulas do.
#![allow(clippy::needless_range_loop)]

use super::dot;
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
    /// The last solve's split ([`solve`]): the coupled variables' problem, and the
    /// multipliers of the variables solved apart.
    split: Split,
}

/// A problem reduced to its coupled variables (module documentation of [`solve`]).
#[derive(Debug, Clone, Default)]
struct Split {
    /// Whether the last solve was split.
    used: bool,
    /// The coupled variables, ascending: the reduced problem's variable a is `coupled[a]`.
    coupled: Vec<usize>,
    /// The reduced H, c, l, u, G and x.
    h: Vec<f64>,
    c: Vec<f64>,
    l: Vec<f64>,
    u: Vec<f64>,
    g: Vec<f64>,
    x: Vec<f64>,
    /// Each variable solved apart: (index, lower-bound multiplier, upper-bound multiplier).
    apart: Vec<(usize, f64, f64)>,
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
        let var = |i: usize| {
            if self.split.used {
                self.split.coupled[i]
            } else {
                i
            }
        };
        for (c, u) in self.active.iter().zip(&self.u) {
            match *c {
                Constraint::Lower(i) => lo[var(i)] = *u,
                Constraint::Upper(i) => up[var(i)] = *u,
                Constraint::Row(k) => rows[k] = *u,
            }
        }
        if self.split.used {
            for &(i, l, u) in &self.split.apart {
                (lo[i], up[i]) = (l, u);
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
    #[inline(always)]
    fn slack(&self, c: Constraint, x: &[f64]) -> f64 {
        match c {
            Constraint::Lower(i) => x[i] - self.l[i],
            Constraint::Upper(i) => self.u[i] - x[i],
            Constraint::Row(k) => dot(&self.g[k * self.n..(k + 1) * self.n], x) - self.h[k],
        }
    }

    /// nᵀ v.
    #[inline(always)]
    fn normal_dot(&self, c: Constraint, v: &[f64]) -> f64 {
        match c {
            Constraint::Lower(i) => v[i],
            Constraint::Upper(i) => -v[i],
            Constraint::Row(k) => dot(&self.g[k * self.n..(k + 1) * self.n], v),
        }
    }

    #[inline(always)]
    fn index(&self, c: Constraint) -> usize {
        match c {
            Constraint::Lower(i) => i,
            Constraint::Upper(i) => self.n + i,
            Constraint::Row(k) => 2 * self.n + k,
        }
    }
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
    screwkit_lie::fma::dispatch(Solve {
        ws,
        hm,
        c,
        l,
        u,
        g,
        h,
        x,
    })
}

/// [`solve`] as a kernel: its body and helpers inlined into the AVX2 clone on CPUs that have
/// it (the dense products then run four lanes wide). No multiply-add is fused and every sum
/// has a fixed order, so both clones give the same bits.
struct Solve<'a> {
    ws: &'a mut QpWorkspace,
    hm: &'a [f64],
    c: &'a [f64],
    l: &'a [f64],
    u: &'a [f64],
    g: &'a [f64],
    h: &'a [f64],
    x: &'a mut [f64],
}

impl screwkit_lie::fma::Kernel for Solve<'_> {
    type Output = Result<QpInfo, SolveError>;
    #[inline(always)]
    fn run<A: screwkit_lie::fma::MulAdd>(self) -> Self::Output {
        solve_split(self)
    }
}

/// Checks the problem, then solves apart every variable that nothing couples to another (no
/// off-diagonal entry in its row of H, no row of G using it: a joint no task or constraint
/// links to the others, x_i = clamp(−c_i / H_ii, l_i, u_i)), and the coupled ones together
/// ([`solve_in`] on H, c, l, u, G restricted to them). A whole-body step's H couples only the
/// joints its frame tasks move and its rows only the joints of the links near contact: the
/// dense method then runs on a tenth of TALOS's 38 variables.
#[inline(always)]
fn solve_split(p: Solve<'_>) -> Result<QpInfo, SolveError> {
    let Solve {
        ws,
        hm,
        c,
        l,
        u,
        g,
        h,
        x,
    } = p;
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
    let mut split = std::mem::take(&mut ws.split);
    split.coupled.clear();
    split.apart.clear();
    for i in 0..n {
        // H's lower triangle: row i left of the diagonal, column i below it.
        let linked = hm[i * n..i * n + i].iter().any(|&v| v != 0.0)
            || (i + 1..n).any(|r| hm[r * n + i] != 0.0)
            || (0..m).any(|k| g[k * n + i] != 0.0);
        if linked {
            split.coupled.push(i);
        }
    }
    let nf = split.coupled.len();
    // Nothing apart, or rows on no variable (their feasibility is the dense method's to say).
    if nf == n || (nf == 0 && m > 0) {
        split.used = false;
        ws.split = split;
        return solve_in(ws, &[], hm, c, l, u, g, h, x);
    }
    let mut held = 0;
    let mut next = 0;
    for i in 0..n {
        if split.coupled.get(next) == Some(&i) {
            next += 1;
            continue;
        }
        let hii = hm[i * n + i];
        if hii.is_nan() || hii <= 0.0 {
            ws.split = split;
            return Err(SolveError::Numerical(format!(
                "the QP's matrix is not positive definite (pivot {hii:e} at variable {i})"
            )));
        }
        let xi = (-c[i] / hii).max(l[i]).min(u[i]);
        x[i] = xi;
        let grad = hii * xi + c[i];
        let lower = if xi == l[i] && grad > 0.0 { grad } else { 0.0 };
        let upper = if xi == u[i] && grad < 0.0 { -grad } else { 0.0 };
        held += usize::from(lower > 0.0 || upper > 0.0);
        split.apart.push((i, lower, upper));
    }
    let Split {
        coupled,
        h: hr,
        c: cr,
        l: lr,
        u: ur,
        g: gr,
        x: xr,
        ..
    } = &mut split;
    hr.clear();
    for &i in coupled.iter() {
        for &j in coupled.iter() {
            hr.push(if j <= i { hm[i * n + j] } else { hm[j * n + i] });
        }
    }
    cr.clear();
    cr.extend(coupled.iter().map(|&i| c[i]));
    lr.clear();
    lr.extend(coupled.iter().map(|&i| l[i]));
    ur.clear();
    ur.extend(coupled.iter().map(|&i| u[i]));
    gr.clear();
    for k in 0..m {
        gr.extend(coupled.iter().map(|&i| g[k * n + i]));
    }
    xr.clear();
    xr.resize(nf, 0.0);
    let result = solve_in(ws, coupled, hr, cr, lr, ur, gr, h, xr);
    for (a, &i) in coupled.iter().enumerate() {
        x[i] = xr[a];
    }
    split.used = true;
    ws.split = split;
    result.map(|info| QpInfo {
        iterations: info.iterations,
        active: info.active + held,
    })
}

/// The dense dual active-set method on a checked problem.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn solve_in(
    ws: &mut QpWorkspace,
    vars: &[usize],
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
    ws.fit(n, m);
    factor(ws, hm, n, vars)?;
    // x = −H⁻¹ c = −J Jᵀ c.
    for a in 0..n {
        ws.d[a] = dot(&ws.j[a * n..(a + 1) * n], c);
    }
    x.fill(0.0);
    for a in 0..n {
        let da = ws.d[a];
        for (xi, j) in x.iter_mut().zip(&ws.j[a * n..(a + 1) * n]) {
            *xi -= da * j;
        }
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
                    describe(np, vars)
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
                add(ws, n, np, u_plus, vars)?;
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

/// Variable `i` of a reduced problem as the caller numbers it (`vars` empty: not reduced).
fn var(vars: &[usize], i: usize) -> usize {
    vars.get(i).copied().unwrap_or(i)
}

/// What a constraint is, in words.
fn describe(c: Constraint, vars: &[usize]) -> String {
    match c {
        Constraint::Lower(i) => format!("the lower bound of variable {}", var(vars, i)),
        Constraint::Upper(i) => format!("the upper bound of variable {}", var(vars, i)),
        Constraint::Row(k) => format!("inequality row {k}"),
    }
}

/// L Lᵀ = H (lower triangle of `hm`), then J = L⁻ᵀ into `ws.j` (by columns: row a of the
/// buffer is row a of L⁻¹).
#[inline(always)]
fn factor(ws: &mut QpWorkspace, hm: &[f64], n: usize, vars: &[usize]) -> Result<(), SolveError> {
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
                        "the QP's matrix is not positive definite (pivot {v:e} at variable {})",
                        var(vars, i)
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
#[inline(always)]
fn givens(a: f64, b: f64) -> (f64, f64, f64) {
    let h = a.hypot(b);
    if h == 0.0 {
        (1.0, 0.0, 0.0)
    } else {
        (a / h, b / h, h)
    }
}

/// Rotates columns a < b of J (rows of the buffer): J_a ← c J_a + s J_b, J_b ← −s J_a + c J_b.
#[inline(always)]
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
#[inline(always)]
fn add(
    ws: &mut QpWorkspace,
    n: usize,
    np: Constraint,
    mult: f64,
    vars: &[usize],
) -> Result<(), SolveError> {
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
            describe(np, vars)
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
#[inline(always)]
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

    /// Problems whose H couples a few variables and whose rows use only those (a whole-body
    /// step's shape): split into the variables apart and the coupled block, the answer and
    /// the multipliers equal the dense method's on the whole problem; errors name the
    /// caller's variables.
    #[test]
    fn split_problems_equal_the_dense_method() {
        let mut rng = SplitMix64(13);
        let mut split_seen = 0;
        for trial in 0..200 {
            let n = 12;
            let block = [1, 4, 7, 9];
            let (dense, _) = problem(&mut rng, block.len());
            let mut hm = vec![0.0; n * n];
            for i in 0..n {
                hm[i * n + i] = uni(&mut rng, 0.1, 2.0);
            }
            for (a, &i) in block.iter().enumerate() {
                for (b, &j) in block.iter().enumerate() {
                    hm[i * n + j] = dense[a * block.len() + b];
                }
            }
            let c: Vec<f64> = (0..n).map(|_| uni(&mut rng, -2.0, 2.0)).collect();
            let l: Vec<f64> = (0..n).map(|_| uni(&mut rng, -1.0, -0.05)).collect();
            let u: Vec<f64> = (0..n).map(|_| uni(&mut rng, 0.05, 1.0)).collect();
            // Rows on the block, and (every other trial) one that also uses variable 10.
            let m = 1 + trial % 4;
            let mut g = vec![0.0; m * n];
            for k in 0..m {
                for &i in &block {
                    g[k * n + i] = uni(&mut rng, -1.0, 1.0);
                }
            }
            if trial % 2 == 0 {
                g[10] = 0.7;
            }
            let hv: Vec<f64> = (0..m).map(|_| uni(&mut rng, -0.3, 0.0)).collect();
            let mut ws = QpWorkspace::new();
            let mut x = vec![0.0; n];
            let info = solve(&mut ws, &hm, &c, &l, &u, &g, &hv, &mut x).unwrap();
            assert!(ws.split.used);
            assert_eq!(ws.split.coupled.len(), 4 + usize::from(trial % 2 == 0));
            split_seen += 1;
            let (lo, up, rows) = ws.multipliers(n, m);
            let mut dense_ws = QpWorkspace::new();
            let mut y = vec![0.0; n];
            let dense_info =
                solve_in(&mut dense_ws, &[], &hm, &c, &l, &u, &g, &hv, &mut y).unwrap();
            let (dlo, dup, drows) = dense_ws.multipliers(n, m);
            assert_eq!(info.active, dense_info.active, "trial {trial}");
            for i in 0..n {
                assert!((x[i] - y[i]).abs() < 1e-10, "trial {trial}: {x:?} vs {y:?}");
                assert!((lo[i] - dlo[i]).abs() < 1e-9 && (up[i] - dup[i]).abs() < 1e-9);
            }
            for k in 0..m {
                assert!((rows[k] - drows[k]).abs() < 1e-9, "trial {trial}: row {k}");
            }
        }
        assert_eq!(split_seen, 200);
        // A variable apart whose H_ii is not positive, and a coupled block that is not
        // positive definite: each named as the caller numbers it.
        let n = 4;
        let mut hm = vec![0.0; n * n];
        for i in 0..n {
            hm[i * n + i] = 1.0;
        }
        hm[2 * n + 1] = 2.0; // couples 1 and 2 (H_11 = H_22 = 1: not positive definite)
        let (l, u, c) = (vec![-1.0; n], vec![1.0; n], vec![0.0; n]);
        let mut x = vec![0.0; n];
        let e = solve(&mut QpWorkspace::new(), &hm, &c, &l, &u, &[], &[], &mut x).unwrap_err();
        assert!(e.to_string().contains("variable 2"), "{e}");
        hm[2 * n + 1] = 0.5;
        hm[3 * n + 3] = 0.0;
        let e = solve(&mut QpWorkspace::new(), &hm, &c, &l, &u, &[], &[], &mut x).unwrap_err();
        assert!(e.to_string().contains("variable 3"), "{e}");
        // An unmeetable row on the coupled pair: the constraint the method could not add,
        // a bound of variable 1 or 2 (reduced variables 0 and 1), or the row.
        hm[3 * n + 3] = 1.0;
        let g = [0.0, 1.0, 1.0, 0.0];
        let e = solve(&mut QpWorkspace::new(), &hm, &c, &l, &u, &g, &[3.0], &mut x).unwrap_err();
        let e = e.to_string();
        assert!(e.contains("cannot all be met"), "{e}");
        assert!(
            ["variable 1", "variable 2", "row 0"]
                .iter()
                .any(|w| e.contains(w)),
            "{e}"
        );
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
