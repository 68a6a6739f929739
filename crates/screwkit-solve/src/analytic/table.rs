//! THE table of decompositions: for each, the family and arrangement of axes it takes, its
//! kernel, whether it is a closed form, and its words. [`method_of`] picks the first row that
//! applies; `closed_form`, `auto` and `describe` read the rows instead of listing methods.
//!
//! **Adding a decomposition**: write its kernel in a file of its own (the module
//! documentation says which subproblem gives which angle), add a [`Method`] variant and its
//! row in [`TABLE`] (before the rows it should win over), and tests against an independent
//! oracle (FK of every solution, a peer on real robots).

use super::*;

/// Which decomposition (module documentation), for the lines in the order solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Method {
    /// Spherical wrist, 2 ∥ 3.
    WristParallel,
    /// Spherical wrist, axes 1 and 2 meet.
    WristIntersecting12,
    /// Spherical wrist, axes 2 and 3 meet.
    WristIntersecting23,
    /// 2 ∥ 3 ∥ 4, axes 5 and 6 meet.
    ThreeParallel,
    /// Spherical wrist only (subproblem 5).
    Wrist,
    /// 2 ∥ 3 ∥ 4 only (subproblem 6).
    ThreeParallelGeneral,
    /// Axes 5 and 6 meeting only: a 1D search over θ₄ (subproblem 5 inside).
    Search56,
    /// Axes 2 ∥ 3 only: a 1D search over θ₁ (subproblem 6 inside).
    Search23,
}

/// The relations of six lines in the order solved, as the rows test them.
pub(super) struct Arrangement {
    /// i where axes i and i+1 are parallel (0-based).
    pub(super) parallel: Vec<usize>,
    /// i where axes i and i+1 meet.
    pub(super) intersecting: Vec<usize>,
}

impl Arrangement {
    #[inline]
    fn par(&self, i: usize) -> bool {
        self.parallel.contains(&i)
    }
    #[inline]
    fn int(&self, i: usize) -> bool {
        self.intersecting.contains(&i)
    }
}

/// A decomposition's kernel: every posture of the prepared problem for g (module
/// documentation of `analytic`), each emitted as six angles in the order solved and whether
/// every subproblem was exact; `singular` set when a free angle was chosen.
pub(super) type Kernel = fn(&Prepared, &Se3, &mut bool, &mut dyn FnMut([f64; 6], bool));

/// One row of the table.
pub(super) struct Decomposition {
    /// Its name in the code.
    pub(super) method: Method,
    /// The families it solves (as classified, lines in the order solved).
    pub(super) families: &'static [Family],
    /// Whether the arrangement of the lines is the one it takes.
    pub(super) applies: fn(&Arrangement) -> bool,
    /// The kernel.
    pub(super) kernel: Kernel,
    /// True for a closed form (every solution, µs); false for a sampled 1D search (ms, a root
    /// where the residual only touches zero may be missed).
    pub(super) closed_form: bool,
    /// What `screwkit info` says of it (`describe`).
    pub(super) words: &'static str,
    /// When it does not apply (and no later row does): what the chain gets instead.
    pub(super) fallback: &'static str,
}

