//! The canonical subproblems of rotation geometry (Paden–Kahan; in the form of Elias & Wen,
//! "IK-Geo: Unified robot inverse kinematics using subproblem decomposition", 2025), the
//! building blocks of analytic IK: each asks which angle(s) θ of a rotation R(k, θ) about a
//! unit axis k through the origin make a geometric condition hold, with the least-squares
//! answer (flagged) when no exact one exists.
//!
//! Everything rests on one identity: for a unit axis k and a point p,
//! R(k, θ) p = k kᵀp + cos θ p⊥ + sin θ (k × p), with p⊥ = p − k kᵀp = −k × (k × p).
//! So `hᵀ R(k, θ) p = (h·k)(k·p) + cos θ (h·p⊥) + sin θ (h·(k × p))`, and every subproblem
//! but the second reduces to `a sin θ + b cos θ = c` ([`trig`]).
//!
//! Subproblems 5 and 6 (three cones; four cones in two angles) reduce to a quartic
//! ([`real_roots`]); they return the exact solutions only (none when there is no exact one).

use nalgebra::Vector3;

/// At most `N` values (two by default), stored inline (subproblems run in the inner loops of
/// analytic IK and must not allocate); reads as a slice.
#[derive(Clone, Copy)]
pub struct Few<T: Copy, const N: usize = 2> {
    items: [T; N],
    len: u8,
}

impl<T: Copy + Default, const N: usize> Default for Few<T, N> {
    fn default() -> Self {
        Self {
            items: [T::default(); N],
            len: 0,
        }
    }
}

impl<T: Copy, const N: usize> Few<T, N> {
    /// One value.
    pub fn one(a: T) -> Self {
        Self {
            items: [a; N],
            len: 1,
        }
    }

    /// Appends a value (ignored when full).
    pub fn push(&mut self, a: T) {
        if usize::from(self.len) < N {
            self.items[usize::from(self.len)] = a;
            self.len += 1;
        }
    }
}

impl<T: Copy> Few<T, 2> {
    /// Two values.
    pub fn two(a: T, b: T) -> Self {
        Self {
            items: [a, b],
            len: 2,
        }
    }
}

impl<T: Copy, const N: usize> std::ops::Deref for Few<T, N> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        &self.items[..usize::from(self.len)]
    }
}

impl<T: Copy, const N: usize> std::ops::DerefMut for Few<T, N> {
    fn deref_mut(&mut self) -> &mut [T] {
        &mut self.items[..usize::from(self.len)]
    }
}

impl<T: Copy + std::fmt::Debug, const N: usize> std::fmt::Debug for Few<T, N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Copy + PartialEq, const N: usize> PartialEq for Few<T, N> {
    fn eq(&self, other: &Self) -> bool {
        **self == **other
    }
}

/// What a subproblem found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Angles {
    /// The exact solutions (one or two angles in (−π, π]; two equal ones at a tangency are
    /// given once).
    Exact(Few<f64>),
    /// No exact solution: the angle that comes closest (in the subproblem's own measure).
    LeastSquares(f64),
    /// Every angle is a solution (the condition does not depend on θ: a point on the axis, …).
    Any,
}

impl Angles {
    /// One angle to go on with: the first exact one, else the least-squares one, else 0 (every
    /// angle solves it).
    pub fn first(self) -> f64 {
        match self {
            Angles::Exact(v) => v[0],
            Angles::LeastSquares(t) => t,
            Angles::Any => 0.0,
        }
    }
}

/// Tolerance for "exact" and for degeneracy, relative to the sizes involved.
const EPS: f64 = 1e-12;

/// R(k, θ) p for a unit k (Rodrigues, written out; the oracle of the tests is the library's
/// `so3::exp`).
pub fn rotate(k: &Vector3<f64>, theta: f64, p: &Vector3<f64>) -> Vector3<f64> {
    let (s, c) = screwkit_lie::trig::sin_cos(theta);
    k * k.dot(p) * (1.0 - c) + p * c + k.cross(p) * s
}

