//! The kinematic tree: links, joints and the paths between links.

use std::collections::HashMap;

use crate::geometry::{Geometry, Shape};

use nalgebra::Vector3;
use screwkit_lie::{ScrewAxis, Se3};

use crate::error::{ErrorKind, ModelError};

/// The type of a URDF joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about the axis within limits.
    Revolute,
    /// Rotation about the axis without limits.
    Continuous,
    /// Translation along the axis within limits.
    Prismatic,
    /// A screw motion about the axis: rotation θ with translation hθ along it (pitch h ≠ 0,
    /// [`TreeJoint::pitch`]), within limits (±∞ for an unbounded one, which is not periodic).
    /// URDF and MJCF have no such joint; robots built from screw axes do.
    Helical,
    /// No motion.
    Fixed,
    /// 6-DoF free joint (not supported on a chain).
    Floating,
    /// 3-DoF planar joint (not supported on a chain).
    Planar,
    /// 3-DoF ball joint (not supported on a chain).
    Spherical,
}

impl JointKind {
    /// The URDF spelling (`"revolute"`, …).
    pub fn as_str(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Continuous => "continuous",
            JointKind::Prismatic => "prismatic",
            JointKind::Helical => "helical",
            JointKind::Fixed => "fixed",
            JointKind::Floating => "floating",
            JointKind::Planar => "planar",
            JointKind::Spherical => "spherical",
        }
    }

    /// True for the one-variable joints a chain can hold (revolute, continuous, prismatic,
    /// helical).
    pub fn is_movable(self) -> bool {
        matches!(
            self,
            JointKind::Revolute | JointKind::Continuous | JointKind::Prismatic | JointKind::Helical
        )
    }

    /// True for a joint that rotates (revolute, continuous, helical).
    pub fn rotates(self) -> bool {
        matches!(
            self,
            JointKind::Revolute | JointKind::Continuous | JointKind::Helical
        )
    }
}

/// True for limits that do not bound the joint: (−∞, +∞).
pub fn is_unbounded(lower: f64, upper: f64) -> bool {
    lower == f64::NEG_INFINITY && upper == f64::INFINITY
}

/// `<limit>` of a joint as written in the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit {
    /// Lower position limit (rad or m).
    pub lower: f64,
    /// Upper position limit (rad or m).
    pub upper: f64,
    /// Velocity limit, if the attribute was written.
    pub velocity: Option<f64>,
    /// Effort limit, if the attribute was written.
    pub effort: Option<f64>,
}

/// `<mimic joint multiplier offset>`: this joint's position is multiplier · q_leader + offset.
#[derive(Debug, Clone, PartialEq)]
pub struct Mimic {
    /// The joint followed.
    pub leader: String,
    /// Multiplier (default 1).
    pub multiplier: f64,
    /// Offset (default 0).
    pub offset: f64,
}

/// A link's `<inertial>`: its mass, centre of mass and rotational inertia.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertial {
    /// `<mass value>` (kg), finite and ≥ 0.
    pub mass: f64,
    /// The centre of mass in the link's frame: `<inertial><origin xyz>` (zero when absent;
    /// `rpy` only turns the inertia tensor's axes, so it does not move the centre).
    pub com: [f64; 3],
    /// The inertia tensor about the centre of mass, in the link's axes (the file's tensor
    /// turned by its `rpy`, or an MJCF `quat`): (ixx, ixy, ixz, iyy, iyz, izz), kg m². Zero
    /// where the file gives none. Not checked here (dynamics checks it: [`Inertial::problem`]).
    pub inertia: [f64; 6],
}

/// An inertia tensor (ixx, ixy, ixz, iyy, iyz, izz) given in axes turned by `r` from the
/// link's, in the link's axes: R I Rᵀ.
pub fn rotate_inertia(local: &[f64; 6], r: &nalgebra::Matrix3<f64>) -> [f64; 6] {
    let [xx, xy, xz, yy, yz, zz] = *local;
    let i = nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
    let o = r * i * r.transpose();
    [
        o[(0, 0)],
        o[(0, 1)],
        o[(0, 2)],
        o[(1, 1)],
        o[(1, 2)],
        o[(2, 2)],
    ]
}

