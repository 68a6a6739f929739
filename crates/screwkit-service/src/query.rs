//! **The query floor**: what a front end asks about — the chain's tip, a frame of the whole
//! tree, or a frame seen from another — is resolved once ([`About::resolve`], the floor's
//! rule of [`crate::whole::wants_tree`]), and each query of it, one configuration or N, is
//! routed here: chain or tree, single call or the library's batch. The single calls run in
//! the calling thread's kept workspace (`Workspace::local`, `TreeWorkspace::local`), so a
//! front end keeps no scratch for them.

use nalgebra::Matrix6xX;
use screwkit_lie::Se3;
use screwkit_solve::analysis::{
    analyze_jacobian, analyze_position_jacobian, Analysis, PositionAnalysis,
};
use screwkit_solve::batch::{fk_all_links_batch, fk_batch, jacobian_batch, write_jacobian};
use screwkit_solve::tree::{batch as tree_batch, fk as tree_fk, jacobian as tree_jacobian};
use screwkit_solve::{
    JacobianKind, Kinematics, SolveError, TreeKinematics, TreeWorkspace, Workspace,
};

use crate::error::{Error, Result};
use crate::load::Robot;
use crate::report::{FkReport, FramesReport, NamedPose};

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

    /// Its pose, Jacobian of `kind` and the Jacobian's singularity analysis at q
    /// ([`analysis_of`]). Checks q.
    pub fn analyze(&self, kind: JacobianKind, q: &[f64]) -> Result<Analyzed, SolveError> {
        let mut flat = vec![0.0; 6 * self.columns()];
        let pose = self.pose_jacobian(kind, q, &mut flat)?;
        let jacobian = Matrix6xX::from_row_slice(&flat);
        let (analysis, position) = analysis_of(&jacobian, kind, pose.translation())?;
        Ok(Analyzed {
            pose,
            jacobian,
            analysis,
            position,
        })
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

/// A Jacobian and its singularity analysis at one configuration ([`About::analyze`]).
#[derive(Debug, Clone)]
pub struct Analyzed {
    /// The frame's pose.
    pub pose: Se3,
    /// The Jacobian (6 × [`About::columns`]).
    pub jacobian: Matrix6xX<f64>,
    /// Its analysis (SVD, rank, manipulability, ellipsoids, lost directions).
    pub analysis: Analysis,
    /// The analysis of the frame point's 3 × n velocity rows.
    pub position: PositionAnalysis,
}

/// The singularity analysis of a Jacobian `j` of `kind` ([`analyze_jacobian`]) and of the
/// velocity of the point `p` where its frame's origin is ([`analyze_position_jacobian`] of
/// [`crate::report::tip_point_rows`]): the one analysis every front end reports.
pub fn analysis_of(
    j: &Matrix6xX<f64>,
    kind: JacobianKind,
    p: &nalgebra::Vector3<f64>,
) -> Result<(Analysis, PositionAnalysis), SolveError> {
    let analysis = analyze_jacobian(j)?;
    let position = analyze_position_jacobian(&crate::report::tip_point_rows(j, kind, p));
    Ok((analysis, position))
}

/// Which frames a pose query gives: the frame selector every front end speaks (the CLI's
/// `fk` options, Python's `fk_all_links` and `fk_all_frames`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Selection<'a> {
    /// The chain's tip; on the whole tree (the floor's rule), its leaves.
    Tip,
    /// Every link: the chain's, base → tip; on the whole tree, every link of the file.
    Links,
    /// Every frame of the whole tree: its links in the file's order, then the added frames.
    All,
    /// The leaf links of the whole tree (links with no joint below them, file order).
    Leaves,
    /// These frames of the whole tree, in the order given (a request naming frames is about
    /// the tree).
    Named(&'a [String]),
}

/// The frames a pose query answers, resolved once ([`Poses::resolve`]), and its poses, one
/// configuration or N, routed here.
#[derive(Debug, Clone)]
pub enum Poses<'k> {
    /// The chain's tip.
    Tip(&'k Kinematics),
    /// The chain's links, base → tip (the tip, with its tool frame, last).
    ChainLinks(&'k Kinematics),
    /// Chosen frames of the whole tree (indices in its frame order), from its all-frame sweep.
    Frames(&'k TreeKinematics, Vec<usize>),
}

impl<'k> Poses<'k> {
    /// The frames `selection` names on `robot` (`tree`: the front end's whole tree, frames it
    /// added included). `All`, `Leaves` and `Named` are about the whole tree; `Tip` and
    /// `Links` about the chain unless the floor's rule says the tree answers
    /// ([`crate::whole::wants_tree`]).
    pub fn resolve(
        robot: &'k Robot,
        tree: Option<&'k TreeKinematics>,
        selection: Selection<'_>,
    ) -> Result<Poses<'k>> {
        let chain_side = matches!(selection, Selection::Tip | Selection::Links);
        if chain_side && !crate::whole::wants_tree(robot, false) {
            let kin = robot.kin()?;
            return Ok(match selection {
                Selection::Tip => Poses::Tip(kin),
                _ => Poses::ChainLinks(kin),
            });
        }
        let tree = match tree {
            Some(t) => t,
            None => robot.whole()?,
        };
        let frames = match selection {
            Selection::Named(names) => names
                .iter()
                .map(|n| tree.frame(n).map_err(Into::into))
                .collect::<Result<Vec<_>>>()?,
            Selection::All => (0..tree.frame_count()).collect(),
            Selection::Links => (0..tree.model().links.len()).collect(),
            Selection::Tip | Selection::Leaves => crate::whole::leaf_frames(tree),
        };
        Ok(Poses::Frames(tree, frames))
    }

    /// True for frames of the whole tree.
    pub fn is_tree(&self) -> bool {
        matches!(self, Poses::Frames(..))
    }

    /// The number of poses per configuration.
    pub fn count(&self) -> usize {
        match self {
            Poses::Tip(_) => 1,
            Poses::ChainLinks(k) => k.links().len(),
            Poses::Frames(_, f) => f.len(),
        }
    }

    /// The poses' frames, by name.
    pub fn names(&self) -> Vec<&'k str> {
        match *self {
            Poses::Tip(k) => vec![k.links().last().map_or("", |l| l.name.as_str())],
            Poses::ChainLinks(k) => k.links().iter().map(|l| l.name.as_str()).collect(),
            Poses::Frames(t, ref f) => f.iter().map(|&i| t.frame_name(i)).collect(),
        }
    }

    /// The length of the q its queries take (the chain's dof, or the tree's nq).
    pub fn q_len(&self) -> usize {
        match self {
            Poses::Tip(k) | Poses::ChainLinks(k) => k.dof(),
            Poses::Frames(t, _) => t.nq(),
        }
    }

    /// The names of q's entries (the chain's joints, or the tree's `q_names`).
    pub fn q_names(&self) -> &'k [String] {
        match *self {
            Poses::Tip(k) | Poses::ChainLinks(k) => k.names(),
            Poses::Frames(t, _) => t.q_names(),
        }
    }

    /// What q's length is called in messages: `dof` (the chain's) or `nq` (the tree's).
    pub fn q_len_word(&self) -> &'static str {
        if self.is_tree() {
            "nq"
        } else {
            "dof"
        }
    }

    /// An error unless q is one configuration (length, finite values).
    pub fn check_q(&self, q: &[f64]) -> Result<(), SolveError> {
        match self {
            Poses::Tip(k) | Poses::ChainLinks(k) => k.check_q(q),
            Poses::Frames(t, _) => t.check_q(q).map(|_| ()),
        }
    }

    /// The shape of one configuration's poses as an array: (4, 4) for the tip, else
    /// ([`Poses::count`], 4, 4).
    pub fn shape(&self) -> Vec<usize> {
        match self {
            Poses::Tip(_) => vec![4, 4],
            _ => vec![self.count(), 4, 4],
        }
    }

    /// The poses at q, row-major into `out` ([`Poses::count`] × 16). Checks q.
    pub fn poses(&self, q: &[f64], out: &mut [f64]) -> Result<(), SolveError> {
        let write = |ts: &mut dyn Iterator<Item = &Se3>, out: &mut [f64]| {
            for (t, o) in ts.zip(out.chunks_mut(16)) {
                t.write_row_major(o);
            }
        };
        match *self {
            Poses::Tip(k) => {
                let t = Workspace::local(k, |ws| screwkit_solve::fk::fk(k, ws, q))?;
                t.write_row_major(&mut out[..16]);
            }
            Poses::ChainLinks(k) => Workspace::local(k, |ws| {
                let all = screwkit_solve::fk::fk_all_links(k, ws, q)?;
                write(&mut all.iter(), out);
                Ok::<_, SolveError>(())
            })?,
            Poses::Frames(t, ref f) => TreeWorkspace::local(t, |ws| {
                let all = tree_fk::fk_frames(t, ws, q)?;
                write(&mut f.iter().map(|&i| &all[i]), out);
                Ok::<_, SolveError>(())
            })?,
        }
        Ok(())
    }

    /// The poses at N configurations (`qs`: N × [`Poses::q_len`]) into `out`
    /// (N × [`Poses::count`] × 16), through the library's batch; each row as the single call.
    pub fn poses_batch(&self, qs: &[f64], out: &mut [f64]) -> Result<(), SolveError> {
        match *self {
            Poses::Tip(k) => fk_batch(k, qs, out),
            Poses::ChainLinks(k) => fk_all_links_batch(k, qs, out),
            Poses::Frames(t, ref f) => {
                let (all_count, k) = (t.frame_count(), f.len());
                if f.iter().copied().eq(0..all_count) {
                    return tree_batch::fk_frames_batch(t, qs, out);
                }
                let rows = out.len() / (16 * k).max(1);
                let mut all = vec![0.0; rows * all_count * 16];
                let result = tree_batch::fk_frames_batch(t, qs, &mut all);
                for (dst, src) in out.chunks_mut(16 * k).zip(all.chunks(16 * all_count)) {
                    for (o, &i) in dst.chunks_mut(16).zip(f) {
                        o.copy_from_slice(&src[16 * i..16 * (i + 1)]);
                    }
                }
                result
            }
        }
    }

    /// The JSON report of one configuration's poses (`poses`: this selection's, row-major):
    /// on the chain `{"q", "pose"}` (with `"links"` for every link; the tip is the last
    /// link), on the whole tree `{"q", "frames"}`.
    pub fn report(&self, q: &[f64], poses: &[f64]) -> PosesReport {
        let named = |names: Vec<&str>| {
            names
                .into_iter()
                .zip(poses.chunks(16))
                .map(|(n, p)| NamedPose::from_row_major(n, p))
                .collect::<Vec<_>>()
        };
        match self {
            Poses::Tip(_) => PosesReport::Chain(FkReport::new(q, poses, None)),
            Poses::ChainLinks(_) => {
                let tip = &poses[poses.len().saturating_sub(16)..];
                PosesReport::Chain(FkReport::new(q, tip, Some(named(self.names()))))
            }
            Poses::Frames(..) => PosesReport::Frames(FramesReport {
                q: q.to_vec(),
                frames: named(self.names()),
            }),
        }
    }
}

/// One configuration's poses as JSON: the chain's shape or the tree's ([`Poses::report`]).
#[derive(Debug, Clone, serde::Serialize)]
#[serde(untagged)]
pub enum PosesReport {
    /// `{"q", "pose"}` (+ `"links"`).
    Chain(FkReport),
    /// `{"q", "frames"}`.
    Frames(FramesReport),
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

    /// The length of a configuration: the chain's dof, or the tree's nq.
    pub fn q_len(&self) -> usize {
        match self {
            Space::Chain(k) => k.dof(),
            Space::Tree(t) => t.nq(),
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
