//! Reading MuJoCo's MJCF: the parts of the format that define kinematics, into the same
//! [`Tree`] as URDF, so that every algorithm works on an MJCF robot as on a URDF one.
//!
//! **What is read** (MuJoCo's XML reference): `<worldbody>` and nested `<body>` (`pos` and
//! every orientation form: `quat` (w x y z), `axisangle`, `euler` in `<compiler eulerseq>`,
//! `xyaxes`, `zaxis`), `<frame>` (a pose applied to what it holds), `<joint>` of type
//! `hinge`, `slide` and `free` (and `<freejoint>`) with `pos`, `axis`, `range`, `limited`,
//! `ref`; `<site>` (each a frame: a link fixed to its body; `site:NAME` when a body has the
//! name; `fromto` sites at their middle, z along the segment); `<inertial pos mass>` (the centre
//! of mass); `<default>` classes with `class` / `childclass` inheritance; `<include file>`
//! (paths relative to the main file's folder, as MuJoCo resolves them); `<compiler angle
//! eulerseq autolimits meshdir assetdir>` (degrees by default); `<equality><joint polycoef>` (a
//! linear coupling becomes a mimic joint).
//!
//! **Geoms** ([`crate::geometry`]): sphere, capsule, cylinder, box, ellipsoid, plane and mesh
//! (`<asset><mesh file scale>`, named from `meshdir`), with `size`, `fromto`, classes, `rgba`
//! or a material's; each is a collision shape when its `contype`/`conaffinity` let it collide
//! (or a `<contact><pair>` names it) and a visual one in MuJoCo's shown groups 0–2. MuJoCo's
//! contact rules come along ([`crate::geometry::ContactRules`]: bodies, `<contact><exclude>`
//! and `<pair>`, `<option><flag filterparent>`). A geom that cannot be used (an `hfield`, an
//! `sdf`, a primitive fitted to a mesh, an unknown mesh asset, a bad size) is a geometry
//! problem naming its line, reported by a body query; the kinematics loads regardless, and a
//! missing mesh file is found only when a query reads it. Actuators, sensors and textures are
//! read past.
//!
//! **Bodies as links.** Each body is a link of its name; MuJoCo's world body is the root link
//! `world`, unless a top-level body floats freely (a free joint) and no fixed-base mechanism
//! stands beside it: that body (of several, the one with the most bodies below it; the others
//! are read past with a warning, as props) is then the root and the tree has a floating base
//! ([`Tree::floating_root`]). Beside a fixed-base mechanism, free bodies are props, read past
//! with a warning. A body welded to its
//! parent (no joint) hangs from a fixed joint. MuJoCo moves a body by its joints in order,
//! B(q) = B₀ · M₁(q₁) ⋯ M_k(q_k), with B₀ the body's pose in its parent and, for a hinge at
//! `pos` p with unit `axis` a, M = Trans(p) Rot(a, q − ref) Trans(−p), for a slide
//! M = Trans(a (q − ref)). The tree writes this as a joint per MuJoCo joint whose child link
//! `BODY/JOINT` sits at the hinge's anchor (a URDF joint turns about its frame's origin), the
//! `Rot(a, −ref)` (or `Trans(−a ref)`) folded into the joint's origin so that its variable is
//! MuJoCo's `qpos` entry itself, and a fixed joint `Trans(−p)` to the body's own link when the
//! last anchor is off the body's origin. Ranges limit `qpos`, as in MuJoCo. Variables come in
//! MuJoCo's joint order (bodies depth first, joints in order), coupled followers excluded.
//!
//! **Refused** with an error naming the file, the line and the element: `ball` joints (three
//! rotations about one point: not a one-variable joint), a free joint below the root,
//! `coordinate="global"`, elements in a namespace, an unknown joint type, numbers that do not parse, a missing or circular
//! `<include>`, an unknown class, a polynomial coupling with terms above the linear,
//! `<replicate>` and `<attach>` (bodies MuJoCo generates: load the model MuJoCo saves).
//! **Warned about** ([`Tree::warnings`]): tendons, equalities other than joint couplings
//! (`connect`, `weld`: loop closures the tree does not hold), `<composite>` and `<flexcomp>`
//! soft bodies (read past), free bodies read past as props, bodies whose mass comes from their
//! geoms (`inertiafromgeom`) when one of them cannot be weighed (a plane, a mesh with
//! `inertia="convex"` or one that is open, `shellinertia`: left massless, never guessed). Solid
//! primitives are weighed as MuJoCo weighs them (density or mass, closed-form inertias), and
//! meshes by MuJoCo's pyramids ([`crate::mesh::mass_properties`]: `legacy`, `exact`, `shell`).

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use crate::error::{ErrorKind, ModelError};
use crate::geometry::{ContactBits, Geometry, Role, Shape};
use crate::input;
use crate::tree::{Inertial, JointKind, Limit, Mimic, QposLayout, Tree, TreeJointSpec};
use screwkit_lie::Se3;

/// Includes nested at most this deep.
pub const MAX_INCLUDE_DEPTH: usize = 32;
/// Elements in the document with every include spliced in, at most.
pub const MAX_ELEMENTS: usize = 1_000_000;
/// What one `<include>` counts for against [`MAX_ELEMENTS`] (so at most 10,000 file reads).
pub const INCLUDE_WEIGHT: usize = 100;

/// True when `text`'s root element is `<mujoco>` (an MJCF model), by content.
pub fn is_mjcf(text: &str) -> bool {
    let body = text.trim_start_matches('\u{feff}');
    // The first element after the prolog, comments and processing instructions.
    let mut rest = body;
    loop {
        rest = rest.trim_start();
        if let Some(r) = rest.strip_prefix("<?") {
            rest = r.split_once("?>").map_or("", |(_, r)| r);
        } else if let Some(r) = rest.strip_prefix("<!--") {
            rest = r.split_once("-->").map_or("", |(_, r)| r);
        } else if let Some(r) = rest.strip_prefix("<!") {
            rest = r.split_once('>').map_or("", |(_, r)| r);
        } else {
            break;
        }
    }
    rest.strip_prefix("<mujoco")
        .and_then(|r| r.chars().next())
        .is_some_and(|c| c.is_whitespace() || c == '>' || c == '/')
}

/// Loads an MJCF file into a [`Tree`].
pub fn load_file(path: impl AsRef<Path>) -> Result<Tree, ModelError> {
    let path = path.as_ref();
    let label = path.display().to_string();
    let bytes = input::read_file(path)?;
    let text = input::decode(&bytes).map_err(|kind| ModelError::new(label.clone(), kind))?;
    let dir = path.parent().unwrap_or(Path::new("."));
    // The main file is on the include stack: a file including it is a cycle.
    let mut reader = Reader {
        dir,
        stack: std::fs::canonicalize(path).into_iter().collect(),
        count: 0,
        bytes: bytes.len() as u64,
    };
    let root = reader.document(&text, &label, 0)?;
    Builder::new(&label, dir).build(&root)
}

/// Loads MJCF text into a [`Tree`]; `source` names it in errors, includes are read from `dir`.
pub fn load_str(text: &str, source: &str, dir: &Path) -> Result<Tree, ModelError> {
    read_str(text, source, dir).map(|(tree, _)| tree)
}

/// Loads MJCF text into a [`Tree`], with the model as one self-contained text: `text` itself
/// when it includes nothing, else the document with every `<include>` spliced in (what the
/// tree was read from, loadable without the included files: pickling, copies).
pub fn read_str(text: &str, source: &str, dir: &Path) -> Result<(Tree, String), ModelError> {
    let mut reader = Reader {
        dir,
        stack: Vec::new(),
        count: 0,
        bytes: text.len() as u64,
    };
    let root = reader.document(text, source, 0)?;
    let mut tree = Builder::new(source, dir).build(&root)?;
    // Mesh files are named from the main file's folder (through `meshdir`).
    tree.resolve_meshes(dir, &[]);
    // Each include counts INCLUDE_WEIGHT elements more than it splices in.
    let text = if reader.count > root.size() {
        let mut out = String::from("<?xml version=\"1.0\"?>\n");
        root.write(&mut out, 0);
        out
    } else {
        text.to_string()
    };
    Ok((tree, text))
}

/// An element with its includes spliced in, and where it was written.
#[derive(Debug, Clone)]
struct El {
    tag: String,
    attrs: Vec<(String, String)>,
    children: Vec<El>,
    file: String,
    line: u32,
}

impl El {
    /// Elements at and below this one.
    fn size(&self) -> usize {
        1 + self.children.iter().map(El::size).sum::<usize>()
    }

    /// This element as XML, indented by `depth` (attribute values escaped).
    fn write(&self, out: &mut String, depth: usize) {
        let pad = "  ".repeat(depth);
        out.push_str(&pad);
        out.push('<');
        out.push_str(&self.tag);
        for (k, v) in &self.attrs {
            out.push(' ');
            out.push_str(k);
            out.push_str("=\"");
            for c in v.chars() {
                match c {
                    '&' => out.push_str("&amp;"),
                    '<' => out.push_str("&lt;"),
                    '>' => out.push_str("&gt;"),
                    '"' => out.push_str("&quot;"),
                    '\n' => out.push_str("&#10;"),
                    '\t' => out.push_str("&#9;"),
                    '\r' => out.push_str("&#13;"),
                    c => out.push(c),
                }
            }
            out.push('"');
        }
        if self.children.is_empty() {
            out.push_str("/>\n");
            return;
        }
        out.push_str(">\n");
        for c in &self.children {
            c.write(out, depth + 1);
        }
        out.push_str(&pad);
        out.push_str("</");
        out.push_str(&self.tag);
        out.push_str(">\n");
    }

    fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }

    /// `<joint name="x">` (the element and its name, for messages).
    fn describe(&self) -> String {
        match self.attr("name") {
            Some(n) => format!("<{} name={}>", self.tag, shown(n)),
            None => format!("<{}>", self.tag),
        }
    }

    fn error(&self, message: impl std::fmt::Display) -> ModelError {
        ModelError::new(
            format!("{}:{}", self.file, self.line),
            ErrorKind::Mjcf(format!("{}: {message}", self.describe())),
        )
    }
}

/// The reading of one model: its files, spliced into one element tree, within the limits
/// that hold for the model as a whole, includes and all.
struct Reader<'d> {
    /// The folder includes are read from (MuJoCo: the main file's, for every include).
    dir: &'d Path,
    /// The files being read, outermost first (a file already on it is a circular include).
    stack: Vec<PathBuf>,
    /// Elements so far (each include counts [`INCLUDE_WEIGHT`]), against [`MAX_ELEMENTS`].
    count: usize,
    /// Bytes read so far, every file summed, against [`input::MAX_FILE_BYTES`].
    bytes: u64,
}

impl Reader<'_> {
    /// Parses one file of the model into [`El`]s, splicing `<include>`d files in place; its
    /// root's children sit `depth` levels deep in the whole model.
    fn document(&mut self, text: &str, source: &str, depth: usize) -> Result<El, ModelError> {
        let doc = input::parse_xml(text).map_err(|k| ModelError::new(source, k))?;
        let root = doc.root_element();
        if root.tag_name().name() != "mujoco" {
            return Err(ModelError::new(
                source,
                ErrorKind::Mjcf("the root element is not <mujoco>".into()),
            ));
        }
        let lines = input::Lines::new(text);
        self.convert(root, source, &lines, depth)
    }

    fn convert(
        &mut self,
        node: roxmltree::Node,
        source: &str,
        lines: &input::Lines,
        depth: usize,
    ) -> Result<El, ModelError> {
        self.count += 1;
        let line = lines.line(node.range().start);
        let at = || format!("{source}:{line}");
        if self.count > MAX_ELEMENTS {
            return Err(ModelError::new(
                at(),
                ErrorKind::TooLarge(format!(
                    "more than {MAX_ELEMENTS} elements with the includes spliced in"
                )),
            ));
        }
        // The nesting limit holds for the model as a whole: each file is parsed within it,
        // and an include adds its depth to its contents'.
        // As `input::parse_xml` counts: the document node is level 1, `<mujoco>` level 2.
        if depth + 2 > input::MAX_ELEMENT_DEPTH {
            return Err(ModelError::new(
                at(),
                ErrorKind::TooLarge(format!(
                    "elements nested more than {} levels deep, includes counted",
                    input::MAX_ELEMENT_DEPTH
                )),
            ));
        }
        // MJCF has no XML namespace: an element of another one is not MuJoCo's (MuJoCo refuses
        // it as a schema violation), never read as if it were.
        if node.tag_name().namespace().is_some() {
            return Err(ModelError::new(
                at(),
                ErrorKind::Mjcf(format!(
                    "<{}> is an element of another XML namespace, not of MJCF",
                    node.tag_name().name()
                )),
            ));
        }
        let mut el = El {
            tag: node.tag_name().name().to_string(),
            attrs: node
                .attributes()
                .map(|a| (a.name().to_string(), a.value().to_string()))
                .collect(),
            children: Vec::new(),
            file: source.to_string(),
            line,
        };
        for child in node.children().filter(|c| c.is_element()) {
            if child.tag_name().name() == "include" {
                let inc = self.convert(child, source, lines, depth + 1)?;
                // The included file's root stands in for the include: its children sit where
                // the include's siblings do.
                let children = self.include(&inc, depth)?;
                el.children.extend(children);
            } else {
                let c = self.convert(child, source, lines, depth + 1)?;
                el.children.push(c);
            }
        }
        Ok(el)
    }

    /// The children of the `<mujoco>` root of the file an `<include file>` names, read at
    /// `depth` (the depth of the include's parent).
    fn include(&mut self, inc: &El, depth: usize) -> Result<Vec<El>, ModelError> {
        let file = inc
            .attr("file")
            .ok_or_else(|| inc.error("needs a file attribute"))?;
        let path = self.dir.join(file);
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(inc.error(format!(
                "includes nested more than {MAX_INCLUDE_DEPTH} deep"
            )));
        }
        // The file named as given, shortened and escaped (an attribute can hold a megabyte or
        // control characters: the message says which include, not all it holds).
        let named = shown(file);
        let canonical = std::fs::canonicalize(&path).map_err(|e| {
            inc.error(format!(
                "cannot read the included file {named}: {}",
                e.kind()
            ))
        })?;
        if self.stack.contains(&canonical) {
            return Err(inc.error("the included file is already being read (a circular include)"));
        }
        // Each include counts as INCLUDE_WEIGHT elements: at most MAX_ELEMENTS / INCLUDE_WEIGHT
        // file reads, whatever the include graph (a diamond doubling at every level).
        self.count += INCLUDE_WEIGHT;
        if self.count > MAX_ELEMENTS {
            return Err(inc.error(format!(
                "too large: more than {} included files",
                MAX_ELEMENTS / INCLUDE_WEIGHT
            )));
        }
        let bytes = input::read_file(&path)
            .map_err(|e| inc.error(format!("the included file {named}: {}", e.kind)))?;
        // One budget for every file the model reads, summed: the same file included twice
        // counts twice (it is read and spliced twice).
        self.bytes += bytes.len() as u64;
        if self.bytes > input::MAX_FILE_BYTES {
            return Err(inc.error(format!(
                "too large: the model's files, includes counted each time, exceed {} MiB",
                input::MAX_FILE_BYTES >> 20
            )));
        }
        let text = input::decode(&bytes)
            .map_err(|k| inc.error(format!("the included file {named}: {k}")))?;
        self.stack.push(canonical);
        let label = path.display().to_string();
        let root = self.document(&text, &label, depth)?;
        self.stack.pop();
        Ok(root.children)
    }
}

/// `<compiler>` settings that change how numbers are read.
#[derive(Debug, Clone)]
struct Compiler {
    degree: bool,
    eulerseq: [u8; 3],
    autolimits: bool,
    /// `inertiafromgeom`: Some(true) "true", Some(false) "false", None "auto" (MuJoCo's
    /// default: geoms give the inertia of a body without `<inertial>`).
    inertiafromgeom: Option<bool>,
    /// `meshdir` (else `assetdir`): the folder mesh files are named from, relative to the
    /// main file's.
    meshdir: Option<String>,
    assetdir: Option<String>,
}

/// A `<mesh>` asset: its file (relative to the model's folder), scale, and why it cannot be
/// used, if it cannot.
#[derive(Debug, Clone)]
struct MeshAsset {
    file: Option<String>,
    scale: [f64; 3],
    problem: Option<String>,
    /// How its mass is spread when a body is weighed from it (`inertia`, MuJoCo's default
    /// `legacy`), or why it cannot be here.
    inertia: Result<crate::mesh::MeshInertia, String>,
}

/// One class of `<default>`: per element tag, the attributes it sets itself, and the class it
/// inherits the rest from. A lookup walks up the parents (at most the XML nesting limit), so
/// memory is the file's attributes once, however many classes inherit them (copying them into
/// every class asked for 10 GB of a 1.2 MB file).
#[derive(Debug, Default)]
struct Class {
    parent: Option<String>,
    own: HashMap<String, Vec<(String, String)>>,
}

/// A body (or frame) context while walking: the class its elements take by default.
#[derive(Debug, Clone)]
struct Context<'a> {
    class: &'a str,
}

/// A body's geoms weighed (MuJoCo's `inertiafromgeom`): mass, first moment and rotational
/// inertia about the body's origin, or why one geom could not be weighed.
#[derive(Debug, Clone, Default)]
struct GeomSum {
    mass: f64,
    first: Vector3<f64>,
    about_origin: nalgebra::Matrix3<f64>,
    unweighed: Option<String>,
}

/// A solid primitive's volume and its principal moments per unit mass about its centre, in its
/// own frame (MuJoCo's shapes: a capsule is a cylinder and two hemispheres, its axis z), or
/// `None` for a shape without a closed form here (a mesh, a plane).
fn solid(shape: &Shape) -> Option<(f64, [f64; 3])> {
    use std::f64::consts::PI;
    Some(match *shape {
        Shape::Sphere { radius: r } => {
            let k = 0.4 * r * r;
            (4.0 / 3.0 * PI * r * r * r, [k, k, k])
        }
        Shape::Box { size } => {
            let [a, b, c] = size.map(|x| x / 2.0);
            let k = |u: f64, v: f64| (u * u + v * v) / 3.0;
            (8.0 * a * b * c, [k(b, c), k(a, c), k(a, b)])
        }
        Shape::Cylinder {
            radius: r,
            length: h,
        } => {
            let side = (3.0 * r * r + h * h) / 12.0;
            (PI * r * r * h, [side, side, r * r / 2.0])
        }
        Shape::Ellipsoid { radii: [a, b, c] } => {
            let k = |u: f64, v: f64| (u * u + v * v) / 5.0;
            (4.0 / 3.0 * PI * a * b * c, [k(b, c), k(a, c), k(a, b)])
        }
        Shape::Capsule {
            radius: r,
            length: h,
        } => {
            // Per unit density: the cylinder and the sphere its two hemispheres make.
            let (vc, vs) = (PI * r * r * h, 4.0 / 3.0 * PI * r * r * r);
            let side = vc * (h * h / 12.0 + r * r / 4.0)
                + vs * (0.4 * r * r + h * h / 4.0 + 3.0 * h * r / 8.0);
            let axial = vc * r * r / 2.0 + vs * 0.4 * r * r;
            let v = vc + vs;
            (v, [side / v, side / v, axial / v])
        }
        _ => return None,
    })
}

