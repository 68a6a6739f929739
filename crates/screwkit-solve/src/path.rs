//! Cartesian paths: the tool moved along the screw (or the straight line) from pose to pose,
//! the joints following on one IK branch, and the reason when they cannot.
//!
//! **The motion.** From the seed's pose X_0 = T(q_seed) through each target X_1, X_2, …, segment
//! k is X(σ) = X_{k−1} exp(log(X_{k−1}⁻¹ X_k) σ) ([`Interpolation::Screw`]: one screw motion) or
//! p(σ) = p_{k−1} + σ (p_k − p_{k−1}), R(σ) = R_{k−1} exp(log(R_{k−1}ᵀ R_k) σ)
//! ([`Interpolation::Line`]), σ ∈ [0, 1], sampled so that no step moves the tool more than
//! `max_step` (metres along the chord, radians of turn; MoveIt's `max_step`).
//!
//! **The joints.** Each sample is solved from the previous one: with closed-form IK, every
//! solution is found and the nearest to the previous sample kept (the same posture and 2π
//! copy); where the two nearest solutions come within `max_joint_step` of each other, two
//! branches meet (a singularity) and the path stops there rather than choose; where no solution
//! lies within `max_joint_step` of the previous, the branch ends (a joint limit, or the edge of
//! the workspace). Without closed-form IK, numerical IK is seeded with the previous sample.
//!
//! **The checks.** A step that moves a joint more than `max_joint_step`, or whose joint-space
//! midpoint puts the tool more than `max_deviation` (m and rad) off the path's midpoint
//! (MoveIt's midpoint-deviation test), is halved, at most [`MAX_HALVINGS`] times, before the
//! path gives up there. With a body ([`cartesian_path_clear`]), every sample is checked for
//! contact (self and obstacles, by the body's margin) and the path stops at the last clear
//! one. Deterministic: the same inputs give the same path.

use screwkit_lie::{so3, Se3};

use crate::analytic::{AnalyticIk, RepresentativeKind};
use crate::error::SolveError;
use crate::fk::fk_unchecked;
use crate::ik::{self, Clearance, IkOptions, NoBody};
use crate::kinematics::Kinematics;
use crate::workspace::Workspace;

/// How many times a step may be halved before the path stops there.
pub const MAX_HALVINGS: usize = 8;

/// The most samples of one path (its steps of `max_step` are refused beyond; a path whose
/// halvings would pass it stops there).
pub const MAX_SAMPLES: usize = 1_000_000;

/// The tool's motion between two poses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interpolation {
    /// One screw motion: X_a exp(log(X_a⁻¹ X_b) σ) (a rotation about and a translation along
    /// one fixed axis).
    #[default]
    Screw,
    /// The origin on the straight line, the rotation about one axis, decoupled.
    Line,
}

/// The steps and checks of [`cartesian_path`].
#[derive(Debug, Clone)]
pub struct PathOptions {
    /// The motion between poses.
    pub interpolation: Interpolation,
    /// The largest tool motion per step (m along the chord, and rad of turn).
    pub max_step: f64,
    /// The largest joint motion per step (rad or m).
    pub max_joint_step: f64,
    /// The largest tool deviation at a step's joint-space midpoint (m, and rad).
    pub max_deviation: f64,
    /// The path stops where the tip's body Jacobian's smallest singular value falls below
    /// this (near a singularity, where two IK branches meet and the joints would have to
    /// race or jump).
    pub min_sigma: f64,
    /// Numerical IK's options (without closed-form IK).
    pub ik: IkOptions,
}

impl Default for PathOptions {
    fn default() -> Self {
        Self {
            interpolation: Interpolation::Screw,
            max_step: 0.005,
            max_joint_step: 0.1,
            max_deviation: 0.001,
            min_sigma: 0.005,
            ik: IkOptions::default(),
        }
    }
}

/// Why a path stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathStop {
    /// Every target reached.
    Reached,
    /// Two IK branches meet (a singularity): the path would have to choose.
    Singularity,
    /// The branch ends: no solution near the previous sample (a joint limit, or the edge of
    /// the workspace).
    BranchEnds,
    /// The pose is out of reach (no exact IK solution; numerical IK did not converge).
    Unreachable,
    /// A step still moves a joint too far, or leaves the path, after the halvings.
    Jump,
    /// The next sample's body touches itself or an obstacle (or comes within the margin).
    Collision,
    /// The caller's interrupt (`PathOptions::ik.interrupt`, Ctrl-C) stopped it.
    Interrupted,
}

