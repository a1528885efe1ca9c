//! Roadside inputs read from files: the lane map (GeoJSON), work zones from a WZDx 4.2
//! feed, and a list of cone positions (JSON or CSV).
//!
//! Every reader takes the whole text, checks all of it, and gives either the value or an
//! [`InputError`] that says where (feature index, list item, line) and what to fix. No
//! input makes a reader panic.
//!
//! # Lane map ([`load_lane_map`])
//!
//! A GeoJSON `FeatureCollection` with one `LineString` feature per lane; coordinates are
//! `[lon, lat]` (an altitude, if given, is ignored). Properties:
//!
//! | property | meaning |
//! |---|---|
//! | `lane_id` | J2735 lane id, 1-255, unique |
//! | `width_m` | lane width, 1.5-6 m |
//! | `direction` | `"forward"`: traffic follows the coordinate order; `"reverse"`: against it |
//! | `speed_limit_kph` or `speed_limit_mph` | the posted limit (exactly one of them) |
//!
//! The collection may carry a top-level `"reference": [lon, lat]` (the J2735 `refPoint`);
//! without it the reference is the first coordinate of the first feature, rounded to
//! 1e-7 degree. Every coordinate must lie within [`MAX_MAP_RADIUS_M`] of the reference.
//!
//! # WZDx work zones ([`work_zones_from_wzdx`])
//!
//! A WZDx 4.2 feed (a `FeatureCollection` of `RoadEventFeature`s). Events whose
//! `core_details.event_type` is not `"work-zone"` (detours, restrictions) are skipped, and
//! so are work zones that do not lie along a lane of the road (see [`work_zones_from_wzdx`]
//! for the matching rules); malformed events are errors.
//!
//! # Cones ([`load_cones`])
//!
//! Either JSON, `[{"lat": 39.75, "lon": -104.99}, ...]`, or CSV lines `lat,lon` with an
//! optional header line (`lat,lon`, `lon,lat`, `latitude,longitude`, ...) and `#` comments.

use crate::clock::{days_from_civil, Utc};
use crate::messages::{SignSpeed, WorkZone, DURATION_INDEFINITE};
use crate::road::{bearing, dist, Road, RoadLane};
use obu::LatLon;
use serde_json::{Map, Value};
use std::fmt;

/// Narrowest lane a lane map may hold, metres.
pub const MIN_LANE_WIDTH_M: f64 = 1.5;
/// Widest lane a lane map may hold, metres.
pub const MAX_LANE_WIDTH_M: f64 = 6.0;
/// Highest speed limit accepted, km/h.
pub const MAX_SPEED_KMH: f64 = 250.0;
/// A lane map covers at most this distance around its reference, metres.
pub const MAX_MAP_RADIUS_M: f64 = 20_000.0;
/// A WZDx event belongs to a lane when its geometry comes this close to the centreline,
/// metres.
pub const MATCH_RADIUS_M: f64 = 30.0;
/// A lane runs the event's way when their bearings differ by less than this, degrees.
pub const SAME_WAY_DEG: f64 = 45.0;
/// A cone farther than this from every lane centreline is refused, metres.
pub const MAX_CONE_DISTANCE_M: f64 = 100.0;

/// Points sampled along a WZDx event geometry to match it to lanes (at most).
const MAX_SAMPLES: f64 = 500.0;
/// Consecutive points closer than this are one point, metres.
const SAME_POINT_M: f64 = 0.01;
/// Miles per hour to km/h.
const KMH_PER_MPH: f64 = 1.609_344;
/// A work zone shorter than this along its lane is refused, metres.
const MIN_ZONE_M: f64 = 1.0;

