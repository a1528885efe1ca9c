//! Puts memory.x where cortex-m-rt's link.x finds it, and turns the codec's committed oracle
//! vectors into Rust tables for the on-target tests:
//!
//! * `vectors.rs`: `MAP_TIM_VECTORS`, (name, MessageFrame UPER) of every MAP and TIM vector.
//! * `other_vectors.rs`: `OTHER_VECTORS`, (name, messageId, UPER) of every other vector.
//! * `work_zone.rs`: the geometry of the `map_work_zone` / `tim_work_zone_left_lane_closed`
//!   drive of `tests/drive.rs`, derived here from the vectors' JER (not from the OBU code):
//!   lane 1's centreline in the MAP's east/north plane in its direction of travel, and where
//!   the TIM path's ends project onto it; and that TIM made eastbound (see [`eastbound_tim`]).
use std::{env, fmt::Write as _, fs, path::PathBuf};

use j2735::frame::{decode_message_into, encode_message};
use j2735::msg::traveler_information::DirectionOfUse;
use j2735::uper::Placeholder;
use j2735::TravelerInformation;
use serde_json::Value;

const VECTORS: &str = "../../codec/tests/vectors/oracle_vectors.jsonl";
/// The independent IEEE 1609.2 vectors (for the on-target tests of `tests/signed.rs`).
const SIGNED_VECTORS: &str = "../../codec/tests/vectors/ieee1609dot2_signed.jsonl";
/// The trust anchors built in when `OBU_TRUST_ANCHORS` is not set: the bench PKI's.
const DEFAULT_ANCHORS: &str = "../../hil-sim/pki/bench/root.oer:../../hil-sim/pki/bench/ca.oer";
/// The MAP and TIM of the drive test, and the lane the car drives on.
const DRIVE_MAP: &str = "map_work_zone";
const DRIVE_TIM: &str = "tim_work_zone_left_lane_closed";
const DRIVE_LANE: u64 = 1;

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("OUT_DIR"));
    fs::copy("memory.x", out.join("memory.x")).expect("memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-changed={VECTORS}");
    let text = fs::read_to_string(VECTORS).expect("oracle vectors");
    let vectors: Vec<Value> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).expect("vector line"))
        .collect();

    let mut map_tim =
        String::from("/// (name, MessageFrame UPER) of the oracle vectors of MAP and TIM.\n");
    map_tim.push_str("pub static MAP_TIM_VECTORS: &[(&str, &[u8])] = &[\n");
    let mut other = String::from(
        "/// (name, messageId, MessageFrame UPER) of the oracle vectors other than MAP and TIM.\n",
    );
    other.push_str("pub static OTHER_VECTORS: &[(&str, u16, &[u8])] = &[\n");
    for v in &vectors {
        let id = v["jer"]["messageId"].as_u64().unwrap_or(0);
        let name = v["name"].as_str().expect("name");
        let bytes = byte_list(v["uper"].as_str().expect("uper"));
        if id == 18 || id == 31 {
            writeln!(map_tim, "    ({name:?}, &[{bytes}]),").unwrap();
        } else {
            writeln!(other, "    ({name:?}, {id}, &[{bytes}]),").unwrap();
        }
    }
    map_tim.push_str("];\n");
    other.push_str("];\n");
    fs::write(out.join("vectors.rs"), map_tim).expect("vectors.rs");
    fs::write(out.join("other_vectors.rs"), other).expect("other_vectors.rs");
    fs::write(out.join("work_zone.rs"), work_zone(&vectors)).expect("work_zone.rs");
    fs::write(out.join("trust_anchors.rs"), trust_anchors()).expect("trust_anchors.rs");
    println!("cargo:rerun-if-changed={SIGNED_VECTORS}");
    let signed = fs::read_to_string(SIGNED_VECTORS).expect("signed vectors");
    fs::write(out.join("signed_vectors.rs"), signed_vectors(&signed)).expect("signed_vectors.rs");
}

