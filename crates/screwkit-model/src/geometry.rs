//! A robot's body as its files describe it: each link's `<collision>` and `<visual>` shapes
//! (URDF), fixed to the link's frame at an origin ([`Geometry`]). Descriptions only: a mesh is
//! its file's path, read when a collision query first needs it (`screwkit-collision`).
//!
//! Conventions (URDF's, kept by every reader): a box is centred on its origin with its full
//! `size` along x, y, z; a cylinder and a capsule have their axis along z, centred, `length`
//! the cylinder's (a capsule adds a half-sphere of `radius` at each end); a mesh's vertices are
//! multiplied by `scale` per axis, in the link's frame after the origin.
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

impl Shape {
    /// The shape's word: `box`, `cylinder`, `sphere`, `capsule`, `mesh`.
    pub fn word(&self) -> &'static str {
        match self {
            Shape::Box { .. } => "box",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Sphere { .. } => "sphere",
            Shape::Capsule { .. } => "capsule",
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
}

/// Where a mesh file named `uri` is: `package://pkg/rest` in package `pkg`'s folder (found
/// below `package_paths`, then `ROS_PACKAGE_PATH`, then `AMENT_PREFIX_PATH`'s `share/`, as
/// xacro's `$(find pkg)`), `file:///abs` that path, anything else relative to `dir` (the robot
/// file's folder). The file itself is not opened here; an unknown package is an error.
pub fn resolve_mesh(uri: &str, dir: &Path, package_paths: &[PathBuf]) -> Result<PathBuf, String> {
    if let Some(rest) = uri.strip_prefix("package://") {
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
