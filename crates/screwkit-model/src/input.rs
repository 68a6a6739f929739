//! Untrusted input: bounded reads and the checks every XML document passes before it is used.
//!
//! A robot file can come from a download or another program, so every read and every parse is
//! bounded. The limits, each an error naming the file (and line) when exceeded:
//!
//! | what | limit |
//! |---|---|
//! | a robot file, a xacro include, a robot on standard input | [`MAX_FILE_BYTES`] (64 MiB) read; an endless or larger source (`/dev/zero`) stops there |
//! | XML element nesting | [`MAX_ELEMENT_DEPTH`] (256 levels) |
//! | XML nodes in one document | [`MAX_NODES`] (4 million) |
//! | text produced by internal DTD entities (`&name;`), summed over every use | [`MAX_ENTITY_BYTES`] (1 MiB) |
//!
//! The xacro expander has its own limits on top (nesting, output size, work): see
//! [`crate::xacro`].

use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::error::{ErrorKind, ModelError};

/// The most bytes read from one robot file, include or standard input (64 MiB).
pub const MAX_FILE_BYTES: u64 = 64 << 20;
/// The deepest XML element nesting accepted (real robot files nest fewer than 10 levels).
pub const MAX_ELEMENT_DEPTH: usize = 256;
/// The most XML nodes (elements, text, …) in one document.
pub const MAX_NODES: u32 = 4_000_000;
/// The most attributes on one element (real robot files have fewer than ten).
pub const MAX_ATTRIBUTES: usize = 1000;
/// The most text that internal DTD entities may expand to in one document, summed over every
/// reference (the "billion laughs" and "quadratic blow-up" attacks).
pub const MAX_ENTITY_BYTES: usize = 1 << 20;

/// Reads at most [`MAX_FILE_BYTES`] from `reader`; more is an error, not a bigger buffer.
pub fn read_bounded(mut reader: impl Read) -> Result<Vec<u8>, ErrorKind> {
    let mut bytes = Vec::new();
    (&mut reader)
        .take(MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| io_kind(&e))?;
    if bytes.len() as u64 > MAX_FILE_BYTES {
        return Err(ErrorKind::TooLarge(format!(
            "more than {} MiB (a robot file is read up to that size)",
            MAX_FILE_BYTES >> 20
        )));
    }
    Ok(bytes)
}

/// A file being read as input stays protected from every output while a holder of it lives:
/// the files a loaded robot was read from (its file, includes) for as long as the robot
/// lives, every file a command-line run reads for the whole run. The one atomic writer of
/// outputs (`screwkit_service::io::atomic`) refuses to write over any of them
/// ([`read_as_input`]), by any name (`./x`, hard and symbolic links), so no output can destroy
/// what it was made from.
///
/// Reads are noted by [`note_read`] while [`collect_reads`] runs on the reading thread (the
/// floor's `Robot::load` and the command line's `main` do); the holders it returns keep them.
#[derive(Debug)]
pub struct InputFile {
    id: (u64, u64),
}

impl Clone for InputFile {
    fn clone(&self) -> Self {
        let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(e) = read.iter_mut().find(|e| e.id == self.id) {
            e.holders += 1;
        }
        InputFile { id: self.id }
    }
}

impl Drop for InputFile {
    fn drop(&mut self) {
        let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(k) = read.iter().position(|e| e.id == self.id) {
            read[k].holders -= 1;
            if read[k].holders == 0 {
                read.swap_remove(k);
            }
        }
    }
}

/// A protected input: its identity, the path it was read by, how many [`InputFile`]s hold it.
struct Entry {
    id: (u64, u64),
    path: PathBuf,
    holders: usize,
}

/// The protected inputs of this process.
static READ: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

thread_local! {
    /// The holders of the files read on this thread while [`collect_reads`] runs.
    static COLLECTING: std::cell::RefCell<Option<Vec<InputFile>>> =
        const { std::cell::RefCell::new(None) };
}

