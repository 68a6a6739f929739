//! `screwkit draw` (SVG) and `screwkit view` (interactive HTML): the pictures of
//! `screwkit-draw`, written to a file or standard output.

use screwkit_draw::{html, svg, Scene, View};

use crate::args::{DrawArgs, ViewArgs};
use crate::output::{CliResult, Failure};

/// Writes `text` to `path` (`-`: standard output).
fn write_out(path: &str, text: &str) -> CliResult {
    if path == "-" {
        crate::output::emit(text)
    } else {
        screwkit_reach::atomic::write(path, text.as_bytes())
            .map_err(|e| Failure(format!("{path}: cannot write: {e}")))
    }
}

/// `screwkit draw`.
pub fn draw(a: &DrawArgs) -> CliResult {
    let views: Vec<View> = if a.view == "all" {
        View::ALL.to_vec()
    } else {
        vec![a.view.parse::<View>().map_err(Failure)?]
    };
    let (chain, kin) = crate::load(&a.chain)?;
    let scene = Scene::new(&chain, &kin, a.q.as_ref().map(|l| l.0.as_slice()))?;
    write_out(&a.output, &svg::render(&scene, &views))
}

/// `screwkit view`.
pub fn view(a: &ViewArgs) -> CliResult {
    let (chain, kin) = crate::load(&a.chain)?;
    let page = html::page(&chain, &kin, a.q.as_ref().map(|l| l.0.as_slice()))?;
    write_out(&a.output, &page)
}
