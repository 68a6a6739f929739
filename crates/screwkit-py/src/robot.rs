//! `screwkit.Robot`: a whole robot (URDF, xacro, MJCF or a screw table) prepared once, its
//! chain and its tree, with FK, Jacobians, analysis and IK on one configuration or on N at once
//! (all cores, GIL released).

use std::path::PathBuf;
use std::sync::{Arc, Mutex, MutexGuard, RwLock};

use numpy::{PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods, ToPyArray};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyType;
use screwkit_model::{table, Chain};
use screwkit_service::query::{About, Poses, Selection};
use screwkit_service::words::{
    self, Collisions, GeometryRoles, JacobianFrame, Meshes, Method, ScrewFrame, TableFormat,
    TableFrames, Views, Word,
};
use screwkit_service::{target, AllSolutions, IkSettings, JointRef, LoadOptions, Source};
use screwkit_solve::ik::{Clearance, IkOptions, IkStatus};
use screwkit_solve::{
    batch, ik, tree, Kinematics, SolveError, TreeKinematics, TreeWorkspace, Workspace,
};

use crate::array::{f64_array, new_array, poses, shape_str, zeros};
use crate::errors::{batch_error, model_error, service_error, solve_error};
use crate::pool;
use crate::results::{Analysis, IkBatchResult, IkResult};
use screwkit_collision::{CollisionModel, CollisionWorkspace};
use screwkit_solve::tree::differential_ik::{self, DiffIkWorkspace};

/// A whole robot (URDF, xacro, MJCF or a screw table), ready for kinematics: its chain base →
/// tip when it has one, and every frame of its tree (`link=…`).
///
/// Conventions: twists and screw axes (ω, v); metres, radians; poses are row-major 4 × 4
/// float64; the space frame is the base link, the body frame the frame asked for (the tip by
/// default).
#[pyclass(frozen, module = "screwkit")]
pub struct Robot {
    /// The floor's robot: tree, chain, kinematics, URDF text (for pickling).
    robot: screwkit_service::Robot,
    /// Scratch of single calls (a fresh one is made when another thread holds it).
    ws: Mutex<Workspace>,
    /// The whole tree (`None` when the file's tree cannot be one: see `Robot::whole`); replaced
    /// by `add_frame`.
    whole: RwLock<Option<Arc<TreeKinematics>>>,
    /// Scratch of single whole-tree calls.
    tree_ws: Mutex<Option<TreeWorkspace>>,
    /// Scratch of whole-body IK steps.
    diff_ws: Mutex<Option<DiffIkWorkspace>>,
    /// The analytic solvers (the default one, each lock, the arm angle), built on first use.
    analytic: screwkit_service::solutions::Solvers,
    /// The body's collision model, built on the first body query; replaced (copied, changed)
    /// by `srdf`, `add_obstacle` and `remove_obstacle`.
    body: RwLock<Option<Arc<CollisionModel>>>,
    /// Scratch of single body queries, with the model and tree it was made for.
    body_ws: Mutex<Option<BodyScratch>>,
    /// The dynamic model (built on first use) with the tree it was made for, and its scratch.
    dynamics: Mutex<Option<DynamicsScratch>>,
    /// The options the dynamic model is built with (`set_dynamics_options`).
    dynamics_options: Mutex<screwkit_solve::tree::dynamics::DynamicsOptions>,
}

/// The dynamic model of a tree, the tree (held, so that `add_frame`'s new tree is told apart)
/// and one thread's scratch.
struct DynamicsScratch {
    kin: Arc<TreeKinematics>,
    model: Arc<screwkit_solve::tree::dynamics::Dynamics>,
    ws: screwkit_solve::tree::dynamics::DynamicsWorkspace,
}

/// A collision workspace kept between calls, and the model and tree it was made for (held, so
/// that a new model or tree, after `srdf`, `add_obstacle` or `add_frame`, is told apart and
/// makes a new one).
struct BodyScratch {
    model: Arc<CollisionModel>,
    kin: Arc<TreeKinematics>,
    ws: CollisionWorkspace,
}

/// A refused target as `ValueError` naming the argument and the reason (a typed
/// [`screwkit_solve::BadTarget`], not a glued message).
fn bad_target(e: SolveError) -> PyErr {
    match e {
        SolveError::BadTarget(screwkit_solve::BadTarget::NotRigid(r)) => {
            PyValueError::new_err(format!("target: not a rigid transform: {r}"))
        }
        SolveError::BadTarget(r) => PyValueError::new_err(format!("target: {r}")),
        e => solve_error(e),
    }
}

/// A pickled body: the disabled link pairs and the added obstacles (name, shape, row-major
/// pose).
type BodyState = (
    Vec<(String, String)>,
    Vec<(String, crate::body::ShapeState, Vec<f64>)>,
);

/// An option word of family `W` from a keyword argument; the error names the keyword.
pub(crate) fn word<W: Word>(keyword: &str, given: &str) -> PyResult<W> {
    words::parse::<W>(given).map_err(|e| PyValueError::new_err(format!("{keyword}: {e}")))
}

/// The options of `ik_tasks` / `ik_trajectory` (Ctrl-C polled).
fn tasks_options(
    max_iterations: usize,
    restarts: usize,
    seed: u64,
    position_limits: bool,
) -> differential_ik::TasksOptions {
    differential_ik::TasksOptions {
        max_iterations,
        restarts,
        seed,
        position_limits,
        interrupt: Some(ik::Interrupt(pool::interrupted)),
        limits: Vec::new(),
    }
}

/// The Python result of `ik_tasks`.
fn tasks_result(
    py: Python<'_>,
    r: differential_ik::TasksResult,
) -> PyResult<crate::tasks::TasksResult> {
    let n = r.task_errors.len();
    let errors = new_array(py, &[n, 2], |o| {
        for (e, out) in r.task_errors.iter().zip(o.chunks_mut(2)) {
            out[0] = e.position;
            out[1] = e.rotation;
        }
    })?;
    Ok(crate::tasks::TasksResult {
        q: r.q.to_pyarray(py).unbind(),
        converged: r.converged,
        iterations: r.iterations,
        stop: r.stop.word().to_string(),
        task_errors: errors.cast_into::<PyArray2<f64>>()?.unbind(),
        task_converged: r.task_errors.iter().map(|e| e.converged).collect(),
    })
}

/// The tasks of a step: a list resolved for this call, or a prepared set.
enum StepTasks<'t> {
    List(Vec<screwkit_solve::tree::tasks::Task>),
    Set(&'t Mutex<screwkit_solve::tree::tasks::TaskSet>),
}

impl StepTasks<'_> {
    /// One `ik_step` with these tasks.
    fn step<'w>(
        &self,
        kin: &TreeKinematics,
        ws: &'w mut DiffIkWorkspace,
        q: &[f64],
        dt: f64,
        limits: &differential_ik::Limits,
    ) -> Result<&'w [f64], screwkit_solve::SolveError> {
        match self {
            StepTasks::List(tasks) => differential_ik::ik_step(kin, ws, q, tasks, dt, limits),
            StepTasks::Set(set) => {
                let set = set.lock().expect("the task set's lock");
                differential_ik::ik_step_set(kin, ws, q, &set, dt, limits)
            }
        }
    }
}

/// Whether q is one configuration (dof,) or a stack (N, dof); the error names the joints.
enum Rows {
    One,
    Many(usize),
}

impl Robot {
    /// The chain and its kinematics (for the other modules of the binding).
    pub(crate) fn parts(&self) -> PyResult<(&Chain, &Kinematics)> {
        self.robot.chain_parts().map_err(service_error)
    }

    fn build(source: &Source, options: &LoadOptions) -> PyResult<Self> {
        Self::wrap(screwkit_service::Robot::load(source, options).map_err(service_error)?)
    }

    fn wrap(robot: screwkit_service::Robot) -> PyResult<Self> {
        // What the reader read past that changes kinematics (an MJCF tendon, a loop closure).
        if !robot.tree().warnings.is_empty() {
            Python::attach(|py| -> PyResult<()> {
                let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
                for w in &robot.tree().warnings {
                    let message = std::ffi::CString::new(format!("{}: {w}", robot.tree().source))
                        .unwrap_or_default();
                    PyErr::warn(py, &category, &message, 2)?;
                }
                Ok(())
            })?;
        }
        let ws = Mutex::new(
            robot
                .kin()
                .map_or_else(|_| Workspace::default(), Workspace::new),
        );
        let whole = RwLock::new(robot.whole().ok().cloned().map(Arc::new));
        Ok(Self {
            robot,
            ws,
            whole,
            tree_ws: Mutex::new(None),
            diff_ws: Mutex::new(None),
            analytic: screwkit_service::solutions::Solvers::default(),
            body: RwLock::new(None),
            body_ws: Mutex::new(None),
            dynamics: Mutex::new(None),
            dynamics_options: Mutex::new(Default::default()),
        })
    }

    /// True when calls without `link=` go to the whole tree: no chain, or a floating base
    /// (the floor's rule, `screwkit_service::whole::wants_tree`).
    fn tree_mode(&self) -> bool {
        screwkit_service::whole::wants_tree(&self.robot, false)
    }

    /// The whole tree as it is now (frames added included).
    fn tree_model(&self) -> PyResult<Arc<TreeKinematics>> {
        match &*self.whole.read().expect("the tree lock") {
            Some(k) => Ok(k.clone()),
            None => Err(service_error(
                self.robot.whole().expect_err("no tree means an error"),
            )),
        }
    }

