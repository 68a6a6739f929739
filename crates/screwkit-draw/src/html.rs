//! The interactive page: one self-contained HTML file (no network, no CDN) with the chain or
//! the whole tree embedded as JSON and a small canvas renderer (`viewer/viewer.js`,
//! `viewer/viewer.css`, compiled in). The page computes FK itself from the embedded screws —
//! the product of exponentials in JavaScript — and writes the drawn frames' poses (a chain's
//! tip; a tree's leaves) at full precision into `<pre id="fk-exact">`, which the browser tests
//! compare with the library's FK.
//!
//! A hand-written renderer rather than three.js: the picture is a few hundred line segments,
//! and 300 lines of plain JavaScript keep the file small (≈ 20 kB), offline and readable.

use screwkit_model::{Chain, JointKind};
use screwkit_solve::{Kinematics, SolveError, TreeKinematics};
use serde_json::{json, Value};

use crate::svg::escape;

const CSS: &str = include_str!("viewer/viewer.css");
const JS: &str = include_str!("viewer/viewer.js");

fn row_major(t: &screwkit_lie::Se3) -> Vec<f64> {
    let mut out = vec![0.0; 16];
    t.write_row_major(&mut out);
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

/// The page of `chain` at `q` (default: each joint at 0, or at the limit nearest 0 when 0 is
/// outside its limits — the Panda's joint 4 is). Checks q.
pub fn page(chain: &Chain, kin: &Kinematics, q: Option<&[f64]>) -> Result<String, SolveError> {
    let zeros: Vec<f64> = (0..kin.dof())
        .map(|k| 0f64.clamp(kin.lower()[k], kin.upper()[k]))
        .collect();
    let q = q.unwrap_or(&zeros);
    kin.check_q(q)?;
    Ok(document(&chain.robot, &model_json(chain, kin, q)))
}

/// The page of the whole tree at `q` (its configuration, `q_names`; default: the neutral
/// configuration with each joint brought inside its limits): every branch, a slider per
/// variable, the pose of every leaf. Checks q.
pub fn tree_page(kin: &TreeKinematics, q: Option<&[f64]>) -> Result<String, SolveError> {
    let (lower, upper) = (kin.lower(), kin.upper());
    let start: Vec<f64> = screwkit_solve::tree::configuration::neutral(kin)
        .into_iter()
        .enumerate()
        .map(|(k, x)| x.clamp(lower[k], upper[k]))
        .collect();
    let q = q.unwrap_or(&start);
    kin.check_q(q)?;
    Ok(document(&kin.model().robot, &tree_json(kin, q)))
}

/// The HTML document around the embedded model.
fn document(robot: &str, model: &Value) -> String {
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
{JS}</script>
</body>
</html>
"#
    )
}
