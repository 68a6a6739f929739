//! # screwkit-draw
//!
//! Pictures of a chain, or of a whole tree, and its screw axes, computed from the solver's
//! all-link FK and per-joint space screws (no kinematics here; [`Scene::new`] for a chain,
//! [`Scene::tree`] and [`html::tree_page`] for the whole tree, every leaf named):
//!
//! - [`svg::render`]: an SVG 1.1 drawing — the skeleton through the link origins, joints marked
//!   by kind, every joint's screw axis S_i(q) as a line (a prismatic joint as an arrow along v),
//!   the base and tip frames as RGB triads, a scale bar, a legend; orthographic front, side and
//!   top views and an isometric one, or all four on one sheet. Deterministic (same input, same
//!   bytes); every joint, axis, link and frame is a `<g>` with an `id`, a `class` and a
//!   `<title>` naming it with its screw.
//! - [`html::page`]: one self-contained HTML file (no network) with the chain embedded as JSON
//!   (S, M, limits, mimic rule) and a small canvas renderer: orbit and zoom, a slider per joint,
//!   the live tip pose and space screw axes. Its FK is the product of exponentials written in
//!   JavaScript, tested equal to the library's in a headless browser.
//! - [`heatmap::render`]: panels of cells coloured by a value in [0, 1] (viridis) with their
//!   axes in metres and a colour bar: the slices of a reachability map.
//! - [`plot::joints`]: joint values against a path's place or time, one panel per joint, the
//!   limits dashed (a Cartesian path's joint plot).
//!
//! ```
//! use screwkit_draw::{svg, Scene, View};
//! let chain = screwkit_model::load_chain(
//!     concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/urdf/planar_3r.urdf"), None, None)?;
//! let kin = screwkit_solve::Kinematics::new(&chain);
//! let scene = Scene::new(&chain, &kin, Some(&[0.3, -0.5, 0.8]))?;
//! let picture = svg::render(&scene, &[View::Top]);
//! assert!(picture.contains("<g id=\"top-axis-1\" class=\"axis revolute\""));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod heatmap;
pub mod html;
pub mod outline;
pub mod plot;
pub mod scene;
pub mod svg;

use screwkit_service::query::Space;
use screwkit_service::Robot;
use screwkit_solve::TreeKinematics;

pub use scene::{FrameMark, FrameRole, LinkMark, Scene};
pub use svg::View;

/// Which picture [`picture`] makes.
#[derive(Debug, Clone, Copy)]
pub enum Picture<'a> {
    /// The SVG drawing ([`svg::render_with`]): its views, names and axes; the body drawn
    /// from the robot's shapes when it has any.
    Svg(&'a svg::Options),
    /// The interactive HTML page ([`html::page`], [`html::tree_page`]), with a motion to
    /// play back and obstacles when given.
    Page(html::PageOptions<'a>),
}

/// The picture of `robot` at q (default: home), routed once for every front end: of the whole
/// tree when the floor's rule says the tree answers (`tree`: the front end's, with the frames
/// it added), q its configuration; else of the chain, q its joint values.
pub fn picture(
    robot: &Robot,
    tree: Option<&TreeKinematics>,
    q: Option<&[f64]>,
    picture: Picture<'_>,
) -> Result<String, screwkit_service::Error> {
    Ok(match (Space::of(robot, tree)?, picture) {
        (Space::Tree(kin), Picture::Svg(o)) => {
            svg::render_with(&Scene::tree(kin, q)?.with_body(&kin.model().tree), o)?
        }
        (Space::Tree(kin), Picture::Page(o)) => {
            let mut model = html::tree_model(kin, q, &o)?;
            add_contacts(robot, &mut model, &o)?;
            html::document(&kin.model().robot, &model)
        }
        (Space::Chain(kin), Picture::Svg(o)) => svg::render_with(
            &Scene::new(robot.chain()?, kin, q)?.with_body(robot.tree()),
            o,
        )?,
        (Space::Chain(kin), Picture::Page(o)) => {
            let chain = robot.chain()?;
            let mut model = html::chain_model(chain, kin, q, Some(robot.tree()), &o)?;
            add_contacts(robot, &mut model, &o)?;
            html::document(&chain.robot, &model)
        }
    })
}

/// The body's contacts ([`screwkit_service::body::contacts`]) at the page's first
/// configuration (`q`) and at each of its motion's frames, as the page's `contacts`: `q` the
/// first's, `frames` the motion's, `within` the distance of the segments shown (absent
/// without `distances`).
fn add_contacts(
    robot: &Robot,
    model: &mut serde_json::Value,
    options: &html::PageOptions<'_>,
) -> Result<(), screwkit_service::Error> {
    let Some(c) = options.contacts else {
        return Ok(());
    };
    let values = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .map(|a| a.iter().filter_map(serde_json::Value::as_f64).collect())
            .unwrap_or_default()
    };
    let first = values(&model["q"]);
    let frames: Vec<Vec<f64>> = model["motion"]["frames"]
        .as_array()
        .map(|f| f.iter().map(values).collect())
        .unwrap_or_default();
    if frames.len() + 1 > html::MAX_CONTACT_FRAMES {
        return Err(screwkit_service::Error::Option {
            name: "show_distances",
            message: format!(
                "the contacts of a motion of {} frames: at most {} (play a part of it)",
                frames.len(),
                html::MAX_CONTACT_FRAMES - 1
            ),
        });
    }
    let within = c.distances.then_some(screwkit_service::body::SHOWN_WITHIN);
    let mut ws = screwkit_collision::CollisionWorkspace::new(c.kin, c.model);
    let mut at = |q: &[f64]| -> Result<serde_json::Value, screwkit_service::Error> {
        let found = screwkit_service::body::contacts(robot, c.kin, c.model, &mut ws, q, within)?;
        Ok(serde_json::to_value(found).unwrap_or_default())
    };
    let shown = at(&first)?;
    let played = frames
        .iter()
        .map(|f| at(f))
        .collect::<Result<Vec<_>, _>>()?;
    model["contacts"] = serde_json::json!({
        "q": shown,
        "frames": played,
        "within": within,
        "pairs": c.model.pair_count(),
    });
    Ok(())
}
