//! The scene as SVG 1.1: orthographic views (front, side, top) and an isometric one, fitted to
//! the page, each element with a `<title>` (shown on hover) and an `id`/`class` scripts can find.
//!
//! Written by hand rather than with the `svg` crate: the document is a few element kinds with
//! fixed attribute order and number formatting (two decimals in px), which is what makes the
//! output byte-for-byte deterministic and easy to diff; a builder crate would add a dependency
//! for the same `format!` calls.

use std::fmt::Write;

use nalgebra::{Vector2, Vector3};
use screwkit_model::JointKind;

use crate::scene::{FrameRole, Scene};

use screwkit_service::words::Word;
pub use screwkit_service::words::{Axes, Labels, View};

/// How a drawing is made: its views, which names it writes, which screw axes it shows.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// One view, or the four of [`View::ALL`] on one sheet.
    pub views: Vec<View>,
    /// The names written ([`Labels::Leaves`] by default).
    pub labels: Labels,
    /// The screw axes shown ([`Axes::Auto`] by default).
    pub axes: Axes,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            views: vec![View::Iso],
            labels: Labels::Leaves,
            axes: Axes::Auto,
        }
    }
}

/// What the view shows, for its caption.
fn caption(view: View) -> &'static str {
    match view {
        View::Front => "front: from +x, y right, z up",
        View::Side => "side: from −y, x right, z up",
        View::Top => "top: from +z, x right, y up",
        View::Iso => "isometric: from (1, 1, 1), z up",
    }
}

/// The screen axes (right, up) in the base frame. Towards the viewer is w; right is ẑ × w
/// normalised (x for the top view) and up is w × right.
fn axes(view: View) -> (Vector3<f64>, Vector3<f64>) {
    let w = match view {
        View::Front => Vector3::x(),
        View::Side => -Vector3::y(),
        View::Top => return (Vector3::x(), Vector3::y()),
        View::Iso => Vector3::repeat(1.0).normalize(),
    };
    let right = Vector3::z().cross(&w).normalize();
    (right, w.cross(&right))
}

const PANEL_W: f64 = 560.0;
const PANEL_H: f64 = 440.0;
const MARGIN: f64 = 36.0;
const LEGEND_ROW: f64 = 24.0;
const LINK: &str = "#3a3a3a";
const AXIS: &str = "#7b3294";
const SLIDE: &str = "#008837";
const XYZ: [&str; 3] = ["#d7191c", "#1a9641", "#2b83ba"];

/// A number in px with two decimals (no "-0.00").
fn px(x: f64) -> String {
    let s = format!("{x:.2}");
    if s == "-0.00" {
        "0.00".into()
    } else {
        s
    }
}

/// A number of the model (m, rad) as shown in titles.
fn num(x: f64) -> String {
    let s = format!("{x:.6}");
    if s == "-0.000000" {
        "0.000000".into()
    } else {
        s
    }
}

fn vec3(v: &Vector3<f64>) -> String {
    format!("({}, {}, {})", num(v.x), num(v.y), num(v.z))
}

/// Escapes text for XML content and attribute values (the workspace's one XML escape).
pub(crate) use screwkit_model::input::escape_xml as escape;

/// A name made safe for an `id` (letters, digits, `-`, `_`, `.`; anything else `_`).
fn id_part(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn kind_name(kind: JointKind) -> &'static str {
    match kind {
        JointKind::Revolute => "revolute",
        JointKind::Continuous => "continuous",
        JointKind::Prismatic => "prismatic",
        JointKind::Helical => "helical",
        _ => "fixed",
    }
}

/// The title of a joint: name, kind, screw at q, pitch.
fn joint_title(scene: &Scene, j: usize) -> String {
    let m = &scene.joints[j];
    let mut t = format!(
        "joint {} {} ({}): S(q) = (ω | v) = {} | {}",
        m.index,
        m.name,
        kind_name(m.kind),
        vec3(&m.screw.w),
        vec3(&m.screw.v)
    );
    match m.pitch {
        Some(h) if h.abs() > 1e-12 => {
            let _ = write!(t, ", pitch {} m/rad", num(h));
        }
        _ => {}
    }
    t
}

/// One panel: the projection of the scene fitted into a `PANEL_W` × `PANEL_H` box at (x0, y0).
struct Panel {
    right: Vector3<f64>,
    up: Vector3<f64>,
    /// Towards the viewer (right × up): the depth of painter's order.
    toward: Vector3<f64>,
    scale: f64,
    centre: Vector2<f64>,
    x0: f64,
    y0: f64,
}

