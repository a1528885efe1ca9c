//! The MapData frame: the road's lanes as egress lanes of one road section, with the
//! construction-zone limit from the zone start on the lanes running with the zone.

use super::{
    checked, cm, densify, fit, node_xy, position, velocity, with_node_at, zone_start_on,
    BuildError, SignSpeed, WorkZone,
};
use crate::road::{Road, RoadLane};
use j2735::msg::common::{
    IntersectionID, IntersectionReferenceID, LaneDataAttribute, LaneDataAttributeList, LaneID,
    LaneWidth, Latitude, Longitude, MsgCount, NodeAttributeSetXY, NodeLLmD64b, NodeListXY,
    NodeOffsetPointXY, NodeSetXY, NodeXY, OffsetB10, RegulatorySpeedLimit, SpeedLimitList,
    SpeedLimitType, Velocity,
};
use j2735::msg::map_data::{
    GenericLane, IntersectionGeometry, LaneAttributes, LaneAttributesVehicle, LaneDirection,
    LaneList, LaneSharing, LaneTypeAttributes, LayerType,
};
use j2735::uper::Extensions;
use j2735::{MapData, MessageFrame, MessageFrameValue};

/// The MapData frame for `road`, intersection (or road section) `id`, `revision`, with
/// `maxSpeedInConstructionZone` from the zone start on the lanes running with the zone.
pub fn build_map(
    road: &Road,
    id: u16,
    revision: u8,
    zone: Option<&WorkZone>,
) -> Result<Box<MessageFrame>, BuildError> {
    let mut lane_set = LaneList::new();
    for lane in &road.lanes {
        lane_set.0.push(map_lane(road, lane, zone)?).ok();
    }
    let base_width = road.lanes.first().map_or(3.6, |l| l.width_m);
    let limit = road.lanes.first().map_or(0.0, |l| l.speed_limit_kmh);
    let revision = fit("revision", revision.into(), MsgCount::new)?;
    let mut intersections = j2735::msg::map_data::IntersectionGeometryList::new();
    let section = IntersectionGeometry {
        name: None,
        id: IntersectionReferenceID {
            region: None,
            id: fit("id", id.into(), IntersectionID::new)?,
        },
        revision,
        ref_point: position(road.reference)?,
        lane_width: Some(fit("laneWidth", cm(base_width), LaneWidth::new)?),
        speed_limits: Some(speed_limits(SpeedLimitType::VehicleMaxSpeed, limit / 3.6)?),
        lane_set,
        preempt_priority_data: None,
        regional: None,
        extensions: Extensions::new(),
    };
    intersections.0.push(section).ok();
    let map = MapData {
        time_stamp: None,
        msg_issue_revision: revision,
        layer_type: Some(LayerType::RoadwaySectionData),
        layer_id: None,
        intersections: Some(intersections),
        road_segments: None,
        data_parameters: None,
        restriction_list: None,
        regional: None,
        extensions: Extensions::new(),
    };
    checked(MessageFrame {
        value: MessageFrameValue::MapData(map.into()),
        extensions: Extensions::new(),
    })
}

/// A one-entry `SpeedLimitList` of `kind` at `mps`.
fn speed_limits(kind: SpeedLimitType, mps: f64) -> Result<SpeedLimitList, BuildError> {
    let mut list = SpeedLimitList::new();
    list.0
        .push(RegulatorySpeedLimit {
            r#type: kind,
            speed: fit("speed", velocity(mps), Velocity::new)?,
        })
        .ok();
    Ok(list)
}

/// One `GenericLane`: egress lanes, nodes in the direction of travel from the reference.
fn map_lane(
    road: &Road,
    lane: &RoadLane,
    zone: Option<&WorkZone>,
) -> Result<GenericLane, BuildError> {
    let base_width = road.lanes.first().map_or(3.6, |l| l.width_m);
    let zone_start = zone.and_then(|z| zone_start_on(road, lane, z));
    let points = match zone_start {
        Some((station, _)) => densify(&with_node_at(lane, station), 300.0),
        None => densify(&lane.centre, 300.0),
    };
    let limit_node = zone_start.and_then(|(station, _)| {
        let target = super::at_point(lane, station);
        points
            .iter()
            .position(|p| crate::road::dist(*p, target) < 0.01)
    });
    let mut nodes = NodeSetXY::new();
    let mut prev = [0.0, 0.0];
    for (i, p) in points.iter().enumerate() {
        let delta = match node_xy(lane.id, prev, *p) {
            // A lane starting far from the reference point starts at an absolute position.
            Err(BuildError::OffsetTooLarge { .. }) if i == 0 => {
                let at = road.to_wgs84(*p).ok_or(BuildError::Position)?;
                NodeOffsetPointXY::NodeLatLon(NodeLLmD64b {
                    lon: fit("lon", at.lon_e7().into(), Longitude::new)?,
                    lat: fit("lat", at.lat_e7().into(), Latitude::new)?,
                })
            }
            other => other?,
        };
        let d_width = (i == 0 && cm(lane.width_m) != cm(base_width))
            .then(|| fit("dWidth", cm(lane.width_m) - cm(base_width), OffsetB10::new))
            .transpose()?;
        let data = match limit_node == Some(i) {
            true => {
                let mps = zone_start.and_then(|(_, l)| l).map_or(0.0, SignSpeed::mps);
                let limits = speed_limits(SpeedLimitType::MaxSpeedInConstructionZone, mps)?;
                let mut data = LaneDataAttributeList::new();
                data.0.push(LaneDataAttribute::SpeedLimits(limits)).ok();
                Some(data)
            }
            false => None,
        };
        let attributes = (d_width.is_some() || data.is_some()).then(|| NodeAttributeSetXY {
            local_node: None,
            disabled: None,
            enabled: None,
            data,
            d_width,
            d_elevation: None,
            regional: None,
            extensions: Extensions::new(),
        });
        nodes
            .0
            .push(NodeXY {
                delta,
                attributes: attributes.map(Into::into),
                extensions: Extensions::new(),
            })
            .ok();
        prev = *p;
    }
    if nodes.0.len() < 2 {
        return Err(BuildError::Degenerate(format!(
            "lane {} has fewer than 2 nodes",
            lane.id
        )));
    }
    Ok(GenericLane {
        lane_id: fit("laneID", lane.id.into(), LaneID::new)?,
        name: None,
        ingress_approach: None,
        egress_approach: None,
        lane_attributes: egress_vehicle_lane()?,
        maneuvers: None,
        node_list: NodeListXY::Nodes(nodes),
        connects_to: None,
        overlays: None,
        regional: None,
        extensions: Extensions::new(),
    })
}

/// A vehicle lane used as an egress path, shared with nobody, no special attributes.
fn egress_vehicle_lane() -> Result<LaneAttributes, BuildError> {
    let bits = |what: &str| BuildError::Codec(format!("{what}: bit string size"));
    let mut directional_use = LaneDirection::zeros(2).ok_or(bits("directionalUse"))?;
    directional_use.0.set(LaneDirection::EGRESS_PATH, true);
    Ok(LaneAttributes {
        directional_use,
        shared_with: LaneSharing::zeros(10).ok_or(bits("sharedWith"))?,
        lane_type: LaneTypeAttributes::Vehicle(
            LaneAttributesVehicle::zeros(8).ok_or(bits("laneType"))?,
        ),
        regional: None,
    })
}
