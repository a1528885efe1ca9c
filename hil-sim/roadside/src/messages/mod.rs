//! The MAP and TIM a roadside unit broadcasts for a [`Road`] and a [`WorkZone`], and the
//! PSM of each road worker its camera tracks ([`build_psm`]).
//!
//! The messages are built directly as the codec's generated J2735 types ([`build_map`] in
//! `map`, [`build_tim`] in `tim`), so the compiler checks their structure; every
//! constrained number goes through its type's checked `new` (a value out of range is a
//! [`BuildError::OutOfRange`]), and each built frame is encoded once more to check the
//! SIZE constraints of its lists. [`encode`] gives the UPER bytes that go on the air.

mod map;
mod psm;
mod tim;

pub use map::build_map;
pub use psm::{build_psm, Worker, MAX_CRUMBS};
pub use tim::build_tim;

use crate::clock::Utc;
use crate::road::{Road, RoadLane};
use j2735::msg::common::{
    HeadingSlice, Latitude, Longitude, NodeOffsetPointXY, NodeXY20b, NodeXY22b, NodeXY24b,
    NodeXY26b, NodeXY28b, NodeXY32b, OffsetB10, OffsetB11, OffsetB12, OffsetB13, OffsetB14,
    OffsetB16, Position3D,
};
use j2735::uper::Extensions;
use j2735::MessageFrame;
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
    /// A number does not fit its J2735 type (`field` names the member).
    OutOfRange {
        /// The J2735 member.
        field: &'static str,
        /// The value given.
        value: i64,
    },
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
            Self::OutOfRange { field, value } => {
                write!(f, "{field} {value} is out of the range of its J2735 type")
            }
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

/// The smallest node-XY form holding the offset from `a` to `b` (centimetres): the
/// first whose largest magnitude (511, 1023, ... 32767) covers both coordinates.
fn node_xy(lane: u8, a: [f64; 2], b: [f64; 2]) -> Result<NodeOffsetPointXY, BuildError> {
    use NodeOffsetPointXY as N;
    let (x, y) = (cm(b[0] - a[0]), cm(b[1] - a[1]));
    let f = "node-XY offset";
    Ok(match x.abs().max(y.abs()) {
        0..=511 => N::NodeXY1(NodeXY20b {
            x: fit(f, x, OffsetB10::new)?,
            y: fit(f, y, OffsetB10::new)?,
        }),
        512..=1023 => N::NodeXY2(NodeXY22b {
            x: fit(f, x, OffsetB11::new)?,
            y: fit(f, y, OffsetB11::new)?,
        }),
        1024..=2047 => N::NodeXY3(NodeXY24b {
            x: fit(f, x, OffsetB12::new)?,
            y: fit(f, y, OffsetB12::new)?,
        }),
        2048..=4095 => N::NodeXY4(NodeXY26b {
            x: fit(f, x, OffsetB13::new)?,
            y: fit(f, y, OffsetB13::new)?,
        }),
        4096..=8191 => N::NodeXY5(NodeXY28b {
            x: fit(f, x, OffsetB14::new)?,
            y: fit(f, y, OffsetB14::new)?,
        }),
        8192..=32767 => N::NodeXY6(NodeXY32b {
            x: fit(f, x, OffsetB16::new)?,
            y: fit(f, y, OffsetB16::new)?,
        }),
        m => {
            return Err(BuildError::OffsetTooLarge {
                lane,
                metres: m as f64 / 100.0,
            })
        }
    })
}

/// Metres to centimetres (rounded).
fn cm(m: f64) -> i64 {
    (m * 100.0).round() as i64
}

/// m/s to J2735 `Velocity` (0.02 m/s units, 8191 = unavailable).
fn velocity(mps: f64) -> i64 {
    ((mps / 0.02).round() as i64).clamp(0, 8190)
}

