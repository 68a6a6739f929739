//! Binary batches: numpy's `.npy` format (version 1.0, little-endian float64, C order), read
//! and written a chunk of rows at a time so memory stays bounded whatever N is (the CLI's
//! `--input FILE.npy` batches). The header is [`super::npz`]'s.

use std::io::{BufReader, Read, Seek, Write};
use std::path::Path;

use super::atomic::AtomicFile;
use super::npz::{npy_header, read_npy_header};
use super::FileError;

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
    pub fn open(path: &str) -> Result<Self, FileError> {
        let err = |m: String| FileError::Format(format!("{path}: {m}"));
        let file = std::fs::File::open(path)
            .map_err(|e| FileError::io_doing(path, "cannot read the file", e))?;
        screwkit_model::input::note_read(&file, Path::new(path));
        let mut file = BufReader::new(file);
        let h = read_npy_header(&mut file).map_err(err)?;
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
        // Sizes from an untrusted header: a product past any file's size is an error, not an
        // overflow.
        let size = |dims: &[usize]| {
            dims.iter()
                .try_fold(1u64, |a, &d| a.checked_mul(d as u64))
                .filter(|n| n.checked_mul(8).is_some_and(|b| b <= i64::MAX as u64))
        };
        let (Some(row), Some(all)) = (size(&shape[1..]), size(&shape)) else {
            return Err(err(format!(
                "shape {shape:?} has more elements than any file can hold"
            )));
        };
        let row_len = row as usize;
        // The data must be exactly what the header says, checked before any output exists.
        let header = file.stream_position().unwrap_or(0);
        let data = all * 8;
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
    pub fn read_rows(&mut self, max: usize, out: &mut Vec<f64>) -> Result<usize, FileError> {
        let rows = max.min(self.remaining);
        // (A header read from a pipe is not held to a file size: its claims are bounded here.)
        let len = rows
            .checked_mul(self.row_len)
            .and_then(|n| n.checked_mul(8))
            .filter(|n| *n <= 1 << 32)
            .ok_or_else(|| {
                FileError::Format(format!(
                    "{}: {rows} rows of {} values are more than one read takes (4 GiB)",
                    self.path, self.row_len
                ))
            })?;
        let mut bytes = vec![0u8; len];
        self.file
            .read_exact(&mut bytes)
            .map_err(|e| FileError::io_doing(&self.path, "the data ends early", e))?;
        out.clear();
        out.extend(super::from_le8(&bytes, f64::from_le_bytes));
        self.remaining -= rows;
        Ok(rows)
    }
}

/// A `.npy` file being written (the shape is known up front).
pub struct NpyWriter {
    file: AtomicFile,
    path: String,
    left: usize,
}

impl NpyWriter {
    /// Starts `path` for an array of `shape` with `descr` (`<f8` or `|b1`): written to a
    /// temporary file beside it and renamed over it by [`NpyWriter::finish`], so a failed run
    /// leaves an existing file as it was.
    pub fn create(path: &str, shape: &[usize], descr: &str) -> Result<Self, FileError> {
        let err = |e: std::io::Error| FileError::io_doing(path, "cannot write", e);
        let mut file = AtomicFile::create(path).map_err(err)?;
        file.write_all(&npy_header(descr, shape)).map_err(err)?;
        let item = if descr == "|b1" { 1 } else { 8 };
        Ok(Self {
            file,
            path: path.to_string(),
            left: shape.iter().product::<usize>() * item,
        })
    }

    /// Appends float64 values.
    pub fn write_f64(&mut self, values: &[f64]) -> Result<(), FileError> {
        self.write_bytes(&super::le_bytes(values, f64::to_le_bytes))
    }

    /// Appends raw bytes (booleans as 0/1).
    pub fn write_bytes(&mut self, bytes: &[u8]) -> Result<(), FileError> {
        self.left = self.left.checked_sub(bytes.len()).ok_or_else(|| {
            FileError::Format(format!("{}: more data than the header says", self.path))
        })?;
        self.file
            .write_all(bytes)
            .map_err(|e| FileError::io_doing(&self.path, "cannot write", e))
    }

    /// Flushes; an error if fewer values were written than the shape says.
    pub fn finish(self) -> Result<(), FileError> {
        if self.left != 0 {
            return Err(FileError::Format(format!(
                "{}: {} bytes missing",
                self.path, self.left
            )));
        }
        let path = self.path;
        self.file
            .commit()
            .map_err(|e| FileError::io_doing(&path, "cannot write", e))
    }
}
