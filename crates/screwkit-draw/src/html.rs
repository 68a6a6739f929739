//! The interactive page: one self-contained HTML file (no network, no CDN) with the chain or
//! the whole tree embedded as JSON, the robot's body (its shapes, meshes embedded once each as
//! base64 float32 vertices and uint32 triangles) and a three.js renderer (WebGL; the subset of
//! three.js the page uses, bundled by `viewer/three/build.sh` from the npm registry and
//! inlined with its MIT licence), and the page's own code (`viewer/viewer.js`,
//! `viewer/viewer.css`, compiled in). The page computes FK itself from the embedded screws —
//! the product of exponentials in JavaScript — places each link's shapes at its pose, and
//! writes the drawn frames' poses (a chain's tip; a tree's leaves) at full precision into
//! `<pre id="fk-exact">`, which the browser tests compare with the library's FK. The visual
//! shapes are drawn by default, the collision shapes as a toggle, the skeleton, screw axes and
//! frames as overlays.

use screwkit_model::{Chain, JointKind};
use screwkit_solve::{Kinematics, SolveError, TreeKinematics};
use serde_json::{json, Value};

use crate::svg::escape;

const CSS: &str = include_str!("viewer/viewer.css");
const JS: &str = include_str!("viewer/viewer.js");
/// three.js, bundled (`viewer/three/build.sh`), and its licence.
const THREE: &str = include_str!("viewer/three/three.min.js");
const THREE_LICENSE: &str = include_str!("viewer/three/LICENSE");

/// A pose row-major, −0 written as 0 (a pose from a file's rpy and the same pose built in
/// Python give the same page).
fn row_major(t: &screwkit_lie::Se3) -> Vec<f64> {
    let mut out = vec![0.0; 16];
    t.write_row_major(&mut out);
    out.iter_mut().for_each(|x| *x += 0.0);
    out
}

fn finite(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

fn kind_word(kind: JointKind) -> &'static str {
    match kind {
        JointKind::Prismatic => "prismatic",
        JointKind::Continuous => "continuous",
        JointKind::Helical => "helical",
        _ => "revolute",
    }
}

/// The chain as the page reads it, in the tree form the page's FK walks (a chain is a tree
/// with one branch): joints (name, kind, home space screw S, the variable driving it with the
/// mimic rule θ = multiplier · q + offset, its parent joint, the index of its child link),
/// variables (name, limits; ±∞ for continuous joints is written as null), links (name, home
/// pose M_L, the joint moving it, the link its segment starts from), the drawn frames (the tip
/// with its home pose M), and q.
pub fn model_json(chain: &Chain, kin: &Kinematics, q: &[f64]) -> Value {
    // Each joint's link: the first link with that many joints before it (one pass).
    let mut link_of: Vec<Option<usize>> = vec![None; chain.joints.len()];
    for (l, link) in kin.links().iter().enumerate() {
        if let Some(slot) = link
            .joints_before
            .checked_sub(1)
            .and_then(|j| link_of.get_mut(j))
        {
            slot.get_or_insert(l);
        }
    }
    let joints: Vec<Value> = chain
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            json!({
                "name": joint.name,
                "kind": kind_word(joint.kind),
                "S": joint.s_space.twist().to_vector().as_slice(),
                "variable": joint.drive.variable,
                "multiplier": joint.drive.multiplier,
                "offset": joint.drive.offset,
                "parent": j.checked_sub(1),
                "link": link_of[j],
            })
        })
        .collect();
    let variables: Vec<Value> = chain
        .variables
        .iter()
        .map(|v| {
            json!({
                "name": v.name,
                "lower": finite(v.lower),
                "upper": finite(v.upper),
                "prismatic": v.kind == JointKind::Prismatic,
            })
        })
        .collect();
    let links: Vec<Value> = kin
        .links()
        .iter()
        .enumerate()
        .map(|(k, l)| {
            json!({
                "name": l.name,
                "home": row_major(&l.home),
                "support": l.joints_before.checked_sub(1),
                "parent": k.checked_sub(1),
            })
        })
        .collect();
    json!({
        "robot": chain.robot,
        "subject": format!("chain {} → {}, {} joint(s)", chain.base, chain.tip, chain.variables.len()),
        "floating": false,
        "joints": joints,
        "variables": variables,
        "links": links,
        "frames": [{
            "name": chain.tip,
            "role": "tip",
            "support": chain.joints.len().checked_sub(1),
            "home": row_major(&chain.home),
        }],
        "q": q,
    })
}

