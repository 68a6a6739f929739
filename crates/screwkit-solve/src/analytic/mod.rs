//! Analytic IK: every solution of a 6R pose — or of a 7R pose with one joint locked — by
//! subproblem decomposition for the families that have a closed form ([`crate::family`]), and
//! by algebraic elimination for any other six revolute axes (the general 6R: two
//! intersecting or two parallel axes anywhere, or none). A chain of several families takes the
//! first row of the table that applies to any of them; the general 6R's row, last, applies to
//! all. Refused: a 6R chain with a spherical shoulder and a spherical wrist (a self-motion, no
//! finite solution set), 6R chains whose Jacobian has rank below 6 at every configuration
//! (coincident or all-parallel axes: `family::generic_rank`), and chains that are not 6R or
//! 7R revolute.
//!
//! Solved here (with g = T_d M⁻¹ = e^\[S₁\]θ₁ ⋯ e^\[S₆\]θ₆, k_i the unit axes, r_i points on
//! them, e_i = e^\[S_i\]θ_i, R_i = R(k_i, θ_i)), one decomposition per file, each file's
//! documentation saying which subproblem gives which angle, all listed in ONE table
//! ([`table`]: family, arrangement, kernel, words):
//!
//! | decomposition | family | file |
//! |---|---|---|
//! | spherical wrist, 2 ∥ 3 (KUKA KR, ABB IRB, PUMA-type) | `spherical_wrist_two_parallel` | `wrist_parallel.rs` |
//! | spherical wrist, axes 1–2 or 2–3 meeting | `spherical_wrist_two_intersecting` | `wrist_intersecting.rs` |
//! | 2 ∥ 3 ∥ 4 and axes 5–6 meeting (UR-type); 2 ∥ 3 ∥ 4 only | `three_parallel_two_intersecting`, `three_parallel` | `three_parallel.rs` |
//! | spherical wrist only (subproblem 5) | `spherical_wrist` | `wrist_only.rs` |
//! | the wrist step of the wrist families | | `wrist.rs` |
//! | a 7R arm with a spherical shoulder and wrist (iiwa) at a given arm angle ψ (not a row: [`AnalyticIk::arm_angle`]) | `redundant_7r` | `arm_angle.rs` |
//! | any six revolute axes: Raghavan–Roth elimination, a 24 × 24 eigenproblem | every 6R family (`general_6r`, `two_intersecting`, `two_parallel`, the others' unsolved arrangements) | `general.rs` (its eigenvalues: `crate::linalg::eigen`) |
//!
//! A closed form has up to 8 postures (solutions modulo 2π), the general 6R up to 16. A chain whose *reversed*
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

mod angles;
mod arm_angle;
mod general;
mod lock;
mod prepared;
mod solutions;
mod solver;
mod table;
mod three_parallel;
mod wrist;
mod wrist_intersecting;
mod wrist_only;
mod wrist_parallel;

use angles::*;
pub use arm_angle::SNAP as ARM_ANGLE_SNAP;
use arm_angle::*;
use general::*;
use lock::*;
pub use lock::{AUTO_POSES, AUTO_SWEEP};
pub(crate) use prepared::PreparedAt;
use prepared::*;
pub use solutions::{Posture, Postures, RepresentativeKind, Representatives, Solutions};
pub use solver::{AnalyticIk, MAX_REPRESENTATIVE_ROWS, MAX_SWEEP};
use table::*;
use three_parallel::*;
use wrist::*;
use wrist_intersecting::*;
use wrist_only::*;
use wrist_parallel::*;

type V3 = Vector3<f64>;
type M3 = Matrix3<f64>;

/// The most variables an analytic solution has (a 7R chain with one joint locked).
pub const MAX_DOF: usize = 7;
/// The most postures (solutions modulo 2π) of one pose: 8 for the special families, 16 for
/// the general 6R.
pub const MAX_POSTURES: usize = 16;

/// An exact posture whose FK residual exceeds this (× max(1, L)) is polished by Newton steps.
const POLISH: f64 = 1e-13;
/// A posture is exact when its (polished) FK residual is at most this (× max(1, L)): the
/// general 6R's candidates, and any posture after its polish.
const EXACT: f64 = 1e-9;

/// What analytic IK screwkit offers for a chain, in words: the family and how it is solved
/// (a special family's closed form, or the general 6R's elimination); for a 7R chain, which
/// joints can be locked (by name) and how each lock is solved.
pub fn describe(kin: &Kinematics) -> String {
    let c = classify(kin);
    match c.family {
        Family::Redundant7R => {
            let (mut closed, mut general) = (Vec::new(), Vec::new());
            for j in 0..7 {
                if let Ok(s) = AnalyticIk::locked(kin, j) {
                    let list = if s.method == Method::General {
                        &mut general
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
            if !general.is_empty() {
                parts.push(format!(
                    "the general 6R (algebraic) with {} locked",
                    general.join(", ")
                ));
            }
            if parts.is_empty() {
                "7R (redundant): no joint whose locking leaves a 6R chain screwkit solves: \
                 numerical IK only"
                    .into()
            } else {
                format!("7R (redundant): analytic, {}", parts.join("; "))
            }
        }
        f => match AnalyticIk::new(kin) {
            Ok(s) => format!(
                "{} ({}{})",
                f.describe(),
                s.words(),
                if s.reversed() {
                    ", solved tip to base"
                } else {
                    ""
                }
            ),
            Err(_) if kin.helical().is_some() => solver::helical_or(kin, ""),
            Err(e) if kin.dof() == 6 => format!("{}; {e}", f.describe()),
            Err(_) => f.describe().into(),
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
    // One row per posture, each joint at its representative nearest the seed: found however
    // wide the limits (every representative of ±50 rad limits is 16⁶ rows).
    let solver = AnalyticIk::new(kin)?;
    let mut sols = Solutions::default();
    solver.solve_postures(
        kin,
        ws,
        target,
        &[0.0],
        Representatives::Nearest(seed),
        &mut sols,
    )?;
    if !sols.is_exact() {
        return Ok(None);
    }
    Ok(sols.nearest(seed, None).map(|i| sols.q(i).to_vec()))
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
