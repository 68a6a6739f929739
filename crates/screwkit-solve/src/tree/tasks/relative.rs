//! **Relative frame task**: frame A to the pose T* given in frame B (T_BA = T_B⁻¹ T_A): one hand
//! relative to the other, a tool relative to the head. Error ξ = log(T_BA⁻¹ T*) in A's frame;
//! rows J_l(ξ)⁻¹ J_rel, J_rel the relative Jacobian of A in B, body form.

use screwkit_lie::Se3;

use super::frame::{check_pose, pose_rows};
use super::{
    base_and_path, check_frame, frame_name, wrong_target, At, Measures, Objective, Rows, Target,
    Task, TaskError,
};
use crate::jacobian::JacobianKind;
use crate::tree::jacobian::relative_unchecked;
use crate::tree::TreeKinematics;

/// Frame `frame` (A) to the pose `target` given in frame `relative_to` (B).
#[derive(Debug, Clone, PartialEq)]
pub struct RelativeTask {
    /// The driven frame (A).
    pub frame: usize,
    /// The frame the target is given in (B).
    pub relative_to: usize,
    /// The target pose of A in B.
    pub target: Se3,
}

impl Objective for RelativeTask {
    fn check(&self, kin: &TreeKinematics) -> Result<(), String> {
        check_frame(kin, self.frame)?;
        check_frame(kin, self.relative_to)?;
        if self.frame == self.relative_to {
            return Err("a frame relative to itself".into());
        }
        check_pose(&self.target)
    }

    fn is_goal(&self) -> bool {
        true
    }

    fn describe(&self, kin: &TreeKinematics) -> String {
        format!(
            "relative frame task on {} in {}",
            frame_name(kin, self.frame),
            frame_name(kin, self.relative_to)
        )
    }

    fn dependence(&self, kin: &TreeKinematics, out: &mut Vec<usize>) {
        base_and_path(kin, self.frame, out);
        base_and_path(kin, self.relative_to, out);
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
            other => Err(wrong_target("relative frame task", "a pose", &other)),
        }
    }

    fn rows(&self, at: &mut At<'_>, task: &Task, rows: &mut Rows) -> TaskError {
        let pose = relative_unchecked(
            at.kin,
            at.ws,
            at.q,
            at.base,
            self.frame,
            self.relative_to,
            JacobianKind::Body,
        );
        pose_rows(at, task, rows, &pose, &self.target)
    }
}
