//! The body's queries at a configuration q of the whole tree (`kin.nq()` values), Pinocchio
//! style: `query(&model, &mut ws, &kin, q)`, the workspace reused from call to call.
//!
//! Each query first places every shape (the tree's all-frame FK, then each shape's world pose
//! and bounding box: the broad phase), then asks the engine only about the pairs it must:
//! - [`in_collision`] and [`collisions`]: pairs whose boxes overlap get an intersection test;
//! - [`distances`]: every pair gets its signed distance, witness points and normal;
//! - [`min_distance`]: pairs in order of their boxes' distance, stopping when the next box
//!   pair is farther than the closest pair found (branch and bound).
//!
//! Batches ([`in_collision_batch`], [`min_distance_batch`]) run rows on all cores, a
//! workspace per thread; a bad row is reported by index and the others are answered.

use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::Shape;
use rayon::prelude::*;
use screwkit_solve::{RowError, SolveError, TreeKinematics, TreeWorkspace};

use crate::convert;
use crate::model::{Attach, CollisionError, CollisionModel};

/// Scratch for the queries: the tree's FK workspace, each shape's world pose and bounding box.
#[derive(Debug, Clone)]
pub struct CollisionWorkspace {
    tree: TreeWorkspace,
    world: Vec<screwkit_lie::Se3>,
    poses: Vec<Pose>,
    boxes: Vec<Aabb>,
    order: Vec<(f64, u32)>,
    /// Each link's space Jacobian (6 × nv, column-major) at the last q, and whether it is.
    jacobians: Vec<f64>,
    jacobian_done: Vec<bool>,
    /// A contact patch's vertices near the plane (gap, local vertex index).
    near: Vec<(f64, u32)>,
}

impl CollisionWorkspace {
    /// Scratch for `kin` and `model`.
    pub fn new(kin: &TreeKinematics, model: &CollisionModel) -> CollisionWorkspace {
        CollisionWorkspace {
            tree: TreeWorkspace::new(kin),
            world: Vec::with_capacity(model.objects.len()),
            poses: Vec::with_capacity(model.objects.len()),
            boxes: Vec::with_capacity(model.objects.len()),
            order: Vec::with_capacity(model.pairs.len()),
            jacobians: Vec::new(),
            jacobian_done: Vec::new(),
            near: Vec::new(),
        }
    }
}

/// One pair's signed distance: the separation (≥ 0), or minus the penetration depth when the
/// shapes overlap; the witness points on each shape (world frame) and the unit normal from a
/// to b (for separated shapes, (p_b − p_a)/d).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairDistance {
    /// The pair's index in the model's pairs.
    pub pair: usize,
    /// The signed distance (m).
    pub distance: f64,
    /// The witness point on shape a.
    pub point_a: [f64; 3],
    /// The witness point on shape b.
    pub point_b: [f64; 3],
    /// The unit normal, from a to b.
    pub normal: [f64; 3],
}

impl PairDistance {
    /// Pair `pair` separated by `distance`, its witness points `a` and `b` (world frame), the
    /// normal their difference made unit (NaN when they coincide).
    fn witnessed(
        pair: usize,
        distance: f64,
        a: nalgebra::Vector3<f64>,
        b: nalgebra::Vector3<f64>,
    ) -> PairDistance {
        let gap = b - a;
        let len = gap.norm();
        PairDistance {
            pair,
            distance,
            point_a: [a.x, a.y, a.z],
            point_b: [b.x, b.y, b.z],
            normal: if len > 0.0 {
                [gap.x / len, gap.y / len, gap.z / len]
            } else {
                [f64::NAN; 3]
            },
        }
    }
}

/// Places every shape at q: world poses and bounding boxes. Checks q.
fn place(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
) -> Result<(), CollisionError> {
    place_poses(model, ws, kin, q)?;
    for (i, o) in model.objects.iter().enumerate() {
        ws.boxes[i] = o.shape.compute_aabb(&ws.poses[i]);
    }
    Ok(())
}

/// Places every shape at q, its world pose only (no box), for the queries that measure pairs
/// without a broad phase or prune by spheres and loose boxes. Checks q.
fn place_poses(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
) -> Result<(), CollisionError> {
    let frames = screwkit_solve::tree::fk::fk_frames(kin, &mut ws.tree, q)?;
    ws.poses.clear();
    ws.world.clear();
    for o in &model.objects {
        let world = match o.attach {
            Attach::Link(l) => frames[l].compose(&o.origin),
            Attach::World => o.origin,
        };
        ws.poses.push(convert::pose(&world));
        ws.world.push(world);
    }
    // No box yet (the queries on a few pairs use none; `place` computes them all).
    ws.boxes.clear();
    ws.boxes.resize(model.objects.len(), Aabb::new_invalid());
    Ok(())
}

