//! WZDx work zones on the road: [`WzdxZone`] and [`work_zones_from_wzdx`].

use super::error::{InputError, Problem};
use super::geometry::project;
use super::json::{feature_collection, parse_json};
use super::wzdx_event::{read_wzdx_event, WzdxEvent, WzdxLane};
use super::wzdx_match::{match_lanes, Matched};
use super::MIN_ZONE_M;
use crate::clock::Utc;
use crate::messages::{SignSpeed, WorkZone, DURATION_INDEFINITE};
use crate::road::Road;
use serde_json::Value;

/// A WZDx work zone on our road, ready to become a [`WorkZone`].
#[derive(Debug, Clone, PartialEq)]
pub struct WzdxZone {
    /// Index of the event in the feed's `features`.
    pub feature_index: usize,
    /// The feature's `id`, if it has one.
    pub event_id: Option<String>,
    /// `core_details.road_names`.
    pub road_names: Vec<String>,
    /// `core_details.direction` (`northbound`, ...), as given.
    pub direction: Option<String>,
    /// Closed lanes of our road, left to right across the travel direction. With no lane
    /// closed but a reduced limit, the one lane the event geometry lies nearest to (see
    /// [`WzdxZone::speed_only`]).
    pub closed_lanes: Vec<u8>,
    /// No lane is closed: the event only reduces the speed limit, and `closed_lanes` holds
    /// the lane nearest to its geometry so that a TIM can carry the limit.
    pub speed_only: bool,
    /// Zone start: the event's first point projected on the first closed lane, metres
    /// along its centreline.
    pub start_m: f64,
    /// Zone end: the event's last point projected on the same lane, metres.
    pub end_m: f64,
    /// `reduced_speed_limit_kph`, rounded to a whole km/h.
    pub speed_limit: Option<SignSpeed>,
    /// `start_date`, milliseconds since the Unix epoch.
    pub start_unix_ms: u64,
    /// `end_date`, milliseconds since the Unix epoch.
    pub end_unix_ms: u64,
}

impl WzdxZone {
    /// The [`WorkZone`] to build MAP and TIM from, valid from `start_date` (its minute) for
    /// [`WzdxZone::duration_min`].
    pub fn to_work_zone(&self, packet_id: [u8; 9], msg_cnt: u8) -> WorkZone {
        WorkZone {
            closed_lanes: self.closed_lanes.clone(),
            start_m: self.start_m,
            end_m: self.end_m,
            speed_limit: self.speed_limit,
            packet_id,
            msg_cnt,
            start: Utc::from_unix_ms(self.start_unix_ms),
            duration_min: self.duration_min(),
        }
    }

    /// TIM `durationTime`: whole minutes from the start minute (J2735 `startTime` drops
    /// the seconds) to `end_date`, rounded up, at least 1; [`DURATION_INDEFINITE`] when the
    /// zone lasts 32000 minutes (about 22 days) or more.
    pub fn duration_min(&self) -> u16 {
        let start_minute = self.start_unix_ms - self.start_unix_ms % 60_000;
        let minutes = self
            .end_unix_ms
            .saturating_sub(start_minute)
            .div_ceil(60_000);
        if minutes >= u64::from(DURATION_INDEFINITE) {
            DURATION_INDEFINITE
        } else {
            minutes.max(1) as u16
        }
    }

    /// A TIM `packetID` that stays the same for this event across feed updates: a hash of
    /// the feature `id` (of the feature index when it has none).
    pub fn packet_id(&self) -> [u8; 9] {
        let key = match &self.event_id {
            Some(id) => id.clone(),
            None => format!("features[{}]", self.feature_index),
        };
        let a = fnv1a(key.as_bytes(), 0xcbf2_9ce4_8422_2325).to_be_bytes();
        let b = fnv1a(key.as_bytes(), 0x8422_2325_cbf2_9ce4).to_be_bytes();
        let mut id = [0u8; 9];
        id[..8].copy_from_slice(&a);
        id[8] = b[0];
        id
    }
}

