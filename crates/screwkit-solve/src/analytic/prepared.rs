//! A 6R problem ready to solve: the lines in the order solved and the points its
//! decomposition needs ([`Prepared`]).

use super::*;

/// A 6R problem ready to solve: lines in the order solved, the home of the 6R chain (chain
/// order), the method's points.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Prepared {
    pub(super) k: [V3; 6],
    pub(super) r: [V3; 6],
    pub(super) home: Se3,
    /// The wrist center or p₅₆.
    pub(super) center: V3,
    /// Where the intersecting pair meets (wrist families with two intersecting axes).
    pub(super) meet: V3,
    /// A unit vector ⊥ k₂ (three-parallel family).
    pub(super) perp: V3,
    /// The problem's length L (general 6R: lengths are solved in units of L).
    pub(super) scale: f64,
    /// The general 6R's reading: roles 1…6 are joints shift+1, … (`general::choose_shift`).
    pub(super) shift: usize,
}

impl Prepared {
    /// From six lines in chain order and their home; reversed: solve tip to base.
    #[inline]
    /// `shift`: the general 6R's reading ([`choose_shift`]; ignored by the other methods).
    pub(super) fn new(
        method: Method,
        lines: &[AxisLine; 6],
        home: Se3,
        reversed: bool,
        shift: usize,
    ) -> Self {
        let mut k = [V3::zeros(); 6];
        let mut r = [V3::zeros(); 6];
        for i in 0..6 {
            let l = if reversed { &lines[5 - i] } else { &lines[i] };
            k[i] = if reversed { -l.direction } else { l.direction };
            r[i] = l.point;
        }
        let line = |i: usize| AxisLine {
            direction: k[i],
            point: r[i],
        };
        let meet = |i: usize| closest_points(&line(i), &line(i + 1)).0;
        let center = match method {
            Method::ThreeParallel => meet(4),
            Method::ThreeParallelGeneral | Method::General => V3::zeros(),
            _ => (meet(3) + meet(4)) / 2.0,
        };
        let pair = match method {
            Method::WristIntersecting12 => meet(0),
            Method::WristIntersecting23 => meet(1),
            _ => V3::zeros(),
        };
        let a = if k[1].x.abs() < 0.9 { V3::x() } else { V3::y() };
        let scale = scale_of(&r, &home);
        Self {
            k,
            r,
            home,
            center,
            meet: pair,
            perp: (a - k[1] * k[1].dot(&a)).normalize(),
            scale,
            shift,
        }
    }
}

/// A locked solver's prepared problem at one lock value, kept in the caller's workspace
/// ([`crate::Workspace`]): a 7R arm solved again and again at the same lock value (EAIK's
/// fixed axes, a user's locked joint) prepares its 6R problem once. Keyed by the solver's
/// identity and the value's bits, so a workspace shared by several solvers, or a sweep, only
/// ever reads the problem it would build.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PreparedAt {
    /// [`AnalyticIk`]'s identity (`id`: one per construction, kept by its clones).
    pub(super) solver: u64,
    /// The lock value's bits.
    pub(super) value: u64,
    pub(super) prepared: Prepared,
}

/// A new solver identity ([`PreparedAt`]).
pub(super) fn next_solver_id() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}