/// The whole tree as the page reads it (the fields of [`model_json`]): every movable joint
/// (parents first) and link, the leaves as the drawn frames, and, with a floating base, the
/// base's seven values first among the variables (position, then the quaternion
/// (qx, qy, qz, qw), which the page normalises).
pub fn tree_json(kin: &TreeKinematics, q: &[f64]) -> Value {
    let model = kin.model();
    // Each joint's child link: the first link moved by it whose parent link it does not move
    // (one pass over the links; a search per joint was quadratic: 100,000 links took 30 s).
    let mut children: Vec<Option<usize>> = vec![None; model.joints.len()];
    for (l, link) in model.links.iter().enumerate() {
        if let Some(k) = link.support {
            let parent_moves = link
                .parent
                .is_some_and(|p| model.links[p].support == Some(k));
            if !parent_moves && k < children.len() && children[k].is_none() {
                children[k] = Some(l);
            }
        }
    }
    let joints: Vec<Value> = model
        .joints
        .iter()
        .enumerate()
        .map(|(k, j)| {
            let child = children[k];
            json!({
                "name": j.name,
                "kind": kind_word(j.kind),
                "S": j.s_space.twist().to_vector().as_slice(),
                "variable": j.drive.variable,
                "multiplier": j.drive.multiplier,
                "offset": j.drive.offset,
                "parent": j.parent,
                "link": child,
            })
        })
        .collect();
    let (lower, upper) = (kin.lower(), kin.upper());
    let base = kin.nq() - model.variables.len();
    let variables: Vec<Value> = kin
        .q_names()
        .iter()
        .enumerate()
        .map(|(k, name)| {
            json!({
                "name": name,
                "lower": finite(lower[k]),
                "upper": finite(upper[k]),
                "prismatic": k < 3 && base > 0
                    || k >= base && model.variables[k - base].kind == JointKind::Prismatic,
            })
        })
        .collect();
    let links: Vec<Value> = model
        .links
        .iter()
        .map(|l| {
            json!({
                "name": l.name,
                "home": row_major(&l.home),
                "support": l.support,
                "parent": l.parent,
            })
        })
        .collect();
    let frames: Vec<Value> = screwkit_service::whole::leaf_frames(kin)
        .into_iter()
        .map(|f| {
            let frame = &model.frames[f];
            json!({
                "name": frame.name,
                "role": "leaf",
                "support": model.links[frame.link].support,
                "home": row_major(&frame.home),
            })
        })
        .collect();
    json!({
        "robot": model.robot,
        "subject": format!(
            "whole tree from {}, {} links, {} joints, {} variables",
            model.root(),
            model.links.len(),
            model.joints.len(),
            kin.nq()
        ),
        "floating": kin.floating_base(),
        "joints": joints,
        "variables": variables,
        "links": links,
        "frames": frames,
        "q": q,
    })
}

/// The most triangles of all the embedded meshes together: past it, a mesh is not drawn (the
/// page says which).
pub const MAX_TRIANGLES: usize = 1_500_000;

/// The most triangles a mesh is drawn with: a finer one is simplified to about this many
/// ([`decimate`]).
pub const MESH_TRIANGLES: usize = 5_000;

