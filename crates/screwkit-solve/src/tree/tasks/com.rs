//! **Centre-of-mass task**: the centre of mass c(q) to the point c* (world). Error c* − c(q),
//! rows J_c ([`crate::tree::com`]), per world axis.

use nalgebra::Vector3;

use super::{wrong_target, At, Measures, Objective, Rows, Target, Task, TaskError};
use crate::tree::com::com_jacobian_unchecked;
use crate::tree::TreeKinematics;

/// The centre of mass to `target` (world).
#[derive(Debug, Clone, PartialEq)]
pub struct ComTask {
    /// The target point.
    pub target: Vector3<f64>,
}

impl Objective for ComTask {
    fn check(&self, kin: &TreeKinematics) -> Result<(), String> {
        if kin.total_mass <= 0.0 {
            return Err("no link has a mass (<inertial><mass value> > 0)".into());
        }
        if !self.target.iter().all(|x| x.is_finite()) {
            return Err("the target is not finite".into());
        }
        Ok(())
    }

    fn is_goal(&self) -> bool {
        true
    }

    fn describe(&self, _kin: &TreeKinematics) -> String {
        "centre-of-mass task".into()
    }

    /// Every velocity entry (a link anywhere moves the centre of mass).
    fn dependence(&self, kin: &TreeKinematics, out: &mut Vec<usize>) {
        out.extend(0..kin.nv());
    }

    fn measures(&self) -> Measures {
        Measures::Position
    }

    fn set_target(&mut self, target: Target) -> Result<(), String> {
        match target {
            Target::Point(p) => {
                self.target = p;
                Ok(())
            }
            other => Err(wrong_target("centre-of-mass task", "a point", &other)),
        }
    }

    fn rows(&self, at: &mut At<'_>, task: &Task, rows: &mut Rows) -> TaskError {
        let nv = at.kin.nv();
        let pw = task.position_weight.map(|x| x * task.weight);
        let c = com_jacobian_unchecked(at.kin, at.ws, at.q, at.base);
        let e = self.target - c;
        let jac = &at.ws.com_jacobian;
        TaskError {
            position: rows.push_point(nv, &pw, task.gain, &e, |r, c| jac[(r, c)]),
            rotation: 0.0,
            converged: false,
        }
    }
}
