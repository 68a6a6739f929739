//! The reports front ends print or return: serde structs that ARE the JSON contract (the field
//! names are decided here, once; docs/guide/json.md lists them). Numbers follow [`crate::io::json`]'s
//! rule. [`to_value`] gives the JSON value the CLI prints (keys in alphabetical order, as
//! every screwkit JSON object has had them).

use serde::Serialize;
use serde_json::Value;

use crate::io::json::{number, numbers, rows};
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

/// serde's form of a 4 × 4 pose (16 values, row-major) as four rows of numbers.
pub(crate) fn pose_rows<S: serde::Serializer>(m: &[f64; 16], s: S) -> Result<S::Ok, S::Error> {
    rows(m, 4).serialize(s)
}

/// A pose by name: a link of `fk --all-links`, a frame of the whole tree's `fk`.
#[derive(Debug, Clone, Serialize)]
pub struct NamedPose {
    /// The link's or frame's name.
    pub name: String,
    /// Its pose, four rows of the 4 × 4 matrix.
    #[serde(serialize_with = "pose_rows")]
    pub pose: [f64; 16],
}

impl NamedPose {
    /// The pose of `name`.
    pub fn new(name: &str, pose: &screwkit_lie::Se3) -> NamedPose {
        let mut m = [0.0; 16];
        pose.write_row_major(&mut m);
        NamedPose {
            name: name.to_string(),
            pose: m,
        }
    }

    /// The pose of `name` from 16 row-major values.
    pub fn from_row_major(name: &str, values: &[f64]) -> NamedPose {
        let mut m = [0.0; 16];
        m.copy_from_slice(&values[..16]);
        NamedPose {
            name: name.to_string(),
            pose: m,
        }
    }
}

/// One configuration's forward kinematics on the chain (`screwkit fk --format json`, a line of
/// an FK batch): q, the tip's pose and, with `--all-links`, every link's.
#[derive(Debug, Clone, Serialize)]
pub struct FkReport {
    /// The joint values.
    #[serde(serialize_with = "numbers")]
    pub q: Vec<f64>,
    /// The tip's pose (with the tool frame), four rows.
    #[serde(serialize_with = "pose_rows")]
    pub pose: [f64; 16],
    /// Every link's pose, in the chain's order (`--all-links`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub links: Option<Vec<NamedPose>>,
}

impl FkReport {
    /// The report of q, its tip pose (16 row-major values) and the links' poses if asked.
    pub fn new(q: &[f64], pose: &[f64], links: Option<Vec<NamedPose>>) -> FkReport {
        let mut m = [0.0; 16];
        m.copy_from_slice(&pose[..16]);
        FkReport {
            q: q.to_vec(),
            pose: m,
            links,
        }
    }
}

/// One configuration's forward kinematics on the whole tree (`screwkit fk --frames …`): q (the
/// tree's) and the chosen frames' poses.
#[derive(Debug, Clone, Serialize)]
pub struct FramesReport {
    /// The whole tree's configuration.
    #[serde(serialize_with = "numbers")]
    pub q: Vec<f64>,
    /// The chosen frames' poses, in the order asked.
    pub frames: Vec<NamedPose>,
}

/// serde's form of an optional number (`null` when absent).
fn optional_number<S: serde::Serializer>(x: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match x {
        Some(x) => number(x, s),
        None => s.serialize_none(),
    }
}

/// serde's form of a list of 6-vectors.
fn vectors<S: serde::Serializer>(xs: &[[f64; 6]], s: S) -> Result<S::Ok, S::Error> {
    Value::Array(xs.iter().map(|x| crate::io::json::nums(x)).collect()).serialize(s)
}

/// A 6 × n matrix as six rows of numbers.
#[derive(Debug, Clone)]
pub struct SixRows(pub nalgebra::Matrix6xX<f64>);

impl Serialize for SixRows {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        Value::Array(
            (0..6)
                .map(|r| crate::io::json::nums(&self.0.row(r).iter().copied().collect::<Vec<_>>()))
                .collect(),
        )
        .serialize(s)
    }
}

/// The position-only part of a Jacobian's analysis: the frame point's 3 × n velocity rows.
#[derive(Debug, Clone, Serialize)]
pub struct PositionReport {
    /// Singular values, largest first.
    #[serde(serialize_with = "numbers")]
    pub singular_values: Vec<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// √det(J_v J_vᵀ).
    #[serde(serialize_with = "number")]
    pub manipulability: f64,
    /// σ_max / σ_min (null when infinite).
    #[serde(serialize_with = "number")]
    pub condition_number: f64,
}

