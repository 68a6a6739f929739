//! `screwkit ik FILE --tasks TASKS.json`: whole-body IK — several frames, the centre of mass and
//! a posture at once on the whole tree, to convergence within the joint limits
//! ([`screwkit_solve::tree::differential_ik::ik_tasks`]); with `--input`, one answer per line
//! of task changes (independent lines on all cores, or in order with `--sequential`: a motion
//! clip retargeted frame by frame). The tasks' JSON, their defaults and the reports are the
//! floor's ([`screwkit_service::tasks`], [`screwkit_service::report::TasksReport`]).

use std::path::Path;
use std::time::Instant;

use screwkit_service::report::{self, TasksReport};
use screwkit_service::tasks::{default_seed, resolve_all, TaskList};
use screwkit_service::{Error, Source};
use screwkit_solve::tree::differential_ik::{
    ik_tasks, ik_tasks_batch, ik_trajectory, DiffIkWorkspace, Segments, TasksOptions, TasksProblem,
    TasksResult,
};
use screwkit_solve::tree::tasks::{Measures, Task};
use screwkit_solve::TreeKinematics;
use serde_json::Value;

use crate::args::{Format, IkArgs};
use crate::batch;
use crate::output::{print_json, tuple, CliResult, Failure};

/// The solver's options: the library's defaults where the command line gives none; with
/// `--avoid-collisions`, every checked pair of the body (SRDF and obstacles applied) kept
/// `--margin` apart ([`screwkit_collision::CollisionAvoidance`], its other settings mink's
/// defaults, the floor's `body::collision_avoidance`).
fn options(args: &IkArgs, robot: &screwkit_service::Robot) -> Result<TasksOptions, Error> {
    let d = TasksOptions::default();
    let mut limits = d.limits.clone();
    if args.avoid_collisions {
        let model = screwkit_service::body::robot_model(
            robot,
            args.srdf.as_deref(),
            args.obstacles.as_deref(),
        )?;
        limits.push(screwkit_service::body::collision_avoidance(
            robot,
            model,
            None,
            args.margin,
        )?);
    }
    Ok(TasksOptions {
        max_iterations: args.max_iter.unwrap_or(d.max_iterations),
        restarts: args.restarts.unwrap_or(d.restarts),
        seed: args.random_seed,
        limits,
        ..d
    })
}

/// A floor error about the tasks, naming the tasks file.
fn file_error(path: &Path, e: Error) -> Failure {
    match e {
        Error::Option { message, .. } => Failure(format!("{}: {message}", path.display())),
        e => Failure(format!("{}: {e}", path.display())),
    }
}

/// One batch line `{"tasks": [change or null, …], "seed": [nq numbers]}` (both optional): the
/// resolved tasks and the seed if given.
fn parse_line(
    kin: &TreeKinematics,
    list: &TaskList,
    text: &str,
) -> Result<(Vec<Task>, Option<Vec<f64>>), String> {
    let obj = batch::parse_object(text)?;
    if let Some(k) = obj.keys().find(|k| *k != "tasks" && *k != "seed") {
        return Err(format!(
            "unknown field \"{k}\" (a line has \"tasks\": a list of task changes, and \"seed\")"
        ));
    }
    let specs = match obj.get("tasks") {
        None => list.specs().to_vec(),
        Some(Value::Array(changes)) => list.with_changes(changes).map_err(|e| e.to_string())?,
        Some(_) => return Err("\"tasks\" must be a list of task changes (objects or null)".into()),
    };
    let tasks = resolve_all(&specs, kin).map_err(|e| e.to_string())?;
    let seed = batch::optional_seed(&obj, |q| kin.check_q(q).map(|_| ()))?;
    Ok((tasks, seed))
}

fn report_value(kin: &TreeKinematics, tasks: &[Task], r: &TasksResult, us: f64) -> Value {
    report::to_value(&TasksReport::new(kin, tasks, r, us))
}

