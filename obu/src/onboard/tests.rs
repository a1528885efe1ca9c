use super::*;
use crate::alert::{AlertKind, AlertStage, LaneAdvice, ZoneState};
use crate::clock::ROLLOVER_MS;
use crate::geo::Point;
use crate::lane::ModelError;
use crate::testutil;
use crate::time::Duration;

/// An OBU with the per-fix matcher: these tests place single fixes far apart (hundreds of
/// metres within 100 ms) to reach each case of the zone and alert logic, which the lane
/// filter would rightly reject as outliers. The filter has its own tests
/// (`matcher::filter`, `tests/drive.rs`) and runs in every scenario.
fn obu_with(zone: bool) -> Obu {
    obu_with_matcher(zone, crate::matcher::MatcherConfig::PER_FIX)
}

/// The test road (and the closure of lane 3 when `zone`) with `matcher`.
fn obu_with_matcher(zone: bool, matcher: crate::matcher::MatcherConfig) -> Obu {
    let config = crate::alert::AlertConfig {
        matcher,
        ..Default::default()
    };
    let mut obu = Obu::new(config);
    let r = obu.update_map(
        Instant::ZERO,
        MapId(7),
        1,
        testutil::reference(),
        1600.0,
        |m| {
            testutil::fill_road(m);
            Ok::<(), ModelError>(())
        },
    );
    assert_eq!(r, Ok(true));
    if zone {
        let key = ZoneKey::packet([1; 9], 0);
        let r = obu.update_zone(Instant::ZERO, key, 1, testutil::validity(), |z| {
            testutil::fill_closure(z);
            Ok::<(), ModelError>(())
        });
        assert_eq!(r, Ok(true));
    }
    obu
}

fn fix_at(x: f32, y: f32, speed: f32) -> Fix {
    Fix {
        speed_mps: Some(speed),
        course_deg: Some(0.0),
        accuracy_m: Some(0.3),
        utc: Some(UtcTime::from_minute_of_year(2024, 2000)),
        ..Fix::at(testutil::at(Point::new(x, y)))
    }
}

fn drive(obu: &mut Obu, t: u64, x: f32, y: f32, speed: f32) -> HmiState {
    obu.on_fix(Instant::from_millis(t), fix_at(x, y, speed))
}

#[test]
fn approach_warn_inside_leave() {
    let mut obu = obu_with(true);
    let v = 40.0 / 3.6;
    let s = drive(&mut obu, 0, 3.5, 0.0, v);
    assert_eq!(
        (s.zone_state, s.primary.map(|a| a.kind)),
        (ZoneState::None, None)
    );
    assert_eq!(s.lane.map(|l| l.lane), Some(3));
    assert!(
        s.speed_limit_mps
            .is_some_and(|l| (l - 60.0 / 3.6).abs() < 0.05)
            && !s.reduced_limit
    );
    let s = drive(&mut obu, 100, 3.5, 150.0, v);
    assert_eq!(s.zone_state, ZoneState::Approaching);
    assert_eq!(s.primary.map(|a| a.kind), Some(AlertKind::LaneClosedOwn));
    assert_eq!(
        s.others.first().map(|a| a.kind),
        Some(AlertKind::ReducedSpeedAhead)
    );
    assert!(s.distance_m.is_some_and(|d| (d - 250.0).abs() < 0.1));
    assert_eq!(s.stage, AlertStage::Information);
    let s = drive(&mut obu, 200, 3.5, 350.0, v);
    assert_eq!(s.zone_state, ZoneState::Warning);
    assert_eq!(
        (&s.closed_lanes[..], s.advice),
        (&[3u8][..], LaneAdvice::MoveLeft)
    );
    // 50 m out at 11 m/s a lane change (55 m) no longer fits: urgent.
    assert_eq!(s.stage, AlertStage::Urgent);
    // The limit in force is still the lane's; the zone's 25 mph is 50 m ahead.
    assert!(
        !s.reduced_limit
            && s.speed_limit_mps
                .is_some_and(|l| (l - 60.0 / 3.6).abs() < 0.05)
    );
    assert!(s
        .limit_ahead_mps
        .is_some_and(|l| (l - 25.0 * 0.447_04).abs() < 0.05));
    assert!(s.limit_ahead_m.is_some_and(|d| (d - 50.0).abs() < 0.1));
    assert!(!s.speed_alarm, "0.02 m/s² to slow down: no red speed");
    let s = drive(&mut obu, 300, 3.5, 450.0, 20.0);
    assert_eq!(s.zone_state, ZoneState::InZone);
    assert!(
        s.reduced_limit
            && s.speed_limit_mps
                .is_some_and(|l| (l - 25.0 * 0.447_04).abs() < 0.05)
    );
    assert!(s.speed_alarm && s.limit_ahead_mps.is_none());
    // Still in the closed lane: "change lane" first, the overspeed after it.
    assert_eq!(s.primary.map(|a| a.kind), Some(AlertKind::LaneClosedOwn));
    assert_eq!(s.others.first().map(|a| a.kind), Some(AlertKind::Overspeed));
    let s = drive(&mut obu, 400, 3.5, 520.0, v);
    assert_eq!((s.zone_state, s.primary), (ZoneState::Leaving, None));
    let s = drive(&mut obu, 500, 3.5, 600.0, v);
    assert_eq!(s.zone_state, ZoneState::None);
}

