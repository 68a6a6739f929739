//! Analytic IK by subproblem decomposition: every solution of a 6R pose — or of a 7R pose with
//! one joint locked — for the families that have a closed form ([`crate::family`]), and by a
//! 1D search for two intersecting axes 5–6 (or 1–2, read from the tip). Two parallel axes
//! only, other placements of two intersecting axes and the general 6R are not solved here:
//! they get numerical IK.
//!
//! Solved here (with g = T_d M⁻¹ = e^\[S₁\]θ₁ ⋯ e^\[S₆\]θ₆, k_i the unit axes, r_i points on
//! them, e_i = e^\[S_i\]θ_i, R_i = R(k_i, θ_i)):
//!
//! * **Spherical wrist, 2 ∥ 3** (KUKA KR, ABB IRB, PUMA-type). p_w, where axes 4, 5, 6 meet,
//!   is not moved by them: y = g p_w = e₁ e₂ e₃ p_w. Rotations 2 and 3 keep k₂ components, so
//!   k₂ · e₁⁻¹ y = k₂ · p_w gives θ₁ (subproblem 4); z = e₁⁻¹ y keeps its distance to axis 2
//!   under e₂: ‖e₃ p_w − r₂‖ = ‖z − r₂‖ gives θ₃ (subproblem 3); e₂ (e₃ p_w) = z gives θ₂
//!   (subproblem 1). Then the wrist (below).
//! * **Spherical wrist, two intersecting axes** (1–2 meeting at o, or 2–3). Axes 1–2: e₁ e₂
//!   fix o, so ‖y − o‖ = ‖e₃ p_w − o‖ gives θ₃ (subproblem 3) and R(k₁, −θ₁)(y − o) =
//!   R(k₂, θ₂)(e₃ p_w − o) gives θ₁, θ₂ (subproblem 2). Axes 2–3: ‖e₁⁻¹ y − o‖ = ‖p_w − o‖
//!   gives θ₁ (subproblem 3), R(k₂, −θ₂)(e₁⁻¹ y − o) = R(k₃, θ₃)(p_w − o) gives θ₂, θ₃
//!   (subproblem 2). Then the wrist.
//! * **The wrist**: R_w = R₄ R₅ R₆ = (R₁ R₂ R₃)ᵀ R_g; k₄ᵀ R₅ k₆ = k₄ᵀ R_w k₆ gives θ₅
//!   (subproblem 4), R₄ (R₅ k₆) = R_w k₆ gives θ₄ and R₆ k₅ = R₅ᵀ R₄ᵀ R_w k₅ gives θ₆
//!   (subproblem 1).
//! * **Three parallel axes 2 ∥ 3 ∥ 4, axes 5 and 6 meeting at p₅₆** (UR-type): k₂ · e₁⁻¹ g p₅₆
//!   = k₂ · p₅₆ gives θ₁ (subproblem 4); k₂ᵀ R₁ᵀ R_g k₆ = k₂ᵀ R₅ k₆ gives θ₅ (subproblem 4);
//!   R₆ (R_gᵀ R₁ k₂) = R(k₅, −θ₅) k₂ gives θ₆ (subproblem 1). Then h = e₁⁻¹ g e₆⁻¹ e₅⁻¹ =
//!   e₂ e₃ e₄ is planar: with p₄ on axis 4, ‖e₃ p₄ − r₂‖ = ‖h p₄ − r₂‖ gives θ₃
//!   (subproblem 3), e₂ (e₃ p₄) = h p₄ gives θ₂ (subproblem 1) and θ₄ is the rotation of h
//!   about k₂ minus θ₂ + θ₃.
//!
//! * **Spherical wrist only**: R(k₁, −θ₁)(y − r₁) + r₁ − r₂ = R₂ ((r₃ − r₂) + R₃ (p_w − r₃))
//!   is subproblem 5 (up to 4 triples), then the wrist.
//! * **Three parallel axes 2 ∥ 3 ∥ 4 only**: the k₂ components of e₁⁻¹ g r₆ = e₂ e₃ e₄ e₅ r₆ and
//!   of R₁ᵀ R_g k₆ = R₂₃₄ R₅ k₆ give k₂ᵀ R(k₁, −θ₁)(g r₆ − r₁) − k₂ᵀ R₅ (r₆ − r₅) = k₂·(r₅ − r₁)
//!   and k₂ᵀ R(k₁, −θ₁) R_g k₆ − k₂ᵀ R₅ k₆ = 0: subproblem 6 in (θ₁, θ₅) (up to 4 pairs); then
//!   θ₆ and the planar problem as for the UR type.
//!
//! Each has up to 8 postures (solutions modulo 2π). A chain whose *reversed*
//! order is of one of these (a spherical shoulder is a spherical wrist seen from the tip) is
//! solved as M T_d⁻¹ = e^\[−S₆\]θ₆ ⋯ e^\[−S₁\]θ₁: the lines in reverse order, directions
//! negated. A 7R chain with joint j locked at v is the 6R chain of the other joints with the
//! lines after j moved by E = e^\[S_j\]v and home E M.
//!
//! [`AnalyticIk`] is the solver prepared once per chain (Pinocchio's model side);
//! [`AnalyticIk::postures`] is the kernel (allocation-free for the closed forms);
//! [`AnalyticIk::solve`] turns postures into [`Solutions`]: the exact postures (or, when none is exact, the least-squares ones),
//! deduplicated modulo 2π, each at every 2π shift inside the joint limits, each with its
//! residual checked by forward kinematics. [`ik_all`] and [`ik_nearest`] are the one-call
//! forms.

use nalgebra::{Matrix3, Vector3};
use screwkit_lie::Se3;

use crate::error::SolveError;
use crate::family::{classify, classify_axes, closest_points, relations, AxisLine, Family};
use crate::fk::fk_unchecked;
use crate::kinematics::Kinematics;
use crate::subproblem::{
    rotate, sp1, sp2, sp3, sp4, sp4_unit, sp5, sp6, wrap, AnglePairs, Angles, Few,
};
use crate::workspace::Workspace;

type V3 = Vector3<f64>;
type M3 = Matrix3<f64>;

/// The most variables an analytic solution has (a 7R chain with one joint locked).
pub const MAX_DOF: usize = 7;
/// The most postures (solutions modulo 2π) of one pose for the families solved here (8 in
/// closed form, 16 for a 1D search).
pub const MAX_POSTURES: usize = 16;

/// Samples of the searched angle over (−π, π] for the 1D-search family.
const SEARCH_SAMPLES: usize = 512;

/// An exact posture whose FK residual exceeds this (× max(1, L)) is polished by Newton steps.
const POLISH: f64 = 1e-13;

/// Which decomposition (module documentation), for the lines in the order solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Method {
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

/// The decomposition the relations of six lines (in the order given) allow, if any.
fn method_of(lines: &[AxisLine], length: f64) -> Option<(Family, Method)> {
    let (family, parallel, intersecting, _) = relations(lines, true, length);
    let int = |i: usize| intersecting.iter().any(|&(j, _)| j == i);
    let method = match family {
        Family::SphericalWristTwoParallel => Some(Method::WristParallel),
        Family::SphericalWristTwoIntersecting if int(0) => Some(Method::WristIntersecting12),
        Family::SphericalWristTwoIntersecting => Some(Method::WristIntersecting23),
        Family::ThreeParallelTwoIntersecting
            if parallel.contains(&1) && parallel.contains(&2) && int(4) =>
        {
            Some(Method::ThreeParallel)
        }
        Family::ThreeParallelTwoIntersecting | Family::ThreeParallel
            if parallel.contains(&1) && parallel.contains(&2) =>
        {
            Some(Method::ThreeParallelGeneral)
        }
        Family::SphericalWrist => Some(Method::Wrist),
        Family::TwoIntersecting if int(4) => Some(Method::Search56),
        Family::TwoParallel if parallel.contains(&1) => Some(Method::Search23),
        _ => None,
    };
    method.map(|m| (family, m))
}

/// True when the first three lines and the last three each meet in a point: a 6R chain
/// with a spherical shoulder and a spherical wrist, whose reachable poses come with a
/// one-parameter self-motion (the iiwa with its elbow locked).
fn shoulder_and_wrist(lines: &[AxisLine], length: f64) -> bool {
    let mut back = lines.to_vec();
    back.reverse();
    relations(lines, true, length).3.is_some() && relations(&back, true, length).3.is_some()
}