/// FNV-1a, 64 bits, from `basis`.
fn fnv1a(bytes: &[u8], basis: u64) -> u64 {
    bytes.iter().fold(basis, |h, b| {
        (h ^ u64::from(*b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The work zones of a WZDx 4.2 feed that lie on `road`.
///
/// For each `work-zone` event:
/// - its geometry (`LineString`, or `MultiPoint` with at least start and end; the first
///   point is where the event begins in the direction of travel) is sampled, and a lane
///   belongs to the event when samples come within [`MATCH_RADIUS_M`] of its centreline
///   with bearings within [`SAME_WAY_DEG`] of the lane's on average. Events with no such
///   lane (another road, or the other carriageway when the map does not hold it) are
///   skipped;
/// - those lanes are sorted left to right across the travel direction and matched, in
///   order, to the event's travel lanes (`lanes` sorted by `order`, 1 = leftmost, without
///   shoulders, sidewalks, bike lanes, parking and medians); lanes with `status` `closed`
///   are the closed lanes. Without `lanes`, `vehicle_impact` `all-lanes-closed` closes
///   every matched lane;
/// - with no closed lane but a `reduced_speed_limit_kph`, the zone holds the lane the
///   event geometry lies nearest to (on average) and is marked [`WzdxZone::speed_only`]:
///   the TIM that [`crate::messages::build_tim`] makes of it then places the limit on that
///   lane (and, as it does for every zone, describes it as a closure). An event with
///   neither a closed lane nor a reduced limit changes nothing for drivers and is skipped;
/// - the zone runs from the event's first to its last point, projected on the first closed
///   lane (clamped to the lane's ends).
///
/// # Errors
///
/// [`InputError::Json`] / [`InputError::Document`] when the text is not a GeoJSON
/// `FeatureCollection`; [`InputError::Feature`] naming the event for a malformed work-zone
/// event: missing `properties`/`core_details`, a geometry that is not a `LineString` or
/// `MultiPoint` of at least 2 distinct valid positions, `start_date`/`end_date` that are
/// not RFC 3339 date-times or end before they start, an invalid `reduced_speed_limit_kph`
/// or `lanes` entry, a lane count that does not match the map, or a zone of no length.
///
/// [`MATCH_RADIUS_M`]: super::MATCH_RADIUS_M
/// [`SAME_WAY_DEG`]: super::SAME_WAY_DEG
pub fn work_zones_from_wzdx(road: &Road, text: &str) -> Result<Vec<WzdxZone>, InputError> {
    let doc = parse_json(text)?;
    let features = feature_collection(&doc, true)?;
    let mut zones = Vec::new();
    for (index, feature) in features.iter().enumerate() {
        let zone = wzdx_event(road, index, feature)
            .map_err(|problem| InputError::Feature { index, problem })?;
        zones.extend(zone);
    }
    Ok(zones)
}

/// One feature: `None` when it is not a work zone or not on our road.
fn wzdx_event(road: &Road, index: usize, feature: &Value) -> Result<Option<WzdxZone>, Problem> {
    let Some(event) = read_wzdx_event(road, feature)? else {
        return Ok(None);
    };
    let Some(matched) = match_lanes(road, &event.path) else {
        return Ok(None);
    };
    let Some((closed_lanes, speed_only)) = closed_lanes(&event, &matched)? else {
        return Ok(None);
    };
    let Some(&first) = closed_lanes.first() else {
        return Ok(None);
    };
    let (start_m, end_m) = zone_stations(road, &event.path, first)?;
    Ok(Some(WzdxZone {
        feature_index: index,
        event_id: event.event_id,
        road_names: event.road_names,
        direction: event.direction,
        closed_lanes,
        speed_only,
        start_m,
        end_m,
        speed_limit: event.speed_limit,
        start_unix_ms: event.start_unix_ms,
        end_unix_ms: event.end_unix_ms,
    }))
}

/// The zone's closed lanes (left to right) and whether it only reduces the speed limit;
/// `None` when it changes nothing.
fn closed_lanes(
    event: &WzdxEvent,
    matched: &[Matched],
) -> Result<Option<(Vec<u8>, bool)>, Problem> {
    let travel: Vec<&WzdxLane> = event.lanes.iter().filter(|l| l.travel).collect();
    let closed: Vec<u8> = if travel.is_empty() {
        if event.all_lanes_closed {
            matched.iter().map(|m| m.id).collect()
        } else {
            Vec::new()
        }
    } else if travel.len() != matched.len() {
        return Err(Problem::LaneCountMismatch {
            wzdx_lanes: travel.len(),
            map_lanes: matched.iter().map(|m| m.id).collect(),
        });
    } else {
        travel
            .iter()
            .zip(matched)
            .filter(|(l, _)| l.closed)
            .map(|(_, m)| m.id)
            .collect()
    };
    if !closed.is_empty() {
        return Ok(Some((closed, false)));
    }
    if event.speed_limit.is_none() {
        return Ok(None);
    }
    let nearest = matched
        .iter()
        .min_by(|a, b| a.distance_m.total_cmp(&b.distance_m))
        .map(|m| m.id);
    Ok(nearest.map(|id| (vec![id], true)))
}

/// Stations of the event's first and last point on lane `id`.
fn zone_stations(road: &Road, path: &[[f64; 2]], id: u8) -> Result<(f64, f64), Problem> {
    let lane = road.lane(id);
    let station = |p: Option<&[f64; 2]>| {
        lane.zip(p)
            .and_then(|(l, p)| project(l, *p))
            .map_or(0.0, |(s, _)| s)
    };
    let (start_m, end_m) = (station(path.first()), station(path.last()));
    if end_m - start_m < MIN_ZONE_M {
        return Err(Problem::NoLength {
            lane_id: id,
            start_m,
            end_m,
        });
    }
    Ok((start_m, end_m))
}
