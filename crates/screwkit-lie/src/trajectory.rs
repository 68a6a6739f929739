//! Trajectories in time (*Modern Robotics* ch. 9): the polynomial time scalings s(t) that rise
//! from 0 to 1 over a duration T_f at rest at both ends, and the straight-line joint path, the
//! screw motion and the decoupled Cartesian motion between two poses sampled N times over it,
//! with the `modern_robotics` package's arguments (each is tested equal to its namesake).
//!
//! With τ = t / T_f:
//!
//! ```text
//! cubic    s = 3τ² − 2τ³                  (zero velocity at both ends)
//! quintic  s = 10τ³ − 15τ⁴ + 6τ⁵           (zero velocity and acceleration)
//! joint      θ(s) = θ_start + s (θ_end − θ_start)
//! screw      X(s) = X_start exp(log(X_start⁻¹ X_end) s)
//! Cartesian  R(s) = R_start exp(log(R_startᵀ R_end) s),  p(s) = p_start + s (p_end − p_start)
//! ```
//!
//! sampled at t_i = i T_f / (N − 1), i = 0 … N − 1 (the first sample the start, the last the
//! end).

use nalgebra::Vector3;

use crate::{so3, LieError, Se3};

/// A polynomial time scaling: the textbook's `method` 3 (cubic) or 5 (quintic).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TimeScaling {
    /// s = 3τ² − 2τ³: at rest at both ends.
    Cubic,
    /// s = 10τ³ − 15τ⁴ + 6τ⁵: at rest and without acceleration at both ends.
    Quintic,
}

impl TimeScaling {
    /// The textbook's `method`: 3 cubic, 5 quintic (anything else is an error; the
    /// `modern_robotics` package takes any other number as quintic).
    pub fn from_method(method: i64) -> Result<Self, LieError> {
        match method {
            3 => Ok(TimeScaling::Cubic),
            5 => Ok(TimeScaling::Quintic),
            m => Err(LieError::OutOfRange {
                what: format!("method {m}: expected 3 (cubic) or 5 (quintic time scaling)"),
            }),
        }
    }

    /// s at time t of a motion of duration `tf` (the module's polynomials in τ = t / T_f).
    pub fn s(self, tf: f64, t: f64) -> f64 {
        let x = t / tf;
        match self {
            TimeScaling::Cubic => 3.0 * x * x - 2.0 * x * x * x,
            TimeScaling::Quintic => x * x * x * (10.0 - 15.0 * x + 6.0 * x * x),
        }
    }
}

/// `CubicTimeScaling(Tf, t)`: 3(t/T_f)² − 2(t/T_f)³.
pub fn cubic_time_scaling(tf: f64, t: f64) -> f64 {
    TimeScaling::Cubic.s(tf, t)
}

/// `QuinticTimeScaling(Tf, t)`: 10(t/T_f)³ − 15(t/T_f)⁴ + 6(t/T_f)⁵.
pub fn quintic_time_scaling(tf: f64, t: f64) -> f64 {
    TimeScaling::Quintic.s(tf, t)
}

/// The N sample times' scalings s_i = s(i T_f / (N − 1)): checks a finite T_f > 0 and N ≥ 2.
fn samples(tf: f64, n: usize, scaling: TimeScaling) -> Result<impl Iterator<Item = f64>, LieError> {
    if !(tf.is_finite() && tf > 0.0) {
        return Err(LieError::OutOfRange {
            what: format!("Tf {tf}: expected a finite duration > 0"),
        });
    }
    if n < 2 {
        return Err(LieError::OutOfRange {
            what: format!("N {n}: expected at least 2 samples (the start and the end)"),
        });
    }
    let gap = tf / (n as f64 - 1.0);
    Ok((0..n).map(move |i| scaling.s(tf, gap * i as f64)))
}

