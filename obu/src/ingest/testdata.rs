//! Small hand-built J2735 values for the unit tests (built in place in boxes; run them
//! on [`crate::testutil::big_stack`]: a no-heap MapData is megabytes).

use std::boxed::Box;

use j2735::msg::common::*;
use j2735::msg::itis::ITIScodes;
use j2735::msg::map_data::{
    ConnectingLane, Connection, ConnectsToList, GenericLane, IntersectionGeometry,
    IntersectionGeometryList, LaneAttributesBarrier, LaneAttributesVehicle, LaneDirection,
    LaneTypeAttributes, MapData, RoadSegment, RoadSegmentList,
};
use j2735::msg::traveler_information::*;
use j2735::uper::{Bits, Placeholder, SeqOf};

/// `v` or a test failure.
pub fn ok<T>(v: Option<T>) -> T {
    v.unwrap_or_else(|| panic!("test value out of range"))
}

/// The reference position of the test messages (42.1234567, -83.7654321).
pub const LAT: i32 = 421_234_567;
/// See [`LAT`].
pub const LON: i32 = -837_654_321;

/// A `Position3D` at 1e-7 degree integers, elevation in 10 cm.
pub fn pos(lat: i32, lon: i32, elev: Option<i32>) -> Position3D {
    let mut p = Position3D::placeholder();
    p.lat = ok(Latitude::new(lat));
    p.long = ok(Longitude::new(lon));
    p.elevation = elev.and_then(Elevation::new);
    p
}

/// A node-XYn offset (`kind` 1..=6) in centimetres.
pub fn xy(kind: u8, x: i32, y: i32) -> NodeXY {
    let mut n = NodeXY::placeholder();
    n.delta = match kind {
        1 => NodeOffsetPointXY::NodeXY1(NodeXY20b {
            x: ok(OffsetB10::new(x as i16)),
            y: ok(OffsetB10::new(y as i16)),
        }),
        2 => NodeOffsetPointXY::NodeXY2(NodeXY22b {
            x: ok(OffsetB11::new(x as i16)),
            y: ok(OffsetB11::new(y as i16)),
        }),
        3 => NodeOffsetPointXY::NodeXY3(NodeXY24b {
            x: ok(OffsetB12::new(x as i16)),
            y: ok(OffsetB12::new(y as i16)),
        }),
        4 => NodeOffsetPointXY::NodeXY4(NodeXY26b {
            x: ok(OffsetB13::new(x as i16)),
            y: ok(OffsetB13::new(y as i16)),
        }),
        5 => NodeOffsetPointXY::NodeXY5(NodeXY28b {
            x: ok(OffsetB14::new(x as i16)),
            y: ok(OffsetB14::new(y as i16)),
        }),
        _ => NodeOffsetPointXY::NodeXY6(NodeXY32b {
            x: ok(OffsetB16::new(x as i16)),
            y: ok(OffsetB16::new(y as i16)),
        }),
    };
    n
}

/// A node-LatLon.
pub fn xy_latlon(lat: i32, lon: i32) -> NodeXY {
    let mut n = NodeXY::placeholder();
    n.delta = NodeOffsetPointXY::NodeLatLon(NodeLLmD64b {
        lon: ok(Longitude::new(lon)),
        lat: ok(Latitude::new(lat)),
    });
    n
}

/// `n` with `dWidth` (cm).
pub fn with_dwidth(mut n: NodeXY, d: i16) -> NodeXY {
    let a = n
        .attributes
        .get_or_insert_with(|| NodeAttributeSetXY::placeholder().into());
    a.d_width = OffsetB10::new(d);
    n
}

/// `n` with a node-level speed limit list.
pub fn with_limits(mut n: NodeXY, limits: SpeedLimitList) -> NodeXY {
    let a = n
        .attributes
        .get_or_insert_with(|| NodeAttributeSetXY::placeholder().into());
    let mut data = LaneDataAttributeList(SeqOf::new());
    let _ = data.0.push(LaneDataAttribute::SpeedLimits(limits));
    a.data = Some(data);
    n
}

/// A speed-limit list of (type, units of 0.02 m/s).
pub fn limits(items: &[(SpeedLimitType, u16)]) -> SpeedLimitList {
    let mut l = SpeedLimitList(SeqOf::new());
    for &(t, v) in items {
        let _ = l.0.push(RegulatorySpeedLimit {
            r#type: t,
            speed: ok(Velocity::new(v)),
        });
    }
    l
}

/// A node list.
pub fn nodes(items: &[NodeXY]) -> NodeListXY {
    let mut set = NodeSetXY(SeqOf::new());
    for n in items {
        let _ = set.0.push(n.clone());
    }
    NodeListXY::Nodes(set)
}