/// The distance between the spheres holding shapes a and b at the placed poses (≤ the shapes'
/// distance; −∞ when either sphere is unbounded, a plane's).
fn sphere_gap(model: &CollisionModel, ws: &CollisionWorkspace, a: usize, b: usize) -> f64 {
    let (oa, ob) = (&model.objects[a], &model.objects[b]);
    let (ra, rb) = (oa.sphere.1, ob.sphere.1);
    if !(ra.is_finite() && rb.is_finite()) {
        return f64::NEG_INFINITY;
    }
    let centre = |w: &screwkit_lie::Se3, c: [f64; 3]| {
        w.rotation() * nalgebra::Vector3::from(c) + w.translation()
    };
    let (ca, cb) = (
        centre(&ws.world[a], oa.sphere.0),
        centre(&ws.world[b], ob.sphere.0),
    );
    (ca - cb).norm() - ra - rb
}

/// True when the shapes of pair (a, b) intersect (touching counts): two exact meshes by their
/// box trees and exact triangle tests ([`crate::mesh_distance::intersects`]), the rest by the
/// engine.
fn intersects(model: &CollisionModel, ws: &CollisionWorkspace, a: usize, b: usize) -> bool {
    let (oa, ob) = (&model.objects[a], &model.objects[b]);
    if let (Some(ta), Some(tb)) = (oa.tree.as_deref(), ob.tree.as_deref()) {
        let rel = ws.world[a].inverse_compose(&ws.world[b]);
        return crate::mesh_distance::intersects(ta, tb, rel.rotation(), rel.translation());
    }
    // An exact mesh and a box: the mesh's tree against the box, in the mesh's frame.
    for (m, o) in [(a, b), (b, a)] {
        let (om, oo) = (&model.objects[m], &model.objects[o]);
        if let (Some(tree), Some(c)) = (om.tree.as_deref(), oo.shape.as_cuboid()) {
            let rel = ws.world[m].inverse_compose(&ws.world[o]);
            let h = nalgebra::Vector3::new(c.half_extents.x, c.half_extents.y, c.half_extents.z);
            return crate::mesh_distance::intersects_box(
                tree,
                &h,
                rel.rotation(),
                rel.translation(),
            );
        }
    }
    screwkit_model::mesh::contained(|| {
        query::intersection_test(&ws.poses[a], &*oa.shape.0, &ws.poses[b], &*ob.shape.0)
            .map(|r| r.intersecting)
    })
    // A pair the engine cannot test (or fails on: parry's EPA can panic on degenerate
    // shapes) is reported as colliding: never a silent "free".
    .map_or(true, |r| r.unwrap_or(true))
}

/// True when some checked pair collides at q (the first found ends the search).
pub fn in_collision(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
) -> Result<bool, CollisionError> {
    place(model, ws, kin, q)?;
    Ok(model.pairs.iter().any(|&(a, b)| {
        let (a, b) = (a as usize, b as usize);
        ws.boxes[a].intersects(&ws.boxes[b]) && intersects(model, ws, a, b)
    }))
}

/// The broad phase alone at q: every shape placed and bounded, and the number of checked pairs
/// whose boxes overlap (the pairs `in_collision` hands to the narrow phase when none collides).
/// For measuring the broad phase's share and what it prunes.
pub fn broad_phase(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
) -> Result<usize, CollisionError> {
    place(model, ws, kin, q)?;
    Ok(model
        .pairs
        .iter()
        .filter(|&&(a, b)| ws.boxes[a as usize].intersects(&ws.boxes[b as usize]))
        .count())
}

/// The colliding pairs at q (indices into the model's pairs, in order) into `out`.
pub fn collisions(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
    out: &mut Vec<usize>,
) -> Result<(), CollisionError> {
    place(model, ws, kin, q)?;
    out.clear();
    for (k, &(a, b)) in model.pairs.iter().enumerate() {
        let (a, b) = (a as usize, b as usize);
        if ws.boxes[a].intersects(&ws.boxes[b]) && intersects(model, ws, a, b) {
            out.push(k);
        }
    }
    Ok(())
}

/// The signed distance of pair `k` (shapes a, b) at the placed poses; NaN (points, normal and
/// distance) when the engine cannot measure it or fails on it (a panic contained).
fn pair_distance(model: &CollisionModel, ws: &CollisionWorkspace, k: usize) -> PairDistance {
    screwkit_model::mesh::contained(|| measure(model, ws, k)).unwrap_or(PairDistance {
        pair: k,
        distance: f64::NAN,
        point_a: [f64::NAN; 3],
        point_b: [f64::NAN; 3],
        normal: [f64::NAN; 3],
    })
}

