//! `screwkit.lie`: the screw calculus of *Modern Robotics* ch. 3 as numpy functions, each one
//! input or a stack of them along a leading axis. The formulas are `screwkit_lie`'s; this file
//! only converts arguments, loops over rows and reports bad rows.
//!
//! Every function takes one value (e.g. a (4, 4) transform) or N of them (N, 4, 4) and returns
//! one result or N. A bad single input raises `ValueError`; a bad row of a stack raises
//! `screwkit.BatchError` after every other row was computed (the bad rows NaN).

use nalgebra::{Matrix3, Matrix4, Vector3};
use numpy::{PyArrayDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use screwkit_lie::so3::{self, DEFAULT_ROTATION_TOLERANCE};
use screwkit_lie::{se3, LieError, ScrewAxis, Se3, Twist};

use crate::array::{f64_array, new_array, shape_str, zeros};

/// An argument: one value of shape `tail` or a stack (N, *tail).
struct Stack<'py> {
    a: Bound<'py, PyArrayDyn<f64>>,
    n: Option<usize>,
}

impl<'py> Stack<'py> {
    fn new(x: &Bound<'py, PyAny>, what: &str, tail: &[usize]) -> PyResult<Self> {
        let a = f64_array(x, what)?;
        let shape = a.shape();
        let n = if shape == tail {
            None
        } else if shape.len() == tail.len() + 1 && &shape[1..] == tail {
            Some(shape[0])
        } else {
            let one = shape_str(tail);
            let many = shape_str(&[&[0], tail].concat()).replacen('0', "N", 1);
            return Err(PyValueError::new_err(format!(
                "{what}: expected shape {one} or {many}, got {}",
                shape_str(shape)
            )));
        };
        Ok(Self { a, n })
    }

    /// One of several same-length arguments: checks that it is stacked as `n` is.
    fn like(self, n: Option<usize>, what: &str, first: &str) -> PyResult<Self> {
        if self.n != n {
            let count =
                |n: Option<usize>| n.map_or("one value".to_string(), |n| format!("{n} rows"));
            return Err(PyValueError::new_err(format!(
                "{what}: {} where {first} has {}",
                count(self.n),
                count(n)
            )));
        }
        Ok(self)
    }
}

/// A per-row scalar: a number, or an array of shape (N,) when the rows are stacked.
enum Scalars<'py> {
    One(f64),
    Many(Bound<'py, PyArrayDyn<f64>>),
}

impl<'py> Scalars<'py> {
    fn new(x: &Bound<'py, PyAny>, what: &str, n: Option<usize>) -> PyResult<Self> {
        if let Ok(v) = x.extract::<f64>() {
            return Ok(Self::One(v));
        }
        let a = f64_array(x, what)?;
        match (a.shape(), n) {
            ([], _) => Ok(Self::One(a.readonly().as_slice()?[0])),
            ([m], Some(n)) if *m == n => Ok(Self::Many(a)),
            (shape, _) => Err(PyValueError::new_err(format!(
                "{what}: expected a number{}, got shape {}",
                n.map_or(String::new(), |n| format!(" or shape ({n},)")),
                shape_str(shape)
            ))),
        }
    }

    fn values(&self) -> PyResult<Vec<f64>> {
        Ok(match self {
            Self::One(v) => vec![*v],
            Self::Many(a) => a.to_vec()?,
        })
    }
}

/// A value of `values` for row `i` (one value for all rows, or one per row).
fn at(values: &[f64], i: usize) -> f64 {
    values[if values.len() == 1 { 0 } else { i }]
}

