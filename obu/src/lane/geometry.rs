//! A lane: attributes plus a compact centreline polyline, and projection onto it.

use heapless::Vec;

use super::{LaneId, LaneKind, ModelError, SpeedLimits, TravelDirection};
use crate::capacity::{MAX_CONNECTIONS, MAX_NODES};
use crate::geo::Point;
use crate::math::{bearing_deg, heading_diff};

/// Width code unit: widths are kept as `u8` multiples of 4 cm (up to 10.2 m).
const WIDTH_UNIT_CM: u16 = 4;
/// Largest delta between stored nodes (i16 centimetres); longer segments are split.
const MAX_DELTA_CM: i64 = i16::MAX as i64;
/// Largest absolute coordinate accepted, in centimetres (about 20 000 km).
const MAX_COORD_CM: f32 = 2.0e9;

/// One lane of a [`super::LaneModel`].
#[derive(Debug, Clone, PartialEq)]
pub struct Lane {
    /// J2735 lane id.
    pub id: LaneId,
    /// Direction of travel relative to the node order.
    pub direction: TravelDirection,
    /// Lane type.
    pub kind: LaneKind,
    /// Speed limits of the whole lane (the MAP's intersection or road-segment
    /// `speedLimits`; unavailable when the MAP gives none). See [`Lane::limits_at`].
    pub limits: SpeedLimits,
    /// Lanes of the same model this lane leads into (in its direction of travel).
    pub connections: Vec<LaneId, MAX_CONNECTIONS, u8>,
    origin: [i32; 2],
    deltas: Vec<[i16; 2], MAX_NODES, u8>,
    widths: [u8; MAX_NODES],
    /// Widest width code of the nodes.
    max_width: u8,
    /// Node (stored index) from which `node_limits` apply in node order; `u8::MAX`: none.
    limits_from: u8,
    /// Limits given at a node (J2735 `LaneDataAttribute` `speedLimits`).
    node_limits: SpeedLimits,
    length: f32,
    /// Bounding box of the nodes in metres: min x, min y, max x, max y.
    bbox: [f32; 4],
}

/// The nearest point of a centreline, in node order.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Projection {
    /// Distance from the first node along the polyline, metres. Below 0 or above the
    /// length when the point lies beyond an end (measured along the end segment).
    pub along: f32,
    /// Signed distance from the centreline, metres, positive to the left of node order.
    pub lateral: f32,
    /// Bearing of the nearest segment in node order, degrees clockwise from north.
    pub bearing_deg: f32,
    /// Lane width at the nearest point, metres.
    pub width: f32,
    /// Index of the nearest segment (from node `segment` to `segment + 1`).
    pub segment: u8,
}

/// A position relative to a lane in its direction of travel.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LanePosition {
    /// Metres from the lane's entry end in the direction of travel.
    pub station: f32,
    /// Signed distance from the centreline, metres, positive to the left of travel.
    pub lateral: f32,
    /// Bearing of the lane at this point in the direction of travel, degrees.
    pub bearing_deg: f32,
    /// Lane width here, metres.
    pub width: f32,
    /// Metres beyond either end of the lane (0 within its extent).
    pub beyond: f32,
    /// True when travel follows the node order.
    pub forward: bool,
    /// Index of the nearest segment in node order (see [`Projection::segment`]).
    pub segment: u8,
}

impl Lane {
    /// An empty lane (no nodes yet).
    pub const fn new(id: LaneId, direction: TravelDirection, kind: LaneKind) -> Self {
        Lane {
            id,
            direction,
            kind,
            limits: SpeedLimits::UNAVAILABLE,
            connections: Vec::new(),
            origin: [0; 2],
            deltas: Vec::new(),
            widths: [0; MAX_NODES],
            max_width: 0,
            limits_from: u8::MAX,
            node_limits: SpeedLimits::UNAVAILABLE,
            length: 0.0,
            bbox: [0.0; 4],
        }
    }

