//! Reading URDF: a strict pre-pass over the XML, then urdf-rs, then the [`Tree`].
//!
//! urdf-rs (0.10) is the parser, but three of its behaviours would let bad files through or
//! reject good ones, so a pre-pass with `roxmltree` runs first:
//!
//! - **Silently shortened vectors.** urdf-rs drops tokens that are not numbers
//!   (`xyz="1 a 2 3"` reads as `1 2 3`). The pre-pass checks every numeric attribute of every
//!   joint (`<origin xyz rpy>`, `<axis xyz>`, `<limit …>`, `<mimic …>`): exactly the expected
//!   count of tokens, each a number, or an error naming the joint.
//! - **A missing `<limit>` reads as [0, 0].** The pre-pass records whether `<limit>` was
//!   written; a revolute or prismatic joint without one is an error on the chain (as in
//!   urdfdom). Continuous joints ignore any limit.
//! - **`<limit>` without `velocity` (or `effort`) is rejected** by urdf-rs for URDF < 1.2,
//!   though real files omit them. The pre-pass hands urdf-rs a copy with the missing
//!   attributes filled in, and the model records them as absent.
//!
//! The pre-pass also reads each link's first `<inertial>` (its `<mass value>` and `<origin
//! xyz>`: the centre of mass; numbers checked like the joints', the mass finite and ≥ 0, an
//! `<inertial>` without a mass an error naming the link, as in urdfdom) into
//! [`Tree::inertials`]; the inertia tensor is not read.
//!
//! urdf-rs also sees only what kinematics needs: each `<link>` as its name and each top-level
//! `<joint>` with its `<origin>`, `<parent>`, `<child>`, `<axis>`, `<limit>` and `<mimic>`, so
//! meshes, materials, inertia, collision, `<transmission>` and `<gazebo>` blocks (which may
//! hold their own `<joint>` elements) can never make a file fail. xacro files are detected
//! (`<xacro:…>` elements, `${…}`/`$(…)` in attribute values; not the mere `xmlns:xacro`
//! declaration, which xacro leaves in its output: [`xacro::is_xacro`]) and expanded natively
//! first ([`crate::xacro`], ROS's xacro semantics) by [`load_str_with`] / [`urdf_text`].

use std::collections::HashMap;
use std::path::Path;

use crate::error::{ErrorKind, ModelError};
use crate::geometry::{Geometry, Role, Shape};
use crate::input;
use crate::tree::{Inertial, JointKind, Limit, Mimic, Tree, TreeJointSpec};
use crate::xacro::{self, XacroOptions};

/// Loads a URDF or xacro file into a [`Tree`] (xacro expanded with the default
/// [`XacroOptions`]: packages from `ROS_PACKAGE_PATH` / `AMENT_PREFIX_PATH`, no arguments).
pub fn load_file(path: impl AsRef<Path>) -> Result<Tree, ModelError> {
    load_file_with(path, &XacroOptions::default())
}

/// Loads a URDF or xacro file into a [`Tree`], expanding xacro with `opts`.
pub fn load_file_with(path: impl AsRef<Path>, opts: &XacroOptions) -> Result<Tree, ModelError> {
    let path = path.as_ref();
    let label = path.display().to_string();
    let bytes = input::read_file(path)?;
    let text = decode(&bytes).map_err(|kind| ModelError::new(label.clone(), kind))?;
    load_str_with(&text, &label, path.parent().unwrap_or(Path::new(".")), opts)
}

pub use crate::input::decode;
use crate::input::tolerate;

/// Loads URDF (or xacro) text into a [`Tree`]; `source` names it in error messages.
/// Relative xacro includes are resolved from the current directory.
pub fn load_str(text: &str, source: &str) -> Result<Tree, ModelError> {
    load_str_with(text, source, Path::new("."), &XacroOptions::default())
}

/// Loads URDF or xacro text into a [`Tree`]: xacro (see [`xacro::is_xacro`]) is expanded first
/// with `opts`, relative includes resolved from `dir`.
pub fn load_str_with(
    text: &str,
    source: &str,
    dir: &Path,
    opts: &XacroOptions,
) -> Result<Tree, ModelError> {
    let mut tree = parse_urdf(&urdf_text(text, source, dir, opts)?, source)?;
    tree.resolve_meshes(dir, &opts.package_paths);
    Ok(tree)
}

