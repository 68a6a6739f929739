//! `screwkit ik`: joint values reaching a target pose.

use std::time::Instant;

use screwkit_collision::ChainClearance;
use screwkit_lie::Se3;
use screwkit_service::report::{self, IkReport};
use screwkit_service::words::Collisions;
use screwkit_service::{body, target as targets, AllSolutions, Robot};
use screwkit_solve::batch::{ik_batch_clear_from, ik_batch_from, ik_path_clear_from, ik_path_from};
use screwkit_solve::ik::{solve, solve_clear, Clearance, IkOptions, IkResult, IkStatus};
use screwkit_solve::{Kinematics, Workspace};
use serde_json::Value;

use crate::args::{Format, IkArgs};
use crate::batch;
use crate::output::{matrix_text, print_json, tuple, CliResult, Failure};

fn target(args: &IkArgs) -> CliResult<Se3> {
    let given = [
        &args.target_xyz_quat,
        &args.target_xyz_rpy,
        &args.target_matrix,
    ]
    .iter()
    .filter(|t| t.is_some())
    .count();
    if given != 1 {
        return Err(Failure(
            "give exactly one target: --target-xyz-quat, --target-xyz-rpy or --target-matrix"
                .into(),
        ));
    }
    if let Some(l) = &args.target_xyz_quat {
        return Ok(targets::from_xyz_quat(&l.0)?);
    }
    if let Some(l) = &args.target_xyz_rpy {
        return Ok(targets::from_xyz_rpy(&l.0)?);
    }
    let l = args.target_matrix.as_ref().expect("counted above");
    if l.0.len() != 16 {
        return Err(Failure(format!(
            "--target-matrix needs 16 numbers, got {}",
            l.0.len()
        )));
    }
    Ok(targets::from_row_major(&l.0)?)
}

fn result_json(q: &[f64], r: &IkStatus, time_us: f64) -> Value {
    report::to_value(&IkReport::new(q, r, time_us))
}

/// One batch line `{"target": [[4x4]], "seed": [n] (optional)}`: the target as 16 row-major
/// values (read once by the floor's [`targets::from_row_major`]: typed matrices accepted and
/// re-orthonormalised) and the seed if given.
fn parse_line(kin: &Kinematics, text: &str) -> Result<(Vec<f64>, Option<Vec<f64>>), String> {
    let obj = batch::parse_object(text)?;
    let rows = obj
        .get("target")
        .and_then(Value::as_array)
        .ok_or("missing \"target\" (4 rows of 4 numbers)")?;
    let mut m = Vec::with_capacity(16);
    for row in rows {
        for x in row
            .as_array()
            .ok_or("\"target\" must be 4 rows of 4 numbers")?
        {
            m.push(x.as_f64().ok_or("\"target\" entries must be numbers")?);
        }
    }
    if rows.len() != 4 || m.len() != 16 {
        return Err("\"target\" must be 4 rows of 4 numbers".into());
    }
    let t = targets::from_row_major(&m).map_err(|e| format!("target: {e}"))?;
    let target = targets::row_major(&t).to_vec();
    let seed = batch::optional_seed(&obj, |q| kin.check_q(q).map(|_| ()))?;
    Ok((target, seed))
}

