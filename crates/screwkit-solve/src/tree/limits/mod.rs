//! Limits of whole-body differential IK as types, one file each (mink's shape): each narrows
//! the box l ≤ Δ ≤ u on a step's displacement Δ = v·dt ([`super::differential_ik`]), and the
//! step applies every one in turn, starting from the unbounded box.
//!
//! - [`PositionLimit`]: q + Δ within the joint variables' bounds (the floating base is
//!   unbounded); a q already outside them is an error naming the joint, never clipped.
//! - [`VelocityLimit`]: |Δ_j| ≤ dt · min(the file's `velocity`, the caller's cap for j), for a
//!   control step (an iteration towards convergence has no dt: nothing to narrow).
//!
//! [`Limits`] is what the front ends configure; [`Limits::each`] lists the limit objects it
//! stands for, then its `extra` ones (a new kind of limit is a file here implementing
//! [`Limit`], given in `extra`). A limit that is not a box (collision avoidance:
//! `screwkit_collision::CollisionAvoidance`, one row per close pair) gives general inequality
//! rows G Δ ≥ h ([`Limit::rows`]); a step with rows is solved by [`crate::linalg::qp`] in place
//! of [`crate::linalg::box_qp`].

use std::sync::Arc;

use super::TreeKinematics;
use crate::error::SolveError;

mod position;
mod velocity;

pub use position::{PositionLimit, LIMIT_TOLERANCE};
pub use velocity::VelocityLimit;

/// A constraint on a step's displacement Δ (nv entries, the floating base's six first).
pub trait Limit: std::fmt::Debug + Send + Sync {
    /// Its own values against the model (lengths, signs): the error says what is wrong.
    fn check(&self, kin: &TreeKinematics) -> Result<(), SolveError>;
    /// Narrows the box `lo ≤ Δ ≤ hi` at q for a control step of `dt` (None: an iteration
    /// towards convergence), never widening it. An error when q itself breaks the limit.
    fn narrow(
        &self,
        kin: &TreeKinematics,
        q: &[f64],
        dt: Option<f64>,
        lo: &mut [f64],
        hi: &mut [f64],
    ) -> Result<(), SolveError>;
    /// Appends its general inequality rows at q, G Δ ≥ h (each row nv values to `g`, its bound
    /// to `h`, and a tag of its own meaning to `tags`: which pair a collision row is), on the
    /// step's displacement Δ = v·dt whatever dt: a box limit has none.
    fn rows(
        &self,
        kin: &TreeKinematics,
        q: &[f64],
        g: &mut Vec<f64>,
        h: &mut Vec<f64>,
        tags: &mut Vec<usize>,
    ) -> Result<(), SolveError> {
        let _ = (kin, q, g, h, tags);
        Ok(())
    }
    /// True when q itself keeps the limit (a collision limit: every pair at least its margin
    /// apart). Whole-body IK to convergence redraws a restart that does not, and prefers an
    /// answer that does. Always true by default (a box limit is kept by the step).
    fn satisfied(&self, kin: &TreeKinematics, q: &[f64]) -> Result<bool, SolveError> {
        let _ = (kin, q);
        Ok(true)
    }
    /// After a step Δ to `q_next`, raises the bounds `h` of its rows (`tags` as [`Limit::rows`]
    /// gave them; `moved` each row's G Δ) whose limit the step broke, by the shortfall (the rows
    /// are the limit's linearisation at q; the limit itself is not linear); true when it
    /// raised any, and the step is then solved again. None by default.
    fn tighten(
        &self,
        kin: &TreeKinematics,
        q_next: &[f64],
        tags: &[usize],
        moved: &[f64],
        h: &mut [f64],
    ) -> Result<bool, SolveError> {
        let _ = (kin, q_next, tags, moved, h);
        Ok(false)
    }
}

/// The rows of a step from every limit, and which limit gave which rows.
#[derive(Debug, Clone, Default)]
pub struct LimitRows {
    /// G, row-major (nv per row).
    pub g: Vec<f64>,
    /// The bounds h of G Δ ≥ h.
    pub h: Vec<f64>,
    /// Each row's tag (the limit's own).
    pub tags: Vec<usize>,
    /// Rows per extra limit, in order.
    counts: Vec<usize>,
    /// Each row's G Δ after a step (scratch of [`Limits::tighten`]).
    moved: Vec<f64>,
}

