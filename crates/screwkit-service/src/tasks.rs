//! Whole-body IK tasks as front ends take them: frames by name, targets as numbers, one set of
//! defaults ([`TaskType::defaults`]) for the CLI's `--tasks` JSON and Python's task classes,
//! resolved against a robot into the library's [`Task`]s ([`screwkit_solve::tree::tasks`]).
//!
//! JSON (one object per task; `type` is `frame`, `relative`, `axis`, `com`, `posture` or
//! `damping`; every other field optional unless its type needs it):
//!
//! ```json
//! {"type": "frame", "frame": "left_sole_link", "target": [16 numbers, row-major 4 x 4],
//!  "gain": 1, "weight": 1, "position_weight": 1, "orientation_weight": [1, 1, 0],
//!  "tol_pos": 1e-9, "tol_rot": 1e-9}
//! {"type": "relative", "frame": "left_hand", "relative_to": "right_hand", "target": [16 numbers]}
//! {"type": "axis", "frame": "gripper", "axis": [0, 0, 1], "direction": [0, 0, -1], "point": [0.3, 0, 0.2]}
//! {"type": "com", "target": [0, 0, 0.8], "position_weight": [1, 1, 0]}
//! {"type": "posture", "q_ref": [nq numbers], "weight": 0.01}
//! {"type": "damping", "weight": 0.001}
//! ```
//!
//! Weights are a number (every axis) or three numbers.

use nalgebra::Vector3;
use screwkit_solve::tree::tasks::{
    AxisTask, ComTask, DampingTask, FrameTask, PostureTask, RelativeTask, Target, Task, TaskKind,
    TaskSet, DAMPING_WEIGHT,
};
use screwkit_solve::TreeKinematics;
use serde::Deserialize;
use serde_json::Value;

use crate::error::{Error, Result};
use crate::target;

/// What kind of task a [`TaskSpec`] is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TaskType {
    /// A frame to a world pose.
    Frame,
    /// A frame to a pose in another frame.
    Relative,
    /// A frame's axis along a direction, its origin at a point.
    Axis,
    /// The centre of mass to a point.
    Com,
    /// q towards a reference.
    Posture,
    /// Small steps.
    Damping,
}

impl TaskType {
    /// Every task type, in the order of the module documentation.
    pub const ALL: [TaskType; 6] = [
        TaskType::Frame,
        TaskType::Relative,
        TaskType::Axis,
        TaskType::Com,
        TaskType::Posture,
        TaskType::Damping,
    ];

    /// The type's word in JSON (`"type": …`).
    pub fn name(self) -> &'static str {
        match self {
            TaskType::Frame => "frame",
            TaskType::Relative => "relative",
            TaskType::Axis => "axis",
            TaskType::Com => "com",
            TaskType::Posture => "posture",
            TaskType::Damping => "damping",
        }
    }

    /// What a task of this type takes for every field left out: **the one home of the
    /// whole-body defaults**. The CLI's JSON leaves fields out; Python's task classes pass
    /// what their signatures show (a test checks every signature default against this, field by
    /// field) and leave out the fields they do not expose. The library's [`Task`] defaults, but
    /// a damping task's weight [`DAMPING_WEIGHT`].
    pub fn defaults(self) -> TaskDefaults {
        let d = Task::posture(Vec::new());
        TaskDefaults {
            gain: d.gain,
            // (Every type named: a new one must say its weight.)
            weight: match self {
                TaskType::Damping => DAMPING_WEIGHT,
                TaskType::Frame
                | TaskType::Relative
                | TaskType::Axis
                | TaskType::Com
                | TaskType::Posture => d.weight,
            },
            position_weight: d.position_weight,
            orientation_weight: d.orientation_weight,
            tol_pos: d.tol_pos,
            tol_rot: d.tol_rot,
        }
    }
}

/// The defaults of a task type's optional fields ([`TaskType::defaults`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TaskDefaults {
    /// The task's gain (the fraction of its error corrected per step).
    pub gain: f64,
    /// Its weight against the other tasks.
    pub weight: f64,
    /// Per-axis weights of the position rows.
    pub position_weight: [f64; 3],
    /// Per-axis weights of the orientation rows.
    pub orientation_weight: [f64; 3],
    /// Position tolerance (m).
    pub tol_pos: f64,
    /// Orientation tolerance (rad).
    pub tol_rot: f64,
}

