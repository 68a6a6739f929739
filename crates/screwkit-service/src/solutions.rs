//! Every analytic IK solution as front ends ask for it (`screwkit ik --all`,
//! `Robot.ik_all`): the solver chosen once (the default one, or with a joint locked), the lock
//! options checked before any target, one target or a batch through the library's
//! [`AnalyticIk::solve_nearest_batch`], and the report.

use screwkit_lie::Se3;
use std::borrow::Cow;
use std::sync::OnceLock;

use screwkit_solve::analytic::{AnalyticIk, Solutions, MAX_DOF};
use screwkit_solve::{Kinematics, SolveError, Workspace};

use crate::error::Result;
use crate::joint::{JointRef, Lock};
use crate::report::{AllSolutionsReport, ArmAngleReport, LockedReport, SolutionReport};
use crate::words::RepresentativesChoice;

/// The analytic solvers of one chain, each built on first use and kept: a front end that
/// answers many calls holds one (building a solver can take milliseconds: the default's choice
/// of lock, the general 6R's reading). The chain must be the same at every call.
#[derive(Debug, Default)]
pub struct Solvers {
    auto: OnceLock<std::result::Result<AnalyticIk, SolveError>>,
    locked: [OnceLock<std::result::Result<AnalyticIk, SolveError>>; MAX_DOF],
    arm_angle: OnceLock<std::result::Result<AnalyticIk, SolveError>>,
}

impl Solvers {
    /// The arm angle ψ of configuration `q` of a 7R arm with a spherical shoulder and wrist
    /// ([`AnalyticIk::arm_angle_of`]: the definition and its reference plane), by the kept
    /// arm-angle solver; NaN where it is undefined; an error for another chain or a bad `q`.
    pub fn arm_angle_of(&self, kin: &Kinematics, q: &[f64]) -> Result<f64> {
        kin.check_q(q)?;
        let arm = JointRef::Name(crate::joint::ARM_ANGLE.into());
        Ok(self
            .get(kin, Some(&arm))?
            .arm_angle_of(q)
            .unwrap_or(f64::NAN))
    }

    /// The solver for `joint` (module documentation of [`AllSolutions::with_solvers`]),
    /// borrowed from the kept ones (a call per target clones nothing).
    pub fn get(&self, kin: &Kinematics, joint: Option<&JointRef>) -> Result<Cow<'_, AnalyticIk>> {
        fn kept<'s>(
            cell: &'s OnceLock<std::result::Result<AnalyticIk, SolveError>>,
            build: impl FnOnce() -> std::result::Result<AnalyticIk, SolveError>,
        ) -> Result<Cow<'s, AnalyticIk>> {
            match cell.get_or_init(build) {
                Ok(solver) => Ok(Cow::Borrowed(solver)),
                Err(e) => Err(e.clone().into()),
            }
        }
        match joint {
            None => kept(&self.auto, || AnalyticIk::auto(kin)),
            Some(joint) if joint.is_arm_angle(kin) => {
                kept(&self.arm_angle, || AnalyticIk::arm_angle(kin))
            }
            Some(joint) => {
                let j = joint.resolve(kin, "lock")?;
                match self.locked.get(j) {
                    Some(cell) => kept(cell, || AnalyticIk::locked(kin, j)),
                    None => Ok(Cow::Owned(AnalyticIk::locked(kin, j)?)),
                }
            }
        }
    }
}

/// The analytic solver with its lock options; the solver borrowed from a front end's kept
/// [`Solvers`] (`'s`), or owned.
#[derive(Debug, Clone)]
pub struct AllSolutions<'s> {
    solver: Cow<'s, AnalyticIk>,
    value: Option<f64>,
    sweep: Option<usize>,
    reps: RepresentativesChoice,
}

impl<'s> AllSolutions<'s> {
    /// The default solver ([`AnalyticIk::auto`]) or, with `lock`, the one with that joint
    /// locked (its value, or the seed's per target; `sweep`: that many values over its
    /// limits). The options are checked here, before any target.
    pub fn new(kin: &Kinematics, lock: Option<&Lock>, sweep: Option<usize>) -> Result<Self> {
        let solvers = Solvers::default();
        let all = AllSolutions::with_solvers(
            kin,
            lock.map(|l| &l.joint),
            lock.and_then(|l| l.value),
            sweep,
            &solvers,
        )?;
        Ok(AllSolutions {
            solver: Cow::Owned(all.solver.into_owned()),
            value: all.value,
            sweep: all.sweep,
            reps: all.reps,
        })
    }

