//! The MAP and TIM a roadside unit broadcasts for a [`Road`] and a [`WorkZone`].
//!
//! The messages are written as JER (X.697 JSON, the 2020 field names) and read by our
//! codec into its J2735 types, so every value is checked against the type model's
//! constraints on the way; [`encode`] then gives the UPER bytes that go on the air.

use crate::clock::Utc;
use crate::road::{bearing, Road, RoadLane};
use j2735::message_frame::MessageFrame;
use serde_json::{json, Value};
use std::fmt;

/// ITIS "road construction".
pub const ITIS_ROAD_CONSTRUCTION: u16 = 1025;
/// ITIS "closed".
pub const ITIS_CLOSED: u16 = 769;
/// ITIS "left lane".
pub const ITIS_LEFT_LANE: u16 = 8195;
/// ITIS "right lane".
pub const ITIS_RIGHT_LANE: u16 = 8196;
/// ITIS "speed limit".
pub const ITIS_SPEED_LIMIT: u16 = 268;
/// ITIS number 0 (the number N is `12544 + N`).
pub const ITIS_NUMBER_BASE: u16 = 12544;
/// ITIS "mph".
pub const ITIS_MPH: u16 = 8720;
/// ITIS "kph".
pub const ITIS_KPH: u16 = 8721;
/// `durationTime` meaning "until further notice".
pub const DURATION_INDEFINITE: u16 = 32000;

/// Why a message could not be built.
#[derive(Debug, Clone, PartialEq)]
pub enum BuildError {
    /// The zone names a lane the road does not have.
    UnknownLane(u8),
    /// A lane has fewer than two nodes or a zone no length.
    Degenerate(String),
    /// A node offset does not fit the largest node-XY form (327.67 m).
    OffsetTooLarge {
        /// The lane.
        lane: u8,
        /// The offset, metres.
        metres: f64,
    },
    /// A position could not be converted to WGS84.
    Position,
    /// The codec refused the value (a constraint of the type model).
    Codec(String),
}

impl fmt::Display for BuildError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::UnknownLane(id) => write!(f, "lane {id} is not on the map"),
            Self::Degenerate(what) => write!(f, "degenerate geometry: {what}"),
            Self::OffsetTooLarge { lane, metres } => write!(
                f,
                "lane {lane}: a node {metres:.1} m from the previous one does not fit node-XY6; add nodes"
            ),
            Self::Position => f.write_str("a node lies outside the WGS84 range"),
            Self::Codec(e) => write!(f, "the codec refused the message: {e}"),
        }
    }
}

impl std::error::Error for BuildError {}

/// A speed limit as the sign shows it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SignSpeed {
    /// The number on the sign (0-511).
    pub value: u16,
    /// Miles per hour (else km/h).
    pub mph: bool,
}

impl SignSpeed {
    /// The limit in m/s.
    pub fn mps(self) -> f64 {
        self.value as f64 * if self.mph { 0.447_04 } else { 1.0 / 3.6 }
    }
}

/// A work zone: lanes closed between two stations of their centrelines.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkZone {
    /// Closed lanes (their stations are measured along the first one).
    pub closed_lanes: Vec<u8>,
    /// Zone start, metres along the first closed lane.
    pub start_m: f64,
    /// Zone end, metres along the first closed lane.
    pub end_m: f64,
    /// Reduced speed limit, if any.
    pub speed_limit: Option<SignSpeed>,
    /// `packetID`: stable for the zone.
    pub packet_id: [u8; 9],
    /// `msgCnt`: bumped on every change.
    pub msg_cnt: u8,
    /// Start of validity.
    pub start: Utc,
    /// `durationTime` in minutes ([`DURATION_INDEFINITE`], 0 cancels).
    pub duration_min: u16,
}

