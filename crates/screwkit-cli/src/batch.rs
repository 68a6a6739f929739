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
use screwkit_solve::SolveError;
use serde_json::{json, Value};

use crate::output::{CliResult, Failure};

/// A non-blank input line: its 1-based number in the file and its text (or why it has none).
pub struct Line {
    /// 1-based line number in the file.
    pub number: usize,
    /// The text.
    pub text: String,
    /// Set when the line is not text (invalid UTF-8): its error.
    pub bad: Option<String>,
}

/// Lines per chunk: enough to keep every core busy, few enough that memory stays small.
pub const CHUNK: usize = 4096;

/// The longest input line read (1 MiB: a 4 × 4 target with a seed is under 1 KiB); a longer
/// line is that line's error, its rest skipped.
pub const MAX_LINE: usize = 1 << 20;
/// The most bytes skipped while looking for the end of an overlong line: beyond this (64 MiB
/// without a newline, `--input /dev/zero`) the input is not lines, and the run stops.
const MAX_SKIP: usize = 64 << 20;

/// One line into `buf` (at most [`MAX_LINE`] bytes kept): `None` at the end of the input,
/// `Some(true)` when the line was longer (its rest read past and dropped).
fn read_line(reader: &mut dyn BufRead, buf: &mut Vec<u8>) -> std::io::Result<Option<bool>> {
    let (mut long, mut skipped, mut any) = (false, 0usize, false);
    loop {
        let chunk = match reader.fill_buf() {
            Ok(c) => c,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if chunk.is_empty() {
            return Ok(any.then_some(long));
        }
        any = true;
        let (part, done) = match chunk.iter().position(|&b| b == b'\n') {
            Some(i) => (&chunk[..=i], true),
            None => (chunk, false),
        };
        let n = part.len();
        if long || buf.len() + n > MAX_LINE {
            long = true;
            skipped += n;
            if skipped > MAX_SKIP {
                return Err(std::io::Error::other(format!(
                    "more than {} MiB without a line break: not JSON lines",
                    MAX_SKIP >> 20
                )));
            }
        } else {
            buf.extend_from_slice(part);
        }
        reader.consume(n);
        if done {
            return Ok(Some(long));
        }
    }
}

/// Reads FILE or stdin (`-`) on a thread and hands out its non-blank lines through a bounded
/// channel (at most 2 × [`CHUNK`] lines in flight).
fn spawn_reader(input: &str) -> CliResult<std::sync::mpsc::Receiver<Result<Line, String>>> {
    let reader: Box<dyn BufRead + Send> = if input == "-" {
        Box::new(std::io::BufReader::new(std::io::stdin()))
    } else {
        let f = std::fs::File::open(input)
            .map_err(|e| Failure(format!("{input}: cannot read the file: {e}")))?;
        screwkit_model::input::note_read(&f, std::path::Path::new(input));
        Box::new(std::io::BufReader::new(f))
    };
    let (tx, rx) = std::sync::mpsc::sync_channel(2 * CHUNK);
    let name = input.to_string();
    std::thread::spawn(move || {
        let mut reader = reader;
        let mut buf = Vec::new();
        let mut number = 0;
        loop {
            buf.clear();
            let long = match read_line(&mut reader, &mut buf) {
                Ok(None) => return,
                Ok(Some(long)) => long,
                Err(e) => {
                    let _ = tx.send(Err(format!("{name}: line {}: {e}", number + 1)));
                    return;
                }
            };
            number += 1;
            while matches!(buf.last(), Some(b'\n' | b'\r')) {
                buf.pop();
            }
            // A byte-order mark (the first line of a file saved by some editors).
            let text = buf.strip_prefix("\u{feff}".as_bytes()).unwrap_or(&buf);
            let line = match std::str::from_utf8(text) {
                _ if long => Line {
                    number,
                    text: String::new(),
                    bad: Some(format!(
                        "the line is longer than {} MiB (one JSON object per line)",
                        MAX_LINE >> 20
                    )),
                },
                Ok(t) if t.trim().is_empty() => continue,
                Ok(t) => Line {
                    number,
                    text: t.to_string(),
                    bad: None,
                },
                Err(_) => Line {
                    number,
                    text: String::new(),
                    bad: Some("the line is not valid UTF-8 text".into()),
                },
            };
            if tx.send(Ok(line)).is_err() {
                return;
            }
        }
    });
    Ok(rx)
}

/// Streams FILE or stdin (`-`) through `process` one chunk of lines at a time — `process(lines,
/// first_row)` gives each line's JSON output and whether it succeeded — writing the answers in
/// input order and flushing after every chunk. A chunk is up to [`CHUNK`] lines, or whatever
/// has arrived when the input pauses (so a program that writes one line and waits gets its
/// answer at once: the co-process use). Memory stays bounded by two chunks of lines and one
/// of answers, whatever the input's size. Rows are numbered from 0 over the whole input. A
/// summary goes to stderr; the run fails (exit code 1) when any line failed.
pub fn stream(
    input: &str,
    mut process: impl FnMut(&[Line], usize) -> CliResult<Vec<(String, bool)>>,
) -> CliResult {
    use std::sync::mpsc::RecvTimeoutError;
    let started = Instant::now();
    let rx = spawn_reader(input)?;
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = ProgressBar::new_spinner();
        if let Ok(style) = ProgressStyle::with_template("{spinner} {pos} lines, {per_sec}") {
            b.set_style(style);
        }
        b
    });
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let write_err = crate::output::write_error;
    let (mut total, mut failures) = (0usize, 0usize);
    while let Ok(first) = rx.recv() {
        let mut chunk = vec![first.map_err(Failure)?];
        while chunk.len() < CHUNK {
            match rx.recv_timeout(std::time::Duration::from_micros(300)) {
                Ok(line) => chunk.push(line.map_err(Failure)?),
                Err(RecvTimeoutError::Timeout | RecvTimeoutError::Disconnected) => break,
            }
        }
        for (text, ok) in process(&chunk, total)? {
            failures += usize::from(!ok);
            writeln!(out, "{text}").map_err(write_err)?;
        }
        out.flush().map_err(write_err)?;
        total += chunk.len();
        if let Some(b) = &bar {
            b.set_position(total as u64);
        }
    }
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

