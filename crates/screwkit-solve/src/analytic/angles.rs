//! The angle helpers every decomposition shares: a rotation matrix about a unit axis, and the
//! roots of the subproblems as angles with their exactness.

use super::*;

/// R(k, θ) as a matrix for a unit k: the library's Rodrigues form
/// ([`screwkit_lie::so3::rotation_from_coefficients`] with φ = k, A = sin θ, B = 1 − cos θ).
#[inline]
pub(super) fn rotation(k: &V3, theta: f64) -> M3 {
    // The library's inlined sine and cosine (≤ 1 ulp), a few ns where the C library's pair
    // took 9 % of a locked Panda's `ik_all` (perf).
    let (s, c) = screwkit_lie::trig::sin_cos(theta);
    screwkit_lie::so3::rotation_from_coefficients(k, 1.0, s, 1.0 - c)
}

/// The angles of a subproblem with their exactness: an exact double root where two are
/// expected (`two`), or a free angle (set to 0), marks the configuration singular.
#[inline]
pub(super) fn roots(a: Angles, two: bool, singular: &mut bool) -> Few<(f64, bool)> {
    match a {
        Angles::Exact(v) => {
            // A double root, or two roots closer than 2e-6 rad (a near-tangency: the roots
            // move by √ε for an ε change in the data).
            if two && (v.len() == 1 || wrap(v[0] - v[1]).abs() < 2e-6) {
                *singular = true;
            }
            if v.len() == 2 {
                Few::two((v[0], true), (v[1], true))
            } else {
                Few::one((v[0], true))
            }
        }
        Angles::LeastSquares(t) => Few::one((t, false)),
        Angles::Any => {
            *singular = true;
            Few::one((0.0, true))
        }
    }
}

/// The pairs of subproblem 2 with their exactness; a point on an axis (degenerate) sets the
/// first angle to 0 and solves the second by subproblem 1, marking the configuration
/// singular.
#[inline]
pub(super) fn pairs(
    a: AnglePairs,
    p1: &V3,
    p2: &V3,
    k2: &V3,
    singular: &mut bool,
) -> Few<(f64, f64, bool)> {
    match a {
        AnglePairs::Exact(v) => {
            if v.len() == 1 {
                *singular = true;
            }
            let f = |x: (f64, f64)| (x.0, x.1, true);
            if v.len() == 2 {
                Few::two(f(v[0]), f(v[1]))
            } else {
                Few::one(f(v[0]))
            }
        }
        AnglePairs::LeastSquares(a, b) => Few::one((a, b, false)),
        AnglePairs::Degenerate => {
            *singular = true;
            // R(k2, θ2) p2 = p1 with θ1 = 0.
            let (t, ok) = roots(sp1(p2, p1, k2), false, singular)[0];
            Few::one((0.0, t, ok))
        }
    }
}
