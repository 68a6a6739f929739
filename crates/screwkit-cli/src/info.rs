//! `screwkit info`: what is in a robot file — the floor's report, as text or JSON.

use screwkit_model::Tree;
use screwkit_service::info::{self, InfoReport};
use screwkit_service::report;

use crate::args::{Format, InfoArgs};
use crate::output::{print_json, CliResult};

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

/// A limit's table cell: the number, or – when absent or unbounded.
fn cell(x: Option<f64>) -> String {
    match x {
        Some(x) if x.is_finite() => format!("{}", x + 0.0),
        _ => "–".to_string(),
    }
}

/// Runs `info`: the floor's report ([`screwkit_service::info`]), as text or JSON.
pub fn run(args: &InfoArgs, format: Format) -> CliResult {
    let tree = crate::read_tree(&args.urdf, &args.xacro)?;
    if args.chains {
        let list = info::chains(&tree);
        if format == Format::Json {
            print_json(&report::to_value(&list))?;
        } else {
            let mut s = format!(
                "Chains of `{}` from the root `{}` to each leaf (end effectors first, sensor-like leaves last):\n\n| tip | DoF |\n|---|---|\n",
                tree.name, tree.links[tree.root]
            );
            for c in &list {
                let d = match (&c.dof, &c.error) {
                    (Some(d), _) => d.to_string(),
                    (None, e) => format!("not a chain: {}", e.as_deref().unwrap_or("")),
                };
                s.push_str(&format!("| {} | {d} |\n", c.tip));
            }
            crate::output::emit(&s)?;
        }
        return Ok(());
    }
    let info = InfoReport::new(&tree, args.base.as_deref(), args.tip.as_deref())?;
    if format == Format::Json {
        print_json(&report::to_value(&info))?;
        return Ok(());
    }
    let movable = tree.joints.iter().filter(|j| j.kind.is_movable()).count();
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
    for j in &info.joints {
        let kind = match &j.mimic {
            Some(m) => format!("{} (mimics {})", j.kind, m.leader),
            None => j.kind.to_string(),
        };
        s.push_str(&format!(
            "| {} | {} | {} → {} | {} | {} | {} | {} |\n",
            j.name,
            kind,
            j.parent,
            j.child,
            cell(j.lower),
            cell(j.upper),
            cell(j.velocity),
            cell(j.effort)
        ));
    }
    s.push_str(&format!("\nLeaves: {}\n", info.leaves.join(", ")));
    if !info.geometry.is_empty() || !info.geometry_problems.is_empty() {
        let count = |role: &str| info.geometry.iter().filter(|g| g.role == role).count();
        let meshes = info.geometry.iter().filter(|g| g.mesh.is_some()).count();
        s.push_str(&format!(
            "Geometry: {} collision and {} visual shapes ({meshes} meshes){}\n",
            count("collision"),
            count("visual"),
            if info.geometry_problems.is_empty() {
                String::new()
            } else {
                format!("; not read: {}", info.geometry_problems.join("; "))
            }
        ));
    }
    match (&info.default_chain, &info.chain_error) {
        (Some(c), _) => s.push_str(&format!(
            "{}: {} → {} ({} DoF: {})\nIK family: {}\n",
            if info.chosen {
                "Chain"
            } else {
                "Default chain"
            },
            c.base,
            c.tip,
            c.dof,
            c.variables.join(", "),
            c.ik_description
        )),
        (None, e) => s.push_str(&format!(
            "Default chain: none — {}\n",
            e.as_deref().unwrap_or("")
        )),
    }
    match (&info.variables, &info.whole_tree_error) {
        (Some(vars), _) => s.push_str(&format!(
            "Whole tree: {} variables (file order; fk --frames, jacobian --of): {}\n",
            vars.len(),
            vars.iter()
                .map(|v| v.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        )),
        (None, e) => s.push_str(&format!(
            "Whole tree: none — {}\n",
            e.as_deref().unwrap_or("")
        )),
    }
    crate::output::emit(&s)?;
    Ok(())
}