/// Runs `f` on every row (`n` rows, or one unstacked value) into outputs of shapes `tails`
/// (stacked when the input is): a row whose `f` fails is NaN and named in the error.
fn map_rows<'py, const K: usize>(
    py: Python<'py>,
    what: &str,
    n: Option<usize>,
    tails: [&[usize]; K],
    mut f: impl FnMut(usize, &mut [&mut [f64]; K]) -> Result<(), String>,
) -> PyResult<[Bound<'py, PyArrayDyn<f64>>; K]> {
    let rows = n.unwrap_or(1);
    let mut outs = Vec::with_capacity(K);
    for tail in tails {
        let shape: Vec<usize> = n.into_iter().chain(tail.iter().copied()).collect();
        outs.push(zeros(py, &shape)?);
    }
    let outs: [Bound<'py, PyArrayDyn<f64>>; K] = match outs.try_into() {
        Ok(o) => o,
        Err(_) => unreachable!("K outputs were made"),
    };
    let lens = tails.map(|t| t.iter().product::<usize>());
    let mut bad: Vec<(usize, String)> = Vec::new();
    {
        // SAFETY: the outputs are new, C-contiguous and not shared with Python yet.
        let mut slices: Vec<&mut [f64]> = Vec::with_capacity(K);
        for o in &outs {
            slices.push(unsafe { o.as_slice_mut()? });
        }
        for i in 0..rows {
            // Ctrl-C interrupts a long stack (a KeyboardInterrupt, nothing returned).
            if i % 65536 == 65535 {
                py.check_signals()?;
            }
            let mut it = slices.iter_mut();
            let mut row: [&mut [f64]; K] = std::array::from_fn(|k| {
                let s = it.next().expect("K slices");
                &mut s[i * lens[k]..(i + 1) * lens[k]]
            });
            if let Err(e) = f(i, &mut row) {
                for r in row.iter_mut() {
                    r.fill(f64::NAN);
                }
                bad.push((i, e));
            }
        }
    }
    if bad.is_empty() {
        return Ok(outs);
    }
    if n.is_none() {
        return Err(PyValueError::new_err(format!("{what}: {}", bad[0].1)));
    }
    let result = if K == 1 {
        outs[0].clone().into_any()
    } else {
        pyo3::types::PyTuple::new(py, outs.iter())?.into_any()
    };
    Err(crate::errors::rows_error(py, what, bad, result))
}

/// A single result (shape `()` out of an unstacked input) as a Python float.
fn out<'py>(
    a: Bound<'py, PyArrayDyn<f64>>,
    n: Option<usize>,
    scalar: bool,
) -> PyResult<Bound<'py, PyAny>> {
    if scalar && n.is_none() {
        let v = a.readonly().as_slice()?[0];
        return Ok(pyo3::types::PyFloat::new(a.py(), v).into_any());
    }
    Ok(a.into_any())
}

fn vec3(x: &[f64]) -> Vector3<f64> {
    Vector3::new(x[0], x[1], x[2])
}

fn finite(x: &[f64], what: &'static str) -> Result<(), String> {
    if x.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(LieError::NonFinite { what }.to_string())
    }
}

fn write3(m: &Matrix3<f64>, o: &mut [f64]) {
    for r in 0..3 {
        for c in 0..3 {
            o[3 * r + c] = m[(r, c)];
        }
    }
}

fn write6(m: &nalgebra::Matrix6<f64>, o: &mut [f64]) {
    for r in 0..6 {
        for c in 0..6 {
            o[6 * r + c] = m[(r, c)];
        }
    }
}

/// A rotation of a row (3 × 3 row-major), validated as every screwkit input is.
fn rotation(x: &[f64]) -> Result<Matrix3<f64>, String> {
    so3::rotation_from_matrix(&Matrix3::from_row_slice(x), DEFAULT_ROTATION_TOLERANCE)
        .map_err(|e| e.to_string())
}

/// A rigid transform of a row (4 × 4 row-major), validated as every screwkit input is.
fn transform(x: &[f64]) -> Result<Se3, String> {
    Se3::from_row_major(x, DEFAULT_ROTATION_TOLERANCE).map_err(|e| e.to_string())
}

/// θ: one number for every row, or one per row (a non-finite θ is that row's error).
fn theta_arg(theta: Option<&Bound<'_, PyAny>>, n: Option<usize>) -> PyResult<Vec<f64>> {
    let t = match theta {
        Some(t) => Scalars::new(t, "theta", n)?.values()?,
        None => vec![1.0],
    };
    // One θ for every row: a bad one is the call's error, not every row's.
    if let [one] = t.as_slice() {
        if !one.is_finite() {
            return Err(PyValueError::new_err(format!("theta: not finite: {one}")));
        }
    }
    Ok(t)
}