struct Builder {
    source: String,
    /// The main file's folder (mesh files are named from it).
    dir: PathBuf,
    /// Meshes weighed (file, scale, mode), each once.
    weighed_meshes: HashMap<
        (PathBuf, [u64; 3], crate::mesh::MeshInertia),
        Result<crate::mesh::MeshMass, String>,
    >,
    compiler: Compiler,
    classes: HashMap<String, Class>,
    links: Vec<String>,
    joints: Vec<(TreeJointSpec, String, String)>,
    /// MuJoCo's `ref` of each joint by name (for couplings).
    refs: HashMap<String, f64>,
    inertials: Vec<(String, Inertial)>,
    warnings: Vec<String>,
    /// Bodies whose mass MuJoCo takes from their geoms; after the bodies are read, those whose
    /// geoms could not all be weighed (one warning).
    geom_mass: Vec<String>,
    /// Why the first of `geom_mass`'s bodies could not be weighed.
    unweighed_why: Option<String>,
    /// The geoms' masses summed per body (about the body's origin), for `geom_mass`'s bodies.
    geom_sums: HashMap<String, GeomSum>,
    bodies: usize,
    floating_root: bool,
    /// Every body's name in the file (sites named alike are renamed).
    body_names: std::collections::HashSet<String>,
    /// Every name the file gives (bodies, joints, sites) and every name made here: a name
    /// screwkit makes (`b_weld`, `b_joint0`, `b/j`, `s_site`, `site:s`) takes a `~k` suffix
    /// when the file already has it, so it never collides with one of the file's own.
    taken: std::collections::HashSet<String>,
    /// The joints' names, given and made (a separate namespace from the links').
    taken_joints: std::collections::HashSet<String>,
    /// The next `~k` to try for a base name (so making names stays linear).
    next_suffix: HashMap<String, usize>,
    /// The sites' own names so far: MuJoCo refuses one given twice.
    site_names: std::collections::HashSet<String>,
    /// The links so far, as a set (a site's name is checked against them).
    link_set: std::collections::HashSet<String>,
    /// Top-level bodies read past (props beside the robot).
    skip: Vec<*const El>,
    /// Each joint element's address in MuJoCo's `qpos` of the whole model.
    addresses: HashMap<*const El, usize>,
    /// The tree's joints and base in that `qpos`.
    layout: QposLayout,
    /// `<asset><mesh>` by name.
    meshes: HashMap<String, MeshAsset>,
    /// `<asset><material>` colours by name.
    materials: HashMap<String, [f64; 4]>,
    /// Geoms read so far, with their link's name.
    geoms: Vec<(String, Geometry)>,
    /// The world body's geoms of a free-floating model (fixed in the world).
    world_geoms: Vec<Geometry>,
    /// Geoms that cannot be used, one sentence each.
    geometry_problems: Vec<String>,
    /// `<option gravity>`, when given.
    gravity: Option<[f64; 3]>,
    /// Each body's link with its parent body's (None: the world).
    body_parent: Vec<(String, Option<String>)>,
    /// The geoms a `<contact><pair>` names (they collide whatever their bits).
    pair_geoms: std::collections::HashSet<String>,
    /// `<option><flag filterparent>`.
    filterparent: bool,
}

/// A pose as MuJoCo composes them.
type Pose = Isometry3<f64>;

impl Builder {
    fn new(source: &str, dir: &Path) -> Builder {
        Builder {
            source: source.to_string(),
            dir: dir.to_path_buf(),
            weighed_meshes: HashMap::new(),
            compiler: Compiler {
                degree: true,
                eulerseq: *b"xyz",
                autolimits: true,
                inertiafromgeom: None,
                meshdir: None,
                assetdir: None,
            },
            meshes: HashMap::new(),
            materials: HashMap::new(),
            geoms: Vec::new(),
            world_geoms: Vec::new(),
            geometry_problems: Vec::new(),
            gravity: None,
            body_parent: Vec::new(),
            pair_geoms: std::collections::HashSet::new(),
            filterparent: true,
            geom_mass: Vec::new(),
            unweighed_why: None,
            geom_sums: HashMap::new(),
            classes: HashMap::new(),
            links: Vec::new(),
            joints: Vec::new(),
            refs: HashMap::new(),
            inertials: Vec::new(),
            warnings: Vec::new(),
            bodies: 0,
            floating_root: false,
            body_names: std::collections::HashSet::new(),
            taken: std::collections::HashSet::new(),
            taken_joints: std::collections::HashSet::new(),
            next_suffix: HashMap::new(),
            site_names: std::collections::HashSet::new(),
            link_set: std::collections::HashSet::new(),
            skip: Vec::new(),
            addresses: HashMap::new(),
            layout: QposLayout {
                len: 0,
                base: None,
                joints: Vec::new(),
            },
        }
    }

    /// MuJoCo's `qpos` addresses of the joints below `holder` (bodies depth first, each
    /// body's joints before its children; a free joint takes 7 entries, a ball 4, a hinge or
    /// slide 1), props included, from `adr` on.
    fn number_joints(&mut self, holder: &El, class: &str, adr: &mut usize) {
        for c in &holder.children {
            let class = c.attr("childclass").unwrap_or(class);
            match c.tag.as_str() {
                "body" => {
                    for j in c
                        .children
                        .iter()
                        .filter(|j| j.tag == "joint" || j.tag == "freejoint")
                    {
                        self.addresses.insert(j as *const El, *adr);
                        let jtype = if j.tag == "freejoint" {
                            "free"
                        } else {
                            self.joint_type(j, class)
                        };
                        *adr += match jtype {
                            "free" => 7,
                            "ball" => 4,
                            _ => 1,
                        };
                    }
                    self.number_joints(c, class, adr);
                }
                "frame" => self.number_joints(c, class, adr),
                _ => {}
            }
        }
    }

    fn build(mut self, root: &El) -> Result<Tree, ModelError> {
        for c in root.children.iter().filter(|c| c.tag == "compiler") {
            self.read_compiler(c)?;
        }
        for d in root.children.iter().filter(|c| c.tag == "default") {
            self.read_defaults(d, None, true)?;
        }
        self.classes.entry("main".into()).or_default();
        self.read_assets(root);
        for o in root.children.iter().filter(|c| c.tag == "option") {
            if let Some(g) = self.numbers(o, "main", "gravity", 3)? {
                self.gravity = Some([g[0], g[1], g[2]]);
            }
            for f in o.children.iter().filter(|c| c.tag == "flag") {
                if let Some(v) = f.attr("filterparent") {
                    self.filterparent = v != "disable";
                }
            }
        }
        for c in root.children.iter().filter(|c| c.tag == "contact") {
            for p in c.children.iter().filter(|p| p.tag == "pair") {
                for k in ["geom1", "geom2"] {
                    if let Some(g) = p.attr(k) {
                        self.pair_geoms.insert(g.to_string());
                    }
                }
            }
        }
        let name = root.attr("model").unwrap_or("mujoco").to_string();
        let mut stack: Vec<&El> = vec![root];
        while let Some(e) = stack.pop() {
            if let Some(n) = own_name(e) {
                if e.tag == "body" {
                    self.body_names.insert(n.to_string());
                }
                match e.tag.as_str() {
                    "body" | "site" => {
                        self.taken.insert(n.to_string());
                    }
                    "joint" | "freejoint" => {
                        self.taken_joints.insert(n.to_string());
                    }
                    _ => {}
                }
            }
            stack.extend(e.children.iter());
        }
        let world: Vec<&El> = root
            .children
            .iter()
            .filter(|c| c.tag == "worldbody")
            .collect();
        // Top-level bodies (within frames too): is the file one free-floating body?
        let mut top = Vec::new();
        for w in &world {
            collect_bodies(w, &mut top);
        }
        // Which body is the robot when some top-level bodies float freely: the only one; else,
        // beside a fixed-base mechanism, none (the world is the root and the free bodies are
        // props, read past); else the free body with the most bodies below it (the others
        // read past: a scene's ball, a box).
        // A joint's type may come from the body's childclass (MuJoCo's class rules).
        let is_free = |b: &El| {
            let class = b.attr("childclass").unwrap_or("main");
            b.children.iter().any(|c| {
                c.tag == "freejoint" || (c.tag == "joint" && self.joint_type(c, class) == "free")
            })
        };
        let free: Vec<&El> = top.iter().copied().filter(|b| is_free(b)).collect();
        let fixed_mechanism = top.iter().any(|b| !is_free(b) && has_joints(b));
        let robot: Option<&El> = match (free.as_slice(), fixed_mechanism) {
            ([], _) | (_, true) => None,
            _ => free
                .iter()
                .copied()
                .max_by_key(|b| (count_bodies(b), std::cmp::Reverse(b.line))),
        };
        let mut adr = 0;
        for w in &world {
            self.number_joints(w, "main", &mut adr);
        }
        self.layout.len = adr;
        let ctx = Context { class: "main" };
        let read_past: Vec<&El> = match robot {
            Some(r) => top
                .iter()
                .copied()
                .filter(|b| !std::ptr::eq(*b, r))
                .collect(),
            None => free.clone(),
        };
        for b in &read_past {
            let why = match robot {
                Some(r) => format!(
                    "the tree is the free-floating body {} (the one with the most bodies)",
                    r.attr("name").unwrap_or("(unnamed)")
                ),
                None => "a free-floating body beside the fixed-base mechanism (a prop)".into(),
            };
            self.warnings.push(format!(
                "line {}: top-level body {} read past: {why}",
                b.line,
                b.attr("name").unwrap_or("(unnamed)"),
            ));
            self.skip.push(*b as *const El);
        }
        if let Some(body) = robot {
            self.floating_root = true;
            self.body(body, None, &Pose::identity(), &ctx)?;
            for w in &world {
                self.world_geoms_of(w, &Pose::identity(), "main")?;
            }
            for w in &world {
                for s in w.children.iter().filter(|c| c.tag == "site") {
                    self.warnings.push(format!(
                        "line {}: site {} on the world body is not part of the free-floating robot's tree",
                        s.line,
                        s.attr("name").unwrap_or("(unnamed)")
                    ));
                }
            }
        } else {
            self.push_link("world".into());
            self.body_parent.push(("world".into(), None));
            for w in &world {
                self.contents(w, "world", &Pose::identity(), &ctx)?;
            }
        }
        self.weighed_inertials();
        if let Some(first) = self.geom_mass.first() {
            let count = match self.geom_mass.len() {
                1 => format!("body {first} takes its"),
                n => format!("{n} bodies ({first}, …) take their"),
            };
            self.warnings.push(format!(
                "{count} mass from geoms in MuJoCo (inertiafromgeom), which screwkit could not \
                 weigh ({first}: {}): massless here",
                self.unweighed_why
                    .as_deref()
                    .unwrap_or("a geom not weighed")
            ));
        }
        self.read_equalities(root)?;
        for t in root.children.iter().filter(|c| c.tag == "tendon") {
            if !t.children.is_empty() {
                self.warnings.push(format!(
                    "line {1}: {0} tendon(s) read past (in MuJoCo they act in the dynamics; the kinematic tree holds none)",
                    t.children.len(),
                    t.line
                ));
            }
        }
        let mut tree = Tree::new(
            name,
            self.source.clone(),
            std::mem::take(&mut self.links),
            std::mem::take(&mut self.joints),
        )?;
        for (link, inertial) in std::mem::take(&mut self.inertials) {
            if let Ok(i) = tree.link(&link) {
                tree.inertials[i] = Some(inertial);
            }
        }
        tree.floating_root = self.floating_root;
        tree.gravity = self.gravity;
        self.geometry_into(&mut tree, root);
        // The file's warnings first, then the tree's own (mimic followers' limits).
        let own = std::mem::take(&mut tree.warnings);
        tree.warnings = std::mem::take(&mut self.warnings);
        tree.warnings.extend(own);
        tree.qpos_layout = Some(std::mem::replace(
            &mut self.layout,
            QposLayout {
                len: 0,
                base: None,
                joints: Vec::new(),
            },
        ));
        Ok(tree)
    }

