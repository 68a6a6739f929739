//! The reports front ends print or return: serde structs that ARE the JSON contract (the field
//! names are decided here, once; docs/guide/json.md lists them). Numbers follow [`crate::io::json`]'s
//! rule. [`to_value`] gives the JSON value the CLI prints (keys in alphabetical order, as
//! every screwkit JSON object has had them).

use serde::Serialize;
use serde_json::Value;

use crate::io::json::{number, numbers};
use screwkit_solve::ik::IkStatus;

/// A report as a JSON value.
pub fn to_value(report: &impl Serialize) -> Value {
    serde_json::to_value(report).unwrap_or(Value::Null)
}

/// One numerical IK answer (`screwkit ik --format json`, a line of an IK batch).
#[derive(Debug, Clone, Serialize)]
pub struct IkReport {
    /// True when the tolerances were met.
    pub converged: bool,
    /// The joint values (the best found when not converged).
    #[serde(serialize_with = "numbers")]
    pub q: Vec<f64>,
    /// Iterations used (all attempts).
    pub iterations: usize,
    /// Random restarts used.
    pub restarts: usize,
    /// ‖ω‖ of the final body twist error (rad).
    #[serde(serialize_with = "number")]
    pub error_rot: f64,
    /// ‖v‖ of the final body twist error (m).
    #[serde(serialize_with = "number")]
    pub error_pos: f64,
    /// Wall time of the solve (µs).
    #[serde(serialize_with = "number")]
    pub time_us: f64,
    /// Why it stopped ([`screwkit_solve::ik::StopReason::as_str`]).
    pub stop: &'static str,
}

impl IkReport {
    /// The report of a solve's status and answer.
    pub fn new(q: &[f64], status: &IkStatus, time_us: f64) -> IkReport {
        IkReport {
            converged: status.converged,
            q: q.to_vec(),
            iterations: status.iterations,
            restarts: status.restarts,
            error_rot: status.error_rot,
            error_pos: status.error_pos,
            time_us,
            stop: status.stop.as_str(),
        }
    }
}

/// The locked joint of a 7R arm's analytic solve.
#[derive(Debug, Clone, Serialize)]
pub struct LockedReport {
    /// The joint's name.
    pub joint: String,
    /// Its position in q (0-based, like every joint index screwkit prints or takes).
    pub index: usize,
    /// The values it was locked at.
    #[serde(serialize_with = "numbers")]
    pub values: Vec<f64>,
}

/// The arm angles a 7R arm was solved at (`"arm_angle": {"values": [...]}`).
#[derive(Debug, Clone, Serialize)]
pub struct ArmAngleReport {
    /// The arm angles ψ (rad): the one asked for, a sweep's samples then the values its
    /// refinement added, or the seed's.
    #[serde(serialize_with = "numbers")]
    pub values: Vec<f64>,
}

/// One analytic solution.
#[derive(Debug, Clone, Serialize)]
pub struct SolutionReport {
    /// The joint values.
    #[serde(serialize_with = "numbers")]
    pub q: Vec<f64>,
    /// True when it reaches the target (else a least-squares configuration).
    pub exact: bool,
    /// Its FK residual.
    #[serde(serialize_with = "number")]
    pub residual: f64,
}

/// Every analytic solution of one target (`screwkit ik --all --format json`).
#[derive(Debug, Clone, Serialize)]
pub struct AllSolutionsReport {
    /// The chain's family: [`screwkit_solve::family::Family::word`].
    pub family: &'static str,
    /// True when the chain is solved tip to base (its reversed order is the family's).
    pub reversed: bool,
    /// The locked joint of a 7R arm.
    pub locked: Option<LockedReport>,
    /// The arm angles solved at (a 7R arm by its arm angle; omitted otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub arm_angle: Option<ArmAngleReport>,
    /// True when every solution is exact (the target is reached).
    pub exact: bool,
    /// True when a free angle was chosen (a singular target).
    pub singular: bool,
    /// The postures found (before the 2π shifts within the limits).
    pub postures: usize,
    /// The solutions within the limits, nearest to the seed first.
    pub solutions: Vec<SolutionReport>,
}