    /// Appends a node at `p` (local metres of the model) with lane width `width_m`.
    pub fn push_node(&mut self, p: Point, width_m: f32) -> Result<(), ModelError> {
        let (x, y, w) = (p.x * 100.0, p.y * 100.0, width_m * 100.0);
        let ok = |v: f32| v.is_finite() && v.abs() <= MAX_COORD_CM;
        if !(ok(x) && ok(y) && ok(w)) || w < 0.0 {
            return Err(ModelError::InvalidValue);
        }
        let w = libm::roundf(w).min(u16::MAX as f32) as u16;
        self.push_node_cm(libm::roundf(x) as i32, libm::roundf(y) as i32, w)
    }

    /// Appends a node at (`x_cm`, `y_cm`) from the model reference with width
    /// `width_cm` (J2735 `LaneWidth` plus any `dWidth`).
    ///
    /// A segment longer than 327.67 m along x or y is split into equal parts, each
    /// taking a node. Nothing is changed when the nodes do not fit.
    pub fn push_node_cm(&mut self, x_cm: i32, y_cm: i32, width_cm: u16) -> Result<(), ModelError> {
        let code = width_code(width_cm);
        let Some(last) = self.last_node_cm() else {
            self.origin = [x_cm, y_cm];
            self.widths[0] = code;
            self.max_width = code;
            self.deltas
                .push([0, 0])
                .map_err(|_| ModelError::CapacityExceeded)?;
            self.update_bbox();
            return Ok(());
        };
        let (dx, dy) = (x_cm as i64 - last[0] as i64, y_cm as i64 - last[1] as i64);
        let parts = (dx.abs().max(dy.abs()) + MAX_DELTA_CM - 1) / MAX_DELTA_CM;
        let parts = parts.max(1);
        if self.deltas.len() as i64 + parts > MAX_NODES as i64 {
            return Err(ModelError::CapacityExceeded);
        }
        let w0 = self.widths[self.deltas.len() - 1] as i64;
        for k in 1..=parts {
            let step = [
                dx * k / parts - dx * (k - 1) / parts,
                dy * k / parts - dy * (k - 1) / parts,
            ];
            let wk = w0 + (code as i64 - w0) * k / parts;
            self.push_delta([step[0] as i16, step[1] as i16], wk as u8);
        }
        Ok(())
    }

    /// Stores one delta (capacity already checked) and updates length and box.
    fn push_delta(&mut self, d: [i16; 2], width: u8) {
        let idx = self.deltas.len();
        if idx >= MAX_NODES || self.deltas.push(d).is_err() {
            return;
        }
        self.widths[idx] = width;
        self.max_width = self.max_width.max(width);
        self.length += libm::hypotf(d[0] as f32, d[1] as f32) / 100.0;
        self.update_bbox();
    }

    /// Recomputes the bounding box from the nodes.
    fn update_bbox(&mut self) {
        let mut b = [f32::MAX, f32::MAX, f32::MIN, f32::MIN];
        for (p, _) in self.nodes() {
            b = [b[0].min(p.x), b[1].min(p.y), b[2].max(p.x), b[3].max(p.y)];
        }
        self.bbox = b;
    }

    /// The last node in centimetres, `None` for an empty lane.
    fn last_node_cm(&self) -> Option<[i32; 2]> {
        if self.deltas.is_empty() {
            return None;
        }
        let mut p = [self.origin[0] as i64, self.origin[1] as i64];
        for d in self.deltas.iter() {
            p[0] += d[0] as i64;
            p[1] += d[1] as i64;
        }
        Some([p[0] as i32, p[1] as i32])
    }

    /// Number of centreline nodes.
    pub fn node_count(&self) -> usize {
        self.deltas.len()
    }