/// Batch mode: every row through the library's IK batch.
fn run_batch(
    kin: &Kinematics,
    input: &str,
    opts: &IkOptions,
    sequential: bool,
    clear: Option<&ChainClearance<'_>>,
) -> CliResult {
    let n = kin.dof();
    let mut scratch = clear.map(|c| c.scratch());
    let mid = kin.midpoint();
    // Trajectory mode: the last converged answer seeds the next line, across chunks.
    let mut warm: Option<Vec<f64>> = None;
    let mut ws = Workspace::new(kin);
    batch::stream(input, |lines, first_row| {
        let parsed = batch::parse_rows(lines, |text| parse_line(kin, text));
        let count = lines.len();
        let mut errors: Vec<Option<String>> = vec![None; count];
        let mut q = vec![f64::NAN; count * n];
        let mut status = vec![IkStatus::default(); count];
        let mut times = vec![0.0; count];
        if sequential {
            for (k, row) in parsed.into_iter().enumerate() {
                let (target, seed) = match row {
                    Ok(r) => r,
                    Err(e) => {
                        errors[k] = Some(e);
                        continue;
                    }
                };
                let t = targets::from_row_major(&target)?;
                let start = seed.or_else(|| warm.clone()).unwrap_or_else(|| mid.clone());
                let t0 = Instant::now();
                let r = match (clear, scratch.as_mut()) {
                    (Some(c), Some(s)) => {
                        ik_path_clear_from(kin, &mut ws, first_row + k, &[t], &start, opts, c, s)?
                    }
                    _ => ik_path_from(kin, &mut ws, first_row + k, &[t], &start, opts)?,
                };
                times[k] = t0.elapsed().as_secs_f64() * 1e6;
                let r = &r[0];
                if r.status.converged {
                    warm = Some(r.q.clone());
                }
                q[k * n..(k + 1) * n].copy_from_slice(&r.q);
                status[k] = r.status;
            }
        } else {
            let parsed: Vec<Result<Vec<f64>, String>> = parsed
                .into_iter()
                .map(|r| {
                    r.map(|(t, s)| {
                        let mut row = t;
                        row.extend(s.unwrap_or_else(|| mid.clone()));
                        row
                    })
                })
                .collect();
            let (rows, parse_errors) = batch::flatten(parsed, 16 + n);
            errors = parse_errors;
            let mut targets = Vec::with_capacity(count * 16);
            let mut seeds = Vec::with_capacity(count * n);
            for row in rows.chunks(16 + n) {
                targets.extend_from_slice(&row[..16]);
                seeds.extend_from_slice(&row[16..]);
            }
            let result = solve_rows(
                kin,
                first_row,
                &targets,
                Some(&seeds),
                opts,
                clear,
                &mut q,
                &mut status,
                Some(&mut times),
            );
            batch::merge_row_errors(result, &mut errors)?;
        }
        Ok(batch::outputs(lines, &errors, |k| {
            let st = &status[k];
            (
                result_json(&q[k * n..(k + 1) * n], st, times[k]),
                st.converged,
            )
        }))
    })
    .map_err(|e| Failure(format!("{} (failed or did not converge)", e.0)))
}

/// Binary batch: N × 4 × 4 targets from a .npy, solutions (N × dof) and status (N × 4:
/// converged, iterations, rotation error, position error) to two .npy files, streamed.
fn run_npy(
    kin: &Kinematics,
    input: &str,
    output: &str,
    opts: &IkOptions,
    clear: Option<&ChainClearance<'_>>,
) -> CliResult {
    let started = Instant::now();
    let status_path = crate::npy::status_path(output);
    let outputs = [output, status_path.as_str()];
    let outputs = if status_path == output {
        &outputs[..1]
    } else {
        &outputs[..]
    };
    screwkit_service::io::atomic::check_distinct(&[input], outputs).map_err(Failure)?;
    let mut r = crate::npy::NpyReader::open(input)?;
    if r.row_len != 16 || r.shape.len() < 2 {
        return Err(Failure(format!(
            "{input}: shape {:?}: expected (N, 4, 4) targets",
            r.shape
        )));
    }
    let (rows_total, n) = (r.shape[0], kin.dof());
    let mut wq = crate::npy::NpyWriter::create(output, &[rows_total, n], "<f8")?;
    let mut ws = crate::npy::NpyWriter::create(&status_path, &[rows_total, 4], "<f8")?;
    let (mut buf, mut first, mut failed) = (Vec::new(), 0usize, 0usize);
    while r.remaining > 0 {
        let rows = r.read_rows(crate::npy::NPY_CHUNK / 8, &mut buf)?;
        let mut q = vec![0.0; rows * n];
        let mut status = vec![IkStatus::default(); rows];
        match solve_rows(
            kin,
            first,
            &buf,
            None,
            opts,
            clear,
            &mut q,
            &mut status,
            None,
        ) {
            Ok(()) | Err(screwkit_solve::SolveError::Rows(_)) => {}
            Err(e) => return Err(Failure(e.to_string())),
        }
        failed += status.iter().filter(|s| !s.converged).count();
        let st: Vec<f64> = status
            .iter()
            .flat_map(|s| {
                [
                    f64::from(u8::from(s.converged)),
                    s.iterations as f64,
                    s.error_rot,
                    s.error_pos,
                ]
            })
            .collect();
        wq.write_f64(&q)?;
        ws.write_f64(&st)?;
        first += rows;
    }
    wq.finish()?;
    ws.finish()?;
    crate::npy::summary(rows_total, failed, started)
        .map_err(|e| Failure(format!("{} (failed or did not converge)", e.0)))
}

