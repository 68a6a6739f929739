//! Triangle meshes from the files a robot names: STL (binary and ASCII), Wavefront OBJ and
//! COLLADA `.dae` (its `<unit>` and node transforms applied), through `mesh-loader` (openrr's
//! parser), told apart by extension and content.
//!
//! Every file is untrusted: it is read bounded by [`crate::input::MAX_FILE_BYTES`], an OBJ's
//! material library is not read (no other file is opened), and the result is checked: at
//! least one triangle, at most [`MAX_TRIANGLES`], every vertex finite, every index in range.
//! Errors name the file. mesh-loader 0.1.13 panics on some damaged COLLADA files (an index
//! past an empty array: found by this crate's fuzz target); its parse runs contained
//! ([`contained`]), so such a file is an error like any other.

use std::cell::Cell;
use std::path::Path;
use std::sync::Once;

/// The most triangles one mesh file may give (all its meshes together).
pub const MAX_TRIANGLES: usize = 4_000_000;

/// A triangle mesh: vertices (m, scaled) and triangles (indices into the vertices,
/// counter-clockwise seen from outside where the file says so).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TriMesh {
    /// The vertices.
    pub vertices: Vec<[f64; 3]>,
    /// The triangles.
    pub triangles: Vec<[u32; 3]>,
}

/// Reads the mesh file at `path`, every vertex multiplied by `scale` per axis; all the
/// file's meshes merged into one. The error is one sentence naming the file.
pub fn read_mesh(path: &Path, scale: [f64; 3]) -> Result<TriMesh, String> {
    let bytes = crate::input::read_file(path).map_err(|e| e.to_string())?;
    parse_mesh(&bytes, path, scale)
}

/// [`read_mesh`] of a file's bytes already read (`path` names it and gives its extension).
pub fn parse_mesh(bytes: &[u8], path: &Path, scale: [f64; 3]) -> Result<TriMesh, String> {
    let name = path.display();
    let refuse = |_: &Path| -> std::io::Result<Vec<u8>> {
        Err(std::io::Error::new(
            std::io::ErrorKind::Unsupported,
            "material libraries are not read",
        ))
    };
    let scene = contained(|| {
        mesh_loader::Loader::default().load_from_slice_with_reader(bytes, path, refuse)
    })
    .map_err(|e| format!("{name}: cannot read the mesh: the parser failed ({e})"))?
    .map_err(|e| format!("{name}: cannot read the mesh: {e}"))?;
    let mut out = TriMesh::default();
    for mesh in &scene.meshes {
        let base = out.vertices.len();
        if out.triangles.len() + mesh.faces.len() > MAX_TRIANGLES {
            return Err(format!(
                "{name}: more than {MAX_TRIANGLES} triangles (a collision mesh this large is a \
                 visual one: simplify it, or give the link a primitive)"
            ));
        }
        for v in &mesh.vertices {
            let p = [
                f64::from(v[0]) * scale[0],
                f64::from(v[1]) * scale[1],
                f64::from(v[2]) * scale[2],
            ];
            if p.iter().any(|x| !x.is_finite()) {
                return Err(format!("{name}: a vertex is not finite: {v:?}"));
            }
            out.vertices.push(p);
        }
        let count = mesh.vertices.len();
        let offset = u32::try_from(base)
            .map_err(|_| format!("{name}: more vertices than a mesh may index"))?;
        for f in &mesh.faces {
            if f.iter().any(|&i| i as usize >= count) {
                return Err(format!(
                    "{name}: a triangle {f:?} names a vertex past the {count} of its mesh"
                ));
            }
            out.triangles.push(f.map(|i| i + offset));
        }
    }
    if out.triangles.is_empty() {
        return Err(format!("{name}: the mesh has no triangles"));
    }
    Ok(out)
}

thread_local! {
    /// True while this thread runs a contained parse: its panics are not printed.
    static CONTAINED: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f`, third-party code (a parser, a geometry engine), turning a panic into an error:
/// the panic's message is returned, not printed (the process's panic hook is wrapped once,
/// and stays silent only for the thread inside a contained call; every other panic is reported
/// as before). Cheap on the way through: a thread-local flag and an unwind landing pad.
pub fn contained<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    static HOOK: Once = Once::new();
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if !CONTAINED.with(Cell::get) {
                previous(info);
            }
        }));
    });
    let was = CONTAINED.with(|c| c.replace(true));
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(f));
    CONTAINED.with(|c| c.set(was));
    result.map_err(|payload| {
        payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "a panic".into())
    })
}
