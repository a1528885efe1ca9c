//! The MAP and TIM the roadside builds, checked by the independent oracle (pycrate,
//! `../shared/oracle`): the oracle decodes our bytes to the same JER we write, and encodes
//! our JER to the same bytes. Needs feature `shared-oracle` (and Python).
#![cfg(feature = "shared-oracle")]

use geodesy::LatLon;
use j2735::message_frame::MessageFrame;
use roadside::clock::Utc;
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
    ]
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