/// What is wrong with one part of an input (the [`InputError`] says which part).
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Problem {
    /// A required member is absent or `null`.
    Missing {
        /// JSON path of the member (`properties.width_m`).
        what: String,
    },
    /// A member of the wrong JSON type.
    WrongType {
        /// JSON path of the member.
        what: String,
        /// The type it must have.
        expected: &'static str,
        /// The type it has.
        found: &'static str,
    },
    /// A value that is not allowed.
    Invalid {
        /// JSON path of the member (or `line`).
        what: String,
        /// The value as found.
        value: String,
        /// What is allowed.
        expected: String,
    },
    /// A line with fewer than two distinct points.
    TooFewPoints {
        /// Points given.
        given: usize,
        /// Points left after merging consecutive ones less than 1 cm apart.
        distinct: usize,
    },
    /// A lane id that an earlier feature already uses.
    DuplicateLaneId {
        /// The lane id.
        lane_id: u8,
        /// Index of the feature that uses it first.
        first_feature: usize,
    },
    /// Two members that exclude each other are both given.
    Conflict {
        /// One member.
        a: &'static str,
        /// The other.
        b: &'static str,
    },
    /// A WZDx event lists a different number of travel lanes than the lane map has running
    /// its way beside it.
    LaneCountMismatch {
        /// Travel lanes of the event (`lanes` entries that are not shoulders, sidewalks,
        /// bike lanes, parking or medians).
        wzdx_lanes: usize,
        /// Ids of the map's lanes running the event's way, left to right.
        map_lanes: Vec<u8>,
    },
    /// A work zone that covers (almost) no length of the lane it closes.
    NoLength {
        /// The lane.
        lane_id: u8,
        /// Station of the event's first point, metres.
        start_m: f64,
        /// Station of the event's last point, metres.
        end_m: f64,
    },
    /// A point too far from the reference or the road.
    TooFar {
        /// JSON path of the point (or `cone`).
        what: String,
        /// What it is too far from (`the reference`, `the nearest lane`).
        from: &'static str,
        /// Its distance, metres.
        distance_m: f64,
        /// The limit, metres.
        limit_m: f64,
    },
    /// The input holds nothing of what it must hold.
    Empty {
        /// What is missing (`features`).
        what: &'static str,
    },
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Missing { what } => write!(f, "{} is missing; add it", Named(what)),
            Self::WrongType {
                what,
                expected,
                found,
            } => write!(f, "{} is {found}; it must be {expected}", Named(what)),
            Self::Invalid {
                what,
                value,
                expected,
            } => write!(f, "{} is {value}; expected {expected}", Named(what)),
            Self::TooFewPoints { given, distinct } => write!(
                f,
                "the geometry has {given} coordinates ({distinct} distinct); a line needs at least 2 distinct points"
            ),
            Self::DuplicateLaneId {
                lane_id,
                first_feature,
            } => write!(
                f,
                "lane_id {lane_id} is already used by features[{first_feature}]; give every lane its own id"
            ),
            Self::Conflict { a, b } => {
                write!(f, "both `{a}` and `{b}` are given; keep only one of them")
            }
            Self::LaneCountMismatch {
                wzdx_lanes,
                map_lanes,
            } => write!(
                f,
                "the event lists {wzdx_lanes} travel lanes but the lane map has {} lanes running its way beside it (ids {map_lanes:?}, left to right); make the feed's `lanes` and the lane map agree",
                map_lanes.len()
            ),
            Self::NoLength {
                lane_id,
                start_m,
                end_m,
            } => write!(
                f,
                "the event runs from station {start_m:.1} m to {end_m:.1} m of lane {lane_id}, which is no zone; check that its geometry starts upstream and lies along the lane map"
            ),
            Self::TooFar {
                what,
                from,
                distance_m,
                limit_m,
            } => write!(
                f,
                "{} lies {distance_m:.0} m from {from}, more than {limit_m:.0} m; check the coordinate (and the lat/lon order)",
                Named(what)
            ),
            Self::Empty { what } => write!(f, "there are no {what}"),
        }
    }
}

/// A JSON path in backticks, or `the line` / `the cone` for those words.
struct Named<'a>(&'a str);

impl fmt::Display for Named<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0 {
            "line" | "cone" => write!(f, "the {}", self.0),
            path => write!(f, "`{path}`"),
        }
    }
}

/// Why an input file was refused: where, and the [`Problem`] there.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum InputError {
    /// The text is not JSON.
    Json {
        /// 1-based line of the parser's complaint.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message.
        message: String,
    },
    /// The document as a whole (its top level).
    Document(Problem),
    /// Feature `index` (0-based, file order) of a `FeatureCollection`.
    Feature {
        /// Index in `features`.
        index: usize,
        /// What is wrong with it.
        problem: Problem,
    },
    /// Item `index` (0-based) of a JSON cone list.
    Item {
        /// Index in the list.
        index: usize,
        /// What is wrong with it.
        problem: Problem,
    },
    /// Line `line` (1-based) of a CSV cone list.
    Line {
        /// The line number.
        line: usize,
        /// What is wrong with it.
        problem: Problem,
    },
}

