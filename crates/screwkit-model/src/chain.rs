//! The serial chain base → tip with its screw axes: the product-of-exponentials model.

use screwkit_lie::{Frame, ScrewAxis, Se3};

use crate::error::{ErrorKind, ModelError};
use crate::tree::{JointKind, Tree, TreeJoint};

/// An independent joint variable q_k of the chain (the chain's degrees of freedom).
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// The name of the joint that owns this variable.
    pub name: String,
    /// Revolute, continuous or prismatic.
    pub kind: JointKind,
    /// Lower position limit (−∞ for continuous joints).
    pub lower: f64,
    /// Upper position limit (+∞ for continuous joints).
    pub upper: f64,
    /// Velocity limit, if the URDF gives one.
    pub velocity: Option<f64>,
    /// Effort limit, if the URDF gives one.
    pub effort: Option<f64>,
}

/// How a chain joint is driven by the chain's variables q: θ = multiplier · q\[variable\] +
/// offset — (1, 0) for an ordinary joint, the `<mimic>` values (composed along a chain of mimic
/// joints) for a mimic joint. [`Drive::theta`] is the one place this rule is evaluated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drive {
    /// Index into [`Chain::variables`] of the variable driving the joint.
    pub variable: usize,
    /// θ = multiplier · q + offset.
    pub multiplier: f64,
    /// θ = multiplier · q + offset.
    pub offset: f64,
}

impl Drive {
    /// An ordinary joint owning variable `variable`: θ = q\[variable\].
    pub fn independent(variable: usize) -> Self {
        Self {
            variable,
            multiplier: 1.0,
            offset: 0.0,
        }
    }

    /// True when a whole turn of q turns the joint whole turns (a finite integer multiplier).
    pub fn whole_turns(&self) -> bool {
        self.multiplier.is_finite() && self.multiplier.fract() == 0.0
    }

    /// θ = multiplier · q\[variable\] + offset (panics if q is too short).
    #[inline(always)]
    pub fn theta(&self, q: &[f64]) -> f64 {
        self.multiplier * q[self.variable] + self.offset
    }
}

/// A movable joint on the chain, with its screw axes at the home configuration.
///
/// Its position is θ = [`ChainJoint::drive`]`.theta(q)`.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainJoint {
    /// Joint name.
    pub name: String,
    /// Revolute, continuous or prismatic.
    pub kind: JointKind,
    /// S_i in the base (space) frame at θ = 0: (ω, −ω × p) for a revolute joint whose frame
    /// is at p with axis ω = R a; (0, R a) for a prismatic joint.
    pub s_space: ScrewAxis,
    /// B_i = \[Ad_{M⁻¹}\] S_i, the same axis in the tip (body) frame at home.
    pub b_body: ScrewAxis,
    /// Which variable drives the joint, and how (θ = multiplier · q + offset).
    pub drive: Drive,
    /// The joint frame in the base frame at home.
    pub home: Se3,
}

impl ChainJoint {
    /// The joint's screw axis at home in `frame`: S_i (space) or B_i (body).
    pub fn screw(&self, frame: Frame) -> &ScrewAxis {
        match frame {
            Frame::Space => &self.s_space,
            Frame::Body => &self.b_body,
        }
    }
}

/// A link on the chain with its pose at home.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainLink {
    /// Link name.
    pub name: String,
    /// Pose of the link frame in the base frame at home (all θ = 0).
    pub home: Se3,
    /// How many chain joints (of [`Chain::joints`]) lie between the base and this link: the
    /// link's pose is e^\[S₁\]θ₁ ⋯ e^\[S_k\]θ_k · home with k = `joints_before`.
    pub joints_before: usize,
}

/// The serial chain from a base link to a tip link: T(q) = e^\[S₁\]θ₁ ⋯ e^\[Sₙ\]θₙ M.
///
/// Space frame = the base link frame; body frame = the tip link frame. Fixed joints are
/// folded into M and into the joint frames. A mimic joint keeps its own screw axis and is
/// driven by its leader's variable: θ_j = m q_leader + o, so its Jacobian column folds into
/// the leader's as m · J_j. The chain's degrees of freedom are its [`Chain::variables`].
#[derive(Debug, Clone, PartialEq)]
pub struct Chain {
    /// The robot's name.
    pub robot: String,
    /// The file it came from.
    pub source: String,
    /// Base link name.
    pub base: String,
    /// Tip link name.
    pub tip: String,
    /// The movable joints base → tip.
    pub joints: Vec<ChainJoint>,
    /// The independent variables, in order of first appearance along the chain.
    pub variables: Vec<Variable>,
    /// M: the tip pose in the base frame at home (all θ = 0).
    pub home: Se3,
    /// Every link on the path, base first, tip last.
    pub links: Vec<ChainLink>,
}