/// Per-axis weights: one number for every axis, or three.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Weights {
    /// The same weight on x, y, z.
    All(f64),
    /// x, y, z.
    Each([f64; 3]),
}

impl Weights {
    fn get(self) -> [f64; 3] {
        match self {
            Weights::All(w) => [w; 3],
            Weights::Each(w) => w,
        }
    }
}

/// One task as a front end gives it (module documentation).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TaskSpec {
    /// The kind.
    #[serde(rename = "type")]
    pub kind: TaskType,
    /// The driven frame (frame, relative, axis).
    #[serde(default)]
    pub frame: Option<String>,
    /// The frame the target is in (relative).
    #[serde(default)]
    pub relative_to: Option<String>,
    /// 16 numbers (frame, relative: row-major 4 × 4) or 3 (com).
    #[serde(default)]
    pub target: Option<Vec<f64>>,
    /// The axis in the frame (axis task).
    #[serde(default)]
    pub axis: Option<[f64; 3]>,
    /// The world direction (axis task).
    #[serde(default)]
    pub direction: Option<[f64; 3]>,
    /// The world point for the origin (axis task, optional).
    #[serde(default)]
    pub point: Option<[f64; 3]>,
    /// The reference configuration (posture: nq numbers).
    #[serde(default)]
    pub q_ref: Option<Vec<f64>>,
    /// Gain in (0, 1] (default 1).
    #[serde(default)]
    pub gain: Option<f64>,
    /// Weight ≥ 0 (default 1).
    #[serde(default)]
    pub weight: Option<f64>,
    /// Position rows' per-axis weights (default 1).
    #[serde(default)]
    pub position_weight: Option<Weights>,
    /// Rotation rows' per-axis weights (default 1).
    #[serde(default)]
    pub orientation_weight: Option<Weights>,
    /// Position tolerance, m (default 1e-9).
    #[serde(default)]
    pub tol_pos: Option<f64>,
    /// Rotation tolerance, rad (default 1e-9).
    #[serde(default)]
    pub tol_rot: Option<f64>,
}

impl TaskSpec {
    /// An empty spec of `kind` (every field at its default).
    pub fn new(kind: TaskType) -> TaskSpec {
        TaskSpec {
            kind,
            frame: None,
            relative_to: None,
            target: None,
            axis: None,
            direction: None,
            point: None,
            q_ref: None,
            gain: None,
            weight: None,
            position_weight: None,
            orientation_weight: None,
            tol_pos: None,
            tol_rot: None,
        }
    }

