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
    let text = crate::urdf::decode(&bytes).map_err(|k| ModelError::new(label.clone(), k))?;
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
    let root = x.parse(&crate::urdf::tolerate(text), source, dir)?;
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

// ---------------------------------------------------------------------------------------------
// The input tree: every file parsed once into owned nodes (comments dropped), so that macro
// bodies and blocks can outlive the document they came from.

/// Where a node came from, for error messages.
#[derive(Debug, Clone)]
struct At {
    file: Rc<str>,
    dir: Rc<Path>,
    line: u32,
}

#[derive(Debug, Clone)]
enum Node {
    Elem(Rc<Elem>),
    /// Text content, with where its element is.
    Text(String, At),
}

#[derive(Debug)]
struct Elem {
    /// For xacro elements, the local name (`property`, `macro`, a macro's name); otherwise the
    /// element's name.
    name: String,
    xacro: bool,
    /// Attributes in no namespace, and xacro-namespace ones as `xacro:NAME`.
    attrs: Vec<(String, String)>,
    children: Vec<Node>,
    at: At,
}

impl Elem {
    fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
}

// ---------------------------------------------------------------------------------------------
// Scopes: properties and macros, looked up through the callers (xacro's dynamic scoping).

#[derive(Debug, Clone)]
enum Prop {
    /// Text not yet evaluated (xacro evaluates properties when they are used), with the scope
    /// it was defined in.
    Lazy(String, Scope, At),
    Value(Value),
    Block(Vec<Node>),
}

#[derive(Debug, Clone)]
struct Macro {
    params: Vec<Param>,
    body: Vec<Node>,
}

#[derive(Debug, Clone)]
struct Param {
    name: String,
    /// 0: a value, 1: `*block` (one element), 2: `**block` (an element's children).
    stars: usize,
    default: Option<String>,
    /// `^`: taken from the caller's scope when not given.
    inherit: bool,
}

#[derive(Debug, Default)]
struct Frame {
    parent: Option<Scope>,
    props: HashMap<String, Prop>,
    macros: HashMap<String, Rc<Macro>>,
    /// Properties being evaluated (cycle detection).
    busy: Vec<String>,
}

#[derive(Debug, Clone)]
struct Scope(Rc<RefCell<Frame>>);

impl Scope {
    fn new(parent: Option<Scope>) -> Self {
        Scope(Rc::new(RefCell::new(Frame {
            parent,
            ..Frame::default()
        })))
    }

    fn prop(&self, name: &str) -> Option<(Prop, Scope)> {
        let f = self.0.borrow();
        match f.props.get(name) {
            Some(p) => Some((p.clone(), self.clone())),
            None => f.parent.as_ref().and_then(|p| p.prop(name)),
        }
    }

    fn macro_(&self, name: &str) -> Option<Rc<Macro>> {
        let f = self.0.borrow();
        match f.macros.get(name) {
            Some(m) => Some(m.clone()),
            None => f.parent.as_ref().and_then(|p| p.macro_(name)),
        }
    }

    fn parent_or_self(&self) -> Scope {
        self.0
            .borrow()
            .parent
            .clone()
            .unwrap_or_else(|| self.clone())
    }

