//! **7R arms by their arm angle**: a spherical shoulder (axes 1–3 meet at S) and a spherical
//! wrist (axes 5–7 meet at W) around an elbow joint 4 — the KUKA iiwa's, Franka-like
//! SRS arms' — whose self-motion is the elbow's swing about the shoulder–wrist line.
//!
//! **The arm angle ψ** (the definition every call here uses): with S and W the centres at
//! home, E the point of axis 4 nearest S (the elbow), a configuration q moves them to
//! W(q) = e₁e₂e₃e₄ W and E(q) = e₁e₂e₃ E (S stays). With u = (W(q) − S)/‖W(q) − S‖ and
//! r the direction of axis 1 made perpendicular to u (the *reference plane* is the plane of
//! the shoulder–wrist line and axis 1: vertical for a floor-mounted arm), and e the elbow's
//! offset E(q) − S made perpendicular to u, ψ = atan2(u · (r × e), r · e): ψ = 0 puts the
//! elbow in the reference plane on axis 1's side (elbow up), ψ grows turning about u by the
//! right hand. Where W(q) lies on axis 1's line through S, r is undefined (a singularity of
//! the parameterisation, not of the arm): the home elbow's offset made perpendicular to u is
//! used instead.
//!
//! **Solving at ψ** (g = T M⁻¹): W_t = g W, D = ‖W_t − S‖; θ₄ by subproblem 3
//! (‖e₄(W) − S‖ = D, up to 2); for each, X = e₄ W, and the elbow at ψ is
//! E_ψ = S + a u + ρ (cos ψ r + sin ψ u × r) with a = (E − S)·(X − S)/‖X − S‖ and
//! ρ² = ‖E − S‖² − a²; the shoulder's rotation R_sh takes (X − S, E − S) to (W_t − S, E_ψ − S)
//! (two vector pairs of equal lengths and angle: one rotation), R₁R₂R₃ = R_sh by the
//! three-axis step (up to 2), R₅R₆R₇ = (R₁R₂R₃R₄)ᵀ R_g (up to 2): up to 8 postures per ψ.
//!
//! **Near-special geometry** is snapped: axes that meet within [`SNAP`] × L (a file that
//! writes π/2 as 1.5708, 1e-6 off) are solved as meeting at the midpoint of their closest
//! points, and each posture is then polished by Newton steps on the real chain (least-norm
//! steps of all seven joints), so the answers are exact for the file as written.

use super::*;

/// Axes closer than this × L are taken to meet (the snapping tolerance).
pub const SNAP: f64 = 1e-5;

/// What an arm-angle solver holds: the seven lines (chain order), the centres and the elbow
/// at home, the home pose.
#[derive(Debug, Clone, Copy)]
pub(super) struct ArmAngle {
    k: [V3; 7],
    r: [V3; 7],
    shoulder: V3,
    elbow: V3,
    wrist: V3,
    home: Se3,
}

/// Where three consecutive lines meet (within `tol`), if they do.
fn meeting(lines: &[AxisLine], tol: f64) -> Option<V3> {
    let meet = |a: &AxisLine, b: &AxisLine| {
        if a.direction.cross(&b.direction).norm() < 1e-9 {
            return None;
        }
        let (p, d) = closest_points(a, b);
        (d <= tol).then_some(p)
    };
    let p = meet(&lines[0], &lines[1])?;
    let q = meet(&lines[1], &lines[2])?;
    ((p - q).norm() <= tol).then_some((p + q) / 2.0)
}

impl ArmAngle {
    /// From a 7R chain's lines and home; None unless axes 1–3 and axes 5–7 each meet in a
    /// point (within [`SNAP`] × `length`) and the elbow's axis misses both points.
    pub(super) fn new(lines: &[AxisLine], home: Se3, length: f64) -> Option<Self> {
        if lines.len() != 7 {
            return None;
        }
        let tol = SNAP * length.max(1e-9);
        let shoulder = meeting(&lines[0..3], tol)?;
        let wrist = meeting(&lines[4..7], tol)?;
        let l4 = &lines[3];
        let elbow = l4.point + l4.direction * l4.direction.dot(&(shoulder - l4.point));
        let off = |c: &V3| (c - l4.point).cross(&l4.direction).norm();
        if off(&shoulder) <= tol || off(&wrist) <= tol || (wrist - shoulder).norm() <= tol {
            return None;
        }
        Some(Self {
            k: std::array::from_fn(|i| lines[i].direction),
            r: std::array::from_fn(|i| lines[i].point),
            shoulder,
            elbow,
            wrist,
            home,
        })
    }

