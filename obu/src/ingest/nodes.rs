//! Node offsets, positions, computed lanes and polyline thinning shared by MAP and TIM.

use j2735::msg::common::{
    ComputedLane, ComputedLaneOffsetXaxis, ComputedLaneOffsetYaxis, Latitude, Longitude,
    NodeOffsetPointXY, Position3D,
};
use j2735::msg::traveler_information::NodeOffsetPointLL;

use super::IngestError;
use crate::geo::{LatLon, Point};

/// One node of a J2735 node list: an offset from the previous node or a position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Step {
    /// Offset east and north (centimetres for node-XY, 1e-7 degree for node-LL).
    Offset(i32, i32),
    /// An absolute position (node-LatLon).
    At(LatLon),
}

/// A J2735 `Latitude`/`Longitude` pair, `None` when unavailable or out of range.
pub(crate) fn latlon(lat: Latitude, lon: Longitude) -> Option<LatLon> {
    LatLon::new(lat.get(), lon.get())
}

/// A `Position3D` as position and elevation in metres (0 when absent or unavailable).
pub(crate) fn position(p: &Position3D) -> Result<(LatLon, f32), IngestError> {
    let at = latlon(p.lat, p.long).ok_or(IngestError::InvalidReference)?;
    let elev = p
        .elevation
        .filter(|e| *e != j2735::msg::common::Elevation::UNAVAILABLE)
        .map_or(0.0, |e| e.get() as f32 * 0.1);
    Ok((at, elev))
}

/// A node-XY offset (centimetres) or node-LatLon position.
pub(crate) fn xy_step(p: &NodeOffsetPointXY) -> Result<Step, IngestError> {
    let xy = |x: i16, y: i16| Ok(Step::Offset(x as i32, y as i32));
    match p {
        NodeOffsetPointXY::NodeXY1(n) => xy(n.x.get(), n.y.get()),
        NodeOffsetPointXY::NodeXY2(n) => xy(n.x.get(), n.y.get()),
        NodeOffsetPointXY::NodeXY3(n) => xy(n.x.get(), n.y.get()),
        NodeOffsetPointXY::NodeXY4(n) => xy(n.x.get(), n.y.get()),
        NodeOffsetPointXY::NodeXY5(n) => xy(n.x.get(), n.y.get()),
        NodeOffsetPointXY::NodeXY6(n) => xy(n.x.get(), n.y.get()),
        NodeOffsetPointXY::NodeLatLon(n) => latlon(n.lat, n.lon)
            .map(Step::At)
            .ok_or(IngestError::InvalidValue),
        NodeOffsetPointXY::Regional(_) => Err(IngestError::UnsupportedNode),
    }
}

/// A node-LL offset (1e-7 degree, east = longitude, north = latitude) or position.
pub(crate) fn ll_step(p: &NodeOffsetPointLL) -> Result<Step, IngestError> {
    let ll = |lon: i32, lat: i32| Ok(Step::Offset(lon, lat));
    match p {
        NodeOffsetPointLL::NodeLL1(n) => ll(n.lon.get() as i32, n.lat.get() as i32),
        NodeOffsetPointLL::NodeLL2(n) => ll(n.lon.get() as i32, n.lat.get() as i32),
        NodeOffsetPointLL::NodeLL3(n) => ll(n.lon.get() as i32, n.lat.get() as i32),
        NodeOffsetPointLL::NodeLL4(n) => ll(n.lon.get(), n.lat.get()),
        NodeOffsetPointLL::NodeLL5(n) => ll(n.lon.get(), n.lat.get()),
        NodeOffsetPointLL::NodeLL6(n) => ll(n.lon.get(), n.lat.get()),
        NodeOffsetPointLL::NodeLatLon(n) => latlon(n.lat, n.lon)
            .map(Step::At)
            .ok_or(IngestError::InvalidValue),
        NodeOffsetPointLL::Regional(_) => Err(IngestError::UnsupportedNode),
    }
}

