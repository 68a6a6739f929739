//! `screwkit.trajectory`: the textbook's trajectory functions (*Modern Robotics* ch. 9) with the
//! `modern_robotics` library's arguments, on [`screwkit_lie::trajectory`]; each batched over a
//! leading axis (times, or stacks of starts and ends).

use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use screwkit_lie::trajectory::{self, TimeScaling};
use screwkit_lie::Se3;

use crate::array::{f64_array, new_array, shape_str};

fn lie_error(e: screwkit_lie::LieError) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// `Tf` checked (finite, > 0) for the time scalings.
fn duration(tf: f64) -> PyResult<f64> {
    if tf.is_finite() && tf > 0.0 {
        Ok(tf)
    } else {
        Err(PyValueError::new_err(format!(
            "Tf {tf}: expected a finite duration > 0"
        )))
    }
}

/// s(t) for one t (a float) or any array of them (the same shape).
fn scaling<'py>(
    py: Python<'py>,
    kind: TimeScaling,
    tf: f64,
    t: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let tf = duration(tf)?;
    if let Ok(x) = t.extract::<f64>() {
        return Ok(kind.s(tf, x).into_pyobject(py)?.into_any());
    }
    let a: Bound<'py, PyArrayDyn<f64>> = f64_array(t, "t")?;
    let v = a.to_vec()?;
    Ok(new_array(py, a.shape(), |o| {
        for (o, x) in o.iter_mut().zip(&v) {
            *o = kind.s(tf, *x);
        }
    })?
    .into_any())
}

/// `CubicTimeScaling(Tf, t)`: 3(t/Tf)² − 2(t/Tf)³, for a float t or an array of them.
#[pyfunction]
#[pyo3(name = "tr_cubic_time_scaling", signature = (Tf, t))]
#[allow(non_snake_case)]
pub fn cubic_time_scaling<'py>(
    py: Python<'py>,
    Tf: f64,
    t: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    scaling(py, TimeScaling::Cubic, Tf, t)
}

/// `QuinticTimeScaling(Tf, t)`: 10(t/Tf)³ − 15(t/Tf)⁴ + 6(t/Tf)⁵, for a float t or an array.
#[pyfunction]
#[pyo3(name = "tr_quintic_time_scaling", signature = (Tf, t))]
#[allow(non_snake_case)]
pub fn quintic_time_scaling<'py>(
    py: Python<'py>,
    Tf: f64,
    t: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    scaling(py, TimeScaling::Quintic, Tf, t)
}

/// N ≥ 2 as a count.
fn count(n: i64) -> PyResult<usize> {
    if (2..=10_000_000).contains(&n) {
        Ok(n as usize)
    } else {
        Err(PyValueError::new_err(format!(
            "N {n}: expected 2 to 10,000,000 samples (the start and the end at least)"
        )))
    }
}