    fn global(&self) -> Scope {
        match &self.0.borrow().parent {
            Some(p) => p.global(),
            None => self.clone(),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The output tree.

#[derive(Debug)]
struct OutElem {
    name: String,
    attrs: Vec<(String, String)>,
    children: Vec<Out>,
}

#[derive(Debug)]
enum Out {
    Elem(OutElem),
    Text(String),
}

fn escape(s: &str, out: &mut String) {
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
}

fn write_elem(s: &mut String, e: &OutElem, depth: usize) {
    let pad = "  ".repeat(depth);
    let _ = write!(s, "{pad}<{}", e.name);
    for (k, v) in &e.attrs {
        let _ = write!(s, " {k}=\"");
        escape(v, s);
        s.push('"');
    }
    if e.children.is_empty() {
        s.push_str("/>\n");
        return;
    }
    if let [Out::Text(t)] = e.children.as_slice() {
        s.push('>');
        escape(t.trim(), s);
        let _ = writeln!(s, "</{}>", e.name);
        return;
    }
    s.push_str(">\n");
    for c in &e.children {
        match c {
            Out::Elem(c) => write_elem(s, c, depth + 1),
            Out::Text(t) => {
                s.push_str(&"  ".repeat(depth + 1));
                escape(t.trim(), s);
                s.push('\n');
            }
        }
    }
    let _ = writeln!(s, "{pad}</{}>", e.name);
}

// ---------------------------------------------------------------------------------------------
// The expander.

struct Expander<'o> {
    opts: &'o XacroOptions,
    args: HashMap<String, String>,
    /// Include and macro nesting, bounded against runaway recursion.
    depth: usize,
    /// Every recursive construct (expression, property definition, macro, element) nested
    /// now, at most [`MAX_NESTING`].
    nest: usize,
    /// Elements, texts and tokens processed so far, at most [`MAX_WORK`].
    work: u64,
    /// Output text produced so far (approximately: names, attribute values and texts), at
    /// most [`MAX_OUTPUT_BYTES`].
    out_bytes: usize,
}

const MAX_DEPTH: usize = 200;

fn fail(at: &At, what: impl std::fmt::Display) -> ModelError {
    ModelError::new(
        format!("{}:{}", at.file, at.line),
        ErrorKind::XacroExpand(what.to_string()),
    )
}

impl Expander<'_> {
    /// Enters one level of nesting ([`MAX_NESTING`]); [`Expander::leave`] undoes it.
    fn nest_in(&mut self, at: &At, what: &str) -> Result<(), ModelError> {
        self.nest += 1;
        if self.nest > MAX_NESTING {
            self.nest -= 1;
            return Err(fail(
                at,
                format!("{what} nested more than {MAX_NESTING} levels deep (expressions, properties, macros and elements together)"),
            ));
        }
        Ok(())
    }

    fn leave(&mut self) {
        self.nest -= 1;
    }

    /// Counts `n` units of work ([`MAX_WORK`]).
    fn count(&mut self, n: u64, at: &At) -> Result<(), ModelError> {
        self.work += n;
        if self.work > MAX_WORK {
            return Err(fail(
                at,
                format!("the expansion does more than {MAX_WORK} steps (macros calling macros many times over?)"),
            ));
        }
        Ok(())
    }

    /// Counts `n` bytes of output ([`MAX_OUTPUT_BYTES`]).
    fn produce(&mut self, n: usize, at: &At) -> Result<(), ModelError> {
        self.out_bytes += n;
        if self.out_bytes > MAX_OUTPUT_BYTES {
            return Err(fail(
                at,
                format!(
                    "the expanded robot is larger than {} MiB",
                    MAX_OUTPUT_BYTES >> 20
                ),
            ));
        }
        Ok(())
    }

    /// Parses a file's text into owned nodes and returns its root element.
    fn parse(&mut self, text: &str, source: &str, dir: &Path) -> Result<Rc<Elem>, ModelError> {
        let file: Rc<str> = source.into();
        let dir: Rc<Path> = dir.into();
        let declared;
        // Checked (sizes, nesting, entities) before anything else reads it; parsed once, or
        // twice when `xacro:` is used without being declared (declared on the root, then read).
        let (text, doc) = match input::parse_xml(text) {
            Ok(doc) => (text, doc),
            Err(ErrorKind::Xml(e)) if e.contains("xacro") => {
                declared = declare_xacro(text)
                    .ok_or_else(|| ModelError::new(source, ErrorKind::Xml(e.clone())))?;
                let doc = input::parse_xml(&declared).map_err(|k| ModelError::new(source, k))?;
                (declared.as_str(), doc)
            }
            Err(k) => return Err(ModelError::new(source, k)),
        };
        let lines = Lines::new(text);
        let cx = Convert {
            text,
            lines: &lines,
            file: &file,
            dir: &dir,
        };
        Ok(cx.elem(doc.root_element()))
    }

    /// Text with `${…}` and `$(…)` evaluated, as a string.
    fn text(&mut self, s: &str, scope: &Scope, at: &At) -> Result<String, ModelError> {
        Ok(self.eval_text(s, scope, at)?.to_text())
    }

    /// Evaluates text: a lone `${expr}` keeps its type; anything else is a string.
    fn eval_text(&mut self, s: &str, scope: &Scope, at: &At) -> Result<Value, ModelError> {
        let mut parts: Vec<Value> = Vec::new();
        let mut lit = String::new();
        let b = s.as_bytes();
        let mut i = 0;
        while i < b.len() {
            if b[i] == b'$'
                && i + 2 < b.len()
                && b[i + 1] == b'$'
                && (b[i + 2] == b'{' || b[i + 2] == b'(')
            {
                lit.push('$');
                lit.push(b[i + 2] as char);
                i += 3;
            } else if b[i] == b'$' && i + 1 < b.len() && (b[i + 1] == b'{' || b[i + 1] == b'(') {
                let close = if b[i + 1] == b'{' { '}' } else { ')' };
                let end = matching(s, i + 2, b[i + 1] as char, close)
                    .ok_or_else(|| fail(at, format!("unclosed \"{}\" in \"{s}\"", &s[i..i + 2])))?;
                let inner = &s[i + 2..end];
                if !lit.is_empty() {
                    parts.push(Value::Str(std::mem::take(&mut lit)));
                }
                if close == '}' {
                    // As xacro: substitutions inside an expression first (`${'$(arg p)' + 'x'}`).
                    let inner = if inner.contains("$(") {
                        self.text(inner, scope, at)?
                    } else {
                        inner.to_string()
                    };
                    parts.push(self.expr(&inner, scope, at)?);
                } else {
                    parts.push(Value::Str(self.extension(inner, scope, at)?));
                }
                i = end + 1;
            } else {
                let c = s[i..].chars().next().unwrap_or(' ');
                lit.push(c);
                i += c.len_utf8();
            }
        }
        if !lit.is_empty() {
            parts.push(Value::Str(lit));
        }
        Ok(match parts.len() {
            0 => Value::Str(String::new()),
            1 => parts.pop().unwrap_or(Value::Str(String::new())),
            _ => {
                let text: Vec<String> = parts.iter().map(Value::to_text).collect();
                if text.iter().map(String::len).sum::<usize>() > MAX_OUTPUT_BYTES {
                    return Err(fail(
                        at,
                        format!("a text longer than {} MiB", MAX_OUTPUT_BYTES >> 20),
                    ));
                }
                Value::Str(text.concat())
            }
        })
    }

    fn expr(&mut self, src: &str, scope: &Scope, at: &At) -> Result<Value, ModelError> {
        let tokens = lex(src).map_err(|e| fail(at, format!("${{{src}}}: {e}")))?;
        self.count(tokens.len() as u64 + 1, at)?;
        let mut p = Parser {
            x: self,
            tokens,
            pos: 0,
            scope,
            at,
            src,
            skip: 0,
        };
        let v = p.ternary()?;
        if p.pos != p.tokens.len() {
            return Err(fail(
                at,
                format!("${{{src}}}: unexpected {:?}", p.tokens[p.pos]),
            ));
        }
        Ok(v)
    }

    /// `$(find pkg)`, `$(arg name)`, `$(env NAME)`, `$(optenv NAME default)`, `$(dirname)`,
    /// `$(eval expr)`.
    fn extension(&mut self, inner: &str, scope: &Scope, at: &At) -> Result<String, ModelError> {
        let inner = self.text(inner, scope, at)?;
        let mut words = inner.split_whitespace();
        let cmd = words.next().unwrap_or("");
        let rest: Vec<&str> = words.collect();
        match (cmd, rest.as_slice()) {
            ("find", [pkg]) => self.find(pkg, at),
            ("arg", [name]) => self.args.get(*name).cloned().ok_or_else(|| {
                fail(at, format!("$(arg {name}): no such argument (declare it with <xacro:arg name=\"{name}\" default=\"…\"/> or pass {name}:=value)"))
            }),
            ("env", [name]) => std::env::var(name)
                .map_err(|_| fail(at, format!("$(env {name}): the environment variable is not set"))),
            ("optenv", [name, default @ ..]) => {
                Ok(std::env::var(name).unwrap_or_else(|_| default.join(" ")))
            }
            ("dirname", []) => Ok(at.dir.display().to_string()),
            ("eval", _) => {
                let e = inner.trim_start().strip_prefix("eval").unwrap_or("");
                Ok(self.expr(e, scope, at)?.to_text())
            }
            _ => Err(fail(at, format!("$({inner}): unknown or malformed substitution"))),
        }
    }

    /// The folder of package `pkg`.
    fn find(&self, pkg: &str, at: &At) -> Result<String, ModelError> {
        let mut roots: Vec<PathBuf> = self.opts.package_paths.clone();
        // Absolute, so that `$(find pkg)/x.xacro` is not joined to the including file's folder
        // a second time when the package path is relative.
        let split = |v: std::ffi::OsString| {
            std::env::split_paths(&v)
                .filter(|p| !p.as_os_str().is_empty())
                .collect::<Vec<_>>()
        };
        if let Some(v) = std::env::var_os("ROS_PACKAGE_PATH") {
            roots.extend(split(v));
        }
        for root in &roots {
            let root = std::path::absolute(root).unwrap_or_else(|_| root.clone());
            if let Some(found) = find_below(&root, pkg, 3) {
                return Ok(found.display().to_string());
            }
        }
        if let Some(v) = std::env::var_os("AMENT_PREFIX_PATH") {
            for prefix in split(v) {
                let d = prefix.join("share").join(pkg);
                let d = std::path::absolute(&d).unwrap_or(d);
                if d.is_dir() {
                    return Ok(d.display().to_string());
                }
            }
        }
        Err(fail(
            at,
            format!("$(find {pkg}): package not found (add its parent folder to the package paths, or set ROS_PACKAGE_PATH)"),
        ))
    }

    /// The value of a property (evaluating it on first use).
    fn lookup(&mut self, name: &str, scope: &Scope, at: &At) -> Result<Value, ModelError> {
        let Some((prop, owner)) = scope.prop(name) else {
            return Err(fail(at, format!("unknown property or name \"{name}\"")));
        };
        match prop {
            Prop::Value(v) => Ok(v),
            Prop::Block(_) => Err(fail(
                at,
                format!("\"{name}\" is a block: use <xacro:insert_block name=\"{name}\"/>"),
            )),
            Prop::Lazy(text, def_scope, def_at) => {
                if owner.0.borrow().busy.iter().any(|b| b == name) {
                    return Err(fail(
                        &def_at,
                        format!("property \"{name}\" is defined in terms of itself"),
                    ));
                }
                owner.0.borrow_mut().busy.push(name.to_string());
                let v = match self.nest_in(at, "properties defined by properties") {
                    Ok(()) => {
                        let v = self.eval_text(&text, &def_scope, &def_at).map(literal);
                        self.leave();
                        v
                    }
                    Err(e) => Err(e),
                };
                owner.0.borrow_mut().busy.retain(|b| b != name);
                let v = v?;
                owner
                    .0
                    .borrow_mut()
                    .props
                    .insert(name.to_string(), Prop::Value(v.clone()));
                Ok(v)
            }
        }
    }

    /// Processes nodes into `out` (the output parent element).
    fn process(
        &mut self,
        nodes: &[Node],
        scope: &Scope,
        out: &mut OutElem,
    ) -> Result<(), ModelError> {
        for node in nodes {
            match node {
                Node::Text(t, at) => {
                    self.count(1, at)?;
                    if !t.trim().is_empty() {
                        let v = self.text(t, scope, at)?;
                        self.produce(v.len(), at)?;
                        out.children.push(Out::Text(v));
                    }
                }
                Node::Elem(e) if e.xacro => {
                    self.count(1, &e.at)?;
                    self.nest_in(&e.at, "macros and elements")?;
                    let r = self.xacro(e, scope, out);
                    self.leave();
                    r?;
                }
                Node::Elem(e) => {
                    self.count(1, &e.at)?;
                    let mut o = OutElem {
                        name: e.name.clone(),
                        attrs: Vec::new(),
                        children: Vec::new(),
                    };
                    for (k, v) in &e.attrs {
                        if !k.starts_with("xacro:") {
                            let v = self.text(v, scope, &e.at)?;
                            o.attrs.push((k.clone(), v));
                        }
                    }
                    self.emitted(&o, &e.at)?;
                    self.nest_in(&e.at, "elements")?;
                    let r = self.process(&e.children, scope, &mut o);
                    self.leave();
                    r?;
                    out.children.push(Out::Elem(o));
                }
            }
        }
        Ok(())
    }

    /// Counts an output element's name and attributes ([`MAX_OUTPUT_BYTES`]).
    fn emitted(&mut self, o: &OutElem, at: &At) -> Result<(), ModelError> {
        let n = o.name.len()
            + 64
            + o.attrs
                .iter()
                .map(|(k, v)| k.len() + v.len() + 4)
                .sum::<usize>();
        self.produce(n, at)
    }

    fn required<'e>(&self, e: &'e Elem, attr: &str) -> Result<&'e str, ModelError> {
        e.attr(attr).ok_or_else(|| {
            fail(
                &e.at,
                format!("<xacro:{}> needs a {attr}=\"…\" attribute", e.name),
            )
        })
    }

    fn xacro(&mut self, e: &Rc<Elem>, scope: &Scope, out: &mut OutElem) -> Result<(), ModelError> {
        match e.name.as_str() {
            "property" => {
                let name = self.text(self.required(e, "name")?, scope, &e.at)?;
                let target = match e.attr("scope") {
                    None => scope.clone(),
                    Some("parent") => scope.parent_or_self(),
                    Some("global") => scope.global(),
                    Some(other) => return Err(fail(&e.at, format!("<xacro:property name=\"{name}\">: unknown scope \"{other}\" (expected parent or global)"))),
                };
                let prop = match (e.attr("value"), e.attr("default")) {
                    (Some(v), _) => Prop::Lazy(v.to_string(), scope.clone(), e.at.clone()),
                    (None, Some(d)) => {
                        if scope.prop(&name).is_some() {
                            return Ok(());
                        }
                        Prop::Lazy(d.to_string(), scope.clone(), e.at.clone())
                    }
                    (None, None) => Prop::Block(e.children.clone()),
                };
                // A value evaluated now when it is meant for an outer scope (its text may name
                // the macro's parameters, which are gone by the time it is used).
                let prop = match prop {
                    Prop::Lazy(t, s, at) if e.attr("scope").is_some() => {
                        Prop::Value(literal(self.eval_text(&t, &s, &at)?))
                    }
                    p => p,
                };
                target.0.borrow_mut().props.insert(name, prop);
            }
            "macro" => {
                let name = self.required(e, "name")?.to_string();
                let params = parse_params(e.attr("params").unwrap_or(""))
                    .map_err(|m| fail(&e.at, format!("<xacro:macro name=\"{name}\">: {m}")))?;
                scope.0.borrow_mut().macros.insert(
                    name,
                    Rc::new(Macro {
                        params,
                        body: e.children.clone(),
                    }),
                );
            }
            "include" => {
                if e.attr("ns").is_some() {
                    return Err(fail(
                        &e.at,
                        "<xacro:include ns=\"…\"> (namespaced includes) is not supported",
                    ));
                }
                let file = self.text(self.required(e, "filename")?, scope, &e.at)?;
                let path = if Path::new(&file).is_absolute() {
                    PathBuf::from(&file)
                } else {
                    e.at.dir.join(&file)
                };
                let text = input::read_file(&path)
                    .and_then(|bytes| {
                        crate::urdf::decode(&bytes)
                            .map_err(|k| ModelError::new(path.display().to_string(), k))
                    })
                    .map_err(|err| {
                        fail(
                            &e.at,
                            format!(
                                "<xacro:include filename=\"{file}\">: cannot read {}: {}",
                                path.display(),
                                err.kind
                            ),
                        )
                    })?;
                let text = crate::urdf::tolerate(&text).into_owned();
                self.enter(&e.at)?;
                let root = self.parse(
                    &text,
                    &path.display().to_string(),
                    path.parent().unwrap_or(Path::new(".")),
                )?;
                let r = self.process(&root.children, scope, out);
                self.depth -= 1;
                r?;
            }
            "if" | "unless" => {
                let v = self.eval_text(self.required(e, "value")?, scope, &e.at)?;
                let b = v
                    .truth()
                    .map_err(|m| fail(&e.at, format!("<xacro:{} value=…>: {m}", e.name)))?;
                if b == (e.name == "if") {
                    self.process(&e.children, scope, out)?;
                }
            }
            "arg" => {
                let name = self.required(e, "name")?.to_string();
                if !self.args.contains_key(&name) {
                    if let Some(d) = e.attr("default") {
                        let d = self.text(d, scope, &e.at)?;
                        self.args.insert(name, d);
                    }
                }
            }
            "insert_block" => {
                let name = self.text(self.required(e, "name")?, scope, &e.at)?;
                match scope.prop(&name) {
                    Some((Prop::Block(nodes), _)) => self.process(&nodes, scope, out)?,
                    Some(_) => {
                        return Err(fail(
                            &e.at,
                            format!(
                                "<xacro:insert_block name=\"{name}\">: \"{name}\" is not a block"
                            ),
                        ))
                    }
                    None => {
                        return Err(fail(
                            &e.at,
                            format!("<xacro:insert_block name=\"{name}\">: no such block"),
                        ))
                    }
                }
            }
            "element" => {
                let name = self.text(self.required(e, "xacro:name")?, scope, &e.at)?;
                check_name(&name).map_err(|m| {
                    fail(&e.at, format!("<xacro:element xacro:name=\"{name}\">: {m}"))
                })?;
                let mut o = OutElem {
                    name,
                    attrs: Vec::new(),
                    children: Vec::new(),
                };
                for (k, v) in &e.attrs {
                    if !k.starts_with("xacro:") {
                        let v = self.text(v, scope, &e.at)?;
                        o.attrs.push((k.clone(), v));
                    }
                }
                self.process(&e.children, scope, &mut o)?;
                out.children.push(Out::Elem(o));
            }
            "attribute" => {
                let name = self.text(self.required(e, "name")?, scope, &e.at)?;
                check_name(&name)
                    .map_err(|m| fail(&e.at, format!("<xacro:attribute name=\"{name}\">: {m}")))?;
                let value = self.text(self.required(e, "value")?, scope, &e.at)?;
                self.produce(name.len() + value.len() + 4, &e.at)?;
                out.attrs.retain(|(k, _)| *k != name);
                out.attrs.push((name, value));
            }
            "call" => {
                let name = self.text(self.required(e, "macro")?, scope, &e.at)?;
                self.call(e, &name, scope, out)?;
            }
            name => {
                let name = name.to_string();
                self.call(e, &name, scope, out)?;
            }
        }
        Ok(())
    }

    fn enter(&mut self, at: &At) -> Result<(), ModelError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(fail(
                at,
                format!("macros or includes nested more than {MAX_DEPTH} deep (a recursion?)"),
            ));
        }
        Ok(())
    }

    fn call(
        &mut self,
        e: &Rc<Elem>,
        name: &str,
        scope: &Scope,
        out: &mut OutElem,
    ) -> Result<(), ModelError> {
        let Some(m) = scope.macro_(name) else {
            return Err(fail(
                &e.at,
                format!("<xacro:{name}>: no such macro or xacro element"),
            ));
        };
        let inner = Scope::new(Some(scope.clone()));
        let mut blocks = e.children.iter().filter_map(|c| match c {
            Node::Elem(b) => Some(b),
            Node::Text(..) => None,
        });
        for p in &m.params {
            let value = match p.stars {
                1 => Prop::Block(vec![Node::Elem(blocks.next().cloned().ok_or_else(|| {
                    fail(&e.at, format!("<xacro:{name}>: block parameter *{} needs a child element", p.name))
                })?)]),
                2 => Prop::Block(
                    blocks
                        .next()
                        .ok_or_else(|| fail(&e.at, format!("<xacro:{name}>: block parameter **{} needs a child element", p.name)))?
                        .children
                        .clone(),
                ),
                _ => match e.attr(&p.name) {
                    Some(v) => Prop::Value(literal(self.eval_text(v, scope, &e.at)?)),
                    None if p.inherit => match (scope.prop(&p.name), &p.default) {
                        (Some(_), _) => Prop::Value(self.lookup(&p.name, scope, &e.at)?),
                        (None, Some(d)) => Prop::Value(literal(self.eval_text(d, scope, &e.at)?)),
                        (None, None) => return Err(fail(&e.at, format!("<xacro:{name}>: parameter {} (:=^) is not given and no outer property has that name", p.name))),
                    },
                    None => match &p.default {
                        Some(d) => Prop::Value(literal(self.eval_text(d, scope, &e.at)?)),
                        None => return Err(fail(&e.at, format!("<xacro:{name}>: missing parameter {}", p.name))),
                    },
                },
            };
            inner.0.borrow_mut().props.insert(p.name.clone(), value);
        }
        let params: Vec<&str> = m.params.iter().map(|p| p.name.as_str()).collect();
        for (k, _) in &e.attrs {
            let known = params.contains(&k.as_str()) || (e.name == "call" && k == "macro");
            if !known {
                return Err(fail(
                    &e.at,
                    format!(
                        "<xacro:{name}>: unknown parameter {k} (parameters: {})",
                        params.join(", ")
                    ),
                ));
            }
        }
        self.enter(&e.at)?;
        let r = self.process(&m.body, &inner, out);
        self.depth -= 1;
        r
    }
}

