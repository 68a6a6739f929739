//! The block kernels of the batches: the tip pose, and the tip pose with the space Jacobian,
//! of W = 8 configurations at once, one per lane of [`screwkit_lie::lanes`] (on AVX-512 one
//! register holds a value of all eight).
//!
//! T ← T e^{\[S\]θ} multiplies T on the right, so each row (R_i0, R_i1, R_i2, p_i) of T's top
//! three changes on its own: the kernels walk the chain one row at a time, the row's four
//! values staying in registers, and read each joint's per-configuration constants (sin θ,
//! cos θ, the translation of e^{\[S\]θ}, the rotation's coefficients), computed once per joint
//! beforehand ([`JointLanes`]). The space Jacobian's column j, \[Ad_T\] S_j = (R ω, R v + p × R ω)
//! with T the joints before j, is row by row too except for p × R ω, which is finished once
//! the three rows are known.
//!
//! The operations and their order are those of [`PoeJoint::apply`] and
//! [`PoeJoint::adjoint_column`] (the multiply-add rounded as the lanes' scalar policy), so
//! every lane equals the single call on its configuration bit for bit.

// Index loops on purpose in this module: an iterator adaptor or closure may stay out of line,
// and then it is compiled without the dispatch's instruction set.
#![allow(clippy::needless_range_loop)]

use screwkit_lie::lanes::{LaneKernel, Lanes, WIDTH};
use screwkit_lie::trig;

use crate::kinematics::Kinematics;
use crate::poe::{Aligned, PoeJoint};

/// Configurations per block.
pub(crate) const W: usize = WIDTH;

/// Which update a joint takes (see [`PoeJoint::apply`]), with its axis: X, Y, Z mix columns
/// (1, 2), (2, 0), (0, 1) of R.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Step {
    /// p ← p + R (v θ).
    Prismatic,
    /// Pitch 0 about an exact coordinate axis: the two-column translation and rotation.
    PlanarX,
    PlanarY,
    PlanarZ,
    /// An exact coordinate axis with a pitch (the full translation, the axis rotation).
    AxisX,
    AxisY,
    AxisZ,
    /// Within [`crate::poe::NEAR_AXIS`] of a coordinate axis: the near-axis rotation.
    NearX,
    NearY,
    NearZ,
    /// Any other axis: Rodrigues' matrix.
    General,
}

impl Step {
    fn of(joint: &PoeJoint) -> Step {
        if joint.prismatic {
            return Step::Prismatic;
        }
        let exact = |u: [f64; 2]| u == [0.0; 2];
        match joint.aligned {
            Aligned::General => Step::General,
            Aligned::X(..) if joint.planar => Step::PlanarX,
            Aligned::Y(..) if joint.planar => Step::PlanarY,
            Aligned::Z(..) if joint.planar => Step::PlanarZ,
            Aligned::X(_, u) if exact(u) => Step::AxisX,
            Aligned::Y(_, u) if exact(u) => Step::AxisY,
            Aligned::Z(_, u) if exact(u) => Step::AxisZ,
            Aligned::X(..) => Step::NearX,
            Aligned::Y(..) => Step::NearY,
            Aligned::Z(..) => Step::NearZ,
        }
    }
}

/// One joint's constants for the eight configurations of a block.
#[derive(Clone, Copy)]
struct JointLanes<V> {
    step: Step,
    /// The translation of e^{\[S\]θ} (v θ for a prismatic joint).
    t: [V; 3],
    /// The rotation's coefficients: for an axis update (g sin θ, −g sin θ, cos θ) and, near an
    /// axis, the four of [`crate::columns::Columns::rotate_near_axis`]; for a general axis the
    /// entries of e^{\[ω\]θ}, row-major.
    r: [V; 9],
}