/// `JointTrajectory(thetastart, thetaend, Tf, N, method)`: (N, n) joint values, the first row
/// thetastart and the last thetaend; thetastart and thetaend (B, n) give (B, N, n).
#[pyfunction]
#[pyo3(name = "tr_joint_trajectory", signature = (thetastart, thetaend, Tf, N, method))]
#[allow(non_snake_case)]
pub fn joint_trajectory<'py>(
    py: Python<'py>,
    thetastart: &Bound<'py, PyAny>,
    thetaend: &Bound<'py, PyAny>,
    Tf: f64,
    N: i64,
    method: i64,
) -> PyResult<Bound<'py, PyAny>> {
    let kind = TimeScaling::from_method(method).map_err(lie_error)?;
    let n = count(N)?;
    let a: Bound<'py, PyArrayDyn<f64>> = f64_array(thetastart, "thetastart")?;
    let b: Bound<'py, PyArrayDyn<f64>> = f64_array(thetaend, "thetaend")?;
    if a.shape() != b.shape() || !(1..=2).contains(&a.ndim()) {
        return Err(PyValueError::new_err(format!(
            "thetastart {} and thetaend {}: expected the same shape, (n,) or (B, n)",
            shape_str(a.shape()),
            shape_str(b.shape())
        )));
    }
    let dof = *a.shape().last().unwrap_or(&0);
    let rows = if a.ndim() == 2 { a.shape()[0] } else { 1 };
    let (start, end) = (a.to_vec()?, b.to_vec()?);
    let mut out = vec![0.0; rows * n * dof];
    for r in 0..rows {
        let (s, e) = (&start[r * dof..(r + 1) * dof], &end[r * dof..(r + 1) * dof]);
        trajectory::joint_trajectory(s, e, Tf, n, kind, &mut out[r * n * dof..(r + 1) * n * dof])
            .map_err(|e| {
            let at = if a.ndim() == 2 {
                format!("row {r}: ")
            } else {
                String::new()
            };
            PyValueError::new_err(format!("{at}{e}"))
        })?;
    }
    let shape: Vec<usize> = if a.ndim() == 2 {
        vec![rows, n, dof]
    } else {
        vec![n, dof]
    };
    Ok(new_array(py, &shape, |o| o.copy_from_slice(&out))?.into_any())
}

/// A pose trajectory of the library (start, end, Tf, N, time scaling).
type PosePath = fn(&Se3, &Se3, f64, usize, TimeScaling) -> Result<Vec<Se3>, screwkit_lie::LieError>;

/// The pose trajectories: (N, 4, 4) from (4, 4) starts and ends, (B, N, 4, 4) from (B, 4, 4).
#[allow(clippy::too_many_arguments)]
fn poses<'py>(
    py: Python<'py>,
    xstart: &Bound<'py, PyAny>,
    xend: &Bound<'py, PyAny>,
    tf: f64,
    n: i64,
    method: i64,
    path: PosePath,
) -> PyResult<Bound<'py, PyAny>> {
    let kind = TimeScaling::from_method(method).map_err(lie_error)?;
    let n = count(n)?;
    let a: Bound<'py, PyArrayDyn<f64>> = f64_array(xstart, "Xstart")?;
    let b: Bound<'py, PyArrayDyn<f64>> = f64_array(xend, "Xend")?;
    let batch = a.ndim() == 3;
    if a.shape() != b.shape() || a.shape()[a.ndim().saturating_sub(2)..] != [4, 4] || a.ndim() > 3 {
        return Err(PyValueError::new_err(format!(
            "Xstart {} and Xend {}: expected the same shape, (4, 4) or (B, 4, 4)",
            shape_str(a.shape()),
            shape_str(b.shape())
        )));
    }
    let rows = if batch { a.shape()[0] } else { 1 };
    let (start, end) = (a.to_vec()?, b.to_vec()?);
    let mut out = vec![0.0; rows * n * 16];
    for r in 0..rows {
        let at = |what: &str, e: screwkit_lie::LieError| {
            let row = if batch {
                format!("[{r}]")
            } else {
                String::new()
            };
            PyValueError::new_err(format!("{what}{row}: {e}"))
        };
        let x0 =
            Se3::from_row_major(&start[r * 16..(r + 1) * 16], 1e-6).map_err(|e| at("Xstart", e))?;
        let x1 =
            Se3::from_row_major(&end[r * 16..(r + 1) * 16], 1e-6).map_err(|e| at("Xend", e))?;
        let samples = path(&x0, &x1, tf, n, kind).map_err(lie_error)?;
        for (i, x) in samples.iter().enumerate() {
            x.write_row_major(&mut out[(r * n + i) * 16..(r * n + i + 1) * 16]);
        }
    }
    let shape: Vec<usize> = if batch {
        vec![rows, n, 4, 4]
    } else {
        vec![n, 4, 4]
    };
    Ok(new_array(py, &shape, |o| o.copy_from_slice(&out))?.into_any())
}