/// For the 1D search: the first three axes (in the order solved) must not nearly meet in one
/// point. When they do — a spherical shoulder written with rounded angles, as the xArm7's
/// 1.5708 for π/2 misses by 1e-6 m — the 3R position problem inside the search has solutions
/// only in θ₄ windows narrower than any sampling, so the search would silently find nothing:
/// an error naming the miss instead.
fn search_guard(lines: &[AxisLine], reversed: bool, length: f64) -> Result<(), SolveError> {
    let mut l = lines.to_vec();
    if reversed {
        l.reverse();
    }
    let pair = |i: usize| {
        if l[i].direction.cross(&l[i + 1].direction).norm() < 1e-6 {
            None
        } else {
            Some(closest_points(&l[i], &l[i + 1]))
        }
    };
    if let (Some((p, d1)), Some((q, d2))) = (pair(0), pair(1)) {
        let miss = d1.max(d2).max((p - q).norm());
        if miss <= 1e-4 * length {
            return Err(SolveError::InvalidInput(format!(
                "axes {} nearly meet in one point (within {miss:.1e}, the file's rounding?): \
                 too close to a spherical shoulder for the 1D search; numerical IK only",
                if reversed { "4-6" } else { "1-3" }
            )));
        }
    }
    Ok(())
}

/// The method for six lines in chain order, read forward or reversed (true): the more
/// specialised family of the two (a closed form before a search), forward on a tie.
fn method_either(lines: &[AxisLine], length: f64) -> Option<(Method, bool)> {
    let mut back = lines.to_vec();
    back.reverse();
    match (method_of(lines, length), method_of(&back, length)) {
        (Some((f, m)), Some((b, n))) => Some(if b < f { (n, true) } else { (m, false) }),
        (Some((_, m)), None) => Some((m, false)),
        (None, Some((_, n))) => Some((n, true)),
        (None, None) => None,
    }
}

/// A 6R problem ready to solve: lines in the order solved, the home of the 6R chain (chain
/// order), the method's points.
#[derive(Debug, Clone, Copy)]
struct Prepared {
    k: [V3; 6],
    r: [V3; 6],
    home: Se3,
    /// The wrist center or p₅₆.
    center: V3,
    /// Where the intersecting pair meets (wrist families with two intersecting axes).
    meet: V3,
    /// A unit vector ⊥ k₂ (three-parallel family).
    perp: V3,
}

impl Prepared {
    /// From six lines in chain order and their home; reversed: solve tip to base.
    fn new(method: Method, lines: &[AxisLine; 6], home: Se3, reversed: bool) -> Self {
        let mut k = [V3::zeros(); 6];
        let mut r = [V3::zeros(); 6];
        for i in 0..6 {
            let l = if reversed { &lines[5 - i] } else { &lines[i] };
            k[i] = if reversed { -l.direction } else { l.direction };
            r[i] = l.point;
        }
        let line = |i: usize| AxisLine {
            direction: k[i],
            point: r[i],
        };
        let meet = |i: usize| closest_points(&line(i), &line(i + 1)).0;
        let center = match method {
            Method::ThreeParallel | Method::Search56 => meet(4),
            Method::ThreeParallelGeneral => V3::zeros(),
            _ => (meet(3) + meet(4)) / 2.0,
        };
        let pair = match method {
            Method::WristIntersecting12 => meet(0),
            Method::WristIntersecting23 => meet(1),
            _ => V3::zeros(),
        };
        let a = if k[1].x.abs() < 0.9 { V3::x() } else { V3::y() };
        Self {
            k,
            r,
            home,
            center,
            meet: pair,
            perp: (a - k[1] * k[1].dot(&a)).normalize(),
        }
    }
}

/// A locked joint of a 7R chain.
#[derive(Debug, Clone, Copy)]
struct Lock {
    joint: usize,
    line: AxisLine,
}

/// One posture: the chain's variables (the first `dof` of `q`) and whether every subproblem
/// on the way was exact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Posture {
    /// The joint values, angles in (−π, π] (a locked joint: its value).
    pub q: [f64; MAX_DOF],
    /// False for a least-squares posture (the pose is out of reach on this branch).
    pub exact: bool,
}

/// The raw output of [`AnalyticIk::postures`]: up to [`MAX_POSTURES`] postures, inline.
#[derive(Debug, Clone)]
pub struct Postures {
    items: [Posture; MAX_POSTURES],
    len: usize,
    dof: usize,
    /// A singular or near-singular configuration was met: an angle left free (set to 0) or
    /// a double root (elbow stretched, wrist center on axis 1, axes 4 and 6 aligned).
    pub singular: bool,
}

impl Default for Postures {
    fn default() -> Self {
        Self {
            items: [Posture {
                q: [0.0; MAX_DOF],
                exact: false,
            }; MAX_POSTURES],
            len: 0,
            dof: 0,
            singular: false,
        }
    }
}

impl Postures {
    /// The postures found.
    pub fn as_slice(&self) -> &[Posture] {
        &self.items[..self.len]
    }

    /// The number of variables of each posture.
    pub fn dof(&self) -> usize {
        self.dof
    }

    fn push(&mut self, q: [f64; MAX_DOF], exact: bool) {
        if self.len < MAX_POSTURES {
            self.items[self.len] = Posture { q, exact };
            self.len += 1;
        }
    }
}

/// Every solution of one pose, nearest-first after [`Solutions::sort_nearest`]. Storage is
/// flat and reused: [`AnalyticIk::solve`] refills it without allocating once it has grown.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Solutions {
    dof: usize,
    q: Vec<f64>,
    exact: Vec<bool>,
    residual: Vec<f64>,
    /// True when a singular or near-singular configuration was met ([`Postures::singular`]):
    /// an angle may have been left free (set to 0), so other solutions exist too.
    pub singular: bool,
    /// How many distinct postures (modulo 2π) the solutions come from: elbow up/down, wrist
    /// flip, shoulder left/right — at most 8. The solutions list every 2π shift of each that
    /// the limits allow (a UR5 with ±2π limits has up to 8 × 2⁶).
    pub branches: usize,
}

impl Solutions {
    /// The number of solutions.
    pub fn len(&self) -> usize {
        self.exact.len()
    }

    /// True when there is none (every posture is outside the joint limits).
    pub fn is_empty(&self) -> bool {
        self.exact.is_empty()
    }

    /// Solution i's joint values.
    pub fn q(&self, i: usize) -> &[f64] {
        &self.q[i * self.dof..(i + 1) * self.dof]
    }

    /// The solutions' joint values, in order.
    pub fn iter(&self) -> impl Iterator<Item = &[f64]> + '_ {
        (0..self.len()).map(|i| self.q(i))
    }

    /// Whether solution i is exact (false: least squares, the pose is out of reach).
    pub fn exact(&self, i: usize) -> bool {
        self.exact[i]
    }

    /// Solution i's residual: the largest entry of |T(q) − T_d| (rotation entries and
    /// translations in the file's length unit), by forward kinematics.
    pub fn residual(&self, i: usize) -> f64 {
        self.residual[i]
    }

    /// True when there are solutions and all are exact (they are either all exact or all
    /// least squares: exact ones are preferred).
    pub fn is_exact(&self) -> bool {
        !self.exact.is_empty() && self.exact.iter().all(|&e| e)
    }

    /// The solutions as owned rows.
    pub fn to_vecs(&self) -> Vec<Vec<f64>> {
        self.iter().map(<[f64]>::to_vec).collect()
    }

    /// The weighted joint-space distance Σ w_j (q_j − seed_j)² from solution i to `seed`
    /// (w = 1 when `weights` is None).
    pub fn distance(&self, i: usize, seed: &[f64], weights: Option<&[f64]>) -> f64 {
        self.q(i)
            .iter()
            .zip(seed)
            .enumerate()
            .map(|(j, (a, b))| weights.map_or(1.0, |w| w[j]) * (a - b) * (a - b))
            .sum()
    }

    /// The index of the solution nearest to `seed` ([`Solutions::distance`]), if any.
    pub fn nearest(&self, seed: &[f64], weights: Option<&[f64]>) -> Option<usize> {
        (0..self.len()).min_by(|&a, &b| {
            self.distance(a, seed, weights)
                .total_cmp(&self.distance(b, seed, weights))
        })
    }

    /// Orders the solutions nearest to `seed` first ([`Solutions::distance`]): the first is
    /// the one that moves the arm least from where it is (branch-stable tracking). Ties keep
    /// their order.
    pub fn sort_nearest(&mut self, seed: &[f64], weights: Option<&[f64]>) {
        let mut order: Vec<usize> = (0..self.len()).collect();
        let d: Vec<f64> = order
            .iter()
            .map(|&i| self.distance(i, seed, weights))
            .collect();
        order.sort_by(|&a, &b| d[a].total_cmp(&d[b]));
        let n = self.dof;
        let q: Vec<f64> = order
            .iter()
            .flat_map(|&i| self.q[i * n..(i + 1) * n].iter().copied())
            .collect();
        self.q = q;
        self.exact = order.iter().map(|&i| self.exact[i]).collect();
        self.residual = order.iter().map(|&i| self.residual[i]).collect();
    }

    fn clear(&mut self, dof: usize) {
        self.dof = dof;
        self.q.clear();
        self.exact.clear();
        self.residual.clear();
        self.singular = false;
        self.branches = 0;
    }
}

