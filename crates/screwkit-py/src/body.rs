//! The robot's body from Python: the shapes of obstacles (`Box`, `Sphere`, `Capsule`,
//! `Cylinder`, `Mesh`) and the `Distances` result; the queries themselves are `Robot`'s
//! methods (`robot.rs`), each a conversion around `screwkit_collision` through the floor's
//! `body` module.

use std::path::PathBuf;

use numpy::{PyArray1, PyArray2, PyArray3, PyArrayMethods, ToPyArray};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use screwkit_model::geometry::Shape;

fn positive(what: &str, x: f64) -> PyResult<f64> {
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(PyValueError::new_err(format!(
            "{what}: expected a finite number > 0, got {x}"
        )))
    }
}

/// A box of full side lengths `size` (x, y, z; m), centred on its pose.
#[pyclass(frozen, skip_from_py_object, module = "screwkit", name = "Box")]
#[derive(Clone)]
pub struct Box_ {
    pub(crate) size: [f64; 3],
}

#[pymethods]
impl Box_ {
    #[new]
    fn new(size: [f64; 3]) -> PyResult<Self> {
        for s in size {
            positive("size", s)?;
        }
        Ok(Self { size })
    }
    /// Side lengths (m).
    #[getter]
    fn size(&self) -> [f64; 3] {
        self.size
    }
    fn __repr__(&self) -> String {
        format!(
            "Box(({}, {}, {}))",
            self.size[0], self.size[1], self.size[2]
        )
    }
}

/// A sphere of `radius` (m) centred on its pose.
#[pyclass(frozen, skip_from_py_object, module = "screwkit")]
#[derive(Clone)]
pub struct Sphere {
    pub(crate) radius: f64,
}

#[pymethods]
impl Sphere {
    #[new]
    fn new(radius: f64) -> PyResult<Self> {
        Ok(Self {
            radius: positive("radius", radius)?,
        })
    }
    /// Radius (m).
    #[getter]
    fn radius(&self) -> f64 {
        self.radius
    }
    fn __repr__(&self) -> String {
        format!("Sphere({})", self.radius)
    }
}

/// A capsule along its pose's z axis: a cylinder of `length` with half-spheres of `radius`.
#[pyclass(frozen, skip_from_py_object, module = "screwkit")]
#[derive(Clone)]
pub struct Capsule {
    pub(crate) radius: f64,
    pub(crate) length: f64,
}

#[pymethods]
impl Capsule {
    #[new]
    fn new(radius: f64, length: f64) -> PyResult<Self> {
        Ok(Self {
            radius: positive("radius", radius)?,
            length: positive("length", length)?,
        })
    }
    /// Radius (m).
    #[getter]
    fn radius(&self) -> f64 {
        self.radius
    }
    /// The cylinder's length (m).
    #[getter]
    fn length(&self) -> f64 {
        self.length
    }
    fn __repr__(&self) -> String {
        format!("Capsule({}, {})", self.radius, self.length)
    }
}

/// A cylinder along its pose's z axis, centred.
#[pyclass(frozen, skip_from_py_object, module = "screwkit")]
#[derive(Clone)]
pub struct Cylinder {
    pub(crate) radius: f64,
    pub(crate) length: f64,
}

#[pymethods]
impl Cylinder {
    #[new]
    fn new(radius: f64, length: f64) -> PyResult<Self> {
        Ok(Self {
            radius: positive("radius", radius)?,
            length: positive("length", length)?,
        })
    }
    /// Radius (m).
    #[getter]
    fn radius(&self) -> f64 {
        self.radius
    }
    /// Length (m).
    #[getter]
    fn length(&self) -> f64 {
        self.length
    }
    fn __repr__(&self) -> String {
        format!("Cylinder({}, {})", self.radius, self.length)
    }
}

/// A triangle mesh file (STL, OBJ, COLLADA), its vertices multiplied by `scale`.
#[pyclass(frozen, skip_from_py_object, module = "screwkit")]
#[derive(Clone)]
pub struct Mesh {
    pub(crate) path: PathBuf,
    pub(crate) scale: [f64; 3],
}

#[pymethods]
impl Mesh {
    #[new]
    #[pyo3(signature = (path, scale = (1.0, 1.0, 1.0)), text_signature = "(path, scale=(1.0, 1.0, 1.0))")]
    fn new(path: PathBuf, scale: (f64, f64, f64)) -> PyResult<Self> {
        let scale = [scale.0, scale.1, scale.2];
        for s in scale {
            positive("scale", s)?;
        }
        Ok(Self { path, scale })
    }
    /// The file.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }
    /// Per-axis scale.
    #[getter]
    fn scale(&self) -> [f64; 3] {
        self.scale
    }
    fn __repr__(&self) -> String {
        format!(
            "Mesh({:?}, scale={:?})",
            self.path.display().to_string(),
            self.scale
        )
    }
}

