//! Reachability maps of a robot arm (Zacharias et al., IROS 2007; Vahrenkamp et al.): the
//! workspace cut into voxels, K tool orientations tested at every voxel centre by screwkit's
//! IK — every solution by the analytic solver for a 6R arm of revolute joints that is not
//! degenerate (a closed form for the special families, algebraic elimination for the others),
//! one solution within the limits by numerical IK otherwise — and per voxel the reachability index
//! (reached ÷ K), per pose the best manipulability √det(J Jᵀ) over its solutions.
//!
//! A front end of the library: the poses come from [`grid`], the solving from
//! `screwkit_solve`'s batch calls ([`screwkit_solve::analytic::AnalyticIk::solve_batch`],
//! [`screwkit_solve::batch::ik_batch_from`], [`screwkit_solve::batch::jacobian_batch`],
//! [`screwkit_solve::analysis::manipulability`]); nothing here computes kinematics.
//!
//! Maps are `.npz` files ([`npz`]) written as they are computed, so memory stays bounded
//! whatever the pose count; a map can be computed in N shards (`--shard i/N`: a contiguous
//! 1/N of the voxels each) and [`merge`]d into the file the unsharded run writes, array for
//! array and byte for byte (no timings or host names in a map). Every pose's result depends
//! only on the spec and the pose's global index (numerical IK restarts from
//! [`screwkit_solve::batch::row_seed`] of it), never on threads, shards or load.

pub mod grid;
pub mod slices;

use nalgebra::Matrix3;

use screwkit_model::digest::Digest;
use screwkit_model::{Chain, JointKind};
use screwkit_solve::analytic::{AnalyticIk, Representatives};
use screwkit_solve::ik::{Clearance, IkMethod, IkOptions, IkStatus, NoBody, StopReason};
use screwkit_solve::{Frame, Kinematics, SolveError};

pub use grid::{orientations, Grid};
use screwkit_service::io::npz::{self, NpzReader, NpzWriter};
use screwkit_service::io::{atomic, FileError};
pub use screwkit_service::request::{ReachSpec, Shard};
use screwkit_service::words::Word;
pub use screwkit_service::words::{OrientationMode, SolverChoice};
use std::ops::Range;

