//! The whole robot: kinematics of every frame of a tree ([`screwkit_model::KinematicTree`]), with
//! an optional floating base (Pinocchio's model with frames: `forwardKinematics` +
//! `updateFramePlacements`, `computeFrameJacobian`).
//!
//! [`TreeKinematics`] is the immutable model, [`TreeWorkspace`] one thread's scratch; every
//! algorithm is `algorithm(&kin, &mut ws, inputs)`:
//!
//! | algorithm | what |
//! |---|---|
//! | [`fk::fk_frames`] | every frame's pose in one sweep (links first, then the extra frames) |
//! | [`fk::fk_frame`], [`fk::relative_pose`] | one frame's pose; frame A in frame B (T_B⁻¹ T_A) |
//! | [`jacobian::frame_jacobian`] | a frame's Jacobian (space, body, world-aligned), one column per velocity entry |
//! | [`jacobian::relative_jacobian`] | the Jacobian of frame A's motion relative to frame B |
//! | [`configuration`] | `integrate`, `difference`, `neutral`, `random` on SE(3) × joints |
//! | [`batch`] | N configurations of each, on all cores |
//!
//! The conventions (variable order, the floating base's q and v) are those of
//! [`screwkit_model::kinematic_tree`]: q = (x, y, z, qx, qy, qz, qw, joints…),
//! v = (ω, v_b of the base in its own frame, joint rates…).
//!
//! **Fast paths.** The path root → F of a frame is a serial chain ([`KinematicTree::chain_to`]);
//! one frame's pose runs the chain's FK kernel ([`crate::fk`]) on that chain's variables
//! gathered from q (and, with a floating base, composes with the base's pose). Every frame at
//! once is one sweep over the tree in each joint's own frame ([`fk::fk_frames`]): G_k =
//! G_parent(k) X_k e^{[a_k]θ_k} per joint, parents first, and T_F = G_support(F) P_F per frame;
//! one frame's Jacobian is the same sweep along its path only, each joint's world column
//! \[Ad_{G_k}\](a_k, 0) read off G_k ([`jacobian`]). The tests hold all of them equal to the URDF
//! composed joint by joint and the Jacobians to finite differences.

pub mod batch;
pub mod com;
pub mod configuration;
pub mod differential_ik;
pub mod dynamics;
pub mod fk;
pub mod jacobian;
pub mod limits;
pub mod tasks;

use nalgebra::Matrix6xX;
use screwkit_lie::Se3;

pub use crate::jacobian::JacobianKind;
use screwkit_model::{KinematicTree, ModelError};

use crate::columns::Columns;
use crate::error::SolveError;
use crate::kinematics::Kinematics;
use crate::poe::PoeJoint;

/// "No joint": a frame or joint with only fixed joints above it.
pub(crate) const NONE: usize = usize::MAX;

/// How far the floating base's quaternion may be from unit length (|‖quat‖ − 1|) before it is
/// refused; within it, the quaternion is normalised. Single precision (1e-7) passes.
pub const QUATERNION_TOLERANCE: f64 = 1e-6;

/// The former name of [`JacobianKind`] (the tree's Jacobians took a `Form`, the chain's a
/// `Frame` or a separate world-aligned function): one kind now serves both.
#[deprecated(note = "use `JacobianKind`, the one Jacobian kind of chains and trees")]
pub type Form = JacobianKind;

/// The chain root → a frame, prepared: its [`Kinematics`] and, for each of its variables, the
/// index of the tree's joint variable.
#[derive(Debug, Clone)]
pub(crate) struct View {
    pub(crate) kin: Kinematics,
    pub(crate) variables: Vec<usize>,
}

/// The per-frame constants.
#[derive(Debug, Clone)]
pub(crate) struct FrameData {
    /// The nearest movable joint above the frame (index into the joints), or [`NONE`].
    pub(crate) support: usize,
    pub(crate) home: Se3,
    /// P_F: the frame in its support joint's frame (in the base's without one).
    pub(crate) placement: fk::Placement,
    /// The chain root → frame, `None` for a frame on the root link; built on first use (so
    /// that preparing a deep tree stays linear: a chain per frame would be O(frames × depth)).
    pub(crate) view: std::sync::OnceLock<Option<View>>,
}

