//! `screwkit draw` (SVG) and `screwkit view` (interactive HTML): the pictures of
//! `screwkit-draw` (of the chain, or of the whole tree), written to a file or standard output.

use screwkit_draw::Picture;

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

/// Loads the robot and writes its picture at q (the chain's, or the whole tree's by the
/// floor's rule: [`screwkit_draw::picture`]) to `output`.
fn picture(
    chain: &crate::args::ChainArgs,
    q: Option<&crate::args::List>,
    output: &str,
    picture: Picture<'_>,
) -> CliResult {
    let robot = crate::load(chain)?;
    let q = q.map(|l| l.0.as_slice());
    write_out(output, &screwkit_draw::picture(&robot, None, q, picture)?)
}

/// `screwkit draw`.
pub fn draw(a: &DrawArgs) -> CliResult {
    let options = screwkit_draw::svg::Options {
        views: a.view.views(),
        labels: a.labels,
        axes: a.axes.clone().unwrap_or_default(),
    };
    picture(&a.chain, a.q.as_ref(), &a.output, Picture::Svg(&options))
}

/// `screwkit view` (with `--motion`: the motion's frames, and `--obstacles`: a scene's
/// obstacles, read by the floor). The page may not overwrite the motion or the scene file
/// (nor the robot's: [`screwkit_service::io::atomic`] refuses it by any name).
pub fn view(a: &ViewArgs) -> CliResult {
    let inputs: Vec<&str> = [&a.motion, &a.obstacles, &a.srdf]
        .into_iter()
        .flatten()
        .filter_map(|p| p.to_str())
        .collect();
    if a.output != "-" {
        screwkit_service::io::atomic::check_distinct(&inputs, &[&a.output]).map_err(Failure)?;
    }
    let frames = match &a.motion {
        Some(path) => {
            Some(screwkit_service::io::motion::read(path).map_err(|e| Failure(e.to_string()))?)
        }
        None => None,
    };
    let motion = frames
        .as_deref()
        .map(|frames| screwkit_draw::html::Motion { frames, fps: a.fps });
    let obstacles = match &a.obstacles {
        Some(scene) => {
            screwkit_service::body::read_scene(scene, &a.chain.xacro.options().package_paths)?
        }
        None => Vec::new(),
    };
    let robot = crate::load(&a.chain)?;
    // The body whose contacts the page shows: the whole tree's collision shapes, an SRDF's
    // disabled pairs left out, the scene's obstacles.
    let body = if a.show_collisions || a.show_distances || a.srdf.is_some() {
        let kin = robot.whole()?;
        let mut model =
            screwkit_service::body::model(kin, robot.options().meshes, a.srdf.as_deref())?;
        screwkit_service::body::add_obstacles(&mut model, &obstacles)?;
        Some((kin, model))
    } else {
        None
    };
    let options = screwkit_draw::html::PageOptions {
        motion,
        obstacles: &obstacles,
        contacts: body
            .as_ref()
            .map(|(kin, model)| screwkit_draw::html::ShowContacts {
                kin,
                model,
                distances: a.show_distances,
            }),
    };
    let q = a.q.as_ref().map(|l| l.0.as_slice());
    write_out(
        &a.output,
        &screwkit_draw::picture(&robot, None, q, Picture::Page(options))?,
    )
}
