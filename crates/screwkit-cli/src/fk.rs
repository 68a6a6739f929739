//! `screwkit fk`: tip pose or every link's pose; on the whole tree, the chosen frames' poses.

use screwkit_lie::Se3;
use screwkit_service::{whole, Robot};
use screwkit_solve::batch::{fk_all_links_batch, fk_batch};
use screwkit_solve::fk::{fk, fk_all_links};
use screwkit_solve::tree::batch::fk_frames_batch;
use screwkit_solve::{Kinematics, TreeKinematics, Workspace};
use serde_json::Value;

use crate::args::{FkArgs, Format};
use crate::batch;
use crate::output::{matrix_text, pose_summary, print_json, tuple, CliResult};
use screwkit_service::report::{self, FkReport, FramesReport, NamedPose};

/// The JSON object of one configuration: `{"q", "pose"}` (+ `"links"`), the floor's report.
fn fk_json(kin: &Kinematics, q: &[f64], pose: &[f64], links: Option<&[f64]>) -> Value {
    let links = links.map(|l| {
        kin.links()
            .iter()
            .zip(l.chunks(16))
            .map(|(link, p)| NamedPose::from_row_major(&link.name, p))
            .collect()
    });
    report::to_value(&FkReport::new(q, pose, links))
}

/// Batch mode: streamed chunk by chunk, every chunk through the library's FK batch.
fn run_batch(kin: &Kinematics, input: &str, all_links: bool) -> CliResult {
    let n = kin.dof();
    let l = kin.links().len();
    batch::stream(input, |lines, _| {
        let (qs, mut errors) = batch::q_rows(kin, lines);
        let rows = lines.len();
        let mut poses = vec![0.0; rows * 16];
        batch::merge_row_errors(fk_batch(kin, &qs, &mut poses), &mut errors)?;
        let mut links = vec![0.0; if all_links { rows * l * 16 } else { 0 }];
        if all_links {
            batch::merge_row_errors(fk_all_links_batch(kin, &qs, &mut links), &mut errors)?;
        }
        Ok(batch::outputs(lines, &errors, |k| {
            let link_poses = all_links.then(|| &links[k * l * 16..(k + 1) * l * 16]);
            (
                fk_json(
                    kin,
                    &qs[k * n..(k + 1) * n],
                    &poses[k * 16..(k + 1) * 16],
                    link_poses,
                ),
                true,
            )
        }))
    })
}

/// The chosen frames' poses from one row of every frame's poses (F × 16).
fn pick(frames: &[usize], all: &[f64], out: &mut [f64]) {
    for (o, &f) in out.chunks_mut(16).zip(frames) {
        o.copy_from_slice(&all[16 * f..16 * (f + 1)]);
    }
}

/// `{"q", "frames": [{"name", "pose"}]}` of one configuration (`poses`: the chosen frames',
/// K × 16), the floor's report.
fn tree_json(kin: &TreeKinematics, frames: &[usize], q: &[f64], poses: &[f64]) -> Value {
    report::to_value(&FramesReport {
        q: q.to_vec(),
        frames: frames
            .iter()
            .zip(poses.chunks(16))
            .map(|(&f, p)| NamedPose::from_row_major(kin.frame_name(f), p))
            .collect(),
    })
}

/// Batch mode on the whole tree: every row through the library's all-frame batch
/// (`tree::batch::fk_frames_batch`), the chosen frames kept. JSON lines give one
/// `{"q", "frames"}` object per line; a `.npy` of shape (N, nq) gives (N, K, 4, 4) for the K
/// chosen frames.
fn run_tree_batch(
    kin: &TreeKinematics,
    frames: &[usize],
    input: &str,
    output: Option<&str>,
) -> CliResult {
    let (nq, f, k) = (kin.nq(), kin.frame_count(), frames.len());
    let mut all = Vec::new();
    if let Some(output) = crate::npy::binary(input, output)? {
        return crate::npy::run(input, output, nq, "nq", &[k, 4, 4], |qs, _, out| {
            all.clear();
            all.resize(qs.len() / nq.max(1) * f * 16, 0.0);
            let result = fk_frames_batch(kin, qs, &mut all);
            for (row, o) in all.chunks(f * 16).zip(out.chunks_mut(k * 16)) {
                pick(frames, row, o);
            }
            result
        });
    }
    batch::stream(input, |lines, _| {
        let (qs, mut errors) = batch::tree_q_rows(kin, lines);
        let mut all = vec![0.0; lines.len() * f * 16];
        batch::merge_row_errors(fk_frames_batch(kin, &qs, &mut all), &mut errors)?;
        Ok(batch::outputs(lines, &errors, |r| {
            let mut chosen = vec![0.0; k * 16];
            pick(frames, &all[r * f * 16..(r + 1) * f * 16], &mut chosen);
            (
                tree_json(kin, frames, &qs[r * nq..(r + 1) * nq], &chosen),
                true,
            )
        }))
    })
}

