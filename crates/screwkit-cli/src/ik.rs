//! `screwkit ik`: joint values reaching a target pose.

use std::time::Instant;

use screwkit_lie::Se3;
use screwkit_solve::analytic::{AnalyticIk, Solutions};
use screwkit_solve::batch::{ik_batch_from, ik_path_from};
use screwkit_solve::ik::{solve, IkMethod, IkOptions, IkStatus};
use screwkit_solve::{Kinematics, Workspace};
use serde_json::{json, Value};

use crate::args::{Format, IkArgs, Method};
use crate::batch;
use crate::output::{matrix_text, num, nums, print_json, tuple, CliResult, Failure};

/// Tolerance on max |RᵀR − I| for typed target matrices (then re-orthonormalised).
use screwkit_lie::so3::TARGET_ROTATION_TOLERANCE as TYPED_ROTATION_TOLERANCE;

fn options(args: &IkArgs) -> CliResult<IkOptions> {
    let weights = match &args.weights {
        None => [1.0; 6],
        Some(w) => w.0.as_slice().try_into().map_err(|_| {
            Failure(format!(
                "--weights needs 6 numbers (ω1, ω2, ω3, v1, v2, v3; 0 masks one out), got {}",
                w.0.len()
            ))
        })?,
    };
    Ok(IkOptions {
        method: match args.method {
            Method::Nr => IkMethod::NewtonRaphson,
            Method::Dls => IkMethod::DLS,
            Method::Lm => IkMethod::LM,
        },
        tol_rot: args.tol_rot,
        tol_pos: args.tol_pos,
        max_iterations: args.max_iter,
        max_restarts: args.restarts,
        timeout: screwkit_solve::ik::timeout_from_ms(args.timeout_ms)
            .map_err(|e| Failure(format!("--timeout-ms: {e}")))?,
        seed: args.random_seed,
        position_only: args.position_only,
        weights,
        ..IkOptions::default()
    })
}

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
    let need = |v: &[f64], n: usize, what: &str| {
        if v.len() == n {
            Ok(())
        } else {
            Err(Failure(format!(
                "{what} needs {n} numbers, got {}",
                v.len()
            )))
        }
    };
    if let Some(l) = &args.target_xyz_quat {
        need(&l.0, 7, "--target-xyz-quat")?;
        return Ok(Se3::from_translation_quaternion(
            [l.0[0], l.0[1], l.0[2]],
            [l.0[3], l.0[4], l.0[5], l.0[6]],
        )?);
    }
    if let Some(l) = &args.target_xyz_rpy {
        need(&l.0, 6, "--target-xyz-rpy")?;
        return Ok(Se3::from_xyz_rpy(
            [l.0[0], l.0[1], l.0[2]],
            [l.0[3], l.0[4], l.0[5]],
        )?);
    }
    let l = args.target_matrix.as_ref().expect("counted above");
    need(&l.0, 16, "--target-matrix")?;
    Ok(Se3::from_row_major(&l.0, TYPED_ROTATION_TOLERANCE)?)
}

fn result_json(q: &[f64], r: &IkStatus, time_us: f64) -> Value {
    json!({
        "converged": r.converged,
        "q": nums(q),
        "iterations": r.iterations,
        "restarts": r.restarts,
        "error_rot": num(r.error_rot),
        "error_pos": num(r.error_pos),
        "time_us": num(time_us),
        "stop": r.stop.as_str(),
    })
}

/// One batch line `{"target": [[4x4]], "seed": [n] (optional)}`: the target as 16 row-major
/// values (typed matrices are accepted to [`TYPED_ROTATION_TOLERANCE`] and re-orthonormalised)
/// and the seed if given.
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
    let t =
        Se3::from_row_major(&m, TYPED_ROTATION_TOLERANCE).map_err(|e| format!("target: {e}"))?;
    let h = t.to_homogeneous();
    let target = (0..16).map(|i| h[(i / 4, i % 4)]).collect();
    let seed = if obj.contains_key("seed") {
        let s = batch::numbers(&obj, "seed")?;
        kin.check_q(&s).map_err(|e| format!("seed: {e}"))?;
        Some(s)
    } else {
        None
    };
    Ok((target, seed))
}