impl Inertial {
    /// The tensor as a symmetric 3 × 3 matrix, rows (ixx ixy ixz), (ixy iyy iyz), (ixz iyz izz).
    pub fn tensor(&self) -> [[f64; 3]; 3] {
        let [xx, xy, xz, yy, yz, zz] = self.inertia;
        [[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]
    }

    /// Why this inertial cannot be a rigid body's, or `None`: a negative mass, an inertia
    /// tensor that is not positive semi-definite (a negative principal moment, beyond a
    /// relative 1e-9), or principal moments breaking the triangle inequality (A + B ≥ C, same
    /// tolerance) — what MuJoCo's compiler refuses.
    pub fn problem(&self) -> Option<String> {
        if !(self.mass.is_finite() && self.mass >= 0.0) {
            return Some(format!("mass {} is not a finite number ≥ 0", self.mass));
        }
        if self.inertia.iter().any(|x| !x.is_finite()) {
            return Some("the inertia tensor is not finite".into());
        }
        let t = self.tensor();
        let m = nalgebra::Matrix3::from_fn(|i, j| t[i][j]);
        let mut e: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
        e.sort_by(f64::total_cmp);
        let scale = e[2].abs().max(f64::MIN_POSITIVE);
        if e[0] < -1e-9 * scale {
            return Some(format!(
                "the inertia tensor is not positive semi-definite (principal moments {:.6e}, {:.6e}, {:.6e})",
                e[0], e[1], e[2]
            ));
        }
        if e[0] + e[1] < e[2] * (1.0 - 1e-9) {
            return Some(format!(
                "the principal moments {:.6e}, {:.6e}, {:.6e} break the triangle inequality (A + B ≥ C)",
                e[0], e[1], e[2]
            ));
        }
        None
    }

    /// The inertial as MuJoCo's `<compiler balanceinertia="true">` makes it: when the principal
    /// moments break the triangle inequality A + B ≥ C, all three become their mean (the
    /// tensor (tr Ī / 3) 1); otherwise unchanged.
    pub fn balanced(&self) -> Inertial {
        let t = self.tensor();
        let m = nalgebra::Matrix3::from_fn(|i, j| t[i][j]);
        if !m.iter().all(|x| x.is_finite()) {
            return *self;
        }
        let mut e: Vec<f64> = m.symmetric_eigenvalues().iter().copied().collect();
        e.sort_by(f64::total_cmp);
        if e[0] + e[1] >= e[2] * (1.0 - 1e-9) {
            return *self;
        }
        let mean = (t[0][0] + t[1][1] + t[2][2]) / 3.0;
        Inertial {
            inertia: [mean, 0.0, 0.0, mean, 0.0, mean],
            ..*self
        }
    }
}

/// A joint's passive dynamics as the file gives them (zero when it says nothing): MuJoCo's
/// `armature` (a rotor's inertia, added to the joint's diagonal entry of the mass matrix) and
/// `damping` (a force −damping · θ̇), URDF's `<dynamics damping>`; the dry friction (URDF's
/// `<dynamics friction>`, MuJoCo's `frictionloss`) is kept for reference. Dynamics uses them
/// only when asked.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct JointDynamics {
    /// Armature inertia (kg m², or kg for a slide).
    pub armature: f64,
    /// Viscous damping (N m s/rad, or N s/m).
    pub damping: f64,
    /// Dry friction (N m, or N).
    pub friction: f64,
}

