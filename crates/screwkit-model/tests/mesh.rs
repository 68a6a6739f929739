//! Mesh files (`screwkit_model::mesh`): one tetrahedron written as ASCII STL, binary STL, OBJ
//! and COLLADA (in millimetres, its `<unit>` applied) reads back as the same four points and
//! four triangles, scaled; a damaged, empty or unknown file is an error naming it.

use screwkit_model::mesh::read_mesh;

const TETRA: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];
const FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

fn ascii_stl() -> String {
    let mut s = String::from("solid t\n");
    for f in FACES {
        s.push_str(" facet normal 0 0 0\n  outer loop\n");
        for i in f {
            let p = TETRA[i];
            s.push_str(&format!("   vertex {} {} {}\n", p[0], p[1], p[2]));
        }
        s.push_str("  endloop\n endfacet\n");
    }
    s + "endsolid t\n"
}

fn binary_stl() -> Vec<u8> {
    let mut b = vec![0u8; 80];
    b.extend_from_slice(&(FACES.len() as u32).to_le_bytes());
    for f in FACES {
        b.extend_from_slice(&[0u8; 12]);
        for i in f {
            for x in TETRA[i] {
                b.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        b.extend_from_slice(&[0u8; 2]);
    }
    b
}

fn obj() -> String {
    let mut s = String::from("mtllib missing.mtl\n");
    for p in TETRA {
        s.push_str(&format!("v {} {} {}\n", p[0], p[1], p[2]));
    }
    for f in FACES {
        s.push_str(&format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1));
    }
    s
}

/// The tetrahedron in millimetres (`<unit meter="0.001">`), so that it reads back in metres.
fn collada() -> String {
    let positions: Vec<String> = TETRA
        .iter()
        .flatten()
        .map(|x| format!("{}", x * 1000.0))
        .collect();
    let indices: Vec<String> = FACES.iter().flatten().map(|i| i.to_string()).collect();
    format!(
        r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="t" name="t"><mesh>
      <source id="t-pos"><float_array id="t-pos-array" count="12">{p}</float_array>
        <technique_common><accessor source="#t-pos-array" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common></source>
      <vertices id="t-vtx"><input semantic="POSITION" source="#t-pos"/></vertices>
      <triangles count="4"><input semantic="VERTEX" source="#t-vtx" offset="0"/><p>{i}</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n">
    <instance_geometry url="#t"/></node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##,
        p = positions.join(" "),
        i = indices.join(" ")
    )
}

/// The set of triangles as sets of points (any vertex order or duplication).
fn triangles(m: &screwkit_model::mesh::TriMesh) -> Vec<Vec<[i64; 3]>> {
    let mut out: Vec<Vec<[i64; 3]>> = m
        .triangles
        .iter()
        .map(|t| {
            let mut pts: Vec<[i64; 3]> = t
                .iter()
                .map(|&i| m.vertices[i as usize].map(|x| (x * 1e9).round() as i64))
                .collect();
            pts.sort();
            pts
        })
        .collect();
    out.sort();
    out
}

#[test]
fn one_tetrahedron_in_every_format() {
    let dir = std::env::temp_dir().join(format!("screwkit-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files: [(&str, Vec<u8>); 4] = [
        ("a.stl", ascii_stl().into_bytes()),
        ("b.STL", binary_stl()),
        ("c.obj", obj().into_bytes()),
        ("d.dae", collada().into_bytes()),
    ];
    let scale = [2.0, 3.0, 0.5];
    let expected = {
        let m = screwkit_model::mesh::TriMesh {
            vertices: TETRA
                .iter()
                .map(|p| [p[0] * scale[0], p[1] * scale[1], p[2] * scale[2]])
                .collect(),
            triangles: FACES.iter().map(|f| f.map(|i| i as u32)).collect(),
        };
        triangles(&m)
    };
    for (name, bytes) in &files {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let m = read_mesh(&path, scale).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(m.triangles.len(), 4, "{name}");
        assert_eq!(triangles(&m), expected, "{name}");
    }
    // Damaged, empty, unknown, missing: errors naming the file.
    let cases: [(&str, &[u8], &str); 4] = [
        (
            "bad.dae",
            b"<COLLADA><library_geometries><geometry",
            "bad.dae",
        ),
        ("empty.stl", b"solid e\nendsolid e\n", "no triangles"),
        ("x.ply", b"ply\nformat ascii 1.0\n", "x.ply"),
        ("short.stl", &binary_stl()[..100], "short.stl"),
    ];
    for (name, bytes, says) in cases {
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let e = read_mesh(&path, [1.0; 3]).unwrap_err();
        assert!(e.contains(says) && e.contains(name), "{name}: {e}");
    }
    let e = read_mesh(&dir.join("missing.stl"), [1.0; 3]).unwrap_err();
    assert!(e.contains("missing.stl"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A damaged COLLADA file on which mesh-loader 0.1.13 panics (found by the fuzz target): an
/// error naming the file, the parser's failure contained, nothing printed.
#[test]
fn a_parser_panic_is_an_error() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/mesh_cases/parser_panic.dae");
    let e = read_mesh(&path, [1.0; 3]).unwrap_err();
    assert!(
        e.contains("parser_panic.dae") && e.contains("the parser failed"),
        "{e}"
    );
}

/// Mass properties against closed forms: a box of sides (a, b, c) as twelve outward
/// triangles has volume abc, its centre at the middle and Ī = V/12 diag(b² + c², a² + c²,
/// a² + b²) per unit density, in every mode that counts volume (legacy = exact on a convex
/// mesh); the shell's area is 2(ab + bc + ca); a mesh turned inside out is refused.
#[test]
fn a_box_mesh_weighs_as_its_closed_form() {
    use screwkit_model::mesh::{mass_properties, MeshInertia, TriMesh};
    let (a, b, c) = (0.2, 0.4, 0.6);
    let (x0, y0, z0) = (1.0, -0.5, 0.25);
    let vertices: Vec<[f64; 3]> = (0..8)
        .map(|k| {
            [
                x0 + a * (k & 1) as f64,
                y0 + b * ((k >> 1) & 1) as f64,
                z0 + c * ((k >> 2) & 1) as f64,
            ]
        })
        .collect();
    // Outward (counter-clockwise seen from outside) faces of the unit cube's corners.
    let triangles: Vec<[u32; 3]> = vec![
        [0, 2, 1],
        [1, 2, 3], // z = 0
        [4, 5, 6],
        [5, 7, 6], // z = 1
        [0, 1, 4],
        [1, 5, 4], // y = 0
        [2, 6, 3],
        [3, 6, 7], // y = 1
        [0, 4, 2],
        [2, 4, 6], // x = 0
        [1, 3, 5],
        [3, 7, 5], // x = 1
    ];
    let mesh = TriMesh {
        vertices,
        triangles,
    };
    let v = a * b * c;
    let want = [
        v / 12.0 * (b * b + c * c),
        0.0,
        0.0,
        v / 12.0 * (a * a + c * c),
        0.0,
        v / 12.0 * (a * a + b * b),
    ];
    for mode in [MeshInertia::Legacy, MeshInertia::Exact] {
        let m = mass_properties(&mesh, mode).unwrap();
        assert!((m.measure - v).abs() < 1e-15, "{mode:?} {}", m.measure);
        let centre = [x0 + a / 2.0, y0 + b / 2.0, z0 + c / 2.0];
        for (got, want) in m.com.iter().zip(centre) {
            assert!((got - want).abs() < 1e-14, "{mode:?} {:?}", m.com);
        }
        for (got, want) in m.inertia.iter().zip(want) {
            assert!((got - want).abs() < 1e-15, "{mode:?} {:?}", m.inertia);
        }
    }
    let shell = mass_properties(&mesh, MeshInertia::Shell).unwrap();
    assert!((shell.measure - 2.0 * (a * b + b * c + c * a)).abs() < 1e-14);
    let inside_out = TriMesh {
        triangles: mesh.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
        ..mesh.clone()
    };
    let e = mass_properties(&inside_out, MeshInertia::Exact).unwrap_err();
    assert!(e.contains("negative"), "{e}");
}
