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
use crate::error::{ErrorKind, ModelError};
use crate::screws::{ScrewJoint, ScrewLeader, ScrewRobot};
use crate::tree::{JointKind, Mimic};

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
            f(j.drive.multiplier),
            leader,
            f(j.drive.offset)
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

/// True when `text` is a screw table rather than a robot file: JSON (`{` first) or the CSV of
/// [`to_csv`] (its header first). URDF, xacro and MJCF begin with `<`.
pub fn is_screw_table(text: &str) -> bool {
    let t = text.trim_start_matches('\u{feff}').trim_start();
    t.starts_with('{') || t.starts_with("frame,index,joint,type,")
}

/// Reads a robot from a screw table: the JSON of [`to_json`] (`screwkit table --format
/// json`; the space screws `screw_space`, or `screw_body` when the object says `"frame":
/// "body"`), the JSON of [`ScrewRobot::to_json`] (one `screw` per joint in `frame`), or the
/// CSV of [`to_csv`] (the space rows when present, else the body rows; printed to
/// [`PRECISION`] decimals, so the robot is that table's to its last digit; unbounded joints,
/// as the CSV has no limits). Errors name `source` and the joint or row.
pub fn read_screw_table(text: &str, source: &str) -> Result<ScrewRobot, ModelError> {
    let t = text.trim_start_matches('\u{feff}').trim_start();
    if t.starts_with('{') {
        from_json(t, source)
    } else {
        from_csv(t, source)
    }
}

fn table_error(source: &str, msg: String) -> ModelError {
    ModelError::new(source, ErrorKind::Screws(msg))
}

fn from_json(text: &str, source: &str) -> Result<ScrewRobot, ModelError> {
    let bad = |msg: String| table_error(source, format!("not a screw table: {msg}"));
    let v: Value = serde_json::from_str(text).map_err(|e| bad(format!("JSON: {e}")))?;
    let frame = match v.get("frame") {
        None | Some(Value::Null) => Frame::Space,
        Some(Value::String(s)) if s == "space" => Frame::Space,
        Some(Value::String(s)) if s == "body" => Frame::Body,
        Some(other) => {
            return Err(bad(format!(
                "\"frame\": {other} (expected \"space\" or \"body\")"
            )))
        }
    };
    let home = json_home(v.get("home")).map_err(|m| bad(format!("\"home\": {m}")))?;
    let joints = v
        .get("joints")
        .and_then(Value::as_array)
        .ok_or_else(|| bad("no \"joints\" array".into()))?;
    let mut out = Vec::with_capacity(joints.len());
    for (i, j) in joints.iter().enumerate() {
        let at = |m: String| bad(format!("joint {i}: {m}"));
        let name = j
            .get("name")
            .and_then(Value::as_str)
            .ok_or_else(|| at("no \"name\"".into()))?
            .to_string();
        let key = if j.get("screw").is_some() {
            "screw"
        } else if frame == Frame::Body {
            "screw_body"
        } else {
            "screw_space"
        };
        let screw = json_numbers::<6>(j.get(key)).map_err(|m| at(format!("\"{key}\": {m}")))?;
        let limits = json_limits(j).map_err(at)?;
        let mimic = match j.get("mimic") {
            None | Some(Value::Null) => None,
            Some(m) => {
                let number = |k: &str, default: f64| match m.get(k) {
                    None | Some(Value::Null) => Ok(default),
                    Some(x) => x
                        .as_f64()
                        .ok_or_else(|| at(format!("\"mimic\": \"{k}\": {x} is not a number"))),
                };
                Some(Mimic {
                    leader: m
                        .get("leader")
                        .and_then(Value::as_str)
                        .ok_or_else(|| at("\"mimic\" without a \"leader\"".into()))?
                        .to_string(),
                    multiplier: number("multiplier", 1.0)?,
                    offset: number("offset", 0.0)?,
                })
            }
        };
        let kind = match j.get("type") {
            None | Some(Value::Null) => None,
            Some(Value::String(t)) => Some(kind_of(t).map_err(at)?),
            Some(x) => return Err(at(format!("\"type\": {x} is not a joint type"))),
        };
        out.push(ScrewJoint {
            name,
            screw,
            limits,
            mimic,
            kind,
        });
    }
    // Leaders named by mimic joints but not in the table (off the chain): a variable each,
    // with the limits the table gives its followers (the variable's), or as listed.
    let mut leaders: Vec<ScrewLeader> = Vec::new();
    if let Some(list) = v.get("leaders") {
        let list = list
            .as_array()
            .ok_or_else(|| bad(format!("\"leaders\": {list} is not an array")))?;
        for (i, l) in list.iter().enumerate() {
            let at = |m: String| bad(format!("leader {i}: {m}"));
            let name = l
                .get("name")
                .and_then(Value::as_str)
                .ok_or_else(|| at("no \"name\"".into()))?;
            leaders.push(ScrewLeader {
                name: name.to_string(),
                limits: json_limits(l).map_err(at)?,
            });
        }
    }
    // Only a table screwkit wrote (every joint with its "variable") names a leader off the
    // chain without listing it; elsewhere an unknown leader stays an error (a typo).
    if joints.iter().all(|j| j.get("variable").is_some()) {
        add_leaders(&out, &mut leaders, |j| j.limits);
    }
    Ok(ScrewRobot {
        leaders,
        name: v
            .get("robot")
            .and_then(Value::as_str)
            .unwrap_or("screws")
            .to_string(),
        source: source.to_string(),
        home,
        frame,
        joints: out,
    })
}

