//! The whole robot as a tree of screws: every movable joint's space screw axis at home, every
//! link's home pose, named frames, and the one variable order.
//!
//! For every link L,
//!
//! ```text
//! T_L(q) = T_base · Π_{j on the path root → L} e^{[S_j]θ_j} · M_L
//! ```
//!
//! with S_j the joint's screw (ω, v) in the root link's frame at home (all θ = 0), M_L the
//! link's pose in the root link's frame at home, the product taken root first, and T_base the
//! identity (a fixed base) or the floating base's pose in the world. θ_j follows from q by the
//! joint's [`Drive`] (θ = m q_k + o; (1, 0) for an ordinary joint). This is the chain's
//! product of exponentials ([`crate::Chain`]) applied along each path of the tree: a chain
//! base → tip is the path of the tip with the base's pose factored out.
//!
//! **Variables.** The independent variables are the file's movable joints (revolute,
//! continuous, prismatic) in the file's joint order, mimic followers excluded. With a floating
//! base the configuration is q = (x, y, z, qx, qy, qz, qw, q_1 … q_n): the base's position in
//! the world, then its orientation as a unit quaternion (x, y, z, w), then the joint variables
//! (nq = 7 + n); the velocity is v = (ω, v_b, q̇_1 … q̇_n): the base's twist in the base (root
//! link) frame, (ω, v) order, then the joint rates (nv = 6 + n). Without it, nq = nv = n.
//!
//! **Frames.** Every link is a frame (same name, same index: links come first); extra frames
//! (a tool centre point, a sensor, an MJCF site) are fixed to a link at a placement. A frame's
//! pose is T_F(q) = T_L(q) · placement, so its home pose is M_F = M_L · placement.

use std::collections::HashMap;

use nalgebra::Vector3;
use screwkit_lie::{ScrewAxis, Se3};

use crate::chain::{variable_of, Chain, Drive, MimicResolver, Variable};
use crate::error::{ErrorKind, ModelError};
use crate::tree::{JointKind, Tree};

/// A movable joint of the whole tree, with its screw axis at home.
#[derive(Debug, Clone, PartialEq)]
pub struct TreeScrew {
    /// Joint name.
    pub name: String,
    /// Revolute, continuous, prismatic or helical.
    pub kind: JointKind,
    /// S_j in the root link's frame at home: (ω, −ω × p) for a revolute joint at p with axis ω,
    /// (ω, −ω × p + hω) for a helical one of pitch h, (0, ω) for a prismatic one
    /// ([`crate::TreeJoint::screw_at`]).
    pub s_space: ScrewAxis,
    /// The joint frame in the root link's frame at home.
    pub home: Se3,
    /// The unit axis in the joint's own frame (the file's `<axis>`, normalised): S_j =
    /// Ad_{home} (axis, 0) for a revolute joint, Ad_{home} (axis, h axis) for a helical one,
    /// Ad_{home} (0, axis) for a prismatic one.
    pub axis: Vector3<f64>,
    /// The joint frame in its parent joint's frame (in the root link's frame when `parent` is
    /// `None`): the file's origins composed from there, so that home = home_parent · placement
    /// holds with the file's own numbers (an exact identity rotation stays exact).
    pub placement: Se3,
    /// Which variable drives it (index into [`KinematicTree::variables`], joint variables
    /// only) and how: θ = multiplier · q + offset.
    pub drive: Drive,
    /// The nearest movable joint above it (index into [`KinematicTree::joints`]), `None` when
    /// only fixed joints lie between it and the root.
    pub parent: Option<usize>,
}

/// A link of the whole tree.
#[derive(Debug, Clone, PartialEq)]
pub struct TreeLink {
    /// Link name.
    pub name: String,
    /// M_L: the link's pose in the root link's frame at home.
    pub home: Se3,
    /// The nearest movable joint above it (index into [`KinematicTree::joints`]), `None` for
    /// links rigidly attached to the root.
    pub support: Option<usize>,
    /// The link frame in its support joint's frame (in the root link's frame without one): the
    /// file's origins composed from there (the identity for the child of a movable joint).
    pub placement: Se3,
    /// The parent link (index into [`KinematicTree::links`]), `None` for the root.
    pub parent: Option<usize>,
}

/// A named frame: a link, or an extra frame fixed to one.
#[derive(Debug, Clone, PartialEq)]
pub struct TreeFrame {
    /// Frame name (unique among links and frames).
    pub name: String,
    /// The link it is fixed to (index into [`KinematicTree::links`]).
    pub link: usize,
    /// Its pose in that link's frame (the identity for a link's own frame).
    pub placement: Se3,
    /// M_F = M_L · placement: its pose in the root link's frame at home.
    pub home: Se3,
}

