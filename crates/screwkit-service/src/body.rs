//! The robot's body for the front ends ([`screwkit_collision`]): the collision model built one
//! way ([`model`]: mesh mode, SRDF), the configuration a body query takes ([`tree_q`]: a chain
//! robot's joint values placed in its whole tree), and the JSON report of `screwkit collide`.

use std::borrow::Cow;

use screwkit_collision::{CollisionModel, MeshMode, Options, PairDistance};
use screwkit_solve::TreeKinematics;
use serde::Serialize;

use crate::error::{Error, Result};
use crate::io::json::number;
use crate::load::Robot;
use crate::query::Space;
use crate::words::Meshes;

impl From<Meshes> for MeshMode {
    fn from(m: Meshes) -> MeshMode {
        match m {
            Meshes::Exact => MeshMode::Exact,
            Meshes::Convex => MeshMode::ConvexHull,
        }
    }
}

/// How a robot's meshes are read when a front end is not told: exactly (their triangles) for
/// URDF, as convex hulls for MJCF (MuJoCo's rule: its collisions see a mesh's hull).
pub fn default_meshes(tree: &screwkit_model::Tree) -> Meshes {
    if tree.contact_rules.is_some() {
        Meshes::Convex
    } else {
        Meshes::Exact
    }
}

/// The SRDF text of `kin`'s generated allowed-collision matrix (named `robot`), meshes read as
/// `meshes` says (else [`default_meshes`]): what `screwkit srdf` writes and `Robot.write_srdf`
/// returns. Its defaults are [`screwkit_collision::acm::Generate::default`]'s.
pub fn generated_srdf(
    robot: &str,
    kin: &TreeKinematics,
    meshes: Option<Meshes>,
    generate: &screwkit_collision::acm::Generate,
) -> Result<String> {
    let meshes = meshes.unwrap_or_else(|| default_meshes(&kin.model().tree));
    let pairs = screwkit_collision::acm::generate(kin, meshes.into(), generate)?;
    Ok(screwkit_model::srdf::write(robot, &pairs))
}

/// The collision model of `robot`'s whole tree `kin` (its `<collision>` shapes; meshes read as
/// `meshes` says, else as [`default_meshes`]), with the pairs an SRDF file disables when one
/// is given.
pub fn model(
    kin: &TreeKinematics,
    meshes: Option<Meshes>,
    srdf: Option<&std::path::Path>,
) -> Result<CollisionModel> {
    let meshes = meshes.unwrap_or_else(|| default_meshes(&kin.model().tree));
    let mut model = CollisionModel::new(
        kin,
        Options {
            mesh_mode: meshes.into(),
            ..Options::default()
        },
    )?;
    if let Some(path) = srdf {
        model.apply_srdf(&screwkit_model::srdf::read_file(path)?)?;
    }
    Ok(model)
}

/// The whole tree's configuration for a body query given `q`: the tree's own (length nq), or,
/// for a robot whose calls answer with its chain, the chain's joint values placed in the tree
/// (the other joints at 0, clamped into their limits). Any other length is an error naming
/// both.
pub fn tree_q<'a>(robot: &Robot, kin: &TreeKinematics, q: &'a [f64]) -> Result<Cow<'a, [f64]>> {
    if q.len() == kin.nq() {
        return Ok(Cow::Borrowed(q));
    }
    if let Space::Chain(chain) = Space::of(robot, Some(kin))? {
        if q.len() == chain.dof() {
            let mut full = screwkit_solve::tree::configuration::neutral(kin);
            let (lower, upper) = (kin.lower(), kin.upper());
            for (x, (l, u)) in full.iter_mut().zip(lower.iter().zip(&upper)) {
                *x = x.max(*l).min(*u);
            }
            for (name, v) in chain.names().iter().zip(q) {
                if let Some(k) = kin.q_names().iter().position(|n| n == name) {
                    full[k] = *v;
                }
            }
            return Ok(Cow::Owned(full));
        }
        return Err(Error::option(
            "q",
            format!(
                "expected the chain's {} joint values or the whole tree's {} (q_names), got {}",
                chain.dof(),
                kin.nq(),
                q.len()
            ),
        ));
    }
    Err(Error::option(
        "q",
        format!(
            "expected the whole tree's {} configuration values (q_names), got {}",
            kin.nq(),
            q.len()
        ),
    ))
}

/// The link (or obstacle) pairs of colliding shape pairs `hits` (indices into the model's
/// pairs), each once, in the model's pair order: what "which pairs collide" answers (a link
/// with several shapes can touch another with more than one).
pub fn colliding_links(model: &CollisionModel, hits: &[usize]) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = Vec::with_capacity(hits.len());
    for &k in hits {
        let (a, b) = model.pair_names(k);
        if !out.iter().any(|(x, y)| x == a && y == b) {
            out.push((a.to_string(), b.to_string()));
        }
    }
    out
}

/// One pair's signed distance in a report.
#[derive(Debug, Clone, Serialize)]
pub struct PairReport {
    /// The two links (or obstacle) the pair's shapes belong to.
    pub pair: [String; 2],
    /// The signed distance (m): negative when the shapes overlap.
    #[serde(serialize_with = "number")]
    pub distance: f64,
    /// The witness points on each shape (world frame).
    pub points: [[f64; 3]; 2],
    /// The unit normal from the first shape to the second.
    pub normal: [f64; 3],
}

impl PairReport {
    /// The report of a pair's distance.
    pub fn new(model: &CollisionModel, d: &PairDistance) -> PairReport {
        let (a, b) = model.pair_names(d.pair);
        PairReport {
            pair: [a.to_string(), b.to_string()],
            distance: d.distance,
            points: [d.point_a, d.point_b],
            normal: d.normal,
        }
    }
}

/// One configuration's body (`screwkit collide --format json`, a line of its batch).
#[derive(Debug, Clone, Serialize)]
pub struct CollideReport {
    /// The whole tree's configuration.
    #[serde(serialize_with = "crate::io::json::numbers")]
    pub q: Vec<f64>,
    /// True when some checked pair collides.
    pub in_collision: bool,
    /// The colliding pairs, by link (or obstacle) name, each once ([`colliding_links`]).
    pub collisions: Vec<[String; 2]>,
    /// The closest pair (null for a robot without pairs).
    pub min_distance: Option<PairReport>,
    /// The number of pairs checked.
    pub pairs: usize,
}
