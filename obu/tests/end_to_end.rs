//! End to end: the codec's work-zone MAP and TIM vectors are decoded and fed to the
//! core, then a synthetic 10 Hz fix trace drives along a lane toward the zone.
//!
//! The two vectors disagree about the direction of travel. The MAP (`map_work_zone`,
//! intersection 7001) has two lanes whose nodes run west from the reference point and
//! whose `directionalUse` is `ingressPath`: traffic moves from the last node toward the
//! first, i.e. east (J2735 node order starts at the stop line). Lane 1 is the north
//! lane, the left one for that traffic, and its far end tapers to zero width. The TIM
//! (`tim_work_zone_left_lane_closed`) closes the "left lane" (ITIS 8195) along lane 1,
//! but its region is `forward` (along its westward node order) with heading slice
//! `0018` (247.5 to 292.5 degrees): west only. The core follows J2735, so with the
//! vectors as committed no vehicle is warned ([`vectors_as_committed_disagree`]). The
//! lane-level drive therefore sets the decoded TIM region's direction to the MAP's
//! (`reverse`, heading slice 67.5 to 112.5 degrees) and leaves everything else as
//! decoded ([`warning_at_the_configured_distance_and_lane_advice`]).

mod common;

use j2735::msg::map_data::MapData;
use j2735::msg::traveler_information::{DirectionOfUse, TravelerInformation};
use obu::alert::{AlertConfig, AlertKind, LaneAdvice, ZoneState};
use obu::geo::Point;
use obu::lane::{LaneId, MapId};
use obu::{Fix, HmiState, Instant, Obu, UtcTime};

/// Speed of the drive, m/s (0.5 m between fixes at 10 Hz).
const SPEED: f32 = 5.0;
/// Configured warning distance, metres (the lane is 95 m long, the zone 36 m into it).
const WARN_M: f32 = 20.0;

fn config() -> AlertConfig {
    AlertConfig {
        warn_distance_m: WARN_M,
        lead_time_s: 1.0,
        ..AlertConfig::DEFAULT
    }
}

/// Decoded MAP and TIM; with `fix_direction` the TIM region's direction is set to the
/// MAP lanes' (eastbound).
fn messages(fix_direction: bool) -> (Box<MapData>, Box<TravelerInformation>) {
    let map = common::decode::<MapData>(&common::vector("map_work_zone"));
    let mut tim =
        common::decode::<TravelerInformation>(&common::vector("tim_work_zone_left_lane_closed"));
    if fix_direction {
        for frame in tim.data_frames.0.iter_mut() {
            for region in frame.regions.0.iter_mut() {
                region.directionality = Some(DirectionOfUse::Reverse);
                let h = region.direction.as_mut().expect("direction");
                (0..16).for_each(|i| {
                    h.0.set(i, i == 3 || i == 4);
                });
            }
        }
    }
    (map, tim)
}

/// A unit fed with both messages.
fn unit(map: &MapData, tim: &TravelerInformation) -> Box<Obu> {
    let mut obu = Box::new(Obu::new(config()));
    let r = obu.on_map(Instant::ZERO, map).expect("MAP stored");
    assert_eq!((r.stored, r.rejected), (1, 0));
    let r = obu.on_tim(Instant::ZERO, tim).expect("TIM stored");
    assert_eq!(
        (r.stored, r.rejected),
        (2, 0),
        "two data frames: closure, speed limit"
    );
    obu
}

/// One fix per step driving east along lane 1 from station `from` (metres from its
/// west end) to `to`; returns (station, state) per fix.
fn drive(obu: &mut Obu, from: f32, to: f32) -> Vec<(f32, HmiState)> {
    let (frame, lane) = {
        let m = obu.maps().get(MapId(7001)).expect("model");
        (*m.frame(), m.lane(LaneId(1)).expect("lane 1").clone())
    };
    let steps = ((to - from) / (SPEED * 0.1)) as u64;
    (0..=steps)
        .map(|k| {
            let station = from + k as f32 * SPEED * 0.1;
            let p = lane.point_at(lane.length() - station).expect("on lane");
            let fix = Fix {
                accuracy_source: Default::default(),
                position: frame.to_wgs84(Point::new(p.x, p.y)).expect("position"),
                accuracy_m: Some(0.3),
                speed_mps: Some(SPEED),
                course_deg: Some(90.0),
                utc: Some(UtcTime::from_minute_of_year(2025, 241_210)),
            };
            let now = Instant::from_millis(1_000 + 100 * k);
            (station, obu.on_fix(now, fix))
        })
        .collect()
}

