//! Rigid-body dynamics of the whole tree in screw form (*Modern Robotics* ch. 8, on a tree; a
//! chain is a tree with one branch): inverse dynamics by recursive Newton–Euler, the mass matrix
//! by the composite-rigid-body algorithm, forward dynamics, gravity, nonlinear effects and the
//! energies.
//!
//! **Conventions.** Twists (ω, v) and wrenches (m, f); each movable joint k carries the body
//! made of the links it supports (their inertials summed rigidly, [`Dynamics::new`]), expressed
//! in the joint's own frame J_k. With T_k = X_k e^{[a_k]θ_k} the joint frame in its parent
//! joint's (X_k the file's origins, a_k the joint's screw in its own frame, θ_k = m q + o by its
//! drive),
//!
//! ```text
//! V_k = [Ad_{T_k⁻¹}] V_parent + a_k θ̇_k
//! V̇_k = [Ad_{T_k⁻¹}] V̇_parent + a_k θ̈_k + [ad_{V_k}] a_k θ̇_k
//! F_k = G_k V̇_k − [ad_{V_k}]ᵀ G_k V_k + Σ_children [Ad_{T_c⁻¹}]ᵀ F_c
//! τ_k = a_kᵀ F_k
//! ```
//!
//! (MR eqs. 8.50–8.53), with G_k the body's 6 × 6 spatial inertia in J_k,
//! G = [[Ī_o, m[c]], [m[c]ᵀ, m 1]] (Ī_o the rotational inertia about the frame's origin, c the
//! centre of mass). Gravity g enters as the root's acceleration −g ((0, −Rᵀg) in the base's
//! frame). A variable driving several joints (mimic) collects m_k τ_k. With a floating base the
//! root link's body moves with the base's twist v = (ω, v_b) in its own frame, and the first
//! six entries of τ are the wrench on it (m, f) in that frame (Pinocchio's free-flyer, in (ω, v)
//! order).
//!
//! Every algorithm is `algorithm(&dynamics, &mut workspace, inputs)`, allocation-free once the
//! workspace is built.

use nalgebra::{DMatrix, Matrix6, Vector3, Vector6};
use screwkit_lie::fma::{dispatch, Kernel, MulAdd};
use screwkit_lie::{Se3, Twist};
use screwkit_model::JointKind;

use super::fk::{sin_cos_lanes, Placement, SweepJoint};
use super::{TreeKinematics, NONE};
use crate::columns::Columns;
use crate::error::SolveError;
use crate::poe::PoeJoint;

/// Standard gravity (m/s²), MuJoCo's and Pinocchio's.
pub const STANDARD_GRAVITY: f64 = 9.81;

/// A rigid body's spatial inertia in a frame: mass m, first moment h = m c (c the centre of
/// mass), and rotational inertia Ī_o about the frame's origin; G = [[Ī_o, [h]], [[h]ᵀ, m 1]].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialInertia {
    /// Mass (kg).
    pub mass: f64,
    /// m c (kg m).
    pub first_moment: Vector3<f64>,
    /// Ī_o (kg m²), about the frame's origin.
    pub rotational: nalgebra::Matrix3<f64>,
}

impl SpatialInertia {
    /// No mass.
    pub fn zero() -> Self {
        Self {
            mass: 0.0,
            first_moment: Vector3::zeros(),
            rotational: nalgebra::Matrix3::zeros(),
        }
    }

    /// A body of mass m, centre of mass c, rotational inertia `about_com` about c (in the
    /// frame's axes): Ī_o = Ī_c − m [c]² (the parallel-axis theorem).
    pub fn from_com(mass: f64, com: Vector3<f64>, about_com: nalgebra::Matrix3<f64>) -> Self {
        let c = com.cross_matrix();
        Self {
            mass,
            first_moment: com * mass,
            rotational: about_com - c * c * mass,
        }
    }

    /// The 6 × 6 matrix G, (ω, v) order.
    pub fn matrix(&self) -> Matrix6<f64> {
        let h = self.first_moment.cross_matrix();
        let mut g = Matrix6::zeros();
        g.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rotational);
        g.fixed_view_mut::<3, 3>(0, 3).copy_from(&h);
        g.fixed_view_mut::<3, 3>(3, 0).copy_from(&h.transpose());
        g.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(nalgebra::Matrix3::identity() * self.mass));
        g
    }

    /// G V for a twist V = (ω, v): the momentum (Ī_o ω + h × v, m v − h × ω).
    #[inline]
    pub fn apply(&self, v: &Vector6<f64>) -> Vector6<f64> {
        let w = v.fixed_rows::<3>(0);
        let lin = v.fixed_rows::<3>(3);
        let top = self.rotational * w + self.first_moment.cross(&lin);
        let bottom = lin * self.mass - self.first_moment.cross(&w);
        Vector6::new(top.x, top.y, top.z, bottom.x, bottom.y, bottom.z)
    }

    /// The same body seen from a frame in which this one is at `t` (this frame's pose in
    /// the new one): G' = [Ad_{t⁻¹}]ᵀ G [Ad_{t⁻¹}].
    pub fn transformed(&self, t: &Se3) -> Self {
        self.rotated_moved(t.rotation(), t.translation())
    }

    /// [`SpatialInertia::transformed`] by t = (R, p): m' = m, h' = R h + m p,
    /// Ī' = R Ī Rᵀ − m[p]² − [p][R h] − [R h][p].
    #[inline(always)]
    pub fn rotated_moved(&self, r: &nalgebra::Matrix3<f64>, p: &Vector3<f64>) -> Self {
        let h = r * self.first_moment;
        // −m[p]² − [p][h] − [h][p] = m(|p|² 1 − p pᵀ) + 2(p·h) 1 − h pᵀ − p hᵀ
        // ([a][b] = b aᵀ − (a·b) 1), symmetric.
        let diag = self.mass * p.norm_squared() + 2.0 * p.dot(&h);
        // R Ī Rᵀ, its upper triangle from B = R Ī (Ī symmetric), written out (nalgebra's
        // generic 3 × 3 product is not inlined here).
        let i = &self.rotational;
        let b: [[f64; 3]; 3] = std::array::from_fn(|row| {
            std::array::from_fn(|col| {
                r[(row, 0)] * i[(0, col)] + r[(row, 1)] * i[(1, col)] + r[(row, 2)] * i[(2, col)]
            })
        });
        let entry = |row: usize, col: usize| {
            b[row][0] * r[(col, 0)] + b[row][1] * r[(col, 1)] + b[row][2] * r[(col, 2)]
                - (self.mass * p[row] * p[col] + h[row] * p[col] + p[row] * h[col])
        };
        let (xx, yy, zz) = (entry(0, 0) + diag, entry(1, 1) + diag, entry(2, 2) + diag);
        let (xy, xz, yz) = (entry(0, 1), entry(0, 2), entry(1, 2));
        let rotational = nalgebra::Matrix3::new(xx, xy, xz, xy, yy, yz, xz, yz, zz);
        Self {
            mass: self.mass,
            first_moment: h + p * self.mass,
            rotational,
        }
    }

    /// The two bodies as one (their sum).
    pub fn plus(&self, other: &Self) -> Self {
        Self {
            mass: self.mass + other.mass,
            first_moment: self.first_moment + other.first_moment,
            rotational: self.rotational + other.rotational,
        }
    }
}

/// How [`Dynamics::with_options`] takes a file's `<inertial>`s: an inertial that no rigid body
/// has (a negative mass, a tensor not positive semi-definite or breaking the triangle
/// inequality) is an error naming its link (`Check`, the default), taken as it is (`AsGiven`),
/// or, when it breaks only the triangle inequality, balanced as MuJoCo's
/// `<compiler balanceinertia="true">` does: all three principal moments set to their mean
/// (`Balance`; [`screwkit_model::Inertial::balanced`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Inertias {
    /// Refuse an impossible inertial, naming its link.
    #[default]
    Check,
    /// Take the file's numbers as they are.
    AsGiven,
    /// Balance a triangle-inequality breach as MuJoCo does (other problems still refused).
    Balance,
}

