//! The MAP and TIM the roadside builds, checked by the independent oracle (pycrate,
//! `../shared/oracle`): the oracle decodes our bytes to the same JER we write, and encodes
//! our JER to the same bytes. Needs feature `shared-oracle` (and Python).
#![cfg(feature = "shared-oracle")]

use geodesy::LatLon;
use j2735::msg::message_frame::MessageFrame;
use roadside::clock::Utc;
use roadside::ellipse::ErrorEllipse;
use roadside::messages::{self, SignSpeed, WorkZone, DURATION_INDEFINITE};
use roadside::road::Road;

/// Runs the oracle (`oracle/j2735_oracle.py ARGS`) on `input`; its standard output.
fn oracle(args: &[&str], input: &str) -> String {
    let script = test_support::shared::shared_dir().join("oracle/j2735_oracle.py");
    test_support::oracle::run_script(&script, args, input)
}

/// A divided road heading north-east: three lanes forward and two back, 2.5 km, 3.5 m
/// lanes, 70 km/h.
fn road() -> Road {
    let reference = LatLon::from_degrees(44.977_8, -93.265_0).unwrap();
    Road::straight(reference, 45.0, 2500.0, (3, 2), 3.5, 70.0)
}

/// Lane 3 closed from 1200 to 1450 m, 40 km/h, from `start` on.
fn zone(start: Utc) -> WorkZone {
    WorkZone {
        closed_lanes: vec![3],
        start_m: 1200.0,
        end_m: 1450.0,
        speed_limit: Some(SignSpeed {
            value: 40,
            mph: false,
        }),
        packet_id: *b"ORACLE-01",
        msg_cnt: 1,
        start,
        duration_min: DURATION_INDEFINITE,
    }
}

fn frames() -> Vec<(&'static str, Box<MessageFrame>)> {
    let road = road();
    let start = Utc::from_unix_ms(1_795_341_600_000);
    let zone = zone(start);
    let mut two_lanes = zone.clone();
    two_lanes.closed_lanes = vec![3, 2];
    two_lanes.speed_limit = Some(SignSpeed {
        value: 25,
        mph: true,
    });
    two_lanes.msg_cnt = 127;
    vec![
        (
            "MAP with a zone",
            messages::build_map(&road, 1501, 1, Some(&zone)).unwrap(),
        ),
        (
            "MAP without",
            messages::build_map(&road, 1501, 2, None).unwrap(),
        ),
        (
            "TIM lane 3, 40 km/h",
            messages::build_tim(&road, &zone).unwrap(),
        ),
        (
            "TIM lanes 3 and 2, 25 mph",
            messages::build_tim(&road, &two_lanes).unwrap(),
        ),
        (
            "PSM walking worker",
            messages::build_psm(&walking_worker(), start, 5).unwrap(),
        ),
        (
            "PSM standing worker",
            messages::build_psm(&standing_worker(), start, 127).unwrap(),
        ),
    ]
}

/// A worker walking east at 1.5 m/s, known within 0.5 m along 120 degrees from north and
/// 0.15 m across, with three crumbs behind.
fn walking_worker() -> messages::Worker {
    let at = LatLon::from_degrees(44.977_8, -93.265_0).unwrap();
    let back = |s: f64| LatLon::from_degrees(44.977_8, -93.265_0 - 1.5 * s / 78_800.0).unwrap();
    messages::Worker {
        id: [0xde, 0xad, 0x00, 0x01],
        position: at,
        accuracy: ErrorEllipse {
            semi_major_m: 0.5,
            semi_minor_m: 0.15,
            orientation_deg: 120.0,
        },
        speed_mps: 1.5,
        heading_deg: Some(90.0),
        history: vec![(back(1.0), 1.0), (back(2.0), 2.0), (back(3.0), 3.0)],
    }
}

/// A worker standing still (no heading, no history).
fn standing_worker() -> messages::Worker {
    messages::Worker {
        id: [0, 0, 0, 7],
        speed_mps: 0.0,
        heading_deg: None,
        history: Vec::new(),
        ..walking_worker()
    }
}

#[test]
fn the_oracle_reads_the_worker_psm_fields_in_j2735_units() {
    let start = Utc::from_unix_ms(1_795_341_600_000 + 12_345);
    let frame = messages::build_psm(&walking_worker(), start, 5).unwrap();
    let hex = j2735::hex::Hex(&messages::encode(&frame).unwrap()).to_string();
    let decoded = oracle(&["decode", "-"], &format!("{hex}\n"));
    let jer: serde_json::Value = serde_json::from_str(decoded.trim()).unwrap();
    assert_eq!(jer["messageId"], 32, "{jer}");
    let psm = &jer["value"];
    assert_eq!(psm["basicType"], "aPUBLICSAFETYWORKER", "{psm}");
    // 12.345 s into the minute, in milliseconds.
    assert_eq!(psm["secMark"], 12_345, "{psm}");
    assert_eq!(psm["msgCnt"], 5, "{psm}");
    assert_eq!(
        psm["id"].as_str().map(str::to_ascii_uppercase),
        Some("DEAD0001".into())
    );
    // 44.9778 N, 93.2650 W in 1e-7 degrees.
    assert_eq!(psm["position"]["lat"], 449_778_000, "{psm}");
    assert_eq!(psm["position"]["long"], -932_650_000, "{psm}");
    // 0.5 m and 0.15 m in 0.05 m units, 120 degrees in 360/65535 degree units; 1.5 m/s in
    // 0.02 m/s; 90 degrees in 0.0125 degrees.
    assert_eq!(psm["accuracy"]["semiMajor"], 10, "{psm}");
    assert_eq!(psm["accuracy"]["semiMinor"], 3, "{psm}");
    assert_eq!(psm["accuracy"]["orientation"], 21_845, "{psm}");
    assert_eq!(psm["speed"], 75, "{psm}");
    assert_eq!(psm["heading"], 7_200, "{psm}");
    let crumbs = psm["pathHistory"]["crumbData"].as_array().unwrap();
    assert_eq!(crumbs.len(), 3, "{psm}");
    // One second back, 1.5 m west: 1.5 / 78 800 degrees of longitude, in 1e-7 degrees.
    assert_eq!(crumbs[0]["timeOffset"], 100, "{psm}");
    assert_eq!(crumbs[0]["latOffset"], 0, "{psm}");
    assert_eq!(crumbs[0]["lonOffset"], -190, "{psm}");
    assert_eq!(crumbs[2]["timeOffset"], 300, "{psm}");
    // BIT STRING (6 bits) 010000: workingOnRoad only, as the oracle writes it (hex).
    assert_eq!(
        psm["activityType"].as_str().map(str::to_ascii_lowercase),
        Some("40".into()),
        "{psm}"
    );
}

#[test]
fn the_oracle_reads_our_bytes_as_our_jer_and_writes_our_bytes_from_it() {
    for (name, frame) in frames() {
        let hex = j2735::hex::Hex(&messages::encode(&frame).unwrap()).to_string();
        let ours: serde_json::Value =
            serde_json::from_str(&j2735::jer::to_string(&*frame)).unwrap();
        let decoded = oracle(&["decode", "-"], &format!("{hex}\n"));
        let theirs: serde_json::Value = serde_json::from_str(decoded.trim()).unwrap();
        if let Err(e) = j2735::jer::equivalent(&ours, &theirs) {
            panic!("{name}: the oracle's JER of our bytes differs at {e}");
        }
        let encoded = oracle(&["encode", "-"], &ours.to_string());
        assert_eq!(encoded.trim(), hex, "{name}: the oracle's bytes of our JER");
    }
}
