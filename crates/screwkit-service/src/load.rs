//! A robot loaded once for every front end: [`Robot::load`] reads a path, text or standard
//! input (bounded, decoded by one rule): URDF, xacro (expanded), MuJoCo's MJCF or a screw
//! table, told apart by content; picks the chain and adds the tool frame. The CLI, Python, the pictures and the maps all start here.

use std::path::{Path, PathBuf};

use screwkit_lie::Se3;
use screwkit_model::{
    input, urdf, Chain, KinematicTree, ModelError, ScrewRobot, Tree, XacroOptions,
};
use screwkit_solve::{Kinematics, TreeKinematics, TreeWorkspace, Workspace};

use crate::error::{Error, Result};

/// Where a robot description comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// A file (URDF, xacro, MJCF or a screw table, told apart by content); relative includes
    /// resolve from its folder.
    Path(PathBuf),
    /// Text in memory; `label` names it in errors, relative includes resolve from `dir`.
    Text {
        /// The description.
        text: String,
        /// Its name in messages (`<string>`).
        label: String,
        /// The folder relative includes are found in.
        dir: PathBuf,
    },
    /// Standard input (read to its end, at most [`input::MAX_FILE_BYTES`]); includes resolve
    /// from the current folder.
    Stdin,
}

impl Source {
    /// A command-line argument: `-` is standard input, anything else a path.
    pub fn from_arg(arg: &Path) -> Source {
        if arg.as_os_str() == "-" {
            Source::Stdin
        } else {
            Source::Path(arg.to_path_buf())
        }
    }

    /// Text in memory named `label`, includes from the current folder.
    pub fn text(text: impl Into<String>, label: impl Into<String>) -> Source {
        Source::Text {
            text: text.into(),
            label: label.into(),
            dir: PathBuf::from("."),
        }
    }

    /// Its name in messages: the path, the label, or `<stdin>`.
    pub fn label(&self) -> String {
        match self {
            Source::Path(p) => p.display().to_string(),
            Source::Text { label, .. } => label.clone(),
            Source::Stdin => "<stdin>".into(),
        }
    }

    /// True for standard input.
    pub fn is_stdin(&self) -> bool {
        matches!(self, Source::Stdin)
    }

    /// The description's text, read by the one rule: at most [`input::MAX_FILE_BYTES`],
    /// UTF-8 with or without a byte-order mark, or Latin-1 when the XML declaration says so
    /// ([`input::decode`]). A file that cannot be opened is [`Error::Io`] with the operating
    /// system's error (a folder too).
    pub fn read(&self) -> Result<String> {
        let label = self.label();
        let bytes = match self {
            Source::Text { text, .. } => return Ok(text.clone()),
            Source::Stdin => input::read_bounded(std::io::stdin().lock())
                .map_err(|k| ModelError::new(label.clone(), k))?,
            Source::Path(p) => {
                let io = |source| Error::Io {
                    path: p.clone(),
                    source,
                };
                let file = std::fs::File::open(p).map_err(io)?;
                input::note_read(&file, p);
                if file.metadata().is_ok_and(|m| m.is_dir()) {
                    return Err(io(std::io::Error::new(
                        std::io::ErrorKind::IsADirectory,
                        "is a directory, not a file",
                    )));
                }
                input::read_bounded(file).map_err(|k| ModelError::new(label.clone(), k))?
            }
        };
        Ok(input::decode(&bytes).map_err(|k| ModelError::new(label, k))?)
    }

    /// The folder relative xacro includes resolve from.
    pub fn dir(&self) -> PathBuf {
        match self {
            Source::Path(p) => p.parent().unwrap_or(Path::new(".")).to_path_buf(),
            Source::Text { dir, .. } => dir.clone(),
            Source::Stdin => PathBuf::from("."),
        }
    }

    /// The URDF this source stands for (xacro expanded with `xacro`): what `screwkit xacro`
    /// prints.
    pub fn urdf(&self, xacro: &XacroOptions) -> Result<String> {
        let text = self.read()?;
        Ok(urdf::urdf_text(&text, &self.label(), &self.dir(), xacro)?)
    }

