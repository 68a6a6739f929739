//! [`Kinematics`]: the immutable model of a chain prepared for the algorithms (Pinocchio's
//! `Model`). Its scratch counterpart is [`crate::Workspace`].

use screwkit_lie::{Frame, Se3};
use screwkit_model::{Chain, ChainLink, JointKind};

use crate::columns::Columns;
use crate::error::SolveError;
use crate::poe::PoeJoint;

/// The immutable kinematic model of a chain, prepared for the algorithms: per-joint constants
/// of the space and body screws, M, the links' home poses, limits, names. Build once with
/// [`Kinematics::new`] and share freely (it is `Send + Sync`); every algorithm takes it by
/// reference together with a per-thread [`crate::Workspace`].
#[derive(Debug, Clone)]
pub struct Kinematics {
    /// The constants of the space screws S_j (used base → tip).
    pub(crate) space: Vec<PoeJoint>,
    /// The constants of the body screws B_j (used tip → base by the body Jacobian).
    pub(crate) body: Vec<PoeJoint>,
    /// M as columns.
    pub(crate) home_columns: Columns,
    pub(crate) home: Se3,
    pub(crate) links: Vec<ChainLink>,
    /// The links' home poses as columns.
    pub(crate) link_columns: Vec<Columns>,
    pub(crate) lower: Vec<f64>,
    pub(crate) upper: Vec<f64>,
    /// Continuous variables that are periodic in 2π (see `periodic`): IK wraps them to
    /// (−π, π] and analytic IK lists their 2π shifts; a continuous joint with a prismatic or
    /// non-integer follower is neither.
    pub(crate) continuous: Vec<bool>,
    /// Variable k turns a screw: adding 2π to it keeps every driven joint's rotation (revolute
    /// or helical joints with integer multipliers, prismatic followers) but not the pose (a
    /// helical joint, or a revolute one with a prismatic follower). IK's stalls try q_k ± 2π
    /// ([`crate::ik`]).
    pub(crate) turns: Vec<bool>,
    /// The first helical joint's name and pitch ([`Kinematics::helical`]).
    pub(crate) helical: Option<(String, f64)>,
    pub(crate) names: Vec<String>,
    /// L: the power of ten nearest the chain's reach at home (the farthest link origin from
    /// the base; 1 when every link sits at the origin). IK measures position errors in units
    /// of L (see [`Kinematics::length_scale`]).
    pub(crate) length_scale: f64,
    /// True when joint j is driven by q\[j\] alone (no mimic joints): θ = q, one Jacobian
    /// column per joint.
    pub(crate) identity_map: bool,
}

impl Kinematics {
    /// Prepares a chain for the algorithms.
    pub fn new(chain: &Chain) -> Self {
        let turning = Turning::of(chain);
        let table = |frame: Frame| -> Vec<PoeJoint> {
            chain
                .joints
                .iter()
                .map(|j| PoeJoint::new(*j.screw(frame).twist(), j.kind, j.drive))
                .collect()
        };
        Self {
            space: table(Frame::Space),
            body: table(Frame::Body),
            home_columns: Columns::from_se3(&chain.home),
            home: chain.home,
            links: chain.links.clone(),
            link_columns: chain
                .links
                .iter()
                .map(|l| Columns::from_se3(&l.home))
                .collect(),
            lower: chain.variables.iter().map(|v| v.lower).collect(),
            upper: chain.variables.iter().map(|v| v.upper).collect(),
            continuous: chain
                .variables
                .iter()
                .zip(&turning)
                .map(|(v, t)| v.kind == JointKind::Continuous && t.periodic())
                .collect(),
            helical: chain
                .joints
                .iter()
                .find(|j| j.kind == JointKind::Helical)
                .map(|j| (j.name.clone(), j.s_space.pitch().unwrap_or(0.0))),
            turns: turning.iter().map(Turning::turns).collect(),
            names: chain.variables.iter().map(|v| v.name.clone()).collect(),
            length_scale: length_scale(chain),
            identity_map: !chain.has_mimic(),
        }
    }

    /// L, the chain's length scale: the power of ten nearest its reach at home (the farthest
    /// link origin from the base), 1 when every link sits at the origin. IK weighs position
    /// errors by 1/L against rotation errors (rad), so its damping and steps behave the same
    /// whatever the robot's size; a power of ten keeps metre-sized arms exactly as before and
    /// makes a robot scaled by 10^k solve the very same normalised problem.
    pub fn length_scale(&self) -> f64 {
        self.length_scale
    }

    /// The first helical joint's name and pitch (m/rad), if the chain has one: such a chain is
    /// solved by numerical IK only (the analytic solvers take revolute joints).
    pub fn helical(&self) -> Option<(&str, f64)> {
        self.helical.as_ref().map(|(name, h)| (name.as_str(), *h))
    }

