//! Batch mode: JSON lines in, JSON lines out in the same order, a summary line on stderr.
//!
//! The text side (parsing and printing JSON, a few µs a line) runs here, in parallel; the
//! kinematics of all rows goes through the library's batch functions (`screwkit_solve::batch`)
//! in one call, so a row gives the same answer here, from the library batch and from a single
//! call. Rows are the non-blank lines, numbered from 0 in input order (the row index of the
//! library batch, which seeds IK restarts); errors name the 1-based line number in the file.

use std::io::{BufRead, IsTerminal, Write};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use screwkit_solve::{Kinematics, SolveError};
use serde_json::{json, Value};

use crate::output::{CliResult, Failure};

/// A non-blank input line: its 1-based number in the file and its text.
pub struct Line {
    /// 1-based line number in the file.
    pub number: usize,
    /// The text.
    pub text: String,
}

/// The non-blank lines of FILE or stdin (`-`).
pub fn read_lines(input: &str) -> CliResult<Vec<Line>> {
    let reader: Box<dyn BufRead> = if input == "-" {
        Box::new(std::io::stdin().lock())
    } else {
        let f = std::fs::File::open(input)
            .map_err(|e| Failure(format!("{input}: cannot read the file: {e}")))?;
        Box::new(std::io::BufReader::new(f))
    };
    let mut out = Vec::new();
    for (i, line) in reader.lines().enumerate() {
        let text = line.map_err(|e| Failure(format!("{input}: line {}: {e}", i + 1)))?;
        if !text.trim().is_empty() {
            out.push(Line {
                number: i + 1,
                text,
            });
        }
    }
    Ok(out)
}

/// Parses one line as a JSON object.
pub fn parse_object(text: &str) -> Result<serde_json::Map<String, Value>, String> {
    match serde_json::from_str::<Value>(text) {
        Ok(Value::Object(m)) => Ok(m),
        Ok(_) => Err("expected a JSON object".into()),
        Err(e) => Err(format!("invalid JSON: {e}")),
    }
}

/// Reads a JSON array of finite numbers from `obj[key]`.
pub fn numbers(obj: &serde_json::Map<String, Value>, key: &str) -> Result<Vec<f64>, String> {
    let arr = obj
        .get(key)
        .and_then(Value::as_array)
        .ok_or_else(|| format!("missing \"{key}\" (an array of numbers)"))?;
    arr.iter()
        .enumerate()
        .map(|(i, v)| {
            v.as_f64()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("\"{key}\"[{i}] is not a finite number"))
        })
        .collect()
}

/// Parses every line in parallel with `parse`.
pub fn parse_rows<T: Send>(
    lines: &[Line],
    parse: impl Fn(&str) -> Result<T, String> + Sync,
) -> Vec<Result<T, String>> {
    lines.par_iter().map(|l| parse(&l.text)).collect()
}

/// The `{"q": [...]}` lines as a flat N × dof buffer (NaN rows where a line is bad) and the
/// per-line parse errors.
pub fn q_rows(kin: &Kinematics, lines: &[Line]) -> (Vec<f64>, Vec<Option<String>>) {
    let parsed = parse_rows(lines, |text| {
        let q = numbers(&parse_object(text)?, "q")?;
        kin.check_q(&q).map_err(|e| e.to_string())?;
        Ok(q)
    });
    flatten(parsed, kin.dof())
}

/// Rows of `width` values into one flat buffer (NaN for the failed rows) and the errors.
pub fn flatten(
    rows: Vec<Result<Vec<f64>, String>>,
    width: usize,
) -> (Vec<f64>, Vec<Option<String>>) {
    let mut flat = vec![f64::NAN; rows.len() * width];
    let errors = rows
        .into_iter()
        .enumerate()
        .map(|(k, r)| match r {
            Ok(v) => {
                flat[k * width..(k + 1) * width].copy_from_slice(&v);
                None
            }
            Err(e) => Some(e),
        })
        .collect();
    (flat, errors)
}

/// Adds the rows a library batch reported as failed (and that parsing had not already failed)
/// to `errors`; any other error of the batch is the run's failure.
pub fn merge_row_errors(
    result: Result<(), SolveError>,
    errors: &mut [Option<String>],
) -> CliResult {
    match result {
        Ok(()) => Ok(()),
        Err(SolveError::Rows(rows)) => {
            for r in rows {
                errors[r.row].get_or_insert_with(|| r.error.to_string());
            }
            Ok(())
        }
        Err(e) => Err(Failure(e.to_string())),
    }
}

/// Prints one JSON line per row — `output(k)` = (value, ok), or `{"error", "line"}` for a row
/// in `errors` — in input order, a progress bar on a terminal for large inputs, and the summary
/// on stderr. Fails (exit code 1) when any row failed or was not ok.
pub fn emit(
    lines: &[Line],
    errors: &[Option<String>],
    started: Instant,
    output: impl Fn(usize) -> (Value, bool) + Sync,
) -> CliResult {
    let total = lines.len();
    let bar = (std::io::stderr().is_terminal() && total >= 10_000).then(|| {
        let b = ProgressBar::new(total as u64);
        if let Ok(style) =
            ProgressStyle::with_template("{bar:40} {pos}/{len} lines, {per_sec}, eta {eta}")
        {
            b.set_style(style);
        }
        b
    });
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut failures = 0usize;
    let write_err = |e: std::io::Error| Failure(format!("cannot write the output: {e}"));
    for start in (0..total).step_by(4096) {
        let end = (start + 4096).min(total);
        let texts: Vec<(String, bool)> = (start..end)
            .into_par_iter()
            .map(|k| match &errors[k] {
                Some(e) => (
                    json!({"error": e, "line": lines[k].number}).to_string(),
                    false,
                ),
                None => {
                    let (v, ok) = output(k);
                    (v.to_string(), ok)
                }
            })
            .collect();
        for (text, ok) in texts {
            failures += usize::from(!ok);
            writeln!(out, "{text}").map_err(write_err)?;
        }
        if let Some(b) = &bar {
            b.inc((end - start) as u64);
        }
    }
    out.flush().map_err(write_err)?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let secs = started.elapsed().as_secs_f64();
    eprintln!(
        "screwkit: {total} lines, {failures} failed, {:.0} lines/s",
        if secs > 0.0 { total as f64 / secs } else { 0.0 }
    );
    if failures == 0 {
        Ok(())
    } else {
        Err(Failure(format!("{failures} line(s) failed")))
    }
}