    /// The library task for `kin`: frames by name, targets checked (a pose's rotation under
    /// the targets' tolerance), the defaults filled in. The error names the field.
    pub fn resolve(&self, kin: &TreeKinematics) -> Result<Task> {
        let frame = |name: &Option<String>, field: &'static str| -> Result<usize> {
            let n = name
                .as_deref()
                .ok_or_else(|| Error::option(field, "is required for this task"))?;
            Ok(kin.frame(n)?)
        };
        let pose = || -> Result<screwkit_lie::Se3> {
            let t = self
                .target
                .as_deref()
                .ok_or_else(|| Error::option("target", "is required for this task"))?;
            if t.len() != 16 {
                return Err(Error::option(
                    "target",
                    format!("needs 16 numbers (a row-major 4 x 4 pose), got {}", t.len()),
                ));
            }
            Ok(target::from_row_major(t)?)
        };
        let vec3 = |v: Option<[f64; 3]>, field: &'static str| -> Result<Vector3<f64>> {
            v.map(Vector3::from)
                .ok_or_else(|| Error::option(field, "is required for this task"))
        };
        let kind = match self.kind {
            TaskType::Frame => TaskKind::Frame(FrameTask {
                frame: frame(&self.frame, "frame")?,
                target: pose()?,
            }),
            TaskType::Relative => TaskKind::Relative(RelativeTask {
                frame: frame(&self.frame, "frame")?,
                relative_to: frame(&self.relative_to, "relative_to")?,
                target: pose()?,
            }),
            TaskType::Axis => TaskKind::Axis(AxisTask {
                frame: frame(&self.frame, "frame")?,
                axis: vec3(self.axis, "axis")?,
                direction: vec3(self.direction, "direction")?,
                point: self.point.map(Vector3::from),
            }),
            TaskType::Com => {
                let t = self
                    .target
                    .as_deref()
                    .ok_or_else(|| Error::option("target", "is required for this task"))?;
                let [x, y, z] = t else {
                    return Err(Error::option(
                        "target",
                        format!("needs 3 numbers (a point), got {}", t.len()),
                    ));
                };
                TaskKind::Com(ComTask {
                    target: Vector3::new(*x, *y, *z),
                })
            }
            TaskType::Posture => TaskKind::Posture(PostureTask {
                q_ref: self
                    .q_ref
                    .clone()
                    .ok_or_else(|| Error::option("q_ref", "is required for this task"))?,
            }),
            TaskType::Damping => TaskKind::Damping(DampingTask),
        };
        let d = self.kind.defaults();
        Ok(Task {
            kind,
            gain: self.gain.unwrap_or(d.gain),
            weight: self.weight.unwrap_or(d.weight),
            orientation_weight: self
                .orientation_weight
                .map_or(d.orientation_weight, Weights::get),
            position_weight: self.position_weight.map_or(d.position_weight, Weights::get),
            tol_rot: self.tol_rot.unwrap_or(d.tol_rot),
            tol_pos: self.tol_pos.unwrap_or(d.tol_pos),
        })
    }
}

/// Parses a JSON task list (an array of task objects, or `{"tasks": [...]}`).
pub fn parse_json(text: &str) -> Result<Vec<TaskSpec>> {
    Ok(TaskList::parse(text)?.specs)
}

/// A task list read from JSON, each task's object kept so that a batch line can change some of
/// its fields ([`TaskList::with_changes`]: the targets of a motion clip's frame, say).
#[derive(Debug, Clone, PartialEq)]
pub struct TaskList {
    objects: Vec<serde_json::Map<String, Value>>,
    specs: Vec<TaskSpec>,
}

/// Task `i`'s object as a spec; the error names the task.
fn spec_of(i: usize, object: &serde_json::Map<String, Value>) -> Result<TaskSpec> {
    TaskSpec::deserialize(Value::Object(object.clone()))
        .map_err(|e| Error::option("tasks", format!("task {i}: {e}")))
}

impl TaskList {
    /// Parses an array of task objects or `{"tasks": [...]}` (module documentation); the error
    /// gives the line and column of bad JSON, or the task and field.
    pub fn parse(text: &str) -> Result<TaskList> {
        let value: Value =
            serde_json::from_str(text).map_err(|e| Error::option("tasks", e.to_string()))?;
        let list = match value {
            Value::Array(list) => list,
            Value::Object(mut o) if o.len() == 1 && o.contains_key("tasks") => {
                match o.remove("tasks") {
                    Some(Value::Array(list)) => list,
                    _ => {
                        return Err(Error::option(
                            "tasks",
                            "\"tasks\" must be a list of task objects",
                        ))
                    }
                }
            }
            _ => {
                return Err(Error::option(
                    "tasks",
                    "expected a list of task objects, or {\"tasks\": [...]}",
                ))
            }
        };
        let mut objects = Vec::with_capacity(list.len());
        for (i, t) in list.into_iter().enumerate() {
            match t {
                Value::Object(o) => objects.push(o),
                other => {
                    return Err(Error::option(
                        "tasks",
                        format!("task {i}: expected an object with a \"type\", got {other}"),
                    ))
                }
            }
        }
        let specs = objects
            .iter()
            .enumerate()
            .map(|(i, o)| spec_of(i, o))
            .collect::<Result<_>>()?;
        Ok(TaskList { objects, specs })
    }

    /// The tasks as read.
    pub fn specs(&self) -> &[TaskSpec] {
        &self.specs
    }

