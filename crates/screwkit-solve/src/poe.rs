//! The product-of-exponentials step on [`Columns`]: per-joint constants of e^{[S]θ} and the
//! walks along the chain that feed every joint its θ, sin θ and cos θ. The fast kernels of
//! [`crate::fk`] and [`crate::jacobian`] are built from these.
//!
//! The formulas are those of `screwkit_lie` ([`screwkit_lie::so3::rotation_from_coefficients`],
//! [`screwkit_lie::se3::translation_from_coefficients`], the adjoint
//! [`screwkit_lie::Se3::adjoint_apply`]); the specialisations ([`Update`]: a revolute joint
//! about an exact coordinate axis mixing two columns of R instead of multiplying by Rodrigues'
//! matrix, its planar form skipping the zero component, the near-axis update) are each tested
//! equal to `T · Se3::exp(S θ)` below.

use nalgebra::Vector3;
use screwkit_lie::fma::MulAdd;
use screwkit_lie::se3::{translation_from_coefficients, translation_of_rotation};
use screwkit_lie::{so3, trig, Twist};
use screwkit_model::{Drive, JointKind};

use crate::columns::{add, cross, Columns, Lane};

/// Largest off-axis component |δ| of a revolute axis ω = ±e_k + δ that still takes the
/// near-axis update ([`Columns::rotate_near_axis`]): the terms that update drops are
/// O(|δ|²) ≤ 1e-18, far below the rounding of the general update.
pub(crate) const NEAR_AXIS: f64 = 1e-9;

/// A revolute axis ω that is a coordinate axis (to within 1e-15 per component), with its sign:
/// then T e^{[S]θ} only mixes two columns of R. Or one that is within [`NEAR_AXIS`] of one —
/// how real files write π/2 (`1.57079632679`) puts their axes 1e-13–1e-11 off — with its sign g
/// and u = g·(δ_I, δ_J), the off-axis components (I, J: the other two axes in cyclic order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Aligned {
    /// Not a coordinate axis.
    General,
    /// ±x or near it (sign; u = g·(ω_y, ω_z), zero when exact).
    X(f64, [f64; 2]),
    /// ±y or near it (sign; u = g·(ω_z, ω_x), zero when exact).
    Y(f64, [f64; 2]),
    /// ±z or near it (sign; u = g·(ω_x, ω_y), zero when exact).
    Z(f64, [f64; 2]),
}

impl Aligned {
    fn of(w: &Vector3<f64>) -> Aligned {
        let tiny = |x: f64| x.abs() < 1e-15;
        let near = |x: f64| x.abs() <= NEAR_AXIS;
        let unit = |x: f64| (x.abs() - 1.0).abs() < 1e-15;
        // (k, I, J) with e_I × e_J = e_k.
        for (k, i, j) in [(0, 1, 2), (1, 2, 0), (2, 0, 1)] {
            if !unit(w[k]) || !near(w[i]) || !near(w[j]) {
                continue;
            }
            let g = w[k].signum();
            let u = if tiny(w[i]) && tiny(w[j]) {
                [0.0; 2]
            } else {
                [g * w[i], g * w[j]]
            };
            return match k {
                0 => Aligned::X(g, u),
                1 => Aligned::Y(g, u),
                _ => Aligned::Z(g, u),
            };
        }
        Aligned::General
    }
}

/// Which update [`PoeJoint::apply`] makes, decided once per joint (the block kernels match on
/// it): the axis k (0, 1, 2 for x, y, z) and its sign g where the axis is ±e_k or near it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Update {
    /// p ← p + R (v θ).
    Prismatic,
    /// Pitch 0 about ±e_k exactly: two columns of R and two components of p.
    Planar(usize, f64),
    /// ±e_k exactly, with a pitch: the full translation, two columns of R.
    Axis(usize, f64),
    /// Within [`NEAR_AXIS`] of ±e_k: the near-axis update, with u of [`Aligned`].
    Near(usize, f64, [f64; 2]),
    /// Any other axis: Rodrigues' matrix.
    General,
}

/// One joint of the chain prepared for the kernels: its unit screw S = (ω, v) with the
/// precomputed ω × v and ω × (ω × v), how its θ follows from q ([`Drive`]), and which update
/// it takes.
#[derive(Debug, Clone)]
pub(crate) struct PoeJoint {
    pub(crate) prismatic: bool,
    pub(crate) aligned: Aligned,
    /// A revolute or continuous joint (pitch 0: ω · v is the rounding of v = −ω × q, which the
    /// update drops): its translation is [`translation_of_rotation`]. A helical joint takes the
    /// general G(θ)v, whatever its pitch.
    pub(crate) pitch_zero: bool,
    /// Pitch 0 about an exact coordinate axis e_K (`aligned` with u = 0): e^{[S]θ} moves p
    /// within the plane of the other two axes only, and R ω is ±column K of R, so the updates
    /// skip the K components (zero, or rounding of v = −ω × q, which the axis update drops too).
    pub(crate) planar: bool,
    /// The update the joint takes (from the fields above).
    pub(crate) update: Update,
    pub(crate) w: [f64; 3],
    pub(crate) v: [f64; 3],
    pub(crate) wv: [f64; 3],
    pub(crate) wwv: [f64; 3],
    pub(crate) drive: Drive,
}

