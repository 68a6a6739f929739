//! The body in a drawing: each shape of each link as the points of its surface at q (a box's
//! corners, rings around cylinders, capsules, spheres and ellipsoids, a mesh's vertices), so
//! that a view draws its silhouette — the convex hull of the points projected on the page
//! ([`hull`], Andrew's monotone chain) — in painter's order (farthest first).
//!
//! A shape's silhouette is the projection of its convex hull: exact for boxes and convex
//! meshes, within the ring spacing (1 − cos(π/[`RING`]) ≈ 0.5 % of the radius) for round
//! shapes, and the outline of the hull for a non-convex mesh (a hand's fingers read as a mitt).

use std::collections::HashMap;

use nalgebra::{Vector2, Vector3};
use screwkit_lie::Se3;
use screwkit_model::geometry::{Role, Shape};

use crate::scene::LinkMark;

/// Points on a circle of a round shape.
pub const RING: usize = 32;

/// One shape of a link at q.
#[derive(Debug, Clone)]
pub struct Outline {
    /// The link it is fixed to (index into [`Scene::links`](crate::Scene::links)).
    pub link: usize,
    /// Visual or collision (the drawing shows a link's visual shapes, or its collision ones
    /// when it has no visual shape).
    pub role: Role,
    /// Points of its surface whose convex hull is the shape's (in the base frame, at q).
    pub points: Vec<Vector3<f64>>,
    /// Its colour (r, g, b, a in [0, 1]) where the file gives one.
    pub rgba: Option<[f64; 4]>,
}

/// Points on the unit circle in the xy-plane, at height z, scaled by (rx, ry).
fn ring(rx: f64, ry: f64, z: f64, out: &mut Vec<Vector3<f64>>) {
    for k in 0..RING {
        let a = std::f64::consts::TAU * k as f64 / RING as f64;
        out.push(Vector3::new(rx * a.cos(), ry * a.sin(), z));
    }
}

/// Points of an ellipsoid's surface (radii r) centred at (0, 0, z0): rings of latitude, with
/// the poles. The hull of rings at latitudes kπ/(RING/2) lies within 1 − cos(π/RING) of it
/// and outside a cut by at most that.
fn ellipsoid(r: [f64; 3], z0: f64, half: Option<bool>, out: &mut Vec<Vector3<f64>>) {
    let n = RING / 2;
    for k in 0..=n {
        let lat = std::f64::consts::PI * (k as f64 / n as f64 - 0.5);
        let (s, c) = lat.sin_cos();
        match half {
            Some(true) if s < 0.0 => continue,
            Some(false) if s > 0.0 => continue,
            _ => {}
        }
        if c.abs() < 1e-12 {
            out.push(Vector3::new(0.0, 0.0, z0 + r[2] * s));
        } else {
            ring(r[0] * c, r[1] * c, z0 + r[2] * s, out);
        }
    }
}

/// The points of `shape` in its own frame, or `None` when it has no bounded surface (a plane)
/// or is a mesh (read by the caller).
fn primitive(shape: &Shape) -> Option<Vec<Vector3<f64>>> {
    let mut out = Vec::new();
    match shape {
        Shape::Box { size } => {
            for k in 0..8 {
                let sign = |b: usize| if k >> b & 1 == 1 { 0.5 } else { -0.5 };
                out.push(Vector3::new(
                    sign(0) * size[0],
                    sign(1) * size[1],
                    sign(2) * size[2],
                ));
            }
        }
        Shape::Cylinder { radius, length } => {
            ring(*radius, *radius, -length / 2.0, &mut out);
            ring(*radius, *radius, length / 2.0, &mut out);
        }
        Shape::Capsule { radius, length } => {
            let r = [*radius; 3];
            ellipsoid(r, length / 2.0, Some(true), &mut out);
            ellipsoid(r, -length / 2.0, Some(false), &mut out);
        }
        Shape::Sphere { radius } => ellipsoid([*radius; 3], 0.0, None, &mut out),
        Shape::Ellipsoid { radii } => ellipsoid(*radii, 0.0, None, &mut out),
        Shape::Plane { .. } | Shape::Mesh { .. } => return None,
    }
    Some(out)
}

