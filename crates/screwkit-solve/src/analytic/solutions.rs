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

    /// Keeps the solutions whose `keep` entry is true, in order (a front end's filter: those
    /// free of collisions). `branches` still counts the postures found before.
    pub fn retain(&mut self, keep: &[bool]) {
        let n = self.dof;
        let mut at = 0;
        for (i, &k) in keep.iter().enumerate().take(self.len()) {
            if k {
                self.q.copy_within(i * n..(i + 1) * n, at * n);
                self.exact[at] = self.exact[i];
                self.residual[at] = self.residual[i];
                at += 1;
            }
        }
        self.q.truncate(at * n);
        self.exact.truncate(at);
        self.residual.truncate(at);
    }

    /// Orders the solutions nearest to `seed` first ([`Solutions::distance`]): the first is
    /// the one that moves the arm least from where it is (branch-stable tracking). Ties keep
    /// their order. Up to [`MAX_POSTURES`] · 2 solutions (every posture, one row each: the
    /// single call's case) are sorted in place by insertion, without allocating; more by an
    /// index sort. Both are stable, so the order is the same.
    #[inline]
    pub fn sort_nearest(&mut self, seed: &[f64], weights: Option<&[f64]>) {
        const SMALL: usize = 2 * MAX_POSTURES;
        let len = self.len();
        if len > SMALL {
            return self.sort_nearest_by_index(seed, weights);
        }
        let mut d = [0.0; SMALL];
        for (i, x) in d[..len].iter_mut().enumerate() {
            *x = self.distance(i, seed, weights);
        }
        let n = self.dof;
        for i in 1..len {
            let mut j = i;
            while j > 0 && d[j - 1].total_cmp(&d[j]).is_gt() {
                d.swap(j - 1, j);
                self.exact.swap(j - 1, j);
                self.residual.swap(j - 1, j);
                let (a, b) = self.q.split_at_mut(j * n);
                a[(j - 1) * n..].swap_with_slice(&mut b[..n]);
                j -= 1;
            }
        }
    }

    /// [`Solutions::sort_nearest`] by sorting an index (any count).
    fn sort_nearest_by_index(&mut self, seed: &[f64], weights: Option<&[f64]>) {
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
        // Room for one row per posture at once (a single call's case: no regrowth).
        self.q.reserve(MAX_POSTURES * dof);
        self.exact.reserve(MAX_POSTURES);
        self.residual.reserve(MAX_POSTURES);
        self.q.clear();
        self.exact.clear();
        self.residual.clear();
        self.singular = false;
        self.branches = 0;
        self.refined.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `count` solutions of `dof` joints, values from a small set so that distances tie.
    fn solutions(count: usize, dof: usize, seed: u64) -> Solutions {
        let mut x = seed;
        let mut next = || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((x >> 33) % 5) as f64 - 2.0
        };
        let mut s = Solutions::default();
        s.clear(dof);
        for k in 0..count {
            s.q.extend((0..dof).map(|_| next()));
            s.exact.push(k % 3 != 0);
            s.residual.push(k as f64);
        }
        s
    }

    #[test]
    fn the_in_place_sort_equals_the_index_sort() {
        for count in 0..=2 * MAX_POSTURES {
            for (case, dof) in [(1u64, 1usize), (2, 6), (3, 7)] {
                let seed: Vec<f64> = (0..dof).map(|i| 0.3 * i as f64 - 0.5).collect();
                let weights: Vec<f64> = (0..dof).map(|i| 1.0 + i as f64).collect();
                for w in [None, Some(&weights[..])] {
                    let mut a = solutions(count, dof, case * 100 + count as u64);
                    let mut b = a.clone();
                    a.sort_nearest(&seed, w);
                    b.sort_nearest_by_index(&seed, w);
                    assert_eq!(a.q, b.q, "{count} × {dof}");
                    assert_eq!(a.exact, b.exact);
                    // The residuals are the original indices: ties kept their order.
                    assert_eq!(a.residual, b.residual);
                    let d: Vec<f64> = (0..a.len()).map(|i| a.distance(i, &seed, w)).collect();
                    assert!(d.windows(2).all(|p| p[0] <= p[1]), "{d:?}");
                }
            }
        }
    }
}