    /// Centreline nodes in node order: (position in local metres, width in metres).
    pub fn nodes(&self) -> impl Iterator<Item = (Point, f32)> + '_ {
        let mut acc = self.origin;
        self.deltas
            .iter()
            .zip(self.widths.iter())
            .map(move |(d, w)| {
                acc[0] = acc[0].wrapping_add(d[0] as i32);
                acc[1] = acc[1].wrapping_add(d[1] as i32);
                let p = Point::new(acc[0] as f32 * 0.01, acc[1] as f32 * 0.01);
                (p, *w as f32 * (WIDTH_UNIT_CM as f32 * 0.01))
            })
    }

    /// Centreline length in metres.
    pub fn length(&self) -> f32 {
        self.length
    }

    /// Bounding box of the centreline in metres: `[min x, min y, max x, max y]`.
    pub fn bbox(&self) -> [f32; 4] {
        self.bbox
    }

    /// The widest node width in metres.
    pub fn max_width(&self) -> f32 {
        self.max_width as f32 * (WIDTH_UNIT_CM as f32 * 0.01)
    }

    /// Speed limits given at node `node` (stored index) that apply from it on in node
    /// order. A lane keeps one such change point: a later one only lowers the values
    /// (the lower of two limits is kept, which is the safe side for warnings).
    pub fn set_limits_from(&mut self, node: usize, limits: SpeedLimits) {
        let node = node.min(u8::MAX as usize - 1) as u8;
        if self.limits_from == u8::MAX {
            self.limits_from = node;
            self.node_limits = limits;
            return;
        }
        self.limits_from = self.limits_from.min(node);
        self.node_limits = self.node_limits.lower(limits);
    }

    /// The limits in force on segment `segment` (node order): node-level values from
    /// their node on replace the lane's values of the same kind.
    pub fn limits_at(&self, segment: u8) -> SpeedLimits {
        if segment < self.limits_from {
            return self.limits;
        }
        self.limits.replaced_by(self.node_limits)
    }

    /// The first node (stop-line end), `None` for an empty lane.
    pub fn first_node(&self) -> Option<Point> {
        self.nodes().next().map(|(p, _)| p)
    }

    /// True when `p` may lie within `margin` metres of the centreline (box test).
    pub fn may_contain(&self, p: Point, margin: f32) -> bool {
        let b = self.bbox;
        !self.deltas.is_empty()
            && p.x >= b[0] - margin
            && p.y >= b[1] - margin
            && p.x <= b[2] + margin
            && p.y <= b[3] + margin
    }

    /// The point `along` metres from the first node in node order (clamped to the
    /// ends), `None` for a lane without segments or non-finite input.
    pub fn point_at(&self, along: f32) -> Option<Point> {
        if !along.is_finite() {
            return None;
        }
        let mut rest = along.max(0.0);
        let mut last = None;
        for (a, b) in self.segments() {
            let len = a.distance(b);
            if rest <= len && len > 0.0 {
                let t = rest / len;
                return Some(Point::new(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t));
            }
            rest -= len;
            last = Some(b);
        }
        last
    }

    /// Segments in node order as point pairs.
    fn segments(&self) -> impl Iterator<Item = (Point, Point)> + '_ {
        let mut it = self.nodes().map(|(p, _)| p);
        let mut prev = it.next();
        it.map(move |p| {
            let a = prev.unwrap_or(p);
            prev = Some(p);
            (a, p)
        })
    }

    /// Projects `p` onto the centreline (node order). `None` without a segment or for
    /// a non-finite point.
    ///
    /// One pass over the segments keeps the nearest by squared distance (the first of
    /// equals); the length before it is summed afterwards and the full fit is made for
    /// that one only.
    pub fn project(&self, p: Point) -> Option<Projection> {
        if !p.is_finite() {
            return None;
        }
        let last = self.deltas.len().checked_sub(2)?;
        let mut acc = self.origin;
        let mut a = Point::new(acc[0] as f32 * 0.01, acc[1] as f32 * 0.01);
        let mut best = Nearest::NONE;
        for (i, d) in self.deltas.iter().skip(1).enumerate() {
            acc = [
                acc[0].wrapping_add(d[0] as i32),
                acc[1].wrapping_add(d[1] as i32),
            ];
            let b = Point::new(acc[0] as f32 * 0.01, acc[1] as f32 * 0.01);
            if let Some(dist2) = nearer(a, b, p, best.dist2) {
                best = Nearest {
                    dist2,
                    index: i,
                    a,
                    b,
                };
            }
            a = b;
        }
        if !best.dist2.is_finite() {
            return None;
        }
        let i = best.index;
        // The length before the nearest segment, summed after the search: a square root
        // per segment before it rather than per segment of the lane.
        let start = self
            .nodes()
            .map(|(n, _)| n)
            .zip(self.nodes().map(|(n, _)| n).skip(1))
            .take(i)
            .map(|(a, b)| libm::sqrtf(dist2_of(a, b)))
            .sum();
        let fit = SegmentFit::new(best.a, best.b, p, i == 0, i == last);
        let width = |k: usize| self.widths[k] as f32 * (WIDTH_UNIT_CM as f32 * 0.01);
        Some(fit.projection(start, width(i), width(i + 1), i as u8))
    }

    /// The cone-to-lane rule: for each segment, rotate `p` by the segment bearing; `p`
    /// is on the lane when it lies within the segment's extent and less than half the
    /// width from it. Returns the node-order distance and segment bearing of the first
    /// segment that holds `p`.
    pub fn cone_along(&self, p: Point) -> Option<(f32, f32)> {
        let mut nodes = self.nodes();
        let (mut a, mut wa) = nodes.next()?;
        let mut start = 0.0f32;
        for (b, wb) in nodes {
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let len = libm::hypotf(dx, dy);
            if len > 0.0 {
                let (rx, ry) = (p.x - a.x, p.y - a.y);
                let x = (rx * dx + ry * dy) / len;
                let y = (dx * ry - dy * rx) / len;
                let half = 0.5 * (wa + (wb - wa) * (x / len).clamp(0.0, 1.0));
                if (0.0..=len).contains(&x) && y.abs() < half {
                    return Some((start + x, bearing_deg(dx, dy)));
                }
            }
            start += len;
            (a, wa) = (b, wb);
        }
        None
    }

    /// Position of `p` in the lane's direction of travel. For lanes usable both ways
    /// the direction closest to `heading_deg` is taken (node order when unknown).
    pub fn locate(&self, p: Point, heading_deg: Option<f32>) -> Option<LanePosition> {
        let proj = self.project(p)?;
        let forward = self.travels_forward(proj.bearing_deg, heading_deg);
        Some(self.position_from(&proj, forward))
    }

    /// True when travel follows node order at a segment of bearing `bearing_deg`.
    pub fn travels_forward(&self, bearing_deg: f32, heading_deg: Option<f32>) -> bool {
        match self.direction {
            TravelDirection::Egress => true,
            TravelDirection::Ingress => false,
            TravelDirection::Both | TravelDirection::None => match heading_deg {
                Some(h) if h.is_finite() => heading_diff(h, bearing_deg) <= 90.0,
                _ => true,
            },
        }
    }

    /// Converts a node-order projection into a position in a travel direction.
    pub fn position_from(&self, proj: &Projection, forward: bool) -> LanePosition {
        let beyond = (-proj.along).max(proj.along - self.length).max(0.0);
        let (station, lateral, bearing) = if forward {
            (proj.along, proj.lateral, proj.bearing_deg)
        } else {
            let b = crate::math::wrap_360(proj.bearing_deg + 180.0);
            (self.length - proj.along, -proj.lateral, b)
        };
        LanePosition {
            station,
            lateral,
            bearing_deg: bearing,
            width: proj.width,
            beyond,
            forward,
            segment: proj.segment,
        }
    }

    /// Node-order distance of a travel-direction `station`.
    pub fn along_of_station(&self, station: f32, forward: bool) -> f32 {
        if forward {
            station
        } else {
            self.length - station
        }
    }
}