/// Refuses an output row that overflowed (|ωθ| near 1e154 squares past f64's range).
fn finite_out(o: &[f64]) -> Result<(), String> {
    if o.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err("the result overflows (the coordinates are too large)".into())
    }
}

/// x θ, checked finite (θ, and the product: 1e200 · 1e200 overflows).
fn scaled<const N: usize>(x: &[f64], theta: f64, what: &'static str) -> Result<[f64; N], String> {
    if !theta.is_finite() {
        return Err(format!("theta: not finite: {theta}"));
    }
    finite(x, what)?;
    let out: [f64; N] = std::array::from_fn(|k| x[k] * theta);
    if !out.iter().all(|v| v.is_finite()) {
        return Err(format!("{what} times theta = {theta} overflows"));
    }
    Ok(out)
}

/// A row-major 4 × 4 into `o`.
fn write4(m: &Matrix4<f64>, o: &mut [f64]) {
    for r in 0..4 {
        for c in 0..4 {
            o[4 * r + c] = m[(r, c)];
        }
    }
}

/// The unit screw axis S = (ŝ, −ŝ × q + hŝ) (6,) through the point q (3,) along the direction
/// ŝ (3,, normalised here) with pitch h (m/rad; 0 for a revolute joint). Stacks: q and s (N, 3),
/// h a number or (N,). *Modern Robotics*' `ScrewToAxis`, which does not normalise ŝ.
#[pyfunction]
#[pyo3(signature = (q, s, h = None))]
pub fn screw_to_axis<'py>(
    py: Python<'py>,
    q: &Bound<'py, PyAny>,
    s: &Bound<'py, PyAny>,
    h: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let q = Stack::new(q, "q", &[3])?;
    let s = Stack::new(s, "s", &[3])?.like(q.n, "s", "q")?;
    let h = match h {
        Some(h) => Scalars::new(h, "h", q.n)?.values()?,
        None => vec![0.0],
    };
    let (qr, sr) = (q.a.readonly(), s.a.readonly());
    let (qv, sv) = (qr.as_slice()?, sr.as_slice()?);
    let [o] = map_rows(py, "screw_to_axis", q.n, [&[6]], |i, [o]| {
        let axis = ScrewAxis::from_point_direction_pitch(
            vec3(&qv[3 * i..]),
            vec3(&sv[3 * i..]),
            at(&h, i),
        )
        .map_err(|e| e.to_string())?;
        o.copy_from_slice(axis.twist().to_vector().as_slice());
        Ok(())
    })?;
    Ok(o.into_any())
}

/// The unit axis and angle of exponential coordinates ω̂θ (3,): (ω̂ (3,), θ). Stacks: (N, 3) →
/// ((N, 3), (N,)). Zero rotation has no axis: an error. *Modern Robotics*' `AxisAng3`.
#[pyfunction]
pub fn axis_angle3<'py>(
    py: Python<'py>,
    expc3: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let x = Stack::new(expc3, "expc3", &[3])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [w, t] = map_rows(py, "axis_angle3", x.n, [&[3], &[]], |i, [w, t]| {
        let p = &v[3 * i..3 * i + 3];
        finite(p, "exponential coordinates")?;
        let theta = vec3(p).norm();
        if theta == 0.0 {
            return Err("zero rotation: no axis".into());
        }
        w.copy_from_slice((vec3(p) / theta).as_slice());
        t[0] = theta;
        Ok(())
    })?;
    Ok((w.into_any(), out(t, x.n, true)?))
}

/// The unit screw axis and distance of exponential coordinates Sθ (6,): (S (6,), θ), with
/// θ = ‖ω‖, or θ = ‖v‖ when ω = 0 exactly (a translation). Stacks: (N, 6) → ((N, 6), (N,)).
/// The zero twist has no axis: an error. *Modern Robotics*' `AxisAng6` (which treats
/// ‖ω‖ < 1e-6 as a translation).
#[pyfunction]
pub fn axis_angle6<'py>(
    py: Python<'py>,
    expc6: &Bound<'py, PyAny>,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    let x = Stack::new(expc6, "expc6", &[6])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [s, t] = map_rows(py, "axis_angle6", x.n, [&[6], &[]], |i, [s, t]| {
        let tw = Twist::try_from_slice(&v[6 * i..6 * i + 6]).map_err(|e| e.to_string())?;
        let (axis, theta) = ScrewAxis::from_twist(&tw).map_err(|e| e.to_string())?;
        s.copy_from_slice(axis.twist().to_vector().as_slice());
        t[0] = theta;
        Ok(())
    })?;
    Ok((s.into_any(), out(t, x.n, true)?))
}

