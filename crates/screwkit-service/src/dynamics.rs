//! Dynamics for the front ends (`screwkit dynamics`, `Robot.inverse_dynamics`, …): the robot's
//! dynamic model (its whole tree's inertials, [`screwkit_solve::tree::dynamics`]) and the
//! report of one configuration.

use serde::Serialize;

use screwkit_solve::tree::dynamics::{self, Dynamics, DynamicsOptions, DynamicsWorkspace};
use screwkit_solve::TreeKinematics;

use crate::error::Result;
use crate::io::json::numbers;

/// The dynamic model of the whole tree `kin` with `options` (default: the links' inertials
/// checked, an inertial that no rigid body has an error naming its link; no armature or
/// damping). Links without an inertial are massless: [`Dynamics::massless`], for the front
/// end's one warning.
pub fn model(kin: &TreeKinematics, options: &DynamicsOptions) -> Result<Dynamics> {
    Ok(Dynamics::with_options(kin, options)?)
}

/// The options from the front ends' words: `inertias` ([`crate::words::Inertias`]), and
/// whether to add the joints' armature and damping.
pub fn options(inertias: crate::words::Inertias, armature: bool, damping: bool) -> DynamicsOptions {
    DynamicsOptions {
        inertias: inertias.rule(),
        armature,
        damping,
    }
}

/// The warning about massless links, or `None` when every link has an `<inertial>`.
pub fn massless_warning(d: &Dynamics) -> Option<String> {
    let names = d.massless();
    if names.is_empty() {
        return None;
    }
    let shown: Vec<&str> = names.iter().take(5).map(String::as_str).collect();
    Some(format!(
        "{} link{} without <inertial> taken as massless: {}{}",
        names.len(),
        if names.len() == 1 { "" } else { "s" },
        shown.join(", "),
        if names.len() > 5 { ", …" } else { "" }
    ))
}

/// One configuration's dynamics (`screwkit dynamics --format json`).
#[derive(Debug, Clone, Serialize)]
pub struct DynamicsReport {
    /// The velocity entries' names (`v_names`): the rows of τ, g, h and of M.
    pub variables: Vec<String>,
    /// The configuration (nq).
    #[serde(serialize_with = "numbers")]
    pub q: Vec<f64>,
    /// The velocity (nv; zeros when not given).
    #[serde(serialize_with = "numbers")]
    pub v: Vec<f64>,
    /// The acceleration (nv; zeros when not given).
    #[serde(serialize_with = "numbers")]
    pub a: Vec<f64>,
    /// τ = ID(q, v, a).
    #[serde(serialize_with = "numbers")]
    pub tau: Vec<f64>,
    /// g(q).
    #[serde(serialize_with = "numbers")]
    pub gravity: Vec<f64>,
    /// h(q, v) = C(q, v) v + g(q).
    #[serde(serialize_with = "numbers")]
    pub nonlinear_effects: Vec<f64>,
    /// M(q), row by row (nv × nv).
    pub mass_matrix: Vec<Vec<f64>>,
    /// ½ vᵀ M v (J).
    pub kinetic_energy: f64,
    /// −Σ m gᵀ c (J).
    pub potential_energy: f64,
}

/// The report at (q, v, a) (v and a zero when not given).
pub fn report(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    names: &[String],
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
) -> Result<DynamicsReport> {
    let nv = d.nv();
    let zeros = vec![0.0; nv];
    let v = v.unwrap_or(&zeros);
    let a = a.unwrap_or(&zeros);
    let tau = dynamics::inverse_dynamics(d, ws, q, v, a)?.to_vec();
    let gravity = dynamics::gravity(d, ws, q)?.to_vec();
    let nonlinear_effects = dynamics::nonlinear_effects(d, ws, q, v)?.to_vec();
    let m = dynamics::mass_matrix(d, ws, q)?;
    let mass_matrix = (0..nv)
        .map(|r| (0..nv).map(|c| m[(r, c)]).collect())
        .collect();
    Ok(DynamicsReport {
        variables: names.to_vec(),
        q: q.to_vec(),
        v: v.to_vec(),
        a: a.to_vec(),
        tau,
        gravity,
        nonlinear_effects,
        mass_matrix,
        kinetic_energy: dynamics::kinetic_energy(d, ws, q, v)?,
        potential_energy: dynamics::potential_energy(d, ws, q)?,
    })
}