/// What can go wrong building, reading or merging a map.
#[derive(Debug, thiserror::Error)]
pub enum ReachError {
    /// A bad spec or argument.
    #[error("{0}")]
    Input(String),
    /// A file could not be read or written (or is not an `.npz`, a damaged one).
    #[error(transparent)]
    File(#[from] FileError),
    /// A file is not a map (or not a shard of the same map).
    #[error("{0}")]
    Format(String),
    /// The solver refused the chain or its input.
    #[error("IK: {0}")]
    Solve(#[from] SolveError),
    /// The analytic solver was asked for and the chain has none.
    #[error("IK: {0} (maps use the analytic solver for 6R chains; choose numerical IK)")]
    NoAnalytic(SolveError),
}

impl ReachError {
    pub(crate) fn io(path: &str, e: std::io::Error) -> Self {
        ReachError::File(FileError::io(path, e))
    }
}

/// The IK a plan resolved to.
#[derive(Debug, Clone)]
enum Solver {
    Analytic(Box<AnalyticIk>),
    Numerical(IkOptions),
}

/// A spec made concrete for one chain: the grid, the K rotations, the solver, and the ball
/// the chain can reach (voxels outside it are not solved: index 0).
#[derive(Debug, Clone)]
pub struct Plan {
    /// The spec.
    pub spec: ReachSpec,
    /// The voxels.
    pub grid: Grid,
    /// The K tool rotations tested at every voxel.
    pub rotations: Vec<Matrix3<f64>>,
    /// Centre of the reachable ball (the first joint's origin at home), base frame; the origin
    /// when the chain has no ball (an unbounded sliding joint: the map's bounds are the
    /// spec's, and the metadata says `null`).
    pub reach_centre: [f64; 3],
    /// Its radius ([`reach_ball`]; ∞ for a chain with an unbounded sliding joint, whose map
    /// takes its bounds from the spec).
    pub reach_radius: f64,
    /// "robot base→tip" for the map's metadata.
    pub label: String,
    /// [`kinematics_hash`] of the chain: two robots with the same name but other screws,
    /// home pose, limits, mimic rules or tool never merge.
    pub kinematics: String,
    solver: Solver,
}

impl Plan {
    /// The plan of `spec` for `chain` (whose kinematics is `kin`).
    pub fn new(chain: &Chain, kin: &Kinematics, spec: &ReachSpec) -> Result<Plan, ReachError> {
        if spec.orientations == 0 {
            return Err(ReachError::Input(
                "at least one orientation per voxel is needed".into(),
            ));
        }
        if spec.orientations > MAX_ORIENTATIONS {
            return Err(ReachError::Input(format!(
                "{} orientations per voxel is more than {MAX_ORIENTATIONS}",
                spec.orientations
            )));
        }
        // A chain with an unbounded sliding joint has no ball: the map needs bounds, and every
        // voxel in them is tried.
        let ball = reach_ball(chain);
        let (reach_centre, reach_radius) = match &ball {
            Ok(b) => *b,
            Err(_) => ([0.0; 3], f64::INFINITY),
        };
        let (lo, hi) = match (spec.bounds, &ball) {
            (Some(b), _) => b,
            (None, Err(joint)) => {
                return Err(ReachError::Input(format!(
                    "variable \"{joint}\" has no limits and drives a prismatic or helical \
                     joint, so the reachable space has no bound: give the map bounds, or the \
                     joint limits"
                )))
            }
            (None, Ok(_)) => {
                let r = reach_radius + spec.resolution;
                (
                    reach_centre.map(|c| c - r),
                    [
                        reach_centre[0] + r,
                        reach_centre[1] + r,
                        reach_centre[2] + r,
                    ],
                )
            }
        };
        let grid = Grid::covering(lo, hi, spec.resolution)?;
        if grid.len() > MAX_VOXELS {
            return Err(ReachError::Input(format!(
                "{} voxels is more than a map may have ({MAX_VOXELS}): use a coarser resolution or smaller bounds",
                grid.len()
            )));
        }
        let numerical = || {
            Solver::Numerical(IkOptions {
                method: IkMethod::LM,
                max_iterations: spec.iterations.max(1),
                max_restarts: spec.restarts,
                timeout: None,
                seed: spec.seed,
                ..IkOptions::default()
            })
        };
        let solver = match spec.solver {
            SolverChoice::Numerical => numerical(),
            SolverChoice::Auto => match AnalyticIk::new(kin) {
                Ok(ik) => Solver::Analytic(Box::new(ik)),
                _ => numerical(),
            },
            SolverChoice::Analytic => match AnalyticIk::new(kin) {
                Ok(ik) => Solver::Analytic(Box::new(ik)),
                Err(e) => return Err(ReachError::NoAnalytic(e)),
            },
        };
        Ok(Plan {
            spec: spec.clone(),
            grid,
            rotations: orientations(spec.mode, spec.orientations),
            reach_centre,
            reach_radius,
            label: format!("{} {}→{}", chain.robot, chain.base, chain.tip),
            kinematics: kinematics_hash(chain),
            solver,
        })
    }

    /// "analytic" or "numerical".
    pub fn solver_name(&self) -> &'static str {
        match self.solver {
            Solver::Analytic(_) => SolverChoice::Analytic.as_str(),
            Solver::Numerical(_) => SolverChoice::Numerical.as_str(),
        }
    }

    /// Poses of the whole map (voxels × K).
    pub fn poses(&self) -> usize {
        self.grid.len() * self.rotations.len()
    }

    /// True when voxel `v`'s centre lies in the reachable ball (with half a voxel's diagonal
    /// to spare), so its poses are solved.
    pub fn in_reach(&self, v: usize) -> bool {
        let c = self.grid.centre(v);
        let d2: f64 = (0..3).map(|a| (c[a] - self.reach_centre[a]).powi(2)).sum();
        d2.sqrt() <= self.reach_radius + 1e-9
    }

    /// The map's metadata (the `meta` entry, JSON): everything that defines its arrays.
    fn meta(&self, shard: Shard, body: Option<&str>) -> String {
        let range = shard.voxels(self.grid.len());
        let mut meta = serde_json::json!({
            "format": "screwkit reachability map 1",
            "robot": self.label,
            "kinematics": self.kinematics,
            "solver": self.solver_name(),
            "spec": self.spec,
            "grid": self.grid,
            // No ball (an unbounded sliding joint): null, not a made-up centre.
            "reach_centre": self.reach_radius.is_finite().then_some(self.reach_centre),
            "reach_radius": self.reach_radius.is_finite().then_some(self.reach_radius),
            "shard": [shard.index, shard.count],
            "voxels": [range.start, range.end],
        });
        // A map clear of contact names the body it kept clear of (a map without one has no
        // such entry: its bytes are those maps had before bodies existed).
        if let (Some(digest), Some(o)) = (body, meta.as_object_mut()) {
            o.insert("body".into(), digest.into());
        }
        meta.to_string()
    }

    /// Solves voxels `voxels` (all K poses of each) and writes each pose's best manipulability
    /// over the solutions `body` finds clear (NaN: not reached) into `out` (voxels × K,
    /// row-major). Returns the poses reached only in contact (every posture of the analytic
    /// solver colliding; numerical IK's budget ended with only colliding answers).
    fn solve_voxels<B: Clearance>(
        &self,
        kin: &Kinematics,
        body: &B,
        voxels: Range<usize>,
        out: &mut [f64],
    ) -> Result<usize, ReachError> {
        let k = self.rotations.len();
        out.fill(f64::NAN);
        // Targets of the voxels in reach, in runs of consecutive global pose indices.
        let mut targets = Vec::new();
        let mut runs: Vec<(usize, usize)> = Vec::new(); // (first global pose, count)
        for v in voxels.clone() {
            if !self.in_reach(v) {
                continue;
            }
            let c = self.grid.centre(v);
            for r in &self.rotations {
                targets.extend_from_slice(&[
                    r[(0, 0)],
                    r[(0, 1)],
                    r[(0, 2)],
                    c[0],
                    r[(1, 0)],
                    r[(1, 1)],
                    r[(1, 2)],
                    c[1],
                    r[(2, 0)],
                    r[(2, 1)],
                    r[(2, 2)],
                    c[2],
                    0.0,
                    0.0,
                    0.0,
                    1.0,
                ]);
            }
            match runs.last_mut() {
                Some((first, count)) if *first + *count == v * k => *count += k,
                _ => runs.push((v * k, k)),
            }
        }
        let n = kin.dof();
        // Every solution found, with the local pose (index into `out`) it belongs to.
        let mut qs: Vec<f64> = Vec::new();
        let mut owner: Vec<usize> = Vec::new();
        let base = voxels.start * k;
        let mut collided = 0;
        match &self.solver {
            Solver::Analytic(ik) => {
                use rayon::prelude::*;
                // One row per posture (the 2π representatives that joints with limits wider
                // than ±π add have the same manipulability and the same body: not listed),
                // those the body finds clear.
                let results = ik.solve_batch_postures(kin, &targets, None, Representatives::One)?;
                let distinct: Vec<(Vec<f64>, bool)> = results
                    .par_iter()
                    .map_init(
                        || body.scratch(),
                        |scratch, r| match r {
                            Ok(s) if s.is_exact() => {
                                let clear: Vec<f64> = s
                                    .iter()
                                    .filter(|q| body.is_clear(scratch, q))
                                    .flatten()
                                    .copied()
                                    .collect();
                                let lost = clear.is_empty() && s.iter().next().is_some();
                                (clear, lost)
                            }
                            _ => (Vec::new(), false),
                        },
                    )
                    .collect();
                collided += distinct.iter().filter(|(_, lost)| *lost).count();
                let distinct: Vec<Vec<f64>> = distinct.into_iter().map(|(q, _)| q).collect();
                let mut row = 0;
                for &(first, count) in &runs {
                    for p in first..first + count {
                        qs.extend_from_slice(&distinct[row]);
                        owner.extend(std::iter::repeat_n(
                            p - base,
                            distinct[row].len() / n.max(1),
                        ));
                        row += 1;
                    }
                }
            }
            Solver::Numerical(opts) => {
                let mut at = 0;
                for &(first, count) in &runs {
                    let t = &targets[16 * at..16 * (at + count)];
                    let mut q = vec![0.0; count * n];
                    let mut status = vec![IkStatus::unsolved(); count];
                    // Bad rows cannot occur (the targets are rotations built here); a row
                    // error would leave its status unsolved, i.e. not reached.
                    let _ = screwkit_solve::batch::ik_batch_clear_from(
                        kin,
                        first,
                        t,
                        None,
                        opts,
                        body,
                        &mut q,
                        &mut status,
                        None,
                    );
                    collided += status
                        .iter()
                        .filter(|st| st.stop == StopReason::InCollision)
                        .count();
                    for (i, st) in status.iter().enumerate() {
                        if st.converged && kin.within_limits(&q[i * n..(i + 1) * n], 1e-9) {
                            qs.extend_from_slice(&q[i * n..(i + 1) * n]);
                            owner.push(first + i - base);
                        }
                    }
                    at += count;
                }
            }
        }
        if owner.is_empty() {
            return Ok(collided);
        }
        let mut jac = vec![0.0; owner.len() * 6 * n];
        screwkit_solve::batch::jacobian_batch(kin, &qs, Frame::Space, &mut jac, None)?;
        let w: Vec<f64> = {
            use rayon::prelude::*;
            jac.par_chunks(6 * n)
                .map(|j| screwkit_solve::analysis::manipulability(j, n))
                .collect()
        };
        for (&p, &w) in owner.iter().zip(&w) {
            out[p] = if out[p].is_nan() { w } else { out[p].max(w) };
        }
        Ok(collided)
    }
}

/// The reachable ball of a chain: centre at the first joint's origin (which no joint moves),
/// radius Σ |o_{j+1} − o_j| + |tip − o_last| over the joint origins at home (each distance is
/// fixed: only joint j moves o_{j+1} relative to o_j, about an axis through o_j) plus what each
/// joint adds by sliding: |m| · travel + |o| for a prismatic joint, |h| (|m| · travel + |o|) for
/// a helical one of pitch h (its rotation is in the link lengths), θ = m q + o its drive and
/// travel the largest |limit| of its variable. A sliding joint whose variable is unbounded has
/// no ball: `Err` with the variable's name.
pub fn reach_ball(chain: &Chain) -> Result<([f64; 3], f64), String> {
    let origins: Vec<nalgebra::Vector3<f64>> = chain
        .joints
        .iter()
        .map(|j| *j.home.translation())
        .chain(std::iter::once(*chain.home.translation()))
        .collect();
    let centre = origins[0];
    let mut r: f64 = origins.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    for j in &chain.joints {
        let per_unit = match j.kind {
            JointKind::Prismatic => 1.0,
            JointKind::Helical => j.s_space.pitch().unwrap_or(0.0).abs(),
            _ => continue,
        };
        // Metres per unit of q (0: the joint does not slide, whatever q).
        let rate = (j.drive.multiplier * per_unit).abs();
        if rate == 0.0 {
            r += (j.drive.offset * per_unit).abs();
            continue;
        }
        let v = &chain.variables[j.drive.variable];
        let travel = rate * v.lower.abs().max(v.upper.abs()) + (j.drive.offset * per_unit).abs();
        if !travel.is_finite() {
            return Err(v.name.clone());
        }
        r += travel;
    }
    Ok(([centre.x, centre.y, centre.z], r))
}

/// What a build did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Summary {
    /// Voxels in this file.
    pub voxels: usize,
    /// Poses in this file (voxels × K).
    pub poses: usize,
    /// Poses solved (their voxel in the reachable ball).
    pub solved: usize,
    /// Poses reached.
    pub reached: usize,
    /// Poses reached only in contact (a map clear of contact; 0 otherwise): the map's loss to
    /// collisions.
    pub collided: usize,
}

