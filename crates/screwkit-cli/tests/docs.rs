//! The README's and the guide's (`docs/guide/*.md`) command-line examples are real.
//!
//! - Every `**`screwkit …`**` command followed by a pasted ```text or ```json block (and each
//!   ```text block that starts with a `$ …` shell line) is run from the repository root and
//!   compared with the block: the text line by line with every number equal to the digits
//!   printed, JSON value by value. Timings (µs, lines/s, `time_us`) are compared as text around
//!   them only; `bench` and `reach` outputs (timings throughout) by their text with every number
//!   left out.
//! - Every line of a ```sh block that is not a set-up command (`pip`, `cargo`, `python3 -m
//!   venv`, `maturin`, activating a venv: the steps `cargo xtask newcomer` and `cargo xtask
//!   wheel` run) is run by `sh` in a scratch folder holding the bundled `assets/`, with this
//!   build's `screwkit` first on the PATH, and must succeed.
//! - No README or guide line names the project's CI data (`../shared`).
//!
//! After a change of output, `SCREWKIT_UPDATE_DOCS=1 cargo test -p screwkit-cli --test docs`
//! pastes the new outputs into the pages; read every changed line in `git diff` before
//! committing it. The Python examples are checked by the Python suite (`test_readme.py`).

use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The README and every page of the guide, relative to the repository root.
fn documents() -> Vec<PathBuf> {
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root().join("docs/guide"))
        .expect("docs/guide")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| PathBuf::from("docs/guide").join(p.file_name().unwrap()))
        .collect();
    pages.sort();
    let mut docs = vec![PathBuf::from("README.md")];
    docs.extend(pages);
    docs
}

/// One checked example: where its pasted block is, the command, the block and its language.
struct Example {
    /// 0-based line range of the block's content (between the fences).
    lines: std::ops::Range<usize>,
    command: String,
    block: String,
    lang: String,
    /// Timings throughout: compared as text with the numbers left out.
    volatile: bool,
}

/// The checked examples of one document.
fn examples(doc: &Path) -> Vec<Example> {
    let text = std::fs::read_to_string(root().join(doc)).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut command: Option<String> = None;
    // The last command paired with a block ("and with `--format json`" repeats it).
    let mut last: Option<String> = None;
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i];
        if let Some(rest) = l.strip_prefix("**`screwkit ") {
            command = rest.split_once("`**").map(|(c, _)| c.to_string());
        } else if l.starts_with("and with `--format json`") {
            command = last.as_ref().map(|c| format!("{c} --format json"));
        }
        if l.starts_with("## ") {
            command = None;
        }
        let fence_end = |start: usize| {
            start
                + lines[start..]
                    .iter()
                    .position(|l| *l == "```")
                    .unwrap_or_else(|| panic!("{}:{}: unclosed block", doc.display(), i + 1))
        };
        if let Some(lang) = l.strip_prefix("```").filter(|s| !s.is_empty()) {
            let (start, end) = (i + 1, fence_end(i + 1));
            if lang == "text" || lang == "json" {
                let block = lines[start..end].join("\n");
                if let Some(shell) = block.strip_prefix("$ ") {
                    let (cmd, output) = shell.split_once('\n').unwrap_or((shell, ""));
                    let volatile =
                        cmd.starts_with("screwkit bench ") || cmd.starts_with("screwkit reach ");
                    out.push(Example {
                        lines: start + 1..end,
                        command: format!("$ {cmd}"),
                        block: output.to_string(),
                        lang: lang.to_string(),
                        volatile,
                    });
                } else if let Some(c) = command.take() {
                    last = Some(c.clone());
                    let volatile = c.starts_with("bench ") || c.starts_with("reach ");
                    out.push(Example {
                        lines: start..end,
                        command: c,
                        block,
                        lang: lang.to_string(),
                        volatile,
                    });
                }
            } else {
                // A block of another language (python, sh, rust): not an output; it ends the
                // command's paragraph too, but the README's "Start here" block pairs its
                // main job with the output under it.
                let start_here =
                    "cargo run --release -p screwkit-cli -- table assets/urdf/ur5.urdf --frame space";
                command = lines[start..end]
                    .iter()
                    .any(|l| l.contains(start_here))
                    .then(|| "table assets/urdf/ur5.urdf --frame space".to_string());
            }
            i = end;
        }
        i += 1;
    }
    out
}

