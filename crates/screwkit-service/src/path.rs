//! Cartesian paths for the front ends (`Robot.cartesian_path`): the chain's closed-form IK when
//! it has one (branches followed exactly), numerical IK seeded by the previous sample
//! otherwise ([`screwkit_solve::path`]).

use std::borrow::Cow;

use screwkit_collision::ChainClearance;
use screwkit_lie::Se3;
use screwkit_solve::analytic::AnalyticIk;
use screwkit_solve::path::{self, CartesianPath, PathOptions, PathStop};
use screwkit_solve::{Kinematics, Workspace};

use crate::error::Result;
use crate::joint::JointRef;
use crate::solutions::Solvers;

/// The closed-form solver a path follows: the chain's own when it needs no lock (a 6R
/// arm's), a 7R arm's with the joint `lock` held at the seed's value (or its arm angle, with
/// [`crate::joint::ARM_ANGLE`]); None — numerical IK seeded by the previous sample, which
/// moves all of a redundant arm's joints a little rather than hold one — for a chain without
/// one, or a redundant arm without a lock. A lock asked for must exist: its error is the
/// answer.
pub fn path_solver<'s>(
    kin: &Kinematics,
    solvers: &'s Solvers,
    lock: Option<&JointRef>,
) -> Result<Option<Cow<'s, AnalyticIk>>> {
    Ok(match lock {
        Some(_) => Some(solvers.get(kin, lock)?),
        None => solvers
            .get(kin, None)
            .ok()
            .filter(|s| s.locked_joint().is_none()),
    })
}

/// The path from `seed` through `targets` (the module documentation of
/// [`screwkit_solve::path`]), following `analytic` ([`path_solver`]) when given. With `body`,
/// every sample is kept clear of contact and the path stops before one that is not, naming
/// the closest pair there.
#[allow(clippy::too_many_arguments)]
pub fn cartesian_path(
    kin: &Kinematics,
    ws: &mut Workspace,
    analytic: Option<&AnalyticIk>,
    targets: &[Se3],
    seed: &[f64],
    options: &PathOptions,
    body: Option<&ChainClearance>,
) -> Result<CartesianPath> {
    let Some(c) = body else {
        return Ok(path::cartesian_path(
            kin, ws, analytic, targets, seed, options,
        )?);
    };
    use screwkit_solve::ik::Clearance;
    let mut scratch = c.scratch();
    let mut p =
        path::cartesian_path_clear(kin, ws, analytic, targets, seed, options, c, &mut scratch)?;
    if let (PathStop::Collision, Some(q)) = (p.stop, &p.refused) {
        if let Some((a, b, d)) = c.closest(&mut scratch, q)? {
            p.message.push_str(&format!(
                ": {a} and {b} {} (margin {} m)",
                if d < 0.0 {
                    format!("overlap by {:.4} m", -d)
                } else {
                    format!("are {d:.4} m apart")
                },
                c.margin()
            ));
        }
    }
    Ok(p)
}

/// The most paths [`cartesian_paths`] computes on the calling thread, without a thread pool
/// (a path is tens to thousands of IK solves: two are worth sharing out).
pub const PATHS_INLINE: usize = 1;

/// Many paths on all cores (rayon's current pool; [`PATHS_INLINE`] or fewer on the calling
/// thread): path k from `seeds` row k (or the one seed, when `seeds` has dof values) through
/// `targets[k]`, each as its single call [`cartesian_path`] whatever the thread count; a bad
/// row is its own error.
pub fn cartesian_paths(
    kin: &Kinematics,
    analytic: Option<&AnalyticIk>,
    targets: &[Vec<Se3>],
    seeds: &[f64],
    options: &PathOptions,
    body: Option<&ChainClearance>,
) -> Result<Vec<Result<CartesianPath>>> {
    use rayon::prelude::*;
    let n = kin.dof();
    let one_seed = seeds.len() == n;
    if !one_seed && seeds.len() != targets.len() * n {
        return Err(screwkit_solve::SolveError::WrongLength {
            what: "seed values",
            expected: targets.len() * n,
            got: seeds.len(),
            names: "one seed (dof) or one per path (N × dof)".into(),
        }
        .into());
    }
    let one = |ws: &mut Workspace, (k, t): (usize, &Vec<Se3>)| {
        let seed = if one_seed {
            seeds
        } else {
            &seeds[k * n..(k + 1) * n]
        };
        cartesian_path(kin, ws, analytic, t, seed, options, body)
    };
    if targets.len() <= PATHS_INLINE {
        let mut ws = Workspace::new(kin);
        return Ok(targets
            .iter()
            .enumerate()
            .map(|row| one(&mut ws, row))
            .collect());
    }
    Ok(targets
        .par_iter()
        .enumerate()
        .with_max_len(1)
        .map_init(|| Workspace::new(kin), one)
        .collect())
}

/// The chain's velocity limits from its file (each variable's `<limit velocity>`), the
/// default of a timing's; an error naming the joints without one.
pub fn velocity_limits(chain: &screwkit_model::Chain) -> Result<Vec<f64>> {
    let missing: Vec<&str> = chain
        .variables
        .iter()
        .filter(|v| !v.velocity.is_some_and(|x| x.is_finite() && x > 0.0))
        .map(|v| v.name.as_str())
        .collect();
    if !missing.is_empty() {
        return Err(screwkit_solve::SolveError::InvalidInput(format!(
            "no velocity limit in the file for {} (give the velocity limits)",
            missing.join(", ")
        ))
        .into());
    }
    Ok(chain.variables.iter().filter_map(|v| v.velocity).collect())
}