#[test]
fn neighbour_lane_is_told_but_not_moved() {
    let mut obu = obu_with(true);
    let s = drive(&mut obu, 0, 0.0, 350.0, 10.0);
    assert_eq!(s.zone_state, ZoneState::Warning);
    assert_eq!(
        s.primary.map(|a| a.kind),
        Some(AlertKind::ReducedSpeedAhead)
    );
    assert!(s
        .others
        .iter()
        .any(|a| a.kind == AlertKind::LaneClosedOther));
    assert_eq!(s.advice, LaneAdvice::None);
    let s = drive(&mut obu, 100, -10.5, 350.0, 10.0);
    assert_eq!(
        s.zone_state,
        ZoneState::None,
        "southbound lanes are not concerned"
    );
}

#[test]
fn stale_gnss_and_deadlines() {
    let mut obu = obu_with(true);
    assert!(obu.next_deadline().is_some());
    let s = drive(&mut obu, 1000, 3.5, 300.0, 10.0);
    assert_eq!(
        (s.position, s.zone_state),
        (PositionSource::Live, ZoneState::Warning)
    );
    assert_eq!(obu.next_deadline(), Some(Instant::from_millis(2001)));
    assert!(obu.poll(Instant::from_millis(1500)).is_none());
    // Dead reckoning along the lane at the last speed: 10 m/s for 1.001 s.
    let s = obu.poll(Instant::from_millis(2001)).unwrap_or_default();
    assert_eq!((s.gnss_ok, s.position), (false, PositionSource::Estimated));
    assert_eq!(s.lane.map(|l| l.lane), Some(3), "the lane stays shown");
    assert!(
        s.distance_m.is_some_and(|d| (d - 89.99).abs() < 0.05),
        "{:?}",
        s.distance_m
    );
    assert_eq!(s.zone_state, ZoneState::Warning);
    assert_eq!(s.speed_mps, None, "the GNSS speed is stale: not shown");
    assert!(s.others.iter().any(|a| a.kind == AlertKind::GnssStale));
    assert_eq!(obu.next_deadline(), Some(Instant::from_millis(2101)));
    assert!(obu.poll(Instant::from_millis(2050)).is_none());
    let s = obu.poll(Instant::from_millis(2101)).unwrap_or_default();
    assert!(s.distance_m.is_some_and(|d| (d - 88.99).abs() < 0.05));
    // CAN speed: shown while fresh, and integrated from when it came.
    obu.on_speed(Instant::from_millis(3001), 5.0);
    let s = obu.state(Instant::from_millis(4001));
    assert_eq!(s.speed_mps, Some(5.0));
    assert!(
        s.distance_m.is_some_and(|d| (d - 74.99).abs() < 0.05),
        "{:?}",
        s.distance_m
    );
    // The horizon (1 s timeout + 5 s): position lost, the zone ahead kept, no distance.
    let mut last = None;
    while let Some(t) = obu.next_deadline().filter(|t| t.millis() <= 7001) {
        last = obu.poll(t).or(last);
    }
    let s = last.unwrap_or_default();
    assert_eq!(s.time_ms, 7001);
    assert_eq!(
        (s.position, s.zone_state),
        (PositionSource::Lost, ZoneState::Warning)
    );
    assert_eq!((s.distance_m, s.lane, s.speed_mps), (None, None, None));
    assert!(s.stage >= AlertStage::Information && s.stage <= AlertStage::Warning);
    assert!(s.primary.is_some_and(|a| a.distance_m.is_none()));
    assert!(
        obu.poll(Instant::from_millis(7101)).is_none(),
        "reported once"
    );
    let s = obu.poll(Instant::from_millis(30_001)).unwrap_or_default();
    assert_eq!((s.zones, s.maps), (0, 1), "zone expired after 30 s unheard");
    let s = obu.poll(Instant::from_millis(60_001)).unwrap_or_default();
    assert!(!s.roadside_data && s.maps == 0, "map expired after 60 s");
    assert_eq!(obu.counters().expired, 2);
}

