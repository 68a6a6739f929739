//! The collision model of a robot, built once ([`CollisionModel::new`]): every collision shape of
//! its file as a parry shape on its link's frame, obstacles fixed in the world, and the pairs a
//! query checks.
//!
//! **Which pairs.** Every pair of shapes on two different links, less:
//! - pairs within one rigid body (links joined by fixed joints can never move apart);
//! - pairs of adjacent bodies (joined by one movable joint: their shapes touch at the joint by
//!   design) — MuJoCo's parent–child rule, and the first rule of MoveIt's generated
//!   allowed-collision matrix;
//! - pairs of links the caller disables ([`CollisionModel::disable`]: an SRDF's
//!   `disable_collisions`);
//!
//! and every robot shape against every obstacle (never two obstacles).
//!
//! An MJCF model brings MuJoCo's own rules instead ([`screwkit_model::geometry::ContactRules`]):
//! not within one weld body; not a body and its parent (by weld bodies, unless one is welded
//! to the world; MuJoCo's `filterparent`, which [`Options::keep_adjacent`] turns off); not two
//! bodies a `<contact><exclude>` names; only geoms whose `contype`/`conaffinity` bits match;
//! and every `<contact><pair>`, whatever the rules. Its world body's geoms are obstacles (a
//! floating base) or shapes on the root link (a fixed base, where the root is the world body);
//! obstacles added later count as world geoms with MuJoCo's default bits (1, 1).
//!
//! **Meshes** are read once per file and scale ([`screwkit_model::mesh`]), as exact triangle
//! meshes (a bounding-volume tree over the triangles: distances to the surface, as coal
//! computes them) or as their convex hulls (MuJoCo's rule for mesh geoms: faster, and what a
//! mesh's inside means to a convex solver). [`MeshMode`] chooses.

use std::collections::{HashMap, HashSet};
use std::sync::Arc;

use parry3d_f64::shape::{Ball, Capsule, Cuboid, Cylinder, HalfSpace, SharedShape};
use screwkit_lie::Se3;
use screwkit_model::geometry::{ContactBits, ContactRules, Geometry, Role, Shape};
use screwkit_solve::TreeKinematics;

use crate::convert;

/// The meshes read so far, by file and scale: the engine's shape and, read exactly, the tree
/// of bounding spheres.
type Meshes = HashMap<
    (std::path::PathBuf, [u64; 3]),
    (SharedShape, Option<Arc<crate::mesh_distance::BoxTree>>),
>;

/// The tree of a mesh read before (by file and scale).
fn tree_of(shape: &Shape, meshes: &Meshes) -> Option<Arc<crate::mesh_distance::BoxTree>> {
    match shape {
        Shape::Mesh { path, scale, .. } => meshes
            .get(&(path.clone(), scale.map(f64::to_bits)))
            .and_then(|(_, t)| t.clone()),
        _ => None,
    }
}

/// How a mesh is read into the engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MeshMode {
    /// The triangles themselves, in a bounding-volume tree (distances to the surface).
    #[default]
    Exact,
    /// The mesh's convex hull (MuJoCo's rule for mesh geoms).
    ConvexHull,
}

/// How a model is built.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Options {
    /// How meshes are read.
    pub mesh_mode: MeshMode,
    /// Keep the pairs of adjacent bodies (joined by one movable joint) instead of excluding
    /// them.
    pub keep_adjacent: bool,
    /// Check every pair of shapes on two different links, within a rigid body too (what
    /// generating an allowed-collision matrix must look at).
    pub all_pairs: bool,
}

/// What a shape is fixed to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Attach {
    /// A link of the tree (its frame index, equal to its link index).
    Link(usize),
    /// The world (an obstacle).
    World,
}

