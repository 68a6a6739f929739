//! `screwkit.dynamics`: the textbook's dynamics functions (*Modern Robotics* §8.3–8.5) for an
//! open chain given by its lists (Mlist, Glist, Slist), with the `modern_robotics` library's
//! arguments, on `screwkit_solve::tree::dynamics` ([`Dynamics::from_screws`]).

use nalgebra::{Matrix6, Vector3};
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use screwkit_lie::{Se3, Twist};
use screwkit_solve::tree::dynamics::{self, Dynamics, DynamicsWorkspace};

use crate::array::{f64_array, new_array, shape_str};
use crate::errors::solve_error;

/// An argument as a flat float64 vector of `shape` (its name in the message).
fn values(x: &Bound<'_, PyAny>, what: &str, shape: &[usize]) -> PyResult<Vec<f64>> {
    let a: Bound<'_, PyArrayDyn<f64>> = f64_array(x, what)?;
    if a.shape() != shape {
        return Err(PyValueError::new_err(format!(
            "{what}: expected shape {}, got {}",
            shape_str(shape),
            shape_str(a.shape())
        )));
    }
    let r = a.readonly();
    let v = r.as_slice()?.to_vec();
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "{what}: entry {i} is {}, not a finite number",
            v[i]
        )));
    }
    Ok(v)
}

/// The chain of the lists: n from Slist (6, n); Mlist (n + 1, 4, 4), Glist (n, 6, 6); gravity g.
fn chain(
    m_list: &Bound<'_, PyAny>,
    g_list: &Bound<'_, PyAny>,
    s_list: &Bound<'_, PyAny>,
    g: Option<&Bound<'_, PyAny>>,
) -> PyResult<Dynamics> {
    let s: Bound<'_, PyArrayDyn<f64>> = f64_array(s_list, "Slist")?;
    let n = match s.shape() {
        [6, n] => *n,
        other => {
            return Err(PyValueError::new_err(format!(
                "Slist: expected shape (6, n), one screw axis per column, got {}",
                shape_str(other)
            )))
        }
    };
    let s = values(s_list, "Slist", &[6, n])?;
    let m = values(m_list, "Mlist", &[n + 1, 4, 4])?;
    let gl = values(g_list, "Glist", &[n, 6, 6])?;
    let screws: Vec<Twist> = (0..n)
        .map(|j| {
            let c = |r: usize| s[r * n + j];
            Twist::new(
                Vector3::new(c(0), c(1), c(2)),
                Vector3::new(c(3), c(4), c(5)),
            )
        })
        .collect();
    let transforms = m
        .chunks(16)
        .enumerate()
        .map(|(i, t)| {
            Se3::from_row_major(t, 1e-6)
                .map_err(|e| PyValueError::new_err(format!("Mlist[{i}]: {e}")))
        })
        .collect::<PyResult<Vec<_>>>()?;
    let inertias: Vec<Matrix6<f64>> = gl.chunks(36).map(Matrix6::from_row_slice).collect();
    let d = Dynamics::from_screws(&transforms, &inertias, &screws).map_err(solve_error)?;
    Ok(match g {
        Some(g) => {
            let g = values(g, "g", &[3])?;
            d.with_gravity(Vector3::new(g[0], g[1], g[2]))
        }
        None => d.with_gravity(Vector3::zeros()),
    })
}

fn tip(x: Option<&Bound<'_, PyAny>>) -> PyResult<[f64; 6]> {
    let mut out = [0.0; 6];
    if let Some(x) = x {
        out.copy_from_slice(&values(x, "Ftip", &[6])?);
    }
    Ok(out)
}

fn vector<'py>(py: Python<'py>, x: &[f64]) -> PyResult<Bound<'py, PyAny>> {
    Ok(new_array(py, &[x.len()], |o| o.copy_from_slice(x))?.into_any())
}

