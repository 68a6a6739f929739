//! Which analytic-IK family a chain belongs to, read from its screw axes at home (never from
//! names): which consecutive revolute axes are parallel, which intersect and where, whether the
//! last three meet in one point (a spherical wrist). The families are those of subproblem
//! decomposition (Elias & Wen, IK-Geo, 2025; Ostermeier et al., EAIK, 2025).
//!
//! Tolerances: two axes are parallel when ‖ω_i × ω_j‖ ≤ 1e-9; two non-parallel axes intersect
//! when the distance between their lines is ≤ 1e-9 · L (L = [`Kinematics::length_scale`]);
//! three axes meet in a point when each pair intersects and the intersection points agree to
//! 1e-9 · L. Files that write π/2 rounded (1.57079632679) stay within these.

use nalgebra::Vector3;

use crate::kinematics::Kinematics;

/// An axis line: a unit direction and the point of the line closest to the base origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisLine {
    /// Unit direction ω.
    pub direction: Vector3<f64>,
    /// The point of the line nearest the base origin, ω × v.
    pub point: Vector3<f64>,
}

/// The analytic-IK family of a chain. Families are listed from the most to the least
/// specialised; a chain whose *reversed* order (tip to base) is of an earlier family than the
/// chain itself is classified by the reversed order ([`Classification::reversed`]): a
/// spherical shoulder is a spherical wrist seen from the tip.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Family {
    /// 6R, spherical wrist (axes 4, 5, 6 meet), axes 2 ∥ 3 (KUKA KR, ABB IRB, PUMA-type):
    /// closed form (subproblems 4, 3, 1 and the wrist), up to 8 solutions.
    SphericalWristTwoParallel,
    /// 6R, spherical wrist, axes 1–2 or 2–3 intersecting (a 7R arm with a spherical shoulder
    /// and one joint locked): closed form (subproblems 3, 2 and the wrist), up to 8 solutions.
    SphericalWristTwoIntersecting,
    /// 6R, three consecutive parallel axes and two other intersecting ones (UR-type): closed
    /// form, up to 8 solutions.
    ThreeParallelTwoIntersecting,
    /// 6R, spherical wrist only: closed form through a quartic (subproblem 5), up to 8.
    SphericalWrist,
    /// 6R, three consecutive parallel axes: closed form through a quartic (subproblem 6), up
    /// to 8 solutions.
    ThreeParallel,
    /// 6R, two consecutive intersecting axes (no closed form): the general 6R's elimination,
    /// up to 16 solutions.
    TwoIntersecting,
    /// 6R, two consecutive parallel axes (no closed form): the general 6R's elimination, up
    /// to 16 solutions.
    TwoParallel,
    /// 6R with none of the above: algebraic elimination (Raghavan–Roth), up to 16 solutions.
    General6R,
    /// A 7R chain: lock one joint (the caller's value, or swept) to make it a 6R one.
    Redundant7R,
    /// Anything else (fewer or more joints, prismatic, helical or mimic joints): numerical IK
    /// only.
    NotAnalytic,
}

impl Family {
    /// Every family, in the order of the enum (most specialised first).
    pub const ALL: [Family; 10] = [
        Family::SphericalWristTwoParallel,
        Family::SphericalWristTwoIntersecting,
        Family::ThreeParallelTwoIntersecting,
        Family::SphericalWrist,
        Family::ThreeParallel,
        Family::TwoIntersecting,
        Family::TwoParallel,
        Family::General6R,
        Family::Redundant7R,
        Family::NotAnalytic,
    ];

    /// The family's word in the JSON contract (`"family"` of `screwkit ik --all`, `info`): a
    /// lower-case identifier that stays when the enum is renamed. Listed in docs/guide/json.md.
    pub fn word(self) -> &'static str {
        match self {
            Family::SphericalWristTwoParallel => "spherical_wrist_two_parallel",
            Family::SphericalWristTwoIntersecting => "spherical_wrist_two_intersecting",
            Family::ThreeParallelTwoIntersecting => "three_parallel_two_intersecting",
            Family::SphericalWrist => "spherical_wrist",
            Family::ThreeParallel => "three_parallel",
            Family::TwoIntersecting => "two_intersecting",
            Family::TwoParallel => "two_parallel",
            Family::General6R => "general_6r",
            Family::Redundant7R => "redundant_7r",
            Family::NotAnalytic => "not_analytic",
        }
    }

    /// The family in words, with what it means for IK (and what screwkit does with it:
    /// [`crate::analytic`] solves the five closed forms and, for every other 6R, the general
    /// 6R's elimination; [`crate::analytic::describe`] says which a chain gets).
    pub fn describe(self) -> &'static str {
        match self {
            Family::SphericalWristTwoParallel => {
                "spherical wrist, axes 2 ∥ 3: closed form, up to 8 solutions"
            }
            Family::SphericalWristTwoIntersecting => {
                "spherical wrist, two intersecting axes: closed form, up to 8 solutions"
            }
            Family::ThreeParallelTwoIntersecting => {
                "three parallel axes and two intersecting: closed form, up to 8 solutions"
            }
            Family::SphericalWrist => {
                "spherical wrist only: closed form by a quartic (subproblem 5), up to 8 \
                 solutions"
            }
            Family::ThreeParallel => {
                "three parallel axes: closed form by a quartic (subproblem 6), up to 8 solutions"
            }
            Family::TwoIntersecting => "two intersecting axes, no closed form: up to 16 solutions",
            Family::TwoParallel => "two parallel axes, no closed form: up to 16 solutions",
            Family::General6R => {
                "general 6R (no two consecutive axes parallel or meeting): up to 16 solutions"
            }
            Family::Redundant7R => "7R (redundant): analytic with one joint locked",
            Family::NotAnalytic => "no analytic solver: numerical IK only",
        }
    }
}

