//! The MAP part of `j2735 info`: intersections and road segments, their lanes and nodes.

use j2735::msg::common::{NodeListXY, SpeedLimitList, Velocity};
use j2735::msg::map_data::{
    GenericLane, IntersectionGeometry, LaneDirection, LaneTypeAttributes, RoadSegment,
};
use j2735::MapData;

use super::{count, identifier, position};

/// The summary lines of a MAP, indented under the frame line.
pub fn lines(map: &MapData) -> Vec<String> {
    let intersections: Vec<&IntersectionGeometry> =
        map.intersections.iter().flat_map(|l| l.iter()).collect();
    let segments: Vec<&RoadSegment> = map.road_segments.iter().flat_map(|l| l.iter()).collect();
    let mut lines = vec![format!(
        "  msgIssueRevision {}, {}, {}",
        map.msg_issue_revision.get(),
        count(intersections.len(), "intersection"),
        count(segments.len(), "road segment")
    )];
    for ix in intersections {
        lines.push(intersection_line(ix));
        lines.extend(ix.lane_set.iter().map(lane_line));
    }
    for segment in segments {
        lines.push(segment_line(segment));
        lines.extend(segment.road_lane_set.iter().map(lane_line));
    }
    lines
}

fn intersection_line(ix: &IntersectionGeometry) -> String {
    let region = ix
        .id
        .region
        .map_or(String::new(), |r| format!(" region {}", r.get()));
    let lanes: Vec<&GenericLane> = ix.lane_set.iter().collect();
    format!(
        "  intersection {}{region}{} rev {}: {}, {}; ref point {}{}{}",
        ix.id.id.get(),
        name(ix.name.as_ref().map(|n| n.as_str())),
        ix.revision.get(),
        count(lanes.len(), "lane"),
        count(node_total(&lanes), "node"),
        position(&ix.ref_point),
        lane_width(ix.lane_width.map(|w| w.get())),
        speed_limits(ix.speed_limits.as_ref()),
    )
}

fn segment_line(segment: &RoadSegment) -> String {
    let region = segment
        .id
        .region
        .map_or(String::new(), |r| format!(" region {}", r.get()));
    let lanes: Vec<&GenericLane> = segment.road_lane_set.iter().collect();
    format!(
        "  road segment {}{region}{} rev {}: {}, {}; ref point {}{}{}",
        segment.id.id.get(),
        name(segment.name.as_ref().map(|n| n.as_str())),
        segment.revision.get(),
        count(lanes.len(), "lane"),
        count(node_total(&lanes), "node"),
        position(&segment.ref_point),
        lane_width(segment.lane_width.map(|w| w.get())),
        speed_limits(segment.speed_limits.as_ref()),
    )
}

fn lane_line(lane: &GenericLane) -> String {
    format!(
        "    lane {}{}: {} {}, {}",
        lane.lane_id.get(),
        name(lane.name.as_ref().map(|n| n.as_str())),
        direction(&lane.lane_attributes.directional_use),
        lane_type(&lane.lane_attributes.lane_type),
        nodes(&lane.node_list),
    )
}

/// The nodes of all lanes with an explicit node list.
fn node_total(lanes: &[&GenericLane]) -> usize {
    lanes
        .iter()
        .map(|lane| match &lane.node_list {
            NodeListXY::Nodes(nodes) => nodes.len(),
            _ => 0,
        })
        .sum()
}

fn nodes(list: &NodeListXY) -> String {
    match list {
        NodeListXY::Nodes(nodes) => count(nodes.len(), "node"),
        NodeListXY::Computed(c) => format!("computed from lane {}", c.reference_lane_id.get()),
        NodeListXY::Extension { .. } => "node list of a later J2735 version".to_string(),
    }
}

fn direction(bits: &LaneDirection) -> &'static str {
    let ingress = bits.0.get(LaneDirection::INGRESS_PATH);
    let egress = bits.0.get(LaneDirection::EGRESS_PATH);
    match (ingress, egress) {
        (true, true) => "ingress+egress",
        (true, false) => "ingress",
        (false, true) => "egress",
        (false, false) => "no-direction",
    }
}

fn lane_type(attributes: &LaneTypeAttributes) -> &'static str {
    match attributes {
        LaneTypeAttributes::Vehicle(_) => "vehicle",
        LaneTypeAttributes::Crosswalk(_) => "crosswalk",
        LaneTypeAttributes::BikeLane(_) => "bikeLane",
        LaneTypeAttributes::Sidewalk(_) => "sidewalk",
        LaneTypeAttributes::Median(_) => "median",
        LaneTypeAttributes::Striping(_) => "striping",
        LaneTypeAttributes::TrackedVehicle(_) => "trackedVehicle",
        LaneTypeAttributes::Parking(_) => "parking",
        LaneTypeAttributes::Extension { .. } => "(extension lane type)",
    }
}

/// ` "name"`, or nothing.
fn name(text: Option<&str>) -> String {
    text.map_or(String::new(), |t| format!(" {t:?}"))
}

/// `, lane width 366 cm`, or nothing.
fn lane_width(cm: Option<u16>) -> String {
    cm.map_or(String::new(), |w| format!(", lane width {w} cm"))
}

/// `, speed limit maxSpeedInConstructionZone 40 km/h`, or nothing.
fn speed_limits(list: Option<&SpeedLimitList>) -> String {
    let Some(list) = list else {
        return String::new();
    };
    let limits: Vec<String> = list
        .iter()
        .map(|l| format!("{} {}", identifier(l.r#type.identifier()), speed(l.speed)))
        .collect();
    format!(", speed limits {}", limits.join(", "))
}

/// A velocity (0.02 m/s units) in km/h.
fn speed(v: Velocity) -> String {
    if v == Velocity::UNAVAILABLE {
        return "unavailable".to_string();
    }
    format!("{:.0} km/h", f64::from(v.get()) * 0.02 * 3.6)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_parts() {
        assert_eq!(name(Some("Main St")), " \"Main St\"");
        assert_eq!(lane_width(Some(366)), ", lane width 366 cm");
        assert_eq!(speed(Velocity::new(556).unwrap()), "40 km/h");
        let mut bits = LaneDirection::zeros(2).unwrap();
        assert_eq!(direction(&bits), "no-direction");
        bits.0.set(LaneDirection::INGRESS_PATH, true);
        assert_eq!(direction(&bits), "ingress");
    }
}