/// Solves `a sin θ + b cos θ = c`: θ = φ ± acos(c / ρ) with φ = atan2(a, b), ρ = √(a² + b²);
/// when |c| > ρ the least-squares θ (|a sin θ + b cos θ − c| smallest) is φ (c > 0) or φ + π;
/// when ρ ≈ 0 every θ solves it if c ≈ 0 (else the least-squares θ is arbitrary: 0).
/// `scale` is the size of the numbers involved, for the tolerances.
pub fn trig(a: f64, b: f64, c: f64, scale: f64) -> Angles {
    let rho = a.hypot(b);
    let tol = EPS * scale.max(f64::MIN_POSITIVE);
    if rho <= tol {
        return if c.abs() <= tol {
            Angles::Any
        } else {
            Angles::LeastSquares(0.0)
        };
    }
    let phi = a.atan2(b);
    let r = c / rho;
    if r.abs() > 1.0 + EPS {
        return Angles::LeastSquares(wrap(if r > 0.0 {
            phi
        } else {
            phi + std::f64::consts::PI
        }));
    }
    let d = r.clamp(-1.0, 1.0).acos();
    if d <= 1e-8 {
        // Tangent: one (double) solution.
        return Angles::Exact(Few::one(wrap(phi)));
    }
    Angles::Exact(Few::two(wrap(phi + d), wrap(phi - d)))
}

/// An angle in (−π, π] ([`screwkit_lie::angle::wrap`], the one angle wrap).
pub use screwkit_lie::angle::wrap;

/// Subproblem 1, rotation of a point onto a point: θ with R(k, θ) p1 = p2,
/// θ = atan2(p2·(k × p1), p2·p1⊥). Exact when p1 and p2 lie on the same circle about k
/// (same height k·p and same distance from the axis, to 1e-12 relative); otherwise the same
/// formula gives the θ minimising ‖R(k, θ) p1 − p2‖ ([`Angles::LeastSquares`]). A point on the
/// axis: [`Angles::Any`].
pub fn sp1(p1: &Vector3<f64>, p2: &Vector3<f64>, k: &Vector3<f64>) -> Angles {
    let kxp = k.cross(p1);
    let (h1, h2) = (k.dot(p1), k.dot(p2));
    let perp = p1 - k * h1;
    let scale = p1.norm_squared().max(p2.norm_squared()).sqrt();
    let (x, y) = (p2.dot(&kxp), p2.dot(&perp));
    // ‖k × p1‖ = ‖p1⊥‖ for a unit k.
    let r1 = kxp.norm();
    if r1 <= EPS * scale.max(f64::MIN_POSITIVE) {
        return if (p1 - p2).norm() <= EPS * scale.max(1e-300) {
            Angles::Any
        } else {
            Angles::LeastSquares(0.0)
        };
    }
    let theta = x.atan2(y);
    // p2's distance to the axis from its perpendicular part (not √(‖p2‖² − h2²), which
    // cancels when p2 is nearly on the axis).
    let r2 = (p2 - k * h2).norm();
    let same_circle =
        (h1 - h2).abs() <= EPS * scale * 10.0 && (r1 - r2).abs() <= EPS * scale * 10.0;
    if same_circle {
        Angles::Exact(Few::one(theta))
    } else {
        Angles::LeastSquares(theta)
    }
}

/// Subproblem 3, rotation to a distance: θ with ‖R(k, θ) p1 − p2‖ = d. From
/// ‖R p1 − p2‖² = ‖p1‖² + ‖p2‖² − 2 p2ᵀ R p1: a sin θ + b cos θ = c with a = p2·(k × p1),
/// b = p2·p1⊥, c = (‖p1‖² + ‖p2‖² − d²)/2 − (k·p1)(k·p2). Up to two solutions; the
/// least-squares θ (distance closest to d) when none.
pub fn sp3(p1: &Vector3<f64>, p2: &Vector3<f64>, k: &Vector3<f64>, d: f64) -> Angles {
    let a = p2.dot(&k.cross(p1));
    let b = p2.dot(&(p1 - k * k.dot(p1)));
    let c = (p1.norm_squared() + p2.norm_squared() - d * d) / 2.0 - k.dot(p1) * k.dot(p2);
    let scale = p1.norm() * p2.norm() + d * d;
    trig(a, b, c, scale)
}

/// Subproblem 4, rotation to a plane: θ with hᵀ R(k, θ) p = d (h a unit normal). From the
/// identity: a sin θ + b cos θ = c with a = h·(k × p), b = h·p⊥, c = d − (h·k)(k·p). Up to two
/// solutions; the least-squares θ (|hᵀRp − d| smallest) when none.
pub fn sp4(h: &Vector3<f64>, p: &Vector3<f64>, k: &Vector3<f64>, d: f64) -> Angles {
    let a = h.dot(&k.cross(p));
    let b = h.dot(&(p - k * k.dot(p)));
    let c = d - h.dot(k) * k.dot(p);
    trig(a, b, c, p.norm() * h.norm() + d.abs())
}

