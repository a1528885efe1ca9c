//! The roadside inputs (`roadside::geojson`): a lane map, a WZDx 4.2 feed and cone lists
//! from the fixtures in `hil-sim/tests/data/` (shared with the scenarios), the MAP and TIM
//! built from them, and the errors of malformed variants.

use j2735::msg::message_frame::MessageFrame;
use roadside::broadcast::Prng;
use roadside::geojson::{
    load_cones, load_lane_map, rfc3339_unix_ms, work_zones_from_wzdx, InputError, Problem,
};
use roadside::messages::{self, SignSpeed};
use roadside::road::Road;
use serde_json::{json, Value};

const LANE_MAP: &str = include_str!("../../tests/data/lane_map_3lanes.geojson");
const WZDX: &str = include_str!("../../tests/data/wzdx_right_lane_closed.geojson");
const CONES_JSON: &str = include_str!("../../tests/data/cones.json");
const CONES_CSV: &str = include_str!("../../tests/data/cones.csv");

/// Metres per degree of longitude at 39.75 N on WGS84.
const M_PER_DEG_LON: f64 = 85_705.3;
/// 2026-11-22T10:00:00Z.
const ZONE_START_MS: u64 = 1_795_341_600_000;

fn road() -> Road {
    load_lane_map(LANE_MAP).expect("the fixture lane map loads")
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// Decodes UPER bytes (the codec checks every constraint).
fn decode(bytes: &[u8]) -> MessageFrame {
    j2735::uper::decode(bytes).expect("our bytes decode")
}

// --- lane map -------------------------------------------------------------------------

#[test]
fn lane_map_has_widths_directions_and_local_geometry() {
    let road = road();
    assert_eq!(
        (road.reference.lat_e7(), road.reference.lon_e7()),
        (397_500_000, -1_049_950_000)
    );
    let ids: Vec<u8> = road.lanes.iter().map(|l| l.id).collect();
    assert_eq!(ids, [1, 2, 3]);
    let widths: Vec<f64> = road.lanes.iter().map(|l| l.width_m).collect();
    assert_eq!(widths, [3.6, 3.4, 3.6]);
    // 45 mph and 70 km/h.
    assert!(close(road.lanes[0].speed_limit_kmh, 72.42, 0.01));
    assert!(close(road.lanes[2].speed_limit_kmh, 70.0, 1e-9));

    // Lane 1 starts at the reference and runs east 0.007 degrees, through its middle node.
    let l1 = road.lane(1).unwrap();
    assert_eq!(l1.centre.len(), 3);
    assert!(close(l1.centre[0][0], 0.0, 0.02) && close(l1.centre[0][1], 0.0, 0.02));
    assert!(close(l1.length_m(), 0.007 * M_PER_DEG_LON, 0.5));
    assert!(close(l1.at(10.0).unwrap().bearing_deg, 90.0, 0.1));
    // Lane 2 lies 3.5 m (half of 3.6 + 3.4) south of lane 1.
    let l2 = road.lane(2).unwrap();
    assert!(close(l2.centre[0][1], -3.5, 0.03), "{:?}", l2.centre[0]);
    // Lane 3 is drawn west to east but travels west: its centreline starts in the east.
    let l3 = road.lane(3).unwrap();
    assert_eq!(l3.centre.len(), 2);
    assert!(close(l3.centre[0][0], 0.007 * M_PER_DEG_LON, 0.5));
    assert!(close(l3.centre[1][0], 0.0, 0.02));
    assert!(close(l3.at(10.0).unwrap().bearing_deg, 270.0, 0.1));
    assert!(close(l3.centre[0][1], 7.77, 0.03));
}

#[test]
fn reference_defaults_to_the_first_coordinate_rounded() {
    let text = json!({
        "type": "FeatureCollection",
        "features": [lane_feature(7, [[-104.99500004, 39.75000006], [-104.994, 39.75]])],
    });
    let road = load_lane_map(&text.to_string()).unwrap();
    assert_eq!(
        (road.reference.lat_e7(), road.reference.lon_e7()),
        (397_500_001, -1_049_950_000)
    );
    assert_eq!(road.lanes[0].id, 7);
}

#[test]
fn map_from_the_lane_map_encodes_and_decodes() {
    let road = road();
    let map = messages::build_map(&road, 1501, 1, None).expect("MAP builds");
    let bytes = messages::encode(&map).expect("MAP encodes");
    assert_eq!(&bytes[..2], &[0x00, 0x12]);
    assert_eq!(decode(&bytes), *map);
}

// --- WZDx -------------------------------------------------------------------------------

#[test]
fn wzdx_zone_closes_the_right_eastbound_lane() {
    let road = road();
    let zones = work_zones_from_wzdx(&road, WZDX).expect("the fixture feed reads");
    // The detour and the work zone on another road are skipped.
    assert_eq!(zones.len(), 1, "{zones:?}");
    let zone = &zones[0];
    assert_eq!(zone.feature_index, 0);
    assert_eq!(zone.event_id.as_deref(), Some("bench-wz-eb-right-lane"));
    assert_eq!(zone.road_names, ["Bench Road"]);
    assert_eq!(zone.direction.as_deref(), Some("eastbound"));
    // WZDx order 3 (order 1 is the left shoulder) is the right travel lane: our lane 2.
    assert_eq!(zone.closed_lanes, [2]);
    assert!(!zone.speed_only);
    // The event runs from 0.002 to 0.005 degrees east of the lane start.
    assert!(
        close(zone.start_m, 0.002 * M_PER_DEG_LON, 0.5),
        "{}",
        zone.start_m
    );
    assert!(
        close(zone.end_m, 0.005 * M_PER_DEG_LON, 0.5),
        "{}",
        zone.end_m
    );
    assert_eq!(
        zone.speed_limit,
        Some(SignSpeed {
            value: 40,
            mph: false
        })
    );
    assert_eq!(zone.start_unix_ms, ZONE_START_MS);
    assert_eq!(zone.end_unix_ms, ZONE_START_MS + (7 * 24 + 8) * 3_600_000);
    assert_eq!(zone.duration_min(), (7 * 24 + 8) * 60);
}

#[test]
fn wzdx_zone_gives_a_tim_and_a_map() {
    let road = road();
    let zone = &work_zones_from_wzdx(&road, WZDX).unwrap()[0];
    let packet_id = zone.packet_id();
    let wz = zone.to_work_zone(packet_id, 3);
    assert_eq!((wz.closed_lanes.clone(), wz.msg_cnt), (vec![2], 3));
    assert_eq!(
        (wz.start.year, wz.start.month, wz.start.day),
        (2026, 11, 22)
    );
    let tim = messages::build_tim(&road, &wz).expect("TIM builds");
    let bytes = messages::encode(&tim).expect("TIM encodes");
    assert_eq!(&bytes[..2], &[0x00, 0x1f]);
    assert_eq!(decode(&bytes), *tim);
    let map = messages::build_map(&road, 1501, 2, Some(&wz)).expect("MAP with the zone builds");
    messages::encode(&map).expect("MAP with the zone encodes");
}

/// A feed with one work-zone event along `coords` ([lon, lat]) with these `lanes`.
fn feed(coords: Value, lanes: Value, speed: Option<f64>) -> String {
    let mut props = json!({
        "core_details": {
            "event_type": "work-zone",
            "data_source_id": "t",
            "road_names": ["Bench Road"],
            "direction": "eastbound",
        },
        "start_date": "2026-11-22T10:00:00Z",
        "end_date": "2026-11-22T12:00:00Z",
        "vehicle_impact": "some-lanes-closed",
        "lanes": lanes,
    });
    if let Some(kph) = speed {
        props["reduced_speed_limit_kph"] = json!(kph);
    }
    json!({
        "type": "FeatureCollection",
        "features": [{"type": "Feature", "properties": props,
                      "geometry": {"type": "LineString", "coordinates": coords}}],
    })
    .to_string()
}

fn general(statuses: &[&str]) -> Value {
    let lanes: Vec<Value> = statuses
        .iter()
        .enumerate()
        .map(|(k, s)| json!({"order": k + 1, "type": "general", "status": s}))
        .collect();
    Value::Array(lanes)
}

const EB_PATH_ON_LANE_2: [[f64; 2]; 2] = [[-104.9930, 39.7499685], [-104.9900, 39.7499685]];

#[test]
fn speed_only_zone_takes_the_nearest_lane() {
    let road = road();
    let text = feed(
        json!(EB_PATH_ON_LANE_2),
        general(&["open", "open"]),
        Some(64.4),
    );
    let zones = work_zones_from_wzdx(&road, &text).unwrap();
    assert_eq!(zones.len(), 1);
    assert!(zones[0].speed_only);
    assert_eq!(zones[0].closed_lanes, [2]);
    assert_eq!(zones[0].speed_limit.map(|s| s.value), Some(64));
    // Without a reduced limit the event changes nothing and is skipped.
    let text = feed(json!(EB_PATH_ON_LANE_2), general(&["open", "open"]), None);
    assert!(work_zones_from_wzdx(&road, &text).unwrap().is_empty());
}

#[test]
fn westbound_event_maps_to_the_westbound_lane() {
    let road = road();
    // Drawn east to west along lane 3: only lane 3 runs this way.
    let path = json!([[-104.9900, 39.7500700], [-104.9930, 39.7500700]]);
    let zones = work_zones_from_wzdx(&road, &feed(path, general(&["closed"]), None)).unwrap();
    assert_eq!(zones[0].closed_lanes, [3]);
    // Lane 3's stations run from its east end.
    assert!(close(zones[0].start_m, 0.002 * M_PER_DEG_LON, 0.5));
    assert!(close(zones[0].end_m, 0.005 * M_PER_DEG_LON, 0.5));
}

#[test]
fn both_lanes_closed_keep_left_to_right_order() {
    let road = road();
    let text = feed(
        json!(EB_PATH_ON_LANE_2),
        general(&["closed", "closed"]),
        None,
    );
    let zones = work_zones_from_wzdx(&road, &text).unwrap();
    assert_eq!(zones[0].closed_lanes, [1, 2]);
}

/// The feature error of a result: its index, problem and message.
fn feature_error(result: Result<impl std::fmt::Debug, InputError>) -> (usize, Problem, String) {
    let err = result.expect_err("an error");
    let text = err.to_string();
    match err {
        InputError::Feature { index, problem } => (index, problem, text),
        other => panic!("expected a feature error, got {other:?}"),
    }
}

#[test]
fn wzdx_errors_name_the_event_and_the_fix() {
    let road = road();
    let (index, problem, text) = feature_error(work_zones_from_wzdx(
        &road,
        &feed(
            json!(EB_PATH_ON_LANE_2),
            general(&["open", "open", "closed"]),
            None,
        ),
    ));
    assert_eq!(index, 0);
    assert_eq!(
        problem,
        Problem::LaneCountMismatch {
            wzdx_lanes: 3,
            map_lanes: vec![1, 2]
        }
    );
    assert!(
        text.contains("features[0]") && text.contains("3 travel lanes"),
        "{text}"
    );

    let bad_status = general(&["open", "shut"]);
    let (_, _, text) = feature_error(work_zones_from_wzdx(
        &road,
        &feed(json!(EB_PATH_ON_LANE_2), bad_status, None),
    ));
    assert!(
        text.contains("lanes[1].status") && text.contains("closed"),
        "{text}"
    );

    let mut doc: Value = serde_json::from_str(&feed(
        json!(EB_PATH_ON_LANE_2),
        general(&["open", "closed"]),
        None,
    ))
    .unwrap();
    doc["features"][0]["properties"]["end_date"] = json!("2026-11-22T09:00:00Z");
    let (_, _, text) = feature_error(work_zones_from_wzdx(&road, &doc.to_string()));
    assert!(
        text.contains("end_date") && text.contains("after start_date"),
        "{text}"
    );
    doc["features"][0]["properties"]["end_date"] = json!("22/11/2026 12:00");
    let (_, _, text) = feature_error(work_zones_from_wzdx(&road, &doc.to_string()));
    assert!(text.contains("RFC 3339"), "{text}");
    doc["features"][0]["properties"]
        .as_object_mut()
        .unwrap()
        .remove("core_details");
    let (_, problem, _) = feature_error(work_zones_from_wzdx(&road, &doc.to_string()));
    assert_eq!(
        problem,
        Problem::Missing {
            what: "properties.core_details".into()
        }
    );

    // Drawn against the travel direction over lanes 1-2, it only runs with lane 3, which
    // the event does not list.
    let reversed = json!([[-104.9900, 39.7499843], [-104.9930, 39.7499843]]);
    let (_, problem, _) = feature_error(work_zones_from_wzdx(
        &road,
        &feed(reversed, general(&["open", "closed"]), None),
    ));
    assert!(
        matches!(problem, Problem::LaneCountMismatch { ref map_lanes, .. } if map_lanes == &[3])
    );

    let point =
        feed(json!([-104.99, 39.75]), general(&["closed"]), None).replace("LineString", "Point");
    let (_, _, text) = feature_error(work_zones_from_wzdx(&road, &point));
    assert!(
        text.contains("geometry.type") && text.contains("MultiPoint"),
        "{text}"
    );
}

#[test]
fn rfc3339_examples_of_the_wzdx_spec() {
    assert_eq!(
        rfc3339_unix_ms("2016-11-03T19:37:00Z"),
        Some(1_478_201_820_000)
    );
    assert_eq!(
        rfc3339_unix_ms("2026-11-22T03:00:00-07:00"),
        Some(ZONE_START_MS)
    );
}

// --- lane map errors ---------------------------------------------------------------------

fn lane_feature(id: u32, coords: [[f64; 2]; 2]) -> Value {
    json!({
        "type": "Feature",
        "properties": {"lane_id": id, "width_m": 3.5, "direction": "forward", "speed_limit_kph": 50},
        "geometry": {"type": "LineString", "coordinates": coords},
    })
}

/// The fixture with feature `index` changed by `edit`.
fn edited(index: usize, edit: impl FnOnce(&mut Value)) -> String {
    let mut doc: Value = serde_json::from_str(LANE_MAP).unwrap();
    edit(&mut doc["features"][index]);
    doc.to_string()
}

#[test]
fn lane_map_errors_name_the_feature_and_the_problem() {
    let cases: Vec<(String, usize, &str)> = vec![
        (
            edited(1, |f| {
                f["geometry"] = json!({"type": "Point", "coordinates": [-104.99, 39.75]})
            }),
            1,
            "geometry.type",
        ),
        (
            edited(2, |f| {
                f["geometry"]["coordinates"] = json!([[-104.99, 39.75]])
            }),
            2,
            "at least 2 distinct points",
        ),
        (
            edited(2, |f| {
                f["geometry"]["coordinates"] = json!([[-104.99, 39.75], [-104.99, 39.75]])
            }),
            2,
            "(1 distinct)",
        ),
        (
            edited(2, |f| f["properties"]["lane_id"] = json!(1)),
            2,
            "already used by features[0]",
        ),
        (
            edited(1, |f| f["properties"]["width_m"] = json!(7.5)),
            1,
            "1.5 to 6",
        ),
        (
            edited(0, |f| f["properties"]["lane_id"] = json!(256)),
            0,
            "1 to 255",
        ),
        (
            edited(0, |f| {
                f["properties"].as_object_mut().unwrap().remove("direction");
            }),
            0,
            "`properties.direction` is missing",
        ),
        (
            edited(0, |f| f["properties"]["direction"] = json!("east")),
            0,
            "\"reverse\"",
        ),
        (
            edited(2, |f| f["properties"]["speed_limit_mph"] = json!(45)),
            2,
            "keep only one",
        ),
        (
            edited(0, |f| {
                f["properties"]
                    .as_object_mut()
                    .unwrap()
                    .remove("speed_limit_mph");
            }),
            0,
            "speed_limit_kph",
        ),
        (
            edited(1, |f| {
                f["geometry"]["coordinates"][1] = json!([39.75, -104.99])
            }),
            1,
            "look swapped",
        ),
        (
            edited(1, |f| {
                f["geometry"]["coordinates"][1] = json!([-104.99, 41.75])
            }),
            1,
            "coordinates[1]` lies 222",
        ),
        (
            edited(1, |f| f["properties"] = json!(null)),
            1,
            "`properties` is missing",
        ),
        (
            edited(1, |f| f["properties"]["width_m"] = json!("3.5")),
            1,
            "must be a number",
        ),
    ];
    for (text, index, needle) in cases {
        let (got, _, message) = feature_error(load_lane_map(&text));
        assert_eq!(got, index, "{message}");
        assert!(message.contains(needle), "{needle:?} not in {message:?}");
    }
}

#[test]
fn lane_map_document_errors() {
    let err = load_lane_map("{\"type\": \"Feature\"}").unwrap_err();
    assert!(matches!(err, InputError::Document(_)));
    assert!(err.to_string().contains("\"FeatureCollection\""), "{err}");
    let err = load_lane_map("{\"type\": \"FeatureCollection\", \"features\": []}").unwrap_err();
    assert_eq!(
        err,
        InputError::Document(Problem::Empty { what: "features" })
    );
    let err = load_lane_map("{\"type\": \"FeatureCollection\",\n \"features\": [}").unwrap_err();
    assert!(matches!(err, InputError::Json { line: 2, .. }), "{err}");
    let err = load_lane_map(&LANE_MAP.replace("[-104.995, 39.75]", "[-104.995]")).unwrap_err();
    assert!(
        err.to_string().starts_with("document: `reference`"),
        "{err}"
    );
    for text in ["", "[]", "null", "42", "{\"type\": 1}", "\u{feff}"] {
        assert!(load_lane_map(text).is_err(), "{text:?}");
    }
}

// --- cones -------------------------------------------------------------------------------

#[test]
fn cone_lists_in_both_formats_give_the_same_points_on_lane_2() {
    let road = road();
    let from_json = load_cones(&road, CONES_JSON).unwrap();
    let from_csv = load_cones(&road, CONES_CSV).unwrap();
    assert_eq!(from_json.len(), 4);
    assert_eq!(from_json, from_csv);
    let l2 = road.lane(2).unwrap();
    let east: Vec<f64> = from_json.iter().map(|p| p[0]).collect();
    assert!(close(east[0], 0.002 * M_PER_DEG_LON, 0.5));
    assert!(east.windows(2).all(|w| w[1] > w[0]));
    for p in &from_json {
        // On lane 2's centreline (the third cone 17 cm to its left).
        let y = p[1] - l2.centre[0][1];
        assert!(y.abs() < 0.2, "{p:?}");
    }
    // A header in the other order, CRLF line ends, no cones at all.
    let swapped = "lon,lat\r\n-104.9930000,39.7499685\r\n";
    assert_eq!(load_cones(&road, swapped).unwrap(), from_json[..1]);
    assert!(load_cones(&road, "# nothing yet\n").unwrap().is_empty());
    assert!(load_cones(&road, "[]").unwrap().is_empty());
}

#[test]
fn cone_errors_name_the_line_or_item() {
    let road = road();
    let err = load_cones(&road, "lat,lon\n39.7499685,-104.993\n39.7499685;-104.992\n").unwrap_err();
    assert!(matches!(err, InputError::Line { line: 3, .. }), "{err}");
    assert!(err.to_string().contains("lat,lon"), "{err}");
    let err = load_cones(&road, "39.7499685,-104.993\nlat,lon\n").unwrap_err();
    assert!(matches!(err, InputError::Line { line: 2, .. }), "{err}");
    let err = load_cones(&road, "-104.993,39.7499685\n").unwrap_err();
    assert!(err.to_string().contains("look swapped"), "{err}");
    let err = load_cones(&road, "39.76,-104.993\n").unwrap_err();
    assert!(
        matches!(err.problem(), Some(Problem::TooFar { .. })),
        "{err}"
    );
    let err = load_cones(&road, "NaN,-104.993\n").unwrap_err();
    assert!(matches!(err, InputError::Line { line: 1, .. }), "{err}");
    let err = load_cones(
        &road,
        "[{\"lat\": 39.7499685, \"lon\": -104.993}, {\"lat\": 39.75}]",
    )
    .unwrap_err();
    assert_eq!(
        err,
        InputError::Item {
            index: 1,
            problem: Problem::Missing { what: "lon".into() }
        }
    );
    let err = load_cones(&road, "{\"lat\": 39.75, \"lon\": -104.99}").unwrap_err();
    assert!(err.to_string().contains("an array"), "{err}");
}

#[test]
fn mutated_inputs_never_panic() {
    let road = road();
    let mut rng = Prng::new(2026);
    let alphabet = b" \"[]{},:.-+eE0123456789#\nabcdefghijklmnopqrstuvwxyzNaN";
    for text in [LANE_MAP, WZDX, CONES_JSON, CONES_CSV] {
        for _ in 0..400 {
            let mut bytes = text.as_bytes().to_vec();
            for _ in 0..=rng.below(4) {
                let at = rng.below(bytes.len() as u64) as usize;
                match rng.below(3) {
                    0 => bytes[at] = alphabet[rng.below(alphabet.len() as u64) as usize],
                    1 => {
                        bytes.remove(at);
                    }
                    _ => bytes.truncate(at),
                }
                if bytes.is_empty() {
                    break;
                }
            }
            // The fixtures and the alphabet are ASCII, so this is still UTF-8.
            let mutated = String::from_utf8(bytes).unwrap();
            let _ = load_lane_map(&mutated);
            let _ = work_zones_from_wzdx(&road, &mutated);
            let _ = load_cones(&road, &mutated);
        }
    }
}