    /// `base`, or `base~k` with the least k that is free: a name made here never takes one the
    /// file gives (nor one made before).
    fn fresh(&mut self, base: String) -> String {
        fresh_in(&mut self.taken, &mut self.next_suffix, base)
    }

    /// [`Builder::fresh`] among the joints' names.
    fn fresh_joint(&mut self, base: String) -> String {
        fresh_in(&mut self.taken_joints, &mut self.next_suffix, base)
    }

    fn push_link(&mut self, name: String) {
        self.link_set.insert(name.clone());
        self.links.push(name);
    }

    fn read_compiler(&mut self, c: &El) -> Result<(), ModelError> {
        if let Some(a) = c.attr("angle") {
            self.compiler.degree = match a {
                "degree" => true,
                "radian" => false,
                other => {
                    return Err(c.error(format!("angle=\"{other}\": expected degree or radian")))
                }
            };
        }
        if let Some(seq) = c.attr("eulerseq") {
            let b = seq.as_bytes();
            if b.len() != 3 || !b.iter().all(|c| b"xyzXYZ".contains(c)) {
                return Err(c.error(format!(
                    "eulerseq=\"{seq}\": expected three of x, y, z (rotating axes) or X, Y, Z (fixed axes)"
                )));
            }
            self.compiler.eulerseq = [b[0], b[1], b[2]];
        }
        if let Some(a) = c.attr("autolimits") {
            self.compiler.autolimits = parse_bool(c, "autolimits", a)?;
        }
        if let Some(a) = c.attr("inertiafromgeom") {
            self.compiler.inertiafromgeom = match a {
                "auto" => None,
                other => Some(parse_bool(c, "inertiafromgeom", other)?),
            };
        }
        if let Some(d) = c.attr("meshdir") {
            self.compiler.meshdir = Some(d.to_string());
        }
        if let Some(d) = c.attr("assetdir") {
            self.compiler.assetdir = Some(d.to_string());
        }
        match c.attr("coordinate") {
            None | Some("local") => {}
            Some("global") => {
                return Err(c.error(
                    "coordinate=\"global\" is not read (MuJoCo 2.3.4 and later refuse it too): \
                     convert the model by loading and saving it in MuJoCo 2.3.3",
                ))
            }
            Some(other) => return Err(c.error(format!("coordinate=\"{other}\": expected local"))),
        }
        Ok(())
    }

    /// A `<default>` element: its class (`main` at the top) inherits `parent`'s attributes.
    fn read_defaults(&mut self, d: &El, parent: Option<&str>, top: bool) -> Result<(), ModelError> {
        let name = match d.attr("class") {
            Some(n) => n.to_string(),
            None if top => "main".to_string(),
            None => return Err(d.error("a nested <default> needs a class name")),
        };
        let mut class = Class {
            parent: parent.map(str::to_string),
            own: HashMap::new(),
        };
        for e in d.children.iter().filter(|c| c.tag != "default") {
            let entry = class.own.entry(e.tag.clone()).or_default();
            for (k, v) in &e.attrs {
                match entry.iter_mut().find(|(ek, _)| ek == k) {
                    Some(slot) => slot.1 = v.clone(),
                    None => entry.push((k.clone(), v.clone())),
                }
            }
        }
        if self.classes.contains_key(&name) {
            return Err(d.error(format!("class \"{name}\" is defined twice")));
        }
        self.classes.insert(name.clone(), class);
        for child in d.children.iter().filter(|c| c.tag == "default") {
            self.read_defaults(child, Some(&name), false)?;
        }
        Ok(())
    }

    /// An attribute of `e`: its own, else its class's (`class`, or the context's childclass),
    /// else the nearest ancestor class's. An orientation a class gives in one form hides the
    /// other forms its ancestors give.
    fn attr<'e>(&'e self, e: &'e El, class: &str, name: &str) -> Option<&'e str> {
        if let Some(v) = e.attr(name) {
            return Some(v);
        }
        let orientation = ORIENTATIONS.contains(&name);
        let mut at = Some(e.attr("class").unwrap_or(class));
        while let Some(c) = at {
            let class = self.classes.get(c)?;
            if let Some(attrs) = class.own.get(&e.tag) {
                if let Some((_, v)) = attrs.iter().find(|(k, _)| k == name) {
                    return Some(v.as_str());
                }
                if orientation
                    && attrs
                        .iter()
                        .any(|(k, _)| ORIENTATIONS.contains(&k.as_str()))
                {
                    return None;
                }
            }
            at = class.parent.as_deref();
        }
        None
    }

    fn check_class(&self, e: &El) -> Result<(), ModelError> {
        match e.attr("class") {
            Some(c) if !self.classes.contains_key(c) => {
                Err(e.error(format!("class \"{c}\" is not defined in any <default>")))
            }
            _ => Ok(()),
        }
    }

    fn joint_type<'e>(&'e self, e: &'e El, class: &str) -> &'e str {
        self.attr(e, class, "type").unwrap_or("hinge")
    }

    /// Numbers of attribute `name` (exactly `n` of them), or `None` when absent.
    fn numbers(
        &self,
        e: &El,
        class: &str,
        name: &str,
        n: usize,
    ) -> Result<Option<Vec<f64>>, ModelError> {
        let Some(text) = self.attr(e, class, name) else {
            return Ok(None);
        };
        let values: Vec<f64> = text
            .split_whitespace()
            .map(|t| t.parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| e.error(format!("{name}={}: not {n} numbers", shown(text))))?;
        if values.len() != n {
            return Err(e.error(format!(
                "{name}={}: expected {n} numbers, got {}",
                shown(text),
                values.len()
            )));
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(e.error(format!("{name}={}: not finite", shown(text))));
        }
        Ok(Some(values))
    }

    fn angle(&self, a: f64) -> f64 {
        if self.compiler.degree {
            a.to_radians()
        } else {
            a
        }
    }

    /// An element's pose in its parent: `pos` and one orientation form.
    fn pose(&self, e: &El, class: &str) -> Result<Pose, ModelError> {
        let pos = self.numbers(e, class, "pos", 3)?.unwrap_or(vec![0.0; 3]);
        let own: Vec<&str> = ORIENTATIONS
            .iter()
            .copied()
            .filter(|f| e.attr(f).is_some())
            .collect();
        if own.len() > 1 {
            return Err(e.error(format!(
                "more than one orientation ({}): give one",
                own.join(", ")
            )));
        }
        let form = own.first().copied().or_else(|| {
            ORIENTATIONS
                .iter()
                .copied()
                .find(|f| self.attr(e, class, f).is_some())
        });
        let rotation = match form {
            None => UnitQuaternion::identity(),
            Some(f) => self.orientation(e, class, f)?,
        };
        Ok(Isometry3::from_parts(
            Translation3::new(pos[0], pos[1], pos[2]),
            rotation,
        ))
    }

    /// A site's pose: `fromto` (a capsule's or cylinder's two ends: the frame at their middle,
    /// z along the segment, the minimal rotation from (0, 0, 1)) when given, else `pos` and its
    /// orientation.
    fn site_pose(&self, e: &El, class: &str) -> Result<Pose, ModelError> {
        let Some(ft) = self.numbers(e, class, "fromto", 6)? else {
            return self.pose(e, class);
        };
        let (a, b) = (
            Vector3::new(ft[0], ft[1], ft[2]),
            Vector3::new(ft[3], ft[4], ft[5]),
        );
        // MuJoCo's frame of a fromto element has z from the second end towards the first
        // (checked against MuJoCo in test_mjcf.py).
        let d = a - b;
        if d.norm() < 1e-10 {
            return Err(e.error("fromto: the two ends coincide"));
        }
        let mid = (a + b) / 2.0;
        Ok(Isometry3::from_parts(
            Translation3::new(mid.x, mid.y, mid.z),
            z_to(d.normalize()),
        ))
    }