/// An analytic solver prepared for one chain (or one 7R chain with a chosen joint locked):
/// build once, solve many poses. `Send + Sync`, cheap to clone.
#[derive(Debug, Clone)]
pub struct AnalyticIk {
    family: Family,
    method: Method,
    reversed: bool,
    lock: Option<Lock>,
    /// Chain variable index of each of the six free joints, in chain order.
    free: [usize; 6],
    dof: usize,
    /// The chain's axis lines at home, one per joint.
    lines: Vec<AxisLine>,
    /// The chain's M.
    home: Se3,
    /// The prepared problem of an unlocked chain.
    fixed: Option<Prepared>,
}

/// The most lock values one sweep may have ([`AnalyticIk::lock_values`]).
pub const MAX_SWEEP: usize = 100_000;

impl AnalyticIk {
    /// The solver of a 6R chain of a family solved here; an error naming the family
    /// otherwise (a 7R chain: lock a joint with [`AnalyticIk::locked`]).
    pub fn new(kin: &Kinematics) -> Result<Self, SolveError> {
        let c = classify(kin);
        if c.family == Family::Redundant7R {
            return Err(SolveError::InvalidInput(format!(
                "{}: lock one joint to solve it analytically",
                c.family.describe()
            )));
        }
        let fail = || {
            SolveError::InvalidInput(format!(
                "no analytic solver for this chain: {}",
                c.family.describe()
            ))
        };
        if c.family == Family::NotAnalytic || kin.dof() != 6 {
            return Err(fail());
        }
        if shoulder_and_wrist(&c.axes, kin.length_scale) {
            return Err(SolveError::InvalidInput(
                "axes 1-3 and axes 4-6 each meet in a point: the reachable poses have a \
                 one-parameter self-motion, so there is no finite solution set"
                    .into(),
            ));
        }
        let (method, reversed) = method_either(&c.axes, kin.length_scale).ok_or_else(fail)?;
        if method == Method::Search56 {
            search_guard(&c.axes, reversed, kin.length_scale)?;
        }
        let lines: [AxisLine; 6] = c.axes.clone().try_into().map_err(|_| fail())?;
        Ok(Self {
            family: c.family,
            method,
            reversed,
            lock: None,
            free: [0, 1, 2, 3, 4, 5],
            dof: 6,
            fixed: Some(Prepared::new(method, &lines, kin.home, reversed)),
            lines: c.axes,
            home: kin.home,
        })
    }

    /// The solver of a 7R chain with joint `joint` (0-based) locked: the other six must form
    /// a family solved here whatever the locked value (checked at two generic values).
    pub fn locked(kin: &Kinematics, joint: usize) -> Result<Self, SolveError> {
        let c = classify(kin);
        if c.family != Family::Redundant7R {
            return Err(SolveError::InvalidInput(format!(
                "locking a joint is for 7R chains; this one is: {}",
                c.family.describe()
            )));
        }
        if joint >= 7 {
            return Err(SolveError::InvalidInput(format!(
                "joint index {joint} out of range (the chain has 7 joints)"
            )));
        }
        let mut solver = Self {
            family: Family::Redundant7R,
            method: Method::WristParallel,
            reversed: false,
            lock: Some(Lock {
                joint,
                line: c.axes[joint],
            }),
            free: [0; 6],
            dof: 7,
            lines: c.axes,
            home: kin.home,
            fixed: None,
        };
        for (slot, j) in (0..7).filter(|&j| j != joint).enumerate() {
            solver.free[slot] = j;
        }
        let l = kin.length_scale;
        let (a, _) = solver.locked_lines(0.7);
        let (b, _) = solver.locked_lines(2.1);
        if shoulder_and_wrist(&a, l) {
            return Err(SolveError::InvalidInput(format!(
                "locking joint {} ({}) leaves a spherical shoulder and a spherical wrist: \
                 the other six joints still have a self-motion (lock another joint)",
                joint + 1,
                kin.names[joint]
            )));
        }
        match (method_either(&a, l), method_either(&b, l)) {
            (Some(x), Some(y)) if x == y => {
                if x.0 == Method::Search56 {
                    search_guard(&a, x.1, l).map_err(|e| {
                        SolveError::InvalidInput(format!(
                            "locking joint {} ({}): {}",
                            joint + 1,
                            kin.names[joint],
                            e.to_string().trim_start_matches("invalid input: ")
                        ))
                    })?;
                }
                solver.method = x.0;
                solver.reversed = x.1;
                solver.family = classify_axes(a.to_vec(), true, l).family;
                Ok(solver)
            }
            _ => Err(SolveError::InvalidInput(format!(
                "locking joint {} ({}) does not leave a 6R chain that screwkit solves \
                 analytically ({})",
                joint + 1,
                kin.names[joint],
                classify_axes(a.to_vec(), true, l).family.describe()
            ))),
        }
    }

    /// The solver of any chain screwkit solves analytically: a 6R chain as
    /// [`AnalyticIk::new`], a 7R chain with the last joint whose locking leaves a closed-form
    /// family (joint 7 first, then 6, …), else the last one that leaves a 1D search.
    pub fn auto(kin: &Kinematics) -> Result<Self, SolveError> {
        if kin.dof() != 7 {
            return Self::new(kin);
        }
        let mut last = None;
        let mut search = None;
        for j in (0..7).rev() {
            match Self::locked(kin, j) {
                Ok(s) if !matches!(s.method, Method::Search56 | Method::Search23) => return Ok(s),
                Ok(s) => {
                    search.get_or_insert(s);
                }
                Err(e) => last = Some(e),
            }
        }
        if let Some(s) = search {
            return Ok(s);
        }
        Err(last.unwrap_or_else(|| SolveError::InvalidInput("no joint to lock".into())))
    }

    /// True when every solution comes in closed form; false for the sampled 1D searches
    /// (1–3 ms per pose, roots may be missed where the error only touches zero).
    pub fn closed_form(&self) -> bool {
        !matches!(self.method, Method::Search56 | Method::Search23)
    }

    /// The family of the 6R problem solved (for a locked 7R chain: of the other six joints).
    pub fn family(&self) -> Family {
        self.family
    }

    /// The locked joint (0-based), if any.
    pub fn locked_joint(&self) -> Option<usize> {
        self.lock.map(|l| l.joint)
    }

    /// True when the chain is solved from tip to base (its reversed order is the family's).
    pub fn reversed(&self) -> bool {
        self.reversed
    }

    /// The six free lines and the home of the 6R chain with the lock at `value`.
    fn locked_lines(&self, value: f64) -> ([AxisLine; 6], Se3) {
        let lock = self.lock.expect("a locked solver");
        let (kj, rj) = (lock.line.direction, lock.line.point);
        let e = rotation(&kj, value);
        let mv = |p: &V3| rj + e * (p - rj);
        let mut out = [lock.line; 6];
        for (slot, &j) in self.free.iter().enumerate() {
            let l = self.lines[j];
            out[slot] = if j > lock.joint {
                AxisLine {
                    direction: e * l.direction,
                    point: mv(&l.point),
                }
            } else {
                l
            };
        }
        let home = Se3::from_parts_unchecked(e * self.home.rotation(), mv(self.home.translation()));
        (out, home)
    }

    /// Every posture reaching `target` (the kernel; allocation-free for the closed forms):
    /// exact ones, and least-squares ones on branches where the pose is out of reach. `lock_value` is the
    /// locked joint's value (ignored without a lock). The target must be finite (checked by
    /// [`AnalyticIk::solve`]).
    pub fn postures(&self, target: &Se3, lock_value: f64, out: &mut Postures) {
        let prepared;
        let p = match &self.fixed {
            Some(p) => p,
            None => {
                let (lines, home) = self.locked_lines(lock_value);
                prepared = Prepared::new(self.method, &lines, home, self.reversed);
                &prepared
            }
        };
        let g = if self.reversed {
            p.home.compose(&target.inverse())
        } else {
            target.compose(&p.home.inverse())
        };
        out.len = 0;
        out.dof = self.dof;
        out.singular = false;
        let mut singular = false;
        let mut emit = |t: [f64; 6], exact: bool| {
            let mut q = [0.0; MAX_DOF];
            for (slot, &j) in self.free.iter().enumerate() {
                q[j] = wrap(if self.reversed { t[5 - slot] } else { t[slot] });
            }
            if let Some(l) = self.lock {
                q[l.joint] = lock_value;
            }
            out.push(q, exact);
        };
        match self.method {
            Method::WristParallel => wrist_parallel(p, &g, &mut singular, &mut emit),
            Method::WristIntersecting12 | Method::WristIntersecting23 => wrist_intersecting(
                p,
                &g,
                self.method == Method::WristIntersecting12,
                &mut singular,
                &mut emit,
            ),
            Method::ThreeParallel => three_parallel(p, &g, false, &mut singular, &mut emit),
            Method::ThreeParallelGeneral => three_parallel(p, &g, true, &mut singular, &mut emit),
            Method::Wrist => wrist_only(p, &g, &mut singular, &mut emit),
            Method::Search56 => search56(p, &g, &mut emit),
            Method::Search23 => search23(p, &g, &mut emit),
        }
        out.singular = singular;
    }

