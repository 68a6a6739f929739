//! The analytic solver prepared once per chain ([`AnalyticIk`]: the model side) and its calls:
//! the postures kernel, solutions within the limits, sweeps, batches.

use super::*;
use crate::linalg::newton;

/// An analytic solver prepared for one chain (or one 7R chain with a chosen joint locked):
/// build once, solve many poses. `Send + Sync`, cheap to clone.
#[derive(Debug, Clone)]
pub struct AnalyticIk {
    pub(super) family: Family,
    pub(super) method: Method,
    pub(super) reversed: bool,
    pub(super) lock: Option<Lock>,
    /// Chain variable index of each of the six free joints, in chain order.
    pub(super) free: [usize; 6],
    pub(super) dof: usize,
    /// The chain's axis lines at home, one per joint.
    pub(super) lines: Vec<AxisLine>,
    /// The chain's M.
    pub(super) home: Se3,
    /// The prepared problem of an unlocked chain.
    pub(super) fixed: Option<Prepared>,
    /// The general 6R's reading (`general::choose_shift`, chosen once per solver); 0 for
    /// the other methods.
    pub(super) shift: usize,
    /// A 7R arm solved by its arm angle (the "lock value" is ψ; [`AnalyticIk::arm_angle`]).
    pub(super) arm: Option<ArmAngle>,
    /// A locked chain's general-6R reading (forward), chosen on first use, for lock values
    /// where its subproblem-5 closed form finds nothing ([`AnalyticIk::postures`]).
    pub(super) fallback_shift: std::sync::OnceLock<usize>,
    /// The caller's "stop now" check ([`AnalyticIk::with_interrupt`]), polled between the
    /// lock values of a sweep and the steps of its refinement.
    pub(super) interrupt: Option<crate::ik::Interrupt>,
    /// This solver's identity, for the prepared problem a workspace keeps ([`PreparedAt`]):
    /// one per construction; a clone (the same lines, method and reading) keeps it.
    pub(super) id: u64,
}

/// What the arm-angle solver says of itself.
const ARM_WORDS: &str = "closed form at an arm angle ψ (spherical shoulder and wrist): \
                         subproblem 3, then the shoulder and the wrist, up to 8 solutions per ψ";

/// The most lock values one sweep may have ([`AnalyticIk::lock_values`]).
pub const MAX_SWEEP: usize = 100_000;
/// The most rows one posture may list with every 2π representative (`all`): a joint whose
/// limits span k turns has k representatives, and the rows are their product (a UR5 with
/// ±2π limits: at most 3⁶ = 729; limits of ±50 rad, as files write for "unlimited": 16⁶).
pub const MAX_REPRESENTATIVE_ROWS: usize = 4096;

/// What [`AnalyticIk::lock_score`] adds where no posture is exact (above any limit excess).
const OUT_OF_REACH: f64 = 1e3;
/// The most local minima of a sweep refined ([`AnalyticIk::solve_swept`]).
const REFINED: usize = 4;
/// Golden-section steps per refined minimum (the bracket shrinks by 0.618 each: 40 steps
/// take it below 1e-8 of the samples' spacing).
const REFINE_STEPS: usize = 40;
/// Parts the bracket of a refined minimum is first divided into.
const SUBDIVIDE: usize = 16;

impl AnalyticIk {
    /// This solver polling `interrupt` between a sweep's lock values and its refinement's
    /// steps (a front end's Ctrl-C): when it says stop, the call ends with an error saying it
    /// was interrupted. One value is one closed form (microseconds): not polled.
    pub fn with_interrupt(mut self, interrupt: crate::ik::Interrupt) -> Self {
        self.interrupt = Some(interrupt);
        self
    }

    /// An error when the caller's interrupt check says stop.
    fn check_interrupt(&self) -> Result<(), SolveError> {
        match self.interrupt {
            Some(crate::ik::Interrupt(stop)) if stop() => Err(SolveError::InvalidInput(
                "interrupted (the caller's stop check)".into(),
            )),
            _ => Ok(()),
        }
    }

    /// The solver of a 6R chain of a family solved here; an error naming the family
    /// otherwise (a 7R chain: lock a joint with [`AnalyticIk::locked`]).
    pub fn new(kin: &Kinematics) -> Result<Self, SolveError> {
        let c = classify(kin);
        if c.family == Family::Redundant7R {
            return Err(SolveError::InvalidInput(format!(
                "{}: lock one joint to solve it analytically",
                c.family.describe()
            )));
        }
        if kin.dof() == 6 && kin.space.iter().all(|j| j.is_revolute()) {
            let rank = crate::family::generic_rank(kin);
            if rank < 6 {
                return Err(SolveError::InvalidInput(format!(
                    "this arm's Jacobian has rank {rank} < 6 at every configuration (six \
                     parallel axes, two coincident ones, …): each pose it reaches has a \
                     {}-parameter self-motion, not a finite solution set; use numerical IK",
                    6 - rank
                )));
            }
        }
        let fail = || {
            SolveError::InvalidInput(format!(
                "no analytic solver for this chain: {}",
                helical_or(kin, c.family.describe())
            ))
        };
        if c.family == Family::NotAnalytic || kin.dof() != 6 {
            return Err(fail());
        }
        if shoulder_and_wrist(&c.axes, kin.length_scale) {
            return Err(SolveError::InvalidInput(
                "axes 1-3 and axes 4-6 each meet in a point: the reachable poses have a \
                 one-parameter self-motion, so there is no finite solution set"
                    .into(),
            ));
        }
        let (family, method, reversed) =
            method_either(&c.axes, kin.length_scale).ok_or_else(fail)?;
        let lines: [AxisLine; 6] = c.axes.clone().try_into().map_err(|_| fail())?;
        let shift = if method == Method::General {
            choose_shift(&lines, kin.home, reversed)
        } else {
            0
        };
        Ok(Self {
            family,
            method,
            reversed,
            lock: None,
            free: [0, 1, 2, 3, 4, 5],
            dof: 6,
            fixed: Some(Prepared::new(method, &lines, kin.home, reversed, shift)),
            shift,
            arm: None,
            fallback_shift: std::sync::OnceLock::new(),
            interrupt: None,
            id: next_solver_id(),
            lines: c.axes,
            home: kin.home,
        })
    }