/// A 64-bit FNV-1a hash (16 hex digits) of everything that decides a chain's reach: each
/// joint's kind, space screw S_i and mimic rule, each variable's limits, and the home pose M
/// (with its tool). The exact bits of every number are hashed.
pub fn kinematics_hash(chain: &Chain) -> String {
    let mut d = Digest::new();
    for j in &chain.joints {
        d.bytes(j.kind.as_str().as_bytes())
            .nums(j.s_space.twist().to_vector().iter().copied())
            .count(j.drive.variable)
            .num(j.drive.multiplier)
            .num(j.drive.offset);
    }
    for v in &chain.variables {
        d.num(v.lower).num(v.upper);
    }
    d.nums(chain.home.to_homogeneous().iter().copied());
    d.hex()
}

/// Poses solved per step of a build (whole voxels; progress is reported after each). Bounds
/// memory: the analytic solver returns every 2π representative of every posture (up to 512
/// for a UR5 with ±2π limits, 24 KB a pose): a step of 8192 poses peaks near 270 MB on the
/// UR5 (measured; 2048 poses: 83 MB but 1.4× the time, the two parallel phases per step
/// idling at their ends).
const CHUNK_POSES: usize = 8192;

/// The most voxels a map may have (at 5 mm over a 2 m cube: 6.4e7).
pub const MAX_VOXELS: usize = 1_000_000_000;
/// The most voxels one shard may hold (its per-voxel arrays take 40 bytes each: 2 GB).
pub const MAX_SHARD_VOXELS: usize = 50_000_000;
/// The most orientations tested per voxel.
pub const MAX_ORIENTATIONS: usize = 100_000;

