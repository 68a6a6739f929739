//! Analytic IK by subproblem decomposition: every solution of a 6R pose, for the families that
//! have a closed form. Implemented: a spherical wrist with axes 2 ∥ 3 (KUKA KR, ABB IRB,
//! PUMA-type; axes 1 and 2 may or may not intersect), and axes 2 ∥ 3 ∥ 4 with axes 5 and 6
//! meeting (UR-type) — the other families are classified ([`crate::family`]) but not solved
//! here yet (issue 12).
//!
//! With g = T_d M⁻¹ = e^\[S₁\]θ₁ ⋯ e^\[S₆\]θ₆ and p_w the wrist center (axes 4, 5, 6 pass
//! through it, so they do not move it): y = g p_w = e₁ e₂ e₃ p_w. Rotations about axes 2 and 3
//! (both along k₂) keep the k₂ component, so k₂ · e₁⁻¹ y = k₂ · p_w gives θ₁ (subproblem 4);
//! with z = e₁⁻¹ y, distances to axis 2 are kept by e₂, so ‖z − r₂‖ = ‖e₃ p_w − r₂‖ gives θ₃
//! (subproblem 3); e₂ (e₃ p_w) = z gives θ₂ (subproblem 1). The wrist's rotation
//! R_w = R(k₄,θ₄) R(k₅,θ₅) R(k₆,θ₆) = rotation of (e₁e₂e₃)⁻¹ g gives θ₅ from
//! k₄ᵀ R₅ k₆ = k₄ᵀ R_w k₆ (subproblem 4), θ₄ from R₄ (R₅ k₆) = R_w k₆ and θ₆ from the rest
//! (subproblem 1). Up to 2 × 2 × 2 = 8 solutions, each then taken at every 2π shift inside the
//! joint limits and checked by FK.

use nalgebra::{Matrix3, Vector3};
use screwkit_lie::{Se3, Twist};

use crate::error::SolveError;
use crate::family::{classify, Family};
use crate::kinematics::Kinematics;
use crate::subproblem::{sp1, sp3, sp4, Angles};

/// All the solutions of one pose.
#[derive(Debug, Clone, PartialEq)]
pub struct Solutions {
    /// Every solution within the joint limits, each a q of length 6.
    pub q: Vec<Vec<f64>>,
    /// False when the pose is out of reach: then `q` holds the least-squares configurations
    /// (closest in the subproblems' measures), which do not reach it.
    pub exact: bool,
    /// True when a wrist or shoulder singularity left an angle free (set to 0): there are
    /// infinitely many solutions and `q` shows one of each family.
    pub singular: bool,
    /// How many of them are different modulo 2π (the arm's distinct postures: elbow up/down,
    /// wrist flip, shoulder left/right — at most 8); `q` also lists every 2π shift of each that
    /// the limits allow (a UR5 with ±2π limits has up to 8 × 2⁶).
    pub branches: usize,
}

impl Solutions {
    /// Orders the solutions nearest to `seed` first (Euclidean distance in joint space): the
    /// first is the one that moves the arm least from where it is.
    pub fn sort_nearest(&mut self, seed: &[f64]) {
        let dist = |q: &[f64]| -> f64 { q.iter().zip(seed).map(|(a, b)| (a - b) * (a - b)).sum() };
        self.q.sort_by(|a, b| dist(a).total_cmp(&dist(b)));
    }
}

/// The angles of a subproblem, each with whether it is exact: the exact ones, or the
/// least-squares one, or 0 for "any" (exact, and `singular` is set).
fn angles(a: Angles, singular: &mut bool) -> Vec<(f64, bool)> {
    match a {
        Angles::Exact(v) => v.into_iter().map(|t| (t, true)).collect(),
        Angles::LeastSquares(t) => vec![(t, false)],
        Angles::Any => {
            *singular = true;
            vec![(0.0, true)]
        }
    }
}

/// e^\[S\]θ applied to a point.
fn move_point(s: &Twist, theta: f64, p: &Vector3<f64>) -> Vector3<f64> {
    Se3::exp(&Twist::new(s.w * theta, s.v * theta)).transform_point(p)
}

fn rot(k: &Vector3<f64>, theta: f64) -> Matrix3<f64> {
    *Se3::exp(&Twist::new(k * theta, Vector3::zeros())).rotation()
}

/// Every solution of T(q) = `target` for a chain of a family solved here (see the module
/// documentation); an error naming the family for any other chain.
pub fn solve_all(kin: &Kinematics, target: &Se3) -> Result<Solutions, SolveError> {
    let c = classify(kin);
    if !target.is_finite() {
        return Err(SolveError::BadTarget(String::new()));
    }
    let mut singular = false;
    let raw = match c.family {
        Family::SphericalWristTwoParallel | Family::SphericalWristTwoIntersecting => {
            spherical_wrist(kin, &c, target, &mut singular)
        }
        Family::ThreeParallelTwoIntersecting
            if c.parallel == [1, 2] && c.intersecting.iter().any(|&(i, _)| i == 4) =>
        {
            three_parallel(kin, &c, target, &mut singular)
        }
        f => {
            return Err(SolveError::InvalidInput(format!(
                "no analytic solver for this chain yet: {}",
                f.describe()
            )))
        }
    };
    Ok(within_limits(kin, raw, singular))
}

