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
//!   left to the engine's SAT penetration, which is exact for them;
//! - **a convex shape beyond one face of a box** (a gripper's hull over a table top): with n
//!   the outward normal of the box face the shape's centre lies beyond (the axis of largest
//!   |c_i| / h_i in the box's frame), s the shape's support point along −n and h its
//!   half-extent along n, d = n · (s − c_box) − h; when d > 0 and s projects inside the
//!   face's rectangle, d is the distance (the box lies in n · (x − c_box) ≤ h, the shape in
//!   n · (x − c_box) ≥ h + d, and s and its projection on the face are d apart), the witness on
//!   the box s − d n, the normal from the shape to the box −n. Otherwise (an edge or corner
//!   of the box is nearest, or they overlap) the engine's GJK answers. One support point
//!   instead of GJK's iterations, which walk a flat hull face's vertices over a flat box.

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
    if let Some(c) = sb.as_cuboid() {
        if let Some((d, on_a, on_b, n)) = beyond_face(sa, pa, na(c.half_extents), pb) {
            return Some((d, on_a, on_b, -n));
        }
    }
    if let Some(c) = sa.as_cuboid() {
        if let Some((d, on_b, on_a, n)) = beyond_face(sb, pb, na(c.half_extents), pa) {
            return Some((d, on_a, on_b, n));
        }
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

/// A convex `shape` (at `pose`) beyond one face of the box of half-extents `h` at `box_pose`,
/// measured exactly (module documentation): (d, the shape's point, the box's point, the face's
/// outward normal), or None when this face does not certify the distance.
fn beyond_face(shape: &dyn Shape, pose: &Pose, h: V, box_pose: &Pose) -> Option<(f64, V, V, V)> {
    if shape.as_cuboid().is_some() {
        return None; // (two boxes: the exact closest features above)
    }
    let support = shape.as_support_map()?;
    let c = na(box_pose.inverse_transform_point(pose.translation));
    let mut axis = None;
    let mut best = 0.0;
    for i in 0..3 {
        if h[i] > 0.0 && (c[i].abs() / h[i]) > best {
            best = c[i].abs() / h[i];
            axis = Some(i);
        }
    }
    let i = axis?;
    let sign = c[i].signum();
    let mut local = V::zeros();
    local[i] = sign;
    let n = box_pose
        .rotation
        .mul_vec3(Vector::new(local.x, local.y, local.z));
    let down = pose.rotation.inverse().mul_vec3(-n);
    let s = pose.transform_point(support.local_support_point(down));
    let p = na(box_pose.inverse_transform_point(s));
    let d = sign * p[i] - h[i];
    if d.is_nan() || d <= 0.0 || (0..3).any(|j| j != i && p[j].abs() > h[j]) {
        return None;
    }
    let mut on_face = p;
    on_face[i] = sign * h[i];
    let on_box = na(box_pose.transform_point(Vector::new(on_face.x, on_face.y, on_face.z)));
    Some((d, na(s), on_box, na(n)))
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

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::shape::{Cuboid, Cylinder};

    /// A tiny deterministic generator (xorshift), so the test needs no crate.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
        fn range(&mut self, a: f64, b: f64) -> f64 {
            a + (b - a) * self.next()
        }
        fn pose(&mut self, spread: f64) -> Pose {
            let axis = Vector::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let t = Vector::new(
                self.range(-spread, spread),
                self.range(-spread, spread),
                self.range(-spread, spread),
            );
            Pose::new(t, axis * self.range(0.0, 3.0))
        }
    }

    /// A convex shape beyond a box face, measured by the closed form, agrees with the engine's
    /// distance (parry's GJK: the distance of two points it found, an upper bound within its
    /// tolerance) — never above it, within 1e-7 of it — on random hulls, cylinders and boxes;
    /// its witness points lie on their shapes (a hull's on one of its vertices, the box's on
    /// its surface) and are d apart along the normal, so d is reached; and the closed form
    /// answers a good share of the separated cases (it is not vacuous).
    #[test]
    fn a_shape_beyond_a_box_face_is_measured_exactly() {
        let mut rng = Rng(0x9e3779b97f4a7c15);
        let (mut answered, mut separated) = (0, 0);
        for k in 0..4000 {
            let points: Vec<Vector> = (0..12)
                .map(|_| {
                    Vector::new(
                        rng.range(-0.1, 0.1),
                        rng.range(-0.05, 0.05),
                        rng.range(-0.08, 0.08),
                    )
                })
                .collect();
            let hull = crate::hull::Hull::new(&points).unwrap();
            let cylinder = Cylinder::new(0.06, 0.03);
            let shape: &dyn Shape = if k % 2 == 0 { &hull } else { &cylinder };
            let table = Cuboid::new(Vector::new(
                rng.range(0.05, 0.5),
                rng.range(0.05, 0.5),
                rng.range(0.02, 0.1),
            ));
            let (ps, pb) = (rng.pose(0.4), rng.pose(0.1));
            let reference = parry3d_f64::query::distance(&ps, shape, &pb, &table)
                .unwrap()
                .distance;
            if reference > 0.0 {
                separated += 1;
            }
            for swapped in [false, true] {
                let got = if swapped {
                    pair((&table, &pb), (shape, &ps))
                } else {
                    pair((shape, &ps), (&table, &pb))
                };
                let Some((d, on_a, on_b, n)) = got else {
                    continue;
                };
                if !swapped {
                    answered += 1;
                }
                assert!(reference > 0.0, "case {k}: answered an overlap");
                assert!(d <= reference + 1e-12, "case {k}: {d} above {reference}");
                assert!(reference - d < 1e-7, "case {k}: {d} against {reference}");
                let (on_shape, on_box) = if swapped { (on_b, on_a) } else { (on_a, on_b) };
                assert!(((on_b - on_a).norm() - d).abs() < 1e-12);
                assert!((on_b - on_a - n * d).norm() < 1e-12, "case {k}: the normal");
                let b = pb.inverse_transform_point(Vector::new(on_box.x, on_box.y, on_box.z));
                let h = table.half_extents;
                assert!(
                    b.x.abs() <= h.x + 1e-12
                        && b.y.abs() <= h.y + 1e-12
                        && b.z.abs() <= h.z + 1e-12
                );
                let s = ps.inverse_transform_point(Vector::new(on_shape.x, on_shape.y, on_shape.z));
                if k % 2 == 0 {
                    assert!(
                        points.iter().any(|v| (*v - s).length() < 1e-12),
                        "case {k}: not a vertex"
                    );
                } else {
                    // On the cylinder's surface: on a cap's rim or its flat face, or its side.
                    let r = (s.x * s.x + s.z * s.z).sqrt();
                    assert!((s.y.abs() - 0.06).abs() < 1e-12 || (r - 0.03).abs() < 1e-12);
                    assert!(r <= 0.03 + 1e-12 && s.y.abs() <= 0.06 + 1e-12);
                }
            }
        }
        assert!(
            separated > 1000 && answered > separated / 4,
            "{answered} of {separated}"
        );
    }
}
