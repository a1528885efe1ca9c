//! TravelerInformation -> work zones: one per data frame, its regions and content.

use heapless::Vec;
use j2735::msg::common::{HeadingSlice as J2735HeadingSlice, NodeListXY, NodeXY};
use j2735::msg::traveler_information::{
    Circle, DirectionOfUse, DistanceUnits, GeographicalPath, GeographicalPathDescription,
    GeometricProjection, NodeListLL, OffsetSystem, OffsetSystemOffset, RegionPointSet,
    TravelerDataFrame, TravelerDataFrameMsgId, TravelerInformation, ValidRegion, ValidRegionArea,
};

use super::nodes::{self, Computed, Step};
use super::{itis, map::DEFAULT_LANE_WIDTH_CM, IngestError, Sink};
use crate::capacity::{MAX_PATH_NODES, MAX_REGIONS};
use crate::geo::{LatLon, Point};
use crate::lane::{LaneId, MapId, MapStore};
use crate::zone::{Directionality, HeadingSlice, KeySource, Region, Validity, WorkZone, ZoneKey};

/// Points of one path before thinning: the anchor and up to 63 nodes.
type Path = Vec<Point, 64>;

/// The key of data frame `index`: the TIM's `packetID`, else a digest of the frame's
/// `msgId` (a `furtherInfoID` as is; a `roadSignID` hashed over position, view angle,
/// MUTCD code and CRC).
pub fn key(tim: &TravelerInformation, frame: &TravelerDataFrame, index: usize) -> ZoneKey {
    let index = index.min(u8::MAX as usize) as u8;
    if let Some(id) = &tim.packet_id {
        return ZoneKey::packet(id.0, index);
    }
    ZoneKey {
        packet_id: msg_id_digest(&frame.msg_id),
        frame: index,
        source: KeySource::MsgId,
    }
}

fn msg_id_digest(id: &TravelerDataFrameMsgId) -> [u8; 9] {
    let mut out = [0u8; 9];
    match id {
        TravelerDataFrameMsgId::FurtherInfoID(f) => {
            out[0] = 1;
            out[1..3].copy_from_slice(&f.0);
        }
        TravelerDataFrameMsgId::RoadSignID(r) => {
            let mut h = Fnv::new();
            h.write(&r.position.lat.get().to_be_bytes());
            h.write(&r.position.long.get().to_be_bytes());
            h.write(
                &r.position
                    .elevation
                    .map_or(i32::MIN, |e| e.get())
                    .to_be_bytes(),
            );
            h.write(r.view_angle.0.as_bytes());
            let mutcd = r.mutcd_code.and_then(|m| m.number()).unwrap_or(-1);
            h.write(&mutcd.to_be_bytes());
            h.write(&r.crc.map_or([0xff; 2], |c| c.0));
            out[0] = 2;
            out[1..].copy_from_slice(&h.0.to_be_bytes());
        }
    }
    out
}

/// FNV-1a, 64 bits.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// `startYear` (0 when absent), `startTime`, `durationTime`.
pub fn validity(frame: &TravelerDataFrame) -> Validity {
    Validity {
        start_year: frame.start_year.map_or(0, |y| y.get()),
        start_minute: frame.start_time.get(),
        duration_min: frame.duration_time.get(),
    }
}

/// Fills a cleared zone from `frame`: priority, content and regions. A region that
/// cannot be converted is left out and recorded in `sink`; a computed path whose MAP is
/// not stored yet fails the whole zone (so that it is converted again later).
pub(crate) fn fill_zone(
    zone: &mut WorkZone,
    frame: &TravelerDataFrame,
    maps: &MapStore,
    sink: &mut Sink,
) -> Result<(), IngestError> {
    zone.priority = frame.priority.get();
    zone.info = itis::content(&frame.content);
    for gp in frame.regions.iter() {
        if zone.regions.len() >= MAX_REGIONS {
            sink.truncated();
            continue;
        }
        match region(gp, maps, sink) {
            Ok(r) => zone.push_region(r)?,
            Err(IngestError::ReferenceMapMissing) => return Err(IngestError::ReferenceMapMissing),
            Err(e) => sink.reject(e),
        }
    }
    Ok(())
}

