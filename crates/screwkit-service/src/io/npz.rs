//! numpy's `.npz`: a zip archive of `.npy` arrays, entries stored (not compressed), zip64 so an
//! entry may exceed 4 GiB, every timestamp 1980-01-01 so the same arrays give the same bytes.
//! An entry is written a chunk at a time (its shape known up front), so a map far larger than
//! memory streams to disk; entries are read back the same way.
//!
//! The `.npy` header (format 1.0): the magic `\x93NUMPY`, version 1 0, a little-endian u16
//! header length, and a Python dict `{'descr': …, 'fortran_order': False, 'shape': (…), }`
//! padded with spaces and a newline to a multiple of 64 bytes.

use std::fs::File;
use std::io::{BufReader, Read, Write};

use zip::write::SimpleFileOptions;

use super::FileError;

const MAGIC: &[u8] = b"\x93NUMPY";

/// The bytes of a `.npy` header for an array of `descr` (`<f8`, `<i8`, `<U12`, …) and `shape`.
pub fn npy_header(descr: &str, shape: &[usize]) -> Vec<u8> {
    let dims = match shape.len() {
        1 => format!("({},)", shape[0]),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|d| d.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut dict = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {dims}, }}");
    let unpadded = MAGIC.len() + 2 + 2 + dict.len() + 1;
    dict.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    dict.push('\n');
    let mut out = MAGIC.to_vec();
    out.extend_from_slice(&[1, 0]);
    out.extend_from_slice(&(dict.len() as u16).to_le_bytes());
    out.extend_from_slice(dict.as_bytes());
    out
}

/// A `.npz` archive being written, one entry at a time.
pub struct NpzWriter {
    zip: zip::ZipWriter<super::atomic::AtomicFile>,
    path: String,
    open: Option<(String, usize)>,
}

impl NpzWriter {
    /// Starts `path`: written to a temporary file beside it and renamed over it by
    /// [`NpzWriter::finish`] ([`super::atomic`]); an existing file is untouched until then.
    pub fn create(path: &str) -> Result<Self, FileError> {
        let file = super::atomic::AtomicFile::create(path).map_err(|e| FileError::io(path, e))?;
        Ok(Self {
            zip: zip::ZipWriter::new(file),
            path: path.to_string(),
            open: None,
        })
    }

    fn zip_err(&self, e: zip::result::ZipError) -> FileError {
        FileError::io(&self.path, std::io::Error::other(e))
    }

    /// Starts entry `name.npy` holding an array of `descr` and `shape`; its data follows with
    /// [`NpzWriter::write_f64`] / [`NpzWriter::write_bytes`] and must add up to the shape.
    pub fn start(&mut self, name: &str, descr: &str, shape: &[usize]) -> Result<(), FileError> {
        self.check_closed()?;
        let options = SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Stored)
            .large_file(true)
            .last_modified_time(zip::DateTime::default());
        self.zip
            .start_file(format!("{name}.npy"), options)
            .map_err(|e| self.zip_err(e))?;
        let header = npy_header(descr, shape);
        self.write_raw(&header)?;
        let item = descr_size(descr)?;
        self.open = Some((name.to_string(), shape.iter().product::<usize>() * item));
        Ok(())
    }

    fn check_closed(&self) -> Result<(), FileError> {
        match &self.open {
            Some((name, left)) if *left > 0 => Err(FileError::Format(format!(
                "{}: entry {name} is {left} bytes short",
                self.path
            ))),
            _ => Ok(()),
        }
    }

    fn write_raw(&mut self, bytes: &[u8]) -> Result<(), FileError> {
        let path = self.path.clone();
        self.zip
            .write_all(bytes)
            .map_err(|e| FileError::io(&path, e))
    }

    /// Raw little-endian data of the open entry.
    pub fn write_bytes(&mut self, bytes: &[u8]) -> Result<(), FileError> {
        match &mut self.open {
            Some((_, left)) if *left >= bytes.len() => *left -= bytes.len(),
            _ => {
                return Err(FileError::Format(format!(
                    "{}: more data than the entry's shape",
                    self.path
                )))
            }
        }
        self.write_raw(bytes)
    }

    /// float64 values of the open entry.
    pub fn write_f64(&mut self, values: &[f64]) -> Result<(), FileError> {
        self.write_bytes(&super::le_bytes(values, f64::to_le_bytes))
    }

    /// int64 values of the open entry.
    pub fn write_i64(&mut self, values: &[i64]) -> Result<(), FileError> {
        self.write_bytes(&super::le_bytes(values, i64::to_le_bytes))
    }

    /// A whole float64 entry.
    pub fn f64_array(&mut self, name: &str, shape: &[usize], v: &[f64]) -> Result<(), FileError> {
        self.start(name, "<f8", shape)?;
        self.write_f64(v)
    }

    /// A whole int64 entry.
    pub fn i64_array(&mut self, name: &str, shape: &[usize], v: &[i64]) -> Result<(), FileError> {
        self.start(name, "<i8", shape)?;
        self.write_i64(v)
    }

    /// A 0-d unicode entry (numpy `str`): UTF-32LE code points.
    pub fn text(&mut self, name: &str, s: &str) -> Result<(), FileError> {
        let chars: Vec<char> = s.chars().collect();
        self.start(name, &format!("<U{}", chars.len().max(1)), &[])?;
        let mut bytes = Vec::with_capacity(4 * chars.len().max(1));
        for c in &chars {
            bytes.extend_from_slice(&(*c as u32).to_le_bytes());
        }
        if chars.is_empty() {
            bytes.extend_from_slice(&[0; 4]);
        }
        self.write_bytes(&bytes)
    }

    /// Closes the last entry and writes the archive's directory.
    pub fn finish(self) -> Result<(), FileError> {
        self.check_closed()?;
        let path = self.path.clone();
        let inner = self
            .zip
            .finish()
            .map_err(|e| FileError::io(&path, std::io::Error::other(e)))?;
        inner.commit().map_err(|e| FileError::io(&path, e))
    }
}