/// One shape of the model.
#[derive(Clone)]
pub struct Object {
    /// The shape's name: `LINK/collision/K` (K counting from 0 on its link, or the element's
    /// `name`), or an obstacle's name.
    pub name: String,
    /// What it is fixed to.
    pub attach: Attach,
    /// Its pose in that frame (for a cylinder or a capsule, with URDF's z axis turned onto
    /// parry's y).
    pub origin: Se3,
    /// The shape.
    pub shape: SharedShape,
    /// `box`, `cylinder`, `sphere`, `capsule`, `ellipsoid`, `plane`, `mesh` or `convex`.
    pub kind: &'static str,
    /// The element's own name (an MJCF geom's, which `<contact><pair>` names).
    pub element: Option<String>,
    /// MuJoCo's collision bits (an MJCF geom's; (1, 1) otherwise).
    pub bits: ContactBits,
    /// An exact mesh's tree of bounding boxes (its distances: [`crate::mesh_distance`]).
    pub(crate) tree: Option<Arc<crate::mesh_distance::BoxTree>>,
    /// An obstacle added by [`CollisionModel::add_obstacle`]: its shape and pose as given.
    pub(crate) added: Option<(Shape, Se3)>,
    /// A sphere holding the shape, in the object's frame (centre, radius; the radius is
    /// infinite for a plane): the cheapest prune of a pair.
    pub(crate) sphere: ([f64; 3], f64),
}

/// The sphere holding `shape` in its own frame (centre, radius).
fn sphere_of(shape: &SharedShape) -> ([f64; 3], f64) {
    let s = shape.compute_local_bounding_sphere();
    let c = s.center();
    ([c.x, c.y, c.z], s.radius())
}

impl std::fmt::Debug for Object {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Object")
            .field("name", &self.name)
            .field("attach", &self.attach)
            .field("kind", &self.kind)
            .finish()
    }
}

/// What stops a collision model from being built or a query from running.
#[derive(Debug, Clone, PartialEq)]
pub enum CollisionError {
    /// A geometry element that cannot be read, or a mesh file: one sentence naming the link
    /// (and the file).
    Geometry(String),
    /// A name the model does not know (a link, an obstacle).
    Unknown(String),
    /// The kinematics refused the configuration (or a batch's rows).
    Solve(screwkit_solve::SolveError),
}

