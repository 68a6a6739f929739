//! THE table of decompositions: for each, the family and arrangement of axes it takes, its
//! kernel and its words. [`method_of`] picks the first row that applies (the general 6R, last,
//! applies to every six revolute axes); `auto` and `describe` read the rows instead of
//! listing methods.
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
    /// Any six revolute axes: algebraic elimination (Raghavan–Roth), a 24 × 24 eigenproblem.
    General,
    /// A 7R arm with a spherical shoulder and wrist at an arm angle (`arm_angle.rs`; not a
    /// row of the table: [`AnalyticIk::arm_angle`] builds it).
    ArmAngle,
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
    /// What `screwkit info` says of it (`describe`).
    pub(super) words: &'static str,
}

/// Every family of six revolute axes (the families before `Redundant7R` in [`Family::ALL`]).
const SIX_R: &[Family] = Family::ALL.split_at(8).0;

/// Every decomposition, best first: the closed forms of the special families (within a family
/// the more specific arrangement first), then the general 6R, which applies to any six
/// revolute axes (algebraic, every solution, tens of µs).
pub(super) const TABLE: &[Decomposition] = &[
    Decomposition {
        method: Method::WristParallel,
        families: &[Family::SphericalWristTwoParallel],
        applies: |_| true,
        kernel: |p, g, s, e| wrist_parallel(p, g, s, &mut &mut *e),
        words: "closed form: subproblems 4, 3, 1, then the wrist",
    },
    Decomposition {
        method: Method::WristIntersecting12,
        families: &[Family::SphericalWristTwoIntersecting],
        applies: |a| a.int(0),
        kernel: |p, g, s, e| wrist_intersecting(p, g, true, s, &mut &mut *e),
        words: "closed form: axes 1-2 meet, subproblems 3, 2, then the wrist",
    },
    Decomposition {
        method: Method::WristIntersecting23,
        families: &[Family::SphericalWristTwoIntersecting],
        applies: |_| true,
        kernel: |p, g, s, e| wrist_intersecting(p, g, false, s, &mut &mut *e),
        words: "closed form: axes 2-3 meet, subproblems 3, 2, then the wrist",
    },
    Decomposition {
        method: Method::ThreeParallel,
        families: &[Family::ThreeParallelTwoIntersecting],
        applies: |a| a.par(1) && a.par(2) && a.int(4),
        kernel: |p, g, s, e| three_parallel(p, g, false, s, &mut &mut *e),
        words: "closed form: 2 ∥ 3 ∥ 4 and 5-6 meeting, subproblems 4, 4, 1, 3, 1",
    },
    Decomposition {
        method: Method::ThreeParallelGeneral,
        families: &[Family::ThreeParallelTwoIntersecting, Family::ThreeParallel],
        applies: |a| a.par(1) && a.par(2),
        kernel: |p, g, s, e| three_parallel(p, g, true, s, &mut &mut *e),
        words: "closed form: 2 ∥ 3 ∥ 4, subproblem 6, then the planar rest",
    },
    Decomposition {
        method: Method::Wrist,
        families: &[Family::SphericalWrist],
        applies: |_| true,
        kernel: |p, g, s, e| wrist_only(p, g, s, &mut &mut *e),
        words: "closed form: subproblem 5, then the wrist",
    },
    Decomposition {
        method: Method::General,
        // Every 6R family: what no closed form above takes (two intersecting or two
        // parallel axes anywhere, three parallel axes 1 ∥ 2 ∥ 3, the general 6R).
        families: SIX_R,
        applies: |_| true,
        kernel: |p, g, s, e| general(p, g, s, &mut &mut *e),
        words: "algebraic elimination (Raghavan–Roth): a 24 × 24 eigenproblem, up to 16 \
                solutions, each polished by Newton steps",
    },
];

/// The row of `method` (every method but [`Method::ArmAngle`], which the solver handles
/// itself).
#[inline]
pub(super) fn row(method: Method) -> &'static Decomposition {
    TABLE
        .iter()
        .find(|d| d.method == method)
        .expect("every method has a row")
}

/// The decomposition the relations of six lines (in the order given) allow, if any: the
/// first row of [`TABLE`] (best first) for any family the lines are of whose arrangement
/// holds, with that family (the general 6R's row takes every family, so any six revolute
/// axes get a method).
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
/// order, read forward or reversed: a special family's closed form before the general 6R,
/// then the more specialised family of the two, forward on a tie.
#[inline]
pub(super) fn method_either(lines: &[AxisLine], length: f64) -> Option<(Family, Method, bool)> {
    let mut back = lines.to_vec();
    back.reverse();
    match (method_of(lines, length), method_of(&back, length)) {
        (Some((f, m)), Some((b, n))) => {
            let rank = |family: Family, method: Method| (method == Method::General, family);
            Some(if rank(b, n) < rank(f, m) {
                (b, n, true)
            } else {
                (f, m, false)
            })
        }
        (Some((f, m)), None) => Some((f, m, false)),
        (None, Some((b, n))) => Some((b, n, true)),
        (None, None) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_general_row_takes_every_six_r_family_and_no_other() {
        assert_eq!(SIX_R.len(), 8);
        assert!(SIX_R.contains(&Family::General6R));
        assert!(SIX_R.contains(&Family::SphericalWristTwoParallel));
        assert!(!SIX_R.contains(&Family::Redundant7R) && !SIX_R.contains(&Family::NotAnalytic));
        assert_eq!(TABLE.last().map(|d| d.method), Some(Method::General));
    }
}