/// `JointTrajectory(thetastart, thetaend, Tf, N, method)`: N rows of θ_start + s_i (θ_end −
/// θ_start) into `out` (N × n, row-major; n the joints' count).
pub fn joint_trajectory(
    start: &[f64],
    end: &[f64],
    tf: f64,
    n: usize,
    scaling: TimeScaling,
    out: &mut [f64],
) -> Result<(), LieError> {
    if end.len() != start.len() {
        return Err(LieError::WrongLength {
            what: "thetaend (as many as thetastart)",
            expected: start.len(),
            got: end.len(),
        });
    }
    if start.iter().chain(end).any(|x| !x.is_finite()) {
        return Err(LieError::NonFinite {
            what: "thetastart or thetaend",
        });
    }
    let dof = start.len();
    let s = samples(tf, n, scaling)?;
    if out.len() != n * dof {
        return Err(LieError::WrongLength {
            what: "the trajectory's output (N × joints)",
            expected: n * dof,
            got: out.len(),
        });
    }
    for (row, s) in out.chunks_mut(dof.max(1)).zip(s) {
        for ((o, a), b) in row.iter_mut().zip(start).zip(end) {
            // The textbook's own expression, so that the samples match it bit for bit.
            *o = s * b + (1.0 - s) * a;
        }
    }
    Ok(())
}

/// `ScrewTrajectory(Xstart, Xend, Tf, N, method)`: X_start exp(log(X_start⁻¹ X_end) s_i), the
/// constant screw motion from X_start to X_end.
pub fn screw_trajectory(
    start: &Se3,
    end: &Se3,
    tf: f64,
    n: usize,
    scaling: TimeScaling,
) -> Result<Vec<Se3>, LieError> {
    let s = samples(tf, n, scaling)?;
    let xi = start.inverse_compose(end).log();
    Ok(s.map(|s| start.compose(&Se3::exp(&(xi * s)))).collect())
}

/// `CartesianTrajectory(Xstart, Xend, Tf, N, method)`: the origin on the straight line
/// p_start + s_i (p_end − p_start), the rotation R_start exp(log(R_startᵀ R_end) s_i),
/// decoupled.
pub fn cartesian_trajectory(
    start: &Se3,
    end: &Se3,
    tf: f64,
    n: usize,
    scaling: TimeScaling,
) -> Result<Vec<Se3>, LieError> {
    let s = samples(tf, n, scaling)?;
    let (r0, p0) = (start.rotation(), start.translation());
    let (r1, p1) = (end.rotation(), end.translation());
    let phi = so3::log(&(r0.transpose() * r1));
    Ok(s.map(|s| {
        let p: Vector3<f64> = p1 * s + p0 * (1.0 - s);
        Se3::from_parts_unchecked(r0 * so3::exp(&(phi * s)), p)
    })
    .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The time scalings' closed-form properties: s(0) = 0, s(T_f) = 1, s(T_f/2) = ½, and
    /// the textbook's examples (T_f = 2, t = 0.6: 0.216 and 0.16308).
    #[test]
    fn time_scalings_rise_from_zero_to_one() {
        for k in [TimeScaling::Cubic, TimeScaling::Quintic] {
            assert_eq!(k.s(3.0, 0.0), 0.0);
            assert!((k.s(3.0, 3.0) - 1.0).abs() < 1e-15);
            assert!((k.s(3.0, 1.5) - 0.5).abs() < 1e-15);
        }
        assert!((cubic_time_scaling(2.0, 0.6) - 0.216).abs() < 1e-15);
        assert!((quintic_time_scaling(2.0, 0.6) - 0.16308).abs() < 1e-15);
        assert!(TimeScaling::from_method(4).is_err());
    }

    /// A screw trajectory about a fixed axis: a rotation by π/2 about z through (1, 0, 0)
    /// with a 0.2 m advance along it; halfway (s = ½ at t = T_f/2) it is π/4 and 0.1 m.
    #[test]
    fn a_screw_trajectory_turns_about_its_axis() {
        let axis = crate::ScrewAxis::from_point_direction_pitch(
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::z(),
            0.2 / std::f64::consts::FRAC_PI_2,
        )
        .unwrap();
        let start = Se3::from_translation(Vector3::new(2.0, 0.0, 0.5));
        let end = Se3::exp_screw(&axis, std::f64::consts::FRAC_PI_2).compose(&start);
        let path = screw_trajectory(&start, &end, 4.0, 3, TimeScaling::Cubic).unwrap();
        let half = Se3::exp_screw(&axis, std::f64::consts::FRAC_PI_4).compose(&start);
        assert!(path[1].max_abs_diff(&half) < 1e-14);
        assert!(path[2].max_abs_diff(&end) < 1e-14 && path[0].max_abs_diff(&start) < 1e-15);
        assert!(screw_trajectory(&start, &end, 0.0, 3, TimeScaling::Cubic).is_err());
        assert!(screw_trajectory(&start, &end, 1.0, 1, TimeScaling::Cubic).is_err());
    }
}