/// The MapData frame for `road`, intersection (or road section) `id`, `revision`, with
/// `maxSpeedInConstructionZone` from the zone start on the lanes running with the zone.
pub fn build_map(
    road: &Road,
    id: u16,
    revision: u8,
    zone: Option<&WorkZone>,
) -> Result<Box<MessageFrame>, BuildError> {
    let mut lanes = Vec::new();
    for lane in &road.lanes {
        lanes.push(map_lane(road, lane, zone)?);
    }
    let base_width = road.lanes.first().map_or(3.6, |l| l.width_m);
    let limit = road.lanes.first().map_or(0.0, |l| l.speed_limit_kmh);
    let jer = json!({
        "messageId": 18,
        "value": {
            "msgIssueRevision": revision,
            "layerType": "roadwaySectionData",
            "intersections": [{
                "id": {"id": id},
                "revision": revision,
                "refPoint": {"lat": road.reference.lat_e7(), "long": road.reference.lon_e7()},
                "laneWidth": cm(base_width),
                "speedLimits": [{"type": "vehicleMaxSpeed", "speed": velocity(limit / 3.6)}],
                "laneSet": lanes,
            }],
        }
    });
    from_jer(&jer)
}

/// One `GenericLane`: egress lanes, nodes in the direction of travel from the reference.
fn map_lane(road: &Road, lane: &RoadLane, zone: Option<&WorkZone>) -> Result<Value, BuildError> {
    let base_width = road.lanes.first().map_or(3.6, |l| l.width_m);
    let zone_start = zone.and_then(|z| zone_start_on(road, lane, z));
    let points = match zone_start {
        Some((station, _)) => densify(&with_node_at(lane, station), 300.0),
        None => densify(&lane.centre, 300.0),
    };
    let limit_node = zone_start.and_then(|(station, _)| {
        let target = at_point(lane, station);
        points
            .iter()
            .position(|p| crate::road::dist(*p, target) < 0.01)
    });
    let mut nodes = Vec::new();
    let mut prev = [0.0, 0.0];
    for (i, p) in points.iter().enumerate() {
        let delta = match node_xy(lane.id, prev, *p) {
            // A lane starting far from the reference point starts at an absolute position.
            Err(BuildError::OffsetTooLarge { .. }) if i == 0 => {
                let at = road.to_wgs84(*p).ok_or(BuildError::Position)?;
                json!({"node-LatLon": {"lon": at.lon_e7(), "lat": at.lat_e7()}})
            }
            other => other?,
        };
        let mut node = json!({ "delta": delta });
        let mut attributes = serde_json::Map::new();
        if i == 0 && cm(lane.width_m) != cm(base_width) {
            attributes.insert("dWidth".into(), json!(cm(lane.width_m) - cm(base_width)));
        }
        if limit_node == Some(i) {
            let mps = zone_start.and_then(|(_, l)| l).map_or(0.0, SignSpeed::mps);
            attributes.insert(
                "data".into(),
                json!([{"speedLimits": [{"type": "maxSpeedInConstructionZone", "speed": velocity(mps)}]}]),
            );
        }
        if !attributes.is_empty() {
            node["attributes"] = Value::Object(attributes);
        }
        nodes.push(node);
        prev = *p;
    }
    if nodes.len() < 2 {
        return Err(BuildError::Degenerate(format!(
            "lane {} has fewer than 2 nodes",
            lane.id
        )));
    }
    Ok(json!({
        "laneID": lane.id,
        "laneAttributes": {
            "directionalUse": "40",
            "sharedWith": "0000",
            "laneType": {"vehicle": "00"},
        },
        "nodeList": {"nodes": nodes},
    }))
}

/// Where the zone starts on `lane` (station and limit) when the lane runs with the zone
/// and lies beside it (within 20 m of its start).
fn zone_start_on(road: &Road, lane: &RoadLane, z: &WorkZone) -> Option<(f64, Option<SignSpeed>)> {
    let first = road.lane(*z.closed_lanes.first()?)?;
    let start = first.at(z.start_m)?;
    let (station, dist) = project(lane, start.point)?;
    let here = lane.at(station)?;
    let same_way = angle_diff(here.bearing_deg, start.bearing_deg) < 45.0;
    (same_way && dist < 20.0 && z.speed_limit.is_some()).then_some((station, z.speed_limit))
}

