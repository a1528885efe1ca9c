//! Decodes a work-zone MAP and TIM (the project's oracle vectors, bytes made by an
//! independent encoder), prints what an OBU reads from them, and re-encodes both to check the
//! bytes. Run: `cargo run --release -p j2735 --example workzone`.
use j2735::frame::{decode_message_into, encode_message, peek_message_id};
use j2735::msg::common::NodeListXY;
use j2735::msg::itis::ITIScodesAndTextItemItem;
use j2735::msg::traveler_information::{
    GeographicalPathDescription, OffsetSystemOffset, SpeedLimitItemItem, TravelerDataFrameContent,
    WorkZoneItemItem,
};
use j2735::uper::Placeholder;
use j2735::{MapData, TravelerInformation};

fn vector(name: &str) -> Vec<u8> {
    let line = include_str!("../tests/vectors/oracle_vectors.jsonl")
        .lines()
        .find(|l| l.contains(&format!("\"name\":\"{name}\"")))
        .expect("vector present");
    let v: serde_json::Value = serde_json::from_str(line).unwrap();
    let hex = v["uper"].as_str().unwrap();
    (0..hex.len() / 2)
        .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).unwrap())
        .collect()
}

fn show_map(bytes: &[u8]) {
    let mut map = Box::new(MapData::placeholder());
    decode_message_into(bytes, &mut *map).expect("MAP decodes");
    println!(
        "MAP ({} octets, messageId {}):",
        bytes.len(),
        peek_message_id(bytes).unwrap()
    );
    for ix in map.intersections.iter().flat_map(|l| l.iter()) {
        let p = &ix.ref_point;
        println!(
            "  intersection {} rev {} at {:.7}, {:.7}: {} lanes",
            ix.id.id.get(),
            ix.revision.get(),
            p.lat.get() as f64 * 1e-7,
            p.long.get() as f64 * 1e-7,
            ix.lane_set.len()
        );
        for lane in ix.lane_set.iter() {
            let nodes = match &lane.node_list {
                NodeListXY::Nodes(n) => n.len(),
                _ => 0,
            };
            println!("    lane {:>3}: {nodes} nodes", lane.lane_id.get());
        }
    }
    check_round_trip(bytes, |buf| encode_message(&*map, buf));
}

fn show_tim(bytes: &[u8]) {
    let mut tim = Box::new(TravelerInformation::placeholder());
    decode_message_into(bytes, &mut *tim).expect("TIM decodes");
    println!(
        "TIM ({} octets), msgCnt {}:",
        bytes.len(),
        tim.msg_cnt.get()
    );
    for frame in tim.data_frames.iter() {
        println!(
            "  start minute {} for {} min, {} region(s)",
            frame.start_time.get(),
            frame.duration_time.get(),
            frame.regions.len()
        );
        for region in frame.regions.iter() {
            if let Some(GeographicalPathDescription::Path(path)) = &region.description {
                let n = match &path.offset {
                    OffsetSystemOffset::Xy(NodeListXY::Nodes(n)) => n.len(),
                    OffsetSystemOffset::Ll(_) | OffsetSystemOffset::Xy(_) => 0,
                };
                println!("    path of {n} node-XY offsets from the anchor");
            }
        }
        let codes: Vec<String> = match &frame.content {
            TravelerDataFrameContent::WorkZone(w) => w
                .iter()
                .map(|i| match &i.item {
                    WorkZoneItemItem::Itis(c) => c.get().to_string(),
                    WorkZoneItemItem::Text(t) => format!("{:?}", t.0.as_str()),
                })
                .collect(),
            TravelerDataFrameContent::Advisory(a) => a
                .iter()
                .map(|i| match &i.item {
                    ITIScodesAndTextItemItem::Itis(c) => c.get().to_string(),
                    ITIScodesAndTextItemItem::Text(t) => format!("{:?}", t.0.as_str()),
                })
                .collect(),
            TravelerDataFrameContent::SpeedLimit(a) => a
                .iter()
                .map(|i| match &i.item {
                    SpeedLimitItemItem::Itis(c) => c.get().to_string(),
                    SpeedLimitItemItem::Text(t) => format!("{:?}", t.0.as_str()),
                })
                .collect(),
            _ => vec![],
        };
        println!("    content ITIS/text: {}", codes.join(", "));
    }
    check_round_trip(bytes, |buf| encode_message(&*tim, buf));
}

fn check_round_trip(
    bytes: &[u8],
    encode: impl FnOnce(&mut [u8]) -> Result<usize, j2735::uper::EncodeError>,
) {
    let mut buf = [0u8; 2048];
    let n = encode(&mut buf).expect("encodes");
    assert_eq!(&buf[..n], bytes, "re-encoded bytes differ");
    println!("  re-encoded: {n} octets, identical");
}

fn main() {
    // MapData with default capacities is megabytes: decode on a thread with room for it.
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(|| {
            show_map(&vector("map_work_zone"));
            show_tim(&vector("tim_work_zone_left_lane_closed"));
        })
        .unwrap()
        .join()
        .unwrap();
}