impl Panel {
    fn new(scene: &Scene, view: View, x0: f64, y0: f64) -> Self {
        let (right, up) = axes(view);
        let flat = |p: &Vector3<f64>| Vector2::new(right.dot(p), up.dot(p));
        let mut pts: Vec<Vector2<f64>> = Vec::new();
        for l in &scene.links {
            pts.push(flat(l.pose.translation()));
        }
        for o in &scene.outlines {
            pts.extend(o.points.iter().map(flat));
        }
        for j in &scene.joints {
            pts.extend(j.line.iter().map(flat));
        }
        for f in &scene.frames {
            for k in 0..3 {
                pts.push(flat(
                    &(f.pose.translation() + f.pose.rotation().column(k) * triad(scene, f)),
                ));
            }
        }
        let (lo, hi) = pts.iter().fold(
            (
                Vector2::repeat(f64::INFINITY),
                Vector2::repeat(f64::NEG_INFINITY),
            ),
            |(lo, hi), p| (lo.inf(p), hi.sup(p)),
        );
        let extent = (hi - lo).sup(&Vector2::repeat(1e-3 * scene.size));
        let scale =
            ((PANEL_W - 2.0 * MARGIN) / extent.x).min((PANEL_H - 2.0 * MARGIN - 18.0) / extent.y);
        Self {
            right,
            up,
            toward: right.cross(&up),
            scale,
            centre: (lo + hi) / 2.0,
            x0,
            y0,
        }
    }

    /// Page coordinates of a point of the base frame.
    fn at(&self, p: &Vector3<f64>) -> (f64, f64) {
        let u = self.right.dot(p) - self.centre.x;
        let v = self.up.dot(p) - self.centre.y;
        (
            self.x0 + PANEL_W / 2.0 + u * self.scale,
            self.y0 + 9.0 + PANEL_H / 2.0 - v * self.scale,
        )
    }
}

fn line(out: &mut String, a: (f64, f64), b: (f64, f64), stroke: &str, width: f64, extra: &str) {
    let _ = writeln!(
        out,
        "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{stroke}\" stroke-width=\"{width}\" stroke-linecap=\"round\"{extra}/>",
        px(a.0),
        px(a.1),
        px(b.0),
        px(b.1)
    );
}

/// A joint's mark: revolute a circle, continuous a double circle, prismatic a square,
/// helical a circle crossed by a thread (its screw axis is dotted).
fn joint_mark(out: &mut String, kind: JointKind, c: (f64, f64)) {
    let (x, y) = (px(c.0), px(c.1));
    match kind {
        JointKind::Prismatic => {
            let _ = writeln!(
                out,
                "<rect x=\"{}\" y=\"{}\" width=\"12\" height=\"12\" fill=\"#ffffff\" stroke=\"{LINK}\" stroke-width=\"2\"/>",
                px(c.0 - 6.0),
                px(c.1 - 6.0)
            );
        }
        JointKind::Helical => {
            let _ = writeln!(out, "<circle cx=\"{x}\" cy=\"{y}\" r=\"6\" fill=\"#ffffff\" stroke=\"{LINK}\" stroke-width=\"2\"/>");
            let _ = writeln!(
                out,
                "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{LINK}\" stroke-width=\"1.5\"/>",
                px(c.0 - 4.0),
                px(c.1 + 4.0),
                px(c.0 + 4.0),
                px(c.1 - 4.0)
            );
        }
        JointKind::Continuous => {
            let _ = writeln!(out, "<circle cx=\"{x}\" cy=\"{y}\" r=\"7\" fill=\"#ffffff\" stroke=\"{LINK}\" stroke-width=\"2\"/>");
            let _ = writeln!(out, "<circle cx=\"{x}\" cy=\"{y}\" r=\"3\" fill=\"none\" stroke=\"{LINK}\" stroke-width=\"1.5\"/>");
        }
        _ => {
            let _ = writeln!(out, "<circle cx=\"{x}\" cy=\"{y}\" r=\"6\" fill=\"#ffffff\" stroke=\"{LINK}\" stroke-width=\"2\"/>");
        }
    }
}