impl PoeJoint {
    /// The joint's screw axis (ω, v) as given to [`PoeJoint::new`].
    pub(crate) fn twist(&self) -> Twist {
        Twist::new(self.w.into(), self.v.into())
    }

    /// A revolute or continuous joint (pitch 0), not prismatic or helical.
    pub(crate) fn is_revolute(&self) -> bool {
        self.pitch_zero
    }

    /// Prepares joint `s` of `kind` (revolute, continuous, prismatic or helical) driven by
    /// `drive`. The kind, not the numbers, says whether the pitch is 0: a helical joint keeps
    /// its pitch however small.
    pub(crate) fn new(s: Twist, kind: JointKind, drive: Drive) -> Self {
        let prismatic = kind == JointKind::Prismatic;
        let wv = s.w.cross(&s.v);
        let wwv = s.w.cross(&wv);
        let aligned = if prismatic {
            Aligned::General
        } else {
            Aligned::of(&s.w)
        };
        let pitch_zero = matches!(kind, JointKind::Revolute | JointKind::Continuous);
        let exact_axis = matches!(aligned, Aligned::X(_, u) | Aligned::Y(_, u) | Aligned::Z(_, u) if u == [0.0; 2]);
        let planar = pitch_zero && exact_axis;
        let update = match aligned {
            _ if prismatic => Update::Prismatic,
            Aligned::General => Update::General,
            Aligned::X(g, u) | Aligned::Y(g, u) | Aligned::Z(g, u) => {
                let k = match aligned {
                    Aligned::X(..) => 0,
                    Aligned::Y(..) => 1,
                    _ => 2,
                };
                if planar {
                    Update::Planar(k, g)
                } else if u == [0.0; 2] {
                    Update::Axis(k, g)
                } else {
                    Update::Near(k, g, u)
                }
            }
        };
        Self {
            prismatic,
            aligned,
            pitch_zero,
            planar,
            update,
            w: s.w.into(),
            v: s.v.into(),
            wv: wv.into(),
            wwv: wwv.into(),
            drive,
        }
    }

    /// T ← T e^{[S]θ}, given (sin θ, cos θ), without forming e^{[S]θ} where the joint allows it:
    /// prismatic p ← p + θ R v (R unchanged); revolute or screw p ← p + R G(θ)v
    /// ([`translation_from_coefficients`]), then R ← R e^{[ω]θ}, which for ω = ±(a coordinate
    /// axis) mixes two columns of R ([`Columns::rotate_axis`], 4 column multiply-adds), for ω
    /// within [`NEAR_AXIS`] of one adds the first-order terms in the offset
    /// ([`Columns::rotate_near_axis`], 8 more) and otherwise multiplies by Rodrigues' matrix
    /// ([`so3::rotation_from_coefficients`]).
    #[inline(always)]
    pub(crate) fn apply<A: MulAdd>(&self, t: &mut Columns, theta: f64, s: f64, c: f64) {
        if self.prismatic {
            t.translate::<A>(&self.v.map(|x| x * theta));
            return;
        }
        let b = 1.0 - c;
        let p_local = self.translation::<A>(theta, s, b);
        match self.aligned {
            Aligned::General => {
                let e = so3::rotation_from_coefficients(&self.w.into(), 1.0, s, b);
                *t = t.compose::<A>(&e, &p_local);
            }
            Aligned::X(g, u) => {
                if self.planar {
                    t.translate_pair::<A, 1, 2>(&p_local);
                    t.rotate_axis::<A, 1, 2>(g * s, c);
                } else {
                    t.translate::<A>(&p_local);
                    if u == [0.0; 2] {
                        t.rotate_axis::<A, 1, 2>(g * s, c);
                    } else {
                        t.rotate_near_axis::<A, 1, 2, 0>(g * s, c, &u);
                    }
                }
            }
            Aligned::Y(g, u) => {
                if self.planar {
                    t.translate_pair::<A, 2, 0>(&p_local);
                    t.rotate_axis::<A, 2, 0>(g * s, c);
                } else {
                    t.translate::<A>(&p_local);
                    if u == [0.0; 2] {
                        t.rotate_axis::<A, 2, 0>(g * s, c);
                    } else {
                        t.rotate_near_axis::<A, 2, 0, 1>(g * s, c, &u);
                    }
                }
            }
            Aligned::Z(g, u) => {
                if self.planar {
                    t.translate_pair::<A, 0, 1>(&p_local);
                    t.rotate_axis::<A, 0, 1>(g * s, c);
                } else {
                    t.translate::<A>(&p_local);
                    if u == [0.0; 2] {
                        t.rotate_axis::<A, 0, 1>(g * s, c);
                    } else {
                        t.rotate_near_axis::<A, 0, 1, 2>(g * s, c, &u);
                    }
                }
            }
        }
    }