impl<V: Copy> JointLanes<V> {
    /// θ, sin θ and cos θ of `joint` (`th`, `s`, `c`) to its constants, with the operations of
    /// [`PoeJoint::apply`].
    #[inline(always)]
    fn new<L: Lanes<V = V>>(l: L, joint: &PoeJoint, th: V, s: V, c: V) -> Self {
        let step = Step::of(joint);
        let zero = l.splat(0.0);
        let mut out = JointLanes {
            step,
            t: [zero; 3],
            r: [zero; 9],
        };
        let (v, wv, wwv) = (&joint.v, &joint.wv, &joint.wwv);
        if step == Step::Prismatic {
            for i in 0..3 {
                out.t[i] = l.mul(l.splat(v[i]), th);
            }
            return out;
        }
        let b = l.sub(l.splat(1.0), c);
        // No closures or `map` in the kernels: a closure may stay out of line, and then it is
        // compiled without the dispatch's instruction set.
        if joint.pitch_zero {
            // `translation_of_rotation`.
            for i in 0..3 {
                out.t[i] = l.madd(l.splat(wv[i]), b, l.mul(l.splat(v[i]), s));
            }
        } else {
            // `translation_from_coefficients` with a = θ, c = θ − sin θ.
            let ts = l.sub(th, s);
            for i in 0..3 {
                out.t[i] = l.madd(
                    l.splat(v[i]),
                    th,
                    l.madd(l.splat(wv[i]), b, l.mul(l.splat(wwv[i]), ts)),
                );
            }
        }
        match joint.aligned {
            Aligned::General => {
                // `so3::rotation_from_coefficients(ω, 1, sin θ, 1 − cos θ)`, as written there.
                let [x, y, z] = [
                    l.splat(joint.w[0]),
                    l.splat(joint.w[1]),
                    l.splat(joint.w[2]),
                ];
                let d = l.sub(l.splat(1.0), l.mul(l.mul(b, l.splat(1.0)), l.splat(1.0)));
                let (bx, by) = (l.mul(b, x), l.mul(b, y));
                let (bxy, bxz, byz) = (l.mul(bx, y), l.mul(bx, z), l.mul(by, z));
                let (ax, ay, az) = (l.mul(s, x), l.mul(s, y), l.mul(s, z));
                out.r = [
                    l.add(d, l.mul(bx, x)),
                    l.sub(bxy, az),
                    l.add(bxz, ay),
                    l.add(bxy, az),
                    l.add(d, l.mul(by, y)),
                    l.sub(byz, ax),
                    l.sub(bxz, ay),
                    l.add(byz, ax),
                    l.add(d, l.mul(l.mul(b, z), z)),
                ];
            }
            Aligned::X(g, u) | Aligned::Y(g, u) | Aligned::Z(g, u) => {
                let gs = l.mul(l.splat(g), s);
                out.r[0] = gs;
                out.r[1] = l.neg(gs);
                out.r[2] = c;
                if matches!(step, Step::NearX | Step::NearY | Step::NearZ) {
                    // `Columns::rotate_near_axis`'s coefficients (s = g sin θ there).
                    let (ui, uj) = (l.splat(u[0]), l.splat(u[1]));
                    out.r[3] = l.madd(b, ui, l.neg(l.mul(gs, uj)));
                    out.r[4] = l.madd(b, uj, l.mul(gs, ui));
                    out.r[5] = l.madd(b, ui, l.mul(gs, uj));
                    out.r[6] = l.madd(b, uj, l.neg(l.mul(gs, ui)));
                }
            }
        }
        out
    }