impl std::fmt::Display for CollisionError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CollisionError::Geometry(m) | CollisionError::Unknown(m) => f.write_str(m),
            CollisionError::Solve(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for CollisionError {}

impl From<screwkit_solve::SolveError> for CollisionError {
    fn from(e: screwkit_solve::SolveError) -> Self {
        CollisionError::Solve(e)
    }
}

/// The collision model: shapes, and the pairs a query checks (module documentation).
#[derive(Debug, Clone)]
pub struct CollisionModel {
    pub(crate) objects: Vec<Object>,
    /// Each object's local bounding box centre offset and half extents are computed per query;
    /// the pairs, as object indices (a < b).
    pub(crate) pairs: Vec<(u32, u32)>,
    /// Each link's rigid body (links joined by fixed joints share one).
    body: Vec<usize>,
    /// Pairs of bodies joined by one movable joint.
    adjacent: HashSet<(usize, usize)>,
    /// Link pairs the caller disabled (by link index, low first).
    disabled: HashSet<(usize, usize)>,
    links: Vec<String>,
    options: Options,
    /// MuJoCo's rules, for an MJCF model.
    mujoco: Option<Mujoco>,
}

/// MuJoCo's contact rules by the model's links and rigid bodies.
#[derive(Debug, Clone)]
struct Mujoco {
    /// The link that is the world body (a fixed base's root), if any.
    world_link: Option<usize>,
    /// The rigid body welded to the world (a fixed base's root's), if any.
    world_body: Option<usize>,
    /// Each link's weld parent: the rigid body of the parent of its weld body's top body
    /// (None: the world).
    weld_parent: Vec<Option<usize>>,
    filterparent: bool,
    /// `<exclude>` body pairs (links; None: the world), low first.
    exclude: HashSet<(Option<usize>, Option<usize>)>,
    /// `<pair>` geom names.
    pairs: Vec<(String, String)>,
}

/// Turns z onto y: parry's cylinders and capsules stand along y, URDF's along z.
fn z_axis() -> Se3 {
    Se3::from_parts_unchecked(
        screwkit_lie::so3::rot_x(std::f64::consts::FRAC_PI_2),
        nalgebra::Vector3::zeros(),
    )
}

/// A shape of the file as the engine's, with the extra rotation its axis needs; meshes read
/// through `meshes` (one read per file and scale).
fn engine_shape(
    shape: &Shape,
    mode: MeshMode,
    meshes: &mut Meshes,
) -> Result<(SharedShape, Option<Se3>, &'static str), String> {
    shape.check()?;
    Ok(match shape {
        Shape::Box { size } => (
            SharedShape(Arc::new(Cuboid::new(convert::vector(
                size.map(|s| s / 2.0),
            )))),
            None,
            "box",
        ),
        Shape::Sphere { radius } => (SharedShape(Arc::new(Ball::new(*radius))), None, "sphere"),
        Shape::Cylinder { radius, length } => (
            SharedShape(Arc::new(Cylinder::new(length / 2.0, *radius))),
            Some(z_axis()),
            "cylinder",
        ),
        Shape::Capsule { radius, length } => (
            SharedShape(Arc::new(Capsule::new_z(length / 2.0, *radius))),
            None,
            "capsule",
        ),
        Shape::Ellipsoid { radii } => (
            SharedShape(Arc::new(crate::ellipsoid::Ellipsoid::new(*radii))),
            None,
            "ellipsoid",
        ),
        Shape::Plane { .. } => (
            SharedShape(Arc::new(HalfSpace::new(parry3d_f64::math::Vector::Z))),
            None,
            "plane",
        ),
        Shape::Mesh { path, scale, .. } => {
            let key = (path.clone(), scale.map(f64::to_bits));
            let kind = match mode {
                MeshMode::Exact => "mesh",
                MeshMode::ConvexHull => "convex",
            };
            if let Some((s, _)) = meshes.get(&key) {
                return Ok((s.clone(), None, kind));
            }
            let mesh = screwkit_model::mesh::read_mesh(path, *scale)?;
            let vertices: Vec<_> = mesh.vertices.iter().map(|v| convert::vector(*v)).collect();
            let tree = (mode == MeshMode::Exact).then(|| {
                let v = |i: u32| {
                    let p = mesh.vertices[i as usize];
                    nalgebra::Vector3::new(p[0], p[1], p[2])
                };
                Arc::new(crate::mesh_distance::BoxTree::new(
                    mesh.triangles.iter().map(|t| t.map(v)).collect(),
                ))
            });
            let built = match mode {
                MeshMode::Exact => SharedShape::trimesh(vertices, mesh.triangles.clone())
                    .map_err(|e| format!("{}: {e}", path.display()))?,
                MeshMode::ConvexHull => crate::hull::Hull::new(&vertices)
                    .map(SharedShape::new)
                    .ok_or_else(|| {
                        format!(
                            "{}: the mesh has no convex hull (its points are flat or too few)",
                            path.display()
                        )
                    })?,
            };
            meshes.insert(key, (built.clone(), tree));
            (built, None, kind)
        }
    })
}

impl CollisionModel {
    /// The model of `kin`'s collision shapes (its tree's `<collision>` elements). A geometry
    /// problem of the file, or a mesh that cannot be read, is an error naming the link (and
    /// the file). A tree without collision shapes gives an empty model.
    pub fn new(kin: &TreeKinematics, options: Options) -> Result<CollisionModel, CollisionError> {
        let tree = &kin.model().tree;
        if let Some(p) = tree.geometry_problems.first() {
            return Err(CollisionError::Geometry(format!("{}: {p}", tree.source)));
        }
        let mut meshes = HashMap::new();
        let mut objects = Vec::new();
        let mut count = vec![0usize; tree.links.len()];
        for g in tree.geometries.iter().filter(|g| g.role == Role::Collision) {
            let link = &tree.links[g.link];
            let k = count[g.link];
            count[g.link] += 1;
            let name = match &g.name {
                Some(n) => format!("{link}/{n}"),
                None => format!("{link}/collision/{k}"),
            };
            let what = format!("link \"{link}\" <collision>");
            objects.push(object(
                g,
                Attach::Link(g.link),
                name,
                &what,
                options.mesh_mode,
                &mut meshes,
            )?);
        }
        // Rigid bodies: a link joined to its parent by a fixed joint is in its parent's body.
        let mut body: Vec<usize> = (0..tree.links.len()).collect();
        let mut order = vec![tree.root];
        let mut k = 0;
        while k < order.len() {
            let l = order[k];
            k += 1;
            for &j in &tree.child_joints[l] {
                let joint = &tree.joints[j];
                if !joint.kind.is_movable() {
                    body[joint.child] = body[l];
                }
                order.push(joint.child);
            }
        }
        let adjacent = tree
            .joints
            .iter()
            .filter(|j| j.kind.is_movable())
            .map(|j| low_first(body[j.parent], body[j.child]))
            .collect();
        let mujoco = tree.contact_rules.as_ref().map(|r| mujoco_rules(r, &body));
        if let Some(rules) = &tree.contact_rules {
            for (k, g) in rules.world.iter().enumerate() {
                if g.role != Role::Collision {
                    continue;
                }
                let name = g.name.clone().unwrap_or_else(|| format!("world/geom/{k}"));
                objects.push(object(
                    g,
                    Attach::World,
                    name,
                    "world geom",
                    options.mesh_mode,
                    &mut meshes,
                )?);
            }
        }
        let mut model = CollisionModel {
            objects,
            pairs: Vec::new(),
            body,
            adjacent,
            disabled: HashSet::new(),
            links: tree.links.clone(),
            options,
            mujoco,
        };
        model.update_pairs();
        Ok(model)
    }

    /// The shapes, robot first (file order), then the obstacles.
    pub fn objects(&self) -> &[Object] {
        &self.objects
    }

    /// The pairs a query checks, as indices into [`CollisionModel::objects`] (a < b).
    pub fn pairs(&self) -> impl ExactSizeIterator<Item = (usize, usize)> + '_ {
        self.pairs.iter().map(|&(a, b)| (a as usize, b as usize))
    }

    /// The number of pairs a query checks.
    pub fn pair_count(&self) -> usize {
        self.pairs.len()
    }

    /// A pair's two shapes' link (or obstacle) names.
    pub fn pair_names(&self, pair: usize) -> (&str, &str) {
        let (a, b) = self.pairs[pair];
        (self.owner(a as usize), self.owner(b as usize))
    }

    /// The link an object is fixed to, or the obstacle's name.
    pub fn owner(&self, object: usize) -> &str {
        match self.objects[object].attach {
            Attach::Link(l) => &self.links[l],
            Attach::World => &self.objects[object].name,
        }
    }

    /// The options it was built with.
    pub fn options(&self) -> Options {
        self.options
    }

    /// Stops checking the shapes of links `a` and `b` against each other (an SRDF's
    /// `disable_collisions`; order does not matter). An unknown link is an error.
    pub fn disable(&mut self, a: &str, b: &str) -> Result<(), CollisionError> {
        let (la, lb) = (self.link(a)?, self.link(b)?);
        self.disabled.insert(low_first(la, lb));
        self.update_pairs();
        Ok(())
    }

    /// Disables every pair an SRDF lists ([`screwkit_model::srdf`]); a link the robot does not
    /// have is an error naming the pair.
    pub fn apply_srdf(&mut self, srdf: &screwkit_model::srdf::Srdf) -> Result<(), CollisionError> {
        for p in &srdf.disabled {
            let (a, b) = match (self.link(&p.link1), self.link(&p.link2)) {
                (Ok(a), Ok(b)) => (a, b),
                _ => {
                    return Err(CollisionError::Unknown(format!(
                        "SRDF <disable_collisions link1=\"{}\" link2=\"{}\">: the robot has no link \"{}\"",
                        p.link1,
                        p.link2,
                        if self.link(&p.link1).is_err() { &p.link1 } else { &p.link2 }
                    )))
                }
            };
            self.disabled.insert(low_first(a, b));
        }
        self.update_pairs();
        Ok(())
    }

    /// The link names, in the tree's order.
    pub fn links(&self) -> &[String] {
        &self.links
    }

    /// The link pairs disabled so far, by name.
    pub fn disabled(&self) -> Vec<(String, String)> {
        let mut v: Vec<_> = self
            .disabled
            .iter()
            .map(|&(a, b)| (self.links[a].clone(), self.links[b].clone()))
            .collect();
        v.sort();
        v
    }

    /// Adds (or replaces) an obstacle named `name`: `shape` at `pose` in the world (the root
    /// link's frame; the world with a floating base). A mesh is read as the model's meshes are.
    pub fn add_obstacle(
        &mut self,
        name: &str,
        shape: &Shape,
        pose: Se3,
    ) -> Result<(), CollisionError> {
        let far = screwkit_model::geometry::MAX_SIZE;
        if pose
            .translation()
            .iter()
            .any(|x| !x.is_finite() || x.abs() > far)
        {
            return Err(CollisionError::Geometry(format!(
                "obstacle \"{name}\": its position {:?} is not within {far} m of the origin",
                pose.translation().as_slice()
            )));
        }
        let mut meshes = HashMap::new();
        let (engine, turn, kind) = engine_shape(shape, self.options.mesh_mode, &mut meshes)
            .map_err(|e| CollisionError::Geometry(format!("obstacle \"{name}\": {e}")))?;
        let origin = match turn {
            Some(t) => pose.compose(&t),
            None => pose,
        };
        self.remove_obstacle(name);
        self.objects.push(Object {
            name: name.to_string(),
            attach: Attach::World,
            origin,
            sphere: sphere_of(&engine),
            shape: engine,
            kind,
            element: None,
            bits: ContactBits::DEFAULT,
            tree: tree_of(shape, &meshes),
            added: Some((shape.clone(), pose)),
        });
        self.update_pairs();
        Ok(())
    }

    /// Removes the obstacle named `name`; true if there was one.
    pub fn remove_obstacle(&mut self, name: &str) -> bool {
        let before = self.objects.len();
        self.objects
            .retain(|o| !(o.attach == Attach::World && o.name == name));
        let removed = self.objects.len() != before;
        if removed {
            self.update_pairs();
        }
        removed
    }

    /// The obstacles added with [`CollisionModel::add_obstacle`] (not the file's world geoms),
    /// in the order added: name, shape and pose as given (what it takes to add them again).
    pub fn added_obstacles(&self) -> Vec<(&str, &Shape, Se3)> {
        self.objects
            .iter()
            .filter_map(|o| o.added.as_ref().map(|(s, p)| (o.name.as_str(), s, *p)))
            .collect()
    }

    /// A digest of everything a query sees ([`screwkit_model::digest`], 16 hex digits): each
    /// shape's name, owner, pose on it, kind, local box and sphere and, for a mesh or a hull,
    /// its vertices; and the pairs checked. Two models with the same digest answer every query
    /// alike: what a file computed from a body (a reachability map clear of contact) stores to
    /// refuse being merged with one computed from another body.
    pub fn digest(&self) -> String {
        let mut d = screwkit_model::digest::Digest::new();
        d.word(match self.options.mesh_mode {
            MeshMode::Exact => "exact",
            MeshMode::ConvexHull => "convex",
        });
        d.count(self.objects.len());
        for o in &self.objects {
            d.word(&o.name).word(o.kind);
            match o.attach {
                Attach::Link(l) => d.word(&self.links[l]),
                Attach::World => d.word(""),
            };
            d.values(o.origin.to_homogeneous().iter().copied());
            let aabb = o.shape.compute_local_aabb();
            d.values(aabb.mins.to_array().into_iter().chain(aabb.maxs.to_array()));
            d.values(o.sphere.0).value(o.sphere.1);
            let points: &[parry3d_f64::math::Vector] = if let Some(m) = o.shape.as_trimesh() {
                m.vertices()
            } else if let Some(h) = o.shape.as_shape::<crate::hull::Hull>() {
                h.points()
            } else {
                &[]
            };
            d.count(points.len());
            for p in points {
                d.values([p.x, p.y, p.z]);
            }
        }
        d.count(self.pairs.len());
        for &(a, b) in &self.pairs {
            d.count(a as usize).count(b as usize);
        }
        d.hex()
    }

    /// The obstacles' names, in the order added.
    pub fn obstacles(&self) -> Vec<&str> {
        self.objects
            .iter()
            .filter(|o| o.attach == Attach::World)
            .map(|o| o.name.as_str())
            .collect()
    }

    fn link(&self, name: &str) -> Result<usize, CollisionError> {
        self.links
            .iter()
            .position(|l| l == name)
            .ok_or_else(|| CollisionError::Unknown(format!("unknown link \"{name}\"")))
    }

    /// Whether objects `a` and `b` are checked against each other (module documentation).
    fn checked(&self, a: &Object, b: &Object) -> bool {
        if let (Some(m), false) = (&self.mujoco, self.options.all_pairs) {
            return self.checked_mujoco(m, a, b);
        }
        match (a.attach, b.attach) {
            (Attach::World, Attach::World) => false,
            (Attach::World, Attach::Link(_)) | (Attach::Link(_), Attach::World) => true,
            (Attach::Link(la), Attach::Link(lb)) if self.options.all_pairs => la != lb,
            (Attach::Link(la), Attach::Link(lb)) => {
                let (ba, bb) = (self.body[la], self.body[lb]);
                ba != bb
                    && (self.options.keep_adjacent || !self.adjacent.contains(&low_first(ba, bb)))
                    && !self.disabled.contains(&low_first(la, lb))
            }
        }
    }

    /// MuJoCo's rules (module documentation).
    fn checked_mujoco(&self, m: &Mujoco, a: &Object, b: &Object) -> bool {
        let named = |o: &Object, n: &str| o.element.as_deref() == Some(n);
        if m.pairs
            .iter()
            .any(|(x, y)| (named(a, x) && named(b, y)) || (named(a, y) && named(b, x)))
        {
            return true;
        }
        // Weld bodies (None: the world) and MuJoCo bodies (links; None: the world).
        let weld = |o: &Object| match o.attach {
            Attach::Link(l) => Some(self.body[l]).filter(|b| Some(*b) != m.world_body),
            Attach::World => None,
        };
        let (wa, wb) = (weld(a), weld(b));
        if wa == wb {
            return false;
        }
        if let (Attach::Link(la), Attach::Link(lb)) = (a.attach, b.attach) {
            if m.filterparent
                && !self.options.keep_adjacent
                && wa.is_some()
                && wb.is_some()
                && (wa == m.weld_parent[lb] || wb == m.weld_parent[la])
            {
                return false;
            }
            if self.disabled.contains(&low_first(la, lb)) {
                return false;
            }
        }
        let body_of = |o: &Object| match o.attach {
            Attach::Link(l) => Some(l).filter(|l| Some(*l) != m.world_link),
            Attach::World => None,
        };
        let (ba, bb) = (body_of(a), body_of(b));
        if m.exclude.contains(&(ba.min(bb), ba.max(bb))) {
            return false;
        }
        a.bits.compatible(b.bits)
    }

    fn update_pairs(&mut self) {
        let n = self.objects.len();
        let mut pairs = Vec::new();
        for a in 0..n {
            for b in a + 1..n {
                if self.checked(&self.objects[a], &self.objects[b]) {
                    pairs.push((a as u32, b as u32));
                }
            }
        }
        self.pairs = pairs;
    }
}

