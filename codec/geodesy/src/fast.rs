//! Tangent-plane transform in f32 from integer deltas (second-order series).

use super::exact::prime_vertical;
use super::{LatLon, Point, RAD_PER_E7, WGS84_E2};

/// Step (radians) of the central difference for the second latitude derivative.
const STEP: f64 = 1e-3;
/// Newton-style refinements in [`LocalFrame32::to_wgs84`].
const INVERSE_ITERATIONS: usize = 3;

/// East/north tangent plane at a reference, evaluated in f32 from the integer
/// latitude/longitude deltas `a`, `b` (1e-7 degree) to the reference:
///
/// `east = b (ke + keab a)`, `north = a (kn + knaa a) + knbb b^2`.
///
/// The coefficients are the Taylor expansion of the exact transform
/// ([`super::LocalFrame64`]) computed once in f64. Third-order terms, the only error
/// left, stay below a few millimetres within 5 km at mid latitudes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LocalFrame32 {
    origin: LatLon,
    ke: f32,
    keab: f32,
    kn: f32,
    knaa: f32,
    knbb: f32,
}

/// The north component of the exact transform along the reference meridian.
fn meridian_north(phi: f64, sin0: f64, cos0: f64, h: f64) -> f64 {
    let (s, c) = (libm::sin(phi), libm::cos(phi));
    let n = prime_vertical(s);
    -sin0 * (n + h) * c + cos0 * (n * (1.0 - WGS84_E2) + h) * s
}

impl LocalFrame32 {
    /// An all-zero frame at (0, 0) (placeholder for empty slots; converts nothing).
    pub const ZERO: LocalFrame32 = LocalFrame32 {
        origin: LatLon::ZERO,
        ke: 0.0,
        keab: 0.0,
        kn: 0.0,
        knaa: 0.0,
        knbb: 0.0,
    };

    /// The plane at `origin`, lifted to `height_m` (non-finite counts as 0).
    pub fn new(origin: LatLon, height_m: f64) -> Self {
        let h = if height_m.is_finite() { height_m } else { 0.0 };
        let phi = origin.lat_e7() as f64 * RAD_PER_E7;
        let (s, c) = (libm::sin(phi), libm::cos(phi));
        let n = prime_vertical(s);
        let dn = n * WGS84_E2 * s * c / (1.0 - WGS84_E2 * s * s);
        let m = n * (1.0 - WGS84_E2) / (1.0 - WGS84_E2 * s * s);
        let f = |p: f64| meridian_north(p, s, c, h);
        let f2 = (f(phi + STEP) - 2.0 * f(phi) + f(phi - STEP)) / (STEP * STEP);
        let u = RAD_PER_E7;
        LocalFrame32 {
            origin,
            ke: ((n + h) * c * u) as f32,
            keab: ((dn * c - (n + h) * s) * u * u) as f32,
            kn: ((m + h) * u) as f32,
            knaa: (f2 / 2.0 * u * u) as f32,
            knbb: ((n + h) * s * c / 2.0 * u * u) as f32,
        }
    }

    /// The reference position.
    pub fn origin(&self) -> LatLon {
        self.origin
    }

    /// Local metres of `p`.
    pub fn to_local(&self, p: LatLon) -> Point {
        let (dlat, dlon) = p.delta_from(self.origin);
        self.delta_to_local(dlat as f32, dlon as f32)
    }

    /// Local metres of integer deltas (1e-7 degree) from the reference.
    pub fn delta_to_local(&self, a: f32, b: f32) -> Point {
        Point {
            x: b * (self.ke + self.keab * a),
            y: a * (self.kn + self.knaa * a) + self.knbb * b * b,
        }
    }

    /// The position at local point `p`, `None` for non-finite input or off the globe.
    pub fn to_wgs84(&self, p: Point) -> Option<LatLon> {
        if !p.is_finite() || self.kn == 0.0 || self.ke == 0.0 {
            return None;
        }
        let mut a = p.y / self.kn;
        let mut b = p.x / self.ke;
        for _ in 0..INVERSE_ITERATIONS {
            a = (p.y - self.knaa * a * a - self.knbb * b * b) / self.kn;
            b = p.x / (self.ke + self.keab * a);
        }
        if !(a.is_finite() && b.is_finite()) {
            return None;
        }
        let (a, b) = (libm::roundf(a) as i64, libm::roundf(b) as i64);
        LatLon::offset_by(self.origin, a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::super::LocalFrame64;
    use super::*;

    #[test]
    fn matches_exact_within_5km() {
        let origin = LatLon::new(450_000_000, 70_000_000).unwrap_or_default();
        let exact = LocalFrame64::new(origin, 200.0);
        let fast = LocalFrame32::new(origin, 200.0);
        for &(e, n) in &[
            (5000.0, 0.0),
            (0.0, -5000.0),
            (3535.0, 3535.0),
            (-10.0, 2.0),
        ] {
            let p = exact.to_wgs84(e, n).unwrap_or_default();
            let q = fast.to_local(p);
            let (e2, n2) = exact.to_local(p);
            assert!((q.x as f64 - e2).abs() < 0.05, "{} {}", q.x, e2);
            assert!((q.y as f64 - n2).abs() < 0.05, "{} {}", q.y, n2);
            assert_eq!(fast.to_wgs84(q), Some(p));
        }
    }

    #[test]
    fn rejects_non_finite() {
        let fast = LocalFrame32::new(LatLon::default(), f64::NAN);
        assert!(fast.to_wgs84(Point::new(f32::NAN, 0.0)).is_none());
        assert!(fast.to_wgs84(Point::new(f32::MAX, f32::MAX)).is_none());
    }
}
