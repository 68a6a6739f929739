//! Any robot description, told apart by content: a screw table ([`crate::table`]), MuJoCo's
//! MJCF (a `<mujoco>` root, [`crate::mjcf`]), or URDF (xacro expanded, [`crate::urdf`]).
//! The one rule every front end and library user loads by ([`Format::of`], [`tree_from_str`],
//! [`load_tree`]).

use std::path::Path;

use crate::{input, mjcf, table, urdf, Chain, ModelError, Tree, XacroOptions};

/// The kinds of robot description screwkit reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A screw table: the home pose M and the space screw axes S ([`table::is_screw_table`]).
    ScrewTable,
    /// MuJoCo's MJCF: a `<mujoco>` root ([`mjcf::is_mjcf`]).
    Mjcf,
    /// URDF, or xacro that expands to it (everything else; its parser names what is wrong).
    Urdf,
}

impl Format {
    /// The format of a description's text, by content (never by the file's extension).
    pub fn of(text: &str) -> Format {
        if table::is_screw_table(text) {
            Format::ScrewTable
        } else if mjcf::is_mjcf(text) {
            Format::Mjcf
        } else {
            Format::Urdf
        }
    }
}

/// The whole tree of a description's text, and the text it stands for: a screw table as it
/// is, MJCF with its includes spliced in (self-contained), URDF with xacro expanded by
/// `xacro`. `label` names the text in errors; relative includes resolve from `dir`.
pub fn tree_from_str(
    text: &str,
    label: &str,
    dir: &Path,
    xacro: &XacroOptions,
) -> Result<(Tree, String), ModelError> {
    match Format::of(text) {
        Format::ScrewTable => Ok((
            table::read_screw_table(text, label)?.tree()?,
            text.to_string(),
        )),
        Format::Mjcf => mjcf::read_str(text, label, dir),
        Format::Urdf => {
            let expanded = urdf::urdf_text(text, label, dir, xacro)?;
            // (The expansion is plain URDF: parsed as it is, meshes found from `dir`.)
            let tree = urdf::load_str_with(&expanded, label, dir, xacro)?;
            Ok((tree, expanded))
        }
    }
}

/// A file's text, read by the one rule (at most [`input::MAX_FILE_BYTES`], decoded by
/// [`input::decode`]), with its label for errors and the folder its includes resolve from.
fn read(path: &Path) -> Result<(String, String, &Path), ModelError> {
    let label = path.display().to_string();
    let bytes = input::read_file(path)?;
    let text = input::decode(&bytes).map_err(|kind| ModelError::new(label.clone(), kind))?;
    Ok((text, label, path.parent().unwrap_or(Path::new("."))))
}

/// [`tree_from_str`] of a file; includes resolve from its folder.
pub fn load_tree(path: impl AsRef<Path>, xacro: &XacroOptions) -> Result<Tree, ModelError> {
    let (text, label, dir) = read(path.as_ref())?;
    Ok(tree_from_str(&text, &label, dir, xacro)?.0)
}

/// The chain `base` → `tip` of any description file ([`crate::Chain::from_tree`] of
/// [`load_tree`]); a screw table with neither named is its own exact chain
/// ([`crate::ScrewRobot::chain`]: the screws as read, not the tree's rebuilt ones).
pub fn load_chain(
    path: impl AsRef<Path>,
    base: Option<&str>,
    tip: Option<&str>,
    xacro: &XacroOptions,
) -> Result<Chain, ModelError> {
    let (text, label, dir) = read(path.as_ref())?;
    if base.is_none() && tip.is_none() && Format::of(&text) == Format::ScrewTable {
        return table::read_screw_table(&text, &label)?.chain();
    }
    Chain::from_tree(&tree_from_str(&text, &label, dir, xacro)?.0, base, tip)
}