/// `fk` on the whole tree: the chosen frames' poses in the root link's frame (the world with
/// a floating base), q the tree's configuration.
fn run_tree(robot: &Robot, args: &FkArgs, format: Format) -> CliResult {
    let kin = robot.whole()?;
    let frames = whole::select_frames(kin, &args.frames, args.all_links)?;
    if let Some(input) = &args.at.input {
        return run_tree_batch(kin, &frames, input, args.at.output.as_deref());
    }
    let q = &args
        .at
        .q
        .as_ref()
        .expect("clap requires --q without --input")
        .0;
    let mut ws = robot.tree_workspace()?;
    let poses = screwkit_solve::tree::fk::fk_frames(kin, &mut ws, q)?;
    let chosen: Vec<(&str, &Se3)> = frames
        .iter()
        .map(|&f| (kin.frame_name(f), &poses[f]))
        .collect();
    if format == Format::Json {
        let mut flat = vec![0.0; 16 * frames.len()];
        for (o, (_, t)) in flat.chunks_mut(16).zip(&chosen) {
            t.write_row_major(o);
        }
        print_json(&tree_json(kin, &frames, q, &flat))?;
        return Ok(());
    }
    let root = kin.model().root();
    let within = if kin.floating_base() {
        format!("the world (floating base under `{root}`)")
    } else {
        format!("`{root}`")
    };
    let mut s = format!("Poses in {within} at q = {}:\n", tuple(q));
    let w = chosen.iter().map(|(n, _)| n.len()).max().unwrap_or(4);
    for (name, p) in &chosen {
        s.push_str(&format!(
            "{:<w$}  position {}  rpy {}\n",
            name,
            tuple(p.translation().as_slice()),
            tuple(&p.rpy())
        ));
    }
    crate::output::emit(&s)?;
    Ok(())
}

/// Runs `fk`.
pub fn run(args: &FkArgs, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    if whole::wants_tree(&robot, !args.frames.is_empty()) {
        return run_tree(&robot, args, format);
    }
    let (chain, kin) = robot.chain_parts()?;
    if let Some(input) = &args.at.input {
        if let Some(output) = crate::npy::binary(input, args.at.output.as_deref())? {
            let (n, l) = (kin.dof(), kin.links().len());
            return if args.all_links {
                crate::npy::run(input, output, n, "dof", &[l, 4, 4], |qs, _, out| {
                    fk_all_links_batch(kin, qs, out)
                })
            } else {
                crate::npy::run(input, output, n, "dof", &[4, 4], |qs, _, out| {
                    fk_batch(kin, qs, out)
                })
            };
        }
        return run_batch(kin, input, args.all_links);
    }
    let q = &args
        .at
        .q
        .as_ref()
        .expect("clap requires --q without --input")
        .0;
    let mut ws = Workspace::new(kin);
    let t = fk(kin, &mut ws, q)?;
    let links: Option<Vec<Se3>> = if args.all_links {
        Some(fk_all_links(kin, &mut ws, q)?.to_vec())
    } else {
        None
    };
    if format == Format::Json {
        let flat = |ts: &[Se3]| {
            let mut v = vec![0.0; 16 * ts.len()];
            for (o, t) in v.chunks_mut(16).zip(ts) {
                t.write_row_major(o);
            }
            v
        };
        let link_poses = links.as_deref().map(flat);
        print_json(&fk_json(kin, q, &flat(&[t]), link_poses.as_deref()))?;
        return Ok(());
    }
    let mut s = format!(
        "Pose of `{}` in `{}` at q = {}:\n",
        chain.tip,
        chain.base,
        tuple(q)
    );
    s.push_str(&matrix_text(&t));
    s.push_str(&pose_summary(&t));
    if let Some(poses) = links {
        let w = kin.links().iter().map(|l| l.name.len()).max().unwrap_or(4);
        s.push_str(&format!(
            "\nEvery link on the chain (in `{}`):\n",
            chain.base
        ));
        for (link, p) in kin.links().iter().zip(&poses) {
            s.push_str(&format!(
                "{:<w$}  position {}  rpy {}\n",
                link.name,
                tuple(p.translation().as_slice()),
                tuple(&p.rpy())
            ));
        }
    }
    crate::output::emit(&s)?;
    Ok(())
}