fn json_numbers<const N: usize>(v: Option<&Value>) -> Result<[f64; N], String> {
    let a = v
        .and_then(Value::as_array)
        .ok_or_else(|| format!("expected {N} numbers"))?;
    if a.len() != N {
        return Err(format!("expected {N} numbers, got {}", a.len()));
    }
    let mut out = [0.0; N];
    for (o, x) in out.iter_mut().zip(a) {
        *o = x.as_f64().ok_or_else(|| format!("{x} is not a number"))?;
    }
    Ok(out)
}

/// `"lower"`/`"upper"` of a JSON object: `None` when both are absent or `null`; a missing
/// bound is ±∞; anything but a number or `null` is an error.
fn json_limits(v: &Value) -> Result<Option<(f64, f64)>, String> {
    let get = |k: &str, inf: f64| -> Result<Option<f64>, String> {
        match v.get(k) {
            None | Some(Value::Null) => Ok(None),
            Some(x) => x
                .as_f64()
                .map(|x| Some(if x.is_finite() { x } else { inf }))
                .ok_or_else(|| format!("\"{k}\": {x} is not a number")),
        }
    };
    Ok(
        match (
            get("lower", f64::NEG_INFINITY)?,
            get("upper", f64::INFINITY)?,
        ) {
            (None, None) => None,
            (l, u) => Some((l.unwrap_or(f64::NEG_INFINITY), u.unwrap_or(f64::INFINITY))),
        },
    )
}

/// A movable joint type by its table word (`revolute`, `continuous`, `prismatic`, `helical`).
fn kind_of(word: &str) -> Result<JointKind, String> {
    [
        JointKind::Revolute,
        JointKind::Continuous,
        JointKind::Prismatic,
        JointKind::Helical,
    ]
    .into_iter()
    .find(|k| k.as_str() == word)
    .ok_or_else(|| format!("type {word:?} (expected revolute, continuous, prismatic or helical)"))
}

/// A leader for every mimic joint's leader that is neither a joint of the table nor listed,
/// with the limits `limits` gives its first follower.
fn add_leaders(
    joints: &[ScrewJoint],
    leaders: &mut Vec<ScrewLeader>,
    limits: impl Fn(&ScrewJoint) -> Option<(f64, f64)>,
) {
    let mut known: std::collections::HashSet<&str> =
        joints.iter().map(|j| j.name.as_str()).collect();
    let listed: Vec<String> = leaders.iter().map(|l| l.name.clone()).collect();
    known.extend(listed.iter().map(String::as_str));
    let mut new = Vec::new();
    for j in joints {
        if let Some(m) = &j.mimic {
            if known.insert(m.leader.as_str()) {
                new.push(ScrewLeader {
                    name: m.leader.clone(),
                    limits: limits(j),
                });
            }
        }
    }
    leaders.extend(new);
}

fn json_home(v: Option<&Value>) -> Result<[f64; 16], String> {
    let rows = v
        .and_then(Value::as_array)
        .ok_or_else(|| "expected a 4 x 4 array of rows".to_string())?;
    if rows.len() != 4 {
        return Err(format!("expected 4 rows, got {}", rows.len()));
    }
    let mut out = [0.0; 16];
    for (r, row) in rows.iter().enumerate() {
        let row = json_numbers::<4>(Some(row)).map_err(|m| format!("row {r}: {m}"))?;
        out[4 * r..4 * r + 4].copy_from_slice(&row);
    }
    Ok(out)
}

