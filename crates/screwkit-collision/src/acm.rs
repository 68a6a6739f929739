//! The allowed-collision matrix generated as MoveIt's setup assistant does: which link pairs
//! need no collision check, with the reason, for an SRDF ([`screwkit_model::srdf::write`]).
//!
//! Over every pair of links that both have collision shapes, in this order of precedence:
//! 1. **Adjacent**: joined by a joint (through links without shapes, as MoveIt counts them);
//! 2. **Default**: in collision at the default configuration (0 for every joint, clamped into
//!    its limits; the floating base at the origin);
//! 3. **Always**: in collision in at least [`Generate::always`] of the samples;
//! 4. **Never** (only when [`Generate::never`]): in collision in none of the samples. A pair
//!    that never collided in N samples may still collide: this one is a bet, so it is asked
//!    for, and flagged by its reason.
//!
//! The samples are random configurations within the limits, sample k drawn from
//! `SplitMix64(row_seed(seed, k))`: the same seed gives the same matrix whatever the thread
//! count.

use std::collections::HashMap;

use rayon::prelude::*;
use screwkit_model::srdf::DisabledPair;
use screwkit_solve::TreeKinematics;

use crate::model::{Attach, CollisionError, CollisionModel, Options};
use crate::query::{collisions, CollisionWorkspace};

/// How the matrix is generated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Generate {
    /// Random configurations sampled (MoveIt's default density: 10,000).
    pub samples: usize,
    /// The sampling seed.
    pub seed: u64,
    /// The fraction of samples in collision from which a pair is disabled as `Always`.
    pub always: f64,
    /// Also disable the pairs that never collided (`Never`).
    pub never: bool,
}

impl Default for Generate {
    fn default() -> Self {
        Generate {
            samples: 10_000,
            seed: 0,
            always: 0.95,
            never: false,
        }
    }
}

/// The disabled pairs of `kin`'s collision shapes (module documentation), sorted by link names.
pub fn generate(
    kin: &TreeKinematics,
    mesh_mode: crate::MeshMode,
    g: &Generate,
) -> Result<Vec<DisabledPair>, CollisionError> {
    let model = CollisionModel::new(
        kin,
        Options {
            mesh_mode,
            keep_adjacent: true,
            all_pairs: true,
        },
    )?;
    let links = model.links();
    // Link pairs (low, high) of the model's shape pairs, and each shape pair's link pair.
    let link_of = |o: usize| match model.objects()[o].attach {
        Attach::Link(l) => l,
        Attach::World => usize::MAX,
    };
    let mut index: HashMap<(usize, usize), usize> = HashMap::new();
    let mut link_pairs: Vec<(usize, usize)> = Vec::new();
    let pair_link: Vec<usize> = model
        .pairs()
        .map(|(a, b)| {
            let (la, lb) = (link_of(a), link_of(b));
            let key = (la.min(lb), la.max(lb));
            *index.entry(key).or_insert_with(|| {
                link_pairs.push(key);
                link_pairs.len() - 1
            })
        })
        .collect();
    let tree = &kin.model().tree;
    let has_shape: Vec<bool> = (0..links.len())
        .map(|l| (0..model.objects().len()).any(|o| link_of(o) == l))
        .collect();
    // Adjacent: each link with shapes and its nearest ancestor with shapes.
    let mut reason: Vec<Option<&'static str>> = vec![None; link_pairs.len()];
    for l in (0..links.len()).filter(|&l| has_shape[l]) {
        let mut up = l;
        while let Some(j) = tree.parent_joint[up] {
            up = tree.joints[j].parent;
            if has_shape[up] {
                if let Some(&k) = index.get(&(l.min(up), l.max(up))) {
                    reason[k] = Some("Adjacent");
                }
                break;
            }
        }
    }
    // Which link pairs collide at q.
    let colliding = |ws: &mut CollisionWorkspace, q: &[f64], hits: &mut Vec<usize>| {
        collisions(&model, ws, kin, q, hits)?;
        let mut out: Vec<usize> = hits.iter().map(|&p| pair_link[p]).collect();
        out.sort_unstable();
        out.dedup();
        Ok::<_, CollisionError>(out)
    };
    let mut ws = CollisionWorkspace::new(kin, &model);
    let mut hits = Vec::new();
    let default = default_configuration(kin);
    for k in colliding(&mut ws, &default, &mut hits)? {
        reason[k].get_or_insert("Default");
    }
    let counts = (0..g.samples)
        .into_par_iter()
        .map_init(
            || (CollisionWorkspace::new(kin, &model), Vec::new()),
            |(ws, hits), s| {
                let mut rng =
                    screwkit_solve::sample::SplitMix64(screwkit_solve::batch::row_seed(g.seed, s));
                let q = screwkit_solve::tree::configuration::random(kin, &mut rng);
                colliding(ws, &q, hits)
            },
        )
        .try_fold(
            || vec![0usize; link_pairs.len()],
            |mut acc, hit| {
                for k in hit? {
                    acc[k] += 1;
                }
                Ok::<_, CollisionError>(acc)
            },
        )
        .try_reduce(
            || vec![0usize; link_pairs.len()],
            |mut a, b| {
                for (x, y) in a.iter_mut().zip(b) {
                    *x += y;
                }
                Ok(a)
            },
        )?;
    if g.samples > 0 {
        for (k, &c) in counts.iter().enumerate() {
            if c as f64 >= g.always * g.samples as f64 {
                reason[k].get_or_insert("Always");
            } else if c == 0 && g.never {
                reason[k].get_or_insert("Never");
            }
        }
    }
    let mut out: Vec<DisabledPair> = link_pairs
        .iter()
        .zip(&reason)
        .filter_map(|(&(a, b), r)| {
            let (n1, n2) = (links[a].clone(), links[b].clone());
            let (link1, link2) = if n1 <= n2 { (n1, n2) } else { (n2, n1) };
            r.map(|r| DisabledPair {
                link1,
                link2,
                reason: r.to_string(),
            })
        })
        .collect();
    out.sort();
    Ok(out)
}

/// 0 for every joint variable clamped into its limits; the floating base at the origin.
fn default_configuration(kin: &TreeKinematics) -> Vec<f64> {
    let mut q = screwkit_solve::tree::configuration::neutral(kin);
    let (lower, upper) = (kin.lower(), kin.upper());
    let start = if kin.floating_base() { 7 } else { 0 };
    for k in start..q.len() {
        // (max then min, not clamp: never a panic on odd limits.)
        q[k] = q[k].max(lower[k]).min(upper[k]);
    }
    q
}