/// A file's identity: (device, inode) on Unix, so that `./x`, hard links and symbolic links
/// of one file are one; elsewhere its canonical path's hash.
fn identity(meta: &std::fs::Metadata, path: &Path) -> (u64, u64) {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let _ = path;
        (meta.dev(), meta.ino())
    }
    #[cfg(not(unix))]
    {
        use std::hash::{Hash, Hasher};
        let _ = meta;
        let mut h = std::collections::hash_map::DefaultHasher::new();
        std::fs::canonicalize(path)
            .unwrap_or_else(|_| path.to_path_buf())
            .hash(&mut h);
        (0, h.finish())
    }
}

/// Runs `f`, collecting a holder of every input file it reads on this thread ([`note_read`]);
/// the files stay protected from outputs while the holders live. Nested calls collect into
/// their own list and hand it to the outer one too.
pub fn collect_reads<T>(f: impl FnOnce() -> T) -> (T, Vec<InputFile>) {
    /// Puts the outer collector back however `f` ends (a panic unwinding through it too), so
    /// a later load on this thread does not collect into a list nobody holds.
    struct Restore(Option<Option<Vec<InputFile>>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            if let Some(outer) = self.0.take() {
                COLLECTING.with(|c| *c.borrow_mut() = outer);
            }
        }
    }
    let mut restore = Restore(Some(
        COLLECTING.with(|c| c.borrow_mut().replace(Vec::new())),
    ));
    let out = f();
    let mine = COLLECTING
        .with(|c| c.borrow_mut().take())
        .unwrap_or_default();
    if let Some(Some(outer)) = restore.0.as_mut() {
        outer.extend(mine.iter().cloned());
    }
    drop(restore);
    (out, mine)
}

/// Notes that `file`, opened from `path`, is read as input, when [`collect_reads`] runs on
/// this thread (otherwise nothing: a program using the parsers directly manages its files).
/// Pipes, terminals and other special files hold nothing to protect.
pub fn note_read(file: &std::fs::File, path: &Path) {
    let collecting = COLLECTING.with(|c| c.borrow().is_some());
    if !collecting {
        return;
    }
    let Ok(meta) = file.metadata() else {
        return;
    };
    if !meta.is_file() {
        return;
    }
    let id = identity(&meta, path);
    {
        let mut read = READ.lock().unwrap_or_else(|e| e.into_inner());
        match read.iter_mut().find(|e| e.id == id) {
            Some(e) => e.holders += 1,
            None => read.push(Entry {
                id,
                path: path.to_path_buf(),
                holders: 1,
            }),
        }
    }
    COLLECTING.with(|c| {
        if let Some(v) = c.borrow_mut().as_mut() {
            v.push(InputFile { id });
        }
    });
}

/// The path by which a protected input was read, when `path` names that file by any name
/// ([`InputFile`]).
pub fn read_as_input(path: &Path) -> Option<PathBuf> {
    let meta = std::fs::metadata(path).ok().filter(|m| m.is_file())?;
    let id = identity(&meta, path);
    let read = READ.lock().unwrap_or_else(|e| e.into_inner());
    read.iter().find(|e| e.id == id).map(|e| e.path.clone())
}

/// Reads a robot file's bytes, bounded by [`MAX_FILE_BYTES`]; errors name the file.
pub fn read_file(path: &Path) -> Result<Vec<u8>, ModelError> {
    let label = path.display().to_string();
    let file =
        std::fs::File::open(path).map_err(|e| ModelError::new(label.clone(), io_kind(&e)))?;
    note_read(&file, path);
    if file.metadata().is_ok_and(|m| m.is_dir()) {
        return Err(ModelError::new(
            label,
            ErrorKind::Io {
                kind: std::io::ErrorKind::IsADirectory,
                message: "is a directory, not a file".into(),
            },
        ));
    }
    read_bounded(file).map_err(|k| ModelError::new(label, k))
}