    /// The solver of a 7R arm with a spherical shoulder (axes 1–3 meet) and a spherical
    /// wrist (axes 5–7 meet) — the iiwa type — at a given *arm angle* ψ (module `arm_angle`:
    /// the definition of ψ and its reference plane), which takes the place of the lock value
    /// in every call ([`AnalyticIk::solve`], sweeps over [−π, π), batches; by default the
    /// seed's arm angle). Axes that meet within [`ARM_ANGLE_SNAP`] × L count as meeting: the
    /// postures of the snapped geometry are polished on the real chain. An error naming what
    /// is missing otherwise.
    pub fn arm_angle(kin: &Kinematics) -> Result<Self, SolveError> {
        let c = classify(kin);
        let all_revolute = kin.space.iter().all(|j| j.is_revolute()) && kin.identity_map;
        let arm = (kin.dof() == 7 && all_revolute)
            .then(|| ArmAngle::new(&c.axes, kin.home, kin.length_scale))
            .flatten()
            .ok_or_else(|| {
                SolveError::InvalidInput(format!(
                    "no arm angle for this chain: it needs 7 revolute joints whose axes 1-3 \
                     and 5-7 each meet in a point (a spherical shoulder and wrist, within \
                     {ARM_ANGLE_SNAP:e} L) and an elbow axis through neither; this one is: {}",
                    c.family.describe()
                ))
            })?;
        Ok(Self {
            family: c.family,
            method: Method::ArmAngle,
            reversed: false,
            lock: None,
            // (Polishing moves all seven joints: the least-norm step.)
            free: [0, 1, 3, 4, 5, 6],
            dof: 7,
            fixed: None,
            shift: 0,
            arm: Some(arm),
            fallback_shift: std::sync::OnceLock::new(),
            interrupt: None,
            id: next_solver_id(),
            lines: c.axes,
            home: kin.home,
        })
    }

    /// True for a solver by the arm angle ([`AnalyticIk::arm_angle`]).
    pub fn by_arm_angle(&self) -> bool {
        self.arm.is_some()
    }

    /// The arm angle ψ of configuration `q` (module `arm_angle`), in [−π, π]: None for a
    /// solver not by the arm angle; NaN where ψ is undefined (the wrist centre at the
    /// shoulder, the elbow on the shoulder–wrist line).
    pub fn arm_angle_of(&self, q: &[f64]) -> Option<f64> {
        let a = self.arm.as_ref()?;
        (q.len() == 7).then(|| a.angle_of(q))
    }

