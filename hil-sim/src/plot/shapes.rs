//! Lane and zone geometry of the trajectory figure: bands, edges and centrelines.

use super::span::{ok, ok_point};
use super::PlotInput;

/// Lane and zone geometry in map coordinates, ready to draw.
pub(super) struct MapShapes {
    /// Per lane: its id and shape.
    pub(super) lanes: Vec<(u8, LaneShape)>,
    pub(super) zones: Vec<LaneShape>,
    pub(super) max_width: f64,
}

/// One lane (or closed piece): its band, two edges, centreline and width.
pub(super) struct LaneShape {
    pub(super) band: Vec<[f64; 2]>,
    pub(super) edges: [Vec<[f64; 2]>; 2],
    pub(super) centre: Vec<[f64; 2]>,
    pub(super) width: f64,
}

/// The shapes of the lanes and closed pieces of the input (widths capped at 50 m).
pub(super) fn map_shapes(input: &PlotInput<'_>) -> MapShapes {
    let widths = input
        .lanes
        .iter()
        .filter_map(|l| ok(l.width_m).filter(|w| *w > 0.0));
    let max_width = widths.fold(None, |m: Option<f64>, w| Some(m.map_or(w, |m| m.max(w))));
    let max_width = max_width.unwrap_or(3.5).min(50.0);
    let lanes = input.lanes.iter().filter_map(|lane| {
        let width = ok(lane.width_m)
            .filter(|w| *w > 0.0)
            .unwrap_or(max_width)
            .min(50.0);
        Some((lane.id, lane_shape(&lane.centre, width)?))
    });
    let lanes = lanes.collect();
    let zones = input
        .zones
        .iter()
        .filter_map(|z| lane_shape(z, max_width))
        .collect();
    MapShapes {
        lanes,
        zones,
        max_width,
    }
}

fn lane_shape(centre: &[[f64; 2]], width: f64) -> Option<LaneShape> {
    let mut pts: Vec<[f64; 2]> = centre.iter().filter_map(|&p| ok_point(p)).collect();
    pts.dedup();
    if pts.len() < 2 {
        return None;
    }
    let left = offset_line(&pts, 0.5 * width);
    let right = offset_line(&pts, -0.5 * width);
    let band = left.iter().chain(right.iter().rev()).copied().collect();
    Some(LaneShape {
        band,
        edges: [left, right],
        centre: pts,
        width,
    })
}

/// The polyline shifted sideways by `off` metres (left positive); `pts` has no repeated points.
pub(super) fn offset_line(pts: &[[f64; 2]], off: f64) -> Vec<[f64; 2]> {
    let normal = |a: [f64; 2], b: [f64; 2]| {
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        [-dy / len, dx / len]
    };
    let shifted = |i: usize| {
        let before = i
            .checked_sub(1)
            .and_then(|j| Some(normal(*pts.get(j)?, pts[i])));
        let after = pts.get(i + 1).map(|&b| normal(pts[i], b));
        let n = match (before, after) {
            (Some(a), Some(b)) => unit([a[0] + b[0], a[1] + b[1]]).unwrap_or(a),
            (Some(n), None) | (None, Some(n)) => n,
            (None, None) => [0.0, 0.0],
        };
        [pts[i][0] + n[0] * off, pts[i][1] + n[1] * off]
    };
    (0..pts.len()).map(shifted).collect()
}

/// The unit vector along `v`, `None` for a (near) zero vector.
pub(super) fn unit(v: [f64; 2]) -> Option<[f64; 2]> {
    let len = v[0].hypot(v[1]);
    (len > 1e-9).then(|| [v[0] / len, v[1] / len])
}