/// The position `step` leads to from `prev`, offsets multiplied by `zoom` (node-LL).
pub(crate) fn ll_next(prev: LatLon, step: Step, zoom: i64) -> Result<LatLon, IngestError> {
    match step {
        Step::At(p) => Ok(p),
        Step::Offset(dlon, dlat) => LatLon::offset_by(prev, dlat as i64 * zoom, dlon as i64 * zoom)
            .ok_or(IngestError::InvalidValue),
    }
}

/// The J2735 `scale` zoom factor 2^N of an `OffsetSystem` (1 when absent).
pub(crate) fn zoom(scale: Option<u8>) -> i64 {
    1i64 << scale.unwrap_or(0).min(15)
}

/// A computed lane's transform of a reference lane: each node moves relative to the
/// reference lane's first node, scaled per axis (`scaleXaxis`/`scaleYaxis`, steps of
/// 0.05 %), rotated clockwise by `rotateXY` (0.0125 degree) about that first node, then
/// translated by (`offsetXaxis`, `offsetYaxis`) (centimetres, times the path zoom).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Computed {
    offset: Point,
    sin: f32,
    cos: f32,
    scale: Point,
}

impl Computed {
    /// The transform of `c`, offsets multiplied by `zoom`.
    pub(crate) fn new(c: &ComputedLane, zoom: i64) -> Self {
        let x = match c.offset_xaxis {
            ComputedLaneOffsetXaxis::Small(v) => v.get() as f32,
            ComputedLaneOffsetXaxis::Large(v) => v.get() as f32,
        };
        let y = match c.offset_yaxis {
            ComputedLaneOffsetYaxis::Small(v) => v.get() as f32,
            ComputedLaneOffsetYaxis::Large(v) => v.get() as f32,
        };
        let z = zoom as f32 * 0.01;
        let angle = c
            .rotate_xy
            .map_or(0.0, |a| a.get() as f32 * 0.0125)
            .to_radians();
        let factor = |s: Option<j2735::msg::common::ScaleB12>| {
            1.0 + s.map_or(0.0, |s| s.get() as f32) * 0.0005
        };
        Computed {
            offset: Point::new(x * z, y * z),
            sin: libm::sinf(angle),
            cos: libm::cosf(angle),
            scale: Point::new(factor(c.scale_xaxis), factor(c.scale_yaxis)),
        }
    }

    /// Where node `p` of a reference lane starting at `first` goes.
    pub(crate) fn apply(&self, first: Point, p: Point) -> Point {
        let (x, y) = (
            (p.x - first.x) * self.scale.x,
            (p.y - first.y) * self.scale.y,
        );
        let (rx, ry) = (x * self.cos + y * self.sin, y * self.cos - x * self.sin);
        Point::new(first.x + rx + self.offset.x, first.y + ry + self.offset.y)
    }
}

/// Removes interior items of a polyline, the one whose removal moves the line least
/// first, until `fits` holds. Items with `keep` stay. Returns how many were removed;
/// [`IngestError::CapacityExceeded`] when nothing more can go.
pub(crate) fn thin<T, const N: usize>(
    items: &mut heapless::Vec<T, N>,
    pos: impl Fn(&T) -> Point,
    keep: impl Fn(&T) -> bool,
    fits: impl Fn(&[T]) -> bool,
) -> Result<usize, IngestError> {
    let mut removed = 0;
    while !fits(items) {
        let cost = |i: usize| {
            let (a, b, c) = (pos(&items[i - 1]), pos(&items[i]), pos(&items[i + 1]));
            segment_distance(a, c, b)
        };
        let victim = (1..items.len().saturating_sub(1))
            .filter(|&i| !keep(&items[i]))
            .min_by(|&i, &j| cost(i).total_cmp(&cost(j)))
            .ok_or(IngestError::CapacityExceeded)?;
        items.remove(victim);
        removed += 1;
    }
    Ok(removed)
}