/// The nearest segment found so far by [`Lane::project`].
#[derive(Clone, Copy)]
struct Nearest {
    dist2: f32,
    index: usize,
    a: Point,
    b: Point,
}

impl Nearest {
    const NONE: Nearest = Nearest {
        dist2: f32::INFINITY,
        index: 0,
        a: Point::new(0.0, 0.0),
        b: Point::new(0.0, 0.0),
    };
}

/// The fit of a point to one segment.
struct SegmentFit {
    d: Point,
    len: f32,
    t: f32,
    rel: Point,
}

impl SegmentFit {
    /// The segment vector, `p` relative to `a`, and the unclamped parameter of the
    /// nearest point of the line.
    fn parts(a: Point, b: Point, p: Point) -> (Point, Point, f32, f32) {
        let d = Point::new(b.x - a.x, b.y - a.y);
        let rel = Point::new(p.x - a.x, p.y - a.y);
        let len2 = d.x * d.x + d.y * d.y;
        let t = if len2 > 0.0 {
            (rel.x * d.x + rel.y * d.y) / len2
        } else {
            0.0
        };
        (d, rel, len2, t)
    }

    /// Squared distance from `p` to the segment `a`-`b` (by the clamped parameter: the
    /// reference [`nearer`] is tested against).
    #[cfg(test)]
    fn dist2(a: Point, b: Point, p: Point) -> f32 {
        let (d, rel, _, t) = Self::parts(a, b, p);
        let tc = t.clamp(0.0, 1.0);
        let (qx, qy) = (rel.x - d.x * tc, rel.y - d.y * tc);
        qx * qx + qy * qy
    }

