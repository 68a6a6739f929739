//! Line plots of joint values as SVG (a path's joints against its place or time): one panel
//! per joint, stacked, sharing the horizontal axis; each panel's vertical range is its own
//! values' (padded), with the joint's limits drawn as dashed lines when they lie within it.
//! Deterministic: the same input gives the same bytes. Knows nothing of robots or paths.

use std::fmt::Write;

use crate::svg::escape;

/// What [`joints`] plots.
#[derive(Debug, Clone, Copy)]
pub struct JointPlot<'a> {
    /// The title on top.
    pub title: &'a str,
    /// The joints' names (n).
    pub names: &'a [String],
    /// The horizontal values (K, increasing): the samples' places or times.
    pub x: &'a [f64],
    /// The name of the horizontal axis.
    pub x_label: &'a str,
    /// The joint values, K × n row-major.
    pub q: &'a [f64],
    /// Each joint's (lower, upper) limits, when known.
    pub limits: Option<(&'a [f64], &'a [f64])>,
}

/// The horizontal axis of a path's joints against its samples' places.
pub const PLACE_LABEL: &str = "place on the path (segment + fraction of it)";

/// The horizontal axis of a timed path's joints.
pub const TIME_LABEL: &str = "time (s)";

/// The title of `robot`'s joint plot.
pub fn title(robot: &str) -> String {
    format!("{robot}: joint values")
}

/// Panel drawing size (px).
const WIDTH: f64 = 640.0;
const PANEL: f64 = 90.0;
const GAP: f64 = 34.0;
const LEFT: f64 = 60.0;
const TOP: f64 = 58.0;
/// Colours of the joints' lines (Okabe–Ito, readable by colour-blind eyes), in turn.
const COLOURS: [&str; 7] = [
    "#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9", "#000000",
];

/// A "nice" tick step near `span / 4` (1, 2 or 5 × 10ᵏ).
fn tick_step(span: f64) -> f64 {
    let raw = (span / 4.0).max(1e-12);
    let k = 10f64.powf(raw.log10().floor());
    let m = raw / k;
    k * if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    }
}

/// A tick's label: as few decimals as its step needs.
fn tick_label(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        s
    }
}