/// What the classification found: the family and the relations between consecutive axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Classification {
    /// The family.
    pub family: Family,
    /// The axis lines at home (space frame), one per joint.
    pub axes: Vec<AxisLine>,
    /// Pairs (i, i + 1) (0-based) of parallel consecutive axes.
    pub parallel: Vec<usize>,
    /// Pairs (i, i + 1) of intersecting consecutive axes, with the intersection point.
    pub intersecting: Vec<(usize, Vector3<f64>)>,
    /// The point where the last three axes meet, if they do.
    pub wrist_center: Option<Vector3<f64>>,
    /// True when the family is that of the chain read from tip to base (axis 6 first): the
    /// analytic solver then solves T⁻¹ = e^[−Ad_M⁻¹ S₆]θ₆ ⋯ e^[−Ad_M⁻¹ S₁]θ₁ M⁻¹.
    pub reversed: bool,
}

const PARALLEL: f64 = 1e-9;
const MEET: f64 = 1e-9;

/// The point where two non-parallel lines meet (the midpoint of their common perpendicular)
/// and the distance between them.
pub fn closest_points(a: &AxisLine, b: &AxisLine) -> (Vector3<f64>, f64) {
    let n = a.direction.cross(&b.direction);
    let n2 = n.norm_squared();
    let d = b.point - a.point;
    let s = d.cross(&b.direction).dot(&n) / n2;
    let t = d.cross(&a.direction).dot(&n) / n2;
    let pa = a.point + a.direction * s;
    let pb = b.point + b.direction * t;
    ((pa + pb) / 2.0, (pa - pb).norm())
}

/// The axis lines of the space screws at home, one per joint.
pub fn axis_lines(kin: &Kinematics) -> Vec<AxisLine> {
    kin.space
        .iter()
        .map(|j| {
            let s = j.twist();
            AxisLine {
                direction: s.w.normalize(),
                point: s.w.cross(&s.v) / s.w.norm_squared(),
            }
        })
        .collect()
}

/// Classifies a chain from its space screw axes at home.
pub fn classify(kin: &Kinematics) -> Classification {
    let all_revolute = kin.space.iter().all(|j| j.is_revolute()) && kin.identity_map;
    let mut c = classify_axes(axis_lines(kin), all_revolute, kin.length_scale);
    // A 6R arm whose Jacobian has rank < 6 at every configuration (six parallel axes, two
    // coincident ones) reaches each pose it reaches along a self-motion: no finite solution
    // set for a closed form to list ([`generic_rank`]).
    if c.family != Family::NotAnalytic && kin.dof() == 6 && generic_rank(kin) < 6 {
        c.family = Family::NotAnalytic;
    }
    c
}

/// The rank of the space Jacobian at a generic configuration: the largest over three seeded
/// configurations within the limits, counting singular values above [`GENERIC_RANK_TOLERANCE`]
/// σ₁ (a geometric tolerance: axes written parallel or coincident with rounded numbers, six
/// decimals say, leave σ_min near 1e-6 σ₁, which the analysis's machine-precision rank counts).
/// Below the number of joints everywhere, the chain has a self-motion at every pose it
/// reaches (the rank theorem: an (n − r)-dimensional family of solutions through each one).
pub fn generic_rank(kin: &Kinematics) -> usize {
    let n = kin.dof();
    let qs = crate::sample::configurations(kin, 3, 0x5eed);
    let mut ws = crate::workspace::Workspace::new(kin);
    qs.chunks(n.max(1))
        .filter_map(|q| {
            let j = crate::jacobian::jacobian(kin, &mut ws, q, crate::Frame::Space).ok()?;
            let s = crate::analysis::analyze_jacobian(j).ok()?.singular_values;
            let largest = s.iter().fold(0.0f64, |m, x| m.max(*x));
            Some(
                s.iter()
                    .filter(|&&x| x > GENERIC_RANK_TOLERANCE * largest)
                    .count(),
            )
        })
        .max()
        .unwrap_or(0)
}