impl InputError {
    /// The problem, unless the text is not JSON at all.
    pub fn problem(&self) -> Option<&Problem> {
        match self {
            Self::Json { .. } => None,
            Self::Document(problem)
            | Self::Feature { problem, .. }
            | Self::Item { problem, .. }
            | Self::Line { problem, .. } => Some(problem),
        }
    }
}

impl fmt::Display for InputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Json {
                line,
                column,
                message,
            } => write!(
                f,
                "not valid JSON at line {line}, column {column}: {message}"
            ),
            Self::Document(problem) => write!(f, "document: {problem}"),
            Self::Feature { index, problem } => write!(f, "features[{index}]: {problem}"),
            Self::Item { index, problem } => write!(f, "item [{index}]: {problem}"),
            Self::Line { line, problem } => write!(f, "line {line}: {problem}"),
        }
    }
}

impl std::error::Error for InputError {}

// ---------------------------------------------------------------------------------------
// Lane map

/// One lane feature as read, before conversion to local metres.
struct LaneFeature {
    id: u8,
    width_m: f64,
    speed_limit_kmh: f64,
    reverse: bool,
    /// `[lon, lat]` degrees, in coordinate order.
    positions: Vec<[f64; 2]>,
}

/// Reads a lane map (see the [module docs](self)) into a [`Road`]: lanes in file order,
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
    let features = feature_collection(&doc)?;
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

/// Appends `p` unless it is the same point as the last one.
fn push_distinct(points: &mut Vec<[f64; 2]>, p: [f64; 2]) {
    if points.last().is_none_or(|q| dist(*q, p) >= SAME_POINT_M) {
        points.push(p);
    }
}

// ---------------------------------------------------------------------------------------
// WZDx

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