/// A mesh's f32 vertices welded (equal positions made one vertex, as STL files repeat them per
/// triangle) and, past [`MESH_TRIANGLES`], simplified by meshoptimizer's edge collapse (the
/// `meshopt` crate) towards that many triangles, within 1 % of the mesh's size; the unused
/// vertices dropped. Returns (vertices, triangles).
pub fn decimate(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut weld: std::collections::HashMap<[u32; 3], u32> = std::collections::HashMap::new();
    let mut points: Vec<[f32; 3]> = Vec::new();
    let remap: Vec<u32> = vertices
        .iter()
        .map(|v| {
            let p = v.map(|x| x as f32);
            *weld.entry(p.map(f32::to_bits)).or_insert_with(|| {
                points.push(p);
                (points.len() - 1) as u32
            })
        })
        .collect();
    let mut indices: Vec<u32> = triangles
        .iter()
        .flatten()
        .filter_map(|&i| remap.get(i as usize).copied())
        .collect();
    indices.truncate(indices.len() / 3 * 3);
    if indices.len() / 3 > MESH_TRIANGLES {
        let bytes: Vec<u8> = points
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        if let Ok(adapter) = meshopt::VertexDataAdapter::new(&bytes, 12, 0) {
            indices = meshopt::simplify(
                &indices,
                &adapter,
                3 * MESH_TRIANGLES,
                0.01,
                meshopt::SimplifyOptions::None,
                None,
            );
        }
    }
    let points = meshopt::optimize_vertex_fetch(&mut indices, &points);
    (points, indices)
}