/// [`pair_distance`] itself.
fn measure(model: &CollisionModel, ws: &CollisionWorkspace, k: usize) -> PairDistance {
    let (a, b) = model.pairs[k];
    let (a, b) = (a as usize, b as usize);
    let (sa, sb) = (&*model.objects[a].shape.0, &*model.objects[b].shape.0);
    let (pa, pb) = (&ws.poses[a], &ws.poses[b]);
    let unknown = PairDistance {
        pair: k,
        distance: f64::NAN,
        point_a: [f64::NAN; 3],
        point_b: [f64::NAN; 3],
        normal: [f64::NAN; 3],
    };
    // Two spheres or capsules, or a plane: closed forms.
    if let Some((distance, p1, p2, n)) = crate::closed_forms::pair((sa, pa), (sb, pb)) {
        return PairDistance {
            pair: k,
            distance,
            point_a: p1.into(),
            point_b: p2.into(),
            normal: n.into(),
        };
    }
    // A mesh read exactly, apart from the other shape: its tree of boxes against the other
    // (a mesh, a box, a sphere or a capsule), exact and fast.
    if let Some(found) = mesh_distance(model, ws, k, a, b) {
        return found;
    }
    // Two convex shapes (no triangle mesh): the closest points in one GJK run.
    if sa.as_trimesh().is_none() && sb.as_trimesh().is_none() {
        if let Convex::Apart(found) = convex_pair(k, (sa, pa), (sb, pb), f64::MAX) {
            return found;
        }
    }
    // The distance first (exact, the triangle trees pruned by it), with the triangles it was
    // measured between; then the witness points of those two convex pieces. (parry's
    // `closest_points` on a whole triangle mesh can stop at a triangle that is not the closest:
    // found against coal on the UR5, 2e-5 m too far.)
    let Ok(found) = query::distance(pa, sa, pb, sb) else {
        return unknown;
    };
    if found.distance > 0.0 {
        if let (Some(ma), Some(mb)) = (sa.as_trimesh(), sb.as_trimesh()) {
            // Two triangles: their closest points exactly, in the world frame.
            let corners = |pose: &Pose, t: parry3d_f64::shape::Triangle| {
                [t.a, t.b, t.c].map(|v| {
                    let w = pose.transform_point(v);
                    nalgebra::Vector3::new(w.x, w.y, w.z)
                })
            };
            let (p1, p2) = crate::triangles::closest(
                &corners(pa, ma.triangle(found.subshape1)),
                &corners(pb, mb.triangle(found.subshape2)),
            );
            // The exact separation of the two triangles (the engine's is within GJK's tolerance
            // of it).
            return PairDistance::witnessed(k, (p2 - p1).norm(), p1, p2);
        }
        // A primitive (box, sphere, capsule) and a triangle: exactly too.
        let exact = match (sa.as_trimesh(), sb.as_trimesh()) {
            (Some(m), None) => primitive_triangle(sb, pb, &m.triangle(found.subshape1), pa)
                .map(|(on_b, on_a)| (on_a, on_b)),
            (None, Some(m)) => primitive_triangle(sa, pa, &m.triangle(found.subshape2), pb),
            _ => None,
        };
        if let Some((p1, p2)) = exact {
            return PairDistance::witnessed(k, (p2 - p1).norm(), p1, p2);
        }
        let ta = sa.as_trimesh().map(|m| m.triangle(found.subshape1));
        let tb = sb.as_trimesh().map(|m| m.triangle(found.subshape2));
        let ga: &dyn Shape = ta.as_ref().map_or(sa, |t| t as &dyn Shape);
        let gb: &dyn Shape = tb.as_ref().map_or(sb, |t| t as &dyn Shape);
        if let Ok(query::ClosestPoints::WithinMargin(p1, p2)) =
            query::closest_points(pa, ga, pb, gb, f64::MAX)
        {
            let na = |v: parry3d_f64::math::Vector| nalgebra::Vector3::new(v.x, v.y, v.z);
            // An ellipsoid's, a cylinder's or a capsule's curved surface: GJK stops short of it
            // (2e-7 m on MuJoCo's cylinders, 1e-6 m on a capsule against a box, against MuJoCo's
            // and coal's GJK at 1e-13); polished by exact projections.
            let smooth = |s: &dyn Shape| {
                s.as_shape::<crate::ellipsoid::Ellipsoid>().is_some()
                    || s.as_cylinder().is_some()
                    || s.as_capsule().is_some()
            };
            if smooth(ga) || smooth(gb) {
                let (p1, p2) = crate::ellipsoid::polish((ga, pa), (gb, pb), p1, p2);
                return PairDistance::witnessed(k, (p2 - p1).length(), na(p1), na(p2));
            }
            return PairDistance::witnessed(k, found.distance, na(p1), na(p2));
        }
        return PairDistance {
            distance: found.distance,
            ..unknown
        };
    }
    // Overlapping: the penetration depth, its points and normal.
    match query::contact(pa, sa, pb, sb, 0.0) {
        Ok(Some(c)) => PairDistance {
            pair: k,
            distance: c.dist.min(0.0),
            point_a: convert::array(c.point1),
            point_b: convert::array(c.point2),
            normal: convert::array(c.normal1),
        },
        _ => PairDistance {
            distance: 0.0,
            ..unknown
        },
    }
}

/// How far beyond a hull pair's distance its other vertices still count as touching (m).
const PATCH: f64 = 1e-3;
/// The most vertices a contact patch adds.
const PATCH_VERTICES: usize = 8;