/// Builds shard `shard` of the map of `plan` into the `.npz` file `path`, streaming the
/// per-pose results: memory holds a chunk of poses and the per-voxel arrays. `progress(done,
/// total)` is called with poses after each chunk. A spec asking for a map clear of contact
/// needs [`build_clear`].
pub fn build(
    plan: &Plan,
    kin: &Kinematics,
    shard: Shard,
    path: &str,
    progress: impl FnMut(usize, usize),
) -> Result<Summary, ReachError> {
    if plan.spec.collision_margin.is_some() {
        return Err(ReachError::Input(
            "a map clear of contact needs the robot's body (its collision geometry)".into(),
        ));
    }
    build_with(plan, kin, &NoBody, None, shard, path, progress)
}

/// The body a map keeps clear of: the robot (its chain placed in its whole tree `tree`, the
/// tree's other joints at their neutral values), checked by `model` (its SRDF and obstacles
/// applied) with the spec's margin.
#[derive(Debug, Clone, Copy)]
pub struct Body<'a> {
    /// The robot whose chain the map is of.
    pub robot: &'a screwkit_service::load::Robot,
    /// Its whole tree.
    pub tree: &'a screwkit_solve::TreeKinematics,
    /// Its collision model.
    pub model: &'a screwkit_collision::CollisionModel,
}

