//! A mesh's convex hull with a fast support function: hill climbing on the hull's vertex–edge
//! graph (MuJoCo's way with mesh geoms), where parry's `ConvexPolyhedron` scans every vertex
//! for each support point. On a convex polyhedron a vertex no neighbour beats along d is a
//! vertex of greatest d · p (a linear function's local maximum over the edge graph is global),
//! so the answer is exact; each search starts from the support vertex of the nearest of 384
//! precomputed directions (a cube map: d's face and cell, looked up without a dot product), a
//! step or two from the answer. The start depends on d alone, so the answer does too (never on earlier
//! calls: reproducible on any thread). Every convex query (GJK distance and
//! intersection, EPA penetration) goes through it, as for the ellipsoid; the world box of a
//! placed hull takes six supports instead of a pass over every vertex.
//!
//! Measured on TALOS's collision meshes as hulls: a whole-body step with collision avoidance
//! spent 62 % of its time in parry's vertex scan (BENCHMARKS.md).

use parry3d_f64::bounding_volume::{Aabb, BoundingSphere};
use parry3d_f64::mass_properties::MassProperties;
use parry3d_f64::math::{Pose, Real, Vector};
use parry3d_f64::query::{PointProjection, PointQuery, Ray, RayCast, RayIntersection};
use parry3d_f64::shape::{ConvexPolyhedron, FeatureId, Shape, ShapeType, SupportMap, TypedShape};

/// Cells per cube face side of the start table: 6 × 8 × 8 directions.
const CELLS: usize = 8;

/// The start table's cell of direction `d` (a cube map: the face of d's largest component,
/// then the cell of the other two components over it), and None for a zero or NaN `d`.
fn cell(d: Vector) -> Option<usize> {
    let a = d.abs();
    let (face, m, u, v) = if a.x >= a.y && a.x >= a.z {
        (usize::from(d.x < 0.0), a.x, d.y, d.z)
    } else if a.y >= a.z {
        (2 + usize::from(d.y < 0.0), a.y, d.x, d.z)
    } else {
        (4 + usize::from(d.z < 0.0), a.z, d.x, d.y)
    };
    if m.is_nan() || m <= 0.0 {
        return None;
    }
    let at = |t: f64| (((t / m + 1.0) * 0.5 * CELLS as f64) as usize).min(CELLS - 1);
    Some((face * CELLS + at(u)) * CELLS + at(v))
}

/// The centre direction of a cell ([`cell`]'s inverse).
fn cell_direction(k: usize) -> Vector {
    let (face, rest) = (k / (CELLS * CELLS), k % (CELLS * CELLS));
    let at = |i: usize| (i as f64 + 0.5) / CELLS as f64 * 2.0 - 1.0;
    let (u, v) = (at(rest / CELLS), at(rest % CELLS));
    let s = if face % 2 == 0 { 1.0 } else { -1.0 };
    match face / 2 {
        0 => Vector::new(s, u, v),
        1 => Vector::new(u, s, v),
        _ => Vector::new(u, v, s),
    }
}

/// A convex hull (module documentation).
#[derive(Debug, Clone)]
pub struct Hull {
    poly: ConvexPolyhedron,
    /// Each vertex's neighbours: `neighbours[offsets[v]..offsets[v + 1]]`.
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    /// The support vertex of each cell's direction ([`cell`]), where searches start.
    starts: Vec<u32>,
    /// The local box and bounding sphere (parry's polyhedron computes them from every vertex
    /// at each call).
    local_aabb: Aabb,
    sphere: BoundingSphere,
}

impl Hull {
    /// The convex hull of `points`; None when they span no volume (fewer than four, or flat).
    pub fn new(points: &[Vector]) -> Option<Hull> {
        let poly = ConvexPolyhedron::from_convex_hull(points)?;
        Some(Hull::from_polyhedron(poly))
    }

    /// The hull of an engine's convex polyhedron.
    pub fn from_polyhedron(poly: ConvexPolyhedron) -> Hull {
        let n = poly.points().len();
        let mut degree = vec![0u32; n + 1];
        for e in poly.edges() {
            degree[e.vertices[0] as usize] += 1;
            degree[e.vertices[1] as usize] += 1;
        }
        let mut offsets = vec![0u32; n + 1];
        for v in 0..n {
            offsets[v + 1] = offsets[v] + degree[v];
        }
        let mut fill = offsets.clone();
        let mut neighbours = vec![0u32; offsets[n] as usize];
        for e in poly.edges() {
            let [a, b] = e.vertices;
            neighbours[fill[a as usize] as usize] = b;
            fill[a as usize] += 1;
            neighbours[fill[b as usize] as usize] = a;
            fill[b as usize] += 1;
        }
        let starts = (0..6 * CELLS * CELLS)
            .map(|k| scan(poly.points(), cell_direction(k)))
            .collect();
        Hull {
            local_aabb: poly.local_aabb(),
            sphere: poly.local_bounding_sphere(),
            poly,
            offsets,
            neighbours,
            starts,
        }
    }

    /// The hull's vertices.
    pub fn points(&self) -> &[Vector] {
        self.poly.points()
    }