/// A hull lying flat against another convex shape touches it along a face: every vertex of
/// the face ties for the distance, and GJK's witness jumps between them from one
/// configuration to the next. A row on the witness alone lets the hull turn about it and push
/// another corner in (seen as chatter: TALOS's gripper on a table top). So each hull vertex
/// within [`PATCH`] of the separating plane (through the other shape's witness point, normal
/// n; the other shape lies beyond it, so the vertex's gap to the plane is a lower bound of its
/// distance) adds the entry of a row: same pair, its gap, the vertex and its foot on the plane,
/// the same normal (at most [`PATCH_VERTICES`], the closest first).
fn contact_patch(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    a: usize,
    b: usize,
    d: &PairDistance,
    out: &mut Vec<PairDistance>,
) {
    let n = nalgebra::Vector3::from(d.normal);
    for (side, (h, witness, plane)) in [(a, d.point_a, d.point_b), (b, d.point_b, d.point_a)]
        .into_iter()
        .enumerate()
    {
        let shape = &model.objects[h].shape;
        // A convex side only: on a mesh (not convex) the plane need not separate the shapes.
        let Some(hull) = shape.as_shape::<crate::hull::Hull>() else {
            continue;
        };
        let vertices = hull.points();
        let w = &ws.world[h];
        let witness = nalgebra::Vector3::from(witness);
        // Side 0 (the hull is a): gap n·(p − v); side 1 (the hull is b): n·(v − p), v = R x + t
        // for the hull's local vertex x: gap = s (n·(p − t) − (Rᵀn)·x), s = ±1, measured in
        // the hull's frame (one dot product a vertex; only the patch's vertices are placed).
        let sign = if side == 0 { 1.0 } else { -1.0 };
        let offset = n.dot(&(nalgebra::Vector3::from(plane) - w.translation()));
        let local = w.rotation().transpose() * n;
        ws.near.clear();
        for (k, x) in vertices.iter().enumerate() {
            let gap = sign * (offset - (local.x * x.x + local.y * x.y + local.z * x.z));
            if gap <= d.distance + PATCH {
                ws.near.push((gap, k as u32));
            }
        }
        ws.near
            .sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        let mut added = 0;
        for &(gap, k) in &ws.near {
            if added == PATCH_VERTICES {
                break;
            }
            let x = vertices[k as usize];
            let v = w.rotation() * nalgebra::Vector3::new(x.x, x.y, x.z) + w.translation();
            if (v - witness).norm() <= 1e-9 {
                continue;
            }
            let foot = v + sign * gap * n;
            let (pa, pb) = if side == 0 { (v, foot) } else { (foot, v) };
            out.push(PairDistance {
                pair: d.pair,
                distance: gap,
                point_a: pa.into(),
                point_b: pb.into(),
                normal: d.normal,
            });
            added += 1;
        }
    }
}

/// What one GJK run says of two convex shapes.
enum Convex {
    /// Apart: their distance, witness points and normal.
    Apart(PairDistance),
    /// Farther apart than the run was asked to look.
    Far,
    /// Overlapping, or the engine cannot answer: the general path measures them.
    Other,
}

/// Two convex shapes: their closest points by one GJK run (polished on curved surfaces, as
/// [`measure`]'s general path) when they are apart, [`Convex::Far`] when GJK proves them
/// farther than `max`.
fn convex_pair(
    k: usize,
    (sa, pa): (&dyn Shape, &Pose),
    (sb, pb): (&dyn Shape, &Pose),
    max: f64,
) -> Convex {
    let p = match query::closest_points(pa, sa, pb, sb, max) {
        Ok(query::ClosestPoints::WithinMargin(p1, p2)) => (p1, p2),
        Ok(query::ClosestPoints::Disjoint) => return Convex::Far,
        _ => return Convex::Other,
    };
    let na = |v: parry3d_f64::math::Vector| nalgebra::Vector3::new(v.x, v.y, v.z);
    let smooth = |s: &dyn Shape| {
        s.as_shape::<crate::ellipsoid::Ellipsoid>().is_some()
            || s.as_cylinder().is_some()
            || s.as_capsule().is_some()
    };
    let (p1, p2) = if smooth(sa) || smooth(sb) {
        crate::ellipsoid::polish((sa, pa), (sb, pb), p.0, p.1)
    } else {
        p
    };
    let d = (p2 - p1).length();
    if d > 0.0 {
        Convex::Apart(PairDistance::witnessed(k, d, na(p1), na(p2)))
    } else {
        Convex::Other
    }
}