/// What [`Dynamics::with_options`] takes from the file beyond the rigid bodies. Off by default,
/// as Pinocchio's algorithms are; MuJoCo always adds both (its `armature` to M's diagonal, its
/// `damping` in the passive forces).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DynamicsOptions {
    /// The inertials' rule.
    pub inertias: Inertias,
    /// Each joint's armature (MJCF `armature`): a rotor inertia on the diagonal of M, so τ
    /// gains armature · a.
    pub armature: bool,
    /// Each joint's viscous damping (MJCF `damping`, URDF `<dynamics damping>`): τ gains
    /// damping · v (the force the joint's damper takes), in ID, h and FD alike.
    pub damping: bool,
}

/// Each placement X_k as columns.
fn homes_of(placements: &[Se3]) -> Vec<Columns> {
    placements.iter().map(Columns::from_se3).collect()
}

/// One moving joint of the dynamic model.
#[derive(Debug, Clone)]
struct Joint {
    /// The parent joint, or [`NONE`] (the root).
    parent: usize,
    /// Its screw in its own frame, a_k.
    axis: Twist,
    /// θ_k = multiplier · q[variable] + offset (the joint variables, after a floating base's;
    /// X_k and the offset are in the sweep's joint).
    variable: usize,
    multiplier: f64,
}

/// The immutable dynamic model of a tree: each moving joint's body (and, with a floating base,
/// the root's) and gravity. Build once with [`Dynamics::new`] (a robot's tree) or
/// [`Dynamics::from_screws`] (the textbook's (M, G, S) lists); share freely.
#[derive(Debug, Clone)]
pub struct Dynamics {
    /// The tree it was built from (None for the textbook's lists).
    kin: Option<TreeKinematics>,
    joints: Vec<Joint>,
    /// The same joints for the placing sweep ([`Sweep`]): X_k and e^{[a_k]θ} in their cheapest
    /// forms, with the fast sine and cosine.
    sweep: Vec<SweepJoint>,
    /// Each X_k as columns.
    homes: Vec<Columns>,
    /// Each joint's body in its own frame (the links it supports).
    bodies: Vec<SpatialInertia>,
    /// The root body (the links no joint moves) in the root link's frame.
    root: SpatialInertia,
    floating: bool,
    nq: usize,
    nv: usize,
    v_names: Vec<String>,
    /// Gravity in the world: the file's (an MJCF's `<option gravity>`), else (0, 0, −9.81).
    gravity: Vector3<f64>,
    /// Links without an `<inertial>` (massless), said once by the front ends.
    massless: Vec<String>,
    /// A frame fixed to the last joint's body where a tip wrench is applied (the textbook's
    /// {n+1}): its pose in that body's frame.
    tip: Se3,
    /// Each variable drives one joint with multiplier 1 (no mimic coupling): forward dynamics
    /// runs the articulated-body algorithm; otherwise it factorises M.
    uncoupled: bool,
    /// Per velocity entry, the armature Σ m_k² armature_k and the damping Σ m_k² damping_k of
    /// the joints it drives (θ_k = m_k q), when asked ([`DynamicsOptions`]); all zero otherwise.
    armature: Vec<f64>,
    damping: Vec<f64>,
    /// Some armature or damping is nonzero.
    passive: bool,
}

impl Dynamics {
    /// The joint variables' count (nq less a floating base's 7).
    fn joints_variables(&self) -> usize {
        if self.floating {
            self.nq - 7
        } else {
            self.nq
        }
    }

    /// The dynamic model of `kin`'s tree from its links' `<inertial>`s. A link without one is
    /// massless (listed in [`Dynamics::massless`]). An inertial that cannot be a rigid body's
    /// (a negative mass, a tensor not positive semi-definite or breaking the triangle
    /// inequality: [`screwkit_model::Inertial::problem`]) is an error naming its link, unless
    /// `as_given` takes the file's numbers as they are.
    pub fn new(kin: &TreeKinematics, as_given: bool) -> Result<Self, SolveError> {
        let inertias = if as_given {
            Inertias::AsGiven
        } else {
            Inertias::Check
        };
        Self::with_options(
            kin,
            &DynamicsOptions {
                inertias,
                ..Default::default()
            },
        )
    }

    /// The dynamic model of `kin`'s tree with `options`: the inertials' rule, and the joints'
    /// armature and damping when asked (an armature or damping that is not a finite number ≥ 0
    /// is then an error naming its joint).
    pub fn with_options(
        kin: &TreeKinematics,
        options: &DynamicsOptions,
    ) -> Result<Self, SolveError> {
        let model = kin.model();
        let tree = &model.tree;
        let mut bodies = vec![SpatialInertia::zero(); model.joints.len()];
        let mut root = SpatialInertia::zero();
        let mut massless = Vec::new();
        for (l, link) in model.links.iter().enumerate() {
            let Some(inertial) = tree.inertials.get(l).copied().flatten() else {
                massless.push(link.name.clone());
                continue;
            };
            let inertial = match options.inertias {
                Inertias::Balance => inertial.balanced(),
                _ => inertial,
            };
            if options.inertias != Inertias::AsGiven {
                if let Some(problem) = inertial.problem() {
                    return Err(SolveError::InvalidInput(format!(
                        "link \"{}\" <inertial>: {problem} (dynamics needs a rigid body's; take the file's numbers as they are with the as-given option, or balance them as MuJoCo does)",
                        link.name
                    )));
                }
            }
            let t = inertial.tensor();
            let body = SpatialInertia::from_com(
                inertial.mass,
                Vector3::from(inertial.com),
                nalgebra::Matrix3::from_fn(|i, j| t[i][j]),
            )
            .transformed(&link.placement);
            match link.support {
                Some(k) => bodies[k] = bodies[k].plus(&body),
                None => root = root.plus(&body),
            }
        }
        let joints = model
            .joints
            .iter()
            .enumerate()
            .map(|(k, j)| Joint {
                parent: kin.parent[k],
                axis: super::local_screw(j),
                variable: j.drive.variable,
                multiplier: j.drive.multiplier,
            })
            .collect();
        Self {
            kin: Some(kin.clone()),
            joints,
            homes: homes_of(&model.joints.iter().map(|j| j.placement).collect::<Vec<_>>()),
            sweep: kin.sweep.clone(),
            bodies,
            root,
            floating: kin.floating,
            nq: kin.nq(),
            nv: kin.nv(),
            v_names: kin.v_names.clone(),
            gravity: tree
                .gravity
                .map_or(Vector3::new(0.0, 0.0, -STANDARD_GRAVITY), Vector3::from),
            massless,
            tip: Se3::identity(),
            uncoupled: false,
            armature: vec![0.0; kin.nv()],
            damping: vec![0.0; kin.nv()],
            passive: false,
        }
        .with_coupling()
        .with_passive(kin, options)
    }

    /// The model with the joints' armature and damping per velocity entry, as `options` asks.
    fn with_passive(
        mut self,
        kin: &TreeKinematics,
        options: &DynamicsOptions,
    ) -> Result<Self, SolveError> {
        if !(options.armature || options.damping) {
            return Ok(self);
        }
        let tree = &kin.model().tree;
        let off = if self.floating { 6 } else { 0 };
        for (k, j) in kin.model().joints.iter().enumerate() {
            let Some(file) = tree.joints.iter().find(|t| t.name == j.name) else {
                continue;
            };
            let m2 = j.drive.multiplier * j.drive.multiplier;
            for (on, what, value, into) in [
                (
                    options.armature,
                    "armature",
                    file.dynamics.armature,
                    &mut self.armature,
                ),
                (
                    options.damping,
                    "damping",
                    file.dynamics.damping,
                    &mut self.damping,
                ),
            ] {
                if !on {
                    continue;
                }
                if !(value.is_finite() && value >= 0.0) {
                    return Err(SolveError::InvalidInput(format!(
                        "joint \"{}\": {what} {value} is not a finite number ≥ 0",
                        j.name
                    )));
                }
                into[off + self.joints[k].variable] += m2 * value;
            }
        }
        self.passive = self.armature.iter().chain(&self.damping).any(|x| *x != 0.0);
        Ok(self)
    }

