//! The interactive page: one self-contained HTML file (no network, no CDN) with the chain
//! embedded as JSON and a small canvas renderer (`viewer/viewer.js`, `viewer/viewer.css`,
//! compiled in). The page computes FK itself from the embedded screws — the product of
//! exponentials in JavaScript — and writes the tip pose at full precision into
//! `<pre id="fk-exact">`, which the browser tests compare with the library's FK.
//!
//! A hand-written renderer rather than three.js: the picture is a few hundred line segments,
//! and 300 lines of plain JavaScript keep the file small (≈ 20 kB), offline and readable.

use screwkit_model::{Chain, JointKind};
use screwkit_solve::{Kinematics, SolveError};
use serde_json::{json, Value};

use crate::svg::escape;

const CSS: &str = include_str!("viewer/viewer.css");
const JS: &str = include_str!("viewer/viewer.js");

fn row_major(t: &screwkit_lie::Se3) -> Vec<f64> {
    let mut out = vec![0.0; 16];
    t.write_row_major(&mut out);
    out
}

/// The chain as the page reads it: joints (name, kind, S, the variable driving it with the
/// mimic rule θ = multiplier · q + offset, the index of its child link), variables (name,
/// limits; ±∞ for continuous joints is written as null), links (name, home pose, joints before
/// it), M, and q.
pub fn model_json(chain: &Chain, kin: &Kinematics, q: &[f64]) -> Value {
    let finite = |x: f64| if x.is_finite() { json!(x) } else { Value::Null };
    let joints: Vec<Value> = chain
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            json!({
                "name": joint.name,
                "kind": match joint.kind {
                    JointKind::Prismatic => "prismatic",
                    JointKind::Continuous => "continuous",
                    _ => "revolute",
                },
                "S": joint.s_space.twist().to_vector().as_slice(),
                "variable": joint.drive.variable,
                "multiplier": joint.drive.multiplier,
                "offset": joint.drive.offset,
                "link": kin.links().iter().position(|l| l.joints_before == j + 1),
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
        .map(|l| json!({"name": l.name, "home": row_major(&l.home), "joints_before": l.joints_before}))
        .collect();
    json!({
        "robot": chain.robot,
        "base": chain.base,
        "tip": chain.tip,
        "joints": joints,
        "variables": variables,
        "links": links,
        "home": row_major(&chain.home),
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
    // "</" inside a <script> element would end it: JSON allows "\/" for "/".
    let json = model_json(chain, kin, q).to_string().replace("</", "<\\/");
    let title = escape(&format!("{} — screwkit", chain.robot));
    Ok(format!(
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
<h2>tip pose T(q)</h2>
<table id="tip"></table>
<h2>space screw axes S<sub>i</sub>(q)</h2>
<table id="screws"></table>
<details><summary>exact values</summary>
<div class="sub">q</div><pre id="q-exact"></pre>
<div class="sub">T(q), row-major</div><pre id="fk-exact"></pre>
</details>
<div class="sub">screwkit: T(q) = e<sup>[S1]θ1</sup> ⋯ e<sup>[Sn]θn</sup> M, twists (ω, v), metres, radians.</div>
</div>
<script type="application/json" id="model">{json}</script>
<script>
{JS}</script>
</body>
</html>
"#
    ))
}