/// Batch mode: every row through the library's IK batch.
fn run_batch(kin: &Kinematics, input: &str, opts: &IkOptions, sequential: bool) -> CliResult {
    let n = kin.dof();
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
                let t = Se3::from_row_major(&target, 1e-12).map_err(|e| Failure(e.to_string()))?;
                let start = seed.or_else(|| warm.clone()).unwrap_or_else(|| mid.clone());
                let t0 = Instant::now();
                let r = ik_path_from(kin, &mut ws, first_row + k, &[t], &start, opts)?;
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
            let result = ik_batch_from(
                kin,
                first_row,
                &targets,
                Some(&seeds),
                opts,
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
fn run_npy(kin: &Kinematics, input: &str, output: &str, opts: &IkOptions) -> CliResult {
    let started = Instant::now();
    let status_path = crate::npy::status_path(output);
    let outputs = [output, status_path.as_str()];
    let outputs = if status_path == output {
        &outputs[..1]
    } else {
        &outputs[..]
    };
    screwkit_reach::atomic::check_distinct(&[input], outputs).map_err(Failure)?;
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
        match ik_batch_from(kin, first, &buf, None, opts, &mut q, &mut status, None) {
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

/// The analytic solver of `ik --all` with the lock options (--lock J=V, --sweep N; neither:
/// the seed's value of the locked joint, per target).
struct AllSolver {
    solver: AnalyticIk,
    family: String,
    value: Option<f64>,
    sweep: Option<usize>,
}

impl AllSolver {
    fn new(kin: &Kinematics, args: &IkArgs) -> CliResult<Self> {
        let (joint, value) = match &args.lock {
            None => (None, None),
            Some(spec) => {
                let (name, value) = match spec.split_once('=') {
                    Some((n, v)) => (
                        n,
                        Some(v.trim().parse::<f64>().map_err(|_| {
                            Failure(format!("--lock {spec}: {v:?} is not a number"))
                        })?),
                    ),
                    None => (spec.as_str(), None),
                };
                let names = kin.names();
                let j = names
                    .iter()
                    .position(|n| n == name)
                    .or_else(|| {
                        name.parse::<usize>()
                            .ok()
                            .filter(|&i| i >= 1 && i <= names.len())
                            .map(|i| i - 1)
                    })
                    .ok_or_else(|| {
                        Failure(format!(
                            "--lock {spec}: no joint {name:?} (the chain's: {})",
                            names.join(", ")
                        ))
                    })?;
                (Some(j), value)
            }
        };
        let solver = match joint {
            Some(j) => AnalyticIk::locked(kin, j)?,
            None => AnalyticIk::auto(kin)?,
        };
        let mut family = format!("{:?}", solver.family());
        if solver.reversed() {
            family.push_str(" (reversed)");
        }
        // Checked once here (with the midpoint as a stand-in seed) so a bad --lock/--sweep
        // fails before any target.
        solver.lock_values(kin, &kin.midpoint(), value, args.sweep)?;
        Ok(Self {
            solver,
            family,
            value,
            sweep: args.sweep,
        })
    }

    /// Every solution of `t`, nearest to `seed` first, and the lock values used.
    fn solve(
        &self,
        kin: &Kinematics,
        ws: &mut Workspace,
        t: &Se3,
        seed: &[f64],
    ) -> Result<(Solutions, Vec<f64>), screwkit_solve::SolveError> {
        let values = self.solver.lock_values(kin, seed, self.value, self.sweep)?;
        let mut sols = Solutions::default();
        self.solver.solve_swept(kin, ws, t, &values, &mut sols)?;
        sols.sort_nearest(seed, None);
        Ok((sols, values))
    }

    /// The JSON of one target's solutions.
    fn json(&self, kin: &Kinematics, sols: &Solutions, values: &[f64]) -> Value {
        let locked = self
            .solver
            .locked_joint()
            .map(|j| json!({"joint": kin.names()[j], "index": j + 1, "values": nums(values)}));
        json!({
            "family": self.family,
            "locked": locked,
            "exact": sols.is_exact(),
            "singular": sols.singular,
            "postures": sols.branches,
            "solutions": (0..sols.len()).map(|i| json!({
                "q": nums(sols.q(i)),
                "exact": sols.exact(i),
                "residual": sols.residual(i),
            })).collect::<Vec<_>>(),
        })
    }
}

/// `ik --all`: every analytic solution, nearest to `seed` first.
fn all_solutions(
    kin: &Kinematics,
    args: &IkArgs,
    t: &Se3,
    seed: &[f64],
    format: Format,
) -> CliResult {
    kin.check_q(seed)?;
    let all = AllSolver::new(kin, args)?;
    let mut ws = Workspace::new(kin);
    let (sols, values) = all.solve(kin, &mut ws, t, seed)?;
    if format == Format::Json {
        print_json(&all.json(kin, &sols, &values))?;
    } else {
        let family = all.solver.family();
        let mut s = format!(
            "{} ({}): {} solution(s) within the limits, {} posture(s){}{}{}, nearest to the seed first:\n",
            all.family,
            family.describe(),
            sols.len(),
            sols.branches,
            match all.solver.locked_joint() {
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
                "{}  residual {:.1e}\n",
                tuple(q),
                sols.residual(i)
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

/// `ik --all --input FILE`: one JSON line of solutions per target line, in parallel through
/// the library (each line's seed, or --seed, orders the solutions and gives the lock value).
fn all_batch(kin: &Kinematics, args: &IkArgs, input: &str, seed: &[f64]) -> CliResult {
    use rayon::prelude::*;
    kin.check_q(seed)?;
    let all = AllSolver::new(kin, args)?;
    batch::stream(input, |lines, _first_row| {
        let parsed = batch::parse_rows(lines, |text| parse_line(kin, text));
        let results: Vec<Result<(Value, bool), String>> = parsed
            .into_par_iter()
            .map_init(
                || Workspace::new(kin),
                |ws, row| {
                    let (target, s) = row?;
                    let t =
                        Se3::from_row_major(&target, 1e-6).map_err(|e| format!("target: {e}"))?;
                    let s = s.unwrap_or_else(|| seed.to_vec());
                    let (sols, values) = all.solve(kin, ws, &t, &s).map_err(|e| e.to_string())?;
                    Ok((all.json(kin, &sols, &values), sols.is_exact()))
                },
            )
            .collect();
        let errors: Vec<Option<String>> =
            results.iter().map(|r| r.as_ref().err().cloned()).collect();
        Ok(batch::outputs(lines, &errors, |k| match &results[k] {
            Ok(v) => v.clone(),
            Err(_) => (Value::Null, false),
        }))
    })
    .map_err(|e| Failure(format!("{} (failed or no exact solution)", e.0)))
}

/// Runs `ik`.
pub fn run(args: &IkArgs, format: Format) -> CliResult {
    let (tree, chain) = crate::load_tree_chain(&args.chain)?;
    let kin = Kinematics::new(&chain);
    let opts = options(args)?;
    // A target given in another frame of the tree: T_base,target = T_base,frame T_frame,target.
    let frame = match &args.target_frame {
        Some(link) => Some(tree.fixed_transform(&chain.base, link)?),
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
            return all_batch(&kin, args, input, &seed);
        }
        if let Some(output) = crate::npy::binary(input, args.output.as_deref())? {
            if args.sequential {
                return Err(Failure("--sequential is for JSON lines input".into()));
            }
            return run_npy(&kin, input, output, &opts);
        }
        return run_batch(&kin, input, &opts, args.sequential);
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
        return all_solutions(&kin, args, &t, &seed, format);
    }
    let mut ws = Workspace::new(&kin);
    let t0 = Instant::now();
    let r = solve(&kin, &mut ws, &t, &seed, &opts)?;
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
