//! Matching a WZDx event geometry to the lanes of the road that run its way beside it.

use super::geometry::{angle_diff, project};
use super::{MATCH_RADIUS_M, MAX_SAMPLES, SAME_WAY_DEG};
use crate::road::{bearing, dist, Road, RoadLane};

/// A lane of the road that runs the event's way beside it.
#[derive(Debug, Clone, Copy)]
pub(super) struct Matched {
    pub(super) id: u8,
    /// Mean distance of the near samples to the centreline, metres.
    pub(super) distance_m: f64,
    /// Mean offset of the centreline to the left of the event path, metres.
    pub(super) left_m: f64,
}

/// The road's lanes running the event's way beside `path`, left to right; `None` if none.
pub(super) fn match_lanes(road: &Road, path: &[[f64; 2]]) -> Option<Vec<Matched>> {
    let samples = sample_path(path);
    let mut matched: Vec<Matched> = road
        .lanes
        .iter()
        .filter_map(|lane| match_lane(lane, &samples))
        .collect();
    matched.sort_by(|a, b| b.left_m.total_cmp(&a.left_m));
    (!matched.is_empty()).then_some(matched)
}

/// How `lane` lies beside the samples, if it runs their way within [`MATCH_RADIUS_M`].
fn match_lane(lane: &RoadLane, samples: &[([f64; 2], f64)]) -> Option<Matched> {
    let (mut n, mut turn, mut distance, mut left) = (0.0, 0.0, 0.0, 0.0);
    for &(p, b) in samples {
        let Some((station, d)) = project(lane, p) else {
            continue;
        };
        let Some(on) = lane.at(station) else { continue };
        if d > MATCH_RADIUS_M {
            continue;
        }
        let r = b.to_radians();
        n += 1.0;
        turn += angle_diff(on.bearing_deg, b);
        distance += d;
        left += -(on.point[0] - p[0]) * r.cos() + (on.point[1] - p[1]) * r.sin();
    }
    (n > 0.0 && turn / n < SAME_WAY_DEG).then(|| Matched {
        id: lane.id,
        distance_m: distance / n,
        left_m: left / n,
    })
}

/// Points along `path` with the bearing there: its nodes and points between them, at most
/// about [`MAX_SAMPLES`] of them and not closer than 5 m.
pub(super) fn sample_path(path: &[[f64; 2]]) -> Vec<([f64; 2], f64)> {
    let total: f64 = path.windows(2).map(|w| dist(w[0], w[1])).sum();
    let step = (total / MAX_SAMPLES).max(5.0);
    let mut out = Vec::new();
    let mut last_bearing = 0.0;
    for w in path.windows(2) {
        let b = bearing(w[0], w[1]);
        let n = (dist(w[0], w[1]) / step).ceil().clamp(1.0, MAX_SAMPLES) as usize;
        for k in 0..n {
            let f = k as f64 / n as f64;
            let p = [
                w[0][0] + f * (w[1][0] - w[0][0]),
                w[0][1] + f * (w[1][1] - w[0][1]),
            ];
            out.push((p, b));
        }
        last_bearing = b;
    }
    if let Some(end) = path.last() {
        out.push((*end, last_bearing));
    }
    out
}