/// The size in bytes of one element of `descr`.
fn descr_size(descr: &str) -> Result<usize, FileError> {
    match descr {
        "<f8" | "<i8" => Ok(8),
        "<i4" | "<f4" => Ok(4),
        "|u1" | "|b1" => Ok(1),
        d if d.starts_with("<U") => d[2..]
            .parse::<usize>()
            .map(|n| 4 * n)
            .map_err(|_| FileError::Format(format!("unknown dtype {d}"))),
        d => Err(FileError::Format(format!("unknown dtype {d}"))),
    }
}

/// A `.npz` archive being read.
pub struct NpzReader {
    zip: zip::ZipArchive<BufReader<File>>,
    path: String,
}

/// One entry being read: its dtype, shape and a reader positioned at its data.
pub struct NpyEntry<'a> {
    /// numpy dtype string (`<f8`, …).
    pub descr: String,
    /// The array's shape.
    pub shape: Vec<usize>,
    data: Box<dyn Read + 'a>,
    path: String,
}

impl NpzReader {
    /// Opens `path`.
    pub fn open(path: &str) -> Result<Self, FileError> {
        let file = File::open(path).map_err(|e| FileError::io(path, e))?;
        screwkit_model::input::note_read(&file, std::path::Path::new(path));
        let zip = zip::ZipArchive::new(BufReader::with_capacity(1 << 20, file))
            .map_err(|e| FileError::Format(format!("{path}: not an .npz archive: {e}")))?;
        Ok(Self {
            zip,
            path: path.to_string(),
        })
    }

