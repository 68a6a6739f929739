//! Robots given by their screw axes, as *Modern Robotics* teaches them: a home pose M and one
//! screw axis S_i = (ω, v) per joint, in the space (base) frame or the body (tip) frame.
//!
//! A row with ‖ω‖ = 1 is a rotating joint of pitch h = ω · v; a row with ω = 0 and ‖v‖ = 1 is
//! prismatic. Unit lengths are accepted to [`UNIT_TOLERANCE`] and normalised (rows typed or
//! printed to six decimals; a row unit to 4 ε is kept as it is); anything else is an error
//! naming the row. A rotating row is revolute when |h| ≤ [`PITCH_ROUNDED`] · max(1, ‖v‖) —
//! kept bit for bit within [`PITCH_ZERO`] (the rounding of v = −ω × q), else with v's
//! component along ω removed (six printed decimals, values typed by hand) — and helical
//! otherwise. A kind the description declares (a table's `type` column) decides between
//! prismatic, helical and pitch 0, and a row that contradicts it is an error; whether a pitch-0
//! joint is revolute or continuous, its limits say (bounded or not; a mimic joint's word stands,
//! its table limits being its leader's).
//!
//! The description gives no link frames. Each joint's frame is put, unrotated, at the point
//! of its axis nearest the previous joint's (the base origin for the first; a prismatic joint
//! keeps the previous point): these are the chain's link poses, what pictures draw, and the
//! frames of the tree ([`ScrewRobot::tree`]) whole-robot algorithms use. The chain
//! ([`ScrewRobot::chain`]) keeps the screws as read; the tree rebuilds them from points and
//! axes, equal to rounding.

use std::collections::HashMap;

use nalgebra::Vector3;
use screwkit_lie::{so3, Frame, ScrewAxis, Se3, Twist};

use crate::chain::{Chain, ChainJoint, ChainLink, Drive, Variable};
use crate::error::{ErrorKind, ModelError};
use crate::tree::{is_unbounded, JointKind, Limit, Mimic, Tree, TreeJointSpec};

/// |ω · v| / max(1, ‖v‖) of a rotating row that is rounding (64 ε, the rounding of
/// v = −ω × q): such a row is revolute and kept bit for bit.
pub const PITCH_ZERO: f64 = 64.0 * f64::EPSILON;

/// Largest |ω · v| / max(1, ‖v‖) of a rotating row read as revolute (2e-6: what six printed
/// decimals of ω and v leave, at most 1.8e-6); v then loses its component along ω. A lead
/// screw of 1 mm per turn has h = 1.6e-4 m/rad, far above.
pub const PITCH_ROUNDED: f64 = 2e-6;

/// How far ‖ω‖ (or a prismatic row's ‖v‖) may be from 1: 1e-6, so that axes printed to six
/// decimals (`screwkit table --format csv`) are read back.
pub const UNIT_TOLERANCE: f64 = 1e-6;

/// One joint of a [`ScrewRobot`].
#[derive(Debug, Clone, PartialEq)]
pub struct ScrewJoint {
    /// Joint name (unique, not empty).
    pub name: String,
    /// Its screw axis (ω, v) at home, in the robot's [`ScrewRobot::frame`].
    pub screw: [f64; 6],
    /// (lower, upper) in rad or m; `None` for an unbounded joint. Infinite bounds are allowed;
    /// a rotating joint of pitch 0 is continuous when unbounded, revolute otherwise.
    pub limits: Option<(f64, f64)>,
    /// The joint this one follows, θ = multiplier · q_leader + offset (the leader must be an
    /// independent joint of the same robot, or one of [`ScrewRobot::leaders`]).
    pub mimic: Option<Mimic>,
    /// The kind the description declares (a table's `type`), which the row must agree with:
    /// prismatic (ω = 0), helical, or revolute/continuous (pitch 0; which of the two, the
    /// limits say, except for a mimic joint). `None`: read from the numbers.
    pub kind: Option<JointKind>,
}

