//! **Velocity limit**: |Δ_j| ≤ dt · s_j for a control step of `dt`, s_j the least of the file's
//! `velocity` for joint variable j (when `file`; over every joint it drives, |θ̇| = |m| |q̇|) and
//! the caller's cap for j; nothing to narrow without dt (an iteration towards convergence).

use super::Limit;
use crate::error::SolveError;
use crate::tree::TreeKinematics;

/// |Δ| within dt times the speed limits.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VelocityLimit<'a> {
    /// The file's `velocity` limits.
    pub file: bool,
    /// The caller's caps per joint variable (∞ for none).
    pub caps: Option<&'a [f64]>,
}

impl Limit for VelocityLimit<'_> {
    fn check(&self, kin: &TreeKinematics) -> Result<(), SolveError> {
        let Some(caps) = self.caps else {
            return Ok(());
        };
        if caps.len() != kin.variable_bounds.len() {
            return Err(SolveError::InvalidInput(format!(
                "velocity_caps has {} values, the model has {} joint variables",
                caps.len(),
                kin.variable_bounds.len()
            )));
        }
        if let Some(i) = caps.iter().position(|c| c.is_nan() || *c < 0.0) {
            return Err(SolveError::InvalidInput(format!(
                "velocity_caps[{i}] = {} is not a number ≥ 0",
                caps[i]
            )));
        }
        Ok(())
    }

    fn narrow(
        &self,
        kin: &TreeKinematics,
        _q: &[f64],
        dt: Option<f64>,
        lo: &mut [f64],
        hi: &mut [f64],
    ) -> Result<(), SolveError> {
        let Some(dt) = dt else {
            return Ok(());
        };
        let vo = kin.v_offset();
        for j in 0..kin.variable_bounds.len() {
            let mut speed = if self.file {
                kin.variable_speed[j]
            } else {
                f64::INFINITY
            };
            if let Some(caps) = self.caps {
                speed = speed.min(caps[j]);
            }
            if speed.is_finite() {
                lo[vo + j] = lo[vo + j].max(-speed * dt);
                hi[vo + j] = hi[vo + j].min(speed * dt);
            }
        }
        Ok(())
    }
}