/// Singular values at most this fraction of the largest count as zero in [`generic_rank`].
pub const GENERIC_RANK_TOLERANCE: f64 = 1e-5;

/// Classifies axis lines (in chain order) of a chain whose joints are all revolute or not
/// (`all_revolute`), with length scale `length` for the tolerances: the family of the lines
/// or, when that of the reversed order is more specialised, the reversed one's.
pub fn classify_axes(axes: Vec<AxisLine>, all_revolute: bool, length: f64) -> Classification {
    let forward = relations(&axes, all_revolute, length);
    if forward.family == Family::SphericalWristTwoParallel || axes.len() != 6 || !all_revolute {
        return classification(axes, forward, false);
    }
    let mut back = axes.clone();
    back.reverse();
    let backward = relations(&back, all_revolute, length);
    if backward.family < forward.family {
        let family = backward.family;
        let mut c = classification(axes, forward, true);
        c.family = family;
        c
    } else {
        classification(axes, forward, false)
    }
}

/// What [`relations`] finds in lines taken in one order.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Relations {
    /// Their family (the most specialised of `families`).
    pub(crate) family: Family,
    /// Every family whose condition they meet (a chain of two parallel and two intersecting
    /// axes is of both families), the most specialised first.
    pub(crate) families: Vec<Family>,
    /// i where lines i and i+1 are parallel (0-based).
    pub(crate) parallel: Vec<usize>,
    /// i where lines i and i+1 meet, and where.
    pub(crate) intersecting: Vec<(usize, Vector3<f64>)>,
    /// Where the last three meet, if they do.
    pub(crate) wrist_center: Option<Vector3<f64>>,
}

fn classification(axes: Vec<AxisLine>, r: Relations, reversed: bool) -> Classification {
    Classification {
        family: r.family,
        axes,
        parallel: r.parallel,
        intersecting: r.intersecting,
        wrist_center: r.wrist_center,
        reversed,
    }
}

/// The family of lines in the order given, with the parallel and intersecting consecutive
/// pairs and the wrist center.
pub(crate) fn relations(axes: &[AxisLine], all_revolute: bool, l: f64) -> Relations {
    let parallel_pair =
        |i: usize, j: usize| axes[i].direction.cross(&axes[j].direction).norm() <= PARALLEL;
    let meet = |i: usize, j: usize| -> Option<Vector3<f64>> {
        if parallel_pair(i, j) {
            return None;
        }
        let (p, d) = closest_points(&axes[i], &axes[j]);
        (d <= MEET * l).then_some(p)
    };
    let n = axes.len();
    let parallel: Vec<usize> = if all_revolute {
        (0..n.saturating_sub(1))
            .filter(|&i| parallel_pair(i, i + 1))
            .collect()
    } else {
        Vec::new()
    };
    let intersecting: Vec<(usize, Vector3<f64>)> = if all_revolute {
        (0..n.saturating_sub(1))
            .filter_map(|i| meet(i, i + 1).map(|p| (i, p)))
            .collect()
    } else {
        Vec::new()
    };
    let wrist_center = if all_revolute && n >= 3 {
        // Axes 4 and 5 meet at p, 5 and 6 at q, and p = q (axes 4 and 6 may be collinear at
        // home, as in most wrists).
        let (a, b, c) = (n - 3, n - 2, n - 1);
        match (meet(a, b), meet(b, c)) {
            (Some(p), Some(q)) if (p - q).norm() <= MEET * l => Some((p + q) / 2.0),
            _ => None,
        }
    } else {
        None
    };
    let is_par = |i: usize| parallel.contains(&i);
    let is_int = |i: usize| intersecting.iter().any(|&(j, _)| j == i);
    let three_parallel = (0..n.saturating_sub(2)).any(|i| is_par(i) && is_par(i + 1));
    let wrist = wrist_center.is_some();
    // Every family whose condition the lines meet, the most specialised first.
    let families: Vec<Family> = match (all_revolute, n) {
        (true, 6) => [
            (Family::SphericalWristTwoParallel, wrist && is_par(1)),
            (
                Family::SphericalWristTwoIntersecting,
                wrist && (is_int(0) || is_int(1)),
            ),
            (
                Family::ThreeParallelTwoIntersecting,
                three_parallel && !intersecting.is_empty(),
            ),
            (Family::SphericalWrist, wrist),
            (Family::ThreeParallel, three_parallel),
            (Family::TwoIntersecting, !intersecting.is_empty()),
            (Family::TwoParallel, !parallel.is_empty()),
            (Family::General6R, true),
        ]
        .into_iter()
        .filter_map(|(f, holds)| holds.then_some(f))
        .collect(),
        (true, 7) => vec![Family::Redundant7R],
        _ => vec![Family::NotAnalytic],
    };
    Relations {
        family: families[0],
        families,
        parallel,
        intersecting,
        wrist_center,
    }
}