/// The URDF a robot file's text stands for: the text itself (what urdfdom tolerates
/// removed: [`tolerate`]), or its xacro expansion ([`xacro::is_xacro`]) with `opts`, relative
/// includes resolved from `dir`. What [`load_str_with`] parses.
pub fn urdf_text(
    text: &str,
    source: &str,
    dir: &Path,
    opts: &XacroOptions,
) -> Result<String, ModelError> {
    let text = &*tolerate(text);
    if text.trim().is_empty() {
        return Err(ModelError::new(source, ErrorKind::Empty));
    }
    if xacro::is_xacro(text) {
        return xacro::expand_str(text, source, dir, opts);
    }
    Ok(text.to_string())
}

/// Plain URDF text into a [`Tree`].
fn parse_urdf(text: &str, source: &str) -> Result<Tree, ModelError> {
    let err = |kind| ModelError::new(source, kind);
    let doc = input::parse_xml(text).map_err(err)?;
    let robot = doc.root_element();
    if robot.tag_name().name() != "robot" || input::is_prefixed(text, &robot) {
        return Err(err(ErrorKind::NotARobot(robot.tag_name().name().into())));
    }
    let (clean, facts, inertials, body) = pre_pass(text, &robot).map_err(err)?;
    let parsed =
        urdf_rs::read_from_string(&clean).map_err(|e| err(ErrorKind::Urdf(e.to_string())))?;
    let links = parsed.links.iter().map(|l| l.name.clone()).collect();
    let joints = parsed
        .joints
        .iter()
        .map(|j| {
            let fact = facts.get(&j.name).copied().unwrap_or_default();
            let kind = match j.joint_type {
                urdf_rs::JointType::Revolute => JointKind::Revolute,
                urdf_rs::JointType::Continuous => JointKind::Continuous,
                urdf_rs::JointType::Prismatic => JointKind::Prismatic,
                urdf_rs::JointType::Fixed => JointKind::Fixed,
                urdf_rs::JointType::Floating => JointKind::Floating,
                urdf_rs::JointType::Planar => JointKind::Planar,
                urdf_rs::JointType::Spherical => JointKind::Spherical,
            };
            let limit = fact.has_limit.then(|| Limit {
                lower: j.limit.lower,
                upper: j.limit.upper,
                velocity: fact.has_velocity.then_some(j.limit.velocity),
                effort: fact.has_effort.then_some(j.limit.effort),
            });
            let spec = TreeJointSpec {
                name: j.name.clone(),
                kind,
                origin_xyz: j.origin.xyz.0,
                origin_rpy: j.origin.rpy.0,
                origin_quat: None,
                axis: j.axis.xyz.0,
                limit,
                mimic: j.mimic.as_ref().map(|m| Mimic {
                    leader: m.joint.clone(),
                    multiplier: m.multiplier.unwrap_or(1.0),
                    offset: m.offset.unwrap_or(0.0),
                }),
                pitch: 0.0,
                dynamics: j.dynamics.as_ref().map_or_else(Default::default, |d| {
                    crate::JointDynamics {
                        armature: 0.0,
                        damping: d.damping,
                        friction: d.friction,
                    }
                }),
            };
            (spec, j.parent.link.clone(), j.child.link.clone())
        })
        .collect();
    let mut tree = Tree::new(parsed.name, source.to_string(), links, joints)?;
    for (name, inertial) in inertials {
        if let Ok(i) = tree.link(&name) {
            tree.inertials[i] = Some(inertial);
        }
    }
    for (name, mut g) in body.shapes {
        if let Ok(i) = tree.link(&name) {
            g.link = i;
            tree.geometries.push(g);
        }
    }
    tree.geometry_problems = body.problems;
    Ok(tree)
}

/// What the pre-pass learned about a joint's `<limit>`.
#[derive(Debug, Clone, Copy, Default)]
struct LimitFacts {
    has_limit: bool,
    has_velocity: bool,
    has_effort: bool,
}

/// What the pre-pass hands on: the reduced document, each joint's limit facts, each link's
/// inertial.
type PrePass = (
    String,
    HashMap<String, LimitFacts>,
    Vec<(String, Inertial)>,
    Body,
);

/// The links' geometry the pre-pass read: (link name, geometry with `link` unset) and the
/// problems of the elements it could not read.
#[derive(Debug, Default)]
struct Body {
    shapes: Vec<(String, Geometry)>,
    problems: Vec<String>,
}

