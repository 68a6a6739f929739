//! A robot's body as its files describe it: each link's `<collision>` and `<visual>` shapes
//! (URDF), fixed to the link's frame at an origin ([`Geometry`]). Descriptions only: a mesh is
//! its file's path, read when a collision query first needs it (`screwkit-collision`).
//!
//! Conventions (URDF's, kept by every reader): a box is centred on its origin with its full
//! `size` along x, y, z; a cylinder and a capsule have their axis along z, centred, `length`
//! the cylinder's (a capsule adds a half-sphere of `radius` at each end); a mesh's vertices are
//! multiplied by `scale` per axis, in the link's frame after the origin. MJCF adds MuJoCo's
//! ellipsoid (semi-axes along x, y, z) and plane (the half-space z ≤ 0 of its frame, infinite
//! for collisions as in MuJoCo; its `size` only says how much of it to draw).
//!
//! Geometry never stops a robot from loading for its kinematics: an element that cannot be read
//! (a malformed number, an unknown shape, a mesh whose package is not found) is kept as a
//! problem naming the link ([`Tree::geometry_problems`](crate::Tree::geometry_problems)); a
//! query of the body reports it then.

use std::path::{Path, PathBuf};

use screwkit_lie::Se3;

/// A geometric primitive or a mesh, in its own frame (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// A box of full side lengths `size` (x, y, z).
    Box {
        /// Side lengths (m).
        size: [f64; 3],
    },
    /// A cylinder along z.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Length (m).
        length: f64,
    },
    /// A sphere.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// A capsule along z: a cylinder of `length` with a half-sphere at each end.
    Capsule {
        /// Radius (m).
        radius: f64,
        /// The cylinder's length (m), the caps not included.
        length: f64,
    },
    /// An ellipsoid (MJCF): semi-axes along x, y, z.
    Ellipsoid {
        /// Semi-axes (m).
        radii: [f64; 3],
    },
    /// A plane (MJCF, on the world): the half-space z ≤ 0 of its frame, infinite for
    /// collisions.
    Plane {
        /// Half sizes along x and y to draw (0: drawn to the scene's size).
        size: [f64; 2],
    },
    /// A triangle mesh read from a file (STL, OBJ, COLLADA).
    Mesh {
        /// The file name as written (`package://…`, `file://…`, or a path).
        uri: String,
        /// Where the file is: resolved at load time (see [`resolve_mesh`]).
        path: PathBuf,
        /// Per-axis scale applied to the vertices.
        scale: [f64; 3],
    },
}

/// The largest dimension a shape may have (m): beyond it a shape is garbage (a box of 1e308
/// m has no finite bounding box), refused with the size it gives.
pub const MAX_SIZE: f64 = 1e6;

impl Shape {
    /// Checks the shape's numbers: every dimension finite, positive (a capsule's length and a
    /// plane's drawn size may be 0) and at most [`MAX_SIZE`]; a mesh's scale finite, non-zero,
    /// and at most [`MAX_SIZE`] in size. The sentence says which number is wrong.
    pub fn check(&self) -> Result<(), String> {
        let check = |what: &str, v: f64, zero_ok: bool| {
            if !v.is_finite() || v < 0.0 || (v == 0.0 && !zero_ok) || v.abs() > MAX_SIZE {
                Err(format!(
                    "{} {what} {v}: expected {} and at most {MAX_SIZE} m",
                    self.word(),
                    if zero_ok { "≥ 0" } else { "> 0" }
                ))
            } else {
                Ok(())
            }
        };
        match self {
            Shape::Box { size } => size.iter().try_for_each(|v| check("size", *v, false)),
            Shape::Cylinder { radius, length } => {
                check("radius", *radius, false)?;
                check("length", *length, false)
            }
            Shape::Sphere { radius } => check("radius", *radius, false),
            Shape::Capsule { radius, length } => {
                check("radius", *radius, false)?;
                check("length", *length, true)
            }
            Shape::Ellipsoid { radii } => radii.iter().try_for_each(|v| check("radius", *v, false)),
            Shape::Plane { size } => size.iter().try_for_each(|v| check("size", *v, true)),
            Shape::Mesh { scale, .. } => scale
                .iter()
                .try_for_each(|v| check("scale", v.abs(), false)),
        }
    }

    /// The shape's word: `box`, `cylinder`, `sphere`, `capsule`, `ellipsoid`, `plane`, `mesh`.
    pub fn word(&self) -> &'static str {
        match self {
            Shape::Box { .. } => "box",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Sphere { .. } => "sphere",
            Shape::Capsule { .. } => "capsule",
            Shape::Ellipsoid { .. } => "ellipsoid",
            Shape::Plane { .. } => "plane",
            Shape::Mesh { .. } => "mesh",
        }
    }
}