/// One entry of a WZDx event's `lanes`, checked.
#[derive(Debug, Clone, Copy)]
struct WzdxLane {
    order: u64,
    closed: bool,
    /// A lane vehicles travel in (not a shoulder, sidewalk, bike lane, parking, median).
    travel: bool,
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
pub fn work_zones_from_wzdx(road: &Road, text: &str) -> Result<Vec<WzdxZone>, InputError> {
    let doc = parse_json(text)?;
    let features = feature_collection(&doc)?;
    let mut zones = Vec::new();
    for (index, feature) in features.iter().enumerate() {
        let zone = wzdx_event(road, index, feature)
            .map_err(|problem| InputError::Feature { index, problem })?;
        zones.extend(zone);
    }
    Ok(zones)
}

/// The fields of a work-zone event, read and checked (before matching it to the road).
struct WzdxEvent {
    event_id: Option<String>,
    road_names: Vec<String>,
    direction: Option<String>,
    path: Vec<[f64; 2]>,
    speed_limit: Option<SignSpeed>,
    start_unix_ms: u64,
    end_unix_ms: u64,
    lanes: Vec<WzdxLane>,
    all_lanes_closed: bool,
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

/// Reads a feature; `None` when it is not a work-zone event.
fn read_wzdx_event(road: &Road, feature: &Value) -> Result<Option<WzdxEvent>, Problem> {
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

/// A lane of the road that runs the event's way beside it.
#[derive(Debug, Clone, Copy)]
struct Matched {
    id: u8,
    /// Mean distance of the near samples to the centreline, metres.
    distance_m: f64,
    /// Mean offset of the centreline to the left of the event path, metres.
    left_m: f64,
}

/// The road's lanes running the event's way beside `path`, left to right; `None` if none.
fn match_lanes(road: &Road, path: &[[f64; 2]]) -> Option<Vec<Matched>> {
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
fn sample_path(path: &[[f64; 2]]) -> Vec<([f64; 2], f64)> {
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

/// Milliseconds since the Unix epoch of an RFC 3339 `date-time`
/// (`2026-11-03T19:37:00Z`, `2026-11-03T12:37:00.250-07:00`; `t`/`z` or a space as the
/// separator are accepted); `None` when malformed or before 1970.
pub fn rfc3339_unix_ms(text: &str) -> Option<u64> {
    let b = text.as_bytes();
    let digits = |from: usize, to: usize| -> Option<i64> {
        let s = text.get(from..to)?;
        s.bytes()
            .all(|c| c.is_ascii_digit())
            .then(|| s.parse().ok())
            .flatten()
    };
    let at = |i: usize, allowed: &[u8]| b.get(i).is_some_and(|c| allowed.contains(c));
    let fixed = at(4, b"-") && at(7, b"-") && at(10, b"Tt ") && at(13, b":") && at(16, b":");
    if !fixed {
        return None;
    }
    let (year, month, day) = (digits(0, 4)?, digits(5, 7)?, digits(8, 10)?);
    let (hour, minute, second) = (digits(11, 13)?, digits(14, 16)?, digits(17, 19)?);
    let valid = (1..=12).contains(&month)
        && day >= 1
        && day <= days_in_month(year, month)
        && hour <= 23
        && minute <= 59
        && second <= 60;
    if !valid {
        return None;
    }
    let (millis, offset_min) = fraction_and_offset(text.get(19..)?)?;
    let days = days_from_civil(year, month as u8, day as u8);
    let ms = ((days * 24 + hour) * 60 + minute - offset_min) * 60_000 + second * 1000 + millis;
    u64::try_from(ms).ok()
}

/// The milliseconds of an optional `.fraction` and the offset in minutes (`Z`, `+hh:mm`).
fn fraction_and_offset(rest: &str) -> Option<(i64, i64)> {
    let (millis, rest) = match rest.strip_prefix('.') {
        Some(frac) => {
            let n = frac.bytes().take_while(u8::is_ascii_digit).count();
            if n == 0 {
                return None;
            }
            let first3: String = frac
                .get(..n)?
                .chars()
                .chain("000".chars())
                .take(3)
                .collect();
            (first3.parse().ok()?, frac.get(n..)?)
        }
        None => (0, rest),
    };
    if rest == "Z" || rest == "z" {
        return Some((millis, 0));
    }
    let sign = match rest.as_bytes().first()? {
        b'+' => 1,
        b'-' => -1,
        _ => return None,
    };
    let (h, m) = rest.get(1..)?.split_once(':')?;
    let ok = |s: &str, max: i64| -> Option<i64> {
        (s.len() == 2 && s.bytes().all(|c| c.is_ascii_digit()))
            .then(|| s.parse().ok())
            .flatten()
            .filter(|v| *v <= max)
    };
    Some((millis, sign * (ok(h, 23)? * 60 + ok(m, 59)?)))
}

/// Days in `month` of `year` (proleptic Gregorian).
fn days_in_month(year: i64, month: i64) -> i64 {
    match month {
        2 if (year % 4 == 0 && year % 100 != 0) || year % 400 == 0 => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

// ---------------------------------------------------------------------------------------
// Cones

/// Reads a cone list (JSON or CSV, see the [module docs](self)) into local points of
/// `road` (east/north metres around its reference). An empty list is valid (no cones).
///
/// The format is JSON when the first character that is not white space is `[` or `{`,
/// else CSV.
///
/// # Errors
///
/// [`InputError::Json`] / [`InputError::Document`] for JSON that is not an array;
/// [`InputError::Item`] for an item without numeric `lat` and `lon`; [`InputError::Line`]
/// for a CSV line that is not two numbers (or a header naming `lat` and `lon`); either for
/// a position out of range or farther than [`MAX_CONE_DISTANCE_M`] from every lane.
pub fn load_cones(road: &Road, text: &str) -> Result<Vec<[f64; 2]>, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let json = text.trim_start().starts_with(['[', '{']);
    if json {
        json_cones(road, text)
    } else {
        csv_cones(road, text)
    }
}

/// `[{"lat": .., "lon": ..}, ...]`.
fn json_cones(road: &Road, text: &str) -> Result<Vec<[f64; 2]>, InputError> {
    let doc = parse_json(text)?;
    let items = doc.as_array().ok_or_else(|| {
        InputError::Document(wrong_type(
            "(top level)",
            "an array of {\"lat\": .., \"lon\": ..} objects",
            &doc,
        ))
    })?;
    let mut cones = Vec::with_capacity(items.len());
    for (index, item) in items.iter().enumerate() {
        let cone = json_cone(road, item).map_err(|problem| InputError::Item { index, problem })?;
        cones.push(cone);
    }
    Ok(cones)
}

/// One JSON cone.
fn json_cone(road: &Road, item: &Value) -> Result<[f64; 2], Problem> {
    let obj = object(item, "cone")?;
    let lat = number(member(obj, "lat", "lat")?, "lat")?;
    let lon = number(member(obj, "lon", "lon")?, "lon")?;
    cone_point(road, lat, lon)
}

/// Column order of a CSV cone list.
#[derive(Clone, Copy)]
enum Columns {
    LatLon,
    LonLat,
}

/// `lat,lon` lines, optional header, `#` comments.
fn csv_cones(road: &Road, text: &str) -> Result<Vec<[f64; 2]>, InputError> {
    let mut columns = None;
    let mut cones = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let content = raw.split_once('#').map_or(raw, |(c, _)| c).trim();
        if content.is_empty() {
            continue;
        }
        let at_line = |problem| InputError::Line { line, problem };
        let fields: Vec<&str> = content.split(',').map(str::trim).collect();
        let &[a, b] = fields.as_slice() else {
            return Err(at_line(invalid(
                "line",
                format!("{content:?}"),
                "two comma-separated fields `lat,lon`",
            )));
        };
        let numbers = a.parse::<f64>().ok().zip(b.parse::<f64>().ok());
        match (numbers, columns) {
            (Some((x, y)), order) => {
                let (lat, lon) = match order.unwrap_or(Columns::LatLon) {
                    Columns::LatLon => (x, y),
                    Columns::LonLat => (y, x),
                };
                cones.push(cone_point(road, lat, lon).map_err(at_line)?);
                columns = Some(order.unwrap_or(Columns::LatLon));
            }
            (None, None) => columns = Some(csv_header(a, b).map_err(at_line)?),
            (None, Some(_)) => {
                return Err(at_line(invalid(
                    "line",
                    format!("{content:?}"),
                    "two numbers `lat,lon` in decimal degrees",
                )))
            }
        }
    }
    Ok(cones)
}

/// The column order a header line names.
fn csv_header(a: &str, b: &str) -> Result<Columns, Problem> {
    let is_lat = |s: &str| ["lat", "latitude"].contains(&s.to_ascii_lowercase().as_str());
    let is_lon =
        |s: &str| ["lon", "lng", "long", "longitude"].contains(&s.to_ascii_lowercase().as_str());
    if is_lat(a) && is_lon(b) {
        Ok(Columns::LatLon)
    } else if is_lon(a) && is_lat(b) {
        Ok(Columns::LonLat)
    } else {
        Err(invalid(
            "line",
            format!("\"{a},{b}\""),
            "two numbers `lat,lon` in decimal degrees, or a first line naming the columns (`lat,lon`)",
        ))
    }
}

/// A cone position in local metres, checked to lie near a lane.
fn cone_point(road: &Road, lat: f64, lon: f64) -> Result<[f64; 2], Problem> {
    let p = road.to_local(latlon(lon, lat, "cone")?);
    let nearest = road
        .lanes
        .iter()
        .filter_map(|lane| project(lane, p))
        .map(|(_, d)| d)
        .min_by(f64::total_cmp);
    match nearest {
        Some(d) if d.is_nan() || d > MAX_CONE_DISTANCE_M => Err(Problem::TooFar {
            what: "cone".into(),
            from: "the nearest lane",
            distance_m: d,
            limit_m: MAX_CONE_DISTANCE_M,
        }),
        _ => Ok(p),
    }
}

// ---------------------------------------------------------------------------------------
// JSON helpers

/// Parses JSON, with the parser's line and column on error.
fn parse_json(text: &str) -> Result<Value, InputError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    serde_json::from_str(text).map_err(|e| InputError::Json {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })
}

/// The non-empty `features` of a `FeatureCollection`.
fn feature_collection(doc: &Value) -> Result<&[Value], InputError> {
    let doc_error = InputError::Document;
    let obj = object(doc, "(top level)").map_err(doc_error)?;
    let kind =
        string(member(obj, "type", "type").map_err(doc_error)?, "type").map_err(doc_error)?;
    if kind != "FeatureCollection" {
        return Err(doc_error(invalid(
            "type",
            format!("{kind:?}"),
            "\"FeatureCollection\"",
        )));
    }
    let features = member(obj, "features", "features").map_err(doc_error)?;
    let features = features
        .as_array()
        .ok_or_else(|| doc_error(wrong_type("features", "an array of features", features)))?;
    if features.is_empty() {
        return Err(doc_error(Problem::Empty { what: "features" }));
    }
    Ok(features)
}

/// A GeoJSON `Feature` object.
fn feature_object(v: &Value) -> Result<&Map<String, Value>, Problem> {
    let feature = object(v, "(feature)")?;
    let kind = string(member(feature, "type", "type")?, "type")?;
    if kind != "Feature" {
        return Err(invalid("type", format!("{kind:?}"), "\"Feature\""));
    }
    Ok(feature)
}

/// The `[lon, lat]` positions of the feature's geometry, whose type must be in `allowed`.
fn geometry_positions(
    feature: &Map<String, Value>,
    allowed: &[&str],
) -> Result<Vec<[f64; 2]>, Problem> {
    let geometry = object(member(feature, "geometry", "geometry")?, "geometry")?;
    let kind = string(member(geometry, "type", "geometry.type")?, "geometry.type")?;
    if !allowed.contains(&kind) {
        return Err(invalid(
            "geometry.type",
            format!("{kind:?}"),
            allowed
                .iter()
                .map(|a| format!("\"{a}\""))
                .collect::<Vec<_>>()
                .join(" or "),
        ));
    }
    const WHAT: &str = "geometry.coordinates";
    let coords = member(geometry, "coordinates", WHAT)?;
    let coords = coords
        .as_array()
        .ok_or_else(|| wrong_type(WHAT, "an array of [lon, lat] positions", coords))?;
    let positions = coords
        .iter()
        .enumerate()
        .map(|(k, c)| position(c, &format!("{WHAT}[{k}]")))
        .collect::<Result<Vec<_>, _>>()?;
    if positions.len() < 2 {
        return Err(Problem::TooFewPoints {
            given: positions.len(),
            distinct: positions.len(),
        });
    }
    Ok(positions)
}

/// A GeoJSON position `[lon, lat]` (or `[lon, lat, alt]`), range-checked.
fn position(v: &Value, what: &str) -> Result<[f64; 2], Problem> {
    const EXPECTED: &str = "a position [lon, lat] in degrees";
    let items = v.as_array().ok_or_else(|| wrong_type(what, EXPECTED, v))?;
    let (Some(lon), Some(lat), 2..=3) = (items.first(), items.get(1), items.len()) else {
        return Err(invalid(what, v, EXPECTED));
    };
    let lon = number(lon, &format!("{what}[0]"))?;
    let lat = number(lat, &format!("{what}[1]"))?;
    latlon(lon, lat, what)?;
    Ok([lon, lat])
}

/// A WGS84 position from degrees, range-checked (with a hint when the order looks swapped).
fn latlon(lon: f64, lat: f64, what: &str) -> Result<LatLon, Problem> {
    let swapped = (-90.0..=90.0).contains(&lon) && (-180.0..=180.0).contains(&lat);
    let hint = match (swapped, what) {
        (false, _) => "",
        (true, "cone") => " (latitude and longitude look swapped)",
        (true, _) => " (latitude and longitude look swapped: GeoJSON positions are [lon, lat])",
    };
    if !(-90.0..=90.0).contains(&lat) {
        return Err(invalid(
            what,
            format!("latitude {lat}"),
            format!("a latitude of -90 to 90 degrees{hint}"),
        ));
    }
    if !(-180.0..=180.0).contains(&lon) {
        return Err(invalid(
            what,
            format!("longitude {lon}"),
            "a longitude of -180 to 180 degrees",
        ));
    }
    LatLon::from_degrees(lat, lon)
        .ok_or_else(|| invalid(what, format!("{lat}, {lon}"), "a position J2735 can carry"))
}

/// Member `name` of `obj`; missing (or `null`) is an error naming `what`.
fn member<'a>(obj: &'a Map<String, Value>, name: &str, what: &str) -> Result<&'a Value, Problem> {
    obj.get(name)
        .filter(|v| !v.is_null())
        .ok_or_else(|| Problem::Missing { what: what.into() })
}

/// `v` as an object.
fn object<'a>(v: &'a Value, what: &str) -> Result<&'a Map<String, Value>, Problem> {
    v.as_object()
        .ok_or_else(|| wrong_type(what, "an object", v))
}