    /// The translation of e^{[S]θ} (b = 1 − cos θ): [`translation_of_rotation`] at pitch 0,
    /// else the general G(θ) v ([`translation_from_coefficients`]).
    #[inline(always)]
    fn translation<A: MulAdd>(&self, theta: f64, s: f64, b: f64) -> [f64; 3] {
        if self.pitch_zero {
            translation_of_rotation::<A>(&self.v, &self.wv, s, b)
        } else {
            translation_from_coefficients::<A>(&self.v, &self.wv, &self.wwv, theta, b, theta - s)
        }
    }

    /// \[Ad_T\] S = (R ω, R v + p × R ω) as two lanes (w = 0): the Jacobian column of this joint
    /// when the joints before it make T ([`screwkit_lie::Se3::adjoint_apply`] on columns).
    #[inline(always)]
    pub(crate) fn adjoint_column<A: MulAdd>(&self, t: &Columns) -> (Lane, Lane) {
        // A planar joint about ±e_K: R ω = ±R e_K, and v has no K component.
        let (w, v) = match (self.planar, self.aligned) {
            (true, Aligned::X(g, _)) => (t.column_scaled(0, g), t.rotate_pair::<A, 1, 2>(&self.v)),
            (true, Aligned::Y(g, _)) => (t.column_scaled(1, g), t.rotate_pair::<A, 2, 0>(&self.v)),
            (true, Aligned::Z(g, _)) => (t.column_scaled(2, g), t.rotate_pair::<A, 0, 1>(&self.v)),
            _ => (t.rotate::<A>(&self.w), t.rotate::<A>(&self.v)),
        };
        let v = add(v, cross(t.p(), w));
        (w, v)
    }
}

/// Walks `joints` base → tip calling `f(j, joint, θ_j, sin θ_j, cos θ_j)`, θ_j from its
/// [`Drive`] (or q\[j\] directly when `identity_map`); the sines and cosines are computed
/// [`trig::LANES`] joints at a time, vectorised.
#[inline(always)]
pub(crate) fn walk<A: MulAdd>(
    joints: &[PoeJoint],
    identity_map: bool,
    q: &[f64],
    mut f: impl FnMut(usize, &PoeJoint, f64, f64, f64),
) {
    const L: usize = trig::LANES;
    for (b, block) in joints.chunks(L).enumerate() {
        let mut theta = [0.0; L];
        for (i, th) in theta.iter_mut().enumerate().take(block.len()) {
            *th = joint_theta(joints, identity_map, b * L + i, q);
        }
        let (mut s, mut c) = ([0.0; L], [0.0; L]);
        trig::sin_cos_lanes_with::<A>(&theta, &mut s, &mut c);
        for (i, jc) in block.iter().enumerate() {
            f(b * L + i, jc, theta[i], s[i], c[i]);
        }
    }
}

/// [`walk`] tip → base.
#[inline(always)]
pub(crate) fn walk_rev<A: MulAdd>(
    joints: &[PoeJoint],
    identity_map: bool,
    q: &[f64],
    mut f: impl FnMut(usize, &PoeJoint, f64, f64, f64),
) {
    const L: usize = trig::LANES;
    let n = joints.len();
    let mut end = n;
    while end > 0 {
        let start = end.saturating_sub(L);
        let mut theta = [0.0; L];
        for (i, th) in theta.iter_mut().enumerate().take(end - start) {
            *th = joint_theta(joints, identity_map, start + i, q);
        }
        let (mut s, mut c) = ([0.0; L], [0.0; L]);
        trig::sin_cos_lanes_with::<A>(&theta, &mut s, &mut c);
        for i in (0..end - start).rev() {
            f(start + i, &joints[start + i], theta[i], s[i], c[i]);
        }
        end = start;
    }
}