    /// The textbook's open chain (*Modern Robotics* §8.3): `m_list` the n + 1 transforms
    /// M_{i−1,i} between consecutive link frames at home (the last, the end-effector frame
    /// {n+1} in link n's), `g_list` the n links' 6 × 6 spatial inertias G_i in their own
    /// frames ((ω, v) order), `s_list` the n joints' space screw axes. Joint i's screw in link
    /// frame i is A_i = [Ad_{M_{0,i}⁻¹}] S_i; its body is G_i.
    pub fn from_screws(
        m_list: &[Se3],
        g_list: &[Matrix6<f64>],
        s_list: &[Twist],
    ) -> Result<Self, SolveError> {
        let n = s_list.len();
        if m_list.len() != n + 1 || g_list.len() != n {
            return Err(SolveError::InvalidInput(format!(
                "Mlist needs n + 1 = {} transforms and Glist n = {n} inertias for {n} screw axes, got {} and {}",
                n + 1,
                m_list.len(),
                g_list.len()
            )));
        }
        let mut home = Se3::identity();
        let mut joints = Vec::with_capacity(n);
        let mut sweep = Vec::with_capacity(n);
        let mut bodies = Vec::with_capacity(n);
        for i in 0..n {
            home = home.compose(&m_list[i]);
            let g = &g_list[i];
            if (g - g.transpose()).amax() > 1e-9 * g.amax().max(1.0)
                || !g.iter().all(|x| x.is_finite())
            {
                return Err(SolveError::InvalidInput(format!(
                    "Glist[{i}] is not a finite symmetric 6 × 6 spatial inertia"
                )));
            }
            let h = Vector3::new(g[(2, 4)], g[(0, 5)], g[(1, 3)]);
            let body = SpatialInertia {
                mass: g[(3, 3)],
                first_moment: h,
                rotational: g.fixed_view::<3, 3>(0, 0).into_owned(),
            };
            // A rigid body's G has m 1 in its lower right and [m c] in its upper right.
            if (body.matrix() - g).amax() > 1e-9 * g.amax().max(1.0) {
                return Err(SolveError::InvalidInput(format!(
                    "Glist[{i}] is not a rigid body's spatial inertia [[I, [mc]], [[mc]ᵀ, m 1]]"
                )));
            }
            bodies.push(body);
            let a = home.inverse().adjoint_apply(&s_list[i]);
            // A unit rotation axis (or none): a = |ω| â, θ' = |ω| θ (the drive's multiplier).
            let scale = a.w.norm();
            let (axis, multiplier) = if scale == 0.0 || scale == 1.0 {
                (a, 1.0)
            } else {
                (a * (1.0 / scale), scale)
            };
            if !(axis.w.iter().chain(axis.v.iter()).all(|x| x.is_finite()))
                || axis.to_vector().norm() == 0.0
            {
                return Err(SolveError::InvalidInput(format!(
                    "Slist[{i}] is not a finite nonzero screw axis"
                )));
            }
            let kind = if axis.w.norm() == 0.0 {
                JointKind::Prismatic
            } else if axis.w.dot(&axis.v) == 0.0 {
                JointKind::Revolute
            } else {
                JointKind::Helical
            };
            let drive = screwkit_model::Drive {
                variable: i,
                multiplier,
                offset: 0.0,
            };
            sweep.push(SweepJoint {
                fixed: Placement::of(&m_list[i]),
                motion: PoeJoint::new(axis, kind, drive),
            });
            joints.push(Joint {
                parent: if i == 0 { NONE } else { i - 1 },
                axis,
                variable: i,
                multiplier,
            });
        }
        Ok(Self {
            kin: None,
            joints,
            sweep,
            homes: homes_of(&m_list[..n]),
            bodies,
            root: SpatialInertia::zero(),
            floating: false,
            nq: n,
            nv: n,
            v_names: (1..=n).map(|i| format!("joint {i}")).collect(),
            gravity: Vector3::new(0.0, 0.0, -STANDARD_GRAVITY),
            massless: Vec::new(),
            tip: m_list[n],
            uncoupled: false,
            armature: vec![0.0; n],
            damping: vec![0.0; n],
            passive: false,
        }
        .with_coupling())
    }

    /// The model with [`Dynamics::uncoupled`] worked out.
    fn with_coupling(mut self) -> Self {
        let mut seen = vec![false; self.joints.len().max(self.nv)];
        self.uncoupled = self.joints.iter().all(|j| {
            let fresh = !std::mem::replace(&mut seen[j.variable], true);
            fresh && j.multiplier == 1.0
        });
        self
    }

    /// The kinematic tree, when built from one.
    pub fn kinematics(&self) -> Option<&TreeKinematics> {
        self.kin.as_ref()
    }

    /// Gravity in the world (m/s²).
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// The model with another gravity (m/s², in the world).
    pub fn with_gravity(mut self, g: Vector3<f64>) -> Self {
        self.gravity = g;
        self
    }

    /// The links without an `<inertial>` (taken as massless).
    pub fn massless(&self) -> &[String] {
        &self.massless
    }

    /// Each moving joint's body in its own frame.
    pub fn bodies(&self) -> &[SpatialInertia] {
        &self.bodies
    }

    /// nv: the velocity's length.
    pub fn nv(&self) -> usize {
        self.nv
    }

    /// Checks q (the tree's rules, or nq finite values) and returns the base's pose.
    fn check_q(&self, q: &[f64]) -> Result<Se3, SolveError> {
        if let Some(kin) = &self.kin {
            return kin.check_q(q);
        }
        check_values(&self.v_names, q, "joint value")?;
        Ok(Se3::identity())
    }
}

/// A wrench (m, f) the robot exerts on its environment at a frame, in that frame's own
/// coordinates, and where the frame is: its body (a joint's index, or [`NONE`] for the root's)
/// and its pose in that body's frame.
#[derive(Debug, Clone, Copy)]
pub struct Exerted {
    body: usize,
    placement: Se3,
    wrench: Vector6<f64>,
}

impl Dynamics {
    /// The textbook's F_tip at its frame {n+1} on the last body.
    fn at_tip(&self, tip: &[f64; 6]) -> Exerted {
        Exerted {
            body: self.joints.len().checked_sub(1).unwrap_or(NONE),
            placement: self.tip,
            wrench: Vector6::from(*tip),
        }
    }

    /// `wrench` = (m, f) exerted by the robot at frame `frame` of its tree (in that frame's
    /// coordinates), for [`static_torques`] and [`inverse_dynamics_exerting`].
    pub fn exerted(&self, frame: usize, wrench: &[f64; 6]) -> Result<Exerted, SolveError> {
        let kin = self.kin.as_ref().ok_or_else(|| {
            SolveError::InvalidInput("a textbook chain has no named frames".into())
        })?;
        let model = kin.model();
        let f = model.frames.get(frame).ok_or_else(|| {
            SolveError::InvalidInput(format!("no frame {frame} ({} frames)", model.frames.len()))
        })?;
        if let Some(i) = wrench.iter().position(|x| !x.is_finite()) {
            return Err(SolveError::InvalidInput(format!(
                "the wrench at \"{}\": entry {i} is not finite",
                f.name
            )));
        }
        let link = &model.links[f.link];
        Ok(Exerted {
            body: link.support.unwrap_or(NONE),
            placement: link.placement.compose(&f.placement),
            wrench: Vector6::from(*wrench),
        })
    }
}

/// Inverse dynamics with the robot exerting wrenches on its environment at frames
/// ([`Dynamics::exerted`]): τ = ID(q, v, a) + Σ J_fᵀ F_f (J_f the frame's body Jacobian).
pub fn inverse_dynamics_exerting<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    exerted: &[Exerted],
) -> Result<&'w [f64], SolveError> {
    check_nv(d, v, "velocity value")?;
    check_nv(d, a, "acceleration value")?;
    let base = place(d, ws, q, Frames::Local)?;
    newton_euler(d, ws, &base, Some(v), Some(a), true, exerted);
    Ok(&ws.tau)
}

/// Statics: the joint forces τ = Σ J_fᵀ F_f that hold the wrenches F_f the robot exerts at
/// frames (each in its frame's coordinates, J_f the body Jacobian), at rest; with `gravity`,
/// plus g(q) (the forces that hold the robot still under gravity as it pushes).
pub fn static_torques<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    exerted: &[Exerted],
    gravity: bool,
) -> Result<&'w [f64], SolveError> {
    let base = place(d, ws, q, Frames::Local)?;
    newton_euler(d, ws, &base, None, None, gravity, exerted);
    Ok(&ws.tau)
}

