//! Whole-body IK tasks from Python: each class holds the floor's `TaskSpec`
//! (`screwkit_service::tasks`), which the robot resolves (frames by name, targets checked) —
//! the same path as the CLI's `--tasks` JSON. The result object of `Robot.ik_tasks`.

use std::sync::{Arc, Mutex};

use numpy::{PyArray1, PyArray2, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::{PyIndexError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use screwkit_service::tasks::{TaskSpec, TaskType, Weights};
use screwkit_solve::tree::tasks::TaskKind;
use screwkit_solve::TreeKinematics;

use crate::array::{f64_array, shape_str};
use crate::errors::{service_error, solve_error};

/// A number or three numbers, for per-axis weights.
fn weights(x: &Bound<'_, PyAny>, what: &str) -> PyResult<Weights> {
    if let Ok(w) = x.extract::<f64>() {
        return Ok(Weights::All(w));
    }
    let a = f64_array(x, what)?;
    match a.readonly().as_slice()? {
        [a, b, c] => Ok(Weights::Each([*a, *b, *c])),
        v => Err(PyValueError::new_err(format!(
            "{what}: expected a number or 3 numbers, got {} values",
            v.len()
        ))),
    }
}

/// A fixed-length vector from Python.
fn vector<const N: usize>(x: &Bound<'_, PyAny>, what: &str) -> PyResult<[f64; N]> {
    let a = f64_array(x, what)?;
    if a.shape() != [N] {
        return Err(PyValueError::new_err(format!(
            "{what}: expected shape ({N},), got {}",
            shape_str(a.shape())
        )));
    }
    let mut out = [0.0; N];
    out.copy_from_slice(a.readonly().as_slice()?);
    Ok(out)
}

/// A (4, 4) pose as 16 numbers.
fn pose(x: &Bound<'_, PyAny>, what: &str) -> PyResult<Vec<f64>> {
    let a = f64_array(x, what)?;
    if a.shape() != [4, 4] {
        return Err(PyValueError::new_err(format!(
            "{what}: expected a (4, 4) pose, got shape {}",
            shape_str(a.shape())
        )));
    }
    Ok(a.to_vec()?)
}

/// The gain, weights and tolerances a task class sets; `None` leaves a field to the floor's
/// default for the task's type (`TaskType::defaults`, the one home of those defaults).
#[allow(clippy::too_many_arguments)]
fn common(
    mut spec: TaskSpec,
    gain: Option<f64>,
    weight: Option<f64>,
    position_weight: Option<&Bound<'_, PyAny>>,
    orientation_weight: Option<&Bound<'_, PyAny>>,
    tol_pos: Option<f64>,
    tol_rot: Option<f64>,
) -> PyResult<TaskSpec> {
    spec.gain = gain;
    spec.weight = weight;
    spec.position_weight = position_weight
        .map(|w| weights(w, "position_weight"))
        .transpose()?;
    spec.orientation_weight = orientation_weight
        .map(|w| weights(w, "orientation_weight"))
        .transpose()?;
    spec.tol_pos = tol_pos;
    spec.tol_rot = tol_rot;
    Ok(spec)
}

/// A frame or relative frame task's spec (the two share every field but `relative_to`).
#[allow(clippy::too_many_arguments)]
fn frame_spec(
    kind: TaskType,
    frame: String,
    relative_to: Option<String>,
    target: &Bound<'_, PyAny>,
    gain: f64,
    weight: f64,
    position_weight: Option<Bound<'_, PyAny>>,
    orientation_weight: Option<Bound<'_, PyAny>>,
    tol_pos: f64,
    tol_rot: f64,
) -> PyResult<TaskSpec> {
    let mut spec = TaskSpec::new(kind);
    spec.frame = Some(frame);
    spec.relative_to = relative_to;
    spec.target = Some(pose(target, "target")?);
    common(
        spec,
        Some(gain),
        Some(weight),
        position_weight.as_ref(),
        orientation_weight.as_ref(),
        Some(tol_pos),
        Some(tol_rot),
    )
}

/// Drives frame `frame` (a link or an added frame) to the world pose `target` (4, 4). The
/// error is the twist ξ = log(T_F⁻¹ T*) in the frame's own axes, rows (ω, v); per-axis weights
/// are along the frame's axes (`orientation_weight=0`: position only).
#[pyclass(frozen, module = "screwkit")]
pub struct FrameTask {
    pub(crate) spec: TaskSpec,
}

#[pymethods]
impl FrameTask {
    #[new]
    #[pyo3(signature = (frame, target, *, gain = 1.0, weight = 1.0, position_weight = None, orientation_weight = None, tol_pos = 1e-9, tol_rot = 1e-9))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        frame: String,
        target: &Bound<'_, PyAny>,
        gain: f64,
        weight: f64,
        position_weight: Option<Bound<'_, PyAny>>,
        orientation_weight: Option<Bound<'_, PyAny>>,
        tol_pos: f64,
        tol_rot: f64,
    ) -> PyResult<Self> {
        let spec = frame_spec(
            TaskType::Frame,
            frame,
            None,
            target,
            gain,
            weight,
            position_weight,
            orientation_weight,
            tol_pos,
            tol_rot,
        )?;
        Ok(Self { spec })
    }

    fn __repr__(&self) -> String {
        format!("FrameTask({:?})", self.spec.frame.as_deref().unwrap_or(""))
    }
}

/// Drives frame `frame`'s pose in frame `relative_to` (T_B⁻¹ T_A) to `target` (4, 4): one
/// hand relative to the other, a tool relative to the head.
#[pyclass(frozen, module = "screwkit")]
pub struct RelativeFrameTask {
    pub(crate) spec: TaskSpec,
}

#[pymethods]
impl RelativeFrameTask {
    #[new]
    #[pyo3(signature = (frame, relative_to, target, *, gain = 1.0, weight = 1.0, position_weight = None, orientation_weight = None, tol_pos = 1e-9, tol_rot = 1e-9))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        frame: String,
        relative_to: String,
        target: &Bound<'_, PyAny>,
        gain: f64,
        weight: f64,
        position_weight: Option<Bound<'_, PyAny>>,
        orientation_weight: Option<Bound<'_, PyAny>>,
        tol_pos: f64,
        tol_rot: f64,
    ) -> PyResult<Self> {
        let spec = frame_spec(
            TaskType::Relative,
            frame,
            Some(relative_to),
            target,
            gain,
            weight,
            position_weight,
            orientation_weight,
            tol_pos,
            tol_rot,
        )?;
        Ok(Self { spec })
    }

    fn __repr__(&self) -> String {
        format!(
            "RelativeFrameTask({:?}, {:?})",
            self.spec.frame.as_deref().unwrap_or(""),
            self.spec.relative_to.as_deref().unwrap_or("")
        )
    }
}