    /// Runs `f` with the whole tree's dynamic model and scratch (built on first use; again
    /// after `add_frame`). An inertial that cannot be a rigid body's is an error naming its
    /// link; a link without one is massless, said once in a warning.
    fn with_dynamics<T>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(
            &screwkit_solve::tree::dynamics::Dynamics,
            &mut screwkit_solve::tree::dynamics::DynamicsWorkspace,
        ) -> Result<T, SolveError>,
    ) -> PyResult<T> {
        use screwkit_solve::tree::dynamics::DynamicsWorkspace;
        let kin = self.tree_model()?;
        let mut guard = self.dynamics.lock().unwrap_or_else(|e| e.into_inner());
        if !guard.as_ref().is_some_and(|d| Arc::ptr_eq(&d.kin, &kin)) {
            let options = *self
                .dynamics_options
                .lock()
                .unwrap_or_else(|e| e.into_inner());
            let model = screwkit_service::dynamics::model(&kin, &options).map_err(service_error)?;
            if let Some(message) = screwkit_service::dynamics::massless_warning(&model) {
                let cls = py.get_type::<pyo3::exceptions::PyUserWarning>();
                PyErr::warn(
                    py,
                    &cls,
                    &std::ffi::CString::new(message).unwrap_or_default(),
                    1,
                )?;
            }
            let ws = DynamicsWorkspace::new(&model);
            *guard = Some(DynamicsScratch {
                kin,
                model: Arc::new(model),
                ws,
            });
        }
        let d = guard.as_mut().expect("built above");
        f(&d.model, &mut d.ws).map_err(solve_error)
    }

    /// `{frame name: (6,) wrench}` as (frame index, wrench × `sign`); errors name the frame.
    fn frame_wrenches(
        &self,
        kin: &TreeKinematics,
        d: &Bound<'_, pyo3::types::PyDict>,
        what: &str,
        sign: f64,
    ) -> PyResult<Vec<(usize, [f64; 6])>> {
        let mut out = Vec::with_capacity(d.len());
        for (k, w) in d.iter() {
            let name: String = k.extract().map_err(|_| {
                PyValueError::new_err(format!("{what}: keys are frame names (str)"))
            })?;
            let frame = kin.frame(&name).map_err(model_error)?;
            let w = Self::one_vector(&w, 6, &format!("{what}[{name:?}]"))?;
            let mut x = [0.0; 6];
            for (o, v) in x.iter_mut().zip(&w) {
                *o = sign * v;
            }
            out.push((frame, x));
        }
        Ok(out)
    }

    /// A dynamics quantity of one configuration (q (nq,), then the nv-wide inputs) or of a
    /// batch (q (N, nq), inputs (N, nv)): (nv,) / (nv, nv) / a float, or (N, nv) / (N, nv, nv) /
    /// (N,). A batch runs on the pool; a bad row raises `BatchError` naming it.
    fn dynamics_call<'py>(
        &self,
        py: Python<'py>,
        what: screwkit_solve::tree::dynamics::Quantity,
        args: &[(&Bound<'py, PyAny>, &str)],
    ) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::{self as dynamics, Quantity};
        let kin = self.tree_model()?;
        let (nq, nv) = (kin.nq(), kin.nv());
        let arrays = args
            .iter()
            .map(|(a, name)| f64_array(a, name))
            .collect::<PyResult<Vec<_>>>()?;
        let batch = arrays[0].ndim() == 2;
        let n = if batch { arrays[0].shape()[0] } else { 1 };
        for (k, (a, (_, name))) in arrays.iter().zip(args).enumerate() {
            let w = if k == 0 { nq } else { nv };
            let want = if batch { vec![n, w] } else { vec![w] };
            if a.shape() != want.as_slice() {
                return Err(PyValueError::new_err(format!(
                    "{name}: expected shape {}, got {}",
                    shape_str(&want),
                    shape_str(a.shape())
                )));
            }
        }
        let width = what.width(nv);
        // The energies are one number per row; every other quantity a vector (nv = 1 too).
        let scalar = matches!(what, Quantity::KineticEnergy | Quantity::PotentialEnergy);
        let shape: Vec<usize> = match (batch, what) {
            (true, Quantity::MassMatrix) => vec![n, nv, nv],
            (true, _) if scalar => vec![n],
            (true, _) => vec![n, nv],
            (false, Quantity::MassMatrix) => vec![nv, nv],
            (false, _) => vec![width],
        };
        if !batch {
            let values = arrays
                .iter()
                .map(|a| Ok(a.to_vec()?))
                .collect::<PyResult<Vec<_>>>()?;
            let empty = Vec::new();
            let (x, y) = (
                values.get(1).unwrap_or(&empty),
                values.get(2).unwrap_or(&empty),
            );
            let mut out = vec![0.0; width];
            self.with_dynamics(py, |d, ws| {
                dynamics::compute(d, ws, what, &values[0], x, y, &mut out)
            })?;
            if scalar {
                return Ok(out[0].into_pyobject(py)?.into_any());
            }
            return Ok(new_array(py, &shape, |o| o.copy_from_slice(&out))?.into_any());
        }
        let in_width = nq + (arrays.len() - 1) * nv;
        let readers = arrays.iter().map(|a| a.readonly()).collect::<Vec<_>>();
        let slices = readers
            .iter()
            .map(|r| r.as_slice())
            .collect::<Result<Vec<_>, _>>()?;
        let rows = new_array(py, &[n, in_width], |o| {
            for r in 0..n {
                let mut at = r * in_width;
                for (k, s) in slices.iter().enumerate() {
                    let w = if k == 0 { nq } else { nv };
                    o[at..at + w].copy_from_slice(&s[r * w..(r + 1) * w]);
                    at += w;
                }
            }
        })?;
        self.with_dynamics(py, |_, _| Ok(()))?;
        let model = self
            .dynamics
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .map(|d| d.model.clone())
            .expect("built above");
        // A few ms of rows between Ctrl-C checks: each chunk is split over the pool's threads
        // (256 rows a task), and too small a chunk leaves them waiting on each hand-off.
        // Whole pairs of the library's 256-row tasks, so two threads share them evenly.
        let chunk = (FK_CHUNK / nv.max(1))
            .clamp(512, FK_CHUNK / 4)
            .next_multiple_of(512);
        run_batch(py, &shape, &rows, chunk, move |input, out| {
            dynamics::batch(&model, what, input, out)
        })
    }

    /// Runs `f` with the shared whole-tree scratch (or a new one when another thread holds
    /// it).
    fn with_tree_ws<T>(&self, kin: &TreeKinematics, f: impl FnOnce(&mut TreeWorkspace) -> T) -> T {
        match self.tree_ws.try_lock() {
            Ok(mut g) => f(g.get_or_insert_with(|| TreeWorkspace::new(kin))),
            Err(_) => f(&mut TreeWorkspace::new(kin)),
        }
    }

    /// Adds a frame to the whole tree.
    fn add_frame_pose(&self, name: &str, link: &str, pose: screwkit_lie::Se3) -> PyResult<()> {
        let mut guard = self.whole.write().expect("the tree lock");
        let Some(kin) = guard.as_ref() else {
            return Err(service_error(self.robot.whole().expect_err("no tree")));
        };
        let mut model = kin.model().clone();
        model.add_frame(name, link, pose).map_err(model_error)?;
        *guard = Some(Arc::new(TreeKinematics::new(&model).map_err(model_error)?));
        Ok(())
    }

    /// Runs `f` with the shared whole-body IK scratch (a new one when another thread holds it).
    fn with_diff_ws<T>(
        &self,
        kin: &TreeKinematics,
        f: impl FnOnce(&mut DiffIkWorkspace) -> T,
    ) -> T {
        match self.diff_ws.try_lock() {
            Ok(mut g) => f(g.get_or_insert_with(|| DiffIkWorkspace::new(kin))),
            Err(_) => f(&mut DiffIkWorkspace::new(kin)),
        }
    }

    /// Python task objects resolved by the floor against `kin`.
    fn resolve_tasks(
        &self,
        kin: &TreeKinematics,
        tasks: &Bound<'_, PyAny>,
    ) -> PyResult<Vec<screwkit_solve::tree::tasks::Task>> {
        let specs = crate::tasks::specs(tasks)?;
        screwkit_service::tasks::resolve_all(&specs, kin).map_err(service_error)
    }

    /// The inputs of a step: the tree, q, the tasks (a list resolved now, or a prepared
    /// `TaskSet`), the limits.
    #[allow(clippy::type_complexity)]
    /// The limit objects of a `limits=` argument (a sequence of `CollisionAvoidance`), each
    /// on the robot's body as it is now.
    fn extra_limits(
        &self,
        limits: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Vec<Arc<dyn tree::limits::Limit>>> {
        let Some(limits) = limits else {
            return Ok(Vec::new());
        };
        let mut out: Vec<Arc<dyn tree::limits::Limit>> = Vec::new();
        for (i, item) in limits.try_iter()?.enumerate() {
            let item = item?;
            let ca = item
                .cast::<crate::body::CollisionAvoidance>()
                .map_err(|_| {
                    pyo3::exceptions::PyTypeError::new_err(format!(
                        "limits[{i}]: expected a CollisionAvoidance, got {}",
                        item.get_type().name().map_or("?".into(), |n| n.to_string())
                    ))
                })?;
            let (kin, model) = self.body_model()?;
            out.push(ca.get().limit(&model, &kin)?);
        }
        Ok(out)
    }

    #[allow(clippy::too_many_arguments)]
    fn step_inputs<'t>(
        &self,
        q: &Bound<'_, PyAny>,
        tasks: &'t Bound<'_, PyAny>,
        position: bool,
        velocity: bool,
        caps: Option<Bound<'_, PyAny>>,
        limits: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<(
        Arc<TreeKinematics>,
        Vec<f64>,
        StepTasks<'t>,
        differential_ik::Limits,
    )> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let tasks = match tasks.cast::<crate::tasks::TaskSet>() {
            Ok(set) => {
                let set = set.get();
                if !Arc::ptr_eq(&set.kin, &kin) {
                    return Err(PyValueError::new_err(
                        "tasks: this TaskSet was prepared for the robot as it was before \
                         frames were added (or for another robot): prepare it again",
                    ));
                }
                StepTasks::Set(&set.set)
            }
            Err(_) => StepTasks::List(self.resolve_tasks(&kin, tasks)?),
        };
        let n = kin.model().variables.len();
        let velocity_caps = caps
            .map(|c| Self::one_vector(&c, n, "velocity_caps"))
            .transpose()?;
        Ok((
            kin,
            q,
            tasks,
            differential_ik::Limits {
                position,
                velocity,
                velocity_caps,
                extra: self.extra_limits(limits)?,
            },
        ))
    }

    /// The whole tree this robot answers with (frames added included) when a request needs it
    /// (`names_frames`, or the floor's rule says the tree answers), else None.
    fn tree_for(&self, names_frames: bool) -> PyResult<Option<Arc<TreeKinematics>>> {
        if names_frames || self.tree_mode() {
            Ok(Some(self.tree_model()?))
        } else {
            Ok(None)
        }
    }

    /// `f` of this robot's configuration space (the floor's `query::Space`: the chain's, or
    /// the whole tree's with the frames added here).
    fn with_space<R>(
        &self,
        f: impl FnOnce(screwkit_service::query::Space<'_>) -> R,
    ) -> PyResult<R> {
        let tree = self.tree_for(false)?;
        let space = screwkit_service::query::Space::of(&self.robot, tree.as_deref())
            .map_err(service_error)?;
        Ok(f(space))
    }

    /// Checks q's shape for what a query is about ([`rows_shape`]).
    fn rows_about(about: &About<'_>, a: &Bound<'_, PyArrayDyn<f64>>, what: &str) -> PyResult<Rows> {
        rows_shape(about.q_len(), about.is_tree(), about.q_names(), a, what)
    }

    /// One vector of `len` values (a configuration q, a velocity v) from Python.
    fn one_vector(a: &Bound<'_, PyAny>, len: usize, what: &str) -> PyResult<Vec<f64>> {
        let arr = f64_array(a, what)?;
        if arr.shape() != [len] {
            return Err(PyValueError::new_err(format!(
                "{what}: expected shape ({len},), got {}",
                shape_str(arr.shape())
            )));
        }
        Ok(arr.to_vec()?)
    }

    /// The poses of `selection` (the floor's `query::Poses`): q (n,) → its shape ((4, 4) or
    /// (K, 4, 4)); q (N, n) → N of them, through the library's batch.
    /// `cartesian_path` (`many` false: (4, 4) or (K, 4, 4) targets) and `cartesian_paths`
    /// (`many`: (N, 4, 4) or (N, K, 4, 4)).
    #[allow(clippy::too_many_arguments)]
    fn paths<'py>(
        &self,
        many: bool,
        py: Python<'py>,
        targets: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
        interpolation: &str,
        max_step: f64,
        max_joint_step: f64,
        max_deviation: f64,
        min_sigma: f64,
        lock: Option<&Bound<'py, PyAny>>,
        avoid_collisions: bool,
        margin: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        let how = word::<screwkit_service::words::Interpolation>("interpolation", interpolation)?;
        let kin = self.kin()?;
        let n = kin.dof();
        let lock = lock.map(|j| joint_ref(j, "lock")).transpose()?;
        let analytic = screwkit_service::path::path_solver(kin, &self.analytic, lock.as_ref())
            .map_err(service_error)?;
        let body = self.avoided_body(avoid_collisions, margin)?;
        let clear = self.clearance(body.as_ref(), margin)?;
        let options = screwkit_solve::path::PathOptions {
            interpolation: how.motion(),
            max_step,
            max_joint_step,
            max_deviation,
            min_sigma,
            ..Default::default()
        };
        let array = f64_array(targets, "targets")?;
        let shape = array.shape().to_vec();
        let bad_shape = || {
            PyValueError::new_err(format!(
                "targets: expected shape {}, got {}",
                if many {
                    "(N, 4, 4) or (N, K, 4, 4)"
                } else {
                    "(4, 4) or (K, 4, 4) (many paths: cartesian_paths)"
                },
                shape_str(&shape)
            ))
        };
        let (paths, per) = match (many, shape.as_slice()) {
            (false, [4, 4]) => (None, 1),
            (false, [k, 4, 4]) => (None, *k),
            (true, [m, 4, 4]) => (Some(*m), 1),
            (true, [m, k, 4, 4]) => (Some(*m), *k),
            _ => return Err(bad_shape()),
        };
        if per == 0 {
            return Err(PyValueError::new_err("targets: no pose given"));
        }
        let values = array.to_vec()?;
        let pose = |k: usize, t: &[f64]| {
            target::from_row_major(t).map_err(|e| {
                let at = match (paths, shape.len()) {
                    (Some(_), _) => format!("[{}, {}]", k / per, k % per),
                    (None, 3) => format!("[{k}]"),
                    _ => String::new(),
                };
                format!("targets{at}: {e}")
            })
        };
        let Some(m) = paths else {
            let seed = match seed {
                Some(s) => Self::one_vector(s, n, "seed")?,
                None => kin.midpoint(),
            };
            // One path polls Ctrl-C (a long numerical one can take seconds).
            let mut options = options.clone();
            options.ik.interrupt = Some(ik::Interrupt(pool::interrupted));
            let targets = values
                .chunks(16)
                .enumerate()
                .map(|(k, t)| pose(k, t).map_err(PyValueError::new_err))
                .collect::<PyResult<Vec<_>>>()?;
            let path = py
                .detach(|| {
                    self.workspace().map(|mut ws| {
                        screwkit_service::path::cartesian_path(
                            kin,
                            &mut ws,
                            analytic.as_deref(),
                            &targets,
                            &seed,
                            &options,
                            clear.as_ref(),
                        )
                    })
                })?
                .map_err(service_error)?;
            pool::take_interrupt(py)?;
            return Ok(crate::results::CartesianPath::new(py, path, n)?
                .into_pyobject(py)?
                .into_any());
        };
        // Many paths: a bad pose is its row's error, the others are computed.
        let mut rows: Vec<Result<Vec<screwkit_lie::Se3>, String>> = Vec::with_capacity(m);
        for r in 0..m {
            rows.push(
                values[r * per * 16..(r + 1) * per * 16]
                    .chunks(16)
                    .enumerate()
                    .map(|(k, t)| pose(r * per + k, t))
                    .collect(),
            );
        }
        let seeds = match seed {
            None => kin.midpoint(),
            Some(s) => {
                let a = f64_array(s, "seed")?;
                match a.shape() {
                    [x] if *x == n => a.to_vec()?,
                    [r, x] if *r == m && *x == n => a.to_vec()?,
                    other => {
                        return Err(PyValueError::new_err(format!(
                            "seed: expected shape ({n},) or ({m}, {n}), got {}",
                            shape_str(other)
                        )))
                    }
                }
            }
        };
        let one_seed = seeds.len() == n;
        let mut out: Vec<Option<screwkit_solve::path::CartesianPath>> = Vec::with_capacity(m);
        let mut bad: Vec<(usize, String)> = Vec::new();
        let mut result = Ok(());
        pool::chunked(
            py,
            m,
            PATH_CHUNK,
            screwkit_service::path::PATHS_INLINE,
            |range| {
                let start = range.start;
                let good: Vec<Vec<screwkit_lie::Se3>> = range
                    .clone()
                    .map(|r| rows[r].clone().unwrap_or_default())
                    .collect();
                let chunk_seeds = if one_seed {
                    seeds.clone()
                } else {
                    seeds[range.start * n..range.end * n].to_vec()
                };
                match screwkit_service::path::cartesian_paths(
                    kin,
                    analytic.as_deref(),
                    &good,
                    &chunk_seeds,
                    &options,
                    clear.as_ref(),
                ) {
                    Ok(done) => {
                        for (k, r) in done.into_iter().enumerate() {
                            let row = start + k;
                            match (&rows[row], r) {
                                (Err(e), _) => {
                                    bad.push((row, e.clone()));
                                    out.push(None);
                                }
                                (Ok(_), Ok(p)) => out.push(Some(p)),
                                (Ok(_), Err(e)) => {
                                    bad.push((row, e.to_string()));
                                    out.push(None);
                                }
                            }
                        }
                    }
                    Err(e) => result = Err(e),
                }
                Ok(())
            },
        )?
        .map_err(solve_error)?;
        result.map_err(service_error)?;
        let list = pyo3::types::PyList::empty(py);
        for p in out {
            match p {
                Some(p) => list.append(crate::results::CartesianPath::new(py, p, n)?)?,
                None => list.append(py.None())?,
            }
        }
        if bad.is_empty() {
            Ok(list.into_any())
        } else {
            Err(crate::errors::rows_error(
                py,
                "cartesian_path",
                bad,
                list.into_any(),
            ))
        }
    }

    fn poses_of<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        selection: Selection<'_>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let tree = self.tree_for(!matches!(selection, Selection::Tip | Selection::Links))?;
        let poses =
            Poses::resolve(&self.robot, tree.as_deref(), selection).map_err(service_error)?;
        let q = f64_array(q, "q")?;
        let shape = poses.shape();
        match rows_shape(poses.q_len(), poses.is_tree(), poses.q_names(), &q, "q")? {
            Rows::One => {
                let q = q.to_vec()?;
                let mut result = Ok(());
                let out = new_array(py, &shape, |o| result = poses.poses(&q, o))?;
                result.map_err(solve_error)?;
                Ok(out.into_any())
            }
            Rows::Many(n) => {
                let chunk = FK_CHUNK / (4 * poses.count()).clamp(4, 64);
                let full: Vec<usize> = std::iter::once(n).chain(shape).collect();
                run_batch(py, &full, &q, chunk, |qs, o| poses.poses_batch(qs, o))
            }
        }
    }

    /// The body's state for pickling: the disabled link pairs and the added obstacles (name,
    /// shape, pose row-major); empty when the body was never built.
    fn body_state(&self) -> BodyState {
        let Some(m) = self.body.read().expect("the body lock").clone() else {
            return (Vec::new(), Vec::new());
        };
        let obstacles = m
            .added_obstacles()
            .into_iter()
            .filter_map(|(name, shape, pose)| {
                let mut flat = vec![0.0; 16];
                pose.write_row_major(&mut flat);
                Some((name.to_string(), crate::body::shape_state(shape)?, flat))
            })
            .collect();
        (m.disabled(), obstacles)
    }

    /// The body `avoid_collisions` keeps clear of (the robot's, as it is now: its disabled
    /// pairs and obstacles), held for a call; None without it, where a margin is an error.
    fn avoided_body(
        &self,
        avoid_collisions: bool,
        margin: f64,
    ) -> PyResult<Option<(Arc<TreeKinematics>, Arc<CollisionModel>)>> {
        if avoid_collisions {
            return self.body_model().map(Some);
        }
        if margin != 0.0 {
            return Err(PyValueError::new_err(
                "margin applies with avoid_collisions=True",
            ));
        }
        Ok(None)
    }

    /// The chain's clearance in `body` ([`Self::avoided_body`]) with `margin`.
    fn clearance<'b>(
        &self,
        body: Option<&'b (Arc<TreeKinematics>, Arc<CollisionModel>)>,
        margin: f64,
    ) -> PyResult<Option<screwkit_collision::ChainClearance<'b>>> {
        body.map(|(tree, model)| {
            screwkit_service::body::chain_clearance(&self.robot, tree, model, margin)
        })
        .transpose()
        .map_err(service_error)
    }

    /// The whole tree and the body's collision model (built on first use).
    fn body_model(&self) -> PyResult<(Arc<TreeKinematics>, Arc<CollisionModel>)> {
        let kin = self.tree_model()?;
        if let Some(m) = self.body.read().expect("the body lock").clone() {
            return Ok((kin, m));
        }
        let m = Arc::new(
            screwkit_service::body::model(&kin, self.robot.options().meshes, None)
                .map_err(service_error)?,
        );
        *self.body.write().expect("the body lock") = Some(m.clone());
        Ok((kin, m))
    }

    /// The floor's robot.
    pub(crate) fn service(&self) -> &screwkit_service::Robot {
        &self.robot
    }

    /// The body a computation keeps clear of: the body as it is now, and the obstacles of the
    /// scene file `scene` added to a copy of it (the robot's own body is left as it is).
    pub(crate) fn body_with_scene(
        &self,
        scene: Option<&std::path::Path>,
    ) -> PyResult<(Arc<TreeKinematics>, Arc<CollisionModel>)> {
        let (kin, model) = self.body_model()?;
        let Some(scene) = scene else {
            return Ok((kin, model));
        };
        let obstacles =
            screwkit_service::body::read_scene(scene, &self.robot.options().xacro.package_paths)
                .map_err(service_error)?;
        let mut copy = (*model).clone();
        screwkit_service::body::add_obstacles(&mut copy, &obstacles).map_err(service_error)?;
        Ok((kin, Arc::new(copy)))
    }

    /// Runs `f` with the kept body workspace (a fresh one when another thread holds it, or the
    /// model or tree changed).
    fn with_body_ws<T>(
        &self,
        kin: &Arc<TreeKinematics>,
        model: &Arc<CollisionModel>,
        f: impl FnOnce(&mut CollisionWorkspace) -> T,
    ) -> T {
        match self.body_ws.try_lock() {
            Ok(mut kept) => {
                let fits = kept
                    .as_ref()
                    .is_some_and(|b| Arc::ptr_eq(&b.model, model) && Arc::ptr_eq(&b.kin, kin));
                if !fits {
                    *kept = Some(BodyScratch {
                        model: model.clone(),
                        kin: kin.clone(),
                        ws: CollisionWorkspace::new(kin, model),
                    });
                }
                f(&mut kept.as_mut().expect("just made").ws)
            }
            Err(_) => f(&mut CollisionWorkspace::new(kin, model)),
        }
    }

    /// Changes the body's model (a copy, then stored).
    fn change_body<T>(
        &self,
        f: impl FnOnce(&mut CollisionModel) -> Result<T, screwkit_service::Error>,
    ) -> PyResult<T> {
        let (_, model) = self.body_model()?;
        let mut copy = (*model).clone();
        let out = f(&mut copy).map_err(service_error)?;
        *self.body.write().expect("the body lock") = Some(Arc::new(copy));
        Ok(out)
    }

    /// A body query's configurations: q (n,) → one row, (N, n) → N rows, each the whole
    /// tree's configuration (a chain robot's joint values placed in its tree: the floor's
    /// `body::tree_q`).
    fn body_rows(&self, kin: &TreeKinematics, q: &Bound<'_, PyAny>) -> PyResult<(Rows, Vec<f64>)> {
        let a = f64_array(q, "q")?;
        let values = a.to_vec()?;
        let tree_q = |row: &[f64]| {
            screwkit_service::body::tree_q(&self.robot, kin, row)
                .map(|c| c.into_owned())
                .map_err(service_error)
        };
        match *a.shape() {
            [_] => Ok((Rows::One, tree_q(&values)?)),
            [n, w] => {
                let mut out = Vec::with_capacity(n * kin.nq());
                for row in values.chunks(w.max(1)).take(n) {
                    out.extend(tree_q(row)?);
                }
                Ok((Rows::Many(n), out))
            }
            ref shape => Err(PyValueError::new_err(format!(
                "q: expected shape ({n},) or (N, {n}), got {}",
                shape_str(shape),
                n = kin.nq()
            ))),
        }
    }

    fn kin(&self) -> PyResult<&Kinematics> {
        self.robot.kin().map_err(service_error)
    }

    fn chain(&self) -> PyResult<&Chain> {
        self.robot.chain().map_err(service_error)
    }

    /// The shared scratch, or a new one when another thread is using it.
    fn workspace(&self) -> PyResult<WorkspaceGuard<'_>> {
        let kin = self.kin()?;
        Ok(match self.ws.try_lock() {
            Ok(g) => WorkspaceGuard::Shared(g),
            Err(_) => WorkspaceGuard::Own(Box::new(Workspace::new(kin))),
        })
    }

    /// Checks q's shape: (dof,) or (N, dof).
    fn rows_of(&self, a: &Bound<'_, PyArrayDyn<f64>>, what: &str) -> PyResult<Rows> {
        let n = self.kin()?.dof();
        match a.shape() {
            [m] if *m == n => Ok(Rows::One),
            [rows, m] if *m == n => Ok(Rows::Many(*rows)),
            shape => Err(PyValueError::new_err(format!(
                "{what}: expected shape ({n},) or (N, {n}) for the joints {}, got {}",
                self.kin()?.names().join(", "),
                shape_str(shape)
            ))),
        }
    }

    /// The picture at q (one configuration of this robot's space, default home): the floor's
    /// routing, chain or tree ([`screwkit_draw::picture`]).
    fn picture(
        &self,
        q: Option<&Bound<'_, PyAny>>,
        picture: screwkit_draw::Picture<'_>,
    ) -> PyResult<String> {
        let tree = self.tree_for(false)?;
        let len = screwkit_service::query::Space::of(&self.robot, tree.as_deref())
            .map_err(service_error)?
            .q_len();
        let q = q.map(|q| Self::one_vector(q, len, "q")).transpose()?;
        screwkit_draw::picture(&self.robot, tree.as_deref(), q.as_deref(), picture)
            .map_err(service_error)
    }

    fn ik_options(&self, o: IkArgs) -> PyResult<IkOptions> {
        let d = IkSettings::default();
        IkSettings {
            method: word::<Method>("method", o.method)?,
            damping: o.damping,
            tol_rot: o.tol_rot,
            tol_pos: o.tol_pos,
            max_iterations: o.max_iterations,
            max_restarts: o.max_restarts,
            timeout_ms: o.timeout_ms.unwrap_or(d.timeout_ms),
            seed: o.seed_rng,
            position_only: o.position_only,
            weights: o.weights.unwrap_or(d.weights),
        }
        .options()
        .map_err(service_error)
    }
}