/// A joint's screw in its own frame: (0, a) for a prismatic joint, (a, h a) for a helical one
/// of pitch h, (a, 0) for a revolute one (a its unit axis).
pub(crate) fn local_screw(j: &screwkit_model::TreeScrew) -> screwkit_lie::Twist {
    match j.kind {
        screwkit_model::JointKind::Prismatic => {
            screwkit_lie::Twist::new(nalgebra::Vector3::zeros(), j.axis)
        }
        screwkit_model::JointKind::Helical => {
            let h = j.s_space.pitch().unwrap_or(0.0);
            screwkit_lie::Twist::new(j.axis, j.axis * h)
        }
        _ => screwkit_lie::Twist::new(j.axis, nalgebra::Vector3::zeros()),
    }
}

/// The immutable kinematic model of a whole tree, prepared for the algorithms. Build once with
/// [`TreeKinematics::new`]; share freely (`Send + Sync`).
#[derive(Debug, Clone)]
pub struct TreeKinematics {
    pub(crate) model: KinematicTree,
    /// The space screws, parents first (the order of [`KinematicTree::joints`]).
    pub(crate) joints: Vec<PoeJoint>,
    /// The same joints in their own frames, for the all-frame sweep ([`fk::fk_frames`]).
    pub(crate) sweep: Vec<fk::SweepJoint>,
    /// Each joint's parent joint (index) or [`NONE`].
    pub(crate) parent: Vec<usize>,
    pub(crate) frames: Vec<FrameData>,
    pub(crate) floating: bool,
    /// The joint variables' limits (without the floating base).
    pub(crate) lower: Vec<f64>,
    pub(crate) upper: Vec<f64>,
    pub(crate) q_names: Vec<String>,
    pub(crate) v_names: Vec<String>,
    /// The most variables of any frame's chain (the size of the gathered q): the joint
    /// variables' count.
    pub(crate) max_view_dof: usize,
    /// Variable name → index (the chains' variables mapped into the tree's).
    pub(crate) variable_index: std::collections::HashMap<String, usize>,
    /// The links with a mass: (link, mass, centre of mass in the link's frame).
    pub(crate) masses: Vec<(usize, f64, nalgebra::Vector3<f64>)>,
    pub(crate) total_mass: f64,
    /// Each joint variable's bounds as every joint it drives allows (a mimic follower's own
    /// limits mapped through θ = m q + o), and its speed limit (∞ where none is given).
    pub(crate) variable_bounds: Vec<(f64, f64)>,
    pub(crate) variable_speed: Vec<f64>,
    /// Continuous (unbounded, periodic) joint variables.
    pub(crate) continuous: Vec<bool>,
}

impl TreeKinematics {
    /// Prepares a tree (with its floating base, if it has one) for the algorithms.
    pub fn new(model: &KinematicTree) -> Result<Self, ModelError> {
        let joints = model
            .joints
            .iter()
            .map(|j| PoeJoint::new(*j.s_space.twist(), j.kind, j.drive))
            .collect();
        let sweep = model
            .joints
            .iter()
            .map(|j| {
                let local = local_screw(j);
                fk::SweepJoint {
                    fixed: fk::Placement::of(&j.placement),
                    motion: PoeJoint::new(local, j.kind, j.drive),
                }
            })
            .collect();
        let parent = model
            .joints
            .iter()
            .map(|j| j.parent.unwrap_or(NONE))
            .collect();
        let frames = model
            .frames
            .iter()
            .map(|f| FrameData {
                support: model.links[f.link].support.unwrap_or(NONE),
                home: f.home,
                placement: fk::Placement::of(&model.links[f.link].placement.compose(&f.placement)),
                view: std::sync::OnceLock::new(),
            })
            .collect();
        let variable_index = model
            .variables
            .iter()
            .enumerate()
            .map(|(k, v)| (v.name.clone(), k))
            .collect();
        let masses: Vec<_> = model
            .tree
            .inertials
            .iter()
            .enumerate()
            .filter_map(|(l, i)| i.map(|i| (l, i.mass, nalgebra::Vector3::from(i.com))))
            .filter(|(_, m, _)| *m > 0.0)
            .collect();
        let total_mass = masses.iter().map(|(_, m, _)| m).sum();
        let (variable_bounds, variable_speed) = variable_limits(model);
        Ok(Self {
            masses,
            total_mass,
            variable_bounds,
            variable_speed,
            continuous: model
                .variables
                .iter()
                .map(|v| v.kind == screwkit_model::JointKind::Continuous)
                .collect(),
            joints,
            sweep,
            parent,
            frames,
            floating: model.floating_base,
            lower: model.variables.iter().map(|v| v.lower).collect(),
            upper: model.variables.iter().map(|v| v.upper).collect(),
            q_names: model.q_names(),
            v_names: model.v_names(),
            max_view_dof: model.variables.len(),
            variable_index,
            model: model.clone(),
        })
    }