/// `ScrewTrajectory(Xstart, Xend, Tf, N, method)`: (N, 4, 4), the constant screw motion
/// Xstart exp(log(Xstart⁻¹ Xend) s(t)).
#[pyfunction]
#[pyo3(name = "tr_screw_trajectory", signature = (Xstart, Xend, Tf, N, method))]
#[allow(non_snake_case)]
pub fn screw_trajectory<'py>(
    py: Python<'py>,
    Xstart: &Bound<'py, PyAny>,
    Xend: &Bound<'py, PyAny>,
    Tf: f64,
    N: i64,
    method: i64,
) -> PyResult<Bound<'py, PyAny>> {
    poses(
        py,
        Xstart,
        Xend,
        Tf,
        N,
        method,
        trajectory::screw_trajectory,
    )
}

/// `CartesianTrajectory(Xstart, Xend, Tf, N, method)`: (N, 4, 4), the origin on the straight
/// line and the rotation Rstart exp(log(Rstartᵀ Rend) s(t)), decoupled.
#[pyfunction]
#[pyo3(name = "tr_cartesian_trajectory", signature = (Xstart, Xend, Tf, N, method))]
#[allow(non_snake_case)]
pub fn cartesian_trajectory<'py>(
    py: Python<'py>,
    Xstart: &Bound<'py, PyAny>,
    Xend: &Bound<'py, PyAny>,
    Tf: f64,
    N: i64,
    method: i64,
) -> PyResult<Bound<'py, PyAny>> {
    poses(
        py,
        Xstart,
        Xend,
        Tf,
        N,
        method,
        trajectory::cartesian_trajectory,
    )
}

/// Adds the functions to the native module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cubic_time_scaling, m)?)?;
    m.add_function(wrap_pyfunction!(quintic_time_scaling, m)?)?;
    m.add_function(wrap_pyfunction!(joint_trajectory, m)?)?;
    m.add_function(wrap_pyfunction!(screw_trajectory, m)?)?;
    m.add_function(wrap_pyfunction!(cartesian_trajectory, m)?)?;
    m.add_function(wrap_pyfunction!(time_parameterize, m)?)?;
    m.add_class::<TimedPath>()?;
    Ok(())
}

/// A joint path timed time-optimally (`screwkit.time_parameterize`): its duration, and q, q̇,
/// q̈ at any times.
#[pyclass(frozen, skip_from_py_object, module = "screwkit")]
pub struct TimedPath {
    inner: screwkit_solve::timing::Timing,
}

impl TimedPath {
    /// (q, q̇, q̈) at each time of `t` (a float: (n,) each; an array of M: (M, n) each).
    fn states<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyAny>,
    ) -> PyResult<[Bound<'py, PyAny>; 3]> {
        let n = self.inner.joints();
        let (times, single): (Vec<f64>, bool) = match t.extract::<f64>() {
            Ok(x) => (vec![x], true),
            Err(_) => {
                let a: Bound<'py, PyArrayDyn<f64>> = f64_array(t, "t")?;
                if a.ndim() != 1 {
                    return Err(PyValueError::new_err(format!(
                        "t: expected a float or a 1-D array, got shape {}",
                        shape_str(a.shape())
                    )));
                }
                (a.to_vec()?, false)
            }
        };
        if let Some(x) = times.iter().find(|x| !x.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "t: {x} is not a finite time"
            )));
        }
        let rows = times.len();
        let (mut q, mut qd, mut qdd) = (
            vec![0.0; rows * n],
            vec![0.0; rows * n],
            vec![0.0; rows * n],
        );
        for (k, t) in times.iter().enumerate() {
            let r = k * n..(k + 1) * n;
            let (a, b, c) = (&mut q[r.clone()], &mut qd[r.clone()], &mut qdd[r]);
            self.inner.sample(*t, a, b, c);
        }
        let shape: Vec<usize> = if single { vec![n] } else { vec![rows, n] };
        let out = |v: &[f64]| -> PyResult<Bound<'py, PyAny>> {
            Ok(new_array(py, &shape, |o| o.copy_from_slice(v))?.into_any())
        };
        Ok([out(&q)?, out(&qd)?, out(&qdd)?])
    }
}

