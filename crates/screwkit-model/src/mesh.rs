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

/// How a mesh's mass is spread when its body is weighed from its geoms: MuJoCo's
/// `<mesh inertia="…">` (its default `legacy`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MeshInertia {
    /// MuJoCo's default: every pyramid from a centre to a triangle counted with a positive
    /// volume (which overcounts a non-convex mesh's volume, as MuJoCo does).
    Legacy,
    /// The solid's own volume integrals (signed pyramids: exact for a closed, consistently
    /// oriented mesh).
    Exact,
    /// The mass on the surface, uniformly (MuJoCo's `shell`).
    Shell,
}

/// A mesh's mass properties per unit density: its volume (its area for a shell), its centre
/// of mass and its rotational inertia about that centre (xx, xy, xz, yy, yz, zz), in the mesh's
/// own coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshMass {
    /// Volume (m³), or area (m²) for [`MeshInertia::Shell`].
    pub measure: f64,
    /// Centre of mass.
    pub com: [f64; 3],
    /// Ī about the centre of mass per unit density.
    pub inertia: [f64; 6],
}

/// The mass properties of `mesh` spread as `mode` says, by MuJoCo's construction (its
/// `mjCMesh::Process`): the pyramids from the area-weighted centroid of the triangles c_f to
/// each triangle (volume V_t = ((g_t − c_f) · n_t) A_t / 3, g_t the triangle's centroid, n_t its
/// unit normal, A_t its area; |V_t| for `Legacy`) give the volume and the centre of mass
/// Σ V_t (¾ g_t + ¼ c_f) / Σ V_t; then the pyramids from that centre give the second moments
/// ∫ x_i x_j dV = V_t / 20 (2 Σ_v v_i v_j + Σ_{v≠w} v_i w_j) over each tetrahedron's three
/// triangle vertices (a shell: A_t / 12, its pyramids' volumes replaced by the areas), and
/// Ī = tr(P) 1 − P. An error (one sentence) when the mesh has no area or volume or the
/// result is not a rigid body's (a misoriented mesh).
pub fn mass_properties(mesh: &TriMesh, mode: MeshInertia) -> Result<MeshMass, String> {
    const MIN: f64 = 1e-15;
    let v = |k: u32| -> [f64; 3] { mesh.vertices[k as usize] };
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let dot = |a: [f64; 3], b: [f64; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    // (area, unit normal, centroid) of a triangle; a degenerate one has no normal.
    let triangle = |d: [f64; 3], e: [f64; 3], f: [f64; 3]| {
        let (x, y) = (sub(e, d), sub(f, d));
        let c = [
            x[1] * y[2] - x[2] * y[1],
            x[2] * y[0] - x[0] * y[2],
            x[0] * y[1] - x[1] * y[0],
        ];
        let norm = dot(c, c).sqrt();
        let centre = std::array::from_fn(|i| (d[i] + e[i] + f[i]) / 3.0);
        let n = if norm > 0.0 {
            c.map(|x| x / norm)
        } else {
            [0.0; 3]
        };
        (norm / 2.0, n, centre)
    };
    let (mut area, mut facecen) = (0.0, [0.0; 3]);
    for t in &mesh.triangles {
        let (a, _, g) = triangle(v(t[0]), v(t[1]), v(t[2]));
        area += a;
        for i in 0..3 {
            facecen[i] += a * g[i];
        }
    }
    if area.is_nan() || area < MIN {
        return Err("the mesh's surface area is too small to weigh".into());
    }
    facecen = facecen.map(|x| x / area);
    // The measure and centre of mass.
    let (mut measure, mut com) = (0.0, [0.0; 3]);
    for t in &mesh.triangles {
        let (a, n, g) = triangle(v(t[0]), v(t[1]), v(t[2]));
        let w = match mode {
            MeshInertia::Shell => a,
            MeshInertia::Exact => dot(sub(g, facecen), n) * a / 3.0,
            MeshInertia::Legacy => (dot(sub(g, facecen), n) * a / 3.0).abs(),
        };
        measure += w;
        for i in 0..3 {
            com[i] += w * (0.75 * g[i] + 0.25 * facecen[i]);
        }
    }
    if measure.is_nan() || measure < MIN {
        return Err(if measure < 0.0 {
            "the mesh's volume is negative (its triangles face inwards)".into()
        } else {
            "the mesh's volume is too small to weigh (an open or flat mesh: try inertia=\"shell\")"
                .into()
        });
    }
    com = com.map(|x| x / measure);
    // Second moments about the centre of mass.
    const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];
    let (mut p, mut total) = ([0.0; 6], 0.0);
    for t in &mesh.triangles {
        let (d, e, f) = (sub(v(t[0]), com), sub(v(t[1]), com), sub(v(t[2]), com));
        let (a, n, g) = triangle(d, e, f);
        let (w, c) = match mode {
            MeshInertia::Shell => (a, 12.0),
            MeshInertia::Exact => (dot(g, n) * a / 3.0, 20.0),
            MeshInertia::Legacy => ((dot(g, n) * a / 3.0).abs(), 20.0),
        };
        total += w;
        for (k, &(i, j)) in PAIRS.iter().enumerate() {
            p[k] += w / c
                * (2.0 * (d[i] * d[j] + e[i] * e[j] + f[i] * f[j])
                    + d[i] * e[j]
                    + d[j] * e[i]
                    + d[i] * f[j]
                    + d[j] * f[i]
                    + e[i] * f[j]
                    + e[j] * f[i]);
        }
    }
    let inertia = [p[1] + p[2], -p[3], -p[4], p[0] + p[2], -p[5], p[0] + p[1]];
    let tensor = nalgebra::Matrix3::new(
        inertia[0], inertia[1], inertia[2], inertia[1], inertia[3], inertia[4], inertia[2],
        inertia[4], inertia[5],
    );
    let mut e: Vec<f64> = tensor.symmetric_eigenvalues().iter().copied().collect();
    e.sort_by(f64::total_cmp);
    let ok =
        e[2] > 0.0 && e.iter().all(|x| x.is_finite()) && e[0] + e[1] >= e[2] * (1.0 - 1e-6) - 1e-9;
    if !ok || total.is_nan() || total < MIN {
        return Err(format!(
            "the mesh's inertia is not a rigid body's (principal moments {:.3e}, {:.3e}, {:.3e}): misoriented triangles?",
            e[0], e[1], e[2]
        ));
    }
    Ok(MeshMass {
        measure: total,
        com,
        inertia,
    })
}