/// An I/O error as an [`ErrorKind::Io`] (its kind kept).
pub(crate) fn io_kind(e: &std::io::Error) -> ErrorKind {
    ErrorKind::Io {
        kind: e.kind(),
        message: e.to_string(),
    }
}

/// `s` escaped for a double-quoted XML attribute value that reads back as `s` exactly: as
/// [`escape_xml`], and tabs and line breaks as character references (a parser normalises them
/// to spaces otherwise). `Err` with the first character XML 1.0 cannot hold at all (NUL and
/// the other control characters): such a name cannot be written.
pub fn escape_attr(s: &str) -> Result<String, char> {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '\t' => out.push_str("&#9;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            c if (c as u32) < 0x20 || c == '\u{fffe}' || c == '\u{ffff}' => return Err(c),
            c => push_escaped_char(c, &mut out),
        }
    }
    Ok(out)
}

/// Appends `s` escaped for XML text and double-quoted attribute values (`&`, `<`, `>`, `"`),
/// as ROS's xacro writes them. The one XML escape of the workspace: URDF pre-pass, xacro
/// output, pictures.
pub fn push_escaped(s: &str, out: &mut String) {
    for c in s.chars() {
        push_escaped_char(c, out);
    }
}

/// One character of [`push_escaped`].
fn push_escaped_char(c: char, out: &mut String) {
    match c {
        '&' => out.push_str("&amp;"),
        '<' => out.push_str("&lt;"),
        '>' => out.push_str("&gt;"),
        '"' => out.push_str("&quot;"),
        c => out.push(c),
    }
}

/// `s` escaped for XML ([`push_escaped`]).
pub fn escape_xml(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    push_escaped(s, &mut out);
    out
}

/// A robot file's bytes as text: UTF-8 (a byte-order mark dropped), or Latin-1 when the XML
/// declaration says so (ISO-8859-1, latin1, …), as urdfdom reads them.
pub fn decode(bytes: &[u8]) -> Result<String, ErrorKind> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s.to_string()),
        Err(e) => {
            let head = String::from_utf8_lossy(&bytes[..bytes.len().min(200)]).to_ascii_lowercase();
            let latin1 = ["iso-8859-1", "iso8859-1", "latin-1", "latin1"];
            if head.trim_start().starts_with("<?xml") && latin1.iter().any(|l| head.contains(l)) {
                Ok(bytes.iter().map(|&b| b as char).collect())
            } else {
                Err(ErrorKind::Io {
                    kind: std::io::ErrorKind::InvalidData,
                    message: format!(
                        "not UTF-8 text (byte {} is invalid; declare encoding=\"ISO-8859-1\" for Latin-1)",
                        e.valid_up_to()
                    ),
                })
            }
        }
    }
}

/// What urdfdom tolerates and a strict XML parser does not: whitespace before the XML
/// declaration, NUL bytes at the end (C strings written whole), and an encoding named in the
/// declaration (the text is already decoded: [`decode`]).
pub fn tolerate(text: &str) -> std::borrow::Cow<'_, str> {
    let t = text
        .trim_start()
        .trim_end_matches(['\0', ' ', '\n', '\r', '\t']);
    if let Some(rest) = t.strip_prefix("<?xml") {
        if let Some(end) = rest.find("?>") {
            if rest[..end].contains("encoding") {
                return format!("<?xml version=\"1.0\"?>{}", &rest[end + 2..]).into();
            }
        }
    }
    t.into()
}

/// The parsing options every document is read with: a DTD allowed (real files have one),
/// [`MAX_NODES`].
pub(crate) fn parse_options<'a>() -> roxmltree::ParsingOptions<'a> {
    roxmltree::ParsingOptions {
        allow_dtd: true,
        nodes_limit: MAX_NODES,
        ..Default::default()
    }
}