/// What `command` prints (stdout; a `$ …` shell line: stdout and stderr), run in `dir` (a
/// scratch folder holding `assets/`, so that files it writes land there) with this build's
/// `screwkit` first on the PATH.
fn run(command: &str, dir: &Path) -> String {
    let out = if let Some(shell) = command.strip_prefix("$ ") {
        Command::new("sh")
            .arg("-c")
            .arg(format!("{shell} 2>&1"))
            .current_dir(dir)
            .env("PATH", path_with_bin())
            .output()
            .unwrap()
    } else {
        Command::new(BIN)
            .args(command.split_whitespace())
            .current_dir(dir)
            .output()
            .unwrap()
    };
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The PATH with this build's `screwkit` first.
fn path_with_bin() -> std::ffi::OsString {
    let bin_dir = Path::new(BIN).parent().unwrap().to_path_buf();
    std::env::join_paths(
        std::iter::once(bin_dir).chain(std::env::split_paths(&std::env::var_os("PATH").unwrap())),
    )
    .unwrap()
}

/// Numbers in a line, and the line with each replaced by `#`.
fn numbers(line: &str) -> (String, Vec<(f64, i32)>) {
    let b = line.as_bytes();
    let (mut skeleton, mut nums) = (String::new(), Vec::new());
    let mut i = 0;
    while i < b.len() {
        let starts = b[i].is_ascii_digit()
            || (b[i] == b'-'
                && i + 1 < b.len()
                && b[i + 1].is_ascii_digit()
                && (i == 0 || !b[i - 1].is_ascii_alphanumeric()));
        if starts && (i == 0 || !(b[i - 1].is_ascii_alphabetic() || b[i - 1] == b'_')) {
            let s = i;
            i += 1;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            if i + 1 < b.len()
                && (b[i] == b'e' || b[i] == b'E')
                && (b[i + 1].is_ascii_digit() || b[i + 1] == b'-' || b[i + 1] == b'+')
            {
                i += 2;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
            }
            let t = &line[s..i];
            let mantissa = t.split(['e', 'E']).next().unwrap_or(t);
            let decimals = mantissa.split_once('.').map_or(0, |(_, d)| d.len() as i32);
            let exp: i32 = t
                .split_once(['e', 'E'])
                .map_or(0, |(_, e)| e.parse().unwrap_or(0));
            nums.push((t.parse().unwrap_or(f64::NAN), exp - decimals));
            skeleton.push('#');
        } else {
            let c = line[i..].chars().next().unwrap();
            skeleton.push(c);
            i += c.len_utf8();
        }
    }
    (skeleton, nums)
}

/// `got` equals `printed` to the printed digits (residuals below 1e-9 count as equal).
fn same_number(got: f64, printed: f64, unit_exp: i32) -> bool {
    let half_ulp = 0.5 * 10f64.powi(unit_exp);
    (got.abs() < 1e-9 && printed.abs() < 1e-9)
        || (got - printed).abs() <= half_ulp * 1.000001 + 1e-12
}

fn compare_text(command: &str, got: &str, want: &str, volatile: bool) -> Result<(), String> {
    let (g, w): (Vec<&str>, Vec<&str>) = (got.trim_end().lines().collect(), want.lines().collect());
    if g.len() != w.len() {
        return Err(format!("{} lines, the page has {}", g.len(), w.len()));
    }
    for (gl, wl) in g.iter().zip(&w) {
        // The host a benchmark ran on is this machine's, not the page's.
        if volatile && gl.starts_with("host ") && wl.starts_with("host ") {
            continue;
        }
        let (gs, gn) = numbers(gl);
        let (ws, wn) = numbers(wl);
        if gs != ws || gn.len() != wn.len() {
            return Err(format!("line differs:\n  got  {gl}\n  page {wl}"));
        }
        if volatile || wl.contains("µs") || wl.contains("lines/s") || wl.contains(" ns ") {
            continue; // timings
        }
        for ((a, _), (p, e)) in gn.iter().zip(&wn) {
            if !same_number(*a, *p, *e) {
                return Err(format!(
                    "{command}: {a} where the page prints {p}:\n  got  {gl}\n  page {wl}"
                ));
            }
        }
    }
    Ok(())
}

fn compare_json(
    got: &serde_json::Value,
    want: &serde_json::Value,
    path: &str,
) -> Result<(), String> {
    use serde_json::Value;
    match (got, want) {
        (Value::Object(a), Value::Object(b)) => {
            let (ka, kb): (Vec<_>, Vec<_>) = (a.keys().collect(), b.keys().collect());
            if ka != kb {
                return Err(format!("{path}: keys {ka:?}, the page has {kb:?}"));
            }
            for (k, v) in b {
                if k == "time_us" {
                    continue;
                }
                compare_json(&a[k], v, &format!("{path}.{k}"))?;
            }
            Ok(())
        }
        (Value::Array(a), Value::Array(b)) if a.len() == b.len() => {
            for (i, (x, y)) in a.iter().zip(b).enumerate() {
                compare_json(x, y, &format!("{path}[{i}]"))?;
            }
            Ok(())
        }
        (Value::Number(a), Value::Number(b)) => {
            let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
            if (a.abs() < 1e-9 && b.abs() < 1e-9) || (a - b).abs() <= 1e-9 * b.abs().max(1.0) {
                Ok(())
            } else {
                Err(format!("{path}: {a}, the page has {b}"))
            }
        }
        (a, b) if a == b => Ok(()),
        (a, b) => Err(format!("{path}: {a}, the page has {b}")),
    }
}

/// Replaces each block's lines by its new content (`SCREWKIT_UPDATE_DOCS=1`).
fn paste(doc: &Path, mut updates: Vec<(std::ops::Range<usize>, String)>) {
    let path = root().join(doc);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    updates.sort_by_key(|(r, _)| std::cmp::Reverse(r.start));
    for (range, content) in updates {
        lines.splice(range, content.lines().map(String::from));
    }
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
}

#[test]
fn every_pasted_output_is_what_the_command_prints() {
    let update = std::env::var_os("SCREWKIT_UPDATE_DOCS").is_some();
    let mut failures = Vec::new();
    let mut count = 0;
    for doc in documents() {
        let dir = scratch(&format!(
            "out-{}",
            doc.file_stem().unwrap().to_string_lossy()
        ));
        let mut updates = Vec::new();
        for ex in examples(&doc) {
            count += 1;
            let got = run(&ex.command, &dir);
            let r = if ex.lang == "json" {
                match (
                    serde_json::from_str(got.trim()),
                    serde_json::from_str(ex.block.trim()),
                ) {
                    (Ok(g), Ok(w)) => compare_json(&g, &w, "$"),
                    (g, w) => Err(format!("not JSON: {:?} / {:?}", g.err(), w.err())),
                }
            } else {
                compare_text(&ex.command, &got, &ex.block, ex.volatile)
            };
            if let Err(e) = r {
                if update {
                    updates.push((ex.lines.clone(), got.trim_end().to_string()));
                }
                let shown = match ex.command.strip_prefix("$ ") {
                    Some(shell) => shell.to_string(),
                    None => format!("screwkit {}", ex.command),
                };
                failures.push(format!(
                    "{}:{}: `{shown}`: {e}\n--- it prints:\n{got}",
                    doc.display(),
                    ex.lines.start,
                ));
            }
        }
        if update && !updates.is_empty() {
            paste(&doc, updates);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(count >= 20, "only {count} examples found");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The lines of every ```sh block of a document, with their 1-based line numbers.
fn shell_lines(doc: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(root().join(doc)).unwrap();
    let mut out = Vec::new();
    let mut inside = false;
    for (i, l) in text.lines().enumerate() {
        if l == "```sh" {
            inside = true;
        } else if inside && l == "```" {
            inside = false;
        } else if inside {
            out.push((i + 1, l.to_string()));
        }
    }
    out
}

/// A set-up step (installing, building, a venv): run by `cargo xtask newcomer` (the README's
/// "Start here" block) and `cargo xtask wheel`, not here.
fn is_setup(line: &str) -> bool {
    [
        "pip ",
        "cargo ",
        "python3 -m venv",
        "maturin ",
        ". ",
        "source ",
    ]
    .iter()
    .any(|p| line.starts_with(p))
}

/// A scratch folder holding the bundled `assets/` (a symbolic link), for commands that write.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("screwkit-docs-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    std::os::unix::fs::symlink(
        root().join("assets").canonicalize().unwrap(),
        dir.join("assets"),
    )
    .unwrap();
    dir
}

