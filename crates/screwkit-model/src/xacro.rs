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
    match roxmltree::Document::parse_with_options(text, parse_options()) {
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

fn parse_options<'a>() -> roxmltree::ParsingOptions<'a> {
    roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    }
}

/// Expands a xacro file into URDF text.
pub fn expand_file(path: impl AsRef<Path>, opts: &XacroOptions) -> Result<String, ModelError> {
    let path = path.as_ref();
    let label = path.display().to_string();
    let bytes = std::fs::read(path)
        .map_err(|e| ModelError::new(label.clone(), ErrorKind::Io(e.to_string())))?;
    let text = crate::urdf::decode(&bytes).map_err(|k| ModelError::new(label.clone(), k))?;
    expand_str(&text, &label, path.parent().unwrap_or(Path::new(".")), opts)
}

/// Expands xacro text into URDF text; `source` names it in errors, `dir` is where relative
/// includes are found.
pub fn expand_str(
    text: &str,
    source: &str,
    dir: &Path,
    opts: &XacroOptions,
) -> Result<String, ModelError> {
    let mut x = Expander {
        opts,
        args: opts.args.iter().cloned().collect(),
        depth: 0,
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
}

const MAX_DEPTH: usize = 200;

fn fail(at: &At, what: impl std::fmt::Display) -> ModelError {
    ModelError::new(
        format!("{}:{}", at.file, at.line),
        ErrorKind::XacroExpand(what.to_string()),
    )
}

impl Expander<'_> {
    /// Parses a file's text into owned nodes and returns its root element.
    fn parse(&mut self, text: &str, source: &str, dir: &Path) -> Result<Rc<Elem>, ModelError> {
        let file: Rc<str> = source.into();
        let dir: Rc<Path> = dir.into();
        let declared;
        let text = match roxmltree::Document::parse_with_options(text, parse_options()) {
            Err(e) if e.to_string().contains("xacro") => {
                // `xacro:` used without declaring it: declare it on the root element.
                declared = declare_xacro(text)
                    .ok_or_else(|| ModelError::new(source, ErrorKind::Xml(e.to_string())))?;
                declared.as_str()
            }
            _ => text,
        };
        let doc = roxmltree::Document::parse_with_options(text, parse_options())
            .map_err(|e| ModelError::new(source, ErrorKind::Xml(e.to_string())))?;
        Ok(convert(&doc, doc.root_element(), &file, &dir))
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
            _ => Value::Str(parts.iter().map(Value::to_text).collect()),
        })
    }

    fn expr(&mut self, src: &str, scope: &Scope, at: &At) -> Result<Value, ModelError> {
        let tokens = lex(src).map_err(|e| fail(at, format!("${{{src}}}: {e}")))?;
        let mut p = Parser {
            x: self,
            tokens,
            pos: 0,
            scope,
            at,
            src,
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
        let split = |v: std::ffi::OsString| std::env::split_paths(&v).collect::<Vec<_>>();
        if let Some(v) = std::env::var_os("ROS_PACKAGE_PATH") {
            roots.extend(split(v));
        }
        for root in &roots {
            if let Some(found) = find_below(root, pkg, 3) {
                return Ok(found.display().to_string());
            }
        }
        if let Some(v) = std::env::var_os("AMENT_PREFIX_PATH") {
            for prefix in split(v) {
                let d = prefix.join("share").join(pkg);
                if d.is_dir() {
                    return Ok(d.display().to_string());
                }
            }
        }
        Err(fail(
            at,
            format!("$(find {pkg}): package not found (give its parent folder with --package-path, or set ROS_PACKAGE_PATH)"),
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
                let v = self.eval_text(&text, &def_scope, &def_at).map(literal);
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
                    if !t.trim().is_empty() {
                        let v = self.text(t, scope, at)?;
                        out.children.push(Out::Text(v));
                    }
                }
                Node::Elem(e) if e.xacro => self.xacro(e, scope, out)?,
                Node::Elem(e) => {
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
                    self.process(&e.children, scope, &mut o)?;
                    out.children.push(Out::Elem(o));
                }
            }
        }
        Ok(())
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
                let text = std::fs::read_to_string(&path).map_err(|err| {
                    fail(
                        &e.at,
                        format!(
                            "<xacro:include filename=\"{file}\">: cannot read {}: {err}",
                            path.display()
                        ),
                    )
                })?;
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
                let value = self.text(self.required(e, "value")?, scope, &e.at)?;
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

fn convert(
    doc: &roxmltree::Document,
    n: roxmltree::Node,
    file: &Rc<str>,
    dir: &Rc<Path>,
) -> Rc<Elem> {
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
        file: file.clone(),
        dir: dir.clone(),
        line: doc.text_pos_at(n.range().start).row,
    };
    let children = n
        .children()
        .filter_map(|c| {
            if c.is_element() {
                match c.tag_name().namespace() {
                    None => Some(Node::Elem(convert(doc, c, file, dir))),
                    Some(ns) if XACRO_NAMESPACES.contains(&ns) => {
                        Some(Node::Elem(convert(doc, c, file, dir)))
                    }
                    Some(_) => None,
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

/// `params="a b:=1 *blk **blks c:=^ d:=^|2"`.
fn parse_params(s: &str) -> Result<Vec<Param>, String> {
    s.split_whitespace()
        .map(|w| {
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
                Some(d) => (false, Some(d.trim_matches('\'').to_string())),
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
            Value::Float(x) => {
                if x.is_finite() && x.fract() == 0.0 && x.abs() < 1e16 {
                    format!("{x:.1}")
                } else if x.is_nan() {
                    "nan".into()
                } else if x.is_infinite() {
                    if *x > 0.0 {
                        "inf".into()
                    } else {
                        "-inf".into()
                    }
                } else {
                    format!("{x:?}")
                }
            }
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
            Value::Str(s) => match s.trim() {
                "true" | "True" | "1" => Ok(true),
                "false" | "False" | "0" => Ok(false),
                other => Err(format!("\"{other}\" is not a boolean")),
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
    if let Ok(i) = t.parse::<i64>() {
        return Value::Int(i);
    }
    if !t.is_empty()
        && !t
            .chars()
            .any(|c| c.is_alphabetic() && !matches!(c, 'e' | 'E'))
    {
        if let Ok(x) = t.parse::<f64>() {
            return Value::Float(x);
        }
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
                Err(_) => Value::Float(
                    t.parse::<f64>()
                        .map_err(|_| format!("bad number \"{t}\""))?,
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
}

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

    fn ternary(&mut self) -> Result<Value, ModelError> {
        let v = self.or()?;
        if self.eat_name("if") {
            let c = self.or()?;
            if !self.eat_name("else") {
                return Err(self.err("'if' without 'else'"));
            }
            let other = self.ternary()?;
            return Ok(if c.truth().map_err(|m| self.err(m))? {
                v
            } else {
                other
            });
        }
        Ok(v)
    }

    fn or(&mut self) -> Result<Value, ModelError> {
        let mut v = self.and()?;
        while self.eat_name("or") {
            let r = self.and()?;
            v = if v.truth().map_err(|m| self.err(m))? {
                v
            } else {
                r
            };
        }
        Ok(v)
    }

    fn and(&mut self) -> Result<Value, ModelError> {
        let mut v = self.not()?;
        while self.eat_name("and") {
            let r = self.not()?;
            v = if v.truth().map_err(|m| self.err(m))? {
                r
            } else {
                v
            };
        }
        Ok(v)
    }

    fn not(&mut self) -> Result<Value, ModelError> {
        if self.eat_name("not") {
            let v = self.not()?;
            return Ok(Value::Bool(!v.truth().map_err(|m| self.err(m))?));
        }
        self.cmp()
    }

    fn cmp(&mut self) -> Result<Value, ModelError> {
        let l = self.add()?;
        for op in ["==", "!=", "<=", ">=", "<", ">"] {
            if self.eat_op(op) {
                let r = self.add()?;
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
                    (Value::Str(a), Value::Str(b)) => Value::Str(format!("{a}{b}")),
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
            let v = self.unary()?;
            return match v {
                Value::Int(i) => Ok(Value::Int(-i)),
                other => Ok(Value::Float(
                    -other.num().ok_or_else(|| self.err("'-' on a string"))?,
                )),
            };
        }
        if self.eat_op("+") {
            return self.unary();
        }
        self.power()
    }

    fn power(&mut self) -> Result<Value, ModelError> {
        let base = self.postfix()?;
        if self.eat_op("**") {
            let e = self.unary()?;
            return self.arith(&base, &e, "**");
        }
        Ok(base)
    }

    fn arith(&self, a: &Value, b: &Value, op: &str) -> Result<Value, ModelError> {
        if let (Value::Int(x), Value::Int(y)) = (a, b) {
            let (x, y) = (*x, *y);
            let r = match op {
                "+" => x.checked_add(y),
                "-" => x.checked_sub(y),
                "*" => x.checked_mul(y),
                "//" if y != 0 => Some(x.div_euclid(y) - i64::from(x.rem_euclid(y) != 0 && y < 0)),
                "%" if y != 0 => Some(((x % y) + y) % y),
                "**" if (0..64).contains(&y) => x.checked_pow(y as u32),
                _ => None,
            };
            if let Some(r) = r {
                return Ok(Value::Int(r));
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
                    return self.call(&name, &args);
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
            "floor" => one(f64::floor).map(|v| Value::Int(v.num().unwrap_or(0.0) as i64)),
            "ceil" => one(f64::ceil).map(|v| Value::Int(v.num().unwrap_or(0.0) as i64)),
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
                [Value::Int(i)] => Ok(Value::Int(i.abs())),
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
                [Value::Str(s)] => s
                    .trim()
                    .parse::<f64>()
                    .map(Value::Float)
                    .map_err(|_| self.err(format!("float(\"{s}\"): not a number"))),
                _ => one(|x| x),
            },
            "int" => match args {
                [Value::Str(s)] => s
                    .trim()
                    .parse::<i64>()
                    .map(Value::Int)
                    .map_err(|_| self.err(format!("int(\"{s}\"): not an integer"))),
                _ => match nums()?.as_slice() {
                    [x] => Ok(Value::Int(x.trunc() as i64)),
                    _ => Err(self.err("int() takes one argument")),
                },
            },
            "round" => match nums()?.as_slice() {
                [x] => Ok(Value::Int(round_half_even(*x) as i64)),
                [x, n] => {
                    let p = 10f64.powi(*n as i32);
                    Ok(Value::Float(round_half_even(x * p) / p))
                }
                _ => Err(self.err("round() takes one or two arguments")),
            },
            "str" => match args {
                [v] => Ok(Value::Str(v.to_text())),
                _ => Err(self.err("str() takes one argument")),
            },
            "bool" => match args {
                [v] => Ok(Value::Bool(v.truth().map_err(|m| self.err(m))?)),
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
