//! `screwkit path`: the floor's Cartesian path ([`screwkit_service::path`]) from a
//! configuration through poses, printed, as JSON, or written as .npy; timed on request; many
//! paths from JSON lines (`--input`) on all cores.

use std::fmt::Write;

use screwkit_service::io::npy::NpyWriter;
use screwkit_service::{body, path, report};
use screwkit_solve::path::{Interpolation, PathOptions};
use screwkit_solve::Workspace;

use crate::args::{Format, PathArgs};
use crate::batch;
use crate::output::{emit, print_json, tuple, CliResult, Failure};

/// Runs `path`.
pub fn run(a: &PathArgs, format: Format) -> CliResult {
    let robot = crate::load(&a.chain)?;
    let (chain, kin) = robot.chain_parts()?;
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
    let solvers = screwkit_service::solutions::Solvers::default();
    let analytic = path::path_solver(kin, &solvers, a.lock.as_ref())?;
    let model = a.avoid.model(&robot)?;
    let clear = match &model {
        Some(m) => Some(body::chain_clearance(
            &robot,
            robot.whole()?,
            m,
            a.avoid.margin,
        )?),
        None => None,
    };
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
    let timing = limits
        .as_ref()
        .map(|(v, acc)| (v.as_slice(), acc.as_slice(), a.dt));
    if let Some(input) = &a.input {
        return batch::stream(input, |lines, _| {
            let rows = batch::parse_rows(lines, |text| {
                let obj = batch::parse_object(text)?;
                let start = batch::numbers(&obj, "from")?;
                let mut targets = Vec::new();
                if let Some(via) = obj.get("via") {
                    let Some(list) = via.as_array() else {
                        return Err("\"via\": expected an array of poses".into());
                    };
                    for (k, v) in list.iter().enumerate() {
                        let values: Vec<f64> = serde_json::from_value(v.clone())
                            .map_err(|_| format!("\"via\"[{k}]: expected an array of numbers"))?;
                        targets.push(
                            path::pose(&values, &format!("\"via\"[{k}]"))
                                .map_err(|e| e.to_string())?,
                        );
                    }
                }
                let to = batch::numbers(&obj, "to")?;
                targets.push(path::pose(&to, "\"to\"").map_err(|e| e.to_string())?);
                Ok((start, targets))
            });
            let errors: Vec<Option<String>> =
                rows.iter().map(|r| r.as_ref().err().cloned()).collect();
            Ok(batch::outputs(lines, &errors, |k| {
                let Ok((start, targets)) = &rows[k] else {
                    unreachable!("a row with an error is reported by `outputs`")
                };
                let mut ws = Workspace::new(kin);
                let r = path::cartesian_path(
                    kin,
                    &mut ws,
                    analytic.as_deref(),
                    targets,
                    start,
                    &options,
                    clear.as_ref(),
                )
                .and_then(|p| path::report(kin.names(), &p, timing));
                match r {
                    Ok(r) => (report::to_value(&r), true),
                    Err(e) => (
                        serde_json::json!({"error": e.to_string(), "line": lines[k].number}),
                        false,
                    ),
                }
            }))
        });
    }
    let targets = match &a.waypoints {
        Some(file) => path::read_waypoints(file)?,
        None => {
            let mut targets = Vec::with_capacity(a.via.len() + 1);
            for (k, v) in a.via.iter().enumerate() {
                targets.push(path::pose(&v.0, &format!("--via #{}", k + 1))?);
            }
            let to =
                a.to.as_ref()
                    .expect("clap requires --to without --input or --waypoints");
            targets.push(path::pose(&to.0, "--to")?);
            targets
        }
    };
    let start = a
        .start
        .as_ref()
        .expect("clap requires --from without --input");
    let mut ws = robot.workspace()?;
    let p = path::cartesian_path(
        kin,
        &mut ws,
        analytic.as_deref(),
        &targets,
        &start.0,
        &options,
        clear.as_ref(),
    )?;
    let r = path::report(kin.names(), &p, timing)?;
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
    if let Some(file) = &a.plot {
        let (x, q, label): (Vec<f64>, Vec<f64>, &str) = match &r.timed {
            Some(t) => (t.t.clone(), t.q.concat(), screwkit_draw::plot::TIME_LABEL),
            None => (
                p.place.clone(),
                p.q.clone(),
                screwkit_draw::plot::PLACE_LABEL,
            ),
        };
        let svg = screwkit_draw::plot::joints(&screwkit_draw::plot::JointPlot {
            title: &screwkit_draw::plot::title(&chain.robot),
            names: kin.names(),
            x: &x,
            x_label: label,
            q: &q,
            limits: Some((kin.lower(), kin.upper())),
        })
        .map_err(Failure)?;
        crate::draw::write_out(file, &svg)?;
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
    if let Some(file) = &a.plot {
        let _ = writeln!(text, "wrote {file}");
    }
    emit(&text)
}
