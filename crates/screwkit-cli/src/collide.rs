//! `screwkit collide` (the robot's body at q: the floor's `body` module around
//! `screwkit_collision`) and `screwkit srdf` (the allowed-collision matrix, generated).

use screwkit_collision::CollisionWorkspace;
use screwkit_service::body;
use screwkit_service::query::Space;
use screwkit_service::report;
use screwkit_solve::SolveError;

use crate::args::{CollideArgs, Format, SrdfArgs};
use crate::batch;
use crate::output::{print_json, tuple, CliResult};

/// Runs `collide`.
pub fn run(args: &CollideArgs, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    let kin = robot.whole()?;
    let model = body::robot_model(&robot, args.srdf.as_deref(), args.obstacles.as_deref())?;
    let width = Space::of(&robot, Some(kin))?.q_len();
    if let Some(input) = &args.at.input {
        if let Some(output) = crate::npy::binary(input, args.at.output.as_deref())? {
            // Each row's smallest signed distance.
            return crate::npy::run(input, output, width, "q", &[], |qs, _, out| {
                let mut rows = Vec::with_capacity(qs.len() / width.max(1) * kin.nq());
                for q in qs.chunks(width.max(1)) {
                    let full = body::tree_q(&robot, kin, q)
                        .map_err(|e| SolveError::InvalidInput(e.to_string()))?;
                    rows.extend_from_slice(&full);
                }
                screwkit_collision::min_distance_batch(&model, kin, &rows, out).map_err(|e| match e
                {
                    screwkit_collision::CollisionError::Solve(s) => s,
                    e => SolveError::InvalidInput(e.to_string()),
                })
            });
        }
        return batch::stream(input, |lines, _| {
            let (qs, errors) = batch::q_rows_checked(lines, width, |q| {
                if q.len() != width {
                    Err(SolveError::InvalidInput(format!(
                        "q: expected {width} values, got {}",
                        q.len()
                    )))
                } else if q.iter().all(|x| x.is_finite()) {
                    Ok(())
                } else {
                    Err(SolveError::InvalidInput("q has non-finite values".into()))
                }
            });
            Ok(batch::outputs(lines, &errors, |k| {
                let mut ws = CollisionWorkspace::new(kin, &model);
                match body::collide_report(
                    &robot,
                    kin,
                    &model,
                    &mut ws,
                    &qs[k * width..(k + 1) * width],
                    args.distances,
                ) {
                    Ok(r) => (report::to_value(&r), true),
                    Err(e) => (
                        serde_json::json!({"error": e.to_string(), "line": lines[k].number}),
                        false,
                    ),
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
    let mut ws = CollisionWorkspace::new(kin, &model);
    let r = body::collide_report(&robot, kin, &model, &mut ws, q, args.distances)?;
    if format == Format::Json {
        print_json(&report::to_value(&r))?;
        return Ok(());
    }
    let mut s = format!(
        "The body of `{}` at q = {}: {} pairs checked\n",
        robot.tree().name,
        tuple(&r.q),
        r.pairs
    );
    if r.in_collision {
        s.push_str("in collision:");
        for [a, b] in &r.collisions {
            s.push_str(&format!(" {a}–{b}"));
        }
        s.push('\n');
    } else {
        s.push_str("not in collision\n");
    }
    match &r.min_distance {
        Some(p) => s.push_str(&format!(
            "closest pair: {}–{}, signed distance {:.6} m, points {} and {}\n",
            p.pair[0],
            p.pair[1],
            p.distance,
            tuple(&p.points[0]),
            tuple(&p.points[1])
        )),
        None => s.push_str("no pair to check (no collision shapes, or all disabled)\n"),
    }
    for p in r.distances.iter().flatten() {
        s.push_str(&format!(
            "  {}–{}: {:.6} m, J_d = {}\n",
            p.pair[0],
            p.pair[1],
            p.distance,
            tuple(p.jacobian.as_deref().unwrap_or_default())
        ));
    }
    crate::output::emit(&s)?;
    Ok(())
}

/// Runs `srdf`.
pub fn srdf(args: &SrdfArgs) -> CliResult {
    let robot = crate::load(&args.chain)?;
    let kin = robot.whole()?;
    let g = screwkit_collision::acm::Generate {
        samples: args.samples,
        seed: args.seed,
        never: args.never,
        ..Default::default()
    };
    let text = body::generated_srdf(&robot.tree().name, kin, robot.options().meshes, &g)?;
    crate::draw::write_out(&args.output, &text)
}
