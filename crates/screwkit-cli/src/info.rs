//! `screwkit info`: what is in a URDF.

use screwkit_model::{Chain, Tree};
use serde_json::{json, Value};

use crate::args::{Format, InfoArgs};
use crate::output::{num, print_json, CliResult};

fn limit_json(tree: &Tree, j: usize) -> (Value, Value, Value, Value) {
    match tree.joints[j].limit {
        Some(l) if tree.joints[j].kind != screwkit_model::JointKind::Continuous => (
            num(l.lower),
            num(l.upper),
            l.velocity.map_or(Value::Null, num),
            l.effort.map_or(Value::Null, num),
        ),
        Some(l) => (
            Value::Null,
            Value::Null,
            l.velocity.map_or(Value::Null, num),
            l.effort.map_or(Value::Null, num),
        ),
        None => (Value::Null, Value::Null, Value::Null, Value::Null),
    }
}

/// Levels of the tree drawn with their guide lines; deeper links show their depth instead
/// (so a 30,000-link chain prints in linear size, not quadratic).
const DRAWN_DEPTH: usize = 32;

/// The tree below `root`, one line per joint, walked with an explicit stack (no recursion:
/// any depth).
fn draw(tree: &Tree, root: usize, out: &mut String) {
    // (link, depth, whether each ancestor level was a last child)
    let mut stack: Vec<(usize, usize, bool)> = Vec::new();
    let mut lasts: Vec<bool> = Vec::new();
    let push_kids = |stack: &mut Vec<(usize, usize, bool)>, link: usize, depth: usize| {
        let kids = &tree.child_joints[link];
        for (i, &j) in kids.iter().enumerate().rev() {
            stack.push((j, depth, i + 1 == kids.len()));
        }
    };
    push_kids(&mut stack, root, 0);
    while let Some((j, depth, last)) = stack.pop() {
        lasts.truncate(depth);
        let mut prefix = String::new();
        for &l in lasts.iter().take(DRAWN_DEPTH) {
            prefix.push_str(if l { "    " } else { "│   " });
        }
        if depth > DRAWN_DEPTH {
            prefix.push_str(&format!("⋮ (depth {}) ", depth + 1));
        }
        let joint = &tree.joints[j];
        out.push_str(&format!(
            "{prefix}{}{} ({}: {})\n",
            if last { "└── " } else { "├── " },
            tree.links[joint.child],
            joint.name,
            joint.kind.as_str()
        ));
        lasts.push(last);
        push_kids(&mut stack, joint.child, depth + 1);
    }
}

/// Whether a leaf link looks like a sensor or a mounting frame rather than an end effector.
fn sensor_like(name: &str) -> bool {
    let n = name.to_ascii_lowercase();
    [
        "camera",
        "sensor",
        "imu",
        "laser",
        "lidar",
        "optical",
        "depth",
        "rgb",
        "sonar",
        "gps",
        "ft_",
        "force",
        "_frame",
        "scan",
        "kinect",
        "realsense",
    ]
    .iter()
    .any(|w| n.contains(w))
}

/// Every chain root → leaf: (leaf, DoF or the reason it is not a chain), end effectors first,
/// sensor-like leaves last, each group in file order.
fn chains(tree: &Tree) -> Vec<(String, Result<usize, String>)> {
    let mut leaves = tree.leaves_below(tree.root);
    leaves.sort_by_key(|&l| sensor_like(&tree.links[l]));
    leaves
        .into_iter()
        .map(|l| {
            let name = tree.links[l].clone();
            let dof = Chain::from_tree(tree, None, Some(&name))
                .map(|c| c.dof())
                .map_err(|e| e.kind.to_string());
            (name, dof)
        })
        .collect()
}

