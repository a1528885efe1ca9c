//! Unit tests of the private helpers.

use super::wzdx_match::sample_path;
use super::{rfc3339_unix_ms, WzdxZone};

#[test]
fn rfc3339_forms() {
    assert_eq!(rfc3339_unix_ms("1970-01-01T00:00:00Z"), Some(0));
    // 2025-11-22T04:16:01.500Z, the instant of clock.rs' test.
    assert_eq!(
        rfc3339_unix_ms("2025-11-22T04:16:01.5Z"),
        Some(1_763_784_961_500)
    );
    assert_eq!(
        rfc3339_unix_ms("2025-11-21t21:16:01.500123-07:00"),
        Some(1_763_784_961_500)
    );
    assert_eq!(
        rfc3339_unix_ms("2025-11-22 09:46:01.5+05:30"),
        Some(1_763_784_961_500)
    );
    assert!(rfc3339_unix_ms("2024-02-29T00:00:00Z").is_some());
    for bad in [
        "",
        "2025-02-29T00:00:00Z",
        "2025-13-01T00:00:00Z",
        "2025-11-22T24:00:00Z",
        "2025-11-22T10:00:00",
        "2025-11-22T10:00:00.Z",
        "2025-11-22T10:00:00+0700",
        "1969-12-31T23:59:59Z",
        "2025-11-22",
        "２０２５-11-22T10:00:00Z",
    ] {
        assert_eq!(rfc3339_unix_ms(bad), None, "{bad}");
    }
}

#[test]
fn samples_cover_the_path() {
    let s = sample_path(&[[0.0, 0.0], [0.0, 100.0], [100.0, 100.0]]);
    assert_eq!(s.first().map(|x| x.0), Some([0.0, 0.0]));
    assert_eq!(s.last().map(|x| x.0), Some([100.0, 100.0]));
    assert!(s.iter().all(|(_, b)| *b == 0.0 || *b == 90.0));
    assert!(s.len() >= 40);
}

#[test]
fn packet_ids_are_stable_and_distinct() {
    let zone = |id: &str| WzdxZone {
        feature_index: 0,
        event_id: Some(id.into()),
        road_names: vec![],
        direction: None,
        closed_lanes: vec![1],
        speed_only: false,
        start_m: 0.0,
        end_m: 10.0,
        speed_limit: None,
        start_unix_ms: 90_000,
        end_unix_ms: 150_001,
    };
    assert_eq!(zone("a").packet_id(), zone("a").packet_id());
    assert_ne!(zone("a").packet_id(), zone("b").packet_id());
    // 00:01:00 to 00:02:30.001: 2 minutes from the start minute, rounded up -> 2.
    assert_eq!(zone("a").duration_min(), 2);
}