/// Checks the numeric attributes of every top-level joint and link inertial and writes the
/// reduced document that urdf-rs parses.
fn pre_pass(text: &str, robot: &roxmltree::Node) -> Result<PrePass, ErrorKind> {
    let mut out = String::with_capacity(text.len() / 4);
    out.push_str("<robot");
    for attr in ["name", "version"] {
        if let Some(v) = robot.attribute(attr) {
            out.push_str(&format!(" {attr}=\"{}\"", input::escape_xml(v)));
        }
    }
    out.push_str(">\n");
    let mut facts = HashMap::new();
    let mut inertials = Vec::new();
    let mut body = Body::default();
    let materials = materials(text, robot);
    // Elements written with a prefix (`<u:joint>`) are another format's: urdfdom never reads them.
    for node in robot
        .children()
        .filter(|n| n.is_element() && !input::is_prefixed(text, n))
    {
        match node.tag_name().name() {
            "link" => {
                // urdf-rs requires the name; let it report a missing one.
                match node.attribute("name") {
                    Some(n) => {
                        out.push_str(&format!("<link name=\"{}\"/>\n", input::escape_xml(n)));
                        if let Some(inertial) = inertial_of(text, &node, n)? {
                            inertials.push((n.to_string(), inertial));
                        }
                        shapes_of(text, &node, n, &materials, &mut body);
                    }
                    None => out.push_str("<link/>\n"),
                }
            }
            "joint" => {
                let (xml, fact) = joint_for_urdf_rs(text, &node)?;
                out.push_str(&xml);
                if let Some(n) = node.attribute("name") {
                    facts.insert(n.to_string(), fact);
                }
            }
            _ => {}
        }
    }
    out.push_str("</robot>\n");
    Ok((out, facts, inertials, body))
}

/// R = Rz(yaw) Ry(pitch) Rx(roll), URDF's fixed-axis roll, pitch, yaw.
fn rotation_rpy([r, p, y]: [f64; 3]) -> nalgebra::Matrix3<f64> {
    *nalgebra::Rotation3::from_euler_angles(r, p, y).matrix()
}

/// A link's first `<inertial>`: mass, centre of mass and inertia tensor, checked (see the
/// module docs).
fn inertial_of(
    text: &str,
    link: &roxmltree::Node,
    name: &str,
) -> Result<Option<Inertial>, ErrorKind> {
    fn child<'a, 'i>(
        text: &str,
        n: &roxmltree::Node<'a, 'i>,
        tag: &str,
    ) -> Option<roxmltree::Node<'a, 'i>> {
        n.children()
            .filter(|c| c.is_element() && !input::is_prefixed(text, c))
            .find(|c| c.tag_name().name() == tag)
    }
    let Some(inertial) = child(text, link, "inertial") else {
        return Ok(None);
    };
    let element = |tag: &str| format!("link \"{name}\" <inertial><{tag}>");
    let mut com = [0.0; 3];
    let mut rpy = [0.0; 3];
    if let Some(origin) = child(text, &inertial, "origin") {
        for attr in ["xyz", "rpy"] {
            if let Some(v) = origin.attribute(attr) {
                check_numbers_of(&element("origin"), attr, v, 3)?;
            }
        }
        for (attr, out) in [("xyz", &mut com), ("rpy", &mut rpy)] {
            if let Some(v) = origin.attribute(attr) {
                for (c, t) in out.iter_mut().zip(v.split_whitespace()) {
                    *c = t.parse().unwrap_or(f64::NAN);
                }
            }
        }
    }
    let bad = |problem: String| ErrorKind::BadInertial {
        link: name.to_string(),
        problem,
    };
    if com.iter().any(|c| !c.is_finite()) {
        return Err(bad("the centre of mass <origin xyz> is not finite".into()));
    }
    if rpy.iter().any(|c| !c.is_finite()) {
        return Err(bad("<origin rpy> is not finite".into()));
    }
    // The tensor in the inertial frame (urdfdom's attributes; a missing one is 0), turned into
    // the link's axes: I = R I' Rᵀ with R = Rz(yaw) Ry(pitch) Rx(roll).
    let mut local = [0.0; 6];
    if let Some(i) = child(text, &inertial, "inertia") {
        for (k, attr) in ["ixx", "ixy", "ixz", "iyy", "iyz", "izz"]
            .iter()
            .enumerate()
        {
            if let Some(v) = i.attribute(*attr) {
                check_numbers_of(&element("inertia"), attr, v, 1)?;
                local[k] = v.trim().parse().unwrap_or(f64::NAN);
            }
        }
    }
    if local.iter().any(|c| !c.is_finite()) {
        return Err(bad("the <inertia> is not finite".into()));
    }
    let inertia = crate::tree::rotate_inertia(&local, &rotation_rpy(rpy));
    let value = child(text, &inertial, "mass")
        .and_then(|m| m.attribute("value"))
        .ok_or_else(|| bad("no <mass value=\"…\"/> (urdfdom requires one)".into()))?;
    check_numbers_of(&element("mass"), "value", value, 1)?;
    let mass: f64 = value.trim().parse().unwrap_or(f64::NAN);
    if !(mass.is_finite() && mass >= 0.0) {
        return Err(bad(format!("mass {value} is not a finite number ≥ 0")));
    }
    Ok(Some(Inertial { mass, com, inertia }))
}