/// A joint of the tree, as read from the URDF (not yet validated for chain use).
#[derive(Debug, Clone, PartialEq)]
pub struct TreeJoint {
    /// Joint name.
    pub name: String,
    /// Joint type.
    pub kind: JointKind,
    /// Index of the parent link.
    pub parent: usize,
    /// Index of the child link.
    pub child: usize,
    /// `<origin xyz>` (zero when absent).
    pub origin_xyz: [f64; 3],
    /// `<origin rpy>` (zero when absent), fixed axes: R = R_z(y) R_y(p) R_x(r).
    pub origin_rpy: [f64; 3],
    /// The origin's rotation exactly, as a unit quaternion (w, x, y, z), when the format gives
    /// it as one (MJCF): used in place of `origin_rpy`, which is then its roll-pitch-yaw for
    /// display only (rpy loses precision near pitch ±π/2).
    pub origin_quat: Option<[f64; 4]>,
    /// `<axis xyz>` as written (default (1, 0, 0)); normalised when a chain is built.
    pub axis: [f64; 3],
    /// `<limit>`, if present.
    pub limit: Option<Limit>,
    /// `<mimic>`, if present.
    pub mimic: Option<Mimic>,
    /// The pitch h of a helical joint (m/rad), 0 for every other kind.
    pub pitch: f64,
    /// Armature, damping and friction (zero when the file gives none).
    pub dynamics: JointDynamics,
}

impl TreeJoint {
    /// The joint's screw axis in the base frame when its frame is at `t` (the base-frame pose
    /// of the joint frame at home): (0, R a) for a prismatic joint, (ω, −ω × p + hω) with
    /// ω = R a for a rotating one (h: [`TreeJoint::pitch`], 0 unless helical).
    pub fn screw_at(&self, t: &Se3) -> Result<ScrewAxis, ErrorKind> {
        let axis = t.rotation() * self.unit_axis()?;
        let pitch = if self.kind == JointKind::Helical {
            self.pitch
        } else {
            0.0
        };
        if !pitch.is_finite() {
            return Err(ErrorKind::NonFinite {
                joint: self.name.clone(),
                what: "pitch".into(),
            });
        }
        if self.kind == JointKind::Prismatic {
            ScrewAxis::prismatic(axis)
        } else {
            ScrewAxis::from_point_direction_pitch(*t.translation(), axis, pitch)
        }
        .map_err(|_| ErrorKind::ZeroAxis(self.name.clone()))
    }

    /// The joint frame in the parent link frame at zero position (`<origin>`), checked finite.
    pub fn origin(&self) -> Result<Se3, ErrorKind> {
        let bad = || ErrorKind::NonFinite {
            joint: self.name.clone(),
            what: "<origin>".into(),
        };
        match self.origin_quat {
            Some([w, x, y, z]) => {
                let q = nalgebra::Quaternion::new(w, x, y, z);
                let t = Vector3::from(self.origin_xyz);
                if !(q.coords.iter().all(|v| v.is_finite()) && t.iter().all(|v| v.is_finite()))
                    || q.norm() < 0.5
                {
                    return Err(bad());
                }
                let r = nalgebra::UnitQuaternion::from_quaternion(q).to_rotation_matrix();
                Ok(Se3::from_parts_unchecked(*r.matrix(), t))
            }
            None => Se3::from_xyz_rpy(self.origin_xyz, self.origin_rpy).map_err(|_| bad()),
        }
    }

    /// The unit axis, checked: finite and non-zero (for movable joints).
    pub fn unit_axis(&self) -> Result<Vector3<f64>, ErrorKind> {
        let a = Vector3::from(self.axis);
        if !a.iter().all(|x| x.is_finite()) {
            return Err(ErrorKind::NonFinite {
                joint: self.name.clone(),
                what: "<axis>".into(),
            });
        }
        // Below 1e-9 the direction is noise (a typo, or rounding of a zero axis): refuse it as
        // a zero axis rather than blow it up to unit length.
        let n = a.norm();
        if n < 1e-9 {
            return Err(ErrorKind::ZeroAxis(self.name.clone()));
        }
        Ok(a / n)
    }
}

