//! Time-optimal timing of a joint path under velocity and acceleration limits, by reachability
//! analysis (TOPP-RA: Pham and Pham, *A new approach to time-optimal path parameterization
//! based on reachability analysis*, IEEE T-RO 2018).
//!
//! **The path.** Waypoints q_0 … q_{m−1} are joined by a cubic spline q(s) over s ∈ [0, 1],
//! knot k at s = k / (m − 1), each joint's spline not-a-knot (SciPy's `CubicSpline` default, the
//! one `toppra.SplineInterpolator` builds): the path is C² and passes through every waypoint.
//!
//! **The problem.** Along the path, q̇ = q′(s) ṡ and q̈ = q′(s) s̈ + q″(s) ṡ². With x = ṡ² and
//! u = s̈ on a grid s_0 = 0 < … < s_N = 1 (Δ_i = s_{i+1} − s_i, x_{i+1} = x_i + 2 Δ_i u_i, u
//! constant between grid points), the limits |q̇_j| ≤ v_j and |q̈_j| ≤ a_j are linear in (x, u):
//!
//! ```text
//! x_i ≤ min_j (v_j / |q′_j(s_i)|)²
//! −a_j ≤ q′_j(s_i) u_i + q″_j(s_i) x_i ≤ a_j                              (at s_i)
//! −a_j ≤ (q′_j(s_{i+1}) + 2Δ_i q″_j(s_{i+1})) u_i + q″_j(s_{i+1}) x_i ≤ a_j  (at s_{i+1})
//! ```
//!
//! (the accelerations held at both ends of each step: toppra's interpolation scheme). The path
//! starts and ends at rest (x_0 = x_N = 0).
//!
//! **The algorithm.** Backward, the controllable sets K_i = [lo_i, hi_i]: the x_i from which
//! some admissible u_i reaches K_{i+1} (K_N = {0}). For fixed x the admissible u form an
//! interval [max_a ℓ_a(x), min_b h_b(x)] of lines; it is not empty iff ℓ_a(x) ≤ h_b(x) for
//! every pair, each pair a bound on x: K_i is exact, no LP solver. Forward, from x_0 = 0 the
//! greedy step u_i = the largest admissible (x_{i+1} ∈ K_{i+1}), which is time-optimal on the
//! grid. Time: t_{i+1} = t_i + 2Δ_i / (ṡ_i + ṡ_{i+1}).
//!
//! **Between grid points** the path bends: the answer is sampled (every [`TimingOptions::check`]
//! seconds) and, where a limit is exceeded there, the default grid is refined (halved, at most
//! [`MAX_REFINEMENTS`] times) and then the limits tightened by the excess (at most
//! [`MAX_TIGHTENINGS`] times), the timing redone each time, so that no sample exceeds a limit.

use crate::error::SolveError;

/// How many times the limits may be tightened after a dense check found an excess.
pub const MAX_TIGHTENINGS: usize = 8;

/// The most grid intervals.
pub const MAX_GRID: usize = 100_000;

/// How many times the default grid may be halved after a dense check found an excess.
pub const MAX_REFINEMENTS: usize = 2;

/// The largest squared path speed x = ṡ² considered (s⁻²): a bound where no limit binds.
const X_CAP: f64 = 1e30;

/// The most samples of one dense check (beyond, the step grows: a path of hours).
pub const MAX_CHECKS: usize = 2_000_000;

/// The grid and the check of [`time_parameterize`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimingOptions {
    /// Grid intervals (N; default: 40 per waypoint interval, at least 1,000, at most 100,000).
    pub grid: Option<usize>,
    /// The dense check's time step (s; default 1 ms; longer when the path would take more than
    /// [`MAX_CHECKS`] samples).
    pub check: f64,
}

impl Default for TimingOptions {
    fn default() -> Self {
        Self {
            grid: None,
            check: 1e-3,
        }
    }
}

/// Each joint's cubic spline over s ∈ [0, 1] (not-a-knot), the knots uniform.
#[derive(Debug, Clone)]
struct Spline {
    /// Knot values, m × n (row-major).
    y: Vec<f64>,
    /// Second derivatives at the knots, m × n.
    m2: Vec<f64>,
    knots: usize,
    joints: usize,
}

