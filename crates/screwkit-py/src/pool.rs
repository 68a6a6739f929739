//! The worker threads of batch calls: rayon's global pool (all cores, or `RAYON_NUM_THREADS`),
//! or a pool of the size set with `screwkit.set_num_threads`.

use std::sync::{Arc, RwLock};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rayon::ThreadPool;

static POOL: RwLock<Option<Arc<ThreadPool>>> = RwLock::new(None);

/// Runs `f` (a batch call) on the chosen pool.
pub fn run<R: Send>(f: impl FnOnce() -> R + Send) -> R {
    let pool = POOL.read().unwrap_or_else(|e| e.into_inner()).clone();
    match pool {
        Some(p) => p.install(f),
        None => f(),
    }
}

/// Sets the number of worker threads of batch calls; `None` (or 0) goes back to the default
/// (all cores, or the `RAYON_NUM_THREADS` environment variable). Results do not depend on it.
#[pyfunction]
#[pyo3(signature = (threads = None))]
pub fn set_num_threads(threads: Option<i64>) -> PyResult<()> {
    let pool = match threads {
        None | Some(0) => None,
        Some(n) if n < 0 => {
            return Err(PyValueError::new_err(format!(
                "threads: expected a positive count (or None for all cores), got {n}"
            )))
        }
        Some(n) => Some(Arc::new(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n as usize)
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("cannot start {n} threads: {e}")))?,
        )),
    };
    *POOL.write().unwrap_or_else(|e| e.into_inner()) = pool;
    Ok(())
}

/// The number of worker threads batch calls run on.
#[pyfunction]
pub fn num_threads() -> usize {
    run(rayon::current_num_threads)
}