/// A robot as a home pose and screw axes: T(q) = e^\[S₁\]θ₁ ⋯ e^\[Sₙ\]θₙ M
/// = M e^\[B₁\]θ₁ ⋯ e^\[Bₙ\]θₙ.
#[derive(Debug, Clone, PartialEq)]
pub struct ScrewRobot {
    /// The robot's name.
    pub name: String,
    /// Where it came from (a file path, or a label such as `<screws>`), for error messages.
    pub source: String,
    /// M, the tip pose at home, row-major 4 × 4: a rigid transform to 1e-3 (max |RᵀR − I|, as
    /// IK targets: typed or printed to four or more decimals), replaced by the nearest one.
    pub home: [f64; 16],
    /// The frame the screws are given in: space (S_i) or body (B_i).
    pub frame: Frame,
    /// The joints, base to tip.
    pub joints: Vec<ScrewJoint>,
    /// Variables that drive mimic joints of the chain without being on it (a gripper finger
    /// that follows the other finger), with their limits: a table of such a chain names them.
    pub leaders: Vec<ScrewLeader>,
}

/// A variable of a [`ScrewRobot`] owned by a joint that is not on its chain.
#[derive(Debug, Clone, PartialEq)]
pub struct ScrewLeader {
    /// The leading joint's name.
    pub name: String,
    /// Its limits (`None`: unbounded).
    pub limits: Option<(f64, f64)>,
}

/// Who owns a variable name: joint k of the chain or leader k.
#[derive(Debug, Clone, Copy)]
enum Owner {
    Joint(usize),
    Leader(usize),
}

/// A row read: its unit screw in the given frame, the same in the space frame, its kind.
#[derive(Debug, Clone, Copy)]
struct Row {
    given: Twist,
    space: Twist,
    kind: JointKind,
}

/// The description read and checked once: M, every name's owner, the rows.
struct Read<'a> {
    m: Se3,
    names: HashMap<&'a str, Owner>,
    rows: Vec<Row>,
}

impl ScrewRobot {
    /// A description from arrays as front ends take them: M row-major, one screw per joint,
    /// `limits` one (lower, upper) per joint (`None`: every joint unbounded), `names` one per
    /// joint (`None`: `joint1`, `joint2`, …). Counts that disagree are an error; everything
    /// else is checked when the chain is built.
    pub fn new(
        source: &str,
        home: [f64; 16],
        screws: Vec<[f64; 6]>,
        frame: Frame,
        limits: Option<Vec<(f64, f64)>>,
        names: Option<Vec<String>>,
    ) -> Result<Self, ModelError> {
        let n = screws.len();
        let count = |what: &str, k: usize| {
            ModelError::new(
                source,
                ErrorKind::Screws(format!("{what} has {k} rows for {n} screw axes")),
            )
        };
        if let Some(l) = &limits {
            if l.len() != n {
                return Err(count("limits", l.len()));
            }
        }
        if let Some(names) = &names {
            if names.len() != n {
                return Err(count("names", names.len()));
            }
        }
        let names = names.unwrap_or_else(|| (1..=n).map(|i| format!("joint{i}")).collect());
        Ok(Self {
            name: "screws".into(),
            source: source.into(),
            home,
            frame,
            joints: screws
                .into_iter()
                .zip(names)
                .enumerate()
                .map(|(i, (screw, name))| ScrewJoint {
                    name,
                    screw,
                    limits: limits.as_ref().map(|l| l[i]),
                    mimic: None,
                    kind: None,
                })
                .collect(),
            leaders: Vec::new(),
        })
    }

