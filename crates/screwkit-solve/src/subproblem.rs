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
//! Subproblems 1–4 are here; 5 and 6 (three and four cones, via a quartic) are not yet
//! (issue 12).

use nalgebra::Vector3;

/// At most two values, stored inline (subproblems run in the inner loops of analytic IK and
/// must not allocate); reads as a slice.
#[derive(Clone, Copy)]
pub struct Few<T: Copy> {
    items: [T; 2],
    len: u8,
}

impl<T: Copy> Few<T> {
    /// One value.
    pub fn one(a: T) -> Self {
        Self {
            items: [a, a],
            len: 1,
        }
    }

    /// Two values.
    pub fn two(a: T, b: T) -> Self {
        Self {
            items: [a, b],
            len: 2,
        }
    }
}

impl<T: Copy> std::ops::Deref for Few<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        &self.items[..usize::from(self.len)]
    }
}

impl<T: Copy> std::ops::DerefMut for Few<T> {
    fn deref_mut(&mut self) -> &mut [T] {
        &mut self.items[..usize::from(self.len)]
    }
}

impl<T: Copy + std::fmt::Debug> std::fmt::Debug for Few<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl<T: Copy + PartialEq> PartialEq for Few<T> {
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

/// Tolerance for "exact" and for degeneracy, relative to the sizes involved.
const EPS: f64 = 1e-12;

/// R(k, θ) p for a unit k (Rodrigues, written out; the oracle of the tests is the library's
/// `so3::exp`).
pub fn rotate(k: &Vector3<f64>, theta: f64, p: &Vector3<f64>) -> Vector3<f64> {
    let (s, c) = theta.sin_cos();
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

/// An angle in (−π, π].
pub fn wrap(x: f64) -> f64 {
    use std::f64::consts::PI;
    // The common cases without a division: already in range, or one turn off.
    if x > -PI && x <= PI {
        return x;
    }
    if x > PI && x <= 3.0 * PI {
        let y = x - 2.0 * PI;
        if y > -PI && y <= PI {
            return y;
        }
    }
    if x <= -PI && x > -3.0 * PI {
        let y = x + 2.0 * PI;
        if y > -PI && y <= PI {
            return y;
        }
    }
    let y = (x + PI).rem_euclid(2.0 * PI) - PI;
    if y <= -PI {
        y + 2.0 * PI
    } else {
        y
    }
}

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
