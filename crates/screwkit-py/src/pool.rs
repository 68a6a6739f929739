//! The worker threads of batch calls, and Ctrl-C while they run.
//!
//! Batches run on a pool of this module's own (all cores, or `RAYON_NUM_THREADS`, or the
//! size set with `screwkit.set_num_threads`), never on rayon's global pool: a process forked
//! from one that ran a batch (`multiprocessing`'s default start method on Linux) inherits the
//! pool's bookkeeping but not its threads, so a batch in the child would wait forever. The
//! pool remembers the process that made it and a forked child makes its own.
//!
//! Long calls run a chunk of rows at a time with the GIL released and check for signals
//! between chunks ([`chunked`]), so Ctrl-C raises `KeyboardInterrupt` within a fraction of a
//! second; one IK solve checks between iterations ([`interrupted`]).

use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rayon::ThreadPool;
use screwkit_solve::{RowError, SolveError};

/// The pool, the process it belongs to, and the thread count asked for (`None`: default).
struct Pool {
    pid: u32,
    threads: Option<usize>,
    pool: Arc<ThreadPool>,
}

static POOL: RwLock<Option<Pool>> = RwLock::new(None);

fn build(threads: Option<usize>) -> Result<ThreadPool, rayon::ThreadPoolBuildError> {
    let mut b = rayon::ThreadPoolBuilder::new().thread_name(|i| format!("screwkit-{i}"));
    if let Some(n) = threads {
        b = b.num_threads(n);
    }
    b.build()
}

/// This process's pool (made on first use, and again in a forked child).
fn pool() -> PyResult<Arc<ThreadPool>> {
    let pid = std::process::id();
    if let Some(p) = POOL.read().unwrap_or_else(|e| e.into_inner()).as_ref() {
        if p.pid == pid {
            return Ok(p.pool.clone());
        }
    }
    let mut slot = POOL.write().unwrap_or_else(|e| e.into_inner());
    let threads = match slot.take() {
        Some(p) if p.pid == pid => {
            let pool = p.pool.clone();
            *slot = Some(p);
            return Ok(pool);
        }
        Some(p) => {
            let threads = p.threads;
            // The parent's pool: its threads do not exist here; never touch it again.
            std::mem::forget(p);
            threads
        }
        None => None,
    };
    let pool =
        Arc::new(build(threads).map_err(|e| {
            PyRuntimeError::new_err(format!("cannot start the batch threads: {e}"))
        })?);
    *slot = Some(Pool {
        pid,
        threads,
        pool: pool.clone(),
    });
    Ok(pool)
}

/// Runs `f` (a batch call) on this process's pool.
pub fn run<R: Send>(f: impl FnOnce() -> R + Send) -> PyResult<R> {
    Ok(pool()?.install(f))
}

/// Runs a batch of `rows` rows `chunk` at a time — `f(range)` computes rows `range` — with
/// the GIL released and the pool's threads, checking for signals (Ctrl-C) between chunks.
/// With a pool of one thread, on the calling thread instead, `inline` rows at a time (at most
/// as many as the library computes without a thread pool): handing work to the one thread and
/// waiting costs 20–60 µs on virtual machines (measured), and gains nothing. The bad rows of
/// every chunk are gathered into one `SolveError::Rows` with their global row numbers, so the
/// result is the one-call result whatever the chunk size.
pub fn chunked(
    py: Python<'_>,
    rows: usize,
    chunk: usize,
    inline: usize,
    mut f: impl FnMut(Range<usize>) -> Result<(), SolveError> + Send,
) -> PyResult<Result<(), SolveError>> {
    let pool = pool()?;
    let alone = pool.current_num_threads() <= 1;
    let step = if alone { chunk.min(inline) } else { chunk }.max(1);
    let mut bad: Vec<RowError> = Vec::new();
    let mut start = 0;
    while start < rows {
        let end = (start + step).min(rows);
        let r = if alone {
            py.detach(|| f(start..end))
        } else {
            py.detach(|| pool.install(|| f(start..end)))
        };
        match r {
            Ok(()) => {}
            Err(SolveError::Rows(rs)) => bad.extend(rs.into_iter().map(|mut e| {
                e.row += start;
                e
            })),
            Err(e) => return Ok(Err(e)),
        }
        py.check_signals()?;
        start = end;
    }
    Ok(if bad.is_empty() {
        Ok(())
    } else {
        Err(SolveError::Rows(bad))
    })
}

