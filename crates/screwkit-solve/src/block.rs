//! The block kernels of the batches: the tip pose, and the tip pose with the space Jacobian,
//! of W = 8 configurations at once, one per lane of [`screwkit_lie::lanes`]: the eight in one
//! pass on AVX-512 (one register holds a value of all eight), in two passes of four on AVX2
//! and portably.
//!
//! T ← T e^{\[S\]θ} multiplies T on the right, so each row (R_i0, R_i1, R_i2, p_i) of T's top
//! three changes on its own: the kernels walk the chain joint by joint, the three rows'
//! twelve values in registers, compute each joint's per-configuration constants once (sin θ,
//! cos θ, the translation of e^{\[S\]θ}, the rotation's coefficients) and apply them to the
//! three rows ([`apply_joint`]). The space Jacobian's column j, \[Ad_T\] S_j = (R ω, R v + p × R ω)
//! with T the joints before j, is row by row too except for p × R ω, finished per joint.
//!
//! The operations and their order are those of [`PoeJoint::apply`] and
//! [`PoeJoint::adjoint_column`] (the multiply-add rounded as the lanes' scalar policy), so
//! every lane equals the single call on its configuration bit for bit.

// Index loops on purpose in this module: an iterator adaptor or closure may stay out of line,
// and then it is compiled without the dispatch's instruction set.
#![allow(clippy::needless_range_loop)]

use screwkit_lie::lanes::{LaneKernel, Lanes, MAX_WIDTH};
use screwkit_lie::trig;

use crate::kinematics::Kinematics;
use crate::poe::{Aligned, PoeJoint, Update};

/// Configurations per block.
pub(crate) const W: usize = MAX_WIDTH;

/// T ← T e^{\[S\]θ} for the eight configurations (θ, sin θ, cos θ per lane) on the rows
/// (R_i0, R_i1, R_i2, p_i) of T: [`PoeJoint::apply`]'s update row by row, the joint's constants
/// computed once for the three rows. One match per joint ([`Update`]), each arm computing only
/// what its update reads.
#[inline(always)]
fn apply_joint<L: Lanes>(
    l: L,
    joint: &PoeJoint,
    th: L::V,
    s: L::V,
    c: L::V,
    rows: &mut [[L::V; 4]; 3],
) {
    match joint.update {
        Update::Prismatic => {
            // p ← p + R (v θ).
            let v = &joint.v;
            let t = [
                l.mul(l.splat(v[0]), th),
                l.mul(l.splat(v[1]), th),
                l.mul(l.splat(v[2]), th),
            ];
            for r in rows.iter_mut() {
                translate(l, r, &t);
            }
        }
        Update::Planar(0, g) => planar::<L, 1, 2>(l, joint, g, s, c, rows),
        Update::Planar(1, g) => planar::<L, 2, 0>(l, joint, g, s, c, rows),
        Update::Planar(_, g) => planar::<L, 0, 1>(l, joint, g, s, c, rows),
        Update::Axis(0, g) => axis::<L, 1, 2>(l, joint, g, th, s, c, rows),
        Update::Axis(1, g) => axis::<L, 2, 0>(l, joint, g, th, s, c, rows),
        Update::Axis(_, g) => axis::<L, 0, 1>(l, joint, g, th, s, c, rows),
        Update::Near(0, g, u) => near::<L, 1, 2, 0>(l, joint, g, &u, th, s, c, rows),
        Update::Near(1, g, u) => near::<L, 2, 0, 1>(l, joint, g, &u, th, s, c, rows),
        Update::Near(_, g, u) => near::<L, 0, 1, 2>(l, joint, g, &u, th, s, c, rows),
        Update::General => general(l, joint, th, s, c, rows),
    }
}

/// The translation of e^{\[S\]θ} (b = 1 − cos θ): `translation_of_rotation` at pitch 0, else
/// `translation_from_coefficients` with a = θ, c = θ − sin θ.
#[inline(always)]
fn translation<L: Lanes>(l: L, joint: &PoeJoint, th: L::V, s: L::V, b: L::V) -> [L::V; 3] {
    let (v, wv, wwv) = (&joint.v, &joint.wv, &joint.wwv);
    let mut t = [b; 3];
    // No closures or `map` in the kernels: a closure may stay out of line, and then it is
    // compiled without the dispatch's instruction set.
    if joint.pitch_zero {
        for i in 0..3 {
            t[i] = l.madd(l.splat(wv[i]), b, l.mul(l.splat(v[i]), s));
        }
    } else {
        let ts = l.sub(th, s);
        for i in 0..3 {
            t[i] = l.madd(
                l.splat(v[i]),
                th,
                l.madd(l.splat(wv[i]), b, l.mul(l.splat(wwv[i]), ts)),
            );
        }
    }
    t
}

