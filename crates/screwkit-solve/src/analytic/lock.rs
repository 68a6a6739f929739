//! A 7R chain with one joint locked: the solver of the other six ([`AnalyticIk::locked`]), the
//! default choice of joint ([`AnalyticIk::auto`]), and the six lines at a locked value.

use super::*;

/// Random poses [`AnalyticIk::auto`] tries each closed-form lock on.
pub const AUTO_POSES: usize = 16;
/// Values of each lock's sweep there.
pub const AUTO_SWEEP: usize = 16;

/// A locked joint of a 7R chain.
#[derive(Debug, Clone, Copy)]
pub(super) struct Lock {
    pub(super) joint: usize,
    pub(super) line: AxisLine,
}

impl AnalyticIk {
    /// The solver of a 7R chain with joint `joint` (0-based) locked: the other six must form
    /// a family solved here whatever the locked value (checked at two generic values).
    pub fn locked(kin: &Kinematics, joint: usize) -> Result<Self, SolveError> {
        let c = classify(kin);
        if c.family != Family::Redundant7R {
            return Err(SolveError::InvalidInput(format!(
                "locking a joint is for 7R chains; this one is: {}",
                super::solver::helical_or(kin, c.family.describe())
            )));
        }
        if joint >= 7 {
            return Err(SolveError::InvalidInput(format!(
                "joint index {joint} out of range (the chain has 7 joints)"
            )));
        }
        let mut solver = Self {
            family: Family::Redundant7R,
            method: Method::WristParallel,
            reversed: false,
            lock: Some(Lock {
                joint,
                line: c.axes[joint],
            }),
            free: [0; 6],
            dof: 7,
            lines: c.axes,
            home: kin.home,
            fixed: None,
            shift: 0,
            arm: None,
            fallback_shift: std::sync::OnceLock::new(),
            interrupt: None,
            id: next_solver_id(),
        };
        for (slot, j) in (0..7).filter(|&j| j != joint).enumerate() {
            solver.free[slot] = j;
        }
        let l = kin.length_scale;
        let (a, _) = solver.locked_lines(0.7);
        let (b, _) = solver.locked_lines(2.1);
        if shoulder_and_wrist(&a, l) {
            return Err(SolveError::InvalidInput(format!(
                "locking {} (index {}) leaves a spherical shoulder and a spherical wrist: \
                 the other six joints still have a self-motion (lock another joint)",
                kin.names[joint], joint
            )));
        }
        // The method that solves the six free joints at every locked value: the one both
        // values take, else (a relation across the locked joint that holds at one value
        // only) the general 6R.
        let (family, method, reversed) = match (method_either(&a, l), method_either(&b, l)) {
            (Some(x), Some(y)) if x == y => x,
            (Some(_), Some(_)) => (Family::General6R, Method::General, false),
            _ => {
                return Err(SolveError::InvalidInput(format!(
                    "locking {} (index {}) does not leave a 6R chain that screwkit solves \
                     analytically ({})",
                    kin.names[joint],
                    joint,
                    classify_axes(a.to_vec(), true, l).family.describe()
                )))
            }
        };
        if method == Method::General {
            let (_, home) = solver.locked_lines(0.7);
            solver.shift = choose_shift(&a, home, reversed);
        }
        solver.method = method;
        solver.reversed = reversed;
        solver.family = family;
        Ok(solver)
    }

    /// The solver of any chain screwkit solves analytically: a 6R chain as
    /// [`AnalyticIk::new`]; a 7R chain with one joint locked, chosen among those whose locking
    /// leaves a special family's closed form (else among the general 6R locks), the most
    /// specialised family first, by how well it covers the self-motion: the one whose
    /// [`AUTO_SWEEP`]-value sweep reaches the most of [`AUTO_POSES`] random poses of the arm
    /// within the limits, counted per value — the chance that a lock at a random seed's value
    /// reaches a random pose — (deterministic: fixed configurations), ties to the later
    /// joint. (An elbow whose value the pose nearly fixes — the PR2's, reaching a pose over a
    /// few mrad — loses to the shoulder pan, which reaches it over most of its range.)
    pub fn auto(kin: &Kinematics) -> Result<Self, SolveError> {
        if kin.dof() != 7 {
            return Self::new(kin);
        }
        let mut last = None;
        let mut closed = Vec::new();
        for j in (0..7).rev() {
            match Self::locked(kin, j) {
                Ok(s) => closed.push(s),
                Err(e) => last = Some(e),
            }
        }
        // The special closed forms before the general 6R, the most specialised family first
        // (its kernel is the simplest, fastest one).
        let rank = |s: &AnalyticIk| (s.method == Method::General, s.family);
        if let Some(best) = closed.iter().map(rank).min() {
            closed.retain(|s| rank(s) == best);
        }
        if closed.len() > 1 {
            let poses = crate::sample::configurations(kin, AUTO_POSES, 0x5eed_a17c);
            let mut ws = Workspace::new(kin);
            let mut sols = Solutions::default();
            let mut reached = |s: &AnalyticIk| -> usize {
                let values = s.sweep(kin, AUTO_SWEEP);
                poses
                    .chunks(7)
                    .map(|q| {
                        let target = fk_unchecked(kin, q);
                        values
                            .iter()
                            .filter(|&&v| {
                                s.solve_postures(
                                    kin,
                                    &mut ws,
                                    &target,
                                    &[v],
                                    super::Representatives::One,
                                    &mut sols,
                                )
                                .is_ok()
                                    && sols.is_exact()
                            })
                            .count()
                    })
                    .sum()
            };
            let counts: Vec<usize> = closed.iter().map(&mut reached).collect();
            // The first (latest joint) of the most reaching.
            let best = (0..closed.len())
                .rev()
                .max_by_key(|&i| counts[i])
                .unwrap_or(0);
            return Ok(closed.swap_remove(best));
        }
        if let Some(s) = closed.pop() {
            return Ok(s);
        }
        Err(last.unwrap_or_else(|| SolveError::InvalidInput("no joint to lock".into())))
    }

    /// The six free lines and the home of the 6R chain with the lock at `value`.
    pub(super) fn locked_lines(&self, value: f64) -> ([AxisLine; 6], Se3) {
        let lock = self.lock.expect("a locked solver");
        let (kj, rj) = (lock.line.direction, lock.line.point);
        let e = rotation(&kj, value);
        let mv = |p: &V3| rj + e * (p - rj);
        let mut out = [lock.line; 6];
        for (slot, &j) in self.free.iter().enumerate() {
            let l = self.lines[j];
            out[slot] = if j > lock.joint {
                AxisLine {
                    direction: e * l.direction,
                    point: mv(&l.point),
                }
            } else {
                l
            };
        }
        let home = Se3::from_parts_unchecked(e * self.home.rotation(), mv(self.home.translation()));
        (out, home)
    }
}