    fn orientation(
        &self,
        e: &El,
        class: &str,
        form: &str,
    ) -> Result<UnitQuaternion<f64>, ModelError> {
        let bad = |what: &str| e.error(format!("{form}: {what}"));
        match form {
            "quat" => {
                let q = self.numbers(e, class, "quat", 4)?.unwrap_or_default();
                let largest = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let quat = nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]);
                if largest == 0.0 || largest * (quat / largest).norm() < 1e-10 {
                    return Err(bad("a zero quaternion"));
                }
                Ok(UnitQuaternion::from_quaternion(quat / largest))
            }
            "axisangle" => {
                let v = self.numbers(e, class, "axisangle", 4)?.unwrap_or_default();
                let axis =
                    unit(Vector3::new(v[0], v[1], v[2])).ok_or_else(|| bad("a zero axis"))?;
                Ok(UnitQuaternion::from_axis_angle(
                    &Unit::new_unchecked(axis),
                    self.angle(v[3]),
                ))
            }
            "euler" => {
                let v = self.numbers(e, class, "euler", 3)?.unwrap_or_default();
                let mut q = UnitQuaternion::identity();
                for (i, &c) in self.compiler.eulerseq.iter().enumerate() {
                    let axis = match c.to_ascii_lowercase() {
                        b'x' => Vector3::x_axis(),
                        b'y' => Vector3::y_axis(),
                        _ => Vector3::z_axis(),
                    };
                    let r = UnitQuaternion::from_axis_angle(&axis, self.angle(v[i]));
                    // Lower case: about the rotating (intrinsic) axes; upper case: fixed axes.
                    q = if c.is_ascii_lowercase() { q * r } else { r * q };
                }
                Ok(q)
            }
            "xyaxes" => {
                let v = self.numbers(e, class, "xyaxes", 6)?.unwrap_or_default();
                let x = Vector3::new(v[0], v[1], v[2]);
                let y = Vector3::new(v[3], v[4], v[5]);
                let x = unit(x).ok_or_else(|| bad("a zero x axis"))?;
                // y scaled to unit size first, so that 1e154 and more do not overflow.
                let y = unit(y).ok_or_else(|| bad("a zero y axis"))?;
                let y = y - x * x.dot(&y);
                if y.norm() < 1e-10 {
                    return Err(bad("y is parallel to x"));
                }
                let y = y.normalize();
                let z = x.cross(&y);
                let m = nalgebra::Matrix3::from_columns(&[x, y, z]);
                Ok(UnitQuaternion::from_rotation_matrix(
                    &nalgebra::Rotation3::from_matrix_unchecked(m),
                ))
            }
            _ => {
                let v = self.numbers(e, class, "zaxis", 3)?.unwrap_or_default();
                let z = unit(Vector3::new(v[0], v[1], v[2])).ok_or_else(|| bad("a zero axis"))?;
                Ok(z_to(z))
            }
        }
    }

    /// A body under `parent` (None: the free-floating root), `offset` the pose of the frame it
    /// was written in relative to the parent link.
    fn body(
        &mut self,
        body: &El,
        parent: Option<&str>,
        offset: &Pose,
        ctx: &Context,
    ) -> Result<(), ModelError> {
        self.bodies += 1;
        self.check_class(body)?;
        let childclass = match body.attr("childclass") {
            Some(c) => {
                if !self.classes.contains_key(c) {
                    return Err(body.error(format!(
                        "childclass \"{c}\" is not defined in any <default>"
                    )));
                }
                c.to_string()
            }
            None => ctx.class.to_string(),
        };
        let name = match own_name(body) {
            Some(n) => n.to_string(),
            None => self.fresh(format!("body_{}", self.bodies)),
        };
        let local = offset * self.pose(body, "main")?;
        self.body_parent
            .push((name.clone(), parent.map(str::to_string)));
        let joints: Vec<&El> = body
            .children
            .iter()
            .filter(|c| c.tag == "joint" || c.tag == "freejoint")
            .collect();
        match parent {
            None => {
                // The free-floating root: its free joint is the floating base.
                if joints.len() != 1 {
                    return Err(body.error("a free-floating body takes only its free joint"));
                }
                self.layout.base = self.addresses.get(&(joints[0] as *const El)).copied();
                self.push_link(name.clone());
            }
            Some(parent) => self.joints_of(&name, parent, &local, &joints, &childclass)?,
        }
        // MuJoCo gives this body the inertia of its geoms (inertiafromgeom "true", or "auto"
        // without <inertial>); screwkit does not compute it yet: counted, and said once.
        let inertial = body.children.iter().any(|c| c.tag == "inertial");
        // Geoms in a <frame> are the body's too.
        fn has_geom(e: &El) -> bool {
            e.children
                .iter()
                .any(|c| c.tag == "geom" || (c.tag == "frame" && has_geom(c)))
        }
        let geoms = has_geom(body);
        let from_geoms = match self.compiler.inertiafromgeom {
            Some(true) => geoms,
            Some(false) => false,
            None => geoms && !inertial,
        };
        if from_geoms {
            self.geom_mass.push(name.clone());
        }
        if let Some(i) = body.children.iter().find(|c| c.tag == "inertial") {
            let mass = self.numbers(i, "main", "mass", 1)?.map_or(0.0, |m| m[0]);
            if mass < 0.0 {
                return Err(i.error(format!("mass {mass} is negative")));
            }
            // The inertial frame (pos and its orientation: quat, euler, …) and the tensor in
            // it: `diaginertia` (its principal moments) or `fullinertia` (M11 M22 M33 M12 M13
            // M23), turned into the body's axes.
            let frame = self.pose(i, "main")?;
            let pos = frame.translation.vector;
            let diag = self.numbers(i, "main", "diaginertia", 3)?;
            let full = self.numbers(i, "main", "fullinertia", 6)?;
            let local = match (diag, full) {
                (Some(_), Some(_)) => {
                    return Err(i.error("both diaginertia and fullinertia: give one"));
                }
                (Some(d), None) => [d[0], 0.0, 0.0, d[1], 0.0, d[2]],
                (None, Some(f)) => [f[0], f[3], f[4], f[1], f[5], f[2]],
                (None, None) => [0.0; 6],
            };
            let r = frame.rotation.to_rotation_matrix();
            self.inertials.push((
                name.clone(),
                Inertial {
                    mass,
                    com: [pos.x, pos.y, pos.z],
                    inertia: crate::tree::rotate_inertia(&local, r.matrix()),
                },
            ));
        }
        let ctx = Context { class: &childclass };
        self.contents(body, &name, &Pose::identity(), &ctx)
    }

    /// What a body (or frame, or the world) holds: sites, frames, bodies.
    fn contents(
        &mut self,
        holder: &El,
        link: &str,
        offset: &Pose,
        ctx: &Context,
    ) -> Result<(), ModelError> {
        for c in &holder.children {
            match c.tag.as_str() {
                "site" => {
                    self.check_class(c)?;
                    // MuJoCo names bodies and sites apart: a site named like a body (or like
                    // another site) is the frame `site:NAME`.
                    if let Some(n) = own_name(c) {
                        if !self.site_names.insert(n.to_string()) {
                            return Err(c.error("this site name is given twice (MuJoCo refuses it)"));
                        }
                    }
                    let name = match own_name(c) {
                        None => self.fresh(format!("{link}/site_{}", self.links.len())),
                        Some(n) if self.body_names.contains(n) || self.link_set.contains(n) => {
                            self.fresh(format!("site:{n}"))
                        }
                        Some(n) => n.to_string(),
                    };
                    let joint = self.fresh_joint(format!("{name}_site"));
                    let pose = offset * self.site_pose(c, ctx.class)?;
                    self.push_link(name.clone());
                    self.joints.push((
                        spec(
                            joint,
                            JointKind::Fixed,
                            &pose,
                            [1.0, 0.0, 0.0],
                            None,
                        ),
                        link.to_string(),
                        name,
                    ));
                }
                "frame" => {
                    self.check_class(c)?;
                    let class = match c.attr("childclass") {
                        Some(k) if !self.classes.contains_key(k) => {
                            return Err(c.error(format!(
                                "childclass \"{k}\" is not defined in any <default>"
                            )))
                        }
                        Some(k) => k.to_string(),
                        None => ctx.class.to_string(),
                    };
                    let pose = offset * self.pose(c, "main")?;
                    self.contents(c, link, &pose, &Context { class: &class })?;
                }
                "replicate" | "attach" => {
                    return Err(c.error(format!(
                        "<{}> (bodies MuJoCo generates when compiling) is not read: save the compiled model with MuJoCo's mj_saveLastXML and load that",
                        c.tag
                    )))
                }
                "composite" | "flexcomp" => self.warnings.push(format!(
                    "line {}: <{}> read past (the soft body's generated bodies and joints are not in the tree)",
                    c.line, c.tag
                )),
                "geom" => {
                    self.check_class(c)?;
                    let found = self.geom(c, offset, ctx.class);
                    if self.geom_mass.iter().any(|b| b == link) {
                        self.weigh(c, ctx.class, link, found.as_ref().map(|(g, _)| g));
                    }
                    if let Some(g) = found {
                        self.push_geom(Some(link), g);
                    }
                }
                "body" if self.skip.contains(&(c as *const El)) => {}
                "body" => self.body(c, Some(link), offset, ctx)?,
                "joint" | "freejoint" if holder.tag != "body" => {
                    return Err(c.error(format!(
                        "a joint belongs in a <body>, not in <{}>",
                        holder.tag
                    )))
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The tree joints of a body's MuJoCo joints (module documentation), ending at the
    /// body's own link.
    fn joints_of(
        &mut self,
        name: &str,
        parent: &str,
        local: &Pose,
        joints: &[&El],
        class: &str,
    ) -> Result<(), ModelError> {
        if joints.is_empty() {
            self.push_link(name.to_string());
            let weld = self.fresh_joint(format!("{name}_weld"));
            self.joints.push((
                spec(weld, JointKind::Fixed, local, [1.0, 0.0, 0.0], None),
                parent.to_string(),
                name.to_string(),
            ));
            return Ok(());
        }
        // `from`: the pose of the next joint's frame in the current link, before its anchor.
        let (mut from, mut current) = (*local, parent.to_string());
        let mut anchor = Vector3::zeros();
        for (k, j) in joints.iter().enumerate() {
            self.check_class(j)?;
            let jname = match own_name(j) {
                Some(n) => n.to_string(),
                None => self.fresh_joint(format!("{name}_joint{k}")),
            };
            let jtype = if j.tag == "freejoint" {
                "free"
            } else {
                self.joint_type(j, class)
            };
            let pos = match jtype {
                "slide" => Vector3::zeros(),
                _ => Vector3::from_vec(self.numbers(j, class, "pos", 3)?.unwrap_or(vec![0.0; 3])),
            };
            let axis = Vector3::from_vec(
                self.numbers(j, class, "axis", 3)?
                    .unwrap_or(vec![0.0, 0.0, 1.0]),
            );
            if axis.norm() < 1e-10 {
                return Err(j.error("axis is zero"));
            }
            let axis = axis.normalize();
            let reference = self.numbers(j, class, "ref", 1)?.map_or(0.0, |r| r[0]);
            let (kind, fold, reference) = match jtype {
                "hinge" => {
                    let r = self.angle(reference);
                    (
                        JointKind::Revolute,
                        Isometry3::from_parts(
                            Translation3::identity(),
                            UnitQuaternion::from_axis_angle(&Unit::new_unchecked(axis), -r),
                        ),
                        r,
                    )
                }
                "slide" => (
                    JointKind::Prismatic,
                    Isometry3::from_parts(Translation3::from(-axis * reference), UnitQuaternion::identity()),
                    reference,
                ),
                "free" => {
                    return Err(j.error(
                        "a free joint is read only on the file's single top-level body (the floating base)",
                    ))
                }
                "ball" => {
                    return Err(j.error(
                        "ball joints (three rotations about one point) are not supported: write them as three hinges",
                    ))
                }
                other => return Err(j.error(format!("unknown joint type \"{other}\""))),
            };
            let limit = self.limit(j, class, jtype)?;
            let kind = match (kind, &limit) {
                (JointKind::Revolute, None) => JointKind::Continuous,
                (k, _) => k,
            };
            let limit = match (kind, limit) {
                (JointKind::Prismatic, None) => Some(Limit {
                    lower: f64::NEG_INFINITY,
                    upper: f64::INFINITY,
                    velocity: None,
                    effort: None,
                }),
                (_, l) => l,
            };
            let origin =
                from * Isometry3::from_parts(
                    Translation3::from(pos - anchor),
                    UnitQuaternion::identity(),
                ) * fold;
            let child = if k + 1 == joints.len() && pos == Vector3::zeros() {
                name.to_string()
            } else {
                self.fresh(format!("{name}/{jname}"))
            };
            self.push_link(child.clone());
            self.refs.insert(jname.clone(), reference);
            if let Some(&a) = self.addresses.get(&(*j as *const El)) {
                self.layout.joints.push((jname.clone(), a));
            }
            let one = |attr: &str| -> Result<f64, ModelError> {
                Ok(self.numbers(j, class, attr, 1)?.map_or(0.0, |x| x[0]))
            };
            let mut joint = spec(jname, kind, &origin, axis.into(), limit);
            joint.dynamics = crate::JointDynamics {
                armature: one("armature")?,
                damping: one("damping")?,
                friction: one("frictionloss")?,
            };
            self.joints.push((joint, current, child.clone()));
            current = child;
            from = Pose::identity();
            anchor = pos;
        }
        if current != name {
            self.push_link(name.to_string());
            let back =
                Isometry3::from_parts(Translation3::from(-anchor), UnitQuaternion::identity());
            self.joints.push((
                spec(
                    format!("{name}_anchor"),
                    JointKind::Fixed,
                    &back,
                    [1.0, 0.0, 0.0],
                    None,
                ),
                current,
                name.to_string(),
            ));
        }
        Ok(())
    }

    /// A hinge's or slide's limits (`limited`, `range`, `autolimits`); None: unlimited.
    fn limit(&self, j: &El, class: &str, jtype: &str) -> Result<Option<Limit>, ModelError> {
        let range = self.numbers(j, class, "range", 2)?;
        let limited = match self.attr(j, class, "limited") {
            Some("true") => true,
            Some("false") => false,
            None | Some("auto") => {
                if !self.compiler.autolimits && range.is_some() {
                    return Err(j.error(
                        "has a range but no limited=\"true\"/\"false\" (with <compiler autolimits=\"false\">)",
                    ));
                }
                // As MuJoCo: limited when the range is a proper interval (its default "0 0",
                // or any lower ≥ upper, leaves the joint unlimited).
                range.as_ref().is_some_and(|r| r[0] < r[1])
            }
            Some(other) => {
                return Err(j.error(format!("limited=\"{other}\": expected true, false or auto")))
            }
        };
        if !limited {
            return Ok(None);
        }
        let r = range.unwrap_or(vec![0.0, 0.0]);
        let (lo, hi) = if jtype == "hinge" {
            (self.angle(r[0]), self.angle(r[1]))
        } else {
            (r[0], r[1])
        };
        if lo >= hi {
            // MuJoCo refuses a limited joint whose range is not lower < upper.
            return Err(j.error(format!(
                "range [{}, {}] is empty (a limited joint needs lower < upper)",
                r[0], r[1]
            )));
        }
        Ok(Some(Limit {
            lower: lo,
            upper: hi,
            velocity: None,
            effort: None,
        }))
    }

    /// `<equality>`: joint couplings become mimic joints; the rest are warnings.
    /// `<asset>`'s meshes (file, scale; the name defaults to the file's stem) and materials'
    /// colours.
    fn read_assets(&mut self, root: &El) {
        let dir = self
            .compiler
            .meshdir
            .clone()
            .or_else(|| self.compiler.assetdir.clone());
        for a in root.children.iter().filter(|c| c.tag == "asset") {
            for m in &a.children {
                match m.tag.as_str() {
                    "mesh" => {
                        let file = m.attr("file").map(|f| match &dir {
                            Some(d) if !Path::new(f).is_absolute() => {
                                Path::new(d).join(f).to_string_lossy().into_owned()
                            }
                            _ => f.to_string(),
                        });
                        let name = own_name(m).map(str::to_string).or_else(|| {
                            let f = m.attr("file")?;
                            let stem = Path::new(f).file_stem()?;
                            Some(stem.to_string_lossy().into_owned())
                        });
                        let Some(name) = name else { continue };
                        let mut problem = None;
                        let scale = match self.numbers(m, "main", "scale", 3) {
                            Ok(v) => v.map_or([1.0; 3], |v| [v[0], v[1], v[2]]),
                            Err(e) => {
                                problem = Some(e.kind.to_string());
                                [1.0; 3]
                            }
                        };
                        if file.is_none() {
                            problem = Some(format!(
                                "mesh asset {} has no file (meshes given by their vertices are not read)",
                                shown(&name)
                            ));
                        }
                        for r in ["refpos", "refquat"] {
                            if m.attr(r).is_some() {
                                problem =
                                    Some(format!("mesh asset {}: {r} is not read", shown(&name)));
                            }
                        }
                        use crate::mesh::MeshInertia;
                        let inertia = match m.attr("inertia") {
                            None | Some("legacy") => Ok(MeshInertia::Legacy),
                            Some("exact") => Ok(MeshInertia::Exact),
                            Some("shell") => Ok(MeshInertia::Shell),
                            Some("convex") => Err(
                                "inertia=\"convex\" (its convex hull's) is not computed here"
                                    .to_string(),
                            ),
                            Some(other) => Err(format!(
                                "inertia={}: expected legacy, exact, convex or shell",
                                shown(other)
                            )),
                        };
                        self.meshes.insert(
                            name,
                            MeshAsset {
                                file,
                                scale,
                                problem,
                                inertia,
                            },
                        );
                    }
                    "material" => {
                        if let (Some(n), Ok(Some(c))) =
                            (own_name(m), self.numbers(m, "main", "rgba", 4))
                        {
                            self.materials
                                .insert(n.to_string(), [c[0], c[1], c[2], c[3]]);
                        }
                    }
                    _ => {}
                }
            }
        }
    }

    /// A `<geom>` at `offset` in its body's frame, with its `group`; None (and a problem said)
    /// when it cannot be read. MuJoCo's sizes: a sphere's radius; a capsule's or a cylinder's
    /// radius and half length; a box's half sides; an ellipsoid's semi-axes; a plane's half
    /// sides to draw; with `fromto`, the length (a box's or an ellipsoid's z) is the segment's,
    /// and a box's or an ellipsoid's x and y are both size[0] (checked against MuJoCo).
    fn geom(&mut self, g: &El, offset: &Pose, class: &str) -> Option<(Geometry, i64)> {
        match self.read_geom(g, offset, class) {
            Ok(found) => Some(found),
            Err(why) => {
                self.geometry_problems.push(format!(
                    "{}:{}: {}: {why}",
                    g.file,
                    g.line,
                    g.describe()
                ));
                None
            }
        }
    }

    fn read_geom(&self, g: &El, offset: &Pose, class: &str) -> Result<(Geometry, i64), String> {
        let text = |e: ModelError| match e.kind {
            ErrorKind::Mjcf(m) => m,
            other => other.to_string(),
        };
        let int = |name: &str, default: i64| -> Result<i64, String> {
            match self.attr(g, class, name) {
                None => Ok(default),
                Some(v) => v
                    .trim()
                    .parse::<i64>()
                    .map_err(|_| format!("{name}={}: not an integer", shown(v))),
            }
        };
        let bits = ContactBits {
            contype: int("contype", 1)? as u32,
            conaffinity: int("conaffinity", 1)? as u32,
        };
        let group = int("group", 0)?;
        let gtype = self.attr(g, class, "type").unwrap_or("sphere");
        let size: Vec<f64> = match self.attr(g, class, "size") {
            None => Vec::new(),
            Some(t) => t
                .split_whitespace()
                .map(|x| x.parse::<f64>().ok().filter(|v| v.is_finite()))
                .collect::<Option<_>>()
                .filter(|v: &Vec<f64>| v.len() <= 3)
                .ok_or_else(|| format!("size={}: not one to three numbers", shown(t)))?,
        };
        let fromto = self.numbers(g, class, "fromto", 6).map_err(text)?;
        let length = fromto
            .as_ref()
            .map(|f| (Vector3::new(f[0], f[1], f[2]) - Vector3::new(f[3], f[4], f[5])).norm());
        let pose = if fromto.is_some() {
            self.site_pose(g, class).map_err(text)?
        } else {
            self.pose(g, class).map_err(text)?
        };
        let need = |n: usize| -> Result<&[f64], String> {
            if size.len() < n {
                return Err(format!(
                    "a {gtype} needs {n} size number(s), has {}",
                    size.len()
                ));
            }
            if size[..n].iter().any(|v| *v <= 0.0) {
                return Err(format!("size {:?}: must be > 0", &size[..n]));
            }
            Ok(&size[..n])
        };
        if g.attr("mesh").is_some() && gtype != "mesh" {
            return Err(format!(
                "a {gtype} fitted to a mesh (type=\"{gtype}\" with mesh=) is not read"
            ));
        }
        let shape = match gtype {
            "sphere" => Shape::Sphere {
                radius: need(1)?[0],
            },
            "capsule" | "cylinder" => {
                let (radius, length) = match length {
                    Some(l) => (need(1)?[0], l),
                    None => {
                        let s = need(2)?;
                        (s[0], 2.0 * s[1])
                    }
                };
                if gtype == "capsule" {
                    Shape::Capsule { radius, length }
                } else {
                    Shape::Cylinder { radius, length }
                }
            }
            "box" => Shape::Box {
                size: match length {
                    // MuJoCo's fromto box is square: size[0] for x and y.
                    Some(l) => {
                        let s = need(1)?;
                        [2.0 * s[0], 2.0 * s[0], l]
                    }
                    None => need(3)?.iter().map(|v| 2.0 * v).collect::<Vec<_>>()[..]
                        .try_into()
                        .map_err(|_| "size".to_string())?,
                },
            },
            "ellipsoid" => Shape::Ellipsoid {
                radii: match length {
                    // Round about the segment, as MuJoCo's: size[0] for x and y.
                    Some(l) => {
                        let s = need(1)?;
                        [s[0], s[0], l / 2.0]
                    }
                    None => {
                        let s = need(3)?;
                        [s[0], s[1], s[2]]
                    }
                },
            },
            "plane" => Shape::Plane {
                size: [
                    size.first().copied().unwrap_or(0.0).max(0.0),
                    size.get(1).copied().unwrap_or(0.0).max(0.0),
                ],
            },
            "mesh" => {
                let name = self
                    .attr(g, class, "mesh")
                    .ok_or("a mesh geom without mesh=")?;
                let asset = self
                    .meshes
                    .get(name)
                    .ok_or_else(|| format!("mesh {} is not an <asset><mesh>", shown(name)))?;
                if let Some(p) = &asset.problem {
                    return Err(p.clone());
                }
                let file = asset.file.clone().unwrap_or_default();
                Shape::Mesh {
                    path: PathBuf::from(&file),
                    uri: file,
                    scale: asset.scale,
                }
            }
            other => {
                return Err(format!(
                    "type=\"{other}\" is not read (sphere, capsule, cylinder, box, ellipsoid, plane and mesh are)"
                ))
            }
        };
        let rgba = match self.numbers(g, class, "rgba", 4).map_err(text)? {
            Some(c) => Some([c[0], c[1], c[2], c[3]]),
            None => self
                .attr(g, class, "material")
                .and_then(|m| self.materials.get(m).copied()),
        };
        let pose = offset * pose;
        let origin = Se3::from_parts_unchecked(
            *pose.rotation.to_rotation_matrix().matrix(),
            pose.translation.vector,
        );
        Ok((
            Geometry {
                link: usize::MAX,
                role: Role::Collision,
                name: own_name(g).map(str::to_string),
                origin,
                shape,
                rgba,
                bits: Some(bits),
            },
            group,
        ))
    }

    /// A geom as the tree's geometry: a collision shape when its bits let it collide with
    /// something (or a `<pair>` names it), a visual one when MuJoCo's viewer shows its group
    /// (0, 1 and 2). `link` None: fixed in the world.
    /// Adds geom `g` (read as `geometry`, None when it could not be) to its body's weight:
    /// its `mass`, or `density` (MuJoCo's 1000) times its volume, at its pose in the body.
    fn weigh(&mut self, g: &El, class: &str, link: &str, geometry: Option<&Geometry>) {
        let number = |name: &str| {
            self.attr(g, class, name)
                .and_then(|v| v.trim().parse::<f64>().ok())
        };
        let (mass, density) = (number("mass"), number("density").unwrap_or(1000.0));
        let shell = self.attr(g, class, "shellinertia") == Some("true");
        let sum = self.geom_sums.entry(link.to_string()).or_default();
        if sum.unweighed.is_some() {
            return;
        }
        let Some(geometry) = geometry else {
            sum.unweighed = Some(format!("line {}: a geom that is not read", g.line));
            return;
        };
        if shell {
            sum.unweighed = Some(format!(
                "line {}: shellinertia=\"true\" is not computed here",
                g.line
            ));
            return;
        }
        // (volume, centre in the geom's frame, inertia about it per unit mass, geom's axes)
        let weighed = match &geometry.shape {
            Shape::Mesh { .. } => self.mesh_weight(g, class, geometry),
            shape => solid(shape)
                .map(|(volume, moments)| {
                    (
                        volume,
                        Vector3::zeros(),
                        nalgebra::Matrix3::from_diagonal(&Vector3::from(moments)),
                    )
                })
                .ok_or_else(|| format!("a {} geom (no closed form here)", shape.word())),
        };
        let sum = self.geom_sums.entry(link.to_string()).or_default();
        let (volume, centre, unit) = match weighed {
            Ok(w) => w,
            Err(why) => {
                sum.unweighed = Some(format!("line {}: {why}", g.line));
                return;
            }
        };
        let m = mass.unwrap_or(density * volume);
        if !(m.is_finite() && m >= 0.0) {
            sum.unweighed = Some(format!("line {}: a geom of mass {m}", g.line));
            return;
        }
        let r = geometry.origin.rotation();
        let c = geometry.origin.rotation() * centre + geometry.origin.translation();
        let about_centre = r * unit * r.transpose() * m;
        sum.mass += m;
        sum.first += c * m;
        sum.about_origin += about_centre
            + (nalgebra::Matrix3::identity() * c.norm_squared() - c * c.transpose()) * m;
    }

    /// A mesh geom's volume, centre of mass and inertia per unit mass about it, in the geom's
    /// frame (its file's coordinates; [`crate::mesh::mass_properties`] as its asset's
    /// `inertia` says), each mesh file read and weighed once; or why not (one phrase).
    fn mesh_weight(
        &mut self,
        g: &El,
        class: &str,
        geometry: &Geometry,
    ) -> Result<(f64, Vector3<f64>, nalgebra::Matrix3<f64>), String> {
        let Shape::Mesh { uri, scale, .. } = &geometry.shape else {
            return Err("not a mesh".into());
        };
        let asset = self
            .attr(g, class, "mesh")
            .and_then(|n| self.meshes.get(n))
            .ok_or("a mesh geom without its asset")?;
        let mode = asset.inertia.clone()?;
        let path = crate::geometry::resolve_mesh(uri, &self.dir, &[])?;
        let key = (path, scale.map(f64::to_bits), mode);
        if !self.weighed_meshes.contains_key(&key) {
            let weighed = crate::mesh::read_mesh(&key.0, *scale)
                .and_then(|m| crate::mesh::mass_properties(&m, mode))
                .map_err(|e| format!("mesh {}: {e}", key.0.display()));
            self.weighed_meshes.insert(key.clone(), weighed);
        }
        let w = self.weighed_meshes[&key].clone()?;
        let [xx, xy, xz, yy, yz, zz] = w.inertia.map(|x| x / w.measure);
        Ok((
            w.measure,
            Vector3::from(w.com),
            nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz),
        ))
    }

    /// The bodies whose geoms were all weighed get that inertia (MuJoCo's, over any
    /// `<inertial>` with `inertiafromgeom="true"`); the others stay in `geom_mass`.
    fn weighed_inertials(&mut self) {
        let names = std::mem::take(&mut self.geom_mass);
        for name in names {
            let sum = self.geom_sums.remove(&name).unwrap_or_default();
            if sum.unweighed.is_some() || sum.mass <= 0.0 || sum.mass.is_nan() {
                if self.unweighed_why.is_none() {
                    self.unweighed_why = Some(
                        sum.unweighed
                            .unwrap_or_else(|| format!("its geoms' mass is {}", sum.mass)),
                    );
                }
                self.geom_mass.push(name);
                continue;
            }
            let c = sum.first / sum.mass;
            let i = sum.about_origin
                - (nalgebra::Matrix3::identity() * c.norm_squared() - c * c.transpose()) * sum.mass;
            self.inertials.retain(|(n, _)| *n != name);
            self.inertials.push((
                name,
                Inertial {
                    mass: sum.mass,
                    com: [c.x, c.y, c.z],
                    inertia: [
                        i[(0, 0)],
                        i[(0, 1)],
                        i[(0, 2)],
                        i[(1, 1)],
                        i[(1, 2)],
                        i[(2, 2)],
                    ],
                },
            ));
        }
    }

    fn push_geom(&mut self, link: Option<&str>, (g, group): (Geometry, i64)) {
        let bits = g.bits.unwrap_or(ContactBits::DEFAULT);
        let paired = g.name.as_ref().is_some_and(|n| self.pair_geoms.contains(n));
        let mut roles = Vec::new();
        if bits.contype != 0 || bits.conaffinity != 0 || paired {
            roles.push(Role::Collision);
        }
        if (0..3).contains(&group) {
            roles.push(Role::Visual);
        }
        for role in roles {
            let g = Geometry { role, ..g.clone() };
            match link {
                Some(l) => self.geoms.push((l.to_string(), g)),
                None => self.world_geoms.push(g),
            }
        }
    }

    /// The world body's geoms of a free-floating model (through frames).
    fn world_geoms_of(
        &mut self,
        holder: &El,
        offset: &Pose,
        class: &str,
    ) -> Result<(), ModelError> {
        for c in &holder.children {
            match c.tag.as_str() {
                "geom" => {
                    self.check_class(c)?;
                    if let Some(g) = self.geom(c, offset, class) {
                        self.push_geom(None, g);
                    }
                }
                "frame" => {
                    let pose = offset * self.pose(c, "main")?;
                    let class = c.attr("childclass").unwrap_or(class).to_string();
                    self.world_geoms_of(c, &pose, &class)?;
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The geoms and MuJoCo's contact rules into the built tree (links by index).
    fn geometry_into(&mut self, tree: &mut Tree, root: &El) {
        for (link, mut g) in std::mem::take(&mut self.geoms) {
            if let Ok(l) = tree.link(&link) {
                g.link = l;
                tree.geometries.push(g);
            }
        }
        let world_link = (!self.floating_root).then_some(tree.root);
        let body = |name: &str| -> Option<Option<usize>> {
            if name == "world" {
                return Some(world_link);
            }
            tree.link(name).ok().map(Some)
        };
        let mut rules = crate::geometry::ContactRules {
            world_link,
            filterparent: self.filterparent,
            ..Default::default()
        };
        for (b, p) in &self.body_parent {
            if let Ok(l) = tree.link(b) {
                let parent = p.as_deref().and_then(|p| tree.link(p).ok());
                rules.body_parent.insert(l, parent);
            }
        }
        let names: std::collections::HashSet<&str> = tree
            .geometries
            .iter()
            .chain(&self.world_geoms)
            .filter_map(|g| g.name.as_deref())
            .collect();
        for c in root.children.iter().filter(|c| c.tag == "contact") {
            for e in &c.children {
                let at = format!("{}:{}: {}", e.file, e.line, e.describe());
                match e.tag.as_str() {
                    "exclude" => {
                        let (b1, b2) =
                            (e.attr("body1").unwrap_or(""), e.attr("body2").unwrap_or(""));
                        match (body(b1), body(b2)) {
                            (Some(a), Some(b)) => rules.exclude.push((a, b)),
                            _ => self.geometry_problems.push(format!(
                                "{at}: body {} is not in the tree",
                                shown(if body(b1).is_none() { b1 } else { b2 })
                            )),
                        }
                    }
                    "pair" => {
                        let (g1, g2) =
                            (e.attr("geom1").unwrap_or(""), e.attr("geom2").unwrap_or(""));
                        match [g1, g2].iter().find(|g| !names.contains(**g)) {
                            Some(missing) => self
                                .geometry_problems
                                .push(format!("{at}: geom {} is not in the tree", shown(missing))),
                            None => rules.pairs.push((g1.to_string(), g2.to_string())),
                        }
                    }
                    _ => {}
                }
            }
        }
        for mut g in std::mem::take(&mut self.world_geoms) {
            g.link = tree.root;
            rules.world.push(g);
        }
        tree.geometry_problems
            .extend(std::mem::take(&mut self.geometry_problems));
        tree.contact_rules = Some(rules);
    }

    fn read_equalities(&mut self, root: &El) -> Result<(), ModelError> {
        for eq in root.children.iter().filter(|c| c.tag == "equality") {
            for e in &eq.children {
                if e.tag != "joint" {
                    self.warnings.push(format!(
                        "line {}: equality {} read past: the tree holds no loop closure",
                        e.line,
                        e.describe()
                    ));
                    continue;
                }
                if e.attr("active").is_some_and(|a| a == "false") {
                    continue;
                }
                let follower = e
                    .attr("joint1")
                    .ok_or_else(|| e.error("needs joint1"))?
                    .to_string();
                let c = self
                    .numbers(e, "main", "polycoef", 5)?
                    .unwrap_or(vec![0.0, 1.0, 0.0, 0.0, 0.0]);
                let Some(leader) = e.attr("joint2") else {
                    self.warnings.push(format!(
                        "line {}: {} locks joint \"{follower}\" (no joint2): read past, the joint stays a variable",
                        e.line,
                        e.describe()
                    ));
                    continue;
                };
                if c[2..].iter().any(|v| *v != 0.0) {
                    return Err(e.error(format!(
                        "polycoef=\"{}\": terms above the linear are not supported (a mimic joint is linear)",
                        c.iter().map(f64::to_string).collect::<Vec<_>>().join(" ")
                    )));
                }
                let (Some(&r1), Some(&r2)) = (self.refs.get(&follower), self.refs.get(leader))
                else {
                    // A joint of a body read past (a prop), or not a hinge or slide.
                    self.warnings.push(format!(
                        "line {}: {} read past: joint1 \"{follower}\" or joint2 \"{leader}\" is not a hinge or slide joint of the tree",
                        e.line,
                        e.describe()
                    ));
                    continue;
                };
                let Some((spec, _, _)) =
                    self.joints.iter_mut().find(|(s, _, _)| s.name == follower)
                else {
                    return Err(
                        e.error(format!("joint1 \"{follower}\" is not a joint of the model"))
                    );
                };
                // q1 − ref1 = c0 + c1 (q2 − ref2), with q MuJoCo's qpos: the tree's variables.
                spec.mimic = Some(Mimic {
                    leader: leader.to_string(),
                    multiplier: c[1],
                    offset: r1 + c[0] - c[1] * r2,
                });
            }
        }
        Ok(())
    }
}

/// The orientation attributes, in MuJoCo's order of precedence for defaults.
const ORIENTATIONS: [&str; 5] = ["quat", "axisangle", "euler", "xyaxes", "zaxis"];

/// `base`, or `base~k` with the least k free in `taken` (counting on from the last k made for
/// that base, so that making n names is linear); the name is then taken.
fn fresh_in(
    taken: &mut std::collections::HashSet<String>,
    next: &mut HashMap<String, usize>,
    base: String,
) -> String {
    let name = if taken.contains(&base) {
        let k = next.entry(base.clone()).or_insert(1);
        loop {
            let c = format!("{base}~{k}");
            *k += 1;
            if !taken.contains(&c) {
                break c;
            }
        }
    } else {
        base
    };
    taken.insert(name.clone());
    name
}

/// An attribute value as messages show it: quoted, escaped (`\n`, `\0`, `\"`), at most 120
/// characters (an attribute can hold a megabyte: the message says which, not all it holds).
fn shown(value: &str) -> String {
    let mut short: String = value.chars().take(120).collect();
    if short.len() < value.len() {
        short.push('…');
    }
    format!("{short:?}")
}

/// An element's `name`, when it has a non-empty one (MuJoCo: `name=""` is no name).
fn own_name(e: &El) -> Option<&str> {
    e.attr("name").filter(|n| !n.is_empty())
}

/// `v` of unit length, or `None` when it is shorter than 1e-10; scaled by its largest entry
/// first, so that entries of 1e154 and more (whose squares overflow) give the right direction.
fn unit(v: Vector3<f64>) -> Option<Vector3<f64>> {
    let largest = v.amax();
    if largest == 0.0 || !largest.is_finite() {
        return None;
    }
    let scaled = v / largest;
    (largest * scaled.norm() >= 1e-10).then(|| scaled.normalize())
}

fn parse_bool(e: &El, name: &str, v: &str) -> Result<bool, ModelError> {
    match v {
        "true" => Ok(true),
        "false" => Ok(false),
        other => Err(e.error(format!("{name}=\"{other}\": expected true or false"))),
    }
}

/// The minimal rotation taking (0, 0, 1) to the unit vector `z` (a half turn about x when
/// they are opposite).
fn z_to(z: Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::rotation_between(&Vector3::z(), &z).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI)
    })
}

/// True when a joint is written anywhere below `b`.
fn has_joints(b: &El) -> bool {
    let mut stack = vec![b];
    while let Some(e) = stack.pop() {
        if e.tag == "joint" || e.tag == "freejoint" {
            return true;
        }
        stack.extend(e.children.iter());
    }
    false
}

/// The bodies at and below `b`.
fn count_bodies(b: &El) -> usize {
    let mut stack = vec![b];
    let mut n = 0;
    while let Some(e) = stack.pop() {
        n += usize::from(e.tag == "body");
        stack.extend(e.children.iter());
    }
    n
}

/// The bodies directly under `holder` (through frames).
fn collect_bodies<'a>(holder: &'a El, out: &mut Vec<&'a El>) {
    for c in &holder.children {
        match c.tag.as_str() {
            "body" => out.push(c),
            "frame" => collect_bodies(c, out),
            _ => {}
        }
    }
}

/// A tree joint at `origin` (its rotation kept exact as a quaternion).
fn spec(
    name: String,
    kind: JointKind,
    origin: &Pose,
    axis: [f64; 3],
    limit: Option<Limit>,
) -> TreeJointSpec {
    let q = origin.rotation;
    let [r, p, y] = screwkit_lie::so3::to_rpy(q.to_rotation_matrix().matrix());
    TreeJointSpec {
        name,
        kind,
        origin_xyz: origin.translation.vector.into(),
        origin_rpy: [r, p, y],
        origin_quat: Some([q.w, q.i, q.j, q.k]),
        axis,
        limit,
        mimic: None,
        pitch: 0.0,
        dynamics: Default::default(),
    }
}
