//! **Posture task** (a regulariser): q towards q_ref. Error q_ref − q per joint variable
//! (continuous joints wrapped to (−π, π]); the identity on the joint variables, as diagonal
//! terms. Without a goal in the set, its error is the merit.

use screwkit_lie::angle;

use super::{wrong_target, At, Measures, Objective, Rows, Target, Task, TaskError};
use crate::tree::TreeKinematics;

/// q towards `q_ref` (nq values; a floating base's seven are not used).
#[derive(Debug, Clone, PartialEq)]
pub struct PostureTask {
    /// The reference configuration.
    pub q_ref: Vec<f64>,
}

impl Objective for PostureTask {
    fn check(&self, kin: &TreeKinematics) -> Result<(), String> {
        if self.q_ref.len() != kin.nq() {
            return Err(format!(
                "q_ref has {} values, the model has nq = {}",
                self.q_ref.len(),
                kin.nq()
            ));
        }
        let qo = kin.q_offset();
        if let Some(i) = self.q_ref[qo..].iter().position(|x| !x.is_finite()) {
            return Err(format!(
                "q_ref[{}] ({}) is not finite",
                qo + i,
                kin.q_names()[qo + i]
            ));
        }
        Ok(())
    }

    fn is_goal(&self) -> bool {
        false
    }

    fn describe(&self, _kin: &TreeKinematics) -> String {
        "posture task".into()
    }

    fn dependence(&self, _kin: &TreeKinematics, _out: &mut Vec<usize>) {}

    fn measures(&self) -> Measures {
        Measures::Configuration
    }

    fn set_target(&mut self, target: Target) -> Result<(), String> {
        match target {
            Target::Configuration(q) => {
                self.q_ref = q;
                Ok(())
            }
            other => Err(wrong_target("posture task", "a configuration", &other)),
        }
    }

    fn rows(&self, at: &mut At<'_>, task: &Task, rows: &mut Rows) -> TaskError {
        let kin = at.kin;
        let (qo, vo) = (kin.q_offset(), kin.v_offset());
        let (g, w2) = (task.gain, task.weight * task.weight);
        let mut pos = 0.0;
        for j in 0..kin.variable_bounds.len() {
            let mut e = self.q_ref[qo + j] - at.q[qo + j];
            if kin.continuous[j] {
                e = angle::wrap(e);
            }
            pos += e * e;
            rows.diag[vo + j] += w2;
            rows.diag_rhs[vo + j] += w2 * g * e;
            if !at.has_goal {
                rows.merit += task.weight * task.weight * e * e;
            }
        }
        TaskError {
            position: pos.sqrt(),
            rotation: 0.0,
            converged: false,
        }
    }
}
