//! **A prepared task set**: tasks checked against the model once, their targets then updated
//! in place ([`TaskSet::set_target`], which checks only the new target), for a control loop
//! that steps at 1 kHz ([`crate::tree::differential_ik::ik_step_set`]) with no name lookup and
//! no check of the unchanged tasks per tick (mink's `task.set_target`).

use nalgebra::Vector3;
use screwkit_lie::Se3;

use super::{check_tasks, Task};
use crate::error::SolveError;
use crate::tree::TreeKinematics;

/// A new target for a task ([`TaskSet::set_target`]): what each type takes.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A pose: a frame task's (world) or a relative task's (in its second frame).
    Pose(Se3),
    /// A point: the centre of mass's, or an axis task's origin.
    Point(Vector3<f64>),
    /// An axis task's world direction.
    Direction(Vector3<f64>),
    /// A posture task's reference configuration (nq values).
    Configuration(Vec<f64>),
}

impl Target {
    /// What the target is, for messages.
    pub fn what(&self) -> &'static str {
        match self {
            Target::Pose(_) => "a pose",
            Target::Point(_) => "a point",
            Target::Direction(_) => "a direction",
            Target::Configuration(_) => "a configuration",
        }
    }
}

/// Tasks checked against one model; targets updated in place.
#[derive(Debug, Clone, PartialEq)]
pub struct TaskSet {
    tasks: Vec<Task>,
    /// The model's sizes when checked (frames, nq, nv): a set is used with that model only.
    shape: (usize, usize, usize),
}

impl TaskSet {
    /// The tasks checked against `kin` ([`check_tasks`]: the error names the task).
    pub fn new(kin: &TreeKinematics, tasks: Vec<Task>) -> Result<TaskSet, SolveError> {
        check_tasks(kin, &tasks)?;
        Ok(TaskSet {
            tasks,
            shape: shape(kin),
        })
    }

    /// The tasks.
    pub fn tasks(&self) -> &[Task] {
        &self.tasks
    }

    /// The number of tasks.
    pub fn len(&self) -> usize {
        self.tasks.len()
    }

    /// True without tasks.
    pub fn is_empty(&self) -> bool {
        self.tasks.is_empty()
    }

    /// Task `index`'s target replaced by `target` (checked as the task's own check does: a
    /// pose or point must be finite, a direction have one, a configuration nq finite values);
    /// on an error the task keeps its target. The error names the task.
    pub fn set_target(
        &mut self,
        kin: &TreeKinematics,
        index: usize,
        target: Target,
    ) -> Result<(), SolveError> {
        self.check_model(kin)?;
        let n = self.tasks.len();
        let task = self.tasks.get_mut(index).ok_or_else(|| {
            SolveError::InvalidInput(format!(
                "task index {index} is out of range: the set has {n} tasks"
            ))
        })?;
        let before = task.kind.clone();
        let result = task
            .kind
            .objective_mut()
            .set_target(target)
            .and_then(|()| task.kind.objective().check(kin));
        result.map_err(|m| {
            task.kind = before;
            SolveError::InvalidInput(format!("task {index} ({}): {m}", task.describe(kin)))
        })
    }

    /// An error unless `kin` is the model the set was checked against (its sizes).
    pub(crate) fn check_model(&self, kin: &TreeKinematics) -> Result<(), SolveError> {
        if shape(kin) == self.shape {
            Ok(())
        } else {
            Err(SolveError::InvalidInput(
                "this task set was prepared for another model (its frame count, nq or nv \
                 differ): prepare it again"
                    .into(),
            ))
        }
    }
}

fn shape(kin: &TreeKinematics) -> (usize, usize, usize) {
    (kin.frame_count(), kin.nq(), kin.nv())
}