/// [`build`] counting only solutions whose body is clear of contact by the spec's
/// `collision_margin`: a pose is reached when one of its analytic postures is clear (every
/// one checked), or numerical IK finds a clear answer (it steers away from contact as
/// `screwkit ik --avoid-collisions` does). The map's metadata names the body by
/// [`screwkit_collision::CollisionModel::digest`], so shards of other bodies never merge.
pub fn build_clear(
    plan: &Plan,
    kin: &Kinematics,
    body: Body<'_>,
    shard: Shard,
    path: &str,
    progress: impl FnMut(usize, usize),
) -> Result<Summary, ReachError> {
    let Some(margin) = plan.spec.collision_margin else {
        return Err(ReachError::Input(
            "the map's spec does not ask to avoid collisions (collision_margin)".into(),
        ));
    };
    let clearance =
        screwkit_service::body::chain_clearance(body.robot, body.tree, body.model, margin)
            .map_err(|e| ReachError::Input(e.to_string()))?;
    let digest = body.model.digest();
    build_with(plan, kin, &clearance, Some(&digest), shard, path, progress)
}

fn build_with<B: Clearance>(
    plan: &Plan,
    kin: &Kinematics,
    body: &B,
    digest: Option<&str>,
    shard: Shard,
    path: &str,
    mut progress: impl FnMut(usize, usize),
) -> Result<Summary, ReachError> {
    let k = plan.rotations.len();
    let range = shard.voxels(plan.grid.len());
    let nv = range.len();
    if nv > MAX_SHARD_VOXELS {
        return Err(ReachError::Input(format!(
            "{nv} voxels in one shard is more than {MAX_SHARD_VOXELS} (40 bytes each are held in memory): cut the map into at least {} shards",
            plan.grid.len().div_ceil(MAX_SHARD_VOXELS)
        )));
    }
    let mut out = NpzWriter::create(path)?;
    out.start("pose_manipulability", "<f8", &[nv, k])?;
    let (mut index, mut best) = (Vec::with_capacity(nv), Vec::with_capacity(nv));
    let mut summary = Summary {
        voxels: nv,
        poses: nv * k,
        solved: 0,
        reached: 0,
        collided: 0,
    };
    let chunk_voxels = (CHUNK_POSES / k).max(1);
    let mut buf = vec![0.0; chunk_voxels * k];
    let mut v = range.start;
    while v < range.end {
        let end = (v + chunk_voxels).min(range.end);
        let w = &mut buf[..(end - v) * k];
        summary.collided += plan.solve_voxels(kin, body, v..end, w)?;
        for (i, poses) in w.chunks(k).enumerate() {
            let reached = poses.iter().filter(|x| !x.is_nan()).count();
            if plan.in_reach(v + i) {
                summary.solved += k;
            }
            summary.reached += reached;
            index.push(reached as f64 / k as f64);
            best.push(poses.iter().copied().fold(f64::NAN, f64::max));
        }
        out.write_f64(w)?;
        v = end;
        progress((v - range.start) * k, nv * k);
    }
    let centres: Vec<f64> = range.clone().flat_map(|v| plan.grid.centre(v)).collect();
    out.f64_array("centres", &[nv, 3], &centres)?;
    out.f64_array("index", &[nv], &index)?;
    out.f64_array("best_manipulability", &[nv], &best)?;
    write_description(
        &mut out,
        plan.meta(shard, digest),
        &plan.grid,
        &plan.rotations,
        shard,
    )?;
    out.finish()?;
    Ok(summary)
}