/// The whole robot as a tree of screws (see the module documentation for the formula, the
/// variable order and the floating base's configuration).
#[derive(Debug, Clone)]
pub struct KinematicTree {
    /// The robot's name.
    pub robot: String,
    /// The file it came from.
    pub source: String,
    /// The parsed tree (kept for the chain views: [`KinematicTree::chain_to`]).
    pub tree: Tree,
    /// A free joint (6 DoF) between the world and the root link.
    pub floating_base: bool,
    /// The movable joints, parents before children (depth first from the root, children in
    /// the file's order).
    pub joints: Vec<TreeScrew>,
    /// The independent joint variables, in the file's joint order (mimic followers excluded).
    pub variables: Vec<Variable>,
    /// Every link, in the file's order.
    pub links: Vec<TreeLink>,
    /// Every frame: the links first (frame i = link i for i < links.len()), then the extra
    /// frames in the order they were added.
    pub frames: Vec<TreeFrame>,
    frame_index: HashMap<String, usize>,
}

/// The names of the floating base's seven configuration entries.
pub const BASE_Q_NAMES: [&str; 7] = ["x", "y", "z", "qx", "qy", "qz", "qw"];
/// The names of the floating base's six velocity entries ((ω, v), base frame).
pub const BASE_V_NAMES: [&str; 6] = ["wx", "wy", "wz", "vx", "vy", "vz"];
/// The name the floating base's variable goes by (in `info` and the q/v labels).
pub const FLOATING_BASE: &str = "floating_base";

impl KinematicTree {
    /// The whole tree of `tree`, with a fixed base.
    pub fn from_tree(tree: &Tree) -> Result<KinematicTree, ModelError> {
        build(tree).map_err(|k| ModelError::new(tree.source.clone(), k))
    }

    /// The same tree with (or without) a floating base.
    pub fn with_floating_base(mut self, floating: bool) -> KinematicTree {
        self.floating_base = floating;
        self
    }

    /// The number of joint variables (without the floating base).
    pub fn joint_dof(&self) -> usize {
        self.variables.len()
    }

    /// nq: the length of a configuration (7 + n with a floating base, else n).
    pub fn nq(&self) -> usize {
        self.variables.len() + if self.floating_base { 7 } else { 0 }
    }

    /// nv: the length of a velocity and the Jacobian's column count (6 + n with a floating
    /// base, else n).
    pub fn nv(&self) -> usize {
        self.variables.len() + if self.floating_base { 6 } else { 0 }
    }

    /// The root link's name.
    pub fn root(&self) -> &str {
        &self.tree.links[self.tree.root]
    }

    /// One label per configuration entry: `floating_base.x` … `floating_base.qw` (with a
    /// floating base), then the joint variables' names.
    pub fn q_names(&self) -> Vec<String> {
        self.labels(&BASE_Q_NAMES)
    }

    /// One label per velocity entry (and Jacobian column): `floating_base.wx` …
    /// `floating_base.vz` (with a floating base), then the joint variables' names.
    pub fn v_names(&self) -> Vec<String> {
        self.labels(&BASE_V_NAMES)
    }

    fn labels(&self, base: &[&str]) -> Vec<String> {
        let base = base
            .iter()
            .filter(|_| self.floating_base)
            .map(|b| format!("{FLOATING_BASE}.{b}"));
        base.chain(self.variables.iter().map(|v| v.name.clone()))
            .collect()
    }

    /// The index of a frame (a link or an extra frame) by name; an error offering the closest
    /// names if there is none.
    pub fn frame(&self, name: &str) -> Result<usize, ModelError> {
        self.frame_index.get(name).copied().ok_or_else(|| {
            let names: Vec<String> = self.frames.iter().map(|f| f.name.clone()).collect();
            ModelError::new(
                self.source.clone(),
                ErrorKind::UnknownFrame {
                    frame: name.to_string(),
                    available: crate::tree::suggest_named(name, &names, "frames"),
                },
            )
        })
    }

    /// Adds a frame fixed to `link` at `placement` (its pose in the link's frame); returns its
    /// index. The name must be new among links and frames.
    pub fn add_frame(
        &mut self,
        name: &str,
        link: &str,
        placement: Se3,
    ) -> Result<usize, ModelError> {
        let err = |k| ModelError::new(self.source.clone(), k);
        if name.is_empty() {
            return Err(err(ErrorKind::BadFrame("a frame needs a name".into())));
        }
        if self.frame_index.contains_key(name) {
            return Err(err(ErrorKind::Duplicate {
                what: "frame",
                name: name.to_string(),
            }));
        }
        let l = self.tree.link(link)?;
        let index = self.frames.len();
        self.frames.push(TreeFrame {
            name: name.to_string(),
            link: l,
            placement,
            home: self.links[l].home.compose(&placement),
        });
        self.frame_index.insert(name.to_string(), index);
        Ok(index)
    }