#[test]
fn the_warning_comes_at_the_last_fix_before_its_distance() {
    // 11 m/s at 10 Hz toward the zone start at y = 400: the first warning must show at
    // or before 100 m, and no more than one fix (1.1 m) plus the display latency early.
    let mut obu = obu_with(true);
    let v = 11.0;
    let mut first = None;
    for k in 0..400u64 {
        let y = 150.0 + v * 0.1 * k as f32;
        let s = drive(&mut obu, 1000 + 100 * k, 0.0, y, v);
        if s.stage >= AlertStage::Warning {
            first = Some(400.0 - y);
            break;
        }
    }
    let d = first.unwrap_or(0.0);
    assert!(
        (100.0..=100.0 + 1.1 + 1.2).contains(&d),
        "first warning {d} m out"
    );
}

#[test]
fn dead_reckoning_never_carries_the_car_out_of_a_zone_it_was_in() {
    // Inside the zone (start y = 400) at 30 m/s when GNSS goes: 6 s of dead reckoning is
    // 180 m, past the end; had the car braked it would still be inside.
    let mut obu = obu_with(true);
    let s = drive(&mut obu, 1000, 3.5, 450.0, 30.0);
    assert_eq!(s.zone_state, ZoneState::InZone);
    let mut last = None;
    while let Some(t) = obu.next_deadline().filter(|t| t.millis() <= 7001) {
        last = obu.poll(t).or(last);
    }
    let s = last.unwrap_or_default();
    assert_eq!(
        (s.position, s.zone_state),
        (PositionSource::Lost, ZoneState::InZone)
    );
    assert_ne!(s.stage, AlertStage::None);
}

#[test]
fn a_fresh_vehicle_speed_replaces_the_fix_speed() {
    let mut obu = obu_with(true);
    obu.on_speed(Instant::from_millis(900), 4.0);
    let s = drive(&mut obu, 1000, 3.5, 150.0, 10.0);
    assert_eq!(s.speed_mps, Some(4.0), "CAN 100 ms old");
    let s = drive(&mut obu, 2000, 3.5, 151.0, 10.0);
    assert_eq!(s.speed_mps, Some(10.0), "CAN 1.1 s old: the fix's own");
}

#[test]
fn an_outage_is_not_the_fix_period() {
    // A fix 3 s after the last one, 110 m out at 11 m/s: the period stays 100 ms, so the
    // look-ahead is 2.2 m, not 3 s of travel.
    let mut obu = obu_with(true);
    let _ = drive(&mut obu, 1000, 0.0, 150.0, 11.0);
    let _ = drive(&mut obu, 1100, 0.0, 151.1, 11.0);
    let s = drive(&mut obu, 4100, 0.0, 290.0, 11.0);
    assert_eq!(s.zone_state, ZoneState::Approaching);
    let s = drive(&mut obu, 4200, 0.0, 297.9, 11.0);
    assert_eq!(s.zone_state, ZoneState::Warning);
}