    /// How it solves, in words (the row of the decomposition table).
    pub fn words(&self) -> &'static str {
        if self.arm.is_some() {
            return ARM_WORDS;
        }
        row(self.method).words
    }

    /// The family of the 6R problem solved (for a locked 7R chain: of the other six joints).
    pub fn family(&self) -> Family {
        self.family
    }

    /// The locked joint (0-based), if any.
    pub fn locked_joint(&self) -> Option<usize> {
        self.lock.map(|l| l.joint)
    }

    /// True when the chain is solved from tip to base (its reversed order is the family's).
    pub fn reversed(&self) -> bool {
        self.reversed
    }

    /// Every posture reaching `target` (the kernel; allocation-free for the closed forms):
    /// exact ones, and least-squares ones on branches where the pose is out of reach. `lock_value` is the
    /// locked joint's value (ignored without a lock). The target must be finite (checked by
    /// [`AnalyticIk::solve`]).
    pub fn postures(&self, target: &Se3, lock_value: f64, out: &mut Postures) {
        self.postures_kept(target, lock_value, &mut None, out);
    }

    /// [`AnalyticIk::postures`], a locked chain's prepared problem taken from `kept` when it
    /// is this solver's at this value, else built and left there ([`PreparedAt`]).
    pub(super) fn postures_kept(
        &self,
        target: &Se3,
        lock_value: f64,
        kept: &mut Option<Box<PreparedAt>>,
        out: &mut Postures,
    ) {
        if let Some(a) = &self.arm {
            out.len = 0;
            out.dof = 7;
            let mut singular = false;
            a.postures(target, lock_value, &mut singular, &mut |t, exact| {
                let mut q = [0.0; MAX_DOF];
                for (x, v) in q.iter_mut().zip(t) {
                    *x = wrap(v);
                }
                out.push(q, exact);
            });
            out.singular = singular;
            return;
        }
        let p = match &self.fixed {
            Some(p) => p,
            None => {
                let value = lock_value.to_bits();
                let fresh = |s: &Self| {
                    let (lines, home) = s.locked_lines(lock_value);
                    PreparedAt {
                        solver: s.id,
                        value,
                        prepared: Prepared::new(s.method, &lines, home, s.reversed, s.shift),
                    }
                };
                // Boxed (a workspace stays small to move) and rewritten in place.
                match kept {
                    Some(k) if k.solver == self.id && k.value == value => {}
                    Some(k) => **k = fresh(self),
                    None => *kept = Some(Box::new(fresh(self))),
                }
                match kept {
                    Some(k) => &k.prepared,
                    None => return,
                }
            }
        };
        self.run(self.method, self.reversed, p, target, lock_value, out);
        // Subproblem 5 on a locked chain can lose every posture at lock values where two of
        // the six lines come close to a relation they do not have elsewhere (TALOS's arm with
        // joint 2 or 3 locked: 0.35 % and 0.015 % of random reachable poses): there the general
        // 6R, which needs no relation, solves the chain. (Only this closed form: the others
        // showed no such loss; each fallback costs a general solve, ~50 µs.)
        if self.lock.is_some()
            && self.method == Method::Wrist
            && !out.as_slice().iter().any(|q| q.exact)
        {
            let (lines, home) = self.locked_lines(lock_value);
            let shift = *self.fallback_shift.get_or_init(|| {
                let (a, h) = self.locked_lines(0.7);
                choose_shift(&a, h, false)
            });
            let general = Prepared::new(Method::General, &lines, home, false, shift);
            let mut alt = Postures::default();
            self.run(
                Method::General,
                false,
                &general,
                target,
                lock_value,
                &mut alt,
            );
            if alt.as_slice().iter().any(|q| q.exact) {
                *out = alt;
            }
        }
    }

    /// The kernel of `method` on the prepared problem `p` (read tip to base when `reversed`)
    /// into `out`, the postures mapped to the chain's variables.
    fn run(
        &self,
        method: Method,
        reversed: bool,
        p: &Prepared,
        target: &Se3,
        lock_value: f64,
        out: &mut Postures,
    ) {
        let g = if reversed {
            p.home.compose(&target.inverse())
        } else {
            target.compose(&p.home.inverse())
        };
        out.len = 0;
        out.dof = self.dof;
        out.singular = false;
        let mut singular = false;
        let mut emit = |t: [f64; 6], exact: bool| {
            let mut q = [0.0; MAX_DOF];
            for (slot, &j) in self.free.iter().enumerate() {
                q[j] = wrap(if reversed { t[5 - slot] } else { t[slot] });
            }
            if let Some(l) = self.lock {
                q[l.joint] = lock_value;
            }
            out.push(q, exact);
        };
        (row(method).kernel)(p, &g, &mut singular, &mut emit);
        out.singular = singular;
    }

    /// Every solution of T(q) = `target` within the joint limits into `out` (see
    /// [`Solutions`]): the exact postures, or the least-squares ones when none is exact,
    /// deduplicated modulo 2π, each at every 2π shift inside the limits, each with its FK
    /// residual (an exact posture whose residual exceeds 1e-13 L is polished by Newton steps).
    /// `lock_value`: the locked joint's value (must be within its limits; ignored without a
    /// lock).
    pub fn solve(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        lock_value: f64,
        out: &mut Solutions,
    ) -> Result<(), SolveError> {
        self.solve_swept(kin, ws, target, &[lock_value], out)
    }

    /// [`AnalyticIk::solve`] with the locked joint at each of `lock_values` in turn (a sweep
    /// of the self-motion of a 7R arm, [`AnalyticIk::sweep`]), all solutions in one list: the
    /// exact ones of every value, or the least-squares ones when no value gives an exact one.
    /// With several values, the best samples that reach nothing within the limits are refined
    /// by a golden-section search between their neighbours (at most 4 of them, each at most 60
    /// steps), and the values so found that reach the pose are solved too
    /// ([`Solutions::refined`]): a coarse sweep does not miss a reachable pose whose band of
    /// lock values falls between its samples.
    pub fn solve_swept(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        lock_values: &[f64],
        out: &mut Solutions,
    ) -> Result<(), SolveError> {
        self.solve_postures(kin, ws, target, lock_values, Representatives::All, out)
    }

    /// [`AnalyticIk::solve_swept`] listing the 2π representatives `reps` asks for
    /// ([`Representatives`]: every one, or one row per posture).
    pub fn solve_postures(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        lock_values: &[f64],
        reps: Representatives<'_>,
        out: &mut Solutions,
    ) -> Result<(), SolveError> {
        if let Representatives::Nearest(seed) = reps {
            kin.check_q(seed)?;
        }
        if kin.dof() != self.dof {
            return Err(SolveError::InvalidInput(format!(
                "this analytic solver is for a {}-joint chain, not {}",
                self.dof,
                kin.dof()
            )));
        }
        if !target.is_finite() {
            return Err(SolveError::BadTarget(crate::BadTarget::NonFinite));
        }
        if self.arm.is_some() {
            if let Some(v) = lock_values.iter().find(|v| !v.is_finite()) {
                return Err(SolveError::InvalidInput(format!(
                    "arm angle {v} is not a finite number"
                )));
            }
        }
        if let Some(l) = self.lock {
            let (lo, hi) = (kin.lower[l.joint], kin.upper[l.joint]);
            if let Some(v) = lock_values.iter().find(|&&v| !(v >= lo && v <= hi)) {
                return Err(SolveError::InvalidInput(format!(
                    "locked value {v} of joint {} outside its limits [{lo}, {hi}]",
                    kin.names[l.joint]
                )));
            }
        }
        out.clear(self.dof);
        if let [v] = lock_values {
            // One value (the hot path, allocation-free for the closed forms).
            let mut raw = Postures::default();
            self.postures_kept(target, *v, &mut ws.analytic, &mut raw);
            let any_exact = raw.as_slice().iter().any(|p| p.exact);
            self.collect(kin, ws, target, &raw, any_exact, reps, out)?;
            return Ok(());
        }
        // A sweep: every value's postures once; then, as its samples may all miss a narrow
        // band of lock values where the pose is reachable within the limits, the best
        // samples that reach nothing refined.
        let mut raws: Vec<Postures> = Vec::with_capacity(lock_values.len());
        for (k, &v) in lock_values.iter().enumerate() {
            if k % 64 == 0 {
                self.check_interrupt()?;
            }
            let mut raw = Postures::default();
            self.postures(target, v, &mut raw);
            raws.push(raw);
        }
        let mut refined = Vec::new();
        if self.lock.is_some() || self.arm.is_some() {
            self.check_interrupt()?;
            refined = self.refine(kin, target, lock_values, &mut raws);
            self.check_interrupt()?;
        }
        // Exact postures are preferred over least-squares ones across all the values.
        let any_exact = raws.iter().any(|r| r.as_slice().iter().any(|p| p.exact));
        for raw in &raws {
            self.collect(kin, ws, target, raw, any_exact, reps, out)?;
        }
        out.refined = refined;
        Ok(())
    }

    /// Appends the solutions of one lock value's postures to `out`: those exact (or, when
    /// `any_exact` is false, the least-squares ones), one per posture modulo 2π, each polished
    /// if its residual is above [`POLISH`] and expanded to the 2π shifts within the limits
    /// that `reps` asks for.
    #[allow(clippy::too_many_arguments)]
    fn collect(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        raw: &Postures,
        any_exact: bool,
        reps: Representatives<'_>,
        out: &mut Solutions,
    ) -> Result<(), SolveError> {
        let n = self.dof;
        out.singular |= raw.singular;
        // One entry per posture (modulo 2π); its shifts are then distinct by construction.
        let mut distinct = [[0.0; MAX_DOF]; MAX_POSTURES];
        let mut count = 0;
        for p in raw.as_slice().iter().filter(|p| p.exact == any_exact) {
            let same = |d: &[f64; MAX_DOF]| (0..n).all(|i| wrap(d[i] - p.q[i]).abs() < 1e-9);
            if distinct[..count].iter().any(same) {
                continue;
            }
            let mut q = p.q;
            let mut residual = fk_unchecked(kin, &q[..n]).max_abs_diff(target);
            if p.exact && residual > POLISH * kin.length_scale.max(1.0) {
                residual = self
                    .polish(kin, ws, &mut q[..n], target)
                    .unwrap_or(residual);
                // A posture its polish cannot bring to the target is not one (a snapped
                // geometry near a singularity of the polished joints): left out.
                if residual > EXACT * kin.length_scale.max(1.0) {
                    continue;
                }
            }
            if self.expand(kin, &q[..n], p.exact, residual, reps, out)? {
                distinct[count] = p.q;
                count += 1;
            }
        }
        out.branches += count;
        Ok(())
    }

    /// How far the postures of one lock value are from a solution within the limits: where
    /// some posture is exact, the least over the exact ones of how far each joint's nearest
    /// 2π shift lies outside its limits; else [`OUT_OF_REACH`] plus the least over the
    /// least-squares ones of FK residual plus that excess. 0: solutions exist.
    fn lock_score(&self, kin: &Kinematics, target: &Se3, raw: &Postures) -> f64 {
        use std::f64::consts::TAU;
        let n = self.dof;
        let any_exact = raw.as_slice().iter().any(|p| p.exact);
        raw.as_slice()
            .iter()
            .filter(|p| p.exact == any_exact)
            .map(|p| {
                // Where the pose is reached (ignoring limits), how far the exact postures are
                // outside the limits; elsewhere, above any of those, the least-squares
                // residual (towards where it is reached).
                let mut score = if p.exact {
                    0.0
                } else {
                    OUT_OF_REACH + fk_unchecked(kin, &p.q[..n]).max_abs_diff(target)
                };
                for i in 0..n {
                    let (lo, hi) = (kin.lower[i], kin.upper[i]);
                    // A joint with a bound at ±∞ reaches every angle by some turn.
                    let unbounded = !lo.is_finite() || !hi.is_finite();
                    if kin.continuous[i] || unbounded || self.lock.is_some_and(|l| l.joint == i) {
                        continue;
                    }
                    // How far the shift of q_i nearest the interval [lo, hi] is outside it.
                    let m = ((0.5 * (lo + hi) - p.q[i]) / TAU).round();
                    score += [m - 1.0, m, m + 1.0]
                        .iter()
                        .map(|k| {
                            let x = p.q[i] + k * TAU;
                            (lo - x).max(x - hi).max(0.0)
                        })
                        .fold(f64::INFINITY, f64::min);
                }
                score
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Lock values between a sweep's samples where the pose is reached within the limits
    /// although no sample nearby reaches it: around each of the (at most [`REFINED`]) best
    /// samples that are a local minimum of [`Self::lock_score`] and reach nothing, the
    /// bracket of its neighbours divided in [`SUBDIVIDE`] parts, then a golden-section search
    /// around the best part. A band narrower than the samples' spacing (the PR2's elbow, locked,
    /// reaches a pose over a few mrad) is so found, not silently missed.
    fn refine(
        &self,
        kin: &Kinematics,
        target: &Se3,
        samples: &[f64],
        raws: &mut Vec<Postures>,
    ) -> Vec<f64> {
        let scores: Vec<f64> = raws
            .iter()
            .map(|r| self.lock_score(kin, target, r))
            .collect();
        let k = samples.len();
        // A continuous joint's or the arm angle's samples close a circle: the first and the
        // last are neighbours across ±π (a band between them is bracketed too).
        let round = k > 2 && self.lock_span(kin).is_some_and(|(_, _, c)| c);
        let before = |i: usize| match i {
            0 if round => Some((k - 1, -std::f64::consts::TAU)),
            0 => None,
            _ => Some((i - 1, 0.0)),
        };
        let after = |i: usize| match i {
            _ if i + 1 == k && round => Some((0, std::f64::consts::TAU)),
            _ if i + 1 == k => None,
            _ => Some((i + 1, 0.0)),
        };
        let mut minima: Vec<usize> = (0..k)
            .filter(|&i| {
                scores[i] > 0.0
                    && scores[i].is_finite()
                    && before(i).is_none_or(|(j, _)| scores[i] <= scores[j])
                    && after(i).is_none_or(|(j, _)| scores[i] <= scores[j])
            })
            .collect();
        minima.sort_by(|&a, &b| scores[a].total_cmp(&scores[b]));
        minima.truncate(REFINED);
        let (lo, hi) = if round {
            (f64::NEG_INFINITY, f64::INFINITY)
        } else {
            self.lock_range(kin)
        };
        let mut found = Vec::new();
        // (Across ±π a value is brought back into (−π, π].)
        let norm = |v: f64| if round { wrap(v) } else { v };
        let score = |v: f64, raw: &mut Postures| {
            self.postures(target, norm(v), raw);
            self.lock_score(kin, target, raw)
        };
        let (mut rc, mut rd) = (Postures::default(), Postures::default());
        for i in minima {
            let a = before(i).map_or(samples[i], |(j, shift)| samples[j] + shift);
            let b = after(i).map_or(samples[i], |(j, shift)| samples[j] + shift);
            let (mut a, mut b) = (a.min(b).max(lo), a.max(b).min(hi));
            // First the bracket evenly subdivided (the score, made of least-squares
            // residuals, may rise right beside a band where the pose is reached), then a
            // golden-section search around the best point for a zero of the score.
            let mut best = (f64::INFINITY, 0.5 * (a + b));
            let mut hit = None;
            for j in 1..SUBDIVIDE {
                let v = a + (b - a) * j as f64 / SUBDIVIDE as f64;
                let f = score(v, &mut rc);
                if f == 0.0 {
                    hit = Some(v);
                    break;
                }
                if f < best.0 {
                    best = (f, v);
                }
            }
            if let Some(v) = hit {
                found.push(norm(v));
                raws.push(rc.clone());
                continue;
            }
            let h = (b - a) / SUBDIVIDE as f64;
            (a, b) = ((best.1 - h).max(a), (best.1 + h).min(b));
            let r = 0.5 * (5f64.sqrt() - 1.0);
            let mut c = b - r * (b - a);
            let mut d = a + r * (b - a);
            let mut fc = score(c, &mut rc);
            let mut fd = score(d, &mut rd);
            for _ in 0..REFINE_STEPS {
                if fc == 0.0 || fd == 0.0 {
                    break;
                }
                if fc < fd {
                    (b, d, fd) = (d, c, fc);
                    std::mem::swap(&mut rc, &mut rd);
                    c = b - r * (b - a);
                    fc = score(c, &mut rc);
                } else {
                    (a, c, fc) = (c, d, fd);
                    std::mem::swap(&mut rc, &mut rd);
                    d = a + r * (b - a);
                    fd = score(d, &mut rd);
                }
            }
            if fc == 0.0 {
                found.push(norm(c));
                raws.push(rc.clone());
            } else if fd == 0.0 {
                found.push(norm(d));
                raws.push(rd.clone());
            }
        }
        found
    }

    /// The locked joint's range as [`AnalyticIk::sweep`] covers it, and whether its ends are
    /// one angle (a continuous joint; the arm angle's [−π, π)); None without a lock.
    fn lock_span(&self, kin: &Kinematics) -> Option<(f64, f64, bool)> {
        use std::f64::consts::PI;
        if self.arm.is_some() {
            return Some((-PI, PI, true));
        }
        let l = self.lock?;
        let (lo, hi) = (kin.lower[l.joint], kin.upper[l.joint]);
        Some(if lo.is_finite() && hi.is_finite() {
            (lo, hi, false)
        } else {
            (-PI, PI, true)
        })
    }

    /// The locked joint's range as [`AnalyticIk::sweep`] covers it.
    fn lock_range(&self, kin: &Kinematics) -> (f64, f64) {
        self.lock_span(kin)
            .map_or((0.0, 0.0), |(lo, hi, _)| (lo, hi))
    }

    /// The lock options' errors, before any target ([`AnalyticIk::lock_values`] takes them):
    /// a value or a sweep for a solver without a lock, both at once, a sweep of 0 or more
    /// than [`MAX_SWEEP`] values.
    pub fn check_lock_options(
        &self,
        kin: &Kinematics,
        value: Option<f64>,
        sweep: Option<usize>,
    ) -> Result<(), SolveError> {
        let bad = |m: String| Err(SolveError::InvalidInput(m));
        if self.lock_span(kin).is_none() {
            if value.is_some() || sweep.is_some() {
                return bad(
                    "a lock value or a sweep is for a 7R chain with a locked joint or \
                            an arm angle"
                        .into(),
                );
            }
            return Ok(());
        }
        match (value, sweep) {
            (Some(_), Some(_)) => bad("a lock value and a sweep exclude each other".into()),
            (None, Some(0)) => bad("a sweep needs at least one value".into()),
            (None, Some(n)) if n > MAX_SWEEP => bad(format!(
                "a sweep of {n} values is more than {MAX_SWEEP} (each value gives up to 8 \
                 postures and their 2π shifts)"
            )),
            _ => Ok(()),
        }
    }

    /// The values of the locked joint (or arm angle) a caller means: `sweep` values evenly
    /// spaced over its limits ([`AnalyticIk::sweep`]), or `value`, or else the seed's value of
    /// that joint (the seed's arm angle); \[0\] without a lock (where a value or a sweep is an
    /// error, as are both at once).
    pub fn lock_values(
        &self,
        kin: &Kinematics,
        seed: &[f64],
        value: Option<f64>,
        sweep: Option<usize>,
    ) -> Result<Vec<f64>, SolveError> {
        self.check_lock_options(kin, value, sweep)?;
        if self.lock_span(kin).is_none() {
            return Ok(vec![0.0]);
        }
        match (value, sweep) {
            (None, Some(n)) => Ok(self.sweep(kin, n)),
            // (With a sweep too: refused above.)
            (Some(v), _) => Ok(vec![v]),
            (None, None) => {
                kin.check_q(seed)?;
                match (&self.arm, self.lock) {
                    (Some(a), _) => {
                        let psi = a.angle_of(seed);
                        // Undefined at the seed (elbow on the shoulder–wrist line): 0.
                        Ok(vec![if psi.is_finite() { psi } else { 0.0 }])
                    }
                    (None, Some(l)) => Ok(vec![seed[l.joint]]),
                    (None, None) => Ok(vec![0.0]),
                }
            }
        }
    }

    /// `count` values of the locked joint (or the arm angle) evenly spaced over its limits,
    /// ends included ([−π, π) for a continuous joint and the arm angle); empty without a lock.
    pub fn sweep(&self, kin: &Kinematics, count: usize) -> Vec<f64> {
        let Some((lo, hi, continuous)) = self.lock_span(kin) else {
            return Vec::new();
        };
        match count {
            0 => Vec::new(),
            1 => vec![0.5 * (lo + hi)],
            _ => {
                // A continuous joint's ends are one angle: leave the upper one out.
                let steps = if continuous { count } else { count - 1 };
                // The ends exactly (lo + (hi − lo) · 1 may round past hi), the rest clamped.
                (0..count)
                    .map(|i| match i {
                        _ if i == steps => hi,
                        _ => (lo + (hi - lo) * i as f64 / steps as f64).clamp(lo, hi),
                    })
                    .collect()
            }
        }
    }

    /// Every solution of every row of `targets` (N × 16, row-major 4 × 4), ordered nearest
    /// that row's seed, in parallel on rayon's pool: row k's lock values are
    /// [`AnalyticIk::lock_values`] of its seed (`seeds`: N × dof, one seed per row, or dof: one
    /// for all), `value` and `sweep`; its solutions [`AnalyticIk::solve_swept`] over them,
    /// sorted by [`Solutions::sort_nearest`] (the values returned: those, then the refined
    /// ones), with the 2π representatives `reps` asks for (nearest: to the row's seed) — row
    /// k is [`AnalyticIk::solve_nearest`] on row k, whatever the thread count; a bad row is
    /// its own error and every other row is solved. An error only for buffers of the wrong
    /// length.
    #[allow(clippy::type_complexity)]
    pub fn solve_nearest_batch(
        &self,
        kin: &Kinematics,
        targets: &[f64],
        seeds: &[f64],
        value: Option<f64>,
        sweep: Option<usize>,
        reps: RepresentativeKind,
    ) -> Result<Vec<Result<(Solutions, Vec<f64>), SolveError>>, SolveError> {
        let rows = target_rows(targets)?;
        let n = kin.dof();
        let one_seed = seeds.len() == n;
        if !one_seed && seeds.len() != rows * n {
            return Err(SolveError::WrongLength {
                what: "seed values",
                expected: rows * n,
                got: seeds.len(),
                names: "one seed (dof) or one per target (N × dof)".into(),
            });
        }
        per_target(kin, targets, |ws, k, t| {
            let seed = if one_seed {
                seeds
            } else {
                &seeds[k * n..(k + 1) * n]
            };
            self.solve_nearest(kin, ws, t, seed, value, sweep, reps)
        })
    }

    /// Every solution of `target`, nearest to `seed` first, and the lock values used: the
    /// values [`AnalyticIk::lock_values`] gives for `seed`, `value` and `sweep`, then those
    /// the sweep's refinement added; the 2π representatives `reps` asks for (nearest: to
    /// `seed`). What a front end calls for one target (row k of
    /// [`AnalyticIk::solve_nearest_batch`] is this call).
    #[allow(clippy::too_many_arguments)]
    pub fn solve_nearest(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        seed: &[f64],
        value: Option<f64>,
        sweep: Option<usize>,
        reps: RepresentativeKind,
    ) -> Result<(Solutions, Vec<f64>), SolveError> {
        kin.check_q(seed)?;
        let mut values = self.lock_values(kin, seed, value, sweep)?;
        let mut out = Solutions::default();
        self.solve_postures(kin, ws, target, &values, reps.with_seed(seed), &mut out)?;
        out.sort_nearest(seed, None);
        values.extend_from_slice(&out.refined);
        Ok((out, values))
    }

    /// [`AnalyticIk::solve`] for every row of `targets` (N × 16, row-major 4 × 4), in parallel
    /// on rayon's pool (one workspace per worker). `lock_values`: the locked joint's value per
    /// row (None: 0, for an unlocked solver). Row k's result equals `solve` on row k whatever
    /// the thread count; a bad row (not finite, not rigid, a lock value outside the limits) is
    /// its own error and every other row is solved. An error only for buffers of the wrong
    /// length.
    pub fn solve_batch(
        &self,
        kin: &Kinematics,
        targets: &[f64],
        lock_values: Option<&[f64]>,
    ) -> Result<Vec<Result<Solutions, SolveError>>, SolveError> {
        self.solve_batch_postures(kin, targets, lock_values, Representatives::All)
    }

    /// [`AnalyticIk::solve_batch`] listing the 2π representatives `reps` asks for (row k's
    /// result equals [`AnalyticIk::solve_postures`] on row k).
    pub fn solve_batch_postures(
        &self,
        kin: &Kinematics,
        targets: &[f64],
        lock_values: Option<&[f64]>,
        reps: Representatives<'_>,
    ) -> Result<Vec<Result<Solutions, SolveError>>, SolveError> {
        let rows = target_rows(targets)?;
        if let Some(v) = lock_values {
            if v.len() != rows {
                return Err(SolveError::WrongLength {
                    what: "lock values (N)",
                    expected: rows,
                    got: v.len(),
                    names: "one per target".into(),
                });
            }
        }
        per_target(kin, targets, |ws, k, t| {
            let mut out = Solutions::default();
            let value = [lock_values.map_or(0.0, |v| v[k])];
            self.solve_postures(kin, ws, t, &value, reps, &mut out)?;
            Ok(out)
        })
    }

    /// Newton steps on the free joints, q ← q + J_b⁻¹ log(T(q)⁻¹ T_d) (body Jacobian, the
    /// locked column left out; by the arm angle every joint moves, the least-norm step J⁺ e on
    /// 7 columns), while the residual falls (at most 4, [`newton::polish`]): for the rare
    /// posture whose subproblems were ill-conditioned (two intersecting axes nearly parallel at
    /// the locked value, …). Returns the residual of `q`, which holds the best iterate (None if
    /// its Jacobian could not be computed).
    #[inline(never)]
    fn polish(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        q: &mut [f64],
        target: &Se3,
    ) -> Option<f64> {
        if self.arm.is_some() && q.len() == 7 {
            polish_columns(kin, ws, q, target, [0, 1, 2, 3, 4, 5, 6])
        } else {
            polish_columns(kin, ws, q, target, self.free)
        }
    }

    /// Appends the 2π shifts of posture `q` inside the limits that `reps` asks for
    /// (continuous joints: the wrapped angle; the locked joint: its value); false when there
    /// is none. Each joint's shifts are counted over its whole range (a joint limited to ±50
    /// rad has 16 of them), so the one nearest a reference is found however wide the limits;
    /// listing every combination (`All`) beyond [`MAX_REPRESENTATIVE_ROWS`] rows per posture
    /// is an error.
    #[allow(clippy::too_many_arguments)]
    fn expand(
        &self,
        kin: &Kinematics,
        q: &[f64],
        exact: bool,
        residual: f64,
        reps: Representatives<'_>,
        out: &mut Solutions,
    ) -> Result<bool, SolveError> {
        use std::f64::consts::TAU;
        let n = q.len();
        // Per joint: the first representative and how many there are.
        let mut first = [0.0; MAX_DOF];
        let mut count = [0.0f64; MAX_DOF];
        for i in 0..n {
            let (lo, hi) = (kin.lower[i], kin.upper[i]);
            let unbounded = !lo.is_finite() && !hi.is_finite();
            if kin.continuous[i] || unbounded || self.lock.is_some_and(|l| l.joint == i) {
                first[i] = q[i];
                count[i] = 1.0;
                continue;
            }
            // A bound at −∞ (a revolute joint limited above only): the four turns below hi;
            // at +∞ (limited below only): the four above lo.
            let (lo, hi) = match (lo.is_finite(), hi.is_finite()) {
                (false, _) => (hi - 4.0 * TAU, hi),
                (_, false) => (lo, lo + 4.0 * TAU),
                _ => (lo, hi),
            };
            let m0 = ((lo - 1e-12 - q[i]) / TAU).ceil();
            first[i] = q[i] + m0 * TAU;
            if first[i] > hi + 1e-12 {
                return Ok(false);
            }
            count[i] = ((hi + 1e-12 - first[i]) / TAU).floor() + 1.0;
            if !kin.lower[i].is_finite() || !kin.upper[i].is_finite() {
                count[i] = count[i].min(4.0);
            }
        }
        // One row: per joint, the shift nearest the reference (the seed, or the angle).
        let reference = match reps {
            Representatives::All => None,
            Representatives::Nearest(seed) => Some(seed),
            Representatives::One => Some(q),
        };
        if let Some(r) = reference {
            for i in 0..n {
                // The shift of q_i nearest r_i, counted from q_i (exact near the reference
                // however far the limits lie), kept among the shifts inside the limits.
                let last = first[i] + (count[i] - 1.0) * TAU;
                let x = if count[i] <= 1.0 {
                    first[i]
                } else {
                    let x = q[i] + ((r[i] - q[i]) / TAU).round() * TAU;
                    if x < first[i] {
                        first[i]
                    } else if x > last {
                        last
                    } else {
                        x
                    }
                };
                out.q.push(x.clamp(kin.lower[i], kin.upper[i]));
            }
            out.exact.push(exact);
            out.residual.push(residual);
            return Ok(true);
        }
        let rows: f64 = count[..n].iter().product();
        if rows > MAX_REPRESENTATIVE_ROWS as f64 {
            return Err(SolveError::InvalidInput(format!(
                "listing every 2π representative would give {rows:.0} rows per posture (more \
                 than {MAX_REPRESENTATIVE_ROWS}: the joint limits span many turns); ask for the \
                 one nearest the seed (representatives \"nearest\") or one per posture (\"none\")"
            )));
        }
        let mut digit = [0usize; MAX_DOF];
        loop {
            for i in 0..n {
                let x = first[i] + digit[i] as f64 * TAU;
                out.q.push(x.clamp(kin.lower[i], kin.upper[i]));
            }
            out.exact.push(exact);
            out.residual.push(residual);
            let mut i = n;
            loop {
                if i == 0 {
                    return Ok(true);
                }
                i -= 1;
                digit[i] += 1;
                if (digit[i] as f64) < count[i] {
                    break;
                }
                digit[i] = 0;
            }
        }
    }
}

/// The rows of an N × 16 target buffer; an error for a length that is not a multiple of 16.
fn target_rows(targets: &[f64]) -> Result<usize, SolveError> {
    if !targets.len().is_multiple_of(16) {
        return Err(SolveError::WrongLength {
            what: "target values (N × 16)",
            expected: targets.len() / 16 * 16,
            got: targets.len(),
            names: "a multiple of 16".into(),
        });
    }
    Ok(targets.len() / 16)
}

/// `f(ws, k, target k)` for every row k of `targets` (checked by [`target_rows`]; a row that is
/// not a finite rigid transform is its own error), in parallel on rayon's pool with one
/// workspace per worker; results in row order, whatever the thread count.
fn per_target<T: Send>(
    kin: &Kinematics,
    targets: &[f64],
    f: impl Fn(&mut Workspace, usize, &Se3) -> Result<T, SolveError> + Sync + Send,
) -> Result<Vec<Result<T, SolveError>>, SolveError> {
    use rayon::prelude::*;
    target_rows(targets)?;
    Ok(targets
        .par_chunks(16)
        .enumerate()
        .with_max_len(64)
        .map_init(
            || Workspace::new(kin),
            |ws, (k, row)| f(ws, k, &crate::batch::target_row(row)?),
        )
        .collect())
}

/// What to say of a chain without an analytic solver: its helical joint when it has one (the
/// analytic solvers take revolute joints only), else `otherwise`.
pub(crate) fn helical_or(kin: &Kinematics, otherwise: &str) -> String {
    match kin.helical() {
        Some((name, h)) => format!(
            "no analytic solver: numerical IK only (joint \"{name}\" is helical, pitch {h} m/rad; \
             the analytic solvers take revolute joints)"
        ),
        None => otherwise.to_string(),
    }
}

/// [`AnalyticIk::polish`] on the joints `columns` (the others held).
fn polish_columns<const M: usize>(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &mut [f64],
    target: &Se3,
    columns: [usize; M],
) -> Option<f64> {
    let n = q.len();
    let mut full = [0.0; MAX_DOF];
    full[..n].copy_from_slice(q);
    let mut x = columns.map(|j| q[j]);
    let budget = newton::Newton {
        steps: 4,
        floor: 0.0,
        dampings: &[],
    };
    let at = newton::polish(&mut x, budget, wrap, |x: &[f64; M]| {
        for (slot, &j) in columns.iter().enumerate() {
            full[j] = x[slot];
        }
        let pj =
            crate::jacobian::fk_jacobian(kin, ws, &full[..n], screwkit_lie::Frame::Body).ok()?;
        let err = pj.pose.inverse_compose(target).log();
        Some(newton::Linear {
            error: nalgebra::Vector6::new(err.w.x, err.w.y, err.w.z, err.v.x, err.v.y, err.v.z),
            jacobian: nalgebra::SMatrix::from_fn(|r, c| pj.jacobian[(r, columns[c])]),
            residual: pj.pose.max_abs_diff(target),
        })
    })?;
    for (slot, &j) in columns.iter().enumerate() {
        q[j] = x[slot];
    }
    Some(at.residual)
}