/// The point of `lane` at `station`, as stored in nodes.
fn at_point(lane: &RoadLane, station: f64) -> [f64; 2] {
    lane.at(station).map_or([0.0, 0.0], |o| o.point)
}

/// The centreline with a node at `station` (unless one lies within 1 cm of it).
fn with_node_at(lane: &RoadLane, station: f64) -> Vec<[f64; 2]> {
    let p = at_point(lane, station);
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(lane.centre.len() + 1);
    let mut placed = false;
    let mut run = 0.0;
    for (i, q) in lane.centre.iter().enumerate() {
        if let Some(prev) = i.checked_sub(1).map(|k| lane.centre[k]) {
            run += crate::road::dist(prev, *q);
            let near = |a: [f64; 2]| crate::road::dist(a, p) < 0.01;
            if !placed && run >= station {
                placed = true;
                if !near(*q) && !near(prev) {
                    out.push(p);
                }
            }
        }
        out.push(*q);
    }
    out
}

/// Adds nodes so that no two consecutive ones are more than `max_m` apart.
fn densify(points: &[[f64; 2]], max_m: f64) -> Vec<[f64; 2]> {
    let mut out: Vec<[f64; 2]> = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        if let Some(a) = i.checked_sub(1).map(|k| points[k]) {
            let n = (crate::road::dist(a, *p) / max_m).ceil().max(1.0) as usize;
            for k in 1..n {
                let f = k as f64 / n as f64;
                out.push([a[0] + f * (p[0] - a[0]), a[1] + f * (p[1] - a[1])]);
            }
        }
        out.push(*p);
    }
    out
}

/// Station of the nearest point of `lane` to `p`, and the distance.
fn project(lane: &RoadLane, p: [f64; 2]) -> Option<(f64, f64)> {
    lane.project(p)
}

/// Smallest of two bearing differences, degrees.
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// The TravelerInformation frame of a work zone on `road`: per closed lane a path region
/// from the zone start (the anchor) to its end, in a `workZone` data frame (ITIS road
/// construction, closed, left/right lane) and, with a reduced limit, a `speedLimit` frame
/// over the same regions.
pub fn build_tim(road: &Road, zone: &WorkZone) -> Result<Box<MessageFrame>, BuildError> {
    if zone.closed_lanes.is_empty() || zone.end_m <= zone.start_m {
        return Err(BuildError::Degenerate(
            "a zone needs a closed lane and end > start".into(),
        ));
    }
    let mut regions = Vec::new();
    let mut codes = vec![ITIS_ROAD_CONSTRUCTION, ITIS_CLOSED];
    let first = road
        .lane(zone.closed_lanes[0])
        .ok_or(BuildError::UnknownLane(zone.closed_lanes[0]))?;
    for (k, &id) in zone.closed_lanes.iter().enumerate() {
        let lane = road.lane(id).ok_or(BuildError::UnknownLane(id))?;
        let (from, to) = if k == 0 {
            (zone.start_m, zone.end_m)
        } else {
            let a = project(lane, at_point(first, zone.start_m)).map_or(zone.start_m, |p| p.0);
            let b = project(lane, at_point(first, zone.end_m)).map_or(zone.end_m, |p| p.0);
            (a, b)
        };
        regions.push(path_region(road, lane, from, to, k as u16 + 1)?);
        if let Some(code) = side_code(road, lane) {
            if !codes.contains(&code) {
                codes.push(code);
            }
        }
    }
    let items = |codes: &[u16]| -> Vec<Value> {
        codes.iter().map(|c| json!({"item": {"itis": c}})).collect()
    };
    let anchor = regions[0]["anchor"].clone();
    let frame = |content: Value, sign: &str| {
        json!({
            "notUsed": 0,
            "frameType": "advisory",
            "msgId": {"roadSignID": {"position": anchor, "viewAngle": "ffff", "mutcdCode": sign}},
            "startYear": zone.start.year,
            "startTime": zone.start.minute_of_year(),
            "durationTime": zone.duration_min,
            "priority": 5,
            "notUsed1": 0,
            "regions": regions,
            "notUsed2": 0,
            "notUsed3": 0,
            "content": content,
        })
    };
    let mut frames = vec![frame(json!({"workZone": items(&codes)}), "warning")];
    if let Some(limit) = zone.speed_limit {
        let number = ITIS_NUMBER_BASE + limit.value.min(511);
        let unit = if limit.mph { ITIS_MPH } else { ITIS_KPH };
        frames.push(frame(
            json!({"speedLimit": items(&[ITIS_SPEED_LIMIT, number, unit])}),
            "regulatory",
        ));
    }
    let jer = json!({
        "messageId": 31,
        "value": {
            "msgCnt": zone.msg_cnt % 128,
            "timeStamp": zone.start.minute_of_year(),
            "packetID": hex(&zone.packet_id),
            "dataFrames": frames,
        }
    });
    from_jer(&jer)
}

