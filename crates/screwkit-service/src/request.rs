//! The requests front ends make, with their one set of defaults: numerical IK settings
//! ([`IkSettings`]), a reachability map ([`ReachSpec`], [`Shard`]). The CLI's flags default to
//! these values, Python's keyword arguments are checked against them, and the library call is
//! made from them ([`IkSettings::options`]).

use std::ops::Range;

use screwkit_solve::ik::{self, IkOptions};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::words::{Method, OrientationMode, SolverChoice};

/// Numerical IK as a front end takes it: words and plain numbers. [`IkSettings::default`] is
/// the library's [`IkOptions::default`], so there is one set of defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSettings {
    /// The method.
    pub method: Method,
    /// LM's damping floor μ̄ or DLS's λ (None: the library's).
    pub damping: Option<f64>,
    /// Rotation tolerance (rad): converged when ‖ω‖ of the body twist error is at most this.
    pub tol_rot: f64,
    /// Position tolerance (m).
    pub tol_pos: f64,
    /// Iteration budget over all attempts.
    pub max_iterations: usize,
    /// Random restarts allowed.
    pub max_restarts: usize,
    /// Wall time per target in ms; 0: none (results then never depend on the machine's load).
    pub timeout_ms: f64,
    /// Seed of the random restarts.
    pub seed: u64,
    /// Solve for the tip position only.
    pub position_only: bool,
    /// Weights of the six twist-error components (ω1, ω2, ω3, v1, v2, v3); 0 masks one out.
    /// Any length is accepted here and checked by [`IkSettings::options`].
    pub weights: Vec<f64>,
}

impl Default for IkSettings {
    fn default() -> Self {
        let d = IkOptions::default();
        Self {
            method: Method::of(&d.method),
            damping: None,
            tol_rot: d.tol_rot,
            tol_pos: d.tol_pos,
            max_iterations: d.max_iterations,
            max_restarts: d.max_restarts,
            timeout_ms: d.timeout.map_or(0.0, |t| t.as_secs_f64() * 1e3),
            seed: d.seed,
            position_only: d.position_only,
            weights: d.weights.to_vec(),
        }
    }
}

impl IkSettings {
    /// The library's options (the rest at their defaults). Errors name the setting.
    pub fn options(&self) -> Result<IkOptions> {
        let weights: [f64; 6] = self.weights.as_slice().try_into().map_err(|_| {
            Error::option(
                "weights",
                format!(
                    "needs 6 numbers (ω1, ω2, ω3, v1, v2, v3; 0 masks one out), got {}",
                    self.weights.len()
                ),
            )
        })?;
        let timeout = ik::timeout_from_ms(self.timeout_ms)
            .map_err(|e| Error::option("timeout_ms", e.to_string()))?;
        Ok(IkOptions {
            method: self.method.with_damping(self.damping)?,
            tol_rot: self.tol_rot,
            tol_pos: self.tol_pos,
            max_iterations: self.max_iterations,
            max_restarts: self.max_restarts,
            timeout,
            seed: self.seed,
            position_only: self.position_only,
            weights,
            ..IkOptions::default()
        })
    }
}

/// What to map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ReachSpec {
    /// Voxel edge (m).
    pub resolution: f64,
    /// Orientations tested per voxel (K).
    pub orientations: usize,
    /// How they are spread.
    pub mode: OrientationMode,
    /// Box to map (min, max corners in the base frame); `None`: the ball the chain can reach.
    pub bounds: Option<([f64; 3], [f64; 3])>,
    /// Which IK.
    pub solver: SolverChoice,
    /// Seed of numerical IK's restarts.
    pub seed: u64,
    /// Numerical IK: random restarts per pose after the first attempt.
    pub restarts: usize,
    /// Numerical IK: iterations per attempt.
    pub iterations: usize,
    /// Count only solutions whose body keeps every checked pair this far apart (m); None:
    /// the body is not looked at. Written in the map's metadata only when set, so a map that
    /// ignores the body has the bytes it had before maps could see one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision_margin: Option<f64>,
}

impl Default for ReachSpec {
    /// 5 cm voxels, 50 free orientations, the reachable ball, IK chosen per chain, numerical
    /// IK with 5 restarts of 100 iterations (an LM solve that converges takes 5–30).
    fn default() -> Self {
        Self {
            resolution: 0.05,
            orientations: 50,
            mode: OrientationMode::Free,
            bounds: None,
            solver: SolverChoice::Auto,
            seed: 0,
            restarts: 5,
            iterations: 100,
            collision_margin: None,
        }
    }
}

impl ReachSpec {
    /// The bounds from six numbers xmin, ymin, zmin, xmax, ymax, zmax.
    pub fn bounds_from(values: &[f64]) -> Result<([f64; 3], [f64; 3])> {
        match values {
            [a, b, c, d, e, f] => Ok(([*a, *b, *c], [*d, *e, *f])),
            v => Err(Error::option(
                "bounds",
                format!(
                    "needs 6 numbers xmin,ymin,zmin,xmax,ymax,zmax, got {}",
                    v.len()
                ),
            )),
        }
    }
}

/// One part of a map: shard `index` of `count` (0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which part, 0 ≤ index < count.
    pub index: usize,
    /// Into how many parts the voxels are cut.
    pub count: usize,
}

impl Shard {
    /// The whole map.
    pub const WHOLE: Shard = Shard { index: 0, count: 1 };

    /// Shard `index` of `count`, checked (0 ≤ index < count).
    pub fn new(index: usize, count: usize) -> Result<Shard> {
        if count == 0 || index >= count {
            return Err(Error::option(
                "shard",
                format!("needs 0 ≤ i < N, got {index} of {count}"),
            ));
        }
        Ok(Shard { index, count })
    }

    /// Parses `i/N` (0 ≤ i < N).
    pub fn parse(s: &str) -> Result<Shard> {
        let bad = || Error::option("shard", format!("needs i/N with 0 ≤ i < N, got '{s}'"));
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse().map_err(|_| bad())?,
            n.trim().parse().map_err(|_| bad())?,
        );
        Shard::new(index, count).map_err(|_| bad())
    }

    /// Its voxels among `total`: the contiguous range [total·i/N, total·(i+1)/N).
    pub fn voxels(self, total: usize) -> Range<usize> {
        let at = |i: usize| ((total as u128 * i as u128) / self.count as u128) as usize;
        at(self.index)..at(self.index + 1)
    }
}

impl std::str::FromStr for Shard {
    type Err = Error;
    fn from_str(s: &str) -> Result<Shard> {
        Shard::parse(s)
    }
}