/// `TRUST_ANCHORS` (certificate COER files named by `OBU_TRUST_ANCHORS`, colon-separated,
/// relative to this crate; default: the bench PKI) and `REQUIRE_SIGNED` (`OBU_REQUIRE_SIGNED`
/// = 0 turns it off; default on).
fn trust_anchors() -> String {
    println!("cargo:rerun-if-env-changed=OBU_TRUST_ANCHORS");
    println!("cargo:rerun-if-env-changed=OBU_REQUIRE_SIGNED");
    let list = env::var("OBU_TRUST_ANCHORS").unwrap_or_else(|_| DEFAULT_ANCHORS.to_string());
    let mut s = String::from("/// The trust anchors built in (certificate COER).\n");
    s.push_str("pub static TRUST_ANCHORS: &[&[u8]] = &[\n");
    for path in list.split(':').filter(|p| !p.is_empty()) {
        println!("cargo:rerun-if-changed={path}");
        let bytes = fs::read(path).unwrap_or_else(|e| panic!("trust anchor {path}: {e}"));
        let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
        writeln!(s, "    &[{}],", byte_list(&hex)).unwrap();
    }
    s.push_str("];\n");
    let require = env::var("OBU_REQUIRE_SIGNED").map_or(true, |v| v != "0");
    writeln!(s, "/// Unsigned MAP and TIM are dropped.").unwrap();
    writeln!(s, "pub const REQUIRE_SIGNED: bool = {require};").unwrap();
    s
}

/// `SIGNED_VECTORS`: (name, expect, Ieee1609Dot2Data COER, verifier's Time64) of the
/// independent signed vectors, and their trust anchors `SIGNED_ROOT`, `SIGNED_CA`.
fn signed_vectors(text: &str) -> String {
    let vectors: Vec<Value> = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| serde_json::from_str(l).expect("signed vector line"))
        .collect();
    let first = vectors.first().expect("a signed vector");
    let anchor = |k: &str| byte_list(first["trust_anchors"][k].as_str().expect("anchor"));
    let mut s = format!(
        "/// The signed vectors' root.\npub static SIGNED_ROOT: &[u8] = &[{}];\n\
         /// The signed vectors' CA.\npub static SIGNED_CA: &[u8] = &[{}];\n",
        anchor("root"),
        anchor("ca")
    );
    s.push_str("/// (name, expect, COER, now as Time64) of the independent signed vectors.\n");
    s.push_str("pub static SIGNED_VECTORS: &[(&str, &str, &[u8], u64)] = &[\n");
    for v in &vectors {
        writeln!(
            s,
            "    ({:?}, {:?}, &[{}], {}),",
            v["name"].as_str().expect("name"),
            v["expect"].as_str().expect("expect"),
            byte_list(v["coer"].as_str().expect("coer")),
            v["now"].as_u64().expect("now")
        )
        .unwrap();
    }
    s.push_str("];\n");
    s
}

/// `0x.., 0x..` of a hex string.
fn byte_list(hex: &str) -> String {
    let bytes: Vec<String> = (0..hex.len() / 2)
        .map(|i| format!("0x{}", &hex[2 * i..2 * i + 2]))
        .collect();
    bytes.join(", ")
}

fn vector<'a>(vectors: &'a [Value], name: &str) -> &'a Value {
    vectors
        .iter()
        .find(|v| v["name"] == name)
        .unwrap_or_else(|| panic!("vector {name} missing"))
}

/// A J2735 node offset in centimetres: `node-XY1`..`node-XY6` (the only kinds the drive's
/// vectors use; anything else stops the build rather than being guessed).
fn xy_cm(delta: &Value) -> (f64, f64) {
    let (kind, xy) = delta
        .as_object()
        .and_then(|o| o.iter().next())
        .expect("node delta");
    assert!(
        kind.starts_with("node-XY"),
        "unsupported node kind {kind} in the drive vectors"
    );
    (xy["x"].as_f64().expect("x"), xy["y"].as_f64().expect("y"))
}

/// Cumulative positions (metres east/north of `origin`) of a node-XY list.
fn positions(nodes: &[Value], origin: (f64, f64)) -> Vec<(f64, f64)> {
    let mut at = origin;
    nodes
        .iter()
        .map(|n| {
            let (dx, dy) = xy_cm(&n["delta"]);
            at = (at.0 + dx / 100.0, at.1 + dy / 100.0);
            at
        })
        .collect()
}

/// (station along `line`, signed lateral offset, positive left) of `p`, with the polyline
/// extended straight beyond both ends.
fn project(line: &[(f64, f64)], p: (f64, f64)) -> (f64, f64) {
    let mut best: Option<(f64, f64, f64)> = None;
    let mut start = 0.0;
    let last = line.len() - 2;
    for (i, w) in line.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = dx.hypot(dy);
        let t = ((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (len * len);
        let lo = if i == 0 { f64::NEG_INFINITY } else { 0.0 };
        let hi = if i == last { f64::INFINITY } else { 1.0 };
        let t = t.clamp(lo, hi);
        let q = (a.0 + t * dx, a.1 + t * dy);
        let d = (p.0 - q.0).hypot(p.1 - q.1);
        let lateral = (dx * (p.1 - a.1) - dy * (p.0 - a.0)) / len;
        if best.is_none_or(|(bd, _, _)| d < bd) {
            best = Some((d, start + t * len, lateral));
        }
        start += len;
    }
    let (_, s, lateral) = best.expect("a segment");
    (s, lateral)
}

/// Bytes of a hex string.
fn from_hex(hex: &str) -> Vec<u8> {
    (0..hex.len() / 2)
        .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).expect("hex"))
        .collect()
}

