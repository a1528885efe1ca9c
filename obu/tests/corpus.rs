//! Every MAP and TIM of the shared conformance corpus (`../shared/corpus/frames`) loads
//! into the model without error, and the result passes a geometric sanity check:
//! finite coordinates, lanes and paths longer than 0, vehicle-lane widths within
//! 1.5-6 m unless a reason is recorded. Needs `--features shared-corpus`; fails when
//! `../shared` is missing. Run with `--nocapture` for the counts.
//!
//! The exceptions are listed in [`UNPLACEABLE`] with their reason: frames whose geometry
//! cannot be placed on the earth near its reference. Each must fail with exactly the
//! listed error (the rest of the frame is still stored), so the list cannot go stale.
#![cfg(feature = "shared-corpus")]

mod common;

use std::collections::BTreeMap;

use j2735::frame::peek_message_id;
use j2735::msg::common::NodeListXY;
use j2735::msg::map_data::MapData;
use j2735::msg::traveler_information::TravelerInformation;
use obu::ingest::map::models;
use obu::ingest::{Ingest, IngestError};
use obu::lane::{LaneKind, LaneModel};
use obu::zone::RegionShape;
use obu::{Instant, Obu};

/// Frames with parts the core rejects, the error `on_map`/`on_tim` returns, and why.
const UNPLACEABLE: [(&str, IngestError, &str); 4] = [
    ("MAP_061", IngestError::InvalidValue, "random-valued codec fixture: node-LatLon nodes thousands of km from the refPoint, computed lanes naming absent lanes"),
    ("TIM_220", IngestError::InvalidValue, "random-valued codec fixture: node-LL offsets (times 2^scale) 160 km and more from the anchor"),
    ("TIM_224", IngestError::InvalidValue, "random-valued sender test: a node-LatLon 16 000 km from the region's anchor"),
    ("TIM_226", IngestError::InvalidValue, "a path whose node-LatLon nodes alternate between two places 440 km apart"),
];

#[derive(Default, Debug)]
struct Tally {
    maps: u32,
    maps_loaded: u32,
    models: u32,
    lanes: u32,
    nodes: u32,
    lanes_thinned: u32,
    tims: u32,
    tims_loaded: u32,
    /// Frames of [`UNPLACEABLE`] that failed as listed.
    unplaceable: u32,
    zones: u32,
    regions_path: u32,
    regions_circle: u32,
    path_nodes: u32,
    paths_thinned: u32,
    truncated: u32,
    width_ok: u32,
    /// Lanes with a node width outside 1.5-6 m, by reason.
    width_reasons: BTreeMap<String, u32>,
    failures: Vec<String>,
}

#[test]
fn corpus_loads_and_is_sane() {
    let tally = common::big_stack(run);
    println!("corpus: {tally:#?}");
    assert!(tally.failures.is_empty(), "{:#?}", tally.failures);
    assert_eq!(tally.unplaceable as usize, UNPLACEABLE.len());
    let loaded = tally.maps_loaded + tally.tims_loaded + tally.unplaceable;
    assert_eq!(loaded, tally.maps + tally.tims);
    assert!(
        tally.maps >= 40 && tally.tims >= 143,
        "{} MAP, {} TIM",
        tally.maps,
        tally.tims
    );
}

fn run() -> Tally {
    let mut t = Tally::default();
    let mut map = Box::new(<MapData as j2735::uper::Placeholder>::placeholder());
    let mut tim = Box::new(<TravelerInformation as j2735::uper::Placeholder>::placeholder());
    for (name, bytes) in common::corpus_frames() {
        match peek_message_id(&bytes) {
            Ok(18) => {
                t.maps += 1;
                match j2735::frame::decode_message_into(&bytes, &mut *map) {
                    Ok(()) => load_map(&name, &map, &mut t),
                    Err(e) => t.failures.push(format!("{name}: decode {e:?}")),
                }
            }
            Ok(31) => {
                t.tims += 1;
                match j2735::frame::decode_message_into(&bytes, &mut *tim) {
                    Ok(()) => load_tim(&name, &tim, &mut t),
                    Err(e) => t.failures.push(format!("{name}: decode {e:?}")),
                }
            }
            _ => {}
        }
    }
    t
}