/// One `<joint>` reduced to its kinematic children, numbers checked, `<limit>` completed.
fn joint_for_urdf_rs(
    text: &str,
    node: &roxmltree::Node,
) -> Result<(String, LimitFacts), ErrorKind> {
    let name = node.attribute("name").unwrap_or("");
    let mut out = String::from("<joint");
    for attr in ["name", "type"] {
        if let Some(v) = node.attribute(attr) {
            out.push_str(&format!(" {attr}=\"{}\"", input::escape_xml(v)));
        }
    }
    out.push('>');
    let mut fact = LimitFacts::default();
    for child in node
        .children()
        .filter(|n| n.is_element() && !input::is_prefixed(text, n))
    {
        let tag = child.tag_name().name();
        let checks: &[(&str, usize)] = match tag {
            "origin" => &[("xyz", 3), ("rpy", 3)],
            "axis" => &[("xyz", 3)],
            "limit" => &[("lower", 1), ("upper", 1), ("effort", 1), ("velocity", 1)],
            "mimic" => &[("multiplier", 1), ("offset", 1)],
            "dynamics" => &[("damping", 1), ("friction", 1)],
            "parent" | "child" => &[],
            _ => continue,
        };
        for &(attr, count) in checks {
            if let Some(v) = child.attribute(attr) {
                check_numbers(name, tag, attr, v, count)?;
            }
        }
        // Rebuilt from its attributes in no namespace (what urdfdom reads): nothing else of
        // the file's text reaches urdf-rs.
        out.push('<');
        out.push_str(tag);
        for a in child.attributes().filter(|a| a.namespace().is_none()) {
            out.push_str(&format!(
                " {}=\"{}\"",
                a.name(),
                input::escape_xml(a.value())
            ));
        }
        if tag == "limit" {
            fact.has_limit = true;
            fact.has_velocity = child.attribute("velocity").is_some();
            fact.has_effort = child.attribute("effort").is_some();
            if !fact.has_velocity {
                out.push_str(" velocity=\"0\"");
            }
            if !fact.has_effort {
                out.push_str(" effort=\"0\"");
            }
        }
        out.push_str("/>");
    }
    out.push_str("</joint>\n");
    Ok((out, fact))
}

/// Exactly `count` whitespace-separated tokens, each a number (NaN/inf are caught later, on
/// the chain, with the joint's name).
fn check_numbers(
    joint: &str,
    tag: &str,
    attr: &str,
    value: &str,
    count: usize,
) -> Result<(), ErrorKind> {
    check_numbers_of(&format!("joint \"{joint}\" <{tag}>"), attr, value, count)
}

/// The element children of `n` named `tag`, unprefixed.
fn children_named<'a, 'i>(
    text: &'a str,
    n: &roxmltree::Node<'a, 'i>,
    tag: &'a str,
) -> impl Iterator<Item = roxmltree::Node<'a, 'i>> + 'a
where
    'i: 'a,
{
    n.children()
        .filter(move |c| c.is_element() && !input::is_prefixed(text, c))
        .filter(move |c| c.tag_name().name() == tag)
}