/// The scratch of one single call.
enum WorkspaceGuard<'a> {
    Shared(MutexGuard<'a, Workspace>),
    Own(Box<Workspace>),
}

impl std::ops::Deref for WorkspaceGuard<'_> {
    type Target = Workspace;
    fn deref(&self) -> &Workspace {
        match self {
            WorkspaceGuard::Shared(g) => g,
            WorkspaceGuard::Own(w) => w,
        }
    }
}

impl std::ops::DerefMut for WorkspaceGuard<'_> {
    fn deref_mut(&mut self) -> &mut Workspace {
        match self {
            WorkspaceGuard::Shared(g) => &mut *g,
            WorkspaceGuard::Own(w) => &mut *w,
        }
    }
}

/// IK settings as given from Python.
struct IkArgs<'a> {
    method: &'a str,
    damping: Option<f64>,
    tol_rot: f64,
    tol_pos: f64,
    max_iterations: usize,
    max_restarts: usize,
    timeout_ms: Option<f64>,
    seed_rng: u64,
    position_only: bool,
    weights: Option<Vec<f64>>,
}

/// Checks q's shape for a query whose q has `n` entries named `names` (the chain's joints, or
/// the whole tree's `q_names` when `tree`): (n,) or (N, n).
fn rows_shape(
    n: usize,
    tree: bool,
    names: &[String],
    a: &Bound<'_, PyArrayDyn<f64>>,
    what: &str,
) -> PyResult<Rows> {
    match a.shape() {
        [m] if *m == n => Ok(Rows::One),
        [rows, m] if *m == n => Ok(Rows::Many(*rows)),
        shape => Err(PyValueError::new_err(if tree {
            format!(
                "{what}: expected shape ({n},) or (N, {n}) for the whole tree's configuration (q_names), got {}",
                shape_str(shape)
            )
        } else {
            format!(
                "{what}: expected shape ({n},) or (N, {n}) for the joints {}, got {}",
                names.join(", "),
                shape_str(shape)
            )
        })),
    }
}

/// Runs a batch function into a new zeroed float64 array of `shape` (N, …) with the GIL
/// released: a batch of at most [`batch::INLINE_ROWS`] rows on this thread (the library runs
/// that many as one task, on the calling thread), a larger one on the batch pool, `chunk` rows
/// at a time with a Ctrl-C check between chunks ([`pool::chunked`]). `f(rows of input, rows of
/// output)` is the library's batch call on those rows (`input` holds N rows). Bad rows raise
/// `BatchError` carrying the array (every other row computed).
fn run_batch<'py>(
    py: Python<'py>,
    shape: &[usize],
    input: &Bound<'py, PyArrayDyn<f64>>,
    chunk: usize,
    f: impl Fn(&[f64], &mut [f64]) -> Result<(), SolveError> + Send + Sync,
) -> PyResult<Bound<'py, PyAny>> {
    // Borrowed (numpy's borrow flags) while the GIL is released; a single row is copied
    // instead (`to_vec`: a tenth of the bookkeeping's cost).
    let input = input.readonly();
    let input = input.as_slice()?;
    let out = zeros(py, shape)?;
    let rows = shape.first().copied().unwrap_or(0);
    let in_width = input.len() / rows.max(1);
    let out_width: usize = shape[1..].iter().product();
    let res = {
        let mut w = out.readwrite();
        let o = w.as_slice_mut()?;
        if rows <= batch::INLINE_ROWS {
            // No pool: its hand-off cost more than the rows (18 µs for one Panda FK row,
            // against 0.3 µs for the single call). The library touches no thread pool for so
            // few rows (rayon's global one would not survive `fork`).
            py.detach(|| f(input, o))
        } else {
            pool::chunked(py, rows, chunk, batch::INLINE_ROWS, |r| {
                f(
                    &input[r.start * in_width..r.end * in_width],
                    &mut o[r.start * out_width..r.end * out_width],
                )
            })?
        }
    };
    res.map_err(|e| batch_error(py, e, out.clone().into_any()))?;
    Ok(out.into_any())
}

/// Rows per chunk of a batch between two Ctrl-C checks (a few ms of work each).
const FK_CHUNK: usize = 1 << 15;
/// Rows per chunk of an IK batch.
const IK_CHUNK: usize = 256;

/// Paths per chunk of a batch of Cartesian paths (a path is hundreds of IK solves: a chunk
/// of 64 keeps Ctrl-C within a fraction of a second and the cores busy).
const PATH_CHUNK: usize = 64;

/// A joint by name, or by its 0-based index in q (`what` names the argument in the error).
fn joint_ref(j: &Bound<'_, PyAny>, what: &str) -> PyResult<JointRef> {
    // (A str checked by type, not by a failed extraction: this runs on every call.)
    Ok(if let Ok(name) = j.cast::<pyo3::types::PyString>() {
        JointRef::Name(name.extract::<String>()?)
    } else {
        JointRef::Index(j.extract::<usize>().map_err(|_| {
            PyValueError::new_err(format!("{what}: a joint name or its index in q (from 0)"))
        })?)
    })
}

/// The library's xacro options from Python's arguments.
pub fn xacro_options(
    package_paths: Option<Vec<PathBuf>>,
    args: Option<std::collections::BTreeMap<String, String>>,
) -> screwkit_model::XacroOptions {
    screwkit_model::XacroOptions {
        package_paths: package_paths.unwrap_or_default(),
        args: args.unwrap_or_default().into_iter().collect(),
    }
}

/// Writes `text` to `path` when one is given.
fn write_text(path: Option<PathBuf>, text: &str) -> PyResult<()> {
    match path {
        Some(p) => screwkit_service::io::atomic::write(&p, text.as_bytes()).map_err(|e| {
            let label = p.display().to_string();
            crate::errors::io_error(&label, &e)
        }),
        None => Ok(()),
    }
}

/// The IK status fields of a batch as arrays.
fn batch_result(q: Bound<'_, PyArrayDyn<f64>>, st: &[IkStatus]) -> PyResult<IkBatchResult> {
    let q = q.cast_into::<PyArray2<f64>>()?;
    Ok(IkBatchResult::new(q.unbind(), st.to_vec()))
}

/// What `ik_all` says of a target no solution within the limits reaches.
const OUT_OF_REACH: &str = "out of reach (no exact solution within the limits)";

#[pymethods]
impl Robot {
    /// Loads the chain `base` → `tip` of a URDF or xacro file (default base: the root link;
    /// default tip: the only leaf below the base). xacro is expanded natively: `package_paths`
    /// are searched for `$(find pkg)` (before ROS_PACKAGE_PATH and AMENT_PREFIX_PATH),
    /// `xacro_args` give `xacro:arg` values.
    ///
    /// The file is read as every front end reads it (at most 64 MiB; UTF-8 with or without a
    /// byte-order mark, or Latin-1 when its XML declaration says so). `tool`: a tool frame
    /// (TCP) fixed to the tip link, (x, y, z, roll, pitch, yaw) in m and rad (URDF rpy); FK,
    /// Jacobians, IK and tables are then of the tool frame. `geometry`: which of the file's
    /// shapes are read (`"collision"`, `"visual"`, `"both"`, `"none"`); `meshes`: how the body's
    /// meshes are read (`"exact"` triangles, `"convex"` hulls; default exact for URDF, convex
    /// for MJCF as MuJoCo). An unreadable file raises the matching `OSError`; a bad one
    /// `ValueError`.
    #[classmethod]
    #[pyo3(signature = (path, base = None, tip = None, *, package_paths = None, xacro_args = None, tool = None, floating_base = false, geometry = "both", meshes = None))]
    #[allow(clippy::too_many_arguments)]
    fn from_urdf(
        _cls: &Bound<'_, PyType>,
        path: PathBuf,
        base: Option<String>,
        tip: Option<String>,
        package_paths: Option<Vec<PathBuf>>,
        xacro_args: Option<std::collections::BTreeMap<String, String>>,
        tool: Option<Vec<f64>>,
        floating_base: bool,
        geometry: &str,
        meshes: Option<&str>,
    ) -> PyResult<Self> {
        let options = LoadOptions {
            xacro: xacro_options(package_paths, xacro_args),
            base,
            tip,
            tool,
            floating_base,
            geometry: word::<GeometryRoles>("geometry", geometry)?,
            meshes: meshes.map(|m| word::<Meshes>("meshes", m)).transpose()?,
        };
        Self::build(&Source::Path(path), &options)
    }

    /// Loads a robot file of any format screwkit reads — URDF, xacro or MuJoCo's MJCF, told
    /// apart by content — with the options of `from_urdf` (which reads them all too). An MJCF
    /// model with a free root joint has a floating base.
    #[classmethod]
    #[pyo3(signature = (path, base = None, tip = None, *, package_paths = None, xacro_args = None, tool = None, floating_base = false, geometry = "both", meshes = None))]
    #[allow(clippy::too_many_arguments)]
    fn from_file(
        cls: &Bound<'_, PyType>,
        path: PathBuf,
        base: Option<String>,
        tip: Option<String>,
        package_paths: Option<Vec<PathBuf>>,
        xacro_args: Option<std::collections::BTreeMap<String, String>>,
        tool: Option<Vec<f64>>,
        floating_base: bool,
        geometry: &str,
        meshes: Option<&str>,
    ) -> PyResult<Self> {
        Self::from_urdf(
            cls,
            path,
            base,
            tip,
            package_paths,
            xacro_args,
            tool,
            floating_base,
            geometry,
            meshes,
        )
    }