    /// The tasks with a batch line's changes: `changes[i]` (an object, or null for none)
    /// replaces the fields it gives of task i; tasks past the end of `changes` are unchanged.
    /// The error (for the line's report) names the task and field.
    pub fn with_changes(&self, changes: &[Value]) -> Result<Vec<TaskSpec>> {
        if changes.len() > self.objects.len() {
            return Err(Error::option(
                "tasks",
                format!(
                    "{} task changes for {} tasks",
                    changes.len(),
                    self.objects.len()
                ),
            ));
        }
        let mut out = self.specs.clone();
        for (i, change) in changes.iter().enumerate() {
            match change {
                Value::Null => {}
                Value::Object(fields) => {
                    let mut o = self.objects[i].clone();
                    o.extend(fields.iter().map(|(k, v)| (k.clone(), v.clone())));
                    out[i] = spec_of(i, &o)?;
                }
                other => {
                    return Err(Error::option(
                        "tasks",
                        format!("task {i}: a change is an object or null, got {other}"),
                    ))
                }
            }
        }
        Ok(out)
    }
}

/// The default seed of whole-body IK: the neutral configuration (the base at the world's
/// origin) with every joint brought within its limits.
pub fn default_seed(kin: &TreeKinematics) -> Vec<f64> {
    let mut q = screwkit_solve::tree::configuration::neutral(kin);
    let (lo, hi) = (kin.lower(), kin.upper());
    let off = kin.nq() - kin.model().variables.len();
    for i in off..q.len() {
        q[i] = q[i].clamp(lo[i], hi[i].max(lo[i]));
    }
    q
}

/// A task set prepared from front-end specs ([`resolve_all`], then checked once:
/// [`TaskSet::new`]); its targets are then changed with [`new_target`].
pub fn prepare(specs: &[TaskSpec], kin: &TreeKinematics) -> Result<TaskSet> {
    Ok(TaskSet::new(kin, resolve_all(specs, kin)?)?)
}

/// A new target for `task` from a front end's numbers, read as the task's type takes it: a
/// frame or relative task 16 values (a row-major 4 x 4 pose, its rotation under the targets'
/// tolerance), a centre-of-mass or axis task 3 (a point; an axis task's `direction` with
/// `direction`), a posture task nq (q_ref). The error says what was expected.
pub fn new_target(task: &Task, values: &[f64], direction: bool) -> Result<Target> {
    let point = |what: &str| -> Result<Vector3<f64>> {
        match values {
            [x, y, z] => Ok(Vector3::new(*x, *y, *z)),
            _ => Err(Error::option(
                "target",
                format!("needs 3 numbers ({what}), got {}", values.len()),
            )),
        }
    };
    if direction && !matches!(task.kind, TaskKind::Axis(_)) {
        return Err(Error::option("direction", "is for an axis task"));
    }
    Ok(match &task.kind {
        TaskKind::Frame(_) | TaskKind::Relative(_) => {
            if values.len() != 16 {
                return Err(Error::option(
                    "target",
                    format!(
                        "needs 16 numbers (a row-major 4 x 4 pose), got {}",
                        values.len()
                    ),
                ));
            }
            Target::Pose(target::from_row_major(values)?)
        }
        TaskKind::Axis(_) if direction => Target::Direction(point("a direction")?),
        TaskKind::Axis(_) | TaskKind::Com(_) => Target::Point(point("a point")?),
        TaskKind::Posture(_) => Target::Configuration(values.to_vec()),
        TaskKind::Damping(_) => {
            return Err(Error::option("target", "a damping task has no target"))
        }
    })
}

