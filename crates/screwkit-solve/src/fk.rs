//! Forward kinematics: T(q) = e^[S₁]θ₁ ⋯ e^[Sₙ]θₙ M (space form) = M e^[B₁]θ₁ ⋯ e^[Bₙ]θₙ (body form).
//!
//! θ_j = q_j for ordinary joints, θ_j = m q_leader + o for mimic joints.

use screwkit_lie::Se3;

use crate::error::SolveError;
use crate::kinematics::{Kinematics, Workspace};

/// Tip pose, space form T(q) = e^[S₁]θ₁ ⋯ e^[Sₙ]θₙ M; checks q (length, finite).
pub fn fk(kin: &Kinematics, q: &[f64]) -> Result<Se3, SolveError> {
    kin.check_q(q)?;
    Ok(fk_unchecked(kin, q))
}

/// [`fk`] without the checks (q must have `dof` finite entries; panics if shorter).
#[inline]
pub fn fk_unchecked(kin: &Kinematics, q: &[f64]) -> Se3 {
    let mut t = Se3::identity();
    kin.walk(q, |_, jc, theta, s, c| t = jc.apply(&t, theta, s, c));
    t.compose(&kin.home)
}

/// Tip pose, body form T(q) = M e^[B₁]θ₁ ⋯ e^[Bₙ]θₙ (equal to [`fk`]; kept as an independent
/// formula for checks and for body-frame users).
pub fn fk_body(kin: &Kinematics, q: &[f64]) -> Result<Se3, SolveError> {
    kin.check_q(q)?;
    let mut t = kin.home;
    for (j, b) in kin.body.iter().enumerate() {
        t = t.compose(&Se3::exp(&(*b * kin.theta(j, q))));
    }
    Ok(t)
}

/// Poses of every link on the chain (base first, tip last), written into the workspace:
/// link k is e^[S₁]θ₁ ⋯ e^[S_m]θ_m · home_k with m the joints before it.
pub fn fk_all_links<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<&'w [Se3], SolveError> {
    kin.check_q(q)?;
    // Links before the first joint, then after each joint j the links with j + 1 joints before.
    let mut prefix = Se3::identity();
    let mut k = 0;
    let links = &kin.links;
    let out = &mut ws.links;
    while k < links.len() && links[k].2 == 0 {
        out[k] = links[k].1;
        k += 1;
    }
    kin.walk(q, |j, jc, theta, s, c| {
        prefix = jc.apply(&prefix, theta, s, c);
        while k < links.len() && links[k].2 == j + 1 {
            out[k] = prefix.compose(&links[k].1);
            k += 1;
        }
    });
    Ok(&ws.links)
}