/// The joint forces τ (n) for the motion (θ, θ̇, θ̈) under gravity g with the end effector
/// exerting Ftip = (m, f) in frame {n+1}: recursive Newton–Euler (MR `InverseDynamics`).
#[pyfunction]
#[pyo3(name = "mr_inverse_dynamics")]
#[allow(clippy::too_many_arguments)]
pub fn inverse_dynamics<'py>(
    py: Python<'py>,
    thetalist: &Bound<'py, PyAny>,
    dthetalist: &Bound<'py, PyAny>,
    ddthetalist: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
    ftip: &Bound<'py, PyAny>,
    mlist: &Bound<'py, PyAny>,
    glist: &Bound<'py, PyAny>,
    slist: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = chain(mlist, glist, slist, Some(g))?;
    let n = d.nv();
    let q = values(thetalist, "thetalist", &[n])?;
    let v = values(dthetalist, "dthetalist", &[n])?;
    let a = values(ddthetalist, "ddthetalist", &[n])?;
    let mut ws = DynamicsWorkspace::new(&d);
    let tau = dynamics::inverse_dynamics_tip(&d, &mut ws, &q, &v, &a, &tip(Some(ftip))?)
        .map_err(solve_error)?;
    vector(py, tau)
}

/// The mass matrix M(θ) (n, n) (MR `MassMatrix`).
#[pyfunction]
#[pyo3(name = "mr_mass_matrix")]
pub fn mass_matrix<'py>(
    py: Python<'py>,
    thetalist: &Bound<'py, PyAny>,
    mlist: &Bound<'py, PyAny>,
    glist: &Bound<'py, PyAny>,
    slist: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = chain(mlist, glist, slist, None)?;
    let n = d.nv();
    let q = values(thetalist, "thetalist", &[n])?;
    let mut ws = DynamicsWorkspace::new(&d);
    let m = dynamics::mass_matrix(&d, &mut ws, &q).map_err(solve_error)?;
    Ok(new_array(py, &[n, n], |o| {
        for r in 0..n {
            for c in 0..n {
                o[r * n + c] = m[(r, c)];
            }
        }
    })?
    .into_any())
}

/// The Coriolis and centripetal forces c(θ, θ̇) (n) (MR `VelQuadraticForces`).
#[pyfunction]
#[pyo3(name = "mr_vel_quadratic_forces")]
pub fn vel_quadratic_forces<'py>(
    py: Python<'py>,
    thetalist: &Bound<'py, PyAny>,
    dthetalist: &Bound<'py, PyAny>,
    mlist: &Bound<'py, PyAny>,
    glist: &Bound<'py, PyAny>,
    slist: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = chain(mlist, glist, slist, None)?;
    let n = d.nv();
    let q = values(thetalist, "thetalist", &[n])?;
    let v = values(dthetalist, "dthetalist", &[n])?;
    let mut ws = DynamicsWorkspace::new(&d);
    let c = dynamics::nonlinear_effects(&d, &mut ws, &q, &v).map_err(solve_error)?;
    vector(py, c)
}

/// The gravity forces g(θ) (n) under gravity g (MR `GravityForces`).
#[pyfunction]
#[pyo3(name = "mr_gravity_forces")]
pub fn gravity_forces<'py>(
    py: Python<'py>,
    thetalist: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
    mlist: &Bound<'py, PyAny>,
    glist: &Bound<'py, PyAny>,
    slist: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = chain(mlist, glist, slist, Some(g))?;
    let q = values(thetalist, "thetalist", &[d.nv()])?;
    let mut ws = DynamicsWorkspace::new(&d);
    let out = dynamics::gravity(&d, &mut ws, &q).map_err(solve_error)?;
    vector(py, out)
}

/// The joint forces Jᵀ(θ) Ftip (n) that hold the end effector's wrench Ftip (MR
/// `EndEffectorForces`).
#[pyfunction]
#[pyo3(name = "mr_end_effector_forces")]
pub fn end_effector_forces<'py>(
    py: Python<'py>,
    thetalist: &Bound<'py, PyAny>,
    ftip: &Bound<'py, PyAny>,
    mlist: &Bound<'py, PyAny>,
    glist: &Bound<'py, PyAny>,
    slist: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = chain(mlist, glist, slist, None)?;
    let n = d.nv();
    let q = values(thetalist, "thetalist", &[n])?;
    let zero = vec![0.0; n];
    let mut ws = DynamicsWorkspace::new(&d);
    let out = dynamics::inverse_dynamics_tip(&d, &mut ws, &q, &zero, &zero, &tip(Some(ftip))?)
        .map_err(solve_error)?;
    vector(py, out)
}