/// One thread's scratch for the dynamics algorithms.
#[derive(Debug, Clone)]
pub struct DynamicsWorkspace {
    /// Each joint frame in its parent's (T_k = X_k e^{[a_k]θ_k}).
    local: Vec<Se3>,
    /// The sweep's angles, sines and cosines (whole lanes of [`screwkit_lie::trig::LANES`]).
    theta: Vec<f64>,
    sin: Vec<f64>,
    cos: Vec<f64>,
    /// T_k as columns.
    local_columns: Vec<Columns>,
    /// Each joint frame in the root link's frame (J_k = J_parent T_k), as columns.
    world: Vec<Columns>,
    /// Each joint's screw in the root link's frame, [Ad_{J_k}] a_k (times its multiplier).
    screw_packed: Vec<[f64; 6]>,
    /// The composite bodies in the root link's frame, packed.
    packed: Vec<Packed>,
    velocity: Vec<Vector6<f64>>,
    acceleration: Vec<Vector6<f64>>,
    force: Vec<Vector6<f64>>,
    root_force: Vector6<f64>,
    /// The mass matrix and its Cholesky factor (nv × nv).
    mass: DMatrix<f64>,
    /// The centroidal momentum map (6 × nv).
    centroidal: DMatrix<f64>,
    factor: DMatrix<f64>,
    tau: Vec<f64>,
    rhs: Vec<f64>,
    /// The articulated-body algorithm's articulated inertias, bias forces, U = I^A a_k,
    /// D = a_kᵀ U, u = τ − a_kᵀ p^A and bias accelerations.
    articulated: Vec<Matrix6<f64>>,
    bias_force: Vec<Vector6<f64>>,
    u_vec: Vec<Vector6<f64>>,
    d_inv: Vec<f64>,
    u_scalar: Vec<f64>,
    bias_acc: Vec<Vector6<f64>>,
}

impl DynamicsWorkspace {
    /// Scratch for `dynamics`.
    pub fn new(dynamics: &Dynamics) -> Self {
        let n = dynamics.bodies.len();
        let nv = dynamics.nv;
        let lanes = n.div_ceil(screwkit_lie::trig::LANES) * screwkit_lie::trig::LANES;
        Self {
            local: vec![Se3::identity(); n],
            theta: vec![0.0; lanes],
            sin: vec![0.0; lanes],
            cos: vec![0.0; lanes],
            local_columns: vec![Columns::identity(); n],
            world: vec![Columns::identity(); n],
            screw_packed: vec![[0.0; 6]; n],
            packed: vec![[0.0; 10]; n],
            velocity: vec![Vector6::zeros(); n],
            acceleration: vec![Vector6::zeros(); n],
            force: vec![Vector6::zeros(); n],
            root_force: Vector6::zeros(),
            mass: DMatrix::zeros(nv, nv),
            centroidal: DMatrix::zeros(6, nv),
            factor: DMatrix::zeros(nv, nv),
            tau: vec![0.0; nv],
            rhs: vec![0.0; nv],
            articulated: vec![Matrix6::zeros(); n],
            bias_force: vec![Vector6::zeros(); n],
            u_vec: vec![Vector6::zeros(); n],
            d_inv: vec![0.0; n],
            u_scalar: vec![0.0; n],
            bias_acc: vec![Vector6::zeros(); n],
        }
    }
}

/// ad_V(W) = [V, W] for twists V = (ω, v), W = (ω', v'): (ω × ω', ω × v' + v × ω').
fn ad(v: &Vector6<f64>, w: &Vector6<f64>) -> Vector6<f64> {
    let (a, b) = (v.fixed_rows::<3>(0), v.fixed_rows::<3>(3));
    let (c, d) = (w.fixed_rows::<3>(0), w.fixed_rows::<3>(3));
    let top = a.cross(&c);
    let bottom = a.cross(&d) + b.cross(&c);
    Vector6::new(top.x, top.y, top.z, bottom.x, bottom.y, bottom.z)
}

/// [ad_V]ᵀ F for a twist V = (ω, v) and a wrench F = (m, f): (−ω × m − v × f, −ω × f).
fn ad_transpose(v: &Vector6<f64>, f: &Vector6<f64>) -> Vector6<f64> {
    let (a, b) = (v.fixed_rows::<3>(0), v.fixed_rows::<3>(3));
    let (m, n) = (f.fixed_rows::<3>(0), f.fixed_rows::<3>(3));
    let top = -a.cross(&m) - b.cross(&n);
    let bottom = -a.cross(&n);
    Vector6::new(top.x, top.y, top.z, bottom.x, bottom.y, bottom.z)
}

/// [Ad_{T⁻¹}] V: a twist given in T's parent frame, in T's own frame.
fn twist_in_child(t: &Se3, v: &Vector6<f64>) -> Vector6<f64> {
    let r = t.rotation();
    let p = t.translation();
    let w = v.fixed_rows::<3>(0).into_owned();
    let lin = v.fixed_rows::<3>(3).into_owned();
    let wc = r.transpose() * w;
    let vc = r.transpose() * (lin - p.cross(&w));
    Vector6::new(wc.x, wc.y, wc.z, vc.x, vc.y, vc.z)
}

/// [Ad_{T⁻¹}]ᵀ F: a wrench given in T's own frame, in T's parent frame.
fn wrench_in_parent(t: &Se3, f: &Vector6<f64>) -> Vector6<f64> {
    let r = t.rotation();
    let p = t.translation();
    let m = r * f.fixed_rows::<3>(0);
    let n = r * f.fixed_rows::<3>(3);
    let mp = m + p.cross(&n);
    Vector6::new(mp.x, mp.y, mp.z, n.x, n.y, n.z)
}

fn vec6(t: &Twist) -> Vector6<f64> {
    t.to_vector()
}

/// Which joint frames [`place`] puts: each in its parent's (T_k, for the passes in the joints'
/// own frames), each in the root link's (J_k, for the passes in that frame), or both.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Frames {
    Local,
    Root,
    Both,
}

/// The root's pose and, at q (checked), each joint's T_k (into `ws.local`) and/or J_k (into
/// `ws.world`).
fn place(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    q: &[f64],
    frames: Frames,
) -> Result<Se3, SolveError> {
    let base = d.check_q(q)?;
    let local = frames != Frames::Root;
    dispatch(Sweep {
        d,
        q: &q[d.nq - d.joints_variables()..],
        theta: &mut ws.theta,
        sin: &mut ws.sin,
        cos: &mut ws.cos,
        local: local.then_some(&mut ws.local_columns[..]),
        world: (frames != Frames::Local).then_some(&mut ws.world[..]),
    });
    if local {
        for (o, c) in ws.local.iter_mut().zip(&ws.local_columns) {
            *o = c.to_se3();
        }
    }
    Ok(base)
}

/// The placing sweep: θ_k by each joint's drive, their sines and cosines in lanes, then per
/// joint T_k = X_k e^{[a_k]θ_k} and/or J_k = J_parent X_k e^{[a_k]θ_k}, each by the cheapest
/// update of the joint's form ([`PoeJoint::apply`], the all-frame FK's).
struct Sweep<'a> {
    d: &'a Dynamics,
    q: &'a [f64],
    theta: &'a mut [f64],
    sin: &'a mut [f64],
    cos: &'a mut [f64],
    local: Option<&'a mut [Columns]>,
    world: Option<&'a mut [Columns]>,
}

impl Kernel for Sweep<'_> {
    type Output = ();
    #[inline(always)]
    fn run<A: MulAdd>(self) {
        let d = self.d;
        for (t, j) in self.theta.iter_mut().zip(&d.sweep) {
            *t = j.motion.drive.theta(self.q);
        }
        sin_cos_lanes::<A>(self.theta, self.sin, self.cos);
        let (mut local, mut world) = (self.local, self.world);
        for (k, j) in d.sweep.iter().enumerate() {
            let (t, s, c) = (self.theta[k], self.sin[k], self.cos[k]);
            if let Some(out) = local.as_deref_mut() {
                let mut g = d.homes[k];
                j.motion.apply::<A>(&mut g, t, s, c);
                out[k] = g;
            }
            if let Some(out) = world.as_deref_mut() {
                let mut g = match d.joints[k].parent {
                    NONE => d.homes[k],
                    p => j.fixed.apply::<A>(&out[p]),
                };
                j.motion.apply::<A>(&mut g, t, s, c);
                out[k] = g;
            }
        }
    }
}

/// Checks `x` against `names` (its length, each value finite).
fn check_values(names: &[String], x: &[f64], what: &'static str) -> Result<(), SolveError> {
    if x.len() != names.len() {
        return Err(SolveError::WrongLength {
            what,
            expected: names.len(),
            got: x.len(),
            names: super::short_names(names),
        });
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite {
            what,
            index: i,
            name: names.get(i).cloned().unwrap_or_default(),
            value: x[i],
        });
    }
    Ok(())
}

