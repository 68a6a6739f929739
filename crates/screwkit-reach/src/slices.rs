//! The picture of a map: its reachability index on the three planes through the base
//! (z = 0, y = 0, x = 0), drawn by [`screwkit_draw::heatmap`].

use screwkit_draw::heatmap::{self, Panel};

use crate::MapFile;

/// The SVG of `map`'s index on the planes through the base. A plane the grid does not
/// contain (bounds that leave the base out) is replaced by the grid's middle layer, and its
/// title says which. Needs a whole map (not a shard).
pub fn svg(map: &MapFile) -> String {
    let g = &map.grid;
    let [_, ny, nz] = g.shape;
    let at = |i: usize, j: usize, k: usize| map.index[(i * ny + j) * nz + k];
    let layer = |axis: usize| g.zero_layer(axis).unwrap_or(g.shape[axis] / 2);
    let coord = |axis: usize, i: usize| g.origin[axis] + i as f64 * g.resolution;
    let names = ["x", "y", "z"];
    // (fixed axis, horizontal axis, vertical axis)
    let panels: Vec<Panel> = [(2, 0, 1), (1, 0, 2), (0, 1, 2)]
        .iter()
        .map(|&(fixed, h, v)| {
            let l = layer(fixed);
            let (nh, nv) = (g.shape[h], g.shape[v]);
            let mut values = vec![f64::NAN; nh * nv];
            for r in 0..nv {
                for c in 0..nh {
                    let mut ijk = [0; 3];
                    ijk[fixed] = l;
                    ijk[h] = c;
                    ijk[v] = r;
                    values[r * nh + c] = at(ijk[0], ijk[1], ijk[2]);
                }
            }
            Panel {
                title: format!("{} = {:.3} m", names[fixed], coord(fixed, l)),
                x_label: names[h].into(),
                y_label: names[v].into(),
                x0: g.origin[h],
                y0: g.origin[v],
                step: g.resolution,
                nx: nh,
                ny: nv,
                values,
            }
        })
        .collect();
    let robot = map.meta["robot"].as_str().unwrap_or("");
    let title = format!(
        "{robot}: reachability index ({} orientations, {} voxels of {} cm, {} IK)",
        map.k,
        g.len(),
        g.resolution * 100.0,
        map.meta["solver"].as_str().unwrap_or("")
    );
    heatmap::render(&title, &panels, "reachability index (reached / K)")
}