/// Standard base64 (RFC 4648, with padding).
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for k in 0..4 {
            if k <= c.len() {
                out.push(ABC[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// The body the page draws for the links named `links` (index = the page's link index): every
/// visual and collision shape of those links in `tree` (`role` tells which; the page shows
/// the visual ones, or the collision ones of a link without visuals, and the rest on a
/// toggle), each with its link, origin, colour and dimensions; meshes read once per file and
/// scale, [`decimate`]d, embedded as base64 little-endian float32 vertices (x, y, z) and
/// uint32 triangles.
/// A mesh that cannot be read is listed in `problems` (one sentence naming the link and file)
/// and drawn as nothing: a picture never fails on the body.
pub fn body_json(
    tree: &screwkit_model::Tree,
    links: &[String],
    obstacles: &[screwkit_service::body::Obstacle],
) -> Value {
    use screwkit_model::geometry::{Role, Shape};
    let index: std::collections::HashMap<&str, usize> = links
        .iter()
        .enumerate()
        .map(|(k, n)| (n.as_str(), k))
        .collect();
    let mut meshes: Vec<Value> = Vec::new();
    let mut read: std::collections::HashMap<(std::path::PathBuf, [u64; 3]), Option<usize>> =
        std::collections::HashMap::new();
    let mut problems: Vec<String> = tree.geometry_problems.clone();
    let mut triangles = 0usize;
    let mut shapes = Vec::new();
    // The robot's shapes on its links; an MJCF world's geoms (a floor, a table) and the
    // obstacles on the world (link null), as obstacles.
    let world = tree
        .contact_rules
        .iter()
        .flat_map(|r| r.world.iter())
        .map(|g| {
            (
                None,
                "obstacle",
                g.origin,
                &g.shape,
                g.rgba,
                tree.links.get(g.link),
            )
        });
    let robot = tree.geometries.iter().filter_map(|g| {
        let link = tree.links.get(g.link).and_then(|n| index.get(n.as_str()))?;
        let role = match g.role {
            Role::Visual => "visual",
            Role::Collision => "collision",
        };
        Some((
            Some(*link),
            role,
            g.origin,
            &g.shape,
            g.rgba,
            tree.links.get(g.link),
        ))
    });
    let added = obstacles
        .iter()
        .map(|o| (None, "obstacle", o.pose, &o.shape, None, Some(&o.name)));
    for (link, role, origin, geometry, rgba, owner) in robot.chain(world).chain(added) {
        let owner = owner.map_or("the world", String::as_str);
        let mut shape = json!({
            "link": link,
            "role": role,
            "origin": row_major(&origin),
            "rgba": rgba,
            "kind": geometry.word(),
        });
        let o = shape.as_object_mut().expect("an object");
        if link.is_none() {
            // An obstacle's name: the contacts name it.
            o.insert("name".into(), json!(owner));
        }
        match geometry {
            Shape::Box { size } => {
                o.insert("size".into(), json!(size));
            }
            Shape::Cylinder { radius, length } | Shape::Capsule { radius, length } => {
                o.insert("radius".into(), json!(radius));
                o.insert("length".into(), json!(length));
            }
            Shape::Sphere { radius } => {
                o.insert("radius".into(), json!(radius));
            }
            Shape::Ellipsoid { radii } => {
                o.insert("radii".into(), json!(radii));
            }
            Shape::Plane { size } => {
                o.insert("size".into(), json!(size));
            }
            Shape::Mesh { path, scale, .. } => {
                let key = (path.clone(), scale.map(f64::to_bits));
                let m = *read.entry(key).or_insert_with(|| {
                    match screwkit_model::mesh::read_mesh(path, *scale) {
                        Ok(mesh) if triangles + mesh.triangles.len().min(MESH_TRIANGLES) <= MAX_TRIANGLES => {
                            let (points, indices) = decimate(&mesh.vertices, &mesh.triangles);
                            triangles += indices.len() / 3;
                            let v: Vec<u8> =
                                points.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
                            let t: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
                            meshes.push(json!({
                                "positions": base64(&v),
                                "indices": base64(&t),
                                "triangles": indices.len() / 3,
                                "file_triangles": mesh.triangles.len(),
                            }));
                            Some(meshes.len() - 1)
                        }
                        Ok(mesh) => {
                            problems.push(format!(
                                "{}: {} triangles would take the page past {MAX_TRIANGLES}: not drawn",
                                path.display(),
                                mesh.triangles.len()
                            ));
                            None
                        }
                        Err(e) => {
                            problems.push(format!("\"{owner}\": {e}"));
                            None
                        }
                    }
                });
                match m {
                    Some(m) => {
                        o.insert("mesh".into(), json!(m));
                    }
                    None => continue,
                }
            }
        }
        shapes.push(shape);
    }
    json!({"shapes": shapes, "meshes": meshes, "problems": problems})
}

/// A motion the page plays back (play/pause, a time slider): `frames` configurations of the
/// page's variables (a chain's joint values, or a whole tree's q), `fps` frames per second.
#[derive(Debug, Clone, Copy)]
pub struct Motion<'a> {
    /// One configuration per frame.
    pub frames: &'a [Vec<f64>],
    /// Frames per second (0 < fps ≤ 1000).
    pub fps: f64,
}

/// What a page shows besides the robot: a motion to play back, obstacles in the world, the
/// body's contacts.
#[derive(Debug, Clone, Copy, Default)]
pub struct PageOptions<'a> {
    /// A motion to play back.
    pub motion: Option<Motion<'a>>,
    /// Obstacles, drawn in the world (the scene's or the robot's body's).
    pub obstacles: &'a [screwkit_service::body::Obstacle],
    /// The body's contacts at the configuration first shown and at each motion frame
    /// ([`crate::picture`] computes them): the colliding links tinted red, and the close
    /// pairs' minimum-distance segments when asked.
    pub contacts: Option<ShowContacts<'a>>,
}

/// The body whose contacts a page shows ([`PageOptions::contacts`]).
#[derive(Debug, Clone, Copy)]
pub struct ShowContacts<'a> {
    /// The whole tree the collision model was built on.
    pub kin: &'a TreeKinematics,
    /// The collision model: the pairs checked (an SRDF's disabled ones left out) and the
    /// obstacles.
    pub model: &'a screwkit_collision::CollisionModel,
    /// Also each pair closer than [`screwkit_service::body::SHOWN_WITHIN`]: its distance and
    /// its minimum-distance segment (`--show-distances`).
    pub distances: bool,
}

/// The most configurations (the first shown and a motion's frames) whose contacts a page
/// embeds.
pub const MAX_CONTACT_FRAMES: usize = 10_000;

/// Frames per second of a motion when not told (the CLI's `--fps`; Python's `fps=30.0`, a
/// literal the stubs can check, tested equal to this).
pub const DEFAULT_FPS: f64 = 30.0;

/// The motion as the page reads it, each frame checked by `check` (an error naming the frame).
fn motion_json(
    motion: &Motion<'_>,
    check: impl Fn(&[f64]) -> Result<(), SolveError>,
) -> Result<Value, SolveError> {
    if !(motion.fps.is_finite() && motion.fps > 0.0 && motion.fps <= 1000.0) {
        return Err(SolveError::InvalidInput(format!(
            "motion: fps must be in (0, 1000], got {}",
            motion.fps
        )));
    }
    if motion.frames.is_empty() {
        return Err(SolveError::InvalidInput("motion: no frames".into()));
    }
    for (k, f) in motion.frames.iter().enumerate() {
        check(f).map_err(|e| SolveError::InvalidInput(format!("motion frame {k}: {e}")))?;
    }
    Ok(json!({"frames": motion.frames, "fps": motion.fps}))
}

/// The page of `chain` at `q` (default: each joint at 0, or at the limit nearest 0 when 0 is
/// outside its limits — the Panda's joint 4 is). Checks q. Without a body: the skeleton.
pub fn page(chain: &Chain, kin: &Kinematics, q: Option<&[f64]>) -> Result<String, SolveError> {
    page_with_body(chain, kin, q, None, &PageOptions::default())
}

/// [`page`] drawing the body `tree` gives the chain's links (its shapes, [`body_json`]) and
/// the obstacles, and playing the motion back (each frame checked as q is).
pub fn page_with_body(
    chain: &Chain,
    kin: &Kinematics,
    q: Option<&[f64]>,
    tree: Option<&screwkit_model::Tree>,
    options: &PageOptions<'_>,
) -> Result<String, SolveError> {
    Ok(document(
        &chain.robot,
        &chain_model(chain, kin, q, tree, options)?,
    ))
}

/// The JSON [`page_with_body`] embeds (its `q` the configuration first shown).
pub fn chain_model(
    chain: &Chain,
    kin: &Kinematics,
    q: Option<&[f64]>,
    tree: Option<&screwkit_model::Tree>,
    options: &PageOptions<'_>,
) -> Result<Value, SolveError> {
    let motion = options.motion.as_ref();
    let zeros: Vec<f64> = (0..kin.dof())
        .map(|k| 0f64.clamp(kin.lower()[k], kin.upper()[k]))
        .collect();
    // The motion first: its errors name the frame (its first frame is the default q).
    let played = motion
        .map(|m| motion_json(m, |f| kin.check_q(f)))
        .transpose()?;
    let first = motion.and_then(|m| m.frames.first()).map(Vec::as_slice);
    let q = q.or(first).unwrap_or(&zeros);
    kin.check_q(q)?;
    let mut model = model_json(chain, kin, q);
    if let Some(tree) = tree {
        let names: Vec<String> = kin.links().iter().map(|l| l.name.clone()).collect();
        model["body"] = body_json(tree, &names, options.obstacles);
    }
    if let Some(m) = played {
        model["motion"] = m;
    }
    Ok(model)
}

/// The page of the whole tree at `q` (its configuration, `q_names`; default: the neutral
/// configuration with each joint brought inside its limits): every branch, a slider per
/// variable, the pose of every leaf. Checks q.
pub fn tree_page(kin: &TreeKinematics, q: Option<&[f64]>) -> Result<String, SolveError> {
    tree_page_with(kin, q, &PageOptions::default())
}

/// [`tree_page`] with the obstacles drawn and the motion played back (each frame a whole
/// configuration, checked as q is).
pub fn tree_page_with(
    kin: &TreeKinematics,
    q: Option<&[f64]>,
    options: &PageOptions<'_>,
) -> Result<String, SolveError> {
    Ok(document(&kin.model().robot, &tree_model(kin, q, options)?))
}

/// The JSON [`tree_page_with`] embeds (its `q` the configuration first shown).
pub fn tree_model(
    kin: &TreeKinematics,
    q: Option<&[f64]>,
    options: &PageOptions<'_>,
) -> Result<Value, SolveError> {
    let motion = options.motion.as_ref();
    let (lower, upper) = (kin.lower(), kin.upper());
    let start: Vec<f64> = screwkit_solve::tree::configuration::neutral(kin)
        .into_iter()
        .enumerate()
        .map(|(k, x)| x.clamp(lower[k], upper[k]))
        .collect();
    let played = motion
        .map(|m| motion_json(m, |f| kin.check_q(f).map(|_| ())))
        .transpose()?;
    let first = motion.and_then(|m| m.frames.first()).map(Vec::as_slice);
    let q = q.or(first).unwrap_or(&start);
    kin.check_q(q)?;
    let mut model = tree_json(kin, q);
    let names: Vec<String> = kin.model().links.iter().map(|l| l.name.clone()).collect();
    model["body"] = body_json(&kin.model().tree, &names, options.obstacles);
    if let Some(m) = played {
        model["motion"] = m;
    }
    Ok(model)
}

/// The HTML document around the embedded model ([`chain_model`], [`tree_model`]).
pub fn document(robot: &str, model: &Value) -> String {
    // "</" inside a <script> element would end it: JSON allows "\/" for "/".
    let json = model.to_string().replace("</", "<\\/");
    let title = escape(&format!("{robot} — screwkit"));
    format!(
        r#"<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
{CSS}</style>
</head>
<body>
<div id="stage"><canvas id="view"></canvas><div id="hint">drag: orbit · wheel: zoom · #q=… in the URL sets the joints</div></div>
<div id="side">
<h1 id="title"></h1>
<div class="sub" id="chain"></div>
<div id="error"></div>
<div id="show"><label><input type="checkbox" id="show-visual" checked> body</label> <label><input type="checkbox" id="show-collision"> collision shapes</label> <label><input type="checkbox" id="show-skeleton"> skeleton</label> <label><input type="checkbox" id="show-axes"> screw axes</label> <label><input type="checkbox" id="show-frames" checked> frames</label></div>
<div id="player" hidden><h2>motion</h2><button id="play">play</button> <input type="range" id="time" min="0" step="1" value="0"> <output id="clock"></output></div>
<div id="contacts" hidden><h2>contacts</h2><div class="sub" id="contact-state"></div><table id="contact-pairs"></table></div>
<h2>joints</h2>
<div id="sliders"></div>
<h2 id="pose-title">tip pose T(q)</h2>
<select id="frame"></select>
<table id="tip"></table>
<h2>space screw axes S<sub>i</sub>(q)</h2>
<table id="screws"></table>
<details><summary>exact values</summary>
<div class="sub">q</div><pre id="q-exact"></pre>
<div class="sub">T(q) of each frame listed above, row-major, one after the other</div><pre id="fk-exact"></pre>
</details>
<div class="sub">screwkit: T(q) = e<sup>[S1]θ1</sup> ⋯ e<sup>[Sn]θn</sup> M, twists (ω, v), metres, radians.</div>
</div>
<script type="application/json" id="model">{json}</script>
<script>
/* three.js (https://threejs.org), the classes this page uses, bundled by esbuild.
{THREE_LICENSE}*/
{THREE}
</script>
<script>
{JS}</script>
</body>
</html>
"#
    )
}
