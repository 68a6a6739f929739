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

/// The collision model of a loaded robot as the command line asks for it: its whole tree's
/// shapes (meshes read as its load options say), an SRDF's disabled pairs and a scene file's
/// obstacles when given (`screwkit collide`, `screwkit ik --all --collisions`).
pub fn robot_model(
    robot: &Robot,
    srdf: Option<&std::path::Path>,
    scene: Option<&std::path::Path>,
) -> Result<CollisionModel> {
    let mut built = model(robot.whole()?, robot.options().meshes, srdf)?;
    if let Some(scene) = scene {
        let obstacles = read_scene(scene, &robot.options().xacro.package_paths)?;
        add_obstacles(&mut built, &obstacles)?;
    }
    Ok(built)
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
            let mut full = chain_base(kin);
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

/// The whole tree's configuration a chain's joint values are placed in: the tree's neutral
/// configuration (its joints at 0) clamped into the limits.
fn chain_base(kin: &TreeKinematics) -> Vec<f64> {
    let mut full = screwkit_solve::tree::configuration::neutral(kin);
    let (lower, upper) = (kin.lower(), kin.upper());
    for (x, (l, u)) in full.iter_mut().zip(lower.iter().zip(&upper)) {
        *x = x.max(*l).min(*u);
    }
    full
}

/// The margin numerical IK keeps by default when it avoids collisions (m): none, contact alone
/// is refused.
pub const DEFAULT_MARGIN: f64 = 0.0;

/// The body numerical IK keeps clear of (`ik --avoid-collisions`, `Robot.ik(avoid_collisions=
/// True)`): the robot's chain placed in its whole tree `kin` as [`tree_q`] places it, checked
/// by `model` (SRDF and obstacles applied) with `margin` (m). A model without a pair to check
/// (no collision shapes, no obstacles) is an error, never a silent "clear".
pub fn chain_clearance<'a>(
    robot: &Robot,
    kin: &'a TreeKinematics,
    model: &'a CollisionModel,
    margin: f64,
) -> Result<screwkit_collision::ChainClearance<'a>> {
    if model.pair_count() == 0 {
        return Err(Error::option(
            "avoid_collisions",
            "the robot has no pair of shapes to keep apart (no <collision> geometry on two \
             bodies, and no obstacles): load it with geometry, or add obstacles",
        ));
    }
    let (_, chain) = robot.chain_parts()?;
    Ok(screwkit_collision::ChainClearance::new(
        model,
        kin,
        chain.names(),
        chain_base(kin),
        margin,
    )?)
}

