//! Distances between triangle meshes (and from a mesh to a box, sphere or capsule), exactly and
//! fast: each mesh keeps a tree of bounding boxes over its triangles (built once), and the
//! distance is a depth-first search over pairs of nodes, the nearer pair of children first,
//! that skips every pair whose bound is no better than the closest pair of triangles found so
//! far (branch and bound, as coal traverses its BVHs). A node of the other mesh is bounded in the first
//! mesh's frame by the box that holds its turned box (centre R c + p, half extents |R| h: one
//! matrix product), so a pair of nodes costs two products and a box distance. The leaves'
//! triangles are compared by the exact closest-feature formulas of [`crate::triangles`].
//!
//! Only for shapes that do not intersect (the caller tests that first): the formulas assume it.

use nalgebra::{Matrix3, Vector3};

use crate::triangles;

type V = Vector3<f64>;

/// Triangles per leaf at most.
const LEAF: usize = 8;

#[derive(Debug, Clone)]
struct Node {
    /// The centre of the node's bounding box (the mesh's frame).
    center: V,
    /// Its half extents.
    half: V,
    /// The node's triangles: `first..first + count` of the ordered list.
    first: u32,
    count: u32,
    /// The two children (`u32::MAX` for a leaf).
    children: [u32; 2],
}

/// A mesh's tree of bounding boxes (in the mesh's frame).
#[derive(Debug, Clone)]
pub struct BoxTree {
    nodes: Vec<Node>,
    triangles: Vec<[V; 3]>,
}

fn bound(tris: &[[V; 3]]) -> (V, V) {
    let mut lo = V::repeat(f64::INFINITY);
    let mut hi = V::repeat(f64::NEG_INFINITY);
    for t in tris {
        for v in t {
            lo = lo.inf(v);
            hi = hi.sup(v);
        }
    }
    ((lo + hi) / 2.0, (hi - lo) / 2.0)
}

impl BoxTree {
    /// The tree of a mesh's triangles (vertices in the mesh's frame).
    pub fn new(mut triangles: Vec<[V; 3]>) -> BoxTree {
        let mut nodes = Vec::with_capacity(2 * triangles.len() / LEAF + 1);
        build(&mut nodes, &mut triangles, 0);
        BoxTree { nodes, triangles }
    }
}

/// Builds the node of `tris[..]` (which starts at `offset` in the whole list) and its
/// subtree; returns its index.
fn build(nodes: &mut Vec<Node>, tris: &mut [[V; 3]], offset: usize) -> u32 {
    let (center, half) = bound(tris);
    let index = nodes.len() as u32;
    nodes.push(Node {
        center,
        half,
        first: offset as u32,
        count: tris.len() as u32,
        children: [u32::MAX; 2],
    });
    if tris.len() > LEAF {
        // Split at the median centroid along the widest axis of the centroids.
        let centroid = |t: &[V; 3]| (t[0] + t[1] + t[2]) / 3.0;
        let mut lo = V::repeat(f64::INFINITY);
        let mut hi = V::repeat(f64::NEG_INFINITY);
        for t in tris.iter() {
            let c = centroid(t);
            lo = lo.inf(&c);
            hi = hi.sup(&c);
        }
        let axis = (hi - lo).imax();
        let mid = tris.len() / 2;
        tris.select_nth_unstable_by(mid, |a, b| centroid(a)[axis].total_cmp(&centroid(b)[axis]));
        let (left, right) = tris.split_at_mut(mid);
        let l = build(nodes, left, offset);
        let r = build(nodes, right, offset + mid);
        nodes[index as usize].children = [l, r];
    }
    index
}

/// What a mesh is measured against.
pub enum Other<'a> {
    /// Another mesh's tree, at the relative pose (rotation, translation) of its frame in the
    /// first mesh's.
    Mesh(&'a BoxTree, Matrix3<f64>, V),
    /// A box of half extents `h` at the relative pose (rotation, translation) of its frame in
    /// the mesh's.
    Box(V, Matrix3<f64>, V),
    /// A sphere or capsule: its axis segment's ends (in the mesh's frame) and radius.
    Swept(V, V, f64),
}

