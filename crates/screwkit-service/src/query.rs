//! **The query floor**: what a front end asks about — the chain's tip, a frame of the whole
//! tree, or a frame seen from another — is resolved once ([`About::resolve`], the floor's
//! rule of [`crate::whole::wants_tree`]), and each query of it, one configuration or N, is
//! routed here: chain or tree, single call or the library's batch. The single calls run in
//! the calling thread's kept workspace (`Workspace::local`, `TreeWorkspace::local`), so a
//! front end keeps no scratch for them.

use screwkit_lie::Se3;
use screwkit_solve::batch::{fk_batch, jacobian_batch, write_jacobian};
use screwkit_solve::tree::{batch as tree_batch, fk as tree_fk, jacobian as tree_jacobian};
use screwkit_solve::{
    JacobianKind, Kinematics, SolveError, TreeKinematics, TreeWorkspace, Workspace,
};

use crate::error::{Error, Result};
use crate::load::Robot;

/// What a query is about (module documentation).
#[derive(Debug, Clone, Copy)]
pub enum About<'k> {
    /// The chain's tip (with its tool frame); q the chain's joint values.
    Tip(&'k Kinematics),
    /// A frame of the whole tree, in the root link's frame (the world with a floating base);
    /// q the tree's configuration.
    Frame(&'k TreeKinematics, usize),
    /// Frame `.1` seen from frame `.2` (T_B⁻¹ T_A) in the whole tree.
    Relative(&'k TreeKinematics, usize, usize),
}

impl<'k> About<'k> {
    /// What a request naming `link` (and `relative_to`) is about: the chain's tip when it names
    /// neither and the chain answers ([`crate::whole::wants_tree`]); else that frame of `tree`
    /// (the whole tree the front end holds, frames it added included). A tree request without
    /// `link` is an error saying to name one (option `link`).
    pub fn resolve(
        robot: &'k Robot,
        tree: Option<&'k TreeKinematics>,
        link: Option<&str>,
        relative_to: Option<&str>,
    ) -> Result<About<'k>> {
        let names = link.is_some() || relative_to.is_some();
        if !crate::whole::wants_tree(robot, names) {
            return Ok(About::Tip(robot.kin()?));
        }
        let tree = match tree {
            Some(t) => t,
            None => robot.whole()?,
        };
        let Some(link) = link else {
            return Err(Error::option(
                "link",
                "this robot is a whole tree (no chain: several leaves, or a floating base): \
                 name the frame, one of the frame_names",
            ));
        };
        let a = tree.frame(link)?;
        Ok(match relative_to {
            None => About::Frame(tree, a),
            Some(b) => About::Relative(tree, a, tree.frame(b)?),
        })
    }

    /// True for a frame of the whole tree.
    pub fn is_tree(&self) -> bool {
        !matches!(self, About::Tip(_))
    }

    /// The length of the q its queries take (the chain's dof, or the tree's nq).
    pub fn q_len(&self) -> usize {
        match self {
            About::Tip(k) => k.dof(),
            About::Frame(t, _) | About::Relative(t, _, _) => t.nq(),
        }
    }

    /// The names of q's entries (the chain's joints, or the tree's `q_names`).
    pub fn q_names(&self) -> &'k [String] {
        match *self {
            About::Tip(k) => k.names(),
            About::Frame(t, _) | About::Relative(t, _, _) => t.q_names(),
        }
    }

    /// The Jacobian's column count (the chain's dof, or the tree's nv).
    pub fn columns(&self) -> usize {
        match self {
            About::Tip(k) => k.dof(),
            About::Frame(t, _) | About::Relative(t, _, _) => t.nv(),
        }
    }

    /// Its pose at q. Checks q.
    pub fn pose(&self, q: &[f64]) -> Result<Se3, SolveError> {
        match *self {
            About::Tip(k) => Workspace::local(k, |ws| screwkit_solve::fk::fk(k, ws, q)),
            About::Frame(t, a) => TreeWorkspace::local(t, |ws| tree_fk::fk_frame(t, ws, q, a)),
            About::Relative(t, a, b) => {
                TreeWorkspace::local(t, |ws| tree_fk::relative_pose(t, ws, q, a, b))
            }
        }
    }

    /// Its pose and Jacobian of `kind` at q, the Jacobian written row-major into `out`
    /// (6 × [`About::columns`]). Checks q.
    pub fn pose_jacobian(
        &self,
        kind: JacobianKind,
        q: &[f64],
        out: &mut [f64],
    ) -> Result<Se3, SolveError> {
        let write = |pj: screwkit_solve::jacobian::PoseJacobian<'_>, out: &mut [f64]| {
            write_jacobian(pj.jacobian, out);
            pj.pose
        };
        match *self {
            About::Tip(k) => Workspace::local(k, |ws| {
                Ok(write(
                    screwkit_solve::jacobian::fk_jacobian(k, ws, q, kind)?,
                    out,
                ))
            }),
            About::Frame(t, a) => TreeWorkspace::local(t, |ws| {
                Ok(write(
                    tree_jacobian::frame_pose_jacobian(t, ws, q, a, kind)?,
                    out,
                ))
            }),
            About::Relative(t, a, b) => TreeWorkspace::local(t, |ws| {
                Ok(write(
                    tree_jacobian::relative_jacobian(t, ws, q, a, b, kind)?,
                    out,
                ))
            }),
        }
    }

    /// Its poses at N configurations (`qs`: N × [`About::q_len`]) into `out` (N × 16,
    /// row-major), through the library's batch; each row as the single call.
    pub fn poses(&self, qs: &[f64], out: &mut [f64]) -> Result<(), SolveError> {
        match *self {
            About::Tip(k) => fk_batch(k, qs, out),
            About::Frame(t, a) => tree_batch::fk_frame_batch(t, a, qs, out),
            About::Relative(t, a, b) => tree_batch::relative_pose_batch(t, (a, b), qs, out),
        }
    }

    /// Its Jacobians of `kind` at N configurations into `out` (N × 6 × [`About::columns`]),
    /// and its poses into `poses` (N × 16) when given, from the same pass, through the
    /// library's batch; each row as the single call.
    pub fn jacobians(
        &self,
        kind: JacobianKind,
        qs: &[f64],
        out: &mut [f64],
        poses: Option<&mut [f64]>,
    ) -> Result<(), SolveError> {
        if self.columns() == 0 {
            // No columns: N empty Jacobians (nor can the flat batch tell N rows from no q
            // values); the poses are the batch's.
            return match poses {
                Some(p) => self.poses(qs, p),
                None => Ok(()),
            };
        }
        match *self {
            About::Tip(k) => jacobian_batch(k, qs, kind, out, poses),
            About::Frame(t, a) => tree_batch::frame_jacobian_batch(t, a, kind, qs, out, poses),
            About::Relative(t, a, b) => {
                tree_batch::relative_jacobian_batch(t, (a, b), kind, qs, out, poses)
            }
        }
    }

    /// An error unless q is one configuration of it (length, finite values).
    pub fn check_q(&self, q: &[f64]) -> Result<(), SolveError> {
        match self {
            About::Tip(k) => k.check_q(q),
            About::Frame(t, _) | About::Relative(t, _, _) => t.check_q(q).map(|_| ()),
        }
    }

    /// The names of the Jacobian's columns (the chain's joints, or the tree's `v_names`).
    pub fn column_names(&self) -> &'k [String] {
        match *self {
            About::Tip(k) => k.names(),
            About::Frame(t, _) | About::Relative(t, _, _) => t.v_names(),
        }
    }
}