impl Chain {
    /// The same chain with a tool frame T_tool fixed to the tip link (a TCP offset): M' = M
    /// T_tool, B'_i = \[Ad_{M'⁻¹}\] S_i, and a last link `TIP+tool` at M'. The space screws
    /// and the variables do not change.
    pub fn with_tool(&self, tool: &Se3) -> Chain {
        let mut c = self.clone();
        c.home = self.home.compose(tool);
        for j in &mut c.joints {
            j.b_body = ScrewAxis::from_unit_twist_unchecked(
                c.home.adjoint_inverse_apply(j.s_space.twist()),
            );
        }
        c.tip = format!("{}+tool", self.tip);
        c.links.push(ChainLink {
            name: c.tip.clone(),
            home: c.home,
            joints_before: c.joints.len(),
        });
        c
    }

    /// Builds the chain from `base` (default: the root) to `tip` (default: the single leaf
    /// below the base).
    pub fn from_tree(
        tree: &Tree,
        base: Option<&str>,
        tip: Option<&str>,
    ) -> Result<Chain, ModelError> {
        let (b, t) = tree.default_ends(base, tip)?;
        let path = tree.path(b, t)?;
        build(tree, b, t, &path).map_err(|k| ModelError::new(tree.source.clone(), k))
    }

    /// The number of independent variables (degrees of freedom).
    pub fn dof(&self) -> usize {
        self.variables.len()
    }

    /// The names of the variables, in order.
    pub fn variable_names(&self) -> Vec<&str> {
        self.variables.iter().map(|v| v.name.as_str()).collect()
    }

    /// True when some joint is driven by another's variable (mimic), so that
    /// `joints.len() != dof()` or multipliers/offsets are not (1, 0).
    pub fn has_mimic(&self) -> bool {
        self.joints.len() != self.variables.len()
            || self
                .joints
                .iter()
                .enumerate()
                .any(|(i, j)| j.drive != Drive::independent(i))
    }
}

fn build(tree: &Tree, base: usize, tip: usize, path: &[usize]) -> Result<Chain, ErrorKind> {
    let mut t = Se3::identity();
    let mut specs = Vec::new();
    let mut links = vec![ChainLink {
        name: tree.links[base].clone(),
        home: t,
        joints_before: 0,
    }];
    for &j in path {
        let joint = &tree.joints[j];
        t = t * joint.origin()?;
        match joint.kind {
            JointKind::Fixed => {}
            k if k.is_movable() => {
                specs.push((j, joint.screw_at(&t)?, t));
            }
            k => {
                return Err(ErrorKind::UnsupportedJoint {
                    joint: joint.name.clone(),
                    kind: k.as_str().into(),
                })
            }
        }
        links.push(ChainLink {
            name: tree.links[joint.child].clone(),
            home: t,
            joints_before: specs.len(),
        });
    }
    let m = t;
    let mut variables: Vec<Variable> = Vec::new();
    // Each independent joint's variable, by joint index.
    let mut owners: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
    let mut joints = Vec::with_capacity(specs.len());
    let mut mimics = MimicResolver::new(tree);
    for (j, s, home) in specs {
        let joint = &tree.joints[j];
        let (leader, multiplier, offset) = mimics.resolve(j)?;
        let variable = match owners.get(&leader) {
            Some(&v) => v,
            None => {
                variables.push(variable_of(&tree.joints[leader])?);
                owners.insert(leader, variables.len() - 1);
                variables.len() - 1
            }
        };
        joints.push(ChainJoint {
            name: joint.name.clone(),
            kind: joint.kind,
            b_body: ScrewAxis::from_unit_twist_unchecked(m.adjoint_inverse_apply(s.twist())),
            s_space: s,
            drive: Drive {
                variable,
                multiplier,
                offset,
            },
            home,
        });
    }
    Ok(Chain {
        robot: tree.name.clone(),
        source: tree.source.clone(),
        base: tree.links[base].clone(),
        tip: tree.links[tip].clone(),
        joints,
        variables,
        home: m,
        links,
    })
}