/// An XML name (what `<xacro:element>` and `<xacro:attribute>` may create): a letter or `_`
/// first, then letters, digits, `_`, `-`, `.` and at most one `:` — never markup.
fn check_name(name: &str) -> Result<(), String> {
    let mut cs = name.chars();
    let first_ok = cs.next().is_some_and(|c| c.is_alphabetic() || c == '_');
    let rest_ok = cs.all(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | ':'));
    if first_ok && rest_ok && name.matches(':').count() <= 1 && !name.ends_with(':') {
        Ok(())
    } else {
        Err("not an XML name".into())
    }
}

/// The index of the bracket closing the one opened just before `from`.
fn matching(s: &str, from: usize, open: char, close: char) -> Option<usize> {
    let mut depth = 1;
    let mut quote: Option<char> = None;
    for (i, c) in s[from..].char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (Some(_), _) => {}
            (None, '\'' | '"') => quote = Some(c),
            (None, c) if c == open => depth += 1,
            (None, c) if c == close => {
                depth -= 1;
                if depth == 0 {
                    return Some(from + i);
                }
            }
            _ => {}
        }
    }
    None
}

/// Adds `xmlns:xacro` to the root element of a file that uses the prefix without declaring it.
fn declare_xacro(text: &str) -> Option<String> {
    let mut i = 0;
    loop {
        let start = i + text[i..].find('<')?;
        let next = text[start + 1..].chars().next()?;
        if next == '?' || next == '!' {
            i = start + 1;
            continue;
        }
        let name_end = start
            + 1
            + text[start + 1..].find(|c: char| c.is_whitespace() || c == '>' || c == '/')?;
        let mut s = String::with_capacity(text.len() + 48);
        s.push_str(&text[..name_end]);
        s.push_str(" xmlns:xacro=\"http://www.ros.org/wiki/xacro\"");
        s.push_str(&text[name_end..]);
        return Some(s);
    }
}

