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

mod cones;
mod error;
mod geometry;
mod json;
mod lane_map;
mod rfc3339;
mod wzdx;
mod wzdx_event;
mod wzdx_match;

#[cfg(test)]
mod tests;

pub use cones::load_cones;
pub use error::{InputError, Problem};
pub use lane_map::load_lane_map;
pub use rfc3339::rfc3339_unix_ms;
pub use wzdx::{work_zones_from_wzdx, WzdxZone};

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