    /// Every solution of T(q) = `target` within the joint limits into `out` (see
    /// [`Solutions`]): the exact postures, or the least-squares ones when none is exact,
    /// deduplicated modulo 2π, each at every 2π shift inside the limits, each with its FK
    /// residual (an exact posture whose residual exceeds 1e-13 L is polished by Newton steps).
    /// `lock_value`: the locked joint's value (must be within its limits; ignored without a
    /// lock).
    pub fn solve(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        lock_value: f64,
        out: &mut Solutions,
    ) -> Result<(), SolveError> {
        self.solve_swept(kin, ws, target, &[lock_value], out)
    }

    /// [`AnalyticIk::solve`] with the locked joint at each of `lock_values` in turn (a sweep
    /// of the self-motion of a 7R arm, [`AnalyticIk::sweep`]), all solutions in one list: the
    /// exact ones of every value, or the least-squares ones when no value gives an exact one.
    pub fn solve_swept(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        lock_values: &[f64],
        out: &mut Solutions,
    ) -> Result<(), SolveError> {
        if kin.dof() != self.dof {
            return Err(SolveError::InvalidInput(format!(
                "this analytic solver is for a {}-joint chain, not {}",
                self.dof,
                kin.dof()
            )));
        }
        if !target.is_finite() {
            return Err(SolveError::BadTarget(crate::BadTarget::NonFinite));
        }
        if let Some(l) = self.lock {
            let (lo, hi) = (kin.lower[l.joint], kin.upper[l.joint]);
            if let Some(v) = lock_values.iter().find(|&&v| !(v >= lo && v <= hi)) {
                return Err(SolveError::InvalidInput(format!(
                    "locked value {v} of joint {} outside its limits [{lo}, {hi}]",
                    kin.names[l.joint]
                )));
            }
        }
        out.clear(self.dof);
        let mut raw = Postures::default();
        // Exact postures are preferred over least-squares ones across all the values.
        let mut any_exact = false;
        if lock_values.len() > 1 {
            for &v in lock_values {
                self.postures(target, v, &mut raw);
                any_exact |= raw.as_slice().iter().any(|p| p.exact);
            }
        }
        let n = self.dof;
        for &v in lock_values {
            self.postures(target, v, &mut raw);
            out.singular |= raw.singular;
            if lock_values.len() == 1 {
                any_exact = raw.as_slice().iter().any(|p| p.exact);
            }
            // One entry per posture (modulo 2π); its shifts are then distinct by construction.
            let mut distinct = [[0.0; MAX_DOF]; MAX_POSTURES];
            let mut count = 0;
            for p in raw.as_slice().iter().filter(|p| p.exact == any_exact) {
                let same = |d: &[f64; MAX_DOF]| (0..n).all(|i| wrap(d[i] - p.q[i]).abs() < 1e-9);
                if distinct[..count].iter().any(same) {
                    continue;
                }
                let mut q = p.q;
                let mut residual = fk_unchecked(kin, &q[..n]).max_abs_diff(target);
                if p.exact && residual > POLISH * kin.length_scale.max(1.0) {
                    residual = self.polish(kin, ws, &mut q[..n], target, residual);
                }
                if self.expand(kin, &q[..n], p.exact, residual, out) {
                    distinct[count] = p.q;
                    count += 1;
                }
            }
            out.branches += count;
        }
        Ok(())
    }

    /// The values of the locked joint a caller means: `sweep` values evenly spaced over its
    /// limits ([`AnalyticIk::sweep`]), or `value`, or else the seed's value of that joint; \[0\]
    /// without a lock (where a value or a sweep is an error, as are both at once).
    pub fn lock_values(
        &self,
        kin: &Kinematics,
        seed: &[f64],
        value: Option<f64>,
        sweep: Option<usize>,
    ) -> Result<Vec<f64>, SolveError> {
        let Some(l) = self.lock else {
            if value.is_some() || sweep.is_some() {
                return Err(SolveError::InvalidInput(
                    "a lock value or a sweep is for a 7R chain with a locked joint".into(),
                ));
            }
            return Ok(vec![0.0]);
        };
        match (value, sweep) {
            (Some(_), Some(_)) => Err(SolveError::InvalidInput(
                "a lock value and a sweep exclude each other".into(),
            )),
            (None, Some(0)) => Err(SolveError::InvalidInput(
                "a sweep needs at least one value".into(),
            )),
            (None, Some(n)) if n > MAX_SWEEP => Err(SolveError::InvalidInput(format!(
                "a sweep of {n} values is more than {MAX_SWEEP} (each value gives up to 8 postures and their 2π shifts)"
            ))),
            (None, Some(n)) => Ok(self.sweep(kin, n)),
            (Some(v), None) => Ok(vec![v]),
            (None, None) => {
                kin.check_q(seed)?;
                Ok(vec![seed[l.joint]])
            }
        }
    }

    /// `count` values of the locked joint evenly spaced over its limits, ends included
    /// ([−π, π) for a continuous joint); empty without a lock.
    pub fn sweep(&self, kin: &Kinematics, count: usize) -> Vec<f64> {
        let Some(l) = self.lock else {
            return Vec::new();
        };
        let (mut lo, mut hi) = (kin.lower[l.joint], kin.upper[l.joint]);
        let continuous = !(lo.is_finite() && hi.is_finite());
        if continuous {
            (lo, hi) = (-std::f64::consts::PI, std::f64::consts::PI);
        }
        match count {
            0 => Vec::new(),
            1 => vec![0.5 * (lo + hi)],
            _ => {
                // A continuous joint's ends are one angle: leave the upper one out.
                let steps = if continuous { count } else { count - 1 };
                (0..count)
                    .map(|i| lo + (hi - lo) * i as f64 / steps as f64)
                    .collect()
            }
        }
    }

    /// Every solution of every row of `targets` (N × 16, row-major 4 × 4), ordered nearest
    /// that row's seed, in parallel on rayon's pool: row k's lock values are
    /// [`AnalyticIk::lock_values`] of its seed (`seeds`: N × dof, one seed per row, or dof: one
    /// for all), `value` and `sweep`; its solutions [`AnalyticIk::solve_swept`] over them,
    /// sorted by [`Solutions::sort_nearest`]. Row k's result (solutions and lock values) equals
    /// those calls on row k whatever the thread count; a bad row is its own error and every
    /// other row is solved. An error only for buffers of the wrong length.
    #[allow(clippy::type_complexity)]
    pub fn solve_nearest_batch(
        &self,
        kin: &Kinematics,
        targets: &[f64],
        seeds: &[f64],
        value: Option<f64>,
        sweep: Option<usize>,
    ) -> Result<Vec<Result<(Solutions, Vec<f64>), SolveError>>, SolveError> {
        use rayon::prelude::*;
        let rows = targets.len() / 16;
        if !targets.len().is_multiple_of(16) {
            return Err(SolveError::WrongLength {
                what: "target values (N × 16)",
                expected: rows * 16,
                got: targets.len(),
                names: "a multiple of 16".into(),
            });
        }
        let n = kin.dof();
        let one_seed = seeds.len() == n;
        if !one_seed && seeds.len() != rows * n {
            return Err(SolveError::WrongLength {
                what: "seed values",
                expected: rows * n,
                got: seeds.len(),
                names: "one seed (dof) or one per target (N × dof)".into(),
            });
        }
        Ok(targets
            .par_chunks(16)
            .enumerate()
            .with_max_len(64)
            .map_init(
                || Workspace::new(kin),
                |ws, (k, row)| {
                    let seed = if one_seed {
                        seeds
                    } else {
                        &seeds[k * n..(k + 1) * n]
                    };
                    let t = crate::batch::target_row(row)?;
                    kin.check_q(seed)?;
                    let values = self.lock_values(kin, seed, value, sweep)?;
                    let mut out = Solutions::default();
                    self.solve_swept(kin, ws, &t, &values, &mut out)?;
                    out.sort_nearest(seed, None);
                    Ok((out, values))
                },
            )
            .collect())
    }