/// Pair `k` (shapes a, b) by a mesh's tree of boxes ([`crate::mesh_distance`]) when one of them is
/// an exact mesh and the other a mesh, box, sphere or capsule: their distance when apart, and
/// for two meshes whose surfaces cross, their deepest crossing; None otherwise (the engine
/// answers: a mesh crossing a primitive).
fn mesh_distance(
    model: &CollisionModel,
    ws: &CollisionWorkspace,
    k: usize,
    a: usize,
    b: usize,
) -> Option<PairDistance> {
    use crate::mesh_distance::{closest, Other};
    let (oa, ob) = (&model.objects[a], &model.objects[b]);
    // The mesh side first.
    let (m, o, swapped) = match (&oa.tree, &ob.tree) {
        (Some(_), _) => (a, b, false),
        (None, Some(_)) => (b, a, true),
        _ => return None,
    };
    let (om, oo) = (&model.objects[m], &model.objects[o]);
    let tree = om.tree.as_deref()?;
    // The other shape's pose in the mesh's frame.
    let rel = ws.world[m].inverse_compose(&ws.world[o]);
    let (rot, p) = (*rel.rotation(), *rel.translation());
    let na = |v: parry3d_f64::math::Vector| nalgebra::Vector3::new(v.x, v.y, v.z);
    let other = if let Some(t) = oo.tree.as_deref() {
        Other::Mesh(t, rot, p)
    } else if let Some(c) = oo.shape.as_cuboid() {
        Other::Box(na(c.half_extents), rot, p)
    } else if let Some(ball) = oo.shape.as_ball() {
        Other::Swept(p, p, ball.radius)
    } else if let Some(c) = oo.shape.as_capsule() {
        Other::Swept(
            rot * na(c.segment.a) + p,
            rot * na(c.segment.b) + p,
            c.radius,
        )
    } else {
        return None;
    };
    let hit = match &other {
        Other::Mesh(t, rot, p) => crate::mesh_distance::intersects(tree, t, rot, p),
        Other::Box(h, rot, p) => crate::mesh_distance::intersects_box(tree, h, rot, p),
        _ => query::intersection_test(&ws.poses[a], &*oa.shape.0, &ws.poses[b], &*ob.shape.0)
            .map(|r| r.intersecting)
            .unwrap_or(true),
    };
    let world = &ws.world[m];
    let to_world = |v: nalgebra::Vector3<f64>| world.rotation() * v + world.translation();
    if hit {
        // Two meshes' surfaces crossing: their deepest crossing, by the trees.
        let Other::Mesh(t, rot, p) = &other else {
            return None;
        };
        let (pm, po, d, n) = crate::mesh_distance::penetration(tree, t, rot, p)?;
        let (pm, po, n) = (to_world(pm), to_world(po), world.rotation() * n);
        let (p1, p2, n) = if swapped { (po, pm, -n) } else { (pm, po, n) };
        return Some(PairDistance {
            pair: k,
            distance: d,
            point_a: p1.into(),
            point_b: p2.into(),
            normal: n.into(),
        });
    }
    let (on_mesh, on_other, d) = closest(tree, &other);
    let (pm, po) = (to_world(on_mesh), to_world(on_other));
    let (p1, p2) = if swapped { (po, pm) } else { (pm, po) };
    Some(PairDistance::witnessed(k, d, p1, p2))
}

/// The closest points (on the primitive, on the triangle), world frame, of a box, sphere or
/// capsule `shape` at `pose` and triangle `t` of a mesh at `mesh_pose`, exactly
/// ([`crate::triangles`]); None for another shape.
fn primitive_triangle(
    shape: &dyn Shape,
    pose: &Pose,
    t: &parry3d_f64::shape::Triangle,
    mesh_pose: &Pose,
) -> Option<(nalgebra::Vector3<f64>, nalgebra::Vector3<f64>)> {
    let na = |v: parry3d_f64::math::Vector| nalgebra::Vector3::new(v.x, v.y, v.z);
    // The triangle in the primitive's frame.
    let local =
        [t.a, t.b, t.c].map(|v| na(pose.inverse_transform_point(mesh_pose.transform_point(v))));
    let world = |v: nalgebra::Vector3<f64>| na(pose.transform_point(convert::from_nalgebra(&v)));
    if let Some(c) = shape.as_cuboid() {
        let (p, q) = crate::triangles::closest_box(&na(c.half_extents), &local);
        return Some((world(p), world(q)));
    }
    let (axis_a, axis_b, radius) = if let Some(b) = shape.as_ball() {
        (
            nalgebra::Vector3::zeros(),
            nalgebra::Vector3::zeros(),
            b.radius,
        )
    } else if let Some(c) = shape.as_capsule() {
        (na(c.segment.a), na(c.segment.b), c.radius)
    } else {
        return None;
    };
    let (p, q) = crate::triangles::closest_segment(&axis_a, &axis_b, &local);
    let d = q - p;
    let len = d.norm();
    if len <= radius {
        return None;
    }
    Some((world(p + d * (radius / len)), world(q)))
}

/// Every checked pair's signed distance at q, in the model's pair order, into `out`.
pub fn distances(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
    out: &mut Vec<PairDistance>,
) -> Result<(), CollisionError> {
    place_poses(model, ws, kin, q)?;
    out.clear();
    out.extend((0..model.pairs.len()).map(|k| pair_distance(model, ws, k)));
    Ok(())
}

/// The distance between two boxes (0 when they overlap): a lower bound of their shapes'.
fn box_distance(a: &Aabb, b: &Aabb) -> f64 {
    let gap = (a.mins - b.maxs)
        .max(b.mins - a.maxs)
        .max(parry3d_f64::math::Vector::ZERO);
    gap.length()
}

/// The closest checked pair at q (its signed distance, points and normal), None for a model
/// without pairs. Pairs are visited in order of their boxes' distance and the search stops
/// when the next boxes are farther apart than the closest pair found: the same answer as the
/// minimum over [`distances`].
pub fn min_distance(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
) -> Result<Option<PairDistance>, CollisionError> {
    place(model, ws, kin, q)?;
    ws.order.clear();
    for (k, &(a, b)) in model.pairs.iter().enumerate() {
        let d = box_distance(&ws.boxes[a as usize], &ws.boxes[b as usize]);
        ws.order.push((d, k as u32));
    }
    ws.order
        .sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let mut best: Option<PairDistance> = None;
    for &(bound, k) in &ws.order {
        // Overlapping boxes (bound 0) can hide any penetration depth: a negative best stops
        // nothing until the boxes part.
        if best.is_some_and(|b| bound > b.distance.max(0.0)) {
            break;
        }
        let d = pair_distance(model, ws, k as usize);
        let better = match best {
            None => true,
            Some(b) => d.distance < b.distance || (d.distance == b.distance && d.pair < b.pair),
        };
        if better || d.distance.is_nan() {
            best = Some(d);
            if d.distance.is_nan() {
                break;
            }
        }
    }
    Ok(best)
}

