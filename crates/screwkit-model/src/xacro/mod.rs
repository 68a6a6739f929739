//! xacro → URDF, natively (no ROS, no Python): what ROS's `xacro` does to the robot
//! descriptions people publish.
//!
//! Supported: `xacro:property` (values, `default=`, `scope="parent"|"global"`, block properties),
//! `xacro:macro` with plain, default (`p:=1`), inherited (`p:=^`, `p:=^|1`) and block parameters
//! (`*p` — the next child element; `**p` — its children), macro calls (`<xacro:NAME …>` and
//! `<xacro:call macro="…">`), `xacro:insert_block`, `xacro:include` (relative to the including
//! file, `$(find pkg)` through [`XacroOptions::package_paths`], `ROS_PACKAGE_PATH` and
//! `AMENT_PREFIX_PATH`), `xacro:if` / `xacro:unless`, `xacro:arg` with `$(arg …)`,
//! `xacro:element` / `xacro:attribute`, `$(find)`, `$(arg)`, `$(env)`, `$(optenv)`,
//! `$(dirname)`, `$(eval)`, `$${` escapes, and `${…}` Python expressions: numbers, strings,
//! `+ - * / // % **`, comparisons, `and or not`, `a if c else b`, `pi`, `e`, `True`/`False`,
//! the `math` functions (`sin`, `radians`, `atan2`, `sqrt`, …, also as `math.sin`), `abs`,
//! `min`, `max`, `float`, `int`, `round`, `str`. Scoping follows xacro: a macro's body sees
//! the caller's properties, its parameters shadow them, properties defined in it stay local.
//! The xacro namespace may be spelled `http://www.ros.org/wiki/xacro`,
//! `http://ros.org/wiki/xacro` or `http://wiki.ros.org/xacro`; a file using the `xacro:` prefix
//! without declaring it is read as xacro too.
//!
//! Not supported (a one-line error names the file, line and construct): `xacro:include` with
//! `ns=`, YAML (`load_yaml`), lists and dictionaries in expressions. Elements and attributes of
//! other XML namespaces (Gazebo plugins, …) are left out of the output: they carry no kinematics.

use std::cell::RefCell;
use std::collections::HashMap;
use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::rc::Rc;

use crate::error::{ErrorKind, ModelError};
use crate::input::{self, Lines};

mod document;
mod expander;
pub(crate) use expander::find_package;
mod expr;
mod output;
mod scope;

use document::*;
use expander::*;
use expr::*;
use output::*;
use scope::*;

/// The namespace URIs xacro files declare.
pub const XACRO_NAMESPACES: [&str; 3] = [
    "http://www.ros.org/wiki/xacro",
    "http://ros.org/wiki/xacro",
    "http://wiki.ros.org/xacro",
];

/// How to expand: where packages are, and the values of `xacro:arg`s.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct XacroOptions {
    /// Folders searched for `$(find pkg)` before `ROS_PACKAGE_PATH` and `AMENT_PREFIX_PATH`:
    /// `DIR/pkg`, or a folder named `pkg` up to three levels below `DIR`.
    pub package_paths: Vec<PathBuf>,
    /// `name:=value` pairs for `xacro:arg` / `$(arg name)`.
    pub args: Vec<(String, String)>,
}

impl XacroOptions {
    /// Parses `name:=value` (the form ROS's xacro takes on its command line).
    pub fn parse_arg(s: &str) -> Result<(String, String), String> {
        match s.split_once(":=") {
            Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.to_string())),
            _ => Err(format!("xacro argument \"{s}\": expected name:=value")),
        }
    }
}

