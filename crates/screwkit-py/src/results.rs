//! Result objects: IK (one target or a batch) and the singularity analysis.

use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use screwkit_solve::ik::IkStatus;

/// The outcome of `Robot.ik` for one target (4, 4).
#[pyclass(frozen, get_all, module = "screwkit")]
pub struct IkResult {
    /// The solution, shape (dof,), within the joint limits; if not converged, the best
    /// configuration found.
    pub q: Py<PyArray1<f64>>,
    /// True when both tolerances were met.
    pub converged: bool,
    /// Iterations used, over all attempts.
    pub iterations: usize,
    /// Random restarts used.
    pub restarts: usize,
    /// Final rotation error: the angle of R(q)ᵀ R_target (rad).
    pub error_rot: f64,
    /// Final position error ‖p_target − p(q)‖ (m).
    pub error_pos: f64,
    /// Why the solve stopped: "converged", "iteration limit", "restart limit", "time limit".
    pub stop: String,
}

#[pymethods]
impl IkResult {
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let q: Vec<f64> = self.q.bind(py).extract()?;
        let q: Vec<String> = q.iter().map(|x| format!("{x:.4}")).collect();
        Ok(format!(
            "IkResult(converged={}, q=[{}], iterations={}, error_rot={:.1e}, error_pos={:.1e}, stop={:?})",
            if self.converged { "True" } else { "False" },
            q.join(", "),
            self.iterations,
            self.error_rot,
            self.error_pos,
            self.stop
        ))
    }
}

/// The outcome of `Robot.ik` for N targets (N, 4, 4): every attribute is one entry per target.
/// The per-target arrays other than `q` are made on first access (then the same array each
/// time): a small batch costs its solutions, not five arrays nobody reads.
#[pyclass(frozen, module = "screwkit")]
pub struct IkBatchResult {
    q: Py<PyArray2<f64>>,
    status: Vec<IkStatus>,
    converged: PyOnceLock<Py<PyArray1<bool>>>,
    iterations: PyOnceLock<Py<PyArray1<i64>>>,
    restarts: PyOnceLock<Py<PyArray1<i64>>>,
    error_rot: PyOnceLock<Py<PyArray1<f64>>>,
    error_pos: PyOnceLock<Py<PyArray1<f64>>>,
}

impl IkBatchResult {
    /// The result of solutions `q` (N, dof) and how each solve ended.
    pub fn new(q: Py<PyArray2<f64>>, status: Vec<IkStatus>) -> Self {
        Self {
            q,
            status,
            converged: PyOnceLock::new(),
            iterations: PyOnceLock::new(),
            restarts: PyOnceLock::new(),
            error_rot: PyOnceLock::new(),
            error_pos: PyOnceLock::new(),
        }
    }

    /// The array in `cell`, made from `f` of every status on first access.
    fn column<T: numpy::Element>(
        &self,
        py: Python<'_>,
        cell: &PyOnceLock<Py<PyArray1<T>>>,
        f: fn(&IkStatus) -> T,
    ) -> Py<PyArray1<T>> {
        cell.get_or_init(py, || {
            PyArray1::from_vec(py, self.status.iter().map(f).collect()).unbind()
        })
        .clone_ref(py)
    }
}

#[pymethods]
impl IkBatchResult {
    /// Solutions, shape (N, dof) (NaN rows for invalid targets or seeds).
    #[getter]
    fn q(&self, py: Python<'_>) -> Py<PyArray2<f64>> {
        self.q.clone_ref(py)
    }

    /// Converged or not, shape (N,), bool.
    #[getter]
    fn converged(&self, py: Python<'_>) -> Py<PyArray1<bool>> {
        self.column(py, &self.converged, |s| s.converged)
    }

    /// Iterations per target, shape (N,), int64.
    #[getter]
    fn iterations(&self, py: Python<'_>) -> Py<PyArray1<i64>> {
        self.column(py, &self.iterations, |s| s.iterations as i64)
    }

    /// Restarts per target, shape (N,), int64.
    #[getter]
    fn restarts(&self, py: Python<'_>) -> Py<PyArray1<i64>> {
        self.column(py, &self.restarts, |s| s.restarts as i64)
    }

    /// Final rotation errors (rad), shape (N,).
    #[getter]
    fn error_rot(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.column(py, &self.error_rot, |s| s.error_rot)
    }

    /// Final position errors (m), shape (N,).
    #[getter]
    fn error_pos(&self, py: Python<'_>) -> Py<PyArray1<f64>> {
        self.column(py, &self.error_pos, |s| s.error_pos)
    }

    /// Why each solve stopped (as in `IkResult.stop`, plus "invalid input").
    #[getter]
    fn stop(&self) -> Vec<&'static str> {
        self.status.iter().map(|s| s.stop.as_str()).collect()
    }

    fn __len__(&self) -> usize {
        self.status.len()
    }

    fn __repr__(&self) -> String {
        let converged = self.status.iter().filter(|s| s.converged).count();
        format!(
            "IkBatchResult(targets={}, converged={converged})",
            self.status.len()
        )
    }
}