/// A URDF robot as a tree: one root, every other link with exactly one parent joint.
#[derive(Debug, Clone)]
pub struct Tree {
    /// The robot's name.
    pub name: String,
    /// Where it was loaded from (file path or label), used in error messages.
    pub source: String,
    /// Link names, in file order.
    pub links: Vec<String>,
    /// Each link's `<inertial>` (index as `links`), `None` where the file has none.
    pub inertials: Vec<Option<Inertial>>,
    /// Joints, in file order.
    pub joints: Vec<TreeJoint>,
    /// For each link, the joint whose child it is (`None` for the root).
    pub parent_joint: Vec<Option<usize>>,
    /// For each link, the joints whose parent it is.
    pub child_joints: Vec<Vec<usize>>,
    /// Index of the root link.
    pub root: usize,
    /// The file gives the root link a free joint (MJCF's `<freejoint>` on the only top-level
    /// body): the whole tree is loaded with a floating base.
    pub floating_root: bool,
    /// What the reader read past that changes kinematics (an MJCF tendon, a loop-closing
    /// equality), one sentence each, for front ends to show.
    pub warnings: Vec<String>,
    /// Where the tree's variables sit in the file's own configuration vector, when the file
    /// has one of another layout (an MJCF model's `qpos`, props read past included).
    pub qpos_layout: Option<QposLayout>,
    /// Every link's collision and visual shapes, in the file's order ([`crate::geometry`]).
    pub geometries: Vec<Geometry>,
    /// The geometry elements that could not be read, one sentence each naming the link; a
    /// query of the body reports them (kinematics does not need them).
    pub geometry_problems: Vec<String>,
    /// MuJoCo's contact rules, for an MJCF model ([`crate::geometry::ContactRules`]); None
    /// for URDF (the collision model's link rules).
    pub contact_rules: Option<crate::geometry::ContactRules>,
    /// The world's gravity (m/s²) when the file gives it (an MJCF's `<option gravity>`); None:
    /// the standard (0, 0, −9.81), also MuJoCo's default.
    pub gravity: Option<[f64; 3]>,
    link_index: HashMap<String, usize>,
    joint_index: HashMap<String, usize>,
}

/// Where a tree's joints sit in a model's whole configuration vector (MuJoCo's `qpos`: every
/// joint of every body, depth first, a free joint's seven numbers, a ball's four, a hinge's or
/// slide's one), so that a model with bodies the tree reads past (props) still converts.
#[derive(Debug, Clone, PartialEq)]
pub struct QposLayout {
    /// The length of the whole model's vector.
    pub len: usize,
    /// The address of the floating root's free joint (seven entries: x, y, z, w, x, y, z).
    pub base: Option<usize>,
    /// Each hinge or slide joint of the tree, by name: its entry's address.
    pub joints: Vec<(String, usize)>,
}

/// Joins names for messages, shortening long lists.
pub(crate) fn name_list<'a>(names: impl IntoIterator<Item = &'a str>) -> String {
    let all: Vec<&str> = names.into_iter().collect();
    let mut s = all
        .iter()
        .take(20)
        .map(|n| format!("\"{n}\""))
        .collect::<Vec<_>>()
        .join(", ");
    if all.len() > 20 {
        s.push_str(&format!(", … ({} in all)", all.len()));
    }
    s
}

/// What an unknown-link error offers: every link of a small model, else the three names
/// closest to `name` (edit distance, ignoring case) and the count.
fn suggest(name: &str, links: &[String]) -> String {
    suggest_named(name, links, "links")
}

/// [`suggest`] for any list of names (`what`: "links", "frames").
pub(crate) fn suggest_named(name: &str, links: &[String], what: &str) -> String {
    if links.len() <= 10 {
        return format!("{what}: {}", name_list(links.iter().map(String::as_str)));
    }
    let want: Vec<char> = name.to_lowercase().chars().take(64).collect();
    let mut scored: Vec<(usize, &str)> = links
        .iter()
        .map(|l| {
            (
                edit_distance(
                    &want,
                    &l.to_lowercase().chars().take(64).collect::<Vec<_>>(),
                ),
                l.as_str(),
            )
        })
        .collect();
    scored.sort_by_key(|&(d, _)| d);
    let best: Vec<String> = scored
        .iter()
        .take(3)
        .map(|(_, l)| format!("\"{l}\""))
        .collect();
    format!(
        "did you mean {}? {} {what} in all",
        best.join(", "),
        links.len()
    )
}