    /// Fits `p` to segment `a`->`b`; `open_start`/`open_end` let the parameter run
    /// past the first/last node so that `along` reports the overshoot.
    fn new(a: Point, b: Point, p: Point, open_start: bool, open_end: bool) -> Self {
        let (d, rel, len2, t) = Self::parts(a, b, p);
        let lo = if open_start { f32::NEG_INFINITY } else { 0.0 };
        let hi = if open_end { f32::INFINITY } else { 1.0 };
        SegmentFit {
            d,
            len: libm::sqrtf(len2),
            t: t.clamp(lo, hi),
            rel,
        }
    }

    /// The projection given the distance of `a` from the first node and the widths.
    fn projection(&self, start: f32, wa: f32, wb: f32, segment: u8) -> Projection {
        let lateral = if self.len > 0.0 {
            (self.d.x * self.rel.y - self.d.y * self.rel.x) / self.len
        } else {
            libm::hypotf(self.rel.x, self.rel.y)
        };
        let tw = self.t.clamp(0.0, 1.0);
        Projection {
            along: start + self.t * self.len,
            lateral,
            bearing_deg: bearing_deg(self.d.x, self.d.y),
            width: wa + (wb - wa) * tw,
            segment,
        }
    }
}

/// Squared distance between two points.
fn dist2_of(a: Point, b: Point) -> f32 {
    let (dx, dy) = (a.x - b.x, a.y - b.y);
    dx * dx + dy * dy
}

/// The squared distance from `p` to the segment `a`-`b` when it is below `best`. Written
/// for the search over every segment of every lane near a fix (the bulk of `on_fix`):
/// across the segment's middle the squared distance is cross² / length², so a segment that
/// is not nearer is told by a multiplication and the division is made for a nearer one
/// only; the cross product keeps the precision the coordinates have (no difference of two
/// large squares).
fn nearer(a: Point, b: Point, p: Point, best: f32) -> Option<f32> {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let (rx, ry) = (p.x - a.x, p.y - a.y);
    let dot = rx * dx + ry * dy;
    let len2 = dx * dx + dy * dy;
    let dist2 = if dot <= 0.0 {
        rx * rx + ry * ry
    } else if dot >= len2 {
        let (qx, qy) = (rx - dx, ry - dy);
        qx * qx + qy * qy
    } else {
        let cross = rx * dy - ry * dx;
        if cross * cross >= best * len2 {
            return None;
        }
        cross * cross / len2
    };
    (dist2 < best).then_some(dist2)
}

/// Width in centimetres to the 4 cm code, at least one unit.
fn width_code(width_cm: u16) -> u8 {
    let c = width_cm.saturating_add(WIDTH_UNIT_CM / 2) / WIDTH_UNIT_CM;
    c.clamp(1, u8::MAX as u16) as u8
}

#[cfg(test)]
mod tests;