/// The model's shape of a Python shape object.
pub(crate) fn shape_of(obj: &Bound<'_, PyAny>) -> PyResult<Shape> {
    if let Ok(b) = obj.cast::<Box_>() {
        return Ok(Shape::Box { size: b.get().size });
    }
    if let Ok(s) = obj.cast::<Sphere>() {
        return Ok(Shape::Sphere {
            radius: s.get().radius,
        });
    }
    if let Ok(c) = obj.cast::<Capsule>() {
        let c = c.get();
        return Ok(Shape::Capsule {
            radius: c.radius,
            length: c.length,
        });
    }
    if let Ok(c) = obj.cast::<Cylinder>() {
        let c = c.get();
        return Ok(Shape::Cylinder {
            radius: c.radius,
            length: c.length,
        });
    }
    if let Ok(m) = obj.cast::<Mesh>() {
        let m = m.get();
        return Ok(Shape::Mesh {
            uri: m.path.display().to_string(),
            path: m.path.clone(),
            scale: m.scale,
        });
    }
    Err(PyValueError::new_err(
        "shape: expected screwkit.Box, Sphere, Capsule, Cylinder or Mesh",
    ))
}

/// An added obstacle's shape as pickling keeps it: its word, its numbers (a box's size, a
/// sphere's radius, a capsule's or a cylinder's radius and length, a mesh's scale) and a mesh's
/// path.
pub(crate) type ShapeState = (String, Vec<f64>, Option<std::path::PathBuf>);

/// [`ShapeState`] of a shape Python can add (None for the file-only ellipsoid and plane).
pub(crate) fn shape_state(shape: &Shape) -> Option<ShapeState> {
    Some(match shape {
        Shape::Box { size } => ("box".into(), size.to_vec(), None),
        Shape::Sphere { radius } => ("sphere".into(), vec![*radius], None),
        Shape::Capsule { radius, length } => ("capsule".into(), vec![*radius, *length], None),
        Shape::Cylinder { radius, length } => ("cylinder".into(), vec![*radius, *length], None),
        Shape::Mesh { path, scale, .. } => ("mesh".into(), scale.to_vec(), Some(path.clone())),
        Shape::Ellipsoid { .. } | Shape::Plane { .. } => return None,
    })
}

/// The shape of a [`ShapeState`].
pub(crate) fn state_shape((word, v, path): &ShapeState) -> PyResult<Shape> {
    let bad = || PyValueError::new_err(format!("a pickled obstacle's shape {word} {v:?}"));
    let three = |v: &[f64]| <[f64; 3]>::try_from(v).map_err(|_| bad());
    Ok(match (word.as_str(), v.as_slice(), path) {
        ("box", v, None) => Shape::Box { size: three(v)? },
        ("sphere", [r], None) => Shape::Sphere { radius: *r },
        ("capsule", [r, l], None) => Shape::Capsule {
            radius: *r,
            length: *l,
        },
        ("cylinder", [r, l], None) => Shape::Cylinder {
            radius: *r,
            length: *l,
        },
        ("mesh", v, Some(p)) => Shape::Mesh {
            uri: p.display().to_string(),
            path: p.clone(),
            scale: three(v)?,
        },
        _ => return Err(bad()),
    })
}

/// Every checked pair's signed distance at one configuration (`Robot.distances`): `pairs`
/// (P pairs of link or obstacle names), `distance` (P,) (negative when the shapes overlap),
/// `points` (P, 2, 3) (the witness points on each shape, world frame), `normal` (P, 3) (unit,
/// from the first shape to the second), and with `jacobians=True` `jacobian` (P, nv): each
/// distance's rate along the tree's velocity (ḋ = J v; None when not asked).
#[pyclass(frozen, skip_from_py_object, module = "screwkit")]
pub struct Distances {
    #[pyo3(get)]
    pairs: Vec<(String, String)>,
    #[pyo3(get)]
    distance: Py<PyArray1<f64>>,
    #[pyo3(get)]
    points: Py<PyArray3<f64>>,
    #[pyo3(get)]
    normal: Py<PyArray2<f64>>,
    #[pyo3(get)]
    jacobian: Option<Py<PyArray2<f64>>>,
}

impl Distances {
    /// The result of a distance query.
    pub(crate) fn new(
        py: Python<'_>,
        model: &screwkit_collision::CollisionModel,
        d: &[screwkit_collision::PairDistance],
        jacobian: Option<(&[f64], usize)>,
    ) -> PyResult<Self> {
        let p = d.len();
        let jacobian = match jacobian {
            Some((rows, nv)) => Some(rows.to_pyarray(py).reshape([p, nv])?.unbind()),
            None => None,
        };
        let points: Vec<f64> = d
            .iter()
            .flat_map(|x| x.point_a.into_iter().chain(x.point_b))
            .collect();
        let normal: Vec<f64> = d.iter().flat_map(|x| x.normal).collect();
        Ok(Self {
            pairs: d
                .iter()
                .map(|x| {
                    let (a, b) = model.pair_names(x.pair);
                    (a.to_string(), b.to_string())
                })
                .collect(),
            distance: d
                .iter()
                .map(|x| x.distance)
                .collect::<Vec<_>>()
                .to_pyarray(py)
                .unbind(),
            points: points.to_pyarray(py).reshape([p, 2, 3])?.unbind(),
            normal: normal.to_pyarray(py).reshape([p, 3])?.unbind(),
            jacobian,
        })
    }
}

