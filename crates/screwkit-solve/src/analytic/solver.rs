//! The analytic solver prepared once per chain ([`AnalyticIk`]: the model side) and its calls:
//! the postures kernel, solutions within the limits, sweeps, batches.

use super::*;

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
}

/// The most lock values one sweep may have ([`AnalyticIk::lock_values`]).
pub const MAX_SWEEP: usize = 100_000;

impl AnalyticIk {
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
        let fail = || {
            SolveError::InvalidInput(format!(
                "no analytic solver for this chain: {}",
                c.family.describe()
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
        let (method, reversed) = method_either(&c.axes, kin.length_scale).ok_or_else(fail)?;
        if method == Method::Search56 {
            search_guard(&c.axes, reversed, kin.length_scale)?;
        }
        let lines: [AxisLine; 6] = c.axes.clone().try_into().map_err(|_| fail())?;
        Ok(Self {
            family: c.family,
            method,
            reversed,
            lock: None,
            free: [0, 1, 2, 3, 4, 5],
            dof: 6,
            fixed: Some(Prepared::new(method, &lines, kin.home, reversed)),
            lines: c.axes,
            home: kin.home,
        })
    }

    /// True when every solution comes in closed form; false for the sampled 1D searches
    /// (1–3 ms per pose, roots may be missed where the error only touches zero).
    pub fn closed_form(&self) -> bool {
        row(self.method).closed_form
    }

    /// How it solves, in words (the row of the decomposition table).
    pub fn words(&self) -> &'static str {
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
        let prepared;
        let p = match &self.fixed {
            Some(p) => p,
            None => {
                let (lines, home) = self.locked_lines(lock_value);
                prepared = Prepared::new(self.method, &lines, home, self.reversed);
                &prepared
            }
        };
        let g = if self.reversed {
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
                q[j] = wrap(if self.reversed { t[5 - slot] } else { t[slot] });
            }
            if let Some(l) = self.lock {
                q[l.joint] = lock_value;
            }
            out.push(q, exact);
        };
        (row(self.method).kernel)(p, &g, &mut singular, &mut emit);
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
    pub fn solve_swept(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        target: &Se3,
        lock_values: &[f64],
        out: &mut Solutions,
    ) -> Result<(), SolveError> {
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
        let mut raw = Postures::default();
        // Exact postures are preferred over least-squares ones across all the values.
        let mut any_exact = false;
        if lock_values.len() > 1 {
            for &v in lock_values {
                self.postures(target, v, &mut raw);
                any_exact |= raw.as_slice().iter().any(|p| p.exact);
            }
        }
        let n = self.dof;
        for &v in lock_values {
            self.postures(target, v, &mut raw);
            out.singular |= raw.singular;
            if lock_values.len() == 1 {
                any_exact = raw.as_slice().iter().any(|p| p.exact);
            }
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
                    residual = self.polish(kin, ws, &mut q[..n], target, residual);
                }
                if self.expand(kin, &q[..n], p.exact, residual, out) {
                    distinct[count] = p.q;
                    count += 1;
                }
            }
            out.branches += count;
        }
        Ok(())
    }

    /// The values of the locked joint a caller means: `sweep` values evenly spaced over its
    /// limits ([`AnalyticIk::sweep`]), or `value`, or else the seed's value of that joint; \[0\]
    /// without a lock (where a value or a sweep is an error, as are both at once).
    pub fn lock_values(
        &self,
        kin: &Kinematics,
        seed: &[f64],
        value: Option<f64>,
        sweep: Option<usize>,
    ) -> Result<Vec<f64>, SolveError> {
        let Some(l) = self.lock else {
            if value.is_some() || sweep.is_some() {
                return Err(SolveError::InvalidInput(
                    "a lock value or a sweep is for a 7R chain with a locked joint".into(),
                ));
            }
            return Ok(vec![0.0]);
        };
        match (value, sweep) {
            (Some(_), Some(_)) => Err(SolveError::InvalidInput(
                "a lock value and a sweep exclude each other".into(),
            )),
            (None, Some(0)) => Err(SolveError::InvalidInput(
                "a sweep needs at least one value".into(),
            )),
            (None, Some(n)) if n > MAX_SWEEP => Err(SolveError::InvalidInput(format!(
                "a sweep of {n} values is more than {MAX_SWEEP} (each value gives up to 8 postures and their 2π shifts)"
            ))),
            (None, Some(n)) => Ok(self.sweep(kin, n)),
            (Some(v), None) => Ok(vec![v]),
            (None, None) => {
                kin.check_q(seed)?;
                Ok(vec![seed[l.joint]])
            }
        }
    }

    /// `count` values of the locked joint evenly spaced over its limits, ends included
    /// ([−π, π) for a continuous joint); empty without a lock.
    pub fn sweep(&self, kin: &Kinematics, count: usize) -> Vec<f64> {
        let Some(l) = self.lock else {
            return Vec::new();
        };
        let (mut lo, mut hi) = (kin.lower[l.joint], kin.upper[l.joint]);
        let continuous = !(lo.is_finite() && hi.is_finite());
        if continuous {
            (lo, hi) = (-std::f64::consts::PI, std::f64::consts::PI);
        }
        match count {
            0 => Vec::new(),
            1 => vec![0.5 * (lo + hi)],
            _ => {
                // A continuous joint's ends are one angle: leave the upper one out.
                let steps = if continuous { count } else { count - 1 };
                (0..count)
                    .map(|i| lo + (hi - lo) * i as f64 / steps as f64)
                    .collect()
            }
        }
    }

    /// Every solution of every row of `targets` (N × 16, row-major 4 × 4), ordered nearest
    /// that row's seed, in parallel on rayon's pool: row k's lock values are
    /// [`AnalyticIk::lock_values`] of its seed (`seeds`: N × dof, one seed per row, or dof: one
    /// for all), `value` and `sweep`; its solutions [`AnalyticIk::solve_swept`] over them,
    /// sorted by [`Solutions::sort_nearest`]. Row k's result (solutions and lock values) equals
    /// those calls on row k whatever the thread count; a bad row is its own error and every
    /// other row is solved. An error only for buffers of the wrong length.
    #[allow(clippy::type_complexity)]
    pub fn solve_nearest_batch(
        &self,
        kin: &Kinematics,
        targets: &[f64],
        seeds: &[f64],
        value: Option<f64>,
        sweep: Option<usize>,
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
            kin.check_q(seed)?;
            let values = self.lock_values(kin, seed, value, sweep)?;
            let mut out = Solutions::default();
            self.solve_swept(kin, ws, t, &values, &mut out)?;
            out.sort_nearest(seed, None);
            Ok((out, values))
        })
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
            self.solve(kin, ws, t, lock_values.map_or(0.0, |v| v[k]), &mut out)?;
            Ok(out)
        })
    }

    /// Newton steps on the free joints, q ← q + J_b⁻¹ log(T(q)⁻¹ T_d) (body Jacobian, the
    /// locked column left out), while the residual falls (at most 4): for the rare posture
    /// whose subproblems were ill-conditioned (two intersecting axes nearly parallel at the
    /// locked value, …). Returns the residual of `q`, which holds the best iterate.
    fn polish(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        q: &mut [f64],
        target: &Se3,
        mut residual: f64,
    ) -> f64 {
        let mut trial = [0.0; MAX_DOF];
        for _ in 0..4 {
            let Ok(pj) = crate::jacobian::fk_jacobian(kin, ws, q, screwkit_lie::Frame::Body) else {
                break;
            };
            let err = pj.pose.inverse_compose(target).log();
            let mut j6 = nalgebra::Matrix6::zeros();
            for (slot, &j) in self.free.iter().enumerate() {
                j6.set_column(slot, &pj.jacobian.column(j));
            }
            let rhs = nalgebra::Vector6::new(err.w.x, err.w.y, err.w.z, err.v.x, err.v.y, err.v.z);
            let Some(step) = j6.lu().solve(&rhs) else {
                break;
            };
            trial[..q.len()].copy_from_slice(q);
            for (slot, &j) in self.free.iter().enumerate() {
                trial[j] = wrap(trial[j] + step[slot]);
            }
            let r = fk_unchecked(kin, &trial[..q.len()]).max_abs_diff(target);
            if r.partial_cmp(&residual) != Some(std::cmp::Ordering::Less) {
                break;
            }
            q.copy_from_slice(&trial[..q.len()]);
            residual = r;
        }
        residual
    }

    /// Appends every 2π shift of posture `q` inside the limits (continuous joints: the
    /// wrapped angle; the locked joint: its value); false when there is none.
    fn expand(
        &self,
        kin: &Kinematics,
        q: &[f64],
        exact: bool,
        residual: f64,
        out: &mut Solutions,
    ) -> bool {
        use std::f64::consts::TAU;
        let n = q.len();
        // Per joint: the first representative and how many there are (at most 4).
        let mut first = [0.0; MAX_DOF];
        let mut count = [0usize; MAX_DOF];
        for i in 0..n {
            let (lo, hi) = (kin.lower[i], kin.upper[i]);
            if kin.continuous[i] || self.lock.is_some_and(|l| l.joint == i) {
                first[i] = q[i];
                count[i] = 1;
                continue;
            }
            let m0 = ((lo - 1e-12 - q[i]) / TAU).ceil();
            let mut c = 0;
            while c < 4 && q[i] + (m0 + c as f64) * TAU <= hi + 1e-12 {
                c += 1;
            }
            if c == 0 {
                return false;
            }
            first[i] = q[i] + m0 * TAU;
            count[i] = c;
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
                    return true;
                }
                i -= 1;
                digit[i] += 1;
                if digit[i] < count[i] {
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