impl Spline {
    /// The spline through `points` (m × n, m ≥ 2): with h = 1 / (m − 1), the moments M_k
    /// solve h M_{k−1} + 4h M_k + h M_{k+1} = 6 (y_{k+1} − 2 y_k + y_{k−1}) / h inside, with
    /// the not-a-knot ends M_0 − 2M_1 + M_2 = 0 and M_{m−3} − 2M_{m−2} + M_{m−1} = 0 (the third
    /// derivative continuous at the second and the second-to-last knots); 3 knots: the
    /// parabola through them; 2: the line.
    fn new(points: &[f64], joints: usize) -> Spline {
        let knots = points.len() / joints.max(1);
        let mut m2 = vec![0.0; knots * joints];
        let h = 1.0 / (knots as f64 - 1.0);
        let y = |k: usize, j: usize| points[k * joints + j];
        if knots == 3 {
            for j in 0..joints {
                let c = (y(2, j) - 2.0 * y(1, j) + y(0, j)) / (h * h);
                for k in 0..3 {
                    m2[k * joints + j] = c;
                }
            }
        } else if knots >= 4 {
            // Unknowns M_1 … M_{m−2}; M_0 = 2M_1 − M_2 and M_{m−1} = 2M_{m−2} − M_{m−3}
            // substituted into the first and last interior rows, which become 6h M_1 and
            // 6h M_{m−2} (h(2M_1 − M_2) + 4h M_1 + h M_2: M_2 cancels).
            let inner = knots - 2;
            let (mut diag, mut lower, mut upper) =
                (vec![4.0 * h; inner], vec![h; inner], vec![h; inner]);
            diag[0] = 6.0 * h;
            upper[0] = 0.0;
            diag[inner - 1] = 6.0 * h;
            lower[inner - 1] = 0.0;
            for j in 0..joints {
                let mut rhs: Vec<f64> = (1..knots - 1)
                    .map(|k| 6.0 * (y(k + 1, j) - 2.0 * y(k, j) + y(k - 1, j)) / h)
                    .collect();
                // Thomas' algorithm (diagonally dominant: 6h and 4h against h).
                let (c, mut d) = (upper.clone(), diag.clone());
                for i in 1..inner {
                    let w = lower[i] / d[i - 1];
                    d[i] -= w * c[i - 1];
                    rhs[i] -= w * rhs[i - 1];
                }
                rhs[inner - 1] /= d[inner - 1];
                for i in (0..inner - 1).rev() {
                    rhs[i] = (rhs[i] - c[i] * rhs[i + 1]) / d[i];
                }
                for (k, v) in rhs.iter().enumerate() {
                    m2[(k + 1) * joints + j] = *v;
                }
                let at = |k: usize, m2: &[f64]| m2[k * joints + j];
                m2[j] = 2.0 * at(1, &m2) - at(2, &m2);
                let l = knots - 1;
                m2[l * joints + j] = 2.0 * at(l - 1, &m2) - at(l - 2, &m2);
            }
        }
        Spline {
            y: points.to_vec(),
            m2,
            knots,
            joints,
        }
    }

    /// q(s), q′(s), q″(s) into the three slices (n each).
    fn eval(&self, s: f64, q: &mut [f64], dq: &mut [f64], ddq: &mut [f64]) {
        let n = self.joints;
        let segments = self.knots - 1;
        let h = 1.0 / segments as f64;
        let k = ((s / h).floor().max(0.0) as usize).min(segments - 1);
        let (a, b) = ((k + 1) as f64 * h - s, s - k as f64 * h);
        for j in 0..n {
            let (y0, y1) = (self.y[k * n + j], self.y[(k + 1) * n + j]);
            let (m0, m1) = (self.m2[k * n + j], self.m2[(k + 1) * n + j]);
            let c0 = y0 / h - m0 * h / 6.0;
            let c1 = y1 / h - m1 * h / 6.0;
            q[j] = m0 * a * a * a / (6.0 * h) + m1 * b * b * b / (6.0 * h) + c0 * a + c1 * b;
            dq[j] = -m0 * a * a / (2.0 * h) + m1 * b * b / (2.0 * h) - c0 + c1;
            ddq[j] = (m0 * a + m1 * b) / h;
        }
    }
}

