//! What a picture shows, in 3D, computed by the solver: every link's pose (all-link FK, of the
//! chain or of the whole tree), every joint's screw axis at q (`jacobian::joint_screws`, the
//! columns of J_s(q) joint by joint) and the lines and marks derived from them. No kinematics
//! here: only where to put the ink.

use nalgebra::Vector3;
use screwkit_lie::{Se3, Twist};
use screwkit_model::{Chain, JointKind};
use screwkit_solve::tree::{fk as tree_fk, jacobian as tree_jacobian};
use screwkit_solve::{
    fk, jacobian, Kinematics, SolveError, TreeKinematics, TreeWorkspace, Workspace,
};

/// A link at q.
#[derive(Debug, Clone)]
pub struct LinkMark {
    /// Link name.
    pub name: String,
    /// Its pose in the base frame.
    pub pose: Se3,
    /// The link the skeleton's segment to this one starts from (index into
    /// [`Scene::links`]): the previous link on a chain, the parent link in a tree; `None` for
    /// the first link.
    pub parent: Option<usize>,
}

/// What a drawn frame (an RGB triad) is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameRole {
    /// The base (the space frame).
    Base,
    /// A chain's tip (with its tool frame).
    Tip,
    /// The end of one branch of a tree (a leaf link), drawn with its name.
    Leaf,
}

/// A frame drawn as a triad.
#[derive(Debug, Clone)]
pub struct FrameMark {
    /// Base, tip or leaf.
    pub role: FrameRole,
    /// The link it is (or is fixed to).
    pub name: String,
    /// Its pose in the base frame.
    pub pose: Se3,
}

/// A moving joint at q and its screw axis.
#[derive(Debug, Clone)]
pub struct JointMark {
    /// 1-based position along the chain, or in the tree's joint order (parents first): the
    /// label drawn next to its axis.
    pub index: usize,
    /// Joint name.
    pub name: String,
    /// Revolute, continuous or prismatic.
    pub kind: JointKind,
    /// The joint frame's origin (its child link's origin) in the base frame.
    pub origin: Vector3<f64>,
    /// Its space screw axis at q, S_j(q) = (ω, v).
    pub screw: Twist,
    /// The pitch ω·v / ‖ω‖² of a rotating joint (0 for URDF's revolute joints), `None` for a
    /// prismatic one.
    pub pitch: Option<f64>,
    /// The segment drawn for the axis: for a rotating joint, the line of the axis through its
    /// point closest to the joint origin, `axis_length` either side; for a prismatic joint, an
    /// arrow from the origin along v.
    pub line: [Vector3<f64>; 2],
}

/// Everything a picture of a chain, or of a whole tree, at q shows.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The robot's name.
    pub robot: String,
    /// What is drawn, for the caption: "chain base → tip" or "whole tree from root, …".
    pub subject: String,
    /// The values drawn (a tree's configuration: its `q_names`).
    pub q: Vec<f64>,
    /// The links: a chain's base → tip, or every link of the tree in the file's order.
    pub links: Vec<LinkMark>,
    /// The moving joints: a chain's base → tip, or every movable joint of the tree.
    pub joints: Vec<JointMark>,
    /// The frames drawn as triads: the base and the tip, or the base and every leaf.
    pub frames: Vec<FrameMark>,
    /// The characteristic size of the picture (m): the diagonal of the box around the link
    /// origins (at least 1 mm), from which axis and triad lengths are taken.
    pub size: f64,
    /// The body: each shape of each link at q ([`Scene::with_body`]); empty for a skeleton.
    pub outlines: Vec<crate::outline::Outline>,
    /// What of the body could not be drawn (a mesh that cannot be read, with its link).
    pub problems: Vec<String>,
}

/// The diagonal of the box around the link origins (at least 1 mm).
pub(crate) fn size_of(links: &[LinkMark]) -> f64 {
    let (lo, hi) = links.iter().fold(
        (
            Vector3::repeat(f64::INFINITY),
            Vector3::repeat(f64::NEG_INFINITY),
        ),
        |(lo, hi), l| (lo.inf(l.pose.translation()), hi.sup(l.pose.translation())),
    );
    (hi - lo).norm().max(1e-3)
}

/// A joint's mark from its screw at q and its frame's origin.
fn joint_mark(
    index: usize,
    name: &str,
    kind: JointKind,
    origin: Vector3<f64>,
    s: &Twist,
    axis_length: f64,
) -> JointMark {
    let (pitch, line) = if kind == JointKind::Prismatic {
        let d = s.v.normalize();
        (None, [origin, origin + d * axis_length])
    } else {
        let n2 = s.w.norm_squared();
        let w = s.w / n2.sqrt();
        // The point of the axis closest to the base origin is ω × v / ‖ω‖²; slide it along
        // the axis to the point closest to the joint origin.
        let p0 = s.w.cross(&s.v) / n2;
        let p = p0 + w * w.dot(&(origin - p0));
        (
            Some(s.w.dot(&s.v) / n2),
            [p - w * axis_length, p + w * axis_length],
        )
    };
    JointMark {
        index,
        name: name.to_string(),
        kind,
        origin,
        screw: *s,
        pitch,
        line,
    }
}

