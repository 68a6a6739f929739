//! What the solver returns: the postures of one pose ([`Postures`], allocation-free) and the
//! solutions within the limits ([`Solutions`]).

use super::*;

/// One posture: the chain's variables (the first `dof` of `q`) and whether every subproblem
/// on the way was exact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Posture {
    /// The joint values, angles in (−π, π] (a locked joint: its value).
    pub q: [f64; MAX_DOF],
    /// False for a least-squares posture (the pose is out of reach on this branch).
    pub exact: bool,
}

/// The raw output of [`AnalyticIk::postures`]: up to [`MAX_POSTURES`] postures, inline.
#[derive(Debug, Clone)]
pub struct Postures {
    pub(super) items: [Posture; MAX_POSTURES],
    pub(super) len: usize,
    pub(super) dof: usize,
    /// A singular or near-singular configuration was met: an angle left free (set to 0) or
    /// a double root (elbow stretched, wrist center on axis 1, axes 4 and 6 aligned).
    pub singular: bool,
}

impl Default for Postures {
    #[inline]
    fn default() -> Self {
        Self {
            items: [Posture {
                q: [0.0; MAX_DOF],
                exact: false,
            }; MAX_POSTURES],
            len: 0,
            dof: 0,
            singular: false,
        }
    }
}

impl Postures {
    /// The postures found.
    #[inline]
    pub fn as_slice(&self) -> &[Posture] {
        &self.items[..self.len]
    }

    /// The number of variables of each posture.
    #[inline]
    pub fn dof(&self) -> usize {
        self.dof
    }

    #[inline]
    pub(super) fn push(&mut self, q: [f64; MAX_DOF], exact: bool) {
        if self.len < MAX_POSTURES {
            self.items[self.len] = Posture { q, exact };
            self.len += 1;
        }
    }
}

/// Which 2π representatives of each posture a solve lists (a joint whose limits are wider
/// than 2π reaches a posture at several angles: a UR5 with ±2π limits has up to 2⁶ rows per
/// posture). The front ends' words: `all`, `nearest`, `none`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Representatives<'a> {
    /// Every 2π shift of every joint inside the limits (each combination a row).
    All,
    /// One row per posture: per joint, the shift inside the limits nearest to this seed's
    /// value (the posture as the arm at the seed would move to it).
    Nearest(&'a [f64]),
    /// One row per posture: per joint, its angle in (−π, π] when inside the limits, else the
    /// shift inside them nearest to it (`none`: no representatives added).
    One,
}

/// [`Representatives`] without the seed, for calls that take one seed per target
/// ([`AnalyticIk::solve_nearest_batch`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RepresentativeKind {
    /// [`Representatives::All`].
    #[default]
    All,
    /// [`Representatives::Nearest`] to each target's seed.
    Nearest,
    /// [`Representatives::One`].
    One,
}

impl RepresentativeKind {
    /// The choice with its seed.
    pub fn with_seed(self, seed: &[f64]) -> Representatives<'_> {
        match self {
            RepresentativeKind::All => Representatives::All,
            RepresentativeKind::Nearest => Representatives::Nearest(seed),
            RepresentativeKind::One => Representatives::One,
        }
    }
}

/// Every solution of one pose, nearest-first after [`Solutions::sort_nearest`]. Storage is
/// flat and reused: [`AnalyticIk::solve`] refills it without allocating once it has grown.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Solutions {
    pub(super) dof: usize,
    pub(super) q: Vec<f64>,
    pub(super) exact: Vec<bool>,
    pub(super) residual: Vec<f64>,
    /// True when a singular or near-singular configuration was met ([`Postures::singular`]):
    /// an angle may have been left free (set to 0), so other solutions exist too.
    pub singular: bool,
    /// How many distinct postures (modulo 2π) the solutions come from: elbow up/down, wrist
    /// flip, shoulder left/right — at most 8. The solutions list every 2π shift of each that
    /// the limits allow (a UR5 with ±2π limits has up to 8 × 2⁶).
    pub branches: usize,
    /// The lock values a sweep's refinement added ([`AnalyticIk::solve_swept`]): where the
    /// pose is reached although no sampled value reaches it; empty without a sweep.
    pub refined: Vec<f64>,
}

