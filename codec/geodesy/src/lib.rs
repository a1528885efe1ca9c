//! WGS84 positions and the local east/north tangent plane (ENU) around a reference.
//!
//! Positions travel as J2735 integers ([`LatLon`], 1e-7 degree) and offsets as
//! centimetres ([`OffsetCm`]) until converted into local metres ([`Point`]).
//! Two conversions are provided:
//!
//! * [`LocalFrame64`]: the exact tangent-plane transform through ECEF in f64, for hosts
//!   and for building models.
//! * [`LocalFrame32`]: a second-order series in the *integer* latitude/longitude deltas
//!   from the reference, evaluated in f32. Deltas stay exact in f32 up to about 180 km,
//!   so single precision keeps centimetre level within a few kilometres.
//!
//! Both keep the point at the reference's ellipsoidal height, so the plane is the
//! one a MAP or TIM encoder with the same reference uses. `tests/geodesy.rs`
//! measures both against an independent ECEF transform and a Vincenty geodesic.
//!
//! The crate is `no_std` and allocation-free: the roadside (`hil-sim/roadside`) builds its
//! lane maps with it on a host, the OBU core (`obu`, re-exported as `obu::geo`) and its
//! firmware use it on the vehicle. It is written by hand rather than taken from a
//! geodesy library because it must run without `std` and keep J2735's integer units
//! (1e-7 degree, centimetres) end to end.
#![no_std]
#![forbid(unsafe_code)]
#![warn(missing_docs)]

mod exact;
mod fast;

pub use exact::LocalFrame64;
pub use fast::LocalFrame32;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// WGS84 semi-major axis in metres.
pub const WGS84_A: f64 = 6_378_137.0;
/// WGS84 flattening.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// WGS84 first eccentricity squared.
pub const WGS84_E2: f64 = WGS84_F * (2.0 - WGS84_F);

/// Radians per 1e-7 degree.
pub(crate) const RAD_PER_E7: f64 = core::f64::consts::PI / 180.0 * 1e-7;
/// 1e-7 degree units in a full turn.
const TURN_E7: i64 = 3_600_000_000;

/// A WGS84 position in J2735 units of 1e-7 degree.
///
/// Latitude is in `-900_000_000..=900_000_000`, longitude in
/// `-1_799_999_999..=1_800_000_000`; the J2735 "unavailable" values are rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct LatLon {
    lat: i32,
    lon: i32,
}

impl LatLon {
    /// Latitude and longitude 0.
    pub const ZERO: LatLon = LatLon { lat: 0, lon: 0 };

    /// J2735 `Latitude` value meaning "unavailable".
    pub const LAT_UNAVAILABLE: i32 = 900_000_001;
    /// J2735 `Longitude` value meaning "unavailable".
    pub const LON_UNAVAILABLE: i32 = 1_800_000_001;

    /// A position from J2735 integers, `None` when out of range or unavailable.
    pub const fn new(lat_e7: i32, lon_e7: i32) -> Option<Self> {
        let lat_ok = lat_e7 >= -900_000_000 && lat_e7 <= 900_000_000;
        let lon_ok = lon_e7 >= -1_799_999_999 && lon_e7 <= 1_800_000_000;
        if lat_ok && lon_ok {
            Some(LatLon {
                lat: lat_e7,
                lon: lon_e7,
            })
        } else {
            None
        }
    }

    /// A position from degrees, rounded to 1e-7 degree; `None` for NaN or out of range.
    pub fn from_degrees(lat_deg: f64, lon_deg: f64) -> Option<Self> {
        let lat = round_e7(lat_deg)?;
        let lon = round_e7(lon_deg)?;
        LatLon::new(lat, lon)
    }

    /// Latitude in 1e-7 degree.
    pub const fn lat_e7(self) -> i32 {
        self.lat
    }

    /// Longitude in 1e-7 degree.
    pub const fn lon_e7(self) -> i32 {
        self.lon
    }

    /// Latitude in degrees.
    pub fn lat_deg(self) -> f64 {
        self.lat as f64 * 1e-7
    }