fn from_csv(text: &str, source: &str) -> Result<ScrewRobot, ModelError> {
    let bad = |line: usize, msg: String| {
        table_error(source, format!("line {line}: not a screw table: {msg}"))
    };
    let mut lines = text.lines().enumerate().map(|(i, l)| (i + 1, l));
    match lines.next() {
        Some((_, h))
            if h.trim_end() == "frame,index,joint,type,w1,w2,w3,v1,v2,v3,qx,qy,qz,pitch" => {}
        _ => {
            return Err(bad(
                1,
                "expected the header of `screwkit table --format csv`".into(),
            ))
        }
    }
    type CsvRow = (usize, String, [f64; 6], Option<Mimic>, JointKind);
    let mut rows: [Vec<CsvRow>; 2] = [Vec::new(), Vec::new()];
    let mut home = [f64::NAN; 16];
    let mut home_rows = [false; 4];
    for (n, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let fields = csv_fields(line).map_err(|m| bad(n, m))?;
        if fields.len() != 14 {
            return Err(bad(n, format!("expected 14 fields, got {}", fields.len())));
        }
        let num = |k: usize| -> Result<f64, ModelError> {
            fields[k].trim().parse::<f64>().map_err(|_| {
                bad(
                    n,
                    format!("field {} is not a number: {:?}", k + 1, fields[k]),
                )
            })
        };
        match fields[0].as_str() {
            "M" => {
                let r: usize = fields[1]
                    .parse()
                    .ok()
                    .filter(|r| (1..=4).contains(r))
                    .ok_or_else(|| bad(n, format!("M row {:?} (expected 1 to 4)", fields[1])))?;
                for c in 0..4 {
                    home[4 * (r - 1) + c] = num(2 + c)?;
                }
                home_rows[r - 1] = true;
            }
            f @ ("space" | "body") => {
                let mut s = [0.0; 6];
                for (k, x) in s.iter_mut().enumerate() {
                    *x = num(4 + k)?;
                }
                let mimic = csv_mimic(&fields[3]).map_err(|m| bad(n, m))?;
                let word = fields[3].split(' ').next().unwrap_or_default();
                let kind = kind_of(word).map_err(|m| bad(n, m))?;
                rows[usize::from(f == "body")].push((n, fields[2].clone(), s, mimic, kind));
            }
            other => return Err(bad(n, format!("unknown frame {other:?}"))),
        }
    }
    if home_rows.contains(&false) {
        return Err(table_error(
            source,
            "not a screw table: the four M rows are missing".into(),
        ));
    }
    let (frame, rows) = if rows[0].is_empty() {
        (Frame::Body, std::mem::take(&mut rows[1]))
    } else {
        (Frame::Space, std::mem::take(&mut rows[0]))
    };
    let joints: Vec<ScrewJoint> = rows
        .into_iter()
        .map(|(_, name, screw, mimic, kind)| ScrewJoint {
            name,
            screw,
            limits: None,
            mimic,
            kind: Some(kind),
        })
        .collect();
    // A leader off the chain (a finger following the other finger): a variable of its own.
    let mut leaders = Vec::new();
    add_leaders(&joints, &mut leaders, |_| None);
    Ok(ScrewRobot {
        name: "screws".into(),
        source: source.to_string(),
        home,
        frame,
        joints,
        leaders,
    })
}

/// The drive in a CSV type field, `KIND (mimic: M × LEADER + O)` (as [`to_csv`] writes it, M
/// and O to [`PRECISION`] decimals, as every number of the table), or `None` for a plain `KIND`.
fn csv_mimic(kind: &str) -> Result<Option<Mimic>, String> {
    let Some((_, rest)) = kind.split_once(" (mimic: ") else {
        return Ok(None);
    };
    let bad = || format!("cannot read the mimic drive in {kind:?}");
    let rest = rest.strip_suffix(')').ok_or_else(bad)?;
    let (m, rest) = rest.split_once(" × ").ok_or_else(bad)?;
    let (leader, o) = rest.rsplit_once(" + ").ok_or_else(bad)?;
    let (multiplier, offset) = (m.parse::<f64>(), o.parse::<f64>());
    match (multiplier, offset) {
        (Ok(multiplier), Ok(offset)) if multiplier.is_finite() && offset.is_finite() => {
            Ok(Some(Mimic {
                leader: leader.to_string(),
                multiplier,
                offset,
            }))
        }
        _ => Err(bad()),
    }
}

/// The fields of one CSV line (quotes as [`to_csv`] writes them).
fn csv_fields(line: &str) -> Result<Vec<String>, String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut chars = line.trim_end_matches('\r').chars().peekable();
    let mut quoted = false;
    while let Some(c) = chars.next() {
        match (quoted, c) {
            (false, ',') => out.push(std::mem::take(&mut cur)),
            (false, '"') if cur.is_empty() => quoted = true,
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                cur.push('"');
            }
            (true, '"') => quoted = false,
            (_, c) => cur.push(c),
        }
    }
    if quoted {
        return Err("an unclosed quote".into());
    }
    out.push(cur);
    Ok(out)
}