/// ITIS left/right lane when `lane` is the leftmost/rightmost of the lanes running its way.
fn side_code(road: &Road, lane: &RoadLane) -> Option<u16> {
    let here = lane.at(0.0)?;
    let mut left = 0;
    let mut right = 0;
    for other in road.lanes.iter().filter(|o| o.id != lane.id) {
        let Some((station, _)) = project(other, here.point) else {
            continue;
        };
        let Some(o) = other.at(station) else { continue };
        if angle_diff(o.bearing_deg, here.bearing_deg) >= 45.0 {
            continue;
        }
        let b = here.bearing_deg.to_radians();
        let lateral =
            -(o.point[0] - here.point[0]) * b.cos() + (o.point[1] - here.point[1]) * b.sin();
        if lateral.abs() > 20.0 {
            continue;
        }
        if lateral > 0.0 {
            left += 1
        } else {
            right += 1
        }
    }
    match (left, right) {
        (0, r) if r > 0 => Some(ITIS_LEFT_LANE),
        (l, 0) if l > 0 => Some(ITIS_RIGHT_LANE),
        _ => None,
    }
}

/// A GeographicalPath along `lane` from station `from` to `to`: anchored at the start,
/// node-XY offsets, the lane width, `forward`, and the heading slice of its bearings.
fn path_region(
    road: &Road,
    lane: &RoadLane,
    from: f64,
    to: f64,
    id: u16,
) -> Result<Value, BuildError> {
    let points = densify(&lane.slice(from, to), 300.0);
    if points.len() < 2 {
        return Err(BuildError::Degenerate(format!(
            "lane {} has no zone path",
            lane.id
        )));
    }
    let anchor = road.to_wgs84(points[0]).ok_or(BuildError::Position)?;
    let mut nodes = Vec::new();
    // The first node is the anchor itself (offset 0, 0): the zone starts there.
    let mut prev = points[0];
    for p in &points {
        nodes.push(json!({"delta": node_xy(lane.id, prev, *p)?}));
        prev = *p;
    }
    let bearings: Vec<f64> = points.windows(2).map(|w| bearing(w[0], w[1])).collect();
    Ok(json!({
        "name": format!("work zone lane {}", lane.id),
        "id": {"id": id},
        "anchor": {"lat": anchor.lat_e7(), "long": anchor.lon_e7()},
        "laneWidth": cm(lane.width_m),
        "directionality": "forward",
        "closedPath": false,
        "direction": hex(&heading_slice(&bearings).to_be_bytes()),
        "description": {"path": {"offset": {"xy": {"nodes": nodes}}}},
    }))
}

