//! **The wrist**: R_w = R₄ R₅ R₆ = (R₁ R₂ R₃)ᵀ R_g; k₄ᵀ R₅ k₆ = k₄ᵀ R_w k₆ gives θ₅
//! (subproblem 4), R₄ (R₅ k₆) = R_w k₆ gives θ₄ and R₆ k₅ = R₅ᵀ R₄ᵀ R_w k₅ gives θ₆
//! (subproblem 1).

use super::*;

/// The spherical wrist: (θ₄, θ₅, θ₆) with R₄ R₅ R₆ = `rw`.
#[inline]
pub(super) fn wrist(
    p: &Prepared,
    rw: &M3,
    singular: &mut bool,
    emit: impl FnMut(f64, f64, f64, bool),
) {
    three_axes([&p.k[3], &p.k[4], &p.k[5]], rw, singular, emit);
}

/// Three rotations about unit axes k₄, k₅, k₆ (through one point) making `rw`: (θ₄, θ₅, θ₆)
/// with R(k₄, θ₄) R(k₅, θ₅) R(k₆, θ₆) = `rw` (the wrist; a spherical shoulder too), up to 2.
#[inline]
pub(super) fn three_axes(
    [k4, k5, k6]: [&V3; 3],
    rw: &M3,
    singular: &mut bool,
    mut emit: impl FnMut(f64, f64, f64, bool),
) {
    let rwk6 = rw * k6;
    let rwtk4 = rw.transpose() * k4;
    let five = sp4_unit(k4, k6, k5, &rwk6).unwrap_or_else(|| sp4(k4, k6, k5, k4.dot(&rwk6)));
    for &(t5, e5) in roots(five, true, singular).iter() {
        let r5 = rotation(k5, t5);
        let r5k6 = r5 * k6;
        let four = sp1(&r5k6, &rwk6, k4);
        if four == Angles::Any {
            // Axes 4 and 6 aligned (R₅ k₆ = s k₄): only θ₄ + s θ₆ = φ matters; with θ₄ = 0,
            // R₆ k₅ = R₅ᵀ R_w k₅ gives φ; split it evenly so both stay within their limits.
            *singular = true;
            let want = r5.transpose() * (rw * k5);
            for &(t6, e6) in roots(sp1(k5, &want, k6), false, singular).iter() {
                let s = k4.dot(&r5k6).signum();
                emit(t6 * s / 2.0, t5, t6 / 2.0, e5 && e6);
            }
            continue;
        }
        // R₆ (R_wᵀ k₄) = R₅ᵀ k₄ (R₄ keeps k₄): θ₆ without R₄.
        let six = sp1(&rwtk4, &(r5.transpose() * k4), k6);
        for &(t4, e4) in roots(four, false, singular).iter() {
            for &(t6, e6) in roots(six, false, singular).iter() {
                emit(t4, t5, t6, e4 && e5 && e6);
            }
        }
    }
}