/// A "nice" length (1, 2 or 5 × 10^k m) near a fifth of `size`, and its label.
fn scale_bar(size: f64) -> (f64, String) {
    let target = size / 5.0;
    let k = target.log10().floor();
    let base = 10f64.powf(k);
    let m = [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .min_by(|a, b| {
            ((a * base) - target)
                .abs()
                .total_cmp(&((b * base) - target).abs())
        })
        .unwrap_or(1.0);
    let len = m * base;
    // 1, 2 or 5 × 10^k printed without float noise: 0.5 mm, 200 mm, 2 m.
    let label = if len >= 1.0 {
        format!("{} m", (len * 1e6).round() / 1e6)
    } else {
        format!("{} mm", (len * 1e9).round() / 1e6)
    };
    (len, label)
}

/// A colour of the model (r, g, b in [0, 1]) times `k`, as `#rrggbb`.
fn hex(rgb: [f64; 3], k: f64) -> String {
    let c = |x: f64| ((x * k).clamp(0.0, 1.0) * 255.0).round() as u8;
    format!("#{:02x}{:02x}{:02x}", c(rgb[0]), c(rgb[1]), c(rgb[2]))
}

/// The colour of a shape the file gives none: a light steel grey.
const BODY: [f64; 3] = [0.74, 0.76, 0.8];

/// The body's silhouettes in painter's order: each shape's points projected, their convex hull
/// ([`crate::outline::hull`]) filled with its colour (lighter the nearer), farthest first.
fn body(out: &mut String, scene: &Scene, p: &Panel, v: &str) {
    if scene.outlines.is_empty() {
        return;
    }
    let depth: Vec<f64> = scene
        .outlines
        .iter()
        .map(|o| {
            o.points.iter().map(|x| p.toward.dot(x)).sum::<f64>() / o.points.len().max(1) as f64
        })
        .collect();
    let mut order: Vec<usize> = (0..depth.len()).collect();
    order.sort_by(|&a, &b| depth[a].total_cmp(&depth[b]).then(a.cmp(&b)));
    let (near, far) = depth
        .iter()
        .fold((f64::MIN, f64::MAX), |(n, f), d| (n.max(*d), f.min(*d)));
    let _ = writeln!(out, "<g id=\"{v}-body\" class=\"body\">");
    for k in order {
        let o = &scene.outlines[k];
        let flat: Vec<Vector2<f64>> = o
            .points
            .iter()
            .map(|x| {
                let (a, b) = p.at(x);
                Vector2::new(a, b)
            })
            .collect();
        // The hull's vertices less than 0.75 px from the last one kept add nothing.
        let mut ring: Vec<Vector2<f64>> = Vec::new();
        for h in crate::outline::hull(&flat) {
            if ring.last().is_none_or(|l| (h - l).norm() >= 0.75) {
                ring.push(h);
            }
        }
        if ring.len() < 3 {
            continue;
        }
        let points: Vec<String> = ring
            .iter()
            .map(|h| format!("{},{}", px(h.x), px(h.y)))
            .collect();
        let rgba = o.rgba.unwrap_or([BODY[0], BODY[1], BODY[2], 1.0]);
        let rgb = [rgba[0], rgba[1], rgba[2]];
        let t = if near > far {
            (depth[k] - far) / (near - far)
        } else {
            1.0
        };
        let opacity = if rgba[3] < 1.0 {
            format!(" fill-opacity=\"{:.2}\"", rgba[3].max(0.1))
        } else {
            String::new()
        };
        let link = &scene.links[o.link].name;
        let role = match o.role {
            screwkit_model::geometry::Role::Visual => "visual",
            screwkit_model::geometry::Role::Collision => "collision",
        };
        let _ = writeln!(
            out,
            "<polygon class=\"shape {role}\" data-link=\"{}\" points=\"{}\" fill=\"{}\"{opacity} stroke=\"{}\" stroke-width=\"0.8\" stroke-linejoin=\"round\"><title>link {} ({role} shape)</title></polygon>",
            escape(link),
            points.join(" "),
            hex(rgb, 0.82 + 0.18 * t),
            hex(rgb, 0.55),
            escape(link)
        );
    }
    let _ = writeln!(out, "</g>");
}

/// A white halo around a label's letters (its stroke painted under its fill), which keeps it
/// readable over the body and the lines.
const HALO: &str = " stroke=\"#ffffff\" stroke-width=\"3.5\" stroke-opacity=\"0.9\" stroke-linejoin=\"round\" paint-order=\"stroke\"";

/// A label waiting for its place: what it names (for its `id`), its text, its point.
struct Label {
    id: String,
    class: &'static str,
    text: String,
    font: f64,
    fill: &'static str,
    anchor: (f64, f64),
}

fn panel(
    out: &mut String,
    scene: &Scene,
    options: &Options,
    shown: &[bool],
    view: View,
    x0: f64,
    y0: f64,
) {
    let p = Panel::new(scene, view, x0, y0);
    let v = view.as_str();
    let _ = writeln!(out, "<g id=\"{v}\" class=\"view\">");
    let _ = writeln!(
        out,
        "<rect x=\"{}\" y=\"{}\" width=\"{PANEL_W}\" height=\"{PANEL_H}\" fill=\"#fbfbf8\" stroke=\"#d0d0d0\"/>",
        px(x0),
        px(y0)
    );
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" font-size=\"13\" fill=\"#555555\">{}</text>",
        px(x0 + 10.0),
        px(y0 + 20.0),
        escape(caption(view))
    );
    // Labels stay inside the panel, off its caption and scale bar.
    let mut placer = Placer::new([x0 + 4.0, y0 + 4.0, x0 + PANEL_W - 4.0, y0 + PANEL_H - 4.0]);
    placer.taken.push([
        x0,
        y0,
        x0 + 10.0 + text_width(caption(view), 13.0) + 4.0,
        y0 + 26.0,
    ]);
    // Scale bar, bottom left.
    let (len, label) = scale_bar(scene.size);
    let (bx, by) = (x0 + 14.0, y0 + PANEL_H - 14.0);
    placer.taken.push([
        x0,
        by - 14.0,
        bx + len * p.scale + 10.0 + text_width(&label, 12.0),
        y0 + PANEL_H,
    ]);
    let _ = writeln!(
        out,
        "<g id=\"{v}-scale\" class=\"scale\"><title>scale bar: {}</title>",
        escape(&label)
    );
    line(out, (bx, by), (bx + len * p.scale, by), "#555555", 2.0, "");
    line(out, (bx, by - 4.0), (bx, by + 0.0), "#555555", 2.0, "");
    line(
        out,
        (bx + len * p.scale, by - 4.0),
        (bx + len * p.scale, by),
        "#555555",
        2.0,
        "",
    );
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" font-size=\"12\" fill=\"#555555\">{}</text></g>",
        px(bx + len * p.scale + 6.0),
        px(by + 4.0),
        escape(&label)
    );
    // The body, under everything else.
    body(out, scene, &p, v);
    let mut labels: Vec<Label> = Vec::new();
    // Screw axes, under the arm.
    for (j, m) in scene.joints.iter().enumerate() {
        if !shown[j] {
            continue;
        }
        let kind = kind_name(m.kind);
        let _ = writeln!(
            out,
            "<g id=\"{v}-axis-{}\" class=\"axis {kind}\" data-joint=\"{}\"><title>{}</title>",
            m.index,
            escape(&m.name),
            escape(&joint_title(scene, j))
        );
        let (a, b) = (p.at(&m.line[0]), p.at(&m.line[1]));
        let end_on = (b.0 - a.0).hypot(b.1 - a.1) < 12.0;
        let anchor = match (end_on, m.kind) {
            (true, JointKind::Prismatic) => (b.0 - 9.0, b.1 - 9.0),
            (true, _) => ((a.0 + b.0) / 2.0 + 8.0, (a.1 + b.1) / 2.0 - 8.0),
            _ => b,
        };
        labels.push(Label {
            id: format!("axis-{}", m.index),
            class: "axis",
            text: m.index.to_string(),
            font: 12.0,
            fill: if m.kind == JointKind::Prismatic {
                SLIDE
            } else {
                AXIS
            },
            anchor,
        });
        if m.kind == JointKind::Prismatic && end_on {
            // Sliding towards or away from the viewer: a solid ring.
            let _ = writeln!(
                out,
                "<circle cx=\"{}\" cy=\"{}\" r=\"9\" fill=\"none\" stroke=\"{SLIDE}\" stroke-width=\"2\"/>",
                px(a.0),
                px(a.1)
            );
        } else if m.kind == JointKind::Prismatic {
            line(out, a, b, SLIDE, 2.5, "");
            // Arrow head.
            let d = (b.0 - a.0, b.1 - a.1);
            let n = (d.0 * d.0 + d.1 * d.1).sqrt().max(1e-9);
            let (ux, uy) = (d.0 / n, d.1 / n);
            let h1 = (b.0 - 9.0 * ux - 5.0 * uy, b.1 - 9.0 * uy + 5.0 * ux);
            let h2 = (b.0 - 9.0 * ux + 5.0 * uy, b.1 - 9.0 * uy - 5.0 * ux);
            let _ = writeln!(
                out,
                "<polygon points=\"{},{} {},{} {},{}\" fill=\"{SLIDE}\"/>",
                px(b.0),
                px(b.1),
                px(h1.0),
                px(h1.1),
                px(h2.0),
                px(h2.1)
            );
        } else if end_on {
            // Seen end-on: a ring around the axis.
            axis_toward_viewer(out, ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0));
        } else {
            let dash = if m.pitch.is_some_and(|h| h.abs() > 1e-12) {
                " stroke-dasharray=\"2 3\""
            } else {
                " stroke-dasharray=\"8 4\""
            };
            line(out, a, b, AXIS, 1.8, dash);
        }
        let _ = writeln!(out, "</g>");
    }
    // Links: a segment from each link's parent (the previous link on a chain) to its origin;
    // thinner over a body.
    let rod = if scene.outlines.is_empty() { 5.0 } else { 2.5 };
    for l in &scene.links {
        let Some(parent) = l.parent else { continue };
        let (a, b) = (
            p.at(scene.links[parent].pose.translation()),
            p.at(l.pose.translation()),
        );
        let _ = writeln!(
            out,
            "<g id=\"{v}-link-{}\" class=\"link\"><title>link {}: origin {}</title>",
            id_part(&l.name),
            escape(&l.name),
            vec3(l.pose.translation())
        );
        line(out, a, b, LINK, rod, "");
        let _ = writeln!(out, "</g>");
    }
    // Frames: the base and the tip, or the base and every leaf of a tree.
    for f in &scene.frames {
        let triad = triad(scene, f);
        let (id, what) = match f.role {
            FrameRole::Base => ("base-frame".to_string(), "base"),
            FrameRole::Tip => ("tip-frame".to_string(), "tip"),
            FrameRole::Leaf => (format!("leaf-{}", id_part(&f.name)), "leaf"),
        };
        let _ = writeln!(
            out,
            "<g id=\"{v}-{id}\" class=\"frame\"><title>{what} frame: link {} at {}</title>",
            escape(&f.name),
            vec3(f.pose.translation())
        );
        let o = p.at(f.pose.translation());
        for (k, colour) in XYZ.iter().enumerate() {
            let end = p.at(&(f.pose.translation() + f.pose.rotation().column(k) * triad));
            line(out, o, end, colour, 2.5, "");
        }
        let _ = writeln!(out, "</g>");
    }
    // Joints on top.
    for (j, m) in scene.joints.iter().enumerate() {
        let _ = writeln!(
            out,
            "<g id=\"{v}-joint-{}\" class=\"joint {}\" data-joint=\"{}\"><title>{}</title>",
            m.index,
            kind_name(m.kind),
            escape(&m.name),
            escape(&joint_title(scene, j))
        );
        joint_mark(out, m.kind, p.at(&m.origin));
        let _ = writeln!(out, "</g>");
    }
    // Names: the ends (a chain's tip, a tree's leaves) first, then every other link.
    let ends = scene
        .frames
        .iter()
        .filter(|f| matches!(f.role, FrameRole::Tip | FrameRole::Leaf));
    let mut named: Vec<(&str, (f64, f64))> = match options.labels {
        Labels::None => Vec::new(),
        _ => ends
            .map(|f| (f.name.as_str(), p.at(f.pose.translation())))
            .collect(),
    };
    if options.labels == Labels::All {
        for l in &scene.links {
            if !named.iter().any(|(n, _)| *n == l.name) {
                named.push((&l.name, p.at(l.pose.translation())));
            }
        }
    }
    labels.extend(named.into_iter().map(|(name, anchor)| Label {
        id: id_part(name),
        class: "name",
        text: name.to_string(),
        font: 11.0,
        fill: "#222222",
        anchor,
    }));
    // Labels on top, each placed off the others (a leader line when moved off its point),
    // or left out when there is no room.
    let _ = writeln!(out, "<g id=\"{v}-labels\" class=\"labels\">");
    for l in &labels {
        let w = text_width(&l.text, l.font);
        let Some(at) = placer.place(l.anchor, w, l.font) else {
            continue;
        };
        if let Some((a, b)) = at.leader {
            line(out, a, b, "#888888", 0.8, "");
        }
        let _ = writeln!(
            out,
            "<text id=\"{v}-label-{}\" class=\"label {}\" x=\"{}\" y=\"{}\" font-size=\"{}\" fill=\"{}\"{HALO}>{}</text>",
            l.id,
            l.class,
            px(at.x),
            px(at.baseline),
            l.font,
            l.fill,
            escape(&l.text)
        );
    }
    if placer.dropped > 0 {
        let note = format!(
            "{} label{} left out for room",
            placer.dropped,
            if placer.dropped == 1 { "" } else { "s" }
        );
        let _ = writeln!(
            out,
            "<text class=\"dropped\" x=\"{}\" y=\"{}\" font-size=\"11\" fill=\"#888888\" text-anchor=\"end\">{note}</text>",
            px(x0 + PANEL_W - 8.0),
            px(y0 + PANEL_H - 8.0)
        );
    }
    let _ = writeln!(out, "</g>");
    let _ = writeln!(out, "</g>");
}

