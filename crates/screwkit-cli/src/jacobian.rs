//! `screwkit jacobian`: the Jacobian of the chain's tip or of a tree frame, any kind, optionally
//! with a singularity analysis: one path through the floor's query (`query::About`).

use nalgebra::Matrix6xX;
use screwkit_lie::display::fixed;
use screwkit_service::query::About;
use screwkit_service::report::{self, JacobianReport};
use screwkit_service::whole;
use screwkit_solve::SolveError;
use serde_json::{json, Value};

use crate::args::{Format, JacobianArgs};
use crate::batch;
use crate::output::{print_json, tuple, CliResult, Failure, PREC};
use screwkit_service::words::{JacobianFrame, Word};

/// A number for people: scientific notation when it is small (or huge), fixed otherwise.
fn readable(x: f64) -> String {
    if !x.is_finite() {
        "∞".into()
    } else if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6) {
        format!("{x:.6e}")
    } else {
        fixed(x, PREC)
    }
}

/// The Jacobian as a markdown table, one column per name, rows ω then v.
fn table(j: &Matrix6xX<f64>, names: &[String]) -> String {
    let mut s = format!(
        "|    | {} |\n|---|{}\n",
        names.join(" | "),
        "---|".repeat(j.ncols())
    );
    for (r, label) in ["ωx", "ωy", "ωz", "vx", "vy", "vz"].iter().enumerate() {
        let cells: Vec<String> = j.row(r).iter().map(|&x| fixed(x, PREC)).collect();
        s.push_str(&format!("| {label} | {} |\n", cells.join(" | ")));
    }
    s
}

/// The singularity analysis of `j` as text (with its position-only part at the point `p`).
fn analysis_text(
    j: &Matrix6xX<f64>,
    frame: JacobianFrame,
    p: &nalgebra::Vector3<f64>,
) -> Result<String, SolveError> {
    let (a, pos) = screwkit_service::query::analysis_of(j, frame.kind(), p)?;
    let mut s = format!(
        "\nsingular values       {}\nrank                  {} of {} (σ ≤ {:.2e} counts as 0)\nmanipulability        {} (√det(J Jᵀ))\ncondition number      {}\n",
        tuple(&a.singular_values),
        a.rank,
        j.ncols().min(6),
        a.rank_tolerance,
        readable(a.manipulability),
        readable(a.condition_number),
    );
    s.push_str(&format!(
        "position only (the tip point, 3 × {n}): singular values {}, rank {} of {}, manipulability {}, condition number {}\n",
        tuple(&pos.singular_values),
        pos.rank,
        j.ncols().min(3),
        readable(pos.manipulability),
        readable(pos.condition_number),
        n = j.ncols(),
    ));
    if let Some(d) = a.determinant {
        s.push_str(&format!("det J                 {}\n", readable(d)));
    }
    s.push_str(&format!("verdict               {}\n", a.verdict()));
    Ok(s)
}

/// The request of one `jacobian` call: what it is about (the floor's `query::About`), the
/// kind and, on the whole tree, the names its JSON gives (`of`, `relative_to`, `columns`).
struct Request<'a> {
    about: About<'a>,
    frame: JacobianFrame,
    analyze: bool,
    /// `--of` and the frame the answer is seen from (the tree's only).
    tree: Option<(&'a str, String)>,
}

impl Request<'_> {
    /// One configuration's JSON, the floor's report; `p` is the frame's position.
    fn json(
        &self,
        q: &[f64],
        j: &Matrix6xX<f64>,
        p: &nalgebra::Vector3<f64>,
    ) -> Result<Value, String> {
        let mut r =
            JacobianReport::new(q, j, self.frame, self.analyze, p).map_err(|e| e.to_string())?;
        if let Some((of, reference)) = &self.tree {
            r.of = Some(of.to_string());
            r.relative_to = Some(reference.clone());
            r.columns = Some(self.about.column_names().to_vec());
        }
        Ok(report::to_value(&r))
    }
}