    /// Entry `name` (without `.npy`).
    pub fn entry(&mut self, name: &str) -> Result<NpyEntry<'_>, FileError> {
        let path = self.path.clone();
        let mut file = self
            .zip
            .by_name(&format!("{name}.npy"))
            .map_err(|_| FileError::Format(format!("{path}: no array '{name}' in the map")))?;
        let (descr, shape) = read_header(&mut file, &path, name)?;
        Ok(NpyEntry {
            descr,
            shape,
            data: Box::new(file),
            path,
        })
    }

    /// A whole float64 entry with its shape (its CRC checked).
    pub fn f64_array(&mut self, name: &str) -> Result<(Vec<usize>, Vec<f64>), FileError> {
        self.array8(name, "<f8", f64::from_le_bytes)
    }

    /// A whole int64 entry with its shape (its CRC checked).
    pub fn i64_array(&mut self, name: &str) -> Result<(Vec<usize>, Vec<i64>), FileError> {
        self.array8(name, "<i8", i64::from_le_bytes)
    }

    /// A whole entry of 8-byte values of `descr` with its shape (its CRC checked).
    fn array8<T>(
        &mut self,
        name: &str,
        descr: &str,
        from: impl Fn([u8; 8]) -> T,
    ) -> Result<(Vec<usize>, Vec<T>), FileError> {
        let mut e = self.entry(name)?;
        e.expect(descr)?;
        let n: usize = e.shape.iter().product();
        let bytes = e.read_all(8 * n)?;
        Ok((e.shape.clone(), super::from_le8(&bytes, from)))
    }

    /// A 0-d unicode entry as a string.
    pub fn text(&mut self, name: &str) -> Result<String, FileError> {
        let mut e = self.entry(name)?;
        let n = e
            .descr
            .strip_prefix("<U")
            .and_then(|d| d.parse::<usize>().ok())
            .ok_or_else(|| FileError::Format(format!("{}: '{name}' is not text", e.path)))?;
        let bytes = e.read_all(n.saturating_mul(4))?;
        Ok(bytes
            .chunks_exact(4)
            .map(|b| u32::from_le_bytes(b.try_into().unwrap_or([0; 4])))
            .take_while(|&c| c != 0)
            .filter_map(char::from_u32)
            .collect())
    }
}

impl NpyEntry<'_> {
    /// An error unless the entry's dtype is `descr`.
    pub fn expect(&self, descr: &str) -> Result<(), FileError> {
        if self.descr == descr {
            Ok(())
        } else {
            Err(FileError::Format(format!(
                "{}: an array of dtype {} where {descr} was expected",
                self.path, self.descr
            )))
        }
    }

    /// All `n` bytes of the data, then the end of the entry (where the zip CRC is checked).
    /// Memory grows with the bytes that really arrive, not with what a header claims.
    pub fn read_all(&mut self, n: usize) -> Result<Vec<u8>, FileError> {
        let mut bytes = Vec::with_capacity(n.min(1 << 20));
        (&mut self.data)
            .take(n as u64)
            .read_to_end(&mut bytes)
            .map_err(|e| FileError::Format(format!("{}: damaged array: {e}", self.path)))?;
        if bytes.len() != n {
            return Err(FileError::Format(format!(
                "{}: truncated array ({} of {n} bytes)",
                self.path,
                bytes.len()
            )));
        }
        self.finish()?;
        Ok(bytes)
    }

    /// Reads to the end of the entry: an error if data is left over or the zip CRC does not
    /// match (a damaged file).
    pub fn finish(&mut self) -> Result<(), FileError> {
        let mut rest = [0u8; 1];
        match self.data.read(&mut rest) {
            Ok(0) => Ok(()),
            Ok(_) => Err(FileError::Format(format!(
                "{}: more data than the array's shape",
                self.path
            ))),
            Err(e) => Err(FileError::Format(format!(
                "{}: damaged array: {e}",
                self.path
            ))),
        }
    }

    /// The next `out.len()` bytes of data.
    pub fn read_bytes(&mut self, out: &mut [u8]) -> Result<(), FileError> {
        self.data
            .read_exact(out)
            .map_err(|e| FileError::Format(format!("{}: truncated array: {e}", self.path)))
    }

    /// The next `out.len()` float64 values.
    pub fn read_f64(&mut self, out: &mut [f64]) -> Result<(), FileError> {
        let mut bytes = vec![0u8; 8 * out.len()];
        self.read_bytes(&mut bytes)?;
        for (o, b) in out.iter_mut().zip(bytes.chunks_exact(8)) {
            *o = f64::from_le_bytes(b.try_into().unwrap_or([0; 8]));
        }
        Ok(())
    }
}

/// A `.npy` header: dtype string (`<f8`, …), C or Fortran order, shape.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NpyHeader {
    /// numpy dtype string, without quotes.
    pub descr: String,
    /// True for a Fortran-ordered (column-major) array.
    pub fortran: bool,
    /// The array's shape (empty for a 0-d array).
    pub shape: Vec<usize>,
}

