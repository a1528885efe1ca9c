use super::*;
use crate::lane::{LaneId, MapId};
use crate::testutil;

#[test]
fn closure_lies_on_lane_three_only() {
    let maps = testutil::store();
    let mut z = testutil::closure();
    associate(&mut z, &maps);
    assert_eq!(z.lanes().len(), 1, "{:?}", z.lanes());
    let l = z.lanes()[0];
    assert_eq!((l.map, l.lane, l.region), (MapId(7), LaneId(3), 0));
    assert!(
        (l.start - 400.0).abs() < 0.05 && (l.end - 500.0).abs() < 0.05,
        "{l:?}"
    );
}

#[test]
fn reverse_region_lands_on_opposite_lanes() {
    let maps = testutil::store();
    let mut z = testutil::closure();
    let mut r = Region::path(testutil::at(Point::new(-7.0, 500.0)), 1600.0, 3.5);
    r.directionality = super::super::Directionality::Forward;
    for y in [0.0, -50.0, -100.0] {
        let _ = r.push_node(Point::new(0.0, y));
    }
    z.regions.clear();
    let _ = z.push_region(r);
    associate(&mut z, &maps);
    assert_eq!(z.lanes().len(), 1);
    let l = z.lanes()[0];
    assert_eq!(l.lane, LaneId(4));
    assert!(
        (l.start - 500.0).abs() < 0.05 && (l.end - 600.0).abs() < 0.05,
        "{l:?}"
    );
}

#[test]
fn direction_filter_excludes_lanes() {
    let maps = testutil::store();
    let mut z = testutil::closure();
    if let Some(r) = z.regions.get_mut(0) {
        r.directionality = super::super::Directionality::Reverse;
    }
    associate(&mut z, &maps);
    assert!(z.lanes().is_empty());
}

#[test]
fn a_path_running_past_the_lane_end_covers_the_lane_to_its_end() {
    // Lane 3 runs north from y = 0 to y = 1000; the closure path goes on to y = 1100 (past
    // the lane's last node): only its first node lies on the lane.
    let maps = testutil::store();
    let mut z = testutil::closure();
    let mut r = Region::path(testutil::at(Point::new(3.5, 900.0)), 1600.0, 3.5);
    for y in [0.0, 200.0] {
        let _ = r.push_node(Point::new(0.0, y));
    }
    z.regions.clear();
    let _ = z.push_region(r);
    associate(&mut z, &maps);
    assert_eq!(z.lanes().len(), 1, "{:?}", z.lanes());
    let l = z.lanes()[0];
    assert_eq!(l.lane, LaneId(3));
    // Points every 200 m / 64 = 3.125 m along the segment: the last one on the lane is at
    // the lane's end.
    assert!(
        (l.start - 900.0).abs() < 0.05 && l.end > 1000.0 - 3.2 && l.end <= 1000.0,
        "{l:?}"
    );
}