#[pymethods]
impl TimedPath {
    /// The duration (s).
    #[getter]
    fn duration(&self) -> f64 {
        self.inner.duration()
    }

    /// The grid points' times (N + 1,).
    #[getter]
    fn grid_times<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let t = self.inner.grid_times();
        Ok(new_array(py, &[t.len()], |o| o.copy_from_slice(t))?.into_any())
    }

    /// The velocity and acceleration limits used ((n,) each): the given ones, or tightened
    /// where sampling between the grid points found them exceeded.
    #[getter]
    fn limits<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let (v, a) = self.inner.limits();
        Ok((
            new_array(py, &[v.len()], |o| o.copy_from_slice(v))?.into_any(),
            new_array(py, &[a.len()], |o| o.copy_from_slice(a))?.into_any(),
        ))
    }

    /// The positions q at time(s) t (clamped to [0, duration]): (n,) for a float, (M, n) for
    /// an array of M times.
    fn __call__<'py>(&self, py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
        let [q, _, _] = self.states(py, t)?;
        Ok(q)
    }

    /// (q, q̇, q̈) at time(s) t, as `__call__` shapes them.
    fn sample<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyAny>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let [q, qd, qdd] = self.states(py, t)?;
        Ok((q, qd, qdd))
    }

    fn __repr__(&self) -> String {
        format!(
            "TimedPath(duration={:.6} s, joints={}, grid={})",
            self.inner.duration(),
            self.inner.joints(),
            self.inner.grid_times().len() - 1
        )
    }
}

/// The time-optimal timing of the joint path through `path` (m, n) (m ≥ 2 waypoints, joined
/// by a not-a-knot cubic spline over s = 0 … 1 as toppra's `SplineInterpolator` joins them),
/// within |q̇_j| ≤ `vel_limits[j]` and |q̈_j| ≤ `acc_limits[j]`, at rest at both ends, by
/// TOPP-RA on `grid` intervals (default 40 per waypoint interval, at least 1,000); sampled
/// every `check` seconds and tightened until no sample exceeds a limit.
#[pyfunction]
#[pyo3(signature = (path, vel_limits, acc_limits, *, grid = None, check = 0.001))]
pub fn time_parameterize(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    vel_limits: &Bound<'_, PyAny>,
    acc_limits: &Bound<'_, PyAny>,
    grid: Option<usize>,
    check: f64,
) -> PyResult<TimedPath> {
    let p: Bound<'_, PyArrayDyn<f64>> = f64_array(path, "path")?;
    let [_, n] = p.shape() else {
        return Err(PyValueError::new_err(format!(
            "path: expected shape (m, n), waypoints by joints, got {}",
            shape_str(p.shape())
        )));
    };
    let n = *n;
    let limits = |x: &Bound<'_, PyAny>, what: &str| -> PyResult<Vec<f64>> {
        let a: Bound<'_, PyArrayDyn<f64>> = f64_array(x, what)?;
        if a.shape() != [n] {
            return Err(PyValueError::new_err(format!(
                "{what}: expected shape ({n},), got {}",
                shape_str(a.shape())
            )));
        }
        Ok(a.to_vec()?)
    };
    let (v, a) = (
        limits(vel_limits, "vel_limits")?,
        limits(acc_limits, "acc_limits")?,
    );
    let points = p.to_vec()?;
    let options = screwkit_solve::timing::TimingOptions { grid, check };
    let inner = py
        .detach(|| screwkit_solve::timing::time_parameterize(&points, n, &v, &a, &options))
        .map_err(crate::errors::solve_error)?;
    Ok(TimedPath { inner })
}
