//! A motion to play back: a sequence of configurations (one row each), read from an `.npy`
//! array (T, n) of float64, or JSON: an array of rows, or JSON lines each a row or
//! `{"q": row}` (what `ik_trajectory` and the CLI's batches write). Untrusted: at most
//! [`MAX_FRAMES`] rows, every row the same length, every value finite; an error names the file
//! and the row.

use std::path::Path;

use super::FileError;

/// The most rows a motion may have (a minute at 1 kHz is 60,000).
pub const MAX_FRAMES: usize = 200_000;

/// Reads the motion at `path` (`.npy` by its extension, JSON otherwise).
pub fn read(path: &Path) -> Result<Vec<Vec<f64>>, FileError> {
    let name = path.display().to_string();
    let bad = |m: String| FileError::Format(format!("{name}: {m}"));
    let rows: Vec<Vec<f64>> = if path.extension().is_some_and(|e| e == "npy") {
        let mut r = super::npy::NpyReader::open(&name)?;
        if r.shape.len() != 2 {
            return Err(bad(format!(
                "shape {:?}: a motion is a 2-D array (frames, joint values)",
                r.shape
            )));
        }
        if r.shape[0] > MAX_FRAMES {
            return Err(bad(format!("{} frames: at most {MAX_FRAMES}", r.shape[0])));
        }
        let n = r.row_len;
        let mut flat = Vec::new();
        r.read_rows(r.shape[0], &mut flat)?;
        flat.chunks(n.max(1)).map(<[f64]>::to_vec).collect()
    } else {
        let text = crate::load::Source::Path(path.to_path_buf())
            .read()
            .map_err(|e| bad(e.to_string()))?;
        let row = |v: &serde_json::Value, at: usize| -> Result<Vec<f64>, FileError> {
            let v = v.get("q").unwrap_or(v);
            let a = v.as_array().ok_or_else(|| {
                bad(format!(
                    "row {at}: expected an array of numbers or {{\"q\": [...]}}"
                ))
            })?;
            a.iter()
                .map(|x| {
                    x.as_f64()
                        .ok_or_else(|| bad(format!("row {at}: {x} is not a number")))
                })
                .collect()
        };
        match serde_json::from_str::<serde_json::Value>(&text) {
            Ok(serde_json::Value::Array(all)) if all.iter().all(|r| !r.is_number()) => {
                if all.len() > MAX_FRAMES {
                    return Err(bad(format!("{} frames: at most {MAX_FRAMES}", all.len())));
                }
                all.iter()
                    .enumerate()
                    .map(|(k, r)| row(r, k))
                    .collect::<Result<_, _>>()?
            }
            _ => {
                let mut out = Vec::new();
                for (k, line) in text.lines().enumerate() {
                    if line.trim().is_empty() {
                        continue;
                    }
                    if out.len() == MAX_FRAMES {
                        return Err(bad(format!("more than {MAX_FRAMES} frames")));
                    }
                    let v: serde_json::Value = serde_json::from_str(line)
                        .map_err(|e| bad(format!("line {}: {e}", k + 1)))?;
                    out.push(row(&v, out.len())?);
                }
                out
            }
        }
    };
    if rows.is_empty() {
        return Err(bad("no frames".into()));
    }
    for (k, r) in rows.iter().enumerate() {
        if r.len() != rows[0].len() {
            return Err(bad(format!(
                "row {k} has {} values, row 0 has {}",
                r.len(),
                rows[0].len()
            )));
        }
        if let Some(x) = r.iter().find(|x| !x.is_finite()) {
            return Err(bad(format!("row {k}: {x} is not finite")));
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("screwkit-motion-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    /// The same two frames from .npy, a JSON array, JSON lines of rows and of {"q": row}.
    #[test]
    fn every_form_gives_the_frames() {
        let want = vec![vec![0.5, -1.0, 2.0], vec![0.25, 0.0, 1e-3]];
        let flat: Vec<f64> = want.iter().flatten().copied().collect();
        let mut npy = crate::io::npz::npy_header("<f8", &[2, 3]);
        npy.extend(crate::io::le_bytes(&flat, f64::to_le_bytes));
        for (name, bytes) in [
            ("m.npy", npy),
            ("a.json", b"[[0.5, -1.0, 2.0], [0.25, 0.0, 0.001]]".to_vec()),
            (
                "l.jsonl",
                b"[0.5, -1.0, 2.0]\n\n[0.25, 0.0, 0.001]\n".to_vec(),
            ),
            (
                "q.jsonl",
                b"{\"q\": [0.5, -1.0, 2.0]}\n{\"q\": [0.25, 0.0, 0.001], \"t\": 0.1}\n".to_vec(),
            ),
        ] {
            assert_eq!(read(&file(name, &bytes)).unwrap(), want, "{name}");
        }
    }

    /// Ragged rows, words, non-finite values, nothing at all and a missing file: an error
    /// naming the file (and the row).
    #[test]
    fn bad_motions_are_named() {
        for (name, bytes, says) in [
            ("ragged.json", &b"[[1, 2], [1]]"[..], "row 1"),
            ("word.jsonl", b"[1, 2]\n[1, \"a\"]\n", "row 1"),
            ("inf.json", b"[[1, 2], [1e999, 2]]", "out of range"),
            ("empty.json", b"[]", "no frames"),
            ("garbage.jsonl", b"[1, 2]\nnot json\n", "line 2"),
        ] {
            let e = read(&file(name, bytes)).unwrap_err().to_string();
            assert!(e.contains(name) && e.contains(says), "{name}: {e}");
        }
        let mut npy = crate::io::npz::npy_header("<f8", &[2, 1]);
        npy.extend(crate::io::le_bytes(&[1.0, f64::NAN], f64::to_le_bytes));
        let e = read(&file("nan.npy", &npy)).unwrap_err().to_string();
        assert!(e.contains("nan.npy") && e.contains("row 1"), "{e}");
        // Too many frames: in .npy,
        // a JSON array and JSON lines; a header claiming more values than the file holds.
        let mut npy = crate::io::npz::npy_header("<f8", &[MAX_FRAMES + 1, 1]);
        npy.extend(crate::io::le_bytes(
            &vec![0.0; MAX_FRAMES + 1],
            f64::to_le_bytes,
        ));
        let e = read(&file("long.npy", &npy)).unwrap_err().to_string();
        assert!(
            e.contains("long.npy") && e.contains("at most 200000"),
            "{e}"
        );
        let many = format!("[{}[0]]", "[0],".repeat(MAX_FRAMES));
        let e = read(&file("long.json", many.as_bytes()))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("long.json") && e.contains("at most 200000"),
            "{e}"
        );
        let e = read(&file(
            "long.jsonl",
            "[0]\n".repeat(MAX_FRAMES + 1).as_bytes(),
        ))
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("long.jsonl") && e.contains("more than 200000"),
            "{e}"
        );
        let mut npy = crate::io::npz::npy_header("<f8", &[10, 1 << 40]);
        npy.extend(crate::io::le_bytes(&[1.0; 4], f64::to_le_bytes));
        let e = read(&file("wide.npy", &npy)).unwrap_err().to_string();
        assert!(e.contains("wide.npy"), "{e}");
        let e = read(Path::new("/nonexistent/m.npy"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("m.npy"), "{e}");
    }
}