/// The map and a closure valid for minute 2000 of 2024 (ended at the start of 2001).
fn obu_with_window() -> Obu {
    let mut obu = obu_with(false);
    let window = Validity {
        start_year: 2024,
        start_minute: 2000,
        duration_min: 1,
    };
    let key = ZoneKey::packet([1; 9], 0);
    let r = obu.update_zone(Instant::ZERO, key, 1, window, |z| {
        testutil::fill_closure(z);
        Ok::<(), ModelError>(())
    });
    assert_eq!(r, Ok(true));
    obu
}

#[test]
fn the_end_of_a_validity_window_is_a_deadline() {
    let mut obu = obu_with_window();
    let mut config = AlertConfig::DEFAULT;
    config.zone_timeout = Duration::from_secs(600);
    config.map_timeout = Duration::from_secs(600);
    obu.set_config(config);
    // The fixes say minute 2000, second 0.
    let _ = drive(&mut obu, 1000, 3.5, 350.0, 10.0);
    assert!(obu.poll(Instant::from_millis(2001)).is_some(), "GNSS stale");
    while let Some(t) = obu.next_deadline().filter(|t| t.millis() <= 7001) {
        let _ = obu.poll(t);
    }
    // Minute 2001 starts 60 s after the fix.
    assert_eq!(obu.next_deadline(), Some(Instant::from_millis(61_000)));
    assert!(obu.poll(Instant::from_millis(60_999)).is_none());
    let s = obu.poll(Instant::from_millis(61_000)).unwrap_or_default();
    assert_eq!(s.zones, 0, "the window has ended");
    assert_eq!(obu.next_deadline(), Some(Instant::from_millis(600_001)));
}

#[test]
fn a_tim_repeated_past_its_window_ends_the_zone_and_is_not_stored_again() {
    let mut obu = obu_with_window();
    let window = Validity {
        start_year: 2024,
        start_minute: 2000,
        duration_min: 1,
    };
    let key = ZoneKey::packet([1; 9], 0);
    let repeat = |obu: &mut Obu, ms| {
        obu.update_zone(Instant::from_millis(ms), key, 1, window, |z| {
            testutil::fill_closure(z);
            Ok::<(), ModelError>(())
        })
    };
    obu.set_reference_time(Instant::ZERO, UtcTime::from_minute_of_year(2024, 2000));
    let _ = drive(&mut obu, 1000, 3.5, 350.0, 10.0);
    assert_eq!(
        repeat(&mut obu, 1100),
        Ok(false),
        "in its window: unchanged"
    );
    assert_eq!(obu.zones().len(), 1);
    // On a trusted time in minute 2001 (the window over) the same TIM arrives again.
    let late = UtcTime::from_minute_of_year(2024, 2001);
    obu.set_reference_time(Instant::from_millis(1200), late);
    let _ = obu.on_fix(
        Instant::from_millis(1200),
        Fix {
            utc: Some(late),
            ..fix_at(3.5, 351.0, 10.0)
        },
    );
    assert_eq!(obu.zones().len(), 1, "not polled yet");
    let expired = obu.counters().expired;
    assert_eq!(repeat(&mut obu, 1300), Ok(true), "the repeat ends its zone");
    assert_eq!(obu.zones().len(), 0);
    assert_eq!(obu.counters().expired, expired + 1);
    for ms in [1400, 1500, 1600] {
        assert_eq!(repeat(&mut obu, ms), Ok(false), "a repeat past its window");
        assert_eq!(obu.zones().len(), 0, "never stored again");
    }
    let _ = obu.poll(Instant::from_millis(1700));
    assert_eq!(
        obu.counters().expired,
        expired + 1,
        "nothing stored, nothing expired"
    );
}

