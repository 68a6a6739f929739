//! `screwkit jacobian`: J_s or J_b, optionally with a singularity analysis.

use nalgebra::Matrix6xX;
use screwkit_lie::display::fixed;
use screwkit_service::report::{self, JacobianReport};
use screwkit_solve::analysis::{analyze_jacobian, analyze_position_jacobian};
use screwkit_solve::batch::jacobian_batch;
use screwkit_solve::jacobian::jacobian;
use screwkit_solve::{Kinematics, SolveError, Workspace};
use serde_json::{json, Value};

use crate::args::{Format, JacobianArgs};
use crate::batch;
use crate::output::{print_json, tuple, CliResult, Failure, PREC};
use screwkit_service::words::{JacobianFrame, Word};

/// `{"q", "frame", "jacobian"}` (+ `"analysis"` with its `"position"` part) for one
/// configuration, the floor's report; `p` is the frame's position.
fn value(
    q: &[f64],
    j: &Matrix6xX<f64>,
    frame: JacobianFrame,
    with_analysis: bool,
    p: &nalgebra::Vector3<f64>,
) -> Result<Value, String> {
    JacobianReport::new(q, j, frame, with_analysis, p)
        .map(|r| report::to_value(&r))
        .map_err(|e| e.to_string())
}

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

/// Batch mode: streamed chunk by chunk, every chunk through the library's Jacobian batch (the
/// analysis, an SVD per row, runs while the lines are formatted).
fn run_batch(
    kin: &Kinematics,
    input: &str,
    frame: JacobianFrame,
    with_analysis: bool,
) -> CliResult {
    let n = kin.dof();
    batch::stream(input, |lines, _| {
        let (qs, mut errors) = batch::q_rows(kin, lines);
        let rows = lines.len();
        let mut jac = vec![0.0; rows * 6 * n];
        let mut poses = vec![0.0; rows * 16];
        let result = jacobian_batch(kin, &qs, frame.kind(), &mut jac, Some(&mut poses));
        batch::merge_row_errors(result, &mut errors)?;
        Ok(batch::outputs(lines, &errors, |k| {
            let j = Matrix6xX::from_row_slice(&jac[k * 6 * n..(k + 1) * 6 * n]);
            let t = &poses[k * 16..(k + 1) * 16];
            let p = nalgebra::Vector3::new(t[3], t[7], t[11]);
            match value(&qs[k * n..(k + 1) * n], &j, frame, with_analysis, &p) {
                Ok(v) => (v, true),
                Err(e) => (json!({"error": e, "line": lines[k].number}), false),
            }
        }))
    })
}

/// One Jacobian of the requested kind.
fn one(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    frame: JacobianFrame,
) -> Result<Matrix6xX<f64>, SolveError> {
    jacobian(kin, ws, q, frame.kind()).cloned()
}

/// The whole-tree request of `jacobian --of A [--relative-to B]`: the frames, the form and the
/// name of the frame the answer is in.
struct TreeRequest<'a> {
    kin: &'a screwkit_solve::TreeKinematics,
    of: &'a str,
    a: usize,
    b: Option<usize>,
    frame: JacobianFrame,
    reference: String,
}

impl TreeRequest<'_> {
    /// One configuration's JSON: `{"q", "frame", "of", "relative_to", "columns",
    /// "jacobian"}` (+ `"analysis"`); `p` is the frame's position (in the reference frame).
    fn json(
        &self,
        q: &[f64],
        j: &Matrix6xX<f64>,
        analyze: bool,
        p: &nalgebra::Vector3<f64>,
    ) -> Result<Value, String> {
        let mut r = JacobianReport::new(q, j, self.frame, analyze, p).map_err(|e| e.to_string())?;
        r.of = Some(self.of.to_string());
        r.relative_to = Some(self.reference.clone());
        r.columns = Some(self.kin.v_names().to_vec());
        Ok(report::to_value(&r))
    }

    /// N Jacobians (N × 6 × nv) and the frame's poses (N × 16) through the library's batch.
    fn batch(
        &self,
        qs: &[f64],
        jac: &mut [f64],
        poses: Option<&mut [f64]>,
    ) -> Result<(), SolveError> {
        use screwkit_solve::tree::batch::{frame_jacobian_batch, relative_jacobian_batch};
        let form = self.frame.kind();
        match self.b {
            Some(b) => relative_jacobian_batch(self.kin, (self.a, b), form, qs, jac, poses),
            None => frame_jacobian_batch(self.kin, self.a, form, qs, jac, poses),
        }
    }
}