/// Parses XML text after checking its entity expansion, then checks its nesting.
pub(crate) fn parse_xml(text: &str) -> Result<roxmltree::Document<'_>, ErrorKind> {
    check_entities(text)?;
    check_attributes(text)?;
    let doc = roxmltree::Document::parse_with_options(text, parse_options())
        .map_err(|e| ErrorKind::Xml(e.to_string()))?;
    check_depth(&doc)?;
    Ok(doc)
}

/// Element nesting at most [`MAX_ELEMENT_DEPTH`] (an iterative walk: no recursion here).
fn check_depth(doc: &roxmltree::Document) -> Result<(), ErrorKind> {
    let mut depth = vec![0u16; doc.descendants().count() + 1];
    for n in doc.descendants() {
        let d = n.parent().map_or(0, |p| depth[p.id().get_usize()]) + 1;
        if usize::from(d) > MAX_ELEMENT_DEPTH {
            let line = doc.text_pos_at(n.range().start).row;
            return Err(ErrorKind::Xml(format!(
                "elements nested more than {MAX_ELEMENT_DEPTH} levels deep at line {line}"
            )));
        }
        depth[n.id().get_usize()] = d;
    }
    Ok(())
}

/// At most [`MAX_ATTRIBUTES`] attributes on any start tag: one linear scan of the text
/// (comments, CDATA, processing instructions and declarations skipped), before the parser.
fn check_attributes(text: &str) -> Result<(), ErrorKind> {
    let b = text.as_bytes();
    let skip_to = |from: usize, end: &str| {
        text[from..]
            .find(end)
            .map_or(b.len(), |i| from + i + end.len())
    };
    let mut i = 0;
    while let Some(lt) = text[i..].find('<').map(|k| i + k) {
        let rest = &text[lt..];
        if rest.starts_with("<!--") {
            i = skip_to(lt + 4, "-->");
        } else if rest.starts_with("<![CDATA[") {
            i = skip_to(lt + 9, "]]>");
        } else if rest.starts_with("<?") {
            i = skip_to(lt + 2, "?>");
        } else {
            // A tag: count `=` outside quotes up to its `>`; declarations (`<!…>`) are
            // walked the same way but not counted.
            let declaration = rest.starts_with("<!");
            let (mut j, mut quote, mut count) = (lt + 1, None, 0usize);
            // In a declaration: inside its `[ … ]` internal subset.
            let mut subset = false;
            while j < b.len() {
                match (quote, b[j]) {
                    (Some(q), c) if c == q => quote = None,
                    (Some(_), _) => {}
                    (None, c @ (b'"' | b'\'')) => quote = Some(c),
                    (None, b'=') => count += 1,
                    (None, b'[') if declaration => subset = true,
                    (None, b']') if declaration => subset = false,
                    (None, b'>') if !subset => break,
                    _ => {}
                }
                j += 1;
            }
            if !declaration && count > MAX_ATTRIBUTES {
                let line = text[..lt].matches('\n').count() + 1;
                return Err(ErrorKind::Xml(format!(
                    "more than {MAX_ATTRIBUTES} attributes on the element at line {line}"
                )));
            }
            i = j.min(b.len());
        }
        if i >= b.len() {
            break;
        }
    }
    Ok(())
}