#[test]
fn a_zone_is_judged_expired_on_a_trusted_time_only() {
    let mut obu = obu_with_window();
    let system = UtcTime::from_minute_of_year(2024, 2000);
    obu.set_reference_time(Instant::ZERO, system);
    // A receiver three minutes ahead, past the window: unverified, the zone kept.
    let ahead = Fix {
        utc: Some(UtcTime::from_minute_of_year(2024, 2003)),
        ..fix_at(3.5, 350.0, 10.0)
    };
    let s = obu.on_fix(Instant::from_millis(1000), ahead);
    assert_eq!(s.time_status, TimeStatus::Unverified);
    assert_eq!((s.zones, s.zone_state), (1, ZoneState::Warning));
    assert!(
        obu.alt_time64(Instant::from_millis(1000)).is_some(),
        "minutes apart: both clocks"
    );
    let _ = obu.poll(Instant::from_millis(1500));
    assert_eq!(obu.zones().len(), 1, "not expired on an unverified time");
    assert_eq!(obu.counters().unverified_time_fixes, 1);
    // Half an hour apart: the system clock is no second clock for signed messages.
    let far = Fix {
        utc: Some(UtcTime::from_minute_of_year(2024, 2030)),
        ..fix_at(3.5, 350.5, 10.0)
    };
    let _ = obu.on_fix(Instant::from_millis(1050), far);
    assert_eq!(obu.alt_time64(Instant::from_millis(1050)), None);
    // The same minute 1024 weeks early (a week-rollover fault): corrected and trusted.
    let faulty = UtcTime::from_abs_millis(system.abs_millis() + 1100 - ROLLOVER_MS);
    assert_eq!(faulty.year, 2004);
    let s = obu.on_fix(
        Instant::from_millis(1100),
        Fix {
            utc: Some(faulty),
            ..fix_at(3.5, 351.0, 10.0)
        },
    );
    assert_eq!(
        (s.time_status, s.zone_state),
        (TimeStatus::Trusted, ZoneState::Warning)
    );
    assert_eq!(obu.counters().rollover_fixes, 1);
    // On a trusted time past the window the zone ends.
    let late = Fix {
        utc: Some(UtcTime::from_minute_of_year(2024, 2002)),
        ..fix_at(3.5, 352.0, 10.0)
    };
    obu.set_reference_time(
        Instant::from_millis(1200),
        UtcTime::from_minute_of_year(2024, 2002),
    );
    let s = obu.on_fix(Instant::from_millis(1200), late);
    assert_eq!(
        (s.time_status, s.zone_state),
        (TimeStatus::Trusted, ZoneState::None)
    );
    let _ = obu.poll(Instant::from_millis(1300));
    assert_eq!(obu.zones().len(), 0);
}

#[test]
fn validity_and_cancel() {
    let mut obu = obu_with(true);
    let early = Fix {
        utc: Some(UtcTime::from_minute_of_year(2024, 10)),
        ..fix_at(3.5, 350.0, 10.0)
    };
    let s = obu.on_fix(Instant::ZERO, early);
    assert_eq!(s.zone_state, ZoneState::None, "not started yet");
    let key = ZoneKey::packet([1; 9], 0);
    let cancel = Validity {
        duration_min: 0,
        ..testutil::validity()
    };
    assert_eq!(
        obu.update_zone(Instant::ZERO, key, 2, cancel, |_| Ok::<(), ModelError>(())),
        Ok(true)
    );
    let s = drive(&mut obu, 100, 3.5, 350.0, 10.0);
    assert_eq!((s.zone_state, s.zones), (ZoneState::None, 0));
    assert_eq!(obu.counters().zones_cancelled, 1);
}

#[test]
fn failed_conversions_are_dropped() {
    let mut obu = obu_with(false);
    let r = obu.update_map(
        Instant::ZERO,
        MapId(8),
        1,
        testutil::reference(),
        0.0,
        |_| Err(ModelError::InvalidValue),
    );
    assert_eq!(r, Err(ModelError::InvalidValue));
    assert_eq!(obu.maps().len(), 1);
    let same = obu.update_map(
        Instant::ZERO,
        MapId(7),
        1,
        testutil::reference(),
        0.0,
        |_| Err(ModelError::InvalidValue),
    );
    assert_eq!(same, Ok(false), "same revision: not refilled");
    let key = ZoneKey::default();
    let r = obu.update_zone(Instant::ZERO, key, 1, testutil::validity(), |_| {
        Err(ModelError::CapacityExceeded)
    });
    assert_eq!(r, Err(ModelError::CapacityExceeded));
    assert!(obu.zones().is_empty());
    let s = drive(&mut obu, 0, 3.5, 100.0, 10.0);
    assert_eq!((s.maps, s.zones, s.roadside_data), (1, 0, true));
    let _ = Duration::ZERO;
}