    /// The index of a vertex of greatest `dir` · p.
    pub fn support_vertex(&self, dir: Vector) -> u32 {
        let points = self.poly.points();
        let mut best = cell(dir).map_or(0, |k| self.starts[k]);
        let mut value = points[best as usize].dot(dir);
        // Each move raises the value strictly: at most one visit per vertex.
        for _ in 0..points.len() {
            let (lo, hi) = (
                self.offsets[best as usize] as usize,
                self.offsets[best as usize + 1] as usize,
            );
            let mut moved = false;
            for &v in &self.neighbours[lo..hi] {
                let x = points[v as usize].dot(dir);
                if x > value {
                    value = x;
                    best = v;
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        best
    }
}

/// The index of a vertex of greatest `dir` · p, by a pass over all.
fn scan(points: &[Vector], dir: Vector) -> u32 {
    let mut best = 0;
    for (k, p) in points.iter().enumerate() {
        if p.dot(dir) > points[best].dot(dir) {
            best = k;
        }
    }
    best as u32
}

impl SupportMap for Hull {
    fn local_support_point(&self, dir: Vector) -> Vector {
        self.poly.points()[self.support_vertex(dir) as usize]
    }
}

impl PointQuery for Hull {
    fn project_local_point(&self, pt: Vector, solid: bool) -> PointProjection {
        self.poly.project_local_point(pt, solid)
    }

    fn project_local_point_and_get_feature(&self, pt: Vector) -> (PointProjection, FeatureId) {
        self.poly.project_local_point_and_get_feature(pt)
    }
}

impl RayCast for Hull {
    fn cast_local_ray_and_get_normal(
        &self,
        ray: &Ray,
        max_time_of_impact: Real,
        solid: bool,
    ) -> Option<RayIntersection> {
        self.poly
            .cast_local_ray_and_get_normal(ray, max_time_of_impact, solid)
    }
}

impl Shape for Hull {
    fn compute_local_aabb(&self) -> Aabb {
        self.local_aabb
    }

    fn compute_local_bounding_sphere(&self) -> BoundingSphere {
        self.sphere
    }

    /// The exact world box: the support points along ±x, ±y, ±z of the world.
    fn compute_aabb(&self, position: &Pose) -> Aabb {
        let axes = [Vector::X, Vector::Y, Vector::Z];
        let (mut lo, mut hi) = (Vector::ZERO, Vector::ZERO);
        for (i, axis) in axes.iter().enumerate() {
            let local = position.rotation.inverse() * *axis;
            let top = position.transform_point(self.local_support_point(local));
            let bottom = position.transform_point(self.local_support_point(-local));
            hi[i] = top[i];
            lo[i] = bottom[i];
        }
        Aabb::new(lo, hi)
    }

    fn clone_dyn(&self) -> Box<dyn Shape> {
        Box::new(self.clone())
    }

    fn scale_dyn(&self, scale: Vector, _num_subdivisions: u32) -> Option<Box<dyn Shape>> {
        Some(Box::new(Hull::from_polyhedron(
            self.poly.clone().scaled(scale)?,
        )))
    }

    fn mass_properties(&self, density: Real) -> MassProperties {
        self.poly.mass_properties(density)
    }

    fn is_convex(&self) -> bool {
        true
    }

    fn shape_type(&self) -> ShapeType {
        ShapeType::Custom
    }

    fn as_typed_shape(&self) -> TypedShape<'_> {
        TypedShape::Custom(self)
    }

    fn ccd_thickness(&self) -> Real {
        self.poly.ccd_thickness()
    }

    fn ccd_angular_thickness(&self) -> Real {
        self.poly.ccd_angular_thickness()
    }

    fn as_support_map(&self) -> Option<&dyn SupportMap> {
        Some(self as &dyn SupportMap)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Hill climbing finds the scan's support value for random directions on random hulls.
    #[test]
    fn support_equals_the_scan() {
        let mut s = 12345u64;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for trial in 0..40 {
            let count = 8 + trial * 25;
            // Points on a squashed sphere and inside it: a hull with many vertices.
            let points: Vec<Vector> = (0..count)
                .map(|_| {
                    let v = Vector::new(next(), next(), next());
                    let v = if trial % 2 == 0 { v / v.length() } else { v };
                    v * Vector::new(1.0, 0.4, 0.2)
                })
                .collect();
            let hull = Hull::new(&points).unwrap();
            for _ in 0..200 {
                let d = Vector::new(next(), next(), next());
                let got = hull.local_support_point(d).dot(d);
                let want = hull.points()[scan(hull.points(), d) as usize].dot(d);
                assert!(
                    (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                    "{got} vs {want}"
                );
            }
            // The world box is the hull's points' box.
            let pose = Pose::new(Vector::new(0.3, -0.2, 1.0), Vector::new(0.4, -1.1, 0.7));
            let aabb = hull.compute_aabb(&pose);
            let (mut lo, mut hi) = (Vector::splat(f64::MAX), Vector::splat(f64::MIN));
            for p in hull.points() {
                let w = pose.transform_point(*p);
                lo = lo.min(w);
                hi = hi.max(w);
            }
            assert!((aabb.mins - lo).abs().max_element() < 1e-12);
            assert!((aabb.maxs - hi).abs().max_element() < 1e-12);
        }
    }
}
