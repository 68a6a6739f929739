//! The owned node tree of a xacro file (parsed once through `input::parse_xml`, line numbers
//! kept) and declaring the xacro prefix where a file uses it without a declaration.

use super::*;

/// Where a node came from, for error messages.
#[derive(Debug, Clone)]
pub(super) struct At {
    pub(super) file: Rc<str>,
    pub(super) dir: Rc<Path>,
    pub(super) line: u32,
}

#[derive(Debug, Clone)]
pub(super) enum Node {
    Elem(Rc<Elem>),
    /// Text content, with where its element is.
    Text(String, At),
}

#[derive(Debug)]
pub(super) struct Elem {
    /// For xacro elements, the local name (`property`, `macro`, a macro's name); otherwise the
    /// element's name.
    pub(super) name: String,
    pub(super) xacro: bool,
    /// Attributes in no namespace, and xacro-namespace ones as `xacro:NAME`.
    pub(super) attrs: Vec<(String, String)>,
    pub(super) children: Vec<Node>,
    pub(super) at: At,
}

impl Elem {
    pub(super) fn attr(&self, name: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(k, _)| k == name)
            .map(|(_, v)| v.as_str())
    }
}

/// Adds `xmlns:xacro` to the root element of a file that uses the prefix without declaring it.
pub(super) fn declare_xacro(text: &str) -> Option<String> {
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
pub(super) struct Convert<'t> {
    pub(super) text: &'t str,
    pub(super) lines: &'t Lines,
    pub(super) file: &'t Rc<str>,
    pub(super) dir: &'t Rc<Path>,
}

impl Convert<'_> {
    pub(super) fn elem(&self, n: roxmltree::Node) -> Rc<Elem> {
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
