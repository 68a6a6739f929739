//! What is in a robot file (`screwkit info`): the tree, its joints and limits, its leaves and
//! chains, the whole tree's variables and frames, the default chain and its IK family —
//! gathered once here as the JSON contract's reports ([`InfoReport`], [`ChainEntry`]); the
//! front ends print or return them.

use serde::Serialize;

use screwkit_model::{Chain, JointKind, KinematicTree, Tree};

use crate::error::Result;
use crate::io::json::number;

/// Whether a leaf link looks like a sensor or a mounting frame rather than an end effector
/// (its name holds `camera`, `imu`, `_frame`, …).
pub fn sensor_like(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    [
        "camera",
        "sensor",
        "imu",
        "laser",
        "lidar",
        "optical",
        "depth",
        "rgb",
        "sonar",
        "gps",
        "ft_",
        "force",
        "_frame",
        "scan",
        "kinect",
        "realsense",
    ]
    .iter()
    .any(|w| n.contains(w))
}

/// One chain root → leaf of `info --chains`.
#[derive(Debug, Clone, Serialize)]
pub struct ChainEntry {
    /// The root link.
    pub base: String,
    /// The leaf.
    pub tip: String,
    /// Its degrees of freedom, when it is a chain.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dof: Option<usize>,
    /// Why it is not a chain.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
    /// The leaf looks like a sensor or a mounting frame ([`sensor_like`]).
    pub sensor_like: bool,
}

/// Every chain root → leaf, end effectors first, sensor-like leaves last, each group in file
/// order.
pub fn chains(tree: &Tree) -> Vec<ChainEntry> {
    let mut leaves = tree.leaves_below(tree.root);
    leaves.sort_by_key(|&l| sensor_like(&tree.links[l]));
    leaves
        .into_iter()
        .map(|l| {
            let tip = tree.links[l].clone();
            let dof = Chain::from_tree(tree, None, Some(&tip)).map(|c| c.dof());
            ChainEntry {
                base: tree.links[tree.root].clone(),
                sensor_like: sensor_like(&tip),
                dof: dof.as_ref().ok().copied(),
                error: dof.err().map(|e| e.kind.to_string()),
                tip,
            }
        })
        .collect()
}

/// serde's form of an optional number (`null` when absent, or not finite).
fn optional<S: serde::Serializer>(x: &Option<f64>, s: S) -> std::result::Result<S::Ok, S::Error> {
    match x {
        Some(x) => number(x, s),
        None => s.serialize_none(),
    }
}

/// A joint of the file.
#[derive(Debug, Clone, Serialize)]
pub struct JointInfo {
    /// Its name.
    pub name: String,
    /// `revolute`, `continuous`, `prismatic`, `fixed`, … ([`JointKind::as_str`]).
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// The parent link.
    pub parent: String,
    /// The child link.
    pub child: String,
    /// Lower position limit (none for a continuous joint or without `<limit>`).
    #[serde(serialize_with = "optional")]
    pub lower: Option<f64>,
    /// Upper position limit.
    #[serde(serialize_with = "optional")]
    pub upper: Option<f64>,
    /// Velocity limit, if written.
    #[serde(serialize_with = "optional")]
    pub velocity: Option<f64>,
    /// Effort limit, if written.
    #[serde(serialize_with = "optional")]
    pub effort: Option<f64>,
    /// The joint it mimics.
    pub mimic: Option<MimicInfo>,
}

/// A mimic joint's rule θ = multiplier · q_leader + offset.
#[derive(Debug, Clone, Serialize)]
pub struct MimicInfo {
    /// The joint followed.
    pub leader: String,
    /// The multiplier.
    #[serde(serialize_with = "number")]
    pub multiplier: f64,
    /// The offset.
    #[serde(serialize_with = "number")]
    pub offset: f64,
}

/// A variable of the whole tree (file order, mimic followers excluded).
#[derive(Debug, Clone, Serialize)]
pub struct VariableInfo {
    /// Its place in the joint variables (0-based).
    pub index: usize,
    /// The joint that owns it.
    pub name: String,
    /// Its joint's kind.
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// Lower limit (null when unbounded).
    #[serde(serialize_with = "number")]
    pub lower: f64,
    /// Upper limit (null when unbounded).
    #[serde(serialize_with = "number")]
    pub upper: f64,
    /// Velocity limit, if written.
    #[serde(serialize_with = "optional")]
    pub velocity: Option<f64>,
    /// Effort limit, if written.
    #[serde(serialize_with = "optional")]
    pub effort: Option<f64>,
}

/// A frame of the whole tree: a link, with its home pose in the root link's frame.
#[derive(Debug, Clone, Serialize)]
pub struct FrameInfo {
    /// The frame's name.
    pub name: String,
    /// The link it is fixed to.
    pub link: String,
    /// Its pose at q = 0, four rows.
    #[serde(serialize_with = "crate::report::pose_rows")]
    pub home: [f64; 16],
}

/// A shape of a link (`<collision>` or `<visual>`).
#[derive(Debug, Clone, Serialize)]
pub struct ShapeInfo {
    /// The link it is fixed to.
    pub link: String,
    /// `collision` or `visual`.
    pub role: &'static str,
    /// `box`, `cylinder`, `sphere`, `capsule` or `mesh`.
    pub shape: &'static str,
    /// A mesh's file name as written.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh: Option<String>,
}

