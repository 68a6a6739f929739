//! The expander: walks the node tree, expands macros, includes, conditionals, properties and
//! `${…}` / `$(…)` substitutions within the limits of [`super::MAX_NESTING`],
//! [`super::MAX_OUTPUT_BYTES`] and [`super::MAX_WORK`].

use super::*;

pub(super) struct Expander<'o> {
    pub(super) opts: &'o XacroOptions,
    pub(super) args: HashMap<String, String>,
    /// Include and macro nesting, bounded against runaway recursion.
    pub(super) depth: usize,
    /// Every recursive construct (expression, property definition, macro, element) nested
    /// now, at most [`MAX_NESTING`].
    pub(super) nest: usize,
    /// Elements, texts and tokens processed so far, at most [`MAX_WORK`].
    pub(super) work: u64,
    /// Output text produced so far (approximately: names, attribute values and texts), at
    /// most [`MAX_OUTPUT_BYTES`].
    pub(super) out_bytes: usize,
}

pub(super) const MAX_DEPTH: usize = 200;

pub(super) fn fail(at: &At, what: impl std::fmt::Display) -> ModelError {
    ModelError::new(
        format!("{}:{}", at.file, at.line),
        ErrorKind::XacroExpand(what.to_string()),
    )
}

impl Expander<'_> {
    /// Enters one level of nesting ([`MAX_NESTING`]); [`Expander::leave`] undoes it.
    pub(super) fn nest_in(&mut self, at: &At, what: &str) -> Result<(), ModelError> {
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

    pub(super) fn leave(&mut self) {
        self.nest -= 1;
    }

    /// Counts `n` units of work ([`MAX_WORK`]).
    pub(super) fn count(&mut self, n: u64, at: &At) -> Result<(), ModelError> {
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
    pub(super) fn produce(&mut self, n: usize, at: &At) -> Result<(), ModelError> {
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
    pub(super) fn parse(
        &mut self,
        text: &str,
        source: &str,
        dir: &Path,
    ) -> Result<Rc<Elem>, ModelError> {
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
    pub(super) fn text(&mut self, s: &str, scope: &Scope, at: &At) -> Result<String, ModelError> {
        Ok(self.eval_text(s, scope, at)?.to_text())
    }

    /// Evaluates text: a lone `${expr}` keeps its type; anything else is a string.
    pub(super) fn eval_text(
        &mut self,
        s: &str,
        scope: &Scope,
        at: &At,
    ) -> Result<Value, ModelError> {
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

    pub(super) fn expr(&mut self, src: &str, scope: &Scope, at: &At) -> Result<Value, ModelError> {
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
    pub(super) fn extension(
        &mut self,
        inner: &str,
        scope: &Scope,
        at: &At,
    ) -> Result<String, ModelError> {
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

    /// The folder of package `pkg` ([`find_package`]).
    pub(super) fn find(&self, pkg: &str, at: &At) -> Result<String, ModelError> {
        find_package(pkg, &self.opts.package_paths)
            .map(|d| d.display().to_string())
            .ok_or_else(|| {
                fail(
                    at,
                    format!("$(find {pkg}): package not found (add its parent folder to the package paths, or set ROS_PACKAGE_PATH)"),
                )
            })
    }

    /// The value of a property (evaluating it on first use).
    pub(super) fn lookup(
        &mut self,
        name: &str,
        scope: &Scope,
        at: &At,
    ) -> Result<Value, ModelError> {
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
    pub(super) fn process(
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
                    let mut o = self.out_elem(e.name.clone(), e, scope)?;
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

    /// The output element `name` with `e`'s attributes expanded (the `xacro:` ones left out).
    pub(super) fn out_elem(
        &mut self,
        name: String,
        e: &Elem,
        scope: &Scope,
    ) -> Result<OutElem, ModelError> {
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
        Ok(o)
    }

    /// Counts an output element's name and attributes ([`MAX_OUTPUT_BYTES`]).
    pub(super) fn emitted(&mut self, o: &OutElem, at: &At) -> Result<(), ModelError> {
        let n = o.name.len()
            + 64
            + o.attrs
                .iter()
                .map(|(k, v)| k.len() + v.len() + 4)
                .sum::<usize>();
        self.produce(n, at)
    }

    pub(super) fn required<'e>(&self, e: &'e Elem, attr: &str) -> Result<&'e str, ModelError> {
        e.attr(attr).ok_or_else(|| {
            fail(
                &e.at,
                format!("<xacro:{}> needs a {attr}=\"…\" attribute", e.name),
            )
        })
    }

    pub(super) fn xacro(
        &mut self,
        e: &Rc<Elem>,
        scope: &Scope,
        out: &mut OutElem,
    ) -> Result<(), ModelError> {
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
                        crate::input::decode(&bytes)
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
                let text = crate::input::tolerate(&text).into_owned();
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
                let mut o = self.out_elem(name, e, scope)?;
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

    pub(super) fn enter(&mut self, at: &At) -> Result<(), ModelError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(fail(
                at,
                format!("macros or includes nested more than {MAX_DEPTH} deep (a recursion?)"),
            ));
        }
        Ok(())
    }

    pub(super) fn call(
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
pub(super) fn check_name(name: &str) -> Result<(), String> {
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
pub(super) fn matching(s: &str, from: usize, open: char, close: char) -> Option<usize> {
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

/// `params="a b:=1 *blk **blks c:=^ d:=^|2"`.
pub(super) fn parse_params(s: &str) -> Result<Vec<Param>, String> {
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
pub(super) fn split_params(s: &str) -> Result<Vec<String>, String> {
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
pub(super) fn unquote(d: &str) -> &str {
    for q in ['\'', '"'] {
        if d.len() >= 2 && d.starts_with(q) && d.ends_with(q) {
            return &d[1..d.len() - 1];
        }
    }
    d
}

/// The folder of ROS package `pkg`, absolute: a folder of that name up to three levels below
/// one of `package_paths`, then below `ROS_PACKAGE_PATH`'s entries, then `share/pkg` of an
/// `AMENT_PREFIX_PATH` entry — xacro's `$(find pkg)` and a mesh's `package://pkg/…` alike.
pub(crate) fn find_package(pkg: &str, package_paths: &[PathBuf]) -> Option<PathBuf> {
    let mut roots: Vec<PathBuf> = package_paths.to_vec();
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
            return Some(found);
        }
    }
    if let Some(v) = std::env::var_os("AMENT_PREFIX_PATH") {
        for prefix in split(v) {
            let d = prefix.join("share").join(pkg);
            let d = std::path::absolute(&d).unwrap_or(d);
            if d.is_dir() {
                return Some(d);
            }
        }
    }
    None
}

/// A folder named `name` at most `depth` levels below `root` (breadth first, sorted, so the
/// answer does not depend on the file system's order).
pub(super) fn find_below(root: &Path, name: &str, depth: usize) -> Option<PathBuf> {
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
