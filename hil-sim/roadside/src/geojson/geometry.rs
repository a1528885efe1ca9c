//! Plane geometry on lane centrelines in local metres.

use super::SAME_POINT_M;
use crate::road::{dist, RoadLane};

/// Appends `p` unless it is the same point as the last one.
pub(super) fn push_distinct(points: &mut Vec<[f64; 2]>, p: [f64; 2]) {
    if points.last().is_none_or(|q| dist(*q, p) >= SAME_POINT_M) {
        points.push(p);
    }
}

/// Station of the point of `lane` nearest to `p`, and the distance to it.
pub(super) fn project(lane: &RoadLane, p: [f64; 2]) -> Option<(f64, f64)> {
    let mut best: Option<(f64, f64)> = None;
    let mut start = 0.0;
    for w in lane.centre.windows(2) {
        let (dx, dy) = (w[1][0] - w[0][0], w[1][1] - w[0][1]);
        let len2 = dx * dx + dy * dy;
        if len2 > 0.0 {
            let t = (((p[0] - w[0][0]) * dx + (p[1] - w[0][1]) * dy) / len2).clamp(0.0, 1.0);
            let d = dist(p, [w[0][0] + t * dx, w[0][1] + t * dy]);
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((start + t * len2.sqrt(), d));
            }
        }
        start += len2.sqrt();
    }
    best
}

/// Smallest difference of two bearings, degrees.
pub(super) fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}
