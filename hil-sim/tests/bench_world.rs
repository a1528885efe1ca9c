//! The HMI bench's road, zone and scenes through the OBU core (the same MAP/TIM bytes and
//! NMEA text the daemon receives): every scene shows what its name promises.

use hil_sim::hmi_bench::{self, SCENES};
use hil_sim::nmea;
use obu::alert::{AlertKind, AlertStage, LaneAdvice, ZoneState};
use obu::input::nmea::{parse, FixAssembler};
use obu::{HmiState, Instant, Obu};
use roadside::clock::Utc;
use roadside::messages;

/// 2026-11-22T10:00:00Z.
const NOW_MS: u64 = 1_795_341_600_000;

/// A unit that received the bench's MAP and TIM (decoded from their UPER bytes).
fn unit() -> Box<Obu> {
    let road = hmi_bench::road();
    let zone = hmi_bench::zone(Utc::from_unix_ms(NOW_MS - 120_000));
    let map = messages::encode(&messages::build_map(&road, 1501, 1, Some(&zone)).unwrap()).unwrap();
    let tim = messages::encode(&messages::build_tim(&road, &zone).unwrap()).unwrap();
    let mut obu = Box::new(Obu::new(hmi_bench::core_config()));
    for bytes in [map, tim] {
        let frame: j2735::msg::message_frame::MessageFrame = j2735::uper::decode(&bytes).unwrap();
        obu.on_frame(Instant::ZERO, &frame)
            .expect("the core takes the bench's messages");
    }
    // One zone per TIM data frame: the closure and the speed limit.
    assert_eq!((obu.maps().len(), obu.zones().len()), (1, 2));
    obu
}

/// Drives `scene` for `secs` at 10 Hz through NMEA text; returns the states.
fn drive(obu: &mut Obu, scene: &str, secs: f64) -> Vec<HmiState> {
    let road = hmi_bench::road();
    let mut asm = FixAssembler::new();
    let mut out = Vec::new();
    for k in 0..(secs * 10.0) as u64 {
        let t = k as f64 * 0.1;
        let mut epoch = hmi_bench::car_epoch(&road, scene, t).unwrap();
        epoch.utc = Utc::from_unix_ms(NOW_MS + k * 100);
        let mut fixes = Vec::new();
        for line in nmea::epoch(&epoch).lines() {
            asm.push(&parse(line).unwrap(), |e| fixes.extend(e.outcome.ok()));
        }
        for fix in fixes {
            out.push(obu.on_fix(Instant::from_millis(k * 100), fix));
        }
    }
    out
}

fn kind(s: &HmiState) -> Option<AlertKind> {
    s.primary.map(|a| a.kind)
}

#[test]
fn every_scene_shows_its_state() {
    for scene in SCENES {
        let mut obu = unit();
        let states = drive(&mut obu, scene.name, 20.0);
        // Past the lane matcher's settling (first second), every state is the scene's.
        for s in &states[10..] {
            let ok = match scene.name {
                "cruise" => s.zone_state == ZoneState::None && s.primary.is_none(),
                "speeding" => {
                    s.zone_state == ZoneState::None
                        && s.primary.is_none()
                        && s.stage == AlertStage::None
                        && s.speed_alarm
                }
                "approach" => {
                    s.zone_state == ZoneState::Approaching && s.stage == AlertStage::Information
                }
                "warning" => {
                    s.zone_state == ZoneState::Warning
                        && s.stage == AlertStage::Warning
                        && !s.speed_alarm
                        && kind(s) == Some(AlertKind::ReducedSpeedAhead)
                        && s.others
                            .iter()
                            .any(|a| a.kind == AlertKind::LaneClosedOther)
                }
                "lane_closed" => {
                    kind(s) == Some(AlertKind::LaneClosedOwn) && s.advice == LaneAdvice::MoveLeft
                }
                "urgent" => {
                    kind(s) == Some(AlertKind::LaneClosedOwn)
                        && s.stage == AlertStage::Urgent
                        && s.advice == LaneAdvice::MoveLeft
                }
                "overspeed" => {
                    kind(s) == Some(AlertKind::Overspeed)
                        && s.stage == AlertStage::Urgent
                        && s.speed_alarm
                }
                "in_zone" => s.zone_state == ZoneState::InZone && s.reduced_limit,
                "leaving" => s.zone_state == ZoneState::Leaving,
                other => panic!("scene {other} has no expectation here"),
            };
            assert!(ok, "{}: {s:?}", scene.name);
            assert!(
                s.gnss_ok && s.lane.is_some_and(|l| l.lane == scene.lane),
                "{}: {s:?}",
                scene.name
            );
            assert_eq!(&s.road_lanes[..], &[1u8, 2, 3][..], "{}", scene.name);
            if matches!(
                s.zone_state,
                ZoneState::Warning | ZoneState::InZone | ZoneState::Approaching
            ) {
                assert_eq!(&s.closed_lanes[..], &[3u8][..], "{}", scene.name);
            }
        }
    }
}

#[test]
fn the_zone_limit_and_the_road_limit() {
    let mut obu = unit();
    let cruise = drive(&mut obu, "cruise", 2.0);
    let limit = cruise.last().unwrap().speed_limit_mps.unwrap();
    assert!((limit - 80.0 / 3.6).abs() < 0.05, "road limit {limit}");
    let mut obu = unit();
    let inside = drive(&mut obu, "in_zone", 2.0);
    let limit = inside.last().unwrap().speed_limit_mps.unwrap();
    assert!((limit - 40.0 / 3.6).abs() < 0.05, "zone limit {limit}");
}
