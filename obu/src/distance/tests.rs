use super::*;
use crate::fix::Fix;
use crate::lane::MapUpdate;
use crate::matcher::{Matcher, MatcherConfig};
use crate::testutil;
use crate::time::Instant;
use crate::zone::associate;

fn setup() -> (MapStore, WorkZone) {
    let maps = testutil::store();
    let mut z = testutil::closure();
    associate(&mut z, &maps);
    (maps, z)
}

fn dist(maps: &MapStore, z: &WorkZone, x: f32, y: f32, course: f32) -> Option<ZoneDistance> {
    let pos = testutil::at(Point::new(x, y));
    let fix = Fix {
        course_deg: Some(course),
        speed_mps: Some(10.0),
        ..Fix::at(pos)
    };
    let m = Matcher::new().update(Instant::ZERO, &fix, maps, &MatcherConfig::default());
    zone_distance(z, maps, m.as_ref(), pos, Some(course), 4.0)
}

#[test]
fn along_the_closed_lane() {
    let (maps, z) = setup();
    let d = dist(&maps, &z, 3.5, 100.0, 0.0).unwrap_or_else(|| panic!("no distance"));
    assert_eq!(d.source, DistanceSource::Lane);
    assert!(
        (d.distance_m - 300.0).abs() < 0.05 && (d.length_m - 100.0).abs() < 0.05,
        "{d:?}"
    );
    assert!(d.on_zone_lane);
    let inside = dist(&maps, &z, 3.5, 450.0, 0.0)
        .map(|d| d.distance_m)
        .unwrap_or_default();
    assert!((inside + 50.0).abs() < 0.05, "negative inside: {inside}");
}

#[test]
fn adjacent_lane_uses_geometry() {
    let (maps, z) = setup();
    let d = dist(&maps, &z, 0.0, 100.0, 0.0).unwrap_or_else(|| panic!("no distance"));
    assert_eq!(d.source, DistanceSource::LaneGeometry);
    assert!(
        (d.distance_m - 300.0).abs() < 0.05 && !d.on_zone_lane,
        "{d:?}"
    );
    assert!(
        dist(&maps, &z, -10.5, 100.0, 180.0).is_none(),
        "opposite direction"
    );
}

#[test]
fn off_map_uses_the_path() {
    let (_, z) = setup();
    let empty = MapStore::new();
    let d = dist(&empty, &z, 3.5, 300.0, 0.0).unwrap_or_else(|| panic!("no distance"));
    assert_eq!(d.source, DistanceSource::Path);
    assert!((d.distance_m - 100.0).abs() < 0.05, "{d:?}");
    assert!(
        dist(&empty, &z, 3.5, 300.0, 180.0).is_none(),
        "forward-only region"
    );
}

#[test]
fn through_a_connection() {
    let mut maps = testutil::store();
    if let MapUpdate::Fill { model, .. } = maps.update(
        Instant::ZERO,
        crate::lane::MapId(7),
        2,
        testutil::reference(),
        1600.0,
        crate::store::Provenance::Verified,
    ) {
        testutil::fill_road(model);
        if let Some(l) = model.lane_mut(LaneId(3)) {
            l.connections.clear();
        }
        let mut feeder = Lane::new(
            LaneId(9),
            crate::lane::TravelDirection::Egress,
            crate::lane::LaneKind::Vehicle,
        );
        let _ = feeder.push_node(Point::new(3.5, -200.0), 3.5);
        let _ = feeder.push_node(Point::new(3.5, -20.0), 3.5);
        let _ = feeder.connections.push(LaneId(3));
        if let Ok(l) = model.add_lane(LaneId(9), feeder.direction, feeder.kind) {
            *l = feeder;
        }
    }
    let mut z = testutil::closure();
    associate(&mut z, &maps);
    let d = dist(&maps, &z, 3.5, -100.0, 0.0).unwrap_or_else(|| panic!("no distance"));
    assert_eq!(d.source, DistanceSource::Connection);
    assert!(
        (d.distance_m - 480.0).abs() < 0.05,
        "80 m left on the feeder + 400 m: {d:?}"
    );
}
