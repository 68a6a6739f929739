//! Pairs whose signed distance has a closed form, answered before the engine's GJK/EPA (which
//! stops within its tolerance of round surfaces, and whose half-space contact is wrong for a
//! shape given first: parry 0.31 measures a capsule 0.38 m into a plane it enters by 0.18 m):
//!
//! - **two round shapes** (spheres, capsules: a point or a segment swept by a radius): with
//!   c_a, c_b the closest points of their two segments, d = ‖c_b − c_a‖ − r_a − r_b, negative
//!   when they overlap (minus the penetration depth: the Minkowski difference is a flat
//!   parallelogram swept by r_a + r_b), the normal n = (c_b − c_a)/‖c_b − c_a‖, the witness
//!   points c_a + r_a n and c_b − r_b n;
//! - **a plane** (MuJoCo's, the half-space z ≤ 0 of its frame, outward normal n) **and any
//!   convex shape or mesh**: d = min over the shape of n · (x − o), reached at the shape's
//!   support point along −n (a mesh's lowest vertex), negative below the plane; the witness
//!   on the plane is that point moved by −d n. The normal from the shape to the plane is −n;
//! - **two boxes apart** (parry's box–box closest points follow the best separating axis of
//!   SAT, which is not the closest pair's direction: 1.5e-4 m off on the bundled humanoid):
//!   the exact closest features ([`crate::triangles::closest_boxes`]). Overlapping boxes are
//!   left to the engine's SAT penetration, which is exact for them.

use nalgebra::Vector3;
use parry3d_f64::math::{Pose, Vector};
use parry3d_f64::shape::Shape;

type V = Vector3<f64>;

fn na(v: Vector) -> V {
    V::new(v.x, v.y, v.z)
}

/// A sphere's centre or a capsule's segment, in the world, and its radius.
fn round(shape: &dyn Shape, pose: &Pose) -> Option<(V, V, f64)> {
    if let Some(b) = shape.as_ball() {
        let c = na(pose.translation);
        return Some((c, c, b.radius));
    }
    let c = shape.as_capsule()?;
    Some((
        na(pose.transform_point(c.segment.a)),
        na(pose.transform_point(c.segment.b)),
        c.radius,
    ))
}

/// The signed distance of shapes a and b (world poses), their witness points and the normal
/// from a to b, when the pair has a closed form (module documentation); None otherwise.
pub(crate) fn pair(
    (sa, pa): (&dyn Shape, &Pose),
    (sb, pb): (&dyn Shape, &Pose),
) -> Option<(f64, V, V, V)> {
    if let (Some((a0, a1, ra)), Some((b0, b1, rb))) = (round(sa, pa), round(sb, pb)) {
        let (ca, cb) = crate::triangles::segments(&a0, &a1, &b0, &b1);
        let gap = cb - ca;
        let len = gap.norm();
        // Coincident axes: any direction across them separates as well.
        let n = if len > 0.0 {
            gap / len
        } else {
            let axis = if (a1 - a0).norm() > 0.0 {
                a1 - a0
            } else {
                b1 - b0
            };
            let other = if axis.x.abs() < 0.9 { V::x() } else { V::y() };
            let n = axis.cross(&other);
            if n.norm() > 0.0 {
                n.normalize()
            } else {
                V::z()
            }
        };
        return Some((len - ra - rb, ca + n * ra, cb - n * rb, n));
    }
    if let (Some(ca), Some(cb)) = (sa.as_cuboid(), sb.as_cuboid()) {
        let overlap = parry3d_f64::query::intersection_test(pa, sa, pb, sb)
            .map(|r| r.intersecting)
            .unwrap_or(true);
        if overlap {
            return None;
        }
        // b in a's frame.
        let rel = pa.inverse() * *pb;
        let rot = nalgebra::Rotation3::from(nalgebra::UnitQuaternion::from_quaternion(
            nalgebra::Quaternion::new(
                rel.rotation.w,
                rel.rotation.x,
                rel.rotation.y,
                rel.rotation.z,
            ),
        ));
        let (p, q) = crate::triangles::closest_boxes(
            &na(ca.half_extents),
            &na(cb.half_extents),
            &rot,
            &na(rel.translation),
        );
        let world = |v: V| na(pa.transform_point(Vector::new(v.x, v.y, v.z)));
        let (p, q) = (world(p), world(q));
        let gap = q - p;
        let len = gap.norm();
        return Some((
            len,
            p,
            q,
            if len > 0.0 {
                gap / len
            } else {
                V::from_element(f64::NAN)
            },
        ));
    }
    let plane = |s: &dyn Shape, p: &Pose| {
        s.as_halfspace()
            .map(|h| (na(p.rotation * h.normal), na(p.translation)))
    };
    if let Some((n, o)) = plane(sb, pb) {
        let (d, on_a) = lowest(sa, pa, &n, &o)?;
        return Some((d, on_a, on_a - n * d, -n));
    }
    if let Some((n, o)) = plane(sa, pa) {
        let (d, on_b) = lowest(sb, pb, &n, &o)?;
        return Some((d, on_b - n * d, on_b, n));
    }
    None
}

/// The point of `shape` (at `pose`) lowest along the plane normal `n` (through `o`), and its
/// height n · (x − o); None for a shape with neither a support function nor vertices.
fn lowest(shape: &dyn Shape, pose: &Pose, n: &V, o: &V) -> Option<(f64, V)> {
    let down = pose
        .rotation
        .inverse()
        .mul_vec3(Vector::new(-n.x, -n.y, -n.z));
    let point = if let Some(s) = shape.as_support_map() {
        na(pose.transform_point(s.local_support_point(down)))
    } else if let Some(m) = shape.as_trimesh() {
        let v = m
            .vertices()
            .iter()
            .min_by(|a, b| a.dot(-down).total_cmp(&b.dot(-down)))?;
        na(pose.transform_point(*v))
    } else {
        return None;
    };
    Some((n.dot(&(point - o)), point))
}