fn write_description(
    out: &mut NpzWriter,
    meta: String,
    grid: &Grid,
    rotations: &[Matrix3<f64>],
    shard: Shard,
) -> Result<(), ReachError> {
    let range = shard.voxels(grid.len());
    let rot: Vec<f64> = rotations
        .iter()
        .flat_map(|r| (0..3).flat_map(move |i| (0..3).map(move |j| r[(i, j)])))
        .collect();
    out.f64_array("orientations", &[rotations.len(), 3, 3], &rot)?;
    out.f64_array("grid_origin", &[3], &grid.origin)?;
    out.i64_array("grid_shape", &[3], &grid.shape.map(|s| s as i64))?;
    out.f64_array("resolution", &[], &[grid.resolution])?;
    out.i64_array("voxel_range", &[2], &[range.start as i64, range.end as i64])?;
    Ok(out.text("meta", &meta)?)
}

/// A map read back (the per-voxel arrays; `pose_manipulability` stays on disk unless asked).
#[derive(Debug, Clone, PartialEq)]
pub struct MapFile {
    /// The `meta` entry (JSON).
    pub meta: serde_json::Value,
    /// The grid.
    pub grid: Grid,
    /// Voxels of this file (a shard's range, or all).
    pub voxels: Range<usize>,
    /// Orientations per voxel.
    pub k: usize,
    /// Reachability index per voxel.
    pub index: Vec<f64>,
    /// Best manipulability per voxel (NaN: none reached).
    pub best: Vec<f64>,
    /// Voxel centres (voxels × 3).
    pub centres: Vec<f64>,
}