/// The named top-level `<material name><color rgba/></material>` colours.
fn materials(text: &str, robot: &roxmltree::Node) -> HashMap<String, [f64; 4]> {
    children_named(text, robot, "material")
        .filter_map(|m| Some((m.attribute("name")?.to_string(), color_of(text, &m)?)))
        .collect()
}

/// A `<material>`'s `<color rgba>`, when it is four numbers in [0, 1].
fn color_of(text: &str, material: &roxmltree::Node) -> Option<[f64; 4]> {
    let rgba = children_named(text, material, "color")
        .next()?
        .attribute("rgba")?;
    let v = numbers(rgba, 4).ok()?;
    v.iter()
        .all(|x| (0.0..=1.0).contains(x))
        .then(|| [v[0], v[1], v[2], v[3]])
}

/// `count` finite numbers of an attribute's value, or what is wrong with it.
fn numbers(value: &str, count: usize) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = value
        .split_whitespace()
        .map(|t| {
            t.parse::<f64>()
                .map_err(|_| format!("\"{t}\" is not a number"))
        })
        .collect::<Result<_, _>>()?;
    if v.len() != count {
        return Err(format!("expected {count} number(s), found {}", v.len()));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(format!("\"{value}\" is not finite"));
    }
    Ok(v)
}

/// A link's `<collision>` and `<visual>` elements into `body` (each a shape or a problem).
fn shapes_of(
    text: &str,
    link: &roxmltree::Node,
    name: &str,
    materials: &HashMap<String, [f64; 4]>,
    body: &mut Body,
) {
    for role in [Role::Collision, Role::Visual] {
        for (k, element) in children_named(text, link, role.word()).enumerate() {
            match shape_of(text, &element, role, materials) {
                Ok(g) => body.shapes.push((name.to_string(), g)),
                Err(problem) => body.problems.push(format!(
                    "link \"{name}\" <{}> {}: {problem}",
                    role.word(),
                    k + 1
                )),
            }
        }
    }
}

/// One `<collision>` or `<visual>` element (link left unset).
fn shape_of(
    text: &str,
    element: &roxmltree::Node,
    role: Role,
    materials: &HashMap<String, [f64; 4]>,
) -> Result<Geometry, String> {
    let mut xyz = [0.0; 3];
    let mut rpy = [0.0; 3];
    if let Some(origin) = children_named(text, element, "origin").next() {
        for (attr, out) in [("xyz", &mut xyz), ("rpy", &mut rpy)] {
            if let Some(v) = origin.attribute(attr) {
                let v = numbers(v, 3).map_err(|e| format!("<origin {attr}>: {e}"))?;
                out.copy_from_slice(&v);
            }
        }
    }
    let origin = screwkit_lie::Se3::from_xyz_rpy(xyz, rpy).map_err(|e| format!("<origin>: {e}"))?;
    let geometry = children_named(text, element, "geometry")
        .next()
        .ok_or("no <geometry>")?;
    let mut shapes = geometry
        .children()
        .filter(|c| c.is_element() && !input::is_prefixed(text, c));
    let shape = shapes.next().ok_or("an empty <geometry>")?;
    if shapes.next().is_some() {
        return Err("<geometry> holds more than one shape".into());
    }
    let tag = shape.tag_name().name();
    let attr = |a: &str, count: usize| -> Result<Vec<f64>, String> {
        let v = shape
            .attribute(a)
            .ok_or_else(|| format!("<{tag}> has no {a}"))?;
        numbers(v, count).map_err(|e| format!("<{tag} {a}>: {e}"))
    };
    let positive = |a: &str| -> Result<f64, String> {
        let v = attr(a, 1)?[0];
        if v > 0.0 {
            Ok(v)
        } else {
            Err(format!("<{tag} {a}> is {v}: it must be > 0"))
        }
    };
    let shape = match tag {
        "box" => {
            let v = attr("size", 3)?;
            if v.iter().any(|x| *x <= 0.0) {
                return Err(format!("<box size> {v:?}: every side must be > 0"));
            }
            Shape::Box {
                size: [v[0], v[1], v[2]],
            }
        }
        "cylinder" => Shape::Cylinder {
            radius: positive("radius")?,
            length: positive("length")?,
        },
        "sphere" => Shape::Sphere {
            radius: positive("radius")?,
        },
        "capsule" => Shape::Capsule {
            radius: positive("radius")?,
            length: attr("length", 1)?[0].max(0.0),
        },
        "mesh" => {
            let uri = shape
                .attribute("filename")
                .ok_or("<mesh> has no filename")?
                .to_string();
            let scale = match shape.attribute("scale") {
                None => [1.0; 3],
                Some(_) => {
                    let v = attr("scale", 3)?;
                    [v[0], v[1], v[2]]
                }
            };
            Shape::Mesh {
                path: std::path::PathBuf::from(&uri),
                uri,
                scale,
            }
        }
        other => return Err(format!("unknown shape <{other}>")),
    };
    let rgba = (role == Role::Visual)
        .then(|| children_named(text, element, "material").next())
        .flatten()
        .and_then(|m| color_of(text, &m).or_else(|| materials.get(m.attribute("name")?).copied()));
    Ok(Geometry {
        link: usize::MAX,
        role,
        name: element.attribute("name").map(str::to_string),
        origin,
        shape,
        rgba,
        bits: None,
    })
}

