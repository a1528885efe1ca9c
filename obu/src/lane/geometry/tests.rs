use super::*;
use crate::lane::Speed;

fn lane(direction: TravelDirection, pts: &[(f32, f32)]) -> Lane {
    let mut l = Lane::new(LaneId(1), direction, LaneKind::Vehicle);
    for &(x, y) in pts {
        assert!(l.push_node(Point::new(x, y), 3.5).is_ok());
    }
    l
}

#[test]
fn egress_follows_node_order() {
    let l = lane(
        TravelDirection::Egress,
        &[(0.0, 0.0), (0.0, 100.0), (100.0, 100.0)],
    );
    assert!((l.length() - 200.0).abs() < 1e-3);
    let pos = l.locate(Point::new(1.0, 50.0), None).unwrap_or_default();
    assert!((pos.station - 50.0).abs() < 1e-3);
    assert!(
        (pos.lateral + 1.0).abs() < 1e-3,
        "right of travel is negative"
    );
    assert!(pos.bearing_deg.abs() < 1e-3 && pos.forward);
    assert!((pos.width - 3.52).abs() < 0.03);
    let pos = l.locate(Point::new(50.0, 99.0), None).unwrap_or_default();
    assert!((pos.station - 150.0).abs() < 1e-3 && (pos.bearing_deg - 90.0).abs() < 1e-3);
}

#[test]
fn ingress_runs_from_last_node_to_first() {
    let l = lane(TravelDirection::Ingress, &[(0.0, 0.0), (0.0, 100.0)]);
    let pos = l.locate(Point::new(1.0, 30.0), None).unwrap_or_default();
    assert!((pos.station - 70.0).abs() < 1e-3);
    assert!(
        (pos.lateral - 1.0).abs() < 1e-3,
        "east is left when driving south"
    );
    assert!((pos.bearing_deg - 180.0).abs() < 1e-3 && !pos.forward);
}

#[test]
fn both_directions_follow_heading() {
    let l = lane(TravelDirection::Both, &[(0.0, 0.0), (0.0, 100.0)]);
    assert!(l
        .locate(Point::new(0.0, 10.0), Some(10.0))
        .is_some_and(|p| p.forward));
    assert!(l
        .locate(Point::new(0.0, 10.0), Some(170.0))
        .is_some_and(|p| !p.forward));
}

#[test]
fn beyond_the_ends() {
    let l = lane(TravelDirection::Egress, &[(0.0, 0.0), (0.0, 100.0)]);
    let p = l.project(Point::new(0.5, -5.0)).unwrap_or_default();
    assert!((p.along + 5.0).abs() < 1e-3 && (p.lateral + 0.5).abs() < 1e-3);
    let pos = l.locate(Point::new(0.0, 107.0), None).unwrap_or_default();
    assert!((pos.beyond - 7.0).abs() < 1e-3);
}

#[test]
fn point_at_and_splitting() {
    let mut l = lane(TravelDirection::Egress, &[(0.0, 0.0)]);
    assert!(l.push_node(Point::new(1000.0, 0.0), 3.0).is_ok());
    assert_eq!(
        l.node_count(),
        5,
        "1000 m split into 4 parts of <= 327.67 m"
    );
    assert!((l.length() - 1000.0).abs() < 1e-2);
    let p = l.point_at(600.0).unwrap_or_default();
    assert!((p.x - 600.0).abs() < 1e-2 && p.y.abs() < 1e-3);
    assert_eq!(l.point_at(5000.0), Some(Point::new(1000.0, 0.0)));
    assert!(l.point_at(f32::NAN).is_none());
}

#[test]
fn capacity_and_invalid_values() {
    let mut l = lane(TravelDirection::Egress, &[]);
    assert!(l.project(Point::default()).is_none());
    assert_eq!(
        l.push_node(Point::new(f32::NAN, 0.0), 3.0),
        Err(ModelError::InvalidValue)
    );
    assert_eq!(
        l.push_node(Point::new(0.0, 0.0), -1.0),
        Err(ModelError::InvalidValue)
    );
    for i in 0..MAX_NODES {
        assert!(l.push_node(Point::new(i as f32, 0.0), 3.0).is_ok());
    }
    assert_eq!(
        l.push_node(Point::new(99.0, 0.0), 3.0),
        Err(ModelError::CapacityExceeded)
    );
    assert_eq!(
        l.push_node_cm(i32::MAX, i32::MIN, 300),
        Err(ModelError::CapacityExceeded)
    );
    assert_eq!(l.limits.max, Speed::UNAVAILABLE);
}

#[test]
fn cone_rule() {
    let l = lane(
        TravelDirection::Egress,
        &[(0.0, 0.0), (0.0, 100.0), (100.0, 100.0)],
    );
    assert_eq!(l.cone_along(Point::new(1.7, 50.0)).map(|c| c.0), Some(50.0));
    assert!(
        l.cone_along(Point::new(1.8, 50.0)).is_none(),
        "half width is 1.76 m"
    );
    assert!(
        l.cone_along(Point::new(0.0, -0.1)).is_none(),
        "before the first node"
    );
    assert_eq!(
        l.cone_along(Point::new(40.0, 100.0)).map(|c| c.1),
        Some(90.0)
    );
}

#[test]
fn quick_rejection() {
    let l = lane(TravelDirection::Egress, &[(0.0, 0.0), (0.0, 100.0)]);
    assert!(l.may_contain(Point::new(0.0, 101.0), 2.0));
    assert!(!l.may_contain(Point::new(0.0, 110.0), 2.0));
}

#[test]
fn the_segment_search_agrees_with_the_clamped_parameter() {
    // Segments far from the origin (coordinates of a few km, as a MAP's are) and points
    // before, beside and after them; the search's distance is the clamped-parameter one.
    let mut seed = 0x2545_f491u32;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        (seed % 20_000) as f32 * 0.01 - 100.0
    };
    for _ in 0..2_000 {
        let base = Point::new(2_000.0 + next(), -1_500.0 + next());
        let a = Point::new(base.x + next(), base.y + next());
        let b = Point::new(a.x + next() * 0.5, a.y + next() * 0.5);
        let p = Point::new(base.x + next(), base.y + next());
        let want = SegmentFit::dist2(a, b, p);
        let got = nearer(a, b, p, f32::INFINITY).unwrap_or(f32::NAN);
        assert!(
            (got - want).abs() <= 1e-3 * want.max(1.0),
            "{a:?} {b:?} {p:?}: {got} vs {want}"
        );
        // Not nearer than itself; nearer than anything farther.
        assert_eq!(nearer(a, b, p, want * 0.999 - 1e-3), None);
        assert!(nearer(a, b, p, want * 1.001 + 1e-3).is_some());
    }
}