/// \[x\]: ω (3,) → the skew-symmetric 3 × 3 \[ω\]; a twist (ω, v) (6,) → the 4 × 4
/// \[\[\[ω\], v\], \[0, 0\]\]. Stacks: (N, 3) → (N, 3, 3), (N, 6) → (N, 4, 4). *Modern Robotics*'
/// `VecToso3` and `VecTose3`.
#[pyfunction]
pub fn hat<'py>(py: Python<'py>, x: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let a = f64_array(x, "x")?;
    let six = a.shape().last() == Some(&6);
    let x = Stack::new(a.as_any(), "x", if six { &[6] } else { &[3] })?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = if six {
        map_rows(py, "hat", x.n, [&[4, 4]], |i, [o]| {
            let t = Twist::try_from_slice(&v[6 * i..6 * i + 6]).map_err(|e| e.to_string())?;
            write4(&t.hat(), o);
            Ok(())
        })?
    } else {
        map_rows(py, "hat", x.n, [&[3, 3]], |i, [o]| {
            let w = &v[3 * i..3 * i + 3];
            finite(w, "ω")?;
            write3(&so3::hat(&vec3(w)), o);
            Ok(())
        })?
    };
    Ok(o.into_any())
}

/// The inverse of [`hat`]: a 3 × 3 → ω (3,) (of its skew part, ½(M − Mᵀ)); a 4 × 4 →
/// (ω, v) (6,) (ω of the skew part of its upper-left block, v its last column). Stacks:
/// (N, 3, 3) → (N, 3), (N, 4, 4) → (N, 6). *Modern Robotics*' `so3ToVec` and `se3ToVec`.
#[pyfunction]
pub fn vee<'py>(py: Python<'py>, m: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let a = f64_array(m, "m")?;
    let four = a.shape().last() == Some(&4);
    let x = Stack::new(a.as_any(), "m", if four { &[4, 4] } else { &[3, 3] })?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = if four {
        map_rows(py, "vee", x.n, [&[6]], |i, [o]| {
            let m = &v[16 * i..16 * i + 16];
            finite(m, "matrix")?;
            let t = Twist::vee(&Matrix4::from_row_slice(m));
            o.copy_from_slice(t.to_vector().as_slice());
            Ok(())
        })?
    } else {
        map_rows(py, "vee", x.n, [&[3]], |i, [o]| {
            let m = &v[9 * i..9 * i + 9];
            finite(m, "matrix")?;
            o.copy_from_slice(so3::vee(&Matrix3::from_row_slice(m)).as_slice());
            Ok(())
        })?
    };
    Ok(o.into_any())
}

/// e^\[ω\]θ: the rotation (3, 3) of exponential coordinates ω (3,) scaled by θ (a number, or
/// (N,) for a stack (N, 3) → (N, 3, 3)). *Modern Robotics*' `MatrixExp3(VecToso3(ωθ))`.
#[pyfunction]
#[pyo3(signature = (w, theta = None))]
pub fn exp3<'py>(
    py: Python<'py>,
    w: &Bound<'py, PyAny>,
    theta: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(w, "w", &[3])?;
    let th = theta_arg(theta, x.n)?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "exp3", x.n, [&[3, 3]], |i, [o]| {
        let p: [f64; 3] = scaled(&v[3 * i..3 * i + 3], at(&th, i), "exponential coordinates")?;
        write3(&so3::exp(&Vector3::from(p)), o);
        finite_out(o)
    })?;
    Ok(o.into_any())
}

