//! **Frame task**: frame F to the pose T* in the world. Error ξ = log(T_F⁻¹ T*) ∈ se(3), (ω, v)
//! in F's own frame; rows J_l(ξ)⁻¹ J_b, J_b the body Jacobian of F (module documentation).

use screwkit_lie::Se3;

use super::{
    base_and_path, check_frame, frame_name, wrong_target, At, Measures, Objective, Rows, Target,
    Task, TaskError,
};
use crate::jacobian::JacobianKind;
use crate::tree::jacobian::pose_jacobian_unchecked;
use crate::tree::TreeKinematics;

/// Frame `frame` to the pose `target` in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameTask {
    /// The driven frame.
    pub frame: usize,
    /// The target pose (world).
    pub target: Se3,
}

impl Objective for FrameTask {
    fn check(&self, kin: &TreeKinematics) -> Result<(), String> {
        check_frame(kin, self.frame)?;
        check_pose(&self.target)
    }

    fn is_goal(&self) -> bool {
        true
    }

    fn describe(&self, kin: &TreeKinematics) -> String {
        format!("frame task on {}", frame_name(kin, self.frame))
    }

    fn dependence(&self, kin: &TreeKinematics, out: &mut Vec<usize>) {
        base_and_path(kin, self.frame, out);
    }

    fn measures(&self) -> Measures {
        Measures::PositionAndRotation
    }

    fn set_target(&mut self, target: Target) -> Result<(), String> {
        match target {
            Target::Pose(t) => {
                self.target = t;
                Ok(())
            }
            other => Err(wrong_target("frame task", "a pose", &other)),
        }
    }

    fn rows(&self, at: &mut At<'_>, task: &Task, rows: &mut Rows) -> TaskError {
        let pose = pose_jacobian_unchecked(
            at.kin,
            at.ws,
            at.q,
            at.base,
            self.frame,
            JacobianKind::Body,
            false,
        );
        pose_rows(at, task, rows, &pose, &self.target)
    }
}

/// The target pose's check (frame and relative tasks).
pub(super) fn check_pose(target: &Se3) -> Result<(), String> {
    if target.is_finite() {
        Ok(())
    } else {
        Err("the target pose is not finite".into())
    }
}

/// The rows of a pose error ξ = log(pose⁻¹ target) with the body Jacobian in the workspace
/// (frame and relative tasks): the error's own derivative, T exp(δ) changes ξ by −J_l(ξ)⁻¹ δ,
/// δ = J_b Δ.
pub(super) fn pose_rows(
    at: &mut At<'_>,
    task: &Task,
    rows: &mut Rows,
    pose: &Se3,
    target: &Se3,
) -> TaskError {
    let nv = at.kin.nv();
    let g = task.gain;
    let ow = task.orientation_weight.map(|x| x * task.weight);
    let pw = task.position_weight.map(|x| x * task.weight);
    let xi = pose.inverse_compose(target).log();
    let e = [xi.w[0], xi.w[1], xi.w[2], xi.v[0], xi.v[1], xi.v[2]];
    let jinv = screwkit_lie::se3::left_jacobian_inverse(&xi);
    let (mut rot, mut pos) = (0.0, 0.0);
    for (r, &er) in e.iter().enumerate() {
        let w = if r < 3 { ow[r] } else { pw[r - 3] };
        if w == 0.0 {
            continue;
        }
        if r < 3 {
            rot += er * er;
        } else {
            pos += er * er;
        }
        rows.merit += (w * er) * (w * er);
        let jac = &at.ws.jacobian;
        let jrow = (0..nv).map(|c| (0..6).map(|k| jinv[(r, k)] * jac[(k, c)]).sum());
        rows.push(nv, w, jrow, g * er);
    }
    TaskError {
        rotation: rot.sqrt(),
        position: pos.sqrt(),
        converged: false,
    }
}