/// J2735 `HeadingSlice`: bit i (from the first) covers [22.5 i, 22.5 (i + 1)) degrees;
/// every sector within 20 degrees of one of the bearings is set.
pub fn heading_slice(bearings_deg: &[f64]) -> u16 {
    let mut bits = 0u16;
    for b in bearings_deg {
        for sector in 0..16u16 {
            let lo = sector as f64 * 22.5;
            let centre = lo + 11.25;
            if angle_diff(centre, *b) < 11.25 + 20.0 {
                bits |= 0x8000 >> sector;
            }
        }
    }
    bits
}

/// The smallest node-XY form holding the offset from `a` to `b` (centimetres).
fn node_xy(lane: u8, a: [f64; 2], b: [f64; 2]) -> Result<Value, BuildError> {
    let (x, y) = (cm_i(b[0] - a[0]), cm_i(b[1] - a[1]));
    let m = x.abs().max(y.abs());
    // Offset-B10 .. B16: the largest magnitude of each form (its negative limit is one more).
    let forms = [
        (511, "node-XY1"),
        (1023, "node-XY2"),
        (2047, "node-XY3"),
        (4095, "node-XY4"),
        (8191, "node-XY5"),
        (32767, "node-XY6"),
    ];
    let (_, name) =
        forms
            .iter()
            .find(|(limit, _)| m <= *limit)
            .ok_or(BuildError::OffsetTooLarge {
                lane,
                metres: m as f64 / 100.0,
            })?;
    Ok(json!({ *name: {"x": x, "y": y} }))
}

/// Metres to centimetres (rounded).
fn cm(m: f64) -> i64 {
    (m * 100.0).round() as i64
}

fn cm_i(m: f64) -> i64 {
    cm(m)
}

/// m/s to J2735 `Velocity` (0.02 m/s units, 8191 = unavailable).
fn velocity(mps: f64) -> i64 {
    ((mps / 0.02).round() as i64).clamp(0, 8190)
}

/// Lowercase hex.
fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Reads JER into a frame (the type model's constraints are checked here).
fn from_jer(jer: &Value) -> Result<Box<MessageFrame>, BuildError> {
    j2735::jer::from_str::<MessageFrame>(&jer.to_string())
        .map(Box::new)
        .map_err(|e| BuildError::Codec(e.to_string()))
}

/// UPER bytes of a frame.
pub fn encode(frame: &MessageFrame) -> Result<Vec<u8>, BuildError> {
    j2735::uper::encode_to_vec(frame).map_err(|e| BuildError::Codec(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heading_slices_of_the_cardinal_directions() {
        // East (90 degrees): sectors 3 and 4 (67.5-112.5), the first bit being sector 0.
        assert_eq!(heading_slice(&[90.0]), 0x1800);
        // West: sectors 11 and 12, the `0018` of J2735 work-zone examples.
        assert_eq!(heading_slice(&[270.0]), 0x0018);
        // North wraps: sectors 15 and 0.
        assert_eq!(heading_slice(&[0.0]), 0x8001);
        // 80 degrees: sector 3 holds it; sectors 2 and 4 come within 20 degrees.
        assert_eq!(heading_slice(&[80.0]), 0x3800);
    }

    #[test]
    fn node_forms_are_the_smallest_that_fit() {
        let form = |m: f64| {
            node_xy(1, [0.0, 0.0], [m, 0.0])
                .unwrap()
                .as_object()
                .unwrap()
                .keys()
                .next()
                .cloned()
                .unwrap()
        };
        assert_eq!(form(5.11), "node-XY1");
        assert_eq!(form(5.12), "node-XY2");
        assert_eq!(form(10.24), "node-XY3");
        assert_eq!(form(20.47), "node-XY3");
        assert_eq!(form(20.48), "node-XY4");
        assert_eq!(form(40.96), "node-XY5");
        assert_eq!(form(81.92), "node-XY6");
        assert_eq!(form(327.67), "node-XY6");
        assert!(matches!(
            node_xy(7, [0.0, 0.0], [327.68, 0.0]),
            Err(BuildError::OffsetTooLarge { lane: 7, .. })
        ));
    }
}