/// Whole-body IK's collision avoidance on `model` (the robot's body, SRDF and obstacles
/// applied): every checked pair (`pairs` None) or the named ones, kept `margin` apart, mink's
/// detection distance and gain ([`screwkit_collision::avoidance`]'s defaults). A model without
/// a pair to check is an error.
pub fn collision_avoidance(
    robot: &Robot,
    model: CollisionModel,
    pairs: Option<&[(String, String)]>,
    margin: f64,
) -> Result<std::sync::Arc<dyn screwkit_solve::tree::limits::Limit>> {
    if model.pair_count() == 0 {
        return Err(Error::option(
            "avoid_collisions",
            "the robot has no pair of shapes to keep apart (no <collision> geometry on two \
             bodies, and no obstacles): load it with geometry, or add obstacles",
        ));
    }
    use screwkit_collision::avoidance::{DEFAULT_DETECTION_DISTANCE, DEFAULT_GAIN};
    Ok(std::sync::Arc::new(
        screwkit_collision::CollisionAvoidance::new(
            std::sync::Arc::new(model),
            robot.whole()?,
            pairs,
            margin,
            DEFAULT_DETECTION_DISTANCE,
            DEFAULT_GAIN,
        )?,
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
    /// The distance's rate along the tree's velocity (nv), when asked.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub jacobian: Option<Vec<f64>>,
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
            jacobian: None,
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
    /// Every checked pair's distance with its Jacobian row, when asked (`--distances`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub distances: Option<Vec<PairReport>>,
}

/// `collide`'s report of q (the whole tree's, or a chain robot's joint values): collision, the
/// colliding link pairs, the closest pair, and with `all` every pair's distance and Jacobian
/// row.
pub fn collide_report(
    robot: &Robot,
    kin: &TreeKinematics,
    model: &CollisionModel,
    ws: &mut screwkit_collision::CollisionWorkspace,
    q: &[f64],
    all: bool,
) -> Result<CollideReport> {
    let full = tree_q(robot, kin, q)?;
    let mut hits = Vec::new();
    screwkit_collision::collisions(model, ws, kin, &full, &mut hits)?;
    let closest = screwkit_collision::min_distance(model, ws, kin, &full)?;
    let distances = if all {
        let (mut d, mut rows) = (Vec::new(), Vec::new());
        screwkit_collision::distance_jacobians(model, ws, kin, &full, &mut d, &mut rows)?;
        let nv = kin.nv().max(1);
        Some(
            d.iter()
                .zip(rows.chunks(nv))
                .map(|(d, row)| PairReport {
                    jacobian: Some(row.to_vec()),
                    ..PairReport::new(model, d)
                })
                .collect(),
        )
    } else {
        None
    };
    Ok(CollideReport {
        q: full.to_vec(),
        in_collision: !hits.is_empty(),
        collisions: colliding_links(model, &hits)
            .into_iter()
            .map(|(a, b)| [a, b])
            .collect(),
        min_distance: closest.map(|d| PairReport::new(model, &d)),
        pairs: model.pair_count(),
        distances,
    })
}

/// The body's contacts at one configuration, as the 3D page shows them ([`contacts`]).
#[derive(Debug, Clone, Serialize)]
pub struct Contacts {
    /// The colliding pairs, by link (or obstacle) name, each once.
    pub collisions: Vec<[String; 2]>,
    /// When asked: each pair of links (or link and obstacle) closer than the distance asked,
    /// once (its closest shapes), closest first; the closest pair of all always among them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub close: Option<Vec<PairReport>>,
}

/// The distance (m) within which the page draws a pair's minimum-distance segment.
pub const SHOWN_WITHIN: f64 = 0.05;

/// The contacts of `model` at q (the whole tree's, or a chain robot's joint values): the
/// colliding link pairs, and with `within` the link pairs closer than it with their witness
/// points (the closest pair always).
pub fn contacts(
    robot: &Robot,
    kin: &TreeKinematics,
    model: &CollisionModel,
    ws: &mut screwkit_collision::CollisionWorkspace,
    q: &[f64],
    within: Option<f64>,
) -> Result<Contacts> {
    let full = tree_q(robot, kin, q)?;
    let mut hits = Vec::new();
    screwkit_collision::collisions(model, ws, kin, &full, &mut hits)?;
    let collisions = colliding_links(model, &hits)
        .into_iter()
        .map(|(a, b)| [a, b])
        .collect();
    let close = match within {
        None => None,
        Some(within) => {
            let mut near = Vec::new();
            screwkit_collision::close_pairs(
                model,
                ws,
                kin,
                &full,
                within,
                f64::NEG_INFINITY,
                None,
                &mut near,
                None,
            )?;
            near.retain(|d| d.distance < within);
            if let Some(closest) = screwkit_collision::min_distance(model, ws, kin, &full)? {
                near.push(closest);
            }
            near.sort_by(|a, b| a.distance.total_cmp(&b.distance).then(a.pair.cmp(&b.pair)));
            let mut out: Vec<PairReport> = Vec::new();
            for d in &near {
                let r = PairReport::new(model, d);
                if !out.iter().any(|o| o.pair == r.pair) {
                    out.push(r);
                }
            }
            Some(out)
        }
    };
    Ok(Contacts { collisions, close })
}

/// One obstacle of a scene: a shape at a pose in the world.
#[derive(Debug, Clone, PartialEq)]
pub struct Obstacle {
    /// Its name (unique in the scene).
    pub name: String,
    /// The shape (a mesh's path resolved).
    pub shape: screwkit_model::geometry::Shape,
    /// Its pose in the world (the root link's frame; the world with a floating base).
    pub pose: screwkit_lie::Se3,
}

/// A scene file's obstacle as written.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ObstacleSpec {
    name: String,
    shape: String,
    size: Option<[f64; 3]>,
    radius: Option<f64>,
    length: Option<f64>,
    path: Option<String>,
    scale: Option<[f64; 3]>,
    xyz: Option<[f64; 3]>,
    rpy: Option<[f64; 3]>,
    pose: Option<[[f64; 4]; 4]>,
}

/// A scene file as written.
#[derive(Debug, serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneSpec {
    obstacles: Vec<ObstacleSpec>,
}

