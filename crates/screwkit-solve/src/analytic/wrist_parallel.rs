//! **Spherical wrist, 2 ∥ 3** (KUKA KR, ABB IRB, PUMA-type). p_w, where axes 4, 5, 6 meet,
//! is not moved by them: y = g p_w = e₁ e₂ e₃ p_w. Rotations 2 and 3 keep k₂ components, so
//! k₂ · e₁⁻¹ y = k₂ · p_w gives θ₁ (subproblem 4); z = e₁⁻¹ y keeps its distance to axis 2
//! under e₂: ‖e₃ p_w − r₂‖ = ‖z − r₂‖ gives θ₃ (subproblem 3); e₂ (e₃ p_w) = z gives θ₂
//! (subproblem 1). Then the wrist (below).

use super::*;

/// Spherical wrist, 2 ∥ 3 (module documentation).
pub(super) fn wrist_parallel(
    p: &Prepared,
    g: &Se3,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let (k, r, pw) = (&p.k, &p.r, &p.center);
    let rg = g.rotation();
    let y = g.transform_point(pw);
    let d1 = k[1].dot(&(pw - r[0]));
    // k₃ = s k₂ (parallel), so R₂ R₃ = R(k₂, θ₂ + s θ₃).
    let s3 = k[1].dot(&k[2]).signum();
    for &(phi, e1) in roots(sp4(&k[1], &(y - r[0]), &k[0], d1), true, singular).iter() {
        let t1 = -phi;
        let r1t = rotation(&k[0], phi);
        let rg1 = r1t * rg;
        let z = r[0] + r1t * (y - r[0]);
        let d = (z - r[1]).norm();
        for &(t3, e3) in roots(sp3(&(pw - r[2]), &(r[1] - r[2]), &k[2], d), true, singular).iter() {
            let x = r[2] + rotate(&k[2], t3, &(pw - r[2]));
            for &(t2, e2) in roots(sp1(&(x - r[1]), &(z - r[1]), &k[1]), false, singular).iter() {
                let rw = rotation(&k[1], -(t2 + s3 * t3)) * rg1;
                wrist(p, &rw, singular, |t4, t5, t6, ok| {
                    emit([t1, t2, t3, t4, t5, t6], ok && e1 && e2 && e3);
                });
            }
        }
    }
}
