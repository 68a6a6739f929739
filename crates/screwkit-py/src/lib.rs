//! The `screwkit` Python package's native module (`screwkit._screwkit`): pyo3 bindings of the
//! screwkit library. Everything here converts arguments and results and maps errors; the
//! kinematics, batching and threading are the library's (`screwkit-solve`).
//!
//! Single calls hold the GIL (they take well under a microsecond, less than releasing it
//! would cost), except IK; batch calls and IK release it and run on the pool of [`pool`].

mod array;
mod body;
mod dynamics;
mod errors;
mod lie;
mod page;
mod pool;
mod reach;
mod results;
mod robot;
mod tasks;
mod trajectory;

use numpy::{PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use screwkit_lie::{so3::DEFAULT_ROTATION_TOLERANCE, Se3};

use array::{f64_array, shape_str};

/// A rigid transform from a (4, 4) array-like (rotation orthonormal to 1e-6, then projected).
pub(crate) fn se3_arg(t: &Bound<'_, PyAny>, what: &str) -> PyResult<Se3> {
    let a = f64_array(t, what)?;
    if a.shape() != [4, 4] {
        return Err(PyValueError::new_err(format!(
            "{what}: expected shape (4, 4), got {}",
            shape_str(a.shape())
        )));
    }
    let r = a.readonly();
    Se3::from_row_major(r.as_slice()?, DEFAULT_ROTATION_TOLERANCE)
        .map_err(|e| PyValueError::new_err(format!("{what}: not a rigid transform: {e}")))
}

/// The restart seed IK row k of a batch uses: batch row k with `seed_rng=s` equals the single
/// call with `seed_rng=row_seed(s, k)`.
#[pyfunction]
fn row_seed(seed: u64, k: usize) -> u64 {
    screwkit_solve::batch::row_seed(seed, k)
}

/// The kernel path the hot kernels take on this CPU, chosen at run time: "avx512" (the batch
/// kernels on 512-bit registers, the single calls fused), "avx2+fma" or "portable" — for
/// benchmarks to say where they ran.
#[pyfunction]
fn kernel_path() -> &'static str {
    screwkit_lie::fma::kernel_path()
}

/// Expands a xacro file into URDF text natively (no ROS): `package_paths` for `$(find pkg)`
/// (searched before ROS_PACKAGE_PATH and AMENT_PREFIX_PATH), `args` for `xacro:arg`.
#[pyfunction]
#[pyo3(signature = (path, package_paths = None, args = None))]
fn xacro(
    path: std::path::PathBuf,
    package_paths: Option<Vec<std::path::PathBuf>>,
    args: Option<std::collections::BTreeMap<String, String>>,
) -> PyResult<String> {
    let opts = robot::xacro_options(package_paths, args);
    screwkit_service::Source::Path(path)
        .expand_xacro(&opts)
        .map_err(errors::service_error)
}

/// The one set of defaults (the floor's), for the suite that checks the signatures and the
/// stubs against it: {"ik": {keyword: value}, "reach": {keyword: value}, "tasks": {type:
/// {field: value}}, …}.
#[pyfunction]
fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyAny>> {
    use screwkit_service::words::Word;
    let ik = screwkit_service::IkSettings::default();
    let m = screwkit_service::ReachSpec::default();
    let wb = screwkit_solve::tree::differential_ik::TasksOptions::default();
    let limits = screwkit_solve::tree::differential_ik::Limits::default();
    let d = serde_json::json!({
        "ik": {
            "method": ik.method.as_str(), "tol_rot": ik.tol_rot, "tol_pos": ik.tol_pos,
            "position_only": ik.position_only,
            // Python's None is the floor's 0 ms: no time budget.
            "timeout_ms": (ik.timeout_ms != 0.0).then_some(ik.timeout_ms),
            "seed_rng": ik.seed, "max_iterations": ik.max_iterations,
            "max_restarts": ik.max_restarts, "damping": ik.damping,
        },
        "ik_tasks": {
            "max_iterations": wb.max_iterations, "restarts": wb.restarts, "seed_rng": wb.seed,
            "position_limits": wb.position_limits,
        },
        "ik_step": {
            "position_limits": limits.position, "velocity_limits": limits.velocity,
        },
        // Every task type's defaults, by its JSON word (the floor's one home of them).
        "tasks": screwkit_service::tasks::TaskType::ALL
            .iter()
            .map(|t| (t.name(), t.defaults()))
            .collect::<std::collections::BTreeMap<_, _>>(),
        // The body's SRDF generation (Robot.write_srdf, screwkit srdf).
        "write_srdf": {
            "samples": screwkit_collision::acm::Generate::default().samples,
            "seed": screwkit_collision::acm::Generate::default().seed,
            "never": screwkit_collision::acm::Generate::default().never,
        },
        "viewer": {"fps": screwkit_draw::html::DEFAULT_FPS},
        "reach": {
            "resolution": m.resolution, "orientations": m.orientations,
            "mode": m.mode.as_str(), "solver": m.solver.as_str(), "seed": m.seed,
            "restarts": m.restarts, "iterations": m.iterations,
        },
    });
    reach::report_dict(py, &d)
}