/// The configuration space of a robot's calls that name no frame: its chain's, or the whole
/// tree's when the floor's rule says the tree answers ([`crate::whole::wants_tree`]).
#[derive(Debug, Clone, Copy)]
pub enum Space<'k> {
    /// The chain `base → tip`: q its joint values.
    Chain(&'k Kinematics),
    /// The whole tree: q its configuration (`q_names`), v its velocity (`v_names`).
    Tree(&'k TreeKinematics),
}

impl<'k> Space<'k> {
    /// The space of `robot` (`tree`: the front end's whole tree, frames it added included).
    pub fn of(robot: &'k Robot, tree: Option<&'k TreeKinematics>) -> Result<Space<'k>> {
        if crate::whole::wants_tree(robot, false) {
            Ok(Space::Tree(match tree {
                Some(t) => t,
                None => robot.whole()?,
            }))
        } else {
            Ok(Space::Chain(robot.kin()?))
        }
    }

    /// Degrees of freedom: the chain's q length, or the tree's v length (nv).
    pub fn dof(&self) -> usize {
        match self {
            Space::Chain(k) => k.dof(),
            Space::Tree(t) => t.nv(),
        }
    }

    /// The joint variables: the chain's joints of q, or the tree's variables (file order).
    pub fn joint_names(&self) -> Vec<String> {
        match self {
            Space::Chain(k) => k.names().to_vec(),
            Space::Tree(t) => t.model().variables.iter().map(|v| v.name.clone()).collect(),
        }
    }

    /// The links: the chain's base → tip, or every link of the file.
    pub fn link_names(&self) -> Vec<String> {
        match self {
            Space::Chain(k) => k.links().iter().map(|l| l.name.clone()).collect(),
            Space::Tree(t) => t.model().links.iter().map(|l| l.name.clone()).collect(),
        }
    }

    /// The lower limits of q (the tree's with a floating base: −∞ for its position, −1 for
    /// its quaternion).
    pub fn lower(&self) -> Vec<f64> {
        match self {
            Space::Chain(k) => k.lower().to_vec(),
            Space::Tree(t) => t.lower(),
        }
    }

    /// The upper limits of q.
    pub fn upper(&self) -> Vec<f64> {
        match self {
            Space::Chain(k) => k.upper().to_vec(),
            Space::Tree(t) => t.upper(),
        }
    }
}