/// Pitch 0 about ±e_K exactly: `translate_pair::<I, J>` (only components I and J of the
/// translation, the K one being zero) then `rotate_axis::<I, J>`.
#[inline(always)]
fn planar<L: Lanes, const I: usize, const J: usize>(
    l: L,
    joint: &PoeJoint,
    g: f64,
    s: L::V,
    c: L::V,
    rows: &mut [[L::V; 4]; 3],
) {
    let (v, wv) = (&joint.v, &joint.wv);
    let b = l.sub(l.splat(1.0), c);
    let ti = l.madd(l.splat(wv[I]), b, l.mul(l.splat(v[I]), s));
    let tj = l.madd(l.splat(wv[J]), b, l.mul(l.splat(v[J]), s));
    let gs = l.mul(l.splat(g), s);
    let minus_gs = l.neg(gs);
    for r in rows.iter_mut() {
        r[3] = l.madd(r[I], ti, l.madd(r[J], tj, r[3]));
        rotate_axis::<L, I, J>(l, r, gs, minus_gs, c);
    }
}

/// An exact coordinate axis with a pitch: `translate` then `rotate_axis::<I, J>`.
#[inline(always)]
fn axis<L: Lanes, const I: usize, const J: usize>(
    l: L,
    joint: &PoeJoint,
    g: f64,
    th: L::V,
    s: L::V,
    c: L::V,
    rows: &mut [[L::V; 4]; 3],
) {
    let AxisLanes {
        t, gs, minus_gs, ..
    } = AxisLanes::new(l, joint, g, th, s, c);
    for r in rows.iter_mut() {
        translate(l, r, &t);
        rotate_axis::<L, I, J>(l, r, gs, minus_gs, c);
    }
}

/// What the updates about (or near) a coordinate axis with a full translation share: b = 1 −
/// cos θ, the translation of e^{\[S\]θ}, and g sin θ with its negative.
struct AxisLanes<V> {
    b: V,
    t: [V; 3],
    gs: V,
    minus_gs: V,
}

impl<V: Copy> AxisLanes<V> {
    #[inline(always)]
    fn new<L: Lanes<V = V>>(l: L, joint: &PoeJoint, g: f64, th: V, s: V, c: V) -> Self {
        let b = l.sub(l.splat(1.0), c);
        let gs = l.mul(l.splat(g), s);
        AxisLanes {
            b,
            t: translation(l, joint, th, s, b),
            gs,
            minus_gs: l.neg(gs),
        }
    }
}

/// `rotate_axis::<I, J>` on one row: col_I ← c col_I + s col_J, col_J ← c col_J − s col_I
/// (s = g sin θ).
#[inline(always)]
fn rotate_axis<L: Lanes, const I: usize, const J: usize>(
    l: L,
    r: &mut [L::V; 4],
    s: L::V,
    minus_s: L::V,
    c: L::V,
) {
    let (u, w) = (r[I], r[J]);
    r[I] = l.madd(w, s, l.mul(u, c));
    r[J] = l.madd(u, minus_s, l.mul(w, c));
}

/// Within [`crate::poe::NEAR_AXIS`] of ±e_K: `translate` then `rotate_near_axis::<I, J, K>`
/// (its four coefficients once for the rows).
#[inline(always)]
#[allow(clippy::too_many_arguments)] // the joint's lanes, spelled out for the kernel
fn near<L: Lanes, const I: usize, const J: usize, const K: usize>(
    l: L,
    joint: &PoeJoint,
    g: f64,
    u: &[f64; 2],
    th: L::V,
    s: L::V,
    c: L::V,
    rows: &mut [[L::V; 4]; 3],
) {
    let AxisLanes { b, t, gs, minus_gs } = AxisLanes::new(l, joint, g, th, s, c);
    let (ui, uj) = (l.splat(u[0]), l.splat(u[1]));
    let ki = l.madd(b, ui, l.neg(l.mul(gs, uj)));
    let kj = l.madd(b, uj, l.mul(gs, ui));
    let ii = l.madd(b, ui, l.mul(gs, uj));
    let ij = l.madd(b, uj, l.neg(l.mul(gs, ui)));
    for r in rows.iter_mut() {
        translate(l, r, &t);
        let (ri, rj, rk) = (r[I], r[J], r[K]);
        r[I] = l.madd(rk, ki, l.madd(rj, gs, l.mul(ri, c)));
        r[J] = l.madd(rk, kj, l.madd(ri, minus_gs, l.mul(rj, c)));
        r[K] = l.madd(ri, ii, l.madd(rj, ij, rk));
    }
}