/// The singular value decomposition of a Jacobian and what it means (`Robot.analyze`).
#[pyclass(frozen, get_all, module = "screwkit")]
pub struct Analysis {
    /// The frame of the analysed Jacobian ("space" or "body").
    pub frame: String,
    /// The Jacobian analysed, shape (6, dof).
    pub jacobian: Py<PyArray2<f64>>,
    /// Singular values, largest first, shape (min(6, dof),).
    pub singular_values: Py<PyArray1<f64>>,
    /// Numerical rank: singular values above `rank_tolerance`.
    pub rank: usize,
    /// max(6, dof) · ε · σ₁.
    pub rank_tolerance: f64,
    /// Yoshikawa's manipulability √det(J Jᵀ) = ∏σᵢ (0 for fewer than 6 joints).
    pub manipulability: f64,
    /// σ_max / σ_min (inf when rank deficient).
    pub condition_number: f64,
    /// det J for a 6-joint chain, else None.
    pub determinant: Option<f64>,
    /// Unit twists (ω, v) the arm cannot make at q (rows), shape (k, 6).
    pub lost_directions: Py<PyArray2<f64>>,
    /// The twist direction of the smallest singular value, shape (6,).
    pub weakest_direction: Py<PyArray1<f64>>,
    /// Principal axes of the angular-velocity ellipsoid (rows), shape (3, 3).
    pub angular_axes: Py<PyArray2<f64>>,
    /// Its semi-axis lengths, shape (3,).
    pub angular_lengths: Py<PyArray1<f64>>,
    /// Principal axes of the linear-velocity ellipsoid (rows), shape (3, 3).
    pub linear_axes: Py<PyArray2<f64>>,
    /// Its semi-axis lengths, shape (3,).
    pub linear_lengths: Py<PyArray1<f64>>,
    /// The verdict in words: singular (and what motion is lost), near singular, or
    /// well-conditioned.
    pub verdict: String,
    /// Position only (the tip point's 3 × dof velocity Jacobian, in m per joint unit): its
    /// singular values, largest first.
    pub position_singular_values: Py<PyArray1<f64>>,
    /// Its numerical rank (3 when the tip point can move every way).
    pub position_rank: usize,
    /// √det(J_v J_vᵀ) (0 for fewer than 3 joints).
    pub position_manipulability: f64,
    /// σ_max / σ_min of J_v (inf when its rank is below 3).
    pub position_condition_number: f64,
}

#[pymethods]
impl Analysis {
    fn __repr__(&self) -> String {
        format!(
            "Analysis(rank={}, manipulability={:.6e}, condition_number={:.6e}, verdict={:?})",
            self.rank, self.manipulability, self.condition_number, self.verdict
        )
    }
}

/// A Cartesian path (`Robot.cartesian_path`): the joint samples `q` (K, dof), the first the
/// seed; each sample's `place` on the path (segment index + fraction of it: 1.5 is halfway
/// along the second segment); the `fraction` of the path's length achieved; why it stopped
/// (`stop`: "reached", "singularity", "branch ends", "unreachable", "jump" or "collision") and a sentence
/// saying where (`message`).
#[pyclass(frozen, get_all, module = "screwkit")]
pub struct CartesianPath {
    /// (K, dof) joint values.
    pub q: Py<PyArray2<f64>>,
    /// (K,) places on the path.
    pub place: Py<PyArray1<f64>>,
    /// The fraction of the path achieved, 0 … 1.
    pub fraction: f64,
    /// Why it stopped.
    pub stop: String,
    /// Where and why, in one sentence.
    pub message: String,
}

impl CartesianPath {
    /// The Python object of the library's path (`dof` joints).
    pub fn new(
        py: Python<'_>,
        path: screwkit_solve::path::CartesianPath,
        dof: usize,
    ) -> PyResult<Self> {
        let rows = path.place.len();
        let q = crate::array::new_array(py, &[rows, dof], |o| o.copy_from_slice(&path.q))?
            .cast_into::<PyArray2<f64>>()?
            .unbind();
        Ok(CartesianPath {
            q,
            place: numpy::ToPyArray::to_pyarray(&path.place[..], py).unbind(),
            fraction: path.fraction,
            stop: path.stop.as_str().to_string(),
            message: path.message,
        })
    }
}

#[pymethods]
impl CartesianPath {
    fn __repr__(&self, py: Python<'_>) -> String {
        format!(
            "CartesianPath({} samples, fraction={:.4}, stop={:?})",
            self.place.bind(py).len().unwrap_or(0),
            self.fraction,
            self.stop
        )
    }
}