/// Runs `jacobian`: the chain's tip, or on the whole tree the frame `--of` (relative to
/// `--relative-to`), one path through the floor's query (`query::About`): `--input` streams
/// JSON lines, or a `.npy` (N, n) → (N, 6, columns), through the library's batches.
pub fn run(args: &JacobianArgs, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    if whole::wants_tree(&robot, args.of.is_some()) && args.of.is_none() {
        return Err(Failure(
            "this robot has no single chain: name the frame with --of FRAME (or pick a chain with --tip)".into(),
        ));
    }
    let about = About::resolve(
        &robot,
        None,
        args.of.as_deref(),
        args.relative_to.as_deref(),
    )?;
    let tree = match (&about, &args.of) {
        (About::Frame(t, _) | About::Relative(t, _, _), Some(of)) => Some((
            of.as_str(),
            match &args.relative_to {
                Some(r) => r.clone(),
                None if t.floating_base() => "world".to_string(),
                None => t.model().root().to_string(),
            },
        )),
        _ => None,
    };
    let req = Request {
        about,
        frame: args.frame,
        analyze: args.analyze,
        tree,
    };
    let kind = args.frame.kind();
    let (nq, n) = (about.q_len(), about.columns());
    if let Some(input) = &args.at.input {
        if let Some(output) = crate::npy::binary(input, args.at.output.as_deref())? {
            if args.analyze {
                return Err(Failure(
                    "--analyze is for JSON output (not with --output .npy)".into(),
                ));
            }
            let what = if about.is_tree() { "nq" } else { "dof" };
            return crate::npy::run(input, output, nq, what, &[6, n], |qs, _, out| {
                about.jacobians(kind, qs, out, None)
            });
        }
        // Streamed chunk by chunk, every chunk through the library's batch (the analysis, an
        // SVD per row, runs while the lines are formatted).
        return batch::stream(input, |lines, _| {
            let (qs, mut errors) = batch::about_q_rows(&about, lines);
            let rows = lines.len();
            let (mut jac, mut poses) = (vec![0.0; rows * 6 * n], vec![0.0; rows * 16]);
            let result = about.jacobians(kind, &qs, &mut jac, Some(&mut poses));
            batch::merge_row_errors(result, &mut errors)?;
            Ok(batch::outputs(lines, &errors, |k| {
                let j = Matrix6xX::from_row_slice(&jac[k * 6 * n..(k + 1) * 6 * n]);
                let t = &poses[k * 16..(k + 1) * 16];
                let p = nalgebra::Vector3::new(t[3], t[7], t[11]);
                match req.json(&qs[k * nq..(k + 1) * nq], &j, &p) {
                    Ok(v) => (v, true),
                    Err(e) => (json!({"error": e, "line": lines[k].number}), false),
                }
            }))
        });
    }
    let q = &args
        .at
        .q
        .as_ref()
        .expect("clap requires --q without --input")
        .0;
    let mut flat = vec![0.0; 6 * n];
    let pose = about.pose_jacobian(kind, q, &mut flat)?;
    let j = Matrix6xX::from_row_slice(&flat);
    let p = *pose.translation();
    if format == Format::Json {
        print_json(&req.json(q, &j, &p).map_err(Failure)?)?;
        return Ok(());
    }
    let mut s = match (&about, &req.tree) {
        (About::Tip(_), _) | (_, None) => {
            let (chain, _) = robot.chain_parts()?;
            let (name, sym) = match args.frame {
                JacobianFrame::Space => ("Space", "J_s"),
                JacobianFrame::Body => ("Body", "J_b"),
                JacobianFrame::WorldAligned => ("World-aligned (tip point, base axes)", "J_wa"),
            };
            format!(
                "{name} Jacobian {sym} (6 × {n}) of `{}` → `{}` at q = {}; rows ω then v:\n\n",
                chain.base,
                chain.tip,
                tuple(q),
            )
        }
        (_, Some((of, reference))) => format!(
            "{} Jacobian (6 × {n}) of `{of}` in `{reference}` at q = {}; rows ω then v:\n\n",
            args.frame.as_str(),
            tuple(q),
        ),
    };
    s.push_str(&table(&j, about.column_names()));
    if args.analyze {
        s.push_str(&analysis_text(&j, args.frame, &p)?);
    }
    crate::output::emit(&s)?;
    Ok(())
}