    /// The chain root → `frame` prepared (built on first use), `None` for a frame on the root
    /// link. The chain of a validated tree always builds (its joints, limits and mimic rules
    /// were checked by [`KinematicTree::from_tree`]).
    pub(crate) fn view(&self, frame: usize) -> Option<&View> {
        self.frames[frame]
            .view
            .get_or_init(|| {
                let chain = self.model.chain_to(frame).ok().flatten()?;
                let variables = chain
                    .variables
                    .iter()
                    .map(|v| self.variable_index.get(&v.name).copied())
                    .collect::<Option<Vec<_>>>()?;
                Some(View {
                    kin: Kinematics::new(&chain),
                    variables,
                })
            })
            .as_ref()
    }

    /// Makes `chain` the kernel of `frame`'s own queries (its pose and Jacobians), for a model
    /// whose chain to that frame is known more exactly than its tree gives it: a robot from
    /// screw axes holds its screws as given in its chain, while its tree's joint frames are
    /// computed from them (equal to rounding). Its answers for that frame are then the chain's,
    /// bit for bit. The chain's variables must be the tree's (by name), its home the frame's
    /// within `tol` (metres and radians, entry by entry), and the frame's chain not built yet;
    /// otherwise an error says which, and nothing changes.
    pub fn set_chain(
        &self,
        frame: usize,
        chain: &screwkit_model::Chain,
        tol: f64,
    ) -> Result<(), SolveError> {
        self.check_frame(frame)?;
        let bad = |m: String| Err(SolveError::InvalidInput(m));
        let variables = match chain
            .variables
            .iter()
            .map(|v| self.variable_index.get(&v.name).copied().ok_or(&v.name))
            .collect::<Result<Vec<_>, _>>()
        {
            Ok(v) => v,
            Err(name) => return bad(format!("the chain's variable \"{name}\" is not the tree's")),
        };
        let kin = Kinematics::new(chain);
        let home = &self.frames[frame].home;
        if kin.home().max_abs_diff(home) > tol {
            return bad(format!(
                "the chain's home is not frame \"{}\"'s",
                self.frame_name(frame)
            ));
        }
        self.frames[frame]
            .view
            .set(Some(View { kin, variables }))
            .or_else(|_| {
                bad(format!(
                    "frame \"{}\"'s chain is built already",
                    self.frame_name(frame)
                ))
            })
    }

    /// The model it was built from.
    pub fn model(&self) -> &KinematicTree {
        &self.model
    }

    /// nq: the configuration's length (7 + joint variables with a floating base).
    pub fn nq(&self) -> usize {
        self.q_names.len()
    }

    /// nv: the velocity's length and the Jacobian's column count (6 + joint variables with a
    /// floating base).
    pub fn nv(&self) -> usize {
        self.v_names.len()
    }

    /// True with a floating base.
    pub fn floating_base(&self) -> bool {
        self.floating
    }

    /// The number of frames (links, then extra frames).
    pub fn frame_count(&self) -> usize {
        self.frames.len()
    }

    /// A frame's index by name (a link or an extra frame).
    pub fn frame(&self, name: &str) -> Result<usize, ModelError> {
        self.model.frame(name)
    }

    /// A frame's name.
    pub fn frame_name(&self, frame: usize) -> &str {
        &self.model.frames[frame].name
    }

    /// The lower limits of q (−∞ for the base's position, −1 for its quaternion).
    pub fn lower(&self) -> Vec<f64> {
        self.bounds(&self.lower, f64::NEG_INFINITY, -1.0)
    }

    /// The upper limits of q (+∞ for the base's position, 1 for its quaternion).
    pub fn upper(&self) -> Vec<f64> {
        self.bounds(&self.upper, f64::INFINITY, 1.0)
    }