/// A Jacobian's singularity analysis (`jacobian --analyze`).
#[derive(Debug, Clone, Serialize)]
pub struct AnalysisReport {
    /// Singular values, largest first.
    #[serde(serialize_with = "numbers")]
    pub singular_values: Vec<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// σ at or below this counts as zero.
    #[serde(serialize_with = "number")]
    pub rank_tolerance: f64,
    /// √det(J Jᵀ).
    #[serde(serialize_with = "number")]
    pub manipulability: f64,
    /// σ₁ / σ_min (null when infinite).
    #[serde(serialize_with = "number")]
    pub condition_number: f64,
    /// det J of a 6 × 6 Jacobian, else null.
    #[serde(serialize_with = "optional_number")]
    pub determinant: Option<f64>,
    /// The twist directions the chain cannot produce, (ω, v).
    #[serde(serialize_with = "vectors")]
    pub lost_directions: Vec<[f64; 6]>,
    /// The verdict in words.
    pub verdict: String,
    /// The frame point's velocity rows alone.
    pub position: PositionReport,
}

/// One configuration's Jacobian (`screwkit jacobian --format json`, a line of a batch): q, the
/// kind's word, the 6 × n matrix and, when asked, its analysis; on the whole tree also the
/// frame, the frame it is seen from and the velocity entries' names.
#[derive(Debug, Clone, Serialize)]
pub struct JacobianReport {
    /// The joint values (the whole tree's configuration on the tree).
    #[serde(serialize_with = "numbers")]
    pub q: Vec<f64>,
    /// The kind's word (`space`, `body`, `world-aligned`).
    pub frame: &'static str,
    /// The Jacobian, six rows (ω, then v).
    pub jacobian: SixRows,
    /// The analysis (`--analyze`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub analysis: Option<AnalysisReport>,
    /// The tree's frame (`--of`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub of: Option<String>,
    /// The frame it is seen from (`--relative-to`, else the root or the world).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub relative_to: Option<String>,
    /// The columns' names (the tree's velocity entries).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub columns: Option<Vec<String>>,
}

impl JacobianReport {
    /// The report of q's Jacobian `j` of `kind` (word `frame`), with its analysis when
    /// `analyze` (its position part for the point `p`, where the frame's origin is: a space
    /// Jacobian's linear rows are moved there, [`tip_point_rows`]).
    pub fn new(
        q: &[f64],
        j: &nalgebra::Matrix6xX<f64>,
        frame: crate::words::JacobianFrame,
        analyze: bool,
        p: &nalgebra::Vector3<f64>,
    ) -> Result<JacobianReport, screwkit_solve::SolveError> {
        use crate::words::Word;
        let analysis = if analyze {
            let (a, pos) = crate::query::analysis_of(j, frame.kind(), p)?;
            Some(AnalysisReport {
                singular_values: a.singular_values.clone(),
                rank: a.rank,
                rank_tolerance: a.rank_tolerance,
                manipulability: a.manipulability,
                condition_number: a.condition_number,
                determinant: a.determinant,
                lost_directions: a.lost_directions.iter().map(|d| (*d).into()).collect(),
                verdict: a.verdict(),
                position: PositionReport {
                    singular_values: pos.singular_values,
                    rank: pos.rank,
                    manipulability: pos.manipulability,
                    condition_number: pos.condition_number,
                },
            })
        } else {
            None
        };
        Ok(JacobianReport {
            q: q.to_vec(),
            frame: frame.as_str(),
            jacobian: SixRows(j.clone()),
            analysis,
            of: None,
            relative_to: None,
            columns: None,
        })
    }
}

/// The 3 × n Jacobian of the velocity of the point `p` (where the frame's origin is) from a
/// Jacobian of `kind`: the body and world-aligned kinds have it as their linear rows; a space
/// Jacobian's linear rows are the velocity at the base origin, moved to p
/// ([`screwkit_solve::jacobian::space_to_world_aligned`]).
pub fn tip_point_rows(
    j: &nalgebra::Matrix6xX<f64>,
    kind: screwkit_solve::JacobianKind,
    p: &nalgebra::Vector3<f64>,
) -> nalgebra::DMatrix<f64> {
    nalgebra::DMatrix::from_fn(3, j.ncols(), |r, c| {
        if kind == screwkit_solve::JacobianKind::Space {
            let mut col = [0.0; 6];
            for (i, x) in col.iter_mut().enumerate() {
                *x = j[(i, c)];
            }
            screwkit_solve::jacobian::space_to_world_aligned(&mut col, p);
            col[3 + r]
        } else {
            j[(3 + r, c)]
        }
    })
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
    /// Whether its configuration collides (with `--collisions flag` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub collides: Option<bool>,
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
    /// Poses reached only in contact (a build clear of contact); None otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lost_to_collisions: Option<usize>,
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
            lost_to_collisions: None,
        }
    }

    /// The report with the poses a build clear of contact reached only in contact.
    pub fn with_lost_to_collisions(mut self, lost: Option<usize>) -> MapReport {
        self.lost_to_collisions = lost;
        self
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
            lost_to_collisions: None,
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