/// Each line's output in order — `output(k)` = (value, ok), or `{"error", "line"}` for a line
/// in `errors` — formatted in parallel.
pub fn outputs(
    lines: &[Line],
    errors: &[Option<String>],
    output: impl Fn(usize) -> (Value, bool) + Sync,
) -> Vec<(String, bool)> {
    (0..lines.len())
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
        .collect()
}

/// Parses one line as a JSON object.
pub fn parse_object(text: &str) -> Result<serde_json::Map<String, Value>, String> {
    match serde_json::from_str::<Value>(text) {
        Ok(Value::Object(m)) => Ok(m),
        Ok(_) => Err("expected a JSON object".into()),
        Err(e) => Err(format!("invalid JSON: {e}")),
    }
}

/// A line's optional `"seed"` (an array of numbers), checked by `check` (the model's
/// configuration check); the error starts with `seed: `.
pub fn optional_seed<E: std::fmt::Display>(
    obj: &serde_json::Map<String, Value>,
    check: impl Fn(&[f64]) -> Result<(), E>,
) -> Result<Option<Vec<f64>>, String> {
    if !obj.contains_key("seed") {
        return Ok(None);
    }
    let s = numbers(obj, "seed")?;
    check(&s).map_err(|e| format!("seed: {e}"))?;
    Ok(Some(s))
}

/// Reads a JSON array of finite numbers from `obj[key]`.
pub fn numbers(obj: &serde_json::Map<String, Value>, key: &str) -> Result<Vec<f64>, String> {
    let arr = obj
        .get(key)
        .and_then(Value::as_array)
        .ok_or_else(|| format!("missing \"{key}\" (an array of numbers)"))?;
    arr.iter()
        .enumerate()
        .map(|(i, v)| match v.as_f64() {
            Some(x) if x.is_finite() => Ok(x),
            Some(_) => Err(format!("\"{key}\"[{i}] is not a finite number")),
            None => Err(format!("\"{key}\"[{i}] is not a number: {v}")),
        })
        .collect()
}

/// Parses every line in parallel with `parse`.
pub fn parse_rows<T: Send>(
    lines: &[Line],
    parse: impl Fn(&str) -> Result<T, String> + Sync,
) -> Vec<Result<T, String>> {
    lines
        .par_iter()
        .map(|l| match &l.bad {
            Some(e) => Err(e.clone()),
            None => parse(&l.text),
        })
        .collect()
}

/// The `{"q": [...]}` rows of what a query is about (the chain's q, or the tree's configuration).
pub fn about_q_rows(
    about: &screwkit_service::query::About<'_>,
    lines: &[Line],
) -> (Vec<f64>, Vec<Option<String>>) {
    q_rows_checked(lines, about.q_len(), |q| about.check_q(q))
}

/// The `{"q": [...]}` rows of a pose query (the chain's q, or the tree's configuration).
pub fn poses_q_rows(
    poses: &screwkit_service::query::Poses<'_>,
    lines: &[Line],
) -> (Vec<f64>, Vec<Option<String>>) {
    q_rows_checked(lines, poses.q_len(), |q| poses.check_q(q))
}

/// The `{"q": [...]}` lines checked by `check`, as rows of `width` values.
pub fn q_rows_checked(
    lines: &[Line],
    width: usize,
    check: impl Fn(&[f64]) -> Result<(), SolveError> + Sync,
) -> (Vec<f64>, Vec<Option<String>>) {
    let parsed = parse_rows(lines, |text| {
        let q = numbers(&parse_object(text)?, "q")?;
        check(&q).map_err(|e| e.to_string())?;
        Ok(q)
    });
    flatten(parsed, width)
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