/// A map build's or merge's summary (`screwkit reach --format json`, Python's dict).
#[derive(Debug, Clone, Serialize)]
pub struct MapReport {
    /// Voxels of the file written.
    pub voxels: usize,
    /// Poses (voxels × orientations).
    pub poses: usize,
    /// Poses solved (inside the reachable ball); None for a merge.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solved: Option<usize>,
    /// Poses reached.
    pub reached: usize,
    /// reached ÷ poses.
    #[serde(serialize_with = "number")]
    pub reached_fraction: f64,
    /// Wall time (s).
    #[serde(serialize_with = "number")]
    pub seconds: f64,
    /// Solves per second; None for a merge.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solves_per_second: Option<f64>,
    /// Threads used; None for a merge.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub threads: Option<usize>,
    /// "analytic" or "numerical"; None for a merge.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub solver: Option<&'static str>,
    /// Shards joined; None for a build.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shards: Option<usize>,
}

impl MapReport {
    /// The report of a build: `solved` poses in `seconds` on `threads` threads.
    pub fn built(
        (voxels, poses, solved, reached): (usize, usize, usize, usize),
        seconds: f64,
        threads: usize,
        solver: &'static str,
    ) -> MapReport {
        MapReport {
            voxels,
            poses,
            solved: Some(solved),
            reached,
            reached_fraction: reached as f64 / poses.max(1) as f64,
            seconds,
            solves_per_second: Some(solved as f64 / seconds.max(1e-9)),
            threads: Some(threads),
            solver: Some(solver),
            shards: None,
        }
    }

    /// The report of a merge of `shards` files.
    pub fn merged(
        (voxels, poses, reached): (usize, usize, usize),
        seconds: f64,
        shards: usize,
    ) -> MapReport {
        MapReport {
            voxels,
            poses,
            solved: None,
            reached,
            reached_fraction: reached as f64 / poses.max(1) as f64,
            seconds,
            solves_per_second: None,
            threads: None,
            solver: None,
            shards: Some(shards),
        }
    }
}

/// One task's final error in a [`TasksReport`].
#[derive(Debug, Clone, Serialize)]
pub struct TaskErrorReport {
    /// The task in words ([`screwkit_solve::tree::tasks::Task::describe`]).
    pub task: String,
    /// Its position error (m; a posture's joint distance).
    #[serde(serialize_with = "number")]
    pub position_error: f64,
    /// Its rotation error (rad).
    #[serde(serialize_with = "number")]
    pub rotation_error: f64,
    /// Within its tolerances (a regulariser: always).
    pub converged: bool,
}

/// A whole-body IK answer (`screwkit ik --tasks … --format json`, a line of its batch).
#[derive(Debug, Clone, Serialize)]
pub struct TasksReport {
    /// Every goal within its tolerances.
    pub converged: bool,
    /// The configuration (nq: the floating base's seven values first), within the limits.
    #[serde(serialize_with = "numbers")]
    pub q: Vec<f64>,
    /// Steps taken over every descent.
    pub iterations: usize,
    /// Why it stopped ([`screwkit_solve::tree::differential_ik::TasksStop::word`]).
    pub stop: &'static str,
    /// Each task's final error, in the tasks' order.
    pub tasks: Vec<TaskErrorReport>,
    /// Wall time of the solve (µs); 0 in a batch solved on all cores.
    #[serde(serialize_with = "number")]
    pub time_us: f64,
}

impl TasksReport {
    /// The report of `result` for `tasks` on `kin`.
    pub fn new(
        kin: &screwkit_solve::TreeKinematics,
        tasks: &[screwkit_solve::tree::tasks::Task],
        result: &screwkit_solve::tree::differential_ik::TasksResult,
        time_us: f64,
    ) -> TasksReport {
        TasksReport {
            converged: result.converged,
            q: result.q.clone(),
            iterations: result.iterations,
            stop: result.stop.word(),
            tasks: tasks
                .iter()
                .zip(&result.task_errors)
                .map(|(t, e)| TaskErrorReport {
                    task: t.describe(kin),
                    position_error: e.position,
                    rotation_error: e.rotation,
                    converged: e.converged,
                })
                .collect(),
            time_us,
        }
    }
}
