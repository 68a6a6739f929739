//! `screwkit reach`: a reachability map (or a shard of one) into an .npz file, with a progress
//! bar on a terminal and a one-line summary; `screwkit reach merge` joins shards. The map is
//! built by `screwkit_reach` (the library's batch IK underneath); this file only parses and
//! prints.

use screwkit_service::io::atomic::check_distinct;
use std::io::IsTerminal;
use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use screwkit_reach::{Plan, ReachSpec, Shard};
use screwkit_service::report::{self, MapReport};

use crate::args::{ChainArgs, Format, ReachArgs, ReachCommand};
use crate::output::{CliResult, Failure};

/// Runs `reach` or `reach merge`.
pub fn run(a: &ReachArgs, format: Format) -> CliResult {
    if let Some(ReachCommand::Merge {
        output,
        svg,
        shards,
    }) = &a.merge
    {
        let started = Instant::now();
        // Every output checked against every input before anything is written.
        let inputs: Vec<&str> = shards.iter().map(String::as_str).collect();
        let outputs: Vec<&str> = std::iter::once(output.as_str())
            .chain(svg.as_deref())
            .collect();
        check_distinct(&inputs, &outputs).map_err(Failure)?;
        let s = screwkit_reach::merge(shards, output)?;
        if let Some(svg) = svg {
            write_svg(output, svg)?;
        }
        let r = MapReport::merged(
            (s.voxels, s.poses, s.reached),
            started.elapsed().as_secs_f64(),
            shards.len(),
        );
        if format == Format::Json {
            crate::output::print_json(&report::to_value(&r))?;
        } else {
            crate::output::emit(&format!(
                "merged {} shards: {} voxels = {} poses, {} reached ({:.1} %), {:.2} s → {output}\n",
                shards.len(),
                r.voxels,
                r.poses,
                r.reached,
                100.0 * r.reached_fraction,
                r.seconds,
            ))?;
        }
        return Ok(());
    }
    let (Some(urdf), Some(output)) = (&a.urdf, &a.output) else {
        return Err(Failure("reach needs a robot file and -o MAP".into()));
    };
    let chain_args = ChainArgs {
        urdf: urdf.clone(),
        xacro: a.xacro.clone(),
        base: a.base.clone(),
        tip: a.tip.clone(),
        tool: a.tool.clone(),
        floating_base: false,
        // The body's shapes are read only for a map clear of contact.
        geometry: if a.avoid.avoid_collisions {
            screwkit_service::words::GeometryRoles::Collision
        } else {
            screwkit_service::words::GeometryRoles::None
        },
        meshes: a.meshes,
    };
    let robot = crate::load(&chain_args)?;
    // The map and its picture: neither an input of this run (the robot's file, an include),
    // nor the same file; checked before the map is computed.
    let outputs: Vec<&str> = std::iter::once(output.as_str())
        .chain(a.svg.as_deref())
        .collect();
    screwkit_service::io::atomic::check_writable(&outputs).map_err(Failure)?;
    check_distinct(&[], &outputs).map_err(Failure)?;
    let (chain, kin) = robot.chain_parts()?;
    let spec = ReachSpec {
        resolution: a.resolution,
        orientations: a.orientations,
        mode: a.mode,
        bounds: match &a.bounds {
            None => None,
            Some(l) => Some(ReachSpec::bounds_from(&l.0)?),
        },
        solver: a.solver,
        seed: a.seed,
        restarts: a.restarts,
        iterations: a.iterations,
        collision_margin: a.avoid.avoid_collisions.then_some(a.avoid.margin),
    };
    let shard = a.shard.unwrap_or(Shard::WHOLE);
    if a.svg.is_some() && shard.count > 1 {
        return Err(Failure(
            "--svg needs the whole map: draw it after `reach merge` (which takes --svg too)".into(),
        ));
    }
    let plan = Plan::new(chain, kin, &spec)?;
    // The body (SRDF and obstacles applied), read before the map is computed.
    let model = a.avoid.model(&robot)?;
    let bar = std::io::stderr().is_terminal().then(|| {
        let b = ProgressBar::new(0);
        if let Ok(style) = ProgressStyle::with_template(
            "{bar:40} {percent:>3}% {human_pos}/{human_len} poses, {per_sec}, ETA {eta}",
        ) {
            b.set_style(style);
        }
        b
    });
    // A small map may be written as text: built as .npz beside it, then exported.
    let text = output.ends_with(".csv") || output.ends_with(".json");
    if !text && !output.ends_with(".npz") {
        return Err(Failure(format!(
            "-o {output}: write a map as .npz, or a small one as .csv or .json"
        )));
    }
    if text && plan.poses() > screwkit_reach::TEXT_MAX_POSES {
        return Err(Failure(format!(
            "-o {output}: {} poses is too many for text; write .npz",
            plan.poses()
        )));
    }
    let npz = if text {
        format!("{output}.npz")
    } else {
        output.clone()
    };
    let started = Instant::now();
    let progress = |done, total| {
        if let Some(b) = &bar {
            b.set_length(total as u64);
            b.set_position(done as u64);
        }
    };
    let s = match &model {
        Some(model) => {
            let body = screwkit_reach::Body {
                robot: &robot,
                tree: robot.whole()?,
                model,
            };
            screwkit_reach::build_clear(&plan, kin, body, shard, &npz, progress)?
        }
        None => screwkit_reach::build(&plan, kin, shard, &npz, progress)?,
    };
    let secs = started.elapsed().as_secs_f64();
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    if let Some(svg) = &a.svg {
        write_svg(&npz, svg)?;
    }
    if text {
        let r = screwkit_reach::export(&npz, output);
        let _ = std::fs::remove_file(&npz);
        r?;
    }
    let what = if shard.count > 1 {
        format!("shard {}/{} → {output}", shard.index, shard.count)
    } else {
        format!("→ {output}")
    };
    print_summary(
        format,
        plan.solver_name(),
        &s,
        Some(plan.rotations.len()),
        secs,
        &what,
        spec.collision_margin.is_some(),
    )
}

fn write_svg(map: &str, svg: &str) -> CliResult {
    let m = screwkit_reach::read(map)?;
    if m.voxels.len() != m.grid.len() {
        return Err(Failure(format!("{map} is a shard: draw the merged map")));
    }
    screwkit_service::io::atomic::write(svg, screwkit_reach::slices::svg(&m).as_bytes())
        .map_err(|e| Failure(format!("cannot write {svg}: {e}")))
}

fn print_summary(
    format: Format,
    solver: &'static str,
    s: &screwkit_reach::Summary,
    k: Option<usize>,
    secs: f64,
    what: &str,
    clear: bool,
) -> CliResult {
    let threads = rayon::current_num_threads();
    let r = MapReport::built(
        (s.voxels, s.poses, s.solved, s.reached),
        secs,
        threads,
        solver,
    )
    .with_lost_to_collisions(clear.then_some(s.collided));
    if format == Format::Json {
        return crate::output::print_json(&report::to_value(&r));
    }
    let k = k
        .map(|k| format!(" × {k} orientations"))
        .unwrap_or_default();
    let lost = r
        .lost_to_collisions
        .map(|n| format!(" ({n} more only in contact)"))
        .unwrap_or_default();
    crate::output::emit(&format!(
        "{} voxels{k} = {} poses ({} solved in reach), {} reached ({:.1} %){lost}, {secs:.2} s, {:.0} solves/s on {threads} threads ({solver} IK) {what}\n",
        r.voxels,
        r.poses,
        s.solved,
        r.reached,
        100.0 * r.reached_fraction,
        r.solves_per_second.unwrap_or(0.0)
    ))
}