    /// A robot from its home pose M (4, 4) and screw axes S (n, 6), one row (ω, v) per joint
    /// base to tip, in the space frame (S_i) or the body frame (B_i), as *Modern Robotics*
    /// writes robots (its `Slist`/`Blist` hold the axes as columns: pass `Slist.T`). A row
    /// with ‖ω‖ = 1 is a revolute joint, or helical when its pitch h = ω · v is above what
    /// rounding leaves (2e-6 · max(1, ‖v‖): rows printed to six decimals or typed by hand
    /// stay revolute, their v made ⊥ ω); ω = 0 with ‖v‖ = 1 a prismatic joint (unit lengths
    /// to 1e-6, then normalised); anything else is a `ValueError` naming the row. `limits`: (n, 2) lower and upper (±inf allowed;
    /// `None`: unbounded, and a revolute joint is then continuous); `names`: n joint names
    /// (default `joint1`, …). The chain runs from link `base` to link `tip`; every algorithm
    /// works on it (analytic IK when its joints are revolute); `tool` as in `from_urdf`.
    #[classmethod]
    #[pyo3(signature = (m, s, frame = "space", limits = None, names = None, *, tool = None, floating_base = false))]
    #[allow(clippy::too_many_arguments)]
    fn from_screws(
        _cls: &Bound<'_, PyType>,
        m: &Bound<'_, PyAny>,
        s: &Bound<'_, PyAny>,
        frame: &str,
        limits: Option<&Bound<'_, PyAny>>,
        names: Option<Vec<String>>,
        tool: Option<Vec<f64>>,
        floating_base: bool,
    ) -> PyResult<Self> {
        let frame: screwkit_lie::Frame = word::<ScrewFrame>("frame", frame)?.into();
        let m = crate::array::f64_array(m, "M")?;
        if m.shape() != [4, 4] {
            return Err(PyValueError::new_err(format!(
                "M: expected shape (4, 4), got {}",
                shape_str(m.shape())
            )));
        }
        let home: [f64; 16] = m.readonly().as_slice()?.try_into().expect("16 values");
        let rows = |x: &Bound<'_, PyAny>, what: &str, k: usize| -> PyResult<Vec<f64>> {
            let a = crate::array::f64_array(x, what)?;
            match a.shape() {
                [_, c] if *c == k => Ok(a.to_vec()?),
                shape => Err(PyValueError::new_err(format!(
                    "{what}: expected shape (n, {k}), got {}",
                    shape_str(shape)
                ))),
            }
        };
        let screws: Vec<[f64; 6]> = rows(s, "S", 6)?
            .chunks(6)
            .map(|c| c.try_into().expect("6 values"))
            .collect();
        let limits = match limits {
            Some(l) => Some(
                rows(l, "limits", 2)?
                    .chunks(2)
                    .map(|c| (c[0], c[1]))
                    .collect(),
            ),
            None => None,
        };
        let options = LoadOptions {
            tool,
            floating_base,
            ..LoadOptions::default()
        };
        let describe = |screws: Vec<[f64; 6]>| {
            screwkit_model::ScrewRobot::new(
                "<screws>",
                home,
                screws,
                frame,
                limits.clone(),
                names.clone(),
            )
        };
        let built = describe(screws.clone())
            .map_err(screwkit_service::Error::from)
            .and_then(|d| screwkit_service::Robot::from_screws(d, &options));
        match built {
            Ok(robot) => Self::wrap(robot),
            Err(e) => {
                // Modern Robotics' Slist holds the axes as columns: say so when S.T would do
                // (its rows read again and made a chain, no robot built).
                let n = screws.len();
                let transposed: Vec<[f64; 6]> = (0..6)
                    .map(|r| std::array::from_fn(|c| if c < n { screws[c][r] } else { f64::NAN }))
                    .collect();
                let err = service_error(e);
                if n == 6 && describe(transposed).and_then(|d| d.chain()).is_ok() {
                    let msg = format!(
                        "{} (S's columns are screw axes: rows are expected, pass S.T)",
                        err.value(_cls.py())
                    );
                    return Err(PyValueError::new_err(msg));
                }
                Err(err)
            }
        }
    }

    /// Loads the chain `base` → `tip` of URDF (or xacro) text; `source` names it in error
    /// messages; `tool` as in `from_urdf`.
    #[classmethod]
    #[pyo3(signature = (xml, base = None, tip = None, source = "<string>", *, tool = None, floating_base = false))]
    fn from_string(
        _cls: &Bound<'_, PyType>,
        xml: String,
        base: Option<String>,
        tip: Option<String>,
        source: &str,
        tool: Option<Vec<f64>>,
        floating_base: bool,
    ) -> PyResult<Self> {
        let options = LoadOptions {
            base,
            tip,
            tool,
            floating_base,
            ..LoadOptions::default()
        };
        Self::build(&Source::text(xml, source), &options)
    }

    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<Bound<'py, PyAny>> {
        let py = slf.py();
        let r = slf.get();
        let ctor = py.get_type::<Robot>().getattr("_restore")?;
        let frames: Vec<(String, String, Vec<f64>)> = match r.tree_model() {
            Ok(kin) => {
                let m = kin.model();
                m.frames[m.links.len()..]
                    .iter()
                    .map(|f| {
                        let mut pose = vec![0.0; 16];
                        f.placement.write_row_major(&mut pose);
                        (f.name.clone(), m.links[f.link].name.clone(), pose)
                    })
                    .collect()
            }
            Err(_) => Vec::new(),
        };
        let o = r.robot.options();
        let args = (
            r.robot.urdf().to_string(),
            o.base.clone(),
            o.tip.clone(),
            r.robot.tree().source.clone(),
            o.tool.clone(),
            o.floating_base,
            frames,
            // What the body needs to be read again: the folder and packages its meshes are
            // named from, which shapes, how meshes are read.
            (
                r.robot.dir().to_path_buf(),
                o.xacro.package_paths.clone(),
                o.geometry.as_str(),
                o.meshes.map(|m| m.as_str()),
            ),
            // The body's state: the pairs disabled (an SRDF's), the obstacles added.
            r.body_state(),
        );
        Ok((ctor, args).into_pyobject(py)?.into_any())
    }

    /// Pickling's constructor: the URDF text, the load options and the added frames.
    #[classmethod]
    #[allow(clippy::too_many_arguments)]
    fn _restore(
        _cls: &Bound<'_, PyType>,
        xml: String,
        base: Option<String>,
        tip: Option<String>,
        source: &str,
        tool: Option<Vec<f64>>,
        floating_base: bool,
        frames: Vec<(String, String, Vec<f64>)>,
        body: (PathBuf, Vec<PathBuf>, String, Option<String>),
        state: BodyState,
    ) -> PyResult<Self> {
        let (dir, package_paths, geometry, meshes) = body;
        let options = LoadOptions {
            base,
            tip,
            tool,
            floating_base,
            xacro: xacro_options(Some(package_paths), None),
            geometry: word::<GeometryRoles>("geometry", &geometry)?,
            meshes: meshes.map(|m| word::<Meshes>("meshes", &m)).transpose()?,
        };
        let source = Source::Text {
            text: xml,
            label: source.to_string(),
            dir,
        };
        let r = Self::build(&source, &options)?;
        for (name, link, pose) in frames {
            let t = screwkit_lie::Se3::from_row_major(&pose, 1e-9)
                .map_err(|e| PyValueError::new_err(format!("frame {name}: {e}")))?;
            r.add_frame_pose(&name, &link, t)?;
        }
        let (disabled, obstacles) = state;
        if !disabled.is_empty() || !obstacles.is_empty() {
            let shapes = obstacles
                .iter()
                .map(|(_, s, _)| crate::body::state_shape(s))
                .collect::<PyResult<Vec<_>>>()?;
            r.change_body(|m| {
                for (a, b) in &disabled {
                    m.disable(a, b)?;
                }
                for ((name, _, pose), shape) in obstacles.iter().zip(&shapes) {
                    let pose = target::from_row_major(pose)?;
                    m.add_obstacle(name, shape, pose)?;
                }
                Ok(())
            })?;
        }
        Ok(r)
    }

    fn __repr__(&self) -> String {
        match self.robot.chain() {
            Ok(c) if !self.tree_mode() => format!(
                "Robot({:?}, base={:?}, tip={:?}, dof={})",
                c.source,
                c.base,
                c.tip,
                c.dof()
            ),
            _ => match self.tree_model() {
                Ok(k) => format!(
                    "Robot({:?}, whole tree: {} links, {} frames, nq={}, nv={}{})",
                    self.robot.tree().source,
                    k.model().links.len(),
                    k.frame_count(),
                    k.nq(),
                    k.nv(),
                    if k.floating_base() {
                        ", floating base"
                    } else {
                        ""
                    }
                ),
                Err(_) => format!("Robot({:?})", self.robot.tree().source),
            },
        }
    }

    /// The robot's name (`<robot name=…>`).
    #[getter]
    fn name(&self) -> &str {
        &self.robot.tree().name
    }

    /// The file the robot came from (or the `source` label of `from_string`).
    #[getter]
    fn source(&self) -> &str {
        &self.robot.tree().source
    }

    /// Base link of the chain (the space frame); `ValueError` when there is no chain.
    #[getter]
    fn base(&self) -> PyResult<String> {
        Ok(self.chain()?.base.clone())
    }

    /// Tip link of the chain (the body frame); `ValueError` when there is no chain.
    #[getter]
    fn tip(&self) -> PyResult<String> {
        Ok(self.chain()?.tip.clone())
    }

    /// Degrees of freedom: the length of the chain's q; for the whole tree (no chain, or a
    /// floating base) the length of v (`nv`).
    #[getter]
    fn dof(&self) -> PyResult<usize> {
        self.with_space(|s| s.dof())
    }

    /// The joints of the chain's q, in order (mimic joints follow their leader and are not in
    /// q); for the whole tree, `variable_names`.
    #[getter]
    fn joint_names(&self) -> PyResult<Vec<String>> {
        self.with_space(|s| s.joint_names())
    }

    /// The chain's velocity limits from its file (dof,): each variable's `<limit velocity>`
    /// (ValueError naming the joints without one).
    #[getter]
    fn velocity_limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let v = screwkit_service::path::velocity_limits(self.chain()?).map_err(service_error)?;
        Ok(v.to_pyarray(py))
    }

    /// The time-optimal timing of the chain's joint path `path` (m, dof), as
    /// `screwkit.time_parameterize` gives it, with `vel_limits` defaulting to the file's
    /// (`velocity_limits`).
    #[pyo3(signature = (path, acc_limits, vel_limits = None, *, grid = None, check = 0.001))]
    fn time_parameterize(
        &self,
        py: Python<'_>,
        path: &Bound<'_, PyAny>,
        acc_limits: &Bound<'_, PyAny>,
        vel_limits: Option<&Bound<'_, PyAny>>,
        grid: Option<usize>,
        check: f64,
    ) -> PyResult<crate::trajectory::TimedPath> {
        let vel = match vel_limits {
            Some(v) => v.clone(),
            None => self.velocity_limits(py)?.into_any(),
        };
        crate::trajectory::time_parameterize(py, path, &vel, acc_limits, grid, check)
    }

    /// The moving joints base → tip, one per row of `screw_axes` (mimic joints included).
    #[getter]
    fn axis_names(&self) -> PyResult<Vec<String>> {
        Ok(self
            .chain()?
            .joints
            .iter()
            .map(|j| j.name.clone())
            .collect())
    }

    /// The links base → tip of the chain, one per pose of `fk_all_links`; for the whole tree
    /// every link in the file's order.
    #[getter]
    fn link_names(&self) -> PyResult<Vec<String>> {
        self.with_space(|s| s.link_names())
    }

    /// Lower limits of q, shape (dof,) (−inf for continuous joints; for the whole tree with a
    /// floating base, −inf for its position and −1 for its quaternion).
    #[getter]
    fn lower<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(self.with_space(|s| s.lower())?.to_pyarray(py))
    }

    /// Upper limits of q, shape (dof,) (+inf for continuous joints; see `lower`).
    #[getter]
    fn upper<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(self.with_space(|s| s.upper())?.to_pyarray(py))
    }

    /// The midpoint of the limits (0 for continuous joints): the default IK seed, shape (dof,).
    #[getter]
    fn midpoint<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(self.kin()?.midpoint().to_pyarray(py))
    }

    /// M: the tip pose at q = 0, shape (4, 4).
    #[getter]
    fn home<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let home = self.chain()?.home;
        Ok(new_array(py, &[4, 4], |o| home.write_row_major(o))?.into_any())
    }

    /// The screw axes at home, one row (ω, v) per moving joint (`axis_names`): S_i in the
    /// space frame or B_i in the body frame. Shape (joints, 6).
    #[pyo3(signature = (frame = "space"))]
    fn screw_axes<'py>(&self, py: Python<'py>, frame: &str) -> PyResult<Bound<'py, PyAny>> {
        let frame: screwkit_lie::Frame = word::<ScrewFrame>("frame", frame)?.into();
        let joints = &self.chain()?.joints;
        Ok(new_array(py, &[joints.len(), 6], |o| {
            for (j, row) in joints.iter().zip(o.chunks_mut(6)) {
                row.copy_from_slice(j.screw(frame).twist().to_vector().as_slice());
            }
        })?
        .into_any())
    }

    /// The screw-axis table as text: `fmt` "markdown", "csv" or "json"; `frame` "space",
    /// "body" or "both" (JSON always has both).
    #[pyo3(signature = (fmt = "markdown", frame = "both"))]
    fn table(&self, fmt: &str, frame: &str) -> PyResult<String> {
        let frames = word::<TableFrames>("frame", frame)?.frames();
        Ok(match word::<TableFormat>("fmt", fmt)? {
            TableFormat::Markdown => table::to_markdown(self.chain()?, &frames),
            TableFormat::Csv => table::to_csv(self.chain()?, &frames),
            TableFormat::Json => table::to_json(self.chain()?).to_string(),
        })
    }

    /// Forward kinematics T(q) = e^[S1]q1 ⋯ e^[Sn]qn M: q (dof,) → (4, 4); q (N, dof) →
    /// (N, 4, 4), computed on all cores with the GIL released.
    ///
    /// With `link` (any frame: a link or an added frame), the pose of that frame of the whole
    /// tree, q the tree's configuration (`q_names`: the file's joint order, after the floating
    /// base's x, y, z, qx, qy, qz, qw); with `relative_to`, its pose in that frame
    /// (T_B⁻¹ T_A). A robot without a chain (several leaves, or a floating base) needs `link`.
    #[pyo3(signature = (q, link = None, *, relative_to = None))]
    fn fk<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        link: Option<&str>,
        relative_to: Option<&str>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let tree = self.tree_for(link.is_some() || relative_to.is_some())?;
        let about = About::resolve(&self.robot, tree.as_deref(), link, relative_to)
            .map_err(service_error)?;
        let q = f64_array(q, "q")?;
        match Self::rows_about(&about, &q, "q")? {
            Rows::One => {
                let t = about.pose(&q.to_vec()?).map_err(solve_error)?;
                Ok(new_array(py, &[4, 4], |o| t.write_row_major(o))?.into_any())
            }
            Rows::Many(n) => {
                run_batch(py, &[n, 4, 4], &q, FK_CHUNK / 4, |qs, o| about.poses(qs, o))
            }
        }
    }

    /// Every link's pose (`link_names` order): q (dof,) → (links, 4, 4); q (N, dof) →
    /// (N, links, 4, 4). For the whole tree: every link of the file in one sweep, q (nq,).
    fn fk_all_links<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.poses_of(py, q, Selection::Links)
    }

    /// Every frame's pose of the whole tree (`frame_names` order: the links, then the added
    /// frames) in one sweep: q (nq,) → (frames, 4, 4); q (N, nq) → (N, frames, 4, 4).
    fn fk_all_frames<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.poses_of(py, q, Selection::All)
    }

    /// The Jacobian in `frame` — "space" (J_s), "body" (J_b) or "world-aligned" (J_wa: the
    /// angular velocity and the tip point's velocity in base axes; Pinocchio's
    /// LOCAL_WORLD_ALIGNED) — rows (ω, v): q (dof,) → (6, dof); q (N, dof) → (N, 6, dof).
    ///
    /// With `link`, the Jacobian of that frame of the whole tree, one column per entry of v
    /// (`v_names`: the floating base's twist (ω, v) in its own frame, then the joint
    /// variables; zeros for joints off the frame's path); with `relative_to`, of its motion
    /// relative to that frame (space: in that frame; body: in `link`'s frame; world-aligned:
    /// that frame's axes at `link`'s origin).
    #[pyo3(signature = (q, frame = "space", link = None, *, relative_to = None))]
    fn jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        frame: &str,
        link: Option<&str>,
        relative_to: Option<&str>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let kind = word::<JacobianFrame>("frame", frame)?.kind();
        let tree = self.tree_for(link.is_some() || relative_to.is_some())?;
        let about = About::resolve(&self.robot, tree.as_deref(), link, relative_to)
            .map_err(service_error)?;
        let q = f64_array(q, "q")?;
        let n = about.columns();
        match Self::rows_about(&about, &q, "q")? {
            // Written straight into the new array (no intermediate copy).
            Rows::One => {
                let q = q.to_vec()?;
                let mut result = Ok(screwkit_lie::Se3::identity());
                let array = new_array(py, &[6, n], |o| result = about.pose_jacobian(kind, &q, o))?;
                result.map_err(solve_error)?;
                Ok(array.into_any())
            }
            Rows::Many(rows) => run_batch(py, &[rows, 6, n], &q, FK_CHUNK / 16, |qs, o| {
                about.jacobians(kind, qs, o, None)
            }),
        }
    }

    /// The whole tree's independent joint variables, in the file's joint order (mimic
    /// followers excluded; without the floating base).
    #[getter]
    fn variable_names(&self) -> PyResult<Vec<String>> {
        let kin = self.tree_model()?;
        Ok(kin
            .model()
            .variables
            .iter()
            .map(|v| v.name.clone())
            .collect())
    }

    /// One label per entry of the whole tree's q: `floating_base.x` … `floating_base.qw`
    /// (with a floating base), then `variable_names`.
    #[getter]
    fn q_names(&self) -> PyResult<Vec<String>> {
        Ok(self.tree_model()?.q_names().to_vec())
    }

    /// One label per entry of v and per Jacobian column: `floating_base.wx` …
    /// `floating_base.vz` (the base's twist (ω, v) in its own frame), then `variable_names`.
    #[getter]
    fn v_names(&self) -> PyResult<Vec<String>> {
        Ok(self.tree_model()?.v_names().to_vec())
    }

    /// The length of the whole tree's q (7 + joint variables with a floating base).
    #[getter]
    fn nq(&self) -> PyResult<usize> {
        Ok(self.tree_model()?.nq())
    }

    /// The length of the whole tree's v (6 + joint variables with a floating base).
    #[getter]
    fn nv(&self) -> PyResult<usize> {
        Ok(self.tree_model()?.nv())
    }

    /// True when a free joint joins the world to the root link.
    #[getter]
    fn floating_base(&self) -> bool {
        self.robot.options().floating_base || self.robot.tree().floating_root
    }

    /// Every frame of the whole tree: the links (file order), then the added frames.
    #[getter]
    fn frame_names(&self) -> PyResult<Vec<String>> {
        let kin = self.tree_model()?;
        Ok((0..kin.frame_count())
            .map(|f| kin.frame_name(f).to_string())
            .collect())
    }

    /// Adds a frame fixed to `parent_link` at `pose` ((4, 4): its pose in the link's frame): a
    /// tool frame, a sensor, a site. Its name must be new among links and frames.
    fn add_frame(&self, name: &str, parent_link: &str, pose: &Bound<'_, PyAny>) -> PyResult<()> {
        let t = crate::se3_arg(pose, "pose")?;
        self.add_frame_pose(name, parent_link, t)
    }

    /// The centre of mass (3,) in the world frame: Σ m_L T_L c_L / Σ m_L over every link with
    /// an `<inertial>` mass (the root link included), q the whole tree's configuration (nq,).
    fn com<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let c = self
            .with_tree_ws(&kin, |ws| tree::com::com(&kin, ws, &q))
            .map_err(solve_error)?;
        Ok(c.as_slice().to_pyarray(py))
    }

    /// The centre of mass's Jacobian (3, nv): ċ = J_c v, columns in `v_names` order.
    fn com_jacobian<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let nv = kin.nv();
        self.with_tree_ws(&kin, |ws| {
            let (_, j) = tree::com::com_jacobian(&kin, ws, &q).map_err(solve_error)?;
            Ok(new_array(py, &[3, nv], |o| {
                for r in 0..3 {
                    for c in 0..nv {
                        o[r * nv + c] = j[(r, c)];
                    }
                }
            })?
            .into_any())
        })
    }

    /// What is in the robot's file, as `screwkit info --format json` gives it (the floor's
    /// report): robot, root, links, joints (type, parent, child, limits, mimic), leaves, the
    /// whole tree's variables and frames (home poses), and the chain (`default_chain`: base,
    /// tip, dof, ik_family).
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let o = self.robot.options();
        let report = screwkit_service::info::InfoReport::new(
            self.robot.tree(),
            o.base.as_deref(),
            o.tip.as_deref(),
        )
        .map_err(service_error)?;
        crate::reach::report_dict(py, &screwkit_service::report::to_value(&report))
    }

    /// True when the robot collides with itself or an obstacle at q (its `<collision>` shapes;
    /// pairs of adjacent or welded links, and pairs an SRDF disables, are not checked). q:
    /// the whole tree's configuration, or a chain robot's joint values (its other joints at 0
    /// clamped into their limits); (N, n) → (N,) bools, on all cores.
    fn in_collision<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (kin, model) = self.body_model()?;
        match self.body_rows(&kin, q)? {
            (Rows::One, q) => {
                let hit = self
                    .with_body_ws(&kin, &model, |ws| {
                        screwkit_collision::in_collision(&model, ws, &kin, &q)
                    })
                    .map_err(|e| service_error(e.into()))?;
                Ok(pyo3::types::PyBool::new(py, hit).to_owned().into_any())
            }
            (Rows::Many(n), qs) => {
                let mut hits = vec![false; n];
                let r = pool::cancellable(py, || {
                    screwkit_collision::in_collision_batch(&model, &kin, &qs, &mut hits)
                })?;
                r.map_err(|e| service_error(e.into()))?;
                Ok(hits.to_pyarray(py).into_any())
            }
        }
    }

    /// The colliding pairs at q, by link (or obstacle) name, each once: [(a, b), …]; (N, n) →
    /// a list of N such lists, on all cores.
    fn collisions<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (kin, model) = self.body_model()?;
        let mut ws = CollisionWorkspace::new(&kin, &model);
        let mut hits = Vec::new();
        let mut one = |q: &[f64]| -> PyResult<Vec<(String, String)>> {
            screwkit_collision::collisions(&model, &mut ws, &kin, q, &mut hits)
                .map_err(|e| service_error(e.into()))?;
            Ok(screwkit_service::body::colliding_links(&model, &hits))
        };
        match self.body_rows(&kin, q)? {
            (Rows::One, q) => Ok(one(&q)?.into_pyobject(py)?.into_any()),
            (Rows::Many(n), qs) => {
                let mut hits = vec![Vec::new(); n];
                pool::cancellable(py, || {
                    screwkit_collision::collisions_batch(&model, &kin, &qs, &mut hits)
                })?
                .map_err(|e| service_error(e.into()))?;
                let all: Vec<_> = hits
                    .iter()
                    .map(|h| screwkit_service::body::colliding_links(&model, h))
                    .collect();
                Ok(all.into_pyobject(py)?.into_any())
            }
        }
    }

    /// Every checked pair's signed distance at q (`Distances`: `pairs`, `distance` (P,),
    /// `points` (P, 2, 3), `normal` (P, 3)); (N, n) → a list of N, on all cores. With
    /// `jacobians=True`, each also holds `jacobian` (P, nv): row k is the rate of distance k
    /// along the tree's velocity v (ḋ = J v; a floating base's six first), the unit force n at
    /// the witness points as a wrench on each link's space Jacobian.
    #[pyo3(signature = (q, *, jacobians = false))]
    fn distances<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        jacobians: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (kin, model) = self.body_model()?;
        let nv = kin.nv();
        let mut ws = CollisionWorkspace::new(&kin, &model);
        let (mut out, mut rows) = (Vec::new(), Vec::new());
        let mut one = |q: &[f64]| -> PyResult<crate::body::Distances> {
            if jacobians {
                screwkit_collision::distance_jacobians(
                    &model, &mut ws, &kin, q, &mut out, &mut rows,
                )
            } else {
                screwkit_collision::distances(&model, &mut ws, &kin, q, &mut out)
            }
            .map_err(|e| service_error(e.into()))?;
            crate::body::Distances::new(py, &model, &out, jacobians.then_some((&rows[..], nv)))
        };
        match self.body_rows(&kin, q)? {
            (Rows::One, q) => Ok(Bound::new(py, one(&q)?)?.into_any()),
            (Rows::Many(n), qs) => {
                let mut all = vec![(Vec::new(), Vec::new()); n];
                pool::cancellable(py, || {
                    if jacobians {
                        screwkit_collision::distance_jacobians_batch(&model, &kin, &qs, &mut all)
                    } else {
                        let mut d = vec![Vec::new(); n];
                        let r = screwkit_collision::distances_batch(&model, &kin, &qs, &mut d);
                        for (slot, d) in all.iter_mut().zip(d) {
                            slot.0 = d;
                        }
                        r
                    }
                })?
                .map_err(|e| service_error(e.into()))?;
                let list = pyo3::types::PyList::empty(py);
                for (d, rows) in &all {
                    let j = jacobians.then_some((&rows[..], nv));
                    list.append(Bound::new(
                        py,
                        crate::body::Distances::new(py, &model, d, j)?,
                    )?)?;
                }
                Ok(list.into_any())
            }
        }
    }

    /// The smallest signed distance over the checked pairs at q (m; negative when some pair
    /// overlaps; inf without pairs); (N, n) → (N,), on all cores.
    fn min_distance<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let (kin, model) = self.body_model()?;
        match self.body_rows(&kin, q)? {
            (Rows::One, q) => {
                let d = self
                    .with_body_ws(&kin, &model, |ws| {
                        screwkit_collision::min_distance(&model, ws, &kin, &q)
                    })
                    .map_err(|e| service_error(e.into()))?;
                Ok(
                    pyo3::types::PyFloat::new(py, d.map_or(f64::INFINITY, |d| d.distance))
                        .into_any(),
                )
            }
            (Rows::Many(n), qs) => {
                let mut out = vec![0.0; n];
                let r = pool::cancellable(py, || {
                    screwkit_collision::min_distance_batch(&model, &kin, &qs, &mut out)
                })?;
                r.map_err(|e| service_error(e.into()))?;
                Ok(out.to_pyarray(py).into_any())
            }
        }
    }

    /// The pairs a body query checks, by link (or obstacle) name.
    #[getter]
    fn collision_pairs(&self) -> PyResult<Vec<(String, String)>> {
        let (_, model) = self.body_model()?;
        Ok((0..model.pair_count())
            .map(|k| {
                let (a, b) = model.pair_names(k);
                (a.to_string(), b.to_string())
            })
            .collect())
    }

    /// Reads an SRDF file and stops checking the link pairs its `disable_collisions` list (a
    /// link the robot lacks is a `ValueError` naming it).
    fn srdf(&self, path: PathBuf) -> PyResult<()> {
        self.change_body(|m| {
            m.apply_srdf(&screwkit_model::srdf::read_file(&path)?)?;
            Ok(())
        })
    }

    /// Generates the allowed-collision matrix as MoveIt's setup assistant does (adjacent links,
    /// pairs colliding at the default configuration, pairs colliding in ≥ 95 % of `samples`
    /// random configurations, and with `never` the pairs that never collided) and returns it
    /// as SRDF text, written to `path` when given. The same seed gives the same bytes.
    #[pyo3(signature = (path = None, *, samples = 10000, seed = 0, never = false))]
    fn write_srdf(
        &self,
        py: Python<'_>,
        path: Option<PathBuf>,
        samples: usize,
        seed: u64,
        never: bool,
    ) -> PyResult<String> {
        let kin = self.tree_model()?;
        let g = screwkit_collision::acm::Generate {
            samples,
            seed,
            never,
            ..Default::default()
        };
        let name = &self.robot.tree().name;
        let meshes = self.robot.options().meshes;
        let text = pool::cancellable(py, || {
            screwkit_service::body::generated_srdf(name, &kin, meshes, &g)
        })?
        .map_err(service_error)?;
        write_text(path, &text)?;
        Ok(text)
    }

    /// Adds (or replaces) the obstacle `name`: `shape` (`screwkit.Box`, `Sphere`, `Capsule`,
    /// `Cylinder`, `Mesh`) at `pose` (4, 4) in the world (the root link's frame). Every body
    /// query then checks it against every link.
    fn add_obstacle(
        &self,
        name: &str,
        shape: &Bound<'_, PyAny>,
        pose: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let shape = crate::body::shape_of(shape)?;
        let p = f64_array(pose, "pose")?;
        if p.shape() != [4, 4] {
            return Err(PyValueError::new_err(format!(
                "pose: expected shape (4, 4), got {}",
                shape_str(p.shape())
            )));
        }
        let pose = target::from_row_major(&p.to_vec()?)
            .map_err(|e| PyValueError::new_err(format!("pose: {e}")))?;
        self.change_body(|m| Ok(m.add_obstacle(name, &shape, pose)?))
    }

    /// Adds the obstacles of a scene file (JSON, as `screwkit collide --obstacles` reads it:
    /// `{"obstacles": [{"name", "shape", "size" | "radius" | "length" | "path" | "scale",
    /// "xyz", "rpy" | "pose"}]}`; mesh paths relative to the file); returns their names. A bad
    /// file raises `ValueError` naming it and the obstacle.
    fn add_obstacles(&self, path: PathBuf) -> PyResult<Vec<String>> {
        let obstacles =
            screwkit_service::body::read_scene(&path, &self.robot.options().xacro.package_paths)
                .map_err(service_error)?;
        self.change_body(|m| screwkit_service::body::add_obstacles(m, &obstacles))?;
        Ok(obstacles.into_iter().map(|o| o.name).collect())
    }

    /// Removes the obstacle `name`; True if there was one.
    fn remove_obstacle(&self, name: &str) -> PyResult<bool> {
        self.change_body(|m| Ok(m.remove_obstacle(name)))
    }

    /// The obstacles' names, in the order added.
    #[getter]
    fn obstacles(&self) -> PyResult<Vec<String>> {
        let (_, model) = self.body_model()?;
        Ok(model.obstacles().into_iter().map(str::to_string).collect())
    }

    /// The total mass (kg) of the links with an `<inertial>` mass (0 when the file has none).
    #[getter]
    fn total_mass(&self) -> PyResult<f64> {
        Ok(tree::com::total_mass(&*self.tree_model()?))
    }

    /// The tool moved along a Cartesian path from the seed's pose through `targets` ((4, 4),
    /// or (K, 4, 4) waypoints), the joints following on one IK branch: by the chain's
    /// closed-form IK when it has one (each sample the nearest solution to the previous:
    /// the same posture and 2π copy; a 7R arm holds one joint at the seed's value, `lock`
    /// (name or index; "arm_angle" for an arm with a spherical shoulder and wrist: its arm
    /// angle held), default the joint its solver chooses), else by numerical IK seeded with
    /// the previous sample.
    /// `interpolation` "screw" (one screw motion between poses) or "line" (the origin on the
    /// straight line, the rotation about one axis); steps of at most `max_step` (m and rad of
    /// the tool), `max_joint_step` (rad or m) per joint and a joint-space midpoint within
    /// `max_deviation` (m and rad) of the path's, each step halved (8 times at most) before
    /// giving up; it stops near a singularity (the Jacobian's smallest singular value below
    /// `min_sigma`) rather than jump. `avoid_collisions`: every sample's body (the whole
    /// robot, its disabled pairs and obstacles as they are now) keeps each checked pair
    /// `margin` metres apart, and the path stops before one that does not ("collision",
    /// naming the pair). Returns a `CartesianPath` (q, place, fraction, stop, message); never
    /// raises for a path that cannot be completed, only for bad arguments.
    /// Many paths at once: `cartesian_paths`.
    #[pyo3(signature = (targets, seed = None, *, interpolation = "screw", max_step = 0.005, max_joint_step = 0.1, max_deviation = 0.001, min_sigma = 0.005, lock = None, avoid_collisions = false, margin = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn cartesian_path<'py>(
        &self,
        py: Python<'py>,
        targets: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
        interpolation: &str,
        max_step: f64,
        max_joint_step: f64,
        max_deviation: f64,
        min_sigma: f64,
        lock: Option<&Bound<'py, PyAny>>,
        avoid_collisions: bool,
        margin: f64,
    ) -> PyResult<Bound<'py, crate::results::CartesianPath>> {
        Ok(self
            .paths(
                false,
                py,
                targets,
                seed,
                interpolation,
                max_step,
                max_joint_step,
                max_deviation,
                min_sigma,
                lock,
                avoid_collisions,
                margin,
            )?
            .cast_into::<crate::results::CartesianPath>()?)
    }

    /// Many Cartesian paths on all cores: `targets` (N, K, 4, 4) (or (N, 4, 4): one target
    /// each) and `seed` (dof,) or (N, dof) → a list of N `CartesianPath`s, each equal to its
    /// `cartesian_path` call whatever the thread count (same arguments); a bad row raises
    /// `BatchError`, whose `.result` is the list with None at those rows.
    #[pyo3(signature = (targets, seed = None, *, interpolation = "screw", max_step = 0.005, max_joint_step = 0.1, max_deviation = 0.001, min_sigma = 0.005, lock = None, avoid_collisions = false, margin = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn cartesian_paths<'py>(
        &self,
        py: Python<'py>,
        targets: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
        interpolation: &str,
        max_step: f64,
        max_joint_step: f64,
        max_deviation: f64,
        min_sigma: f64,
        lock: Option<&Bound<'py, PyAny>>,
        avoid_collisions: bool,
        margin: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        self.paths(
            true,
            py,
            targets,
            seed,
            interpolation,
            max_step,
            max_joint_step,
            max_deviation,
            min_sigma,
            lock,
            avoid_collisions,
            margin,
        )
    }

    /// How the dynamics (`inverse_dynamics`, `mass_matrix`, …) takes the file: `inertias`
    /// "check" (an `<inertial>` no rigid body has raises ValueError naming its link),
    /// "as-given" (taken as it is) or "balance" (a triangle-inequality breach balanced as
    /// MuJoCo's `balanceinertia` does); `armature` adds each joint's armature to M's diagonal,
    /// `damping` each joint's damping · v to τ and h (both off by default, as in Pinocchio;
    /// MuJoCo always adds them). A bad armature or damping raises ValueError naming its joint.
    #[pyo3(signature = (*, inertias = "check", armature = false, damping = false))]
    fn set_dynamics_options(
        &self,
        py: Python<'_>,
        inertias: &str,
        armature: bool,
        damping: bool,
    ) -> PyResult<()> {
        let word = word::<screwkit_service::words::Inertias>("inertias", inertias)?;
        let options = screwkit_service::dynamics::options(word, armature, damping);
        let previous = std::mem::replace(
            &mut *self
                .dynamics_options
                .lock()
                .unwrap_or_else(|e| e.into_inner()),
            options,
        );
        *self.dynamics.lock().unwrap_or_else(|e| e.into_inner()) = None;
        // Built now, so that a bad file says so here (and the old options stay).
        if let Err(e) = self.with_dynamics(py, |_, _| Ok(())) {
            *self
                .dynamics_options
                .lock()
                .unwrap_or_else(|e| e.into_inner()) = previous;
            return Err(e);
        }
        Ok(())
    }

    /// Inverse dynamics τ = ID(q, v, a) of the whole tree (nv): the generalized forces that give
    /// the accelerations `a` at (q, v) under gravity, by recursive Newton–Euler in screw form
    /// (Pinocchio's `rnea`). q as `com` takes it (nq), v and a in `v_names` order; with a
    /// floating base τ starts with the wrench (m, f) on the base in its own frame. A batch:
    /// q (N, nq), v and a (N, nv) give (N, nv), on all cores.
    #[pyo3(signature = (q, v, a, f_ext = None))]
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        a: &Bound<'py, PyAny>,
        f_ext: Option<&Bound<'py, pyo3::types::PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::{self as dynamics, Quantity};
        let Some(f_ext) = f_ext else {
            return self.dynamics_call(
                py,
                Quantity::InverseDynamics,
                &[(q, "q"), (v, "v"), (a, "a")],
            );
        };
        // External wrenches on the robot: the robot exerts their opposites.
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let v = Self::one_vector(v, kin.nv(), "v")?;
        let a = Self::one_vector(a, kin.nv(), "a")?;
        let wrenches = self.frame_wrenches(&kin, f_ext, "f_ext", -1.0)?;
        let tau = self.with_dynamics(py, |d, ws| {
            let exerted = wrenches
                .iter()
                .map(|(f, w)| d.exerted(*f, w))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(dynamics::inverse_dynamics_exerting(d, ws, &q, &v, &a, &exerted)?.to_vec())
        })?;
        Ok(tau.to_pyarray(py).into_any())
    }

    /// Statics: the joint forces τ = Σ J_fᵀ F_f (nv) that hold the wrenches F_f = (m, f) the
    /// robot exerts on its environment at frames (`{frame name: (6,)}`, each in its frame's own
    /// coordinates; J_f the frame's body Jacobian), at rest; with `gravity=True`, plus g(q).
    #[pyo3(signature = (q, wrenches, *, gravity = false))]
    fn static_torques<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        wrenches: &Bound<'py, pyo3::types::PyDict>,
        gravity: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let wrenches = self.frame_wrenches(&kin, wrenches, "wrenches", 1.0)?;
        let tau = self.with_dynamics(py, |d, ws| {
            let exerted = wrenches
                .iter()
                .map(|(f, w)| d.exerted(*f, w))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(
                screwkit_solve::tree::dynamics::static_torques(d, ws, &q, &exerted, gravity)?
                    .to_vec(),
            )
        })?;
        Ok(tau.to_pyarray(py).into_any())
    }

    /// The gravity forces g(q) (nv) = ID(q, 0, 0) (Pinocchio's `computeGeneralizedGravity`);
    /// (N, nv) for q (N, nq).
    fn gravity<'py>(&self, py: Python<'py>, q: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::Quantity;
        self.dynamics_call(py, Quantity::Gravity, &[(q, "q")])
    }

    /// The nonlinear effects h(q, v) = C(q, v) v + g(q) (nv) (Pinocchio's `nonLinearEffects`);
    /// (N, nv) for a batch.
    fn nonlinear_effects<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::Quantity;
        self.dynamics_call(py, Quantity::NonlinearEffects, &[(q, "q"), (v, "v")])
    }

    /// The mass matrix M(q) (nv, nv), by the composite-rigid-body algorithm (Pinocchio's
    /// `crba`, both triangles filled); (N, nv, nv) for q (N, nq).
    fn mass_matrix<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::Quantity;
        self.dynamics_call(py, Quantity::MassMatrix, &[(q, "q")])
    }

    /// Forward dynamics a = FD(q, v, τ) = M(q)⁻¹ (τ − h(q, v)) (nv): the accelerations the
    /// forces τ give (Pinocchio's `aba` answers the same); (N, nv) for a batch. `f_ext`:
    /// external wrenches on the robot, `{frame name: (6,)}` each (m, f) in its frame's own
    /// coordinates, as `inverse_dynamics` takes them (one configuration only).
    #[pyo3(signature = (q, v, tau, f_ext = None))]
    fn forward_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        tau: &Bound<'py, PyAny>,
        f_ext: Option<&Bound<'py, pyo3::types::PyDict>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::{self as dynamics, Quantity};
        let Some(f_ext) = f_ext else {
            return self.dynamics_call(
                py,
                Quantity::ForwardDynamics,
                &[(q, "q"), (v, "v"), (tau, "tau")],
            );
        };
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let v = Self::one_vector(v, kin.nv(), "v")?;
        let tau = Self::one_vector(tau, kin.nv(), "tau")?;
        // External wrenches on the robot: the robot exerts their opposites.
        let wrenches = self.frame_wrenches(&kin, f_ext, "f_ext", -1.0)?;
        let a = self.with_dynamics(py, |d, ws| {
            let exerted = wrenches
                .iter()
                .map(|(f, w)| d.exerted(*f, w))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(dynamics::forward_dynamics_exerting(d, ws, &q, &v, &tau, &exerted)?.to_vec())
        })?;
        Ok(a.to_pyarray(py).into_any())
    }

    /// The centroidal momentum map A_G(q) (6, nv): the momentum about the centre of mass of
    /// unit speed of each variable, (angular, linear) rows in the world's axes (Pinocchio's
    /// `computeCentroidalMap`, whose rows are (linear, angular)).
    fn centroidal_map<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let rows = self.with_dynamics(py, |d, ws| {
            let (map, _) = screwkit_solve::tree::dynamics::centroidal_map(d, ws, &q)?;
            Ok(map
                .row_iter()
                .map(|r| r.iter().copied().collect())
                .collect::<Vec<Vec<f64>>>())
        })?;
        Ok(PyArray2::from_vec2(py, &rows)?)
    }

    /// The centroidal momentum h_G = A_G(q) v (6,): (k_G, p), the angular momentum about the
    /// centre of mass and the linear momentum, in the world's axes (Pinocchio's
    /// `computeCentroidalMomentum`, in (linear, angular) order).
    fn centroidal_momentum<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let v = Self::one_vector(v, kin.nv(), "v")?;
        let h = self.with_dynamics(py, |d, ws| {
            Ok(screwkit_solve::tree::dynamics::centroidal_momentum(d, ws, &q, &v)?.0)
        })?;
        Ok(h.to_pyarray(py))
    }

    /// The kinetic energy ½ vᵀ M(q) v (J); (N,) for a batch.
    fn kinetic_energy<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::Quantity;
        self.dynamics_call(py, Quantity::KineticEnergy, &[(q, "q"), (v, "v")])
    }

    /// The potential energy −Σ m_i gᵀ c_i (J; zero at the world's origin height); (N,) for a
    /// batch.
    fn potential_energy<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        use screwkit_solve::tree::dynamics::Quantity;
        self.dynamics_call(py, Quantity::PotentialEnergy, &[(q, "q")])
    }

    /// The tasks prepared for this robot's whole tree (`TaskSet`): frames found and every task
    /// checked once; change a target with `TaskSet.set_target` and step with
    /// `ik_step(q, task_set, dt)` (or `ik_step_qp`), which then looks no name up. Adding a
    /// frame to the robot makes a new model: prepare the set again.
    fn task_set(&self, tasks: &Bound<'_, PyAny>) -> PyResult<crate::tasks::TaskSet> {
        let kin = self.tree_model()?;
        let specs = crate::tasks::specs(tasks)?;
        let set = screwkit_service::tasks::prepare(&specs, &kin).map_err(service_error)?;
        Ok(crate::tasks::TaskSet {
            kin,
            set: Mutex::new(set),
        })
    }

    /// One whole-body differential IK step: the velocity v (nv,) that moves every task by its
    /// gain in time `dt` as the weights decide, q + v·dt within the joints' position limits and
    /// |v| within their velocity limits (the file's `velocity`, and `velocity_caps` (joint
    /// variables,) when given). A q outside its limits raises ValueError naming the joint. The
    /// GIL is released. `tasks`: task objects, or a `TaskSet` prepared by `task_set` (no name
    /// lookup per step: a control loop's form).
    #[pyo3(signature = (q, tasks, dt, *, position_limits = true, velocity_limits = true, velocity_caps = None, limits = None))]
    #[allow(clippy::too_many_arguments)]
    fn ik_step<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        tasks: &Bound<'py, PyAny>,
        dt: f64,
        position_limits: bool,
        velocity_limits: bool,
        velocity_caps: Option<Bound<'py, PyAny>>,
        limits: Option<Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (kin, q, tasks, limits) = self.step_inputs(
            q,
            tasks,
            position_limits,
            velocity_limits,
            velocity_caps,
            limits.as_ref(),
        )?;
        let v = py
            .detach(|| {
                self.with_diff_ws(&kin, |ws| {
                    tasks.step(&kin, ws, &q, dt, &limits).map(|v| v.to_vec())
                })
            })
            .map_err(solve_error)?;
        Ok(v.to_pyarray(py))
    }

    /// The quadratic program `ik_step` solves, for inspection and reference solvers:
    /// (H (nv, nv), c (nv,), lower (nv,), upper (nv,)); its minimiser of ½ΔᵀHΔ + cᵀΔ within
    /// lower ≤ Δ ≤ upper is Δ = v·dt. With `limits` whose rows bind (`CollisionAvoidance`
    /// near contact) the problem also has G Δ ≥ h: `with_rows=True` returns (H, c, lower,
    /// upper, G (m, nv), h (m,)) (m = 0 when no row binds; the rows as the step last solved
    /// them, after raising a broken row's bound); without it such a step raises ValueError
    /// rather than return a problem that is not the one solved.
    #[pyo3(signature = (q, tasks, dt, *, position_limits = true, velocity_limits = true, velocity_caps = None, limits = None, with_rows = false))]
    #[allow(clippy::too_many_arguments)]
    fn ik_step_qp<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        tasks: &Bound<'py, PyAny>,
        dt: f64,
        position_limits: bool,
        velocity_limits: bool,
        velocity_caps: Option<Bound<'py, PyAny>>,
        limits: Option<Bound<'py, PyAny>>,
        with_rows: bool,
    ) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let (kin, q, tasks, limits) = self.step_inputs(
            q,
            tasks,
            position_limits,
            velocity_limits,
            velocity_caps,
            limits.as_ref(),
        )?;
        let nv = kin.nv();
        let ((h, c, l, u), (g, gh)) = self
            .with_diff_ws(&kin, |ws| {
                tasks.step(&kin, ws, &q, dt, &limits)?;
                let (h, c, l, u) = ws.qp();
                let (g, gh) = ws.rows();
                Ok::<_, screwkit_solve::SolveError>((
                    (h.to_vec(), c.to_vec(), l.to_vec(), u.to_vec()),
                    (g.to_vec(), gh.to_vec()),
                ))
            })
            .map_err(solve_error)?;
        if !with_rows && !gh.is_empty() {
            return Err(PyValueError::new_err(format!(
                "this step's QP has {} general rows from `limits` (G Δ ≥ h): ask for them with with_rows=True",
                gh.len()
            )));
        }
        // The full symmetric H (the solver reads its lower triangle).
        let hm = new_array(py, &[nv, nv], |o| {
            for i in 0..nv {
                for j in 0..nv {
                    o[i * nv + j] = if j <= i { h[i * nv + j] } else { h[j * nv + i] };
                }
            }
        })?;
        let mut items = vec![
            hm.into_any(),
            c.to_pyarray(py).into_any(),
            l.to_pyarray(py).into_any(),
            u.to_pyarray(py).into_any(),
        ];
        if with_rows {
            let gm = new_array(py, &[gh.len(), nv], |o| o.copy_from_slice(&g))?;
            items.push(gm.into_any());
            items.push(gh.to_pyarray(py).into_any());
        }
        pyo3::types::PyTuple::new(py, items)
    }

    /// Whole-body IK to convergence from `seed` (nq,; default: the neutral configuration with
    /// the joints brought within their limits): steps until every goal (frame, axis,
    /// centre-of-mass task) is within its tolerances, restarting from random joint values
    /// (`restarts`, seeded by `seed_rng`) when a descent stalls. Returns a TasksResult (.q,
    /// .converged, .iterations, .stop, .task_errors). The GIL is released; Ctrl-C interrupts.
    #[pyo3(signature = (tasks, seed = None, *, max_iterations = 100, restarts = 50, seed_rng = 0, position_limits = true, limits = None))]
    #[allow(clippy::too_many_arguments)]
    fn ik_tasks(
        &self,
        py: Python<'_>,
        tasks: &Bound<'_, PyAny>,
        seed: Option<Bound<'_, PyAny>>,
        max_iterations: usize,
        restarts: usize,
        seed_rng: u64,
        position_limits: bool,
        limits: Option<Bound<'_, PyAny>>,
    ) -> PyResult<crate::tasks::TasksResult> {
        let kin = self.tree_model()?;
        let tasks = self.resolve_tasks(&kin, tasks)?;
        let seed = match seed {
            Some(s) => Self::one_vector(&s, kin.nq(), "seed")?,
            None => screwkit_service::tasks::default_seed(&kin),
        };
        let opts = differential_ik::TasksOptions {
            limits: self.extra_limits(limits.as_ref())?,
            ..tasks_options(max_iterations, restarts, seed_rng, position_limits)
        };
        let r = py
            .detach(|| {
                self.with_diff_ws(&kin, |ws| {
                    differential_ik::ik_tasks(&kin, ws, &tasks, &seed, &opts)
                })
            })
            .map_err(solve_error)?;
        pool::take_interrupt(py)?;
        tasks_result(py, r)
    }

    /// N target sets solved in order, each seeded by the previous answer (the first by `seed`):
    /// `task_sets` a sequence of task lists; a list of TasksResult. With `segment` > 0 the sets
    /// are solved in segments of that many on all cores, each segment first solving the
    /// `warm_up` sets before it from `seed` (the answers depend on these two, never on the
    /// thread count).
    #[pyo3(signature = (task_sets, seed = None, *, segment = 0, warm_up = 0, max_iterations = 100, restarts = 50, seed_rng = 0, position_limits = true, limits = None))]
    #[allow(clippy::too_many_arguments)]
    fn ik_trajectory(
        &self,
        py: Python<'_>,
        task_sets: &Bound<'_, PyAny>,
        seed: Option<Bound<'_, PyAny>>,
        segment: usize,
        warm_up: usize,
        max_iterations: usize,
        restarts: usize,
        seed_rng: u64,
        position_limits: bool,
        limits: Option<Bound<'_, PyAny>>,
    ) -> PyResult<Vec<crate::tasks::TasksResult>> {
        let kin = self.tree_model()?;
        let mut sets = Vec::new();
        for (i, t) in task_sets.try_iter()?.enumerate() {
            let t = t?;
            let specs = crate::tasks::specs(&t)?;
            sets.push(
                screwkit_service::tasks::resolve_all(&specs, &kin)
                    .map_err(|e| PyValueError::new_err(format!("task_sets[{i}]: {e}")))?,
            );
        }
        let seed = match seed {
            Some(s) => Self::one_vector(&s, kin.nq(), "seed")?,
            None => screwkit_service::tasks::default_seed(&kin),
        };
        // The sets run on the pool's threads: Ctrl-C reaches them through `pool::cancelled`.
        let opts = differential_ik::TasksOptions {
            interrupt: Some(ik::Interrupt(pool::cancelled)),
            limits: self.extra_limits(limits.as_ref())?,
            ..tasks_options(max_iterations, restarts, seed_rng, position_limits)
        };
        let segments = differential_ik::Segments {
            length: segment,
            warm_up,
        };
        let out = pool::cancellable(py, || {
            differential_ik::ik_trajectory(&kin, &sets, &seed, &opts, segments)
        })?
        .map_err(solve_error)?;
        out.into_iter()
            .enumerate()
            .map(|(i, r)| {
                let r = r.map_err(|e| PyValueError::new_err(format!("task_sets[{i}]: {e}")))?;
                tasks_result(py, r)
            })
            .collect()
    }

    /// q ⊕ v·dt on SE(3) × joints: the floating base moves by the exponential map
    /// (T ← T e^[V dt], V its twist in its own frame; its quaternion is composed, never added
    /// to), the joints by q + v dt. q (nq,), v (nv,) → (nq,).
    fn integrate<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        v: &Bound<'py, PyAny>,
        dt: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let v = Self::one_vector(v, kin.nv(), "v")?;
        let out = tree::configuration::integrate(&kin, &q, &v, dt).map_err(solve_error)?;
        Ok(out.to_pyarray(py))
    }

    /// The robot's kinematic tree as URDF text (as `screwkit urdf` writes it: links, joints,
    /// limits, mimic rules, masses; an MJCF model's sites as fixed child links), written to
    /// `path` when given. Loading it (with `floating_base` as this robot's) gives the same FK.
    #[pyo3(signature = (path = None))]
    fn to_urdf(&self, path: Option<PathBuf>) -> PyResult<String> {
        let text =
            screwkit_model::urdf::write(self.robot.tree()).map_err(crate::errors::model_error)?;
        write_text(path, &text)?;
        Ok(text)
    }

    /// screwkit's q (nq,) of MuJoCo's `qpos` for this model — the robot's own entries or the
    /// whole model's `data.qpos` (props read past included: the robot's entries are read at
    /// their addresses): the free joint's quaternion (w first in MuJoCo) reordered to qx, qy,
    /// qz, qw, each variable its joint's entry, a coupled follower's entry not read.
    // The issue's (and users' scripts') name: a conversion of this robot's qpos, so it takes self.
    #[allow(clippy::wrong_self_convention)]
    fn from_mujoco_qpos<'py>(
        &self,
        py: Python<'py>,
        qpos: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kin = self.tree_model()?;
        let arr = f64_array(qpos, "qpos")?;
        if arr.ndim() != 1 {
            return Err(PyValueError::new_err(format!(
                "qpos: expected a vector, got shape {}",
                shape_str(arr.shape())
            )));
        }
        let qpos = arr.to_vec()?;
        let q = screwkit_service::mujoco::from_qpos(&kin, &qpos).map_err(service_error)?;
        Ok(q.to_pyarray(py))
    }

    /// MuJoCo's `qpos` of screwkit's q (nq,): the base's quaternion w first, every joint's
    /// value, a coupled follower's as its coupling gives it. With `qpos` (the whole model's,
    /// e.g. `data.qpos`), a copy of it with the robot's entries written in (props keep theirs).
    #[pyo3(signature = (q, qpos = None))]
    fn to_mujoco_qpos<'py>(
        &self,
        py: Python<'py>,
        q: &Bound<'py, PyAny>,
        qpos: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kin = self.tree_model()?;
        let q = Self::one_vector(q, kin.nq(), "q")?;
        let model = match qpos {
            Some(m) => Some(Self::one_vector(
                m,
                screwkit_service::mujoco::model_qpos_len(&kin),
                "qpos",
            )?),
            None => None,
        };
        let out =
            screwkit_service::mujoco::to_qpos(&kin, &q, model.as_deref()).map_err(service_error)?;
        Ok(out.to_pyarray(py))
    }

    /// The v (nv,) with `integrate(q0, v, 1) = q1`: the base's log(T0⁻¹ T1), the joints
    /// q1 − q0.
    fn difference<'py>(
        &self,
        py: Python<'py>,
        q0: &Bound<'py, PyAny>,
        q1: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kin = self.tree_model()?;
        let a = Self::one_vector(q0, kin.nq(), "q0")?;
        let b = Self::one_vector(q1, kin.nq(), "q1")?;
        let out = tree::configuration::difference(&kin, &a, &b).map_err(solve_error)?;
        Ok(out.to_pyarray(py))
    }

    /// The whole tree's neutral configuration (nq,): the base at the origin with the
    /// identity quaternion (0, 0, 0, 1), the joints at zero.
    fn neutral<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(tree::configuration::neutral(&*self.tree_model()?).to_pyarray(py))
    }

    /// A random configuration of the whole tree (nq,) from `seed`: joints uniform within
    /// their limits ([−π, π] when unbounded), the base's orientation uniform and its position
    /// uniform in [−1, 1]³ m.
    #[pyo3(signature = (seed = 0))]
    fn random_configuration<'py>(
        &self,
        py: Python<'py>,
        seed: u64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let kin = self.tree_model()?;
        let mut rng = screwkit_solve::sample::SplitMix64(seed);
        Ok(tree::configuration::random(&kin, &mut rng).to_pyarray(py))
    }

    /// Singular values, rank, manipulability, condition number, ellipsoids and the verdict in
    /// words of the Jacobian in `frame` ("space", "body" or "world-aligned") at one
    /// configuration q (dof,). With `link` (and `relative_to`), of that frame of the whole tree
    /// (q (nq,)), as `jacobian` gives it; the position-only figures are of the frame point's
    /// velocity.
    #[pyo3(signature = (q, frame = "space", link = None, *, relative_to = None))]
    fn analyze(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        frame: &str,
        link: Option<&str>,
        relative_to: Option<&str>,
    ) -> PyResult<Analysis> {
        let frame_name = frame.to_string();
        let kind = word::<JacobianFrame>("frame", frame)?.kind();
        let tree = self.tree_for(link.is_some() || relative_to.is_some())?;
        let about = About::resolve(&self.robot, tree.as_deref(), link, relative_to)
            .map_err(service_error)?;
        let q = f64_array(q, "q")?;
        if let Rows::Many(_) = Self::rows_about(&about, &q, "q")? {
            return Err(PyValueError::new_err(format!(
                "q: analyze takes one configuration of shape ({},), got {}",
                about.q_len(),
                shape_str(q.shape())
            )));
        }
        let found = about.analyze(kind, &q.to_vec()?).map_err(solve_error)?;
        let (a, pos) = (&found.analysis, &found.position);
        let jac = new_array(py, &[6, about.columns()], |o| {
            batch::write_jacobian(&found.jacobian, o)
        })?
        .cast_into::<PyArray2<f64>>()?;
        let rows3 = |axes: &[nalgebra::Vector3<f64>; 3]| {
            PyArray2::from_vec2(
                py,
                &axes
                    .iter()
                    .map(|a| a.as_slice().to_vec())
                    .collect::<Vec<_>>(),
            )
        };
        let lost: Vec<Vec<f64>> = a
            .lost_directions
            .iter()
            .map(|d| d.as_slice().to_vec())
            .collect();
        let lost = if lost.is_empty() {
            PyArray2::zeros(py, [0, 6], false)
        } else {
            PyArray2::from_vec2(py, &lost)?
        };
        Ok(Analysis {
            verdict: a.verdict(),
            frame: frame_name,
            jacobian: jac.unbind(),
            singular_values: a.singular_values.to_pyarray(py).unbind(),
            rank: a.rank,
            rank_tolerance: a.rank_tolerance,
            manipulability: a.manipulability,
            condition_number: a.condition_number,
            determinant: a.determinant,
            lost_directions: lost.unbind(),
            weakest_direction: a.weakest_direction.as_slice().to_pyarray(py).unbind(),
            angular_axes: rows3(&a.angular.axes)?.unbind(),
            angular_lengths: a.angular.lengths.to_pyarray(py).unbind(),
            linear_axes: rows3(&a.linear.axes)?.unbind(),
            linear_lengths: a.linear.lengths.to_pyarray(py).unbind(),
            position_singular_values: pos.singular_values.to_pyarray(py).unbind(),
            position_rank: pos.rank,
            position_manipulability: pos.manipulability,
            position_condition_number: pos.condition_number,
        })
    }

    /// An SVG plot of a joint path `q` (K, dof) of the chain: one panel per joint against `x`
    /// (K, increasing; default: the sample's index), each joint's limits dashed where they
    /// fall in its panel's range; `x_label` default "place on the path …" when `x` is given.
    /// For a Cartesian path `plot_joints(path.q, path.place)`; for a timed one
    /// `plot_joints(q, t, x_label="time (s)")`. Returns the SVG text and writes it
    /// to `path` when given. Deterministic.
    #[pyo3(signature = (q, x = None, path = None, *, x_label = None, title = None))]
    fn plot_joints(
        &self,
        q: &Bound<'_, PyAny>,
        x: Option<&Bound<'_, PyAny>>,
        path: Option<PathBuf>,
        x_label: Option<&str>,
        title: Option<&str>,
    ) -> PyResult<String> {
        let kin = self.kin()?;
        let n = kin.dof();
        let q = f64_array(q, "q")?;
        let k = match q.shape() {
            [k, c] if *c == n => *k,
            other => {
                return Err(PyValueError::new_err(format!(
                    "q: expected shape (K, {n}), got {}",
                    shape_str(other)
                )))
            }
        };
        let q = q.to_vec()?;
        let given = x.is_some();
        let x = match x {
            Some(x) => {
                let v = f64_array(x, "x")?.to_vec()?;
                if v.len() != k {
                    return Err(PyValueError::new_err(format!(
                        "x: expected {k} values (one per row of q), got {}",
                        v.len()
                    )));
                }
                v
            }
            None => (0..k).map(|i| i as f64).collect(),
        };
        let (chain, _) = self.robot.chain_parts().map_err(service_error)?;
        let text = screwkit_draw::plot::joints(&screwkit_draw::plot::JointPlot {
            title: title.unwrap_or(&screwkit_draw::plot::title(&chain.robot)),
            names: kin.names(),
            x: &x,
            x_label: x_label.unwrap_or(if given {
                screwkit_draw::plot::PLACE_LABEL
            } else {
                "sample"
            }),
            q: &q,
            limits: Some((kin.lower(), kin.upper())),
        })
        .map_err(PyValueError::new_err)?;
        write_text(path, &text)?;
        Ok(text)
    }

    /// An SVG picture of the chain at q (default: home): the body's silhouettes (each shape
    /// of each link projected, in painter's order) under the skeleton through the link
    /// origins, joints by kind, the screw axes S_i(q) asked, base and tip frames, a scale bar
    /// and a legend. A whole tree (no chain, or a floating base; q of shape (nq,)) is drawn
    /// with every branch and every leaf's frame. `view`: "iso", "front", "side", "top" or
    /// "all" (the four on one sheet). `labels`: the names written — "none", "leaves" (a
    /// chain's tip, a tree's leaves) or "all" (every link) — each placed off the others, or
    /// left out when there is no room. `axes`: "all", "none", or joints by name or number
    /// (a list, or "J1,J2"); default: all for a chain or a tree of at most 12 joints, none
    /// for a larger tree. Returns the SVG text and writes it to `path` when given.
    /// Deterministic.
    #[pyo3(signature = (q = None, path = None, *, view = "iso", labels = "leaves", axes = None))]
    fn draw(
        &self,
        q: Option<&Bound<'_, PyAny>>,
        path: Option<PathBuf>,
        view: &str,
        labels: &str,
        axes: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<String> {
        let axes = match axes {
            None => screwkit_service::words::Axes::Auto,
            Some(a) if a.is_instance_of::<pyo3::types::PyString>() => a
                .extract::<String>()?
                .parse()
                .map_err(|e: String| PyValueError::new_err(format!("axes: {e}")))?,
            Some(a) => {
                // A list of names (str) or numbers (int, from 1).
                let mut names = Vec::new();
                for item in a.try_iter().map_err(|_| {
                    pyo3::exceptions::PyTypeError::new_err("axes: expected \"all\", \"none\", a string of joints or a list of joint names or numbers")
                })? {
                    let item = item?;
                    names.push(match item.extract::<String>() {
                        Ok(n) => n,
                        Err(_) => item
                            .extract::<usize>()
                            .map_err(|_| {
                                pyo3::exceptions::PyTypeError::new_err(format!(
                                    "axes: {item} is neither a joint name nor a number"
                                ))
                            })?
                            .to_string(),
                    });
                }
                screwkit_service::words::Axes::Joints(names)
            }
        };
        let options = screwkit_draw::svg::Options {
            views: word::<Views>("view", view)?.views(),
            labels: word::<screwkit_service::words::Labels>("labels", labels)?,
            axes,
        };
        let text = self.picture(q, screwkit_draw::Picture::Svg(&options))?;
        write_text(path, &text)?;
        Ok(text)
    }

    /// A self-contained interactive HTML page of the robot at q (default: home): its body
    /// (visual shapes and meshes; collision shapes, skeleton, screw axes and frames as
    /// toggles) in 3D with orbit and zoom, a slider per joint, the live tip pose and screw
    /// axes; `#q=a,b,…` in its URL sets the joints. Of a whole tree (as `draw`): every branch,
    /// a slider per variable, the pose of the leaf chosen. `motion`: configurations to play
    /// back, an array (frames, values) — `ik_trajectory`'s output — or a file (`.npy`, JSON)
    /// as `screwkit view --motion` reads it, at `fps` frames per second. `show_collisions`:
    /// the links (and obstacles) in collision tinted red, at the configuration first shown and
    /// at each motion frame (the body's pairs: its SRDF's disabled pairs left out, its
    /// obstacles in); `show_distances`: also each pair closer than 5 cm as its
    /// minimum-distance segment, the distances listed. Returns the HTML and writes it to
    /// `path` when given.
    #[pyo3(signature = (q = None, path = None, *, motion = None, fps = 30.0, show_collisions = false, show_distances = false))]
    #[allow(clippy::too_many_arguments)]
    fn viewer(
        &self,
        q: Option<&Bound<'_, PyAny>>,
        path: Option<PathBuf>,
        motion: Option<&Bound<'_, PyAny>>,
        fps: f64,
        show_collisions: bool,
        show_distances: bool,
    ) -> PyResult<String> {
        let frames: Option<Vec<Vec<f64>>> = match motion {
            None => None,
            // A file name (str or os.PathLike), else an array.
            Some(m) => Some(match m.extract::<PathBuf>() {
                Ok(file)
                    if m.is_instance_of::<pyo3::types::PyString>()
                        || m.hasattr("__fspath__")? =>
                {
                    // The page may not be written over the motion it plays.
                    if let (Some(out), Some(input)) =
                        (path.as_ref().and_then(|p| p.to_str()), file.to_str())
                    {
                        screwkit_service::io::atomic::check_distinct(&[input], &[out])
                            .map_err(PyValueError::new_err)?;
                    }
                    screwkit_service::io::motion::read(&file).map_err(crate::errors::file_error)?
                }
                _ => {
                    let a = crate::array::f64_array(m, "motion")?;
                    let shape = a.shape().to_vec();
                    let [_, n] = shape[..] else {
                        return Err(PyValueError::new_err(format!(
                            "motion: expected an array (frames, values), got shape {}",
                            shape_str(&shape)
                        )));
                    };
                    let flat = a.readonly();
                    flat.as_slice()?
                        .chunks(n.max(1))
                        .map(<[f64]>::to_vec)
                        .collect()
                }
            }),
        };
        let motion = frames
            .as_deref()
            .map(|frames| screwkit_draw::html::Motion { frames, fps });
        // The obstacles added to the body (not building the body just for them).
        let obstacles: Vec<screwkit_service::body::Obstacle> =
            match self.body.read().expect("the body lock").as_deref() {
                Some(m) => m
                    .added_obstacles()
                    .into_iter()
                    .map(|(name, shape, pose)| screwkit_service::body::Obstacle {
                        name: name.to_string(),
                        shape: shape.clone(),
                        pose,
                    })
                    .collect(),
                None => Vec::new(),
            };
        let body = if show_collisions || show_distances {
            Some(self.body_model()?)
        } else {
            None
        };
        let options = screwkit_draw::html::PageOptions {
            motion,
            obstacles: &obstacles,
            contacts: body
                .as_ref()
                .map(|(kin, model)| screwkit_draw::html::ShowContacts {
                    kin,
                    model,
                    distances: show_distances,
                }),
        };
        let text = self.picture(q, screwkit_draw::Picture::Page(options))?;
        write_text(path, &text)?;
        Ok(text)
    }

    /// The interactive page ([`Robot::viewer`]'s) as a notebook shows it: a `Page` that
    /// Jupyter displays inline (an iframe holding the whole page: nothing to install), with
    /// the HTML in `.html` and `.save(path)`. `height`: the iframe's, in pixels.
    #[pyo3(signature = (q = None, *, motion = None, fps = 30.0, height = 600, show_collisions = false, show_distances = false))]
    #[allow(clippy::too_many_arguments)]
    fn show(
        &self,
        q: Option<&Bound<'_, PyAny>>,
        motion: Option<&Bound<'_, PyAny>>,
        fps: f64,
        height: u32,
        show_collisions: bool,
        show_distances: bool,
    ) -> PyResult<crate::page::Page> {
        crate::page::Page::new(
            self.viewer(q, None, motion, fps, show_collisions, show_distances)?,
            height,
        )
    }

    /// The arm angle ψ (rad, in [−π, π]) of configuration `q` of a 7R arm with a spherical
    /// shoulder (axes 1–3 meet at S) and a spherical wrist (axes 5–7 meet at W), the iiwa
    /// type: the angle about u = (W − S)/‖W − S‖ from r, axis 1's direction made ⊥ u, to
    /// the elbow's offset from the shoulder–wrist line (ψ = 0: the elbow in the plane of axis
    /// 1 and the line, on axis 1's side; right-handed about u). NaN where undefined (the elbow
    /// on the line); raises `ValueError` for another chain.
    fn arm_angle(&self, q: &Bound<'_, PyAny>) -> PyResult<f64> {
        let a = f64_array(q, "q")?;
        let r = a.readonly();
        self.analytic
            .arm_angle_of(self.kin()?, r.as_slice()?)
            .map_err(service_error)
    }

    /// Every IK solution from the analytic solver: any 6R arm of revolute joints (the special
    /// families in closed form, the others by algebraic elimination) and 7R arms with one
    /// joint locked or at an arm angle. `target` (4, 4) → an array (K, dof), nearest to `seed` first (default: the
    /// midpoint of the limits); raises `ValueError` for a chain without an analytic solver
    /// (naming its family) and for a target out of reach. (N, 4, 4) → a list of N such arrays
    /// (all cores, GIL released; each row as its single call: a row out of reach or bad
    /// raises `BatchError` naming the rows, whose `.result` is the list, empty (0, dof) arrays
    /// at those rows).
    /// 7R arms: `lock` names the joint to lock (name or 0-based index; default: among the
    /// joints leaving the most specialised closed form, the one whose lock reaches the most
    /// random poses), `lock_value` its value (default: the seed's), or `sweep=n` solves at n
    /// values evenly spaced over its limits (the best samples that reach nothing refined
    /// between their neighbours, so that a narrow band of reaching values is not missed).
    /// 7R arms with a spherical shoulder and wrist (the iiwa): `arm_angle=ψ` (or
    /// `lock="arm_angle"` with `lock_value`/`sweep`, default the seed's arm angle) gives the
    /// solutions at arm angle ψ (`Robot.arm_angle`: its definition).
    /// `representatives`: "nearest" (the default: one row per posture, each joint at its 2π
    /// representative nearest the seed), "all" (every representative inside the limits: a UR5
    /// with ±2π limits lists up to 2⁶ rows per posture), "none" (one row per posture, angles
    /// in (−π, π] where the limits allow). `collisions`: "ignore" (the default), "flag" (each
    /// target's answer is `(q, collides)`, `collides` (K,) bool: does that configuration's body
    /// collide, itself or the obstacles, with the SRDF applied), "filter" (the colliding
    /// solutions dropped).
    #[pyo3(signature = (target, seed = None, *, lock = None, lock_value = None, sweep = None, representatives = "nearest", arm_angle = None, collisions = "ignore"))]
    #[allow(clippy::too_many_arguments)]
    fn ik_all<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
        lock: Option<&Bound<'py, PyAny>>,
        lock_value: Option<f64>,
        sweep: Option<usize>,
        representatives: &str,
        arm_angle: Option<f64>,
        collisions: &str,
    ) -> PyResult<Bound<'py, PyAny>> {
        let collisions = word::<Collisions>("collisions", collisions)?;
        // The body, built (once) only when asked.
        let body = match collisions {
            Collisions::Ignore => None,
            _ => Some(self.body_model()?),
        };
        let body = body
            .as_ref()
            .map(|(kin, model)| screwkit_service::body::SolutionBody {
                robot: &self.robot,
                kin,
                model,
                mode: collisions,
            });
        if arm_angle.is_some() && (lock.is_some() || lock_value.is_some()) {
            return Err(PyValueError::new_err(
                "arm_angle: give it alone (it stands for lock=\"arm_angle\", lock_value=ψ)",
            ));
        }
        let lock_value = lock_value.or(arm_angle);
        let reps: screwkit_service::words::RepresentativesChoice =
            screwkit_service::words::parse(representatives)
                .map_err(|e| PyValueError::new_err(format!("representatives: {e}")))?;
        use screwkit_solve::analytic::Solutions;
        let (targets, count) = poses(target, "target")?;
        let seed = match seed {
            Some(s) => {
                let a = f64_array(s, "seed")?;
                a.to_vec()?
            }
            None => self.kin()?.midpoint(),
        };
        self.kin()?.check_q(&seed).map_err(solve_error)?;
        let joint = match lock {
            None if arm_angle.is_some() => {
                Some(JointRef::Name(screwkit_service::joint::ARM_ANGLE.into()))
            }
            None => None,
            Some(j) => Some(joint_ref(j, "lock")?),
        };
        let all = AllSolutions::with_solvers(
            self.kin()?,
            joint.as_ref(),
            lock_value,
            sweep,
            &self.analytic,
        )
        .map_err(service_error)?
        .with_representatives(reps)
        .with_interrupt(screwkit_solve::ik::Interrupt(pool::cancelled));
        let n = self.kin()?.dof();
        // A target's answer: its solutions (K, dof), filtered, or with their flags.
        let to_array = |py: Python<'py>, sols: &Solutions| -> PyResult<Bound<'py, PyAny>> {
            let mut sols = sols.clone();
            let flags = match &body {
                Some(b) => b.apply(&mut sols).map_err(service_error)?,
                None => None,
            };
            let q = new_array(py, &[sols.len(), n], |o| {
                for (row, q) in o.chunks_mut(n.max(1)).zip(sols.iter()) {
                    row.copy_from_slice(q);
                }
            })?
            .into_any();
            Ok(match flags {
                Some(f) => (q, numpy::PyArray1::from_vec(py, f))
                    .into_pyobject(py)?
                    .into_any(),
                None => q,
            })
        };
        let tv = targets.readonly();
        let flat = tv.as_slice()?;
        if count.is_none() {
            let t = target::from_row_major(flat).map_err(bad_target)?;
            let kin = self.kin()?;
            let (sols, _) = if sweep.is_some() {
                // A sweep takes milliseconds to seconds: off the main thread, which runs
                // Python's signal handlers meanwhile (Ctrl-C stops it: KeyboardInterrupt).
                pool::cancellable(py, || {
                    let mut ws = Workspace::new(kin);
                    all.solve(kin, &mut ws, &t, &seed)
                })?
            } else {
                // One closed form (microseconds): on this thread.
                let mut ws = self.workspace()?;
                all.solve(kin, &mut ws, &t, &seed)
            }
            .map_err(solve_error)?;
            if !sols.is_exact() {
                return Err(PyValueError::new_err(format!("target: {OUT_OF_REACH}")));
            }
            return to_array(py, &sols);
        }
        let kin = self.kin()?;
        let results =
            pool::cancellable(py, || all.solve_batch(kin, flat, &seed))?.map_err(solve_error)?;
        let list = pyo3::types::PyList::empty(py);
        let mut bad = Vec::new();
        // A failed row's answer: no solution (with no flags).
        let empty = |py: Python<'py>| -> PyResult<Bound<'py, PyAny>> {
            let q = zeros(py, &[0, n])?;
            Ok(match collisions {
                Collisions::Flag => (q, numpy::PyArray1::<bool>::zeros(py, 0, false))
                    .into_pyobject(py)?
                    .into_any(),
                _ => q.into_any(),
            })
        };
        for (k, r) in results.into_iter().enumerate() {
            match r {
                Ok((sols, _)) if sols.is_exact() => list.append(to_array(py, &sols)?)?,
                // As the single call: out of reach is this row's error.
                Ok(_) => {
                    list.append(empty(py)?)?;
                    bad.push(screwkit_solve::RowError {
                        row: k,
                        error: screwkit_solve::SolveError::InvalidInput(OUT_OF_REACH.into()),
                    });
                }
                Err(error) => {
                    list.append(empty(py)?)?;
                    bad.push(screwkit_solve::RowError { row: k, error });
                }
            }
        }
        if bad.is_empty() {
            Ok(list.into_any())
        } else {
            Err(batch_error(
                py,
                screwkit_solve::SolveError::Rows(bad),
                list.into_any(),
            ))
        }
    }

    /// Inverse kinematics: joint values q, within the limits, with T(q) = target.
    ///
    /// `target` (4, 4) → `IkResult`; (N, 4, 4) → `IkBatchResult` (all cores, GIL released;
    /// row k restarts from `row_seed(seed_rng, k)`, so it equals the single call with that
    /// seed, whatever the thread count). `seed`: the start, (dof,) or (N, dof) (default: the
    /// midpoint of the limits). `method`: "lm" (Levenberg–Marquardt), "dls" (damped least
    /// squares), "nr" (Newton–Raphson); `damping`: LM's floor μ̄ or DLS's λ. Converged when the
    /// body twist error has ‖ω‖ ≤ tol_rot (rad) and ‖v‖ ≤ tol_pos (m). Budgets: iterations and
    /// random restarts over all attempts, and `timeout_ms` of wall time per target (None, the
    /// default: no clock, so results are reproducible). Not converging is a result
    /// (converged=False), not an exception. `avoid_collisions`: only answers whose body (the
    /// whole robot, its disabled pairs and obstacles as they are now) keeps every checked pair
    /// at least `margin` metres apart; steps steer away from close pairs, and `stop` says "in
    /// collision" when the budget ends with only colliding answers.
    #[pyo3(signature = (target, seed = None, *, method = "lm", tol_rot = 1e-9, tol_pos = 1e-9,
        position_only = false, timeout_ms = None, seed_rng = 0, max_iterations = 2000,
        max_restarts = 200, damping = None, weights = None, avoid_collisions = false,
        margin = 0.0))]
    #[allow(clippy::too_many_arguments)]
    fn ik<'py>(
        &self,
        py: Python<'py>,
        target: &Bound<'py, PyAny>,
        seed: Option<&Bound<'py, PyAny>>,
        method: &str,
        tol_rot: f64,
        tol_pos: f64,
        position_only: bool,
        timeout_ms: Option<f64>,
        seed_rng: u64,
        max_iterations: usize,
        max_restarts: usize,
        damping: Option<f64>,
        weights: Option<Vec<f64>>,
        avoid_collisions: bool,
        margin: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        // The body kept clear of (its model and tree held for the call).
        let body = self.avoided_body(avoid_collisions, margin)?;
        let clear = self.clearance(body.as_ref(), margin)?;
        let clear = clear.as_ref();
        let opts = self.ik_options(IkArgs {
            method,
            damping,
            tol_rot,
            tol_pos,
            max_iterations,
            max_restarts,
            timeout_ms,
            seed_rng,
            position_only,
            weights,
        })?;
        let n = self.kin()?.dof();
        let (targets, count) = poses(target, "target")?;
        let seed = seed.map(|s| f64_array(s, "seed")).transpose()?;
        let seed_rows = seed.as_ref().map(|s| self.rows_of(s, "seed")).transpose()?;
        let targets = targets.readonly();
        let tv = targets.as_slice()?;
        let seed_ro = seed.as_ref().map(|s| s.readonly());
        let seed_values = seed_ro.as_ref().map(|s| s.as_slice()).transpose()?;
        match count {
            None => {
                if let Some(Rows::Many(_)) = seed_rows {
                    return Err(PyValueError::new_err(format!(
                        "seed: one target takes one seed of shape ({n},)"
                    )));
                }
                let target = target::from_row_major(tv).map_err(bad_target)?;
                let mid = self.kin()?.midpoint();
                let seed = seed_values.unwrap_or(&mid);
                let opts = IkOptions {
                    interrupt: Some(ik::Interrupt(pool::interrupted)),
                    ..opts
                };
                let kin = self.kin()?;
                let r = py
                    .detach(|| {
                        self.workspace().map(|mut ws| match clear {
                            Some(c) => ik::solve_clear(
                                kin,
                                &mut ws,
                                &target,
                                seed,
                                &opts,
                                c,
                                &mut c.scratch(),
                            ),
                            None => ik::solve(kin, &mut ws, &target, seed, &opts),
                        })
                    })?
                    .map_err(solve_error)?;
                pool::take_interrupt(py)?;
                let st = r.status;
                let res = IkResult {
                    q: r.q.to_pyarray(py).unbind(),
                    converged: st.converged,
                    iterations: st.iterations,
                    restarts: st.restarts,
                    error_rot: st.error_rot,
                    error_pos: st.error_pos,
                    stop: st.stop.as_str().to_string(),
                };
                Ok(Bound::new(py, res)?.into_any())
            }
            Some(rows) => {
                // One seed for all targets is repeated; a stack must have one per target.
                let tiled: Option<Vec<f64>> = match (&seed_rows, seed_values) {
                    (Some(Rows::One), Some(s)) => Some(s.repeat(rows)),
                    (Some(Rows::Many(m)), _) if *m != rows => {
                        return Err(PyValueError::new_err(format!(
                            "seed: {m} seeds for {rows} targets (give one seed, or one per target)"
                        )))
                    }
                    _ => None,
                };
                let seeds = tiled.as_deref().or(seed_values);
                let q = zeros(py, &[rows, n])?;
                let mut status = vec![IkStatus::unsolved(); rows];
                let res = {
                    let mut w = q.readwrite();
                    let qo = w.as_slice_mut()?;
                    let st = &mut status;
                    let kin = self.kin()?;
                    if clear.is_none() && rows <= batch::IK_INLINE_ROWS {
                        // A few targets in turn on this thread, in the robot's workspace:
                        // handing them to the pool would cost more than sharing them saves.
                        let mut ws = self.workspace()?;
                        let ws = &mut *ws;
                        py.detach(|| batch::ik_batch_in(kin, ws, 0, tv, seeds, &opts, qo, st, None))
                    } else {
                        // Restart seeds by global row: the same answers whatever the chunking.
                        let piece = |r: std::ops::Range<usize>| {
                            let targets = &tv[16 * r.start..16 * r.end];
                            let seeds = seeds.map(|s| &s[n * r.start..n * r.end]);
                            let (q, st) = (&mut qo[n * r.start..n * r.end], &mut st[r.clone()]);
                            match clear {
                                Some(c) => batch::ik_batch_clear_from(
                                    kin, r.start, targets, seeds, &opts, c, q, st, None,
                                ),
                                None => batch::ik_batch_from(
                                    kin, r.start, targets, seeds, &opts, q, st, None,
                                ),
                            }
                        };
                        pool::chunked(py, rows, IK_CHUNK, batch::IK_INLINE_ROWS, piece)?
                    }
                };
                let result = Bound::new(py, batch_result(q, &status)?)?.into_any();
                res.map_err(|e| batch_error(py, e, result.clone()))?;
                Ok(result)
            }
        }
    }
}