/// One parsed file turned into owned nodes (recursion bounded by
/// [`input::MAX_ELEMENT_DEPTH`], checked when it was parsed).
struct Convert<'t> {
    text: &'t str,
    lines: &'t Lines,
    file: &'t Rc<str>,
    dir: &'t Rc<Path>,
}

impl Convert<'_> {
    fn elem(&self, n: roxmltree::Node) -> Rc<Elem> {
        let xacro = n
            .tag_name()
            .namespace()
            .is_some_and(|ns| XACRO_NAMESPACES.contains(&ns));
        let attrs = n
            .attributes()
            .filter_map(|a| match a.namespace() {
                None => Some((a.name().to_string(), a.value().to_string())),
                Some(ns) if XACRO_NAMESPACES.contains(&ns) => {
                    Some((format!("xacro:{}", a.name()), a.value().to_string()))
                }
                Some(_) => None,
            })
            .collect();
        let at = At {
            file: self.file.clone(),
            dir: self.dir.clone(),
            line: self.lines.line(n.range().start),
        };
        let children = n
            .children()
            .filter_map(|c| {
                if c.is_element() {
                    let ns = c.tag_name().namespace();
                    if ns.is_some_and(|ns| XACRO_NAMESPACES.contains(&ns)) {
                        Some(Node::Elem(self.elem(c)))
                    } else if input::is_prefixed(self.text, &c) {
                        // Another format's element (a Gazebo plugin's): left out.
                        None
                    } else {
                        Some(Node::Elem(self.elem(c)))
                    }
                } else if c.is_text() {
                    c.text().map(|t| Node::Text(t.to_string(), at.clone()))
                } else {
                    None
                }
            })
            .collect();
        Rc::new(Elem {
            name: n.tag_name().name().to_string(),
            xacro,
            attrs,
            children,
            at,
        })
    }
}

