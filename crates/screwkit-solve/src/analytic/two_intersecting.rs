//! Two intersecting axes 5–6 only (or 1–2, read from the tip): a 1D search over θ₄; at each
//! θ₄ the position of the point where axes 5 and 6 meet is a 3R problem in θ₁, θ₂, θ₃
//! ([`position_3r`], subproblem 5), and θ₅, θ₆ follow from the rotation (subproblems 4 and 1).

use super::*;

/// The triples (θ₁, θ₂, θ₃) reaching y = e₁ e₂ e₃ e₄ p₅₆ at θ₄ (subproblem 5), each with the
/// orientation error e = k₅ᵀ R_w k₆ − k₅ᵀ k₆ (R_w = (R₁R₂R₃R₄)ᵀ R_g), zero exactly when
/// R₅ R₆ = R_w has a solution.
pub(super) fn search56_at(p: &Prepared, g: &Se3, t4: f64) -> Few<([f64; 4], f64), 4> {
    let (k, r, p56) = (&p.k, &p.r, &p.center);
    let y = g.transform_point(p56);
    let x = r[3] + rotate(&k[3], t4, &(p56 - r[3]));
    let mut out = Few::default();
    for &(t1, t2, t3) in position_3r(p, &y, &x).iter() {
        let t = [t1, t2, t3, t4];
        let r14 = rotation(&k[0], t[0])
            * rotation(&k[1], t[1])
            * rotation(&k[2], t[2])
            * rotation(&k[3], t[3]);
        let rw = r14.transpose() * g.rotation();
        out.push((t, k[4].dot(&(rw * k[5])) - k[4].dot(&k[5])));
    }
    out
}

/// Axes 5 and 6 meeting (a 1D search over θ₄, as IK-Geo does for this family): p₅₆ is moved
/// by joints 1–4 only, so for each θ₄ subproblem 5 gives up to 4 triples (θ₁, θ₂, θ₃)
/// ([`search56_at`]), and a triple belongs to a solution when R₅ R₆ = R_w is solvable, i.e.
/// when e(θ₄) = k₅ᵀ R_w k₆ − k₅ᵀ k₆ = 0 ([`search_1d`]); θ₅ and θ₆ then follow by
/// subproblem 1.
pub(super) fn search56(p: &Prepared, g: &Se3, emit: &mut impl FnMut([f64; 6], bool)) {
    let (k, rg) = (&p.k, g.rotation());
    let roots = search_1d(|t4| search56_at(p, g, t4));
    let mut found: Few<[f64; 6], MAX_POSTURES> = Few::default();
    for t in roots {
        let r14 = rotation(&k[0], t[0])
            * rotation(&k[1], t[1])
            * rotation(&k[2], t[2])
            * rotation(&k[3], t[3]);
        let rw = r14.transpose() * rg;
        // R₅ k₆ = R_w k₆, R₆ k₅ = R₅ᵀ R_w k₅.
        let t5 = sp1(&k[5], &(rw * k[5]), &k[4]).first();
        let want = rotation(&k[4], t5).transpose() * (rw * k[4]);
        let t6 = sp1(&k[4], &want, &k[5]).first();
        let q = [t[0], t[1], t[2], wrap(t[3]), t5, t6];
        if !found
            .iter()
            .any(|f| (0..6).all(|i| wrap(f[i] - q[i]).abs() < 1e-7))
        {
            found.push(q);
            emit(q, true);
        }
    }
}