/// Every checked pair's signed distance at q (as [`distances`]) into `out`, and its
/// Jacobian row into `rows` (P × nv, row-major): the rate of the distance along the tree's
/// velocity v, ḋ = J_d v (a floating base's six velocities first, as the tree's Jacobians).
///
/// With witness points p_a, p_b (fixed to links a and b at q) and the unit normal n from a to
/// b, ḋ = n · (ṗ_b − ṗ_a), and a point p fixed to a link of space twist (ω, v_s) moves at
/// ṗ = v_s + ω × p; so each row is the unit force n at p_b as a wrench (p_b × n, n) applied to
/// b's space Jacobian, less the same at p_a on a's (mink's collision rows). An obstacle does
/// not move (no term). Each link's Jacobian is computed once per call. A pair without witness
/// points (the engine could not measure it) has a row of NaN.
pub fn distance_jacobians(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
    out: &mut Vec<PairDistance>,
    rows: &mut Vec<f64>,
) -> Result<(), CollisionError> {
    distances(model, ws, kin, q, out)?;
    pair_rows(model, ws, kin, q, out, rows)
}

/// Each pair of `found` (measured at q, the shapes placed) its Jacobian row into `rows`
/// (row-major, nv per pair): [`distance_jacobians`]' formula, each link's space Jacobian
/// computed once.
fn pair_rows(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
    found: &[PairDistance],
    rows: &mut Vec<f64>,
) -> Result<(), CollisionError> {
    let nv = kin.nv();
    let links = kin.model().links.len();
    ws.jacobians.resize(links * 6 * nv, 0.0);
    ws.jacobian_done.clear();
    ws.jacobian_done.resize(links, false);
    rows.clear();
    rows.resize(found.len() * nv, 0.0);
    for (d, row) in found.iter().zip(rows.chunks_mut(nv.max(1))) {
        let (a, b) = model.pairs[d.pair];
        let n = nalgebra::Vector3::from(d.normal);
        let ends = [
            (a as usize, nalgebra::Vector3::from(d.point_a), -1.0),
            (b as usize, nalgebra::Vector3::from(d.point_b), 1.0),
        ];
        for (object, p, sign) in ends {
            let Attach::Link(l) = model.objects[object].attach else {
                continue;
            };
            if !ws.jacobian_done[l] {
                let j = screwkit_solve::tree::jacobian::frame_jacobian(
                    kin,
                    &mut ws.tree,
                    q,
                    l,
                    screwkit_solve::JacobianKind::Space,
                )?;
                ws.jacobians[l * 6 * nv..(l + 1) * 6 * nv].copy_from_slice(j.as_slice());
                ws.jacobian_done[l] = true;
            }
            let j = &ws.jacobians[l * 6 * nv..(l + 1) * 6 * nv];
            // The wrench of a unit force n at p: moment p × n, force n.
            let m = p.cross(&n);
            let wrench = [m.x, m.y, m.z, n.x, n.y, n.z];
            for (c, r) in row.iter_mut().enumerate() {
                let col = &j[c * 6..c * 6 + 6];
                let dot: f64 = col.iter().zip(&wrench).map(|(x, w)| x * w).sum();
                *r += sign * dot;
            }
        }
    }
    Ok(())
}