/// The obstacles of a scene file (`screwkit collide --obstacles`, Python's
/// `Robot.add_obstacles`), JSON:
///
/// ```json
/// {"obstacles": [
///   {"name": "table", "shape": "box", "size": [1.0, 0.8, 0.05], "xyz": [0.6, 0, 0.4]},
///   {"name": "ball", "shape": "sphere", "radius": 0.1, "xyz": [0.4, 0.3, 0.9]},
///   {"name": "post", "shape": "cylinder", "radius": 0.05, "length": 1.0, "rpy": [0, 1.57, 0]},
///   {"name": "bin", "shape": "mesh", "path": "bin.stl", "scale": [0.001, 0.001, 0.001],
///    "pose": [[1, 0, 0, 0.5], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}
/// ]}
/// ```
///
/// Shapes as URDF's: `box` (`size`, full sides), `sphere` (`radius`), `cylinder` and `capsule`
/// (`radius`, `length`, along z), `mesh` (`path` relative to the scene file, or `package://`
/// through `package_paths`, or `file://`; `scale` optional). The pose is `xyz` and `rpy` (URDF's
/// origin; both optional) or `pose` (4 × 4, row-major, a rotation checked to 1e-9), not both.
/// Every field is checked: an unknown one, one the shape does not take, a name given twice, a
/// bad number, are errors naming the file (with serde's line and column) and the obstacle.
pub fn read_scene(
    path: &std::path::Path,
    package_paths: &[std::path::PathBuf],
) -> Result<Vec<Obstacle>> {
    let text = crate::load::Source::Path(path.to_path_buf()).read()?;
    let dir = path.parent().unwrap_or(std::path::Path::new("."));
    scene_from_str(&text, &path.display().to_string(), dir, package_paths)
}

