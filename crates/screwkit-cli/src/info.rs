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

fn draw(tree: &Tree, link: usize, prefix: &str, out: &mut String) {
    let kids = &tree.child_joints[link];
    for (i, &j) in kids.iter().enumerate() {
        let last = i + 1 == kids.len();
        let joint = &tree.joints[j];
        out.push_str(&format!(
            "{prefix}{}{} ({}: {})\n",
            if last { "└── " } else { "├── " },
            tree.links[joint.child],
            joint.name,
            joint.kind.as_str()
        ));
        let next = format!("{prefix}{}", if last { "    " } else { "│   " });
        draw(tree, joint.child, &next, out);
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
            print_json(&Value::Array(v));
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
            print!("{s}");
        }
        return Ok(());
    }
    let leaves = tree.leaves_below(tree.root);
    let default = Chain::from_tree(&tree, None, None);
    let movable = tree.joints.iter().filter(|j| j.kind.is_movable()).count();
    if format == Format::Json {
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
            "default_chain": default.as_ref().ok().map(|c| json!({
                "base": c.base, "tip": c.tip, "dof": c.dof(),
                "ik_family": format!("{:?}", screwkit_solve::family::classify(&screwkit_solve::Kinematics::new(c)).family),
            })),
        }));
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
    draw(&tree, tree.root, "", &mut s);
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
            "Default chain: {} → {} ({} DoF: {})\nIK family: {}\n",
            c.base,
            c.tip,
            c.dof(),
            c.variable_names().join(", "),
            screwkit_solve::analytic::describe(&screwkit_solve::Kinematics::new(c))
        )),
        Err(e) => s.push_str(&format!("Default chain: none — {}\n", e.kind)),
    }
    print!("{s}");
    Ok(())
}