/// Points frame `frame`'s `axis` (in its own axes) along the world `direction` and, with
/// `point`, puts its origin there; free about the axis (5-DoF targets: a drill, a 5-axis arm).
#[pyclass(frozen, module = "screwkit")]
pub struct AxisTask {
    pub(crate) spec: TaskSpec,
}

#[pymethods]
impl AxisTask {
    #[new]
    #[pyo3(signature = (frame, *, axis, direction, point = None, gain = 1.0, weight = 1.0, position_weight = None, orientation_weight = 1.0, tol_pos = 1e-9, tol_rot = 1e-9))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        frame: String,
        axis: &Bound<'_, PyAny>,
        direction: &Bound<'_, PyAny>,
        point: Option<Bound<'_, PyAny>>,
        gain: f64,
        weight: f64,
        position_weight: Option<Bound<'_, PyAny>>,
        orientation_weight: f64,
        tol_pos: f64,
        tol_rot: f64,
    ) -> PyResult<Self> {
        let mut spec = TaskSpec::new(TaskType::Axis);
        spec.frame = Some(frame);
        spec.axis = Some(vector::<3>(axis, "axis")?);
        spec.direction = Some(vector::<3>(direction, "direction")?);
        spec.point = point.map(|p| vector::<3>(&p, "point")).transpose()?;
        let ow = orientation_weight.into_pyobject(py)?.into_any();
        Ok(Self {
            spec: common(
                spec,
                Some(gain),
                Some(weight),
                position_weight.as_ref(),
                Some(&ow),
                Some(tol_pos),
                Some(tol_rot),
            )?,
        })
    }

    fn __repr__(&self) -> String {
        format!("AxisTask({:?})", self.spec.frame.as_deref().unwrap_or(""))
    }
}