impl Scene {
    /// The scene of `chain` at `q` (default: all zeros, the home configuration).
    pub fn new(chain: &Chain, kin: &Kinematics, q: Option<&[f64]>) -> Result<Self, SolveError> {
        let zeros = vec![0.0; kin.dof()];
        let q = q.unwrap_or(&zeros);
        let mut ws = Workspace::new(kin);
        let screws = jacobian::joint_screws(kin, &mut ws, q)?;
        let poses = fk::fk_all_links(kin, &mut ws, q)?;
        let links: Vec<LinkMark> = kin
            .links()
            .iter()
            .zip(poses)
            .enumerate()
            .map(|(k, (l, pose))| LinkMark {
                name: l.name.clone(),
                pose: *pose,
                parent: k.checked_sub(1),
            })
            .collect();
        let size = size_of(&links);
        let joints = chain
            .joints
            .iter()
            .zip(&screws)
            .enumerate()
            .map(|(j, (joint, s))| {
                // The joint frame is its child link's frame: the first link after j + 1 joints.
                let origin = kin
                    .links()
                    .iter()
                    .position(|l| l.joints_before == j + 1)
                    .map_or_else(Vector3::zeros, |k| *links[k].pose.translation());
                joint_mark(j + 1, &joint.name, joint.kind, origin, s, 0.18 * size)
            })
            .collect();
        let tip = links.last().map_or_else(Se3::identity, |l| l.pose);
        Ok(Self {
            robot: chain.robot.clone(),
            subject: format!("chain {} → {}", chain.base, chain.tip),
            q: q.to_vec(),
            links,
            joints,
            frames: vec![
                FrameMark {
                    role: FrameRole::Base,
                    name: chain.base.clone(),
                    pose: Se3::identity(),
                },
                FrameMark {
                    role: FrameRole::Tip,
                    name: chain.tip.clone(),
                    pose: tip,
                },
            ],
            size,
            outlines: Vec::new(),
            problems: Vec::new(),
        })
    }

    /// The scene of the whole tree at `q` (its configuration, `q_names`; default: the neutral
    /// configuration): every link, every movable joint and its screw axis, the base and every
    /// leaf (the end of each branch) as a named triad.
    pub fn tree(kin: &TreeKinematics, q: Option<&[f64]>) -> Result<Self, SolveError> {
        let neutral = screwkit_solve::tree::configuration::neutral(kin);
        let q = q.unwrap_or(&neutral);
        let model = kin.model();
        let mut ws = TreeWorkspace::new(kin);
        let screws = tree_jacobian::joint_screws(kin, &mut ws, q)?;
        let poses = tree_fk::fk_frames(kin, &mut ws, q)?;
        let links: Vec<LinkMark> = model
            .links
            .iter()
            .zip(poses)
            .map(|(l, pose)| LinkMark {
                name: l.name.clone(),
                pose: *pose,
                parent: l.parent,
            })
            .collect();
        let size = size_of(&links);
        let joints: Vec<JointMark> = model
            .joints
            .iter()
            .zip(&screws)
            .enumerate()
            .map(|(k, (j, s))| {
                joint_mark(
                    k + 1,
                    &j.name,
                    j.kind,
                    *s.frame.translation(),
                    &s.screw,
                    0.18 * size,
                )
            })
            .collect();
        let root = model.tree.root;
        let mut frames = vec![FrameMark {
            role: FrameRole::Base,
            name: model.root().to_string(),
            pose: links[root].pose,
        }];
        let leaves = model
            .tree
            .child_joints
            .iter()
            .enumerate()
            .filter(|&(l, c)| c.is_empty() && l != root);
        frames.extend(leaves.map(|(l, _)| FrameMark {
            role: FrameRole::Leaf,
            name: links[l].name.clone(),
            pose: links[l].pose,
        }));
        Ok(Self {
            robot: model.robot.clone(),
            subject: format!(
                "whole tree from {}, {} links, {} joints, {} leaves",
                model.root(),
                links.len(),
                joints.len(),
                frames.len() - 1
            ),
            q: q.to_vec(),
            links,
            joints,
            frames,
            size,
            outlines: Vec::new(),
            problems: Vec::new(),
        })
    }

    /// The scene with the body of its links from `tree` (the robot file's shapes: each link's
    /// visual shapes, or its collision ones when it has none; [`crate::outline::outlines`]).
    pub fn with_body(mut self, tree: &screwkit_model::Tree) -> Self {
        let (outlines, problems) = crate::outline::outlines(tree, &self.links);
        self.outlines = outlines;
        self.problems.extend(tree.geometry_problems.iter().cloned());
        self.problems.extend(problems);
        self
    }

    /// The tip's pose (a chain's; the last leaf of a tree).
    pub fn tip_pose(&self) -> Se3 {
        self.frames.last().map_or_else(Se3::identity, |f| f.pose)
    }
}