/// The exact branches if there are any (a branch can be out of reach while another is not),
/// otherwise the least-squares ones; each at every 2π shift inside the joint limits.
fn within_limits(kin: &Kinematics, raw: Vec<([f64; 6], bool)>, singular: bool) -> Solutions {
    let exact = raw.iter().any(|(_, ok)| *ok);
    let mut q: Vec<Vec<f64>> = Vec::new();
    // One entry per posture (modulo 2π); its shifts are then distinct by construction.
    let mut distinct: Vec<[f64; 6]> = Vec::new();
    for (sol, ok) in raw {
        if ok != exact {
            continue;
        }
        let wrapped = sol.map(crate::subproblem::wrap);
        let same = |d: &[f64; 6]| {
            d.iter()
                .zip(&wrapped)
                .all(|(a, b)| crate::subproblem::wrap(a - b).abs() < 1e-9)
        };
        if distinct.iter().any(same) {
            continue;
        }
        let mut options: Vec<Vec<f64>> = vec![Vec::new()];
        for (i, &t) in wrapped.iter().enumerate() {
            let (lo, hi) = (kin.lower[i], kin.upper[i]);
            let shifts: Vec<f64> = if kin.continuous[i] {
                vec![t]
            } else {
                (-2..=2)
                    .map(|m| t + f64::from(m) * std::f64::consts::TAU)
                    .filter(|x| *x >= lo - 1e-12 && *x <= hi + 1e-12)
                    .map(|x| x.clamp(lo, hi))
                    .collect()
            };
            options = options
                .into_iter()
                .flat_map(|prefix| {
                    shifts.iter().map(move |&x| {
                        let mut p = prefix.clone();
                        p.push(x);
                        p
                    })
                })
                .collect();
        }
        if !options.is_empty() {
            distinct.push(wrapped);
            q.extend(options);
        }
    }
    Solutions {
        q,
        exact,
        singular,
        branches: distinct.len(),
    }
}

/// The spherical-wrist, 2 ∥ 3 family (module documentation).
fn spherical_wrist(
    kin: &Kinematics,
    c: &crate::family::Classification,
    target: &Se3,
    singular: &mut bool,
) -> Vec<([f64; 6], bool)> {
    let pw = c.wrist_center.expect("the family has a wrist center");
    let s: Vec<Twist> = kin.space.iter().map(|j| j.twist()).collect();
    let k: Vec<Vector3<f64>> = c.axes.iter().map(|a| a.direction).collect();
    let r: Vec<Vector3<f64>> = c.axes.iter().map(|a| a.point).collect();
    let g = target.compose(&kin.home.inverse());
    let y = g.transform_point(&pw);
    let mut raw: Vec<([f64; 6], bool)> = Vec::new();
    // θ1: k2 · e1⁻¹ y = k2 · p_w, i.e. k2ᵀ R(k1, −θ1)(y − r1) = k2 · (p_w − r1).
    for (phi, e1) in angles(
        sp4(&k[1], &(y - r[0]), &k[0], k[1].dot(&(pw - r[0]))),
        singular,
    ) {
        let t1 = -phi;
        let z = move_point(&s[0], -t1, &y);
        // θ3: ‖e3 p_w − r2‖ = ‖z − r2‖.
        let d = (z - r[1]).norm();
        for (t3, e3) in angles(sp3(&(pw - r[2]), &(r[1] - r[2]), &k[2], d), singular) {
            let x = move_point(&s[2], t3, &pw);
            // θ2: e2 x = z.
            for (t2, e2) in angles(sp1(&(x - r[1]), &(z - r[1]), &k[1]), singular) {
                let e123 = [(0, t1), (1, t2), (2, t3)]
                    .iter()
                    .fold(Se3::identity(), |acc, &(i, t)| {
                        acc.compose(&Se3::exp(&Twist::new(s[i].w * t, s[i].v * t)))
                    });
                let rw = e123.inverse().compose(&g);
                let rw = rw.rotation();
                // θ5: k4ᵀ R(k5, θ5) k6 = k4ᵀ R_w k6.
                let d5 = k[3].dot(&(rw * k[5]));
                for (t5, e5) in angles(sp4(&k[3], &k[5], &k[4], d5), singular) {
                    let r5k6 = rot(&k[4], t5) * k[5];
                    for (t4, e4) in angles(sp1(&r5k6, &(rw * k[5]), &k[3]), singular) {
                        // θ6: R(k6, θ6) x = (R4 R5)ᵀ R_w x for an x not along k6.
                        let x6 = if k[4].cross(&k[5]).norm() > 1e-6 {
                            k[4]
                        } else {
                            k[3]
                        };
                        let r45 = rot(&k[3], t4) * rot(&k[4], t5);
                        let want = r45.transpose() * rw * x6;
                        for (t6, e6) in angles(sp1(&x6, &want, &k[5]), singular) {
                            let ok = e1 && e2 && e3 && e4 && e5 && e6;
                            raw.push(([t1, t2, t3, t4, t5, t6], ok));
                        }
                    }
                }
            }
        }
    }
    raw
}