/// Every spec resolved; the error names the task's index.
pub fn resolve_all(specs: &[TaskSpec], kin: &TreeKinematics) -> Result<Vec<Task>> {
    specs
        .iter()
        .enumerate()
        .map(|(i, s)| {
            s.resolve(kin).map_err(|e| match e {
                Error::Option { name, message } => {
                    Error::option("tasks", format!("task {i}: {name}: {message}"))
                }
                other => Error::option("tasks", format!("task {i}: {other}")),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kin() -> TreeKinematics {
        let tree =
            screwkit_model::urdf::load_file(screwkit_testkit_path("torso_two_arms.urdf")).unwrap();
        TreeKinematics::new(&screwkit_model::KinematicTree::from_tree(&tree).unwrap()).unwrap()
    }

    fn screwkit_testkit_path(file: &str) -> String {
        format!("{}/../../assets/urdf/{file}", env!("CARGO_MANIFEST_DIR"))
    }

    #[test]
    fn json_tasks_resolve_with_defaults_and_name_what_is_wrong() {
        let kin = kin();
        let eye = "[1,0,0,0.3, 0,1,0,0.1, 0,0,1,0.2, 0,0,0,1]";
        let text = format!(
            r#"{{"tasks": [
                {{"type": "frame", "frame": "left_hand", "target": {eye}, "orientation_weight": 0}},
                {{"type": "relative", "frame": "left_hand", "relative_to": "right_hand", "target": {eye}, "position_weight": [1, 1, 0]}},
                {{"type": "axis", "frame": "right_hand", "axis": [0, 0, 1], "direction": [1, 0, 0]}},
                {{"type": "damping", "weight": 0.001}}
            ]}}"#
        );
        let specs = parse_json(&text).unwrap();
        let tasks = resolve_all(&specs, &kin).unwrap();
        assert_eq!(tasks.len(), 4);
        assert_eq!(tasks[0].orientation_weight, [0.0; 3]);
        assert_eq!(tasks[0].position_weight, [1.0; 3]);
        assert_eq!(tasks[1].position_weight, [1.0, 1.0, 0.0]);
        assert_eq!((tasks[0].gain, tasks[0].tol_pos), (1.0, 1e-9));
        assert!(matches!(tasks[1].kind, TaskKind::Relative(_)));
        assert_eq!(tasks[3].weight, 1e-3);
        // Every field left out takes the type's default: damping's weight is 1e-3, as Python's
        // DampingTask() (it was 1.0 in JSON until the defaults got one home).
        for kind in TaskType::ALL {
            let spec = TaskSpec::new(kind);
            let mut spec = spec;
            spec.frame = Some("left_hand".into());
            spec.relative_to = Some("right_hand".into());
            spec.target = Some(match kind {
                TaskType::Com => vec![0.0, 0.0, 0.5],
                _ => serde_json::from_str(eye).unwrap(),
            });
            spec.axis = Some([0.0, 0.0, 1.0]);
            spec.direction = Some([1.0, 0.0, 0.0]);
            spec.q_ref = Some(vec![0.0; kin.nq()]);
            let task = spec.resolve(&kin).unwrap();
            let d = kind.defaults();
            assert_eq!(
                (
                    task.gain,
                    task.weight,
                    task.position_weight,
                    task.orientation_weight
                ),
                (d.gain, d.weight, d.position_weight, d.orientation_weight),
                "{}",
                kind.name()
            );
            assert_eq!((task.tol_pos, task.tol_rot), (d.tol_pos, d.tol_rot));
            let json = format!(r#"[{{"type": "{}"}}]"#, kind.name());
            assert_eq!(parse_json(&json).unwrap()[0].kind, kind);
        }
        assert_eq!(TaskType::Damping.defaults().weight, 1e-3);
        assert_eq!(TaskType::Frame.defaults().weight, 1.0);
        for (bad, words) in [
            (
                r#"[{"type": "frame", "frame": "nowhere", "target": [1]}]"#,
                "task 0: ",
            ),
            (
                r#"[{"type": "frame", "frame": "left_hand"}]"#,
                "target: is required",
            ),
            (
                r#"[{"type": "frame", "frame": "left_hand", "target": [1, 2]}]"#,
                "needs 16 numbers",
            ),
            (r#"[{"type": "com", "target": [1, 2]}]"#, "needs 3 numbers"),
            (
                r#"[{"type": "axis", "frame": "left_hand", "axis": [0, 0, 1]}]"#,
                "direction: is required",
            ),
        ] {
            let e = parse_json(bad)
                .and_then(|s| resolve_all(&s, &kin))
                .unwrap_err()
                .to_string();
            assert!(e.contains(words), "{e} (wanted {words})");
        }
        for bad in [
            r#"[{"type": "spin"}]"#,
            r#"[{"type": "damping", "wieght": 1}]"#,
            "{",
        ] {
            let e = parse_json(bad).unwrap_err().to_string();
            assert!(e.starts_with("tasks: "), "{e}");
        }
    }
}