    /// [`AnalyticIk::solve`] for every row of `targets` (N × 16, row-major 4 × 4), in parallel
    /// on rayon's pool (one workspace per worker). `lock_values`: the locked joint's value per
    /// row (None: 0, for an unlocked solver). Row k's result equals `solve` on row k whatever
    /// the thread count; a bad row (not finite, not rigid, a lock value outside the limits) is
    /// its own error and every other row is solved. An error only for buffers of the wrong
    /// length.
    pub fn solve_batch(
        &self,
        kin: &Kinematics,
        targets: &[f64],
        lock_values: Option<&[f64]>,
    ) -> Result<Vec<Result<Solutions, SolveError>>, SolveError> {
        use rayon::prelude::*;
        if !targets.len().is_multiple_of(16) {
            return Err(SolveError::WrongLength {
                what: "target values (N × 16)",
                expected: targets.len() / 16 * 16,
                got: targets.len(),
                names: "a multiple of 16".into(),
            });
        }
        let rows = targets.len() / 16;
        if let Some(v) = lock_values {
            if v.len() != rows {
                return Err(SolveError::WrongLength {
                    what: "lock values (N)",
                    expected: rows,
                    got: v.len(),
                    names: "one per target".into(),
                });
            }
        }
        Ok(targets
            .par_chunks(16)
            .enumerate()
            .with_max_len(64)
            .map_init(
                || Workspace::new(kin),
                |ws, (k, row)| {
                    let t = crate::batch::target_row(row)?;
                    let mut out = Solutions::default();
                    self.solve(kin, ws, &t, lock_values.map_or(0.0, |v| v[k]), &mut out)?;
                    Ok(out)
                },
            )
            .collect())
    }

    /// Newton steps on the free joints, q ← q + J_b⁻¹ log(T(q)⁻¹ T_d) (body Jacobian, the
    /// locked column left out), while the residual falls (at most 4): for the rare posture
    /// whose subproblems were ill-conditioned (two intersecting axes nearly parallel at the
    /// locked value, …). Returns the residual of `q`, which holds the best iterate.
    fn polish(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        q: &mut [f64],
        target: &Se3,
        mut residual: f64,
    ) -> f64 {
        let mut trial = [0.0; MAX_DOF];
        for _ in 0..4 {
            let Ok(pj) = crate::jacobian::fk_jacobian(kin, ws, q, screwkit_lie::Frame::Body) else {
                break;
            };
            let err = pj.pose.inverse_compose(target).log();
            let mut j6 = nalgebra::Matrix6::zeros();
            for (slot, &j) in self.free.iter().enumerate() {
                j6.set_column(slot, &pj.jacobian.column(j));
            }
            let rhs = nalgebra::Vector6::new(err.w.x, err.w.y, err.w.z, err.v.x, err.v.y, err.v.z);
            let Some(step) = j6.lu().solve(&rhs) else {
                break;
            };
            trial[..q.len()].copy_from_slice(q);
            for (slot, &j) in self.free.iter().enumerate() {
                trial[j] = wrap(trial[j] + step[slot]);
            }
            let r = fk_unchecked(kin, &trial[..q.len()]).max_abs_diff(target);
            if r.partial_cmp(&residual) != Some(std::cmp::Ordering::Less) {
                break;
            }
            q.copy_from_slice(&trial[..q.len()]);
            residual = r;
        }
        residual
    }

    /// Appends every 2π shift of posture `q` inside the limits (continuous joints: the
    /// wrapped angle; the locked joint: its value); false when there is none.
    fn expand(
        &self,
        kin: &Kinematics,
        q: &[f64],
        exact: bool,
        residual: f64,
        out: &mut Solutions,
    ) -> bool {
        use std::f64::consts::TAU;
        let n = q.len();
        // Per joint: the first representative and how many there are (at most 4).
        let mut first = [0.0; MAX_DOF];
        let mut count = [0usize; MAX_DOF];
        for i in 0..n {
            let (lo, hi) = (kin.lower[i], kin.upper[i]);
            if kin.continuous[i] || self.lock.is_some_and(|l| l.joint == i) {
                first[i] = q[i];
                count[i] = 1;
                continue;
            }
            let m0 = ((lo - 1e-12 - q[i]) / TAU).ceil();
            let mut c = 0;
            while c < 4 && q[i] + (m0 + c as f64) * TAU <= hi + 1e-12 {
                c += 1;
            }
            if c == 0 {
                return false;
            }
            first[i] = q[i] + m0 * TAU;
            count[i] = c;
        }
        let mut digit = [0usize; MAX_DOF];
        loop {
            for i in 0..n {
                let x = first[i] + digit[i] as f64 * TAU;
                out.q.push(x.clamp(kin.lower[i], kin.upper[i]));
            }
            out.exact.push(exact);
            out.residual.push(residual);
            let mut i = n;
            loop {
                if i == 0 {
                    return true;
                }
                i -= 1;
                digit[i] += 1;
                if digit[i] < count[i] {
                    break;
                }
                digit[i] = 0;
            }
        }
    }
}

/// What analytic IK screwkit offers for a chain, in words: the family and, for a 6R chain of
/// a closed-form family in an arrangement not solved here, that it falls back to numerical IK;
/// for a 7R chain, which joints can be locked (by name).
pub fn describe(kin: &Kinematics) -> String {
    let c = classify(kin);
    match c.family {
        Family::Redundant7R => {
            let (mut closed, mut search) = (Vec::new(), Vec::new());
            for j in 0..7 {
                if let Ok(s) = AnalyticIk::locked(kin, j) {
                    let list = if matches!(s.method, Method::Search56 | Method::Search23) {
                        &mut search
                    } else {
                        &mut closed
                    };
                    list.push(kin.names()[j].clone());
                }
            }
            let mut parts = Vec::new();
            if !closed.is_empty() {
                parts.push(format!("closed form with {} locked", closed.join(", ")));
            }
            if !search.is_empty() {
                parts.push(format!("a 1D search with {} locked", search.join(", ")));
            }
            if parts.is_empty() {
                "7R (redundant): no joint whose locking leaves a family screwkit solves: \
                 numerical IK only"
                    .into()
            } else {
                format!("7R (redundant): analytic, {}", parts.join("; "))
            }
        }
        f => match AnalyticIk::new(kin) {
            Ok(s) if s.reversed() => format!("{} (solved tip to base)", f.describe()),
            Ok(_) => f.describe().into(),
            Err(e) => match f {
                Family::SphericalWristTwoParallel
                | Family::SphericalWristTwoIntersecting
                | Family::ThreeParallelTwoIntersecting
                | Family::SphericalWrist
                | Family::ThreeParallel
                | Family::TwoIntersecting => format!(
                    "{}; this arrangement is not solved by screwkit yet ({e}): numerical IK only",
                    f.describe()
                ),
                _ => f.describe().into(),
            },
        },
    }
}

/// Every solution of T(q) = `target` for a 6R chain of a family solved here ([`Solutions`],
/// in the order found). For many poses build an [`AnalyticIk`] once and call
/// [`AnalyticIk::solve`].
pub fn ik_all(kin: &Kinematics, ws: &mut Workspace, target: &Se3) -> Result<Solutions, SolveError> {
    let solver = AnalyticIk::new(kin)?;
    let mut out = Solutions::default();
    solver.solve(kin, ws, target, 0.0, &mut out)?;
    Ok(out)
}

/// The exact solution nearest to `seed` (Euclidean in joint space), None when the pose is out
/// of reach or no solution is within the limits.
pub fn ik_nearest(
    kin: &Kinematics,
    ws: &mut Workspace,
    target: &Se3,
    seed: &[f64],
) -> Result<Option<Vec<f64>>, SolveError> {
    kin.check_q(seed)?;
    let sols = ik_all(kin, ws, target)?;
    if !sols.is_exact() {
        return Ok(None);
    }
    Ok(sols.nearest(seed, None).map(|i| sols.q(i).to_vec()))
}

/// R(k, θ) as a matrix for a unit k: the library's Rodrigues form
/// ([`screwkit_lie::so3::rotation_from_coefficients`] with φ = k, A = sin θ, B = 1 − cos θ).
fn rotation(k: &V3, theta: f64) -> M3 {
    let (s, c) = theta.sin_cos();
    screwkit_lie::so3::rotation_from_coefficients(k, 1.0, s, 1.0 - c)
}