/// Set when a signal handler raised during a single solve ([`interrupted`]).
static RAISED: AtomicBool = AtomicBool::new(false);

/// The IK solver's interrupt check for one solve called from Python: at most every 50 ms,
/// takes the GIL and runs Python's signal handlers; true (stop the solve) when one raised
/// (the exception is re-raised by [`take_interrupt`]). Does nothing off the main thread.
pub fn interrupted() -> bool {
    use std::cell::Cell;
    use std::time::{Duration, Instant};
    thread_local! {
        static LAST: Cell<Option<Instant>> = const { Cell::new(None) };
    }
    let now = Instant::now();
    let due = LAST.with(|l| match l.get() {
        Some(t) if now.duration_since(t) < Duration::from_millis(50) => false,
        _ => {
            l.set(Some(now));
            true
        }
    });
    if !due {
        return false;
    }
    let raised = Python::attach(|py| match py.check_signals() {
        Ok(()) => false,
        Err(e) => {
            e.restore(py);
            true
        }
    });
    if raised {
        RAISED.store(true, Ordering::SeqCst);
    }
    raised
}

/// Set while a [`cancellable`] call is being cancelled (a signal handler raised).
static CANCEL: AtomicBool = AtomicBool::new(false);

/// The interrupt check of work running on the pool's threads under [`cancellable`] (off the
/// main thread, where Python's signal handlers cannot run): true once the main thread saw a
/// signal handler raise.
pub fn cancelled() -> bool {
    CANCEL.load(Ordering::Relaxed)
}

/// Runs `f` on the pool with the GIL released while this thread waits, running Python's
/// signal handlers every 50 ms; when one raises (Ctrl-C), [`cancelled`] turns true — `f`'s
/// solvers poll it and stop — and the exception is raised once `f` has returned.
pub fn cancellable<R: Send>(py: Python<'_>, f: impl FnOnce() -> R + Send) -> PyResult<R> {
    use std::time::Duration;
    let pool = pool()?;
    let mut raised: Option<PyErr> = None;
    let out = py.detach(|| {
        std::thread::scope(|s| {
            let waiter = std::thread::current();
            let worker = s.spawn(move || {
                let r = pool.install(f);
                waiter.unpark();
                r
            });
            while !worker.is_finished() {
                std::thread::park_timeout(Duration::from_millis(50));
                if raised.is_none() && !worker.is_finished() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        raised = Some(e);
                        CANCEL.store(true, Ordering::SeqCst);
                    }
                }
            }
            worker.join()
        })
    });
    CANCEL.store(false, Ordering::SeqCst);
    if let Some(e) = raised {
        return Err(e);
    }
    out.map_err(|_| PyRuntimeError::new_err("internal error: a batch thread panicked"))
}

/// The exception a signal handler raised during the last solve, if any.
pub fn take_interrupt(py: Python<'_>) -> PyResult<()> {
    if RAISED.swap(false, Ordering::SeqCst) {
        if let Some(e) = PyErr::take(py) {
            return Err(e);
        }
        return Err(pyo3::exceptions::PyKeyboardInterrupt::new_err(""));
    }
    Ok(())
}

/// Sets the number of worker threads of batch calls; `None` (or 0) goes back to the default
/// (all cores, or the `RAYON_NUM_THREADS` environment variable). Results do not depend on it.
#[pyfunction]
#[pyo3(signature = (threads = None))]
pub fn set_num_threads(threads: Option<i64>) -> PyResult<()> {
    let threads = match threads {
        None | Some(0) => None,
        Some(n) if n < 0 => {
            return Err(PyValueError::new_err(format!(
                "threads: expected a positive count (or None for all cores), got {n}"
            )))
        }
        Some(n) if n > 4096 => {
            return Err(PyValueError::new_err(format!(
                "threads: {n} is more than 4096"
            )))
        }
        Some(n) => Some(n as usize),
    };
    let pool = Arc::new(
        build(threads)
            .map_err(|e| PyRuntimeError::new_err(format!("cannot start the threads: {e}")))?,
    );
    let mut slot = POOL.write().unwrap_or_else(|e| e.into_inner());
    if let Some(old) = slot.take() {
        if old.pid != std::process::id() {
            std::mem::forget(old);
        }
    }
    *slot = Some(Pool {
        pid: std::process::id(),
        threads,
        pool,
    });
    Ok(())
}

/// The number of worker threads batch calls run on.
#[pyfunction]
pub fn num_threads() -> PyResult<usize> {
    run(rayon::current_num_threads)
}