/// Reads the per-voxel arrays and metadata of map (or shard) `path`.
pub fn read(path: &str) -> Result<MapFile, ReachError> {
    let mut z = NpzReader::open(path)?;
    let meta: serde_json::Value = serde_json::from_str(&z.text("meta")?)
        .map_err(|e| ReachError::Format(format!("{path}: bad meta: {e}")))?;
    if meta["format"] != "screwkit reachability map 1" {
        return Err(ReachError::Format(format!(
            "{path}: not a screwkit reachability map"
        )));
    }
    let grid: Grid = serde_json::from_value(meta["grid"].clone())
        .map_err(|e| ReachError::Format(format!("{path}: bad grid: {e}")))?;
    let (_, r) = z.i64_array("voxel_range")?;
    let voxels = match r.as_slice() {
        [a, b] if 0 <= *a && a <= b && (*b as u64) <= grid.len() as u64 => *a as usize..*b as usize,
        _ => {
            return Err(ReachError::Format(format!(
                "{path}: voxel_range {r:?} is not a range of the map's {} voxels",
                grid.len()
            )))
        }
    };
    let (_, index) = z.f64_array("index")?;
    let (_, best) = z.f64_array("best_manipulability")?;
    let (_, centres) = z.f64_array("centres")?;
    let k = meta["spec"]["orientations"].as_u64().unwrap_or(0) as usize;
    if index.len() != voxels.len()
        || best.len() != voxels.len()
        || centres.len() != 3 * voxels.len()
    {
        return Err(ReachError::Format(format!(
            "{path}: arrays do not match the voxel range"
        )));
    }
    Ok(MapFile {
        meta,
        grid,
        voxels,
        k,
        index,
        best,
        centres,
    })
}

/// Joins the shards `paths` (any order) into the map `out`: the file the unsharded build
/// writes, byte for byte. An error naming the file when a shard belongs to another map, is
/// missing, or appears twice. Streams `pose_manipulability`; memory holds the per-voxel arrays.
pub fn merge(paths: &[String], out: &str) -> Result<Summary, ReachError> {
    if paths.is_empty() {
        return Err(ReachError::Input("no shards to merge".into()));
    }
    let inputs: Vec<&str> = paths.iter().map(String::as_str).collect();
    atomic::check_distinct(&inputs, &[out]).map_err(ReachError::Input)?;
    let mut shards: Vec<(MapFile, &String)> = paths
        .iter()
        .map(|p| read(p).map(|m| (m, p)))
        .collect::<Result<_, _>>()?;
    shards.sort_by_key(|(m, _)| m.voxels.start);
    let strip = |m: &serde_json::Value| {
        let mut m = m.clone();
        for key in ["shard", "voxels"] {
            m.as_object_mut().map(|o| o.remove(key));
        }
        m
    };
    let (first, first_path) = &shards[0];
    let count = first.meta["shard"][1].as_u64().unwrap_or(0) as usize;
    let mut expect = 0;
    for (m, p) in &shards {
        if strip(&m.meta) != strip(&first.meta) {
            return Err(ReachError::Format(format!(
                "{p}: a shard of another map than {first_path} (robot, spec or grid differ)"
            )));
        }
        if m.voxels.start != expect {
            return Err(ReachError::Format(format!(
                "{p}: voxels {}..{} where {expect} was expected next (a shard missing or twice)",
                m.voxels.start, m.voxels.end
            )));
        }
        expect = m.voxels.end;
    }
    if expect != first.grid.len() || shards.len() != count {
        return Err(ReachError::Format(format!(
            "the shards cover voxels 0..{expect} of {} ({} of {count} shards given)",
            first.grid.len(),
            shards.len()
        )));
    }
    let k = first.k;
    let nv = first.grid.len();
    let mut w = NpzWriter::create(out)?;
    w.start("pose_manipulability", "<f8", &[nv, k])?;
    for (_, p) in &shards {
        let mut r = NpzReader::open(p)?;
        npz::copy_entry(&mut r, "pose_manipulability", &mut w, 1 << 20)?;
    }
    let cat = |f: &dyn Fn(&MapFile) -> &Vec<f64>| -> Vec<f64> {
        shards.iter().flat_map(|(m, _)| f(m).clone()).collect()
    };
    let (centres, index, best) = (cat(&|m| &m.centres), cat(&|m| &m.index), cat(&|m| &m.best));
    w.f64_array("centres", &[nv, 3], &centres)?;
    w.f64_array("index", &[nv], &index)?;
    w.f64_array("best_manipulability", &[nv], &best)?;
    let mut whole = strip(&first.meta);
    if let Some(o) = whole.as_object_mut() {
        o.insert("shard".into(), serde_json::json!([0, 1]));
        o.insert("voxels".into(), serde_json::json!([0, nv]));
    }
    let mut r = NpzReader::open(first_path)?;
    let (_, rot) = r.f64_array("orientations")?;
    let rotations: Vec<Matrix3<f64>> = rot.chunks_exact(9).map(Matrix3::from_row_slice).collect();
    write_description(
        &mut w,
        whole.to_string(),
        &first.grid,
        &rotations,
        Shard::WHOLE,
    )?;
    w.finish()?;
    let reached = index.iter().map(|x| (x * k as f64).round() as usize).sum();
    Ok(Summary {
        voxels: nv,
        poses: nv * k,
        solved: 0,
        reached,
        collided: 0,
    })
}