/// Checks a vector of nv values named `what`.
fn check_nv(d: &Dynamics, x: &[f64], what: &'static str) -> Result<(), SolveError> {
    check_values(&d.v_names, x, what)
}

/// The recursive Newton–Euler pass at placed joints: τ into `ws.tau` (the module's formulas),
/// the root's acceleration `root_acc` (its own frame) and velocity `root_vel`; `gravity`
/// adds −g to the root's acceleration.
fn newton_euler(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    base: &Se3,
    v: Option<&[f64]>,
    a: Option<&[f64]>,
    gravity: bool,
    exerted: &[Exerted],
) {
    let off = if d.floating { 6 } else { 0 };
    let at = |x: Option<&[f64]>, k: usize| x.map_or(0.0, |x| x[k]);
    let mut root_vel = Vector6::zeros();
    let mut root_acc = Vector6::zeros();
    if d.floating {
        for i in 0..6 {
            root_vel[i] = at(v, i);
            root_acc[i] = at(a, i);
        }
    }
    if gravity {
        // −g seen from the root (the world for a fixed base).
        let up = base.rotation().transpose() * -d.gravity;
        root_acc[3] += up.x;
        root_acc[4] += up.y;
        root_acc[5] += up.z;
    }
    let joints = &d.joints;
    for (k, j) in joints.iter().enumerate() {
        let (vp, ap) = match j.parent {
            NONE => (root_vel, root_acc),
            p => (ws.velocity[p], ws.acceleration[p]),
        };
        let t = &ws.local[k];
        let s = vec6(&j.axis);
        let var = off + j.variable;
        let rate = j.multiplier * at(v, var);
        let acc = j.multiplier * at(a, var);
        let g = &d.bodies[k];
        if v.is_none() {
            // At rest: no velocity, no bias terms.
            let ak = twist_in_child(t, &ap) + s * acc;
            ws.force[k] = g.apply(&ak);
            ws.acceleration[k] = ak;
            continue;
        }
        let vk = twist_in_child(t, &vp) + s * rate;
        let ak = twist_in_child(t, &ap) + s * acc + ad(&vk, &s) * rate;
        ws.force[k] = g.apply(&ak) - ad_transpose(&vk, &g.apply(&vk));
        ws.velocity[k] = vk;
        ws.acceleration[k] = ak;
    }
    let mut root_extra = Vector6::zeros();
    for e in exerted {
        // A wrench the robot exerts on the environment at a frame (the textbook's F_tip),
        // carried into its body's frame: the joints must supply it too.
        let w = wrench_in_parent(&e.placement, &e.wrench);
        match e.body {
            NONE => root_extra += w,
            k => ws.force[k] += w,
        }
    }
    ws.root_force = root_extra
        + if d.floating {
            let g = &d.root;
            g.apply(&root_acc) - ad_transpose(&root_vel, &g.apply(&root_vel))
        } else {
            Vector6::zeros()
        };
    ws.tau.iter_mut().for_each(|x| *x = 0.0);
    for k in (0..joints.len()).rev() {
        let j = &joints[k];
        let s = vec6(&j.axis);
        ws.tau[off + j.variable] += j.multiplier * s.dot(&ws.force[k]);
        let up = wrench_in_parent(&ws.local[k], &ws.force[k]);
        match j.parent {
            NONE => ws.root_force += up,
            p => ws.force[p] += up,
        }
    }
    if d.floating {
        for i in 0..6 {
            ws.tau[i] = ws.root_force[i];
        }
    }
    if d.passive {
        // The joints' rotors and dampers (asked for in the options).
        for i in 0..d.nv {
            ws.tau[i] += d.armature[i] * at(a, i) + d.damping[i] * at(v, i);
        }
    }
}

/// Inverse dynamics τ = ID(q, v, a): the generalized forces (nv) that give the accelerations
/// a at (q, v) under gravity, by recursive Newton–Euler. Pinocchio's `rnea`.
pub fn inverse_dynamics<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<&'w [f64], SolveError> {
    check_nv(d, v, "velocity value")?;
    check_nv(d, a, "acceleration value")?;
    let base = place(d, ws, q, Frames::Local)?;
    newton_euler(d, ws, &base, Some(v), Some(a), true, &[]);
    Ok(&ws.tau)
}

/// [`inverse_dynamics`] with the wrench `tip` = (m, f) that the last body exerts on the
/// environment at its tip frame, in that frame (the textbook's F_tip, §8.3:
/// `InverseDynamics`): τ gains Jᵀ F_tip.
pub fn inverse_dynamics_tip<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    tip: &[f64; 6],
) -> Result<&'w [f64], SolveError> {
    check_nv(d, v, "velocity value")?;
    check_nv(d, a, "acceleration value")?;
    check_values(&TIP_NAMES.map(String::from), tip, "tip wrench value")?;
    let base = place(d, ws, q, Frames::Local)?;
    let at_tip = [d.at_tip(tip)];
    newton_euler(d, ws, &base, Some(v), Some(a), true, &at_tip);
    Ok(&ws.tau)
}

/// The entries of a wrench (m, f), for messages.
const TIP_NAMES: [&str; 6] = ["mx", "my", "mz", "fx", "fy", "fz"];

/// The gravity forces g(q) = ID(q, 0, 0). Pinocchio's `computeGeneralizedGravity`.
pub fn gravity<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
) -> Result<&'w [f64], SolveError> {
    let base = place(d, ws, q, Frames::Local)?;
    newton_euler(d, ws, &base, None, None, true, &[]);
    Ok(&ws.tau)
}

/// The nonlinear effects h(q, v) = C(q, v) v + g(q) = ID(q, v, 0). Pinocchio's
/// `nonLinearEffects`.
pub fn nonlinear_effects<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
) -> Result<&'w [f64], SolveError> {
    check_nv(d, v, "velocity value")?;
    let base = place(d, ws, q, Frames::Local)?;
    newton_euler(d, ws, &base, Some(v), None, true, &[]);
    Ok(&ws.tau)
}

/// The mass matrix M(q) (nv × nv, symmetric positive definite for a body with mass on every
/// moving joint), by the composite-rigid-body algorithm: each joint's composite body
/// I_k = G_k + Σ_children [Ad_{T_c⁻¹}]ᵀ I_c [Ad_{T_c⁻¹}], then M(k, l) = a_lᵀ (wrench of
/// I_k a_k carried up to l) for l = k and its ancestors (a mimic variable collecting its
/// joints' m). Pinocchio's `crba`.
pub fn mass_matrix<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
) -> Result<&'w DMatrix<f64>, SolveError> {
    place(d, ws, q, Frames::Root)?;
    dispatch(Pass(|| crba(d, ws)));
    Ok(&ws.mass)
}

/// The composite bodies I^c_k (into `ws.packed`) and the joints' screws S_k (into
/// `ws.screw_packed`), in the root link's frame, at placed J_k; returns the whole robot's
/// composite body there ([`crba`]'s first two steps).
#[inline(always)]
fn composite(d: &Dynamics, ws: &mut DynamicsWorkspace) -> Packed {
    let joints = &d.joints;
    let n = joints.len();
    for (k, joint) in joints.iter().enumerate() {
        let g = &ws.world[k];
        ws.packed[k] = packed_at(&d.bodies[k], g);
        let [c0, c1, c2, p] = g.0;
        let a = &joint.axis;
        let rot = |x: &Vector3<f64>| -> [f64; 3] {
            std::array::from_fn(|i| c0[i] * x.x + c1[i] * x.y + c2[i] * x.z)
        };
        let (w, v) = (rot(&a.w), rot(&a.v));
        let m = joint.multiplier;
        ws.screw_packed[k] = [
            m * w[0],
            m * w[1],
            m * w[2],
            m * (v[0] + p[1] * w[2] - p[2] * w[1]),
            m * (v[1] + p[2] * w[0] - p[0] * w[2]),
            m * (v[2] + p[0] * w[1] - p[1] * w[0]),
        ];
    }
    let r = &d.root;
    let ri = &r.rotational;
    let mut root: Packed = [
        r.mass,
        r.first_moment.x,
        r.first_moment.y,
        r.first_moment.z,
        ri[(0, 0)],
        ri[(0, 1)],
        ri[(0, 2)],
        ri[(1, 1)],
        ri[(1, 2)],
        ri[(2, 2)],
    ];
    for k in (0..n).rev() {
        let c = ws.packed[k];
        let to = match joints[k].parent {
            NONE => &mut root,
            p => &mut ws.packed[p],
        };
        for (t, x) in to.iter_mut().zip(c) {
            *t += x;
        }
    }
    root
}