impl Solutions {
    /// The number of solutions.
    #[inline]
    pub fn len(&self) -> usize {
        self.exact.len()
    }

    /// True when there is none (every posture is outside the joint limits).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.exact.is_empty()
    }

    /// Solution i's joint values.
    #[inline]
    pub fn q(&self, i: usize) -> &[f64] {
        &self.q[i * self.dof..(i + 1) * self.dof]
    }

    /// The solutions' joint values, in order.
    #[inline]
    pub fn iter(&self) -> impl Iterator<Item = &[f64]> + '_ {
        (0..self.len()).map(|i| self.q(i))
    }

    /// Whether solution i is exact (false: least squares, the pose is out of reach).
    #[inline]
    pub fn exact(&self, i: usize) -> bool {
        self.exact[i]
    }

    /// Solution i's residual: the largest entry of |T(q) − T_d| (rotation entries and
    /// translations in the file's length unit), by forward kinematics.
    #[inline]
    pub fn residual(&self, i: usize) -> f64 {
        self.residual[i]
    }

    /// True when there are solutions and all are exact (they are either all exact or all
    /// least squares: exact ones are preferred).
    #[inline]
    pub fn is_exact(&self) -> bool {
        !self.exact.is_empty() && self.exact.iter().all(|&e| e)
    }

    /// The solutions as owned rows.
    #[inline]
    pub fn to_vecs(&self) -> Vec<Vec<f64>> {
        self.iter().map(<[f64]>::to_vec).collect()
    }

    /// The weighted joint-space distance Σ w_j (q_j − seed_j)² from solution i to `seed`
    /// (w = 1 when `weights` is None).
    #[inline]
    pub fn distance(&self, i: usize, seed: &[f64], weights: Option<&[f64]>) -> f64 {
        self.q(i)
            .iter()
            .zip(seed)
            .enumerate()
            .map(|(j, (a, b))| weights.map_or(1.0, |w| w[j]) * (a - b) * (a - b))
            .sum()
    }

    /// The index of the solution nearest to `seed` ([`Solutions::distance`]), if any.
    #[inline]
    pub fn nearest(&self, seed: &[f64], weights: Option<&[f64]>) -> Option<usize> {
        (0..self.len()).min_by(|&a, &b| {
            self.distance(a, seed, weights)
                .total_cmp(&self.distance(b, seed, weights))
        })
    }

    /// Orders the solutions nearest to `seed` first ([`Solutions::distance`]): the first is
    /// the one that moves the arm least from where it is (branch-stable tracking). Ties keep
    /// their order.
    #[inline]
    pub fn sort_nearest(&mut self, seed: &[f64], weights: Option<&[f64]>) {
        let mut order: Vec<usize> = (0..self.len()).collect();
        let d: Vec<f64> = order
            .iter()
            .map(|&i| self.distance(i, seed, weights))
            .collect();
        order.sort_by(|&a, &b| d[a].total_cmp(&d[b]));
        let n = self.dof;
        let q: Vec<f64> = order
            .iter()
            .flat_map(|&i| self.q[i * n..(i + 1) * n].iter().copied())
            .collect();
        self.q = q;
        self.exact = order.iter().map(|&i| self.exact[i]).collect();
        self.residual = order.iter().map(|&i| self.residual[i]).collect();
    }

    #[inline]
    pub(super) fn clear(&mut self, dof: usize) {
        self.dof = dof;
        self.q.clear();
        self.exact.clear();
        self.residual.clear();
        self.singular = false;
        self.branches = 0;
        self.refined.clear();
    }
}