/// The pairs closer than `within` at q (signed distance ≤ `within`), in the model's pair
/// order, into `out`, with their Jacobian rows into `rows` when given (as
/// [`distance_jacobians`]): what a
/// step that keeps clear of contact constrains (mink's detection distance). Only the pairs
/// `selected` (a flag per model pair; None: all) whose bounding boxes are within `within` are
/// measured; a pair the engine cannot measure is left out. With `rows`, a pair with a convex
/// hull closer than `patch_within` also gives its contact patch: an entry (and row) for each
/// other hull vertex within 1 mm of the separating plane, so that a hull lying flat on a
/// shape is held at its face's corners, not at GJK's witness alone.
#[allow(clippy::too_many_arguments)]
pub fn close_pairs(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
    within: f64,
    patch_within: f64,
    selected: Option<&[bool]>,
    out: &mut Vec<PairDistance>,
    rows: Option<&mut Vec<f64>>,
) -> Result<(), CollisionError> {
    place_poses(model, ws, kin, q)?;
    out.clear();
    for (k, &(a, b)) in model.pairs.iter().enumerate() {
        if selected.is_some_and(|s| !s.get(k).copied().unwrap_or(false)) {
            continue;
        }
        let (a, b) = (a as usize, b as usize);
        // The spheres holding the shapes first (a lower bound of their distance), then their
        // local boxes turned into the world (a box around the shape's box: O(1) where the
        // exact world box of a hull takes six support points).
        if sphere_gap(model, ws, a, b) > within {
            continue;
        }
        let loose = |i: usize| {
            model.objects[i]
                .shape
                .compute_local_aabb()
                .transform_by(&ws.poses[i])
        };
        if box_distance(&loose(a), &loose(b)) > within {
            continue;
        }
        // Two convex shapes no closed form measures: GJK stops as soon as it proves them
        // farther than `within`.
        let (sa, sb) = (&*model.objects[a].shape.0, &*model.objects[b].shape.0);
        let (pa, pb) = (&ws.poses[a], &ws.poses[b]);
        let convex = sa.as_trimesh().is_none()
            && sb.as_trimesh().is_none()
            && crate::closed_forms::pair((sa, pa), (sb, pb)).is_none();
        if convex {
            match screwkit_model::mesh::contained(|| convex_pair(k, (sa, pa), (sb, pb), within)) {
                Ok(Convex::Far) => continue,
                Ok(Convex::Apart(d)) => {
                    if d.distance <= within {
                        out.push(d);
                        if rows.is_some() && d.distance <= patch_within {
                            contact_patch(model, ws, a, b, &d, out);
                        }
                    }
                    continue;
                }
                _ => {}
            }
        }
        // An exact mesh whose hull is already farther than `within`: no triangles.
        if hulls_apart(model, ws, a, b, within) {
            continue;
        }
        let d = pair_distance(model, ws, k);
        if d.distance <= within && d.normal.iter().all(|v| v.is_finite()) {
            out.push(d);
            if rows.is_some()
                && d.distance > 0.0
                && d.distance <= patch_within
                && model.objects[a].tree.is_none()
                && model.objects[b].tree.is_none()
            {
                contact_patch(model, ws, a, b, &d, out);
            }
        }
    }
    match rows {
        Some(rows) => pair_rows(model, ws, kin, q, out, rows),
        None => Ok(()),
    }
}

/// The signed distances of the pairs `pairs` (indices into the model's pairs) at q, in that
/// order, into `out`.
pub fn pair_distances(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
    pairs: &[usize],
    out: &mut Vec<PairDistance>,
) -> Result<(), CollisionError> {
    if let Some(&k) = pairs.iter().find(|&&k| k >= model.pairs.len()) {
        return Err(CollisionError::Unknown(format!(
            "pair {k}: the model has {} pairs",
            model.pairs.len()
        )));
    }
    place_poses(model, ws, kin, q)?;
    out.clear();
    out.extend(pairs.iter().map(|&k| pair_distance(model, ws, k)));
    Ok(())
}

/// True when every checked pair is at least `margin` apart at q (margin 0: none touches, the
/// negation of [`in_collision`]). Pairs whose boxes are `margin` apart or more are not
/// measured; the others get the intersection test first, then (margin > 0) their distance. A
/// pair the engine cannot measure counts as too close.
pub fn clear(
    model: &CollisionModel,
    ws: &mut CollisionWorkspace,
    kin: &TreeKinematics,
    q: &[f64],
    margin: f64,
) -> Result<bool, CollisionError> {
    place(model, ws, kin, q)?;
    for (k, &(a, b)) in model.pairs.iter().enumerate() {
        let (a, b) = (a as usize, b as usize);
        let gap = box_distance(&ws.boxes[a], &ws.boxes[b]);
        if gap > margin || (gap == margin && margin > 0.0) {
            continue;
        }
        if hulls_apart(model, ws, a, b, margin) {
            continue;
        }
        if (gap == 0.0 && ws.boxes[a].intersects(&ws.boxes[b]) && intersects(model, ws, a, b))
            || (margin > 0.0 && {
                // NaN (not measured) counts as too close.
                let d = pair_distance(model, ws, k).distance;
                d.is_nan() || d < margin
            })
        {
            return Ok(false);
        }
    }
    Ok(true)
}

/// True when a pair with an exact mesh is at least `margin` apart (and apart) by the convex
/// hulls standing in for its meshes: a mesh lies in its hull, so the hulls' distance bounds the
/// shapes' from below, and one GJK run on the hulls (stopped once they are proven farther than
/// the margin) spares the triangle trees (measured: a collision-free reach map of the UR5 on
/// exact meshes, BENCHMARKS.md). False when it cannot tell: the exact test decides.
fn hulls_apart(
    model: &CollisionModel,
    ws: &CollisionWorkspace,
    a: usize,
    b: usize,
    margin: f64,
) -> bool {
    let (oa, ob) = (&model.objects[a], &model.objects[b]);
    if oa.tree.is_none() && ob.tree.is_none() {
        return false;
    }
    fn convex(o: &crate::model::Object) -> Option<&dyn Shape> {
        match o.tree.as_deref() {
            Some(t) => crate::mesh_distance::hull(t).map(|h| h as &dyn Shape),
            None => (o.shape.as_trimesh().is_none() && o.shape.as_support_map().is_some())
                .then_some(&*o.shape.0),
        }
    }
    let (Some(sa), Some(sb)) = (convex(oa), convex(ob)) else {
        return false;
    };
    let (pa, pb) = (&ws.poses[a], &ws.poses[b]);
    match screwkit_model::mesh::contained(|| query::closest_points(pa, sa, pb, sb, margin)) {
        Ok(Ok(query::ClosestPoints::Disjoint)) => true,
        Ok(Ok(query::ClosestPoints::WithinMargin(p, r))) => {
            let d = (r - p).length();
            d > 0.0 && d >= margin
        }
        _ => false,
    }
}

