//! The TIM part of `j2735 info`: each data frame's sign, validity window, regions and
//! content (kind, ITIS codes and text).

use j2735::msg::common::NodeListXY;
use j2735::msg::itis::ITIScodesAndTextItemItem as AdvisoryItem;
use j2735::msg::traveler_information::{
    ExitServiceItemItem, GenericSignageItemItem, GeographicalPath, GeographicalPathDescription,
    MinutesDuration, NodeListLL, OffsetSystem, OffsetSystemOffset, SpeedLimitItemItem,
    TravelerDataFrame, TravelerDataFrameContent, TravelerDataFrameMsgId, WorkZoneItemItem,
};
use j2735::TravelerInformation;

use super::{count, identifier, position};
use crate::{itis, output::to_hex};

mod time;

/// The summary lines of a TIM, indented under the frame line.
pub fn lines(tim: &TravelerInformation) -> Vec<String> {
    let packet = tim
        .packet_id
        .as_ref()
        .map_or(String::new(), |p| format!(", packetID {}", to_hex(&p.0)));
    let mut lines = vec![format!(
        "  msgCnt {}{packet}, {}",
        tim.msg_cnt.get(),
        count(tim.data_frames.len(), "data frame")
    )];
    for (index, frame) in tim.data_frames.iter().enumerate() {
        lines.extend(data_frame(index + 1, frame));
    }
    lines
}

fn data_frame(n: usize, frame: &TravelerDataFrame) -> Vec<String> {
    let mut lines = vec![
        format!(
            "  data frame {n}: {}, priority {}, {}",
            identifier(frame.frame_type.identifier()),
            frame.priority.get(),
            sign(&frame.msg_id)
        ),
        format!(
            "    valid {}",
            time::validity(
                frame.start_year.map(|y| y.get()),
                frame.start_time.get(),
                frame.duration_time.get(),
                MinutesDuration::INDEFINITE.get(),
            )
        ),
    ];
    for (index, region) in frame.regions.iter().enumerate() {
        lines.push(format!("    region {}: {}", index + 1, region_text(region)));
    }
    let (kind, items) = content(&frame.content);
    lines.push(format!("    content {kind}: {}", items.join(", ")));
    lines
}

fn sign(id: &TravelerDataFrameMsgId) -> String {
    match id {
        TravelerDataFrameMsgId::FurtherInfoID(f) => format!("furtherInfoID {}", to_hex(&f.0)),
        TravelerDataFrameMsgId::RoadSignID(r) => {
            let mutcd = r.mutcd_code.map_or(String::new(), |m| {
                format!(", MUTCD {}", identifier(m.identifier()))
            });
            format!("roadSignID at {}{mutcd}", position(&r.position))
        }
    }
}

fn region_text(region: &GeographicalPath) -> String {
    let mut parts = vec![description(region.description.as_ref())];
    if let Some(anchor) = &region.anchor {
        parts.push(format!("anchor {}", position(anchor)));
    }
    if let Some(width) = region.lane_width {
        parts.push(format!("lane width {} cm", width.get()));
    }
    if let Some(directionality) = region.directionality {
        parts.push(identifier(directionality.identifier()).to_string());
    }
    if region.closed_path == Some(true) {
        parts.push("closed path".to_string());
    }
    if let Some(direction) = &region.direction {
        parts.push(format!("heading slices {}", to_hex(direction.0.as_bytes())));
    }
    parts.join(", ")
}

fn description(description: Option<&GeographicalPathDescription>) -> String {
    match description {
        None => "no description".to_string(),
        Some(GeographicalPathDescription::Path(path)) => path_text(path),
        Some(GeographicalPathDescription::Geometry(g)) => format!(
            "circle of radius {} {}",
            g.circle.radius.get(),
            identifier(g.circle.units.identifier())
        ),
        Some(GeographicalPathDescription::OldRegion(_)) => "oldRegion".to_string(),
        Some(GeographicalPathDescription::Extension { .. }) => {
            "description of a later J2735 version".to_string()
        }
    }
}

fn path_text(path: &OffsetSystem) -> String {
    let nodes = match &path.offset {
        OffsetSystemOffset::Xy(NodeListXY::Nodes(n)) => format!("{} node-XY offsets", n.len()),
        OffsetSystemOffset::Xy(NodeListXY::Computed(c)) => {
            format!("offsets computed from lane {}", c.reference_lane_id.get())
        }
        OffsetSystemOffset::Ll(NodeListLL::Nodes(n)) => format!("{} node-LL offsets", n.len()),
        OffsetSystemOffset::Xy(NodeListXY::Extension { .. })
        | OffsetSystemOffset::Ll(NodeListLL::Extension { .. }) => {
            "a node list of a later J2735 version".to_string()
        }
    };
    let scale = path
        .scale
        .map_or(String::new(), |s| format!(" (scale {})", s.get()));
    format!("path of {nodes}{scale}")
}

/// ITIS codes as `1025 (road construction)`, text as a quoted string.
macro_rules! items {
    ($list:expr, $item:ident) => {
        $list
            .iter()
            .map(|i| match &i.item {
                $item::Itis(code) => format!("ITIS {}", itis::describe(code.get())),
                $item::Text(text) => format!("text {:?}", text.as_str()),
            })
            .collect()
    };
}

fn content(content: &TravelerDataFrameContent) -> (&'static str, Vec<String>) {
    match content {
        TravelerDataFrameContent::Advisory(l) => ("advisory", items!(l, AdvisoryItem)),
        TravelerDataFrameContent::WorkZone(l) => ("workZone", items!(l, WorkZoneItemItem)),
        TravelerDataFrameContent::GenericSign(l) => {
            ("genericSign", items!(l, GenericSignageItemItem))
        }
        TravelerDataFrameContent::SpeedLimit(l) => ("speedLimit", items!(l, SpeedLimitItemItem)),
        TravelerDataFrameContent::ExitService(l) => ("exitService", items!(l, ExitServiceItemItem)),
    }
}