    /// T ← T e^{\[S\]θ} on the rows (R_i0, R_i1, R_i2, p_i) of T: the single call's update
    /// row by row ([`crate::columns::Columns`]' operations, row i of each column).
    #[inline(always)]
    fn apply<L: Lanes<V = V>>(&self, l: L, rows: &mut [[V; 4]; 3]) {
        // One match, then the three rows inside each arm (no closures: see `new`).
        macro_rules! each_row {
            ($r:ident => $e:expr) => {
                for $r in rows.iter_mut() {
                    $e
                }
            };
        }
        match self.step {
            Step::Prismatic => each_row!(r => translate(l, r, &self.t)),
            Step::PlanarX => each_row!(r => self.planar::<L, 1, 2>(l, r)),
            Step::PlanarY => each_row!(r => self.planar::<L, 2, 0>(l, r)),
            Step::PlanarZ => each_row!(r => self.planar::<L, 0, 1>(l, r)),
            Step::AxisX => each_row!(r => self.axis::<L, 1, 2>(l, r)),
            Step::AxisY => each_row!(r => self.axis::<L, 2, 0>(l, r)),
            Step::AxisZ => each_row!(r => self.axis::<L, 0, 1>(l, r)),
            Step::NearX => each_row!(r => self.near::<L, 1, 2, 0>(l, r)),
            Step::NearY => each_row!(r => self.near::<L, 2, 0, 1>(l, r)),
            Step::NearZ => each_row!(r => self.near::<L, 0, 1, 2>(l, r)),
            Step::General => each_row!(r => self.general(l, r)),
        }
    }

    /// `translate` then the rotation columns times Rodrigues' matrix (`Columns::compose`).
    #[inline(always)]
    fn general<L: Lanes<V = V>>(&self, l: L, r: &mut [V; 4]) {
        translate(l, r, &self.t);
        let [a, b, c, _] = *r;
        let e = &self.r;
        for k in 0..3 {
            r[k] = l.madd(a, e[k], l.madd(b, e[3 + k], l.mul(c, e[6 + k])));
        }
    }

    /// `translate_pair::<I, J>` then `rotate_axis::<I, J>`.
    #[inline(always)]
    fn planar<L: Lanes<V = V>, const I: usize, const J: usize>(&self, l: L, r: &mut [V; 4]) {
        r[3] = l.madd(r[I], self.t[I], l.madd(r[J], self.t[J], r[3]));
        self.rotate_axis::<L, I, J>(l, r);
    }

    /// `translate` then `rotate_axis::<I, J>`.
    #[inline(always)]
    fn axis<L: Lanes<V = V>, const I: usize, const J: usize>(&self, l: L, r: &mut [V; 4]) {
        translate(l, r, &self.t);
        self.rotate_axis::<L, I, J>(l, r);
    }

    /// `rotate_axis::<I, J>`: col_I ← c col_I + s col_J, col_J ← c col_J − s col_I.
    #[inline(always)]
    fn rotate_axis<L: Lanes<V = V>, const I: usize, const J: usize>(&self, l: L, r: &mut [V; 4]) {
        let (u, w) = (r[I], r[J]);
        let [gs, minus_gs, c, ..] = self.r;
        r[I] = l.madd(w, gs, l.mul(u, c));
        r[J] = l.madd(u, minus_gs, l.mul(w, c));
    }

    /// `translate` then `rotate_near_axis::<I, J, K>`.
    #[inline(always)]
    fn near<L: Lanes<V = V>, const I: usize, const J: usize, const K: usize>(
        &self,
        l: L,
        r: &mut [V; 4],
    ) {
        translate(l, r, &self.t);
        let [s, minus_s, c, ki, kj, ii, ij, ..] = self.r;
        let (ri, rj, rk) = (r[I], r[J], r[K]);
        r[I] = l.madd(rk, ki, l.madd(rj, s, l.mul(ri, c)));
        r[J] = l.madd(rk, kj, l.madd(ri, minus_s, l.mul(rj, c)));
        r[K] = l.madd(ri, ii, l.madd(rj, ij, rk));
    }
}

/// `Columns::translate` on one row: p_i ← R_i0 t_0 + (R_i1 t_1 + (R_i2 t_2 + p_i)).
#[inline(always)]
fn translate<L: Lanes>(l: L, r: &mut [L::V; 4], t: &[L::V; 3]) {
    r[3] = l.madd(r[0], t[0], l.madd(r[1], t[1], l.madd(r[2], t[2], r[3])));
}