/// Drives the centre of mass (`Robot.com`) to the world point `target` (3,); per-axis weights
/// in world axes (`position_weight=(1, 1, 0)`: over the feet, any height).
#[pyclass(frozen, module = "screwkit")]
pub struct ComTask {
    pub(crate) spec: TaskSpec,
}

#[pymethods]
impl ComTask {
    #[new]
    #[pyo3(signature = (target, *, gain = 1.0, weight = 1.0, position_weight = None, tol_pos = 1e-9))]
    fn new(
        target: &Bound<'_, PyAny>,
        gain: f64,
        weight: f64,
        position_weight: Option<Bound<'_, PyAny>>,
        tol_pos: f64,
    ) -> PyResult<Self> {
        let mut spec = TaskSpec::new(TaskType::Com);
        spec.target = Some(vector::<3>(target, "target")?.to_vec());
        Ok(Self {
            spec: common(
                spec,
                Some(gain),
                Some(weight),
                position_weight.as_ref(),
                None,
                Some(tol_pos),
                None,
            )?,
        })
    }

    fn __repr__(&self) -> String {
        "ComTask()".into()
    }
}

/// Pulls the joints towards `q_ref` (nq,; a floating base's seven entries are not used): a
/// regulariser that picks among the solutions of the other tasks.
#[pyclass(frozen, module = "screwkit")]
pub struct PostureTask {
    pub(crate) spec: TaskSpec,
}

#[pymethods]
impl PostureTask {
    #[new]
    #[pyo3(signature = (q_ref, *, weight = 1.0, gain = 1.0))]
    fn new(q_ref: &Bound<'_, PyAny>, weight: f64, gain: f64) -> PyResult<Self> {
        let a = f64_array(q_ref, "q_ref")?;
        if a.ndim() != 1 {
            return Err(PyValueError::new_err(format!(
                "q_ref: expected shape (nq,), got {}",
                shape_str(a.shape())
            )));
        }
        let mut spec = TaskSpec::new(TaskType::Posture);
        spec.q_ref = Some(a.to_vec()?);
        spec.weight = Some(weight);
        spec.gain = Some(gain);
        Ok(Self { spec })
    }

    fn __repr__(&self) -> String {
        let weight = self
            .spec
            .weight
            .unwrap_or(TaskType::Posture.defaults().weight);
        format!("PostureTask(weight={weight})")
    }
}

/// Prefers small steps: ‖v·dt‖² weighted by `weight`².
#[pyclass(frozen, module = "screwkit")]
pub struct DampingTask {
    pub(crate) spec: TaskSpec,
}

#[pymethods]
impl DampingTask {
    #[new]
    #[pyo3(signature = (weight = 1e-3))]
    fn new(weight: f64) -> Self {
        let mut spec = TaskSpec::new(TaskType::Damping);
        spec.weight = Some(weight);
        Self { spec }
    }

    fn __repr__(&self) -> String {
        let weight = self
            .spec
            .weight
            .unwrap_or(TaskType::Damping.defaults().weight);
        format!("DampingTask({weight})")
    }
}

/// Tasks prepared for one robot (`Robot.task_set`): frames found and every task checked once,
/// targets then changed in place with `set_target`, so that a control loop's
/// `robot.ik_step(q, task_set, dt)` looks no name up and checks only what changed.
#[pyclass(frozen, module = "screwkit")]
pub struct TaskSet {
    /// The whole tree it was prepared for.
    pub(crate) kin: Arc<TreeKinematics>,
    pub(crate) set: Mutex<screwkit_solve::tree::tasks::TaskSet>,
}