    /// The xacro expansion of this source, whether or not it uses xacro (ROS's `xacro`
    /// command: a plain URDF comes out re-written by the expander).
    pub fn expand_xacro(&self, xacro: &XacroOptions) -> Result<String> {
        let text = self.read()?;
        Ok(screwkit_model::xacro::expand_str(
            &text,
            &self.label(),
            &self.dir(),
            xacro,
        )?)
    }

    /// The whole tree of the description, and its text: URDF (xacro expanded), MJCF (a
    /// `<mujoco>` root: [`screwkit_model::mjcf`], includes read from [`Source::dir`] and
    /// spliced into the text), or a screw table ([`ScrewRobot::tree`]), told apart by content.
    pub fn tree(&self, xacro: &XacroOptions) -> Result<(Tree, String)> {
        self.tree_of(self.read()?, xacro)
    }

    /// [`Source::tree`] of this source's text, already read: the model's one rule
    /// ([`screwkit_model::tree_from_str`]).
    fn tree_of(&self, text: String, xacro: &XacroOptions) -> Result<(Tree, String)> {
        Ok(screwkit_model::tree_from_str(
            &text,
            &self.label(),
            &self.dir(),
            xacro,
        )?)
    }
}

/// How to read a robot and which chain of it to take.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LoadOptions {
    /// xacro expansion: package folders for `$(find pkg)`, `xacro:arg` values.
    pub xacro: XacroOptions,
    /// The chain's base link (None: the root link).
    pub base: Option<String>,
    /// The chain's tip link (None: the only leaf below the base).
    pub tip: Option<String>,
    /// A tool frame (TCP) fixed to the tip link: x, y, z, roll, pitch, yaw (m, rad; URDF rpy).
    /// FK, Jacobians, IK and tables are then of the tool frame.
    pub tool: Option<Vec<f64>>,
    /// A free joint (6 DoF) between the world and the root link in the whole tree
    /// ([`screwkit_model::kinematic_tree`] states its configuration and velocity).
    pub floating_base: bool,
    /// Which shapes of the file are read (collision, visual, both, none).
    pub geometry: crate::words::GeometryRoles,
    /// How the body's meshes are read (None: [`crate::body::default_meshes`]).
    pub meshes: Option<crate::words::Meshes>,
}

impl LoadOptions {
    /// The tool frame's pose in the tip link, if one is given.
    pub fn tool_pose(&self) -> Result<Option<Se3>> {
        let Some(t) = &self.tool else {
            return Ok(None);
        };
        let [x, y, z, r, p, w] = t.as_slice() else {
            return Err(Error::option(
                "tool",
                format!("needs 6 numbers x,y,z,roll,pitch,yaw, got {}", t.len()),
            ));
        };
        Se3::from_xyz_rpy([*x, *y, *z], [*r, *p, *w])
            .map(Some)
            .map_err(|e| Error::option("tool", e.to_string()))
    }
}

/// A robot description read once: the whole tree (every frame, [`TreeKinematics`]) and, where
/// one is named or the file is a single chain, the chain `base → tip` ([`Kinematics`]).
///
/// Loading succeeds when the file parses and what was asked for can be built: with `base`,
/// `tip` or `tool` the chain must build; otherwise the whole tree or the default chain (a
/// file with several leaves has no default chain: [`Robot::chain`] then says so, and the
/// whole-tree algorithms still work).
#[derive(Debug, Clone)]
pub struct Robot {
    tree: Tree,
    whole: std::result::Result<TreeKinematics, ModelError>,
    chain: std::result::Result<(Chain, Kinematics), ModelError>,
    urdf: String,
    options: LoadOptions,
    /// The files it was read from (its file, includes), protected from every output while it
    /// lives ([`input::InputFile`]).
    inputs: Vec<input::InputFile>,
    /// The folder its relative names (includes, meshes) were read from.
    dir: PathBuf,
}