/// The drive's TIM with every region set to the MAP lanes' direction of travel, as
/// `obu/tests/end_to_end.rs` does: `directionality` `reverse` (against the westward node
/// order) and heading slice bits 3 and 4 (67.5 to 112.5 degrees, eastbound) instead of
/// `forward` and `0018` (westbound). `msgCnt` + 1, so that it replaces the committed TIM's
/// zones (same packetID). Everything else as committed. Decoded and re-encoded with the
/// project's codec on the build host.
fn eastbound_tim(uper: &[u8]) -> Vec<u8> {
    let mut tim = TravelerInformation::placeholder();
    decode_message_into(uper, &mut tim).expect("the drive TIM decodes");
    let mut out = vec![0u8; 4096];
    let n = encode_message(&tim, &mut out).expect("re-encodes");
    assert_eq!(&out[..n], uper, "the drive TIM re-encodes byte for byte");
    tim.msg_cnt = j2735::msg::common::MsgCount::new((tim.msg_cnt.get() + 1) % 128).expect("msgCnt");
    let mut regions = 0;
    for frame in tim.data_frames.0.iter_mut() {
        for region in frame.regions.0.iter_mut() {
            assert_eq!(region.directionality, Some(DirectionOfUse::Forward));
            region.directionality = Some(DirectionOfUse::Reverse);
            let slice = region.direction.as_mut().expect("heading slice");
            for i in 0..16 {
                assert_eq!(slice.0.get(i), i == 11 || i == 12, "committed: 247.5-292.5");
                slice.0.set(i, i == 3 || i == 4);
            }
            regions += 1;
        }
    }
    assert_eq!(regions, 2, "one region per data frame");
    let n = encode_message(&tim, &mut out).expect("encodes");
    out.truncate(n);
    out
}