    /// The solver with `joint` locked (None: the default solver, which for a 7R arm locks a
    /// joint of its own choice; [`crate::joint::ARM_ANGLE`]: a 7R arm with a spherical
    /// shoulder and wrist by its arm angle, [`AnalyticIk::arm_angle`]) at `value` (None: the
    /// seed's per target) or swept over `sweep` values, taken from `solvers` (built there on
    /// first use and kept for the next call).
    pub fn with_solvers(
        kin: &Kinematics,
        joint: Option<&JointRef>,
        value: Option<f64>,
        sweep: Option<usize>,
        solvers: &'s Solvers,
    ) -> Result<Self> {
        let solver = solvers.get(kin, joint)?;
        solver.check_lock_options(kin, value, sweep)?;
        Ok(Self {
            solver,
            value,
            sweep,
            reps: RepresentativesChoice::Nearest,
        })
    }

    /// The solver polling `interrupt` between a sweep's lock values (a front end's Ctrl-C:
    /// [`AnalyticIk::with_interrupt`]). Without a sweep there is nothing to poll (one value
    /// is one closed form, microseconds) and the solver is left as it is, borrowed.
    pub fn with_interrupt(mut self, interrupt: screwkit_solve::ik::Interrupt) -> Self {
        if self.sweep.is_some() {
            self.solver = Cow::Owned(self.solver.into_owned().with_interrupt(interrupt));
        }
        self
    }

    /// Which 2π representatives are listed (default: the one nearest the seed per posture).
    pub fn with_representatives(mut self, reps: RepresentativesChoice) -> Self {
        self.reps = reps;
        self
    }

    /// The solver.
    pub fn solver(&self) -> &AnalyticIk {
        &self.solver
    }

    /// Every solution of `target`, nearest to `seed` first, and the lock values used (a
    /// sweep's samples, then the values its refinement added).
    pub fn solve(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        seed: &[f64],
    ) -> Result<(Solutions, Vec<f64>), SolveError> {
        self.solver.solve_nearest(
            kin,
            ws,
            target,
            seed,
            self.value,
            self.sweep,
            self.reps.kind(),
        )
    }

    /// [`AllSolutions::solve`] of every row of `targets` (N × 16) with `seeds` (one dof row
    /// for all, or N × dof), on all cores; each row's own result.
    #[allow(clippy::type_complexity)]
    pub fn solve_batch(
        &self,
        kin: &Kinematics,
        targets: &[f64],
        seeds: &[f64],
    ) -> Result<Vec<Result<(Solutions, Vec<f64>), SolveError>>, SolveError> {
        self.solver.solve_nearest_batch(
            kin,
            targets,
            seeds,
            self.value,
            self.sweep,
            self.reps.kind(),
        )
    }

    /// The report of one target's solutions (`values`: the lock values used; `collides`: each
    /// solution's collision flag, when asked).
    pub fn report(
        &self,
        kin: &Kinematics,
        sols: &Solutions,
        values: &[f64],
        collides: Option<&[bool]>,
    ) -> AllSolutionsReport {
        AllSolutionsReport {
            family: self.solver.family().word(),
            reversed: self.solver.reversed(),
            locked: self.solver.locked_joint().map(|j| LockedReport {
                joint: kin.names()[j].clone(),
                index: j,
                values: values.to_vec(),
            }),
            arm_angle: self.solver.by_arm_angle().then(|| ArmAngleReport {
                values: values.to_vec(),
            }),
            exact: sols.is_exact(),
            singular: sols.singular,
            postures: sols.branches,
            solutions: (0..sols.len())
                .map(|i| SolutionReport {
                    q: sols.q(i).to_vec(),
                    exact: sols.exact(i),
                    residual: sols.residual(i),
                    collides: collides.and_then(|c| c.get(i).copied()),
                })
                .collect(),
        }
    }
}
