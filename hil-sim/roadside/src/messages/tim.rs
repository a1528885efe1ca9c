//! The TravelerInformation frame of a work zone: per closed lane a path region from the
//! zone start to its end, a `workZone` data frame of ITIS codes and, with a reduced
//! limit, a `speedLimit` frame over the same regions.

use super::{
    angle_diff, at_point, checked, cm, densify, fit, heading_bits, heading_slice, node_xy,
    position, project, BuildError, WorkZone, ITIS_CLOSED, ITIS_KPH, ITIS_LEFT_LANE, ITIS_MPH,
    ITIS_NUMBER_BASE, ITIS_RIGHT_LANE, ITIS_ROAD_CONSTRUCTION, ITIS_SPEED_LIMIT,
};
use crate::road::{bearing, Road, RoadLane};
use j2735::msg::common::{
    DYear, DescriptiveName, LaneWidth, MinuteOfTheYear, MsgCount, NodeListXY, NodeSetXY, NodeXY,
    RoadSegmentID, RoadSegmentReferenceID, SSPindex,
};
use j2735::msg::itis::ITIScodes;
use j2735::msg::traveler_information::{
    DirectionOfUse, GeographicalPath, GeographicalPathDescription, MUTCDCode, MinutesDuration,
    OffsetSystem, OffsetSystemOffset, RoadSignID, SignPrority, SpeedLimit, SpeedLimitItem,
    SpeedLimitItemItem, TravelerDataFrame, TravelerDataFrameContent, TravelerDataFrameList,
    TravelerDataFrameMsgId, TravelerDataFrameRegions, TravelerInfoType, UniqueMSGID,
    WorkZone as WorkZoneContent, WorkZoneItem, WorkZoneItemItem,
};
use j2735::uper::Extensions;
use j2735::{MessageFrame, MessageFrameValue, TravelerInformation};

/// The TravelerInformation frame of a work zone on `road`: per closed lane a path region
/// from the zone start (the anchor) to its end, in a `workZone` data frame (ITIS road
/// construction, closed, left/right lane) and, with a reduced limit, a `speedLimit` frame
/// over the same regions.
pub fn build_tim(road: &Road, zone: &WorkZone) -> Result<Box<MessageFrame>, BuildError> {
    if zone.closed_lanes.is_empty() || zone.end_m <= zone.start_m {
        return Err(BuildError::Degenerate(
            "a zone needs a closed lane and end > start".into(),
        ));
    }
    let mut regions = TravelerDataFrameRegions::new();
    let mut codes = vec![ITIS_ROAD_CONSTRUCTION, ITIS_CLOSED];
    let first = road
        .lane(zone.closed_lanes[0])
        .ok_or(BuildError::UnknownLane(zone.closed_lanes[0]))?;
    for (k, &id) in zone.closed_lanes.iter().enumerate() {
        let lane = road.lane(id).ok_or(BuildError::UnknownLane(id))?;
        let (from, to) = if k == 0 {
            (zone.start_m, zone.end_m)
        } else {
            let a = project(lane, at_point(first, zone.start_m)).map_or(zone.start_m, |p| p.0);
            let b = project(lane, at_point(first, zone.end_m)).map_or(zone.end_m, |p| p.0);
            (a, b)
        };
        regions
            .0
            .push(path_region(road, lane, from, to, k as i64 + 1)?)
            .ok();
        if let Some(code) = side_code(road, lane) {
            if !codes.contains(&code) {
                codes.push(code);
            }
        }
    }
    let mut frames = TravelerDataFrameList::new();
    let mut items = WorkZoneContent::new();
    for c in &codes {
        let item = WorkZoneItemItem::Itis(fit("itis", (*c).into(), ITIScodes::new)?);
        items.0.push(WorkZoneItem { item }).ok();
    }
    let content = TravelerDataFrameContent::WorkZone(items);
    frames
        .0
        .push(data_frame(zone, &regions, content, MUTCDCode::Warning)?)
        .ok();
    if let Some(limit) = zone.speed_limit {
        let number = ITIS_NUMBER_BASE + limit.value.min(511);
        let unit = if limit.mph { ITIS_MPH } else { ITIS_KPH };
        let mut items = SpeedLimit::new();
        for c in [ITIS_SPEED_LIMIT, number, unit] {
            let item = SpeedLimitItemItem::Itis(fit("itis", c.into(), ITIScodes::new)?);
            items.0.push(SpeedLimitItem { item }).ok();
        }
        let content = TravelerDataFrameContent::SpeedLimit(items);
        frames
            .0
            .push(data_frame(zone, &regions, content, MUTCDCode::Regulatory)?)
            .ok();
    }
    let tim = TravelerInformation {
        msg_cnt: fit("msgCnt", (zone.msg_cnt % 128).into(), MsgCount::new)?,
        time_stamp: Some(minute_of_year(zone)?),
        packet_id: Some(UniqueMSGID(zone.packet_id)),
        url_b: None,
        data_frames: frames,
        regional: None,
        extensions: Extensions::new(),
    };
    checked(MessageFrame {
        value: MessageFrameValue::TravelerInformation(tim.into()),
        extensions: Extensions::new(),
    })
}