fn work_zone(vectors: &[Value]) -> String {
    let map = &vector(vectors, DRIVE_MAP)["jer"]["value"];
    let tim = &vector(vectors, DRIVE_TIM)["jer"]["value"];
    let ix = &map["intersections"][0];
    let map_id = ix["id"]["id"].as_u64().expect("intersection id");
    let reference = &ix["refPoint"];
    let (lat_e7, lon_e7) = (
        reference["lat"].as_i64().expect("lat"),
        reference["long"].as_i64().expect("long"),
    );
    let lane = ix["laneSet"]
        .as_array()
        .expect("laneSet")
        .iter()
        .find(|l| l["laneID"] == DRIVE_LANE)
        .expect("drive lane");
    // directionalUse bit 0 (first of the BIT STRING, 0x80) = ingressPath: traffic moves
    // toward the stop line, which is the first node, so it drives the nodes in reverse order.
    let directional = lane["laneAttributes"]["directionalUse"]
        .as_str()
        .expect("directionalUse");
    assert_eq!(directional, "80", "the drive lane is an ingress-only lane");
    let lane_nodes = lane["nodeList"]["nodes"].as_array().expect("lane nodes");
    let mut drive = positions(lane_nodes, (0.0, 0.0));
    drive.reverse();

    let region = &tim["dataFrames"][0]["regions"][0];
    let anchor = &region["anchor"];
    assert!(
        anchor["lat"] == reference["lat"] && anchor["long"] == reference["long"],
        "the TIM path is anchored at the MAP's reference point (one plane for both)"
    );
    assert!(
        region["description"]["path"]["scale"].is_null(),
        "no zoom on the TIM path"
    );
    let tim_nodes = region["description"]["path"]["offset"]["xy"]["nodes"]
        .as_array()
        .expect("TIM path nodes");
    // A node-XY path counts from its anchor: the anchor is its first point.
    let mut path = vec![(0.0, 0.0)];
    path.extend(positions(tim_nodes, (0.0, 0.0)));
    // Travelled along the lane (eastbound), the path runs against its node order: the zone
    // starts at its last point and ends at the anchor.
    let (zone_start, zone_start_lat) = project(&drive, *path.last().expect("nodes"));
    let (zone_end, zone_end_lat) = project(&drive, path[0]);
    let nodes_s: Vec<String> = path
        .iter()
        .rev()
        .map(|&p| format!("{:?}", project(&drive, p).0))
        .collect();

    // WGS84 radii of curvature at the reference latitude: degrees per metre north and east
    // (a linear approximation; over the drive's few hundred metres it errs by millimetres).
    let (a, f) = (6_378_137.0_f64, 1.0 / 298.257_223_563);
    let e2 = f * (2.0 - f);
    let phi = (lat_e7 as f64 * 1e-7).to_radians();
    let w = 1.0 - e2 * phi.sin().powi(2);
    let meridian = a * (1.0 - e2) / w.powf(1.5);
    let prime = a / w.sqrt();
    let deg_per_m_north = (1.0 / meridian).to_degrees();
    let deg_per_m_east = (1.0 / (prime * phi.cos())).to_degrees();

    let tim_uper = from_hex(vector(vectors, DRIVE_TIM)["uper"].as_str().expect("uper"));
    let eastbound = eastbound_tim(&tim_uper);

    let mut s = String::new();
    writeln!(
        s,
        "// Generated by build.rs from {DRIVE_MAP} and {DRIVE_TIM} (oracle_vectors.jsonl)."
    )
    .unwrap();
    writeln!(
        s,
        "/// {DRIVE_TIM} made eastbound (`reverse`, 67.5-112.5 degrees, msgCnt + 1): \
         MessageFrame UPER."
    )
    .unwrap();
    let hex: String = eastbound.iter().map(|b| format!("{b:02x}")).collect();
    writeln!(
        s,
        "pub static TIM_EASTBOUND: &[u8] = &[{}];",
        byte_list(&hex)
    )
    .unwrap();
    writeln!(s, "/// Intersection id of the drive's MAP.").unwrap();
    writeln!(s, "pub const MAP_ID: u32 = {map_id};").unwrap();
    writeln!(s, "/// Lane the car drives on.").unwrap();
    writeln!(s, "pub const LANE_ID: u8 = {DRIVE_LANE};").unwrap();
    writeln!(
        s,
        "/// Reference point of the MAP (and anchor of the TIM), degrees."
    )
    .unwrap();
    writeln!(
        s,
        "pub const REF_LAT_DEG: f64 = {:?};",
        lat_e7 as f64 * 1e-7
    )
    .unwrap();
    writeln!(
        s,
        "pub const REF_LON_DEG: f64 = {:?};",
        lon_e7 as f64 * 1e-7
    )
    .unwrap();
    writeln!(
        s,
        "/// Degrees of latitude per metre north at the reference."
    )
    .unwrap();
    writeln!(s, "pub const DEG_PER_M_NORTH: f64 = {deg_per_m_north:?};").unwrap();
    writeln!(
        s,
        "/// Degrees of longitude per metre east at the reference."
    )
    .unwrap();
    writeln!(s, "pub const DEG_PER_M_EAST: f64 = {deg_per_m_east:?};").unwrap();
    writeln!(
        s,
        "/// Lane {DRIVE_LANE}'s centreline in its direction of travel: (east m, north m, \
         station m, course of the segment from this node, degrees)."
    )
    .unwrap();
    writeln!(s, "pub static DRIVE: &[(f64, f64, f64, f64)] = &[").unwrap();
    let mut station = 0.0;
    for (i, &(x, y)) in drive.iter().enumerate() {
        let next = drive.get(i + 1).copied();
        let (dx, dy) = next.map_or_else(
            || (x - drive[i - 1].0, y - drive[i - 1].1),
            |n| (n.0 - x, n.1 - y),
        );
        let course = dx.atan2(dy).to_degrees().rem_euclid(360.0);
        writeln!(s, "    ({x:?}, {y:?}, {station:?}, {course:?}),").unwrap();
        if let Some(n) = next {
            station += (n.0 - x).hypot(n.1 - y);
        }
    }
    writeln!(s, "];").unwrap();
    writeln!(s, "/// Length of the lane, metres.").unwrap();
    writeln!(s, "pub const LANE_LENGTH_M: f64 = {station:?};").unwrap();
    writeln!(
        s,
        "/// Station of the zone start (the TIM path's last node, projected on the lane line; \
         lateral offset {zone_start_lat:.3} m)."
    )
    .unwrap();
    writeln!(s, "pub const ZONE_START_S: f64 = {zone_start:?};").unwrap();
    writeln!(
        s,
        "/// Station of the zone end (the TIM anchor, projected on the lane line extended; \
         lateral offset {zone_end_lat:.3} m)."
    )
    .unwrap();
    writeln!(s, "pub const ZONE_END_S: f64 = {zone_end:?};").unwrap();
    writeln!(
        s,
        "/// Stations of the TIM path's points (nodes and anchor) in the direction of travel."
    )
    .unwrap();
    writeln!(
        s,
        "pub static ZONE_NODES_S: &[f64] = &[{}];",
        nodes_s.join(", ")
    )
    .unwrap();
    s
}