/// [`read_scene`] of text named `label`, meshes named from `dir`.
pub fn scene_from_str(
    text: &str,
    label: &str,
    dir: &std::path::Path,
    package_paths: &[std::path::PathBuf],
) -> Result<Vec<Obstacle>> {
    use screwkit_model::geometry::Shape;
    let bad = |message: String| Error::option("obstacles", format!("{label}: {message}"));
    let spec: SceneSpec = serde_json::from_str(text).map_err(|e| bad(e.to_string()))?;
    let mut out: Vec<Obstacle> = Vec::with_capacity(spec.obstacles.len());
    for (k, o) in spec.obstacles.into_iter().enumerate() {
        let at = |message: String| bad(format!("obstacle {k} (\"{}\"): {message}", o.name));
        if out.iter().any(|x| x.name == o.name) {
            return Err(at("the name is given twice".into()));
        }
        let fields = [
            ("size", o.size.is_some()),
            ("radius", o.radius.is_some()),
            ("length", o.length.is_some()),
            ("path", o.path.is_some()),
            ("scale", o.scale.is_some()),
        ];
        let takes: &[&str] = match o.shape.as_str() {
            "box" => &["size"],
            "sphere" => &["radius"],
            "cylinder" | "capsule" => &["radius", "length"],
            "mesh" => &["path", "scale"],
            other => {
                return Err(at(format!(
                    "shape \"{other}\": expected box, sphere, cylinder, capsule or mesh"
                )))
            }
        };
        if let Some((f, _)) = fields
            .iter()
            .find(|(f, given)| *given && !takes.contains(f))
        {
            return Err(at(format!("a {} takes no \"{f}\"", o.shape)));
        }
        let need =
            |v: Option<f64>, f: &str| v.ok_or_else(|| at(format!("a {} needs \"{f}\"", o.shape)));
        let shape = match o.shape.as_str() {
            "box" => Shape::Box {
                size: o.size.ok_or_else(|| at("a box needs \"size\"".into()))?,
            },
            "sphere" => Shape::Sphere {
                radius: need(o.radius, "radius")?,
            },
            "cylinder" => Shape::Cylinder {
                radius: need(o.radius, "radius")?,
                length: need(o.length, "length")?,
            },
            "capsule" => Shape::Capsule {
                radius: need(o.radius, "radius")?,
                length: need(o.length, "length")?,
            },
            _ => {
                let uri = o
                    .path
                    .clone()
                    .ok_or_else(|| at("a mesh needs \"path\"".into()))?;
                let path =
                    screwkit_model::geometry::resolve_mesh(&uri, dir, package_paths).map_err(at)?;
                Shape::Mesh {
                    uri,
                    path,
                    scale: o.scale.unwrap_or([1.0; 3]),
                }
            }
        };
        shape.check().map_err(at)?;
        let pose = match (o.pose, o.xyz.is_some() || o.rpy.is_some()) {
            (Some(_), true) => return Err(at("give \"pose\" or \"xyz\"/\"rpy\", not both".into())),
            (Some(p), false) => {
                let flat: Vec<f64> = p.iter().flatten().copied().collect();
                crate::target::from_row_major(&flat).map_err(|e| at(format!("pose: {e}")))?
            }
            (None, _) => screwkit_lie::Se3::from_xyz_rpy(
                o.xyz.unwrap_or([0.0; 3]),
                o.rpy.unwrap_or([0.0; 3]),
            )
            .map_err(|e| at(format!("xyz/rpy: {e}")))?,
        };
        out.push(Obstacle {
            name: o.name,
            shape,
            pose,
        });
    }
    Ok(out)
}

/// Adds a scene's obstacles to `model` (each replaces one of its name).
pub fn add_obstacles(model: &mut CollisionModel, obstacles: &[Obstacle]) -> Result<()> {
    for o in obstacles {
        model.add_obstacle(&o.name, &o.shape, o.pose)?;
    }
    Ok(())
}

/// The body's verdict on a chain's analytic solutions (`Collisions::Flag` or `Filter`): each
/// solution's configuration placed in the whole tree ([`tree_q`]) and checked for collision,
/// self and obstacles, all of a target's solutions on all cores.
pub struct SolutionBody<'a> {
    /// The robot (its chain's joint values are placed in its tree).
    pub robot: &'a Robot,
    /// The whole tree.
    pub kin: &'a TreeKinematics,
    /// The collision model (SRDF and obstacles applied).
    pub model: &'a CollisionModel,
    /// Flag or filter.
    pub mode: crate::words::Collisions,
}

impl SolutionBody<'_> {
    /// Each solution's flag: true when its configuration collides.
    pub fn flags(&self, sols: &screwkit_solve::analytic::Solutions) -> Result<Vec<bool>> {
        let mut qs = Vec::with_capacity(sols.len() * self.kin.nq());
        for q in sols.iter() {
            qs.extend_from_slice(&tree_q(self.robot, self.kin, q)?);
        }
        let mut out = vec![false; sols.len()];
        if !out.is_empty() {
            screwkit_collision::in_collision_batch(self.model, self.kin, &qs, &mut out)?;
        }
        Ok(out)
    }

    /// The mode applied to `sols`: flagged (the flags returned, one per solution), or the
    /// colliding ones dropped (None returned); `Ignore` leaves them (None).
    pub fn apply(
        &self,
        sols: &mut screwkit_solve::analytic::Solutions,
    ) -> Result<Option<Vec<bool>>> {
        use crate::words::Collisions;
        match self.mode {
            Collisions::Ignore => Ok(None),
            Collisions::Flag => self.flags(sols).map(Some),
            Collisions::Filter => {
                let free: Vec<bool> = self.flags(sols)?.iter().map(|c| !c).collect();
                sols.retain(&free);
                Ok(None)
            }
        }
    }
}