/// The default (or chosen) chain.
#[derive(Debug, Clone, Serialize)]
pub struct ChainInfo {
    /// Its base link.
    pub base: String,
    /// Its tip link.
    pub tip: String,
    /// Its degrees of freedom.
    pub dof: usize,
    /// Its analytic-IK family word ([`screwkit_solve::family::Family::word`]).
    pub ik_family: &'static str,
    /// Its variables, in order (for text).
    #[serde(skip)]
    pub variables: Vec<String>,
    /// The analytic IK it gets, in words ([`screwkit_solve::analytic::describe`]; for text).
    #[serde(skip)]
    pub ik_description: String,
}

/// What is in a robot file (`screwkit info --format json`).
#[derive(Debug, Clone, Serialize)]
pub struct InfoReport {
    /// The robot's name.
    pub robot: String,
    /// The root link.
    pub root: String,
    /// Every link, in the file's order.
    pub links: Vec<String>,
    /// Every joint, in the file's order.
    pub joints: Vec<JointInfo>,
    /// The leaf links below the root.
    pub leaves: Vec<String>,
    /// The whole tree's variables (null when it has none: see `whole_tree_error`).
    pub variables: Option<Vec<VariableInfo>>,
    /// The whole tree's frames (every link, with its home pose).
    pub frames: Option<Vec<FrameInfo>>,
    /// Why the file has no whole tree, if it has none.
    pub whole_tree_error: Option<String>,
    /// The chain asked for, or the default one (null when there is none).
    pub default_chain: Option<ChainInfo>,
    /// Every link's shapes, in the file's order.
    pub geometry: Vec<ShapeInfo>,
    /// The geometry elements that could not be read, one sentence each naming the link.
    pub geometry_problems: Vec<String>,
    /// Why there is no default chain (for text).
    #[serde(skip)]
    pub chain_error: Option<String>,
    /// True when a base or tip was asked for.
    #[serde(skip)]
    pub chosen: bool,
}

impl InfoReport {
    /// The report of `tree`, its chain `base` → `tip` (either given: an error when it is not a
    /// chain; neither: the default chain, if the file has one).
    pub fn new(tree: &Tree, base: Option<&str>, tip: Option<&str>) -> Result<InfoReport> {
        let chosen = base.is_some() || tip.is_some();
        let chain = Chain::from_tree(tree, base, tip);
        if chosen {
            if let Err(e) = &chain {
                return Err(e.clone().into());
            }
        }
        let whole = KinematicTree::from_tree(tree);
        let joints = tree
            .joints
            .iter()
            .map(|j| {
                let limit = j.limit;
                let bounded = j.kind != JointKind::Continuous;
                JointInfo {
                    name: j.name.clone(),
                    kind: j.kind.as_str(),
                    parent: tree.links[j.parent].clone(),
                    child: tree.links[j.child].clone(),
                    lower: limit.filter(|_| bounded).map(|l| l.lower),
                    upper: limit.filter(|_| bounded).map(|l| l.upper),
                    velocity: limit.and_then(|l| l.velocity),
                    effort: limit.and_then(|l| l.effort),
                    mimic: j.mimic.as_ref().map(|m| MimicInfo {
                        leader: m.leader.clone(),
                        multiplier: m.multiplier,
                        offset: m.offset,
                    }),
                }
            })
            .collect();
        let (variables, frames) = match &whole {
            Ok(m) => (
                Some(
                    m.variables
                        .iter()
                        .enumerate()
                        .map(|(index, v)| VariableInfo {
                            index,
                            name: v.name.clone(),
                            kind: v.kind.as_str(),
                            lower: v.lower,
                            upper: v.upper,
                            velocity: v.velocity,
                            effort: v.effort,
                        })
                        .collect(),
                ),
                Some(
                    m.frames
                        .iter()
                        .map(|f| {
                            let mut home = [0.0; 16];
                            f.home.write_row_major(&mut home);
                            FrameInfo {
                                name: f.name.clone(),
                                link: m.links[f.link].name.clone(),
                                home,
                            }
                        })
                        .collect(),
                ),
            ),
            Err(_) => (None, None),
        };
        let default_chain = chain.as_ref().ok().map(|c| {
            let kin = screwkit_solve::Kinematics::new(c);
            ChainInfo {
                base: c.base.clone(),
                tip: c.tip.clone(),
                dof: c.dof(),
                ik_family: screwkit_solve::family::classify(&kin).family.word(),
                variables: c.variable_names().iter().map(|s| s.to_string()).collect(),
                ik_description: screwkit_solve::analytic::describe(&kin),
            }
        });
        Ok(InfoReport {
            robot: tree.name.clone(),
            root: tree.links[tree.root].clone(),
            links: tree.links.clone(),
            joints,
            leaves: tree
                .leaves_below(tree.root)
                .iter()
                .map(|&l| tree.links[l].clone())
                .collect(),
            variables,
            frames,
            whole_tree_error: whole.as_ref().err().map(|e| e.kind.to_string()),
            default_chain,
            // An MJCF model's world geoms (a floating base: fixed in the world) as `world`'s.
            geometry: tree
                .geometries
                .iter()
                .map(|g| (tree.links[g.link].as_str(), g))
                .chain(
                    tree.contact_rules
                        .iter()
                        .flat_map(|r| r.world.iter().map(|g| ("world", g))),
                )
                .map(|(link, g)| ShapeInfo {
                    link: link.to_string(),
                    role: g.role.word(),
                    shape: g.shape.word(),
                    mesh: match &g.shape {
                        screwkit_model::geometry::Shape::Mesh { uri, .. } => Some(uri.clone()),
                        _ => None,
                    },
                })
                .collect(),
            geometry_problems: tree.geometry_problems.clone(),
            chain_error: chain.err().map(|e| e.kind.to_string()),
            chosen,
        })
    }
}
