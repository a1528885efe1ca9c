//! A TIM region (`GeographicalPath`): anchor, path or circle, width, directions.

use heapless::Vec;

use super::{Directionality, HeadingSlice};
use crate::capacity::MAX_PATH_NODES;
use crate::geo::{LatLon, LocalFrame32, Point};
use crate::lane::ModelError;
use crate::math::{bearing_deg, heading_diff};

/// Largest node offset from the anchor accepted, metres (beyond, f32 loses centimetres).
const MAX_OFFSET_M: f32 = 100_000.0;

/// Region geometry (TIM `description`).
#[derive(Debug, Clone, PartialEq)]
pub enum RegionShape {
    /// A path: nodes in metres from the anchor, in the sender's node order.
    Path(Vec<Point, MAX_PATH_NODES, u8>),
    /// A circle around the anchor (TIM `geometry` with `circle`).
    Circle {
        /// Radius in metres.
        radius_m: f32,
    },
}

/// One region of a work zone.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    frame: LocalFrame32,
    /// `laneWidth` in metres.
    pub lane_width_m: f32,
    /// `directionality`.
    pub directionality: Directionality,
    /// `direction` (HeadingSlice).
    pub heading: HeadingSlice,
    /// `closedPath`: the last node joins the first.
    pub closed_path: bool,
    /// `extent` of a geometry region in metres (`None` when absent, infinite for
    /// `forever`): how far the information applies (kept for the display).
    pub extent_m: Option<f32>,
    /// Geometry.
    pub shape: RegionShape,
    /// Path length in metres (sum of the segments).
    length_m: f32,
}

/// Where a point lies relative to a region path.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PathFit {
    /// Metres from the first node along the path (negative before it).
    pub along: f32,
    /// Signed distance from the path, metres (positive left of node order).
    pub lateral: f32,
    /// Bearing of the nearest segment in node order, degrees.
    pub bearing_deg: f32,
    /// Path length in metres.
    pub length: f32,
}

impl Region {
    /// A path region anchored at `anchor` (elevation in metres, 0 when absent) with no
    /// nodes yet. Push the anchor itself (`Point::new(0.0, 0.0)`) first when it is the
    /// start of the path, as the project's senders do.
    pub fn path(anchor: LatLon, elevation_m: f32, lane_width_m: f32) -> Self {
        Region {
            frame: LocalFrame32::new(anchor, elevation_m as f64),
            lane_width_m: crate::math::finite_or(lane_width_m, 0.0).max(0.0),
            directionality: Directionality::Both,
            heading: HeadingSlice::ALL,
            closed_path: false,
            extent_m: None,
            shape: RegionShape::Path(Vec::new()),
            length_m: 0.0,
        }
    }

    /// A circle region of `radius_m` around `anchor`.
    pub fn circle(anchor: LatLon, elevation_m: f32, radius_m: f32) -> Self {
        let mut r = Region::path(anchor, elevation_m, 0.0);
        r.shape = RegionShape::Circle {
            radius_m: crate::math::finite_or(radius_m, 0.0).max(0.0),
        };
        r
    }

    /// The anchor position.
    pub fn anchor(&self) -> LatLon {
        self.frame.origin()
    }

    /// The anchor's local plane.
    pub fn frame(&self) -> &LocalFrame32 {
        &self.frame
    }

    /// Appends a path node at `p` metres from the anchor. A node within 1 cm of the
    /// previous one is skipped (a zero-length segment has no direction).
    pub fn push_node(&mut self, p: Point) -> Result<(), ModelError> {
        let RegionShape::Path(nodes) = &mut self.shape else {
            return Err(ModelError::InvalidValue);
        };
        if !(p.is_finite() && p.x.abs() < MAX_OFFSET_M && p.y.abs() < MAX_OFFSET_M) {
            return Err(ModelError::InvalidValue);
        }
        let step = nodes.last().map_or(0.0, |q| q.distance(p));
        if !nodes.is_empty() && step < 0.01 {
            return Ok(());
        }
        nodes.push(p).map_err(|_| ModelError::CapacityExceeded)?;
        self.length_m += step;
        Ok(())
    }