/// [`resolve_mimic`] for every joint of a tree, each link of a mimic chain followed once:
/// a joint's drive is its leader's composed with its own rule (30,000 chained mimics, each
/// resolved from scratch, took minutes).
pub(crate) struct MimicResolver<'t> {
    tree: &'t Tree,
    memo: Vec<Option<(usize, f64, f64)>>,
}

impl<'t> MimicResolver<'t> {
    pub(crate) fn new(tree: &'t Tree) -> Self {
        Self {
            tree,
            memo: vec![None; tree.joints.len()],
        }
    }

    /// Joint `j`'s independent joint and rule: θ_j = m q_leader + o.
    pub(crate) fn resolve(&mut self, j: usize) -> Result<(usize, f64, f64), ErrorKind> {
        let tree = self.tree;
        let mut path = Vec::new();
        let mut cur = j;
        let mut base = loop {
            if let Some(r) = self.memo[cur] {
                break r;
            }
            let Some(mimic) = &tree.joints[cur].mimic else {
                break (cur, 1.0, 0.0);
            };
            let valid = tree.joint(&mimic.leader).filter(|&l| {
                tree.joints[l].kind.is_movable()
                    && mimic.multiplier.is_finite()
                    && mimic.offset.is_finite()
            });
            match valid {
                Some(leader) if path.len() <= tree.joints.len() => {
                    path.push(cur);
                    cur = leader;
                }
                // An undefined or fixed leader, a non-finite rule or a cycle: the message of
                // the joint asked about, by the one-joint walk.
                _ => return resolve_mimic(tree, j),
            }
        };
        for &p in path.iter().rev() {
            let Some(mimic) = &tree.joints[p].mimic else {
                unreachable!("every joint on the path mimics the next")
            };
            // θ_p = m_p θ_next + o_p, θ_next = m q + o.
            base = (
                base.0,
                mimic.multiplier * base.1,
                mimic.multiplier * base.2 + mimic.offset,
            );
            self.memo[p] = Some(base);
        }
        self.memo[j] = Some(base);
        Ok(base)
    }
}

/// Follows `<mimic>` links to the independent joint: θ_j = m q_leader + o.
pub(crate) fn resolve_mimic(tree: &Tree, j: usize) -> Result<(usize, f64, f64), ErrorKind> {
    let name = &tree.joints[j].name;
    let (mut cur, mut m, mut o) = (j, 1.0, 0.0);
    let mut steps = 0;
    while let Some(mimic) = &tree.joints[cur].mimic {
        let problem = |p: String| ErrorKind::Mimic {
            joint: name.clone(),
            problem: p,
        };
        let leader = tree
            .joint(&mimic.leader)
            .ok_or_else(|| problem(format!("joint \"{}\", which is not defined", mimic.leader)))?;
        if !tree.joints[leader].kind.is_movable() {
            return Err(problem(format!(
                "joint \"{}\", which is {} (not movable)",
                mimic.leader,
                tree.joints[leader].kind.as_str()
            )));
        }
        if !(mimic.multiplier.is_finite() && mimic.offset.is_finite()) {
            return Err(problem("with a non-finite multiplier or offset".into()));
        }
        // θ_cur = m_c θ_leader + o_c, and θ_j = m θ_cur + o.
        o += m * mimic.offset;
        m *= mimic.multiplier;
        cur = leader;
        steps += 1;
        if steps > tree.joints.len() {
            return Err(problem("in a cycle of mimic joints".into()));
        }
    }
    Ok((cur, m, o))
}

/// The variable of an independent joint, with its limits checked.
pub(crate) fn variable_of(joint: &TreeJoint) -> Result<Variable, ErrorKind> {
    let (lower, upper) = match joint.kind {
        JointKind::Continuous => (f64::NEG_INFINITY, f64::INFINITY),
        _ => {
            let l = joint
                .limit
                .ok_or_else(|| ErrorKind::MissingLimit(joint.name.clone()))?;
            if l.lower.is_nan() || l.upper.is_nan() {
                return Err(ErrorKind::NonFinite {
                    joint: joint.name.clone(),
                    what: "<limit lower/upper>".into(),
                });
            }
            if l.lower > l.upper {
                return Err(ErrorKind::LimitOrder {
                    joint: joint.name.clone(),
                    lower: l.lower,
                    upper: l.upper,
                });
            }
            (l.lower, l.upper)
        }
    };
    Ok(Variable {
        name: joint.name.clone(),
        kind: joint.kind,
        lower,
        upper,
        velocity: joint.limit.and_then(|l| l.velocity),
        effort: joint.limit.and_then(|l| l.effort),
    })
}
