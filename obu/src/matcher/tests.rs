use super::*;
use crate::geo::Point;
use crate::testutil;

fn fix(x: f32, y: f32, course: f32, speed: f32) -> Fix {
    Fix {
        speed_mps: Some(speed),
        course_deg: Some(course),
        accuracy_m: Some(0.5),
        ..Fix::at(testutil::at(Point::new(x, y)))
    }
}

fn run(m: &mut Matcher, maps: &MapStore, t: u64, f: Fix) -> Option<(u8, LaneMatch)> {
    let cfg = MatcherConfig::PER_FIX;
    m.update(Instant::from_millis(t), &f, maps, &cfg)
        .map(|r| (r.lane.0, r))
}

#[test]
fn matches_lane_station_and_confidence() {
    let maps = testutil::store();
    let mut m = Matcher::new();
    let (lane, r) = run(&mut m, &maps, 0, fix(0.3, 100.0, 0.0, 10.0)).unwrap_or_default();
    assert_eq!(lane, 2);
    assert!((r.position.station - 100.0).abs() < 0.05 && (r.position.lateral + 0.3).abs() < 0.05);
    assert!(r.confidence >= 95, "{}", r.confidence);
    let (_, edge) = run(&mut m, &maps, 100, fix(1.6, 101.0, 0.0, 10.0)).unwrap_or_default();
    assert!(edge.confidence < 70, "near the edge: {}", edge.confidence);
}

#[test]
fn heading_gate_and_direction() {
    let maps = testutil::store();
    let mut m = Matcher::new();
    assert!(
        run(&mut m, &maps, 0, fix(0.0, 100.0, 90.0, 10.0)).is_none(),
        "crossing"
    );
    assert!(
        run(&mut m, &maps, 100, fix(0.0, 100.0, 180.0, 10.0)).is_none(),
        "wrong way"
    );
    let (lane, r) = run(&mut m, &maps, 200, fix(-7.0, 100.0, 180.0, 10.0)).unwrap_or_default();
    assert_eq!(lane, 4);
    assert!(
        (r.position.station - 900.0).abs() < 0.05,
        "ingress station from the far end"
    );
    assert!(
        run(&mut m, &maps, 300, fix(0.0, 1100.0, 0.0, 10.0)).is_none(),
        "beyond the end"
    );
}

#[test]
fn frozen_heading_when_slow() {
    let maps = testutil::store();
    let mut m = Matcher::new();
    assert!(run(&mut m, &maps, 0, fix(0.0, 100.0, 0.0, 10.0)).is_some());
    let slow = fix(0.0, 100.0, 120.0, 0.2);
    assert_eq!(
        run(&mut m, &maps, 100, slow).map(|r| r.0),
        Some(2),
        "course ignored when slow"
    );
    let unknown = Fix {
        course_deg: None,
        speed_mps: None,
        ..slow
    };
    assert_eq!(run(&mut m, &maps, 200, unknown).map(|r| r.0), Some(2));
}

#[test]
fn hysteresis_holds_before_switching() {
    let maps = testutil::store();
    let mut m = Matcher::new();
    assert_eq!(
        run(&mut m, &maps, 0, fix(0.0, 100.0, 0.0, 10.0)).map(|r| r.0),
        Some(2)
    );
    let lanes: heapless::Vec<u8, 8> = (1..=5u64)
        .filter_map(|k| {
            run(
                &mut m,
                &maps,
                k * 100,
                fix(2.5, 100.0 + k as f32, 0.0, 10.0),
            )
            .map(|r| r.0)
        })
        .collect();
    assert_eq!(
        &lanes[..],
        &[2, 2, 2, 3, 3],
        "switch once best for 300 ms and 3 fixes"
    );
    assert_eq!(m.switches(), 1);
    let back = run(&mut m, &maps, 600, fix(1.5, 106.0, 0.0, 10.0)).map(|r| r.0);
    assert_eq!(back, Some(3), "one noisy fix does not flip back");
    assert_eq!(
        run(&mut m, &maps, 700, fix(5.5, 107.0, 0.0, 10.0)).map(|r| r.0),
        Some(3),
        "held"
    );
    assert!(
        run(&mut m, &maps, 800, fix(30.0, 107.0, 0.0, 10.0)).is_none(),
        "off map"
    );
}
