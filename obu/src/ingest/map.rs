//! MapData -> lane models: one per intersection and road segment.

use heapless::Vec;
use j2735::msg::common::{
    LaneDataAttribute, NodeListXY, NodeXY, Position3D, SpeedLimitList, SpeedLimitType,
};
use j2735::msg::map_data::{
    GenericLane, IntersectionGeometry, LaneDirection, LaneTypeAttributes, MapData, RoadSegment,
};

use super::nodes::{self, Computed, Step};
use super::{IngestError, Sink};
use crate::capacity::MAX_NODES;
use crate::geo::{LocalFrame32, Point};
use crate::lane::{Lane, LaneId, LaneKind, LaneModel, MapId, Speed, SpeedLimits, TravelDirection};

/// Lane width when a model gives none (J2735 `laneWidth` is optional): 3.66 m.
pub const DEFAULT_LANE_WIDTH_CM: i32 = 366;
/// Largest centimetre coordinate accepted from the reference point (20 km).
const MAX_OFFSET_CM: i64 = 2_000_000;
/// Largest J2735 delta between two stored nodes (see [`Lane::push_node_cm`]).
const MAX_DELTA_CM: i64 = i16::MAX as i64;

/// One intersection or road segment of a MAP, as the conversion reads it.
#[derive(Debug, Clone, Copy)]
pub struct ModelSource<'a> {
    /// Identity (`RoadRegulatorID` and intersection or segment id).
    pub id: MapId,
    /// `revision`.
    pub revision: u8,
    /// `refPoint`.
    pub ref_point: &'a Position3D,
    /// `laneWidth` in centimetres, when given.
    pub lane_width_cm: Option<u16>,
    /// `speedLimits`, when given.
    pub speed_limits: Option<&'a SpeedLimitList>,
    /// `laneSet` or `roadLaneSet`.
    pub lanes: &'a [GenericLane],
}

impl<'a> ModelSource<'a> {
    /// The reference position and elevation (metres).
    pub fn reference(&self) -> Result<(crate::geo::LatLon, f32), IngestError> {
        nodes::position(self.ref_point)
    }

    fn intersection(g: &'a IntersectionGeometry) -> Self {
        ModelSource {
            id: MapId::new(g.id.region.map_or(0, |r| r.get()), g.id.id.get()),
            revision: g.revision.get(),
            ref_point: &g.ref_point,
            lane_width_cm: g.lane_width.map(|w| w.get()),
            speed_limits: g.speed_limits.as_ref(),
            lanes: &g.lane_set,
        }
    }

    fn segment(s: &'a RoadSegment) -> Self {
        ModelSource {
            id: MapId::new(s.id.region.map_or(0, |r| r.get()), s.id.id.get()),
            revision: s.revision.get(),
            ref_point: &s.ref_point,
            lane_width_cm: s.lane_width.map(|w| w.get()),
            speed_limits: s.speed_limits.as_ref(),
            lanes: &s.road_lane_set,
        }
    }
}

/// Every intersection, then every road segment, of `map`.
pub fn models(map: &MapData) -> impl Iterator<Item = ModelSource<'_>> {
    let ix = map.intersections.iter().flat_map(|l| l.iter());
    let rs = map.road_segments.iter().flat_map(|l| l.iter());
    ix.map(ModelSource::intersection)
        .chain(rs.map(ModelSource::segment))
}

/// The speed limits of a J2735 list that the core keeps.
pub fn speed_limits(list: &SpeedLimitList) -> SpeedLimits {
    let mut out = SpeedLimits::UNAVAILABLE;
    for l in list.iter() {
        let v = Speed::from_units(l.speed.get()).unwrap_or(Speed::UNAVAILABLE);
        match l.r#type {
            SpeedLimitType::VehicleMaxSpeed => out.max = out.max.min_available(v),
            SpeedLimitType::MaxSpeedInConstructionZone => {
                out.construction_max = out.construction_max.min_available(v)
            }
            _ => {}
        }
    }
    out
}

