//! The lane map reader: a GeoJSON `FeatureCollection` of lane `LineString`s to a [`Road`].

use super::error::{InputError, Problem};
use super::geometry::push_distinct;
use super::json::{
    feature_collection, feature_object, geometry_positions, invalid, latlon, member, number,
    object, parse_json, position, string,
};
use super::{KMH_PER_MPH, MAX_LANE_WIDTH_M, MAX_MAP_RADIUS_M, MAX_SPEED_KMH, MIN_LANE_WIDTH_M};
use crate::road::{dist, Road, RoadLane};
use geodesy::LatLon;
use serde_json::{Map, Value};

/// One lane feature as read, before conversion to local metres.
struct LaneFeature {
    id: u8,
    width_m: f64,
    speed_limit_kmh: f64,
    reverse: bool,
    /// `[lon, lat]` degrees, in coordinate order.
    positions: Vec<[f64; 2]>,
}

/// Reads a lane map (see the [module docs](super)) into a [`Road`]: lanes in file order,
/// centrelines in the direction of travel, in metres around the reference.
///
/// # Errors
///
/// [`InputError::Json`] for text that is not JSON; [`InputError::Document`] when it is not
/// a `FeatureCollection` with at least one feature or the `reference` is not a position;
/// [`InputError::Feature`] naming the feature for a geometry that is not a `LineString`,
/// fewer than 2 distinct coordinates, coordinates out of range or farther than
/// [`MAX_MAP_RADIUS_M`] from the reference, a missing or invalid property, a duplicate
/// `lane_id` or a width outside 1.5-6 m.
pub fn load_lane_map(text: &str) -> Result<Road, InputError> {
    let doc = parse_json(text)?;
    let features = feature_collection(&doc, false)?;
    let mut read: Vec<LaneFeature> = Vec::with_capacity(features.len());
    for (index, feature) in features.iter().enumerate() {
        let lane =
            lane_feature(feature).map_err(|problem| InputError::Feature { index, problem })?;
        if let Some(first_feature) = read.iter().position(|l| l.id == lane.id) {
            let problem = Problem::DuplicateLaneId {
                lane_id: lane.id,
                first_feature,
            };
            return Err(InputError::Feature { index, problem });
        }
        read.push(lane);
    }
    let reference = map_reference(&doc, &read)?;
    let mut road = Road::new(reference, Vec::new());
    for (index, lane) in read.into_iter().enumerate() {
        let lane =
            local_lane(&road, lane).map_err(|problem| InputError::Feature { index, problem })?;
        road.lanes.push(lane);
    }
    Ok(road)
}

/// The reference: the `reference` member, else the first coordinate of the first lane.
fn map_reference(doc: &Value, lanes: &[LaneFeature]) -> Result<LatLon, InputError> {
    let given = match doc.get("reference") {
        Some(Value::Null) | None => None,
        Some(v) => Some(position(v, "reference").map_err(InputError::Document)?),
    };
    let first = lanes.first().and_then(|l| l.positions.first()).copied();
    let [lon, lat] = given
        .or(first)
        .ok_or(InputError::Document(Problem::Empty { what: "features" }))?;
    latlon(lon, lat, "reference").map_err(InputError::Document)
}

/// A lane feature's values, checked.
fn lane_feature(feature: &Value) -> Result<LaneFeature, Problem> {
    let feature = feature_object(feature)?;
    let positions = geometry_positions(feature, &["LineString"])?;
    let props = object(member(feature, "properties", "properties")?, "properties")?;
    let id = lane_id(props)?;
    let width_m = number(
        member(props, "width_m", "properties.width_m")?,
        "properties.width_m",
    )?;
    if !(MIN_LANE_WIDTH_M..=MAX_LANE_WIDTH_M).contains(&width_m) {
        return Err(invalid(
            "properties.width_m",
            width_m,
            "a lane width of 1.5 to 6 (metres)",
        ));
    }
    Ok(LaneFeature {
        id,
        width_m,
        speed_limit_kmh: speed_limit_kmh(props)?,
        reverse: travel_reversed(props)?,
        positions,
    })
}

/// `properties.lane_id`: an integer 1-255.
fn lane_id(props: &Map<String, Value>) -> Result<u8, Problem> {
    const WHAT: &str = "properties.lane_id";
    let v = number(member(props, "lane_id", WHAT)?, WHAT)?;
    if v.fract() != 0.0 || !(1.0..=255.0).contains(&v) {
        return Err(invalid(WHAT, v, "an integer 1 to 255 (J2735 LaneID)"));
    }
    Ok(v as u8)
}

/// `properties.direction`: whether travel runs against the coordinate order.
fn travel_reversed(props: &Map<String, Value>) -> Result<bool, Problem> {
    const WHAT: &str = "properties.direction";
    match string(member(props, "direction", WHAT)?, WHAT)? {
        "forward" => Ok(false),
        "reverse" => Ok(true),
        other => Err(invalid(
            WHAT,
            format!("{other:?}"),
            "\"forward\" (travel follows the coordinates) or \"reverse\" (against them)",
        )),
    }
}

/// `properties.speed_limit_kph` or `properties.speed_limit_mph`, in km/h.
fn speed_limit_kmh(props: &Map<String, Value>) -> Result<f64, Problem> {
    const KPH: &str = "properties.speed_limit_kph";
    const MPH: &str = "properties.speed_limit_mph";
    let given = |name: &str| props.get(name).filter(|v| !v.is_null());
    let kmh = match (given("speed_limit_kph"), given("speed_limit_mph")) {
        (Some(_), Some(_)) => return Err(Problem::Conflict { a: KPH, b: MPH }),
        (Some(v), None) => number(v, KPH)?,
        (None, Some(v)) => number(v, MPH)? * KMH_PER_MPH,
        (None, None) => {
            return Err(Problem::Missing {
                what: "properties.speed_limit_kph (or properties.speed_limit_mph)".into(),
            })
        }
    };
    if kmh <= 0.0 || kmh > MAX_SPEED_KMH {
        let what = if given("speed_limit_kph").is_some() {
            KPH
        } else {
            MPH
        };
        return Err(invalid(
            what,
            kmh,
            "a speed limit above 0 and at most 250 km/h",
        ));
    }
    Ok(kmh)
}

/// The lane in local metres, in the direction of travel.
fn local_lane(road: &Road, lane: LaneFeature) -> Result<RoadLane, Problem> {
    let mut centre = Vec::with_capacity(lane.positions.len());
    for (k, [lon, lat]) in lane.positions.iter().copied().enumerate() {
        let what = format!("geometry.coordinates[{k}]");
        let p = road.to_local(latlon(lon, lat, &what)?);
        let distance_m = dist(p, [0.0, 0.0]);
        if distance_m.is_nan() || distance_m > MAX_MAP_RADIUS_M {
            return Err(Problem::TooFar {
                what,
                from: "the reference",
                distance_m,
                limit_m: MAX_MAP_RADIUS_M,
            });
        }
        push_distinct(&mut centre, p);
    }
    if centre.len() < 2 {
        return Err(Problem::TooFewPoints {
            given: lane.positions.len(),
            distinct: centre.len(),
        });
    }
    if lane.reverse {
        centre.reverse();
    }
    Ok(RoadLane {
        id: lane.id,
        width_m: lane.width_m,
        speed_limit_kmh: lane.speed_limit_kmh,
        centre,
    })
}
