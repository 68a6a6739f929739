//! Output files written whole or not at all: a temporary file in the same folder, renamed
//! over the destination only when complete. A failed or interrupted run leaves the previous
//! file as it was (never a header-only or half-written one), and an output that is also an
//! input is refused before anything is touched ([`check_distinct`]). The CLI's `.npy`
//! batches, the maps and their merge, pictures and tables all write through here.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The temporary files being written now, for [`remove_pending`].
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Removes every temporary file not yet committed or dropped: what a program's Ctrl-C
/// handler calls before it exits (the CLI's does), so an interrupted run leaves nothing.
pub fn remove_pending() {
    let pending = std::mem::take(&mut *PENDING.lock().unwrap_or_else(|e| e.into_inner()));
    for p in pending {
        let _ = std::fs::remove_file(p);
    }
}

fn forget_pending(tmp: &Path) {
    PENDING
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .retain(|p| p != tmp);
}

/// A file being written to a temporary name beside `path`; [`AtomicFile::commit`] renames it
/// into place, dropping it uncommitted removes it.
#[derive(Debug)]
pub struct AtomicFile {
    tmp: PathBuf,
    path: PathBuf,
    file: Option<BufWriter<File>>,
    /// Special files (`/dev/null`, a pipe, a terminal) are written in place: they cannot be
    /// renamed over and hold nothing to lose.
    direct: bool,
}

impl AtomicFile {
    /// Starts writing `path` (its folder must exist). Refused, before anything is written,
    /// when `path` is a file this process read as input (a robot file, an include, a batch, a
    /// map: [`screwkit_model::input::read_as_input`]), by any name.
    pub fn create(path: impl AsRef<Path>) -> std::io::Result<Self> {
        let path = path.as_ref().to_path_buf();
        if let Some(why) = protected_input(&path) {
            return Err(std::io::Error::new(std::io::ErrorKind::InvalidInput, why));
        }
        let special = std::fs::metadata(&path).is_ok_and(|m| !m.is_file() && !m.is_dir());
        if special {
            let file = std::fs::OpenOptions::new().write(true).open(&path)?;
            return Ok(Self {
                tmp: path.clone(),
                path,
                file: Some(BufWriter::with_capacity(1 << 20, file)),
                direct: true,
            });
        }
        let name = path
            .file_name()
            .ok_or_else(|| std::io::Error::other("not a file name"))?
            .to_string_lossy()
            .into_owned();
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
        let tmp_name = format!(".{name}.{}.tmp", std::process::id());
        let tmp = dir.map_or_else(|| PathBuf::from(&tmp_name), |d| d.join(&tmp_name));
        let file = File::create(&tmp)?;
        PENDING
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .push(tmp.clone());
        Ok(Self {
            tmp,
            path,
            file: Some(BufWriter::with_capacity(1 << 20, file)),
            direct: false,
        })
    }

    /// The destination.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Flushes, syncs and renames the file into place.
    pub fn commit(mut self) -> std::io::Result<()> {
        let file = self
            .file
            .take()
            .ok_or_else(|| std::io::Error::other("already committed"))?;
        let file = file.into_inner().map_err(|e| e.into_error())?;
        if self.direct {
            return Ok(());
        }
        file.sync_all()?;
        drop(file);
        let r = std::fs::rename(&self.tmp, &self.path);
        if r.is_err() {
            let _ = std::fs::remove_file(&self.tmp);
        }
        forget_pending(&self.tmp);
        r
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.file {
            Some(f) => f.write(buf),
            None => Err(std::io::Error::other("already committed")),
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.file {
            Some(f) => f.flush(),
            None => Ok(()),
        }
    }
}

impl std::io::Seek for AtomicFile {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        match &mut self.file {
            Some(f) => f.seek(pos),
            None => Err(std::io::Error::other("already committed")),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.take().is_some() && !self.direct {
            let _ = std::fs::remove_file(&self.tmp);
            forget_pending(&self.tmp);
        }
    }
}

/// Whether two paths name the same existing file (same device and inode on Unix; the same
/// canonical path elsewhere).
pub fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(x), Ok(y)) => x.dev() == y.dev() && x.ino() == y.ino() && x.is_file(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (a.canonicalize(), b.canonicalize()) {
            (Ok(x), Ok(y)) => x == y,
            _ => false,
        }
    }
}

/// An error naming the pair when any output is also an input (`--input a.npy --output
/// a.npy`, `merge -o s0.npz s0.npz s1.npz`), or when two outputs are one file.
pub fn check_distinct(inputs: &[&str], outputs: &[&str]) -> Result<(), String> {
    for (k, o) in outputs.iter().enumerate() {
        if let Some(i) = inputs
            .iter()
            .find(|i| same_file(Path::new(i), Path::new(o)))
        {
            return Err(format!(
                "the output {o} is also an input ({i}): write it to another file"
            ));
        }
        if let Some(o2) = outputs[k + 1..]
            .iter()
            .find(|o2| o2 == &o || same_file(Path::new(o2), Path::new(o)))
        {
            return Err(format!("two outputs are the same file ({o} and {o2})"));
        }
    }
    Ok(())
}

/// Why `path` may not be written: it is a protected input of this run (the robot's file, an
/// include: [`screwkit_model::input::InputFile`]), by any name.
fn protected_input(path: &Path) -> Option<String> {
    let input = screwkit_model::input::read_as_input(path)?;
    Some(if input == path {
        "is an input of this run: write the output to another file".to_string()
    } else {
        format!(
            "is an input of this run ({}): write the output to another file",
            input.display()
        )
    })
}

/// Checks, before any work, that none of `outputs` is a protected input of this run (what
/// [`AtomicFile::create`] would refuse later): for commands that write several files, so that
/// the first is not written when the second would be refused.
pub fn check_writable(outputs: &[&str]) -> Result<(), String> {
    for o in outputs {
        if let Some(why) = protected_input(Path::new(o)) {
            return Err(format!("{o}: {why}"));
        }
    }
    Ok(())
}

/// Writes `bytes` to `path` whole or not at all ([`AtomicFile`]).
pub fn write(path: impl AsRef<Path>, bytes: &[u8]) -> std::io::Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes)?;
    f.commit()
}