/// Batch mode: each line's problem through the library's batch (all cores) or, `sequential`,
/// through its trajectory mode (each line seeded by the previous answer unless it gives a
/// seed), across chunks.
fn run_batch(
    kin: &TreeKinematics,
    list: &TaskList,
    input: &str,
    seed: &[f64],
    opts: &TasksOptions,
    sequential: bool,
) -> CliResult {
    let mut warm = seed.to_vec();
    batch::stream(input, |lines, first_row| {
        let parsed = batch::parse_rows(lines, |text| parse_line(kin, list, text));
        let count = lines.len();
        let mut errors: Vec<Option<String>> = vec![None; count];
        let mut results: Vec<Option<(Vec<Task>, TasksResult)>> = vec![None; count];
        let mut good = Vec::new();
        for (k, row) in parsed.into_iter().enumerate() {
            match row {
                Ok(r) => good.push((k, r)),
                Err(e) => errors[k] = Some(e),
            }
        }
        if sequential {
            // Runs of lines without a seed go through the trajectory mode from the last good
            // answer. A line with a seed is solved alone from it: when that seed is bad (not
            // finite, outside the limits), that line alone is refused and the next lines go on
            // from the last good answer.
            let mut i = 0;
            while i < good.len() {
                let seeded = good[i].1 .1.clone();
                let start = seeded.clone().unwrap_or_else(|| warm.clone());
                let mut j = i + 1;
                while seeded.is_none() && j < good.len() && good[j].1 .1.is_none() {
                    j += 1;
                }
                let sets: Vec<Vec<Task>> = good[i..j].iter().map(|(_, r)| r.0.clone()).collect();
                let answers = match ik_trajectory(kin, &sets, &start, opts, Segments::default()) {
                    Ok(a) => a,
                    Err(e) => {
                        for (k, _) in &good[i..j] {
                            errors[*k] = Some(e.to_string());
                        }
                        i = j;
                        continue;
                    }
                };
                for ((k, (tasks, _)), answer) in good[i..j].iter().zip(answers) {
                    match answer {
                        Ok(r) => {
                            warm.copy_from_slice(&r.q);
                            results[*k] = Some((tasks.clone(), r));
                        }
                        Err(e) => errors[*k] = Some(e.to_string()),
                    }
                }
                i = j;
            }
        } else {
            let problems: Vec<TasksProblem> = good
                .iter()
                .map(|(k, (tasks, s))| TasksProblem {
                    tasks: tasks.clone(),
                    seed: s.clone().unwrap_or_else(|| seed.to_vec()),
                    row: first_row + k,
                })
                .collect();
            for ((k, (tasks, _)), answer) in good.iter().zip(ik_tasks_batch(kin, &problems, opts)) {
                match answer {
                    Ok(r) => results[*k] = Some((tasks.clone(), r)),
                    Err(e) => errors[*k] = Some(e.to_string()),
                }
            }
        }
        Ok(batch::outputs(lines, &errors, |k| match &results[k] {
            Some((tasks, r)) => (report_value(kin, tasks, r, 0.0), r.converged),
            None => (Value::Null, false),
        }))
    })
    .map_err(|e| Failure(format!("{} (failed or did not converge)", e.0)))
}

/// Runs `ik --tasks FILE`.
pub fn run(args: &IkArgs, path: &Path, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    let kin = robot.whole()?;
    let source = Source::from_arg(path);
    if source.is_stdin() && args.input.as_deref() == Some("-") {
        return Err(Failure(
            "--tasks - and --input - cannot both read standard input".into(),
        ));
    }
    let text = source.read().map_err(|e| file_error(path, e))?;
    let list = TaskList::parse(&text).map_err(|e| file_error(path, e))?;
    let opts = options(args, &robot)?;
    let seed = match &args.seed {
        Some(s) => {
            kin.check_q(&s.0)
                .map_err(|e| Failure(format!("--seed: {e}")))?;
            s.0.clone()
        }
        None => default_seed(kin),
    };
    if let Some(input) = &args.input {
        return run_batch(kin, &list, input, &seed, &opts, args.sequential);
    }
    let tasks = resolve_all(list.specs(), kin).map_err(|e| file_error(path, e))?;
    let mut ws = DiffIkWorkspace::new(kin);
    let t0 = Instant::now();
    // The tasks' values are checked by the solver: its refusals name the file too.
    let r = ik_tasks(kin, &mut ws, &tasks, &seed, &opts).map_err(|e| {
        if e.is_invalid_input() {
            Failure(format!("{}: {e}", path.display()))
        } else {
            e.into()
        }
    })?;
    let us = t0.elapsed().as_secs_f64() * 1e6;
    if format == Format::Json {
        print_json(&report_value(kin, &tasks, &r, us))?;
    } else {
        let mut s = format!(
            "converged          {}\nstopped because    {}\niterations         {} ({:.1} µs)\nq                  {}\nvariables          {}\n",
            if r.converged { "yes" } else { "NO" },
            r.stop.word(),
            r.iterations,
            us,
            tuple(&r.q),
            kin.q_names().join(", "),
        );
        for (i, (t, e)) in tasks.iter().zip(&r.task_errors).enumerate() {
            let error = match t.kind.measures() {
                Measures::Nothing => String::new(),
                Measures::Configuration => format!(": |q - q_ref| {:.3e}", e.position),
                Measures::Position => format!(": position {:.3e} m", e.position),
                Measures::PositionAndRotation => format!(
                    ": position {:.3e} m, rotation {:.3e} rad",
                    e.position, e.rotation
                ),
            };
            s.push_str(&format!(
                "task {i:<13} {}{error}{}\n",
                t.describe(kin),
                if e.converged { "" } else { "  (not met)" }
            ));
        }
        crate::output::emit(&s)?;
    }
    if r.converged {
        Ok(())
    } else {
        let unmet: Vec<String> = tasks
            .iter()
            .zip(&r.task_errors)
            .filter(|(_, e)| !e.converged)
            .map(|(t, e)| {
                format!(
                    "{} (position {:.3e} m, rotation {:.3e} rad)",
                    t.describe(kin),
                    e.position,
                    e.rotation
                )
            })
            .collect();
        Err(Failure(format!(
            "whole-body IK did not converge ({}): {}",
            r.stop.word(),
            unmet.join(", ")
        )))
    }
}
