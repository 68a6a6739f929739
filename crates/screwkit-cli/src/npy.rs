//! Binary batches: numpy's `.npy` format (version 1.0, little-endian float64, C order), read
//! and written a chunk of rows at a time so memory stays bounded whatever N is.
//!
//! The header (magic, version, Python dict) is `screwkit_reach::npz`'s, which writes the maps'
//! arrays; the reader here needs only `<f8` C-order arrays and the writer knows N up front.

use std::io::{BufReader, Read, Seek, Write};

use crate::output::{CliResult, Failure};

/// A `.npy` file of float64 rows being read.
pub struct NpyReader {
    file: BufReader<std::fs::File>,
    path: String,
    /// The array's shape.
    pub shape: Vec<usize>,
    /// Values per row (the product of all but the first dimension).
    pub row_len: usize,
    /// Rows not read yet.
    pub remaining: usize,
}

impl NpyReader {
    /// Opens a `.npy` file of float64 (`<f8`, C order).
    pub fn open(path: &str) -> CliResult<Self> {
        let err = |m: String| Failure(format!("{path}: {m}"));
        let mut file = BufReader::new(
            std::fs::File::open(path).map_err(|e| err(format!("cannot read the file: {e}")))?,
        );
        let h = screwkit_reach::npz::read_npy_header(&mut file).map_err(err)?;
        if !matches!(h.descr.as_str(), "<f8" | "=f8") {
            return Err(err(format!(
                "dtype '{}': expected float64 ('<f8'); convert with a.astype(np.float64)",
                h.descr
            )));
        }
        if h.fortran {
            return Err(err(
                "Fortran-ordered array: save np.ascontiguousarray(a)".into()
            ));
        }
        let shape = h.shape;
        if shape.is_empty() {
            return Err(err("a scalar, not an array of rows".into()));
        }
        let row_len: usize = shape[1..].iter().product();
        // The data must be exactly what the header says, checked before any output exists.
        let header = file.stream_position().unwrap_or(0);
        let data = shape.iter().product::<usize>() as u64 * 8;
        if let Ok(m) = file.get_ref().metadata() {
            if m.is_file() && m.len() != header + data {
                return Err(err(format!(
                    "the header says shape {shape:?} ({data} bytes of data) but the file holds {} bytes after it",
                    m.len().saturating_sub(header)
                )));
            }
        }
        Ok(Self {
            file,
            path: path.to_string(),
            remaining: shape[0],
            shape,
            row_len,
        })
    }

    /// Reads up to `max` rows into `out` (cleared first); returns how many.
    pub fn read_rows(&mut self, max: usize, out: &mut Vec<f64>) -> CliResult<usize> {
        let rows = max.min(self.remaining);
        let mut bytes = vec![0u8; rows * self.row_len * 8];
        self.file
            .read_exact(&mut bytes)
            .map_err(|e| Failure(format!("{}: the data ends early: {e}", self.path)))?;
        out.clear();
        out.extend(
            bytes
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes(b.try_into().expect("8 bytes"))),
        );
        self.remaining -= rows;
        Ok(rows)
    }
}

/// A `.npy` file being written (the shape is known up front).
pub struct NpyWriter {
    file: screwkit_reach::atomic::AtomicFile,
    path: String,
    left: usize,
}

impl NpyWriter {
    /// Starts `path` for an array of `shape` with `descr` (`<f8` or `|b1`): written to a
    /// temporary file beside it and renamed over it by [`NpyWriter::finish`], so a failed run
    /// leaves an existing file as it was.
    pub fn create(path: &str, shape: &[usize], descr: &str) -> CliResult<Self> {
        let err = |e: std::io::Error| Failure(format!("{path}: cannot write: {e}"));
        let mut file = screwkit_reach::atomic::AtomicFile::create(path).map_err(err)?;
        file.write_all(&screwkit_reach::npz::npy_header(descr, shape))
            .map_err(err)?;
        let item = if descr == "|b1" { 1 } else { 8 };
        Ok(Self {
            file,
            path: path.to_string(),
            left: shape.iter().product::<usize>() * item,
        })
    }

    /// Appends float64 values.
    pub fn write_f64(&mut self, values: &[f64]) -> CliResult {
        let mut bytes = Vec::with_capacity(values.len() * 8);
        for v in values {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        self.write_bytes(&bytes)
    }

    /// Appends raw bytes (booleans as 0/1).
    pub fn write_bytes(&mut self, bytes: &[u8]) -> CliResult {
        self.left = self
            .left
            .checked_sub(bytes.len())
            .ok_or_else(|| Failure(format!("{}: more data than the header says", self.path)))?;
        self.file
            .write_all(bytes)
            .map_err(|e| Failure(format!("{}: cannot write: {e}", self.path)))
    }

    /// Flushes; an error if fewer values were written than the shape says.
    pub fn finish(self) -> CliResult {
        if self.left != 0 {
            return Err(Failure(format!(
                "{}: {} bytes missing",
                self.path, self.left
            )));
        }
        let path = self.path;
        self.file
            .commit()
            .map_err(|e| Failure(format!("{path}: cannot write: {e}")))
    }
}

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
    screwkit_reach::atomic::check_distinct(&[input], &[output]).map_err(Failure)?;
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
