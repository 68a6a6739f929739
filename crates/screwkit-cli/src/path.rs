//! `screwkit path`: the floor's Cartesian path ([`screwkit_service::path`]) from a
//! configuration through poses, printed, as JSON, or written as .npy; timed on request.

use std::fmt::Write;

use screwkit_service::io::npy::NpyWriter;
use screwkit_service::{path, report};
use screwkit_solve::path::{Interpolation, PathOptions};

use crate::args::{Format, PathArgs};
use crate::output::{emit, print_json, tuple, CliResult};

/// Runs `path`.
pub fn run(a: &PathArgs, format: Format) -> CliResult {
    let robot = crate::load(&a.chain)?;
    let (chain, kin) = robot.chain_parts()?;
    let mut targets = Vec::with_capacity(a.via.len() + 1);
    for (k, v) in a.via.iter().enumerate() {
        targets.push(path::pose(&v.0, &format!("--via #{}", k + 1))?);
    }
    targets.push(path::pose(&a.to.0, "--to")?);
    let options = PathOptions {
        interpolation: if a.line {
            Interpolation::Line
        } else {
            Interpolation::Screw
        },
        max_step: a.max_step,
        max_joint_step: a.max_joint_step,
        ..Default::default()
    };
    let mut ws = robot.workspace()?;
    let solvers = screwkit_service::solutions::Solvers::default();
    let p = path::cartesian_path(kin, &mut ws, &solvers, &targets, &a.start.0, &options)?;
    let limits = if a.timed {
        let v = match &a.vel {
            Some(v) => v.0.clone(),
            None => path::velocity_limits(chain)?,
        };
        let acc = a.acc.as_ref().map(|x| x.0.clone()).unwrap_or_default();
        Some((v, acc))
    } else {
        None
    };
    let r = path::report(
        kin.names(),
        &p,
        limits
            .as_ref()
            .map(|(v, acc)| (v.as_slice(), acc.as_slice(), a.dt)),
    )?;
    if let Some(out) = &a.output {
        let n = kin.dof();
        let (rows, width, values): (usize, usize, Vec<f64>) = match &r.timed {
            Some(t) => (
                t.t.len(),
                n + 1,
                t.t.iter()
                    .zip(&t.q)
                    .flat_map(|(time, q)| std::iter::once(*time).chain(q.iter().copied()))
                    .collect(),
            ),
            None => (r.q.len(), n, p.q.clone()),
        };
        let mut w = NpyWriter::create(out, &[rows, width], "<f8")?;
        w.write_f64(&values)?;
        w.finish()?;
    }
    if format == Format::Json {
        return print_json(&report::to_value(&r));
    }
    let mut text = String::new();
    let _ = writeln!(
        text,
        "Cartesian path of `{}` ({} joints, {}): {} samples, {:.1} % of the path, {}",
        chain.robot,
        kin.dof(),
        if a.line {
            "straight lines"
        } else {
            "screw motions"
        },
        r.q.len(),
        100.0 * r.fraction,
        r.stop
    );
    if r.stop != "reached" {
        let _ = writeln!(text, "{}", r.message);
    }
    let _ = writeln!(text, "first q = {}", tuple(&r.q[0]));
    let _ = writeln!(text, "last q  = {}", tuple(r.q.last().unwrap_or(&r.q[0])));
    if let Some(t) = &r.timed {
        let _ = writeln!(
            text,
            "timed: {:.4} s, {} samples every {} s",
            t.duration,
            t.t.len(),
            a.dt
        );
    }
    if let Some(out) = &a.output {
        let _ = writeln!(text, "wrote {out}");
    }
    emit(&text)
}
