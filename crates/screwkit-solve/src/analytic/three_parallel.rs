//! Three parallel axes 2 ∥ 3 ∥ 4 (g = T_d M⁻¹ = e^\[S₁\]θ₁ ⋯ e^\[S₆\]θ₆, k_i the unit axes,
//! r_i points on them, e_i = e^\[S_i\]θ_i, R_i = R(k_i, θ_i), as in every decomposition).
//!
//! **Axes 5 and 6 meeting at p₅₆** (UR-type): k₂ · e₁⁻¹ g p₅₆ = k₂ · p₅₆ gives θ₁
//! (subproblem 4); k₂ᵀ R₁ᵀ R_g k₆ = k₂ᵀ R₅ k₆ gives θ₅ (subproblem 4); R₆ (R_gᵀ R₁ k₂) =
//! R(k₅, −θ₅) k₂ gives θ₆ (subproblem 1). Then h = e₁⁻¹ g e₆⁻¹ e₅⁻¹ = e₂ e₃ e₄ is planar:
//! with p₄ on axis 4, ‖e₃ p₄ − r₂‖ = ‖h p₄ − r₂‖ gives θ₃ (subproblem 3), e₂ (e₃ p₄) = h p₄
//! gives θ₂ (subproblem 1) and θ₄ is the rotation of h about k₂ minus θ₂ + θ₃.
//!
//! **Only the three parallel axes** (`general`): the k₂ components of e₁⁻¹ g r₆ = e₂ e₃ e₄ e₅
//! r₆ and of R₁ᵀ R_g k₆ = R₂₃₄ R₅ k₆ give k₂ᵀ R(k₁, −θ₁)(g r₆ − r₁) − k₂ᵀ R₅ (r₆ − r₅) =
//! k₂·(r₅ − r₁) and k₂ᵀ R(k₁, −θ₁) R_g k₆ − k₂ᵀ R₅ k₆ = 0: subproblem 6 in (θ₁, θ₅) (up to 4
//! pairs); then θ₆ and the planar problem as for the UR type.

use super::*;

/// 2 ∥ 3 ∥ 4 with axes 5 and 6 meeting, or (`general`) without (module documentation).
pub(super) fn three_parallel(
    p: &Prepared,
    g: &Se3,
    general: bool,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let (k, r) = (&p.k, &p.r);
    let rg = g.rotation();
    let p4 = r[3];
    // (θ₁, θ₅) with their exactness: axes 5, 6 meeting at p₅₆, subproblems 4 then 4; in
    // general subproblem 6 on the k₂ components (module documentation).
    let mut pairs15: Few<(f64, bool, f64, bool), 4> = Few::default();
    if general {
        let gr6 = g.transform_point(&r[5]) - r[0];
        let rgk6 = rg * k[5];
        let (p6, mk6) = (r[4] - r[5], -k[5]);
        for &(phi, t5) in sp6(
            [&k[1], &k[1], &k[1], &k[1]],
            [&k[0], &k[4], &k[0], &k[4]],
            [&gr6, &p6, &rgk6, &mk6],
            k[1].dot(&(r[4] - r[0])),
            0.0,
        )
        .iter()
        {
            pairs15.push((-phi, true, t5, true));
        }
    } else {
        let p56 = &p.center;
        let y = g.transform_point(p56);
        let d1 = k[1].dot(&(p56 - r[0]));
        for &(phi, e1) in roots(sp4(&k[1], &(y - r[0]), &k[0], d1), true, singular).iter() {
            let v5 = rotation(&k[0], phi) * rg * k[5];
            let five = sp4_unit(&k[1], &k[5], &k[4], &v5)
                .unwrap_or_else(|| sp4(&k[1], &k[5], &k[4], k[1].dot(&v5)));
            for &(t5, e5) in roots(five, true, singular).iter() {
                pairs15.push((-phi, e1, t5, e5));
            }
        }
    }
    for &(t1, e1, t5, e5) in pairs15.iter() {
        let phi = -t1;
        let r1t = rotation(&k[0], phi);
        let rg1 = r1t * rg;
        {
            let r5t = rotation(&k[4], -t5);
            let a = rg1.transpose() * k[1];
            let b = r5t * k[1];
            let x5 = r[4] + r5t * (p4 - r[4]);
            let sixes = match sp1(&a, &b, &k[5]) {
                Angles::Any => {
                    // Axis 6 ∥ k₂ (θ₅ = 0 or π): θ₆ joins the planar problem (a planar 4R),
                    // so pick it to put h p₄ at the middle of the 3R's reach:
                    // ‖h p₄ − r₂‖ = ‖R(k₆, −θ₆)(x₅ − r₆) − w‖ with x₅ = e₅⁻¹ p₄ and
                    // w = −R_gᵀ R₁ (r₁ − r₂ + R₁ᵀ (g r₆ − r₁)) (subproblem 3).
                    *singular = true;
                    let c0 = r[0] - r[1] + r1t * (g.transform_point(&r[5]) - r[0]);
                    let w = -(rg1.transpose() * c0);
                    let (v, u) = (p4 - r[2], r[1] - r[2]);
                    let mid = (v.norm_squared() + u.norm_squared()
                        - 2.0 * k[2].dot(&v) * k[2].dot(&u))
                    .max(0.0)
                    .sqrt();
                    // θ₆ is a free choice here: its own exactness does not matter, the planar
                    // subproblems below tell whether the pose is reached.
                    let mut out = roots(sp3(&(x5 - r[5]), &w, &k[5], mid), false, singular);
                    for x in out.iter_mut() {
                        *x = (-x.0, true);
                    }
                    out
                }
                other => roots(other, false, singular),
            };
            for &(t6, e6) in sixes.iter() {
                // h = e₁⁻¹ g e₆⁻¹ e₅⁻¹ applied to p₄, and its rotation applied to perp.
                let r6t = rotation(&k[5], -t6);
                let x = r[5] + r6t * (x5 - r[5]);
                let x = g.transform_point(&x);
                let hp4 = r[0] + r1t * (x - r[0]);
                let hperp = rg1 * (r6t * (r5t * p.perp));
                let (sum, es) = roots(sp1(&p.perp, &hperp, &k[1]), false, singular)[0];
                let d = (hp4 - r[1]).norm();
                for &(t3, e3) in
                    roots(sp3(&(p4 - r[2]), &(r[1] - r[2]), &k[2], d), true, singular).iter()
                {
                    let x = r[2] + rotate(&k[2], t3, &(p4 - r[2]));
                    for &(t2, e2) in
                        roots(sp1(&(x - r[1]), &(hp4 - r[1]), &k[1]), false, singular).iter()
                    {
                        let t4 = wrap(sum - t2 - t3);
                        emit([t1, t2, t3, t4, t5, t6], e1 && e5 && e6 && es && e3 && e2);
                    }
                }
            }
        }
    }
}