#[test]
fn off_map_counts() {
    let mut obu = obu_with(false);
    let s = drive(&mut obu, 0, 100.0, 100.0, 10.0);
    assert!(s.lane.is_none() && s.lane_confidence == 0);
    assert_eq!(obu.counters().off_map, 1);
}

#[test]
fn road_lanes_left_to_right_in_the_direction_of_travel() {
    // Lanes 1-3 run north (x = -3.5, 0, 3.5); 4 and 5 run south west of them.
    for x in [3.5f32, 0.0, -3.5] {
        let s = drive(&mut obu_with(false), 0, x, 300.0, 15.0);
        assert_eq!(
            &s.road_lanes[..],
            &[1u8, 2, 3][..],
            "in the lane at x = {x}"
        );
    }
    // Southbound at x = -7: left of the traveller is east, so lane 4 comes before 5.
    let mut obu = obu_with(false);
    let s = obu.on_fix(
        Instant::from_millis(0),
        Fix {
            course_deg: Some(180.0),
            ..fix_at(-7.0, 300.0, 15.0)
        },
    );
    assert_eq!(s.lane.map(|l| l.lane), Some(4));
    assert_eq!(&s.road_lanes[..], &[4u8, 5][..]);
    // Off map: no road.
    let s = drive(&mut obu, 100, 400.0, 300.0, 15.0);
    assert!(s.lane.is_none() && s.road_lanes.is_empty());
}

#[test]
fn circle_region_warns_along_the_heading() {
    use crate::zone::{ContentKind, Region, ZoneInfo};
    let mut obu = obu_with(false);
    let key = ZoneKey::packet([2; 9], 0);
    let r = obu.update_zone(Instant::ZERO, key, 1, testutil::validity(), |z| {
        // Workers within 40 m of a point on lane 2 at y = 600 m; 25 mph.
        let _ = z.push_region(Region::circle(
            testutil::at(Point::new(0.0, 600.0)),
            1600.0,
            40.0,
        ));
        let mut info = ZoneInfo::new(ContentKind::WorkZone);
        for c in [1025, 268, 12569, 8720] {
            info.push_itis(c);
        }
        z.info = info;
        Ok::<(), ModelError>(())
    });
    assert_eq!(r, Ok(true));
    let s = drive(&mut obu, 0, 0.0, 300.0, 10.0);
    assert_eq!(s.zone_state, ZoneState::Approaching);
    assert!(
        s.distance_m.is_some_and(|d| (d - 260.0).abs() < 0.5),
        "{s:?}"
    );
    let s = drive(&mut obu, 100, 0.0, 500.0, 10.0);
    assert_eq!(s.zone_state, ZoneState::Warning);
    assert_eq!(
        s.primary.map(|a| a.kind),
        Some(AlertKind::ReducedSpeedAhead)
    );
    let s = drive(&mut obu, 200, 0.0, 600.0, 10.0);
    assert_eq!(s.zone_state, ZoneState::InZone);
    // Southbound on lane 4 at x = -7, past the circle's centre line: it is 7 m aside,
    // so the line of travel crosses it as well (the slice allows every heading). Later
    // (a jump of 200 m and a turn within one fix would be an outlier to the lane filter).
    let s = obu.on_fix(
        Instant::from_millis(3_000),
        Fix {
            course_deg: Some(180.0),
            ..fix_at(-7.0, 800.0, 10.0)
        },
    );
    assert!(
        s.distance_m.is_some_and(|d| d > 150.0 && d < 170.0),
        "{s:?}"
    );
}

