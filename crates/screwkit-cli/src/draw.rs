//! `screwkit draw` (SVG) and `screwkit view` (interactive HTML): the pictures of
//! `screwkit-draw`, written to a file or standard output.

use screwkit_draw::{html, svg, Scene};

use crate::args::{DrawArgs, ViewArgs};
use crate::output::{CliResult, Failure};

/// Writes `text` to `path` (`-`: standard output).
fn write_out(path: &str, text: &str) -> CliResult {
    if path == "-" {
        crate::output::emit(text)
    } else {
        screwkit_service::io::atomic::write(path, text.as_bytes())
            .map_err(|e| Failure(format!("{path}: cannot write: {e}")))
    }
}

/// Loads the chain, makes the picture at q (`make`: the library's picture of chain, kinematics
/// and q) and writes it to `output`.
fn picture(
    chain: &crate::args::ChainArgs,
    q: Option<&crate::args::List>,
    output: &str,
    make: impl FnOnce(
        &screwkit_model::Chain,
        &screwkit_solve::Kinematics,
        Option<&[f64]>,
    ) -> Result<String, screwkit_solve::SolveError>,
) -> CliResult {
    let robot = crate::load(chain)?;
    let text = make(robot.chain()?, robot.kin()?, q.map(|l| l.0.as_slice()))?;
    write_out(output, &text)
}

/// `screwkit draw`.
pub fn draw(a: &DrawArgs) -> CliResult {
    picture(&a.chain, a.q.as_ref(), &a.output, |c, k, q| {
        Ok(svg::render(&Scene::new(c, k, q)?, &a.view.views()))
    })
}

/// `screwkit view`.
pub fn view(a: &ViewArgs) -> CliResult {
    picture(&a.chain, a.q.as_ref(), &a.output, html::page)
}