/// Levenshtein distance (insertions, deletions, substitutions), O(|a|·|b|) with one row.
fn edit_distance(a: &[char], b: &[char]) -> usize {
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

impl Tree {
    /// Builds and validates the tree: unique names, existing parent/child links, one parent
    /// per link, exactly one root, no cycles.
    pub fn new(
        name: String,
        source: String,
        links: Vec<String>,
        joints: Vec<(TreeJointSpec, String, String)>,
    ) -> Result<Tree, ModelError> {
        let err = |kind| ModelError::new(source.clone(), kind);
        let mut link_index = HashMap::new();
        for (i, l) in links.iter().enumerate() {
            if link_index.insert(l.clone(), i).is_some() {
                return Err(err(ErrorKind::Duplicate {
                    what: "link",
                    name: l.clone(),
                }));
            }
        }
        if links.is_empty() {
            return Err(err(ErrorKind::NoRoot("the robot has no links".into())));
        }
        let mut joint_index = HashMap::new();
        let mut tree_joints = Vec::with_capacity(joints.len());
        let mut parent_joint: Vec<Option<usize>> = vec![None; links.len()];
        let mut child_joints = vec![Vec::new(); links.len()];
        for (j, (spec, parent, child)) in joints.into_iter().enumerate() {
            if joint_index.insert(spec.name.clone(), j).is_some() {
                return Err(err(ErrorKind::Duplicate {
                    what: "joint",
                    name: spec.name,
                }));
            }
            let find = |link: &str, role| {
                link_index.get(link).copied().ok_or_else(|| {
                    err(ErrorKind::MissingLink {
                        joint: spec.name.clone(),
                        role,
                        link: link.to_string(),
                    })
                })
            };
            let p = find(&parent, "parent")?;
            let c = find(&child, "child")?;
            if let Some(first) = parent_joint[c] {
                let first: &TreeJoint = &tree_joints[first];
                return Err(err(ErrorKind::TwoParents {
                    link: child,
                    first: first.name.clone(),
                    second: spec.name,
                }));
            }
            parent_joint[c] = Some(j);
            child_joints[p].push(j);
            tree_joints.push(spec.into_joint(p, c));
        }
        let roots: Vec<usize> = (0..links.len())
            .filter(|&l| parent_joint[l].is_none())
            .collect();
        let root = match roots.as_slice() {
            [r] => *r,
            [] => {
                return Err(err(ErrorKind::NoRoot(
                    "every link is the child of a joint, so the joints form a cycle".into(),
                )))
            }
            _ => {
                return Err(err(ErrorKind::SeveralRoots(name_list(
                    roots.iter().map(|&r| links[r].as_str()),
                ))))
            }
        };
        // With one root and one parent per link, a link not reachable from the root is on a
        // cycle.
        let mut seen = vec![false; links.len()];
        let mut stack = vec![root];
        while let Some(l) = stack.pop() {
            seen[l] = true;
            for &j in &child_joints[l] {
                let c = tree_joints[j].child;
                if !seen[c] {
                    stack.push(c);
                }
            }
        }
        if seen.iter().any(|s| !s) {
            return Err(err(ErrorKind::Cycle(name_list(
                (0..links.len())
                    .filter(|&l| !seen[l])
                    .map(|l| links[l].as_str()),
            ))));
        }
        let warnings = mimic_limit_warnings(&tree_joints, &joint_index);
        Ok(Tree {
            name,
            source,
            inertials: vec![None; links.len()],
            links,
            joints: tree_joints,
            parent_joint,
            child_joints,
            root,
            floating_root: false,
            warnings,
            qpos_layout: None,
            geometries: Vec::new(),
            geometry_problems: Vec::new(),
            gravity: None,
            contact_rules: None,
            link_index,
            joint_index,
        })
    }

    /// Resolves every mesh's file name ([`crate::geometry::resolve_mesh`]) from `dir` (the
    /// robot file's folder) and `package_paths`; a name that cannot be resolved becomes a
    /// problem naming its link, and its shape is dropped.
    pub fn resolve_meshes(&mut self, dir: &std::path::Path, package_paths: &[std::path::PathBuf]) {
        let mut problems = Vec::new();
        let links = &self.links;
        self.geometries.retain_mut(|g| {
            let Shape::Mesh { uri, path, .. } = &mut g.shape else {
                return true;
            };
            match crate::geometry::resolve_mesh(uri, dir, package_paths) {
                Ok(p) => {
                    *path = p;
                    true
                }
                Err(e) => {
                    problems.push(format!(
                        "link \"{}\" <{}>: {e}",
                        links[g.link],
                        g.role.word()
                    ));
                    false
                }
            }
        });
        self.geometry_problems.extend(problems);
    }

    fn error(&self, kind: ErrorKind) -> ModelError {
        ModelError::new(self.source.clone(), kind)
    }

    /// The index of a link by name; an error listing the links if unknown.
    pub fn link(&self, name: &str) -> Result<usize, ModelError> {
        self.link_index.get(name).copied().ok_or_else(|| {
            self.error(ErrorKind::UnknownLink {
                link: name.to_string(),
                available: suggest(name, &self.links),
            })
        })
    }

    /// The index of a joint by name.
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joint_index.get(name).copied()
    }

    /// The leaf links (no child joints) at or below `link`, in depth-first order.
    pub fn leaves_below(&self, link: usize) -> Vec<usize> {
        let mut out = Vec::new();
        let mut stack = vec![link];
        while let Some(l) = stack.pop() {
            if self.child_joints[l].is_empty() {
                out.push(l);
            }
            for &j in self.child_joints[l].iter().rev() {
                stack.push(self.joints[j].child);
            }
        }
        out
    }

    /// The joints from `base` down to `tip`, in order; an error if `base` is not an ancestor
    /// of `tip`.
    pub fn path(&self, base: usize, tip: usize) -> Result<Vec<usize>, ModelError> {
        if base == tip {
            return Err(self.error(ErrorKind::SameLink(self.links[base].clone())));
        }
        let mut path = Vec::new();
        let mut l = tip;
        while l != base {
            match self.parent_joint[l] {
                Some(j) => {
                    path.push(j);
                    l = self.joints[j].parent;
                }
                None => {
                    return Err(self.error(ErrorKind::NotAncestor {
                        base: self.links[base].clone(),
                        tip: self.links[tip].clone(),
                    }))
                }
            }
        }
        path.reverse();
        Ok(path)
    }

    /// The pose of link `to` in the frame of link `from` when they are rigidly attached: every
    /// joint between them (below their common ancestor) is fixed. Otherwise an error naming
    /// the joint that moves.
    pub fn fixed_transform(&self, from: &str, to: &str) -> Result<Se3, ModelError> {
        let (a, b) = (self.link(from)?, self.link(to)?);
        let up = |mut l: usize| {
            let mut joints = Vec::new();
            while let Some(j) = self.parent_joint[l] {
                joints.push(j);
                l = self.joints[j].parent;
            }
            joints.reverse();
            joints
        };
        let (pa, pb) = (up(a), up(b));
        let common = pa.iter().zip(&pb).take_while(|(x, y)| x == y).count();
        let compose = |joints: &[usize]| -> Result<Se3, ModelError> {
            let mut t = Se3::identity();
            for &j in joints {
                let joint = &self.joints[j];
                if joint.kind != JointKind::Fixed {
                    return Err(self.error(ErrorKind::NotRigid {
                        from: from.to_string(),
                        to: to.to_string(),
                        joint: joint.name.clone(),
                    }));
                }
                t = t.compose(&joint.origin().map_err(|k| self.error(k))?);
            }
            Ok(t)
        };
        Ok(compose(&pa[common..])?
            .inverse()
            .compose(&compose(&pb[common..])?))
    }

    /// The default chain ends: base = the given link or the root; tip = the given link or
    /// the single leaf below the base (an error listing the leaves if there are several).
    pub fn default_ends(
        &self,
        base: Option<&str>,
        tip: Option<&str>,
    ) -> Result<(usize, usize), ModelError> {
        let b = match base {
            Some(n) => self.link(n)?,
            None => self.root,
        };
        let t = match tip {
            Some(n) => self.link(n)?,
            None => {
                let leaves = self.leaves_below(b);
                match leaves.as_slice() {
                    [one] => *one,
                    _ => {
                        return Err(self.error(ErrorKind::AmbiguousTip {
                            base: self.links[b].clone(),
                            count: leaves.len(),
                            leaves: name_list(leaves.iter().map(|&l| self.links[l].as_str())),
                        }))
                    }
                }
            }
        };
        Ok((b, t))
    }
}

