//! Distance along the road to a work zone's start.
//!
//! Routes, tried in order:
//! 1. **Lane**: the matched lane is one a zone region lies on ([`WorkZone::lanes`]):
//!    distance = zone start station - vehicle station.
//! 2. **Connection**: the matched lane leads (up to two connections) into such a lane.
//! 3. **Lane geometry**: the region's start projects onto the matched lane within a
//!    lateral reach (adjacent lanes of the same road, zones not drawn on a lane).
//! 4. **Path**: the vehicle lies on the region path or its extension before the first
//!    node (no lane match needed).
//!
//! Distances are negative inside the zone; `length_m` is the zone's extent, so the
//! zone has been passed once `distance_m < -length_m`. Only regions applying to the
//! vehicle's direction (directionality, heading slice) count; the caller checks the
//! validity window.

use crate::geo::{LatLon, Point};
use crate::lane::{Lane, LaneId, LaneModel, MapStore};
use crate::matcher::LaneMatch;
use crate::zone::{Region, WorkZone};

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// How a distance was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum DistanceSource {
    /// Along the matched lane, which the zone lies on.
    Lane,
    /// Along the matched lane and its connections into a zone lane.
    Connection,
    /// Along the matched lane to the projection of the zone start.
    LaneGeometry,
    /// Along the zone's own path.
    Path,
    /// Along the heading to the edge of a circle region.
    Circle,
}

/// Distance to one zone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZoneDistance {
    /// Metres to the zone start along the road; negative inside the zone.
    pub distance_m: f32,
    /// Zone extent along the road, metres.
    pub length_m: f32,
    /// True when the vehicle's own lane is one the zone lies on.
    pub on_zone_lane: bool,
    /// Route used.
    pub source: DistanceSource,
}

/// Distance from the vehicle to `zone`, `None` when the zone does not concern it.
/// `reach_m` is the lateral room for routes 3 and 4 (beyond half the zone width).
pub fn zone_distance(
    zone: &WorkZone,
    maps: &MapStore,
    matched: Option<&LaneMatch>,
    position: LatLon,
    heading: Option<f32>,
    reach_m: f32,
) -> Option<ZoneDistance> {
    let by_lane = matched.and_then(|m| {
        let map = maps.slot(m.slot as usize)?;
        let lane = map.lane(m.lane)?;
        via_lane(zone, m)
            .or_else(|| via_connection(zone, map, lane, m))
            .or_else(|| via_geometry(zone, lane, m, reach_m))
    });
    by_lane.or_else(|| via_path(zone, position, heading, reach_m))
}

/// Route 1: the zone lies on the matched lane.
fn via_lane(zone: &WorkZone, m: &LaneMatch) -> Option<ZoneDistance> {
    let s = m.position.station;
    let entries = zone
        .lanes()
        .iter()
        .filter(|z| z.map == m.map && z.lane == m.lane);
    let best = entries
        .map(|z| (z.start - s, z.end - z.start))
        .min_by(|a, b| rank(*a).total_cmp(&rank(*b)))?;
    Some(ZoneDistance {
        distance_m: best.0,
        length_m: best.1,
        on_zone_lane: true,
        source: DistanceSource::Lane,
    })
}

/// Orders (distance, length) pairs: zones ahead or occupied first, nearest first.
fn rank((d, len): (f32, f32)) -> f32 {
    if d >= -len {
        d
    } else {
        1.0e6 - d
    }
}

/// Route 2: the matched lane leads into a zone lane (depth two).
fn via_connection(
    zone: &WorkZone,
    map: &LaneModel,
    lane: &Lane,
    m: &LaneMatch,
) -> Option<ZoneDistance> {
    let rest = lane.length() - m.position.station;
    let hit = |id: LaneId| zone.lane(map.id, id).map(|z| (z.start, z.end - z.start));
    for &c in lane.connections.iter() {
        if let Some((start, len)) = hit(c) {
            return Some(connection(rest + start, len));
        }
        let Some(next) = map.lane(c) else { continue };
        for &c2 in next.connections.iter() {
            if let Some((start, len)) = hit(c2) {
                return Some(connection(rest + next.length() + start, len));
            }
        }
    }
    None
}