/// log R: the exponential coordinates ω̂θ (3,) of a rotation (3, 3), θ in \[0, π\] (a stack
/// (N, 3, 3) → (N, 3)). R must be orthonormal to 1e-6 with det +1 (then it is projected).
/// *Modern Robotics*' `so3ToVec(MatrixLog3(R))`, accurate also near θ = 0 and θ = π.
#[pyfunction]
pub fn log3<'py>(py: Python<'py>, r: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(r, "R", &[3, 3])?;
    let rr = x.a.readonly();
    let v = rr.as_slice()?;
    let [o] = map_rows(py, "log3", x.n, [&[3]], |i, [o]| {
        o.copy_from_slice(so3::log(&rotation(&v[9 * i..9 * i + 9])?).as_slice());
        Ok(())
    })?;
    Ok(o.into_any())
}

/// e^\[ξ\]θ: the rigid transform (4, 4) of moving along the twist ξ = (ω, v) (6,) for θ (a
/// number, or (N,) for a stack (N, 6) → (N, 4, 4)); for a unit screw axis S, θ is the angle in
/// rad, or the distance in m if ω = 0. *Modern Robotics*' `MatrixExp6(VecTose3(ξθ))`.
#[pyfunction]
#[pyo3(signature = (twist, theta = None))]
pub fn exp6<'py>(
    py: Python<'py>,
    twist: &Bound<'py, PyAny>,
    theta: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(twist, "twist", &[6])?;
    let th = theta_arg(theta, x.n)?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "exp6", x.n, [&[4, 4]], |i, [o]| {
        let xi: [f64; 6] = scaled(&v[6 * i..6 * i + 6], at(&th, i), "twist")?;
        Se3::exp(&Twist::try_from_slice(&xi).map_err(|e| e.to_string())?).write_row_major(o);
        finite_out(o)
    })?;
    Ok(o.into_any())
}

/// log T: the exponential coordinates ξ = Sθ (6,) (ω, v) with e^\[ξ\] = T, rotation angle ‖ω‖
/// in \[0, π\] (a stack (N, 4, 4) → (N, 6)). *Modern Robotics*' `se3ToVec(MatrixLog6(T))`.
#[pyfunction]
pub fn log6<'py>(py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(t, "T", &[4, 4])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "log6", x.n, [&[6]], |i, [o]| {
        o.copy_from_slice(
            transform(&v[16 * i..16 * i + 16])?
                .log()
                .to_vector()
                .as_slice(),
        );
        Ok(())
    })?;
    Ok(o.into_any())
}

/// \[Ad_T\] (6, 6), mapping twists (ω, v) from the frame of T to the frame T is expressed in:
/// V_a = \[Ad_{T_ab}\] V_b (a stack (N, 4, 4) → (N, 6, 6)). *Modern Robotics*' `Adjoint`.
#[pyfunction]
pub fn adjoint<'py>(py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(t, "T", &[4, 4])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "adjoint", x.n, [&[6, 6]], |i, [o]| {
        write6(&transform(&v[16 * i..16 * i + 16])?.adjoint(), o);
        Ok(())
    })?;
    Ok(o.into_any())
}

/// \[ad_V\] (6, 6), the Lie bracket with the twist V = (ω, v) (6,): \[ad_V\] W = \[V, W\],
/// \[\[\[ω\], 0\], \[\[v\], \[ω\]\]\] (a stack (N, 6) → (N, 6, 6)). *Modern Robotics*' `ad`.
#[pyfunction]
pub fn ad<'py>(py: Python<'py>, v: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(v, "V", &[6])?;
    let r = x.a.readonly();
    let vals = r.as_slice()?;
    let [o] = map_rows(py, "ad", x.n, [&[6, 6]], |i, [o]| {
        let tw = Twist::try_from_slice(&vals[6 * i..6 * i + 6]).map_err(|e| e.to_string())?;
        write6(&tw.ad(), o);
        Ok(())
    })?;
    Ok(o.into_any())
}

/// T⁻¹ = \[\[Rᵀ, −Rᵀp\], \[0, 1\]\] of a rigid transform (4, 4) (a stack (N, 4, 4)).
/// *Modern Robotics*' `TransInv`; T must be a transform (rotation to 1e-6, bottom row
/// (0, 0, 0, 1)).
#[pyfunction]
pub fn trans_inv<'py>(py: Python<'py>, t: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(t, "T", &[4, 4])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "trans_inv", x.n, [&[4, 4]], |i, [o]| {
        transform(&v[16 * i..16 * i + 16])?
            .inverse()
            .write_row_major(o);
        Ok(())
    })?;
    Ok(o.into_any())
}