    /// The description as JSON, exactly (shortest round-trip numbers; ±∞ limits as `null`):
    /// `{"robot", "frame", "home": [[4 x 4]], "joints": [{"name", "type", "screw": [6],
    /// "lower", "upper", "mimic"}], "leaders"}` (`type` `null` unless declared), which [`crate::table::read_screw_table`] reads back into the same
    /// description (so the same chain, bit for bit).
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::{json, Value};
        let num = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
        let joints: Vec<Value> = self
            .joints
            .iter()
            .map(|j| {
                let (l, u) = j
                    .limits
                    .map_or((Value::Null, Value::Null), |(l, u)| (num(l), num(u)));
                json!({
                    "name": j.name,
                    "type": j.kind.map_or(Value::Null, |k| json!(k.as_str())),
                    "screw": j.screw.to_vec(),
                    "lower": l,
                    "upper": u,
                    "mimic": j.mimic.as_ref().map_or(Value::Null, |m| json!({
                        "leader": m.leader, "multiplier": m.multiplier, "offset": m.offset,
                    })),
                })
            })
            .collect();
        let mut out = json!({
            "robot": self.name,
            "frame": self.frame.as_str(),
            "home": self.home.chunks(4).map(|r| r.to_vec()).collect::<Vec<_>>(),
            "joints": joints,
        });
        if !self.leaders.is_empty() {
            out["leaders"] = self
                .leaders
                .iter()
                .map(|l| {
                    let (lo, up) = l
                        .limits
                        .map_or((Value::Null, Value::Null), |(a, b)| (num(a), num(b)));
                    json!({"name": l.name, "lower": lo, "upper": up})
                })
                .collect();
        }
        out
    }

    fn error(&self, kind: ErrorKind) -> ModelError {
        ModelError::new(self.source.clone(), kind)
    }

    fn screw_error(&self, row: usize, problem: String) -> ModelError {
        self.error(ErrorKind::Screw {
            row,
            joint: self.joints[row].name.clone(),
            problem,
        })
    }

    fn home(&self) -> Result<Se3, ModelError> {
        Se3::from_row_major(&self.home, so3::TARGET_ROTATION_TOLERANCE).map_err(|e| {
            self.error(ErrorKind::Screws(format!(
                "the home pose M is not a rigid transform: {e}"
            )))
        })
    }

    /// Reads row `i`: finite; ‖ω‖ = 1 (revolute or helical) or ω = 0 and ‖v‖ = 1
    /// (prismatic), agreeing with its declared kind (see the module documentation).
    fn row(&self, i: usize) -> Result<(Twist, JointKind), ModelError> {
        let j = &self.joints[i];
        let bad = |p: String| Err(self.screw_error(i, p));
        if !j.screw.iter().all(|x| x.is_finite()) {
            return bad("it holds NaN or infinity".into());
        }
        let t = Twist::try_from_slice(&j.screw).map_err(|e| self.screw_error(i, e.to_string()))?;
        let (wn, vn) = (t.w.norm(), t.v.norm());
        let declared = j.kind;
        if let Some(k) = declared.filter(|k| !k.is_movable()) {
            return bad(format!("a {} joint has no screw axis", k.as_str()));
        }
        if wn == 0.0 {
            if declared.is_some_and(|k| k != JointKind::Prismatic) {
                let k = declared.map_or("", JointKind::as_str);
                return bad(format!("ω = 0 (a translation) for a joint of type {k}"));
            }
            if (vn - 1.0).abs() > UNIT_TOLERANCE {
                return bad(format!(
                    "ω = 0 and ‖v‖ = {vn}: a prismatic joint's v is a unit vector (a screw \
                     axis has ‖ω‖ = 1, or ω = 0 and ‖v‖ = 1)"
                ));
            }
            return Ok((
                Twist::new(Vector3::zeros(), t.v * unit_scale(vn)),
                JointKind::Prismatic,
            ));
        }
        if declared == Some(JointKind::Prismatic) {
            return bad(format!("‖ω‖ = {wn} for a prismatic joint (its ω is 0)"));
        }
        if (wn - 1.0).abs() > UNIT_TOLERANCE {
            return bad(format!(
                "‖ω‖ = {wn}: a screw axis has ‖ω‖ = 1 (revolute or helical), or ω = 0 and \
                 ‖v‖ = 1 (prismatic)"
            ));
        }
        let s = t * unit_scale(wn);
        let h = s.w.dot(&s.v);
        let scale = s.v.norm().max(1.0);
        let revolute = match declared {
            Some(JointKind::Helical) => false,
            Some(k) if h.abs() > PITCH_ROUNDED * scale => {
                return bad(format!(
                    "pitch ω · v = {h} m/rad for a joint of type {} (pitch 0; a helical \
                     joint is type helical)",
                    k.as_str()
                ));
            }
            Some(_) => true,
            None => h.abs() <= PITCH_ROUNDED * scale,
        };
        if !revolute {
            return Ok((s, JointKind::Helical));
        }
        // Rounding of v = −ω × q is kept bit for bit; more (six printed decimals, typed
        // values) is removed: v ⊥ ω.
        let screw = if h.abs() <= PITCH_ZERO * scale {
            s
        } else {
            Twist::new(s.w, s.v - s.w * h)
        };
        // Revolute or continuous: an independent joint's limits say (a revolute joint without
        // limits would be neither wrapped nor bounded); a mimic joint's limits are its
        // leader's (as tables print them), so its declared word stands.
        let kind = match declared {
            Some(k @ (JointKind::Revolute | JointKind::Continuous)) if j.mimic.is_some() => k,
            _ if j.limits.is_none_or(|(l, u)| is_unbounded(l, u)) => JointKind::Continuous,
            _ => JointKind::Revolute,
        };
        Ok((screw, kind))
    }

    /// Checks names, limits, mimic joints and leaders, and reads every row (the space screw
    /// of a body-frame row by the adjoint: S = \[Ad_M\] B).
    fn read(&self) -> Result<Read<'_>, ModelError> {
        let m = self.home()?;
        if self.joints.is_empty() {
            return Err(self.error(ErrorKind::Screws("no joints: S has no rows".into())));
        }
        let names = self.names()?;
        let check_limits = |name: &str, limits: Option<(f64, f64)>| match limits {
            Some((l, u)) if l.is_nan() || u.is_nan() => Err(self.error(ErrorKind::NonFinite {
                joint: name.to_string(),
                what: "limit".into(),
            })),
            Some((l, u)) if l > u => Err(self.error(ErrorKind::LimitOrder {
                joint: name.to_string(),
                lower: l,
                upper: u,
            })),
            _ => Ok(()),
        };
        for l in &self.leaders {
            check_limits(&l.name, l.limits)?;
        }
        for j in &self.joints {
            check_limits(&j.name, j.limits)?;
            if let Some(mimic) = &j.mimic {
                let problem = |p: String| {
                    self.error(ErrorKind::Mimic {
                        joint: j.name.clone(),
                        problem: p,
                    })
                };
                match names.get(mimic.leader.as_str()) {
                    None => {
                        return Err(problem(format!(
                            "joint \"{}\", which is not defined",
                            mimic.leader
                        )))
                    }
                    Some(Owner::Joint(k)) if self.joints[*k].mimic.is_some() => {
                        return Err(problem(format!(
                            "joint \"{}\", which follows another joint itself (name the \
                             independent one)",
                            mimic.leader
                        )))
                    }
                    _ => {}
                }
                if !(mimic.multiplier.is_finite() && mimic.offset.is_finite()) {
                    return Err(problem("with a non-finite multiplier or offset".into()));
                }
            }
        }
        let rows = (0..self.joints.len())
            .map(|i| {
                let (given, kind) = self.row(i)?;
                let space = match self.frame {
                    Frame::Space => given,
                    Frame::Body => m.adjoint_apply(&given),
                };
                Ok(Row { given, space, kind })
            })
            .collect::<Result<Vec<_>, ModelError>>()?;
        Ok(Read { m, names, rows })
    }

    /// Every joint's and leader's name, each once (a repeated or empty one is an error).
    fn names(&self) -> Result<HashMap<&str, Owner>, ModelError> {
        let mut names = HashMap::with_capacity(self.joints.len() + self.leaders.len());
        let owners = self
            .joints
            .iter()
            .enumerate()
            .map(|(k, j)| (j.name.as_str(), Owner::Joint(k)));
        let leaders = self
            .leaders
            .iter()
            .enumerate()
            .map(|(k, l)| (l.name.as_str(), Owner::Leader(k)));
        for (name, owner) in owners.chain(leaders) {
            match owner {
                Owner::Joint(k) if name.is_empty() => {
                    return Err(self.screw_error(k, "the joint has an empty name".into()))
                }
                Owner::Leader(k) if name.is_empty() => {
                    return Err(
                        self.error(ErrorKind::Screws(format!("leader {k} has an empty name")))
                    )
                }
                _ => {}
            }
            if names.insert(name, owner).is_some() {
                return Err(self.error(ErrorKind::Duplicate {
                    what: "joint",
                    name: name.to_string(),
                }));
            }
        }
        Ok(names)
    }

    /// The joints' frames at home (see the module documentation): unrotated, at the point of
    /// each space axis nearest the previous joint's point.
    fn joint_points(rows: &[Row]) -> Vec<Vector3<f64>> {
        let mut prev = Vector3::zeros();
        rows.iter()
            .map(|r| {
                let s = &r.space;
                if r.kind != JointKind::Prismatic {
                    // The axis: the point ω × v (nearest the origin; ‖ω‖ = 1) plus any
                    // multiple of ω; the one nearest `prev`.
                    let p0 = s.w.cross(&s.v);
                    prev = p0 + s.w * s.w.dot(&(prev - p0));
                }
                prev
            })
            .collect()
    }

    /// The variables in order of first appearance along the chain (a mimic joint's leader
    /// where the joint comes first, as for a URDF chain) and every joint's drive. A leader off
    /// the chain takes its first follower's kind.
    fn variables(&self, read: &Read<'_>) -> (Vec<Variable>, Vec<Drive>) {
        let mut variables: Vec<Variable> = Vec::new();
        let mut index: HashMap<&str, usize> = HashMap::new();
        let mut drives = Vec::with_capacity(read.rows.len());
        for (j, r) in self.joints.iter().zip(&read.rows) {
            let (owner, multiplier, offset) = match &j.mimic {
                None => (j.name.as_str(), 1.0, 0.0),
                Some(m) => (m.leader.as_str(), m.multiplier, m.offset),
            };
            let variable = *index.entry(owner).or_insert_with(|| {
                let (limits, kind) = match read.names[owner] {
                    Owner::Joint(k) => (self.joints[k].limits, read.rows[k].kind),
                    Owner::Leader(k) => (self.leaders[k].limits, r.kind),
                };
                let (lower, upper) = limits.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
                variables.push(Variable {
                    name: owner.to_string(),
                    kind,
                    lower,
                    upper,
                    velocity: None,
                    effort: None,
                });
                variables.len() - 1
            });
            drives.push(Drive {
                variable,
                multiplier,
                offset,
            });
        }
        (variables, drives)
    }

    /// The serial chain base → tip with the screws as given (normalised), the other frame's
    /// screws by the adjoint (B_i = \[Ad_{M⁻¹}\] S_i, or S_i = \[Ad_M\] B_i), and link poses at
    /// the joints' points. Its base link is `base`, its tip `tip`.
    pub fn chain(&self) -> Result<Chain, ModelError> {
        let read = self.read()?;
        let (m, rows) = (read.m, &read.rows);
        let points = Self::joint_points(rows);
        let (variables, drives) = self.variables(&read);
        let mut links = vec![ChainLink {
            name: "base".into(),
            home: Se3::identity(),
            joints_before: 0,
        }];
        let mut joints = Vec::with_capacity(rows.len());
        for (i, (j, r)) in self.joints.iter().zip(rows).enumerate() {
            let b = match self.frame {
                Frame::Space => m.adjoint_inverse_apply(&r.given),
                Frame::Body => r.given,
            };
            let home = Se3::from_translation(points[i]);
            joints.push(ChainJoint {
                name: j.name.clone(),
                kind: r.kind,
                s_space: ScrewAxis::from_unit_twist_unchecked(r.space),
                b_body: ScrewAxis::from_unit_twist_unchecked(b),
                drive: drives[i],
                home,
            });
            links.push(ChainLink {
                name: link_name(&j.name),
                home,
                joints_before: i + 1,
            });
        }
        links.push(ChainLink {
            name: "tip".into(),
            home: m,
            joints_before: rows.len(),
        });
        Ok(Chain {
            robot: self.name.clone(),
            source: self.source.clone(),
            base: "base".into(),
            tip: "tip".into(),
            joints,
            variables,
            home: m,
            links,
        })
    }

    /// The same robot as a [`Tree`] (links `base`, `<joint>_link` …, `tip`; unrotated joint
    /// frames at the joints' points, a helical joint with its pitch, a fixed joint to `tip`
    /// at M), for the algorithms that take a whole robot. Its screws equal the chain's to
    /// rounding.
    pub fn tree(&self) -> Result<Tree, ModelError> {
        let read = self.read()?;
        let (m, rows) = (read.m, &read.rows);
        let points = Self::joint_points(rows);
        let mut links = vec!["base".to_string()];
        links.extend(self.joints.iter().map(|j| link_name(&j.name)));
        links.push("tip".into());
        let mut specs = Vec::with_capacity(rows.len() + self.leaders.len() + 1);
        let mut prev = Vector3::zeros();
        for (i, j) in self.joints.iter().enumerate() {
            let spec = tree_joint(&j.name, &rows[i], points[i] - prev, j.limits);
            specs.push((
                TreeJointSpec {
                    mimic: j.mimic.clone(),
                    ..spec
                },
                links[i].clone(),
                links[i + 1].clone(),
            ));
            prev = points[i];
        }
        // A leader off the chain: a branch of its own from the base (the table does not say
        // where it is), moving a link of its name the way its first follower moves.
        let mut first_follower: HashMap<&str, usize> = HashMap::new();
        for (i, j) in self.joints.iter().enumerate() {
            if let Some(m) = &j.mimic {
                first_follower.entry(m.leader.as_str()).or_insert(i);
            }
        }
        let mut leader_links = Vec::new();
        for l in &self.leaders {
            let Some(&i) = first_follower.get(l.name.as_str()) else {
                continue;
            };
            let link = link_name(&l.name);
            specs.push((
                tree_joint(&l.name, &rows[i], points[i], l.limits),
                "base".into(),
                link.clone(),
            ));
            leader_links.push(link);
        }
        let mut fixed = "tip_fixed".to_string();
        while read.names.contains_key(fixed.as_str()) {
            fixed.push('_');
        }
        let [x, y, z, w] = m.quaternion();
        specs.push((
            TreeJointSpec {
                name: fixed,
                kind: JointKind::Fixed,
                origin_xyz: (m.translation() - prev).into(),
                origin_rpy: m.rpy(),
                origin_quat: Some([w, x, y, z]),
                axis: [1.0, 0.0, 0.0],
                limit: None,
                mimic: None,
                pitch: 0.0,
                dynamics: Default::default(),
            },
            links[rows.len()].clone(),
            "tip".into(),
        ));
        links.extend(leader_links);
        Tree::new(self.name.clone(), self.source.clone(), links, specs)
    }
}

