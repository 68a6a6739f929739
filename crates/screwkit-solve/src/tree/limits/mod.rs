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
//! [`Limit`], given in `extra`). Limits that need general inequality rows beside the box
//! (collision avoidance) add a method to [`Limit`] and a QP that takes them.

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
}
