//! Screw-axis tables: Markdown, CSV and JSON.
//!
//! Markdown and CSV print numbers with [`PRECISION`] decimals (−0 printed as 0); JSON carries
//! full `f64` precision (shortest round-trip form). The JSON object is the stable contract of
//! `screwkit table --format json`:
//! `{"robot", "base", "tip", "joints": [{"name", "type", "screw_space": [6], "screw_body": [6],
//! "lower", "upper", "variable", "mimic"}], "home": [[4x4]]}` — `lower`/`upper` are `null` for
//! continuous joints; `mimic` is `null` or `{"leader", "multiplier", "offset"}`.

use screwkit_lie::display::fixed;
use screwkit_lie::{Frame, Se3};
use serde_json::{json, Value};

use crate::chain::{Chain, ChainJoint};

/// Decimals printed in the Markdown and CSV tables.
pub const PRECISION: usize = 6;

fn kind_label(chain: &Chain, j: &ChainJoint) -> String {
    let leader = &chain.variables[j.drive.variable].name;
    if *leader == j.name {
        j.kind.as_str().to_string()
    } else {
        format!(
            "{} (mimic: {} × {} + {})",
            j.kind.as_str(),
            fixed(j.drive.multiplier, 3),
            leader,
            fixed(j.drive.offset, 3)
        )
    }
}

fn f(x: f64) -> String {
    fixed(x, PRECISION)
}

/// Markdown: one table per frame (index, joint, type, ω, v, closest point q, pitch h), then M.
///
/// q is the point of the axis closest to the frame's origin (base origin for space axes, tip
/// origin for body axes); q and h are "–" and "∞" for a prismatic joint.
pub fn to_markdown(chain: &Chain, frames: &[Frame]) -> String {
    let mut s = format!(
        "Robot `{}`: chain `{}` → `{}`, {} joint(s), {} variable(s). Screw axes S = (ω, v); numbers to {} decimals.\n",
        chain.robot,
        chain.base,
        chain.tip,
        chain.joints.len(),
        chain.dof(),
        PRECISION
    );
    for &fr in frames {
        let (title, origin) = match fr {
            Frame::Body => ("Body screw axes B_i (tip frame)", "tip"),
            Frame::Space => ("Space screw axes S_i (base frame)", "base"),
        };
        s.push_str(&format!(
            "\n### {title}\n\n| # | joint | type | ω₁ | ω₂ | ω₃ | v₁ | v₂ | v₃ | q (closest to {origin} origin) | h |\n|---|---|---|---|---|---|---|---|---|---|---|\n"
        ));
        for (i, j) in chain.joints.iter().enumerate() {
            let a = j.screw(fr);
            let t = a.twist();
            let (q, h) = match (a.point(), a.pitch()) {
                (Some(q), Some(h)) => (format!("({}, {}, {})", f(q.x), f(q.y), f(q.z)), f(h)),
                _ => ("–".to_string(), "∞".to_string()),
            };
            s.push_str(&format!(
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                i + 1,
                j.name,
                kind_label(chain, j),
                f(t.w.x),
                f(t.w.y),
                f(t.w.z),
                f(t.v.x),
                f(t.v.y),
                f(t.v.z),
                q,
                h
            ));
        }
    }
    s.push_str(&format!(
        "\n### M: home pose of `{}` in `{}`\n\n",
        chain.tip, chain.base
    ));
    s.push_str(&matrix_markdown(&chain.home));
    s
}

fn matrix_markdown(t: &Se3) -> String {
    let m = t.to_homogeneous();
    let mut s = String::from("| | | | |\n|---|---|---|---|\n");
    for i in 0..4 {
        s.push_str(&format!(
            "| {} | {} | {} | {} |\n",
            f(m[(i, 0)]),
            f(m[(i, 1)]),
            f(m[(i, 2)]),
            f(m[(i, 3)])
        ));
    }
    s
}

/// CSV: header `frame,index,joint,type,w1,w2,w3,v1,v2,v3,qx,qy,qz,pitch`, one row per joint
/// and frame (q and pitch empty for prismatic joints), then four rows `M,<row>,m1,m2,m3,m4`.
pub fn to_csv(chain: &Chain, frames: &[Frame]) -> String {
    let mut s = String::from("frame,index,joint,type,w1,w2,w3,v1,v2,v3,qx,qy,qz,pitch\n");
    for &fr in frames {
        let label = fr.as_str();
        for (i, j) in chain.joints.iter().enumerate() {
            let a = j.screw(fr);
            let t = a.twist();
            let (q, h) = match (a.point(), a.pitch()) {
                (Some(q), Some(h)) => (format!("{},{},{}", f(q.x), f(q.y), f(q.z)), f(h)),
                _ => (",,".to_string(), String::new()),
            };
            s.push_str(&format!(
                "{label},{},{},{},{},{},{},{},{},{},{q},{h}\n",
                i + 1,
                csv_field(&j.name),
                csv_field(&kind_label(chain, j)),
                f(t.w.x),
                f(t.w.y),
                f(t.w.z),
                f(t.v.x),
                f(t.v.y),
                f(t.v.z)
            ));
        }
    }
    let m = chain.home.to_homogeneous();
    for i in 0..4 {
        s.push_str(&format!(
            "M,{},{},{},{},{},,,,,,,,\n",
            i + 1,
            f(m[(i, 0)]),
            f(m[(i, 1)]),
            f(m[(i, 2)]),
            f(m[(i, 3)])
        ));
    }
    s
}

fn csv_field(x: &str) -> String {
    if x.contains([',', '"', '\n']) {
        format!("\"{}\"", x.replace('"', "\"\""))
    } else {
        x.to_string()
    }
}

/// A JSON number with −0 turned into 0 (non-finite values become `null`).
fn json_number(x: f64) -> Value {
    if x == 0.0 {
        json!(0.0)
    } else {
        json!(x)
    }
}

/// A transform as a 4x4 array of rows.
fn json_matrix(t: &Se3) -> Value {
    let m = t.to_homogeneous();
    Value::Array(
        (0..4)
            .map(|i| Value::Array((0..4).map(|k| json_number(m[(i, k)])).collect()))
            .collect(),
    )
}

fn json_limit(x: f64) -> Value {
    if x.is_finite() {
        json_number(x)
    } else {
        Value::Null
    }
}

/// The JSON object of the table (see the module documentation for the contract).
pub fn to_json(chain: &Chain) -> Value {
    let joints: Vec<Value> = chain
        .joints
        .iter()
        .map(|j| {
            let var = &chain.variables[j.drive.variable];
            let mimic = if var.name == j.name {
                Value::Null
            } else {
                json!({"leader": var.name, "multiplier": j.drive.multiplier, "offset": json_number(j.drive.offset)})
            };
            json!({
                "name": j.name,
                "type": j.kind.as_str(),
                "screw_space": j.s_space.twist().to_vector().iter().map(|&x| json_number(x)).collect::<Vec<_>>(),
                "screw_body": j.b_body.twist().to_vector().iter().map(|&x| json_number(x)).collect::<Vec<_>>(),
                "lower": json_limit(var.lower),
                "upper": json_limit(var.upper),
                "variable": j.drive.variable,
                "mimic": mimic,
            })
        })
        .collect();
    json!({
        "robot": chain.robot,
        "base": chain.base,
        "tip": chain.tip,
        "joints": joints,
        "home": json_matrix(&chain.home),
    })
}
