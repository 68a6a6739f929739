//! Test helpers: bundled asset paths, a minimal product-of-exponentials loop, random joints.

#![allow(dead_code)]

use screwkit_lie::Se3;
use screwkit_model::reference::fk_by_composition;
use screwkit_model::{Chain, Tree};

/// Path of a bundled URDF.
pub fn asset(name: &str) -> String {
    format!("{}/../../assets/urdf/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// θ_j = multiplier · q[variable] + offset for every chain joint.
pub fn joint_positions(chain: &Chain, q: &[f64]) -> Vec<f64> {
    chain
        .joints
        .iter()
        .map(|j| j.multiplier * q[j.variable] + j.offset)
        .collect()
}

/// Space form T = e^[S₁]θ₁ ⋯ e^[Sₙ]θₙ M (the minimal loop; the solver crate has the fast one).
pub fn poe_space(chain: &Chain, q: &[f64]) -> Se3 {
    let theta = joint_positions(chain, q);
    let mut t = Se3::identity();
    for (j, th) in chain.joints.iter().zip(theta) {
        t = t * Se3::exp_screw(&j.s_space, th);
    }
    t * chain.home
}

/// Body form T = M e^[B₁]θ₁ ⋯ e^[Bₙ]θₙ.
pub fn poe_body(chain: &Chain, q: &[f64]) -> Se3 {
    let theta = joint_positions(chain, q);
    let mut t = chain.home;
    for (j, th) in chain.joints.iter().zip(theta) {
        t = t * Se3::exp_screw(&j.b_body, th);
    }
    t
}

/// A deterministic xorshift generator (tests must be reproducible).
pub struct Rng(pub u64);

impl Rng {
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform within each variable's limits ([−π, π] where unbounded).
    pub fn config(&mut self, chain: &Chain) -> Vec<f64> {
        chain
            .variables
            .iter()
            .map(|v| {
                let (lo, hi) = if v.lower.is_finite() && v.upper.is_finite() {
                    (v.lower, v.upper)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                };
                lo + (hi - lo) * self.uniform()
            })
            .collect()
    }
}

/// The oracle check: for `count` random configurations, the space and body POE forms equal
/// direct composition of the URDF joint transforms to 1e-12.
pub fn assert_poe_matches_composition(
    tree: &Tree,
    chain: &Chain,
    rng: &mut Rng,
    count: usize,
    label: &str,
) {
    for _ in 0..count {
        let q = rng.config(chain);
        let want = fk_by_composition(tree, chain, &q).unwrap();
        let space = poe_space(chain, &q).to_homogeneous();
        let body = poe_body(chain, &q).to_homogeneous();
        assert!(
            (space - want).amax() < 1e-12,
            "{label}: space form {:e} at {q:?}",
            (space - want).amax()
        );
        assert!(
            (body - want).amax() < 1e-12,
            "{label}: body form {:e} at {q:?}",
            (body - want).amax()
        );
    }
}