#[pymethods]
impl TaskSet {
    /// Task `index`'s new target, as its class takes it: a frame or relative frame task a
    /// (4, 4) pose, a centre-of-mass task a point (3,), an axis task its origin's point (3,)
    /// or, with `direction=True`, its world direction (3,), a posture task q_ref (nq,).
    /// Raises `IndexError` for an index out of range and `ValueError` for a target the task
    /// does not take (the task then keeps its target).
    #[pyo3(signature = (index, target, *, direction = false))]
    fn set_target(&self, index: usize, target: &Bound<'_, PyAny>, direction: bool) -> PyResult<()> {
        let a = f64_array(target, "target")?;
        let values = a.to_vec()?;
        let mut set = self.set.lock().expect("the task set's lock");
        let Some(task) = set.tasks().get(index) else {
            return Err(PyIndexError::new_err(format!(
                "task index {index} is out of range: the set has {} tasks",
                set.len()
            )));
        };
        let pose = matches!(task.kind, TaskKind::Frame(_) | TaskKind::Relative(_));
        if pose && a.shape() != [4, 4] {
            return Err(PyValueError::new_err(format!(
                "target: expected a (4, 4) pose, got shape {}",
                shape_str(a.shape())
            )));
        }
        let new =
            screwkit_service::tasks::new_target(task, &values, direction).map_err(service_error)?;
        set.set_target(&self.kin, index, new).map_err(solve_error)
    }

    fn __len__(&self) -> usize {
        self.set.lock().expect("the task set's lock").len()
    }

    fn __repr__(&self) -> String {
        let set = self.set.lock().expect("the task set's lock");
        let tasks: Vec<String> = set.tasks().iter().map(|t| t.describe(&self.kin)).collect();
        format!("TaskSet([{}])", tasks.join(", "))
    }
}

/// The specs of a Python sequence of task objects; a `TypeError` names the item.
pub(crate) fn specs(tasks: &Bound<'_, PyAny>) -> PyResult<Vec<TaskSpec>> {
    let mut out = Vec::new();
    for (i, t) in tasks.try_iter()?.enumerate() {
        let t = t?;
        let spec = if let Ok(x) = t.cast::<FrameTask>() {
            x.get().spec.clone()
        } else if let Ok(x) = t.cast::<RelativeFrameTask>() {
            x.get().spec.clone()
        } else if let Ok(x) = t.cast::<AxisTask>() {
            x.get().spec.clone()
        } else if let Ok(x) = t.cast::<ComTask>() {
            x.get().spec.clone()
        } else if let Ok(x) = t.cast::<PostureTask>() {
            x.get().spec.clone()
        } else if let Ok(x) = t.cast::<DampingTask>() {
            x.get().spec.clone()
        } else {
            return Err(PyTypeError::new_err(format!(
                "tasks[{i}]: expected FrameTask, RelativeFrameTask, AxisTask, ComTask, PostureTask or DampingTask, got {}",
                t.get_type().name()?
            )));
        };
        out.push(spec);
    }
    Ok(out)
}

/// The outcome of `Robot.ik_tasks`.
#[pyclass(frozen, get_all, module = "screwkit")]
pub struct TasksResult {
    /// The final configuration (nq,), within the joint limits.
    pub q: Py<PyArray1<f64>>,
    /// Every goal (frame, axis, centre-of-mass task) within its tolerances.
    pub converged: bool,
    /// Steps taken over every descent.
    pub iterations: usize,
    /// Why it stopped: "converged", "iterations", "stalled", "conflicting", "interrupted".
    pub stop: String,
    /// Each task's error at q, shape (tasks, 2): (position in m, rotation in rad) of the
    /// axes it weighs (a posture's joint distance as its position).
    pub task_errors: Py<PyArray2<f64>>,
    /// Each task within its tolerances (regularisers: always true).
    pub task_converged: Vec<bool>,
}

#[pymethods]
impl TasksResult {
    fn __repr__(&self) -> String {
        format!(
            "TasksResult(converged={}, iterations={}, stop={:?})",
            if self.converged { "True" } else { "False" },
            self.iterations,
            self.stop
        )
    }
}