/// The longest `.npy` header read (numpy's own reader refuses more than 10,000 bytes).
pub const MAX_NPY_HEADER: usize = 1 << 16;
/// The most elements a `.npy` shape may declare (2^56: an exabyte of float64), so that byte
/// counts never overflow; a shape beyond the file's real size is caught when it is read.
pub const MAX_NPY_ELEMENTS: usize = 1 << 56;

/// Reads a `.npy` header (format 1.0, 2.0 or 3.0) from `r`, leaving it at the data. The error
/// says what is wrong in a few words ("not a .npy file (no \x93NUMPY magic)", "truncated
/// header", "bad shape …"); the caller adds the file's name.
pub fn read_npy_header(r: &mut impl Read) -> Result<NpyHeader, String> {
    let mut head = [0u8; 10];
    r.read_exact(&mut head)
        .map_err(|_| "not a .npy file (too short)".to_string())?;
    if &head[..6] != MAGIC {
        return Err("not a .npy file (no \\x93NUMPY magic)".into());
    }
    let len = match head[6] {
        1 => u16::from_le_bytes([head[8], head[9]]) as usize,
        2 | 3 => {
            let mut more = [0u8; 2];
            r.read_exact(&mut more)
                .map_err(|_| "truncated header".to_string())?;
            u32::from_le_bytes([head[8], head[9], more[0], more[1]]) as usize
        }
        v => return Err(format!(".npy version {v} is not supported")),
    };
    if len > MAX_NPY_HEADER {
        return Err(format!(
            "a header of {len} bytes (more than {MAX_NPY_HEADER}: numpy writes a few hundred)"
        ));
    }
    let mut dict = vec![0u8; len];
    r.read_exact(&mut dict)
        .map_err(|_| "truncated header".to_string())?;
    let dict = String::from_utf8_lossy(&dict).to_string();
    let field = |key: &str| -> Option<String> {
        let start = dict.find(&format!("'{key}':"))? + key.len() + 3;
        let rest = dict[start..].trim_start();
        let end = if rest.starts_with('(') {
            rest.find(')')? + 1
        } else {
            rest.find(',').or_else(|| rest.find('}'))?
        };
        Some(rest[..end].trim().trim_matches('\'').to_string())
    };
    let descr = field("descr").ok_or_else(|| "no dtype in the header".to_string())?;
    let fortran = field("fortran_order").as_deref() == Some("True");
    let shape_text = field("shape").ok_or_else(|| "no shape in the header".to_string())?;
    let shape = shape_text
        .trim_matches(|c| c == '(' || c == ')')
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<usize>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|_| format!("bad shape {shape_text}"))?;
    shape
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .filter(|&n| n <= MAX_NPY_ELEMENTS)
        .ok_or_else(|| format!("shape {shape_text} has more elements than any file can hold"))?;
    Ok(NpyHeader {
        descr,
        fortran,
        shape,
    })
}

/// The (descr, shape) of entry `name`'s header, C order required.
fn read_header(
    r: &mut impl Read,
    path: &str,
    name: &str,
) -> Result<(String, Vec<usize>), FileError> {
    let bad = |why: &str| FileError::Format(format!("{path}: array '{name}': {why}"));
    let h = read_npy_header(r).map_err(|e| bad(&e))?;
    if h.fortran {
        return Err(bad("Fortran order is not read"));
    }
    Ok((h.descr, h.shape))
}

/// Copies entry `name` of `from` into the open entry of `to`, `chunk` bytes at a time (the
/// merge of shards: memory bounded whatever the entry's size).
pub fn copy_entry(
    from: &mut NpzReader,
    name: &str,
    to: &mut NpzWriter,
    chunk: usize,
) -> Result<Vec<usize>, FileError> {
    let mut e = from.entry(name)?;
    let total = e
        .shape
        .iter()
        .product::<usize>()
        .checked_mul(descr_size(&e.descr)?)
        .ok_or_else(|| FileError::Format(format!("{}: array '{name}' too large", e.path)))?;
    let shape = e.shape.clone();
    let mut buf = vec![0u8; chunk.max(1)];
    let mut left = total;
    while left > 0 {
        let n = left.min(buf.len());
        e.read_bytes(&mut buf[..n])?;
        to.write_bytes(&buf[..n])?;
        left -= n;
    }
    e.finish()?;
    Ok(shape)
}