/// [`check_numbers`] for any element, named as `element` in the message.
fn check_numbers_of(element: &str, attr: &str, value: &str, count: usize) -> Result<(), ErrorKind> {
    let bad = |problem: String| ErrorKind::BadNumber {
        element: element.to_string(),
        attribute: attr.to_string(),
        value: value.to_string(),
        problem,
    };
    let tokens: Vec<&str> = value.split_whitespace().collect();
    if let Some(t) = tokens.iter().find(|t| t.parse::<f64>().is_err()) {
        return Err(bad(format!("\"{t}\" is not a number")));
    }
    if tokens.len() != count {
        return Err(bad(format!(
            "expected {count} number(s), found {}",
            tokens.len()
        )));
    }
    Ok(())
}

/// The tree as URDF text (what `screwkit urdf FILE` writes, so that URDF-only tools can use a
/// robot read from another format): every link (with its mass and centre of mass where it has
/// an inertial; the inertia tensor, not kept, is written as a small placeholder), every joint
/// with its origin (xyz and roll-pitch-yaw from the exact rotation, [`screwkit_lie::so3::to_rpy`],
/// to 17 significant digits), axis, limits (`velocity`/`effort` only where known; an unbounded
/// prismatic or helical joint's limits as ±1e300) and mimic rule. URDF has no free joint: a
/// tree with a floating root says so in a comment, and is loaded with `--floating-base` /
/// `floating_base=True`. URDF has no helical joint either: one is written as a rotating joint
/// to a new link `<child>_screw` and a prismatic follower `<joint>_advance` along the same
/// axis (mimic, multiplier = the pitch). Loading the text gives the same FK to rounding.
pub fn write(tree: &Tree) -> Result<String, ModelError> {
    // Every name as an attribute value that reads back exactly; a name XML cannot hold (a NUL,
    // a control character) is an error naming it.
    let esc = |what: &str, name: &str| {
        input::escape_attr(name).map_err(|c| {
            ModelError::new(
                tree.source.clone(),
                ErrorKind::Unwritable(format!(
                    "{what} {:?} cannot be written as URDF: it holds the character U+{:04X}, \
                     which XML cannot hold",
                    name, c as u32
                )),
            )
        })
    };
    // Comment text: no "--" (it would end or break the comment), escaped as text.
    let comment = |text: &str| {
        let mut t = input::escape_xml(text);
        while t.contains("--") {
            t = t.replace("--", "- -");
        }
        t
    };
    let num = |x: f64| {
        if x.is_infinite() {
            if x > 0.0 {
                "1e300".to_string()
            } else {
                "-1e300".to_string()
            }
        } else {
            format!("{x:e}")
        }
    };
    let vec3 = |v: [f64; 3]| format!("{} {} {}", num(v[0]), num(v[1]), num(v[2]));
    let mut out = String::new();
    out.push_str("<?xml version=\"1.0\"?>\n");
    out.push_str(&format!(
        "<!-- Written by screwkit from {} (the kinematic tree: links, joints, limits, mimic rules, masses). -->\n",
        comment(&tree.source)
    ));
    if tree.floating_root {
        out.push_str(&format!(
            "<!-- The file gives the root link \"{}\" a free joint (a floating base): URDF has none; load with a floating base. -->\n",
            comment(&tree.links[tree.root])
        ));
    }
    out.push_str(&format!(
        "<robot name=\"{}\">\n",
        esc("the robot name", &tree.name)?
    ));
    for (l, name) in tree.links.iter().enumerate() {
        match tree.inertials[l] {
            Some(i) => out.push_str(&format!(
                "  <link name=\"{}\">\n    <inertial>\n      <origin xyz=\"{}\"/>\n      <mass value=\"{}\"/>\n      <inertia ixx=\"1e-9\" ixy=\"0\" ixz=\"0\" iyy=\"1e-9\" iyz=\"0\" izz=\"1e-9\"/>\n    </inertial>\n  </link>\n",
                esc("the link", name)?,
                vec3(i.com),
                num(i.mass)
            )),
            None => out.push_str(&format!("  <link name=\"{}\"/>\n", esc("the link", name)?)),
        }
    }
    // URDF has no helical joint: each is written as a rotating joint to a new link and a
    // prismatic follower along the same axis (mimic, multiplier = the pitch), which reads back
    // as the same screw motion.
    let fresh = |base: String| {
        let mut name = base;
        while tree.link(&name).is_ok() || tree.joint(&name).is_some() {
            name.push('_');
        }
        name
    };
    let screw_links: Vec<Option<(String, String)>> = tree
        .joints
        .iter()
        .map(|j| {
            (j.kind == JointKind::Helical).then(|| {
                (
                    fresh(format!("{}_screw", tree.links[j.child])),
                    fresh(format!("{}_advance", j.name)),
                )
            })
        })
        .collect();
    for (link, _) in screw_links.iter().flatten() {
        out.push_str(&format!("  <link name=\"{}\"/>\n", esc("the link", link)?));
    }
    for (j, screw) in tree.joints.iter().zip(&screw_links) {
        let unbounded = j
            .limit
            .is_none_or(|l| crate::tree::is_unbounded(l.lower, l.upper));
        let (kind, child) = match screw {
            Some((link, _)) if unbounded => ("continuous", link.as_str()),
            Some((link, _)) => ("revolute", link.as_str()),
            None => (j.kind.as_str(), tree.links[j.child].as_str()),
        };
        let rpy = match j.origin() {
            Ok(t) => screwkit_lie::so3::to_rpy(t.rotation()),
            Err(_) => j.origin_rpy,
        };
        out.push_str(&format!(
            "  <joint name=\"{}\" type=\"{}\">\n    <origin xyz=\"{}\" rpy=\"{}\"/>\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n",
            esc("the joint", &j.name)?,
            kind,
            vec3(j.origin_xyz),
            vec3(rpy),
            esc("the link", &tree.links[j.parent])?,
            esc("the link", child)?,
        ));
        if j.kind.is_movable() {
            out.push_str(&format!("    <axis xyz=\"{}\"/>\n", vec3(j.axis)));
        }
        if let (Some(l), true) = (j.limit, j.kind != JointKind::Fixed) {
            let mut s = format!(
                "    <limit lower=\"{}\" upper=\"{}\"",
                num(l.lower),
                num(l.upper)
            );
            if let Some(v) = l.velocity {
                s.push_str(&format!(" velocity=\"{}\"", num(v)));
            }
            if let Some(e) = l.effort {
                s.push_str(&format!(" effort=\"{}\"", num(e)));
            }
            out.push_str(&s);
            out.push_str("/>\n");
        }
        if let Some(m) = &j.mimic {
            out.push_str(&format!(
                "    <mimic joint=\"{}\" multiplier=\"{}\" offset=\"{}\"/>\n",
                esc("the joint", &m.leader)?,
                num(m.multiplier),
                num(m.offset)
            ));
        }
        out.push_str("  </joint>\n");
        if let Some((link, advance)) = screw {
            out.push_str(&format!(
                "  <joint name=\"{}\" type=\"prismatic\">\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n    <axis xyz=\"{}\"/>\n    <limit lower=\"-1e300\" upper=\"1e300\"/>\n    <mimic joint=\"{}\" multiplier=\"{}\" offset=\"0\"/>\n  </joint>\n",
                esc("the joint", advance)?,
                esc("the link", link)?,
                esc("the link", &tree.links[j.child])?,
                vec3(j.axis),
                esc("the joint", &j.name)?,
                num(j.pitch)
            ));
        }
    }
    out.push_str("</robot>\n");
    Ok(out)
}
