//! `screwkit fk`: one path — the arguments say which frames (`query::Selection`), the floor
//! resolves them (`query::Poses`: the chain's tip or links, or frames of the whole tree) and
//! computes their poses, one configuration or a batch; its report is printed as text or JSON.

use screwkit_lie::Se3;
use screwkit_service::query::{Poses, Selection};
use screwkit_service::report;

use crate::args::{FkArgs, Format};
use crate::batch;
use crate::output::{matrix_text, pose_summary, print_json, tuple, CliResult};

/// Batch mode: a `.npy` of shape (N, dof or nq) gives (N, 4, 4) for the tip or (N, K, 4, 4)
/// for K frames; JSON lines give one report per line, streamed chunk by chunk through the
/// library's batch.
fn run_batch(poses: &Poses<'_>, input: &str, output: Option<&str>) -> CliResult {
    let (width, k) = (poses.q_len(), poses.count());
    if let Some(output) = crate::npy::binary(input, output)? {
        return crate::npy::run(
            input,
            output,
            width,
            poses.q_len_word(),
            &poses.shape(),
            |qs, _, out| poses.poses_batch(qs, out),
        );
    }
    batch::stream(input, |lines, _| {
        let (qs, mut errors) = batch::poses_q_rows(poses, lines);
        let mut out = vec![0.0; lines.len() * k * 16];
        batch::merge_row_errors(poses.poses_batch(&qs, &mut out), &mut errors)?;
        Ok(batch::outputs(lines, &errors, |r| {
            let q = &qs[r * width..(r + 1) * width];
            let row = &out[r * k * 16..(r + 1) * k * 16];
            (report::to_value(&poses.report(q, row)), true)
        }))
    })
}

/// One line per pose: name, position, rpy.
fn pose_lines(names: &[&str], poses: &[Se3]) -> String {
    let w = names.iter().map(|n| n.len()).max().unwrap_or(4);
    let mut s = String::new();
    for (name, p) in names.iter().zip(poses) {
        s.push_str(&format!(
            "{:<w$}  position {}  rpy {}\n",
            name,
            tuple(p.translation().as_slice()),
            tuple(&p.rpy())
        ));
    }
    s
}

/// The text of one configuration's poses.
fn text(robot: &screwkit_service::Robot, poses: &Poses<'_>, q: &[f64], flat: &[f64]) -> String {
    let ts: Vec<Se3> = flat
        .chunks(16)
        .map(|p| {
            Se3::from_parts_unchecked(
                nalgebra::Matrix3::new(p[0], p[1], p[2], p[4], p[5], p[6], p[8], p[9], p[10]),
                nalgebra::Vector3::new(p[3], p[7], p[11]),
            )
        })
        .collect();
    let names = poses.names();
    match poses {
        Poses::Frames(kin, _) => {
            let root = kin.model().root();
            let within = if kin.floating_base() {
                format!("the world (floating base under `{root}`)")
            } else {
                format!("`{root}`")
            };
            let mut s = format!("Poses in {within} at q = {}:\n", tuple(q));
            s.push_str(&pose_lines(&names, &ts));
            s
        }
        Poses::Tip(_) | Poses::ChainLinks(_) => {
            // The chain answers only when there is one.
            let chain = robot.chain().expect("a chain query has a chain");
            let tip = ts.last().expect("a chain has its tip");
            let mut s = format!(
                "Pose of `{}` in `{}` at q = {}:\n",
                chain.tip,
                chain.base,
                tuple(q)
            );
            s.push_str(&matrix_text(tip));
            s.push_str(&pose_summary(tip));
            if matches!(poses, Poses::ChainLinks(_)) {
                s.push_str(&format!(
                    "\nEvery link on the chain (in `{}`):\n",
                    chain.base
                ));
                s.push_str(&pose_lines(&names, &ts));
            }
            s
        }
    }
}

/// Runs `fk`.
pub fn run(args: &FkArgs, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    let selection = if !args.frames.is_empty() {
        Selection::Named(&args.frames)
    } else if args.all_links {
        Selection::Links
    } else {
        Selection::Tip
    };
    let poses = Poses::resolve(&robot, None, selection)?;
    if let Some(input) = &args.at.input {
        return run_batch(&poses, input, args.at.output.as_deref());
    }
    let q = &args
        .at
        .q
        .as_ref()
        .expect("clap requires --q without --input")
        .0;
    let mut flat = vec![0.0; 16 * poses.count()];
    poses.poses(q, &mut flat)?;
    if format == Format::Json {
        print_json(&report::to_value(&poses.report(q, &flat)))?;
        return Ok(());
    }
    crate::output::emit(&text(&robot, &poses, q, &flat))?;
    Ok(())
}