/// The angles of a subproblem with their exactness: an exact double root where two are
/// expected (`two`), or a free angle (set to 0), marks the configuration singular.
fn roots(a: Angles, two: bool, singular: &mut bool) -> Few<(f64, bool)> {
    match a {
        Angles::Exact(v) => {
            // A double root, or two roots closer than 2e-6 rad (a near-tangency: the roots
            // move by √ε for an ε change in the data).
            if two && (v.len() == 1 || wrap(v[0] - v[1]).abs() < 2e-6) {
                *singular = true;
            }
            if v.len() == 2 {
                Few::two((v[0], true), (v[1], true))
            } else {
                Few::one((v[0], true))
            }
        }
        Angles::LeastSquares(t) => Few::one((t, false)),
        Angles::Any => {
            *singular = true;
            Few::one((0.0, true))
        }
    }
}

/// The pairs of subproblem 2 with their exactness; a point on an axis (degenerate) sets the
/// first angle to 0 and solves the second by subproblem 1, marking the configuration
/// singular.
fn pairs(a: AnglePairs, p1: &V3, p2: &V3, k2: &V3, singular: &mut bool) -> Few<(f64, f64, bool)> {
    match a {
        AnglePairs::Exact(v) => {
            if v.len() == 1 {
                *singular = true;
            }
            let f = |x: (f64, f64)| (x.0, x.1, true);
            if v.len() == 2 {
                Few::two(f(v[0]), f(v[1]))
            } else {
                Few::one(f(v[0]))
            }
        }
        AnglePairs::LeastSquares(a, b) => Few::one((a, b, false)),
        AnglePairs::Degenerate => {
            *singular = true;
            // R(k2, θ2) p2 = p1 with θ1 = 0.
            let (t, ok) = roots(sp1(p2, p1, k2), false, singular)[0];
            Few::one((0.0, t, ok))
        }
    }
}

/// The spherical wrist: (θ₄, θ₅, θ₆) with R₄ R₅ R₆ = `rw`.
fn wrist(p: &Prepared, rw: &M3, singular: &mut bool, mut emit: impl FnMut(f64, f64, f64, bool)) {
    let (k4, k5, k6) = (&p.k[3], &p.k[4], &p.k[5]);
    let rwk6 = rw * k6;
    let rwtk4 = rw.transpose() * k4;
    let five = sp4_unit(k4, k6, k5, &rwk6).unwrap_or_else(|| sp4(k4, k6, k5, k4.dot(&rwk6)));
    for &(t5, e5) in roots(five, true, singular).iter() {
        let r5 = rotation(k5, t5);
        let r5k6 = r5 * k6;
        let four = sp1(&r5k6, &rwk6, k4);
        if four == Angles::Any {
            // Axes 4 and 6 aligned (R₅ k₆ = s k₄): only θ₄ + s θ₆ = φ matters; with θ₄ = 0,
            // R₆ k₅ = R₅ᵀ R_w k₅ gives φ; split it evenly so both stay within their limits.
            *singular = true;
            let want = r5.transpose() * (rw * k5);
            for &(t6, e6) in roots(sp1(k5, &want, k6), false, singular).iter() {
                let s = k4.dot(&r5k6).signum();
                emit(t6 * s / 2.0, t5, t6 / 2.0, e5 && e6);
            }
            continue;
        }
        // R₆ (R_wᵀ k₄) = R₅ᵀ k₄ (R₄ keeps k₄): θ₆ without R₄.
        let six = sp1(&rwtk4, &(r5.transpose() * k4), k6);
        for &(t4, e4) in roots(four, false, singular).iter() {
            for &(t6, e6) in roots(six, false, singular).iter() {
                emit(t4, t5, t6, e4 && e5 && e6);
            }
        }
    }
}

/// Spherical wrist, 2 ∥ 3 (module documentation).
fn wrist_parallel(
    p: &Prepared,
    g: &Se3,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let (k, r, pw) = (&p.k, &p.r, &p.center);
    let rg = g.rotation();
    let y = g.transform_point(pw);
    let d1 = k[1].dot(&(pw - r[0]));
    // k₃ = s k₂ (parallel), so R₂ R₃ = R(k₂, θ₂ + s θ₃).
    let s3 = k[1].dot(&k[2]).signum();
    for &(phi, e1) in roots(sp4(&k[1], &(y - r[0]), &k[0], d1), true, singular).iter() {
        let t1 = -phi;
        let r1t = rotation(&k[0], phi);
        let rg1 = r1t * rg;
        let z = r[0] + r1t * (y - r[0]);
        let d = (z - r[1]).norm();
        for &(t3, e3) in roots(sp3(&(pw - r[2]), &(r[1] - r[2]), &k[2], d), true, singular).iter() {
            let x = r[2] + rotate(&k[2], t3, &(pw - r[2]));
            for &(t2, e2) in roots(sp1(&(x - r[1]), &(z - r[1]), &k[1]), false, singular).iter() {
                let rw = rotation(&k[1], -(t2 + s3 * t3)) * rg1;
                wrist(p, &rw, singular, |t4, t5, t6, ok| {
                    emit([t1, t2, t3, t4, t5, t6], ok && e1 && e2 && e3);
                });
            }
        }
    }
}

/// Spherical wrist, axes 1–2 (`first`) or 2–3 meeting (module documentation).
fn wrist_intersecting(
    p: &Prepared,
    g: &Se3,
    first: bool,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let (k, r, pw, o) = (&p.k, &p.r, &p.center, &p.meet);
    let rg = g.rotation();
    let y = g.transform_point(pw);
    let mut finish = |t1: f64, t2: f64, t3: f64, ok: bool, singular: &mut bool| {
        let r123 = rotation(&k[0], t1) * rotation(&k[1], t2) * rotation(&k[2], t3);
        let rw = r123.transpose() * rg;
        wrist(p, &rw, singular, |t4, t5, t6, e| {
            emit([t1, t2, t3, t4, t5, t6], ok && e);
        });
    };
    if first {
        let d = (y - o).norm();
        for &(t3, e3) in roots(sp3(&(pw - r[2]), &(o - r[2]), &k[2], d), true, singular).iter() {
            let x = r[2] + rotate(&k[2], t3, &(pw - r[2]));
            let (a, b) = (y - o, x - o);
            for &(m1, t2, e12) in pairs(sp2(&a, &b, &k[0], &k[1]), &a, &b, &k[1], singular).iter() {
                finish(-m1, t2, t3, e3 && e12, singular);
            }
        }
    } else {
        let d = (pw - o).norm();
        for &(phi, e1) in roots(sp3(&(y - r[0]), &(o - r[0]), &k[0], d), true, singular).iter() {
            let z = r[0] + rotate(&k[0], phi, &(y - r[0]));
            let (a, b) = (z - o, pw - o);
            for &(m2, t3, e23) in pairs(sp2(&a, &b, &k[1], &k[2]), &a, &b, &k[2], singular).iter() {
                finish(-phi, -m2, t3, e1 && e23, singular);
            }
        }
    }
}

/// (θ₁, θ₂, θ₃) with e₁ e₂ e₃ x = y for three general axes: R(k₁, −θ₁)(y − r₁) + r₁ − r₂ =
/// R₂ ((r₃ − r₂) + R₃ (x − r₃)), subproblem 5 (up to 4 triples).
fn position_3r(p: &Prepared, y: &V3, x: &V3) -> Few<(f64, f64, f64), 4> {
    let (k, r) = (&p.k, &p.r);
    let mut out = sp5(
        &(r[0] - r[1]),
        &(y - r[0]),
        &(r[2] - r[1]),
        &(x - r[2]),
        &k[0],
        &k[1],
        &k[2],
    );
    for t in out.iter_mut() {
        t.0 = -t.0;
    }
    out
}

/// Spherical wrist only (module documentation): subproblem 5 for θ₁, θ₂, θ₃, then the wrist.
fn wrist_only(p: &Prepared, g: &Se3, singular: &mut bool, emit: &mut impl FnMut([f64; 6], bool)) {
    let (k, pw) = (&p.k, &p.center);
    let rg = g.rotation();
    let y = g.transform_point(pw);
    for &(t1, t2, t3) in position_3r(p, &y, pw).iter() {
        let r123 = rotation(&k[0], t1) * rotation(&k[1], t2) * rotation(&k[2], t3);
        let rw = r123.transpose() * rg;
        wrist(p, &rw, singular, |t4, t5, t6, ok| {
            emit([t1, t2, t3, t4, t5, t6], ok);
        });
    }
}

/// The triples (θ₁, θ₂, θ₃) reaching y = e₁ e₂ e₃ e₄ p₅₆ at θ₄ (subproblem 5), each with the
/// orientation error e = k₅ᵀ R_w k₆ − k₅ᵀ k₆ (R_w = (R₁R₂R₃R₄)ᵀ R_g), zero exactly when
/// R₅ R₆ = R_w has a solution.
fn search56_at(p: &Prepared, g: &Se3, t4: f64) -> Few<([f64; 4], f64), 4> {
    let (k, r, p56) = (&p.k, &p.r, &p.center);
    let y = g.transform_point(p56);
    let x = r[3] + rotate(&k[3], t4, &(p56 - r[3]));
    let mut out = Few::default();
    for &(t1, t2, t3) in position_3r(p, &y, &x).iter() {
        let t = [t1, t2, t3, t4];
        let r14 = rotation(&k[0], t[0])
            * rotation(&k[1], t[1])
            * rotation(&k[2], t[2])
            * rotation(&k[3], t[3]);
        let rw = r14.transpose() * g.rotation();
        out.push((t, k[4].dot(&(rw * k[5])) - k[4].dot(&k[5])));
    }
    out
}