/// The zone's start as `MinuteOfTheYear`.
fn minute_of_year(zone: &WorkZone) -> Result<MinuteOfTheYear, BuildError> {
    let minute = zone.start.minute_of_year().into();
    fit("startTime", minute, MinuteOfTheYear::new)
}

/// One advisory data frame over `regions`, its sign anchored at the first region's anchor.
fn data_frame(
    zone: &WorkZone,
    regions: &TravelerDataFrameRegions,
    content: TravelerDataFrameContent,
    sign: MUTCDCode,
) -> Result<TravelerDataFrame, BuildError> {
    let anchor = regions.0.first().and_then(|r| r.anchor.clone());
    let position = anchor.ok_or(BuildError::Degenerate("a region without anchor".into()))?;
    let unused = || fit("notUsed", 0, SSPindex::new);
    Ok(TravelerDataFrame {
        not_used: unused()?,
        frame_type: TravelerInfoType::Advisory,
        msg_id: TravelerDataFrameMsgId::RoadSignID(RoadSignID {
            position,
            view_angle: heading_bits(0xffff)?,
            mutcd_code: Some(sign),
            crc: None,
        }),
        start_year: Some(fit("startYear", zone.start.year.into(), DYear::new)?),
        start_time: minute_of_year(zone)?,
        duration_time: fit(
            "durationTime",
            zone.duration_min.into(),
            MinutesDuration::new,
        )?,
        priority: fit("priority", 5, SignPrority::new)?,
        not_used1: unused()?,
        regions: regions.clone(),
        not_used2: unused()?,
        not_used3: unused()?,
        content,
        url: None,
        extensions: Extensions::new(),
    })
}

/// ITIS left/right lane when `lane` is the leftmost/rightmost of the lanes running its way.
fn side_code(road: &Road, lane: &RoadLane) -> Option<u16> {
    let here = lane.at(0.0)?;
    let mut left = 0;
    let mut right = 0;
    for other in road.lanes.iter().filter(|o| o.id != lane.id) {
        let Some((station, _)) = project(other, here.point) else {
            continue;
        };
        let Some(o) = other.at(station) else { continue };
        if angle_diff(o.bearing_deg, here.bearing_deg) >= 45.0 {
            continue;
        }
        let b = here.bearing_deg.to_radians();
        let lateral =
            -(o.point[0] - here.point[0]) * b.cos() + (o.point[1] - here.point[1]) * b.sin();
        if lateral.abs() > 20.0 {
            continue;
        }
        if lateral > 0.0 {
            left += 1
        } else {
            right += 1
        }
    }
    match (left, right) {
        (0, r) if r > 0 => Some(ITIS_LEFT_LANE),
        (l, 0) if l > 0 => Some(ITIS_RIGHT_LANE),
        _ => None,
    }
}

/// A GeographicalPath along `lane` from station `from` to `to`: anchored at the start,
/// node-XY offsets, the lane width, `forward`, and the heading slice of its bearings.
fn path_region(
    road: &Road,
    lane: &RoadLane,
    from: f64,
    to: f64,
    id: i64,
) -> Result<GeographicalPath, BuildError> {
    let points = densify(&lane.slice(from, to), 300.0);
    if points.len() < 2 {
        return Err(BuildError::Degenerate(format!(
            "lane {} has no zone path",
            lane.id
        )));
    }
    let anchor = road.to_wgs84(points[0]).ok_or(BuildError::Position)?;
    let mut nodes = NodeSetXY::new();
    // The first node is the anchor itself (offset 0, 0): the zone starts there.
    let mut prev = points[0];
    for p in &points {
        let delta = node_xy(lane.id, prev, *p)?;
        let node = NodeXY {
            delta,
            attributes: None,
            extensions: Extensions::new(),
        };
        nodes.0.push(node).ok();
        prev = *p;
    }
    let bearings: Vec<f64> = points.windows(2).map(|w| bearing(w[0], w[1])).collect();
    let name = format!("work zone lane {}", lane.id);
    let offset = OffsetSystemOffset::Xy(NodeListXY::Nodes(nodes));
    Ok(GeographicalPath {
        name: Some(
            DescriptiveName::new(&name).ok_or_else(|| {
                BuildError::Codec(format!("name {name:?} is not a DescriptiveName"))
            })?,
        ),
        id: Some(RoadSegmentReferenceID {
            region: None,
            id: fit("id", id, RoadSegmentID::new)?,
        }),
        anchor: Some(position(anchor)?),
        lane_width: Some(fit("laneWidth", cm(lane.width_m), LaneWidth::new)?),
        directionality: Some(DirectionOfUse::Forward),
        closed_path: Some(false),
        direction: Some(heading_bits(heading_slice(&bearings))?),
        description: Some(GeographicalPathDescription::Path(OffsetSystem {
            scale: None,
            offset,
        })),
        regional: None,
        extensions: Extensions::new(),
    })
}