/// A spatial inertia packed for the composite pass: m, h = m c, then Ī_o's upper triangle
/// (xx, xy, xz, yy, yz, zz).
type Packed = [f64; 10];

/// `b` (in a joint frame) seen from the frame where that joint frame is at `g` (the formula of
/// [`SpatialInertia::rotated_moved`], written out on the columns of R).
#[inline(always)]
fn packed_at(b: &SpatialInertia, g: &Columns) -> Packed {
    let [c0, c1, c2, p] = g.0;
    let rot = |x: [f64; 3]| -> [f64; 3] {
        std::array::from_fn(|i| c0[i] * x[0] + c1[i] * x[1] + c2[i] * x[2])
    };
    let m = b.mass;
    let hr = rot(b.first_moment.into());
    let i = &b.rotational;
    // B = R Ī (columns: R times Ī's columns), then (B Rᵀ)(r, c) = Σ_k B(r, k) R(c, k).
    let b0 = rot([i[(0, 0)], i[(1, 0)], i[(2, 0)]]);
    let b1 = rot([i[(0, 1)], i[(1, 1)], i[(2, 1)]]);
    let b2 = rot([i[(0, 2)], i[(1, 2)], i[(2, 2)]]);
    let rr = |r: usize, c: usize| b0[r] * c0[c] + b1[r] * c1[c] + b2[r] * c2[c];
    let diag = m * (p[0] * p[0] + p[1] * p[1] + p[2] * p[2])
        + 2.0 * (p[0] * hr[0] + p[1] * hr[1] + p[2] * hr[2]);
    let shift = |r: usize, c: usize| m * p[r] * p[c] + hr[r] * p[c] + p[r] * hr[c];
    [
        m,
        hr[0] + m * p[0],
        hr[1] + m * p[1],
        hr[2] + m * p[2],
        rr(0, 0) - shift(0, 0) + diag,
        rr(0, 1) - shift(0, 1),
        rr(0, 2) - shift(0, 2),
        rr(1, 1) - shift(1, 1) + diag,
        rr(1, 2) - shift(1, 2),
        rr(2, 2) - shift(2, 2) + diag,
    ]
}

/// G S for a packed inertia and a twist S = (ω, v): (Ī_o ω + h × v, m v − h × ω).
#[inline(always)]
fn packed_apply(g: &Packed, s: &[f64; 6]) -> [f64; 6] {
    let [m, hx, hy, hz, xx, xy, xz, yy, yz, zz] = *g;
    let [wx, wy, wz, vx, vy, vz] = *s;
    [
        xx * wx + xy * wy + xz * wz + (hy * vz - hz * vy),
        xy * wx + yy * wy + yz * wz + (hz * vx - hx * vz),
        xz * wx + yz * wy + zz * wz + (hx * vy - hy * vx),
        m * vx - (hy * wz - hz * wy),
        m * vy - (hz * wx - hx * wz),
        m * vz - (hx * wy - hy * wx),
    ]
}

/// The composite-rigid-body pass at placed joints (their frames J_k in the root link's frame),
/// into `ws.mass`, in the root link's frame (Featherstone's and Pinocchio's world convention):
/// each body there, I_k = [Ad_{J_k⁻¹}]ᵀ G_k [Ad_{J_k⁻¹}], each joint's screw
/// S_k = [Ad_{J_k}] a_k; the composite bodies are plain sums I^c_k = I_k + Σ_children I^c_c, and
/// M(l, k) = S_lᵀ I^c_k S_k for l = k and its ancestors (m_l m_k with a mimic's multipliers;
/// with a floating base, M(base, k) = I^c_k S_k and M(base, base) = the whole robot's I^c).
#[inline(always)]
fn crba(d: &Dynamics, ws: &mut DynamicsWorkspace) {
    let off = if d.floating { 6 } else { 0 };
    let joints = &d.joints;
    let root = composite(d, ws);
    let nv = d.nv;
    let mass = ws.mass.as_mut_slice();
    mass.fill(0.0);
    if d.floating {
        let [m, hx, hy, hz, xx, xy, xz, yy, yz, zz] = root;
        let g = [
            [xx, xy, xz, 0.0, -hz, hy],
            [xy, yy, yz, hz, 0.0, -hx],
            [xz, yz, zz, -hy, hx, 0.0],
            [0.0, hz, -hy, m, 0.0, 0.0],
            [-hz, 0.0, hx, 0.0, m, 0.0],
            [hy, -hx, 0.0, 0.0, 0.0, m],
        ];
        for c in 0..6 {
            for r in 0..6 {
                mass[c * nv + r] = g[r][c];
            }
        }
    }
    let dot = |a: &[f64; 6], b: &[f64; 6]| {
        (a[0] * b[0] + a[1] * b[1]) + (a[2] * b[2] + a[3] * b[3]) + (a[4] * b[4] + a[5] * b[5])
    };
    for k in 0..joints.len() {
        let vk = off + joints[k].variable;
        let f = packed_apply(&ws.packed[k], &ws.screw_packed[k]);
        let mut l = k;
        loop {
            let vl = off + joints[l].variable;
            let m = dot(&ws.screw_packed[l], &f);
            mass[vk * nv + vl] += m;
            if l != k {
                mass[vl * nv + vk] += m;
            }
            match joints[l].parent {
                NONE => break,
                p => l = p,
            }
        }
        if d.floating {
            for i in 0..6 {
                mass[vk * nv + i] += f[i];
                mass[i * nv + vk] += f[i];
            }
        }
    }
    if d.passive {
        // The rotors' inertias (asked for in the options).
        for (i, a) in d.armature.iter().enumerate() {
            mass[i * nv + i] += a;
        }
    }
}

/// Forward dynamics a = FD(q, v, τ) = M(q)⁻¹ (τ − h(q, v)): the accelerations the forces τ
/// give at (q, v) under gravity — by the articulated-body algorithm ([`aba`]) for a model of at
/// least [`ABA_FROM`] velocity entries whose variables each drive one joint, else by a
/// Cholesky factorisation of the mass matrix. Pinocchio's `aba` answers the same. An error
/// when M is not positive definite (a moving joint with no mass beyond it).
pub fn forward_dynamics<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<&'w [f64], SolveError> {
    // The articulated-body algorithm is O(n) but with 6 × 6 products per joint; the mass
    // matrix and its factorisation win below a dozen variables (measured: the UR5's 6, 1.09
    // against 1.23 µs; the humanoid's 23, 4.97 against 4.47 µs).
    if d.uncoupled && d.nv >= ABA_FROM {
        return aba(d, ws, q, v, tau);
    }
    forward_dynamics_tip(d, ws, q, v, tau, &[0.0; 6])
}

/// The fewest velocity entries for which [`forward_dynamics`] runs the articulated-body
/// algorithm (when no variable drives several joints).
pub const ABA_FROM: usize = 12;

