//! Reading one WZDx road event feature: its geometry, dates, speed limit and lanes.

use super::error::Problem;
use super::geometry::push_distinct;
use super::json::{
    feature_object, geometry_positions, invalid, latlon, member, number, object, string, wrong_type,
};
use super::rfc3339::rfc3339_unix_ms;
use crate::messages::SignSpeed;
use crate::road::Road;
use serde_json::{Map, Value};

/// One entry of a WZDx event's `lanes`, checked.
#[derive(Debug, Clone, Copy)]
pub(super) struct WzdxLane {
    pub(super) order: u64,
    pub(super) closed: bool,
    /// A lane vehicles travel in (not a shoulder, sidewalk, bike lane, parking, median).
    pub(super) travel: bool,
}

/// WZDx `LaneType` values of lanes vehicles travel in.
const TRAVEL_LANE_TYPES: [&str; 7] = [
    "general",
    "exit-lane",
    "exit-ramp",
    "entrance-lane",
    "entrance-ramp",
    "two-way-center-turn-lane",
    "center-left-turn-lane",
];
/// WZDx `LaneType` values of the other parts of the roadway.
const OTHER_LANE_TYPES: [&str; 5] = ["sidewalk", "bike-lane", "shoulder", "parking", "median"];
/// WZDx `LaneStatus` values.
const LANE_STATUSES: [&str; 7] = [
    "open",
    "closed",
    "shift-left",
    "shift-right",
    "merge-left",
    "merge-right",
    "alternating-flow",
];

/// The fields of a work-zone event, read and checked (before matching it to the road).
pub(super) struct WzdxEvent {
    pub(super) event_id: Option<String>,
    pub(super) road_names: Vec<String>,
    pub(super) direction: Option<String>,
    pub(super) path: Vec<[f64; 2]>,
    pub(super) speed_limit: Option<SignSpeed>,
    pub(super) start_unix_ms: u64,
    pub(super) end_unix_ms: u64,
    pub(super) lanes: Vec<WzdxLane>,
    pub(super) all_lanes_closed: bool,
}

/// Reads a feature; `None` when it is not a work-zone event.
pub(super) fn read_wzdx_event(road: &Road, feature: &Value) -> Result<Option<WzdxEvent>, Problem> {
    let feature = feature_object(feature)?;
    let props = object(member(feature, "properties", "properties")?, "properties")?;
    let core = object(
        member(props, "core_details", "properties.core_details")?,
        "properties.core_details",
    )?;
    const TYPE: &str = "properties.core_details.event_type";
    if string(member(core, "event_type", TYPE)?, TYPE)? != "work-zone" {
        return Ok(None);
    }
    let positions = geometry_positions(feature, &["LineString", "MultiPoint"])?;
    let mut path = Vec::with_capacity(positions.len());
    for (k, [lon, lat]) in positions.iter().copied().enumerate() {
        let p = road.to_local(latlon(lon, lat, &format!("geometry.coordinates[{k}]"))?);
        push_distinct(&mut path, p);
    }
    if path.len() < 2 {
        return Err(Problem::TooFewPoints {
            given: positions.len(),
            distinct: path.len(),
        });
    }
    let (start_unix_ms, end_unix_ms) = validity(props)?;
    Ok(Some(WzdxEvent {
        event_id: feature_id(feature)?,
        road_names: road_names(core)?,
        direction: optional_string(core, "direction", "properties.core_details.direction")?,
        path,
        speed_limit: reduced_speed(props)?,
        start_unix_ms,
        end_unix_ms,
        lanes: wzdx_lanes(props)?,
        all_lanes_closed: optional_string(props, "vehicle_impact", "properties.vehicle_impact")?
            .is_some_and(|v| v == "all-lanes-closed"),
    }))
}

/// The feature's `id` (a string or a number), if any.
fn feature_id(feature: &Map<String, Value>) -> Result<Option<String>, Problem> {
    match feature.get("id") {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        Some(Value::Number(n)) => Ok(Some(n.to_string())),
        Some(other) => Err(wrong_type("id", "a string", other)),
    }
}

/// `core_details.road_names` (optional here, though WZDx requires it).
fn road_names(core: &Map<String, Value>) -> Result<Vec<String>, Problem> {
    const WHAT: &str = "properties.core_details.road_names";
    let Some(v) = core.get("road_names").filter(|v| !v.is_null()) else {
        return Ok(Vec::new());
    };
    let items = v
        .as_array()
        .ok_or_else(|| wrong_type(WHAT, "an array of strings", v))?;
    items
        .iter()
        .enumerate()
        .map(|(k, name)| string(name, &format!("{WHAT}[{k}]")).map(str::to_owned))
        .collect()
}

