//! Forward kinematics: T(q) = e^[S₁]θ₁ ⋯ e^[Sₙ]θₙ M (space form) = M e^[B₁]θ₁ ⋯ e^[Bₙ]θₙ (body form).
//!
//! θ_j = q_j for ordinary joints, θ_j = m q_leader + o for mimic joints. The hot paths run on
//! [`Columns`] and are compiled twice (see [`screwkit_lie::fma`]): portable, and with AVX2 + FMA
//! where the CPU has them (chosen at run time; the two agree to the last bit or so).

use screwkit_lie::fma::{MulAdd, Plain};
use screwkit_lie::Se3;

use crate::columns::Columns;
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
    #[cfg(target_arch = "x86_64")]
    if screwkit_lie::fma::fused_available() {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        return unsafe { fk_fused(kin, q) };
    }
    fk_with::<Plain>(kin, q)
}

/// [`fk_with`] compiled for AVX2 + FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn fk_fused(kin: &Kinematics, q: &[f64]) -> Se3 {
    fk_with::<screwkit_lie::fma::Fused>(kin, q)
}

/// T = (Π_j e^[S_j]θ_j) M on columns.
#[inline(always)]
pub(crate) fn fk_with<A: MulAdd>(kin: &Kinematics, q: &[f64]) -> Se3 {
    let mut t = Columns::identity();
    kin.walk::<A>(q, |_, jc, theta, s, c| jc.apply::<A>(&mut t, theta, s, c));
    t.compose::<A>(kin.home.rotation(), &(*kin.home.translation()).into())
        .to_se3()
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
    #[cfg(target_arch = "x86_64")]
    if screwkit_lie::fma::fused_available() {
        // SAFETY: the CPU has AVX2 and FMA (checked just above).
        unsafe { fk_all_links_fused(kin, &mut ws.links, q) };
        return Ok(&ws.links);
    }
    fk_all_links_with::<Plain>(kin, &mut ws.links, q);
    Ok(&ws.links)
}

/// [`fk_all_links_with`] compiled for AVX2 + FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
fn fk_all_links_fused(kin: &Kinematics, out: &mut [Se3], q: &[f64]) {
    fk_all_links_with::<screwkit_lie::fma::Fused>(kin, out, q);
}

/// Every link pose: the links before the first joint are their home poses; after joint j, the
/// links with j + 1 joints before them are (prefix through j) · home.
#[inline(always)]
pub(crate) fn fk_all_links_with<A: MulAdd>(kin: &Kinematics, out: &mut [Se3], q: &[f64]) {
    let mut prefix = Columns::identity();
    let mut k = 0;
    let links = &kin.links;
    while k < links.len() && links[k].2 == 0 {
        out[k] = links[k].1;
        k += 1;
    }
    kin.walk::<A>(q, |j, jc, theta, s, c| {
        jc.apply::<A>(&mut prefix, theta, s, c);
        while k < links.len() && links[k].2 == j + 1 {
            let home = &links[k].1;
            out[k] = prefix
                .compose::<A>(home.rotation(), &(*home.translation()).into())
                .to_se3();
            k += 1;
        }
    });
}