/// The UR-type family: axes 2, 3, 4 parallel (along k₂), axes 5 and 6 meeting at p₅₆.
/// Rotations 2–4 keep k₂ components of points and vectors, so with g = T_d M⁻¹:
/// k₂ · e₁⁻¹ g p₅₆ = k₂ · p₅₆ gives θ₁ (subproblem 4; p₅₆ is on axes 5 and 6); with
/// R₁ known, k₂ᵀ R₁ᵀ R_g k₆ = k₂ᵀ R(k₅, θ₅) k₆ gives θ₅ (subproblem 4, k₆ is kept by R₆);
/// R(k₆, θ₆) R_gᵀ R₁ k₂ = R(k₅, −θ₅) k₂ gives θ₆ (subproblem 1). Then h = e₁⁻¹ g e₆⁻¹ e₅⁻¹
/// = e₂ e₃ e₄ is a planar 3R problem: p₄ (on axis 4) gives ‖e₃ p₄ − r₂‖ = ‖h p₄ − r₂‖ → θ₃
/// (subproblem 3), e₂ (e₃ p₄) = h p₄ → θ₂ (subproblem 1), and θ₄ from the rotation of h about
/// k₂ minus θ₂ + θ₃ (subproblem 1 on a vector ⊥ k₂). Up to 2 × 2 × 2 = 8 solutions.
fn three_parallel(
    kin: &Kinematics,
    c: &crate::family::Classification,
    target: &Se3,
    singular: &mut bool,
) -> Vec<([f64; 6], bool)> {
    let s: Vec<Twist> = kin.space.iter().map(|j| j.twist()).collect();
    let k: Vec<Vector3<f64>> = c.axes.iter().map(|a| a.direction).collect();
    let r: Vec<Vector3<f64>> = c.axes.iter().map(|a| a.point).collect();
    let p56 = c
        .intersecting
        .iter()
        .find(|&&(i, _)| i == 4)
        .map(|&(_, p)| p)
        .expect("axes 5 and 6 meet");
    let e = |i: usize, t: f64| Se3::exp(&Twist::new(s[i].w * t, s[i].v * t));
    let g = target.compose(&kin.home.inverse());
    let rg = *g.rotation();
    let y = g.transform_point(&p56);
    // A vector perpendicular to k2, for the planar rotation sum.
    let perp = {
        let a = if k[1].x.abs() < 0.9 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        (a - k[1] * k[1].dot(&a)).normalize()
    };
    let mut raw = Vec::new();
    for (phi, e1) in angles(
        sp4(&k[1], &(y - r[0]), &k[0], k[1].dot(&(p56 - r[0]))),
        singular,
    ) {
        let t1 = -phi;
        let r1 = rot(&k[0], t1);
        let d5 = k[1].dot(&(r1.transpose() * rg * k[5]));
        for (t5, e5) in angles(sp4(&k[1], &k[5], &k[4], d5), singular) {
            let a = rg.transpose() * r1 * k[1];
            let b = rot(&k[4], -t5) * k[1];
            for (t6, e6) in angles(sp1(&a, &b, &k[5]), singular) {
                let h = e(0, t1)
                    .inverse()
                    .compose(&g)
                    .compose(&e(5, t6).inverse())
                    .compose(&e(4, t5).inverse());
                // The rotation of h about k2: θ2 + θ3 + θ4.
                let sum = match sp1(&perp, &(h.rotation() * perp), &k[1]) {
                    Angles::Exact(v) => (v[0], true),
                    Angles::LeastSquares(t) => (t, false),
                    Angles::Any => (0.0, true),
                };
                let p4 = r[3];
                let hp4 = h.transform_point(&p4);
                let d = (hp4 - r[1]).norm();
                for (t3, e3) in angles(sp3(&(p4 - r[2]), &(r[1] - r[2]), &k[2], d), singular) {
                    let x = e(2, t3).transform_point(&p4);
                    for (t2, e2) in angles(sp1(&(x - r[1]), &(hp4 - r[1]), &k[1]), singular) {
                        let t4 = crate::subproblem::wrap(sum.0 - t2 - t3);
                        let ok = e1 && e5 && e6 && sum.1 && e3 && e2;
                        raw.push(([t1, t2, t3, t4, t5, t6], ok));
                    }
                }
            }
        }
    }
    raw
}