fn low_first(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

/// One collision shape of the file as a model object named `name`, fixed to `attach`; `what`
/// names it in an error.
fn object(
    g: &Geometry,
    attach: Attach,
    name: String,
    what: &str,
    mode: MeshMode,
    meshes: &mut Meshes,
) -> Result<Object, CollisionError> {
    let (shape, turn, kind) = engine_shape(&g.shape, mode, meshes)
        .map_err(|e| CollisionError::Geometry(format!("{what}: {e}")))?;
    Ok(Object {
        name,
        attach,
        origin: match turn {
            Some(t) => g.origin.compose(&t),
            None => g.origin,
        },
        sphere: sphere_of(&shape),
        shape,
        kind,
        element: g.name.clone(),
        bits: g.bits.unwrap_or(ContactBits::DEFAULT),
        tree: tree_of(&g.shape, meshes),
        added: None,
    })
}

/// MuJoCo's rules by the collision model's rigid bodies (`body`: each link's).
fn mujoco_rules(rules: &ContactRules, body: &[usize]) -> Mujoco {
    let world_body = rules.world_link.map(|w| body[w]);
    let weld = |l: usize| Some(body[l]).filter(|b| Some(*b) != world_body);
    let weld_parent = (0..body.len())
        .map(|l| {
            // Up the MuJoCo bodies while they stay in l's rigid body.
            let mut m = l;
            for _ in 0..body.len() {
                match rules.body_parent.get(&m) {
                    Some(Some(p)) if body[*p] == body[l] => m = *p,
                    Some(Some(p)) => return weld(*p),
                    _ => return None,
                }
            }
            None
        })
        .collect();
    let world = |b: Option<usize>| b.filter(|l| Some(*l) != rules.world_link);
    Mujoco {
        world_link: rules.world_link,
        world_body,
        weld_parent,
        filterparent: rules.filterparent,
        exclude: rules
            .exclude
            .iter()
            .map(|&(a, b)| {
                let (a, b) = (world(a), world(b));
                (a.min(b), a.max(b))
            })
            .collect(),
        pairs: rules.pairs.clone(),
    }
}
