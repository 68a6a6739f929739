//! The README's pasted outputs are real: every `**`screwkit …`**` command followed by a
//! pasted block (and the batch example's `$ …` line) is run here and compared with the
//! block — the text line by line with every number equal to the digits printed, JSON
//! value by value. Timings (µs, lines/s, `time_us`) are compared as text around them only.
//! After a change of output, paste the new run into README.md.

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_screwkit");

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// (command line, pasted block, block language) of every checked example.
fn examples() -> Vec<(String, String, String)> {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
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
        if let Some(other) = l
            .strip_prefix("```")
            .filter(|s| !s.is_empty() && *s != "text" && *s != "json")
        {
            // A block of another language (python, sh, rust): not an output; it ends the
            // command's paragraph too.
            let _ = other;
            let end = i + 1 + lines[i + 1..].iter().position(|l| *l == "```").unwrap();
            let start_here =
                "cargo run --release -p screwkit-cli -- table assets/urdf/ur5.urdf --frame space";
            command = lines[i..end]
                .iter()
                .any(|l| l.contains(start_here))
                .then(|| "table assets/urdf/ur5.urdf --frame space".to_string());
            i = end;
        } else if let Some(lang) = l
            .strip_prefix("```")
            .filter(|s| *s == "text" || *s == "json")
        {
            let start = i + 1;
            let end = start + lines[start..].iter().position(|l| *l == "```").unwrap();
            let block = lines[start..end].join("\n");
            if let Some(shell) = block.strip_prefix("$ ") {
                let (cmd, output) = shell.split_once('\n').unwrap();
                out.push((format!("$ {cmd}"), output.to_string(), lang.to_string()));
            } else if let Some(c) = command.take() {
                last = Some(c.clone());
                let volatile = c.starts_with("bench ") || c.starts_with("reach ");
                if !volatile {
                    out.push((c, block, lang.to_string()));
                }
            }
            i = end;
        }
        i += 1;
    }
    out
}

fn run(command: &str) -> String {
    let out = if let Some(shell) = command.strip_prefix("$ ") {
        let shell = shell.replace("| screwkit ", &format!("| {BIN} "));
        Command::new("sh")
            .arg("-c")
            .arg(format!("{shell} 2>&1"))
            .current_dir(root())
            .output()
            .unwrap()
    } else {
        Command::new(BIN)
            .args(command.split_whitespace())
            .current_dir(root())
            .output()
            .unwrap()
    };
    String::from_utf8_lossy(&out.stdout).into_owned()
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

fn compare_text(command: &str, got: &str, want: &str) -> Result<(), String> {
    let (g, w): (Vec<&str>, Vec<&str>) = (got.trim_end().lines().collect(), want.lines().collect());
    if g.len() != w.len() {
        return Err(format!("{} lines, the README has {}", g.len(), w.len()));
    }
    for (gl, wl) in g.iter().zip(&w) {
        let (gs, gn) = numbers(gl);
        let (ws, wn) = numbers(wl);
        if gs != ws || gn.len() != wn.len() {
            return Err(format!("line differs:\n  got    {gl}\n  README {wl}"));
        }
        if wl.contains("µs") || wl.contains("lines/s") || wl.contains(" ns ") {
            continue; // timings
        }
        for ((a, _), (p, e)) in gn.iter().zip(&wn) {
            if !same_number(*a, *p, *e) {
                return Err(format!(
                    "{command}: {a} where the README prints {p}:\n  got    {gl}\n  README {wl}"
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
                return Err(format!("{path}: keys {ka:?}, the README has {kb:?}"));
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
                Err(format!("{path}: {a}, the README has {b}"))
            }
        }
        (a, b) if a == b => Ok(()),
        (a, b) => Err(format!("{path}: {a}, the README has {b}")),
    }
}

#[test]
fn every_pasted_output_is_what_the_command_prints() {
    let examples = examples();
    assert!(
        examples.len() >= 10,
        "only {} examples found",
        examples.len()
    );
    let mut failures = Vec::new();
    for (command, block, lang) in &examples {
        let got = run(command);
        let r = if lang == "json" {
            match (
                serde_json::from_str(got.trim()),
                serde_json::from_str(block.trim()),
            ) {
                (Ok(g), Ok(w)) => compare_json(&g, &w, "$"),
                (g, w) => Err(format!("not JSON: {:?} / {:?}", g.err(), w.err())),
            }
        } else {
            compare_text(command, &got, block)
        };
        if let Err(e) = r {
            failures.push(format!("`screwkit {command}`: {e}\n--- it prints:\n{got}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// Every JSON family word the library can print is in the README's JSON contract.
#[test]
fn every_family_word_is_in_the_json_contract() {
    let text = std::fs::read_to_string(root().join("README.md")).unwrap();
    let contract = text
        .split("## JSON contract")
        .nth(1)
        .and_then(|t| t.split("\n## ").next())
        .expect("a JSON contract section");
    for f in screwkit_solve::family::Family::ALL {
        assert!(
            contract.contains(&format!("`{}`", f.word())),
            "{} is not in the README's JSON contract",
            f.word()
        );
    }
}