/// A triangle's bounding box (lowest, highest corner).
fn box_of(t: &[V; 3]) -> (V, V) {
    (t[0].inf(&t[1]).inf(&t[2]), t[0].sup(&t[1]).sup(&t[2]))
}

/// A pair of nodes to visit, with the lower bound of their distance.
struct Pending(f64, u32, u32);

/// Pushes the two child pairs that can still beat `best`, the nearer last (so it is visited
/// first: depth first, nearest first).
fn push_nearer_last(stack: &mut Vec<Pending>, x: Pending, y: Pending, best: f64) {
    let (near, far) = if y.0 < x.0 { (y, x) } else { (x, y) };
    if far.0 < best {
        stack.push(far);
    }
    if near.0 < best {
        stack.push(near);
    }
}

/// The closest points (on the mesh, on the other shape), in the mesh's frame, of a mesh and a
/// shape that do not intersect, and their distance.
pub fn closest(tree: &BoxTree, other: &Other<'_>) -> (V, V, f64) {
    let mut best = (V::zeros(), V::zeros(), f64::INFINITY);
    let mut stack: Vec<Pending> = Vec::with_capacity(64);
    // A box of the other side in the mesh's frame: centre R c + p, half extents |R| h (the box
    // that holds the turned one).
    let (rot, p) = match other {
        Other::Mesh(_, r, p) | Other::Box(_, r, p) => (*r, *p),
        Other::Swept(..) => (Matrix3::identity(), V::zeros()),
    };
    let abs = rot.abs();
    let placed = |c: &V, h: &V| (rot * c + p, abs * h);
    // The other shape's whole box (a primitive is one node, index 0).
    let (oc, oh) = match other {
        Other::Mesh(t, ..) => placed(&t.nodes[0].center, &t.nodes[0].half),
        Other::Box(h, ..) => placed(&V::zeros(), h),
        Other::Swept(a, b, r) => ((a + b) / 2.0, (b - a).abs() / 2.0 + V::repeat(*r)),
    };
    let bound = |a: &Node, c: &V, h: &V| {
        let gap = ((a.center - c).abs() - a.half - h).sup(&V::zeros());
        gap.norm()
    };
    stack.push(Pending(bound(&tree.nodes[0], &oc, &oh), 0, 0));
    while let Some(Pending(lb, ia, ib)) = stack.pop() {
        // (A stack is not sorted: a pair beaten since it was pushed is skipped, not the rest.)
        if lb >= best.2 {
            continue;
        }
        let a = &tree.nodes[ia as usize];
        let a_leaf = a.children[0] == u32::MAX;
        match other {
            Other::Mesh(t, ..) => {
                let b = &t.nodes[ib as usize];
                let b_leaf = b.children[0] == u32::MAX;
                if a_leaf && b_leaf {
                    // The leaf's few triangles placed in this mesh's frame, with their boxes,
                    // on the stack.
                    let mut placed_b = [((V::zeros(), V::zeros()), [V::zeros(); 3]); LEAF];
                    let nb = b.count as usize;
                    for (slot, tb) in placed_b
                        .iter_mut()
                        .zip(&t.triangles[b.first as usize..b.first as usize + nb])
                    {
                        let tb = tb.map(|v| rot * v + p);
                        *slot = (box_of(&tb), tb);
                    }
                    for ta in &tree.triangles[a.first as usize..(a.first + a.count) as usize] {
                        let box_a = box_of(ta);
                        for (box_b, tb) in &placed_b[..nb] {
                            // The triangles' boxes first: no closer than the best, no test.
                            let gap = (box_b.0 - box_a.1)
                                .sup(&(box_a.0 - box_b.1))
                                .sup(&V::zeros());
                            if gap.norm_squared() >= best.2 * best.2 {
                                continue;
                            }
                            let (x, y) = triangles::closest(ta, tb);
                            let d = (y - x).norm();
                            if d < best.2 {
                                best = (x, y, d);
                            }
                        }
                    }
                } else if !a_leaf && (b_leaf || a.half.norm_squared() >= b.half.norm_squared()) {
                    let (cb, hb) = placed(&b.center, &b.half);
                    let [l, r] = a.children;
                    push_nearer_last(
                        &mut stack,
                        Pending(bound(&tree.nodes[l as usize], &cb, &hb), l, ib),
                        Pending(bound(&tree.nodes[r as usize], &cb, &hb), r, ib),
                        best.2,
                    );
                } else {
                    let [l, r] = b.children;
                    let (cl, hl) = placed(&t.nodes[l as usize].center, &t.nodes[l as usize].half);
                    let (cr, hr) = placed(&t.nodes[r as usize].center, &t.nodes[r as usize].half);
                    push_nearer_last(
                        &mut stack,
                        Pending(bound(a, &cl, &hl), ia, l),
                        Pending(bound(a, &cr, &hr), ia, r),
                        best.2,
                    );
                }
            }
            _ if !a_leaf => {
                let [l, r] = a.children;
                push_nearer_last(
                    &mut stack,
                    Pending(bound(&tree.nodes[l as usize], &oc, &oh), l, 0),
                    Pending(bound(&tree.nodes[r as usize], &oc, &oh), r, 0),
                    best.2,
                );
            }
            _ => {
                for ta in &tree.triangles[a.first as usize..(a.first + a.count) as usize] {
                    let (x, y) = match other {
                        Other::Box(h, ..) => {
                            // The triangle in the box's frame, the points back.
                            let local = ta.map(|v| rot.transpose() * (v - p));
                            let (on_box, on_tri) = triangles::closest_box(h, &local);
                            (rot * on_tri + p, rot * on_box + p)
                        }
                        Other::Swept(s0, s1, r) => {
                            let (on_axis, on_tri) = triangles::closest_segment(s0, s1, ta);
                            let d = on_tri - on_axis;
                            let len = d.norm();
                            let surface = if len > 0.0 {
                                on_axis + d * (r / len)
                            } else {
                                on_axis
                            };
                            (on_tri, surface)
                        }
                        Other::Mesh(..) => unreachable!("handled above"),
                    };
                    let d = (y - x).norm();
                    if d < best.2 {
                        best = (x, y, d);
                    }
                }
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn random_mesh(rng: &mut screwkit_solve::sample::SplitMix64, n: usize, at: V) -> Vec<[V; 3]> {
        let mut v = || V::new(rng.uniform(), rng.uniform(), rng.uniform()) * 0.3;
        (0..n)
            .map(|_| {
                let base = v() + at;
                [base, base + v() * 0.3, base + v() * 0.3]
            })
            .collect()
    }

    /// Against every pair of triangles: the same distance, points on their triangles.
    #[test]
    fn equals_every_pair() {
        let mut rng = screwkit_solve::sample::SplitMix64(0x5FE2_0001);
        for case in 0..20 {
            let a = random_mesh(&mut rng, 60 + case, V::zeros());
            let b = random_mesh(&mut rng, 40 + 3 * case, V::new(1.2, 0.1 * case as f64, 0.0));
            let rot =
                nalgebra::Rotation3::from_euler_angles(0.3 * case as f64, -0.2, 0.7).into_inner();
            let p = V::new(0.1, -0.2, 0.05 * case as f64);
            let ta = BoxTree::new(a.clone());
            let tb = BoxTree::new(b.clone());
            let (x, y, d) = closest(&ta, &Other::Mesh(&tb, rot, p));
            let mut brute = f64::INFINITY;
            for s in &a {
                for t in &b {
                    let t = t.map(|v| rot * v + p);
                    let (u, w) = triangles::closest(s, &t);
                    brute = brute.min((w - u).norm());
                }
            }
            assert_eq!(d, brute, "{case}");
            assert!(((y - x).norm() - d).abs() < 1e-15);
        }
    }
}