/// `params="a b:=1 *blk **blks c:=^ d:=^|2"`.
fn parse_params(s: &str) -> Result<Vec<Param>, String> {
    split_params(s)?
        .into_iter()
        .map(|w| {
            let w = w.as_str();
            let stars = w.chars().take_while(|&c| c == '*').count();
            let w = &w[stars..];
            if stars > 2 || w.is_empty() {
                return Err(format!("bad parameter \"{w}\""));
            }
            let (name, default) = match w.split_once(":=").or_else(|| w.split_once('=')) {
                Some((n, d)) => (n, Some(d)),
                None => (w, None),
            };
            let (inherit, default) = match default {
                Some(d) if d.starts_with('^') => {
                    (true, d.strip_prefix("^|").map(|x| x.to_string()))
                }
                Some(d) => (false, Some(unquote(d).to_string())),
                None => (false, None),
            };
            Ok(Param {
                name: name.to_string(),
                stars,
                default,
                inherit,
            })
        })
        .collect()
}

/// Splits a macro's `params` on whitespace outside quotes (`xyz:='0 0 0' rpy:="0 0 0"`, as
/// in Franka's panda_arm.xacro).
fn split_params(s: &str) -> Result<Vec<String>, String> {
    let mut words = Vec::new();
    let mut word = String::new();
    let mut quote: Option<char> = None;
    for c in s.chars() {
        match quote {
            Some(q) if c == q => {
                quote = None;
                word.push(c);
            }
            Some(_) => word.push(c),
            None if c == '\'' || c == '"' => {
                quote = Some(c);
                word.push(c);
            }
            None if c.is_whitespace() => {
                if !word.is_empty() {
                    words.push(std::mem::take(&mut word));
                }
            }
            None => word.push(c),
        }
    }
    if quote.is_some() {
        return Err(format!("unclosed quote in params=\"{s}\""));
    }
    if !word.is_empty() {
        words.push(word);
    }
    Ok(words)
}

/// A default written in quotes, without them.
fn unquote(d: &str) -> &str {
    for q in ['\'', '"'] {
        if d.len() >= 2 && d.starts_with(q) && d.ends_with(q) {
            return &d[1..d.len() - 1];
        }
    }
    d
}

// ---------------------------------------------------------------------------------------------
// Values and expressions (the Python subset xacro files use).

/// A value of a `${…}` expression.
#[derive(Debug, Clone, PartialEq)]
enum Value {
    Int(i64),
    Float(f64),
    Bool(bool),
    Str(String),
}

impl Value {
    /// As Python's `str()` writes it (floats shortest round-trip, as Python's repr).
    fn to_text(&self) -> String {
        match self {
            Value::Int(i) => i.to_string(),
            Value::Float(x) => python_repr(*x),
            Value::Bool(b) => if *b { "True" } else { "False" }.into(),
            Value::Str(s) => s.clone(),
        }
    }

    fn num(&self) -> Option<f64> {
        match self {
            Value::Int(i) => Some(*i as f64),
            Value::Float(x) => Some(*x),
            Value::Bool(b) => Some(f64::from(u8::from(*b))),
            Value::Str(_) => None,
        }
    }

    fn truth(&self) -> Result<bool, String> {
        match self {
            Value::Bool(b) => Ok(*b),
            Value::Int(i) => Ok(*i != 0),
            Value::Float(x) => Ok(*x != 0.0),
            // xacro's get_boolean_value: true/false words, else an integer's truth.
            Value::Str(s) => match s.trim() {
                "true" | "True" => Ok(true),
                "false" | "False" => Ok(false),
                other => other
                    .parse::<i64>()
                    .map(|i| i != 0)
                    .map_err(|_| format!("\"{other}\" is not a boolean")),
            },
        }
    }
}