/// The roots of a 1D search: `at(θ)` gives up to 4 branches (a state whose first 3 entries
/// identify the branch, and an error e); the roots are the θ where a branch's e = 0. θ is
/// sampled at [`SEARCH_SAMPLES`] points over a turn; consecutive branches are matched by
/// nearness of their states; a sign change along a branch — or before a branch ends or after
/// it begins inside an interval (two roots of a quartic merging: a fold, located by bisection
/// on existence) — is bisected to machine precision. A root where e only touches zero (a
/// double root) is missed, as by any sampled search; a sign change across a branch jump is
/// rejected (|e| must vanish). Returns the states at the roots.
fn search_1d(at: impl Fn(f64) -> Few<([f64; 4], f64), 4>) -> Vec<[f64; 4]> {
    use std::f64::consts::{PI, TAU};
    let theta = |i: usize| -PI + TAU * i as f64 / SEARCH_SAMPLES as f64;
    let samples: Vec<Few<([f64; 4], f64), 4>> = (0..SEARCH_SAMPLES).map(|i| at(theta(i))).collect();
    let dist = |a: &[f64; 4], b: &[f64; 4]| (0..3).map(|i| wrap(a[i] - b[i]).abs()).sum::<f64>();
    // The branch at θ nearest to a reference state.
    let nearest = |t: f64, reference: &[f64; 4]| -> Option<([f64; 4], f64)> {
        at(t)
            .iter()
            .copied()
            .min_by(|a, b| dist(&a.0, reference).total_cmp(&dist(&b.0, reference)))
            .filter(|c| dist(&c.0, reference) < 0.5)
    };
    // The branch's sign change between `a` (triple ta, error ea) and `b`, bisected along it.
    let bisect = |mut a: f64, mut b: f64, ea: f64, ta: [f64; 4]| -> Option<[f64; 4]> {
        let (mut ea, mut ta) = (ea, ta);
        for _ in 0..60 {
            let mid = 0.5 * (a + b);
            let (tm, em) = nearest(mid, &ta)?;
            if em.signum() == ea.signum() && em != 0.0 {
                (a, ea, ta) = (mid, em, tm);
            } else {
                b = mid;
            }
            if (b - a).abs() < 1e-15 {
                break;
            }
        }
        nearest(0.5 * (a + b), &ta)
            .filter(|c| c.1.abs() <= 1e-9)
            .map(|c| c.0)
    };
    // Where the branch through `t` at `from` ends on the way to `to` (roots of the quartic
    // merging: a fold): the last point it exists, its triple and error.
    let fold = |from: f64, to: f64, t: [f64; 4], e: f64| -> (f64, [f64; 4], f64) {
        let (mut a, mut b, mut last) = (from, to, (t, e));
        for _ in 0..50 {
            let mid = 0.5 * (a + b);
            match nearest(mid, &last.0) {
                Some(c) => {
                    a = mid;
                    last = c;
                }
                None => b = mid,
            }
        }
        (a, last.0, last.1)
    };
    let matched = |t: &[f64; 4], set: &Few<([f64; 4], f64), 4>| {
        set.iter()
            .copied()
            .min_by(|x, y| dist(&x.0, t).total_cmp(&dist(&y.0, t)))
            .filter(|c| dist(&c.0, t) < 0.5)
    };
    let mut roots: Vec<[f64; 4]> = Vec::new();
    for i in 0..SEARCH_SAMPLES {
        let j = (i + 1) % SEARCH_SAMPLES;
        let (a0, b0) = (theta(i), theta(i) + TAU / SEARCH_SAMPLES as f64);
        for &(ta, ea) in samples[i].iter() {
            match matched(&ta, &samples[j]) {
                Some((_, eb)) => {
                    if ea.signum() != eb.signum() || ea == 0.0 {
                        roots.extend(bisect(a0, b0, ea, ta));
                    }
                }
                None => {
                    // The branch ends inside the interval: a sign change before its end.
                    let (end, te, ee) = fold(a0, b0, ta, ea);
                    if ea.signum() != ee.signum() {
                        roots.extend(bisect(a0, end, ea, ta));
                    } else if ee.abs() <= 1e-9 {
                        roots.push(te);
                    }
                }
            }
        }
        // Branches born inside the interval.
        for &(tb, eb) in samples[j].iter() {
            if matched(&tb, &samples[i]).is_some() {
                continue;
            }
            let (start, ts, es) = fold(b0, a0, tb, eb);
            if es.signum() != eb.signum() {
                roots.extend(bisect(start, b0, es, ts));
            } else if es.abs() <= 1e-9 {
                roots.push(ts);
            }
        }
    }
    roots
}

/// Axes 5 and 6 meeting (a 1D search over θ₄, as IK-Geo does for this family): p₅₆ is moved
/// by joints 1–4 only, so for each θ₄ subproblem 5 gives up to 4 triples (θ₁, θ₂, θ₃)
/// ([`search56_at`]), and a triple belongs to a solution when R₅ R₆ = R_w is solvable, i.e.
/// when e(θ₄) = k₅ᵀ R_w k₆ − k₅ᵀ k₆ = 0 ([`search_1d`]); θ₅ and θ₆ then follow by
/// subproblem 1.
fn search56(p: &Prepared, g: &Se3, emit: &mut impl FnMut([f64; 6], bool)) {
    let (k, rg) = (&p.k, g.rotation());
    let roots = search_1d(|t4| search56_at(p, g, t4));
    let mut found: Few<[f64; 6], MAX_POSTURES> = Few::default();
    for t in roots {
        let r14 = rotation(&k[0], t[0])
            * rotation(&k[1], t[1])
            * rotation(&k[2], t[2])
            * rotation(&k[3], t[3]);
        let rw = r14.transpose() * rg;
        // R₅ k₆ = R_w k₆, R₆ k₅ = R₅ᵀ R_w k₅.
        let t5 = sp1(&k[5], &(rw * k[5]), &k[4]).first();
        let want = rotation(&k[4], t5).transpose() * (rw * k[4]);
        let t6 = sp1(&k[4], &want, &k[5]).first();
        let q = [t[0], t[1], t[2], wrap(t[3]), t5, t6];
        if !found
            .iter()
            .any(|f| (0..6).all(|i| wrap(f[i] - q[i]).abs() < 1e-7))
        {
            found.push(q);
            emit(q, true);
        }
    }
}

/// For the two-parallel search at θ₁, with h = e₁⁻¹ g = e₂ e₃ e₄ e₅ e₆ and R₂₃ = R(k₂, θ₂₃):
/// the k₂ components of h e₆⁻¹ r₅ = e₂ e₃ e₄ r₅ and of R₄ R₅ k₅ = R₂₃ᵀ R_h R₆ᵀ k₅ give
/// (R_hᵀ k₂)ᵀ R(k₆, −θ₆)(r₅ − r₆) − k₂ᵀ R₄ (r₅ − r₄) = k₂·r₄ − k₂·(h r₆) and
/// (R_hᵀ k₂)ᵀ R(k₆, −θ₆) k₅ − k₂ᵀ R₄ k₅ = 0: subproblem 6 in (−θ₆, θ₄). Then θ₂₃ (subproblem
/// 1), θ₅ (subproblem 1) and H₂₃ = h e₆⁻¹ e₅⁻¹ e₄⁻¹ = e₂ e₃; the branch is a solution when
/// H₂₃ r₃ is as far from axis 2 as r₃ is: the error. State: (θ₆, θ₄, θ₂₃, θ₁).
fn search23_at(p: &Prepared, g: &Se3, t1: f64) -> Few<([f64; 4], f64), 4> {
    let (k, r) = (&p.k, &p.r);
    let r1t = rotation(&k[0], -t1);
    let hr = r1t * g.rotation();
    let h = |x: &V3| r[0] + r1t * (g.transform_point(x) - r[0]);
    let hk2 = hr.transpose() * k[1];
    let (p56, p45) = (r[4] - r[5], r[3] - r[4]);
    let mk5 = -k[4];
    let d1 = k[1].dot(&r[3]) - k[1].dot(&h(&r[5]));
    let mut out = Few::default();
    for &(m6, t4) in sp6(
        [&hk2, &k[1], &hk2, &k[1]],
        [&k[5], &k[3], &k[5], &k[3]],
        [&p56, &p45, &k[4], &mk5],
        d1,
        0.0,
    )
    .iter()
    {
        let t6 = -m6;
        let (r4, r6) = (rotation(&k[3], t4), rotation(&k[5], t6));
        let t23 = sp1(&(r4 * k[4]), &(hr * (r6.transpose() * k[4])), &k[1]).first();
        let (h23, _) = two_parallel_rest(p, g, t1, t23, t4, t6);
        let off = |x: V3| {
            let d = x - r[1];
            (d - k[1] * k[1].dot(&d)).norm()
        };
        out.push(([t6, t4, t23, t1], off(h23) - off(r[2])));
    }
    out
}