#[test]
fn every_shell_command_of_the_pages_runs() {
    let path = path_with_bin();
    let mut failures = Vec::new();
    let mut ran = 0;
    for doc in documents() {
        let dir = scratch(&doc.file_stem().unwrap().to_string_lossy());
        for (line, l) in shell_lines(&doc) {
            let l = l.trim();
            if l.is_empty() || l.starts_with('#') || is_setup(l) {
                continue;
            }
            ran += 1;
            let out = Command::new("sh")
                .args(["-c", l])
                .current_dir(&dir)
                .env("PATH", &path)
                .output()
                .unwrap();
            if !out.status.success() {
                failures.push(format!(
                    "{}:{line}: `{l}` failed ({}): {}",
                    doc.display(),
                    out.status,
                    String::from_utf8_lossy(&out.stderr)
                ));
            }
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(ran >= 3, "only {ran} shell lines run");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn no_page_names_the_ci_data() {
    for doc in documents() {
        let text = std::fs::read_to_string(root().join(&doc)).unwrap();
        for (i, l) in text.lines().enumerate() {
            assert!(
                !l.contains(&["../", "shared"].concat()) && !l.contains("SCREWKIT_SHARED"),
                "{}:{}: names the project's CI data, which a user does not have: {l}",
                doc.display(),
                i + 1
            );
        }
    }
}

/// Every JSON family word the library can print is in the guide's JSON contract.
#[test]
fn every_family_word_is_in_the_json_contract() {
    let text = std::fs::read_to_string(root().join("docs/guide/json.md")).unwrap();
    let contract = text
        .split("## JSON contract")
        .nth(1)
        .and_then(|t| t.split("\n## ").next())
        .expect("a JSON contract section");
    for f in screwkit_solve::family::Family::ALL {
        assert!(
            contract.contains(&format!("`{}`", f.word())),
            "{} is not in the guide's JSON contract (docs/guide/json.md)",
            f.word()
        );
    }
}

/// Every relative link of the README and the guide points at a file of the repository.
#[test]
fn every_relative_link_resolves() {
    for doc in documents() {
        let text = std::fs::read_to_string(root().join(&doc)).unwrap();
        let base = root().join(doc.parent().unwrap());
        for (i, l) in text.lines().enumerate() {
            for target in l.split("](").skip(1).filter_map(|t| t.split(')').next()) {
                let target = target.split('#').next().unwrap_or("");
                if target.is_empty() || target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                assert!(
                    base.join(target).exists(),
                    "{}:{}: the link {target} points at nothing",
                    doc.display(),
                    i + 1
                );
            }
        }
    }
}

/// Code reaches the project's CI data only through the `SCREWKIT_SHARED_*` variables: no source
/// file of the workspace builds a path to `../shared` itself (a test would then read it on a
/// developer's machine and fail or skip silently on a newcomer's).
#[test]
fn no_code_builds_a_path_to_the_ci_data() {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            let name = e.file_name().to_string_lossy().into_owned();
            if p.is_dir() {
                if !name.starts_with('.') && name != "target" && name != "node_modules" {
                    walk(&p, out);
                }
            } else if ["rs", "py", "toml", "sh", "js"]
                .iter()
                .any(|x| name.ends_with(&format!(".{x}")))
            {
                out.push(p);
            }
        }
    }
    let mut files = Vec::new();
    for d in ["crates", "xtask", "src", "tests", "examples"] {
        walk(&root().join(d), &mut files);
    }
    assert!(files.len() > 50);
    // The ways code has spelled that path.
    let spellings = [
        ["\"../", "shared"].concat(),
        ["/../../../", "shared"].concat(),
        ["\"shared\"", " / "].concat(),
        ["join(\"../", "shared"].concat(),
    ];
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap_or_default();
        for (i, l) in text.lines().enumerate() {
            for s in &spellings {
                assert!(
                    !l.contains(s.as_str()),
                    "{}:{}: builds a path to the CI data; read SCREWKIT_SHARED_* instead: {l}",
                    f.display(),
                    i + 1
                );
            }
        }
    }
}