    fn bounds(&self, joints: &[f64], position: f64, quaternion: f64) -> Vec<f64> {
        let base = [
            position, position, position, quaternion, quaternion, quaternion, quaternion,
        ];
        base.iter()
            .filter(|_| self.floating)
            .copied()
            .chain(joints.iter().copied())
            .collect()
    }

    /// The q labels (`floating_base.x` …, then the joint variables).
    pub fn q_names(&self) -> &[String] {
        &self.q_names
    }

    /// The v labels (`floating_base.wx` …, then the joint variables).
    pub fn v_names(&self) -> &[String] {
        &self.v_names
    }

    /// The offset of the joint variables in q (7 with a floating base).
    pub(crate) fn q_offset(&self) -> usize {
        if self.floating {
            7
        } else {
            0
        }
    }

    /// The offset of the joint variables in v (6 with a floating base).
    pub(crate) fn v_offset(&self) -> usize {
        if self.floating {
            6
        } else {
            0
        }
    }

    /// Checks a frame index.
    pub(crate) fn check_frame(&self, frame: usize) -> Result<(), SolveError> {
        if frame < self.frames.len() {
            Ok(())
        } else {
            Err(SolveError::InvalidInput(format!(
                "frame index {frame} is out of range: the model has {} frames",
                self.frames.len()
            )))
        }
    }

    /// Checks a configuration (nq values, finite, the base's quaternion of unit length within
    /// [`QUATERNION_TOLERANCE`]) and returns the base's pose (the identity for a fixed base).
    pub fn check_q(&self, q: &[f64]) -> Result<Se3, SolveError> {
        if q.len() != self.nq() {
            return Err(SolveError::WrongLength {
                what: "configuration values",
                expected: self.nq(),
                got: q.len(),
                names: short_names(&self.q_names),
            });
        }
        // One pass without early exit (it vectorises), then the search for the message.
        if q.iter().fold(false, |bad, x| bad | !x.is_finite()) {
            let i = q.iter().position(|x| !x.is_finite()).unwrap_or(0);
            return Err(SolveError::NonFinite {
                what: "configuration value",
                index: i,
                name: self.q_names[i].clone(),
                value: q[i],
            });
        }
        if !self.floating {
            return Ok(Se3::identity());
        }
        base_pose(q)
    }
}

/// Each joint variable's bounds and speed limit: its position bounds are its leader joint's
/// own (a mimic follower's limits do not narrow them, as in ROS; `Tree::warnings` names a
/// follower that cannot hold its limits over its leader's range), its speed limit the least
/// over every joint it drives (|θ̇| = |m| |q̇| ≤ speed; a speed limit of 0 or none in the file
/// is no limit).
fn variable_limits(model: &KinematicTree) -> (Vec<(f64, f64)>, Vec<f64>) {
    let bounds: Vec<(f64, f64)> = model.variables.iter().map(|v| (v.lower, v.upper)).collect();
    let mut speed = vec![f64::INFINITY; bounds.len()];
    for j in &model.joints {
        let Some(tj) = model.tree.joint(&j.name).map(|i| &model.tree.joints[i]) else {
            continue;
        };
        let (k, m) = (j.drive.variable, j.drive.multiplier);
        if k >= bounds.len() || m == 0.0 {
            continue;
        }
        let Some(limit) = tj.limit else { continue };
        if let Some(v) = limit.velocity.filter(|v| *v > 0.0 && v.is_finite()) {
            speed[k] = speed[k].min(v / m.abs());
        }
    }
    (bounds, speed)
}

/// The floating base's pose from q\[0..7\] = (x, y, z, qx, qy, qz, qw), the quaternion checked
/// within [`QUATERNION_TOLERANCE`] of unit length and normalised.
pub(crate) fn base_pose(q: &[f64]) -> Result<Se3, SolveError> {
    let quat = [q[3], q[4], q[5], q[6]];
    let norm = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > QUATERNION_TOLERANCE {
        return Err(SolveError::InvalidInput(format!(
            "the floating base's quaternion q[3..7] = (qx, qy, qz, qw) = ({}, {}, {}, {}) has norm {norm}, not 1",
            quat[0], quat[1], quat[2], quat[3]
        )));
    }
    Se3::from_translation_quaternion([q[0], q[1], q[2]], quat)
        .map_err(|e| SolveError::InvalidInput(format!("the floating base's pose: {e}")))
}