/// A triad's length: 12 % of the picture for the base and a chain's tip, 5 % for a tree's
/// leaves (a hand's fingertips are centimetres apart).
fn triad(scene: &Scene, f: &crate::scene::FrameMark) -> f64 {
    match f.role {
        FrameRole::Leaf => 0.05 * scene.size,
        _ => 0.12 * scene.size,
    }
}

/// An upper bound on the width (px) of `text` at `font` px in the sans-serif fonts a browser
/// uses for "Helvetica, Arial, sans-serif" (DejaVu Sans, the widest of them where Helvetica
/// and Arial are missing; Liberation Sans; Arial): per character, the largest advance of its
/// class in those fonts, in ems. Tested against a browser's measure of every label.
pub fn text_width(text: &str, font: f64) -> f64 {
    text.chars()
        .map(|c| match c {
            'i' | 'j' | 'l' | '.' | ',' | ':' | ';' | '\'' | '|' | '!' | 'I' => 0.33,
            'f' | 'r' | 't' | ' ' | '(' | ')' | '[' | ']' | '-' => 0.45,
            'm' | 'w' | 'M' | 'W' | '@' | '%' => 1.0,
            c if c.is_ascii_uppercase() => 0.8,
            c if c.is_ascii() => 0.66,
            _ => 1.0,
        })
        .sum::<f64>()
        * font
}