    /// The movable joints on the path root → `frame`'s link, root first (indices into
    /// [`KinematicTree::joints`]).
    pub fn path(&self, frame: usize) -> Vec<usize> {
        let mut path = Vec::new();
        let mut j = self.links[self.frames[frame].link].support;
        while let Some(k) = j {
            path.push(k);
            j = self.joints[k].parent;
        }
        path.reverse();
        path
    }

    /// The serial chain root → `frame`'s link (with the frame's placement as its tool when the
    /// frame is not a link's own), or `None` when the frame is on the root link. Its space frame
    /// is the root link's, so its FK equals the tree's FK of the frame (fixed base).
    pub fn chain_to(&self, frame: usize) -> Result<Option<Chain>, ModelError> {
        let f = &self.frames[frame];
        if f.link == self.tree.root {
            return Ok(None);
        }
        let chain = Chain::from_tree(
            &self.tree,
            Some(self.root()),
            Some(&self.tree.links[f.link]),
        )?;
        Ok(Some(if frame < self.links.len() {
            chain
        } else {
            chain.with_tool(&f.placement)
        }))
    }
}

fn build(tree: &Tree) -> Result<KinematicTree, ErrorKind> {
    // The variables: the file's movable joints without a <mimic>, in file order.
    let mut variables = Vec::new();
    let mut variable_of_joint: HashMap<usize, usize> = HashMap::new();
    for (j, joint) in tree.joints.iter().enumerate() {
        match joint.kind {
            JointKind::Fixed => {}
            k if k.is_movable() => {
                if joint.mimic.is_none() {
                    variable_of_joint.insert(j, variables.len());
                    variables.push(variable_of(joint)?);
                }
            }
            k => {
                return Err(ErrorKind::UnsupportedJoint {
                    joint: joint.name.clone(),
                    kind: k.as_str().into(),
                })
            }
        }
    }
    let n_links = tree.links.len();
    let mut links: Vec<Option<TreeLink>> = vec![None; n_links];
    links[tree.root] = Some(TreeLink {
        name: tree.links[tree.root].clone(),
        home: Se3::identity(),
        support: None,
        placement: Se3::identity(),
        parent: None,
    });
    let mut joints = Vec::new();
    let mut mimics = MimicResolver::new(tree);
    // Depth first from the root, children in file order: (link, its home pose, its support,
    // its pose in the support's frame).
    let mut stack = vec![(tree.root, Se3::identity(), None::<usize>, Se3::identity())];
    while let Some((link, pose, support, local)) = stack.pop() {
        let mut below = Vec::new();
        for &j in &tree.child_joints[link] {
            let joint = &tree.joints[j];
            let origin = joint.origin()?;
            let t = pose.compose(&origin);
            let mut child_local = local.compose(&origin);
            let mut child_support = support;
            if joint.kind.is_movable() {
                let local_axis = joint.unit_axis()?;
                let s = joint.screw_at(&t)?;
                let (leader, multiplier, offset) = mimics.resolve(j)?;
                let variable = *variable_of_joint
                    .get(&leader)
                    .ok_or_else(|| ErrorKind::Mimic {
                        joint: joint.name.clone(),
                        problem: format!(
                            "joint \"{}\", which is not an independent variable",
                            tree.joints[leader].name
                        ),
                    })?;
                joints.push(TreeScrew {
                    name: joint.name.clone(),
                    kind: joint.kind,
                    s_space: s,
                    home: t,
                    axis: local_axis,
                    placement: child_local,
                    drive: Drive {
                        variable,
                        multiplier,
                        offset,
                    },
                    parent: support,
                });
                child_support = Some(joints.len() - 1);
                child_local = Se3::identity();
            }
            links[joint.child] = Some(TreeLink {
                name: tree.links[joint.child].clone(),
                home: t,
                support: child_support,
                placement: child_local,
                parent: Some(link),
            });
            below.push((joint.child, t, child_support, child_local));
        }
        stack.extend(below.into_iter().rev());
    }
    let links: Vec<TreeLink> = links
        .into_iter()
        .map(|l| l.expect("every link is reachable from the root (checked by Tree::new)"))
        .collect();
    let frames = links
        .iter()
        .enumerate()
        .map(|(i, l)| TreeFrame {
            name: l.name.clone(),
            link: i,
            placement: Se3::identity(),
            home: l.home,
        })
        .collect::<Vec<_>>();
    let frame_index = frames
        .iter()
        .enumerate()
        .map(|(i, f)| (f.name.clone(), i))
        .collect();
    Ok(KinematicTree {
        robot: tree.name.clone(),
        source: tree.source.clone(),
        tree: tree.clone(),
        floating_base: false,
        joints,
        variables,
        links,
        frames,
        frame_index,
    })
}