/// A joint as parsed, before its links are resolved to indices.
#[derive(Debug, Clone)]
pub struct TreeJointSpec {
    /// Joint name.
    pub name: String,
    /// Joint type.
    pub kind: JointKind,
    /// `<origin xyz>`.
    pub origin_xyz: [f64; 3],
    /// `<origin rpy>`.
    pub origin_rpy: [f64; 3],
    /// The origin's rotation as a unit quaternion (w, x, y, z), overriding `origin_rpy`.
    pub origin_quat: Option<[f64; 4]>,
    /// `<axis xyz>`.
    pub axis: [f64; 3],
    /// `<limit>`.
    pub limit: Option<Limit>,
    /// `<mimic>`.
    pub mimic: Option<Mimic>,
    /// The pitch of a helical joint (0 otherwise).
    pub pitch: f64,
    /// Armature, damping and friction.
    pub dynamics: JointDynamics,
}

impl TreeJointSpec {
    fn into_joint(self, parent: usize, child: usize) -> TreeJoint {
        TreeJoint {
            name: self.name,
            kind: self.kind,
            parent,
            child,
            origin_xyz: self.origin_xyz,
            origin_rpy: self.origin_rpy,
            origin_quat: self.origin_quat,
            axis: self.axis,
            limit: self.limit,
            mimic: self.mimic,
            pitch: self.pitch,
            dynamics: self.dynamics,
        }
    }
}