/// A batch of numerical IK rows: the library's batch, keeping clear of contact with `clear`.
#[allow(clippy::too_many_arguments)]
fn solve_rows(
    kin: &Kinematics,
    first_row: usize,
    targets: &[f64],
    seeds: Option<&[f64]>,
    opts: &IkOptions,
    clear: Option<&ChainClearance<'_>>,
    q: &mut [f64],
    status: &mut [IkStatus],
    times_us: Option<&mut [f64]>,
) -> Result<(), screwkit_solve::SolveError> {
    match clear {
        Some(c) => {
            ik_batch_clear_from(kin, first_row, targets, seeds, opts, c, q, status, times_us)
        }
        None => ik_batch_from(kin, first_row, targets, seeds, opts, q, status, times_us),
    }
}

/// The body for `--avoid-collisions` (SRDF and obstacles applied), or None.
fn clearance_model(
    robot: &Robot,
    args: &IkArgs,
) -> Result<Option<screwkit_collision::CollisionModel>, screwkit_service::Error> {
    if !args.avoid_collisions {
        return Ok(None);
    }
    body::robot_model(robot, args.srdf.as_deref(), args.obstacles.as_deref()).map(Some)
}

/// The family in words for people: the JSON word, and whether the chain is read tip to base.
fn family_text(all: &AllSolutions) -> String {
    let s = all.solver();
    let mut w = s.family().word().to_string();
    if s.reversed() {
        w.push_str(" (reversed)");
    }
    w
}

/// The body's model for `--collisions flag|filter` (the SRDF and obstacles applied), or None.
fn solution_model(
    robot: &Robot,
    args: &IkArgs,
) -> Result<Option<screwkit_collision::CollisionModel>, screwkit_service::Error> {
    if args.collisions == Collisions::Ignore {
        return Ok(None);
    }
    body::robot_model(robot, args.srdf.as_deref(), args.obstacles.as_deref()).map(Some)
}

/// The verdict on solutions that `model` gives (None: the body is not asked).
fn solution_body<'a>(
    robot: &'a Robot,
    args: &IkArgs,
    model: Option<&'a screwkit_collision::CollisionModel>,
) -> Result<Option<body::SolutionBody<'a>>, screwkit_service::Error> {
    Ok(match model {
        Some(model) => Some(body::SolutionBody {
            robot,
            kin: robot.whole()?,
            model,
            mode: args.collisions,
        }),
        None => None,
    })
}