    /// Longitude in degrees.
    pub fn lon_deg(self) -> f64 {
        self.lon as f64 * 1e-7
    }

    /// Latitude and longitude deltas from `origin` in 1e-7 degree, the longitude
    /// wrapped into one half turn either side.
    pub(crate) fn delta_from(self, origin: LatLon) -> (i32, i32) {
        let dlat = self.lat as i64 - origin.lat as i64;
        let dlon = wrap_lon_delta(self.lon as i128 - origin.lon as i128);
        (dlat as i32, dlon as i32)
    }

    /// `origin` shifted by integer deltas in 1e-7 degree, longitude wrapped; `None` off
    /// the globe.
    pub fn offset_by(origin: LatLon, dlat: i64, dlon: i64) -> Option<LatLon> {
        let lat = (origin.lat as i64).saturating_add(dlat);
        let lon = wrap_lon_delta(origin.lon as i128 + dlon as i128);
        let lat = i32::try_from(lat).ok()?;
        LatLon::new(lat, lon as i32)
    }
}

/// Wraps a longitude (delta) in 1e-7 degree into `(-180, 180]` degrees.
fn wrap_lon_delta(d: i128) -> i64 {
    let turn = TURN_E7 as i128;
    let half = turn / 2;
    ((d + half - 1).rem_euclid(turn) - half + 1) as i64
}

/// Rounds degrees to i32 1e-7 degree, `None` if not finite or out of i32.
fn round_e7(deg: f64) -> Option<i32> {
    let v = libm::round(deg * 1e7);
    if v.is_finite() && v.abs() <= i32::MAX as f64 {
        Some(v as i32)
    } else {
        None
    }
}

/// A point of the local plane in metres: `x` east, `y` north of the reference.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Point {
    /// East of the reference, metres.
    pub x: f32,
    /// North of the reference, metres.
    pub y: f32,
}

impl Point {
    /// A point from east and north metres.
    pub const fn new(x: f32, y: f32) -> Self {
        Point { x, y }
    }

    /// Distance to `other` in metres.
    pub fn distance(self, other: Point) -> f32 {
        libm::hypotf(self.x - other.x, self.y - other.y)
    }

    /// True if both coordinates are finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

/// A J2735-style offset in centimetres (east, north), as node deltas carry it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct OffsetCm {
    /// East, centimetres.
    pub x: i32,
    /// North, centimetres.
    pub y: i32,
}

impl OffsetCm {
    /// An offset from east and north centimetres.
    pub const fn new(x: i32, y: i32) -> Self {
        OffsetCm { x, y }
    }

    /// The offset in metres as a local point.
    pub fn to_point(self) -> Point {
        Point::new(self.x as f32 / 100.0, self.y as f32 / 100.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn latlon_ranges() {
        assert!(LatLon::new(LatLon::LAT_UNAVAILABLE, 0).is_none());
        assert!(LatLon::new(0, LatLon::LON_UNAVAILABLE).is_none());
        assert!(LatLon::new(-900_000_000, 1_800_000_000).is_some());
        assert!(LatLon::from_degrees(f64::NAN, 0.0).is_none());
        assert_eq!(
            LatLon::from_degrees(40.5, -105.25).map(|p| p.lat_e7()),
            Some(405_000_000)
        );
    }

    #[test]
    fn longitude_wraps() {
        let a = LatLon::new(0, 1_799_999_000).unwrap_or_default();
        let b = LatLon::new(0, -1_799_999_000).unwrap_or_default();
        assert_eq!(b.delta_from(a), (0, 2_000));
        assert_eq!(a.delta_from(b), (0, -2_000));
        let c = LatLon::offset_by(a, 0, 2_000);
        assert_eq!(c.map(|p| p.lon_e7()), Some(-1_799_999_000));
        assert!(LatLon::offset_by(a, 1_000_000_000, 0).is_none());
    }

    #[test]
    fn offsets_to_points() {
        let p = OffsetCm::new(150, -250).to_point();
        assert_eq!(p, Point::new(1.5, -2.5));
        assert!((Point::new(3.0, 4.0).distance(Point::default()) - 5.0).abs() < 1e-6);
    }
}
