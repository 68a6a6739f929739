//! Test helpers: bundled asset paths, the oracle check of the screws against the URDF.

#![allow(dead_code)]

use screwkit_model::{Chain, Tree};
pub use screwkit_testkit::reference::{fk_by_composition, poe_body, poe_space};
pub use screwkit_testkit::Sampler;

/// Path of a bundled URDF.
pub fn asset(name: &str) -> String {
    screwkit_testkit::bundled(name)
}

/// The oracle check: for `count` random configurations, the space and body POE forms equal
/// direct composition of the URDF joint transforms to 1e-12.
pub fn assert_poe_matches_composition(
    tree: &Tree,
    chain: &Chain,
    rng: &mut Sampler,
    count: usize,
    label: &str,
) {
    for _ in 0..count {
        let q = rng.chain_config(chain);
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