/// Which limits a step respects (module documentation): what front ends configure.
#[derive(Debug, Clone)]
pub struct Limits {
    /// q + v·dt within the position bounds (default true): [`PositionLimit`].
    pub position: bool,
    /// |v_j| within the file's `velocity` limits (default true): [`VelocityLimit`].
    pub velocity: bool,
    /// The caller's speed caps per joint variable (n values, rad/s or m/s; ∞ for none),
    /// combined with the file's by the minimum.
    pub velocity_caps: Option<Vec<f64>>,
    /// Further limits, applied after those (none by default).
    pub extra: Vec<Arc<dyn Limit>>,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            position: true,
            velocity: true,
            velocity_caps: None,
            extra: Vec::new(),
        }
    }
}

impl PartialEq for Limits {
    /// Equal settings and the same extra limit objects.
    fn eq(&self, other: &Limits) -> bool {
        self.position == other.position
            && self.velocity == other.velocity
            && self.velocity_caps == other.velocity_caps
            && self.extra.len() == other.extra.len()
            && self
                .extra
                .iter()
                .zip(&other.extra)
                .all(|(a, b)| Arc::ptr_eq(a, b))
    }
}

impl Limits {
    /// Every limit object these settings stand for, in the order they narrow the box.
    pub fn each(
        &self,
        f: &mut dyn FnMut(&dyn Limit) -> Result<(), SolveError>,
    ) -> Result<(), SolveError> {
        if self.position {
            f(&PositionLimit)?;
        }
        if self.velocity || self.velocity_caps.is_some() {
            f(&VelocityLimit {
                file: self.velocity,
                caps: self.velocity_caps.as_deref(),
            })?;
        }
        for limit in &self.extra {
            f(limit.as_ref())?;
        }
        Ok(())
    }

    /// The box of a step at q: every limit checked, then narrowing the unbounded box in turn.
    pub(crate) fn bounds(
        &self,
        kin: &TreeKinematics,
        q: &[f64],
        dt: Option<f64>,
        lo: &mut [f64],
        hi: &mut [f64],
    ) -> Result<(), SolveError> {
        lo.fill(f64::NEG_INFINITY);
        hi.fill(f64::INFINITY);
        self.each(&mut |limit| limit.check(kin))?;
        self.each(&mut |limit| limit.narrow(kin, q, dt, lo, hi))
    }

    /// The general rows of a step at q (after [`Limits::bounds`], which checked the limits):
    /// `rows` cleared, then every limit's appended.
    pub(crate) fn rows(
        &self,
        kin: &TreeKinematics,
        q: &[f64],
        rows: &mut LimitRows,
    ) -> Result<(), SolveError> {
        rows.g.clear();
        rows.h.clear();
        rows.tags.clear();
        rows.counts.clear();
        for limit in &self.extra {
            let before = rows.h.len();
            limit.rows(kin, q, &mut rows.g, &mut rows.h, &mut rows.tags)?;
            if rows.tags.len() != rows.h.len() || rows.g.len() != rows.h.len() * kin.nv() {
                return Err(SolveError::InvalidInput(format!(
                    "limit {limit:?} gave rows of the wrong shape"
                )));
            }
            rows.counts.push(rows.h.len() - before);
        }
        Ok(())
    }

    /// True when q keeps every extra limit ([`Limit::satisfied`]).
    pub(crate) fn satisfied(&self, kin: &TreeKinematics, q: &[f64]) -> Result<bool, SolveError> {
        for limit in &self.extra {
            if !limit.satisfied(kin, q)? {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Every limit's [`Limit::tighten`] on its own rows after a step Δ to `q_next`: true when
    /// any bound was raised.
    pub(crate) fn tighten(
        &self,
        kin: &TreeKinematics,
        q_next: &[f64],
        delta: &[f64],
        rows: &mut LimitRows,
    ) -> Result<bool, SolveError> {
        let nv = kin.nv();
        rows.moved.clear();
        rows.moved.extend(
            rows.g
                .chunks(nv.max(1))
                .take(rows.h.len())
                .map(|r| r.iter().zip(delta).map(|(a, b)| a * b).sum::<f64>()),
        );
        let mut raised = false;
        let mut at = 0;
        for (limit, &count) in self.extra.iter().zip(&rows.counts) {
            let range = at..at + count;
            at += count;
            if count > 0 {
                raised |= limit.tighten(
                    kin,
                    q_next,
                    &rows.tags[range.clone()],
                    &rows.moved[range.clone()],
                    &mut rows.h[range],
                )?;
            }
        }
        Ok(raised)
    }
}