fn connection(distance_m: f32, length_m: f32) -> ZoneDistance {
    ZoneDistance {
        distance_m,
        length_m,
        on_zone_lane: false,
        source: DistanceSource::Connection,
    }
}

/// Region path ends in the map plane (cached by the association, [`WorkZone::ends`]),
/// in the vehicle's direction of travel.
fn ends_in_map(
    zone: &WorkZone,
    r: usize,
    slot: usize,
    travel_deg: f32,
) -> Option<(Point, Point, f32)> {
    let region = zone.regions.get(r)?;
    let nodes = region.nodes();
    let (first, second) = (*nodes.first()?, *nodes.get(1)?);
    let bearing = crate::math::bearing_deg(second.x - first.x, second.y - first.y);
    if !region.applies_to(travel_deg, bearing) {
        return None;
    }
    let ends = zone.ends(r, slot)?;
    let (start, end) = if Region::is_reverse(travel_deg, bearing) {
        (ends.end, ends.start)
    } else {
        (ends.start, ends.end)
    };
    Some((start, end, region.length()))
}

/// Route 3: project the region's start (and end) onto the matched lane.
fn via_geometry(zone: &WorkZone, lane: &Lane, m: &LaneMatch, reach: f32) -> Option<ZoneDistance> {
    let mut best: Option<ZoneDistance> = None;
    for (r, region) in zone.regions.iter().enumerate() {
        let travel = m.position.bearing_deg;
        let Some((start, end, path_len)) = ends_in_map(zone, r, m.slot as usize, travel) else {
            continue;
        };
        let room = region.lane_width_m * 0.5 + reach;
        let Some(s0) = station_on(lane, start, m.position.forward, room) else {
            continue;
        };
        let len = station_on(lane, end, m.position.forward, room)
            .map_or(path_len, |s1| (s1 - s0).max(0.0));
        let d = ZoneDistance {
            distance_m: s0 - m.position.station,
            length_m: len,
            on_zone_lane: false,
            source: DistanceSource::LaneGeometry,
        };
        if best.is_none_or(|b| rank((d.distance_m, d.length_m)) < rank((b.distance_m, b.length_m)))
        {
            best = Some(d);
        }
    }
    best
}

/// Travel-direction station of `p` on `lane` if within `room` laterally and the extent.
fn station_on(lane: &Lane, p: Point, forward: bool, room: f32) -> Option<f32> {
    if !lane.may_contain(p, room) {
        return None;
    }
    let proj = lane.project(p)?;
    let pos = lane.position_from(&proj, forward);
    (pos.lateral.abs() <= room && pos.beyond <= 0.0).then_some(pos.station)
}

/// Route 4: the vehicle on the region path or before its start.
fn via_path(
    zone: &WorkZone,
    position: LatLon,
    heading: Option<f32>,
    reach: f32,
) -> Option<ZoneDistance> {
    let heading = heading?;
    let mut best: Option<ZoneDistance> = None;
    for region in zone.regions.iter() {
        let p = region.frame().to_local(position);
        if let Some((entry, chord)) = region.circle_crossing(p, heading) {
            let d = ZoneDistance {
                distance_m: entry,
                length_m: chord,
                on_zone_lane: false,
                source: DistanceSource::Circle,
            };
            if best.is_none_or(|b| rank((entry, chord)) < rank((b.distance_m, b.length_m))) {
                best = Some(d);
            }
            continue;
        }
        let Some(fit) = region.fit(p) else { continue };
        if !region.applies_to(heading, fit.bearing_deg)
            || fit.lateral.abs() > region.lane_width_m * 0.5 + reach
        {
            continue;
        }
        let along = if Region::is_reverse(heading, fit.bearing_deg) {
            fit.length - fit.along
        } else {
            fit.along
        };
        let d = ZoneDistance {
            distance_m: -along,
            length_m: fit.length,
            on_zone_lane: false,
            source: DistanceSource::Path,
        };
        if best.is_none_or(|b| rank((d.distance_m, d.length_m)) < rank((b.distance_m, b.length_m)))
        {
            best = Some(d);
        }
    }
    best
}

#[cfg(test)]
mod tests;
