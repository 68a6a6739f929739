//! `screwkit fk`: tip pose or every link's pose.

use screwkit_solve::fk::{fk, fk_all_links};
use screwkit_solve::{Kinematics, Workspace};
use serde_json::{json, Value};

use crate::args::{FkArgs, Format};
use crate::batch;
use crate::output::{
    matrix_text, nums, pose_json, pose_summary, print_json, tuple, CliResult, Failure,
};

fn fk_value(
    kin: &Kinematics,
    ws: &mut Workspace,
    q: &[f64],
    all_links: bool,
) -> Result<Value, String> {
    let t = fk(kin, q).map_err(|e| e.to_string())?;
    let mut v = json!({"q": nums(q), "pose": pose_json(&t)});
    if all_links {
        let poses = fk_all_links(kin, ws, q).map_err(|e| e.to_string())?;
        v["links"] = Value::Array(
            kin.link_names()
                .zip(poses)
                .map(|(name, p)| json!({"name": name, "pose": pose_json(p)}))
                .collect(),
        );
    }
    Ok(v)
}

/// Runs `fk`.
pub fn run(args: &FkArgs, format: Format) -> CliResult {
    let (chain, kin) = crate::load(&args.chain)?;
    if let Some(input) = &args.input {
        return batch::run_q_lines(&kin, input, |ws, q| fk_value(&kin, ws, q, args.all_links));
    }
    let q = &args
        .q
        .as_ref()
        .expect("clap requires --q without --input")
        .0;
    let mut ws = Workspace::new(&kin);
    let v = fk_value(&kin, &mut ws, q, args.all_links).map_err(Failure)?;
    if format == Format::Json {
        print_json(&v);
        return Ok(());
    }
    let t = fk(&kin, q)?;
    let mut s = format!(
        "Pose of `{}` in `{}` at q = {}:\n",
        chain.tip,
        chain.base,
        tuple(q)
    );
    s.push_str(&matrix_text(&t));
    s.push_str(&pose_summary(&t));
    if args.all_links {
        let poses = fk_all_links(&kin, &mut ws, q)?;
        let w = kin.link_names().map(str::len).max().unwrap_or(4);
        s.push_str(&format!(
            "\nEvery link on the chain (in `{}`):\n",
            chain.base
        ));
        for (name, p) in kin.link_names().zip(poses) {
            s.push_str(&format!(
                "{name:<w$}  position {}  rpy {}\n",
                tuple(p.translation().as_slice()),
                tuple(&p.rpy())
            ));
        }
    }
    print!("{s}");
    Ok(())
}