/// The rule for a mimic follower's own limits (one rule, everywhere: `lower`/`upper`, IK,
/// whole-body IK and their messages): a joint variable's position limits are its leader
/// joint's own, as ROS's tools treat mimic joints; a follower's `<limit>` does not narrow them.
/// Where a follower's limits cannot hold over its leader's whole range (the PR2's gripper: a
/// follower of multiplier −1 given the leader's own [0, 0.548]), that is said once, naming the
/// follower, instead of silently locking the leader at the one value both allow.
fn mimic_limit_warnings(
    joints: &[TreeJoint],
    index: &std::collections::HashMap<String, usize>,
) -> Vec<String> {
    let mut out = Vec::new();
    for f in joints {
        let Some(m) = &f.mimic else { continue };
        let Some(&l) = index.get(&m.leader) else {
            continue;
        };
        let leader = &joints[l];
        let bounded = |j: &TreeJoint| {
            matches!(j.kind, JointKind::Revolute | JointKind::Prismatic)
                .then_some(j.limit)
                .flatten()
                .filter(|l| l.lower.is_finite() && l.upper.is_finite() && l.lower <= l.upper)
        };
        let (Some(fl), Some(ll)) = (bounded(f), bounded(leader)) else {
            continue;
        };
        if m.multiplier == 0.0 || !m.multiplier.is_finite() || !m.offset.is_finite() {
            continue;
        }
        // The follower's angles over the leader's range, against its own limits.
        let (a, b) = (
            m.multiplier * ll.lower + m.offset,
            m.multiplier * ll.upper + m.offset,
        );
        let (a, b) = (a.min(b), a.max(b));
        let slack = 1e-9 * (1.0 + fl.lower.abs().max(fl.upper.abs()));
        if a < fl.lower - slack || b > fl.upper + slack {
            out.push(format!(
                "joint \"{}\" mimics \"{}\" ({} = {} x {} + {}), but its own limits [{}, {}] \
                 do not hold over the leader's [{}, {}] (it would reach [{a}, {b}]): the leader's \
                 limits are kept, as ROS does, and the follower's are not enforced",
                f.name,
                m.leader,
                f.name,
                m.multiplier,
                m.leader,
                m.offset,
                fl.lower,
                fl.upper,
                ll.lower,
                ll.upper
            ));
        }
    }
    out
}