/// Fills a cleared model (identity and reference set) with the lanes of `src`. Lanes
/// that cannot be converted are left out and recorded in `sink`; explicit lanes come
/// first so that computed lanes find their reference lane.
pub(crate) fn fill_model(model: &mut LaneModel, src: &ModelSource<'_>, sink: &mut Sink) {
    let ctx = Context {
        frame: *model.frame(),
        width_cm: src.lane_width_cm.map_or(DEFAULT_LANE_WIDTH_CM, i32::from),
        limits: src
            .speed_limits
            .map_or(SpeedLimits::UNAVAILABLE, speed_limits),
    };
    let computed = |l: &&GenericLane| matches!(l.node_list, NodeListXY::Computed(_));
    for lane in src.lanes.iter().filter(|l| !computed(l)) {
        if let Err(e) = explicit_lane(model, lane, &ctx, sink) {
            sink.reject(e);
        }
    }
    for lane in src.lanes.iter().filter(computed) {
        if let Err(e) = computed_lane(model, lane, &ctx, sink) {
            sink.reject(e);
        }
    }
}

/// What every lane of a model shares.
struct Context {
    frame: LocalFrame32,
    width_cm: i32,
    limits: SpeedLimits,
}

/// A node collected before it is stored: centimetres from the reference point.
#[derive(Debug, Clone, Copy)]
struct Node {
    x: i32,
    y: i32,
    width_cm: i32,
    limits: Option<SpeedLimits>,
}

impl Node {
    fn point(&self) -> Point {
        Point::new(self.x as f32 * 0.01, self.y as f32 * 0.01)
    }
}

/// Nodes of one lane (J2735 allows 63).
type Nodes = Vec<Node, 64>;

fn explicit_lane(
    model: &mut LaneModel,
    gl: &GenericLane,
    ctx: &Context,
    sink: &mut Sink,
) -> Result<(), IngestError> {
    let NodeListXY::Nodes(set) = &gl.node_list else {
        return Err(IngestError::UnsupportedNode);
    };
    let mut nodes = Nodes::new();
    collect_nodes(set, ctx, &mut nodes)?;
    store_lane(model, gl, ctx, &mut nodes, sink)
}

/// Places the nodes: node-XY offsets from the previous node (the first from the
/// reference point), node-LatLon absolute; the width is `laneWidth` plus every `dWidth`
/// so far (J2735: "from this node onwards").
fn collect_nodes(set: &[NodeXY], ctx: &Context, out: &mut Nodes) -> Result<(), IngestError> {
    let (mut x, mut y, mut width) = (0i64, 0i64, ctx.width_cm);
    for n in set {
        match nodes::xy_step(&n.delta)? {
            Step::Offset(dx, dy) => (x, y) = (x + dx as i64, y + dy as i64),
            Step::At(p) => {
                let q = ctx.frame.to_local(p);
                (x, y) = (cm(q.x)?, cm(q.y)?);
            }
        }
        if x.abs() > MAX_OFFSET_CM || y.abs() > MAX_OFFSET_CM {
            return Err(IngestError::InvalidValue);
        }
        let attrs = n.attributes.as_ref();
        width += attrs.and_then(|a| a.d_width).map_or(0, |d| d.get() as i32);
        let limits = attrs.and_then(|a| a.data.as_ref()).and_then(|d| {
            d.iter().find_map(|a| match a {
                LaneDataAttribute::SpeedLimits(l) => Some(speed_limits(l)),
                _ => None,
            })
        });
        let node = Node {
            x: x as i32,
            y: y as i32,
            width_cm: width,
            limits,
        };
        out.push(node).map_err(|_| IngestError::CapacityExceeded)?;
    }
    Ok(())
}

/// Metres to whole centimetres, rejecting non-finite values.
fn cm(m: f32) -> Result<i64, IngestError> {
    let v = libm::roundf(m * 100.0);
    if v.is_finite() && v.abs() <= MAX_OFFSET_CM as f32 {
        Ok(v as i64)
    } else {
        Err(IngestError::InvalidValue)
    }
}

/// Stored nodes the polyline needs (long segments are split, see
/// [`Lane::push_node_cm`]).
fn slots(nodes: &[Node]) -> usize {
    let parts = nodes.windows(2).map(|w| {
        let d = (w[1].x as i64 - w[0].x as i64)
            .abs()
            .max((w[1].y as i64 - w[0].y as i64).abs());
        ((d + MAX_DELTA_CM - 1) / MAX_DELTA_CM).max(1) as usize
    });
    nodes.len().min(1) + parts.sum::<usize>()
}

