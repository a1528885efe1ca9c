//! Exact tangent-plane transform in f64 through earth-centred coordinates.

use super::{LatLon, RAD_PER_E7, WGS84_A, WGS84_E2};

/// The exact east/north tangent plane at a reference position, in f64.
///
/// Longitudes are handled relative to the reference, so the transform works in a
/// rotated earth-centred frame whose x axis passes through the reference meridian.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFrame64 {
    origin: LatLon,
    height: f64,
    sin0: f64,
    cos0: f64,
    /// Reference point in the rotated earth-centred frame (x, z; y is zero).
    x0: f64,
    z0: f64,
}

/// Prime-vertical radius of curvature at latitude with sine `s`.
pub(crate) fn prime_vertical(s: f64) -> f64 {
    WGS84_A / libm::sqrt(1.0 - WGS84_E2 * s * s)
}

impl LocalFrame64 {
    /// The plane tangent to the ellipsoid at `origin`, lifted to `height_m` metres
    /// (J2735 elevation; 0 when unknown). Non-finite heights count as 0.
    pub fn new(origin: LatLon, height_m: f64) -> Self {
        let height = if height_m.is_finite() { height_m } else { 0.0 };
        let phi = origin.lat_e7() as f64 * RAD_PER_E7;
        let (sin0, cos0) = (libm::sin(phi), libm::cos(phi));
        let n = prime_vertical(sin0);
        LocalFrame64 {
            origin,
            height,
            sin0,
            cos0,
            x0: (n + height) * cos0,
            z0: (n * (1.0 - WGS84_E2) + height) * sin0,
        }
    }

    /// The reference position.
    pub fn origin(&self) -> LatLon {
        self.origin
    }

    /// The reference height in metres.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// East and north metres of `p` (taken at the reference height).
    pub fn to_local(&self, p: LatLon) -> (f64, f64) {
        let (dlat, dlon) = p.delta_from(self.origin);
        let phi = (self.origin.lat_e7() as f64 + dlat as f64) * RAD_PER_E7;
        let lam = dlon as f64 * RAD_PER_E7;
        let (s, c) = (libm::sin(phi), libm::cos(phi));
        let n = prime_vertical(s);
        let x = (n + self.height) * c * libm::cos(lam);
        let y = (n + self.height) * c * libm::sin(lam);
        let z = (n * (1.0 - WGS84_E2) + self.height) * s;
        let north = -self.sin0 * (x - self.x0) + self.cos0 * (z - self.z0);
        (y, north)
    }

    /// The position at `east`, `north` metres on the reference-height surface,
    /// rounded to 1e-7 degree; `None` for non-finite input or off the globe.
    pub fn to_wgs84(&self, east: f64, north: f64) -> Option<LatLon> {
        if !(east.is_finite() && north.is_finite()) {
            return None;
        }
        let r = prime_vertical(self.sin0) + self.height;
        let mut up = -(east * east + north * north) / (2.0 * r);
        let mut geo = (0.0, 0.0);
        for _ in 0..3 {
            let x = self.x0 - self.sin0 * north + self.cos0 * up;
            let z = self.z0 + self.cos0 * north + self.sin0 * up;
            let (phi, lam, h) = geodetic(x, east, z);
            geo = (phi, lam);
            up -= h - self.height;
        }
        let dlat = libm::round(geo.0 / RAD_PER_E7) as i64 - self.origin.lat_e7() as i64;
        let dlon = libm::round(geo.1 / RAD_PER_E7) as i64;
        LatLon::offset_by(self.origin, dlat, dlon)
    }
}

/// Latitude (rad), longitude (rad) and height of an earth-centred point.
fn geodetic(x: f64, y: f64, z: f64) -> (f64, f64, f64) {
    let p = libm::hypot(x, y);
    let lam = libm::atan2(y, x);
    let mut phi = libm::atan2(z, p * (1.0 - WGS84_E2));
    let mut h = 0.0;
    for _ in 0..5 {
        let s = libm::sin(phi);
        let n = prime_vertical(s);
        h = p / libm::cos(phi) - n;
        phi = libm::atan2(z, p * (1.0 - WGS84_E2 * n / (n + h)));
    }
    (phi, lam, h)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_exact() {
        let origin = LatLon::new(404_744_115, -1_049_690_138).unwrap_or_default();
        let f = LocalFrame64::new(origin, 1500.0);
        for &(e, n) in &[(0.0, 0.0), (1234.5, -987.6), (-4000.0, 3000.0)] {
            let p = f.to_wgs84(e, n).unwrap_or_default();
            let (e2, n2) = f.to_local(p);
            assert!((e2 - e).abs() < 0.01 && (n2 - n).abs() < 0.01, "{e2} {n2}");
        }
        assert_eq!(f.to_local(origin), (0.0, 0.0));
        assert!(f.to_wgs84(f64::NAN, 0.0).is_none());
        let _ = f.to_wgs84(1e30, 0.0);
    }
}
