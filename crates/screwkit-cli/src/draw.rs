//! `screwkit draw` (SVG) and `screwkit view` (interactive HTML): the pictures of
//! `screwkit-draw` (of the chain, or of the whole tree), written to a file or standard output.

use screwkit_draw::{html, svg, Scene};

use crate::args::{DrawArgs, ViewArgs};
use crate::output::{CliResult, Failure};

/// Writes `text` to `path` (`-`: standard output).
pub(crate) fn write_out(path: &str, text: &str) -> CliResult {
    if path == "-" {
        crate::output::emit(text)
    } else {
        screwkit_service::io::atomic::write(path, text.as_bytes())
            .map_err(|e| Failure(format!("{path}: cannot write: {e}")))
    }
}

/// Loads the robot and makes the picture at q: of the whole tree when the floor's rule says
/// so (`whole::wants_tree`: no chain, or a floating base), else of the chain; writes it to
/// `output`.
fn picture(
    chain: &crate::args::ChainArgs,
    q: Option<&crate::args::List>,
    output: &str,
    of_chain: impl FnOnce(
        &screwkit_model::Chain,
        &screwkit_solve::Kinematics,
        Option<&[f64]>,
    ) -> Result<String, screwkit_solve::SolveError>,
    of_tree: impl FnOnce(
        &screwkit_solve::TreeKinematics,
        Option<&[f64]>,
    ) -> Result<String, screwkit_solve::SolveError>,
) -> CliResult {
    let robot = crate::load(chain)?;
    let q = q.map(|l| l.0.as_slice());
    let text = if screwkit_service::whole::wants_tree(&robot, false) {
        of_tree(robot.whole()?, q)?
    } else {
        of_chain(robot.chain()?, robot.kin()?, q)?
    };
    write_out(output, &text)
}

/// `screwkit draw`.
pub fn draw(a: &DrawArgs) -> CliResult {
    let views = a.view.views();
    picture(
        &a.chain,
        a.q.as_ref(),
        &a.output,
        |c, k, q| Ok(svg::render(&Scene::new(c, k, q)?, &views)),
        |k, q| Ok(svg::render(&Scene::tree(k, q)?, &views)),
    )
}

/// `screwkit view`.
pub fn view(a: &ViewArgs) -> CliResult {
    picture(
        &a.chain,
        a.q.as_ref(),
        &a.output,
        html::page,
        html::tree_page,
    )
}