/// `value` as the J2735 type whose checked constructor is `new` (member `field`).
fn fit<P: TryFrom<i64>, T>(
    field: &'static str,
    value: i64,
    new: fn(P) -> Option<T>,
) -> Result<T, BuildError> {
    P::try_from(value)
        .ok()
        .and_then(new)
        .ok_or(BuildError::OutOfRange { field, value })
}

/// A `Position3D` without elevation.
fn position(at: geodesy::LatLon) -> Result<Position3D, BuildError> {
    Ok(Position3D {
        lat: fit("lat", at.lat_e7().into(), Latitude::new)?,
        long: fit("long", at.lon_e7().into(), Longitude::new)?,
        elevation: None,
        regional: None,
        extensions: Extensions::new(),
    })
}

/// A `HeadingSlice` from its 16 bits, the first sector in the top bit.
fn heading_bits(bits: u16) -> Result<HeadingSlice, BuildError> {
    let mut slice = HeadingSlice::zeros(16).ok_or(BuildError::Codec("HeadingSlice".into()))?;
    for i in 0..16 {
        slice.0.set(i, bits & (0x8000 >> i) != 0);
    }
    Ok(slice)
}

/// Checks the SIZE constraints of a built frame's lists (the codec encodes it once).
fn checked(frame: MessageFrame) -> Result<Box<MessageFrame>, BuildError> {
    encode(&frame)?;
    Ok(Box::new(frame))
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
        let form = |m: f64| match node_xy(1, [0.0, 0.0], [m, 0.0]).unwrap() {
            NodeOffsetPointXY::NodeXY1(_) => "node-XY1",
            NodeOffsetPointXY::NodeXY2(_) => "node-XY2",
            NodeOffsetPointXY::NodeXY3(_) => "node-XY3",
            NodeOffsetPointXY::NodeXY4(_) => "node-XY4",
            NodeOffsetPointXY::NodeXY5(_) => "node-XY5",
            NodeOffsetPointXY::NodeXY6(_) => "node-XY6",
            other => panic!("{other:?}"),
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

    fn zone(closed: u8, start_m: f64, end_m: f64) -> WorkZone {
        WorkZone {
            closed_lanes: vec![closed],
            start_m,
            end_m,
            speed_limit: Some(SignSpeed {
                value: 40,
                mph: false,
            }),
            packet_id: *b"TESTZONE1",
            msg_cnt: 1,
            start: Utc::from_unix_ms(1_795_341_600_000),
            duration_min: DURATION_INDEFINITE,
        }
    }

    fn road(length_m: f64) -> Road {
        let reference = geodesy::LatLon::from_degrees(39.7392, -104.9903).unwrap();
        Road::straight(reference, 90.0, length_m, (2, 1), 3.6, 80.0)
    }

    #[test]
    fn numbers_out_of_their_j2735_range_are_errors() {
        // MsgCount is 0..127, MinutesDuration 0..32000 (J2735 2020).
        assert_eq!(
            build_map(&road(1000.0), 1, 128, None).unwrap_err(),
            BuildError::OutOfRange {
                field: "revision",
                value: 128
            }
        );
        assert!(build_map(&road(1000.0), 1, 127, None).is_ok());
        let mut z = zone(1, 100.0, 200.0);
        z.duration_min = 32001;
        assert_eq!(
            build_tim(&road(1000.0), &z).unwrap_err(),
            BuildError::OutOfRange {
                field: "durationTime",
                value: 32001
            }
        );
        z.duration_min = 32000;
        assert!(build_tim(&road(1000.0), &z).is_ok());
    }

    #[test]
    fn a_path_over_the_node_list_size_is_an_error() {
        // NodeSetXY holds 2..63 nodes; nodes are at most 300 m apart, so a 19.5 km zone
        // path needs 66 of them.
        let long = build_tim(&road(20_000.0), &zone(1, 0.0, 19_500.0));
        assert!(matches!(long, Err(BuildError::Codec(_))), "{long:?}");
        assert!(build_tim(&road(20_000.0), &zone(1, 0.0, 18_000.0)).is_ok());
    }
}