/// An optional string member.
fn optional_string(
    obj: &Map<String, Value>,
    name: &str,
    what: &str,
) -> Result<Option<String>, Problem> {
    match obj.get(name) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => string(v, what).map(|s| Some(s.to_owned())),
    }
}

/// `start_date` and `end_date` as Unix milliseconds; the end after the start.
fn validity(props: &Map<String, Value>) -> Result<(u64, u64), Problem> {
    let date = |name: &str| -> Result<(u64, String), Problem> {
        let what = format!("properties.{name}");
        let text = string(member(props, name, &what)?, &what)?;
        let ms = rfc3339_unix_ms(text).ok_or_else(|| {
            invalid(
                &what,
                format!("{text:?}"),
                "an RFC 3339 date-time at or after 1970, e.g. \"2026-11-03T19:37:00Z\"",
            )
        })?;
        Ok((ms, text.to_owned()))
    };
    let (start, start_text) = date("start_date")?;
    let (end, end_text) = date("end_date")?;
    if end <= start {
        return Err(invalid(
            "properties.end_date",
            format!("{end_text:?}"),
            format!("a time after start_date {start_text:?}"),
        ));
    }
    Ok((start, end))
}

/// `reduced_speed_limit_kph`, if given: above 0, at most 511 (the ITIS number range).
fn reduced_speed(props: &Map<String, Value>) -> Result<Option<SignSpeed>, Problem> {
    const WHAT: &str = "properties.reduced_speed_limit_kph";
    let Some(v) = props
        .get("reduced_speed_limit_kph")
        .filter(|v| !v.is_null())
    else {
        return Ok(None);
    };
    let kph = number(v, WHAT)?;
    let value = kph.round();
    if !(1.0..=511.0).contains(&value) {
        return Err(invalid(WHAT, kph, "a speed of 1 to 511 km/h"));
    }
    Ok(Some(SignSpeed {
        value: value as u16,
        mph: false,
    }))
}

/// `lanes`, checked and sorted by `order` (empty when absent).
fn wzdx_lanes(props: &Map<String, Value>) -> Result<Vec<WzdxLane>, Problem> {
    let Some(v) = props.get("lanes").filter(|v| !v.is_null()) else {
        return Ok(Vec::new());
    };
    let items = v
        .as_array()
        .ok_or_else(|| wrong_type("properties.lanes", "an array of Lane objects", v))?;
    let mut lanes = Vec::with_capacity(items.len());
    for (k, item) in items.iter().enumerate() {
        let lane = wzdx_lane(item, &format!("properties.lanes[{k}]"))?;
        if lanes.iter().any(|l: &WzdxLane| l.order == lane.order) {
            return Err(invalid(
                &format!("properties.lanes[{k}].order"),
                lane.order,
                "an order no other lane of the event has",
            ));
        }
        lanes.push(lane);
    }
    lanes.sort_by_key(|l| l.order);
    Ok(lanes)
}

/// One WZDx `Lane`.
fn wzdx_lane(item: &Value, what: &str) -> Result<WzdxLane, Problem> {
    let lane = object(item, what)?;
    let order_what = format!("{what}.order");
    let order = number(member(lane, "order", &order_what)?, &order_what)?;
    if order.fract() != 0.0 || !(1.0..=1e6).contains(&order) {
        return Err(invalid(
            &order_what,
            order,
            "a positive integer (1 = leftmost)",
        ));
    }
    let status_what = format!("{what}.status");
    let status = string(member(lane, "status", &status_what)?, &status_what)?;
    if !LANE_STATUSES.contains(&status) {
        let expected = format!("one of {}", LANE_STATUSES.join(", "));
        return Err(invalid(&status_what, format!("{status:?}"), expected));
    }
    let type_what = format!("{what}.type");
    let kind = string(member(lane, "type", &type_what)?, &type_what)?;
    let travel = TRAVEL_LANE_TYPES.contains(&kind);
    if !travel && !OTHER_LANE_TYPES.contains(&kind) {
        let all: Vec<&str> = TRAVEL_LANE_TYPES
            .iter()
            .chain(OTHER_LANE_TYPES.iter())
            .copied()
            .collect();
        let expected = format!("a WZDx LaneType: {}", all.join(", "));
        return Err(invalid(&type_what, format!("{kind:?}"), expected));
    }
    Ok(WzdxLane {
        order: order as u64,
        closed: status == "closed",
        travel,
    })
}