/// What a shape is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Role {
    /// `<collision>`: what collision and distance queries use.
    Collision,
    /// `<visual>`: what pictures draw.
    Visual,
}

impl Role {
    /// `collision` or `visual`.
    pub fn word(self) -> &'static str {
        match self {
            Role::Collision => "collision",
            Role::Visual => "visual",
        }
    }
}

/// One shape fixed to a link.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// The link it is fixed to (index into [`Tree::links`](crate::Tree::links)).
    pub link: usize,
    /// Collision or visual.
    pub role: Role,
    /// The element's `name`, if it has one.
    pub name: Option<String>,
    /// Its pose in the link's frame (`<origin xyz rpy>`).
    pub origin: Se3,
    /// The shape.
    pub shape: Shape,
    /// Its colour (r, g, b, a in [0, 1]) where a visual's `<material>` gives one.
    pub rgba: Option<[f64; 4]>,
    /// MuJoCo's collision bits of an MJCF geom; None for URDF's shapes.
    pub bits: Option<ContactBits>,
}

/// MuJoCo's collision filter of a geom: geoms a and b may collide when
/// `contype_a & conaffinity_b` or `contype_b & conaffinity_a` is non-zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactBits {
    /// `contype` (MuJoCo's default 1).
    pub contype: u32,
    /// `conaffinity` (MuJoCo's default 1).
    pub conaffinity: u32,
}

impl ContactBits {
    /// MuJoCo's default bits (1, 1): what a URDF shape or an obstacle counts as.
    pub const DEFAULT: ContactBits = ContactBits {
        contype: 1,
        conaffinity: 1,
    };

    /// Whether two geoms' bits let them collide.
    pub fn compatible(self, other: ContactBits) -> bool {
        self.contype & other.conaffinity != 0 || other.contype & self.conaffinity != 0
    }
}

/// MuJoCo's contact rules of an MJCF model, beside its geoms' [`ContactBits`] (MuJoCo's
/// `mj_collision`): a pair of geoms is checked when their bodies are not welded together, the
/// parent filter lets them (`filterparent`: a body and its parent, by their weld bodies,
/// unless one is welded to the world), no `<contact><exclude>` names their two bodies, and
/// their bits are compatible; a `<contact><pair>` adds its two geoms whatever the rules.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactRules {
    /// Each MuJoCo body's link, with its parent body's link (None: the world body).
    pub body_parent: std::collections::HashMap<usize, Option<usize>>,
    /// The link that is MuJoCo's world body (the root of a fixed-base model); None with a
    /// floating base (the world is no link).
    pub world_link: Option<usize>,
    /// MuJoCo's `filterparent` flag (on unless `<option><flag filterparent="disable">`).
    pub filterparent: bool,
    /// `<contact><exclude>`: pairs of bodies (their links; None: the world) never checked.
    pub exclude: Vec<(Option<usize>, Option<usize>)>,
    /// `<contact><pair>`: pairs of geoms (by name) always checked.
    pub pairs: Vec<(String, String)>,
    /// The world body's geoms of a floating-base model, fixed in the world (their `link` is
    /// the root's and is not used).
    pub world: Vec<Geometry>,
}

/// Where a mesh file named `uri` is: `package://pkg/rest` (or `package:///pkg/rest`) in package `pkg`'s folder (found
/// below `package_paths`, then `ROS_PACKAGE_PATH`, then `AMENT_PREFIX_PATH`'s `share/`, as
/// xacro's `$(find pkg)`), `file:///abs` that path, anything else relative to `dir` (the robot
/// file's folder). The file itself is not opened here; an unknown package is an error.
pub fn resolve_mesh(uri: &str, dir: &Path, package_paths: &[PathBuf]) -> Result<PathBuf, String> {
    if let Some(rest) = uri.strip_prefix("package://") {
        // `package:///pkg/rest` (an empty package name, as example-robot-data's
        // talos_full_v2.urdf writes): a path below a package folder's parent, as Pinocchio
        // reads it — the same as `package://pkg/rest`.
        let rest = rest.trim_start_matches('/');
        let (pkg, inner) = rest.split_once('/').unwrap_or((rest, ""));
        if pkg.is_empty() {
            return Err(format!("mesh \"{uri}\": no package name after package://"));
        }
        let root = crate::xacro::find_package(pkg, package_paths).ok_or_else(|| {
            format!(
                "mesh \"{uri}\": package \"{pkg}\" not found (add its parent folder to the package paths, or set ROS_PACKAGE_PATH)"
            )
        })?;
        return Ok(root.join(inner));
    }
    if let Some(rest) = uri.strip_prefix("file://") {
        return Ok(PathBuf::from(rest));
    }
    if uri.contains("://") {
        return Err(format!(
            "mesh \"{uri}\": only package://, file:// and paths are read"
        ));
    }
    Ok(dir.join(uri))
}