/// Subproblem 4 for unit vectors where it loses precision least: θ with hᵀ R(k, θ) p = h·v
/// for unit h, p ⊥ k and a unit v (the data the pose gives). Then hᵀ R(k, θ) p = cos(θ − θ₀)
/// with R(k, θ₀) p = h, and the angle between h and v is α = atan2(‖h × v‖, h·v), so
/// θ = θ₀ ± α. Unlike `acos(h·v)` this keeps full precision near the tangency (α ≈ 0 or π: a
/// wrist or UR-type θ₅ near 0, where `acos` loses half the digits). None when h or p is not
/// ⊥ k (within 1e-12): use [`sp4`].
pub fn sp4_unit(
    h: &Vector3<f64>,
    p: &Vector3<f64>,
    k: &Vector3<f64>,
    v: &Vector3<f64>,
) -> Option<Angles> {
    if h.dot(k).abs() > 1e-12 || p.dot(k).abs() > 1e-12 {
        return None;
    }
    let theta0 = h.dot(&k.cross(p)).atan2(h.dot(p));
    let alpha = h.cross(v).norm().atan2(h.dot(v));
    if alpha <= 1e-15 || alpha >= std::f64::consts::PI - 1e-15 {
        return Some(Angles::Exact(Few::one(wrap(theta0 + alpha))));
    }
    Some(Angles::Exact(Few::two(
        wrap(theta0 + alpha),
        wrap(theta0 - alpha),
    )))
}

/// The outcome of subproblem 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum AnglePairs {
    /// Exact (θ1, θ2) pairs (one at a tangency, two otherwise).
    Exact(Few<(f64, f64)>),
    /// No exact solution: the pair that comes closest.
    LeastSquares(f64, f64),
    /// The axes are parallel: the subproblem is not defined (a different decomposition is
    /// needed), or a point is on its axis.
    Degenerate,
}