/// Station on lane 1 (metres from its west end, eastbound) of a TIM path node given as
/// metres from the shared reference point (the TIM anchor is the MAP's refPoint).
fn station_of(obu: &Obu, x: f32, y: f32) -> f32 {
    let m = obu.maps().get(MapId(7001)).expect("model");
    let lane = m.lane(LaneId(1)).expect("lane 1");
    lane.locate(Point::new(x, y), Some(90.0))
        .expect("on lane")
        .station
}

#[test]
fn warning_at_the_configured_distance_and_lane_advice() {
    common::big_stack(|| {
        let (map, tim) = messages(true);
        let mut obu = unit(&map, &tim);
        // The TIM path: anchor, then node-XY offsets -120/40, -3100/25, -2950/-10 cm.
        // Eastbound, the zone starts at its last node (x = -61.7 m, on lane 1).
        let start = station_of(&obu, -1.2 - 31.0 - 29.5, 0.4 + 0.25 - 0.1);
        let trace = drive(&mut obu, 2.0, 80.0);
        let first = |s: ZoneState| trace.iter().find(|(_, h)| h.zone_state == s);
        let (at, warn) = first(ZoneState::Warning).expect("a warning");
        println!(
            "zone start at station {start:.2} m; warning first at {at:.2} m, distance {:?}",
            warn.distance_m
        );
        let step = SPEED * 0.1;
        // At the last fix before the configured distance would be passed: at or before it,
        // at most one fix plus the display latency of travel early.
        let lookahead = step + SPEED * config().display_latency_s;
        let early = start - at - WARN_M;
        assert!(
            (-0.05..=lookahead + 0.05).contains(&early),
            "warning {:.2} m before the zone start, configured {WARN_M} m (look-ahead {lookahead} m)",
            start - at
        );
        let before = first(ZoneState::Approaching).expect("approaching first");
        assert!(before.0 < *at, "approaching before the warning");
        assert_eq!(warn.lane.map(|l| l.lane), Some(1));
        assert_eq!(warn.primary.map(|a| a.kind), Some(AlertKind::LaneClosedOwn));
        assert_eq!(
            warn.advice,
            LaneAdvice::MoveRight,
            "left lane closed: lane 2 is right"
        );
        assert_eq!(&warn.closed_lanes[..], &[1]);
        // Before the zone its limit is the one ahead, not yet in force.
        let limit = warn.limit_ahead_mps.expect("limit ahead");
        assert!(
            !warn.reduced_limit && (limit - 139.0 * 0.02).abs() < 1e-3,
            "{limit}"
        );
        assert!(warn
            .limit_ahead_m
            .is_some_and(|d| (d - (start - at)).abs() < 0.5));
        assert!(warn
            .others
            .iter()
            .any(|a| a.kind == AlertKind::ReducedSpeedAhead && a.limit_mps.is_some()));
        let (inside, _) = first(ZoneState::InZone).expect("inside");
        assert!(
            (inside - start).abs() <= step + 0.05,
            "in zone from its start: {inside}"
        );
    });
}

#[test]
fn vectors_as_committed_disagree() {
    common::big_stack(|| {
        let (map, tim) = messages(false);
        let mut obu = unit(&map, &tim);
        let zone = obu.zones().iter().next().expect("zone");
        assert!(
            zone.lanes().is_empty(),
            "a westbound zone lies on no eastbound lane"
        );
        assert!(zone.regions[0].heading.contains(270.0) && !zone.regions[0].heading.contains(90.0));
        let trace = drive(&mut obu, 2.0, 80.0);
        assert!(trace
            .iter()
            .all(|(_, h)| h.lane.is_some_and(|l| l.lane == 1) || h.lane.is_none()));
        assert!(
            trace
                .iter()
                .all(|(_, h)| h.zone_state == ZoneState::None && h.primary.is_none()),
            "eastbound traffic is not concerned by a westbound-only region"
        );
        let anchor = tim.data_frames[0].regions[0]
            .anchor
            .as_ref()
            .expect("anchor");
        let reference = &map.intersections.as_ref().expect("ix")[0].ref_point;
        assert_eq!((anchor.lat, anchor.long), (reference.lat, reference.long));
    });
}
