//! **Axis task**: frame F's axis a (in F) along the world direction d, F's origin at the point
//! p when given; free about the axis. Rotation error θ = ∠(R_F a, d) along b₁ = unit(R_F a × d),
//! 0 along b₂ = R_F a × b₁; rows b₁ᵀ J_ω, b₂ᵀ J_ω; position error p − p_F, rows J_v (world-aligned
//! form).

use nalgebra::Vector3;

use super::{
    base_and_path, check_frame, check_unit, frame_name, wrong_target, At, Measures, Objective,
    Rows, Target, Task, TaskError,
};
use crate::jacobian::JacobianKind;
use crate::tree::jacobian::pose_jacobian_unchecked;
use crate::tree::TreeKinematics;

/// Frame `frame`'s unit axis `axis` (in its own frame) along the world direction `direction`,
/// its origin at `point` (world) when given; free about the axis.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisTask {
    /// The driven frame.
    pub frame: usize,
    /// The axis in the frame (normalised when used).
    pub axis: Vector3<f64>,
    /// The direction in the world (normalised when used).
    pub direction: Vector3<f64>,
    /// The origin's target, if any.
    pub point: Option<Vector3<f64>>,
}

impl Objective for AxisTask {
    fn check(&self, kin: &TreeKinematics) -> Result<(), String> {
        check_frame(kin, self.frame)?;
        check_unit("axis", &self.axis)?;
        check_unit("direction", &self.direction)?;
        if self.point.is_some_and(|p| !p.iter().all(|x| x.is_finite())) {
            return Err("the point is not finite".into());
        }
        Ok(())
    }

    fn is_goal(&self) -> bool {
        true
    }

    fn describe(&self, kin: &TreeKinematics) -> String {
        format!("axis task on {}", frame_name(kin, self.frame))
    }

    fn dependence(&self, kin: &TreeKinematics, out: &mut Vec<usize>) {
        base_and_path(kin, self.frame, out);
    }

    fn measures(&self) -> Measures {
        Measures::PositionAndRotation
    }

    /// A point (its origin's target) or a direction (its axis's).
    fn set_target(&mut self, target: Target) -> Result<(), String> {
        match target {
            Target::Point(p) => {
                self.point = Some(p);
                Ok(())
            }
            Target::Direction(d) => {
                self.direction = d;
                Ok(())
            }
            other => Err(wrong_target("axis task", "a point or a direction", &other)),
        }
    }

    fn rows(&self, at: &mut At<'_>, task: &Task, rows: &mut Rows) -> TaskError {
        let nv = at.kin.nv();
        let g = task.gain;
        let ow = task.orientation_weight.map(|x| x * task.weight);
        let pw = task.position_weight.map(|x| x * task.weight);
        let mut error = TaskError::default();
        let pose = pose_jacobian_unchecked(
            at.kin,
            at.ws,
            at.q,
            at.base,
            self.frame,
            JacobianKind::WorldAligned,
            false,
        );
        let aw = pose.rotation() * self.axis.normalize();
        let d = self.direction.normalize();
        let cross = aw.cross(&d);
        let theta = cross.norm().atan2(aw.dot(&d));
        let b1 = if cross.norm() > 1e-12 {
            cross.normalize()
        } else {
            any_perpendicular(&aw)
        };
        let b2 = aw.cross(&b1);
        let w = ow[0];
        if w != 0.0 {
            error.rotation = theta;
            rows.merit += (w * theta) * (w * theta);
            for (bi, ei) in [(b1, theta), (b2, 0.0)] {
                let jac = &at.ws.jacobian;
                let jrow = (0..nv)
                    .map(|c| bi[0] * jac[(0, c)] + bi[1] * jac[(1, c)] + bi[2] * jac[(2, c)]);
                rows.push(nv, w, jrow, g * ei);
            }
        }
        if let Some(p) = self.point {
            let e = p - pose.translation();
            let jac = &at.ws.jacobian;
            error.position = rows.push_point(nv, &pw, g, &e, |r, c| jac[(3 + r, c)]);
        }
        error
    }
}

/// A unit vector perpendicular to the unit vector `a`.
fn any_perpendicular(a: &Vector3<f64>) -> Vector3<f64> {
    let e = if a[0].abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    a.cross(&e).normalize()
}