/// `v` as a string.
fn string<'a>(v: &'a Value, what: &str) -> Result<&'a str, Problem> {
    v.as_str().ok_or_else(|| wrong_type(what, "a string", v))
}

/// `v` as a finite number.
fn number(v: &Value, what: &str) -> Result<f64, Problem> {
    v.as_f64()
        .filter(|x| x.is_finite())
        .ok_or_else(|| wrong_type(what, "a number", v))
}

/// A [`Problem::WrongType`] for `found`.
fn wrong_type(what: &str, expected: &'static str, found: &Value) -> Problem {
    Problem::WrongType {
        what: what.into(),
        expected,
        found: match found {
            Value::Null => "null",
            Value::Bool(_) => "a boolean",
            Value::Number(_) => "a number",
            Value::String(_) => "a string",
            Value::Array(_) => "an array",
            Value::Object(_) => "an object",
        },
    }
}

/// A [`Problem::Invalid`].
fn invalid(what: &str, value: impl fmt::Display, expected: impl Into<String>) -> Problem {
    Problem::Invalid {
        what: what.into(),
        value: value.to_string(),
        expected: expected.into(),
    }
}

// ---------------------------------------------------------------------------------------
// Geometry helpers

/// Station of the point of `lane` nearest to `p`, and the distance to it.
fn project(lane: &RoadLane, p: [f64; 2]) -> Option<(f64, f64)> {
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
fn angle_diff(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rfc3339_forms() {
        assert_eq!(rfc3339_unix_ms("1970-01-01T00:00:00Z"), Some(0));
        // 2025-11-22T04:16:01.500Z, the instant of clock.rs' test.
        assert_eq!(
            rfc3339_unix_ms("2025-11-22T04:16:01.5Z"),
            Some(1_763_784_961_500)
        );
        assert_eq!(
            rfc3339_unix_ms("2025-11-21t21:16:01.500123-07:00"),
            Some(1_763_784_961_500)
        );
        assert_eq!(
            rfc3339_unix_ms("2025-11-22 09:46:01.5+05:30"),
            Some(1_763_784_961_500)
        );
        assert!(rfc3339_unix_ms("2024-02-29T00:00:00Z").is_some());
        for bad in [
            "",
            "2025-02-29T00:00:00Z",
            "2025-13-01T00:00:00Z",
            "2025-11-22T24:00:00Z",
            "2025-11-22T10:00:00",
            "2025-11-22T10:00:00.Z",
            "2025-11-22T10:00:00+0700",
            "1969-12-31T23:59:59Z",
            "2025-11-22",
            "２０２５-11-22T10:00:00Z",
        ] {
            assert_eq!(rfc3339_unix_ms(bad), None, "{bad}");
        }
    }

    #[test]
    fn samples_cover_the_path() {
        let s = sample_path(&[[0.0, 0.0], [0.0, 100.0], [100.0, 100.0]]);
        assert_eq!(s.first().map(|x| x.0), Some([0.0, 0.0]));
        assert_eq!(s.last().map(|x| x.0), Some([100.0, 100.0]));
        assert!(s.iter().all(|(_, b)| *b == 0.0 || *b == 90.0));
        assert!(s.len() >= 40);
    }

    #[test]
    fn packet_ids_are_stable_and_distinct() {
        let zone = |id: &str| WzdxZone {
            feature_index: 0,
            event_id: Some(id.into()),
            road_names: vec![],
            direction: None,
            closed_lanes: vec![1],
            speed_only: false,
            start_m: 0.0,
            end_m: 10.0,
            speed_limit: None,
            start_unix_ms: 90_000,
            end_unix_ms: 150_001,
        };
        assert_eq!(zone("a").packet_id(), zone("a").packet_id());
        assert_ne!(zone("a").packet_id(), zone("b").packet_id());
        // 00:01:00 to 00:02:30.001: 2 minutes from the start minute, rounded up -> 2.
        assert_eq!(zone("a").duration_min(), 2);
    }
}