    /// Appends a node given as a centimetre delta from the previous node (from the
    /// anchor for the first), as J2735 `node-XY` offsets are.
    pub fn push_delta_cm(&mut self, dx_cm: i32, dy_cm: i32) -> Result<(), ModelError> {
        let last = self.nodes().last().copied().unwrap_or_default();
        let p = Point::new(last.x + dx_cm as f32 / 100.0, last.y + dy_cm as f32 / 100.0);
        self.push_node(p)
    }

    /// Appends an absolute node (J2735 `node-LatLon`).
    pub fn push_latlon(&mut self, p: LatLon) -> Result<(), ModelError> {
        let local = self.frame.to_local(p);
        self.push_node(local)
    }

    /// Path nodes (empty for a circle).
    pub fn nodes(&self) -> &[Point] {
        match &self.shape {
            RegionShape::Path(nodes) => nodes,
            RegionShape::Circle { .. } => &[],
        }
    }

    /// True when a vehicle heading `heading_deg` on a path segment of bearing
    /// `path_bearing_deg` is concerned (directionality and heading slice).
    pub fn applies_to(&self, heading_deg: f32, path_bearing_deg: f32) -> bool {
        self.heading.contains(heading_deg)
            && self.directionality.allows(heading_deg, path_bearing_deg)
    }

    /// True when travel on a segment of `path_bearing_deg` heading `heading_deg` runs
    /// against the node order.
    pub fn is_reverse(heading_deg: f32, path_bearing_deg: f32) -> bool {
        heading_diff(heading_deg, path_bearing_deg) > 90.0
    }

    /// Fits a point (metres from the anchor) to the path; `None` without a segment.
    /// `along` runs past either end along the end segments.
    pub fn fit(&self, p: Point) -> Option<PathFit> {
        let nodes = self.nodes();
        let last = nodes.len().checked_sub(2)?;
        let mut best: Option<(f32, PathFit)> = None;
        let mut start = 0.0;
        for (i, w) in nodes.windows(2).enumerate() {
            let (d2, fit, len) = fit_segment(w[0], w[1], p, i == 0, i == last, start);
            if best.as_ref().is_none_or(|(b, _)| d2 < *b) {
                best = Some((d2, fit));
            }
            start += len;
        }
        best.map(|(_, f)| PathFit { length: start, ..f })
    }

    /// Path length in metres (0 for a circle).
    pub fn length(&self) -> f32 {
        self.length_m
    }

    /// For a circle: where a vehicle at `p` (metres from the centre) heading
    /// `heading_deg` meets it, as (metres along the heading to the edge, negative once
    /// inside or past; chord length). `None` for a path, a heading outside the heading
    /// slice, or a line of travel that misses the circle.
    pub fn circle_crossing(&self, p: Point, heading_deg: f32) -> Option<(f32, f32)> {
        let radius = self.radius()?;
        if !self.heading.contains(heading_deg) || !p.is_finite() {
            return None;
        }
        let h = heading_deg.to_radians();
        let (ux, uy) = (libm::sinf(h), libm::cosf(h));
        // The centre seen from the vehicle: ahead by `along`, aside by `aside`.
        let along = -(p.x * ux + p.y * uy);
        let aside = p.x * uy - p.y * ux;
        let half2 = radius * radius - aside * aside;
        if half2.is_nan() || half2 < 0.0 {
            return None;
        }
        let half = libm::sqrtf(half2);
        Some((along - half, 2.0 * half))
    }

    /// The circle radius in metres, `None` for a path.
    pub fn radius(&self) -> Option<f32> {
        match self.shape {
            RegionShape::Circle { radius_m } => Some(radius_m),
            RegionShape::Path(_) => None,
        }
    }
}