/// Runs `info`.
pub fn run(args: &InfoArgs, format: Format) -> CliResult {
    let tree = crate::read_tree(&args.urdf, &args.xacro)?;
    if args.chains {
        let list = chains(&tree);
        if format == Format::Json {
            let v: Vec<Value> = list
                .iter()
                .map(|(leaf, dof)| match dof {
                    Ok(d) => json!({"base": tree.links[tree.root], "tip": leaf, "dof": d, "sensor_like": sensor_like(leaf)}),
                    Err(e) => json!({"base": tree.links[tree.root], "tip": leaf, "error": e, "sensor_like": sensor_like(leaf)}),
                })
                .collect();
            print_json(&Value::Array(v))?;
        } else {
            let mut s = format!(
                "Chains of `{}` from the root `{}` to each leaf (end effectors first, sensor-like leaves last):\n\n| tip | DoF |\n|---|---|\n",
                tree.name, tree.links[tree.root]
            );
            for (leaf, dof) in &list {
                let d = match dof {
                    Ok(d) => d.to_string(),
                    Err(e) => format!("not a chain: {e}"),
                };
                s.push_str(&format!("| {leaf} | {d} |\n"));
            }
            crate::output::emit(&s)?;
        }
        return Ok(());
    }
    let leaves = tree.leaves_below(tree.root);
    // The chain asked for (`--base`/`--tip`: an error when it is not one), else the default.
    let chosen = args.base.is_some() || args.tip.is_some();
    let default = Chain::from_tree(&tree, args.base.as_deref(), args.tip.as_deref());
    if chosen {
        default
            .as_ref()
            .map_err(|e| crate::output::Failure(e.to_string()))?;
    }
    let movable = tree.joints.iter().filter(|j| j.kind.is_movable()).count();
    let whole = screwkit_model::KinematicTree::from_tree(&tree);
    if format == Format::Json {
        // The whole tree's variables (the file's joint order, mimic followers excluded) and
        // frames (every link, with its home pose in the root link's frame).
        let (variables, frames) = match &whole {
            Ok(m) => (
                Value::Array(
                    m.variables
                        .iter()
                        .enumerate()
                        .map(|(k, v)| {
                            json!({
                                "index": k, "name": v.name, "type": v.kind.as_str(),
                                "lower": num(v.lower), "upper": num(v.upper),
                                "velocity": v.velocity.map_or(Value::Null, num), "effort": v.effort.map_or(Value::Null, num),
                            })
                        })
                        .collect(),
                ),
                Value::Array(
                    m.frames
                        .iter()
                        .map(|f| {
                            json!({
                                "name": f.name, "link": m.links[f.link].name,
                                "home": crate::output::pose_json(&f.home),
                            })
                        })
                        .collect(),
                ),
            ),
            Err(_) => (Value::Null, Value::Null),
        };
        let joints: Vec<Value> = (0..tree.joints.len())
            .map(|j| {
                let jt = &tree.joints[j];
                let (lo, up, vel, eff) = limit_json(&tree, j);
                json!({
                    "name": jt.name, "type": jt.kind.as_str(),
                    "parent": tree.links[jt.parent], "child": tree.links[jt.child],
                    "lower": lo, "upper": up, "velocity": vel, "effort": eff,
                    "mimic": jt.mimic.as_ref().map(|m| json!({"leader": m.leader, "multiplier": m.multiplier, "offset": m.offset})),
                })
            })
            .collect();
        print_json(&json!({
            "robot": tree.name,
            "root": tree.links[tree.root],
            "links": tree.links,
            "joints": joints,
            "leaves": leaves.iter().map(|&l| tree.links[l].clone()).collect::<Vec<_>>(),
            "variables": variables,
            "frames": frames,
            "whole_tree_error": whole.as_ref().err().map(|e| e.kind.to_string()),
            "default_chain": default.as_ref().ok().map(|c| json!({
                "base": c.base, "tip": c.tip, "dof": c.dof(),
                "ik_family": screwkit_solve::family::classify(&screwkit_solve::Kinematics::new(c)).family.word(),
            })),
        }))?;
        return Ok(());
    }
    let mut s = format!(
        "Robot `{}` ({}): {} links, {} joints ({} movable)\n\nTree:\n{}\n",
        tree.name,
        args.urdf.display(),
        tree.links.len(),
        tree.joints.len(),
        movable,
        tree.links[tree.root]
    );
    draw(&tree, tree.root, &mut s);
    s.push_str("\nJoints:\n\n| joint | type | parent → child | lower | upper | velocity | effort |\n|---|---|---|---|---|---|---|\n");
    let cell = |v: Value| match v {
        Value::Null => "–".to_string(),
        Value::Number(n) => n.as_f64().map_or("–".into(), |x| format!("{x}")),
        _ => "–".to_string(),
    };
    for j in 0..tree.joints.len() {
        let jt = &tree.joints[j];
        let (lo, up, vel, eff) = limit_json(&tree, j);
        let kind = match &jt.mimic {
            Some(m) => format!("{} (mimics {})", jt.kind.as_str(), m.leader),
            None => jt.kind.as_str().to_string(),
        };
        s.push_str(&format!(
            "| {} | {} | {} → {} | {} | {} | {} | {} |\n",
            jt.name,
            kind,
            tree.links[jt.parent],
            tree.links[jt.child],
            cell(lo),
            cell(up),
            cell(vel),
            cell(eff)
        ));
    }
    s.push_str(&format!(
        "\nLeaves: {}\n",
        leaves
            .iter()
            .map(|&l| tree.links[l].as_str())
            .collect::<Vec<_>>()
            .join(", ")
    ));
    match &default {
        Ok(c) => s.push_str(&format!(
            "{}: {} → {} ({} DoF: {})\nIK family: {}\n",
            if chosen { "Chain" } else { "Default chain" },
            c.base,
            c.tip,
            c.dof(),
            c.variable_names().join(", "),
            screwkit_solve::analytic::describe(&screwkit_solve::Kinematics::new(c))
        )),
        Err(e) => s.push_str(&format!("Default chain: none — {}\n", e.kind)),
    }
    match &whole {
        Ok(m) => s.push_str(&format!(
            "Whole tree: {} variables (file order; fk --frames, jacobian --of): {}\n",
            m.variables.len(),
            m.variables
                .iter()
                .map(|v| v.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )),
        Err(e) => s.push_str(&format!("Whole tree: none — {}\n", e.kind)),
    }
    crate::output::emit(&s)?;
    Ok(())
}