/// Everything a `GeographicalPath` says besides its shape.
#[derive(Clone, Copy)]
struct Common {
    anchor: Option<(LatLon, f32)>,
    id: Option<MapId>,
    width_m: Option<f32>,
    directionality: Directionality,
    heading: Option<HeadingSlice>,
    closed: bool,
}

/// One region. An unusable anchor only matters where offsets count from it.
pub(crate) fn region(
    gp: &GeographicalPath,
    maps: &MapStore,
    sink: &mut Sink,
) -> Result<Region, IngestError> {
    let common = Common {
        anchor: usable(gp.anchor.as_ref()),
        id: gp
            .id
            .as_ref()
            .map(|i| MapId::new(i.region.map_or(0, |r| r.get()), i.id.get())),
        width_m: gp.lane_width.map(|w| w.get() as f32 * 0.01),
        directionality: directionality(gp.directionality),
        heading: gp.direction.as_ref().map(heading_slice),
        closed: gp.closed_path.unwrap_or(false),
    };
    let mut r = match &gp.description {
        Some(GeographicalPathDescription::Path(os)) => offset_path(&common, os, maps, sink)?,
        Some(GeographicalPathDescription::Geometry(g)) => geometry(&common, g)?,
        Some(GeographicalPathDescription::OldRegion(v)) => old_region(&common, v, maps, sink)?,
        _ => return Err(IngestError::NoGeometry),
    };
    r.closed_path = common.closed;
    Ok(r)
}

/// An anchor's position and elevation, `None` when absent or unavailable.
fn usable(anchor: Option<&j2735::msg::common::Position3D>) -> Option<(LatLon, f32)> {
    anchor.and_then(|a| nodes::position(a).ok())
}

/// A region shell at `anchor` with the common attributes.
fn shell(c: &Common, anchor: (LatLon, f32)) -> Region {
    let width = c.width_m.unwrap_or(DEFAULT_LANE_WIDTH_CM as f32 * 0.01);
    let mut r = Region::path(anchor.0, anchor.1, width);
    r.directionality = c.directionality;
    r.heading = c.heading.unwrap_or(HeadingSlice::ALL);
    r
}

/// An `OffsetSystem` path: node-XY or node-LL offsets (or a computed lane) from the
/// anchor, times the `scale` zoom.
fn offset_path(
    c: &Common,
    os: &OffsetSystem,
    maps: &MapStore,
    sink: &mut Sink,
) -> Result<Region, IngestError> {
    let zoom = nodes::zoom(os.scale.map(|s| s.get()));
    match &os.offset {
        OffsetSystemOffset::Xy(list) => xy_path(c, list, zoom, maps, sink),
        OffsetSystemOffset::Ll(NodeListLL::Nodes(set)) => {
            let steps = set.iter().map(|n| nodes::ll_step(&n.delta));
            ll_path(c, steps, zoom, sink)
        }
        OffsetSystemOffset::Ll(NodeListLL::Extension { .. }) => Err(IngestError::UnsupportedNode),
    }
}

/// A node-XY list or computed lane.
fn xy_path(
    c: &Common,
    list: &NodeListXY,
    zoom: i64,
    maps: &MapStore,
    sink: &mut Sink,
) -> Result<Region, IngestError> {
    match list {
        NodeListXY::Nodes(set) => xy_nodes(c, set, zoom, sink),
        NodeListXY::Computed(cl) => computed_path(c, cl, zoom, maps, sink),
        NodeListXY::Extension { .. } => Err(IngestError::UnsupportedNode),
    }
}

/// Where a path starts: at its first node when that is absolute (node-LatLon; the
/// anchor then plays no part, and a wrong anchor does not move the path), else at the
/// anchor, from which the first offset counts.
fn path_origin(c: &Common, lead: Option<LatLon>) -> Result<((LatLon, f32), bool), IngestError> {
    match (lead, c.anchor) {
        (Some(p), anchor) => Ok(((p, anchor.map_or(0.0, |a| a.1)), false)),
        (None, Some(anchor)) => Ok((anchor, true)),
        (None, None) => Err(IngestError::InvalidReference),
    }
}

