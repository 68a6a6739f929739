//! Two parallel axes 2 ∥ 3 only (or 4 ∥ 5, read from the tip): a 1D search over θ₁; at each
//! θ₁ the planar pair and the rest follow from subproblem 6 ([`two_parallel_rest`]).

use super::*;

/// For the two-parallel search at θ₁, with h = e₁⁻¹ g = e₂ e₃ e₄ e₅ e₆ and R₂₃ = R(k₂, θ₂₃):
/// the k₂ components of h e₆⁻¹ r₅ = e₂ e₃ e₄ r₅ and of R₄ R₅ k₅ = R₂₃ᵀ R_h R₆ᵀ k₅ give
/// (R_hᵀ k₂)ᵀ R(k₆, −θ₆)(r₅ − r₆) − k₂ᵀ R₄ (r₅ − r₄) = k₂·r₄ − k₂·(h r₆) and
/// (R_hᵀ k₂)ᵀ R(k₆, −θ₆) k₅ − k₂ᵀ R₄ k₅ = 0: subproblem 6 in (−θ₆, θ₄). Then θ₂₃ (subproblem
/// 1), θ₅ (subproblem 1) and H₂₃ = h e₆⁻¹ e₅⁻¹ e₄⁻¹ = e₂ e₃; the branch is a solution when
/// H₂₃ r₃ is as far from axis 2 as r₃ is: the error. State: (θ₆, θ₄, θ₂₃, θ₁).
pub(super) fn search23_at(p: &Prepared, g: &Se3, t1: f64) -> Few<([f64; 4], f64), 4> {
    let (k, r) = (&p.k, &p.r);
    let r1t = rotation(&k[0], -t1);
    let hr = r1t * g.rotation();
    let h = |x: &V3| r[0] + r1t * (g.transform_point(x) - r[0]);
    let hk2 = hr.transpose() * k[1];
    let (p56, p45) = (r[4] - r[5], r[3] - r[4]);
    let mk5 = -k[4];
    let d1 = k[1].dot(&r[3]) - k[1].dot(&h(&r[5]));
    let mut out = Few::default();
    for &(m6, t4) in sp6(
        [&hk2, &k[1], &hk2, &k[1]],
        [&k[5], &k[3], &k[5], &k[3]],
        [&p56, &p45, &k[4], &mk5],
        d1,
        0.0,
    )
    .iter()
    {
        let t6 = -m6;
        let (r4, r6) = (rotation(&k[3], t4), rotation(&k[5], t6));
        let t23 = sp1(&(r4 * k[4]), &(hr * (r6.transpose() * k[4])), &k[1]).first();
        let (h23, _) = two_parallel_rest(p, g, t1, t23, t4, t6);
        let off = |x: V3| {
            let d = x - r[1];
            (d - k[1] * k[1].dot(&d)).norm()
        };
        out.push(([t6, t4, t23, t1], off(h23) - off(r[2])));
    }
    out
}

/// θ₅ and H₂₃ r₃ for the two-parallel search (see [`search23_at`]).
pub(super) fn two_parallel_rest(
    p: &Prepared,
    g: &Se3,
    t1: f64,
    t23: f64,
    t4: f64,
    t6: f64,
) -> (V3, f64) {
    let (k, r) = (&p.k, &p.r);
    let r1t = rotation(&k[0], -t1);
    let hr = r1t * g.rotation();
    let (r4, r6, r23) = (
        rotation(&k[3], t4),
        rotation(&k[5], t6),
        rotation(&k[1], t23),
    );
    // R₅ = R₄ᵀ R₂₃ᵀ R_h R₆ᵀ: R₅ k₆ = R₄ᵀ R₂₃ᵀ R_h k₆ (or, with k₆ ∥ k₅, R₅ᵀ k₄ = R₆ R_hᵀ R₂₃ k₄).
    let t5 = if k[4].cross(&k[5]).norm() > 1e-3 {
        let want = r4.transpose() * (r23.transpose() * (hr * k[5]));
        sp1(&k[5], &want, &k[4]).first()
    } else {
        let want = r6 * (hr.transpose() * (r23 * k[3]));
        -sp1(&k[3], &want, &k[4]).first()
    };
    // H₂₃ r₃ = h(e₆⁻¹(e₅⁻¹(e₄⁻¹ r₃))).
    let back = |i: usize, t: f64, x: V3| r[i] + rotate(&k[i], -t, &(x - r[i]));
    let x = back(5, t6, back(4, t5, back(3, t4, r[2])));
    let hx = r[0] + r1t * (g.transform_point(&x) - r[0]);
    (hx, t5)
}

/// Axes 2 ∥ 3 only (a 1D search over θ₁, as IK-Geo does for this family): [`search23_at`]
/// and [`search_1d`]; then θ₂ by subproblem 1 (e₂ r₃ = H₂₃ r₃) and θ₃ = ±(θ₂₃ − θ₂).
pub(super) fn search23(p: &Prepared, g: &Se3, emit: &mut impl FnMut([f64; 6], bool)) {
    let (k, r) = (&p.k, &p.r);
    let s3 = k[1].dot(&k[2]).signum();
    let mut found: Few<[f64; 6], MAX_POSTURES> = Few::default();
    for st in search_1d(|t1| search23_at(p, g, t1)) {
        let [t6, t4, t23, t1] = st;
        let (h23, t5) = two_parallel_rest(p, g, t1, t23, t4, t6);
        let t2 = sp1(&(r[2] - r[1]), &(h23 - r[1]), &k[1]).first();
        let q = [wrap(t1), t2, wrap(s3 * (t23 - t2)), t4, t5, t6];
        if !found
            .iter()
            .any(|f| (0..6).all(|i| wrap(f[i] - q[i]).abs() < 1e-7))
        {
            found.push(q);
            emit(q, true);
        }
    }
}