impl Robot {
    /// Reads `source` (see [`Source::read`]), expands xacro when the content is xacro, parses
    /// the URDF, builds the whole tree (with a floating base if asked) and the chain
    /// `options.base` → `options.tip` with the tool frame.
    ///
    /// A screw table (`screwkit table --format json|csv`, or [`ScrewRobot::to_json`]) is read
    /// as the robot of its screws ([`Robot::from_screws`]).
    ///
    /// ```
    /// use screwkit_service::load::{LoadOptions, Robot, Source};
    /// // An MJCF humanoid with a free root joint: the whole tree, with its floating base.
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/mjcf/humanoid.xml");
    /// let robot = Robot::load(&Source::Path(path.into()), &LoadOptions::default())?;
    /// let tree = robot.whole()?;
    /// assert_eq!((tree.nq(), tree.nv()), (30, 29)); // 7 + 23 joints, 6 + 23 velocities
    /// // A chain of it, chosen as the CLI's --base/--tip choose it.
    /// let options = LoadOptions {
    ///     base: Some("pelvis".into()),
    ///     tip: Some("left_sole".into()),
    ///     ..LoadOptions::default()
    /// };
    /// let leg = Robot::load(&Source::Path(path.into()), &options)?;
    /// assert_eq!(leg.chain()?.dof(), 6);
    /// # Ok::<(), screwkit_service::error::Error>(())
    /// ```
    pub fn load(source: &Source, options: &LoadOptions) -> Result<Robot> {
        let (robot, inputs) = input::collect_reads(|| Robot::read(source, options));
        let mut robot = robot?;
        robot.inputs = inputs;
        robot.dir = source.dir();
        Ok(robot)
    }

    /// [`Robot::load`] without keeping its inputs.
    fn read(source: &Source, options: &LoadOptions) -> Result<Robot> {
        let text = source.read()?;
        if screwkit_model::table::is_screw_table(&text) {
            let screws = screwkit_model::table::read_screw_table(&text, &source.label())?;
            return Robot::from_screws(screws, options);
        }
        let (tree, urdf) = source.tree_of(text, &options.xacro)?;
        Robot::from_tree(tree, urdf, options)
    }

    /// The robot of a home pose and screw axes ([`ScrewRobot`]): its chain `base → tip` holds
    /// the screws as given, its whole tree the same robot with a frame at each joint
    /// ([`ScrewRobot::tree`]). `options.base`/`tip` may only name `base` and `tip`; a tool
    /// frame and a floating base apply as for a file. [`Robot::urdf`] is then the
    /// description's JSON, which loads back into the same robot.
    pub fn from_screws(screws: ScrewRobot, options: &LoadOptions) -> Result<Robot> {
        for (what, given, only) in [
            ("base", &options.base, "base"),
            ("tip", &options.tip, "tip"),
        ] {
            if let Some(g) = given.as_deref().filter(|g| *g != only) {
                return Err(Error::option(
                    what,
                    format!(
                        "\"{g}\": a robot given by screw axes is one chain, from \"base\" to \
                         \"tip\""
                    ),
                ));
            }
        }
        let tool = options.tool_pose()?;
        let exact = screws.chain()?;
        let chain = match &tool {
            Some(tool) => exact.with_tool(tool),
            None => exact.clone(),
        };
        let kin = Kinematics::new(&chain);
        let tree = screws.tree()?;
        let whole = KinematicTree::from_tree(&tree)
            .and_then(|m| TreeKinematics::new(&m.with_floating_base(options.floating_base)))
            .inspect(|whole| {
                // One exact model: the tree's "tip" answers with the screws as given (its
                // frames are computed from them, equal to rounding), so `fk(q)` and
                // `fk(q, link="tip")` are the same numbers. The chain always fits the tree it
                // was made with; were it not to, the tree's own chain answers (to rounding).
                if let Ok(tip) = whole.frame("tip") {
                    let _ = whole.set_chain(tip, &exact, 1e-9);
                }
            });
        let text = serde_json::to_string_pretty(&screws.to_json())
            .map_err(|e| Error::option("screws", e.to_string()))?;
        Ok(Robot {
            tree,
            whole,
            chain: Ok((chain, kin)),
            urdf: text,
            options: options.clone(),
            inputs: Vec::new(),
            dir: PathBuf::from("."),
        })
    }

