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
use screwkit_lie::{Se3, Twist};

use super::{TreeKinematics, NONE};
use crate::error::SolveError;

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

    /// The same body seen from a frame in which this one is at `t` (this frame's pose in
    /// the new one): G' = [Ad_{t⁻¹}]ᵀ G [Ad_{t⁻¹}].
    pub fn transformed(&self, t: &Se3) -> Self {
        let r = t.rotation();
        let p = t.translation();
        let h = r * self.first_moment;
        let px = p.cross_matrix();
        let hx = h.cross_matrix();
        Self {
            mass: self.mass,
            first_moment: h + p * self.mass,
            rotational: r * self.rotational * r.transpose()
                - px * px * self.mass
                - px * hx
                - hx * px,
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

/// The immutable dynamic model of a tree: each moving joint's body (and, with a floating base,
/// the root's) and gravity. Build once with [`Dynamics::new`], share freely.
#[derive(Debug, Clone)]
pub struct Dynamics {
    kin: TreeKinematics,
    /// Each joint's body in its own frame (the links it supports).
    bodies: Vec<SpatialInertia>,
    /// The root body (the links no joint moves) in the root link's frame.
    root: SpatialInertia,
    /// Each joint's screw in its own frame, and its home placement in its parent joint's frame.
    axes: Vec<Twist>,
    placements: Vec<Se3>,
    /// Gravity in the world (default (0, 0, −9.81)).
    gravity: Vector3<f64>,
    /// Links without an `<inertial>` (massless), said once by the front ends.
    massless: Vec<String>,
}

impl Dynamics {
    /// The dynamic model of `kin`'s tree from its links' `<inertial>`s. A link without one is
    /// massless (listed in [`Dynamics::massless`]). An inertial that cannot be a rigid body's
    /// (a negative mass, a tensor not positive semi-definite or breaking the triangle
    /// inequality: [`screwkit_model::Inertial::problem`]) is an error naming its link, unless
    /// `as_given` takes the file's numbers as they are.
    pub fn new(kin: &TreeKinematics, as_given: bool) -> Result<Self, SolveError> {
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
            if !as_given {
                if let Some(problem) = inertial.problem() {
                    return Err(SolveError::InvalidInput(format!(
                        "link \"{}\" <inertial>: {problem} (dynamics needs a rigid body's; take the file's numbers as they are with the as-given option)",
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
        let axes = model.joints.iter().map(super::local_screw).collect();
        let placements = model.joints.iter().map(|j| j.placement).collect();
        Ok(Self {
            kin: kin.clone(),
            bodies,
            root,
            axes,
            placements,
            gravity: Vector3::new(0.0, 0.0, -STANDARD_GRAVITY),
            massless,
        })
    }

    /// The kinematic tree.
    pub fn kinematics(&self) -> &TreeKinematics {
        &self.kin
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
}

/// One thread's scratch for the dynamics algorithms.
#[derive(Debug, Clone)]
pub struct DynamicsWorkspace {
    /// Each joint frame in its parent's (T_k = X_k e^{[a_k]θ_k}).
    local: Vec<Se3>,
    velocity: Vec<Vector6<f64>>,
    acceleration: Vec<Vector6<f64>>,
    force: Vec<Vector6<f64>>,
    composite: Vec<Matrix6<f64>>,
    root_force: Vector6<f64>,
    /// The mass matrix and its Cholesky factor (nv × nv).
    mass: DMatrix<f64>,
    factor: DMatrix<f64>,
    tau: Vec<f64>,
    rhs: Vec<f64>,
    /// Each joint frame in the world.
    world: Vec<Se3>,
}

impl DynamicsWorkspace {
    /// Scratch for `dynamics`.
    pub fn new(dynamics: &Dynamics) -> Self {
        let n = dynamics.bodies.len();
        let nv = dynamics.kin.nv();
        Self {
            local: vec![Se3::identity(); n],
            velocity: vec![Vector6::zeros(); n],
            acceleration: vec![Vector6::zeros(); n],
            force: vec![Vector6::zeros(); n],
            composite: vec![Matrix6::zeros(); n],
            root_force: Vector6::zeros(),
            mass: DMatrix::zeros(nv, nv),
            factor: DMatrix::zeros(nv, nv),
            tau: vec![0.0; nv],
            rhs: vec![0.0; nv],
            world: vec![Se3::identity(); n],
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

/// The root's pose and each joint's T_k at q (checked); the joint variables' θ from q.
fn place(d: &Dynamics, ws: &mut DynamicsWorkspace, q: &[f64]) -> Result<Se3, SolveError> {
    let kin = &d.kin;
    let base = kin.check_q(q)?;
    let joints = &q[kin.q_offset()..];
    for (k, j) in kin.model.joints.iter().enumerate() {
        let theta = j.drive.multiplier * joints[j.drive.variable] + j.drive.offset;
        ws.local[k] = d.placements[k].compose(&Se3::exp(&(d.axes[k] * theta)));
    }
    Ok(base)
}

/// Checks a vector of nv values named `what`.
fn check_nv(kin: &TreeKinematics, x: &[f64], what: &'static str) -> Result<(), SolveError> {
    if x.len() != kin.nv() {
        return Err(SolveError::WrongLength {
            what,
            expected: kin.nv(),
            got: x.len(),
            names: super::short_names(&kin.v_names),
        });
    }
    if let Some(i) = x.iter().position(|v| !v.is_finite()) {
        return Err(SolveError::NonFinite {
            what,
            index: i,
            name: kin.v_names.get(i).cloned().unwrap_or_default(),
            value: x[i],
        });
    }
    Ok(())
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
) {
    let kin = &d.kin;
    let off = if kin.floating { 6 } else { 0 };
    let at = |x: Option<&[f64]>, k: usize| x.map_or(0.0, |x| x[k]);
    let mut root_vel = Vector6::zeros();
    let mut root_acc = Vector6::zeros();
    if kin.floating {
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
    let joints = &kin.model.joints;
    for (k, j) in joints.iter().enumerate() {
        let (vp, ap) = match kin.parent[k] {
            NONE => (root_vel, root_acc),
            p => (ws.velocity[p], ws.acceleration[p]),
        };
        let t = &ws.local[k];
        let s = vec6(&d.axes[k]);
        let var = off + j.drive.variable;
        let rate = j.drive.multiplier * at(v, var);
        let acc = j.drive.multiplier * at(a, var);
        let vk = twist_in_child(t, &vp) + s * rate;
        let ak = twist_in_child(t, &ap) + s * acc + ad(&vk, &s) * rate;
        let g = d.bodies[k].matrix();
        ws.force[k] = g * ak - ad_transpose(&vk, &(g * vk));
        ws.velocity[k] = vk;
        ws.acceleration[k] = ak;
    }
    ws.root_force = if kin.floating {
        let g = d.root.matrix();
        g * root_acc - ad_transpose(&root_vel, &(g * root_vel))
    } else {
        Vector6::zeros()
    };
    ws.tau.iter_mut().for_each(|x| *x = 0.0);
    for k in (0..joints.len()).rev() {
        let j = &joints[k];
        let s = vec6(&d.axes[k]);
        ws.tau[off + j.drive.variable] += j.drive.multiplier * s.dot(&ws.force[k]);
        let up = wrench_in_parent(&ws.local[k], &ws.force[k]);
        match kin.parent[k] {
            NONE => ws.root_force += up,
            p => ws.force[p] += up,
        }
    }
    if kin.floating {
        for i in 0..6 {
            ws.tau[i] = ws.root_force[i];
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
    check_nv(&d.kin, v, "velocity value")?;
    check_nv(&d.kin, a, "acceleration value")?;
    let base = place(d, ws, q)?;
    newton_euler(d, ws, &base, Some(v), Some(a), true);
    Ok(&ws.tau)
}

/// The gravity forces g(q) = ID(q, 0, 0). Pinocchio's `computeGeneralizedGravity`.
pub fn gravity<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
) -> Result<&'w [f64], SolveError> {
    let base = place(d, ws, q)?;
    newton_euler(d, ws, &base, None, None, true);
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
    check_nv(&d.kin, v, "velocity value")?;
    let base = place(d, ws, q)?;
    newton_euler(d, ws, &base, Some(v), None, true);
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
    place(d, ws, q)?;
    crba(d, ws);
    Ok(&ws.mass)
}

/// The composite-rigid-body pass at placed joints, into `ws.mass`.
fn crba(d: &Dynamics, ws: &mut DynamicsWorkspace) {
    let kin = &d.kin;
    let off = if kin.floating { 6 } else { 0 };
    let joints = &kin.model.joints;
    let n = joints.len();
    for k in 0..n {
        ws.composite[k] = d.bodies[k].matrix();
    }
    let mut root = d.root.matrix();
    for k in (0..n).rev() {
        let x = ws.local[k].inverse().adjoint();
        let up = x.transpose() * ws.composite[k] * x;
        match kin.parent[k] {
            NONE => root += up,
            p => ws.composite[p] += up,
        }
    }
    ws.mass.fill(0.0);
    if kin.floating {
        // (Exactly symmetric: the sums above round each triangle on its own.)
        let root = (root + root.transpose()) * 0.5;
        ws.mass.view_mut((0, 0), (6, 6)).copy_from(&root);
    }
    for k in 0..n {
        let jk = &joints[k];
        let vk = off + jk.drive.variable;
        let sk = vec6(&d.axes[k]);
        let mut f = ws.composite[k] * sk * jk.drive.multiplier;
        let mut l = k;
        loop {
            let jl = &joints[l];
            let vl = off + jl.drive.variable;
            let m = jl.drive.multiplier * vec6(&d.axes[l]).dot(&f);
            ws.mass[(vl, vk)] += m;
            if l != k {
                ws.mass[(vk, vl)] += m;
            }
            f = wrench_in_parent(&ws.local[l], &f);
            match kin.parent[l] {
                NONE => break,
                p => l = p,
            }
        }
        if kin.floating {
            for i in 0..6 {
                ws.mass[(i, vk)] += f[i];
                ws.mass[(vk, i)] += f[i];
            }
        }
    }
}

/// Forward dynamics a = FD(q, v, τ) = M(q)⁻¹ (τ − h(q, v)): the accelerations the forces τ
/// give at (q, v) under gravity (a Cholesky factorisation of the mass matrix). Pinocchio's
/// `aba` answers the same. An error when M is not positive definite (a moving joint with no
/// mass beyond it).
#[allow(clippy::needless_range_loop)] // the factorisation reads as its formulas, by index
pub fn forward_dynamics<'w>(
    d: &Dynamics,
    ws: &'w mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
) -> Result<&'w [f64], SolveError> {
    check_nv(&d.kin, v, "velocity value")?;
    check_nv(&d.kin, tau, "force value")?;
    let base = place(d, ws, q)?;
    newton_euler(d, ws, &base, Some(v), None, true);
    crba(d, ws);
    let nv = d.kin.nv();
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
                d.kin.v_names[j]
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

/// The kinetic energy ½ Σ V_kᵀ G_k V_k (= ½ vᵀ M(q) v).
pub fn kinetic_energy(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    q: &[f64],
    v: &[f64],
) -> Result<f64, SolveError> {
    check_nv(&d.kin, v, "velocity value")?;
    let base = place(d, ws, q)?;
    newton_euler(d, ws, &base, Some(v), None, false);
    let kin = &d.kin;
    let mut e = 0.0;
    for k in 0..d.bodies.len() {
        let vk = ws.velocity[k];
        e += 0.5 * vk.dot(&(d.bodies[k].matrix() * vk));
    }
    if kin.floating {
        let vr = Vector6::from_iterator(v[..6].iter().copied());
        e += 0.5 * vr.dot(&(d.root.matrix() * vr));
    }
    Ok(e)
}

/// The potential energy −Σ m_i gᵀ c_i (c_i each body's centre of mass in the world; zero at
/// the world's origin height for g along −z).
pub fn potential_energy(
    d: &Dynamics,
    ws: &mut DynamicsWorkspace,
    q: &[f64],
) -> Result<f64, SolveError> {
    let base = place(d, ws, q)?;
    let kin = &d.kin;
    let mut e = 0.0;
    let body_energy = |b: &SpatialInertia, t: &Se3| -> f64 {
        // The first moment in the world: R h + m p.
        let h = t.rotation() * b.first_moment + t.translation() * b.mass;
        -d.gravity.dot(&h)
    };
    for k in 0..d.bodies.len() {
        let parent = match kin.parent[k] {
            NONE => base,
            p => ws.world[p],
        };
        ws.world[k] = parent.compose(&ws.local[k]);
        e += body_energy(&d.bodies[k], &ws.world[k]);
    }
    e += body_energy(&d.root, &base);
    Ok(e)
}