/// A time-optimal timing of a path: the grid, the squared path speed x_i = ṡ_i² and the path
/// acceleration u_i on each step, and the times. Sample it with [`Timing::sample`].
#[derive(Debug, Clone)]
pub struct Timing {
    spline: Spline,
    s: Vec<f64>,
    sdot: Vec<f64>,
    u: Vec<f64>,
    t: Vec<f64>,
    /// The limits finally used (the given ones, or tightened after the dense check).
    velocity: Vec<f64>,
    acceleration: Vec<f64>,
}

impl Timing {
    /// The duration (s).
    pub fn duration(&self) -> f64 {
        *self.t.last().unwrap_or(&0.0)
    }

    /// The joints' count.
    pub fn joints(&self) -> usize {
        self.spline.joints
    }

    /// The grid points' times (N + 1).
    pub fn grid_times(&self) -> &[f64] {
        &self.t
    }

    /// The velocity and acceleration limits the timing was made with (the given ones divided
    /// by the dense check's excess, when it found one).
    pub fn limits(&self) -> (&[f64], &[f64]) {
        (&self.velocity, &self.acceleration)
    }

    /// q, q̇, q̈ at time t (clamped to [0, duration]) into the three slices (n each): on the
    /// step holding t, s = s_i + ṡ_i τ + ½ u_i τ², ṡ = ṡ_i + u_i τ, s̈ = u_i, then
    /// q̇ = q′ ṡ, q̈ = q′ s̈ + q″ ṡ².
    pub fn sample(&self, t: f64, q: &mut [f64], qd: &mut [f64], qdd: &mut [f64]) {
        let t = t.clamp(0.0, self.duration());
        let i = match self.t.partition_point(|x| *x <= t) {
            0 => 0,
            p => (p - 1).min(self.u.len() - 1),
        };
        let tau = t - self.t[i];
        let (sd0, u) = (self.sdot[i], self.u[i]);
        let s = (self.s[i] + sd0 * tau + 0.5 * u * tau * tau).clamp(self.s[i], self.s[i + 1]);
        let sd = (sd0 + u * tau).max(0.0);
        self.spline.eval(s, q, qd, qdd);
        for j in 0..q.len() {
            let d1 = qd[j];
            qd[j] = d1 * sd;
            qdd[j] = d1 * u + qdd[j] * sd * sd;
        }
    }
}

/// The time-optimal timing of the joint path through `waypoints` (m × n row-major, m ≥ 2),
/// within |q̇_j| ≤ `velocity[j]` and |q̈_j| ≤ `acceleration[j]`, at rest at both ends (the
/// module's method). Errors name the bad input: a non-finite waypoint, a limit that is not a
/// finite number > 0.
pub fn time_parameterize(
    waypoints: &[f64],
    joints: usize,
    velocity: &[f64],
    acceleration: &[f64],
    options: &TimingOptions,
) -> Result<Timing, SolveError> {
    let bad = |what: String| Err(SolveError::InvalidInput(what));
    if joints == 0 || !waypoints.len().is_multiple_of(joints) || waypoints.len() / joints < 2 {
        return bad(format!(
            "a path needs at least 2 waypoints of {joints} joint values (got {} values)",
            waypoints.len()
        ));
    }
    if let Some(i) = waypoints.iter().position(|x| !x.is_finite()) {
        return bad(format!(
            "waypoint {}, joint {}: {} is not finite",
            i / joints,
            i % joints,
            waypoints[i]
        ));
    }
    for (what, limits) in [("velocity", velocity), ("acceleration", acceleration)] {
        if limits.len() != joints {
            return bad(format!(
                "{what} limits: expected {joints}, got {}",
                limits.len()
            ));
        }
        if let Some(j) = limits.iter().position(|x| !(x.is_finite() && *x > 0.0)) {
            return bad(format!(
                "{what} limit of joint {j}: {} is not a finite number > 0",
                limits[j]
            ));
        }
    }
    if !(options.check.is_finite() && options.check > 0.0) {
        return bad(format!("check step {}: expected > 0", options.check));
    }
    let first = &waypoints[..joints];
    if waypoints.chunks(joints).all(|w| w == first) {
        return bad("the path does not move (every waypoint is the first)".into());
    }
    let spline = Spline::new(waypoints, joints);
    let m = waypoints.len() / joints;
    let n = options
        .grid
        .unwrap_or(40 * (m - 1))
        .clamp(if options.grid.is_some() { 1 } else { 1000 }, MAX_GRID);
    let (mut v, mut a) = (velocity.to_vec(), acceleration.to_vec());
    let mut n = n;
    let mut timing = solve(&spline, n, &v, &a)?;
    let mut refinements = 0;
    for _ in 0..MAX_TIGHTENINGS + MAX_REFINEMENTS {
        let (ev, ea) = excess(&timing, velocity, acceleration, options.check);
        if ev <= 1.0 && ea <= 1.0 {
            break;
        }
        // First a finer grid (the excess between grid points shrinks with the steps), then,
        // for what remains, tighter limits.
        if options.grid.is_none() && refinements < MAX_REFINEMENTS && 2 * n <= MAX_GRID {
            refinements += 1;
            n *= 2;
            timing = solve(&spline, n, &v, &a)?;
            continue;
        }
        // Tightened by the excess, a little more than it.
        for x in v.iter_mut() {
            *x /= ev.max(1.0) * (1.0 + 1e-6);
        }
        for x in a.iter_mut() {
            *x /= ea.max(1.0) * (1.0 + 1e-6);
        }
        timing = solve(&spline, n, &v, &a)?;
    }
    Ok(timing)
}

