//! `screwkit ik`: joint values reaching a target pose.

use std::time::{Duration, Instant};

use screwkit_lie::Se3;
use screwkit_solve::batch::row_seed;
use screwkit_solve::ik::{solve, IkMethod, IkOptions, IkResult};
use screwkit_solve::{Kinematics, Workspace};
use serde_json::{json, Value};

use crate::args::{Format, IkArgs, Method};
use crate::batch;
use crate::output::{matrix_text, num, nums, print_json, tuple, CliResult, Failure};

/// Tolerance on max |RᵀR − I| for typed target matrices (then re-orthonormalised).
const TYPED_ROTATION_TOLERANCE: f64 = 1e-3;

fn options(args: &IkArgs) -> IkOptions {
    IkOptions {
        method: match args.method {
            Method::Nr => IkMethod::NewtonRaphson,
            Method::Dls => IkMethod::DLS,
            Method::Lm => IkMethod::LM,
        },
        tol_rot: args.tol_rot,
        tol_pos: args.tol_pos,
        max_iterations: args.max_iter,
        max_restarts: args.restarts,
        timeout: (args.timeout_ms > 0.0).then(|| Duration::from_secs_f64(args.timeout_ms / 1e3)),
        seed: args.random_seed,
        position_only: args.position_only,
        ..IkOptions::default()
    }
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

fn result_json(r: &IkResult, time_us: f64) -> Value {
    json!({
        "converged": r.converged,
        "q": nums(&r.q),
        "iterations": r.iterations,
        "restarts": r.restarts,
        "error_rot": num(r.error_rot),
        "error_pos": num(r.error_pos),
        "time_us": num(time_us),
        "stop": r.stop.as_str(),
    })
}

fn timed(
    kin: &Kinematics,
    ws: &mut Workspace,
    t: &Se3,
    seed: &[f64],
    o: &IkOptions,
) -> Result<(IkResult, f64), String> {
    let t0 = Instant::now();
    let r = solve(kin, ws, t, seed, o).map_err(|e| e.to_string())?;
    Ok((r, t0.elapsed().as_secs_f64() * 1e6))
}

/// Runs `ik`.
pub fn run(args: &IkArgs, format: Format) -> CliResult {
    let (chain, kin) = crate::load(&args.chain)?;
    let opts = options(args);
    if let Some(input) = &args.input {
        let lines = batch::read_lines(input)?;
        let mid = kin.midpoint();
        let failures = batch::run(&kin, lines, |ws, line_no, text| {
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
            let t = Se3::from_row_major(&m, TYPED_ROTATION_TOLERANCE)
                .map_err(|e| format!("target: {e}"))?;
            let seed = if obj.contains_key("seed") {
                batch::numbers(&obj, "seed")?
            } else {
                mid.clone()
            };
            let o = IkOptions {
                seed: row_seed(opts.seed, line_no),
                ..opts.clone()
            };
            let (r, us) = timed(&kin, ws, &t, &seed, &o)?;
            Ok((result_json(&r, us), r.converged))
        })?;
        return if failures == 0 {
            Ok(())
        } else {
            Err(Failure(format!(
                "{failures} line(s) failed or did not converge"
            )))
        };
    }
    let t = target(args)?;
    let seed = match &args.seed {
        Some(s) => s.0.clone(),
        None => kin.midpoint(),
    };
    let mut ws = Workspace::new(&kin);
    let (r, us) = timed(&kin, &mut ws, &t, &seed, &opts).map_err(Failure)?;
    if format == Format::Json {
        print_json(&result_json(&r, us));
    } else {
        let mut s = format!(
            "Target pose of `{}` in `{}`:\n{}",
            chain.tip,
            chain.base,
            matrix_text(&t)
        );
        s.push_str(&format!(
            "\nconverged          {}\nq                  {}\njoints             {}\niterations         {} ({} restarts, {:.1} µs)\nrotation error     {:.3e} rad\nposition error     {:.3e} m\nstopped because    {}\n",
            if r.converged { "yes" } else { "NO" },
            tuple(&r.q),
            kin.names().join(", "),
            r.iterations,
            r.restarts,
            us,
            r.error_rot,
            r.error_pos,
            r.stop.as_str()
        ));
        print!("{s}");
    }
    if r.converged {
        Ok(())
    } else {
        Err(Failure(format!(
            "IK did not converge ({}): best rotation error {:.3e} rad, position error {:.3e} m",
            r.stop.as_str(),
            r.error_rot,
            r.error_pos
        )))
    }
}