/// `jacobian` on the whole tree: the Jacobian of `--of` (or of it relative to
/// `--relative-to`), 6 × nv, one column per entry of the tree's velocity; `--input` streams
/// JSON lines or a `.npy` (N, nq) → (N, 6, nv) through the library's tree batch.
fn run_tree(robot: &screwkit_service::Robot, args: &JacobianArgs, format: Format) -> CliResult {
    let kin = robot.whole()?;
    let Some(of) = &args.of else {
        return Err(Failure(
            "this robot has no single chain: name the frame with --of FRAME (or pick a chain with --tip)".into(),
        ));
    };
    let req = TreeRequest {
        kin,
        of,
        a: kin.frame(of)?,
        b: args
            .relative_to
            .as_deref()
            .map(|r| kin.frame(r))
            .transpose()?,
        frame: args.frame,
        reference: match &args.relative_to {
            Some(r) => r.clone(),
            None if kin.floating_base() => "world".to_string(),
            None => kin.model().root().to_string(),
        },
    };
    let (nq, nv) = (kin.nq(), kin.nv());
    if let Some(input) = &args.at.input {
        if let Some(output) = crate::npy::binary(input, args.at.output.as_deref())? {
            if args.analyze {
                return Err(Failure(
                    "--analyze is for JSON output (not with --output .npy)".into(),
                ));
            }
            return crate::npy::run(input, output, nq, "nq", &[6, nv], |qs, _, out| {
                req.batch(qs, out, None)
            });
        }
        return batch::stream(input, |lines, _| {
            let (qs, mut errors) = batch::tree_q_rows(kin, lines);
            let rows = lines.len();
            let (mut jac, mut poses) = (vec![0.0; rows * 6 * nv], vec![0.0; rows * 16]);
            batch::merge_row_errors(req.batch(&qs, &mut jac, Some(&mut poses)), &mut errors)?;
            Ok(batch::outputs(lines, &errors, |k| {
                let j = Matrix6xX::from_row_slice(&jac[k * 6 * nv..(k + 1) * 6 * nv]);
                let t = &poses[k * 16..(k + 1) * 16];
                let p = nalgebra::Vector3::new(t[3], t[7], t[11]);
                match req.json(&qs[k * nq..(k + 1) * nq], &j, args.analyze, &p) {
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
    let mut ws = robot.tree_workspace()?;
    let form = args.frame.kind();
    let pj = match req.b {
        Some(b) => {
            screwkit_solve::tree::jacobian::relative_jacobian(kin, &mut ws, q, req.a, b, form)?
        }
        None => screwkit_solve::tree::jacobian::frame_pose_jacobian(kin, &mut ws, q, req.a, form)?,
    };
    let (j, p) = (pj.jacobian, *pj.pose.translation());
    if format == Format::Json {
        print_json(&req.json(q, j, args.analyze, &p).map_err(Failure)?)?;
        return Ok(());
    }
    let mut s = format!(
        "{} Jacobian (6 × {}) of `{of}` in `{}` at q = {}; rows ω then v:\n\n",
        args.frame.as_str(),
        j.ncols(),
        req.reference,
        tuple(q),
    );
    s.push_str(&table(j, kin.v_names()));
    if args.analyze {
        s.push_str(&analysis_text(j, args.frame, &p)?);
    }
    crate::output::emit(&s)?;
    Ok(())
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
    let a = analyze_jacobian(j)?;
    let pos = analyze_position_jacobian(&report::tip_point_rows(j, frame.kind(), p));
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

/// Runs `jacobian`.
pub fn run(args: &JacobianArgs, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    if screwkit_service::whole::wants_tree(&robot, args.of.is_some()) {
        return run_tree(&robot, args, format);
    }
    let (chain, kin) = robot.chain_parts()?;
    if let Some(input) = &args.at.input {
        if let Some(output) = crate::npy::binary(input, args.at.output.as_deref())? {
            if args.analyze {
                return Err(Failure(
                    "--analyze is for JSON output (not with --output .npy)".into(),
                ));
            }
            let n = kin.dof();
            let kind = args.frame.kind();
            return crate::npy::run(input, output, n, "dof", &[6, n], |qs, _, out| {
                jacobian_batch(kin, qs, kind, out, None)
            });
        }
        return run_batch(kin, input, args.frame, args.analyze);
    }
    let q = &args
        .at
        .q
        .as_ref()
        .expect("clap requires --q without --input")
        .0;
    let mut ws = Workspace::new(kin);
    let j = one(kin, &mut ws, q, args.frame)?;
    let p = *screwkit_solve::fk::fk(kin, &mut ws, q)?.translation();
    if format == Format::Json {
        let v = value(q, &j, args.frame, args.analyze, &p).map_err(Failure)?;
        print_json(&v)?;
        return Ok(());
    }
    let (name, sym) = match args.frame {
        JacobianFrame::Space => ("Space", "J_s"),
        JacobianFrame::Body => ("Body", "J_b"),
        JacobianFrame::WorldAligned => ("World-aligned (tip point, base axes)", "J_wa"),
    };
    let mut s = format!(
        "{name} Jacobian {sym} (6 × {}) of `{}` → `{}` at q = {}; rows ω then v:\n\n",
        j.ncols(),
        chain.base,
        chain.tip,
        tuple(q),
    );
    s.push_str(&table(&j, kin.names()));
    if args.analyze {
        s.push_str(&analysis_text(&j, args.frame, &p)?);
    }
    crate::output::emit(&s)?;
    Ok(())
}
