//! `screwkit jacobian`: J_s or J_b, optionally with a singularity analysis.

use nalgebra::{Matrix6xX, Vector6};
use screwkit_lie::display::fixed;
use screwkit_solve::analysis::{analyze, Analysis};
use screwkit_solve::jacobian::{fk_jacobian_body, fk_jacobian_space};
use screwkit_solve::{Kinematics, Workspace};
use serde_json::{json, Value};

use crate::args::{Format, JacFrame, JacobianArgs};
use crate::batch;
use crate::output::{num, nums, print_json, tuple, CliResult, Failure, PREC};

/// Above this condition number a configuration is called near singular.
const NEAR_SINGULAR_CONDITION: f64 = 1e3;

fn compute(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    frame: JacFrame,
) -> Result<Matrix6xX<f64>, String> {
    let r = match frame {
        JacFrame::Space => fk_jacobian_space(kin, ws, q),
        JacFrame::Body => fk_jacobian_body(kin, ws, q),
    };
    r.map(|(_, j)| j.clone()).map_err(|e| e.to_string())
}

/// Plain words for a twist direction (ω, v).
fn describe(u: &Vector6<f64>) -> String {
    let w = u.fixed_rows::<3>(0).into_owned();
    let v = u.fixed_rows::<3>(3).into_owned();
    if v.norm() < 0.05 {
        format!("rotation about {}", tuple(w.normalize().as_slice()))
    } else if w.norm() < 0.05 {
        format!("translation along {}", tuple(v.normalize().as_slice()))
    } else {
        format!(
            "the twist (ω | v) = ({} | {})",
            tuple(w.as_slice()),
            tuple(v.as_slice())
        )
    }
}

/// The verdict in plain words.
fn verdict(a: &Analysis, n: usize) -> String {
    let k = n.min(6);
    if a.rank < k {
        let dirs: Vec<String> = a
            .lost_directions
            .iter()
            .take(k - a.rank)
            .map(describe)
            .collect();
        format!(
            "singular (rank {} of {k}): loses motion along {}",
            a.rank,
            dirs.join("; ")
        )
    } else if a.condition_number > NEAR_SINGULAR_CONDITION {
        format!(
            "near singular (condition number {:.3e}): loses motion along {}",
            a.condition_number,
            describe(&a.weakest_direction)
        )
    } else if n < 6 {
        format!(
            "full rank {n}, but a {n}-joint chain can never produce {} of the 6 twist directions",
            6 - n
        )
    } else {
        format!(
            "well-conditioned (condition number {:.3})",
            a.condition_number
        )
    }
}

fn analysis_json(a: &Analysis, n: usize) -> Value {
    json!({
        "singular_values": nums(&a.singular_values),
        "rank": a.rank,
        "rank_tolerance": num(a.rank_tolerance),
        "manipulability": num(a.manipulability),
        "condition_number": num(a.condition_number),
        "determinant": a.determinant.map_or(Value::Null, num),
        "lost_directions": a.lost_directions.iter().map(|d| nums(d.as_slice())).collect::<Vec<_>>(),
        "verdict": verdict(a, n),
    })
}

fn value(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    frame: JacFrame,
    with_analysis: bool,
) -> Result<Value, String> {
    let j = compute(kin, ws, q, frame)?;
    let rows: Vec<Value> = (0..6)
        .map(|r| nums(&j.row(r).iter().copied().collect::<Vec<_>>()))
        .collect();
    let mut v = json!({
        "q": nums(q),
        "frame": if frame == JacFrame::Space { "space" } else { "body" },
        "jacobian": rows,
    });
    if with_analysis {
        let a = analyze(&j).map_err(|e| e.to_string())?;
        v["analysis"] = analysis_json(&a, j.ncols());
    }
    Ok(v)
}

/// Runs `jacobian`.
pub fn run(args: &JacobianArgs, format: Format) -> CliResult {
    let (chain, kin) = crate::load(&args.chain)?;
    if let Some(input) = &args.input {
        return batch::run_q_lines(&kin, input, |ws, q| {
            value(&kin, ws, q, args.frame, args.analyze)
        });
    }
    let q = &args
        .q
        .as_ref()
        .expect("clap requires --q without --input")
        .0;
    let mut ws = Workspace::new(&kin);
    if format == Format::Json {
        print_json(&value(&kin, &mut ws, q, args.frame, args.analyze).map_err(Failure)?);
        return Ok(());
    }
    let j = compute(&kin, &mut ws, q, args.frame).map_err(Failure)?;
    let (name, sym) = match args.frame {
        JacFrame::Space => ("Space", "J_s"),
        JacFrame::Body => ("Body", "J_b"),
    };
    let mut s = format!(
        "{name} Jacobian {sym} (6 × {}) of `{}` → `{}` at q = {}; rows ω then v:\n\n|    | {} |\n|---|{}\n",
        j.ncols(),
        chain.base,
        chain.tip,
        tuple(q),
        kin.names().join(" | "),
        "---|".repeat(j.ncols())
    );
    for (r, label) in ["ωx", "ωy", "ωz", "vx", "vy", "vz"].iter().enumerate() {
        let cells: Vec<String> = j.row(r).iter().map(|&x| fixed(x, PREC)).collect();
        s.push_str(&format!("| {label} | {} |\n", cells.join(" | ")));
    }
    if args.analyze {
        let a = analyze(&j)?;
        s.push_str(&format!(
            "\nsingular values       {}\nrank                  {} of {} (σ ≤ {:.2e} counts as 0)\nmanipulability        {} (√det(J Jᵀ))\ncondition number      {}\n",
            tuple(&a.singular_values),
            a.rank,
            j.ncols().min(6),
            a.rank_tolerance,
            fixed(a.manipulability, PREC),
            if !a.condition_number.is_finite() {
                "∞".into()
            } else if a.condition_number >= 1e6 {
                format!("{:.6e}", a.condition_number)
            } else {
                format!("{:.6}", a.condition_number)
            },
        ));
        if let Some(d) = a.determinant {
            s.push_str(&format!("det J                 {}\n", fixed(d, PREC)));
        }
        s.push_str(&format!(
            "verdict               {}\n",
            verdict(&a, j.ncols())
        ));
    }
    print!("{s}");
    Ok(())
}