/// Where a label went: the start of its baseline, and the leader line from its point when it
/// was moved away from it.
struct Placed {
    x: f64,
    baseline: f64,
    leader: Option<((f64, f64), (f64, f64))>,
}

/// Labels placed so far in a panel, as boxes (x0, y0, x1, y1): a new label goes to the first
/// free spot around its point — right, below right, above right, below, above, left, … at
/// growing distances — inside the panel; none free, it is left out and counted.
struct Placer {
    taken: Vec<[f64; 4]>,
    bounds: [f64; 4],
    dropped: usize,
}

impl Placer {
    /// How far labels may move from their point (px), nearest first.
    const RADII: [f64; 6] = [3.0, 10.0, 20.0, 34.0, 52.0, 76.0];
    /// A label's box above and below its baseline, in ems (every font above: ascent ≤ 0.93,
    /// descent ≤ 0.24).
    const ASCENT: f64 = 0.95;
    const DESCENT: f64 = 0.25;
    /// Space kept between two labels (px).
    const GAP: f64 = 3.0;

    fn new(bounds: [f64; 4]) -> Self {
        Self {
            taken: Vec::new(),
            bounds,
            dropped: 0,
        }
    }

    fn place(&mut self, (ax, ay): (f64, f64), w: f64, font: f64) -> Option<Placed> {
        let h = (Self::ASCENT + Self::DESCENT) * font;
        const D: f64 = std::f64::consts::FRAC_1_SQRT_2;
        let dirs = [
            (1.0, 0.0),
            (D, D),
            (D, -D),
            (0.0, 1.0),
            (0.0, -1.0),
            (-1.0, 0.0),
            (-D, D),
            (-D, -D),
        ];
        let [bx0, by0, bx1, by1] = self.bounds;
        for r in Self::RADII {
            for (dx, dy) in dirs {
                let x0 = match dx {
                    d if d > 0.0 => ax + r * d,
                    d if d < 0.0 => ax + r * d - w,
                    _ => ax - w / 2.0,
                };
                let y0 = match dy {
                    d if d > 0.0 => ay + r * d,
                    d if d < 0.0 => ay + r * d - h,
                    _ => ay - h / 2.0,
                };
                let b = [x0, y0, x0 + w, y0 + h];
                let inside = b[0] >= bx0 && b[1] >= by0 && b[2] <= bx1 && b[3] <= by1;
                let free = self.taken.iter().all(|t| {
                    b[2] + Self::GAP <= t[0]
                        || t[2] + Self::GAP <= b[0]
                        || b[3] + Self::GAP <= t[1]
                        || t[3] + Self::GAP <= b[1]
                });
                if inside && free {
                    self.taken.push(b);
                    let leader = (r > 10.0)
                        .then(|| ((ax, ay), (ax.clamp(b[0], b[2]), ay.clamp(b[1], b[3]))));
                    return Some(Placed {
                        x: x0,
                        baseline: y0 + Self::ASCENT * font,
                        leader,
                    });
                }
            }
        }
        self.dropped += 1;
        None
    }
}

