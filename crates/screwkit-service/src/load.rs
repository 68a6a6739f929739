//! A robot loaded once for every front end: [`Robot::load`] reads a path, text or standard
//! input (bounded, decoded by one rule), expands xacro when the content is xacro, picks the
//! chain and adds the tool frame. The CLI, Python, the pictures and the maps all start here.

use std::path::{Path, PathBuf};

use screwkit_lie::Se3;
use screwkit_model::{input, urdf, Chain, ModelError, Tree, XacroOptions};
use screwkit_solve::{Kinematics, Workspace};

use crate::error::{Error, Result};

/// Where a robot description comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// A file (URDF or xacro, told apart by content); relative xacro includes resolve from
    /// its folder.
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

    /// The whole tree of the description, and its URDF text.
    pub fn tree(&self, xacro: &XacroOptions) -> Result<(Tree, String)> {
        let urdf = self.urdf(xacro)?;
        let tree = urdf::load_str(&urdf, &self.label())?;
        Ok((tree, urdf))
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

/// A robot description read once, with the chain the options name, ready for kinematics.
#[derive(Debug, Clone)]
pub struct Robot {
    tree: Tree,
    chain: Chain,
    kin: Kinematics,
    urdf: String,
    options: LoadOptions,
}

impl Robot {
    /// Reads `source` (see [`Source::read`]), expands xacro when the content is xacro, parses
    /// the URDF, takes the chain `options.base` → `options.tip` and adds the tool frame.
    pub fn load(source: &Source, options: &LoadOptions) -> Result<Robot> {
        let (tree, urdf) = source.tree(&options.xacro)?;
        Robot::from_tree(tree, urdf, options)
    }

    /// The chain of an already parsed tree (`urdf`: its text, kept for [`Robot::urdf`]).
    pub fn from_tree(tree: Tree, urdf: String, options: &LoadOptions) -> Result<Robot> {
        let chain = Chain::from_tree(&tree, options.base.as_deref(), options.tip.as_deref())?;
        let chain = match options.tool_pose()? {
            Some(tool) => chain.with_tool(&tool),
            None => chain,
        };
        let kin = Kinematics::new(&chain);
        Ok(Robot {
            tree,
            chain,
            kin,
            urdf,
            options: options.clone(),
        })
    }

    /// The whole tree of the file.
    pub fn tree(&self) -> &Tree {
        &self.tree
    }

    /// The chain (with the tool frame, if any).
    pub fn chain(&self) -> &Chain {
        &self.chain
    }

    /// Its kinematics, for the library's algorithms.
    pub fn kin(&self) -> &Kinematics {
        &self.kin
    }

    /// A new scratch for the library's algorithms on this chain.
    pub fn workspace(&self) -> Workspace {
        Workspace::new(&self.kin)
    }

    /// The URDF text (after xacro expansion): loading it with the same options gives the same
    /// robot (pickling, pages).
    pub fn urdf(&self) -> &str {
        &self.urdf
    }

    /// The options it was loaded with.
    pub fn options(&self) -> &LoadOptions {
        &self.options
    }

    /// The pose of `link` (rigidly attached to the base) in the base frame: a target given in
    /// that link's frame is `frame_pose(link) · target` in the base frame.
    pub fn frame_pose(&self, link: &str) -> Result<Se3> {
        Ok(self.tree.fixed_transform(&self.chain.base, link)?)
    }
}