/// A mesh's vertices, one per cell of a grid of `cell` metres (the drawing cannot tell them
/// apart), in the file's order of first appearance.
fn thin(vertices: &[[f64; 3]], cell: f64) -> Vec<Vector3<f64>> {
    let mut seen = std::collections::HashSet::new();
    vertices
        .iter()
        .filter(|v| {
            let key = v.map(|x| (x / cell).round() as i64);
            seen.insert(key)
        })
        .map(|v| Vector3::new(v[0], v[1], v[2]))
        .collect()
}

/// A mesh read once: its file and scale (as bits).
type MeshKey = (std::path::PathBuf, [u64; 3]);

/// The outlines of the links `links` (at their poses) from `tree`'s shapes: each link's
/// visual shapes, or its collision shapes when it has no visual one; meshes read once per file
/// and scale. Returns them with the problems met (a mesh that cannot be read, named with its
/// link), which leave that shape out: a drawing never fails on the body.
pub fn outlines(tree: &screwkit_model::Tree, links: &[LinkMark]) -> (Vec<Outline>, Vec<String>) {
    let index: HashMap<&str, usize> = links
        .iter()
        .enumerate()
        .map(|(k, l)| (l.name.as_str(), k))
        .collect();
    let size = crate::scene::size_of(links);
    let mut problems = Vec::new();
    let mut meshes: HashMap<MeshKey, Option<Vec<Vector3<f64>>>> = HashMap::new();
    let on = |g: &&screwkit_model::geometry::Geometry| {
        tree.links
            .get(g.link)
            .and_then(|n| index.get(n.as_str()).copied())
    };
    let has_visual: std::collections::HashSet<usize> = tree
        .geometries
        .iter()
        .filter(|g| g.role == Role::Visual)
        .filter_map(|g| on(&g))
        .collect();
    let mut out = Vec::new();
    for g in &tree.geometries {
        let Some(link) = on(&g) else { continue };
        if g.role == Role::Collision && has_visual.contains(&link) {
            continue;
        }
        let local = match &g.shape {
            Shape::Mesh { path, scale, .. } => {
                let key = (path.clone(), scale.map(f64::to_bits));
                let m = meshes
                    .entry(key)
                    .or_insert_with(|| match screwkit_model::mesh::read_mesh(path, *scale) {
                        Ok(mesh) => Some(thin(&mesh.vertices, size * 5e-4)),
                        Err(e) => {
                            problems.push(format!("\"{}\": {e}", links[link].name));
                            None
                        }
                    });
                match m {
                    Some(points) => points.clone(),
                    None => continue,
                }
            }
            shape => match primitive(shape) {
                Some(points) => points,
                None => continue,
            },
        };
        let pose: Se3 = links[link].pose * g.origin;
        out.push(Outline {
            link,
            role: g.role,
            points: local.iter().map(|p| pose.transform_point(p)).collect(),
            rgba: g.rgba,
        });
    }
    (out, problems)
}

