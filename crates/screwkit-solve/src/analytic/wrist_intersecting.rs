//! **Spherical wrist, two intersecting axes** (1–2 meeting at o, or 2–3). Axes 1–2: e₁ e₂
//! fix o, so ‖y − o‖ = ‖e₃ p_w − o‖ gives θ₃ (subproblem 3) and R(k₁, −θ₁)(y − o) =
//! R(k₂, θ₂)(e₃ p_w − o) gives θ₁, θ₂ (subproblem 2). Axes 2–3: ‖e₁⁻¹ y − o‖ = ‖p_w − o‖
//! gives θ₁ (subproblem 3), R(k₂, −θ₂)(e₁⁻¹ y − o) = R(k₃, θ₃)(p_w − o) gives θ₂, θ₃
//! (subproblem 2). Then the wrist.

use super::*;

/// Spherical wrist, axes 1–2 (`first`) or 2–3 meeting (module documentation).
pub(super) fn wrist_intersecting(
    p: &Prepared,
    g: &Se3,
    first: bool,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let (k, r, pw, o) = (&p.k, &p.r, &p.center, &p.meet);
    let rg = g.rotation();
    let y = g.transform_point(pw);
    let mut finish = |t1: f64, t2: f64, t3: f64, ok: bool, singular: &mut bool| {
        let r123 = rotation(&k[0], t1) * rotation(&k[1], t2) * rotation(&k[2], t3);
        let rw = r123.transpose() * rg;
        wrist(p, &rw, singular, |t4, t5, t6, e| {
            emit([t1, t2, t3, t4, t5, t6], ok && e);
        });
    };
    if first {
        let d = (y - o).norm();
        for &(t3, e3) in roots(sp3(&(pw - r[2]), &(o - r[2]), &k[2], d), true, singular).iter() {
            let x = r[2] + rotate(&k[2], t3, &(pw - r[2]));
            let (a, b) = (y - o, x - o);
            for &(m1, t2, e12) in pairs(sp2(&a, &b, &k[0], &k[1]), &a, &b, &k[1], singular).iter() {
                finish(-m1, t2, t3, e3 && e12, singular);
            }
        }
    } else {
        let d = (pw - o).norm();
        for &(phi, e1) in roots(sp3(&(y - r[0]), &(o - r[0]), &k[0], d), true, singular).iter() {
            let z = r[0] + rotate(&k[0], phi, &(y - r[0]));
            let (a, b) = (z - o, pw - o);
            for &(m2, t3, e23) in pairs(sp2(&a, &b, &k[1], &k[2]), &a, &b, &k[2], singular).iter() {
                finish(-phi, -m2, t3, e1 && e23, singular);
            }
        }
    }
}