impl PathStop {
    /// The word for it.
    pub fn as_str(self) -> &'static str {
        match self {
            PathStop::Reached => "reached",
            PathStop::Singularity => "singularity",
            PathStop::BranchEnds => "branch ends",
            PathStop::Unreachable => "unreachable",
            PathStop::Jump => "jump",
            PathStop::Collision => "collision",
            PathStop::Interrupted => "interrupted",
        }
    }
}

/// A Cartesian path: the joint samples (K × dof), each one's place on the path (the segment's
/// index plus σ, so 1.5 is halfway along the second segment), the fraction of the path (by the
/// tool's travel) achieved, and why it stopped (with a sentence).
#[derive(Debug, Clone)]
pub struct CartesianPath {
    /// The joint values, K × dof, row-major; the first row is the seed.
    pub q: Vec<f64>,
    /// Each sample's place: segment k − 1 + σ.
    pub place: Vec<f64>,
    /// The fraction of the path's length achieved (1 when reached).
    pub fraction: f64,
    /// Why it stopped.
    pub stop: PathStop,
    /// What happened where, in one sentence.
    pub message: String,
    /// The joint values the path stopped short of, when it stopped at a sample it had
    /// solved (a collision): what a front end examines to say more.
    pub refused: Option<Vec<f64>>,
}

impl CartesianPath {
    /// The path stopped with `why` at `(travelled, total, segment, σ)` (the tool's travel so
    /// far and in all, the segment's index and the place on it), saying so with `sentence`.
    fn stopped(mut self, why: PathStop, at: (f64, f64, usize, f64), sentence: &str) -> Self {
        let (travelled, total, k, sigma) = at;
        self.stop = why;
        self.fraction = if total > 0.0 { travelled / total } else { 0.0 };
        self.message = format!(
            "stopped on segment {} at {:.1} % of it: {sentence}",
            k + 1,
            100.0 * sigma
        );
        self
    }
}

/// The pose at σ between `a` and `b`.
fn between(
    a: &Se3,
    b: &Se3,
    xi: &screwkit_lie::Twist,
    phi: &nalgebra::Vector3<f64>,
    how: Interpolation,
    s: f64,
) -> Se3 {
    match how {
        Interpolation::Screw => a.compose(&Se3::exp(&(*xi * s))),
        Interpolation::Line => Se3::from_parts_unchecked(
            a.rotation() * so3::exp(&(phi * s)),
            a.translation() * (1.0 - s) + b.translation() * s,
        ),
    }
}

/// The distance between two poses: (translation, rotation angle).
fn apart(a: &Se3, b: &Se3) -> (f64, f64) {
    let d = a.inverse_compose(b);
    (
        (a.translation() - b.translation()).norm(),
        so3::log(d.rotation()).norm(),
    )
}

