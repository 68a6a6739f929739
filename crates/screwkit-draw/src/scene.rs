//! What a picture shows, in 3D, computed by the solver: every link's pose (all-link FK), every
//! joint's screw axis at q (`jacobian::joint_screws`, the columns of J_s(q) joint by joint) and
//! the lines and marks derived from them. No kinematics here: only where to put the ink.

use nalgebra::Vector3;
use screwkit_lie::{Se3, Twist};
use screwkit_model::{Chain, JointKind};
use screwkit_solve::{fk, jacobian, Kinematics, SolveError, Workspace};

/// A link on the chain at q.
#[derive(Debug, Clone)]
pub struct LinkMark {
    /// Link name.
    pub name: String,
    /// Its pose in the base frame.
    pub pose: Se3,
}

/// A moving joint at q and its screw axis.
#[derive(Debug, Clone)]
pub struct JointMark {
    /// 1-based position along the chain (the label drawn next to its axis).
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

/// Everything a picture of a chain at q shows.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The robot's name.
    pub robot: String,
    /// Base link (the space frame, drawn as a triad at the origin).
    pub base: String,
    /// Tip link (its frame drawn as a triad).
    pub tip: String,
    /// The joint values drawn.
    pub q: Vec<f64>,
    /// The chain's links base → tip.
    pub links: Vec<LinkMark>,
    /// The chain's moving joints base → tip.
    pub joints: Vec<JointMark>,
    /// The characteristic size of the picture (m): the diagonal of the box around the link
    /// origins (at least 1 mm), from which axis and triad lengths are taken.
    pub size: f64,
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
            .map(|(l, pose)| LinkMark {
                name: l.name.clone(),
                pose: *pose,
            })
            .collect();
        let (lo, hi) = links.iter().fold(
            (
                Vector3::repeat(f64::INFINITY),
                Vector3::repeat(f64::NEG_INFINITY),
            ),
            |(lo, hi), l| (lo.inf(l.pose.translation()), hi.sup(l.pose.translation())),
        );
        let size = (hi - lo).norm().max(1e-3);
        let axis_length = 0.18 * size;
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
                let (pitch, line) = if joint.kind == JointKind::Prismatic {
                    let d = s.v.normalize();
                    (None, [origin, origin + d * axis_length])
                } else {
                    let n2 = s.w.norm_squared();
                    let w = s.w / n2.sqrt();
                    // The point of the axis closest to the base origin is ω × v / ‖ω‖²; slide
                    // it along the axis to the point closest to the joint origin.
                    let p0 = s.w.cross(&s.v) / n2;
                    let p = p0 + w * w.dot(&(origin - p0));
                    (
                        Some(s.w.dot(&s.v) / n2),
                        [p - w * axis_length, p + w * axis_length],
                    )
                };
                JointMark {
                    index: j + 1,
                    name: joint.name.clone(),
                    kind: joint.kind,
                    origin,
                    screw: *s,
                    pitch,
                    line,
                }
            })
            .collect();
        Ok(Self {
            robot: chain.robot.clone(),
            base: chain.base.clone(),
            tip: chain.tip.clone(),
            q: q.to_vec(),
            links,
            joints,
            size,
        })
    }

    /// The tip link's pose.
    pub fn tip_pose(&self) -> Se3 {
        self.links.last().map_or_else(Se3::identity, |l| l.pose)
    }
}