/// R⁻¹ = Rᵀ of a rotation (3, 3) (a stack (N, 3, 3)). *Modern Robotics*' `RotInv`; R must be
/// a rotation (orthonormal to 1e-6, det +1).
#[pyfunction]
pub fn rot_inv<'py>(py: Python<'py>, r: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(r, "R", &[3, 3])?;
    let rr = x.a.readonly();
    let v = rr.as_slice()?;
    let [o] = map_rows(py, "rot_inv", x.n, [&[3, 3]], |i, [o]| {
        write3(&rotation(&v[9 * i..9 * i + 9])?.transpose(), o);
        Ok(())
    })?;
    Ok(o.into_any())
}

/// The rotation nearest to a 3 × 3 matrix M in the Frobenius norm, always proper (det +1):
/// U diag(1, 1, det UVᵀ) Vᵀ from M = UΣVᵀ (a stack (N, 3, 3)). *Modern Robotics*'
/// `ProjectToSO3`, which negates a column of UVᵀ instead when det UVᵀ < 0 (a proper rotation,
/// but not the nearest one).
#[pyfunction]
pub fn project_to_so3<'py>(py: Python<'py>, m: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(m, "M", &[3, 3])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "project_to_so3", x.n, [&[3, 3]], |i, [o]| {
        let p = &v[9 * i..9 * i + 9];
        finite(p, "matrix")?;
        write3(&so3::nearest_rotation(&Matrix3::from_row_slice(p)), o);
        Ok(())
    })?;
    Ok(o.into_any())
}

/// The transform nearest to a 4 × 4 matrix: the nearest proper rotation of its upper-left
/// block ([`project_to_so3`]), its translation kept, bottom row (0, 0, 0, 1) (a stack
/// (N, 4, 4)). *Modern Robotics*' `ProjectToSE3`.
#[pyfunction]
pub fn project_to_se3<'py>(py: Python<'py>, m: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(m, "M", &[4, 4])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "project_to_se3", x.n, [&[4, 4]], |i, [o]| {
        se3::project_to_se3(&Matrix4::from_row_slice(&v[16 * i..16 * i + 16]))
            .map_err(|e| e.to_string())?
            .write_row_major(o);
        Ok(())
    })?;
    Ok(o.into_any())
}

/// How far a 3 × 3 matrix is from SO(3): ‖MᵀM − I‖_F when det M > 0, +∞ otherwise (a float,
/// or (N,) for a stack; NaN for non-finite input). *Modern Robotics*' `DistanceToSO3`, which
/// returns 1e9 for det M ≤ 0.
#[pyfunction]
pub fn distance_to_so3<'py>(py: Python<'py>, m: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(m, "M", &[3, 3])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "distance_to_so3", x.n, [&[]], |i, [o]| {
        o[0] = so3::distance_to_so3(&Matrix3::from_row_slice(&v[9 * i..9 * i + 9]));
        Ok(())
    })?;
    out(o, x.n, true)
}

/// How far a 4 × 4 matrix is from SE(3): ‖\[\[RᵀR, 0\], \[its last row\]\] − I‖_F when
/// det R > 0, +∞ otherwise (a float, or (N,) for a stack; NaN for non-finite input).
/// *Modern Robotics*' `DistanceToSE3`, which returns 1e9 for det R ≤ 0.
#[pyfunction]
pub fn distance_to_se3<'py>(py: Python<'py>, m: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    let x = Stack::new(m, "M", &[4, 4])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let [o] = map_rows(py, "distance_to_se3", x.n, [&[]], |i, [o]| {
        o[0] = se3::distance_to_se3(&Matrix4::from_row_slice(&v[16 * i..16 * i + 16]));
        Ok(())
    })?;
    out(o, x.n, true)
}

// The Python default of `tol` is written out (a constant would show as `...` in the signature).
const _: () = assert!(DEFAULT_ROTATION_TOLERANCE == 1e-6);