/// Whether `text` is xacro: an element or attribute in a xacro namespace, the `xacro:` prefix
/// used without a declaration, or a kinematic element (`link`, `joint`, `origin`, `axis`, `limit`, `parent`, `child`, `mimic`)
/// has `${…}` or `$(…)` in an attribute. (Elsewhere, in a Gazebo plugin's parameters say,
/// `${…}` is left as text: xacro's own output keeps what `$${…}` escaped.)
pub fn is_xacro(text: &str) -> bool {
    const KINEMATIC: [&str; 8] = [
        "link", "joint", "origin", "axis", "limit", "parent", "child", "mimic",
    ];
    let xacro_ns = |ns: Option<&str>| ns.is_some_and(|ns| XACRO_NAMESPACES.contains(&ns));
    match input::parse_xml(text) {
        Ok(doc) => doc.descendants().filter(|n| n.is_element()).any(|n| {
            xacro_ns(n.tag_name().namespace())
                || n.attributes().any(|a| xacro_ns(a.namespace()))
                || (KINEMATIC.contains(&n.tag_name().name())
                    && n.attributes()
                        .any(|a| a.value().contains("${") || a.value().contains("$(")))
        }),
        // Not well-formed: xacro if it uses the prefix without declaring it.
        Err(_) => text.contains("<xacro:"),
    }
}

/// Expands a xacro file into URDF text.
pub fn expand_file(path: impl AsRef<Path>, opts: &XacroOptions) -> Result<String, ModelError> {
    let path = path.as_ref();
    let label = path.display().to_string();
    let bytes = input::read_file(path)?;
    let text = crate::input::decode(&bytes).map_err(|k| ModelError::new(label.clone(), k))?;
    expand_str(&text, &label, path.parent().unwrap_or(Path::new(".")), opts)
}

/// Expands xacro text into URDF text; `source` names it in errors, `dir` is where relative
/// includes are found.
///
/// Limits (each an error naming the file and line): macros and includes nested at most
/// 200 deep; expressions, properties defined by properties, macros and elements nested at most
/// [`MAX_NESTING`] levels together; at most [`MAX_OUTPUT_BYTES`] of output (and of any one
/// string value); at most [`MAX_WORK`] elements, texts and expressions processed (exponential
/// macro fan-out); every file read at most [`input::MAX_FILE_BYTES`]. The expansion runs on a
/// thread of its own with a stack sized for these limits, whatever the caller's stack.
pub fn expand_str(
    text: &str,
    source: &str,
    dir: &Path,
    opts: &XacroOptions,
) -> Result<String, ModelError> {
    std::thread::scope(|s| {
        std::thread::Builder::new()
            .name("xacro".into())
            .stack_size(EXPANDER_STACK)
            .spawn_scoped(s, || expand_on_this_thread(text, source, dir, opts))
            .map_err(|e| {
                ModelError::new(
                    source,
                    ErrorKind::Io {
                        kind: e.kind(),
                        message: format!("cannot start the xacro expander: {e}"),
                    },
                )
            })?
            .join()
            .unwrap_or_else(|_| {
                Err(ModelError::new(
                    source,
                    ErrorKind::XacroExpand("internal error in the xacro expander".into()),
                ))
            })
    })
}

/// The expander thread's stack: [`MAX_NESTING`] levels of the deepest recursion measured at
/// under 4 KiB each in a debug build, with room to spare (virtual memory: only the pages used
/// are ever touched).
const EXPANDER_STACK: usize = 64 << 20;

/// The most levels of expressions, property definitions, macro calls and elements nested in
/// one another during an expansion.
pub const MAX_NESTING: usize = 1000;
/// The most text an expansion may produce (and the longest string value); each element
/// counts 64 bytes besides its name and attributes (what it takes in memory).
pub const MAX_OUTPUT_BYTES: usize = 64 << 20;
/// The most elements, texts and expression tokens one expansion may process.
pub const MAX_WORK: u64 = 5_000_000;

fn expand_on_this_thread(
    text: &str,
    source: &str,
    dir: &Path,
    opts: &XacroOptions,
) -> Result<String, ModelError> {
    let mut x = Expander {
        opts,
        args: opts.args.iter().cloned().collect(),
        depth: 0,
        nest: 0,
        work: 0,
        out_bytes: 0,
    };
    let root = x.parse(&crate::input::tolerate(text), source, dir)?;
    let scope = Scope::new(None);
    let mut out = OutElem {
        name: root.name.clone(),
        attrs: Vec::new(),
        children: Vec::new(),
    };
    for (k, v) in &root.attrs {
        let v = x.text(v, &scope, &root.at)?;
        out.attrs.push((k.clone(), v));
    }
    x.process(&root.children, &scope, &mut out)?;
    let mut s = String::from("<?xml version=\"1.0\"?>\n");
    write_elem(&mut s, &out, 0);
    Ok(s)
}
