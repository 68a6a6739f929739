//! Space and body Jacobians, computed with the pose in one O(n) pass.
//!
//! Space: J_s column i = \[Ad_{e^[S₁]θ₁ ⋯ e^[S_{i−1}]θ_{i−1}}\] S_i, so V_s = J_s q̇.
//! Body: J_b = \[Ad_{T⁻¹}\] J_s, so V_b = J_b q̇. Rows are (ω, v). With mimic joints, the
//! column of a variable is Σ multiplier_j · (column of joint j) over the joints it drives.

use nalgebra::{Matrix6xX, Vector3};
use screwkit_lie::Se3;

use crate::error::SolveError;
use crate::kinematics::{Kinematics, Workspace};

/// Pose and space Jacobian in one pass, unchecked (q must have `dof` finite entries).
#[inline]
pub(crate) fn fk_jacobian_space_into(kin: &Kinematics, jac: &mut Matrix6xX<f64>, q: &[f64]) -> Se3 {
    if !kin.identity_map {
        jac.fill(0.0);
    }
    let mut t = Se3::identity();
    kin.walk(q, |j, jc, theta, s, c| {
        let col = t.adjoint_apply(&jc.s).to_vector();
        if kin.identity_map {
            jac.set_column(j, &col);
        } else {
            let mut dst = jac.column_mut(jc.variable);
            dst.axpy(jc.multiplier, &col, 1.0);
        }
        t = jc.apply(&t, theta, s, c);
    });
    t.compose(&kin.home)
}

/// Pose and body Jacobian in one pass, unchecked.
#[inline]
pub(crate) fn fk_jacobian_body_into(kin: &Kinematics, jac: &mut Matrix6xX<f64>, q: &[f64]) -> Se3 {
    let t = fk_jacobian_space_into(kin, jac, q);
    // Column-wise [Ad_{T⁻¹}] V = (Rᵀω, Rᵀ(v − p × ω)), in place.
    let rt = t.rotation().transpose();
    let p = *t.translation();
    for mut c in jac.column_iter_mut() {
        let w = Vector3::new(c[0], c[1], c[2]);
        let v = Vector3::new(c[3], c[4], c[5]);
        let wb = rt * w;
        let vb = rt * (v - p.cross(&w));
        c[0] = wb.x;
        c[1] = wb.y;
        c[2] = wb.z;
        c[3] = vb.x;
        c[4] = vb.y;
        c[5] = vb.z;
    }
    t
}

/// The tip pose and the space Jacobian J_s(q) (6 × dof, in the workspace).
pub fn fk_jacobian_space<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<(Se3, &'w Matrix6xX<f64>), SolveError> {
    kin.check_q(q)?;
    let t = fk_jacobian_space_into(kin, &mut ws.jacobian, q);
    Ok((t, &ws.jacobian))
}

/// The tip pose and the body Jacobian J_b(q) = \[Ad_{T⁻¹}\] J_s(q) (6 × dof, in the workspace).
pub fn fk_jacobian_body<'w>(
    kin: &Kinematics,
    ws: &'w mut Workspace,
    q: &[f64],
) -> Result<(Se3, &'w Matrix6xX<f64>), SolveError> {
    kin.check_q(q)?;
    let t = fk_jacobian_body_into(kin, &mut ws.jacobian, q);
    Ok((t, &ws.jacobian))
}

/// Which frame a Jacobian or twist is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Frame {
    /// The base (space) frame.
    Space,
    /// The tip (body) frame.
    Body,
}

/// The Jacobian in the chosen frame, as an owned matrix (allocates; for one-off use).
pub fn jacobian(kin: &Kinematics, q: &[f64], frame: Frame) -> Result<Matrix6xX<f64>, SolveError> {
    let mut ws = Workspace::new(kin);
    match frame {
        Frame::Space => fk_jacobian_space(kin, &mut ws, q)?,
        Frame::Body => fk_jacobian_body(kin, &mut ws, q)?,
    };
    Ok(ws.jacobian)
}