fn tolerance(tol: f64) -> PyResult<f64> {
    if tol.is_finite() && tol >= 0.0 {
        Ok(tol)
    } else {
        Err(PyValueError::new_err(format!(
            "tol: expected a finite number ≥ 0, got {tol}"
        )))
    }
}

/// Whether screwkit takes `m` for a rotation: finite, max |MᵀM − I| ≤ tol, det M > 0 (a bool,
/// or a bool array (N,) for a stack). The default tolerance is the one every screwkit input is
/// read with. *Modern Robotics*' `TestIfSO3` is `distance_to_so3(m) < 1e-3` instead.
#[pyfunction]
#[pyo3(signature = (m, tol = 1e-6))]
pub fn is_so3<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    tol: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let tol = tolerance(tol)?;
    let x = Stack::new(m, "M", &[3, 3])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let test =
        |i: usize| so3::check_rotation(&Matrix3::from_row_slice(&v[9 * i..9 * i + 9]), tol).is_ok();
    bools(py, x.n, test)
}

/// Whether screwkit takes `m` for a rigid transform: [`is_so3`] of its upper-left block and a
/// bottom row within max(tol, 1e-12) of (0, 0, 0, 1) (a bool, or a bool array (N,) for a stack).
/// *Modern Robotics*' `TestIfSE3` is `distance_to_se3(m) < 1e-3` instead.
#[pyfunction]
#[pyo3(signature = (m, tol = 1e-6))]
pub fn is_se3<'py>(
    py: Python<'py>,
    m: &Bound<'py, PyAny>,
    tol: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let tol = tolerance(tol)?;
    let x = Stack::new(m, "M", &[4, 4])?;
    let r = x.a.readonly();
    let v = r.as_slice()?;
    let test = |i: usize| {
        Se3::from_homogeneous_with_tolerance(&Matrix4::from_row_slice(&v[16 * i..16 * i + 16]), tol)
            .is_ok()
    };
    bools(py, x.n, test)
}

fn bools<'py>(
    py: Python<'py>,
    n: Option<usize>,
    test: impl Fn(usize) -> bool,
) -> PyResult<Bound<'py, PyAny>> {
    match n {
        None => Ok(pyo3::types::PyBool::new(py, test(0)).to_owned().into_any()),
        Some(n) => Ok(new_array::<bool>(py, &[n], |o| {
            for (i, b) in o.iter_mut().enumerate() {
                *b = test(i);
            }
        })?
        .into_any()),
    }
}

/// Adds the functions to the native module (as `screwkit._screwkit.<name>`; `screwkit.lie`
/// re-exports them, and `exp`, `log`, `adjoint` stay at the top level as before).
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(screw_to_axis, m)?)?;
    m.add_function(wrap_pyfunction!(axis_angle3, m)?)?;
    m.add_function(wrap_pyfunction!(axis_angle6, m)?)?;
    m.add_function(wrap_pyfunction!(hat, m)?)?;
    m.add_function(wrap_pyfunction!(vee, m)?)?;
    m.add_function(wrap_pyfunction!(exp3, m)?)?;
    m.add_function(wrap_pyfunction!(log3, m)?)?;
    m.add_function(wrap_pyfunction!(exp6, m)?)?;
    m.add_function(wrap_pyfunction!(log6, m)?)?;
    m.add_function(wrap_pyfunction!(adjoint, m)?)?;
    m.add_function(wrap_pyfunction!(ad, m)?)?;
    m.add_function(wrap_pyfunction!(trans_inv, m)?)?;
    m.add_function(wrap_pyfunction!(rot_inv, m)?)?;
    m.add_function(wrap_pyfunction!(project_to_so3, m)?)?;
    m.add_function(wrap_pyfunction!(project_to_se3, m)?)?;
    m.add_function(wrap_pyfunction!(distance_to_so3, m)?)?;
    m.add_function(wrap_pyfunction!(distance_to_se3, m)?)?;
    m.add_function(wrap_pyfunction!(is_so3, m)?)?;
    m.add_function(wrap_pyfunction!(is_se3, m)?)?;
    Ok(())
}
