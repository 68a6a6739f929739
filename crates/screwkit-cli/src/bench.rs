//! `screwkit bench`: the IK protocol plus FK and Jacobian costs.

use screwkit_service::words::Word;
use screwkit_solve::ik::IkOptions;
use screwkit_testkit::protocol;
use serde_json::json;

use crate::args::{BenchArgs, Format};
use crate::output::{num, print_json, CliResult};

/// Runs `bench`.
pub fn run(args: &BenchArgs, format: Format) -> CliResult {
    let robot = crate::load(&args.chain)?;
    let (chain, kin) = robot.chain_parts()?;
    let label = args.method.as_str();
    let opts = IkOptions {
        method: args.method.with_damping(None)?,
        timeout: Some(screwkit_testkit::protocol::TIME_CAP),
        ..IkOptions::default()
    };
    let r = protocol::run(kin, args.n, args.seed, &opts);
    if format == Format::Json {
        print_json(&json!({
            "robot": chain.robot, "base": chain.base, "tip": chain.tip, "dof": kin.dof(),
            "method": label, "queries": r.queries, "solved": r.solved,
            "solve_rate": num(r.solve_rate()), "mean_us": num(r.mean_us),
            "median_us": num(r.median_us), "p99_us": num(r.p99_us),
            "mean_iterations": num(r.mean_iterations), "fk_ns": num(r.fk_ns),
            "jacobian_ns": num(r.jacobian_ns), "host": protocol::host(),
        }))?;
    } else {
        crate::output::emit(&format!(
            "IK protocol on `{}` ({} → {}, {} DoF), method {label}, {} targets, seed {}:\n\
             solved             {:.2} % ({} of {}; success = {:.0e} rad / {:.0e} m by independent FK, within limits)\n\
             time per query     mean {:.1} µs, median {:.1} µs, p99 {:.1} µs ({} ms cap, failures included)\n\
             iterations         {:.1} per query\n\
             FK                 {:.0} ns per call\n\
             FK + Jacobian      {:.0} ns per call\n\
             host               {}\n",
            chain.robot,
            chain.base,
            chain.tip,
            kin.dof(),
            r.queries,
            args.seed,
            100.0 * r.solve_rate(),
            r.solved,
            r.queries,
            protocol::SUCCESS_ROT,
            protocol::SUCCESS_POS,
            r.mean_us,
            r.median_us,
            r.p99_us,
            protocol::TIME_CAP.as_millis(),
            r.mean_iterations,
            r.fk_ns,
            r.jacobian_ns,
            protocol::host()
        ))?;
    }
    Ok(())
}
