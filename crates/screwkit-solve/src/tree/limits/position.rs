//! **Position limit**: q_j + Δ_j within joint variable j's bounds — its joint's `<limit>` and,
//! for a variable driving mimic joints, theirs mapped through θ = m q + o; continuous joints
//! and the floating base have none. A q already outside (beyond [`LIMIT_TOLERANCE`] relative)
//! is an error naming the joint, never clipped silently.

use super::Limit;
use crate::error::SolveError;
use crate::tree::TreeKinematics;

/// Relative tolerance of "already outside the limits".
pub const LIMIT_TOLERANCE: f64 = 1e-9;

/// q + Δ within the position bounds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PositionLimit;

impl Limit for PositionLimit {
    fn check(&self, _kin: &TreeKinematics) -> Result<(), SolveError> {
        Ok(())
    }

    fn narrow(
        &self,
        kin: &TreeKinematics,
        q: &[f64],
        _dt: Option<f64>,
        lo: &mut [f64],
        hi: &mut [f64],
    ) -> Result<(), SolveError> {
        let (qo, vo) = (kin.q_offset(), kin.v_offset());
        for (j, &(bl, bu)) in kin.variable_bounds.iter().enumerate() {
            let x = q[qo + j];
            let tol = |b: f64| LIMIT_TOLERANCE * b.abs().max(1.0);
            if x < bl - tol(bl) || x > bu + tol(bu) {
                return Err(SolveError::InvalidInput(format!(
                    "joint \"{}\" is at {x}, outside its limits [{bl}, {bu}]: bring it inside first (the step does not clip it)",
                    kin.q_names()[qo + j]
                )));
            }
            lo[vo + j] = lo[vo + j].max((bl - x).min(0.0));
            hi[vo + j] = hi[vo + j].min((bu - x).max(0.0));
        }
        Ok(())
    }
}