/// Forward dynamics by the articulated-body algorithm (Featherstone; Pinocchio's `aba`), for
/// a model whose variables each drive one joint: outward, each body's velocity, bias
/// acceleration c_k = [ad_{V_k}] a_k θ̇_k and bias force p_k = −[ad_{V_k}]ᵀ G_k V_k; inward,
/// the articulated inertia I^A_k and bias p^A_k, U = I^A a, D = aᵀ U, u = τ − aᵀ p^A, the
/// parent gaining [Ad]ᵀ (I^A − U D⁻¹ Uᵀ) [Ad] and [Ad]ᵀ (p^A + I^a c + U D⁻¹ u); outward
/// again, θ̈_k = (u − Uᵀ A'_k) / D with A'_k = [Ad_{T_k⁻¹}] A_parent + c_k. Gravity is the
/// root's acceleration −g.
pub fn aba<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<&'w [f64], SolveError> {
    check_nv(d, v, "velocity value")?;
    check_nv(d, tau, "force value")?;
    let base = place(d, ws, q, Frames::Local)?;
    let off = if d.floating { 6 } else { 0 };
    let joints = &d.joints;
    let n = joints.len();
    let mut root_vel = Vector6::zeros();
    if d.floating {
        root_vel = Vector6::from_iterator(v[..6].iter().copied());
    }
    // −g seen from the root.
    let up = base.rotation().transpose() * -d.gravity;
    let lift = Vector6::new(0.0, 0.0, 0.0, up.x, up.y, up.z);
    for (k, j) in joints.iter().enumerate() {
        let vp = match j.parent {
            NONE => root_vel,
            p => ws.velocity[p],
        };
        let s = vec6(&j.axis);
        let rate = v[off + j.variable];
        let vk = twist_in_child(&ws.local[k], &vp) + s * rate;
        ws.velocity[k] = vk;
        ws.bias_acc[k] = ad(&vk, &s) * rate;
        let g = &d.bodies[k];
        ws.articulated[k] = g.matrix();
        ws.bias_force[k] = -ad_transpose(&vk, &g.apply(&vk));
    }
    let mut root_inertia = d.root.matrix();
    let mut root_bias = if d.floating {
        -ad_transpose(&root_vel, &d.root.apply(&root_vel))
    } else {
        Vector6::zeros()
    };
    for k in (0..n).rev() {
        let j = &joints[k];
        let s = vec6(&j.axis);
        let ia = ws.articulated[k];
        let u_vec = ia * s;
        // (A rotor's armature adds to D, a damper's force −damping · θ̇ to u.)
        let var = off + j.variable;
        let dk = s.dot(&u_vec) + d.armature[var];
        let uk = tau[var] - d.damping[var] * v[var] - s.dot(&ws.bias_force[k]);
        if !(dk > 0.0 && dk.is_finite()) {
            return Err(SolveError::InvalidInput(format!(
                "no inertia moves with \"{}\" (the articulated inertia about its axis is {dk})",
                d.v_names[off + j.variable]
            )));
        }
        let dinv = 1.0 / dk;
        ws.u_vec[k] = u_vec;
        ws.d_inv[k] = dinv;
        ws.u_scalar[k] = uk;
        let reduced = ia - u_vec * u_vec.transpose() * dinv;
        let bias = ws.bias_force[k] + reduced * ws.bias_acc[k] + u_vec * (dinv * uk);
        let x = ws.local[k].inverse().adjoint();
        let up_inertia = x.transpose() * reduced * x;
        let up_bias = wrench_in_parent(&ws.local[k], &bias);
        match j.parent {
            NONE => {
                root_inertia += up_inertia;
                root_bias += up_bias;
            }
            p => {
                ws.articulated[p] += up_inertia;
                ws.bias_force[p] += up_bias;
            }
        }
    }
    // The root's acceleration with gravity's lift: −g for a fixed base; for a floating one,
    // solved from its articulated inertia, I^A A_root + p^A = τ_base, the base's own
    // acceleration being A_root − lift.
    let root_acc = if d.floating {
        let f = Vector6::from_iterator(tau[..6].iter().copied()) - root_bias;
        let sym = (root_inertia + root_inertia.transpose()) * 0.5;
        let a = sym.cholesky().map(|c| c.solve(&f)).ok_or_else(|| {
            SolveError::InvalidInput("the floating base carries no inertia".into())
        })?;
        for i in 0..6 {
            ws.tau[i] = a[i] - lift[i];
        }
        a
    } else {
        lift
    };
    for (k, j) in joints.iter().enumerate() {
        let ap = match j.parent {
            NONE => root_acc,
            p => ws.acceleration[p],
        };
        let s = vec6(&j.axis);
        let a_prime = twist_in_child(&ws.local[k], &ap) + ws.bias_acc[k];
        let qdd = ws.d_inv[k] * (ws.u_scalar[k] - ws.u_vec[k].dot(&a_prime));
        ws.acceleration[k] = a_prime + s * qdd;
        ws.tau[off + j.variable] = qdd;
    }
    Ok(&ws.tau)
}

/// [`forward_dynamics`] with the last body pressing on the environment with the wrench `tip`
/// at its tip frame (the textbook's `ForwardDynamics`): a = M⁻¹ (τ − h − Jᵀ F_tip).
pub fn forward_dynamics_tip<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    tip: &[f64; 6],
) -> Result<&'w [f64], SolveError> {
    check_values(&TIP_NAMES.map(String::from), tip, "tip wrench value")?;
    let at_tip = [d.at_tip(tip)];
    let pressed = if tip.iter().any(|x| *x != 0.0) {
        &at_tip[..]
    } else {
        &[]
    };
    forward_dynamics_exerting(d, ws, q, v, tau, pressed)
}

/// Forward dynamics with the robot exerting wrenches on its environment at frames
/// ([`Dynamics::exerted`]; a wrench on the robot is the opposite of one it exerts):
/// a = M⁻¹ (τ − h − Σ J_fᵀ F_f), by the mass matrix's Cholesky factorisation.
#[allow(clippy::needless_range_loop)] // the factorisation reads as its formulas, by index
pub fn forward_dynamics_exerting<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    pressed: &[Exerted],
) -> Result<&'w [f64], SolveError> {
    check_nv(d, v, "velocity value")?;
    check_nv(d, tau, "force value")?;
    let base = place(d, ws, q, Frames::Both)?;
    newton_euler(d, ws, &base, Some(v), None, true, pressed);
    crba(d, ws);
    let nv = d.nv;
    for i in 0..nv {
        ws.rhs[i] = tau[i] - ws.tau[i];
    }
    // M = L Lᵀ in `factor` (its lower triangle), then L y = rhs, Lᵀ a = y.
    let (m, l) = (&ws.mass, &mut ws.factor);
    for j in 0..nv {
        let mut s = m[(j, j)];
        for k in 0..j {
            s -= l[(j, k)] * l[(j, k)];
        }
        if !(s > 0.0 && s.is_finite()) {
            return Err(SolveError::InvalidInput(format!(
                "the mass matrix is not positive definite at \"{}\" (no mass moves with it?)",
                d.v_names[j]
            )));
        }
        let ljj = s.sqrt();
        l[(j, j)] = ljj;
        for i in j + 1..nv {
            let mut s = m[(i, j)];
            for k in 0..j {
                s -= l[(i, k)] * l[(j, k)];
            }
            l[(i, j)] = s / ljj;
        }
    }
    let y = &mut ws.rhs;
    for i in 0..nv {
        let mut s = y[i];
        for k in 0..i {
            s -= l[(i, k)] * y[k];
        }
        y[i] = s / l[(i, i)];
    }
    for i in (0..nv).rev() {
        let mut s = y[i];
        for k in i + 1..nv {
            s -= l[(k, i)] * y[k];
        }
        y[i] = s / l[(i, i)];
    }
    ws.tau.copy_from_slice(&ws.rhs);
    Ok(&ws.tau)
}

/// The centroidal momentum map A_G(q) (6 × nv) and the centre of mass c (world): the robot's
/// momentum about its centre of mass, h_G = A_G v = (k_G, p) (angular, then linear; the
/// wrench order), in the world's axes (Orin and Goswami's centroidal momentum; Pinocchio's
/// `computeCentroidalMap`, whose rows are (linear, angular)). The centre of mass is every
/// link's, those fixed to the world too (as `com` computes it; Pinocchio's leaves out a fixed
/// base's links, which moves its angular rows by (c − c_pin) × p).
///
/// Column k is the momentum of unit speed of variable k: in the root link's frame at its
/// origin, the composite body's I^c_k S_k of [`mass_matrix`] (with a floating base, the whole
/// robot's I^c e_i for the base's six), turned into the world's axes (R) and taken about c:
/// (k, p) = (R m − [c − p_base] R f, R f).
pub fn centroidal_map<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
) -> Result<(&'w DMatrix<f64>, [f64; 3]), SolveError> {
    let base = place(d, ws, q, Frames::Root)?;
    let off = if d.floating { 6 } else { 0 };
    let root = dispatch(Pass(|| composite(d, ws)));
    let [m, hx, hy, hz, ..] = root;
    if m.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(SolveError::InvalidInput(
            "the robot has no mass: no centre of mass".into(),
        ));
    }
    let (rb, pb) = (base.rotation(), base.translation());
    // c − p_base in the world's axes (the root link's frame at the base's pose).
    let lever = rb * Vector3::new(hx / m, hy / m, hz / m);
    let map = &mut ws.centroidal;
    map.fill(0.0);
    let mut column = |col: usize, f: [f64; 6]| {
        let ang = rb * Vector3::new(f[0], f[1], f[2]);
        let lin = rb * Vector3::new(f[3], f[4], f[5]);
        let k = ang - lever.cross(&lin);
        for (i, x) in [k.x, k.y, k.z, lin.x, lin.y, lin.z].into_iter().enumerate() {
            map[(i, col)] += x;
        }
    };
    if d.floating {
        for i in 0..6 {
            let mut e = [0.0; 6];
            e[i] = 1.0;
            column(i, packed_apply(&root, &e));
        }
    }
    for (k, j) in d.joints.iter().enumerate() {
        column(
            off + j.variable,
            packed_apply(&ws.packed[k], &ws.screw_packed[k]),
        );
    }
    let c = lever + pb;
    Ok((&ws.centroidal, [c.x, c.y, c.z]))
}