/// xacro's literal conversion of a property's text: 'quoted' → the string, then int, float,
/// boolean, else the string itself.
fn literal(v: Value) -> Value {
    let Value::Str(s) = &v else { return v };
    let t = s.trim();
    if t.len() >= 2 && t.starts_with('\'') && t.ends_with('\'') {
        return Value::Str(t[1..t.len() - 1].to_string());
    }
    // As xacro: text with an underscore stays text (Python would read `1_0` as 10).
    if t.contains('_') {
        return v;
    }
    if let Ok(i) = t.parse::<i64>() {
        return Value::Int(i);
    }
    if let Some(x) = python_float(t) {
        return Value::Float(x);
    }
    match t {
        "true" | "True" => Value::Bool(true),
        "false" | "False" => Value::Bool(false),
        _ => v,
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(Value),
    Str(String),
    Name(String),
    Op(&'static str),
}

fn lex(s: &str) -> Result<Vec<Tok>, String> {
    const OPS: [&str; 22] = [
        "**", "//", "==", "!=", "<=", ">=", "+", "-", "*", "/", "%", "<", ">", "(", ")", ",", ".",
        "[", "]", "{", "}", ":",
    ];
    let mut out = Vec::new();
    let cs: Vec<char> = s.chars().collect();
    let mut i = 0;
    while i < cs.len() {
        let c = cs[i];
        if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_digit()
            || (c == '.' && cs.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < cs.len()
                && (cs[i].is_ascii_alphanumeric()
                    || cs[i] == '.'
                    || ((cs[i] == '+' || cs[i] == '-') && matches!(cs[i - 1], 'e' | 'E')))
            {
                i += 1;
            }
            let t: String = cs[start..i].iter().collect();
            let v = match t.parse::<i64>() {
                Ok(n) => Value::Int(n),
                Err(_) if t.chars().all(|c| c.is_ascii_digit()) => {
                    return Err(format!("integer {t} is beyond 64 bits (Python's unbounded integers are not supported)"));
                }
                Err(_) => Value::Float(
                    t.parse::<f64>()
                        .ok()
                        .filter(|_| !t.contains(['i', 'I', 'n', 'N']))
                        .ok_or_else(|| format!("bad number \"{t}\""))?,
                ),
            };
            out.push(Tok::Num(v));
        } else if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < cs.len() && (cs[i].is_alphanumeric() || cs[i] == '_') {
                i += 1;
            }
            out.push(Tok::Name(cs[start..i].iter().collect()));
        } else if c == '\'' || c == '"' {
            let start = i + 1;
            i += 1;
            while i < cs.len() && cs[i] != c {
                i += 1;
            }
            if i == cs.len() {
                return Err("unclosed string".into());
            }
            out.push(Tok::Str(cs[start..i].iter().collect()));
            i += 1;
        } else {
            let rest: String = cs[i..cs.len().min(i + 2)].iter().collect();
            let op = OPS
                .iter()
                .find(|o| rest.starts_with(**o))
                .ok_or_else(|| format!("unexpected character '{c}'"))?;
            out.push(Tok::Op(op));
            i += op.chars().count();
        }
    }
    Ok(out)
}

struct Parser<'a, 'o> {
    x: &'a mut Expander<'o>,
    tokens: Vec<Tok>,
    pos: usize,
    scope: &'a Scope,
    at: &'a At,
    src: &'a str,
    /// Above zero: parsing only, no evaluation (the branch of `a if c else b`, `and`, `or`
    /// that Python does not evaluate). Values are placeholders and nothing fails but syntax.
    skip: u32,
}

/// The placeholder value of an expression parsed but not evaluated.
const SKIPPED: Value = Value::Int(0);

impl Parser<'_, '_> {
    fn err(&self, m: impl std::fmt::Display) -> ModelError {
        fail(self.at, format!("${{{}}}: {m}", self.src))
    }

    fn peek(&self) -> Option<&Tok> {
        self.tokens.get(self.pos)
    }

    fn eat_op(&mut self, op: &str) -> bool {
        if matches!(self.peek(), Some(Tok::Op(o)) if *o == op) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    fn eat_name(&mut self, n: &str) -> bool {
        if matches!(self.peek(), Some(Tok::Name(x)) if x == n) {
            self.pos += 1;
            true
        } else {
            false
        }
    }

    /// Runs `f` one nesting level deeper ([`MAX_NESTING`]).
    fn nested(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<Value, ModelError>,
    ) -> Result<Value, ModelError> {
        self.x.nest_in(self.at, "expressions")?;
        let r = f(self);
        self.x.leave();
        r
    }

    /// Runs `f` without evaluating (see [`Parser::skip`]).
    fn skipping(
        &mut self,
        f: impl FnOnce(&mut Self) -> Result<Value, ModelError>,
    ) -> Result<Value, ModelError> {
        self.skip += 1;
        let r = f(self);
        self.skip -= 1;
        r.map(|_| SKIPPED)
    }

    /// Python's truth of a value inside an expression: a non-empty string is true.
    fn truthy(&self, v: &Value) -> bool {
        match v {
            Value::Bool(b) => *b,
            Value::Int(i) => *i != 0,
            Value::Float(x) => *x != 0.0,
            Value::Str(s) => !s.is_empty(),
        }
    }

    /// `v if c else other`: as Python, only the branch chosen is evaluated (the value side is
    /// parsed first here, so an error in it counts only when it is chosen).
    fn ternary(&mut self) -> Result<Value, ModelError> {
        self.nested(|p| {
            let start = p.pos;
            let v = match p.or() {
                Ok(v) => Ok(v),
                Err(e) if p.skip == 0 => {
                    // Find where the value ends, then decide whether its error matters.
                    p.pos = start;
                    p.skipping(Self::or)?;
                    Err(e)
                }
                Err(e) => return Err(e),
            };
            if !p.eat_name("if") {
                return v;
            }
            if p.skip > 0 {
                p.or()?;
                if !p.eat_name("else") {
                    return Err(p.err("'if' without 'else'"));
                }
                p.ternary()?;
                return Ok(SKIPPED);
            }
            let c = p.or()?;
            if !p.eat_name("else") {
                return Err(p.err("'if' without 'else'"));
            }
            if p.truthy(&c) {
                p.skipping(Self::ternary)?;
                v
            } else {
                p.ternary()
            }
        })
    }

    fn or(&mut self) -> Result<Value, ModelError> {
        let mut v = self.and()?;
        while self.eat_name("or") {
            if self.skip > 0 || self.truthy(&v) {
                self.skipping(Self::and)?;
            } else {
                v = self.and()?;
            }
        }
        Ok(v)
    }

    fn and(&mut self) -> Result<Value, ModelError> {
        let mut v = self.not()?;
        while self.eat_name("and") {
            if self.skip > 0 || !self.truthy(&v) {
                self.skipping(Self::not)?;
            } else {
                v = self.not()?;
            }
        }
        Ok(v)
    }

    fn not(&mut self) -> Result<Value, ModelError> {
        if self.eat_name("not") {
            let v = self.nested(Self::not)?;
            return Ok(Value::Bool(!self.truthy(&v)));
        }
        self.cmp()
    }

    fn cmp(&mut self) -> Result<Value, ModelError> {
        let l = self.add()?;
        for op in ["==", "!=", "<=", ">=", "<", ">"] {
            if self.eat_op(op) {
                let r = self.add()?;
                if self.skip > 0 {
                    return Ok(SKIPPED);
                }
                // Numbers compare as numbers, anything with a string as text (NaN: unordered).
                let ord = match (l.num(), r.num()) {
                    (Some(a), Some(b))
                        if !matches!((&l, &r), (Value::Str(_), _) | (_, Value::Str(_))) =>
                    {
                        a.partial_cmp(&b)
                    }
                    _ => Some(l.to_text().cmp(&r.to_text())),
                };
                use std::cmp::Ordering::{Equal, Greater, Less};
                let b = match (op, ord) {
                    ("==", o) => o == Some(Equal),
                    ("!=", o) => o != Some(Equal),
                    ("<=", o) => matches!(o, Some(Less | Equal)),
                    (">=", o) => matches!(o, Some(Greater | Equal)),
                    ("<", o) => o == Some(Less),
                    (_, o) => o == Some(Greater),
                };
                return Ok(Value::Bool(b));
            }
        }
        Ok(l)
    }

    fn add(&mut self) -> Result<Value, ModelError> {
        let mut v = self.mul()?;
        loop {
            if self.eat_op("+") {
                let r = self.mul()?;
                v = match (&v, &r) {
                    _ if self.skip > 0 => SKIPPED,
                    (Value::Str(a), Value::Str(b)) => {
                        if a.len() + b.len() > MAX_OUTPUT_BYTES {
                            return Err(self.err(format!(
                                "a string longer than {} MiB",
                                MAX_OUTPUT_BYTES >> 20
                            )));
                        }
                        Value::Str(format!("{a}{b}"))
                    }
                    _ => self.arith(&v, &r, "+")?,
                };
            } else if self.eat_op("-") {
                let r = self.mul()?;
                v = self.arith(&v, &r, "-")?;
            } else {
                return Ok(v);
            }
        }
    }

    fn mul(&mut self) -> Result<Value, ModelError> {
        let mut v = self.unary()?;
        loop {
            let op = ["*", "//", "/", "%"].into_iter().find(|op| self.eat_op(op));
            match op {
                Some(op) => {
                    let r = self.unary()?;
                    v = self.arith(&v, &r, op)?;
                }
                None => return Ok(v),
            }
        }
    }

    fn unary(&mut self) -> Result<Value, ModelError> {
        if self.eat_op("-") {
            let v = self.nested(Self::unary)?;
            return match v {
                _ if self.skip > 0 => Ok(SKIPPED),
                Value::Int(i) => i
                    .checked_neg()
                    .map(Value::Int)
                    .ok_or_else(|| self.overflow()),
                other => Ok(Value::Float(
                    -other.num().ok_or_else(|| self.err("'-' on a string"))?,
                )),
            };
        }
        if self.eat_op("+") {
            return self.nested(Self::unary);
        }
        self.power()
    }

    fn power(&mut self) -> Result<Value, ModelError> {
        let base = self.postfix()?;
        if self.eat_op("**") {
            let e = self.nested(Self::unary)?;
            return self.arith(&base, &e, "**");
        }
        Ok(base)
    }

    /// An integer result beyond 64 bits: Python's integers have no bound, ours do.
    fn overflow(&self) -> ModelError {
        self.err("integer result beyond 64 bits (Python's unbounded integers are not supported)")
    }

    fn arith(&self, a: &Value, b: &Value, op: &str) -> Result<Value, ModelError> {
        if self.skip > 0 {
            return Ok(SKIPPED);
        }
        if let (Value::Int(x), Value::Int(y)) = (a, b) {
            let (x, y) = (*x, *y);
            // None: not an integer operation (division by zero, a negative power), handled
            // below as Python does; Some(None): the integer result overflows.
            let r: Option<Option<i64>> = match op {
                "+" => Some(x.checked_add(y)),
                "-" => Some(x.checked_sub(y)),
                "*" => Some(x.checked_mul(y)),
                "//" if y != 0 => Some(if y == -1 {
                    x.checked_neg()
                } else {
                    let q = x / y;
                    Some(if x % y != 0 && ((x < 0) != (y < 0)) {
                        q - 1
                    } else {
                        q
                    })
                }),
                "%" if y != 0 => Some(if y == -1 {
                    Some(0)
                } else {
                    let r = x % y;
                    Some(if r != 0 && ((r < 0) != (y < 0)) {
                        r + y
                    } else {
                        r
                    })
                }),
                "**" if y >= 0 => Some(match x {
                    0 | 1 => Some(if y == 0 { 1 } else { x }),
                    -1 => Some(if y % 2 == 0 { 1 } else { -1 }),
                    _ => u32::try_from(y).ok().and_then(|y| x.checked_pow(y)),
                }),
                _ => None,
            };
            match r {
                Some(Some(r)) => return Ok(Value::Int(r)),
                Some(None) => return Err(self.overflow()),
                None => {}
            }
        }
        let (x, y) = match (a.num(), b.num()) {
            (Some(x), Some(y)) if !matches!(a, Value::Str(_)) && !matches!(b, Value::Str(_)) => {
                (x, y)
            }
            _ => {
                return Err(self.err(format!(
                    "cannot apply '{op}' to {} and {}",
                    a.to_text(),
                    b.to_text()
                )))
            }
        };
        if (op == "/" || op == "//" || op == "%") && y == 0.0 {
            return Err(self.err("division by zero"));
        }
        Ok(Value::Float(match op {
            "+" => x + y,
            "-" => x - y,
            "*" => x * y,
            "/" => x / y,
            "//" => (x / y).floor(),
            "%" => x - y * (x / y).floor(),
            _ => x.powf(y),
        }))
    }

    fn postfix(&mut self) -> Result<Value, ModelError> {
        let tok = self
            .tokens
            .get(self.pos)
            .cloned()
            .ok_or_else(|| self.err("unexpected end"))?;
        self.pos += 1;
        match tok {
            Tok::Num(v) => Ok(v),
            Tok::Str(s) => Ok(Value::Str(s)),
            Tok::Op("(") => {
                let v = self.ternary()?;
                if !self.eat_op(")") {
                    return Err(self.err("missing ')'"));
                }
                Ok(v)
            }
            Tok::Name(mut name) => {
                if name == "math" && self.eat_op(".") {
                    match self.tokens.get(self.pos).cloned() {
                        Some(Tok::Name(f)) => {
                            self.pos += 1;
                            name = f;
                        }
                        _ => return Err(self.err("'math.' without a name")),
                    }
                }
                if self.eat_op("(") {
                    let mut args = Vec::new();
                    if !self.eat_op(")") {
                        loop {
                            args.push(self.ternary()?);
                            if self.eat_op(")") {
                                break;
                            }
                            if !self.eat_op(",") {
                                return Err(self.err(format!("{name}(…): expected ',' or ')'")));
                            }
                        }
                    }
                    if self.skip > 0 {
                        return Ok(SKIPPED);
                    }
                    return self.call(&name, &args);
                }
                if self.skip > 0 {
                    return Ok(SKIPPED);
                }
                match name.as_str() {
                    "pi" => Ok(Value::Float(std::f64::consts::PI)),
                    "e" if self.scope.prop("e").is_none() => Ok(Value::Float(std::f64::consts::E)),
                    "inf" => Ok(Value::Float(f64::INFINITY)),
                    "nan" => Ok(Value::Float(f64::NAN)),
                    "True" | "true" => Ok(Value::Bool(true)),
                    "False" | "false" => Ok(Value::Bool(false)),
                    _ => self.x.lookup(&name, self.scope, self.at),
                }
            }
            Tok::Op(o) => Err(self.err(format!("unexpected '{o}'"))),
        }
    }

    /// A float as a Python int (`int()`, `math.floor`, `round`): NaN, ±inf and values beyond
    /// 64 bits are errors, as Python's are (or would need unbounded integers).
    fn to_int(&self, f: &str, x: f64) -> Result<Value, ModelError> {
        if x.is_nan() {
            return Err(self.err(format!("{f}(): cannot convert NaN to an integer")));
        }
        if x.is_infinite() {
            return Err(self.err(format!("{f}(): cannot convert infinity to an integer")));
        }
        if x.abs() >= 2f64.powi(63) {
            return Err(self.overflow());
        }
        Ok(Value::Int(x as i64))
    }

    fn call(&self, f: &str, args: &[Value]) -> Result<Value, ModelError> {
        let nums = || -> Result<Vec<f64>, ModelError> {
            args.iter()
                .map(|a| {
                    a.num().ok_or_else(|| {
                        self.err(format!("{f}(): \"{}\" is not a number", a.to_text()))
                    })
                })
                .collect()
        };
        let one = |g: fn(f64) -> f64| -> Result<Value, ModelError> {
            match nums()?.as_slice() {
                [x] => Ok(Value::Float(g(*x))),
                _ => Err(self.err(format!("{f}() takes one argument"))),
            }
        };
        let one_num = || -> Result<f64, ModelError> {
            match nums()?.as_slice() {
                [x] => Ok(*x),
                _ => Err(self.err(format!("{f}() takes one argument"))),
            }
        };
        match f {
            "radians" => one(f64::to_radians),
            "degrees" => one(f64::to_degrees),
            "sin" => one(f64::sin),
            "cos" => one(f64::cos),
            "tan" => one(f64::tan),
            "asin" => one(f64::asin),
            "acos" => one(f64::acos),
            "atan" => one(f64::atan),
            "sinh" => one(f64::sinh),
            "cosh" => one(f64::cosh),
            "tanh" => one(f64::tanh),
            "sqrt" => one(f64::sqrt),
            "exp" => one(f64::exp),
            "log10" => one(f64::log10),
            "fabs" => one(f64::abs),
            "floor" => match args {
                [Value::Int(i)] => Ok(Value::Int(*i)),
                _ => self.to_int(f, one_num()?.floor()),
            },
            "ceil" => match args {
                [Value::Int(i)] => Ok(Value::Int(*i)),
                _ => self.to_int(f, one_num()?.ceil()),
            },
            "log" => match nums()?.as_slice() {
                [x] => Ok(Value::Float(x.ln())),
                [x, b] => Ok(Value::Float(x.ln() / b.ln())),
                _ => Err(self.err("log() takes one or two arguments")),
            },
            "atan2" | "pow" | "hypot" | "copysign" | "fmod" => match nums()?.as_slice() {
                [y, x] => Ok(Value::Float(match f {
                    "atan2" => y.atan2(*x),
                    "pow" => y.powf(*x),
                    "hypot" => y.hypot(*x),
                    "copysign" => y.copysign(*x),
                    _ => y % x,
                })),
                _ => Err(self.err(format!("{f}() takes two arguments"))),
            },
            "abs" => match args {
                [Value::Int(i)] => i
                    .checked_abs()
                    .map(Value::Int)
                    .ok_or_else(|| self.overflow()),
                _ => one(f64::abs),
            },
            "min" | "max" => {
                let v = nums()?;
                if v.is_empty() {
                    return Err(self.err(format!("{f}() needs arguments")));
                }
                let pick = if f == "min" {
                    v.iter().cloned().fold(f64::INFINITY, f64::min)
                } else {
                    v.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
                };
                let i = v.iter().position(|x| *x == pick).unwrap_or(0);
                Ok(args[i].clone())
            }
            "float" => match args {
                [Value::Str(s)] => python_float(s)
                    .map(Value::Float)
                    .ok_or_else(|| self.err(format!("float(\"{s}\"): not a number"))),
                _ => one(|x| x),
            },
            "int" => match args {
                [Value::Str(s)] => s.trim().parse::<i64>().map(Value::Int).map_err(|_| {
                    self.err(format!("int(\"{s}\"): not an integer (or beyond 64 bits)"))
                }),
                [Value::Int(i)] => Ok(Value::Int(*i)),
                _ => self.to_int(f, one_num()?.trunc()),
            },
            "round" => match args {
                [Value::Int(i)] => Ok(Value::Int(*i)),
                [Value::Int(i), Value::Int(n)] if *n >= 0 => Ok(Value::Int(*i)),
                [Value::Int(i), Value::Int(n)] => {
                    // Python: an int rounded to 10^-n, halves to even.
                    let p = 10i64.checked_pow(u32::try_from(-*n).unwrap_or(u32::MAX));
                    match p {
                        None => Ok(Value::Int(0)),
                        Some(p) => {
                            let r = round_half_even(*i as f64 / p as f64) as i64;
                            r.checked_mul(p)
                                .map(Value::Int)
                                .ok_or_else(|| self.overflow())
                        }
                    }
                }
                [_] => self.to_int(f, round_half_even(one_num()?)),
                [x, Value::Int(n)] => {
                    let x = x.num().ok_or_else(|| self.err("round(): not a number"))?;
                    Ok(Value::Float(python_round(x, *n)))
                }
                [_, _] => Err(self.err("round(): the number of digits must be an integer")),
                _ => Err(self.err("round() takes one or two arguments")),
            },
            "str" => match args {
                [v] => Ok(Value::Str(v.to_text())),
                _ => Err(self.err("str() takes one argument")),
            },
            "bool" => match args {
                [v] => Ok(Value::Bool(self.truthy(v))),
                _ => Err(self.err("bool() takes one argument")),
            },
            _ => Err(self.err(format!("unknown function {f}()"))),
        }
    }
}

/// Python's `round`: halves to even.
fn round_half_even(x: f64) -> f64 {
    let r = x.round();
    if (x - x.trunc()).abs() == 0.5 && r % 2.0 != 0.0 {
        r - x.signum()
    } else {
        r
    }
}

/// Python's `round(x, n)` for a float: the exact binary value rounded to n decimals, halves
/// to even (so `round(2.675, 2)` is 2.67: 2.675 is stored as 2.67499999…).
fn python_round(x: f64, n: i64) -> f64 {
    if !x.is_finite() || n > 330 {
        return x;
    }
    if n >= 0 {
        // Rust's fixed-precision formatting rounds the exact value, ties to even.
        format!("{x:.prec$}", prec = n as usize)
            .parse()
            .unwrap_or(x)
    } else {
        let p = 10f64.powi((-n).min(400) as i32);
        if p.is_infinite() {
            return 0.0 * x;
        }
        round_half_even(x / p) * p
    }
}

/// Python's `float(text)`: surrounding whitespace, `inf`/`nan`/`infinity` in any case, no
/// underscores (PEP 515 digits are not accepted here).
fn python_float(s: &str) -> Option<f64> {
    let t = s.trim();
    if t.contains('_') {
        return None;
    }
    t.parse::<f64>().ok()
}

/// Python's `repr` of a float (which `str` gives too): the shortest digits that read back
/// the same, fixed notation for 1e-4 ≤ |x| < 1e16, else `d.ddde±XX` with at least two
/// exponent digits (`1e-07`, `1.5e+16`).
fn python_repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf" } else { "-inf" }.into();
    }
    if x == 0.0 {
        return if x.is_sign_negative() { "-0.0" } else { "0.0" }.into();
    }
    // Shortest round-trip digits and the decimal exponent, from Rust's `{:e}`.
    let sci = format!("{x:e}");
    let (mantissa, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    let (sign, mantissa) = match mantissa.strip_prefix('-') {
        Some(m) => ("-", m),
        None => ("", mantissa),
    };
    let digits: String = mantissa.chars().filter(|c| *c != '.').collect();
    if (-4..16).contains(&exp) {
        let n = digits.len() as i32;
        let s = if exp < 0 {
            format!("0.{}{}", "0".repeat((-exp - 1) as usize), digits)
        } else if exp + 1 >= n {
            format!("{}{}.0", digits, "0".repeat((exp + 1 - n) as usize))
        } else {
            let (a, b) = digits.split_at((exp + 1) as usize);
            format!("{a}.{b}")
        };
        format!("{sign}{s}")
    } else {
        let m = if digits.len() > 1 {
            format!("{}.{}", &digits[..1], &digits[1..])
        } else {
            digits
        };
        let es = if exp < 0 { '-' } else { '+' };
        format!("{sign}{m}e{es}{:02}", exp.abs())
    }
}

/// A folder named `name` at most `depth` levels below `root` (breadth first, sorted, so the
/// answer does not depend on the file system's order).
fn find_below(root: &Path, name: &str, depth: usize) -> Option<PathBuf> {
    if root.file_name().is_some_and(|n| n == name) && root.is_dir() {
        return Some(root.to_path_buf());
    }
    let mut level = vec![root.to_path_buf()];
    for _ in 0..depth {
        let mut next = Vec::new();
        for dir in &level {
            let Ok(rd) = std::fs::read_dir(dir) else {
                continue;
            };
            let mut subs: Vec<PathBuf> = rd
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.is_dir())
                .collect();
            subs.sort();
            if let Some(hit) = subs
                .iter()
                .find(|p| p.file_name().is_some_and(|n| n == name))
            {
                return Some(hit.clone());
            }
            next.extend(subs);
        }
        level = next;
    }
    None
}