/// θ₅ and H₂₃ r₃ for the two-parallel search (see [`search23_at`]).
fn two_parallel_rest(p: &Prepared, g: &Se3, t1: f64, t23: f64, t4: f64, t6: f64) -> (V3, f64) {
    let (k, r) = (&p.k, &p.r);
    let r1t = rotation(&k[0], -t1);
    let hr = r1t * g.rotation();
    let (r4, r6, r23) = (
        rotation(&k[3], t4),
        rotation(&k[5], t6),
        rotation(&k[1], t23),
    );
    // R₅ = R₄ᵀ R₂₃ᵀ R_h R₆ᵀ: R₅ k₆ = R₄ᵀ R₂₃ᵀ R_h k₆ (or, with k₆ ∥ k₅, R₅ᵀ k₄ = R₆ R_hᵀ R₂₃ k₄).
    let t5 = if k[4].cross(&k[5]).norm() > 1e-3 {
        let want = r4.transpose() * (r23.transpose() * (hr * k[5]));
        sp1(&k[5], &want, &k[4]).first()
    } else {
        let want = r6 * (hr.transpose() * (r23 * k[3]));
        -sp1(&k[3], &want, &k[4]).first()
    };
    // H₂₃ r₃ = h(e₆⁻¹(e₅⁻¹(e₄⁻¹ r₃))).
    let back = |i: usize, t: f64, x: V3| r[i] + rotate(&k[i], -t, &(x - r[i]));
    let x = back(5, t6, back(4, t5, back(3, t4, r[2])));
    let hx = r[0] + r1t * (g.transform_point(&x) - r[0]);
    (hx, t5)
}

/// Axes 2 ∥ 3 only (a 1D search over θ₁, as IK-Geo does for this family): [`search23_at`]
/// and [`search_1d`]; then θ₂ by subproblem 1 (e₂ r₃ = H₂₃ r₃) and θ₃ = ±(θ₂₃ − θ₂).
fn search23(p: &Prepared, g: &Se3, emit: &mut impl FnMut([f64; 6], bool)) {
    let (k, r) = (&p.k, &p.r);
    let s3 = k[1].dot(&k[2]).signum();
    let mut found: Few<[f64; 6], MAX_POSTURES> = Few::default();
    for st in search_1d(|t1| search23_at(p, g, t1)) {
        let [t6, t4, t23, t1] = st;
        let (h23, t5) = two_parallel_rest(p, g, t1, t23, t4, t6);
        let t2 = sp1(&(r[2] - r[1]), &(h23 - r[1]), &k[1]).first();
        let q = [wrap(t1), t2, wrap(s3 * (t23 - t2)), t4, t5, t6];
        if !found
            .iter()
            .any(|f| (0..6).all(|i| wrap(f[i] - q[i]).abs() < 1e-7))
        {
            found.push(q);
            emit(q, true);
        }
    }
}

/// 2 ∥ 3 ∥ 4 with axes 5 and 6 meeting, or (`general`) without (module documentation).
fn three_parallel(
    p: &Prepared,
    g: &Se3,
    general: bool,
    singular: &mut bool,
    emit: &mut impl FnMut([f64; 6], bool),
) {
    let (k, r) = (&p.k, &p.r);
    let rg = g.rotation();
    let p4 = r[3];
    // (θ₁, θ₅) with their exactness: axes 5, 6 meeting at p₅₆, subproblems 4 then 4; in
    // general subproblem 6 on the k₂ components (module documentation).
    let mut pairs15: Few<(f64, bool, f64, bool), 4> = Few::default();
    if general {
        let gr6 = g.transform_point(&r[5]) - r[0];
        let rgk6 = rg * k[5];
        let (p6, mk6) = (r[4] - r[5], -k[5]);
        for &(phi, t5) in sp6(
            [&k[1], &k[1], &k[1], &k[1]],
            [&k[0], &k[4], &k[0], &k[4]],
            [&gr6, &p6, &rgk6, &mk6],
            k[1].dot(&(r[4] - r[0])),
            0.0,
        )
        .iter()
        {
            pairs15.push((-phi, true, t5, true));
        }
    } else {
        let p56 = &p.center;
        let y = g.transform_point(p56);
        let d1 = k[1].dot(&(p56 - r[0]));
        for &(phi, e1) in roots(sp4(&k[1], &(y - r[0]), &k[0], d1), true, singular).iter() {
            let v5 = rotation(&k[0], phi) * rg * k[5];
            let five = sp4_unit(&k[1], &k[5], &k[4], &v5)
                .unwrap_or_else(|| sp4(&k[1], &k[5], &k[4], k[1].dot(&v5)));
            for &(t5, e5) in roots(five, true, singular).iter() {
                pairs15.push((-phi, e1, t5, e5));
            }
        }
    }
    for &(t1, e1, t5, e5) in pairs15.iter() {
        let phi = -t1;
        let r1t = rotation(&k[0], phi);
        let rg1 = r1t * rg;
        {
            let r5t = rotation(&k[4], -t5);
            let a = rg1.transpose() * k[1];
            let b = r5t * k[1];
            let x5 = r[4] + r5t * (p4 - r[4]);
            let sixes = match sp1(&a, &b, &k[5]) {
                Angles::Any => {
                    // Axis 6 ∥ k₂ (θ₅ = 0 or π): θ₆ joins the planar problem (a planar 4R),
                    // so pick it to put h p₄ at the middle of the 3R's reach:
                    // ‖h p₄ − r₂‖ = ‖R(k₆, −θ₆)(x₅ − r₆) − w‖ with x₅ = e₅⁻¹ p₄ and
                    // w = −R_gᵀ R₁ (r₁ − r₂ + R₁ᵀ (g r₆ − r₁)) (subproblem 3).
                    *singular = true;
                    let c0 = r[0] - r[1] + r1t * (g.transform_point(&r[5]) - r[0]);
                    let w = -(rg1.transpose() * c0);
                    let (v, u) = (p4 - r[2], r[1] - r[2]);
                    let mid = (v.norm_squared() + u.norm_squared()
                        - 2.0 * k[2].dot(&v) * k[2].dot(&u))
                    .max(0.0)
                    .sqrt();
                    // θ₆ is a free choice here: its own exactness does not matter, the planar
                    // subproblems below tell whether the pose is reached.
                    let mut out = roots(sp3(&(x5 - r[5]), &w, &k[5], mid), false, singular);
                    for x in out.iter_mut() {
                        *x = (-x.0, true);
                    }
                    out
                }
                other => roots(other, false, singular),
            };
            for &(t6, e6) in sixes.iter() {
                // h = e₁⁻¹ g e₆⁻¹ e₅⁻¹ applied to p₄, and its rotation applied to perp.
                let r6t = rotation(&k[5], -t6);
                let x = r[5] + r6t * (x5 - r[5]);
                let x = g.transform_point(&x);
                let hp4 = r[0] + r1t * (x - r[0]);
                let hperp = rg1 * (r6t * (r5t * p.perp));
                let (sum, es) = roots(sp1(&p.perp, &hperp, &k[1]), false, singular)[0];
                let d = (hp4 - r[1]).norm();
                for &(t3, e3) in
                    roots(sp3(&(p4 - r[2]), &(r[1] - r[2]), &k[2], d), true, singular).iter()
                {
                    let x = r[2] + rotate(&k[2], t3, &(p4 - r[2]));
                    for &(t2, e2) in
                        roots(sp1(&(x - r[1]), &(hp4 - r[1]), &k[1]), false, singular).iter()
                    {
                        let t4 = wrap(sum - t2 - t3);
                        emit([t1, t2, t3, t4, t5, t6], e1 && e5 && e6 && es && e3 && e2);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_matches_rotate() {
        let k = V3::new(0.3, -0.4, 0.5).normalize();
        let p = V3::new(1.0, 2.0, -0.5);
        for t in [-3.0, -0.2, 0.0, 1.1, 3.1] {
            assert!((rotation(&k, t) * p - rotate(&k, t, &p)).norm() < 1e-14);
        }
    }
}