/// Node-XY offsets: centimetres from the previous node (the first from the anchor).
fn xy_nodes(c: &Common, set: &[NodeXY], zoom: i64, sink: &mut Sink) -> Result<Region, IngestError> {
    let lead = match set.first().map(|n| nodes::xy_step(&n.delta)) {
        Some(Ok(Step::At(p))) => Some(p),
        _ => None,
    };
    let (origin, from_anchor) = path_origin(c, lead)?;
    let mut r = shell(c, origin);
    let mut path = Path::new();
    let mut cur = Point::default();
    if from_anchor {
        push(&mut path, cur)?;
    }
    for n in set {
        cur = match nodes::xy_step(&n.delta)? {
            Step::Offset(dx, dy) => {
                let z = zoom as f32 * 0.01;
                Point::new(cur.x + dx as f32 * z, cur.y + dy as f32 * z)
            }
            Step::At(p) => r.frame().to_local(p),
        };
        push(&mut path, cur)?;
    }
    store_path(&mut r, &mut path, sink)?;
    Ok(r)
}

/// Node-LL offsets: 1e-7 degree from the previous node (the first from the anchor).
fn ll_path(
    c: &Common,
    mut steps: impl Iterator<Item = Result<Step, IngestError>> + Clone,
    zoom: i64,
    sink: &mut Sink,
) -> Result<Region, IngestError> {
    let lead = match steps.clone().next() {
        Some(Ok(Step::At(p))) => Some(p),
        _ => None,
    };
    let (origin, from_anchor) = path_origin(c, lead)?;
    let mut r = shell(c, origin);
    let mut path = Path::new();
    let mut cur = r.anchor();
    if from_anchor {
        push(&mut path, Point::default())?;
    }
    steps.try_for_each(|s| {
        cur = nodes::ll_next(cur, s?, zoom)?;
        push(&mut path, r.frame().to_local(cur))
    })?;
    store_path(&mut r, &mut path, sink)?;
    Ok(r)
}

/// A computed path: a lane of the MAP named by the region's `id`, moved. Without an
/// `id` the reference lane cannot be found.
fn computed_path(
    c: &Common,
    cl: &j2735::msg::common::ComputedLane,
    zoom: i64,
    maps: &MapStore,
    sink: &mut Sink,
) -> Result<Region, IngestError> {
    let id = c.id.ok_or(IngestError::ReferenceLaneMissing)?;
    let map = maps.get(id).ok_or(IngestError::ReferenceMapMissing)?;
    let lane = map
        .lane(LaneId(cl.reference_lane_id.get()))
        .ok_or(IngestError::ReferenceLaneMissing)?;
    let first = lane.first_node().ok_or(IngestError::ReferenceLaneMissing)?;
    let t = Computed::new(cl, zoom);
    let to_wgs = |p: Point| {
        map.frame()
            .to_wgs84(t.apply(first, p))
            .ok_or(IngestError::InvalidValue)
    };
    let mut r = shell(c, c.anchor.unwrap_or((to_wgs(first)?, 0.0)));
    let mut path = Path::new();
    for (p, _) in lane.nodes() {
        push(&mut path, r.frame().to_local(to_wgs(p)?))?;
    }
    store_path(&mut r, &mut path, sink)?;
    Ok(r)
}

fn push(path: &mut Path, p: Point) -> Result<(), IngestError> {
    if !p.is_finite() {
        return Err(IngestError::InvalidValue);
    }
    path.push(p).map_err(|_| IngestError::CapacityExceeded)
}

/// Thins the path to [`MAX_PATH_NODES`] and stores it.
fn store_path(r: &mut Region, path: &mut Path, sink: &mut Sink) -> Result<(), IngestError> {
    if nodes::thin(path, |p| *p, |_| false, |p| p.len() <= MAX_PATH_NODES)? > 0 {
        sink.thinned();
    }
    path.iter().try_for_each(|&p| r.push_node(p))?;
    Ok(())
}

/// A `GeometricProjection`: a circle with its own heading slice, extent and width.
fn geometry(c: &Common, g: &GeometricProjection) -> Result<Region, IngestError> {
    let mut r = circle(c, &g.circle)?;
    r.heading = heading_slice(&g.direction);
    r.extent_m = g.extent.and_then(|e| e.number()).map(extent_m);
    if let Some(w) = g.lane_width {
        r.lane_width_m = w.get() as f32 * 0.01;
    }
    Ok(r)
}