/// θ_j: q\[j\] when every joint owns its variable, else the joint's [`Drive`].
#[inline(always)]
pub(crate) fn joint_theta(joints: &[PoeJoint], identity_map: bool, j: usize, q: &[f64]) -> f64 {
    if identity_map {
        q[j]
    } else {
        joints[j].drive.theta(q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use screwkit_lie::{ScrewAxis, Se3};

    /// Every arm of `apply` (aligned axes with either sign, pitch 0 and ≠ 0, a general axis,
    /// prismatic) equals T · e^{[S]θ} with the exponential of screwkit-lie.
    #[test]
    fn apply_equals_compose_with_the_exponential() {
        let t = Se3::exp(&Twist::new(
            Vector3::new(0.3, -0.8, 0.5),
            Vector3::new(0.2, 0.1, -0.4),
        ));
        let point = Vector3::new(0.3, -0.2, 0.7);
        let mut cases = vec![];
        for axis in [
            Vector3::x(),
            -Vector3::x(),
            Vector3::y(),
            -Vector3::y(),
            Vector3::z(),
            -Vector3::z(),
            Vector3::new(1.0, 1.0, 0.0).normalize(),
            // Off a coordinate axis by 1e-11 .. 1e-9: the near-axis update.
            Vector3::new(1.0, 3e-11, -2e-12).normalize(),
            Vector3::new(-4e-12, -1.0, 1e-9).normalize(),
            Vector3::new(-2e-11, 7e-13, 1.0).normalize(),
            Vector3::new(1e-13, 0.0, -1.0).normalize(),
        ] {
            for pitch in [0.0, 0.35] {
                let s = ScrewAxis::from_point_direction_pitch(point, axis, pitch).unwrap();
                let kind = if pitch == 0.0 {
                    JointKind::Revolute
                } else {
                    JointKind::Helical
                };
                let jc = PoeJoint::new(*s.twist(), kind, Drive::independent(0));
                assert_eq!(
                    jc.aligned == Aligned::General,
                    axis.x.abs() > 0.5 && axis.y.abs() > 0.5
                );
                let off = [axis.x, axis.y, axis.z]
                    .iter()
                    .filter(|x| x.abs() < 0.5 && x.abs() >= 1e-15)
                    .count();
                assert_eq!(
                    matches!(jc.aligned, Aligned::X(_, u) | Aligned::Y(_, u) | Aligned::Z(_, u) if u != [0.0; 2]),
                    off > 0 && jc.aligned != Aligned::General,
                    "{axis:?}"
                );
                // Planar (the lean translation and adjoint column): pitch 0 about an exact axis.
                let exact = matches!(jc.aligned, Aligned::X(_, u) | Aligned::Y(_, u) | Aligned::Z(_, u) if u == [0.0; 2]);
                assert_eq!(jc.pitch_zero, pitch == 0.0, "{axis:?}");
                assert_eq!(jc.planar, pitch == 0.0 && exact, "{axis:?}");
                cases.push((*s.twist(), jc));
            }
        }
        let slide = ScrewAxis::prismatic(Vector3::new(0.2, -0.4, 0.8).normalize()).unwrap();
        cases.push((
            *slide.twist(),
            PoeJoint::new(*slide.twist(), JointKind::Prismatic, Drive::independent(0)),
        ));
        for (twist, jc) in &cases {
            for theta in [-2.5f64, -0.3, 0.0, 1e-9, 0.7, 3.0] {
                let (sn, cs) = theta.sin_cos();
                let mut cols = Columns::from_se3(&t);
                let mut fused = cols;
                jc.apply::<screwkit_lie::fma::Plain>(&mut cols, theta, sn, cs);
                // Fused outside the dispatched clone is a library call: slow, same values.
                jc.apply::<screwkit_lie::fma::Fused>(&mut fused, theta, sn, cs);
                let oracle = t.compose(&Se3::exp(&(*twist * theta)));
                for got in [cols.to_se3(), fused.to_se3()] {
                    assert!(got.max_abs_diff(&oracle) < 1e-14, "{twist:?} {theta}");
                }
                // The near-axis and axis updates against Rodrigues' full product (the general
                // update of the same joint): equal to rounding.
                let mut general = jc.clone();
                general.aligned = Aligned::General;
                let mut full = Columns::from_se3(&t);
                general.apply::<screwkit_lie::fma::Plain>(&mut full, theta, sn, cs);
                let diff = cols.to_se3().max_abs_diff(&full.to_se3());
                assert!(
                    diff < 2e-16 * (1.0 + theta.abs()),
                    "{twist:?} {theta}: {diff:e}"
                );
                let (w, v) = jc.adjoint_column::<screwkit_lie::fma::Plain>(&Columns::from_se3(&t));
                let want = t.adjoint_apply(twist);
                for i in 0..3 {
                    assert!((w[i] - want.w[i]).abs() < 1e-15 && (v[i] - want.v[i]).abs() < 1e-15);
                }
            }
        }
    }
}