/// The largest ratio |q̇_j| / v_j and |q̈_j| / a_j over samples every `step` seconds (and at
/// the grid points).
fn excess(timing: &Timing, v: &[f64], a: &[f64], step: f64) -> (f64, f64) {
    let n = timing.joints();
    let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut ev, mut ea) = (0.0f64, 0.0f64);
    // At most MAX_CHECKS samples (a long, slow path is checked at a coarser step).
    let step = step.max(timing.duration() / MAX_CHECKS as f64);
    let samples = (timing.duration() / step).ceil() as usize;
    let times = (0..=samples)
        .map(|k| (k as f64 * step).min(timing.duration()))
        .chain(timing.grid_times().iter().copied());
    for t in times {
        timing.sample(t, &mut q, &mut qd, &mut qdd);
        for j in 0..n {
            ev = ev.max(qd[j].abs() / v[j]);
            ea = ea.max(qdd[j].abs() / a[j]);
        }
    }
    (ev, ea)
}

/// One line of u as a function of x: u ≥ (or ≤) c0 + c1 x.
#[derive(Debug, Clone, Copy)]
struct Line {
    c0: f64,
    c1: f64,
}

/// The u-bounds at one step for given constraint data: each joint's acceleration at s_i
/// (p u + r x within ±a) and at s_{i+1} ((p′ + 2Δ r′) u + r′ x within ±a), the reach of
/// [lo, hi] (x + 2Δ u within it); lines into `lower`/`upper`, x-only bounds into [xmin, xmax].
#[allow(clippy::too_many_arguments)]
fn step_lines(
    d1: &[f64],
    d2: &[f64],
    e1: &[f64],
    e2: &[f64],
    delta: f64,
    a: &[f64],
    next: (f64, f64),
    lower: &mut Vec<Line>,
    upper: &mut Vec<Line>,
    xbounds: &mut (f64, f64),
) {
    lower.clear();
    upper.clear();
    let mut constrain = |p: f64, r: f64, lim: f64| {
        // −lim ≤ p u + r x ≤ lim.
        if p.abs() > 1e-12 * (1.0 + r.abs()) {
            let (lo, hi) = (
                Line {
                    c0: -lim / p,
                    c1: -r / p,
                },
                Line {
                    c0: lim / p,
                    c1: -r / p,
                },
            );
            if p > 0.0 {
                lower.push(lo);
                upper.push(hi);
            } else {
                lower.push(hi);
                upper.push(lo);
            }
        } else if r.abs() > 0.0 {
            // |r x| ≤ lim, x ≥ 0: x ≤ lim / |r|.
            xbounds.1 = xbounds.1.min(lim / r.abs());
        }
    };
    for j in 0..a.len() {
        constrain(d1[j], d2[j], a[j]);
        constrain(e1[j] + 2.0 * delta * e2[j], e2[j], a[j]);
    }
    // lo ≤ x + 2Δ u ≤ hi.
    lower.push(Line {
        c0: next.0 / (2.0 * delta),
        c1: -1.0 / (2.0 * delta),
    });
    upper.push(Line {
        c0: next.1 / (2.0 * delta),
        c1: -1.0 / (2.0 * delta),
    });
}