/// The SVG plot of `p`: an error for sizes that do not agree, non-finite or decreasing x,
/// or no sample.
pub fn joints(p: &JointPlot) -> Result<String, String> {
    let n = p.names.len();
    let k = p.x.len();
    if n == 0 || k == 0 {
        return Err("nothing to plot: no joint or no sample".into());
    }
    if p.q.len() != k * n {
        return Err(format!(
            "q has {} values: expected {k} samples × {n} joints",
            p.q.len()
        ));
    }
    if let Some((lo, hi)) = p.limits {
        if lo.len() != n || hi.len() != n {
            return Err(format!("limits: expected {n} lower and upper values"));
        }
    }
    if p.x.iter().chain(p.q).any(|v| !v.is_finite()) {
        return Err("a value to plot is not finite".into());
    }
    if p.x.windows(2).any(|w| w[1] < w[0]) {
        return Err("the horizontal values must not decrease".into());
    }
    let (x0, x1) = (p.x[0], p.x[k - 1]);
    let xs = if x1 > x0 { x1 - x0 } else { 1.0 };
    let height = TOP + n as f64 * (PANEL + GAP) + 30.0;
    let total = LEFT + WIDTH + 30.0;
    let mut s = String::new();
    let _ = write!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"{total:.0}\" height=\"{height:.0}\" viewBox=\"0 0 {total:.0} {height:.0}\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<text x=\"{LEFT}\" y=\"24\" font-size=\"15\">{}</text>\n",
        escape(p.title)
    );
    let px = |x: f64| LEFT + (x - x0) / xs * WIDTH;
    let xstep = tick_step(xs);
    for j in 0..n {
        let top = TOP + j as f64 * (PANEL + GAP);
        let values = (0..k).map(|r| p.q[r * n + j]);
        let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        let span = (hi - lo).max(0.05);
        let mid = 0.5 * (hi + lo);
        let (y0, y1) = (mid - 0.6 * span, mid + 0.6 * span);
        let py = |v: f64| top + PANEL - (v - y0) / (y1 - y0) * PANEL;
        let colour = COLOURS[j % COLOURS.len()];
        let _ = write!(
            s,
            "<g id=\"joint-{j}\" class=\"joint\"><title>{}</title>\n<rect x=\"{LEFT}\" y=\"{top:.1}\" width=\"{WIDTH}\" height=\"{PANEL}\" fill=\"none\" stroke=\"#888\"/>\n<text x=\"{LEFT}\" y=\"{:.1}\" fill=\"{colour}\">{}</text>\n",
            escape(&p.names[j]),
            top - 6.0,
            escape(&p.names[j])
        );
        let ystep = tick_step(y1 - y0);
        let mut t = (y0 / ystep).ceil() * ystep;
        while t <= y1 {
            let y = py(t);
            let _ = writeln!(
                s,
                "<line x1=\"{LEFT}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#eee\"/><text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"end\" font-size=\"10\">{}</text>",
                LEFT + WIDTH,
                LEFT - 4.0,
                y + 3.0,
                tick_label(t, ystep)
            );
            t += ystep;
        }
        if let Some((lower, upper)) = p.limits {
            for (which, v) in [("lower", lower[j]), ("upper", upper[j])] {
                if v.is_finite() && v > y0 && v < y1 {
                    let y = py(v);
                    let _ = writeln!(
                        s,
                        "<line class=\"limit {which}\" x1=\"{LEFT}\" y1=\"{y:.1}\" x2=\"{:.1}\" y2=\"{y:.1}\" stroke=\"#c00\" stroke-dasharray=\"5,4\"><title>{which} limit {v}</title></line>",
                        LEFT + WIDTH
                    );
                }
            }
        }
        let mut d = String::new();
        for r in 0..k {
            let _ = write!(
                d,
                "{}{:.2},{:.2}",
                if r == 0 { "M" } else { " L" },
                px(p.x[r]),
                py(p.q[r * n + j])
            );
        }
        let _ = writeln!(
            s,
            "<path d=\"{d}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"1.6\"/>\n</g>"
        );
    }
    let bottom = TOP + n as f64 * (PANEL + GAP) - GAP;
    let mut t = (x0 / xstep).ceil() * xstep;
    while t <= x1 + 1e-9 * xs {
        let x = px(t);
        let _ = writeln!(
            s,
            "<line x1=\"{x:.1}\" y1=\"{bottom:.1}\" x2=\"{x:.1}\" y2=\"{:.1}\" stroke=\"#888\"/><text x=\"{x:.1}\" y=\"{:.1}\" text-anchor=\"middle\" font-size=\"10\">{}</text>",
            bottom + 4.0,
            bottom + 15.0,
            tick_label(t, xstep)
        );
        t += xstep;
    }
    let _ = write!(
        s,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\">{}</text>\n</svg>\n",
        LEFT + WIDTH * 0.5,
        bottom + 30.0,
        escape(p.x_label)
    );
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A line from (0, 0) to (2, 1) in joint a lands on the panel's corners as the axes say:
    /// its first point at the left edge, its last at the right, the two ends 1.0 apart in
    /// the panel's scale; a limit inside the range is drawn, one outside is not.
    #[test]
    fn the_points_land_where_the_axes_say() {
        let names = vec!["a".to_string(), "b".to_string()];
        let x = [0.0, 1.0, 2.0];
        let q = [0.0, 5.0, 0.5, 5.0, 1.0, 5.0];
        let lower = [-0.1, -10.0];
        let upper = [10.0, 10.0];
        let svg = joints(&JointPlot {
            title: "t",
            names: &names,
            x: &x,
            x_label: "place",
            q: &q,
            limits: Some((&lower, &upper)),
        })
        .unwrap();
        let first = svg.find("<path d=\"M").unwrap();
        let d: Vec<(f64, f64)> = svg[first + 10..]
            .split('"')
            .next()
            .unwrap()
            .split(" L")
            .map(|p| {
                let (a, b) = p.split_once(',').unwrap();
                (a.parse().unwrap(), b.parse().unwrap())
            })
            .collect();
        assert_eq!(d.len(), 3);
        assert_eq!((d[0].0, d[2].0), (LEFT, LEFT + WIDTH));
        // The range 0 … 1 padded to −0.1 … 1.1: the ends at 1/12 and 11/12 of the panel.
        assert!(
            (d[0].1 - (TOP + PANEL * (1.0 - 0.1 / 1.2))).abs() < 0.01,
            "{d:?}"
        );
        assert!(
            (d[2].1 - (TOP + PANEL * (1.0 - 1.1 / 1.2))).abs() < 0.01,
            "{d:?}"
        );
        assert!((d[1].1 - 0.5 * (d[0].1 + d[2].1)).abs() < 0.01);
        assert_eq!(svg.matches("class=\"limit").count(), 0, "{svg}");
        let inside = [0.2, -10.0];
        let svg = joints(&JointPlot {
            title: "t",
            names: &names,
            x: &x,
            x_label: "place",
            q: &q,
            limits: Some((&inside, &upper)),
        })
        .unwrap();
        assert_eq!(svg.matches("class=\"limit lower\"").count(), 1);
    }

    #[test]
    fn bad_input_is_refused() {
        let names = vec!["a".to_string()];
        let plot = |x: &[f64], q: &[f64]| {
            joints(&JointPlot {
                title: "t",
                names: &names,
                x,
                x_label: "s",
                q,
                limits: None,
            })
        };
        assert!(plot(&[0.0, 1.0], &[0.0])
            .unwrap_err()
            .contains("expected 2"));
        assert!(plot(&[1.0, 0.0], &[0.0, 1.0])
            .unwrap_err()
            .contains("decrease"));
        assert!(plot(&[0.0, f64::NAN], &[0.0, 1.0])
            .unwrap_err()
            .contains("finite"));
        assert!(plot(&[], &[]).is_err());
        // One sample: drawn (a single point), not refused.
        assert!(plot(&[0.0], &[0.3]).is_ok());
    }
}