/// `ik --all`: every analytic solution, nearest to `seed` first (with `body`: flagged or
/// filtered by collision).
fn all_solutions(
    kin: &Kinematics,
    args: &IkArgs,
    t: &Se3,
    seed: &[f64],
    format: Format,
    body: Option<&body::SolutionBody<'_>>,
) -> CliResult {
    kin.check_q(seed)?;
    let all = AllSolutions::new(kin, args.lock.as_ref(), args.sweep)?
        .with_representatives(args.representatives);
    let mut ws = Workspace::new(kin);
    let (mut sols, values) = all.solve(kin, &mut ws, t, seed)?;
    let flags = match body {
        Some(b) => b.apply(&mut sols)?,
        None => None,
    };
    if format == Format::Json {
        print_json(&report::to_value(&all.report(
            kin,
            &sols,
            &values,
            flags.as_deref(),
        )))?;
    } else {
        let family = all.solver().family();
        let mut s = format!(
            "{} ({}): {} solution(s) within the limits, {} posture(s){}{}{}, nearest to the seed first:\n",
            family_text(&all),
            family.describe(),
            sols.len(),
            sols.branches,
            match all.solver().locked_joint() {
                None if all.solver().by_arm_angle() && values.len() == 1 => format!("; at arm angle {}", values[0]),
                None if all.solver().by_arm_angle() => format!("; at {} arm angles from {} to {}", values.len(),
                    values.first().copied().unwrap_or(0.0), values.last().copied().unwrap_or(0.0)),
                Some(j) if values.len() == 1 => format!("; {} locked at {}", kin.names()[j], values[0]),
                Some(j) => format!("; {} locked at {} values from {} to {}", kin.names()[j], values.len(),
                    values.first().copied().unwrap_or(0.0), values.last().copied().unwrap_or(0.0)),
                None => String::new(),
            },
            if sols.is_exact() || sols.is_empty() { "" } else { "; OUT OF REACH: least-squares configurations" },
            if sols.singular { "; singular: a free angle was chosen" } else { "" },
        );
        for (i, q) in sols.iter().enumerate() {
            s.push_str(&format!(
                "{}  residual {:.1e}{}\n",
                tuple(q),
                sols.residual(i),
                match flags.as_ref().map(|f| f[i]) {
                    Some(true) => "  COLLIDES",
                    Some(false) => "  collision-free",
                    None => "",
                }
            ));
        }
        crate::output::emit(&s)?;
    }
    if sols.is_exact() {
        Ok(())
    } else {
        Err(Failure("no exact solution within the joint limits".into()))
    }
}

/// `ik --all --input FILE`: one JSON line of solutions per target line, each chunk through the
/// floor's batch (the library's, on all cores; each line's seed, or --seed, orders the
/// solutions and gives the lock value).
fn all_batch(
    kin: &Kinematics,
    args: &IkArgs,
    input: &str,
    seed: &[f64],
    body: Option<&body::SolutionBody<'_>>,
) -> CliResult {
    kin.check_q(seed)?;
    let all = AllSolutions::new(kin, args.lock.as_ref(), args.sweep)?
        .with_representatives(args.representatives);
    let n = kin.dof();
    batch::stream(input, |lines, _first_row| {
        let parsed = batch::parse_rows(lines, |text| parse_line(kin, text));
        let mut errors: Vec<Option<String>> = vec![None; lines.len()];
        // Good rows only, in order; `at[k]`: the batch row of line k.
        let (mut targets, mut seeds, mut at) = (Vec::new(), Vec::new(), Vec::new());
        for (k, row) in parsed.into_iter().enumerate() {
            match row {
                Ok((t, s)) => {
                    at.push(Some(targets.len() / 16));
                    targets.extend_from_slice(&t);
                    seeds.extend_from_slice(s.as_deref().unwrap_or(seed));
                }
                Err(e) => {
                    errors[k] = Some(e);
                    at.push(None);
                }
            }
        }
        let results = all.solve_batch(
            kin,
            &targets,
            if targets.len() == 16 {
                &seeds[..n]
            } else {
                &seeds
            },
        )?;
        let mut values: Vec<Option<(Value, bool)>> = vec![None; lines.len()];
        for (k, row) in at.iter().enumerate() {
            if let Some(r) = row {
                match &results[*r] {
                    Ok((sols, v)) => {
                        let mut sols = sols.clone();
                        let flags = match body {
                            Some(b) => b.apply(&mut sols)?,
                            None => None,
                        };
                        let report = all.report(kin, &sols, v, flags.as_deref());
                        values[k] = Some((report::to_value(&report), sols.is_exact()))
                    }
                    Err(e) => errors[k] = Some(e.to_string()),
                }
            }
        }
        Ok(batch::outputs(lines, &errors, |k| {
            values[k].clone().unwrap_or((Value::Null, false))
        }))
    })
    .map_err(|e| Failure(format!("{} (failed or no exact solution)", e.0)))
}

