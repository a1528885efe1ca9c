//! A certificate's region, kept without the certificate's bytes, and the test whether a
//! location lies in it.

use heapless::Vec;
use j2735::envelope::ieee1609dot2::{GeographicRegion, TwoDLocation};

use crate::capacity::MAX_REGION_POINTS;
use crate::geo::LatLon;
use crate::geo::LocalFrame64;

/// Why a region could not be kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RegionError {
    /// More points than [`MAX_REGION_POINTS`].
    TooLarge,
    /// A latitude or longitude out of range.
    Invalid,
}

/// `GeographicRegion` as the verifier keeps it.
#[derive(Debug, Clone, PartialEq)]
pub enum Region {
    /// A centre and a radius, metres.
    Circle {
        /// The centre.
        center: LatLon,
        /// The radius, metres.
        radius_m: u16,
    },
    /// The union of rectangles: (north-west, south-east) corners, in pairs.
    Rectangles(Vec<LatLon, MAX_REGION_POINTS>),
    /// One polygon's vertices.
    Polygon(Vec<LatLon, MAX_REGION_POINTS>),
    /// Countries and subdivisions: not checked (no border data on board), accepted.
    Identified,
}

fn lat_lon(p: TwoDLocation) -> Result<LatLon, RegionError> {
    LatLon::new(p.latitude, p.longitude).ok_or(RegionError::Invalid)
}

impl Region {
    /// Keeps `region`.
    ///
    /// # Errors
    ///
    /// [`RegionError`] when it has too many points or invalid coordinates.
    pub fn from_certificate(region: &GeographicRegion<'_>) -> Result<Self, RegionError> {
        let points = |locations: &j2735::envelope::ieee1609dot2::Locations<'_>| {
            let mut out = Vec::new();
            for p in locations.iter() {
                out.push(lat_lon(p)?).map_err(|_| RegionError::TooLarge)?;
            }
            Ok::<_, RegionError>(out)
        };
        Ok(match region {
            GeographicRegion::Circular { center, radius_m } => Region::Circle {
                center: lat_lon(*center)?,
                radius_m: *radius_m,
            },
            GeographicRegion::Rectangular(l) => Region::Rectangles(points(l)?),
            GeographicRegion::Polygonal(l) => Region::Polygon(points(l)?),
            GeographicRegion::Identified(_) | GeographicRegion::Other => Region::Identified,
        })
    }

    /// Whether `p` lies in the region (on the edge counts as inside).
    pub fn contains(&self, p: LatLon) -> bool {
        match self {
            Region::Circle { center, radius_m } => {
                let (east, north) = LocalFrame64::new(*center, 0.0).to_local(p);
                libm::hypot(east, north) <= f64::from(*radius_m)
            }
            Region::Rectangles(corners) => corners.chunks_exact(2).any(|c| {
                let (nw, se) = (c[0], c[1]);
                (se.lat_e7()..=nw.lat_e7()).contains(&p.lat_e7())
                    && (nw.lon_e7()..=se.lon_e7()).contains(&p.lon_e7())
            }),
            Region::Polygon(vertices) => polygon_contains(vertices, p),
            Region::Identified => true,
        }
    }
}

/// Even-odd rule in a local plane centred on `p` (metres), so that the test is a ray from
/// the origin along +x.
fn polygon_contains(vertices: &[LatLon], p: LatLon) -> bool {
    let frame = LocalFrame64::new(p, 0.0);
    let mut inside = false;
    let n = vertices.len();
    for i in 0..n {
        let (ax, ay) = frame.to_local(vertices[i]);
        let (bx, by) = frame.to_local(vertices[(i + 1) % n]);
        if (ay > 0.0) != (by > 0.0) {
            let x = ax + (0.0 - ay) * (bx - ax) / (by - ay);
            if x > 0.0 {
                inside = !inside;
            }
        }
    }
    inside
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ll(lat: f64, lon: f64) -> LatLon {
        LatLon::from_degrees(lat, lon).unwrap()
    }

    #[test]
    fn circle_by_distance() {
        let c = Region::Circle {
            center: ll(42.0, -83.0),
            radius_m: 1000,
        };
        assert!(c.contains(ll(42.0089, -83.0))); // ~989 m north
        assert!(!c.contains(ll(42.0091, -83.0))); // ~1011 m
    }

    #[test]
    fn rectangles_and_polygons() {
        let mut corners = Vec::new();
        corners.extend([ll(42.1, -83.1), ll(42.0, -83.0)]);
        let r = Region::Rectangles(corners);
        assert!(r.contains(ll(42.05, -83.05)) && !r.contains(ll(42.15, -83.05)));
        let mut tri = Vec::new();
        tri.extend([ll(42.0, -83.0), ll(42.0, -82.9), ll(42.1, -83.0)]);
        let poly = Region::Polygon(tri);
        assert!(poly.contains(ll(42.02, -82.98)));
        assert!(!poly.contains(ll(42.08, -82.92)));
    }
}