#[pymethods]
impl Distances {
    fn __len__(&self) -> usize {
        self.pairs.len()
    }
    fn __repr__(&self, py: Python<'_>) -> String {
        let d = self.distance.bind(py).to_vec().unwrap_or_default();
        let min = d.iter().copied().fold(f64::INFINITY, f64::min);
        format!("Distances({} pairs, min {min:.6} m)", self.pairs.len())
    }
}

/// Collision avoidance for whole-body IK (`ik_step`, `ik_step_qp`, `ik_tasks`,
/// `ik_trajectory`: `limits=[CollisionAvoidance(…)]`), mink's `CollisionAvoidanceLimit`: each
/// pair of the robot's body (its checked pairs with the SRDF's disabled and the obstacles, as
/// they are at the call) closer than `detection_distance` beyond `margin` gives one row,
/// n · (J_b(p_b) − J_a(p_a)) v ≥ −gain (d − margin) / dt, so no pair closes faster than `gain`
/// of its gap per step and a pair already too close moves apart. `pairs`: "all" (every checked
/// pair), or a list of (link or obstacle, link or obstacle) names.
#[pyclass(frozen, skip_from_py_object, module = "screwkit")]
pub struct CollisionAvoidance {
    pairs: Option<Vec<(String, String)>>,
    margin: f64,
    detection_distance: f64,
    gain: f64,
    /// The limit built on a body model of a tree, kept while they are the robot's.
    built: std::sync::Mutex<Option<Built>>,
}

type Built = (
    std::sync::Arc<screwkit_collision::CollisionModel>,
    std::sync::Arc<screwkit_solve::TreeKinematics>,
    std::sync::Arc<screwkit_collision::CollisionAvoidance>,
);

#[pymethods]
impl CollisionAvoidance {
    #[new]
    #[pyo3(signature = (pairs = None, margin = 0.005, detection_distance = 0.05, gain = 0.85))]
    fn new(
        pairs: Option<&Bound<'_, PyAny>>,
        margin: f64,
        detection_distance: f64,
        gain: f64,
    ) -> PyResult<Self> {
        let pairs = match pairs {
            None => None,
            Some(p) if p.extract::<String>().is_ok_and(|s| s == "all") => None,
            Some(p) => Some(p.extract::<Vec<(String, String)>>().map_err(|_| {
                PyValueError::new_err(
                    "pairs: \"all\", or a list of (name, name) pairs of links or obstacles",
                )
            })?),
        };
        // The values are checked here too, so a bad one fails where it is written.
        screwkit_collision::avoidance::check_settings(margin, detection_distance, gain)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Self {
            pairs,
            margin,
            detection_distance,
            gain,
            built: std::sync::Mutex::new(None),
        })
    }
    /// The pairs constrained: None for all, else the (name, name) pairs given.
    #[getter]
    fn pairs(&self) -> Option<Vec<(String, String)>> {
        self.pairs.clone()
    }
    /// The least distance kept (m).
    #[getter]
    fn margin(&self) -> f64 {
        self.margin
    }
    /// Pairs closer than this beyond the margin get a row (m).
    #[getter]
    fn detection_distance(&self) -> f64 {
        self.detection_distance
    }
    /// The fraction of its gap a pair may close in one step.
    #[getter]
    fn gain(&self) -> f64 {
        self.gain
    }
    fn __repr__(&self) -> String {
        let pairs = match &self.pairs {
            None => "'all'".to_string(),
            Some(p) => format!("{p:?}"),
        };
        format!(
            "CollisionAvoidance(pairs={pairs}, margin={}, detection_distance={}, gain={})",
            self.margin, self.detection_distance, self.gain
        )
    }
}

impl CollisionAvoidance {
    /// The limit on `model` (the body of tree `kin`): built once per model and tree.
    pub(crate) fn limit(
        &self,
        model: &std::sync::Arc<screwkit_collision::CollisionModel>,
        kin: &std::sync::Arc<screwkit_solve::TreeKinematics>,
    ) -> PyResult<std::sync::Arc<screwkit_collision::CollisionAvoidance>> {
        use std::sync::Arc;
        let mut built = self.built.lock().expect("the limit's lock");
        if let Some((m, k, limit)) = built.as_ref() {
            if Arc::ptr_eq(m, model) && Arc::ptr_eq(k, kin) {
                return Ok(limit.clone());
            }
        }
        let limit = Arc::new(
            screwkit_collision::CollisionAvoidance::new(
                model.clone(),
                kin,
                self.pairs.as_deref(),
                self.margin,
                self.detection_distance,
                self.gain,
            )
            .map_err(|e| PyValueError::new_err(e.to_string()))?,
        );
        *built = Some((model.clone(), kin.clone(), limit.clone()));
        Ok(limit)
    }
}