/// Any other axis: `translate` then the rotation columns times Rodrigues' matrix
/// (`so3::rotation_from_coefficients(ω, 1, sin θ, 1 − cos θ)`, as written there;
/// `Columns::compose`).
#[inline(always)]
fn general<L: Lanes>(
    l: L,
    joint: &PoeJoint,
    th: L::V,
    s: L::V,
    c: L::V,
    rows: &mut [[L::V; 4]; 3],
) {
    let b = l.sub(l.splat(1.0), c);
    let t = translation(l, joint, th, s, b);
    let [x, y, z] = [
        l.splat(joint.w[0]),
        l.splat(joint.w[1]),
        l.splat(joint.w[2]),
    ];
    let d = l.sub(l.splat(1.0), l.mul(l.mul(b, l.splat(1.0)), l.splat(1.0)));
    let (bx, by) = (l.mul(b, x), l.mul(b, y));
    let (bxy, bxz, byz) = (l.mul(bx, y), l.mul(bx, z), l.mul(by, z));
    let (ax, ay, az) = (l.mul(s, x), l.mul(s, y), l.mul(s, z));
    let e = [
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
    for r in rows.iter_mut() {
        translate(l, r, &t);
        let [r0, r1, r2, _] = *r;
        for k in 0..3 {
            r[k] = l.madd(r0, e[k], l.madd(r1, e[3 + k], l.mul(r2, e[6 + k])));
        }
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

/// The rows of T = e^{\[S₁\]θ₁} ⋯ e^{\[Sₙ\]θₙ} for the [`Lanes::WIDTH`] configurations at the
/// start of `qs` (rows of dof values), and with `jac` (row-major 6 × dof each; the chain's
/// joints must each own their variable) their space Jacobians.
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
                    for (x, row) in lanes[..L::WIDTH].iter_mut().zip(qs.chunks_exact(n)) {
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
        apply_joint(l, joint, theta[k], s, c, &mut rows);
        if let (Some(jac), true) = (jac.as_deref_mut(), k == 3 || j + 1 == joints.len()) {
            let first = j - k;
            for (i, col) in cols.iter().enumerate() {
                l.store_transposed(col, k + 1, jac, i * n + first, 6 * n);
            }
        }
    }
    rows
}

/// The rows times the home pose M (`Columns::compose` with M's constants), written as
/// [`Lanes::WIDTH`] row-major 4 × 4 poses.
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
    for pose in out[..16 * L::WIDTH].chunks_exact_mut(16) {
        pose[12..].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
    }
}

/// The tip poses of W configurations: `qs` holds W rows of dof values, `out` gets W
/// row-major 4 × 4 poses, each equal to [`crate::fk::fk`] of its row bit for bit. Used by
/// [`crate::batch::fk_batch`].
pub(crate) struct TipBlock<'a> {
    pub(crate) kin: &'a Kinematics,
    pub(crate) qs: &'a [f64],
    pub(crate) out: &'a mut [f64],
}

/// Whether every value of `xs` (a whole number of lane values long) is finite.
#[inline(always)]
fn all_finite<L: Lanes>(l: L, xs: &[f64]) -> bool {
    let mut finite = true;
    for x in xs.chunks_exact(L::WIDTH) {
        finite &= l.all_below(l.abs(l.load(x)), f64::INFINITY);
    }
    finite
}

impl LaneKernel for TipBlock<'_> {
    /// False (nothing written) when a value of `qs` is not finite.
    type Output = bool;
    #[inline(always)]
    fn run<L: Lanes>(self, l: L) -> bool {
        let n = self.kin.dof();
        if !all_finite(l, &self.qs[..W * n]) {
            return false;
        }
        for first in (0..W).step_by(L::WIDTH) {
            let rows = chain_rows(l, self.kin, &self.qs[first * n..], None);
            write_poses(l, self.kin, &rows, &mut self.out[16 * first..]);
        }
        true
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
    /// False (nothing written) when a value of `qs` is not finite.
    type Output = bool;
    #[inline(always)]
    fn run<L: Lanes>(self, l: L) -> bool {
        debug_assert!(self.kin.identity_map);
        let Self {
            kin,
            qs,
            jac,
            mut poses,
        } = self;
        let n = kin.dof();
        if !all_finite(l, &qs[..W * n]) {
            return false;
        }
        for first in (0..W).step_by(L::WIDTH) {
            let rows = chain_rows(l, kin, &qs[first * n..], Some(&mut jac[6 * n * first..]));
            if let Some(p) = poses.as_deref_mut() {
                write_poses(l, kin, &rows, &mut p[16 * first..]);
            }
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use crate::poe::Update;

    /// The test chains (`kernels_agree` checks the block kernels on them) take every update,
    /// about every axis.
    #[test]
    fn the_test_chains_take_every_update() {
        let mut seen = Vec::new();
        for (_, kin) in crate::test_chains() {
            for joint in &kin.space {
                let kind = match joint.update {
                    Update::Prismatic => (0, 0),
                    Update::Planar(k, _) => (1, k),
                    Update::Axis(k, _) => (2, k),
                    Update::Near(k, ..) => (3, k),
                    Update::General => (4, 0),
                };
                if !seen.contains(&kind) {
                    seen.push(kind);
                }
            }
        }
        assert_eq!(seen.len(), 11, "{seen:?}");
    }
}