/// A long list of names shortened for a message.
pub(crate) fn short_names(names: &[String]) -> String {
    if names.len() <= 12 {
        names.join(", ")
    } else {
        format!("{}, … {} in all", names[..10].join(", "), names.len())
    }
}

/// Reusable scratch for one thread, sized for one [`TreeKinematics`].
#[derive(Debug, Clone)]
pub struct TreeWorkspace {
    /// G_k per joint (the sweep's products).
    pub(crate) joint_poses: Vec<Columns>,
    /// θ, sin θ, cos θ per joint (length rounded up to whole lanes).
    pub(crate) theta: Vec<f64>,
    pub(crate) sin: Vec<f64>,
    pub(crate) cos: Vec<f64>,
    pub(crate) frame_columns: Vec<Columns>,
    pub(crate) frames: Vec<Se3>,
    /// The gathered q of one frame's chain, and that chain's Jacobian (6 × its variables, in
    /// the first columns).
    pub(crate) view_q: Vec<f64>,
    pub(crate) view_jacobian: Matrix6xX<f64>,
    pub(crate) jacobian: Matrix6xX<f64>,
    pub(crate) other: Matrix6xX<f64>,
    /// The centre of mass's Jacobian and, per joint, the mass and the mass-weighted centre of
    /// the links it carries.
    pub(crate) com_jacobian: nalgebra::Matrix3xX<f64>,
    pub(crate) subtree: Vec<(f64, nalgebra::Vector3<f64>)>,
    /// Checked by [`TreeWorkspace::fit`].
    frames_len: usize,
    nv: usize,
}

impl TreeWorkspace {
    /// Scratch sized for `kin`.
    pub fn new(kin: &TreeKinematics) -> Self {
        let lanes =
            kin.joints.len().div_ceil(screwkit_lie::trig::LANES) * screwkit_lie::trig::LANES;
        Self {
            joint_poses: vec![Columns::identity(); kin.joints.len()],
            theta: vec![0.0; lanes],
            sin: vec![0.0; lanes],
            cos: vec![0.0; lanes],
            frame_columns: vec![Columns::identity(); kin.frames.len()],
            frames: vec![Se3::identity(); kin.frames.len()],
            view_q: vec![0.0; kin.max_view_dof],
            view_jacobian: Matrix6xX::zeros(kin.max_view_dof),
            jacobian: Matrix6xX::zeros(kin.nv()),
            other: Matrix6xX::zeros(kin.nv()),
            com_jacobian: nalgebra::Matrix3xX::zeros(kin.nv()),
            subtree: vec![(0.0, nalgebra::Vector3::zeros()); kin.joints.len()],
            frames_len: kin.frames.len(),
            nv: kin.nv(),
        }
    }

    /// Runs `f` in this thread's kept workspace, fitted to `kin` (as
    /// [`crate::Workspace`]'s: a small batch on the calling thread then makes none; 0.48 µs
    /// for the bundled humanoid's).
    /// Kept boxed: taking it out and back moves a pointer, not the workspace.
    pub fn local<R>(kin: &TreeKinematics, f: impl FnOnce(&mut TreeWorkspace) -> R) -> R {
        thread_local! {
            static KEPT: std::cell::RefCell<Option<Box<TreeWorkspace>>> = const { std::cell::RefCell::new(None) };
        }
        let mut ws = KEPT
            .with(|k| k.borrow_mut().take())
            .unwrap_or_else(|| Box::new(TreeWorkspace::new(kin)));
        ws.fit(kin);
        let out = f(&mut ws);
        KEPT.with(|k| *k.borrow_mut() = Some(ws));
        out
    }

    /// Makes the workspace fit `kin` (rebuilt if it was made for another model).
    #[inline(always)]
    pub(crate) fn fit(&mut self, kin: &TreeKinematics) {
        if self.frames_len != kin.frames.len()
            || self.nv != kin.nv()
            || self.joint_poses.len() != kin.joints.len()
            || self.view_q.len() != kin.max_view_dof
        {
            *self = TreeWorkspace::new(kin);
        }
    }
}