    /// Number of independent variables (the length of q).
    pub fn dof(&self) -> usize {
        self.names.len()
    }

    /// Variable names, in order.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Lower limits (−∞ for continuous joints).
    pub fn lower(&self) -> &[f64] {
        &self.lower
    }

    /// Upper limits (+∞ for continuous joints).
    pub fn upper(&self) -> &[f64] {
        &self.upper
    }

    /// M: the tip pose at home.
    pub fn home(&self) -> &Se3 {
        &self.home
    }

    /// The chain's links, base first, tip last, with their home poses: the order of
    /// [`crate::fk::fk_all_links`].
    pub fn links(&self) -> &[ChainLink] {
        &self.links
    }

    /// The midpoint of the limits (0 for unbounded variables): the default IK seed.
    pub fn midpoint(&self) -> Vec<f64> {
        self.lower
            .iter()
            .zip(&self.upper)
            .map(|(&l, &u)| {
                if l.is_finite() && u.is_finite() {
                    0.5 * (l + u)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// True when q has one value per variable and every value is within its limits (inclusive,
    /// widened by `tol`); false for a q of the wrong length or holding NaN.
    pub fn within_limits(&self, q: &[f64], tol: f64) -> bool {
        q.len() == self.dof()
            && q.iter()
                .zip(self.lower.iter().zip(&self.upper))
                .all(|(&x, (&l, &u))| x >= l - tol && x <= u + tol)
    }

    /// A slice of `got` values that must hold one value per variable (`what` names it in the
    /// error, with the variables' names).
    pub(crate) fn check_len(&self, what: &'static str, got: usize) -> Result<(), SolveError> {
        if got == self.dof() {
            return Ok(());
        }
        Err(SolveError::WrongLength {
            what,
            expected: self.dof(),
            got,
            names: self.names.join(", "),
        })
    }

    /// Checks a joint vector: one value per variable, all finite. Every checked algorithm
    /// calls this first; the error names the variable.
    pub fn check_q(&self, q: &[f64]) -> Result<(), SolveError> {
        self.check_len("joint values", q.len())?;
        match q.iter().position(|x| !x.is_finite()) {
            None => Ok(()),
            Some(i) => Err(SolveError::NonFinite {
                what: "joint value",
                index: i,
                name: self.names[i].clone(),
                value: q[i],
            }),
        }
    }
}

/// See [`Kinematics::length_scale`].
fn length_scale(chain: &Chain) -> f64 {
    let reach = chain
        .links
        .iter()
        .map(|l| l.home.translation().norm())
        .fold(0.0, f64::max);
    if reach > 1e-12 && reach.is_finite() {
        10f64.powf(reach.log10().round())
    } else {
        1.0
    }
}

/// What a whole turn (2π) of each variable does to the joints it drives, from one pass over
/// the joints.
#[derive(Debug, Clone, Copy)]
struct Turning {
    /// Every driven joint is revolute or continuous with a whole-turn multiplier (θ = m q + o
    /// turns m whole turns).
    all_whole_revolute: bool,
    /// Every driven joint keeps its rotation: rotating with a whole-turn multiplier, or
    /// prismatic.
    rotation_kept: bool,
    /// Some driven joint rotates.
    rotates: bool,
    /// Some driven joint slides (prismatic or helical).
    slides: bool,
}

impl Turning {
    fn of(chain: &Chain) -> Vec<Turning> {
        let mut out = vec![
            Turning {
                all_whole_revolute: true,
                rotation_kept: true,
                rotates: false,
                slides: false,
            };
            chain.variables.len()
        ];
        for j in &chain.joints {
            let t = &mut out[j.drive.variable];
            let whole = j.drive.whole_turns();
            t.all_whole_revolute &=
                matches!(j.kind, JointKind::Revolute | JointKind::Continuous) && whole;
            t.rotation_kept &= j.kind == JointKind::Prismatic || (j.kind.rotates() && whole);
            t.rotates |= j.kind.rotates();
            t.slides |= matches!(j.kind, JointKind::Prismatic | JointKind::Helical);
        }
        out
    }

    /// Adding 2π leaves the pose unchanged. A continuous joint with a prismatic or helical
    /// follower (a helical joint written as a mimic pair) or a non-integer multiplier is not
    /// periodic, and IK must not wrap it.
    fn periodic(&self) -> bool {
        self.all_whole_revolute
    }

    /// Adding 2π keeps every driven joint's rotation but moves the tip (a screw variable).
    fn turns(&self) -> bool {
        self.rotation_kept && self.rotates && self.slides
    }
}
