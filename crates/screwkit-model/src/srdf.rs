//! SRDF, MoveIt's semantic robot description: which link pairs need no collision check
//! (`<disable_collisions link1 link2 reason/>`), the planning groups (`<group>` of links,
//! joints, chains and subgroups) and the end effectors (`<end_effector>`). Read strictly
//! (every file is untrusted: bounded, gated XML, errors naming the element), written back
//! deterministically.

use std::path::Path;

use crate::error::{ErrorKind, ModelError};
use crate::input;

/// A link pair whose collisions are not checked.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord)]
pub struct DisabledPair {
    /// One link.
    pub link1: String,
    /// The other.
    pub link2: String,
    /// Why (`Adjacent`, `Default`, `Always`, `Never`, `User`, or the file's word).
    pub reason: String,
}

/// A planning group: its members as the file lists them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Group {
    /// The group's name.
    pub name: String,
    /// `<link name>` members.
    pub links: Vec<String>,
    /// `<joint name>` members.
    pub joints: Vec<String>,
    /// `<chain base_link tip_link>` members.
    pub chains: Vec<(String, String)>,
    /// `<group name>` members (subgroups).
    pub subgroups: Vec<String>,
}

/// An end effector: a group attached to a link.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EndEffector {
    /// Its name.
    pub name: String,
    /// The group that makes it up.
    pub group: String,
    /// The link it is attached to.
    pub parent_link: String,
    /// The group that link belongs to, if given.
    pub parent_group: Option<String>,
}

/// What an SRDF file says.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Srdf {
    /// The robot's name (`<robot name>`).
    pub robot: String,
    /// The disabled pairs, in the file's order.
    pub disabled: Vec<DisabledPair>,
    /// The planning groups.
    pub groups: Vec<Group>,
    /// The end effectors.
    pub end_effectors: Vec<EndEffector>,
}

/// Reads an SRDF file (bounded, decoded as robot files are).
pub fn read_file(path: &Path) -> Result<Srdf, ModelError> {
    let label = path.display().to_string();
    let bytes = input::read_file(path)?;
    let text = input::decode(&bytes).map_err(|k| ModelError::new(label.clone(), k))?;
    parse(&text, &label)
}

/// Reads SRDF text; `source` names it in errors.
pub fn parse(text: &str, source: &str) -> Result<Srdf, ModelError> {
    let fail = |m: String| ModelError::new(source, ErrorKind::Srdf(m));
    let doc = input::parse_xml(text).map_err(|k| ModelError::new(source, k))?;
    let robot = doc.root_element();
    if robot.tag_name().name() != "robot" {
        return Err(fail(format!(
            "the root element is <{}>, not <robot>",
            robot.tag_name().name()
        )));
    }
    let attr = |n: &roxmltree::Node, a: &str| -> Result<String, ModelError> {
        n.attribute(a).map(str::to_string).ok_or_else(|| {
            let line = doc.text_pos_at(n.range().start).row;
            fail(format!("line {line}: <{}> has no {a}", n.tag_name().name()))
        })
    };
    let mut out = Srdf {
        robot: robot.attribute("name").unwrap_or_default().to_string(),
        ..Srdf::default()
    };
    for node in robot.children().filter(|n| n.is_element()) {
        match node.tag_name().name() {
            "disable_collisions" => out.disabled.push(DisabledPair {
                link1: attr(&node, "link1")?,
                link2: attr(&node, "link2")?,
                reason: node.attribute("reason").unwrap_or("").to_string(),
            }),
            "group" => {
                let mut g = Group {
                    name: attr(&node, "name")?,
                    ..Group::default()
                };
                for m in node.children().filter(|n| n.is_element()) {
                    match m.tag_name().name() {
                        "link" => g.links.push(attr(&m, "name")?),
                        "joint" => g.joints.push(attr(&m, "name")?),
                        "chain" => g
                            .chains
                            .push((attr(&m, "base_link")?, attr(&m, "tip_link")?)),
                        "group" => g.subgroups.push(attr(&m, "name")?),
                        _ => {}
                    }
                }
                out.groups.push(g);
            }
            "end_effector" => out.end_effectors.push(EndEffector {
                name: attr(&node, "name")?,
                group: attr(&node, "group")?,
                parent_link: attr(&node, "parent_link")?,
                parent_group: node.attribute("parent_group").map(str::to_string),
            }),
            _ => {}
        }
    }
    Ok(out)
}

/// SRDF text of a robot's disabled pairs (sorted by link names, one line each), what
/// `screwkit srdf` writes: the same pairs give the same bytes.
pub fn write(robot: &str, disabled: &[DisabledPair]) -> String {
    let mut pairs = disabled.to_vec();
    for p in &mut pairs {
        if p.link2 < p.link1 {
            std::mem::swap(&mut p.link1, &mut p.link2);
        }
    }
    pairs.sort();
    pairs.dedup_by(|a, b| a.link1 == b.link1 && a.link2 == b.link2);
    let mut s = format!(
        "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- Written by screwkit: link pairs whose collisions need no check. -->\n<robot name=\"{}\">\n",
        input::escape_xml(robot)
    );
    for p in &pairs {
        s.push_str(&format!(
            "  <disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/>\n",
            input::escape_xml(&p.link1),
            input::escape_xml(&p.link2),
            input::escape_xml(&p.reason)
        ));
    }
    s.push_str("</robot>\n");
    s
}