#[test]
fn lane_changes_follow_the_fixes_own_clock_not_their_arrival() {
    // The car moves from lane 3 (x = 3.5) to lane 2 (x = 0) over fixes 10 to 30 at 10 m/s;
    // the receiver stamps its fixes 100 ms apart. Both lane methods run on the time between
    // fixes (the per-fix matcher's hold, the filter's prediction): it must be the
    // receiver's, not the arrival's.
    for matcher in [
        crate::matcher::MatcherConfig::PER_FIX,
        crate::matcher::MatcherConfig::DEFAULT,
    ] {
        lane_change_on_the_receivers_clock(matcher);
    }
}

fn lane_change_on_the_receivers_clock(matcher: crate::matcher::MatcherConfig) {
    let run = |arrivals: &[u64]| -> std::vec::Vec<Option<u8>> {
        let mut obu = obu_with_matcher(false, matcher);
        let mut lanes = std::vec::Vec::new();
        for (k, &t) in arrivals.iter().enumerate() {
            let x = |k: usize| 3.5 - 3.5 * ((k as f32 - 10.0) / 20.0).clamp(0.0, 1.0);
            let dx = x(k + 1) - x(k);
            let fix = Fix {
                utc: Some(UtcTime {
                    year: 2024,
                    ms_of_year: 1_000_000 + 100 * k as u64,
                }),
                course_deg: Some(libm::atan2f(dx, 1.0).to_degrees().rem_euclid(360.0)),
                ..fix_at(x(k), k as f32, 10.0)
            };
            lanes.push(
                obu.on_fix(Instant::from_millis(t), fix)
                    .lane
                    .map(|l| l.lane),
            );
        }
        lanes
    };
    let steady: std::vec::Vec<u64> = (0..40).map(|k| 100 * k).collect();
    let jitter = [0, 90, 10, 80, 0, 95, 5, 70, 15, 60];
    let late: std::vec::Vec<u64> = steady
        .iter()
        .zip(jitter.iter().cycle())
        .map(|(t, j)| t + j)
        .collect();
    let on_time = run(&steady);
    assert_eq!(on_time.first(), Some(&Some(3)));
    assert_eq!(
        on_time.last(),
        Some(&Some(2)),
        "the change was made: {on_time:?}"
    );
    assert_eq!(
        run(&late),
        on_time,
        "arrival jitter does not move the decision"
    );
    // Without usable receiver times the arrival times are the clock.
    let mut obu = obu_with_matcher(false, matcher);
    let s = obu.on_fix(
        Instant::from_millis(0),
        Fix {
            utc: None,
            ..fix_at(3.5, 0.0, 10.0)
        },
    );
    assert_eq!(s.lane.map(|l| l.lane), Some(3));
}

#[test]
fn an_uncertain_lane_gives_lane_closure_ahead_with_the_side_not_your_lane_closed() {
    // Lane 3 (x = 3.5) is closed ahead. Fixes on the line between lanes 2 and 3 with a 1 m
    // error: the filter cannot tell the lane, so it names none, but the closure ahead
    // stays, as another lane's, with the way to keep.
    let mut obu = obu_with_matcher(true, crate::matcher::MatcherConfig::DEFAULT);
    let v = 40.0 / 3.6;
    let mut s = drive(&mut obu, 0, 1.75, 100.0, v);
    for k in 1..20u64 {
        let fix = Fix {
            accuracy_m: Some(1.0),
            utc: Some(UtcTime::from_minute_of_year(2024, 2000)),
            ..fix_at(1.75, 100.0 + 1.1 * k as f32, v)
        };
        s = obu.on_fix(Instant::from_millis(100 * k), fix);
    }
    assert_eq!(s.lane, None, "{s:?}");
    assert!(s.lane_confidence < 80, "{s:?}");
    assert_eq!(s.zone_state, ZoneState::Approaching, "{s:?}");
    let kinds: std::vec::Vec<_> = s
        .primary
        .iter()
        .chain(s.others.iter())
        .map(|a| a.kind)
        .collect();
    assert!(kinds.contains(&AlertKind::LaneClosedOther), "{s:?}");
    assert!(!kinds.contains(&AlertKind::LaneClosedOwn), "{s:?}");
    assert_eq!(s.advice, LaneAdvice::MoveLeft, "{s:?}");
}

mod workers;
