//! Batch mode: JSON lines in, JSON lines out in the same order, all cores, a progress bar on a
//! terminal, a summary line on stderr.

use std::io::{BufRead, IsTerminal, Write};
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use screwkit_solve::{Kinematics, Workspace};
use serde_json::{json, Value};

use crate::output::{CliResult, Failure};

/// Lines (1-based number, text) of FILE or stdin (`-`), blank lines skipped.
pub fn read_lines(input: &str) -> CliResult<Vec<(usize, String)>> {
    let reader: Box<dyn BufRead> = if input == "-" {
        Box::new(std::io::stdin().lock())
    } else {
        let f = std::fs::File::open(input)
            .map_err(|e| Failure(format!("{input}: cannot read the file: {e}")))?;
        Box::new(std::io::BufReader::new(f))
    };
    let mut out = Vec::new();
    for (i, line) in reader.lines().enumerate() {
        let line = line.map_err(|e| Failure(format!("{input}: line {}: {e}", i + 1)))?;
        if !line.trim().is_empty() {
            out.push((i + 1, line));
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

/// Runs `f` on every line in parallel (one workspace per worker), prints the results in input
/// order and a summary; returns the number of failures. `f` gives (output, ok).
pub fn run<F>(kin: &Kinematics, lines: Vec<(usize, String)>, f: F) -> CliResult<usize>
where
    F: Fn(&mut Workspace, usize, &str) -> Result<(Value, bool), String> + Sync,
{
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
    let start = Instant::now();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    let mut failures = 0usize;
    for chunk in lines.chunks(4096) {
        let results: Vec<(Value, bool)> = chunk
            .par_iter()
            .enumerate()
            .map_init(
                || Workspace::new(kin),
                |ws, (_, (line_no, text))| match f(ws, *line_no, text) {
                    Ok(r) => r,
                    Err(e) => (json!({"error": e, "line": line_no}), false),
                },
            )
            .collect();
        for (v, ok) in results {
            if !ok {
                failures += 1;
            }
            writeln!(out, "{v}").map_err(|e| Failure(format!("cannot write the output: {e}")))?;
        }
        if let Some(b) = &bar {
            b.inc(chunk.len() as u64);
        }
    }
    out.flush()
        .map_err(|e| Failure(format!("cannot write the output: {e}")))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "screwkit: {total} lines, {failures} failed, {:.0} lines/s",
        if secs > 0.0 { total as f64 / secs } else { 0.0 }
    );
    Ok(failures)
}

/// Batch mode for commands whose input lines are `{"q": [...]}`: runs `f` on each q and fails
/// (exit code 1) when any line failed.
pub fn run_q_lines<F>(kin: &Kinematics, input: &str, f: F) -> CliResult
where
    F: Fn(&mut Workspace, &[f64]) -> Result<Value, String> + Sync,
{
    let lines = read_lines(input)?;
    let failures = run(kin, lines, |ws, _, text| {
        let obj = parse_object(text)?;
        let q = numbers(&obj, "q")?;
        Ok((f(ws, &q)?, true))
    })?;
    if failures == 0 {
        Ok(())
    } else {
        Err(Failure(format!("{failures} line(s) failed")))
    }
}