/// Subproblem 2, two rotations: (θ1, θ2) with R(k1, θ1) p1 = R(k2, θ2) p2 for non-parallel
/// unit axes through the origin. The common point c lies on both cones: k1·c = k1·p1,
/// k2·c = k2·p2, ‖c‖ = ‖p1‖; with c = α k1 + β k2 + γ (k1 × k2) and s = k1·k2:
/// α = (k1·p1 − s k2·p2)/(1 − s²), β = (k2·p2 − s k1·p1)/(1 − s²),
/// γ² = (‖p1‖² − α² − β² − 2αβ s)/‖k1 × k2‖²; then θ1 = sp1(p1 → c, k1), θ2 = sp1(p2 → c, k2).
/// When γ² < 0 (the circles do not meet) the least-squares pair uses γ = 0.
pub fn sp2(
    p1: &Vector3<f64>,
    p2: &Vector3<f64>,
    k1: &Vector3<f64>,
    k2: &Vector3<f64>,
) -> AnglePairs {
    let s = k1.dot(k2);
    let k12 = k1.cross(k2);
    let n2 = k12.norm_squared();
    if n2 <= 1e-20 {
        return AnglePairs::Degenerate;
    }
    let (a1, a2) = (k1.dot(p1), k2.dot(p2));
    let det = 1.0 - s * s;
    let alpha = (a1 - s * a2) / det;
    let beta = (a2 - s * a1) / det;
    // The two points should have one norm; for a least-squares answer use their mean.
    let r2 = (p1.norm_squared() + p2.norm_squared()) / 2.0;
    let g2 = (r2 - alpha * alpha - beta * beta - 2.0 * alpha * beta * s) / n2;
    let scale = r2.max(f64::MIN_POSITIVE);
    let norms_agree = (p1.norm() - p2.norm()).abs() <= EPS * 10.0 * scale.sqrt();
    let base = k1 * alpha + k2 * beta;
    let pair = |c: &Vector3<f64>| -> Option<(f64, f64)> {
        let t1 = match sp1(p1, c, k1) {
            Angles::Exact(v) => v[0],
            Angles::LeastSquares(t) => t,
            Angles::Any => return None,
        };
        let t2 = match sp1(p2, c, k2) {
            Angles::Exact(v) => v[0],
            Angles::LeastSquares(t) => t,
            Angles::Any => return None,
        };
        Some((t1, t2))
    };
    if g2 < -EPS * scale / n2 || !norms_agree {
        let g = g2.max(0.0).sqrt();
        return match pair(&(base + k12 * g)) {
            Some((t1, t2)) => AnglePairs::LeastSquares(t1, t2),
            None => AnglePairs::Degenerate,
        };
    }
    let g = g2.max(0.0).sqrt();
    let (Some(a), Some(b)) = (pair(&(base + k12 * g)), pair(&(base - k12 * g))) else {
        return AnglePairs::Degenerate;
    };
    if (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9 {
        AnglePairs::Exact(Few::one(a))
    } else {
        AnglePairs::Exact(Few::two(a, b))
    }
}

/// The real roots of the polynomial c\[0\] + c\[1\] x + … + c\[n\] xⁿ (n ≤ 4), each polished by
/// Newton steps, in no particular order: the eigenvalues of the companion matrix
/// ([`crate::linalg`]'s Francis QR) whose imaginary part is below 1e-5 of the root's size (a double root splits into a
/// complex pair of order √ε; the callers check every root against their own equations), then
/// 3 Newton steps on the polynomial. Leading coefficients
/// below 1e-13 of the largest are dropped (the degree falls).
pub fn real_roots(c: &[f64]) -> Few<f64, 4> {
    let big = c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let mut out = Few::default();
    // (f64::max passes NaN over: every coefficient is checked.)
    if big == 0.0 || !c.iter().all(|x| x.is_finite()) {
        return out;
    }
    let mut n = c.len().min(5) - 1;
    while n > 0 && c[n].abs() <= 1e-13 * big {
        n -= 1;
    }
    if n == 0 {
        return out;
    }
    let eval = |x: f64| -> (f64, f64) {
        // Horner: value and derivative.
        let (mut v, mut d) = (c[n], 0.0);
        for i in (0..n).rev() {
            d = d * x + v;
            v = v * x + c[i];
        }
        (v, d)
    };
    let polish = |mut x: f64| {
        for _ in 0..3 {
            let (v, d) = eval(x);
            if d == 0.0 || !v.is_finite() {
                break;
            }
            let nx = x - v / d;
            if (eval(nx).0).abs() > v.abs() {
                break;
            }
            x = nx;
        }
        x
    };
    // The companion matrix's eigenvalues (the crate's one eigenvalue routine, bounded
    // iterations: a companion matrix whose QR iteration does not converge gives no roots,
    // never a hang), on the stack for each degree.
    let mut roots = [(f64::NAN, f64::NAN); 4];
    macro_rules! companion {
        ($n:literal) => {{
            let mut m = [[0.0; $n]; $n];
            for i in 1..$n {
                m[i][i - 1] = 1.0;
            }
            for i in 0..$n {
                m[i][$n - 1] = -c[i] / c[$n];
            }
            let Some(values) = crate::linalg::eigen::eigenvalues(&mut m) else {
                return out;
            };
            roots[..$n].copy_from_slice(&values);
        }};
    }
    match n {
        1 => roots[0] = (-c[0] / c[1], 0.0),
        2 => companion!(2),
        3 => companion!(3),
        _ => companion!(4),
    }
    for &(re, im) in roots.iter().take(n) {
        if im.abs() <= 1e-5 * (1.0 + re.abs()) {
            let x = polish(re);
            if x.is_finite()
                && !out
                    .iter()
                    .any(|&y| (y - x).abs() <= 1e-12 * (1.0 + x.abs()))
            {
                out.push(x);
            }
        }
    }
    out
}

/// A circle of points c + u cos θ + w sin θ (u ⊥ w, ‖u‖ = ‖w‖): R(k, θ) p moved by `offset`.
struct Circle {
    c: Vector3<f64>,
    u: Vector3<f64>,
    w: Vector3<f64>,
}

impl Circle {
    fn new(offset: &Vector3<f64>, k: &Vector3<f64>, p: &Vector3<f64>) -> Self {
        let along = k * k.dot(p);
        Self {
            c: offset + along,
            u: p - along,
            w: k.cross(p),
        }
    }

    fn at(&self, x: (f64, f64)) -> Vector3<f64> {
        self.c + self.u * x.0 + self.w * x.1
    }
}

/// Polynomial product (ascending coefficients; `a.len() + b.len() - 1 ≤ 5`).
fn poly_mul(a: &[f64], b: &[f64]) -> [f64; 5] {
    let mut out = [0.0; 5];
    for (i, x) in a.iter().enumerate() {
        for (j, y) in b.iter().enumerate() {
            out[i + j] += x * y;
        }
    }
    out
}

/// Subproblem 5, three cones: (θ1, θ2, θ3) with p0 + R(k1, θ1) p1 = R(k2, θ2)(p2 + R(k3, θ3) p3).
///
/// v1(θ1) = p0 + R1 p1 and v3(θ3) = p2 + R3 p3 run on circles c + u cos θ + w sin θ; R2 maps v3
/// onto v1 exactly when both have the same height h = k2·v and the same norm. On circle i the
/// height is δᵢ + gᵢ·x (x = (cos θ, sin θ), gᵢ = (k2·uᵢ, k2·wᵢ), Gᵢ = ‖gᵢ‖), so for a height h,
/// x = gᵢ (h − δᵢ)/Gᵢ² ± gᵢ⊥ √Rᵢ / Gᵢ² with Rᵢ = Gᵢ² − (h − δᵢ)², and the squared norm
/// ‖c‖² + ‖u‖² + mᵢ·x (mᵢ = 2(c·u, c·w)) is Pᵢ(h) ± Bᵢ √Rᵢ with Pᵢ linear. Equal norms,
/// P1 − P3 = ∓B1 √R1 ± B3 √R3, squared twice: (D² − B1² R1 − B3² R3)² = 4 B1² B3² R1 R3 with
/// D = P1 − P3 — a quartic in h (a quadratic when B1 or B3 vanishes). Each real root, with the sign pair whose norms agree, gives
/// θ1 and θ3; θ2 is subproblem 1 (v3 → v1 about k2). Up to 4 solutions; none when there is no
/// exact one. A circle whose height does not change (Gᵢ ≈ 0: its axis ∥ k2) fixes h, and the
/// other angle follows by [`trig`].
pub fn sp5(
    p0: &Vector3<f64>,
    p1: &Vector3<f64>,
    p2: &Vector3<f64>,
    p3: &Vector3<f64>,
    k1: &Vector3<f64>,
    k2: &Vector3<f64>,
    k3: &Vector3<f64>,
) -> Few<(f64, f64, f64), 4> {
    let one = Circle::new(p0, k1, p1);
    let three = Circle::new(p2, k3, p3);
    let scale = [p0, p1, p2, p3]
        .iter()
        .map(|v| v.norm())
        .sum::<f64>()
        .max(1e-300);
    let mut out: Few<(f64, f64, f64), 4> = Few::default();
    let height = |s: &Circle| (k2.dot(&s.c), (k2.dot(&s.u), k2.dot(&s.w)));
    let norm_coeffs = |s: &Circle| {
        (
            s.c.norm_squared() + s.u.norm_squared(),
            (2.0 * s.c.dot(&s.u), 2.0 * s.c.dot(&s.w)),
        )
    };
    let (d1, g1) = height(&one);
    let (d3, g3) = height(&three);
    let (n1, m1) = norm_coeffs(&one);
    let (n3, m3) = norm_coeffs(&three);
    let gg1 = g1.0 * g1.0 + g1.1 * g1.1;
    let gg3 = g3.0 * g3.0 + g3.1 * g3.1;
    let tol = 1e-12 * scale * scale;
    let mut accept = |x1: (f64, f64), x3: (f64, f64)| {
        // A loose first test (two close roots of the quartic carry √ε errors into their
        // points: a stretched elbow), then Newton steps and a tight one on the equation.
        let (v1, v3) = (one.at(x1), three.at(x3));
        if (v1.norm_squared() - v3.norm_squared()).abs() > 1e-5 * scale * scale
            || (k2.dot(&v1) - k2.dot(&v3)).abs() > 1e-5 * scale
        {
            return;
        }
        let t2 = sp1(&v3, &v1, k2).first();
        let t = polish5(
            p0,
            p1,
            p2,
            p3,
            k1,
            k2,
            k3,
            (x1.1.atan2(x1.0), t2, x3.1.atan2(x3.0)),
        );
        let residual = p0 + rotate(k1, t.0, p1) - rotate(k2, t.1, &(p2 + rotate(k3, t.2, p3)));
        if residual.norm() > 1e-7 * scale {
            return;
        }
        let near = |a: &(f64, f64, f64)| {
            wrap(a.0 - t.0).abs() < 1e-9
                && wrap(a.1 - t.1).abs() < 1e-9
                && wrap(a.2 - t.2).abs() < 1e-9
        };
        if !out.iter().any(near) {
            out.push(t);
        }
    };
    // x on a circle at height h: the two points (or one at the tangency).
    let points = |h: f64, d: f64, g: (f64, f64), gg: f64| -> Few<(f64, f64)> {
        let r = gg - (h - d) * (h - d);
        if r < -1e-9 * gg {
            return Few::default();
        }
        let root = r.max(0.0).sqrt();
        let base = (g.0 * (h - d) / gg, g.1 * (h - d) / gg);
        let perp = (-g.1 * root / gg, g.0 * root / gg);
        let a = (base.0 + perp.0, base.1 + perp.1);
        let b = (base.0 - perp.0, base.1 - perp.1);
        if root == 0.0 {
            Few::one(a)
        } else {
            Few::two(a, b)
        }
    };
    // x on a circle with squared norm `target` (n + m·x = target): trig.
    let by_norm = |n: f64, m: (f64, f64), target: f64| -> Few<(f64, f64)> {
        match trig(m.1, m.0, target - n, m.0.abs() + m.1.abs() + n.abs()) {
            Angles::Exact(v) => {
                let mut f = Few::default();
                for &t in v.iter() {
                    f.push((t.cos(), t.sin()));
                }
                f
            }
            _ => Few::default(),
        }
    };
    match (gg1 > tol, gg3 > tol) {
        (true, true) => {}
        (false, true) => {
            for &x3 in points(d1, d3, g3, gg3).iter() {
                let target = n3 + m3.0 * x3.0 + m3.1 * x3.1;
                for &x1 in by_norm(n1, m1, target).iter() {
                    accept(x1, x3);
                }
            }
            return out;
        }
        (true, false) => {
            for &x1 in points(d3, d1, g1, gg1).iter() {
                let target = n1 + m1.0 * x1.0 + m1.1 * x1.1;
                for &x3 in by_norm(n3, m3, target).iter() {
                    accept(x1, x3);
                }
            }
            return out;
        }
        (false, false) => return out,
    }
    // Pᵢ(h) = pᵢ0 + pᵢ1 h, Bᵢ, Rᵢ(h) = (Gᵢ² − δᵢ²) + 2δᵢ h − h².
    let lin = |n: f64, m: (f64, f64), d: f64, g: (f64, f64), gg: f64| {
        let mg = (m.0 * g.0 + m.1 * g.1) / gg;
        ([n - mg * d, mg], (m.1 * g.0 - m.0 * g.1) / gg)
    };
    let (p1c, b1) = lin(n1, m1, d1, g1, gg1);
    let (p3c, b3) = lin(n3, m3, d3, g3, gg3);
    let r1 = [gg1 - d1 * d1, 2.0 * d1, -1.0];
    let r3 = [gg3 - d3 * d3, 2.0 * d3, -1.0];
    let d = [p1c[0] - p3c[0], p1c[1] - p3c[1]];
    let dd = poly_mul(&d, &d);
    // A norm that does not depend on the side of the circle (B ≈ 0: the circle's axis meets
    // k2, as when two consecutive axes intersect) leaves one square root: D² = B² R, a
    // quadratic (squaring again would only double its roots).
    let small = 1e-9 * scale * scale;
    let poly: [f64; 5] = match (b1.abs() <= small, b3.abs() <= small) {
        (true, true) => [d[0], d[1], 0.0, 0.0, 0.0],
        (true, false) | (false, true) => {
            let (b, r) = if b1.abs() <= small {
                (b3, r3)
            } else {
                (b1, r1)
            };
            [
                dd[0] - b * b * r[0],
                dd[1] - b * b * r[1],
                dd[2] - b * b * r[2],
                0.0,
                0.0,
            ]
        }
        (false, false) => {
            let mut lhs = [0.0; 3];
            for i in 0..3 {
                lhs[i] = dd[i] - b1 * b1 * r1[i] - b3 * b3 * r3[i];
            }
            let left = poly_mul(&lhs, &lhs);
            let right = poly_mul(&r1, &r3);
            let mut q = [0.0; 5];
            for i in 0..5 {
                q[i] = left[i] - 4.0 * b1 * b1 * b3 * b3 * right[i];
            }
            q
        }
    };
    for &h in real_roots(&poly).iter() {
        for &x1 in points(h, d1, g1, gg1).iter() {
            for &x3 in points(h, d3, g3, gg3).iter() {
                accept(x1, x3);
            }
        }
    }
    out
}

/// Newton steps on subproblem 5's equation f = p0 + R1 p1 − R2 (p2 + R3 p3) (3 equations, 3
/// angles; ∂f/∂θ1 = k1 × R1 p1, ∂f/∂θ2 = −k2 × R2 v3, ∂f/∂θ3 = −R2 (k3 × R3 p3)) while ‖f‖
/// falls: the quartic's roots carry its rounding (√ε near a double root) into the angles.
#[allow(clippy::too_many_arguments)]
fn polish5(
    p0: &Vector3<f64>,
    p1: &Vector3<f64>,
    p2: &Vector3<f64>,
    p3: &Vector3<f64>,
    k1: &Vector3<f64>,
    k2: &Vector3<f64>,
    k3: &Vector3<f64>,
    mut t: (f64, f64, f64),
) -> (f64, f64, f64) {
    let f = |t: (f64, f64, f64)| {
        let v3 = p2 + rotate(k3, t.2, p3);
        p0 + rotate(k1, t.0, p1) - rotate(k2, t.1, &v3)
    };
    let mut err = f(t);
    for _ in 0..4 {
        let r3p3 = rotate(k3, t.2, p3);
        let v3 = p2 + r3p3;
        let j = nalgebra::Matrix3::from_columns(&[
            k1.cross(&rotate(k1, t.0, p1)),
            -k2.cross(&rotate(k2, t.1, &v3)),
            -rotate(k2, t.1, &k3.cross(&r3p3)),
        ]);
        let Some(step) = j.lu().solve(&(-err)) else {
            break;
        };
        let next = (t.0 + step[0], t.1 + step[1], t.2 + step[2]);
        let e = f(next);
        if e.norm() >= err.norm() {
            break;
        }
        t = next;
        err = e;
    }
    (wrap(t.0), wrap(t.1), wrap(t.2))
}

/// Subproblem 6, four cones in two angles: (θ1, θ2) with
/// h1ᵀ R(k1, θ1) p1 + h2ᵀ R(k2, θ2) p2 = d1 and h3ᵀ R(k3, θ1) p3 + h4ᵀ R(k4, θ2) p4 = d2.
///
/// Each term is affine in x1 = (cos θ1, sin θ1) or x2 (the identity in the module
/// documentation), so A \[x1; x2\] = b with A 2 × 4: x = x₀ + N ξ (x₀ the least-norm solution,
/// N a basis of A's null space, by SVD). With x1 = a + M1 ξ and x2 = b + M2 ξ, and M1
/// invertible (else the roles swap), x1 = η on the unit circle gives x2 = e + F η
/// (F = M2 M1⁻¹, e = b − F a), and ‖e + F η‖² = 1 with η = (cos φ, sin φ) is a quartic in
/// t = tan(φ/2) (φ = π checked apart). Up to 4 solutions; none when there is no exact one or
/// A has rank < 2 (a degenerate instance).
pub fn sp6(
    h: [&Vector3<f64>; 4],
    k: [&Vector3<f64>; 4],
    p: [&Vector3<f64>; 4],
    d1: f64,
    d2: f64,
) -> Few<(f64, f64), 4> {
    use nalgebra::{Matrix2, Vector2, Vector4};
    let row = |i: usize| {
        let perp = p[i] - k[i] * k[i].dot(p[i]);
        (
            h[i].dot(&perp),
            h[i].dot(&k[i].cross(p[i])),
            h[i].dot(k[i]) * k[i].dot(p[i]),
        )
    };
    let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
    let rhs = Vector2::new(d1 - r0.2 - r1.2, d2 - r2.2 - r3.2);
    let mut out: Few<(f64, f64), 4> = Few::default();
    // A = U Σ Vᵀ by the crate's one SVD (None for non-finite input: no solution). The
    // least-norm solution is V Σ⁻¹ Uᵀ b; the null space is the orthogonal complement of V's
    // columns.
    if !rhs.iter().all(|x| x.is_finite()) {
        return out;
    }
    let Some(crate::linalg::svd::Svd2x4 {
        s: sv,
        u: u2,
        v: v2,
    }) = crate::linalg::svd::svd_2x4(&[[r0.0, r0.1, r1.0, r1.1], [r2.0, r2.1, r3.0, r3.1]])
    else {
        return out;
    };
    if sv[1] <= 1e-12 * sv[0].max(1e-300) {
        return out;
    }
    let u = nalgebra::Matrix4x2::from_columns(&[Vector4::from(v2[0]), Vector4::from(v2[1])]);
    let y = Vector2::new(
        u2[0][0] * rhs[0] + u2[0][1] * rhs[1],
        u2[1][0] * rhs[0] + u2[1][1] * rhs[1],
    );
    let x0: Vector4<f64> = u * Vector2::new(y[0] / sv[0], y[1] / sv[1]);
    let proj = nalgebra::Matrix4::identity() - u * u.transpose();
    // Two columns of the projector spanning the complement, orthonormalised.
    let mut basis: Vec<Vector4<f64>> = Vec::new();
    for j in 0..4 {
        let mut v: Vector4<f64> = proj.column(j).into();
        for b in &basis {
            v -= b * b.dot(&v);
        }
        if v.norm() > 1e-6 && basis.len() < 2 {
            basis.push(v.normalize());
        }
    }
    if basis.len() < 2 {
        return out;
    }
    let nm = nalgebra::Matrix4x2::from_columns(&[basis[0], basis[1]]);
    let (xa, xb) = (Vector2::new(x0[0], x0[1]), Vector2::new(x0[2], x0[3]));
    let ma: Matrix2<f64> = nm.fixed_rows::<2>(0).into();
    let mb: Matrix2<f64> = nm.fixed_rows::<2>(2).into();
    let swap = ma.determinant().abs() < mb.determinant().abs();
    let (a0, m_a, b0, m_b) = if swap {
        (xb, mb, xa, ma)
    } else {
        (xa, ma, xb, mb)
    };
    let Some(inv) = m_a.try_inverse() else {
        return out;
    };
    let f = m_b * inv;
    let e = b0 - f * a0;
    let s = f.transpose() * f;
    let fe = f.transpose() * e;
    let c0 = e.norm_squared() - 1.0;
    // S00 c² + 2 S01 c s + S11 s² + 2 fe·(c, s) + c0 = 0, c = (1 − t²)/(1 + t²), s = 2t/(1 + t²).
    let one_m = [1.0, 0.0, -1.0];
    let two_t = [0.0, 2.0, 0.0];
    let one_p = [1.0, 0.0, 1.0];
    let mut quartic = [0.0; 5];
    let terms = [
        (s[(0, 0)], poly_mul(&one_m, &one_m)),
        (2.0 * s[(0, 1)], poly_mul(&one_m, &two_t)),
        (s[(1, 1)], poly_mul(&two_t, &two_t)),
        (2.0 * fe[0], poly_mul(&one_m, &one_p)),
        (2.0 * fe[1], poly_mul(&two_t, &one_p)),
        (c0, poly_mul(&one_p, &one_p)),
    ];
    for (w, poly) in terms {
        for i in 0..5 {
            quartic[i] += w * poly[i];
        }
    }
    let mut etas: Few<(f64, f64), 5> = Few::default();
    for &t in real_roots(&quartic).iter() {
        let q = 1.0 + t * t;
        etas.push(((1.0 - t * t) / q, 2.0 * t / q));
    }
    // φ = π (t = ∞) is a root when the quartic's leading coefficient vanishes.
    let at_pi = Vector2::new(-1.0, 0.0);
    if ((e + f * at_pi).norm_squared() - 1.0).abs() <= 1e-10 {
        etas.push((-1.0, 0.0));
    }
    for &(c, sn) in etas.iter() {
        let eta = Vector2::new(c, sn);
        let other = e + f * eta;
        if (other.norm_squared() - 1.0).abs() > 1e-7 {
            continue;
        }
        let (x1, x2) = if swap { (other, eta) } else { (eta, other) };
        let t = polish6(h, k, p, d1, d2, (x1[1].atan2(x1[0]), x2[1].atan2(x2[0])));
        if !out
            .iter()
            .any(|o| wrap(o.0 - t.0).abs() < 1e-9 && wrap(o.1 - t.1).abs() < 1e-9)
        {
            out.push(t);
        }
    }
    out
}

/// Newton steps on subproblem 6's two equations (∂/∂θ hᵀ R(k, θ) p = hᵀ (k × R(k, θ) p)) while
/// the residual falls: the quartic's rounding, carried into the angles, taken out.
fn polish6(
    h: [&Vector3<f64>; 4],
    k: [&Vector3<f64>; 4],
    p: [&Vector3<f64>; 4],
    d1: f64,
    d2: f64,
    mut t: (f64, f64),
) -> (f64, f64) {
    let term = |i: usize, th: f64| h[i].dot(&rotate(k[i], th, p[i]));
    let slope = |i: usize, th: f64| h[i].dot(&k[i].cross(&rotate(k[i], th, p[i])));
    let f = |t: (f64, f64)| {
        nalgebra::Vector2::new(
            term(0, t.0) + term(1, t.1) - d1,
            term(2, t.0) + term(3, t.1) - d2,
        )
    };
    let mut err = f(t);
    for _ in 0..4 {
        let j = nalgebra::Matrix2::new(slope(0, t.0), slope(1, t.1), slope(2, t.0), slope(3, t.1));
        let Some(step) = j.lu().solve(&(-err)) else {
            break;
        };
        let next = (t.0 + step[0], t.1 + step[1]);
        let e = f(next);
        if e.norm() >= err.norm() {
            break;
        }
        t = next;
        err = e;
    }
    (wrap(t.0), wrap(t.1))
}
