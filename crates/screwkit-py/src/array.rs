//! numpy ⇄ Rust: array-likes in (converted once to C-contiguous float64), new arrays out.

use numpy::{
    Element, PyArray, PyArrayDescrMethods, PyArrayDyn, PyArrayMethods, PyUntypedArray,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An input as a C-contiguous float64 array: a float64 C-contiguous ndarray is used as is (no
/// copy); anything else — lists, other integer or float dtypes, strided views — is converted
/// once with `numpy.ascontiguousarray(x, dtype=float64)`. Booleans, complex numbers, strings and
/// objects that are not numbers are refused (`ValueError` naming `what`).
pub fn f64_array<'py>(x: &Bound<'py, PyAny>, what: &str) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if let Ok(a) = x.cast::<PyArrayDyn<f64>>() {
        if a.is_c_contiguous() {
            return Ok(a.clone());
        }
    }
    let py = x.py();
    let np = py.import("numpy")?;
    let a = match x.cast::<PyUntypedArray>() {
        Ok(a) => a.clone().into_any(),
        Err(_) => np
            .call_method1("asarray", (x,))
            .map_err(|e| PyValueError::new_err(format!("{what}: not an array of numbers: {e}")))?,
    };
    let untyped = a.cast::<PyUntypedArray>()?;
    let kind = untyped.dtype().kind();
    if !matches!(kind, b'f' | b'i' | b'u') {
        let dtype = untyped.dtype().str()?.to_string();
        return Err(PyValueError::new_err(format!(
            "{what}: expected real numbers, got an array of dtype {dtype}"
        )));
    }
    let c = np.call_method1("ascontiguousarray", (a, "float64"))?;
    Ok(c.cast_into::<PyArrayDyn<f64>>()?)
}

/// A new C-contiguous array of `shape`, filled by `fill` (which must write every element).
pub fn new_array<'py, T: Element>(
    py: Python<'py>,
    shape: &[usize],
    fill: impl FnOnce(&mut [T]),
) -> PyResult<Bound<'py, PyArrayDyn<T>>> {
    // SAFETY: the array is new, C-contiguous and not shared yet; `fill` writes every element
    // before it is handed to Python.
    let a = unsafe { PyArray::<T, _>::new(py, shape, false) };
    fill(unsafe { a.as_slice_mut()? });
    Ok(a)
}

/// A shape in Python's notation, e.g. `(3, 6)` or `(6,)`.
pub fn shape_str(shape: &[usize]) -> String {
    match shape {
        [one] => format!("({one},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// The pose values of a (4, 4) or (N, 4, 4) array: (values, Some(N) for a stack).
pub fn poses<'py>(
    x: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Option<usize>)> {
    let a = f64_array(x, what)?;
    let shape = a.shape().to_vec();
    match shape.as_slice() {
        [4, 4] => Ok((a, None)),
        [n, 4, 4] => Ok((a, Some(*n))),
        _ => Err(PyValueError::new_err(format!(
            "{what}: expected shape (4, 4) or (N, 4, 4), got {}",
            shape_str(&shape)
        ))),
    }
}

/// A new zero-filled C-contiguous float64 array of `shape` (the output of a batch call),
/// made by `numpy.zeros`: an output numpy cannot allocate is numpy's `MemoryError` (or
/// `ValueError` for a shape beyond any address space), never a crash.
pub fn zeros<'py>(py: Python<'py>, shape: &[usize]) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let shape = pyo3::types::PyTuple::new(py, shape)?;
    let a = py
        .import("numpy")?
        .getattr("zeros")?
        .call1((shape, "float64"))?;
    Ok(a.cast_into::<PyArrayDyn<f64>>()?)
}
