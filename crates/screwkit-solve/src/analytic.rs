//! Analytic IK by subproblem decomposition: every solution of a 6R pose, for the families that
//! have a closed form. Implemented: a spherical wrist with axes 2 ∥ 3 (KUKA KR, ABB IRB,
//! PUMA-type; axes 1 and 2 may or may not intersect) — the other families are classified
//! ([`crate::family`]) but not solved here yet (issue 12).
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

/// Every solution of T(q) = `target` for a chain of the spherical-wrist, 2 ∥ 3 family (see
/// the module documentation); an error naming the family for any other chain.
pub fn solve_all(kin: &Kinematics, target: &Se3) -> Result<Solutions, SolveError> {
    let c = classify(kin);
    if !matches!(
        c.family,
        Family::SphericalWristTwoParallel | Family::SphericalWristTwoIntersecting
    ) {
        return Err(SolveError::InvalidInput(format!(
            "no analytic solver for this chain yet: {}",
            c.family.describe()
        )));
    }
    if !target.is_finite() {
        return Err(SolveError::BadTarget(String::new()));
    }
    let pw = c.wrist_center.expect("the family has a wrist center");
    let s: Vec<Twist> = kin.space.iter().map(|j| j.twist()).collect();
    let k: Vec<Vector3<f64>> = c.axes.iter().map(|a| a.direction).collect();
    let r: Vec<Vector3<f64>> = c.axes.iter().map(|a| a.point).collect();
    let g = target.compose(&kin.home.inverse());
    let y = g.transform_point(&pw);
    let mut singular = false;
    let mut raw: Vec<([f64; 6], bool)> = Vec::new();
    // θ1: k2 · e1⁻¹ y = k2 · p_w, i.e. k2ᵀ R(k1, −θ1)(y − r1) = k2 · (p_w − r1).
    for (phi, e1) in angles(
        sp4(&k[1], &(y - r[0]), &k[0], k[1].dot(&(pw - r[0]))),
        &mut singular,
    ) {
        let t1 = -phi;
        let z = move_point(&s[0], -t1, &y);
        // θ3: ‖e3 p_w − r2‖ = ‖z − r2‖.
        let d = (z - r[1]).norm();
        for (t3, e3) in angles(sp3(&(pw - r[2]), &(r[1] - r[2]), &k[2], d), &mut singular) {
            let x = move_point(&s[2], t3, &pw);
            // θ2: e2 x = z.
            for (t2, e2) in angles(sp1(&(x - r[1]), &(z - r[1]), &k[1]), &mut singular) {
                let e123 = [(0, t1), (1, t2), (2, t3)]
                    .iter()
                    .fold(Se3::identity(), |acc, &(i, t)| {
                        acc.compose(&Se3::exp(&Twist::new(s[i].w * t, s[i].v * t)))
                    });
                let rw = e123.inverse().compose(&g);
                let rw = rw.rotation();
                // θ5: k4ᵀ R(k5, θ5) k6 = k4ᵀ R_w k6.
                let d5 = k[3].dot(&(rw * k[5]));
                for (t5, e5) in angles(sp4(&k[3], &k[5], &k[4], d5), &mut singular) {
                    let r5k6 = rot(&k[4], t5) * k[5];
                    for (t4, e4) in angles(sp1(&r5k6, &(rw * k[5]), &k[3]), &mut singular) {
                        // θ6: R(k6, θ6) x = (R4 R5)ᵀ R_w x for an x not along k6.
                        let x6 = if k[4].cross(&k[5]).norm() > 1e-6 {
                            k[4]
                        } else {
                            k[3]
                        };
                        let r45 = rot(&k[3], t4) * rot(&k[4], t5);
                        let want = r45.transpose() * rw * x6;
                        for (t6, e6) in angles(sp1(&x6, &want, &k[5]), &mut singular) {
                            let ok = e1 && e2 && e3 && e4 && e5 && e6;
                            raw.push(([t1, t2, t3, t4, t5, t6], ok));
                        }
                    }
                }
            }
        }
    }
    // The exact branches if there are any (a branch can be out of reach while another is not);
    // otherwise the least-squares ones.
    let exact = raw.iter().any(|(_, ok)| *ok);
    // Every 2π shift of each angle inside the joint limits.
    let mut q: Vec<Vec<f64>> = Vec::new();
    for (sol, ok) in raw {
        if ok != exact {
            continue;
        }
        let mut options: Vec<Vec<f64>> = vec![Vec::new()];
        for (i, &t) in sol.iter().enumerate() {
            let (lo, hi) = (kin.lower[i], kin.upper[i]);
            let shifts: Vec<f64> = if kin.continuous[i] {
                vec![crate::subproblem::wrap(t)]
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
        for o in options {
            if !q
                .iter()
                .any(|p| p.iter().zip(&o).all(|(a, b)| (a - b).abs() < 1e-9))
            {
                q.push(o);
            }
        }
    }
    Ok(Solutions { q, exact, singular })
}