/// Largest map [`export`] writes as text (poses).
pub const TEXT_MAX_POSES: usize = 10_000_000;

/// Writes map `npz` (whole or shard) as text for small maps: `.csv` (a header, then one line
/// per voxel: x, y, z, index, best_manipulability) or `.json` (`{"meta": …, "voxels": [{"centre",
/// "index", "best_manipulability", "pose_manipulability": [K]}]}`, NaN as null), chosen by
/// `out`'s extension. An error above [`TEXT_MAX_POSES`] poses.
pub fn export(npz: &str, out: &str) -> Result<(), ReachError> {
    use std::io::Write;
    let m = read(npz)?;
    let poses = m.index.len() * m.k;
    if poses > TEXT_MAX_POSES {
        return Err(ReachError::Input(format!(
            "{poses} poses is too many for text: keep the .npz (numpy reads it directly)"
        )));
    }
    atomic::check_distinct(&[npz], &[out]).map_err(ReachError::Input)?;
    let mut w = atomic::AtomicFile::create(out).map_err(|e| ReachError::io(out, e))?;
    let num = screwkit_service::io::json::num;
    let res = if out.ends_with(".csv") {
        let mut r = writeln!(w, "x,y,z,index,best_manipulability");
        for (i, c) in m.centres.chunks(3).enumerate() {
            if r.is_err() {
                break;
            }
            r = writeln!(
                w,
                "{},{},{},{},{}",
                c[0],
                c[1],
                c[2],
                m.index[i],
                if m.best[i].is_nan() {
                    String::new()
                } else {
                    m.best[i].to_string()
                }
            );
        }
        r
    } else if out.ends_with(".json") {
        let mut z = NpzReader::open(npz)?;
        let (_, pose) = z.f64_array("pose_manipulability")?;
        if pose.len() != m.index.len() * m.k {
            return Err(ReachError::Format(format!(
                "{npz}: pose_manipulability does not hold voxels × orientations values"
            )));
        }
        let voxels: Vec<serde_json::Value> = (0..m.index.len())
            .map(|i| {
                serde_json::json!({
                    "centre": &m.centres[3 * i..3 * i + 3],
                    "index": m.index[i],
                    "best_manipulability": num(m.best[i]),
                    "pose_manipulability": pose[i * m.k..(i + 1) * m.k]
                        .iter()
                        .map(|&x| num(x))
                        .collect::<Vec<_>>(),
                })
            })
            .collect();
        serde_json::to_writer(
            &mut w,
            &serde_json::json!({"meta": m.meta, "voxels": voxels}),
        )
        .map_err(std::io::Error::other)
        .and_then(|()| writeln!(w))
    } else {
        return Err(ReachError::Input(format!(
            "{out}: write a map as .npz, or a small one as .csv or .json"
        )));
    };
    res.and_then(|()| w.commit())
        .map_err(|e| ReachError::io(out, e))
}