/// The joint accelerations θ̈ (n) that τ gives at (θ, θ̇) under gravity g, the end effector
/// exerting Ftip (MR `ForwardDynamics`).
#[pyfunction]
#[pyo3(name = "mr_forward_dynamics")]
#[allow(clippy::too_many_arguments)]
pub fn forward_dynamics<'py>(
    py: Python<'py>,
    thetalist: &Bound<'py, PyAny>,
    dthetalist: &Bound<'py, PyAny>,
    taulist: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
    ftip: &Bound<'py, PyAny>,
    mlist: &Bound<'py, PyAny>,
    glist: &Bound<'py, PyAny>,
    slist: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = chain(mlist, glist, slist, Some(g))?;
    let n = d.nv();
    let q = values(thetalist, "thetalist", &[n])?;
    let v = values(dthetalist, "dthetalist", &[n])?;
    let tau = values(taulist, "taulist", &[n])?;
    let mut ws = DynamicsWorkspace::new(&d);
    let a = dynamics::forward_dynamics_tip(&d, &mut ws, &q, &v, &tau, &tip(Some(ftip))?)
        .map_err(solve_error)?;
    vector(py, a)
}

/// τ along a trajectory (N, n): one row per sample of (θ, θ̇, θ̈) and Ftip (N, 6) (MR
/// `InverseDynamicsTrajectory`).
#[pyfunction]
#[pyo3(name = "mr_inverse_dynamics_trajectory")]
#[allow(clippy::too_many_arguments)]
pub fn inverse_dynamics_trajectory<'py>(
    py: Python<'py>,
    thetamat: &Bound<'py, PyAny>,
    dthetamat: &Bound<'py, PyAny>,
    ddthetamat: &Bound<'py, PyAny>,
    g: &Bound<'py, PyAny>,
    ftipmat: &Bound<'py, PyAny>,
    mlist: &Bound<'py, PyAny>,
    glist: &Bound<'py, PyAny>,
    slist: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let d = chain(mlist, glist, slist, Some(g))?;
    let n = d.nv();
    let rows = f64_array(thetamat, "thetamat")?
        .shape()
        .first()
        .copied()
        .unwrap_or(0);
    let q = values(thetamat, "thetamat", &[rows, n])?;
    let v = values(dthetamat, "dthetamat", &[rows, n])?;
    let a = values(ddthetamat, "ddthetamat", &[rows, n])?;
    let f = values(ftipmat, "Ftipmat", &[rows, 6])?;
    let mut ws = DynamicsWorkspace::new(&d);
    let mut out = vec![0.0; rows * n];
    for r in 0..rows {
        let span = r * n..(r + 1) * n;
        let mut w = [0.0; 6];
        w.copy_from_slice(&f[r * 6..(r + 1) * 6]);
        let tau = dynamics::inverse_dynamics_tip(
            &d,
            &mut ws,
            &q[span.clone()],
            &v[span.clone()],
            &a[span.clone()],
            &w,
        )
        .map_err(|e| PyValueError::new_err(format!("row {r}: {e}")))?;
        out[span].copy_from_slice(tau);
    }
    Ok(new_array(py, &[rows, n], |o| o.copy_from_slice(&out))?.into_any())
}

/// Adds the functions to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(inverse_dynamics, m)?)?;
    m.add_function(wrap_pyfunction!(mass_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(vel_quadratic_forces, m)?)?;
    m.add_function(wrap_pyfunction!(gravity_forces, m)?)?;
    m.add_function(wrap_pyfunction!(end_effector_forces, m)?)?;
    m.add_function(wrap_pyfunction!(forward_dynamics, m)?)?;
    m.add_function(wrap_pyfunction!(inverse_dynamics_trajectory, m)?)?;
    Ok(())
}