/// A circle around its centre.
fn circle(c: &Common, circle: &Circle) -> Result<Region, IngestError> {
    let (centre, elev) = nodes::position(&circle.center)?;
    let radius = circle.radius.get() as f32 * unit_m(circle.units);
    let mut r = Region::circle(centre, elev, radius);
    r.lane_width_m = c.width_m.unwrap_or(0.0);
    r.directionality = c.directionality;
    r.heading = c.heading.unwrap_or(HeadingSlice::ALL);
    Ok(r)
}

/// An old-style `ValidRegion`: a shape point set (a path), a circle or a region point
/// set (a closed outline of node-LL offsets).
fn old_region(
    c: &Common,
    v: &ValidRegion,
    maps: &MapStore,
    sink: &mut Sink,
) -> Result<Region, IngestError> {
    let mut r = match &v.area {
        ValidRegionArea::Circle(circ) => circle(c, circ)?,
        ValidRegionArea::ShapePointSet(s) => {
            let own = Common {
                anchor: usable(s.anchor.as_ref()).or(c.anchor),
                width_m: s.lane_width.map(|w| w.get() as f32 * 0.01).or(c.width_m),
                directionality: s
                    .directionality
                    .map_or(c.directionality, |d| directionality(Some(d))),
                ..*c
            };
            xy_path(&own, &s.node_list, 1, maps, sink)?
        }
        ValidRegionArea::RegionPointSet(s) => outline(c, s, sink)?,
    };
    r.heading = heading_slice(&v.direction);
    r.extent_m = v.extent.and_then(|e| e.number()).map(extent_m);
    Ok(r)
}

/// A `RegionPointSet`: `xOffset` (longitude) and `yOffset` (latitude) steps of 1e-7
/// degree from the anchor, times the zoom; the outline is closed.
fn outline(c: &Common, s: &RegionPointSet, sink: &mut Sink) -> Result<Region, IngestError> {
    let own = Common {
        anchor: usable(s.anchor.as_ref()).or(c.anchor),
        ..*c
    };
    let zoom = nodes::zoom(s.scale.map(|z| z.get()));
    let steps = s.node_list.iter().map(|o| {
        Ok(Step::Offset(
            o.x_offset.get() as i32,
            o.y_offset.get() as i32,
        ))
    });
    let mut r = ll_path(&own, steps, zoom, sink)?;
    r.closed_path = true;
    Ok(r)
}

/// `directionality` (absent or `unavailable`: both ways).
fn directionality(d: Option<DirectionOfUse>) -> Directionality {
    match d {
        Some(DirectionOfUse::Forward) => Directionality::Forward,
        Some(DirectionOfUse::Reverse) => Directionality::Reverse,
        _ => Directionality::Both,
    }
}

/// J2735 `HeadingSlice` (bit 0, the first bit of the BIT STRING, is
/// `from000-0to022-5degrees`) as the core's mask (bit n = slice n).
pub fn heading_slice(h: &J2735HeadingSlice) -> HeadingSlice {
    let mask = (0..16)
        .filter(|&i| h.0.get(i))
        .fold(0u16, |m, i| m | 1 << i);
    HeadingSlice(mask)
}

/// Metres per `DistanceUnits` unit.
fn unit_m(u: DistanceUnits) -> f32 {
    match u {
        DistanceUnits::Centimeter => 0.01,
        DistanceUnits::Cm2_5 => 0.025,
        DistanceUnits::Decimeter => 0.1,
        DistanceUnits::Meter => 1.0,
        DistanceUnits::Kilometer => 1000.0,
        DistanceUnits::Foot => 0.3048,
        DistanceUnits::Yard => 0.9144,
        DistanceUnits::Mile => 1609.344,
    }
}

/// Metres of an `Extent` by its number (`useInstantlyOnly` 0 .. `forever` 15).
fn extent_m(n: i64) -> f32 {
    const M: [f32; 15] = [
        0.0, 3.0, 10.0, 50.0, 100.0, 500.0, 1e3, 5e3, 1e4, 5e4, 1e5, 5e5, 1e6, 5e6, 1e7,
    ];
    usize::try_from(n)
        .ok()
        .and_then(|i| M.get(i).copied())
        .unwrap_or(f32::INFINITY)
}

#[cfg(test)]
mod tests;