/// Every option word family and its words (the floor's), for the suite that checks the stubs'
/// `Literal` types against them.
#[pyfunction]
fn words(py: Python<'_>) -> PyResult<Bound<'_, pyo3::types::PyDict>> {
    use screwkit_service::words::{self as w, Word};
    fn all<W: Word>() -> Vec<&'static str> {
        W::ALL
            .iter()
            .flat_map(|x| std::iter::once(x.as_str()).chain(x.aliases().iter().copied()))
            .collect()
    }
    let d = pyo3::types::PyDict::new(py);
    d.set_item("method", all::<w::Method>())?;
    d.set_item("screw_frame", all::<w::ScrewFrame>())?;
    d.set_item("jacobian_frame", all::<w::JacobianFrame>())?;
    d.set_item("table_frames", all::<w::TableFrames>())?;
    d.set_item("table_format", all::<w::TableFormat>())?;
    d.set_item("views", all::<w::Views>())?;
    d.set_item("labels", all::<w::Labels>())?;
    d.set_item("orientation_mode", all::<w::OrientationMode>())?;
    d.set_item("solver_choice", all::<w::SolverChoice>())?;
    d.set_item("geometry", all::<w::GeometryRoles>())?;
    d.set_item("meshes", all::<w::Meshes>())?;
    d.set_item("collisions", all::<w::Collisions>())?;
    d.set_item("inertias", all::<w::Inertias>())?;
    d.set_item("interpolation", all::<w::Interpolation>())?;
    Ok(d)
}

/// The native module.
#[pymodule]
fn _screwkit(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<robot::Robot>()?;
    m.add_class::<results::CartesianPath>()?;
    m.add_class::<page::Page>()?;
    m.add_class::<body::Distances>()?;
    m.add_class::<body::Box_>()?;
    m.add_class::<body::CollisionAvoidance>()?;
    m.add_class::<body::Sphere>()?;
    m.add_class::<body::Capsule>()?;
    m.add_class::<body::Cylinder>()?;
    m.add_class::<body::Mesh>()?;
    m.add_class::<results::IkResult>()?;
    m.add_class::<results::IkBatchResult>()?;
    m.add_class::<results::Analysis>()?;
    m.add_class::<tasks::FrameTask>()?;
    m.add_class::<tasks::RelativeFrameTask>()?;
    m.add_class::<tasks::AxisTask>()?;
    m.add_class::<tasks::ComTask>()?;
    m.add_class::<tasks::PostureTask>()?;
    m.add_class::<tasks::DampingTask>()?;
    m.add_class::<tasks::TaskSet>()?;
    m.add_class::<tasks::TasksResult>()?;
    m.add("BatchError", m.py().get_type::<errors::BatchError>())?;
    lie::register(m)?;
    dynamics::register(m)?;
    trajectory::register(m)?;
    // The names the package had before `screwkit.lie`: the same functions.
    m.add("exp", m.getattr("exp6")?)?;
    m.add("log", m.getattr("log6")?)?;
    m.add_function(wrap_pyfunction!(row_seed, m)?)?;
    m.add_function(wrap_pyfunction!(kernel_path, m)?)?;
    m.add_function(wrap_pyfunction!(xacro, m)?)?;
    // Plumbing of the Python layer, not public API: set as attributes (not in `__all__`).
    m.setattr("_reach_build", wrap_pyfunction!(reach::reach_build, m)?)?;
    m.setattr("_reach_merge", wrap_pyfunction!(reach::reach_merge, m)?)?;
    m.setattr("_reach_svg", wrap_pyfunction!(reach::reach_svg, m)?)?;
    m.setattr("_defaults", wrap_pyfunction!(defaults, m)?)?;
    m.setattr("_words", wrap_pyfunction!(words, m)?)?;
    m.add_function(wrap_pyfunction!(pool::set_num_threads, m)?)?;
    m.add_function(wrap_pyfunction!(pool::num_threads, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