/// `Columns::rotate` on one row: R_i · x = R_i0 x_0 + (R_i1 x_1 + R_i2 x_2).
#[inline(always)]
fn rotate_row<L: Lanes>(l: L, r: &[L::V; 4], x: &[f64; 3]) -> L::V {
    l.madd(
        r[0],
        l.splat(x[0]),
        l.madd(r[1], l.splat(x[1]), l.mul(r[2], l.splat(x[2]))),
    )
}

/// Row i of joint `joint`'s space-Jacobian column before p × R ω: ((R ω)_i, (R v)_i), as
/// [`PoeJoint::adjoint_column`] computes them.
#[inline(always)]
fn column_row<L: Lanes>(l: L, joint: &PoeJoint, r: &[L::V; 4]) -> (L::V, L::V) {
    match (joint.planar, joint.aligned) {
        (true, Aligned::X(g, _)) => (
            l.mul(r[0], l.splat(g)),
            rotate_pair::<L, 1, 2>(l, r, &joint.v),
        ),
        (true, Aligned::Y(g, _)) => (
            l.mul(r[1], l.splat(g)),
            rotate_pair::<L, 2, 0>(l, r, &joint.v),
        ),
        (true, Aligned::Z(g, _)) => (
            l.mul(r[2], l.splat(g)),
            rotate_pair::<L, 0, 1>(l, r, &joint.v),
        ),
        _ => (rotate_row(l, r, &joint.w), rotate_row(l, r, &joint.v)),
    }
}

/// `Columns::rotate_pair::<I, J>` on one row: R_iI x_I + R_iJ x_J.
#[inline(always)]
fn rotate_pair<L: Lanes, const I: usize, const J: usize>(
    l: L,
    r: &[L::V; 4],
    x: &[f64; 3],
) -> L::V {
    l.madd(r[I], l.splat(x[I]), l.mul(r[J], l.splat(x[J])))
}

/// The identity's three rows.
#[inline(always)]
fn identity_rows<L: Lanes>(l: L) -> [[L::V; 4]; 3] {
    let (o, z) = (l.splat(1.0), l.splat(0.0));
    [[o, z, z, z], [z, o, z, z], [z, z, o, z]]
}

/// The rows of T = e^{\[S₁\]θ₁} ⋯ e^{\[Sₙ\]θₙ} for the W configurations of `qs` (W rows of dof
/// values), and with `jac` (W row-major 6 × dof; the chain's joints must each own their
/// variable) the space Jacobians.
#[inline(always)]
fn chain_rows<L: Lanes>(
    l: L,
    kin: &Kinematics,
    qs: &[f64],
    mut jac: Option<&mut [f64]>,
) -> [[L::V; 4]; 3] {
    // dof values per row of `qs`; as many joints as values unless some are mimic joints
    // (then no Jacobian: `jac` is None).
    let (n, joints) = (kin.dof(), &kin.space);
    let mut rows = identity_rows(l);
    let zero = l.splat(0.0);
    // θ of four joints, one value per joint holding every configuration.
    let mut theta = [zero; 4];
    // Jacobian columns (ω, v) of up to four joints, written out four at a time.
    let mut cols = [[zero; 4]; 6];
    for j in 0..joints.len() {
        let k = j % 4;
        if k == 0 {
            let m = (joints.len() - j).min(4);
            if kin.identity_map {
                theta = l.load_transposed(qs, j, n, m);
            } else {
                for (t, joint) in theta.iter_mut().zip(&joints[j..j + m]) {
                    let mut lanes = [0.0; W];
                    for (x, row) in lanes.iter_mut().zip(qs.chunks_exact(n)) {
                        *x = joint.drive.theta(row);
                    }
                    *t = l.load(&lanes);
                }
            }
        }
        let joint = &joints[j];
        if jac.is_some() {
            // \[Ad_T\] S_j = (R ω, R v + p × R ω) with T the joints before j (`columns::cross`).
            let mut w = [zero; 3];
            let mut v = [zero; 3];
            for i in 0..3 {
                (w[i], v[i]) = column_row(l, joint, &rows[i]);
            }
            let p = [rows[0][3], rows[1][3], rows[2][3]];
            let cross = [
                l.sub(l.mul(p[1], w[2]), l.mul(p[2], w[1])),
                l.sub(l.mul(p[2], w[0]), l.mul(p[0], w[2])),
                l.sub(l.mul(p[0], w[1]), l.mul(p[1], w[0])),
            ];
            for i in 0..3 {
                cols[i][k] = w[i];
                cols[3 + i][k] = l.add(v[i], cross[i]);
            }
        }
        let (s, c) = trig::sin_cos_in(l, theta[k]);
        JointLanes::new(l, joint, theta[k], s, c).apply(l, &mut rows);
        if let (Some(jac), true) = (jac.as_deref_mut(), k == 3 || j + 1 == joints.len()) {
            let first = j - k;
            for (i, col) in cols.iter().enumerate() {
                l.store_transposed(col, k + 1, jac, i * n + first, 6 * n);
            }
        }
    }
    rows
}