/// The centroidal momentum h_G = A_G(q) v = (k_G, p) (angular about the centre of mass, then
/// linear; world axes) and the centre of mass c ([`centroidal_map`]; Pinocchio's
/// `computeCentroidalMomentum`, in (linear, angular) order).
pub fn centroidal_momentum(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
) -> Result<([f64; 6], [f64; 3]), SolveError> {
    check_nv(d, v, "velocity value")?;
    let (map, c) = centroidal_map(d, ws, q)?;
    let mut h = [0.0; 6];
    for (col, x) in map.column_iter().zip(v) {
        for (h, a) in h.iter_mut().zip(col.iter()) {
            *h += a * x;
        }
    }
    Ok((h, c))
}

/// A pass run by [`dispatch`]: its body compiled for AVX2 and FMA where the CPU has them (the
/// multiply-adds as the compiler writes them; the kernels' explicit ones are `A`'s).
struct Pass<T, F: FnOnce() -> T>(F);

impl<T, F: FnOnce() -> T> Kernel for Pass<T, F> {
    type Output = T;
    #[inline(always)]
    fn run<A: MulAdd>(self) -> T {
        (self.0)()
    }
}

/// The kinetic energy ½ Σ V_kᵀ G_k V_k (= ½ vᵀ M(q) v).
pub fn kinetic_energy(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
) -> Result<f64, SolveError> {
    check_nv(d, v, "velocity value")?;
    let base = place(d, ws, q, Frames::Local)?;
    newton_euler(d, ws, &base, Some(v), None, false, &[]);
    let mut e = 0.0;
    for k in 0..d.bodies.len() {
        let vk = ws.velocity[k];
        e += 0.5 * vk.dot(&d.bodies[k].apply(&vk));
    }
    if d.floating {
        let vr = Vector6::from_iterator(v[..6].iter().copied());
        e += 0.5 * vr.dot(&d.root.apply(&vr));
    }
    // The rotors' (armature, when asked).
    e += 0.5
        * d.armature
            .iter()
            .zip(v)
            .map(|(a, x)| a * x * x)
            .sum::<f64>();
    Ok(e)
}

/// The potential energy −Σ m_i gᵀ c_i (c_i each body's centre of mass in the world; zero at
/// the world's origin height for g along −z).
pub fn potential_energy(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    q: &[f64],
) -> Result<f64, SolveError> {
    let base = place(d, ws, q, Frames::Root)?;
    let mut e = 0.0;
    let body_energy = |b: &SpatialInertia, r: &nalgebra::Matrix3<f64>, p: &Vector3<f64>| {
        // The first moment in the world: R h + m p.
        let h = r * b.first_moment + p * b.mass;
        -d.gravity.dot(&h)
    };
    let (rb, pb) = (base.rotation(), base.translation());
    for k in 0..d.bodies.len() {
        // The joint frame in the world: the base's pose, then J_k (in the root link's frame).
        let (r, p) = ws.world[k].rotation_translation();
        e += body_energy(&d.bodies[k], &(rb * r), &(rb * p + pb));
    }
    e += body_energy(&d.root, rb, pb);
    Ok(e)
}

/// What [`batch`] computes per row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// τ = ID(q, v, a): inputs q, v, a; nv values.
    InverseDynamics,
    /// g(q): input q; nv values.
    Gravity,
    /// h(q, v): inputs q, v; nv values.
    NonlinearEffects,
    /// M(q): input q; nv × nv values, row-major.
    MassMatrix,
    /// a = FD(q, v, τ): inputs q, v, τ; nv values.
    ForwardDynamics,
    /// ½ vᵀ M v: inputs q, v; one value.
    KineticEnergy,
    /// The potential energy: input q; one value.
    PotentialEnergy,
}

impl Quantity {
    /// How many nv-wide inputs it takes after q (0, 1 or 2).
    pub fn inputs(self) -> usize {
        match self {
            Quantity::Gravity | Quantity::MassMatrix | Quantity::PotentialEnergy => 0,
            Quantity::NonlinearEffects | Quantity::KineticEnergy => 1,
            Quantity::InverseDynamics | Quantity::ForwardDynamics => 2,
        }
    }

    /// Its values per row.
    pub fn width(self, nv: usize) -> usize {
        match self {
            Quantity::MassMatrix => nv * nv,
            Quantity::KineticEnergy | Quantity::PotentialEnergy => 1,
            _ => nv,
        }
    }
}

/// `what` at one configuration into `out` ([`Quantity::width`] values): q, then the nv-wide
/// inputs it takes in `x` and `y` (empty otherwise). One row of [`batch`].
pub fn compute(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    what: Quantity,
    q: &[f64],
    x: &[f64],
    y: &[f64],
    out: &mut [f64],
) -> Result<(), SolveError> {
    match what {
        Quantity::InverseDynamics => out.copy_from_slice(inverse_dynamics(d, ws, q, x, y)?),
        Quantity::Gravity => out.copy_from_slice(gravity(d, ws, q)?),
        Quantity::NonlinearEffects => out.copy_from_slice(nonlinear_effects(d, ws, q, x)?),
        Quantity::ForwardDynamics => out.copy_from_slice(forward_dynamics(d, ws, q, x, y)?),
        // M is exactly symmetric: its column-major storage is its row-major one.
        Quantity::MassMatrix => out.copy_from_slice(mass_matrix(d, ws, q)?.as_slice()),
        Quantity::KineticEnergy => out[0] = kinetic_energy(d, ws, q, x)?,
        Quantity::PotentialEnergy => out[0] = potential_energy(d, ws, q)?,
    }
    Ok(())
}

/// `what` for N rows in parallel (rayon; a batch of at most one chunk on the calling thread):
/// each row of `rows` is q (nq) followed by the nv-wide inputs `what` takes (v, then a or τ:
/// [`Quantity::inputs`]); `out` is N × [`Quantity::width`]. A bad row gets NaN and is listed
/// in [`SolveError::Rows`], the others are computed; row k equals the single call on row k
/// bit for bit whatever the thread count.
pub fn batch(
    d: &Dynamics,
    what: Quantity,
    rows: &[f64],
    out: &mut [f64],
) -> Result<(), SolveError> {
    use crate::batch::{check_out, finish, rows_of, CHUNK};
    use crate::error::RowError;
    use rayon::prelude::*;
    let (nq, nv) = (d.nq, d.nv);
    let in_width = nq + what.inputs() * nv;
    let n = rows_of(
        rows.len(),
        in_width.max(1),
        "input values (N × (nq + k nv))",
    )?;
    let width = what.width(nv);
    check_out(out.len(), n, width, "output values")?;
    let work = |ws: &mut DynamicsWorkspace, (chunk, o): (usize, &mut [f64])| {
        let mut errors = Vec::new();
        let first = chunk * CHUNK;
        for (i, out_row) in o.chunks_mut(width.max(1)).enumerate() {
            let r = first + i;
            let input = &rows[r * in_width..(r + 1) * in_width];
            let (q, rest) = input.split_at(nq);
            let (x, y) = rest.split_at(rest.len().min(nv));
            if let Err(error) = compute(d, ws, what, q, x, y, out_row) {
                out_row.fill(f64::NAN);
                errors.push(RowError { row: r, error });
            }
        }
        errors
    };
    if n <= CHUNK {
        return finish(work(&mut DynamicsWorkspace::new(d), (0, out)));
    }
    let errors: Vec<RowError> = out
        .par_chunks_mut(CHUNK * width.max(1))
        .enumerate()
        .map_init(|| DynamicsWorkspace::new(d), work)
        .flatten()
        .collect();
    finish(errors)
}