/// Runs `ik`.
pub fn run(args: &IkArgs, format: Format) -> CliResult {
    if (args.srdf.is_some() || args.obstacles.is_some())
        && !args.avoid_collisions
        && args.collisions == Collisions::Ignore
    {
        return Err(Failure(
            "--srdf and --obstacles apply with --avoid-collisions, or --all with --collisions flag|filter"
                .into(),
        ));
    }
    if let Some(path) = &args.tasks {
        return crate::whole_body::run(args, path, format);
    }
    let robot = crate::load(&args.chain)?;
    let (chain, kin) = robot.chain_parts()?;
    let opts = args.settings().options()?;
    let tree_model = clearance_model(&robot, args)?;
    let clear = match &tree_model {
        Some(m) => Some(body::chain_clearance(
            &robot,
            robot.whole()?,
            m,
            args.margin,
        )?),
        None => None,
    };
    let clear = clear.as_ref();
    // A target given in another frame of the tree: T_base,target = T_base,frame T_frame,target.
    let frame = match &args.target_frame {
        Some(link) => Some(robot.frame_pose(link)?),
        None => None,
    };
    if let Some(input) = &args.input {
        if frame.is_some() {
            return Err(Failure(
                "--target-frame applies to a single target (give batch targets in the base frame)"
                    .into(),
            ));
        }
        if args.all {
            let seed = match &args.seed {
                Some(s) => s.0.clone(),
                None => kin.midpoint(),
            };
            let model = solution_model(&robot, args)?;
            let body = solution_body(&robot, args, model.as_ref())?;
            return all_batch(kin, args, input, &seed, body.as_ref());
        }
        if let Some(output) = crate::npy::binary(input, args.output.as_deref())? {
            if args.sequential {
                return Err(Failure("--sequential is for JSON lines input".into()));
            }
            return run_npy(kin, input, output, &opts, clear);
        }
        return run_batch(kin, input, &opts, args.sequential, clear);
    }
    let t = target(args)?;
    let t = match &frame {
        Some(f) => f.compose(&t),
        None => t,
    };
    let seed = match &args.seed {
        Some(s) => s.0.clone(),
        None => kin.midpoint(),
    };
    if args.all {
        let model = solution_model(&robot, args)?;
        let body = solution_body(&robot, args, model.as_ref())?;
        return all_solutions(kin, args, &t, &seed, format, body.as_ref());
    }
    let mut ws = Workspace::new(kin);
    let t0 = Instant::now();
    let r: IkResult = match clear {
        Some(c) => solve_clear(kin, &mut ws, &t, &seed, &opts, c, &mut c.scratch())?,
        None => solve(kin, &mut ws, &t, &seed, &opts)?,
    };
    let us = t0.elapsed().as_secs_f64() * 1e6;
    let st = &r.status;
    if format == Format::Json {
        print_json(&result_json(&r.q, st, us))?;
    } else {
        let mut s = format!(
            "Target pose of `{}` in `{}`:\n{}",
            chain.tip,
            chain.base,
            matrix_text(&t)
        );
        s.push_str(&format!(
            "\nconverged          {}\nq                  {}\njoints             {}\niterations         {} ({} restarts, {:.1} µs)\nrotation error     {:.3e} rad\nposition error     {:.3e} m\nstopped because    {}\n",
            if st.converged { "yes" } else { "NO" },
            tuple(&r.q),
            kin.names().join(", "),
            st.iterations,
            st.restarts,
            us,
            st.error_rot,
            st.error_pos,
            st.stop.as_str()
        ));
        crate::output::emit(&s)?;
    }
    if st.converged {
        Ok(())
    } else {
        // A chain with fewer than 6 joints reaches a full pose only by luck: say what to do.
        let hint = if kin.dof() < 6 && !args.position_only && args.weights.is_none() {
            format!(
                "; a {}-joint chain cannot reach most full poses: try --position-only, or --weights to mask what it cannot do",
                kin.dof()
            )
        } else {
            String::new()
        };
        Err(Failure(format!(
            "IK did not converge ({}): best rotation error {:.3e} rad, position error {:.3e} m{hint}",
            st.stop.as_str(),
            st.error_rot,
            st.error_pos
        )))
    }
}