/// Every decomposition, best first: closed forms before searches; within a family the more
/// specific arrangement first.
pub(super) const TABLE: &[Decomposition] = &[
    Decomposition {
        method: Method::WristParallel,
        families: &[Family::SphericalWristTwoParallel],
        applies: |_| true,
        kernel: |p, g, s, e| wrist_parallel(p, g, s, &mut &mut *e),
        closed_form: true,
        words: "closed form: subproblems 4, 3, 1, then the wrist",
        fallback: "numerical IK",
    },
    Decomposition {
        method: Method::WristIntersecting12,
        families: &[Family::SphericalWristTwoIntersecting],
        applies: |a| a.int(0),
        kernel: |p, g, s, e| wrist_intersecting(p, g, true, s, &mut &mut *e),
        closed_form: true,
        words: "closed form: axes 1-2 meet, subproblems 3, 2, then the wrist",
        fallback: "the 2-3 row",
    },
    Decomposition {
        method: Method::WristIntersecting23,
        families: &[Family::SphericalWristTwoIntersecting],
        applies: |_| true,
        kernel: |p, g, s, e| wrist_intersecting(p, g, false, s, &mut &mut *e),
        closed_form: true,
        words: "closed form: axes 2-3 meet, subproblems 3, 2, then the wrist",
        fallback: "numerical IK",
    },
    Decomposition {
        method: Method::ThreeParallel,
        families: &[Family::ThreeParallelTwoIntersecting],
        applies: |a| a.par(1) && a.par(2) && a.int(4),
        kernel: |p, g, s, e| three_parallel(p, g, false, s, &mut &mut *e),
        closed_form: true,
        words: "closed form: 2 ∥ 3 ∥ 4 and 5-6 meeting, subproblems 4, 4, 1, 3, 1",
        fallback: "the three-parallel row",
    },
    Decomposition {
        method: Method::ThreeParallelGeneral,
        families: &[Family::ThreeParallelTwoIntersecting, Family::ThreeParallel],
        applies: |a| a.par(1) && a.par(2),
        kernel: |p, g, s, e| three_parallel(p, g, true, s, &mut &mut *e),
        closed_form: true,
        words: "closed form: 2 ∥ 3 ∥ 4, subproblem 6, then the planar rest",
        fallback: "numerical IK",
    },
    Decomposition {
        method: Method::Wrist,
        families: &[Family::SphericalWrist],
        applies: |_| true,
        kernel: |p, g, s, e| wrist_only(p, g, s, &mut &mut *e),
        closed_form: true,
        words: "closed form: subproblem 5, then the wrist",
        fallback: "numerical IK",
    },
    Decomposition {
        method: Method::Search56,
        families: &[Family::TwoIntersecting],
        applies: |a| a.int(4),
        kernel: |p, g, _, e| search56(p, g, &mut &mut *e),
        closed_form: false,
        words: "1D search over θ4 (axes 5-6 meet)",
        fallback: "numerical IK (other placements of the intersecting pair are not solved)",
    },
    Decomposition {
        method: Method::Search23,
        families: &[Family::TwoParallel],
        applies: |a| a.par(1),
        kernel: |p, g, _, e| search23(p, g, &mut &mut *e),
        closed_form: false,
        words: "1D search over θ1 (axes 2 ∥ 3)",
        fallback: "numerical IK (other placements of the parallel pair are not solved)",
    },
];

/// The row of `method`.
#[inline]
pub(super) fn row(method: Method) -> &'static Decomposition {
    TABLE
        .iter()
        .find(|d| d.method == method)
        .expect("every method has a row")
}

/// What a chain of `family` gets when no row's arrangement holds (the last row's fallback).
#[inline]
pub(super) fn fallback(family: Family) -> &'static str {
    TABLE
        .iter()
        .rfind(|d| d.families.contains(&family))
        .map_or("numerical IK", |d| d.fallback)
}

/// True when some row solves `family` (in some arrangement).
#[inline]
pub(super) fn has_row(family: Family) -> bool {
    TABLE.iter().any(|d| d.families.contains(&family))
}

/// The decomposition the relations of six lines (in the order given) allow, if any: the
/// first row of [`TABLE`] (best first) for any family the lines are of whose arrangement
/// holds, with that family (an ABB IRB 140 whose axis 6 is offset from axis 4 is of the
/// two-intersecting family by axes 4–5, which no search takes, and of the two-parallel one by
/// axes 2 ∥ 3, which the 2 ∥ 3 search takes).
#[inline]
pub(super) fn method_of(lines: &[AxisLine], length: f64) -> Option<(Family, Method)> {
    let r = relations(lines, true, length);
    let a = Arrangement {
        parallel: r.parallel,
        intersecting: r.intersecting.iter().map(|&(j, _)| j).collect(),
    };
    TABLE.iter().find_map(|d| {
        let family = d.families.iter().find(|f| r.families.contains(f))?;
        (d.applies)(&a).then_some((*family, d.method))
    })
}

/// True when the first three lines and the last three each meet in a point: a 6R chain
/// with a spherical shoulder and a spherical wrist, whose reachable poses come with a
/// one-parameter self-motion (the iiwa with its elbow locked).
#[inline]
pub(super) fn shoulder_and_wrist(lines: &[AxisLine], length: f64) -> bool {
    let mut back = lines.to_vec();
    back.reverse();
    relations(lines, true, length).wrist_center.is_some()
        && relations(&back, true, length).wrist_center.is_some()
}

/// The family solved, the method and the reading (reversed: true) for six lines in chain
/// order, read forward or reversed: the more specialised family of the two (a closed form
/// before a search), forward on a tie.
#[inline]
pub(super) fn method_either(lines: &[AxisLine], length: f64) -> Option<(Family, Method, bool)> {
    let mut back = lines.to_vec();
    back.reverse();
    match (method_of(lines, length), method_of(&back, length)) {
        (Some((f, m)), Some((b, n))) => Some(if b < f { (b, n, true) } else { (f, m, false) }),
        (Some((f, m)), None) => Some((f, m, false)),
        (None, Some((b, n))) => Some((b, n, true)),
        (None, None) => None,
    }
}
