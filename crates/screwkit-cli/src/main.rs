//! The `screwkit` command line: screw tables, FK, Jacobians, IK, the exp/log calculator and
//! the IK benchmark, in text for people and JSON for scripts.
//!
//! Exit codes: 0 success, 1 a failed operation (bad URDF, unknown link, wrong number of joint
//! values, IK not converged, failed batch lines), 2 bad usage, 130 interrupted (Ctrl-C). Errors are one line on stderr.

mod args;
mod batch;
mod bench;
mod calc;
mod draw;
mod fk;
mod ik;
mod info;
mod jacobian;
mod npy;
mod output;
mod reach;
mod table;

use std::process::ExitCode;

use clap::Parser;
use screwkit_model::{urdf, Chain, ModelError, Tree};
use screwkit_solve::Kinematics;

use args::{ChainArgs, Cli, Command, Format};
use output::{CliResult, Failure};

/// Reads a robot file (URDF or xacro; `-`: standard input) into its tree.
pub(crate) fn read_tree(path: &std::path::Path, xacro: &args::XacroArgs) -> CliResult<Tree> {
    if path.as_os_str() == "-" {
        let bytes = screwkit_model::input::read_bounded(std::io::stdin())
            .map_err(|k| ModelError::new("<stdin>", k))?;
        let text = urdf::decode(&bytes).map_err(|k| ModelError::new("<stdin>", k))?;
        let cwd = std::path::Path::new(".");
        return Ok(urdf::load_str_with(
            &text,
            "<stdin>",
            cwd,
            &xacro.options(),
        )?);
    }
    Ok(urdf::load_file_with(path, &xacro.options())?)
}

/// Loads the tree and the chain named by the arguments (with its tool frame, if given).
pub(crate) fn load_tree_chain(c: &ChainArgs) -> CliResult<(Tree, Chain)> {
    let tree = read_tree(&c.urdf, &c.xacro)?;
    let chain = Chain::from_tree(&tree, c.base.as_deref(), c.tip.as_deref())?;
    let chain = match &c.tool {
        None => chain,
        Some(t) => {
            let [x, y, z, r, p, w] = t.0.as_slice() else {
                return Err(Failure(format!(
                    "--tool needs 6 numbers x,y,z,roll,pitch,yaw, got {}",
                    t.0.len()
                )));
            };
            let tool = screwkit_lie::Se3::from_xyz_rpy([*x, *y, *z], [*r, *p, *w])
                .map_err(|e| Failure(format!("--tool: {e}")))?;
            chain.with_tool(&tool)
        }
    };
    Ok((tree, chain))
}

/// Loads the chain named by the arguments.
pub(crate) fn load_chain(c: &ChainArgs) -> CliResult<Chain> {
    Ok(load_tree_chain(c)?.1)
}

/// Loads the chain named by the arguments and prepares it for solving.
pub(crate) fn load(c: &ChainArgs) -> CliResult<(Chain, Kinematics)> {
    let chain = load_chain(c)?;
    let kin = Kinematics::new(&chain);
    Ok((chain, kin))
}

fn run(cli: &Cli) -> CliResult {
    if cli.format != Format::Text
        && matches!(
            cli.command,
            Command::Draw(_) | Command::View(_) | Command::Xacro(_)
        )
    {
        return Err(Failure(
            "--format does not apply to `draw`, `view` and `xacro` (they write SVG, HTML or URDF)"
                .into(),
        ));
    }
    let batch_from_stdin = match &cli.command {
        Command::Fk(a) => Some((&a.chain, &a.input)),
        Command::Jacobian(a) => Some((&a.chain, &a.input)),
        Command::Ik(a) => Some((&a.chain, &a.input)),
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
        Command::Draw(a) => draw::draw(a),
        Command::View(a) => draw::view(a),
        Command::Xacro(a) => {
            let text = if a.file.as_os_str() == "-" {
                let bytes = screwkit_model::input::read_bounded(std::io::stdin())
                    .map_err(|k| ModelError::new("<stdin>", k))?;
                let text = urdf::decode(&bytes).map_err(|k| ModelError::new("<stdin>", k))?;
                let cwd = std::path::Path::new(".");
                screwkit_model::xacro::expand_str(&text, "<stdin>", cwd, &a.xacro.options())?
            } else {
                screwkit_model::xacro::expand_file(&a.file, &a.xacro.options())?
            };
            crate::output::emit(&text)?;
            Ok(())
        }
    }
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
        screwkit_reach::atomic::remove_pending();
        eprintln!("screwkit: interrupted");
        std::process::exit(130);
    });
    let cli = Cli::parse();
    match std::panic::catch_unwind(|| run(&cli)) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) if e.0 == output::CLOSED_PIPE => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("screwkit: error: {e}");
            ExitCode::from(1)
        }
        Err(_) => ExitCode::from(1),
    }
}
