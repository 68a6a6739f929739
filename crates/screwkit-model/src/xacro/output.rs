//! The expanded document: elements and text, written as URDF text (escaped by the
//! workspace's one XML escape, `input::push_escaped`).

use super::*;
use crate::input::push_escaped as escape;

#[derive(Debug)]
pub(super) struct OutElem {
    pub(super) name: String,
    pub(super) attrs: Vec<(String, String)>,
    pub(super) children: Vec<Out>,
}

#[derive(Debug)]
pub(super) enum Out {
    Elem(OutElem),
    Text(String),
}

pub(super) fn write_elem(s: &mut String, e: &OutElem, depth: usize) {
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