/// The convex hull of `points` counter-clockwise (in a y-up frame), by Andrew's monotone
/// chain: O(n log n), collinear points dropped; fewer than three distinct points give those.
pub fn hull(points: &[Vector2<f64>]) -> Vec<Vector2<f64>> {
    let mut p: Vec<Vector2<f64>> = points.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: &Vector2<f64>, a: &Vector2<f64>, b: &Vector2<f64>| {
        (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x)
    };
    let mut h: Vec<Vector2<f64>> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = h.len();
        let pts: Box<dyn Iterator<Item = &Vector2<f64>>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for q in pts {
            while h.len() >= start + 2 && cross(&h[h.len() - 2], &h[h.len() - 1], q) <= 0.0 {
                h.pop();
            }
            h.push(*q);
        }
        h.pop();
    }
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point is in the hull iff it is on the inner side of every edge (counter-clockwise).
    fn inside(h: &[Vector2<f64>], p: &Vector2<f64>) -> bool {
        (0..h.len()).all(|k| {
            let (a, b) = (h[k], h[(k + 1) % h.len()]);
            (b - a).perp(&(p - a)) >= -1e-12
        })
    }

    /// The hull holds every point, is convex and counter-clockwise, and each of its vertices
    /// is an input point that no other input point's hull without it holds (checked against
    /// the definition, by brute force on random clouds).
    #[test]
    fn the_hull_is_the_smallest_convex_polygon_holding_the_points() {
        let mut rng = screwkit_solve::sample::SplitMix64(7);
        let mut rand = || rng.uniform();
        for n in [3, 5, 20, 200] {
            let pts: Vec<Vector2<f64>> = (0..n)
                .map(|_| Vector2::new(rand() * 2.0 - 1.0, rand() * 2.0 - 1.0))
                .collect();
            let h = hull(&pts);
            assert!(h.len() >= 3);
            assert!(pts.iter().all(|p| inside(&h, p)), "n = {n}");
            for k in 0..h.len() {
                let (a, b, c) = (h[k], h[(k + 1) % h.len()], h[(k + 2) % h.len()]);
                assert!((b - a).perp(&(c - b)) > 0.0, "not convex at {k}");
                assert!(pts.contains(&b));
                let rest: Vec<Vector2<f64>> = h.iter().filter(|p| **p != b).copied().collect();
                assert!(!inside(&hull(&rest), &b), "vertex {k} is not needed");
            }
        }
        // Collinear and repeated points.
        let line: Vec<Vector2<f64>> = (0..5).map(|k| Vector2::new(k as f64, 0.0)).collect();
        assert_eq!(hull(&line).len(), 2);
        assert_eq!(hull(&[Vector2::new(1.0, 1.0); 4]).len(), 1);
    }

    /// A round shape's points lie on its surface, and their hull reaches its extent in every
    /// direction to within the ring spacing.
    #[test]
    fn round_shapes_are_sampled_on_their_surface() {
        let slack = 1.0 - (std::f64::consts::PI / RING as f64).cos();
        let cases = [
            (Shape::Sphere { radius: 0.2 }, [0.2, 0.2, 0.2]),
            (
                Shape::Ellipsoid {
                    radii: [0.1, 0.2, 0.3],
                },
                [0.1, 0.2, 0.3],
            ),
            (
                Shape::Capsule {
                    radius: 0.1,
                    length: 0.4,
                },
                [0.1, 0.1, 0.3],
            ),
            (
                Shape::Cylinder {
                    radius: 0.1,
                    length: 0.4,
                },
                [0.1, 0.1, 0.2],
            ),
        ];
        for (shape, extent) in cases {
            let pts = primitive(&shape).unwrap();
            for k in 0..3 {
                let max = pts.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
                let min = pts.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
                assert!(
                    (max - extent[k]).abs() <= slack * extent[k] + 1e-12,
                    "{shape:?}"
                );
                assert!(
                    (min + extent[k]).abs() <= slack * extent[k] + 1e-12,
                    "{shape:?}"
                );
            }
            if let Shape::Sphere { radius } = shape {
                assert!(pts.iter().all(|p| (p.norm() - radius).abs() < 1e-12));
            }
        }
        let b = primitive(&Shape::Box {
            size: [0.2, 0.4, 0.6],
        })
        .unwrap();
        assert_eq!(b.len(), 8);
        assert!(b
            .iter()
            .all(|p| (p.x.abs() - 0.1).abs() < 1e-15 && (p.z.abs() - 0.3).abs() < 1e-15));
        assert!(primitive(&Shape::Plane { size: [1.0, 1.0] }).is_none());
    }
}
