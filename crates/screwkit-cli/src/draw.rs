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

/// `screwkit draw`.
pub fn draw(a: &DrawArgs) -> CliResult {
    let robot = crate::load(&a.chain)?;
    let scene = Scene::new(
        robot.chain(),
        robot.kin(),
        a.q.as_ref().map(|l| l.0.as_slice()),
    )?;
    write_out(&a.output, &svg::render(&scene, &a.view.views()))
}

/// `screwkit view`.
pub fn view(a: &ViewArgs) -> CliResult {
    let robot = crate::load(&a.chain)?;
    let page = html::page(
        robot.chain(),
        robot.kin(),
        a.q.as_ref().map(|l| l.0.as_slice()),
    )?;
    write_out(&a.output, &page)
}
