//! **Spherical wrist only**: R(k₁, −θ₁)(y − r₁) + r₁ − r₂ = R₂ ((r₃ − r₂) + R₃ (p_w − r₃))
//! is subproblem 5 (up to 4 triples), then the wrist.

use super::*;

/// (θ₁, θ₂, θ₃) with e₁ e₂ e₃ x = y for three general axes: R(k₁, −θ₁)(y − r₁) + r₁ − r₂ =
/// R₂ ((r₃ − r₂) + R₃ (x − r₃)), subproblem 5 (up to 4 triples).
pub(super) fn position_3r(p: &Prepared, y: &V3, x: &V3) -> Few<(f64, f64, f64), 4> {
    let (k, r) = (&p.k, &p.r);
    let mut out = sp5(
        &(r[0] - r[1]),
        &(y - r[0]),
        &(r[2] - r[1]),
        &(x - r[2]),
        &k[0],
        &k[1],
        &k[2],
    );
    for t in out.iter_mut() {
        t.0 = -t.0;
    }
    out
}

/// Spherical wrist only (module documentation): subproblem 5 for θ₁, θ₂, θ₃, then the wrist.
pub(super) fn wrist_only(
    p: &Prepared,
    g: &Se3,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let (k, pw) = (&p.k, &p.center);
    let rg = g.rotation();
    let y = g.transform_point(pw);
    for &(t1, t2, t3) in position_3r(p, &y, pw).iter() {
        let r123 = rotation(&k[0], t1) * rotation(&k[1], t2) * rotation(&k[2], t3);
        let rw = r123.transpose() * rg;
        wrist(p, &rw, singular, |t4, t5, t6, ok| {
            emit([t1, t2, t3, t4, t5, t6], ok);
        });
    }
}
