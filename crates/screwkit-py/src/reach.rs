//! Reachability maps from Python: `screwkit_reach`'s build, merge and slices, the GIL
//! released while a map is computed (on the pool of `screwkit.set_num_threads`).

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use screwkit_reach::{Plan, ReachError, ReachSpec, Shard};
use screwkit_service::report::MapReport;
use screwkit_service::words::{OrientationMode, SolverChoice};

use crate::pool;
use crate::robot::{word, Robot};

fn reach_error(e: ReachError) -> PyErr {
    match e {
        ReachError::File(f) => crate::errors::file_error(f),
        e => PyValueError::new_err(e.to_string()),
    }
}

/// A report of the floor as a Python dict (its JSON, read by `json.loads`: the same field names
/// as the CLI's `--format json`).
pub(crate) fn report_dict<'py>(
    py: Python<'py>,
    report: &impl serde::Serialize,
) -> PyResult<Bound<'py, PyAny>> {
    let text = screwkit_service::report::to_value(report).to_string();
    py.import("json")?.call_method1("loads", (text,))
}

/// Builds shard `shard_index` of `shard_count` of the map of `robot` into the .npz `path`;
/// returns its report as a dict (the fields of `screwkit reach --format json`).
#[pyfunction]
#[pyo3(signature = (robot, path, *, resolution, orientations, mode, bounds, solver, seed, restarts, iterations, shard_index, shard_count, collision_margin = None, obstacles = None))]
#[allow(clippy::too_many_arguments)]
pub fn reach_build<'py>(
    py: Python<'py>,
    robot: &Robot,
    path: String,
    resolution: f64,
    orientations: usize,
    mode: &str,
    bounds: Option<[f64; 6]>,
    solver: &str,
    seed: u64,
    restarts: usize,
    iterations: usize,
    shard_index: usize,
    shard_count: usize,
    collision_margin: Option<f64>,
    obstacles: Option<std::path::PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let spec = ReachSpec {
        resolution,
        orientations,
        mode: word::<OrientationMode>("mode", mode)?,
        bounds: bounds.map(|b| ([b[0], b[1], b[2]], [b[3], b[4], b[5]])),
        solver: word::<SolverChoice>("solver", solver)?,
        seed,
        restarts,
        iterations,
        collision_margin,
    };
    let shard = Shard::new(shard_index, shard_count).map_err(crate::errors::service_error)?;
    let (chain, kin) = robot.parts()?;
    let plan = Plan::new(chain, kin, &spec).map_err(reach_error)?;
    if collision_margin.is_none() && obstacles.is_some() {
        return Err(PyValueError::new_err(
            "obstacles apply with avoid_collisions=True",
        ));
    }
    // The body (read before the map is computed), when the map keeps clear of it.
    let body = collision_margin
        .map(|_| robot.body_with_scene(obstacles.as_deref()))
        .transpose()?;
    let started = std::time::Instant::now();
    let s = py
        .detach(|| {
            pool::run(|| match &body {
                Some((tree, model)) => screwkit_reach::build_clear(
                    &plan,
                    kin,
                    screwkit_reach::Body {
                        robot: robot.service(),
                        tree,
                        model,
                    },
                    shard,
                    &path,
                    |_, _| {},
                ),
                None => screwkit_reach::build(&plan, kin, shard, &path, |_, _| {}),
            })
        })?
        .map_err(reach_error)?;
    report_dict(
        py,
        &MapReport::built(
            (s.voxels, s.poses, s.solved, s.reached),
            started.elapsed().as_secs_f64(),
            pool::num_threads()?,
            plan.solver_name(),
        )
        .with_lost_to_collisions(collision_margin.map(|_| s.collided)),
    )
}

/// Joins shard files into the map `path` (the file the unsharded build writes).
#[pyfunction]
pub fn reach_merge<'py>(
    py: Python<'py>,
    shards: Vec<String>,
    path: String,
) -> PyResult<Bound<'py, PyAny>> {
    let started = std::time::Instant::now();
    let s = py
        .detach(|| screwkit_reach::merge(&shards, &path))
        .map_err(reach_error)?;
    report_dict(
        py,
        &MapReport::merged(
            (s.voxels, s.poses, s.reached),
            started.elapsed().as_secs_f64(),
            shards.len(),
        ),
    )
}

/// The SVG slices through the base of the (whole) map `path`.
#[pyfunction]
pub fn reach_svg(path: String) -> PyResult<String> {
    let m = screwkit_reach::read(&path).map_err(reach_error)?;
    if m.voxels.len() != m.grid.len() {
        return Err(PyValueError::new_err(format!(
            "{path} is a shard: draw the merged map"
        )));
    }
    Ok(screwkit_reach::slices::svg(&m))
}