/// The rows times the home pose M (`Columns::compose` with M's constants), written as W
/// row-major 4 × 4 poses.
#[inline(always)]
fn write_poses<L: Lanes>(l: L, kin: &Kinematics, rows: &[[L::V; 4]; 3], out: &mut [f64]) {
    let (e, t) = (kin.home.rotation(), kin.home.translation());
    for (i, r) in rows.iter().enumerate() {
        let mut r = *r;
        translate(l, &mut r, &[l.splat(t.x), l.splat(t.y), l.splat(t.z)]);
        let mut four = r;
        for k in 0..3 {
            four[k] = l.madd(
                r[0],
                l.splat(e[(0, k)]),
                l.madd(r[1], l.splat(e[(1, k)]), l.mul(r[2], l.splat(e[(2, k)]))),
            );
        }
        l.store_transposed(&four, 4, out, 4 * i, 16);
    }
    for pose in out[..16 * W].chunks_exact_mut(16) {
        pose[12..].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
    }
}

/// The tip poses of W configurations: `qs` holds W rows of dof finite values, `out` gets W
/// row-major 4 × 4 poses, each equal to [`crate::fk::fk`] of its row bit for bit. Used by
/// [`crate::batch::fk_batch`].
pub(crate) struct TipBlock<'a> {
    pub(crate) kin: &'a Kinematics,
    pub(crate) qs: &'a [f64],
    pub(crate) out: &'a mut [f64],
}

impl LaneKernel for TipBlock<'_> {
    type Output = ();
    #[inline(always)]
    fn run<L: Lanes>(self, l: L) {
        let rows = chain_rows(l, self.kin, self.qs, None);
        write_poses(l, self.kin, &rows, self.out);
    }
}

/// Tip poses and space Jacobians of W configurations, for chains whose joints each own their
/// variable: `qs` W rows of dof values, `jac` W row-major 6 × dof Jacobians, `poses` W
/// row-major 4 × 4 (when given); each row equals [`crate::jacobian::fk_jacobian`] bit for bit.
pub(crate) struct SpaceJacobianBlock<'a> {
    pub(crate) kin: &'a Kinematics,
    pub(crate) qs: &'a [f64],
    pub(crate) jac: &'a mut [f64],
    pub(crate) poses: Option<&'a mut [f64]>,
}

impl LaneKernel for SpaceJacobianBlock<'_> {
    type Output = ();
    #[inline(always)]
    fn run<L: Lanes>(self, l: L) {
        debug_assert!(self.kin.identity_map);
        let rows = chain_rows(l, self.kin, self.qs, Some(self.jac));
        if let Some(p) = self.poses {
            write_poses(l, self.kin, &rows, p);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Step;

    /// The test chains (`kernels_agree` checks the block kernels on them) take every update.
    #[test]
    fn the_test_chains_take_every_update() {
        let mut seen = Vec::new();
        for (_, kin) in crate::test_chains() {
            for joint in &kin.space {
                let step = Step::of(joint);
                if !seen.contains(&step) {
                    seen.push(step);
                }
            }
        }
        assert_eq!(seen.len(), 11, "{seen:?}");
    }
}