    /// e_i(x): x turned by θ about line i.
    #[inline]
    fn turn(&self, i: usize, t: f64, x: &V3) -> V3 {
        self.r[i] + rotate(&self.k[i], t, &(x - self.r[i]))
    }

    /// The unit shoulder–wrist direction u for a wrist centre `w` and the reference r ⊥ u
    /// (module documentation); None when w is at the shoulder.
    fn frame(&self, w: &V3) -> Option<(V3, V3)> {
        let d = w - self.shoulder;
        let n = d.norm();
        if n.is_nan() || n <= 0.0 {
            return None;
        }
        let u = d / n;
        let perp = |v: V3| {
            let p = v - u * u.dot(&v);
            let m = p.norm();
            (m > 1e-9 * v.norm().max(1e-300)).then(|| p / m)
        };
        let any = if u.x.abs() < 0.9 { V3::x() } else { V3::y() };
        let r = perp(self.k[0])
            .or_else(|| perp(self.elbow - self.shoulder))
            .or_else(|| perp(any))?;
        Some((u, r))
    }

    /// The arm angle ψ of configuration `q` (7 values), in [−π, π]; NaN where the wrist
    /// centre is at the shoulder or the elbow on the shoulder–wrist line.
    pub(super) fn angle_of(&self, q: &[f64]) -> f64 {
        let mut w = self.turn(3, q[3], &self.wrist);
        let mut e = self.elbow;
        for i in (0..3).rev() {
            w = self.turn(i, q[i], &w);
            e = self.turn(i, q[i], &e);
        }
        let Some((u, r)) = self.frame(&w) else {
            return f64::NAN;
        };
        let d = e - self.shoulder;
        let off = d - u * u.dot(&d);
        if off.norm() <= 1e-12 * d.norm() {
            return f64::NAN;
        }
        u.dot(&r.cross(&off)).atan2(r.dot(&off))
    }

    /// Every posture at arm angle `psi` (module documentation), each as 7 angles with its
    /// exactness; `singular` set at a double root (elbow stretched), a free angle, or an
    /// elbow on the shoulder–wrist line.
    pub(super) fn postures(
        &self,
        target: &Se3,
        psi: f64,
        singular: &mut bool,
        emit: &mut impl FnMut([f64; 7], bool),
    ) {
        let g = target.compose(&self.home.inverse());
        let wt = g.transform_point(&self.wrist);
        let s = self.shoulder;
        let Some((u, r)) = self.frame(&wt) else {
            *singular = true;
            return;
        };
        let d = (wt - s).norm();
        let (k4, r4) = (self.k[3], self.r[3]);
        let four = sp3(&(self.wrist - r4), &(s - r4), &k4, d);
        let (sp, cp) = psi.sin_cos();
        let toward = r * cp + u.cross(&r) * sp;
        let rg = *g.rotation();
        for &(t4, e4) in roots(four, true, singular).iter() {
            let x = self.turn(3, t4, &self.wrist) - s;
            let (xn, en) = (x.norm(), self.elbow - s);
            if xn.is_nan() || xn <= 0.0 {
                *singular = true;
                continue;
            }
            let ux = x / xn;
            let a = en.dot(&ux);
            let off = en - ux * a;
            let rho = off.norm();
            if rho <= 1e-12 * en.norm() {
                // The elbow on the shoulder–wrist line: ψ does not move it.
                *singular = true;
                continue;
            }
            // R_sh takes the frame (ux, off/ρ) to (u, toward).
            let f = M3::from_columns(&[ux, off / rho, ux.cross(&(off / rho))]);
            let h = M3::from_columns(&[u, toward, u.cross(&toward)]);
            let rsh = h * f.transpose();
            let r4m = rotation(&k4, t4);
            let (k, rg) = (&self.k, &rg);
            let mut wrist_singular = false;
            three_axes([&k[0], &k[1], &k[2]], &rsh, singular, |t1, t2, t3, e123| {
                let r14 = rotation(&k[0], t1) * rotation(&k[1], t2) * rotation(&k[2], t3) * r4m;
                let rw = r14.transpose() * rg;
                three_axes(
                    [&k[4], &k[5], &k[6]],
                    &rw,
                    &mut wrist_singular,
                    |t5, t6, t7, e567| {
                        emit([t1, t2, t3, t4, t5, t6, t7], e4 && e123 && e567);
                    },
                );
            });
            *singular |= wrist_singular;
        }
    }
}