    /// The robot of an already parsed tree (`urdf`: its text, kept for [`Robot::urdf`]), with
    /// the shapes `options.geometry` asks for.
    pub fn from_tree(mut tree: Tree, urdf: String, options: &LoadOptions) -> Result<Robot> {
        let tool = options.tool_pose()?;
        let roles = options.geometry;
        tree.geometries.retain(|g| roles.keeps(g.role));
        if let Some(rules) = &mut tree.contact_rules {
            rules.world.retain(|g| roles.keeps(g.role));
        }
        if !roles.keeps(screwkit_model::geometry::Role::Collision) {
            // Nothing of the body is queried: what could not be read does not matter.
            tree.geometry_problems.clear();
        }
        let chain =
            Chain::from_tree(&tree, options.base.as_deref(), options.tip.as_deref()).map(|chain| {
                let chain = match &tool {
                    Some(tool) => chain.with_tool(tool),
                    None => chain,
                };
                let kin = Kinematics::new(&chain);
                (chain, kin)
            });
        // A file that gives its root a free joint (MJCF) has a floating base whatever asked.
        let floating = options.floating_base || tree.floating_root;
        let whole = KinematicTree::from_tree(&tree)
            .and_then(|m| TreeKinematics::new(&m.with_floating_base(floating)));
        let chain_asked = options.base.is_some() || options.tip.is_some() || tool.is_some();
        match (&whole, &chain) {
            (_, Err(e)) if chain_asked => return Err(e.clone().into()),
            (Err(e), Err(_)) => return Err(e.clone().into()),
            _ => {}
        }
        Ok(Robot {
            tree,
            whole,
            chain,
            urdf,
            options: options.clone(),
            inputs: Vec::new(),
            dir: PathBuf::from("."),
        })
    }

    /// The folder the robot's relative names (includes, meshes) were read from.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The parsed tree.
    pub fn tree(&self) -> &Tree {
        &self.tree
    }

    /// The chain `base → tip` (with the tool frame), or why there is none (a file with several
    /// leaves and no tip given).
    pub fn chain(&self) -> Result<&Chain> {
        self.chain_parts().map(|(c, _)| c)
    }

    /// The chain's prepared kinematics (see [`Robot::chain`]).
    pub fn kin(&self) -> Result<&Kinematics> {
        self.chain_parts().map(|(_, k)| k)
    }

    /// The chain and its kinematics.
    pub fn chain_parts(&self) -> Result<(&Chain, &Kinematics)> {
        match &self.chain {
            Ok((c, k)) => Ok((c, k)),
            Err(e) => Err(e.clone().into()),
        }
    }

    /// True when the options or the file give a chain.
    pub fn has_chain(&self) -> bool {
        self.chain.is_ok()
    }

    /// A fresh workspace for the chain.
    pub fn workspace(&self) -> Result<Workspace> {
        Ok(Workspace::new(self.kin()?))
    }

    /// The whole tree prepared for the algorithms ([`screwkit_solve::tree`]), or why it could
    /// not be built (a joint type the tree does not hold).
    pub fn whole(&self) -> Result<&TreeKinematics> {
        self.whole.as_ref().map_err(|e| e.clone().into())
    }

    /// A fresh workspace for the whole tree.
    pub fn tree_workspace(&self) -> Result<TreeWorkspace> {
        Ok(TreeWorkspace::new(self.whole()?))
    }

    /// Adds a named frame fixed to `link` at `placement` to the whole tree (a tool frame, a
    /// site); returns its frame index.
    pub fn add_frame(&mut self, name: &str, link: &str, placement: Se3) -> Result<usize> {
        let mut model = self.whole()?.model().clone();
        let index = model.add_frame(name, link, placement)?;
        self.whole = Ok(TreeKinematics::new(&model)?);
        Ok(index)
    }

    /// The URDF text (xacro expanded) the robot was read from (the MJCF text with includes
    /// spliced in; the JSON of a robot given by screw axes).
    pub fn urdf(&self) -> &str {
        &self.urdf
    }

    /// The options it was loaded with.
    pub fn options(&self) -> &LoadOptions {
        &self.options
    }

    /// The pose of `link` in the chain's base frame, when rigidly attached to it (targets
    /// expressed in another frame). Without a chain, in the root link's frame.
    pub fn frame_pose(&self, link: &str) -> Result<Se3> {
        let base = match &self.chain {
            Ok((c, _)) => c.base.clone(),
            Err(_) => self.tree.links[self.tree.root].clone(),
        };
        Ok(self.tree.fixed_transform(&base, link)?)
    }
}