/// A pose written as 6 numbers (x, y, z, roll, pitch, yaw), 7 (x, y, z, qx, qy, qz, qw) or 16
/// (the 4 × 4 matrix, row-major); `what` names it in the error.
pub fn pose(values: &[f64], what: &str) -> Result<Se3> {
    let t = match values.len() {
        6 => crate::target::from_xyz_rpy(values),
        7 => crate::target::from_xyz_quat(values),
        16 => Ok(crate::target::from_row_major(values)?),
        n => Err(screwkit_solve::SolveError::InvalidInput(format!(
            "expected 6 (x,y,z,roll,pitch,yaw), 7 (x,y,z,qx,qy,qz,qw) or 16 (a 4x4 matrix) numbers, got {n}"
        ))
        .into()),
    };
    t.map_err(|e| screwkit_solve::SolveError::InvalidInput(format!("{what}: {e}")).into())
}

/// The most waypoints a file may hold ([`read_waypoints`]).
pub const MAX_WAYPOINTS: usize = 100_000;

/// The poses of a `.npy` file of float64, in order (the last the goal): (K, 4, 4) matrices, or
/// K rows of 6, 7 or 16 numbers as [`pose`] reads them; an error names the file and the row.
pub fn read_waypoints(file: &str) -> Result<Vec<Se3>> {
    let mut r = crate::io::npy::NpyReader::open(file)?;
    let bad = |m: String| screwkit_solve::SolveError::InvalidInput(format!("{file}: {m}"));
    let width = match r.shape.as_slice() {
        [_, 4, 4] => 16,
        [_, w] if matches!(w, 6 | 7 | 16) => *w,
        other => {
            return Err(bad(format!(
                "shape {other:?}: expected (K, 4, 4) poses, or K rows of 6, 7 or 16 numbers"
            ))
            .into())
        }
    };
    let rows = r.shape[0];
    if rows == 0 || rows > MAX_WAYPOINTS {
        return Err(bad(format!("{rows} poses: expected 1 to {MAX_WAYPOINTS}")).into());
    }
    let mut values = Vec::with_capacity(rows * width);
    r.read_rows(rows, &mut values)?;
    values
        .chunks(width)
        .enumerate()
        .map(|(k, row)| pose(row, &format!("{file}: row {k}")))
        .collect()
}

/// A path's report (`screwkit path --format json`): the chain's variables, the joint samples,
/// each one's place on the path, the fraction achieved, why it stopped; with a timing, its
/// duration and the samples' times and joint values every `dt`.
#[derive(Debug, Clone, serde::Serialize)]
pub struct PathReport {
    /// The chain's variable names (the columns of `q`).
    pub variables: Vec<String>,
    /// The joint samples (K rows).
    pub q: Vec<Vec<f64>>,
    /// Each sample's place: segment index + σ.
    #[serde(serialize_with = "crate::io::json::numbers")]
    pub place: Vec<f64>,
    /// The fraction of the path achieved.
    pub fraction: f64,
    /// "reached", "singularity", "branch ends", "unreachable", "jump" or "collision".
    pub stop: String,
    /// Where and why, in one sentence.
    pub message: String,
    /// The timed path, when asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub timed: Option<TimedReport>,
}

/// A timed path: its duration, and t and q every dt (the last sample at the end).
#[derive(Debug, Clone, serde::Serialize)]
pub struct TimedReport {
    /// The duration (s).
    pub duration: f64,
    /// The sample times (s).
    #[serde(serialize_with = "crate::io::json::numbers")]
    pub t: Vec<f64>,
    /// q at each time.
    pub q: Vec<Vec<f64>>,
}

/// The report of `path` for chain variables `names`, timed when `timing` is given ((velocity,
/// acceleration) limits, the sample step).
pub fn report(
    names: &[String],
    path: &CartesianPath,
    timing: Option<(&[f64], &[f64], f64)>,
) -> Result<PathReport> {
    let n = names.len();
    let rows = |q: &[f64]| q.chunks(n.max(1)).map(<[f64]>::to_vec).collect::<Vec<_>>();
    let timed = match timing {
        None => None,
        Some((v, a, dt)) => {
            if !(dt.is_finite() && dt > 0.0) {
                return Err(screwkit_solve::SolveError::InvalidInput(format!(
                    "dt {dt}: expected a finite step > 0"
                ))
                .into());
            }
            if path.place.len() < 2 {
                None
            } else {
                let t = screwkit_solve::timing::time_parameterize(
                    &path.q,
                    n,
                    v,
                    a,
                    &Default::default(),
                )?;
                let count = (t.duration() / dt).ceil() as usize;
                if count > 10_000_000 {
                    return Err(screwkit_solve::SolveError::InvalidInput(format!(
                        "the timed path takes {:.3} s: {count} samples of dt {dt} (at most 10,000,000)",
                        t.duration()
                    ))
                    .into());
                }
                let times: Vec<f64> = (0..=count)
                    .map(|k| (k as f64 * dt).min(t.duration()))
                    .collect();
                let (mut q, mut qd, mut qdd) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                let mut out = Vec::with_capacity(times.len());
                for time in &times {
                    t.sample(*time, &mut q, &mut qd, &mut qdd);
                    out.push(q.clone());
                }
                Some(TimedReport {
                    duration: t.duration(),
                    t: times,
                    q: out,
                })
            }
        }
    };
    Ok(PathReport {
        variables: names.to_vec(),
        q: rows(&path.q),
        place: path.place.clone(),
        fraction: path.fraction,
        stop: path.stop.as_str().to_string(),
        message: path.message.clone(),
        timed,
    })
}
