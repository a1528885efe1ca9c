//! Association of work-zone regions with MAP lanes (cone-to-lane rule).

use super::{MapEnds, Region, WorkZone, ZoneLane};
use crate::geo::Point;
use crate::lane::{Lane, LaneKind, LaneModel, MapStore, TravelDirection};
use crate::math::{bearing_deg, wrap_360};

/// Recomputes which lanes of every stored map the zone's path regions lie on.
///
/// A lane is associated when at least one point of the path (a node, or a point between
/// two nodes, at most `SAMPLE_STEP_M` = 2 m apart) lies on it by the cone-to-lane rule
/// ([`Lane::cone_along`]) and the lane's travel direction there is one the region applies
/// to (directionality and heading slice). The zone's extent on the lane runs from the
/// smallest to the largest station of those points, so a path that runs on past the end of
/// a lane (over the stop line into the intersection) covers the lane to its end, not only
/// to its last node on the lane. Associations beyond
/// [`MAX_ZONE_LANES`](crate::capacity::MAX_ZONE_LANES) are dropped.
/// It also caches each path region's first and last node in every map's plane
/// ([`WorkZone::ends`]).
pub fn associate(zone: &mut WorkZone, maps: &MapStore) {
    zone.clear_lanes(None);
    zone.clear_ends();
    for (slot, map) in maps.iter() {
        associate_map(zone, slot, map);
    }
}

/// Recomputes the associations of `zone` with the map in slot `slot`.
fn associate_map(zone: &mut WorkZone, slot: usize, map: &LaneModel) {
    zone.clear_lanes(Some(map.id));
    for r in 0..zone.regions.len() {
        let mut found = heapless::Vec::<ZoneLane, 16>::new();
        let mut ends = None;
        if let Some(region) = zone.regions.get(r) {
            let pts = nodes_in_map(region, map);
            region_lanes(region, &pts, r as u8, map, &mut found);
            ends = region_ends(&pts);
        }
        zone.set_ends(r, slot, ends);
        for z in found {
            zone.add_lane(z);
        }
    }
}

/// First and last node of a path (converted) in a map plane.
fn region_ends(pts: &[Point]) -> Option<MapEnds> {
    Some(MapEnds {
        start: *pts.first()?,
        end: *pts.last()?,
    })
}

/// Path nodes of `region` in the plane of `map` (skipping unconvertible ones).
fn nodes_in_map(
    region: &Region,
    map: &LaneModel,
) -> heapless::Vec<Point, { crate::capacity::MAX_PATH_NODES }> {
    let mut out = heapless::Vec::new();
    for &n in region.nodes() {
        if let Some(p) = region.frame().to_wgs84(n) {
            let _ = out.push(map.frame().to_local(p));
        }
    }
    out
}

fn region_lanes(
    region: &Region,
    pts: &[Point],
    index: u8,
    map: &LaneModel,
    out: &mut heapless::Vec<ZoneLane, 16>,
) {
    for lane in map.lanes() {
        if lane.direction == TravelDirection::None || lane.kind != LaneKind::Vehicle {
            continue;
        }
        if let Some((start, end)) = extent_on_lane(region, pts, lane) {
            let entry = ZoneLane {
                map: map.id,
                lane: lane.id,
                region: index,
                start,
                end,
            };
            let _ = out.push(entry);
        }
    }
}

/// Bearing of the path at node `i` (its outgoing segment, the last one at the end).
fn path_bearing(pts: &[Point], i: usize) -> Option<f32> {
    let j = if i + 1 < pts.len() {
        i
    } else {
        i.checked_sub(1)?
    };
    let (a, b) = (pts.get(j)?, pts.get(j + 1)?);
    Some(bearing_deg(b.x - a.x, b.y - a.y))
}

/// Largest spacing of the points taken along a path segment, metres.
const SAMPLE_STEP_M: f32 = 2.0;
/// Most points taken inside one path segment (a hostile 300 m segment is sampled every
/// ~5 m instead of every 2 m, bounding the work per message).
const MAX_SEGMENT_SAMPLES: usize = 64;

/// Smallest and largest travel-direction station of the path's points on `lane`: its
/// nodes and points along each segment.
fn extent_on_lane(region: &Region, pts: &[Point], lane: &Lane) -> Option<(f32, f32)> {
    let mut range: Option<(f32, f32)> = None;
    for (i, &p) in pts.iter().enumerate() {
        let path_b = path_bearing(pts, i);
        let mut take = |q: Point| {
            if let Some(s) = station_on_lane(region, q, path_b, lane) {
                range = Some(range.map_or((s, s), |(lo, hi)| (lo.min(s), hi.max(s))));
            }
        };
        take(p);
        if let Some(&next) = pts.get(i + 1) {
            let (dx, dy) = (next.x - p.x, next.y - p.y);
            let n = (libm::ceilf(libm::hypotf(dx, dy) / SAMPLE_STEP_M) as usize)
                .clamp(1, MAX_SEGMENT_SAMPLES);
            for k in 1..n {
                let t = k as f32 / n as f32;
                take(Point::new(p.x + dx * t, p.y + dy * t));
            }
        }
    }
    range
}

/// Travel-direction station of `p` on `lane` when it lies on the lane and the region
/// applies to the lane's travel direction there (`path_b`: the path's bearing at `p`).
fn station_on_lane(region: &Region, p: Point, path_b: Option<f32>, lane: &Lane) -> Option<f32> {
    let (along, seg_bearing) = lane.cone_along(p)?;
    let path_b = path_b.unwrap_or(seg_bearing);
    let forward = lane.travels_forward(seg_bearing, Some(travel_hint(region, path_b)));
    let travel = if forward {
        seg_bearing
    } else {
        wrap_360(seg_bearing + 180.0)
    };
    region
        .applies_to(travel, path_b)
        .then(|| lane.along_of_station(along, forward))
}

/// The heading a region implies for two-way lanes.
fn travel_hint(region: &Region, path_bearing: f32) -> f32 {
    match region.directionality {
        super::Directionality::Reverse => wrap_360(path_bearing + 180.0),
        _ => path_bearing,
    }
}

#[cfg(test)]
mod tests;