/// [`distance_jacobians`] of each row of `qs` (N × nq) into `out` (N lists of distances, N
/// row-major P × nv matrices), on all cores.
pub fn distance_jacobians_batch(
    model: &CollisionModel,
    kin: &TreeKinematics,
    qs: &[f64],
    out: &mut [(Vec<PairDistance>, Vec<f64>)],
) -> Result<(), CollisionError> {
    batch(model, kin, qs, out, |ws, q| {
        let mut d = Vec::with_capacity(model.pairs.len());
        let mut rows = Vec::with_capacity(model.pairs.len() * kin.nv());
        distance_jacobians(model, ws, kin, q, &mut d, &mut rows)?;
        Ok((d, rows))
    })
}

/// Runs `f` on each row of `qs` (N × nq) on all cores; a row the kinematics refuses is reported
/// by index ([`SolveError::Rows`]), the others are answered.
///
/// Rows go in contiguous pieces, about sixteen per thread, each with one workspace made for
/// it: a body query's rows differ 20× in cost (a row in contact runs its narrow phase to the
/// end), so the pieces must be small enough to balance, and few enough that making workspaces
/// does not eat the gain (a fresh one per rayon split with `map_init`, on every steal: the
/// Panda's 50 µs rows scaled 1.5× on 2 threads that way, 1.87× in pieces; 8 per thread 1.90×
/// and 1.71× on the UR5, 16 1.87× and 1.83×, 32 1.81× and 1.79×).
fn batch<T: Send>(
    model: &CollisionModel,
    kin: &TreeKinematics,
    qs: &[f64],
    out: &mut [T],
    f: impl Fn(&mut CollisionWorkspace, &[f64]) -> Result<T, CollisionError> + Sync,
) -> Result<(), CollisionError> {
    let nq = kin.nq();
    if nq == 0 || qs.len() != out.len() * nq {
        return Err(CollisionError::Solve(SolveError::InvalidInput(format!(
            "expected {} rows of {nq} configuration values, got {} values",
            out.len(),
            qs.len()
        ))));
    }
    let piece = out.len().div_ceil(16 * rayon::current_num_threads()).max(1);
    let bad: Vec<Vec<RowError>> = out
        .par_chunks_mut(piece)
        .zip(qs.par_chunks(piece * nq))
        .enumerate()
        .map(|(k, (o, q))| {
            let mut ws = CollisionWorkspace::new(kin, model);
            let mut bad = Vec::new();
            for (i, (o, q)) in o.iter_mut().zip(q.chunks(nq)).enumerate() {
                let row = k * piece + i;
                match f(&mut ws, q) {
                    Ok(v) => *o = v,
                    Err(CollisionError::Solve(error)) => bad.push(RowError { row, error }),
                    Err(e) => bad.push(RowError {
                        row,
                        error: SolveError::InvalidInput(e.to_string()),
                    }),
                }
            }
            bad
        })
        .collect();
    let bad: Vec<RowError> = bad.into_iter().flatten().collect();
    if bad.is_empty() {
        Ok(())
    } else {
        Err(CollisionError::Solve(SolveError::Rows(bad)))
    }
}

/// [`in_collision`] of each row of `qs` (N × nq) into `out` (N), on all cores; the same answers
/// whatever the thread count.
pub fn in_collision_batch(
    model: &CollisionModel,
    kin: &TreeKinematics,
    qs: &[f64],
    out: &mut [bool],
) -> Result<(), CollisionError> {
    batch(model, kin, qs, out, |ws, q| in_collision(model, ws, kin, q))
}

/// [`min_distance`]'s signed distance of each row of `qs` into `out` (N; +∞ for a model
/// without pairs), on all cores.
pub fn min_distance_batch(
    model: &CollisionModel,
    kin: &TreeKinematics,
    qs: &[f64],
    out: &mut [f64],
) -> Result<(), CollisionError> {
    batch(model, kin, qs, out, |ws, q| {
        Ok(min_distance(model, ws, kin, q)?.map_or(f64::INFINITY, |d| d.distance))
    })
}

/// [`distances`] of each row of `qs` (N × nq) into `out` (N lists), on all cores.
pub fn distances_batch(
    model: &CollisionModel,
    kin: &TreeKinematics,
    qs: &[f64],
    out: &mut [Vec<PairDistance>],
) -> Result<(), CollisionError> {
    batch(model, kin, qs, out, |ws, q| {
        let mut d = Vec::with_capacity(model.pairs.len());
        distances(model, ws, kin, q, &mut d)?;
        Ok(d)
    })
}

/// [`collisions`] of each row of `qs` (N × nq) into `out` (N lists of pair indices), on all
/// cores.
pub fn collisions_batch(
    model: &CollisionModel,
    kin: &TreeKinematics,
    qs: &[f64],
    out: &mut [Vec<usize>],
) -> Result<(), CollisionError> {
    batch(model, kin, qs, out, |ws, q| {
        let mut hits = Vec::new();
        collisions(model, ws, kin, q, &mut hits)?;
        Ok(hits)
    })
}