/// Distance from `p` to the segment `a`-`b`.
fn segment_distance(a: Point, b: Point, p: Point) -> f32 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    Point::new(a.x + dx * t, a.y + dy * t).distance(p)
}

#[cfg(test)]
mod tests {
    use super::*;
    use j2735::msg::common::{Angle, DrivenLineOffsetLg, DrivenLineOffsetSm, LaneID, ScaleB12};

    fn computed(x: i16, y: i16, rot: Option<u16>, sx: Option<i16>) -> ComputedLane {
        let mut c = <ComputedLane as j2735::uper::Placeholder>::placeholder();
        c.reference_lane_id = LaneID::new(1).unwrap_or(c.reference_lane_id);
        c.offset_xaxis = match DrivenLineOffsetSm::new(x) {
            Some(v) => ComputedLaneOffsetXaxis::Small(v),
            None => ComputedLaneOffsetXaxis::Large(DrivenLineOffsetLg::new(x).unwrap_or(c_lg())),
        };
        c.offset_yaxis =
            ComputedLaneOffsetYaxis::Large(DrivenLineOffsetLg::new(y).unwrap_or(c_lg()));
        c.rotate_xy = rot.and_then(Angle::new);
        c.scale_xaxis = sx.and_then(ScaleB12::new);
        c
    }

    fn c_lg() -> DrivenLineOffsetLg {
        <DrivenLineOffsetLg as j2735::uper::Placeholder>::placeholder()
    }

    fn close(a: Point, b: Point) -> bool {
        a.distance(b) < 1e-3
    }

    #[test]
    fn computed_translate_rotate_scale() {
        let first = Point::new(10.0, 0.0);
        let p = Point::new(10.0, 100.0);
        let t = Computed::new(&computed(-366, 0, None, None), 1);
        assert!(close(t.apply(first, p), Point::new(6.34, 100.0)));
        let t = Computed::new(&computed(0, 200, Some(7200), None), 1);
        assert!(
            close(t.apply(first, p), Point::new(110.0, 2.0)),
            "90 degrees clockwise: north becomes east"
        );
        let t = Computed::new(&computed(0, 0, None, Some(2000)), 2);
        let q = Point::new(20.0, 0.0);
        assert!(
            close(t.apply(first, q), Point::new(30.0, 0.0)),
            "x scaled by 2"
        );
        let t = Computed::new(&computed(100, 0, None, None), 8);
        assert!(
            close(t.apply(first, first), Point::new(18.0, 0.0)),
            "zoom 8"
        );
    }

    #[test]
    fn thinning_keeps_shape() {
        let mut v: heapless::Vec<Point, 8> = heapless::Vec::new();
        for (x, y) in [(0.0, 0.0), (1.0, 0.01), (2.0, 0.0), (3.0, 5.0), (4.0, 0.0)] {
            let _ = v.push(Point::new(x, y));
        }
        let removed = thin(&mut v, |p| *p, |_| false, |s| s.len() <= 4);
        assert_eq!(removed, Ok(1));
        assert_eq!(
            v[1],
            Point::new(2.0, 0.0),
            "the nearly straight node went first"
        );
        let kept = thin(&mut v, |p| *p, |_| true, |s| s.len() <= 2);
        assert_eq!(kept, Err(IngestError::CapacityExceeded));
    }

    #[test]
    fn steps_and_zoom() {
        assert_eq!(zoom(None), 1);
        assert_eq!(zoom(Some(3)), 8);
        assert_eq!(zoom(Some(200)), 1 << 15);
        let p = LatLon::new(420_000_000, -830_000_000).unwrap_or_default();
        let q = ll_next(p, Step::Offset(10, -20), 4);
        assert_eq!(
            q.map(|q| (q.lat_e7(), q.lon_e7())),
            Ok((419_999_920, -829_999_960))
        );
        assert_eq!(ll_next(p, Step::At(q.unwrap_or(p)), 1), q);
    }
}
