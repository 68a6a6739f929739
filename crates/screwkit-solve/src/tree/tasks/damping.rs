//! **Damping task** (a regulariser): small steps, ‖Δ‖² weighted — the identity on every
//! velocity entry, as diagonal terms. No error.

use super::{wrong_target, At, Measures, Objective, Rows, Target, Task, TaskError};
use crate::tree::TreeKinematics;

/// Small steps: ‖Δ‖² weighted by the task's weight squared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct DampingTask;

impl Objective for DampingTask {
    fn check(&self, _kin: &TreeKinematics) -> Result<(), String> {
        Ok(())
    }

    fn is_goal(&self) -> bool {
        false
    }

    fn describe(&self, _kin: &TreeKinematics) -> String {
        "damping task".into()
    }

    fn dependence(&self, _kin: &TreeKinematics, _out: &mut Vec<usize>) {}

    fn measures(&self) -> Measures {
        Measures::Nothing
    }

    fn set_target(&mut self, target: Target) -> Result<(), String> {
        Err(wrong_target("damping task", "nothing", &target))
    }

    fn rows(&self, _at: &mut At<'_>, task: &Task, rows: &mut Rows) -> TaskError {
        let w2 = task.weight * task.weight;
        for d in rows.diag.iter_mut() {
            *d += w2;
        }
        TaskError::default()
    }
}