/// A computed node list.
pub fn computed(
    reference: u8,
    dx: i16,
    dy: i16,
    rotate: Option<u16>,
    scale: Option<(i16, i16)>,
) -> NodeListXY {
    let mut c = ComputedLane::placeholder();
    c.reference_lane_id = ok(LaneID::new(reference));
    c.offset_xaxis = match DrivenLineOffsetSm::new(dx) {
        Some(v) => ComputedLaneOffsetXaxis::Small(v),
        None => ComputedLaneOffsetXaxis::Large(ok(DrivenLineOffsetLg::new(dx))),
    };
    c.offset_yaxis = match DrivenLineOffsetSm::new(dy) {
        Some(v) => ComputedLaneOffsetYaxis::Small(v),
        None => ComputedLaneOffsetYaxis::Large(ok(DrivenLineOffsetLg::new(dy))),
    };
    c.rotate_xy = rotate.and_then(Angle::new);
    c.scale_xaxis = scale.and_then(|s| ScaleB12::new(s.0));
    c.scale_yaxis = scale.and_then(|s| ScaleB12::new(s.1));
    NodeListXY::Computed(c)
}

/// Lane `id` with the two `directionalUse` bits, a vehicle lane type and `list`.
pub fn fill_lane(l: &mut GenericLane, id: u8, ingress: bool, egress: bool, list: NodeListXY) {
    l.lane_id = ok(LaneID::new(id));
    let mut d = ok(LaneDirection::zeros(2));
    d.0.set(LaneDirection::INGRESS_PATH, ingress);
    d.0.set(LaneDirection::EGRESS_PATH, egress);
    l.lane_attributes.directional_use = d;
    l.lane_attributes.lane_type =
        LaneTypeAttributes::Vehicle(LaneAttributesVehicle(ok(Bits::zeros(8))));
    l.node_list = list;
}

/// Adds a lane to `lanes` and fills it with `f`.
pub fn add(lanes: &mut SeqOf<GenericLane, 64>, f: impl FnOnce(&mut GenericLane)) {
    if let Some(l) = lanes.push_slot() {
        f(l);
    }
}

/// Makes `l` a median.
pub fn make_median(l: &mut GenericLane) {
    l.lane_attributes.lane_type =
        LaneTypeAttributes::Median(LaneAttributesBarrier(ok(Bits::zeros(16))));
}

/// Adds connections to `lanes` (the last one to a remote intersection).
pub fn connect(l: &mut GenericLane, lanes: &[u8], remote: Option<u16>) {
    let mut list = ConnectsToList(SeqOf::new());
    for (i, &id) in lanes.iter().enumerate() {
        let mut c = Connection::placeholder();
        c.connecting_lane = ConnectingLane {
            lane: ok(LaneID::new(id)),
            maneuver: None,
        };
        if i + 1 == lanes.len() {
            c.remote_intersection = remote.map(|r| IntersectionReferenceID {
                region: None,
                id: ok(IntersectionID::new(r)),
            });
        }
        let _ = list.0.push(c);
    }
    l.connects_to = Some(list);
}

/// A MapData with one intersection `id`, revision `rev`, at the test reference, lane
/// width `width` cm; `lanes` fills its lane set.
pub fn map_with(
    id: u16,
    rev: u8,
    width: Option<u16>,
    lanes: impl FnOnce(&mut SeqOf<GenericLane, 64>),
) -> Box<MapData> {
    let mut map = Box::new(MapData::placeholder());
    let mut list = IntersectionGeometryList(SeqOf::new());
    if let Some(ix) = list.0.push_slot() {
        fill_intersection(ix, id, rev, width);
        lanes(&mut ix.lane_set.0);
    }
    map.intersections = Some(list);
    map
}

fn fill_intersection(ix: &mut IntersectionGeometry, id: u16, rev: u8, width: Option<u16>) {
    ix.id = IntersectionReferenceID {
        region: None,
        id: ok(IntersectionID::new(id)),
    };
    ix.revision = ok(MsgCount::new(rev));
    ix.ref_point = pos(LAT, LON, Some(2710));
    ix.lane_width = width.and_then(LaneWidth::new);
}

/// Adds a road segment (region 26) with one egress lane of two node-XY3 nodes.
pub fn add_segment(map: &mut MapData, id: u16, rev: u8) {
    let mut list = RoadSegmentList(SeqOf::new());
    if let Some(rs) = list.0.push_slot() {
        fill_segment(rs, id, rev);
    }
    map.road_segments = Some(list);
}