/// The legend's entries: (width in px, what to draw at (x, y)).
type Entry = (f64, fn(&mut String, f64, f64));

const LEGEND: [Entry; 7] = [
    (78.0, |o, x, y| {
        line(o, (x, y), (x + 26.0, y), LINK, 5.0, "");
        legend_text(o, x + 32.0, y, "link");
    }),
    (92.0, |o, x, y| {
        joint_mark(o, JointKind::Revolute, (x + 6.0, y));
        legend_text(o, x + 18.0, y, "revolute");
    }),
    (104.0, |o, x, y| {
        joint_mark(o, JointKind::Continuous, (x + 6.0, y));
        legend_text(o, x + 18.0, y, "continuous");
    }),
    (92.0, |o, x, y| {
        joint_mark(o, JointKind::Prismatic, (x + 6.0, y));
        legend_text(o, x + 18.0, y, "prismatic");
    }),
    (292.0, |o, x, y| {
        line(
            o,
            (x, y),
            (x + 30.0, y),
            AXIS,
            1.8,
            " stroke-dasharray=\"8 4\"",
        );
        axis_toward_viewer(o, (x + 44.0, y));
        legend_text(o, x + 60.0, y, "screw axis S_i(q) (ring: towards you)");
    }),
    (100.0, |o, x, y| {
        line(o, (x, y), (x + 26.0, y), SLIDE, 2.5, "");
        legend_text(o, x + 32.0, y, "slide axis");
    }),
    (130.0, |o, x, y| {
        for (k, c) in XYZ.iter().enumerate() {
            let x = x + 14.0 * k as f64;
            line(o, (x, y + 6.0), (x + 10.0, y - 6.0), c, 2.5, "");
        }
        legend_text(o, x + 46.0, y, "frames x y z");
    }),
];