/// Thins the nodes to the capacity and adds the lane to the model.
fn store_lane(
    model: &mut LaneModel,
    gl: &GenericLane,
    ctx: &Context,
    nodes: &mut Nodes,
    sink: &mut Sink,
) -> Result<(), IngestError> {
    let fits = |n: &[Node]| slots(n) <= MAX_NODES;
    if nodes::thin(nodes, Node::point, |n| n.limits.is_some(), fits)? > 0 {
        sink.thinned();
    }
    let mut lane = Lane::new(
        LaneId(gl.lane_id.get()),
        direction(&gl.lane_attributes.directional_use),
        kind(&gl.lane_attributes.lane_type),
    );
    lane.limits = ctx.limits;
    connections(gl, &mut lane, sink);
    for n in nodes.iter() {
        let width = n.width_cm.clamp(0, u16::MAX as i32) as u16;
        lane.push_node_cm(n.x, n.y, width)?;
        if let Some(l) = n.limits {
            lane.set_limits_from(lane.node_count() - 1, l);
        }
    }
    let slot = model.add_lane(lane.id, lane.direction, lane.kind)?;
    *slot = lane;
    Ok(())
}

/// `connectsTo` lanes of the same model (connections to a remote intersection are not
/// followed); beyond the capacity they are counted as truncated.
fn connections(gl: &GenericLane, lane: &mut Lane, sink: &mut Sink) {
    let list = gl.connects_to.iter().flat_map(|l| l.iter());
    for c in list.filter(|c| c.remote_intersection.is_none()) {
        let id = LaneId(c.connecting_lane.lane.get());
        if !lane.connections.contains(&id) && lane.connections.push(id).is_err() {
            sink.truncated();
        }
    }
}

/// A computed lane: the reference lane's stored nodes (and widths) moved.
fn computed_lane(
    model: &mut LaneModel,
    gl: &GenericLane,
    ctx: &Context,
    sink: &mut Sink,
) -> Result<(), IngestError> {
    let NodeListXY::Computed(c) = &gl.node_list else {
        return Err(IngestError::UnsupportedNode);
    };
    let reference = model
        .lane(LaneId(c.reference_lane_id.get()))
        .ok_or(IngestError::ReferenceLaneMissing)?;
    let t = Computed::new(c, 1);
    let first = reference
        .first_node()
        .ok_or(IngestError::ReferenceLaneMissing)?;
    let mut nodes = Nodes::new();
    for (p, w) in reference.nodes() {
        let q = t.apply(first, p);
        let node = Node {
            x: cm(q.x)? as i32,
            y: cm(q.y)? as i32,
            width_cm: libm::roundf(w * 100.0) as i32,
            limits: None,
        };
        nodes
            .push(node)
            .map_err(|_| IngestError::CapacityExceeded)?;
    }
    store_lane(model, gl, ctx, &mut nodes, sink)
}

/// `directionalUse`: the ingress and egress bits.
pub fn direction(d: &LaneDirection) -> TravelDirection {
    TravelDirection::from_bits(
        d.0.get(LaneDirection::INGRESS_PATH),
        d.0.get(LaneDirection::EGRESS_PATH),
    )
}

/// `laneType` choice.
pub fn kind(t: &LaneTypeAttributes) -> LaneKind {
    match t {
        LaneTypeAttributes::Vehicle(_) => LaneKind::Vehicle,
        LaneTypeAttributes::Crosswalk(_) => LaneKind::Crosswalk,
        LaneTypeAttributes::BikeLane(_) => LaneKind::Bike,
        LaneTypeAttributes::Sidewalk(_) => LaneKind::Sidewalk,
        LaneTypeAttributes::Median(_) => LaneKind::Median,
        LaneTypeAttributes::Striping(_) => LaneKind::Striping,
        LaneTypeAttributes::TrackedVehicle(_) => LaneKind::Tracked,
        LaneTypeAttributes::Parking(_) => LaneKind::Parking,
        LaneTypeAttributes::Extension { .. } => LaneKind::Other,
    }
}

#[cfg(test)]
mod tests;