/// Distance squared, fit and segment length of `p` against segment `a`->`b`.
fn fit_segment(
    a: Point,
    b: Point,
    p: Point,
    open_start: bool,
    open_end: bool,
    start: f32,
) -> (f32, PathFit, f32) {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let (rx, ry) = (p.x - a.x, p.y - a.y);
    let len2 = dx * dx + dy * dy;
    let len = libm::sqrtf(len2);
    let t = if len2 > 0.0 {
        (rx * dx + ry * dy) / len2
    } else {
        0.0
    };
    let tc = t.clamp(0.0, 1.0);
    let (qx, qy) = (rx - dx * tc, ry - dy * tc);
    let lo = if open_start { f32::NEG_INFINITY } else { 0.0 };
    let hi = if open_end { f32::INFINITY } else { 1.0 };
    let lateral = if len > 0.0 {
        (dx * ry - dy * rx) / len
    } else {
        libm::hypotf(rx, ry)
    };
    let fit = PathFit {
        along: start + t.clamp(lo, hi) * len,
        lateral,
        bearing_deg: bearing_deg(dx, dy),
        length: 0.0,
    };
    (qx * qx + qy * qy, fit, len)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn straight() -> Region {
        let mut r = Region::path(LatLon::ZERO, 0.0, 3.6);
        for p in [(0.0, 0.0), (0.0, 50.0), (0.0, 100.0)] {
            assert!(r.push_node(Point::new(p.0, p.1)).is_ok());
        }
        r
    }

    #[test]
    fn circle_crossing_along_the_heading() {
        let c = Region::circle(LatLon::ZERO, 0.0, 50.0);
        // 200 m south of the centre heading north: the edge is 150 m ahead, chord 100 m.
        let (d, chord) = c.circle_crossing(Point::new(0.0, -200.0), 0.0).unwrap();
        assert!((d - 150.0).abs() < 1e-3 && (chord - 100.0).abs() < 1e-3);
        // 30 m aside: half chord 40 m (3-4-5).
        let (d, chord) = c.circle_crossing(Point::new(30.0, -200.0), 0.0).unwrap();
        assert!((d - 160.0).abs() < 1e-3 && (chord - 80.0).abs() < 1e-3);
        // Inside, at the centre: the edge was 50 m back.
        let (d, _) = c.circle_crossing(Point::new(0.0, 0.0), 90.0).unwrap();
        assert!((d + 50.0).abs() < 1e-3);
        // A line of travel that misses it, and a path region.
        assert!(c.circle_crossing(Point::new(60.0, -200.0), 0.0).is_none());
        assert!(straight()
            .circle_crossing(Point::new(0.0, 0.0), 0.0)
            .is_none());
    }

    #[test]
    fn fits_points() {
        let r = straight();
        let f = r.fit(Point::new(1.0, 70.0)).unwrap_or_default();
        assert!((f.along - 70.0).abs() < 1e-4 && (f.lateral + 1.0).abs() < 1e-4);
        assert!((f.length - 100.0).abs() < 1e-4);
        let f = r.fit(Point::new(0.0, -20.0)).unwrap_or_default();
        assert!((f.along + 20.0).abs() < 1e-4);
        assert!((r.length() - 100.0).abs() < 1e-4);
    }

    #[test]
    fn builds_from_offsets() {
        let mut r = Region::path(LatLon::ZERO, 0.0, 3.6);
        assert!(r.push_delta_cm(0, 0).is_ok() && r.push_delta_cm(100, 200).is_ok());
        assert!(r.push_delta_cm(100, 0).is_ok());
        assert_eq!(r.nodes()[2], Point::new(2.0, 2.0));
        assert_eq!(
            r.push_node(Point::new(f32::NAN, 0.0)),
            Err(ModelError::InvalidValue)
        );
        let p = r.frame().to_wgs84(Point::new(5.0, 5.0)).unwrap_or_default();
        assert!(r.push_latlon(p).is_ok());
        assert!((r.nodes()[3].x - 5.0).abs() < 0.02);
        assert!(r.push_node(Point::new(5.0, 5.005)).is_ok(), "1 cm: skipped");
        assert_eq!(r.nodes().len(), 4);
        let mut c = Region::circle(LatLon::ZERO, 0.0, 50.0);
        assert!(c.nodes().is_empty() && c.fit(Point::default()).is_none());
        assert_eq!((c.radius(), r.radius()), (Some(50.0), None));
        assert_eq!(c.push_node(Point::default()), Err(ModelError::InvalidValue));
    }

    #[test]
    fn directions() {
        let mut r = straight();
        r.directionality = Directionality::Forward;
        r.heading = HeadingSlice(0b1000_0000_0000_0001);
        assert!(r.applies_to(5.0, 0.0) && r.applies_to(350.0, 0.0));
        assert!(!r.applies_to(30.0, 0.0), "outside the heading slice");
        assert!(!r.applies_to(180.0, 0.0) && Region::is_reverse(180.0, 0.0));
    }
}