/// The legend's entry for helical joints, shown when a picture has one.
const HELICAL: Entry = (170.0, |o, x, y| {
    joint_mark(o, JointKind::Helical, (x + 6.0, y));
    legend_text(o, x + 18.0, y, "helical (dotted axis)");
});

/// The legend's entry for the body, shown when a picture has one.
const BODY_ENTRY: Entry = (150.0, |o, x, y| {
    let _ = writeln!(
        o,
        "<polygon points=\"{},{} {},{} {},{} {},{}\" fill=\"{}\" stroke=\"{}\" stroke-width=\"0.8\"/>",
        px(x),
        px(y - 6.0),
        px(x + 20.0),
        px(y - 8.0),
        px(x + 24.0),
        px(y + 6.0),
        px(x + 3.0),
        px(y + 7.0),
        hex(BODY, 1.0),
        hex(BODY, 0.55)
    );
    legend_text(o, x + 32.0, y, "body (silhouettes)");
});

/// The legend's entries beyond the fixed ones a picture needs.
#[derive(Debug, Clone, Copy)]
struct Extras {
    helical: bool,
    body: bool,
}

/// The legend's entries for a scene.
fn entries(extras: Extras) -> impl Iterator<Item = Entry> {
    extras
        .body
        .then_some(BODY_ENTRY)
        .into_iter()
        .chain(LEGEND)
        .chain(extras.helical.then_some(HELICAL))
}

fn legend_text(out: &mut String, x: f64, y: f64, s: &str) {
    let _ = writeln!(
        out,
        "<text x=\"{}\" y=\"{}\" font-size=\"12\" fill=\"#333333\">{s}</text>",
        px(x),
        px(y + 4.0)
    );
}

/// A screw axis seen end-on (pointing at the viewer): a dashed ring around it.
fn axis_toward_viewer(out: &mut String, c: (f64, f64)) {
    let _ = writeln!(
        out,
        "<circle cx=\"{}\" cy=\"{}\" r=\"11\" fill=\"none\" stroke=\"{AXIS}\" stroke-width=\"1.8\" stroke-dasharray=\"3 3\"/>",
        px(c.0),
        px(c.1)
    );
}

/// The legend from (14, y), wrapped to lines of `width`; returns the rows used.
fn legend(out: &mut String, y: f64, width: f64, extras: Extras) {
    let _ = writeln!(out, "<g id=\"legend\" class=\"legend\">");
    let (mut x, mut y) = (14.0, y);
    for (w, draw) in entries(extras) {
        if x + w > width - 10.0 && x > 14.0 {
            x = 14.0;
            y += LEGEND_ROW;
        }
        draw(out, x, y);
        x += w;
    }
    let _ = writeln!(out, "</g>");
}

/// How many legend rows a sheet of `width` needs.
fn legend_rows(width: f64, extras: Extras) -> usize {
    let (mut x, mut rows) = (14.0, 1);
    for (w, _) in entries(extras) {
        if x + w > width - 10.0 && x > 14.0 {
            x = 14.0;
            rows += 1;
        }
        x += w;
    }
    rows
}