/// The largest |a_j − b_j|.
fn joint_step(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Whether the smallest singular value of the body Jacobian at q is below `sigma`: J Jᵀ − σ² 1
/// (6 × 6; JᵀJ for fewer than six joints) is then not positive definite, which a Cholesky
/// attempt tells without an SVD.
fn near_singular(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    sigma: f64,
) -> Result<bool, SolveError> {
    let j = crate::jacobian::jacobian(kin, ws, q, screwkit_lie::Frame::Body)?;
    let s2 = sigma * sigma;
    Ok(if j.ncols() >= 6 {
        let g: nalgebra::Matrix6<f64> = j * j.transpose() - nalgebra::Matrix6::identity() * s2;
        g.cholesky().is_none()
    } else {
        let n = j.ncols();
        let g = j.transpose() * j - nalgebra::DMatrix::identity(n, n) * s2;
        g.cholesky().is_none()
    })
}

/// One sample's IK from the previous one; Err(stop, sentence) when the path must stop.
fn follow(
    kin: &Kinematics,
    ws: &mut Workspace,
    analytic: Option<&AnalyticIk>,
    target: &Se3,
    prev: &[f64],
    opts: &PathOptions,
) -> Result<Result<Vec<f64>, (PathStop, String)>, SolveError> {
    match analytic {
        Some(a) => {
            let (sols, _) = a.solve_nearest(
                kin,
                ws,
                target,
                prev,
                None,
                None,
                RepresentativeKind::Nearest,
            )?;
            if sols.is_empty() || !sols.is_exact() {
                return Ok(Err((
                    PathStop::Unreachable,
                    "the pose is out of reach (no exact IK solution within the joint limits)"
                        .into(),
                )));
            }
            let best = sols.q(0).to_vec();
            let d1 = joint_step(&best, prev);
            if d1 > opts.max_joint_step {
                return Ok(Err((
                    PathStop::BranchEnds,
                    format!(
                        "the branch ends: the nearest solution is {d1:.4} away (more than max_joint_step)"
                    ),
                )));
            }
            // Another posture (not a 2π copy of this one) as near: two branches meet.
            for i in 1..sols.len() {
                let other = sols.q(i);
                let gap = joint_step(other, &best);
                let copy = other.iter().zip(&best).all(|(x, y)| {
                    let d = (x - y).abs();
                    d < 1e-9
                        || ((d / std::f64::consts::TAU).round() * std::f64::consts::TAU - d).abs()
                            < 1e-6
                });
                if !copy && gap < opts.max_joint_step {
                    return Ok(Err((
                        PathStop::Singularity,
                        format!(
                            "two IK branches meet ({gap:.4} apart, within max_joint_step): a singularity"
                        ),
                    )));
                }
            }
            Ok(Ok(best))
        }
        None => {
            let r = ik::solve(kin, ws, target, prev, &opts.ik)?;
            if !r.status.converged {
                return Ok(Err((
                    PathStop::Unreachable,
                    format!(
                        "numerical IK did not converge ({} iterations; residual {:.2e} rad, {:.2e} m)",
                        r.status.iterations, r.status.error_rot, r.status.error_pos
                    ),
                )));
            }
            Ok(Ok(r.q))
        }
    }
}

/// The Cartesian path of the chain `kin` from `seed` through `targets` (the module's method);
/// `analytic`: the chain's closed-form IK, when it has one (then branches are followed
/// exactly). Errors only for bad inputs (a seed outside the limits, non-finite options).
pub fn cartesian_path(
    kin: &Kinematics,
    ws: &mut Workspace,
    analytic: Option<&AnalyticIk>,
    targets: &[Se3],
    seed: &[f64],
    opts: &PathOptions,
) -> Result<CartesianPath, SolveError> {
    cartesian_path_clear(kin, ws, analytic, targets, seed, opts, &NoBody, &mut ())
}

/// [`cartesian_path`] keeping `body` clear of contact (`scratch`: its scratch): the seed and
/// every sample are checked ([`Clearance::is_clear`]), and the path stops at the last clear
/// sample with [`PathStop::Collision`] (the colliding sample in `refused`).
#[allow(clippy::too_many_arguments)]
pub fn cartesian_path_clear<C: Clearance>(
    kin: &Kinematics,
    ws: &mut Workspace,
    analytic: Option<&AnalyticIk>,
    targets: &[Se3],
    seed: &[f64],
    opts: &PathOptions,
    body: &C,
    scratch: &mut C::Scratch,
) -> Result<CartesianPath, SolveError> {
    kin.check_q(seed)?;
    for (what, x) in [
        ("max_step", opts.max_step),
        ("max_joint_step", opts.max_joint_step),
        ("max_deviation", opts.max_deviation),
        ("min_sigma", opts.min_sigma),
    ] {
        if !(x.is_finite() && x > 0.0) {
            return Err(SolveError::InvalidInput(format!(
                "{what} {x}: expected a finite number > 0"
            )));
        }
    }
    if let Some(k) = targets.iter().position(|t| !t.is_finite()) {
        return Err(SolveError::InvalidInput(format!(
            "target {k} is not finite"
        )));
    }
    let dof = kin.dof();
    let mut out = CartesianPath {
        q: seed.to_vec(),
        place: vec![0.0],
        fraction: 1.0,
        stop: PathStop::Reached,
        message: "every target reached".into(),
        refused: None,
    };
    let mut poses = vec![fk_unchecked(kin, seed)];
    poses.extend_from_slice(targets);
    // Each segment's length (the larger of its chord / max_step and turn / max_step, in steps).
    let lengths: Vec<f64> = poses
        .windows(2)
        .map(|w| {
            let (d, a) = apart(&w[0], &w[1]);
            d.max(a)
        })
        .collect();
    let total: f64 = lengths.iter().sum();
    let planned: f64 = lengths.iter().map(|l| (l / opts.max_step).ceil()).sum();
    if planned > MAX_SAMPLES as f64 {
        return Err(SolveError::InvalidInput(format!(
            "the path would take {planned:.0} steps of max_step {} (at most {MAX_SAMPLES}): a larger max_step",
            opts.max_step
        )));
    }
    if !body.is_clear(scratch, seed) {
        out.stop = PathStop::Collision;
        out.fraction = 0.0;
        out.message =
            "the seed's body is in contact (or within the margin): no path from it".into();
        out.refused = Some(seed.to_vec());
        return Ok(out);
    }
    let mut done = 0.0;
    let mut ticks = 0u64;
    let mut prev = seed.to_vec();
    for (k, w) in poses.windows(2).enumerate() {
        let (a, b) = (&w[0], &w[1]);
        let xi = a.inverse_compose(b).log();
        let phi = so3::log(&(a.rotation().transpose() * b.rotation()));
        let steps = (lengths[k] / opts.max_step).ceil().max(1.0) as usize;
        let mut sigma = 0.0;
        let mut step = 1.0 / steps as f64;
        let mut halvings = 0;
        while sigma < 1.0 {
            ticks += 1;
            if ticks.is_multiple_of(16)
                && opts.ik.interrupt.is_some_and(|ik::Interrupt(stop)| stop())
            {
                let at = (done + sigma * lengths[k], total, k, sigma);
                return Ok(out.stopped(
                    PathStop::Interrupted,
                    at,
                    "interrupted (Ctrl-C, or the caller's interrupt check)",
                ));
            }
            if out.place.len() > MAX_SAMPLES {
                let at = (done + sigma * lengths[k], total, k, sigma);
                let why = format!("more than {MAX_SAMPLES} samples (its steps keep halving)");
                return Ok(out.stopped(PathStop::Jump, at, &why));
            }
            let next = (sigma + step).min(1.0);
            let target = between(a, b, &xi, &phi, opts.interpolation, next);
            let stop = match follow(kin, ws, analytic, &target, &prev, opts)? {
                Err(stop) => Some(stop),
                Ok(q) => {
                    let jump = joint_step(&q, &prev);
                    let mid: Vec<f64> = q.iter().zip(&prev).map(|(x, y)| 0.5 * (x + y)).collect();
                    let want = between(a, b, &xi, &phi, opts.interpolation, 0.5 * (sigma + next));
                    let (dp, dr) = apart(&fk_unchecked(kin, &mid), &want);
                    if jump <= opts.max_joint_step
                        && dp.max(dr) <= opts.max_deviation
                        && !body.is_clear(scratch, &q)
                    {
                        // (Not halved: the sample before is clear, within a step of contact.)
                        halvings = MAX_HALVINGS;
                        out.refused = Some(q);
                        Some((
                            PathStop::Collision,
                            "the next sample's body is in contact (or within the margin)".into(),
                        ))
                    } else if jump <= opts.max_joint_step && dp.max(dr) <= opts.max_deviation {
                        prev = q;
                        out.q.extend_from_slice(&prev);
                        out.place.push(k as f64 + next);
                        sigma = next;
                        halvings = 0;
                        step = 1.0 / steps as f64;
                        if near_singular(kin, ws, &prev, opts.min_sigma)? {
                            // (The SVD only here, for the message.)
                            let sv = crate::analysis::analyze(
                                kin,
                                ws,
                                &prev,
                                screwkit_lie::Frame::Body,
                            )?
                            .singular_values;
                            let weakest = sv.last().copied().unwrap_or(0.0);
                            halvings = MAX_HALVINGS;
                            Some((
                                PathStop::Singularity,
                                format!(
                                    "a singularity: the Jacobian's smallest singular value is {weakest:.2e} (below min_sigma {}), where IK branches meet",
                                    opts.min_sigma
                                ),
                            ))
                        } else {
                            None
                        }
                    } else {
                        Some((
                            PathStop::Jump,
                            format!(
                                "a step moves a joint {jump:.4} and leaves the path by {:.2e} at its middle, after {MAX_HALVINGS} halvings",
                                dp.max(dr)
                            ),
                        ))
                    }
                }
            };
            if let Some((why, sentence)) = stop {
                if halvings < MAX_HALVINGS {
                    halvings += 1;
                    step *= 0.5;
                    continue;
                }
                debug_assert_eq!(out.q.len(), out.place.len() * dof);
                let at = (done + sigma * lengths[k], total, k, sigma);
                return Ok(out.stopped(why, at, &sentence));
            }
        }
        done += lengths[k];
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn ur5() -> Kinematics {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/ur5.urdf");
        let chain = screwkit_model::urdf::load_file(path)
            .and_then(|t| screwkit_model::Chain::from_tree(&t, None, None))
            .unwrap();
        Kinematics::new(&chain)
    }

    /// A 20 cm straight line with a quarter turn, on the UR5 by its closed-form IK: every
    /// sample's tool pose is on the line (by FK), no joint step exceeds max_joint_step, and
    /// the posture never changes (each sample the nearest solution to the previous).
    #[test]
    fn the_ur5_follows_a_line_on_one_branch() {
        let kin = ur5();
        let mut ws = Workspace::new(&kin);
        let analytic = AnalyticIk::new(&kin).unwrap();
        let seed = [0.3, -1.2, 1.4, -1.5, -1.4, 0.4];
        let start = fk_unchecked(&kin, &seed);
        let turn =
            Se3::from_parts_unchecked(so3::exp(&Vector3::new(0.0, 0.0, 0.4)), Vector3::zeros());
        let goal = Se3::from_parts_unchecked(
            start.rotation() * turn.rotation(),
            start.translation() + Vector3::new(0.1, -0.15, 0.05),
        );
        let opts = PathOptions {
            interpolation: Interpolation::Line,
            ..Default::default()
        };
        let path = cartesian_path(&kin, &mut ws, Some(&analytic), &[goal], &seed, &opts).unwrap();
        assert_eq!(path.stop, PathStop::Reached, "{}", path.message);
        assert_eq!(path.fraction, 1.0);
        let rows: Vec<&[f64]> = path.q.chunks(6).collect();
        assert!(rows.len() > 30);
        for (w, place) in rows.windows(2).zip(path.place.iter().skip(1)) {
            assert!(joint_step(w[0], w[1]) <= opts.max_joint_step);
            let x = fk_unchecked(&kin, w[1]);
            let on = between(
                &start,
                &goal,
                &start.inverse_compose(&goal).log(),
                &so3::log(&(start.rotation().transpose() * goal.rotation())),
                Interpolation::Line,
                *place,
            );
            assert!(x.max_abs_diff(&on) < 1e-9, "{place}");
        }
        assert!(fk_unchecked(&kin, rows.last().unwrap()).max_abs_diff(&goal) < 1e-9);
    }

    /// Through a wrist singularity (joint 5 to 0: joints 4 and 6 aligned; the screw from the
    /// start to the goal is joint 5's own rotation) the path stops just before it and says
    /// so: about halfway, the last sample within min_sigma's reach of q5 = 0.
    #[test]
    fn a_wrist_singularity_stops_the_ur5() {
        let kin = ur5();
        let mut ws = Workspace::new(&kin);
        let analytic = AnalyticIk::new(&kin).unwrap();
        let seed = [0.3, -1.2, 1.4, -1.5, 0.3, 0.4];
        let through = [0.3, -1.2, 1.4, -1.5, -0.3, 0.4];
        let goal = fk_unchecked(&kin, &through);
        let path = cartesian_path(
            &kin,
            &mut ws,
            Some(&analytic),
            &[goal],
            &seed,
            &PathOptions::default(),
        )
        .unwrap();
        assert_ne!(path.stop, PathStop::Reached, "{}", path.message);
        assert!(
            path.fraction < 1.0 && path.fraction > 0.1,
            "{} {}",
            path.fraction,
            path.message
        );
    }

    /// A body that is clear while the tool is above a plane (a stand-in for a table): the path
    /// down through it stops at the last sample above, the refused one below, and a seed
    /// below gives no path.
    #[test]
    fn a_body_stops_the_path_before_contact() {
        struct Above<'a>(&'a Kinematics, f64);
        impl Clearance for Above<'_> {
            type Scratch = ();
            fn scratch(&self) {}
            fn is_clear(&self, _: &mut (), q: &[f64]) -> bool {
                fk_unchecked(self.0, q).translation().z > self.1
            }
            fn close_rows(
                &self,
                _: &mut (),
                _: &[f64],
                _: f64,
                _: &mut Vec<f64>,
                _: &mut Vec<f64>,
            ) {
            }
        }
        let kin = ur5();
        let mut ws = Workspace::new(&kin);
        let analytic = AnalyticIk::new(&kin).unwrap();
        let seed = [0.3, -1.2, 1.4, -1.5, -1.4, 0.4];
        let start = fk_unchecked(&kin, &seed);
        let z0 = start.translation().z;
        let goal = Se3::from_parts_unchecked(
            *start.rotation(),
            start.translation() - Vector3::new(0.0, 0.0, 0.2),
        );
        let opts = PathOptions {
            interpolation: Interpolation::Line,
            ..Default::default()
        };
        let plane = Above(&kin, z0 - 0.05);
        let path = cartesian_path_clear(
            &kin,
            &mut ws,
            Some(&analytic),
            &[goal],
            &seed,
            &opts,
            &plane,
            &mut (),
        )
        .unwrap();
        assert_eq!(path.stop, PathStop::Collision, "{}", path.message);
        assert!(
            (path.fraction - 0.25).abs() <= 0.025 + 1e-12,
            "{}",
            path.fraction
        );
        let last = path.q.chunks(6).last().unwrap();
        assert!(fk_unchecked(&kin, last).translation().z > z0 - 0.05);
        let refused = path.refused.as_deref().unwrap();
        assert!(fk_unchecked(&kin, refused).translation().z <= z0 - 0.05);
        let high = Above(&kin, z0 + 0.01);
        let none = cartesian_path_clear(
            &kin,
            &mut ws,
            Some(&analytic),
            &[goal],
            &seed,
            &opts,
            &high,
            &mut (),
        )
        .unwrap();
        assert_eq!(
            (none.stop, none.fraction, none.place.len()),
            (PathStop::Collision, 0.0, 1)
        );
    }

    /// The Cholesky test of the smallest singular value agrees with the SVD's (the reference)
    /// on configurations near and far from the wrist singularity.
    #[test]
    fn the_cholesky_test_agrees_with_the_svd() {
        let kin = ur5();
        let mut ws = Workspace::new(&kin);
        for q5 in [0.5, 0.1, 0.02, 0.014, 0.0148, 0.015, 0.016, 0.001, -0.01] {
            let q = [0.3, -1.2, 1.4, -1.5, q5, 0.4];
            let sv = crate::analysis::analyze(&kin, &mut ws, &q, screwkit_lie::Frame::Body)
                .unwrap()
                .singular_values;
            let weakest = *sv.last().unwrap();
            for sigma in [0.005, 0.01, 0.05] {
                assert_eq!(
                    near_singular(&kin, &mut ws, &q, sigma).unwrap(),
                    weakest < sigma,
                    "q5 {q5}, sigma {sigma}: weakest {weakest}"
                );
            }
        }
    }

    /// Untrusted options: a step so small the path would take billions of samples is refused
    /// before any is made (no unbounded memory); NaN options and targets are named.
    #[test]
    fn hostile_options_are_refused() {
        let kin = ur5();
        let mut ws = Workspace::new(&kin);
        let seed = [0.3, -1.2, 1.4, -1.5, -1.4, 0.4];
        let mut goal = fk_unchecked(&kin, &seed);
        goal = Se3::from_parts_unchecked(
            *goal.rotation(),
            goal.translation() + Vector3::new(0.5, 0.0, 0.0),
        );
        let tiny = PathOptions {
            max_step: 1e-9,
            ..Default::default()
        };
        let e = cartesian_path(&kin, &mut ws, None, &[goal], &seed, &tiny).unwrap_err();
        assert!(e.to_string().contains("at most 1000000"), "{e}");
        let nan = PathOptions {
            max_deviation: f64::NAN,
            ..Default::default()
        };
        let e = cartesian_path(&kin, &mut ws, None, &[goal], &seed, &nan).unwrap_err();
        assert!(e.to_string().contains("max_deviation"), "{e}");
        let bad = Se3::from_parts_unchecked(*goal.rotation(), Vector3::new(f64::NAN, 0.0, 0.0));
        let e = cartesian_path(
            &kin,
            &mut ws,
            None,
            &[goal, bad],
            &seed,
            &PathOptions::default(),
        )
        .unwrap_err();
        assert!(e.to_string().contains("target 1"), "{e}");
    }
}
