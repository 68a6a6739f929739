//! The `screwkit` command line, in text for people and JSON for scripts: `info`, `table`
//! (screw tables), `fk`, `jacobian`, `ik` (numerical, `--all` analytic, `--tasks` whole-body),
//! `exp`/`log` (the screw calculator), `bench` (the IK benchmark), `draw` and `view` (pictures),
//! `reach` (maps), `xacro` and `urdf` (a file expanded or written as URDF).
//!
//! Exit codes: 0 success, 1 a failed operation (bad URDF, unknown link, wrong number of joint
//! values, IK not converged, failed batch lines), 2 bad usage, 130 interrupted (Ctrl-C). Errors are one line on stderr.

mod args;
mod batch;
mod bench;
mod calc;
mod collide;
mod draw;
mod dynamics;
mod fk;
mod ik;
mod info;
mod jacobian;
mod npy;
mod output;
mod path;
mod reach;
mod table;
mod whole_body;

use std::process::ExitCode;

use clap::Parser;
use screwkit_model::Tree;
use screwkit_service::{Robot, Source};

use args::{ChainArgs, Cli, Command, Format};
use output::{CliResult, Failure};

/// Reads a robot file (URDF or xacro; `-`: standard input) into its tree (the floor's
/// loading: one decoding rule for every front end).
pub(crate) fn read_tree(path: &std::path::Path, xacro: &args::XacroArgs) -> CliResult<Tree> {
    let tree = Source::from_arg(path).tree(&xacro.options())?.0;
    warn(&tree);
    Ok(tree)
}

/// What the reader read past that changes kinematics (an MJCF tendon, a loop closure): one
/// line each on stderr.
fn warn(tree: &Tree) {
    for w in &tree.warnings {
        eprintln!("screwkit: warning: {}: {w}", tree.source);
    }
}

/// Loads the robot and the chain named by the arguments (with its tool frame, if given).
pub(crate) fn load(c: &ChainArgs) -> CliResult<Robot> {
    let robot = Robot::load(&Source::from_arg(&c.urdf), &c.options())?;
    warn(robot.tree());
    Ok(robot)
}

fn run(cli: &Cli) -> CliResult {
    if cli.format != Format::Text
        && matches!(
            cli.command,
            Command::Draw(_)
                | Command::View(_)
                | Command::Xacro(_)
                | Command::Urdf(_)
                | Command::Srdf(_)
        )
    {
        return Err(Failure(
            "--format does not apply to `draw`, `view`, `xacro`, `urdf` and `srdf` (they write SVG, HTML, URDF or SRDF)"
                .into(),
        ));
    }
    let batch_from_stdin = match &cli.command {
        Command::Fk(a) => Some((&a.chain, &a.at.input)),
        Command::Jacobian(a) => Some((&a.chain, &a.at.input)),
        Command::Ik(a) => Some((&a.chain, &a.input)),
        Command::Collide(a) => Some((&a.chain, &a.at.input)),
        _ => None,
    };
    if let Some((c, Some(input))) = batch_from_stdin {
        if input == "-" && c.urdf.as_os_str() == "-" {
            return Err(Failure(
                "the robot and the batch cannot both come from standard input (-)".into(),
            ));
        }
    }
    if cli.format == Format::Csv && !matches!(cli.command, Command::Table(_)) {
        return Err(Failure("--format csv is only available for `table`".into()));
    }
    match &cli.command {
        Command::Info(a) => info::run(a, cli.format),
        Command::Table(a) => table::run(a, cli.format),
        Command::Fk(a) => fk::run(a, cli.format),
        Command::Jacobian(a) => jacobian::run(a, cli.format),
        Command::Ik(a) => ik::run(a, cli.format),
        Command::Exp(a) => calc::exp(a, cli.format),
        Command::Log(a) => calc::log(a, cli.format),
        Command::Bench(a) => bench::run(a, cli.format),
        Command::Reach(a) => reach::run(a, cli.format),
        Command::Collide(a) => collide::run(a, cli.format),
        Command::Srdf(a) => collide::srdf(a),
        Command::Dynamics(a) => dynamics::run(a, cli.format),
        Command::Path(a) => path::run(a, cli.format),
        Command::Draw(a) => draw::draw(a),
        Command::View(a) => draw::view(a),
        Command::Xacro(a) => {
            let text = Source::from_arg(&a.file).expand_xacro(&a.xacro.options())?;
            crate::output::emit(&text)?;
            Ok(())
        }
        Command::Urdf(a) => {
            let tree = read_tree(&a.file, &a.xacro)?;
            draw::write_out(&a.output, &screwkit_model::urdf::write(&tree)?)
        }
    }
}

/// A usage error of clap in one line (errors are one line on stderr): its message and the
/// lines that detail it (the possible values, the missing arguments), without the usage and
/// help hints.
fn one_line(rendered: &str) -> String {
    rendered
        .lines()
        .map(str::trim)
        .filter(|l| {
            !l.is_empty() && !l.starts_with("Usage:") && !l.starts_with("For more information")
        })
        .map(|l| l.strip_prefix("error: ").unwrap_or(l))
        .collect::<Vec<_>>()
        .join(" ")
}

fn main() -> ExitCode {
    // A bug must still end in one line and exit code 1, never a backtrace.
    std::panic::set_hook(Box::new(|info| {
        eprintln!("screwkit: internal error: {info}");
    }));
    // Ctrl-C (and SIGTERM): remove the temporary files of outputs being written, then exit
    // 130 as a shell expects; outputs are renamed into place only when complete, so nothing
    // half-written and no temporary file stays behind.
    let _ = ctrlc::set_handler(|| {
        screwkit_service::io::atomic::remove_pending();
        eprintln!("screwkit: interrupted");
        std::process::exit(130);
    });
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if !e.use_stderr() => e.exit(), // --help, --version
        Err(e) => {
            eprintln!("screwkit: error: {}", one_line(&e.render().to_string()));
            return ExitCode::from(2);
        }
    };
    // Every file the run reads as input (the robot's file, includes, batches, maps) is
    // protected from its outputs until it ends (`input::collect_reads`).
    let (outcome, _inputs) =
        screwkit_model::input::collect_reads(|| std::panic::catch_unwind(|| run(&cli)));
    match outcome {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) if e.0 == output::CLOSED_PIPE => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("screwkit: error: {e}");
            ExitCode::from(1)
        }
        Err(_) => ExitCode::from(1),
    }
}