/// The width of a caption character at 15 px (Helvetica's average, digits and commas
/// included, with a margin).
const CAPTION_CHAR_W: f64 = 8.0;
/// The distance between two caption lines.
const CAPTION_LINE: f64 = 18.0;

/// `text` cut into lines of at most `max` characters, at spaces (a word longer than a line
/// stands alone).
fn wrap(text: &str, max: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > max.max(1) {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    lines.push(line);
    lines
}

/// The SVG document of `scene` in `views` with the default names and axes
/// ([`Options::default`]); [`render_with`] chooses them.
pub fn render(scene: &Scene, views: &[View]) -> String {
    let options = Options {
        views: views.to_vec(),
        ..Options::default()
    };
    // The default axes (`Axes::Auto`) name no joint, so they cannot be refused.
    render_with(scene, &options).unwrap_or_default()
}

/// The SVG document of `scene` as `options` ask (one panel, or the four of `View::ALL` in a
/// 2 × 2 sheet), with a legend and a caption naming the robot, the chain and q: the body's
/// silhouettes (when the scene has one), the skeleton, the screw axes asked, frames, and the
/// names asked placed without overlap. An error names an axis asked of a joint not drawn.
pub fn render_with(scene: &Scene, options: &Options) -> Result<String, screwkit_service::Error> {
    let names: Vec<&str> = scene.joints.iter().map(|j| j.name.as_str()).collect();
    let chain = scene.frames.iter().any(|f| f.role == FrameRole::Tip);
    let shown =
        options
            .axes
            .shown(&names, chain)
            .map_err(|message| screwkit_service::Error::Option {
                name: "axes",
                message,
            })?;
    let views = &options.views;
    let cols = if views.len() > 1 { 2 } else { 1 };
    let rows = views.len().div_ceil(cols);
    let width = cols as f64 * PANEL_W + (cols as f64 + 1.0) * 10.0;
    let helical = scene.joints.iter().any(|j| j.kind == JointKind::Helical);
    let extras = Extras {
        helical,
        body: !scene.outlines.is_empty(),
    };
    let legend_h = legend_rows(width, extras) as f64 * LEGEND_ROW + 16.0;
    let q: Vec<String> = scene.q.iter().map(|x| num(*x)).collect();
    let caption = format!("{}: {}, q = [{}]", scene.robot, scene.subject, q.join(", "));
    // The caption wrapped to the sheet's width (a single 580 px panel cut a 7-joint one).
    let mut caption_lines = wrap(&caption, ((width - 20.0) / CAPTION_CHAR_W) as usize);
    if let Some(first) = scene.problems.first() {
        let more = match scene.problems.len() {
            1 => String::new(),
            n => format!(" (and {} more)", n - 1),
        };
        caption_lines.extend(wrap(
            &format!("not drawn: {first}{more}"),
            ((width - 20.0) / CAPTION_CHAR_W) as usize,
        ));
    }
    let extra = (caption_lines.len() as f64 - 1.0) * CAPTION_LINE;
    let height = rows as f64 * PANEL_H + (rows as f64 + 1.0) * 10.0 + 28.0 + extra + legend_h;
    let mut out = String::new();
    let _ = writeln!(out, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>");
    let _ = writeln!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"Helvetica, Arial, sans-serif\">",
        w = px(width),
        h = px(height)
    );
    let _ = writeln!(out, "<title>{}</title>", escape(&caption));
    let _ = writeln!(
        out,
        "<desc>Drawn by screwkit: the skeleton through the link origins, each joint's screw axis S_i(q) (the columns of the space Jacobian at q), the base and tip frames, or the base and every leaf of a tree (x red, y green, z blue). Metres, radians.</desc>"
    );
    let _ = writeln!(
        out,
        "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>"
    );
    for (k, l) in caption_lines.iter().enumerate() {
        let _ = writeln!(
            out,
            "<text x=\"10\" y=\"{}\" font-size=\"15\" fill=\"#222222\">{}</text>",
            px(22.0 + k as f64 * CAPTION_LINE),
            escape(l)
        );
    }
    for (i, view) in views.iter().enumerate() {
        let (c, r) = (i % cols, i / cols);
        let x0 = 10.0 + c as f64 * (PANEL_W + 10.0);
        let y0 = 38.0 + extra + r as f64 * (PANEL_H + 10.0);
        panel(&mut out, scene, options, &shown, *view, x0, y0);
    }
    legend(
        &mut out,
        height - legend_h + LEGEND_ROW / 2.0 + 4.0,
        width,
        extras,
    );
    let _ = writeln!(out, "</svg>");
    Ok(out)
}
