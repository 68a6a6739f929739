//! Binary batches: numpy's `.npy` format (version 1.0, little-endian float64, C order), read
//! and written a chunk of rows at a time so memory stays bounded whatever N is.
//!
//! The reader and writer are the floor's (`screwkit_service::io::npy`); this file holds what
//! the command line adds: the `--output` rule, the status file's name, the chunked run.

pub use screwkit_service::io::npy::{NpyReader, NpyWriter};

use crate::output::{CliResult, Failure};

/// The output file of a binary batch: `Some` when the input is a `.npy` (which needs
/// `--output FILE.npy`), `None` for JSON lines (where `--output` is refused).
pub fn binary<'a>(input: &str, output: Option<&'a str>) -> CliResult<Option<&'a str>> {
    match (input.ends_with(".npy"), output) {
        (true, Some(o)) => Ok(Some(o)),
        (true, None) => Err(Failure(format!(
            "{input}: a .npy input needs --output FILE.npy"
        ))),
        (false, Some(_)) => Err(Failure(
            "--output is for .npy batches (--input FILE.npy); JSON lines go to stdout".into(),
        )),
        (false, None) => Ok(None),
    }
}

/// The status file beside an IK batch's solutions: `OUT.status.npy` (`OUT` without its
/// `.npy`); a special file (`/dev/null`) takes the status too.
pub fn status_path(output: &str) -> String {
    if std::fs::metadata(output).is_ok_and(|m| !m.is_file() && !m.is_dir()) {
        return output.to_string();
    }
    match output.strip_suffix(".npy") {
        Some(stem) => format!("{stem}.status.npy"),
        None => format!("{output}.status.npy"),
    }
}

/// Rows per chunk of a binary batch (a few MB of input and output at a time).
pub const NPY_CHUNK: usize = 1 << 16;

/// A binary batch: rows of `row_len` float64 from `input` (shape (N, …) whose row has
/// `row_len` values) through `solve(rows, first_row, out)` into `output` of shape (N, tail…),
/// chunk by chunk. Rows the library reports as failed are NaN in the output and counted; the
/// summary goes to stderr and the run fails when any row failed.
pub fn run(
    input: &str,
    output: &str,
    row_len: usize,
    what: &str,
    tail: &[usize],
    mut solve: impl FnMut(&[f64], usize, &mut [f64]) -> Result<(), screwkit_solve::SolveError>,
) -> CliResult {
    let started = std::time::Instant::now();
    screwkit_service::io::atomic::check_distinct(&[input], &[output]).map_err(Failure)?;
    let mut r = NpyReader::open(input)?;
    if r.row_len != row_len || r.shape.len() < 2 {
        return Err(Failure(format!(
            "{input}: shape {:?}: expected (N, {what})",
            r.shape
        )));
    }
    let n = r.shape[0];
    let width: usize = tail.iter().product();
    let mut shape = vec![n];
    shape.extend_from_slice(tail);
    let mut w = NpyWriter::create(output, &shape, "<f8")?;
    let (mut buf, mut out) = (Vec::new(), Vec::new());
    let (mut first, mut failed) = (0usize, 0usize);
    while r.remaining > 0 {
        let rows = r.read_rows(NPY_CHUNK, &mut buf)?;
        out.clear();
        out.resize(rows * width, 0.0);
        match solve(&buf, first, &mut out) {
            Ok(()) => {}
            Err(screwkit_solve::SolveError::Rows(bad)) => failed += bad.len(),
            Err(e) => return Err(Failure(e.to_string())),
        }
        w.write_f64(&out)?;
        first += rows;
    }
    w.finish()?;
    summary(n, failed, started)
}

/// The stderr summary of a binary batch, and its outcome.
pub fn summary(rows: usize, failed: usize, started: std::time::Instant) -> CliResult {
    let secs = started.elapsed().as_secs_f64();
    eprintln!(
        "screwkit: {rows} rows, {failed} failed, {:.0} rows/s",
        if secs > 0.0 { rows as f64 / secs } else { 0.0 }
    );
    if failed == 0 {
        Ok(())
    } else {
        Err(Failure(format!(
            "{failed} row(s) failed (NaN in the output)"
        )))
    }
}