/// The x for which some u lies between every lower and every upper line, within [xmin, xmax]:
/// each pair ℓ(x) ≤ h(x) bounds x.
fn feasible_x(lower: &[Line], upper: &[Line], (mut xmin, mut xmax): (f64, f64)) -> (f64, f64) {
    for l in lower {
        for h in upper {
            // l.c0 + l.c1 x ≤ h.c0 + h.c1 x  ⇔  (l.c1 − h.c1) x ≤ h.c0 − l.c0.
            let (k, c) = (l.c1 - h.c1, h.c0 - l.c0);
            if k > 0.0 {
                xmax = xmax.min(c / k);
            } else if k < 0.0 {
                xmin = xmin.max(c / k);
            } else if c < 0.0 {
                return (1.0, 0.0);
            }
        }
    }
    (xmin, xmax)
}

/// TOPP-RA on an N-interval grid with the limits v, a (the module's formulas).
fn solve(spline: &Spline, n: usize, v: &[f64], a: &[f64]) -> Result<Timing, SolveError> {
    let joints = spline.joints;
    let s: Vec<f64> = (0..=n).map(|i| i as f64 / n as f64).collect();
    // q′ and q″ at every grid point; the velocity bound on x.
    let mut d1 = vec![0.0; (n + 1) * joints];
    let mut d2 = vec![0.0; (n + 1) * joints];
    let mut xv = vec![f64::INFINITY; n + 1];
    let mut q = vec![0.0; joints];
    for i in 0..=n {
        let (a1, a2) = (
            &mut d1[i * joints..(i + 1) * joints],
            &mut d2[i * joints..(i + 1) * joints],
        );
        spline.eval(s[i], &mut q, a1, a2);
        for j in 0..joints {
            if a1[j] != 0.0 {
                xv[i] = xv[i].min((v[j] / a1[j]).powi(2));
            }
        }
    }
    // Step i's lines (the joints' accelerations at both ends, the reach of `next`).
    let lines = |i: usize,
                 next: (f64, f64),
                 lower: &mut Vec<Line>,
                 upper: &mut Vec<Line>,
                 xb: &mut (f64, f64)| {
        let (here, there) = (
            i * joints..(i + 1) * joints,
            (i + 1) * joints..(i + 2) * joints,
        );
        step_lines(
            &d1[here.clone()],
            &d2[here],
            &d1[there.clone()],
            &d2[there],
            s[i + 1] - s[i],
            a,
            next,
            lower,
            upper,
            xb,
        );
    };
    // Backward: the controllable sets.
    let mut sets = vec![(0.0, 0.0); n + 1];
    let (mut lower, mut upper) = (Vec::new(), Vec::new());
    for i in (0..n).rev() {
        // (x capped: a stretch where no limit binds would otherwise be unbounded.)
        let mut xb = (0.0, xv[i].min(X_CAP));
        lines(i, sets[i + 1], &mut lower, &mut upper, &mut xb);
        let (lo, hi) = feasible_x(&lower, &upper, xb);
        if lo > hi + 1e-12 * hi.abs().max(1.0) {
            return Err(SolveError::InvalidInput(format!(
                "the path cannot be timed at s = {:.6} (no admissible speed there)",
                s[i]
            )));
        }
        sets[i] = (lo.max(0.0), hi.max(lo.max(0.0)));
    }
    // Forward: the greedy steps from rest.
    let mut x = vec![0.0; n + 1];
    let mut u = vec![0.0; n];
    for i in 0..n {
        let delta = s[i + 1] - s[i];
        let mut xb = (0.0, f64::INFINITY);
        lines(i, sets[i + 1], &mut lower, &mut upper, &mut xb);
        let eval = |l: &Line| l.c0 + l.c1 * x[i];
        let hi = upper.iter().map(eval).fold(f64::INFINITY, f64::min);
        let lo = lower.iter().map(eval).fold(f64::NEG_INFINITY, f64::max);
        // (Rounding can leave hi a hair below lo at the sets' edges.)
        u[i] = hi.max(lo);
        let (slo, shi) = sets[i + 1];
        x[i + 1] = (x[i] + 2.0 * delta * u[i]).clamp(slo, shi).max(0.0);
        u[i] = (x[i + 1] - x[i]) / (2.0 * delta);
    }
    let sdot: Vec<f64> = x.iter().map(|x| x.sqrt()).collect();
    let mut t = vec![0.0; n + 1];
    for i in 0..n {
        let speed = sdot[i] + sdot[i + 1];
        if speed <= 0.0 {
            return Err(SolveError::InvalidInput(format!(
                "the path cannot be timed: it stops at s = {:.6} (no speed there)",
                s[i]
            )));
        }
        t[i + 1] = t[i] + 2.0 * (s[i + 1] - s[i]) / speed;
    }
    Ok(Timing {
        spline: spline.clone(),
        s,
        sdot,
        u,
        t,
        velocity: v.to_vec(),
        acceleration: a.to_vec(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line of one joint over 1 rad, v = 1, a = 2: bang-coast-bang is the optimum,
    /// T = d/v + v/a = 1.5 s (accelerate 0.5 s over 0.25 rad, coast 0.5 s, brake 0.5 s); the
    /// grid's answer is within 1 %, and no 1 ms sample exceeds a limit.
    #[test]
    fn a_straight_line_is_bang_coast_bang() {
        let path = [0.0, 0.25, 0.5, 0.75, 1.0];
        let t = time_parameterize(&path, 1, &[1.0], &[2.0], &TimingOptions::default()).unwrap();
        assert!((t.duration() - 1.5).abs() < 0.015, "{}", t.duration());
        let (ev, ea) = excess(&t, &[1.0], &[2.0], 1e-4);
        assert!(ev <= 1.0 + 1e-9 && ea <= 1.0 + 1e-9, "{ev} {ea}");
        let (mut q, mut qd, mut qdd) = ([0.0], [0.0], [0.0]);
        t.sample(t.duration(), &mut q, &mut qd, &mut qdd);
        assert!((q[0] - 1.0).abs() < 1e-12 && qd[0].abs() < 1e-9);
        t.sample(0.75, &mut q, &mut qd, &mut qdd);
        assert!((q[0] - 0.5).abs() < 0.01 && (qd[0] - 1.0).abs() < 1e-6);
    }

    /// The spline through the knots, and not-a-knot: a cubic is reproduced exactly.
    #[test]
    fn the_spline_reproduces_a_cubic() {
        let f = |s: f64| 2.0 * s * s * s - s * s + 0.5 * s - 1.0;
        let points: Vec<f64> = (0..7).map(|k| f(k as f64 / 6.0)).collect();
        let spline = Spline::new(&points, 1);
        let (mut q, mut dq, mut ddq) = ([0.0], [0.0], [0.0]);
        for k in 0..=100 {
            let s = k as f64 / 100.0;
            spline.eval(s, &mut q, &mut dq, &mut ddq);
            assert!((q[0] - f(s)).abs() < 1e-12, "{s}");
            assert!((dq[0] - (6.0 * s * s - 2.0 * s + 0.5)).abs() < 1e-10);
            assert!((ddq[0] - (12.0 * s - 2.0)).abs() < 1e-9);
        }
    }

    /// Untrusted paths: one that does not move, one of hours (its check bounded), a repeated
    /// waypoint amid a moving path; errors name the input.
    #[test]
    fn hostile_paths_are_answered_or_named() {
        let o = TimingOptions::default();
        let e = time_parameterize(&[1.0, 1.0, 1.0], 1, &[1.0], &[1.0], &o).unwrap_err();
        assert!(e.to_string().contains("does not move"), "{e}");
        let e = time_parameterize(&[0.0, f64::NAN], 1, &[1.0], &[1.0], &o).unwrap_err();
        assert!(e.to_string().contains("waypoint 1"), "{e}");
        let e = time_parameterize(&[0.0, 1.0], 1, &[-1.0], &[1.0], &o).unwrap_err();
        assert!(e.to_string().contains("velocity limit of joint 0"), "{e}");
        // 1e6 rad at 1e-3 rad/s: 1e9 s, checked in at most MAX_CHECKS samples.
        let t = time_parameterize(&[0.0, 1e6], 1, &[1e-3], &[1e-3], &o).unwrap();
        assert!(
            (t.duration() / (1e9 + 1.0) - 1.0).abs() < 0.01,
            "{}",
            t.duration()
        );
        let t = time_parameterize(&[0.0, 0.5, 0.5, 1.0], 1, &[1.0], &[1.0], &o).unwrap();
        assert!(t.duration().is_finite() && t.duration() > 2.0);
    }
}