/// The text the internal DTD's entities would produce, summed over every reference in the
/// document, at most [`MAX_ENTITY_BYTES`].
fn check_entities(text: &str) -> Result<(), ErrorKind> {
    let Some(doctype) = text.find("<!DOCTYPE") else {
        return Ok(());
    };
    let Some(open) = text[doctype..].find('[').map(|i| doctype + i) else {
        return Ok(());
    };
    let Some(close) = text[open..].find("]>").map(|i| open + i) else {
        return Ok(());
    };
    let subset = &text[open + 1..close];
    // name → value of every general entity.
    let mut values: Vec<(&str, &str)> = Vec::new();
    let mut rest = subset;
    while let Some(i) = rest.find("<!ENTITY") {
        rest = rest[i + "<!ENTITY".len()..].trim_start();
        if rest.starts_with('%') {
            continue; // parameter entities: roxmltree does not expand them
        }
        let name_end = rest.find(|c: char| c.is_whitespace()).unwrap_or(rest.len());
        let name = &rest[..name_end];
        let after = rest[name_end..].trim_start();
        let Some(q) = after.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            continue;
        };
        let Some(end) = after[1..].find(q) else {
            break;
        };
        values.push((name, &after[1..1 + end]));
        rest = &after[1 + end..];
    }
    if values.is_empty() {
        return Ok(());
    }
    let too_much = || {
        ErrorKind::Xml(format!(
            "the DTD's entities expand to more than {} KiB of text (an entity expansion attack?)",
            MAX_ENTITY_BYTES >> 10
        ))
    };
    // Expanded length of each entity (memoised; depth bounded as roxmltree bounds it).
    fn expanded(
        name: &str,
        values: &[(&str, &str)],
        memo: &mut Vec<Option<usize>>,
        depth: usize,
    ) -> Option<usize> {
        let i = values.iter().position(|(n, _)| *n == name)?;
        if let Some(l) = memo[i] {
            return Some(l);
        }
        if depth > 10 {
            return Some(0); // roxmltree reports the loop itself
        }
        let value = values[i].1;
        let mut len = 0usize;
        for (lit, r) in references(value) {
            len = len.saturating_add(lit);
            if let Some(r) = r {
                len =
                    len.saturating_add(expanded(r, values, memo, depth + 1).unwrap_or(r.len() + 2));
            }
        }
        memo[i] = Some(len);
        Some(len)
    }
    let mut memo = vec![None; values.len()];
    let body = &text[close + 2..];
    let mut total = 0usize;
    for (_, r) in references(body) {
        if let Some(r) = r {
            if let Some(l) = expanded(r, &values, &mut memo, 0) {
                total = total.saturating_add(l);
                if total > MAX_ENTITY_BYTES {
                    return Err(too_much());
                }
            }
        }
    }
    Ok(())
}

/// Splits text into (length of literal text, the entity reference `&name;` after it).
fn references(s: &str) -> impl Iterator<Item = (usize, Option<&str>)> + '_ {
    let mut rest = s;
    let mut done = false;
    std::iter::from_fn(move || {
        if done {
            return None;
        }
        let Some(i) = rest.find('&') else {
            done = true;
            return Some((rest.len(), None));
        };
        let after = &rest[i + 1..];
        match after.find(';') {
            Some(j)
                if j > 0
                    && !after[..j].starts_with('#')
                    && !after[..j].contains(char::is_whitespace) =>
            {
                rest = &after[j + 1..];
                Some((i, Some(&after[..j])))
            }
            _ => {
                rest = after;
                Some((i + 1, None))
            }
        }
    })
}

/// Whether an element is written with a namespace prefix (`<u:origin>`): urdfdom compares
/// qualified names, so it never reads such an element as URDF.
pub(crate) fn is_prefixed(text: &str, node: &roxmltree::Node) -> bool {
    let s = &text[node.range()];
    let name_end = s
        .find(|c: char| c.is_whitespace() || c == '>' || c == '/')
        .unwrap_or(s.len());
    s[..name_end].contains(':')
}

/// A line-number index of a text: the line of a byte offset by binary search (a linear scan
/// per element made files with many elements quadratic).
#[derive(Debug, Clone)]
pub(crate) struct Lines(Vec<usize>);

impl Lines {
    pub(crate) fn new(text: &str) -> Self {
        Lines(
            text.bytes()
                .enumerate()
                .filter(|(_, b)| *b == b'\n')
                .map(|(i, _)| i)
                .collect(),
        )
    }

    /// The 1-based line of byte offset `at`.
    pub(crate) fn line(&self, at: usize) -> u32 {
        (self.0.partition_point(|&nl| nl < at) + 1) as u32
    }
}
