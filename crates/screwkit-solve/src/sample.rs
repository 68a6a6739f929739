//! Random configurations within the joint limits, from a seeded generator: the IK restarts,
//! the benchmark targets, dataset generation. Reproducible: the same seed gives the same
//! configurations on every machine.

use crate::kinematics::Kinematics;

/// SplitMix64 (Steele, Lea & Flood 2014): a small, well-distributed, seedable generator.
#[derive(Debug, Clone)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The interval a variable is sampled from: its limits, or [−π, π] when unbounded (continuous
/// joints).
#[inline]
pub(crate) fn range(lower: f64, upper: f64) -> (f64, f64) {
    if lower.is_finite() && upper.is_finite() {
        (lower, upper)
    } else {
        (-std::f64::consts::PI, std::f64::consts::PI)
    }
}

/// Fills `q` (one value per variable) uniformly within the limits ([−π, π] for unbounded
/// variables). Panics if `q` is shorter than the DoF.
pub fn configuration_into(kin: &Kinematics, rng: &mut SplitMix64, q: &mut [f64]) {
    for (k, x) in q[..kin.dof()].iter_mut().enumerate() {
        let (l, u) = range(kin.lower[k], kin.upper[k]);
        *x = l + (u - l) * rng.uniform();
    }
}

/// `count` configurations uniform within the limits ([−π, π] for unbounded variables) drawn
/// from `seed`, as flat row-major rows of `dof` values.
pub fn configurations(kin: &Kinematics, count: usize, seed: u64) -> Vec<f64> {
    let mut rng = SplitMix64(seed);
    let n = kin.dof();
    let mut qs = vec![0.0; count * n];
    if n > 0 {
        for row in qs.chunks_mut(n) {
            configuration_into(kin, &mut rng, row);
        }
    }
    qs
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every sample is within the limits, and an unbounded (continuous) variable is sampled in
    /// [−π, π] — never `lower + (upper − lower) u`, which is NaN for (−∞, ∞).
    #[test]
    fn samples_are_finite_and_within_limits() {
        for (file, kin) in crate::test_chains() {
            let n = kin.dof();
            let qs = configurations(&kin, 2000, 5);
            assert_eq!(qs.len(), 2000 * n);
            for q in qs.chunks(n) {
                assert!(q.iter().all(|x| x.is_finite()), "{file}: {q:?}");
                assert!(kin.within_limits(q, 0.0), "{file}: {q:?}");
                for (k, x) in q.iter().enumerate() {
                    if !kin.lower()[k].is_finite() {
                        assert!(x.abs() <= std::f64::consts::PI, "{file}: {x}");
                    }
                }
            }
            assert_eq!(qs, configurations(&kin, 2000, 5), "reproducible");
        }
        let tricky = crate::test_chains().remove(4).1;
        assert!(
            tricky.lower().iter().any(|l| l.is_infinite()),
            "a continuous joint is covered"
        );
    }
}