/// Checks the outcome against [`UNPLACEABLE`]; true when the frame loaded.
fn outcome(name: &str, r: Result<Ingest, IngestError>, t: &mut Tally) -> bool {
    let listed = UNPLACEABLE.iter().find(|(n, _, _)| name.starts_with(n));
    match (r, listed) {
        (Ok(r), None) => {
            t.truncated += r.truncated as u32;
            t.lanes_thinned +=
                (r.message == obu::ingest::MessageKind::Map) as u32 * r.thinned as u32;
            t.paths_thinned +=
                (r.message == obu::ingest::MessageKind::Tim) as u32 * r.thinned as u32;
            true
        }
        (Err(e), Some((_, want, _))) if e == *want => {
            t.unplaceable += 1;
            false
        }
        (r, _) => {
            t.failures
                .push(format!("{name}: {r:?}, listed: {listed:?}"));
            false
        }
    }
}

fn load_map(name: &str, map: &MapData, t: &mut Tally) {
    let mut obu = Box::new(Obu::default());
    if !outcome(name, obu.on_map(Instant::ZERO, map), t) {
        return;
    }
    t.maps_loaded += 1;
    for src in models(map) {
        let Some(model) = obu.maps().get(src.id) else {
            return t
                .failures
                .push(format!("{name}: model {} not stored", src.id));
        };
        t.models += 1;
        check_model(name, model, &src, t);
    }
}

fn check_model(
    name: &str,
    model: &LaneModel,
    src: &obu::ingest::map::ModelSource<'_>,
    t: &mut Tally,
) {
    for lane in model.lanes() {
        t.lanes += 1;
        t.nodes += lane.node_count() as u32;
        let finite = lane.nodes().all(|(p, w)| p.is_finite() && w.is_finite());
        if !(finite && lane.length() > 0.0) {
            t.failures.push(format!(
                "{name}: lane {} not finite or of length 0",
                lane.id
            ));
        }
        let out = lane.nodes().any(|(_, w)| !(1.5..=6.0).contains(&w));
        if !out {
            t.width_ok += 1;
            continue;
        }
        let gl = src.lanes.iter().find(|l| l.lane_id.get() == lane.id.0);
        let reason = width_reason(lane.kind, gl, src.lane_width_cm);
        match reason {
            Some(r) => *t.width_reasons.entry(r).or_default() += 1,
            None => t
                .failures
                .push(format!("{name}: lane {} width out of 1.5-6 m", lane.id)),
        }
    }
}

/// Why a lane's width may lie outside 1.5-6 m.
fn width_reason(
    kind: LaneKind,
    gl: Option<&j2735::msg::map_data::GenericLane>,
    lane_width_cm: Option<u16>,
) -> Option<String> {
    if kind != LaneKind::Vehicle {
        return Some(format!("not a vehicle lane ({kind:?})"));
    }
    let tapered = gl.is_some_and(|gl| match &gl.node_list {
        NodeListXY::Nodes(n) => n
            .iter()
            .any(|n| n.attributes.as_ref().is_some_and(|a| a.d_width.is_some())),
        _ => false,
    });
    if tapered {
        return Some("dWidth taper given by the MAP".into());
    }
    lane_width_cm.map(|w| format!("laneWidth {w} cm given by the MAP"))
}

fn load_tim(name: &str, tim: &TravelerInformation, t: &mut Tally) {
    let mut obu = Box::new(Obu::default());
    if !outcome(name, obu.on_tim(Instant::ZERO, tim), t) {
        return;
    }
    t.tims_loaded += 1;
    for zone in obu.zones().iter() {
        t.zones += 1;
        for r in zone.regions.iter() {
            match r.shape {
                RegionShape::Circle { radius_m } => {
                    t.regions_circle += 1;
                    if !radius_m.is_finite() {
                        t.failures.push(format!("{name}: circle radius {radius_m}"));
                    }
                }
                RegionShape::Path(_) => {
                    t.regions_path += 1;
                    t.path_nodes += r.nodes().len() as u32;
                    let finite = r.nodes().iter().all(|p| p.is_finite());
                    if !(finite && r.length() > 0.0) {
                        t.failures
                            .push(format!("{name}: path not finite or of length 0"));
                    }
                }
            }
        }
    }
}
