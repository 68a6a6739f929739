//! Heat-map panels as SVG (the slices of a reachability map): each panel a grid of cells
//! coloured by a value in [0, 1] on the viridis scale (0 light grey, NaN white),
//! with its axes in metres, a cross at the origin and one colour bar for the sheet.
//! Deterministic: the same panels give the same bytes. Knows nothing of robots or maps.

use std::fmt::Write;

use crate::svg::escape;

/// One panel: `values[r * nx + c]` is the cell whose centre is (x0 + c·step, y0 + r·step);
/// NaN is drawn white. Row 0 is drawn at the bottom (y up).
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// Title above the panel.
    pub title: String,
    /// Name of the horizontal axis ("x", …).
    pub x_label: String,
    /// Name of the vertical axis.
    pub y_label: String,
    /// Centre of the first column (m).
    pub x0: f64,
    /// Centre of the first row (m).
    pub y0: f64,
    /// Cell size (m).
    pub step: f64,
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// Values in [0, 1] (clamped), NaN for none.
    pub values: Vec<f64>,
}

/// Viridis (matplotlib's, 9 stops, linear between them) at t ∈ [0, 1].
pub fn viridis(t: f64) -> (u8, u8, u8) {
    const STOPS: [(f64, f64, f64); 9] = [
        (68.0, 1.0, 84.0),
        (71.0, 44.0, 122.0),
        (59.0, 81.0, 139.0),
        (44.0, 113.0, 142.0),
        (33.0, 144.0, 141.0),
        (39.0, 173.0, 129.0),
        (92.0, 200.0, 99.0),
        (170.0, 220.0, 50.0),
        (253.0, 231.0, 37.0),
    ];
    let x = t.clamp(0.0, 1.0) * 8.0;
    let i = (x.floor() as usize).min(7);
    let f = x - i as f64;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let mix = |p: f64, q: f64| (p + (q - p) * f).round() as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn colour(v: f64) -> String {
    if v <= 0.0 {
        return "#e6e6e6".into();
    }
    let (r, g, b) = viridis(v);
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// Panel drawing size (px).
const SIZE: f64 = 320.0;
const MARGIN: f64 = 46.0;

/// The sheet: `title` on top, the panels side by side, a colour bar labelled `scale` (0 → 1).
pub fn render(title: &str, panels: &[Panel], scale: &str) -> String {
    let width = MARGIN + panels.len() as f64 * (SIZE + MARGIN) + 70.0;
    let height = SIZE + 2.0 * MARGIN + 40.0;
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{width:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {width:.0} {height:.0}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{MARGIN}\" y=\"22\" font-size=\"15\">{}</text>\n",
        escape(title)
    );
    for (i, p) in panels.iter().enumerate() {
        let left = MARGIN + i as f64 * (SIZE + MARGIN);
        panel(&mut s, p, left, 40.0 + MARGIN * 0.5);
    }
    // Colour bar.
    let x = width - 60.0;
    let (top, h) = (40.0 + MARGIN * 0.5, SIZE);
    let _ = writeln!(s, "<g id=\"colour-bar\">");
    for k in 0..50 {
        let t = 1.0 - (k as f64 + 0.5) / 50.0;
        let _ = writeln!(
            s,
            "<rect x=\"{x:.1}\" y=\"{:.2}\" width=\"14\" height=\"{:.2}\" fill=\"{}\"/>",
            top + k as f64 * h / 50.0,
            h / 50.0 + 0.3,
            colour(t.max(1e-9))
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\">1</text>\n<text x=\"{:.1}\" y=\"{:.1}\">0</text>\n<text x=\"{:.1}\" y=\"{:.1}\" transform=\"rotate(-90 {:.1} {:.1})\" text-anchor=\"middle\">{}</text>\n</g>",
        x + 18.0,
        top + 10.0,
        x + 18.0,
        top + h,
        x + 40.0,
        top + h / 2.0,
        x + 40.0,
        top + h / 2.0,
        escape(scale)
    );
    s.push_str("</svg>\n");
    s
}

fn panel(s: &mut String, p: &Panel, left: f64, top: f64) {
    let n = p.nx.max(p.ny).max(1) as f64;
    let cell = SIZE / n;
    // Centre the grid in the square.
    let ox = left + (SIZE - p.nx as f64 * cell) / 2.0;
    let oy = top + (SIZE - p.ny as f64 * cell) / 2.0;
    let _ = writeln!(
        s,
        "<g class=\"panel\" id=\"panel-{}{}\">\n<text x=\"{left:.1}\" y=\"{:.1}\">{}</text>\n<rect x=\"{left:.1}\" y=\"{top:.1}\" width=\"{SIZE}\" height=\"{SIZE}\" fill=\"none\" stroke=\"#999\"/>",
        escape(&p.x_label),
        escape(&p.y_label),
        top - 6.0,
        escape(&p.title)
    );
    // The grid's extent in the colour of 0, then every other cell (0 cells are most of a
    // map: one rectangle for all of them keeps the file small).
    let _ = writeln!(
        s,
        "<rect class=\"zero\" x=\"{ox:.2}\" y=\"{oy:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{}\"/>",
        p.nx as f64 * cell,
        p.ny as f64 * cell,
        colour(0.0)
    );
    for r in 0..p.ny {
        for c in 0..p.nx {
            let v = p.values[r * p.nx + c];
            if v <= 0.0 {
                continue;
            }
            let fill = if v.is_nan() {
                "white".into()
            } else {
                colour(v)
            };
            let _ = writeln!(
                s,
                "<rect x=\"{:.2}\" y=\"{:.2}\" width=\"{:.2}\" height=\"{:.2}\" fill=\"{fill}\"/>",
                ox + c as f64 * cell,
                oy + (p.ny - 1 - r) as f64 * cell,
                cell + 0.05,
                cell + 0.05,
            );
        }
    }
    // Axes: coordinates of the panel's edges and the origin cross.
    let to_px = |x: f64, y: f64| {
        (
            ox + (x - p.x0) / p.step * cell + cell / 2.0,
            oy + (p.ny as f64 - 0.5 - (y - p.y0) / p.step) * cell,
        )
    };
    let (x_lo, x_hi) = (p.x0 - p.step / 2.0, p.x0 + (p.nx as f64 - 0.5) * p.step);
    let (y_lo, y_hi) = (p.y0 - p.step / 2.0, p.y0 + (p.ny as f64 - 0.5) * p.step);
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\">{x_lo:.2}</text>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{x_hi:.2}</text>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{} (m)</text>",
        ox,
        top + SIZE + 14.0,
        ox + p.nx as f64 * cell,
        top + SIZE + 14.0,
        left + SIZE / 2.0,
        top + SIZE + 28.0,
        escape(&p.x_label)
    );
    let _ = writeln!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{y_lo:.2}</text>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\">{y_hi:.2}</text>\n<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\" transform=\"rotate(-90 {:.1} {:.1})\">{} (m)</text>",
        left - 4.0,
        oy + p.ny as f64 * cell,
        left - 4.0,
        oy + 10.0,
        left - 34.0,
        top + SIZE / 2.0,
        left - 34.0,
        top + SIZE / 2.0,
        escape(&p.y_label)
    );
    if (x_lo..=x_hi).contains(&0.0) && (y_lo..=y_hi).contains(&0.0) {
        let (cx, cy) = to_px(0.0, 0.0);
        let _ = writeln!(
            s,
            "<g class=\"origin\" stroke=\"#d7191c\" stroke-width=\"1.5\"><line x1=\"{:.2}\" y1=\"{cy:.2}\" x2=\"{:.2}\" y2=\"{cy:.2}\"/><line x1=\"{cx:.2}\" y1=\"{:.2}\" x2=\"{cx:.2}\" y2=\"{:.2}\"/><title>the base origin</title></g>",
            cx - 6.0,
            cx + 6.0,
            cy - 6.0,
            cy + 6.0
        );
    }
    s.push_str("</g>\n");
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_colours_and_the_origin() {
        let p = Panel {
            title: "z = 0".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            x0: -0.1,
            y0: -0.1,
            step: 0.1,
            nx: 3,
            ny: 3,
            values: vec![0.0, 0.5, 1.0, f64::NAN, 0.25, 0.75, 0.1, 0.2, 0.3],
        };
        let svg = render("map", &[p], "reachability index");
        // 7 cells above 0 and the NaN one (white) drawn, the 0 one by the grid's background;
        // plus 50 colour-bar rects and the frame.
        let cells = svg.matches("<rect x=").count();
        assert_eq!(cells, 8 + 50 + 1);
        // The sheet's background and the NaN cell.
        assert_eq!(svg.matches("fill=\"white\"/>").count(), 2);
        assert!(svg.contains("class=\"zero\"") && svg.contains("#e6e6e6"));
        assert!(svg.contains("#fde725")); // viridis(1)
        assert!(svg.contains("class=\"origin\""));
        assert_eq!(viridis(0.0), (68, 1, 84));
        assert_eq!(viridis(0.5), (33, 144, 141));
        let again = render(
            "map",
            &[Panel {
                title: "z = 0".into(),
                x_label: "x".into(),
                y_label: "y".into(),
                x0: -0.1,
                y0: -0.1,
                step: 0.1,
                nx: 3,
                ny: 3,
                values: vec![0.0, 0.5, 1.0, f64::NAN, 0.25, 0.75, 0.1, 0.2, 0.3],
            }],
            "reachability index",
        );
        assert_eq!(svg, again);
        assert!(roxmltree::Document::parse(&svg).is_ok());
    }
}