/// The tree joint of row `r` whose unrotated frame sits at `origin` in its parent link: axis
/// ω (v for a prismatic joint), the pitch ω · v of a helical joint; the limits, ±∞ when
/// unbounded, except a continuous joint's (URDF gives it none); no mimic.
fn tree_joint(
    name: &str,
    r: &Row,
    origin: Vector3<f64>,
    limits: Option<(f64, f64)>,
) -> TreeJointSpec {
    let (s, kind) = (&r.space, r.kind);
    let (lower, upper) = limits.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
    TreeJointSpec {
        name: name.to_string(),
        kind,
        origin_xyz: origin.into(),
        origin_rpy: [0.0; 3],
        origin_quat: None,
        axis: if kind == JointKind::Prismatic {
            s.v
        } else {
            s.w
        }
        .into(),
        limit: (kind != JointKind::Continuous).then_some(Limit {
            lower,
            upper,
            velocity: None,
            effort: None,
        }),
        mimic: None,
        pitch: if kind == JointKind::Helical {
            s.w.dot(&s.v)
        } else {
            0.0
        },
        dynamics: Default::default(),
    }
}

/// The factor that normalises a vector of norm `n` (≈ 1): 1/n, or exactly 1 when n is within
/// 4 ε of 1 — a row that is already unit to rounding (a table screwkit printed) is kept bit
/// for bit, so reading a table back gives the same robot.
fn unit_scale(n: f64) -> f64 {
    if (n - 1.0).abs() <= 4.0 * f64::EPSILON {
        1.0
    } else {
        1.0 / n
    }
}

fn link_name(joint: &str) -> String {
    format!("{joint}_link")
}