fn fill_segment(rs: &mut RoadSegment, id: u16, rev: u8) {
    rs.id = RoadSegmentReferenceID {
        region: RoadRegulatorID::new(26),
        id: ok(RoadSegmentID::new(id)),
    };
    rs.revision = ok(MsgCount::new(rev));
    rs.ref_point = pos(LAT + 10_000, LON, None);
    if let Some(l) = rs.road_lane_set.0.push_slot() {
        fill_lane(l, 1, false, true, nodes(&[xy(3, 0, 0), xy(3, 0, 2000)]));
    }
}

/// A TIM with `packet` (or none), msgCnt `cnt`, one data frame per `frames` entry.
pub fn tim_with(
    packet: Option<u8>,
    cnt: u8,
    frames: &[&dyn Fn(&mut TravelerDataFrame)],
) -> Box<TravelerInformation> {
    let mut tim = Box::new(TravelerInformation::placeholder());
    tim.msg_cnt = ok(MsgCount::new(cnt));
    tim.packet_id = packet.map(|b| UniqueMSGID([b; 9]));
    for f in frames {
        if let Some(df) = tim.data_frames.0.push_slot() {
            *df = TravelerDataFrame::placeholder();
            df.start_year = DYear::new(2025);
            df.start_time = ok(MinuteOfTheYear::new(1000));
            df.duration_time = ok(MinutesDuration::new(60));
            f(df);
        }
    }
    tim
}

/// Sets the frame's content to work-zone ITIS codes.
pub fn work_zone(df: &mut TravelerDataFrame, codes: &[u16]) {
    let mut wz = j2735::msg::traveler_information::WorkZone(SeqOf::new());
    for &c in codes {
        let _ = wz.0.push(WorkZoneItem {
            item: WorkZoneItemItem::Itis(ok(ITIScodes::new(c))),
        });
    }
    df.content = TravelerDataFrameContent::WorkZone(wz);
}

/// A path region at the test reference (offset `d_lat` 1e-7 degree north) with a
/// node-XY list, `scale`, directionality and heading-slice bits.
pub fn xy_region(
    d_lat: i32,
    list: NodeListXY,
    scale: Option<u8>,
    dir: DirectionOfUse,
    slices: &[usize],
) -> GeographicalPath {
    let mut gp = GeographicalPath::placeholder();
    gp.anchor = Some(pos(LAT + d_lat, LON, None));
    gp.lane_width = LaneWidth::new(366);
    gp.directionality = Some(dir);
    gp.closed_path = Some(false);
    gp.direction = Some(heading(slices));
    gp.description = Some(GeographicalPathDescription::Path(OffsetSystem {
        scale: scale.and_then(Zoom::new),
        offset: OffsetSystemOffset::Xy(list),
    }));
    gp
}

/// A J2735 HeadingSlice with the given bits (bit 0 = first bit = 0 to 22.5 degrees).
pub fn heading(slices: &[usize]) -> HeadingSlice {
    let mut h = ok(HeadingSlice::zeros(16));
    for &i in slices {
        h.0.set(i, true);
    }
    h
}

/// A node-LL path region (offsets (lon, lat) 1e-7 degree; `None` = node-LatLon at
/// the reference).
pub fn ll_region(steps: &[Option<(i16, i16)>]) -> GeographicalPath {
    let mut set = NodeSetLL(SeqOf::new());
    for s in steps {
        let mut n = NodeLL::placeholder();
        n.delta = match s {
            Some((lon, lat)) => NodeOffsetPointLL::NodeLL2(NodeLL28B {
                lon: ok(OffsetLLB14::new(*lon)),
                lat: ok(OffsetLLB14::new(*lat)),
            }),
            None => NodeOffsetPointLL::NodeLatLon(NodeLLmD64b {
                lon: ok(Longitude::new(LON)),
                lat: ok(Latitude::new(LAT)),
            }),
        };
        let _ = set.0.push(n);
    }
    let mut gp = GeographicalPath::placeholder();
    gp.anchor = Some(pos(LAT, LON, None));
    gp.description = Some(GeographicalPathDescription::Path(OffsetSystem {
        scale: None,
        offset: OffsetSystemOffset::Ll(NodeListLL::Nodes(set)),
    }));
    gp
}

/// A circle region (geometry) of `radius` `units` at the reference.
pub fn circle_region(radius: u16, units: DistanceUnits, slices: &[usize]) -> GeographicalPath {
    let mut gp = GeographicalPath::placeholder();
    let mut g = GeometricProjection::placeholder();
    g.direction = heading(slices);
    g.extent = Some(Extent::UseFor500meters);
    g.circle = Circle {
        center: pos(LAT, LON, None),
        radius: ok(RadiusB12::new(radius)),
        units,
    };
    gp.description = Some(GeographicalPathDescription::Geometry(g.into()));
    gp
}

/// Adds `gp` to the frame's regions.
pub fn add_region(df: &mut TravelerDataFrame, gp: GeographicalPath) {
    let _ = df.regions.0.push(gp);
}
