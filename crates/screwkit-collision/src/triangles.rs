//! The closest points of two triangles that do not intersect, exactly: the closest pair is a
//! vertex of one and its projection on the other, or the closest points of an edge of each
//! (Ericson, *Real-Time Collision Detection*, §5.1.9 and §5.1.5), so it is the best of the six
//! vertex–triangle and nine edge–edge candidates. GJK's answer on two triangles stops within
//! its tolerance (1e-5 relative on the Panda's meshes); this one is exact to rounding.

use nalgebra::Vector3;

type V = Vector3<f64>;

/// The point of segment [p, q] nearest to segment [r, s], and that of [r, s] (clamped
/// parameters; degenerate segments handled).
pub fn segments(p: &V, q: &V, r: &V, s: &V) -> (V, V) {
    let (d1, d2, w) = (q - p, s - r, p - r);
    let (a, e, f) = (d1.dot(&d1), d2.dot(&d2), d2.dot(&w));
    let eps = f64::EPSILON;
    let (t1, t2) = if a <= eps && e <= eps {
        (0.0, 0.0)
    } else if a <= eps {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(&w);
        if e <= eps {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut t1 = if denom > eps * a * e {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t2 = (b * t1 + f) / e;
            if t2 < 0.0 {
                t2 = 0.0;
                t1 = (-c / a).clamp(0.0, 1.0);
            } else if t2 > 1.0 {
                t2 = 1.0;
                t1 = ((b - c) / a).clamp(0.0, 1.0);
            }
            (t1, t2)
        }
    };
    (p + d1 * t1, r + d2 * t2)
}

/// The point of triangle (a, b, c) nearest to p (Ericson §5.1.5, by Voronoi regions).
pub(crate) fn point_triangle(p: &V, a: &V, b: &V, c: &V) -> V {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return *a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        return *b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        return *c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = va + vb + vc;
    if denom.abs() <= f64::MIN_POSITIVE {
        return *a;
    }
    a + ab * (vb / denom) + ac * (vc / denom)
}

/// True when segment [a, b] meets triangle `t` (touching counts): the segment crosses the
/// triangle's plane at a point inside it; a segment in the plane meets it when their distance
/// is zero (to 1e-12 of the triangle's size).
fn segment_meets(a: &V, b: &V, t: &[V; 3]) -> bool {
    let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
    let (da, db) = (n.dot(&(a - t[0])), n.dot(&(b - t[0])));
    if (da > 0.0 && db > 0.0) || (da < 0.0 && db < 0.0) {
        return false;
    }
    if da == db {
        // In the plane (da = db = 0), or a degenerate triangle (n = 0): by distance.
        let (p, q) = closest_segment(a, b, t);
        let scale = (t[1] - t[0]).norm().max((t[2] - t[0]).norm()).max(1e-300);
        return (q - p).norm() <= 1e-12 * scale;
    }
    let x = a + (b - a) * (da / (da - db));
    // Inside: x on the inner side of each edge (inclusive).
    (0..3).all(|k| {
        let (e0, e1) = (t[k], t[(k + 1) % 3]);
        (e1 - e0).cross(&(x - e0)).dot(&n) >= 0.0
    })
}

/// True when triangles `t1` and `t2` intersect (touching counts): two triangles meet exactly
/// when an edge of one meets the other (their intersection, a segment, ends on such edges);
/// first rejected when one lies strictly on one side of the other's plane.
pub fn intersect(t1: &[V; 3], t2: &[V; 3]) -> bool {
    let apart = |s: &[V; 3], t: &[V; 3]| {
        let n = (t[1] - t[0]).cross(&(t[2] - t[0]));
        let d = s.map(|v| n.dot(&(v - t[0])));
        (d[0] > 0.0 && d[1] > 0.0 && d[2] > 0.0) || (d[0] < 0.0 && d[1] < 0.0 && d[2] < 0.0)
    };
    if apart(t1, t2) || apart(t2, t1) {
        return false;
    }
    (0..3).any(|k| segment_meets(&t1[k], &t1[(k + 1) % 3], t2))
        || (0..3).any(|k| segment_meets(&t2[k], &t2[(k + 1) % 3], t1))
}

/// True when triangle `t` meets the box of half extents `h` centred at the origin of its frame
/// (`t` in that frame; touching counts): no separating axis among the box's three, the
/// triangle's normal and the nine products of a box axis and a triangle edge (Akenine-Möller's
/// test).
pub fn meets_box(h: &V, t: &[V; 3]) -> bool {
    // The box's axes.
    for k in 0..3 {
        let (lo, hi) = (
            t[0][k].min(t[1][k]).min(t[2][k]),
            t[0][k].max(t[1][k]).max(t[2][k]),
        );
        if lo > h[k] || hi < -h[k] {
            return false;
        }
    }
    let edges = [t[1] - t[0], t[2] - t[1], t[0] - t[2]];
    // The triangle's plane.
    let n = edges[0].cross(&edges[1]);
    if n.dot(&t[0]).abs() > n.abs().dot(h) {
        return false;
    }
    for e in &edges {
        for k in 0..3 {
            let mut axis = V::zeros();
            axis[k] = 1.0;
            let a = axis.cross(e);
            let p = [a.dot(&t[0]), a.dot(&t[1]), a.dot(&t[2])];
            let r = a.abs().dot(h);
            if p[0].min(p[1]).min(p[2]) > r || p[0].max(p[1]).max(p[2]) < -r {
                return false;
            }
        }
    }
    true
}

/// The penetration of two intersecting triangles: the smallest translation of `t2` that
/// separates them (the separating-axis theorem over the two normals and the nine edge
/// products, exact for two convex polygons), as (depth, unit normal n from t1 to t2, the point
/// of t1 furthest along n, the point of t2 furthest along −n); None when some axis separates
/// them.
pub fn penetration(t1: &[V; 3], t2: &[V; 3]) -> Option<(f64, V, V, V)> {
    let e1 = [t1[1] - t1[0], t1[2] - t1[1], t1[0] - t1[2]];
    let e2 = [t2[1] - t2[0], t2[2] - t2[1], t2[0] - t2[2]];
    let mut axes = [V::zeros(); 11];
    axes[0] = e1[0].cross(&e1[1]);
    axes[1] = e2[0].cross(&e2[1]);
    for i in 0..3 {
        for j in 0..3 {
            axes[2 + 3 * i + j] = e1[i].cross(&e2[j]);
        }
    }
    let scale = e1
        .iter()
        .chain(&e2)
        .map(|e| e.norm_squared())
        .fold(0.0, f64::max);
    let mut best: Option<(f64, V)> = None;
    for a in axes {
        let len2 = a.norm_squared();
        // Parallel edges (or a degenerate triangle) give no axis.
        if len2 <= 1e-24 * scale * scale {
            continue;
        }
        let u = a / len2.sqrt();
        let p1 = t1.map(|v| u.dot(&v));
        let p2 = t2.map(|v| u.dot(&v));
        let (lo1, hi1) = (p1[0].min(p1[1]).min(p1[2]), p1[0].max(p1[1]).max(p1[2]));
        let (lo2, hi2) = (p2[0].min(p2[1]).min(p2[2]), p2[0].max(p2[1]).max(p2[2]));
        let (forward, backward) = (hi1 - lo2, hi2 - lo1);
        if forward < 0.0 || backward < 0.0 {
            return None;
        }
        let (depth, n) = if forward <= backward {
            (forward, u)
        } else {
            (backward, -u)
        };
        if best.is_none_or(|(d, _)| depth < d) {
            best = Some((depth, n));
        }
    }
    let (depth, n) = best?;
    let furthest = |t: &[V; 3], d: &V| {
        *t.iter()
            .max_by(|a, b| d.dot(a).total_cmp(&d.dot(b)))
            .expect("three vertices")
    };
    Some((depth, n, furthest(t1, &n), furthest(t2, &-n)))
}

/// The closest pair of points among the candidates offered.
struct Best {
    pair: (V, V),
    squared: f64,
}

impl Best {
    fn new() -> Best {
        Best {
            pair: (V::zeros(), V::zeros()),
            squared: f64::INFINITY,
        }
    }

    /// Keeps (p, q) if it is closer than the best so far.
    fn consider(&mut self, p: V, q: V) {
        let d = (q - p).norm_squared();
        if d < self.squared {
            self.squared = d;
            self.pair = (p, q);
        }
    }
}

/// The closest points (on the first, on the second) of two triangles that do not intersect.
pub fn closest(t1: &[V; 3], t2: &[V; 3]) -> (V, V) {
    let mut best = Best::new();
    for v in t1 {
        best.consider(*v, point_triangle(v, &t2[0], &t2[1], &t2[2]));
    }
    for v in t2 {
        best.consider(point_triangle(v, &t1[0], &t1[1], &t1[2]), *v);
    }
    for i in 0..3 {
        for j in 0..3 {
            let (p, q) = segments(&t1[i], &t1[(i + 1) % 3], &t2[j], &t2[(j + 1) % 3]);
            best.consider(p, q);
        }
    }
    best.pair
}

/// The closest points (on the box, on the triangle) of a box of half extents `h` centred at
/// the origin of its frame and a triangle given in that frame, not intersecting: the best of
/// the triangle's vertices clamped into the box, the box's corners projected on the triangle,
/// and the closest points of each pair of edges (the features a closest pair of two convex
/// polytopes can be reduced to).
pub fn closest_box(h: &V, t: &[V; 3]) -> (V, V) {
    let mut best = Best::new();
    for v in t {
        let p = V::new(
            v.x.clamp(-h.x, h.x),
            v.y.clamp(-h.y, h.y),
            v.z.clamp(-h.z, h.z),
        );
        best.consider(p, *v);
    }
    let corner = |i: usize| {
        V::new(
            if i & 1 == 0 { -h.x } else { h.x },
            if i & 2 == 0 { -h.y } else { h.y },
            if i & 4 == 0 { -h.z } else { h.z },
        )
    };
    for i in 0..8 {
        let c = corner(i);
        best.consider(c, point_triangle(&c, &t[0], &t[1], &t[2]));
    }
    for i in 0..8usize {
        for bit in [1, 2, 4] {
            let j = i | bit;
            if j == i {
                continue;
            }
            let (c0, c1) = (corner(i), corner(j));
            for k in 0..3 {
                let (p, q) = segments(&c0, &c1, &t[k], &t[(k + 1) % 3]);
                best.consider(p, q);
            }
        }
    }
    best.pair
}

/// The corners of a box of half extents `h` centred at the origin, corner i's signs from its
/// bits (x: bit 0, y: bit 1, z: bit 2).
fn corner(h: &V, i: usize) -> V {
    V::new(
        if i & 1 == 0 { -h.x } else { h.x },
        if i & 2 == 0 { -h.y } else { h.y },
        if i & 4 == 0 { -h.z } else { h.z },
    )
}

/// The closest points (on box a, on box b; a's frame) of two boxes that do not intersect: a of
/// half extents `ha` centred at the origin, b of half extents `hb` at rotation `r` and centre
/// `p`. The closest pair of two convex polytopes is a vertex of one and its nearest point on
/// the other, or the closest points of an edge of each: the best of b's corners clamped into
/// a, a's corners clamped into b (in b's frame), and the 12 × 12 edge pairs.
pub fn closest_boxes(ha: &V, hb: &V, r: &nalgebra::Rotation3<f64>, p: &V) -> (V, V) {
    let mut best = Best::new();
    let clamp = |v: &V, h: &V| {
        V::new(
            v.x.clamp(-h.x, h.x),
            v.y.clamp(-h.y, h.y),
            v.z.clamp(-h.z, h.z),
        )
    };
    let b_corners: [V; 8] = std::array::from_fn(|i| r * corner(hb, i) + p);
    for c in &b_corners {
        best.consider(clamp(c, ha), *c);
    }
    for i in 0..8 {
        let c = corner(ha, i);
        // a's corner in b's frame, clamped into b, back in a's frame.
        let local = r.inverse() * (c - p);
        best.consider(c, r * clamp(&local, hb) + p);
    }
    let edges = |i: usize| {
        [1usize, 2, 4]
            .into_iter()
            .filter(move |bit| i & bit == 0)
            .map(move |bit| (i, i | bit))
    };
    for ia in 0..8 {
        for (a0, a1) in edges(ia) {
            let (pa, qa) = (corner(ha, a0), corner(ha, a1));
            for ib in 0..8 {
                for (b0, b1) in edges(ib) {
                    let (x, y) = segments(&pa, &qa, &b_corners[b0], &b_corners[b1]);
                    best.consider(x, y);
                }
            }
        }
    }
    best.pair
}

/// The point of the segment [a, b] and the point of triangle `t` closest to each other, when
/// they do not intersect: the segment's ends projected on the triangle, and the closest
/// points of the segment and each edge.
pub fn closest_segment(a: &V, b: &V, t: &[V; 3]) -> (V, V) {
    let mut best = Best::new();
    for e in [a, b] {
        best.consider(*e, point_triangle(e, &t[0], &t[1], &t[2]));
    }
    for k in 0..3 {
        let (p, q) = segments(a, b, &t[k], &t[(k + 1) % 3]);
        best.consider(p, q);
    }
    best.pair
}

#[cfg(test)]
mod intersect_tests {
    use super::*;

    /// Crossing, touching at a vertex, coplanar overlapping, apart, and parallel triangles.
    #[test]
    fn intersect_cases() {
        let t = [
            V::new(0.0, 0.0, 0.0),
            V::new(1.0, 0.0, 0.0),
            V::new(0.0, 1.0, 0.0),
        ];
        let cross = [
            V::new(0.2, 0.2, -1.0),
            V::new(0.2, 0.2, 1.0),
            V::new(0.9, 0.9, 0.0),
        ];
        assert!(intersect(&t, &cross) && intersect(&cross, &t));
        let touch = [
            V::new(1.0, 0.0, 0.0),
            V::new(2.0, 0.0, 1.0),
            V::new(2.0, 1.0, 1.0),
        ];
        assert!(intersect(&t, &touch));
        let coplanar = t.map(|v| v * 0.5 + V::new(0.2, 0.2, 0.0));
        assert!(intersect(&t, &coplanar));
        let apart = t.map(|v| v + V::new(0.0, 0.0, 1e-9));
        assert!(!intersect(&t, &apart));
        let beside = t.map(|v| v + V::new(1.2, 0.0, 0.0));
        assert!(!intersect(&t, &beside));
        // The box test: a triangle through a box with its corners outside, one beside it.
        let h = V::new(0.5, 0.5, 0.5);
        let through = [
            V::new(-2.0, -2.0, 0.1),
            V::new(3.0, -2.0, 0.1),
            V::new(0.0, 3.0, 0.1),
        ];
        assert!(meets_box(&h, &through));
        let over = through.map(|v| v + V::new(0.0, 0.0, 0.41));
        assert!(!meets_box(&h, &over));
        // Across a corner: the triangle's points come within 0.028 of the box (sampled finely
        // in numpy: max |p_k| − 0.5 ≥ 0.0277 over it), or 0.045 into it when moved back.
        let corner = [
            V::new(0.95, 0.05, 0.6),
            V::new(0.05, 0.95, 0.6),
            V::new(0.95, 0.95, -0.6),
        ];
        assert!(!meets_box(&h, &corner));
        assert!(meets_box(&h, &corner.map(|v| v - V::new(0.1, 0.1, 0.0))));
        // A triangle through the other's interior, its edges around it (the second one's edges
        // cross the first).
        let big = [
            V::new(0.3, 0.3, -5.0),
            V::new(0.3, 0.3, 5.0),
            V::new(0.3, -9.0, 0.0),
        ];
        assert!(intersect(&t, &big));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against brute force: the minimum over a fine grid of barycentric points of both
    /// triangles is never below the exact answer, and comes within the grid's resolution.
    #[test]
    fn closest_points_of_random_triangles() {
        let mut rng = screwkit_solve::sample::SplitMix64(0x7A1A_0001);
        let mut v = || V::new(rng.uniform(), rng.uniform(), rng.uniform());
        let grid = |t: &[V; 3]| -> Vec<V> {
            let n = 40;
            let mut out = Vec::new();
            for i in 0..=n {
                for j in 0..=n - i {
                    let (u, w) = (i as f64 / n as f64, j as f64 / n as f64);
                    out.push(t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * w);
                }
            }
            out
        };
        for case in 0..60 {
            let t1 = [v(), v(), v()];
            let shift = V::new(1.5, 0.2 * (case % 3) as f64, 0.0);
            let t2 = [v() + shift, v() + shift, v() + shift];
            let (p, q) = closest(&t1, &t2);
            let exact = (q - p).norm();
            let (g1, g2) = (grid(&t1), grid(&t2));
            let mut brute = f64::INFINITY;
            for a in &g1 {
                for b in &g2 {
                    brute = brute.min((b - a).norm());
                }
            }
            assert!(exact <= brute + 1e-12, "{case}: {exact} > {brute}");
            assert!(brute - exact < 0.05, "{case}: {exact} far below {brute}");
            // The points lie on their triangles: each is its own projection.
            assert!((point_triangle(&p, &t1[0], &t1[1], &t1[2]) - p).norm() < 1e-12);
            assert!((point_triangle(&q, &t2[0], &t2[1], &t2[2]) - q).norm() < 1e-12);
        }
    }
}
