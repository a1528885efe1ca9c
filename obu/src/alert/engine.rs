//! Pure alert logic: zone state from distance, alerts per zone with their stage,
//! arbitration.

use heapless::Vec;

use super::{Alert, AlertConfig, AlertKind, AlertStage, HmiState, ZoneState};
use crate::distance::ZoneDistance;
use crate::zone::ZoneInfo;

/// A zone as the alert engine sees it.
#[derive(Debug, Clone, Copy)]
pub struct ZoneView<'a> {
    /// Parsed content.
    pub info: &'a ZoneInfo,
    /// Distance to it.
    pub distance: ZoneDistance,
}

/// The vehicle's motion as the thresholds need it.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Motion {
    /// Speed, m/s, when known.
    pub speed_mps: Option<f32>,
    /// Metres travelled before the next state reaches the driver
    /// ([`AlertConfig::lookahead_m`]).
    pub lookahead_m: f32,
    /// The last state was urgent: it stays so until the driver clears the thresholds by a
    /// margin ([`URGENT_RELEASE`]) or leaves the closed lane, so the tone does not restart
    /// on every small change of speed.
    pub was_urgent: bool,
}

/// An urgent state ends only with a needed deceleration below the comfortable one divided
/// by this, or more than this times the lane-change distance left.
pub const URGENT_RELEASE: f32 = 1.25;

/// The state for a zone at distance `d` for a vehicle moving as `motion`. Approaching and
/// warning start when the distance as it will be at the next state would be past their
/// threshold; in zone and leaving follow the distance now.
pub fn zone_state(cfg: &AlertConfig, d: &ZoneDistance, motion: &Motion) -> ZoneState {
    let warn = cfg.warning_distance(motion.speed_mps);
    let approach = warn * cfg.approach_factor.max(1.0);
    let (dist, len) = (d.distance_m, d.length_m.max(0.0));
    let next = dist - motion.lookahead_m.max(0.0);
    if !dist.is_finite() || next > approach {
        ZoneState::None
    } else if next > warn {
        ZoneState::Approaching
    } else if dist > 0.0 {
        ZoneState::Warning
    } else if dist >= -len {
        ZoneState::InZone
    } else if dist >= -len - cfg.leaving_distance_m {
        ZoneState::Leaving
    } else {
        ZoneState::None
    }
}

/// Deceleration needed to slow from `speed_mps` to `limit_mps` over `distance_m`, m/s²
/// (the callers pass the limit plus the overspeed tolerance: within it no one must brake)
/// (`None` when already at or below the limit, or the distance is not ahead).
pub fn decel_needed(
    speed_mps: Option<f32>,
    limit_mps: Option<f32>,
    distance_m: f32,
) -> Option<f32> {
    let (v, l) = (speed_mps?, limit_mps?);
    if v <= l || !distance_m.is_finite() || distance_m <= 0.0 {
        return None;
    }
    Some((v * v - l * l) / (2.0 * distance_m.max(1.0)))
}

/// Appends the alerts one zone raises in `state` (ignoring overflow), each with its stage:
/// information while approaching, warning within the warning distance, urgent when the
/// driver is not complying (in the closed lane where a lane change no longer fits, a
/// needed deceleration above the comfortable one, over the limit inside).
pub fn zone_alerts<const N: usize>(
    cfg: &AlertConfig,
    zone: &ZoneView<'_>,
    state: ZoneState,
    motion: &Motion,
    out: &mut Vec<Alert, N>,
) {
    let ahead_stage = match state {
        ZoneState::Approaching => AlertStage::Information,
        ZoneState::Warning => AlertStage::Warning,
        ZoneState::InZone => AlertStage::Urgent,
        ZoneState::None | ZoneState::Leaving => return,
    };
    let limit = zone.info.speed_limit.mps();
    let dist = zone.distance.distance_m;
    let mut push = |kind, stage| {
        let _ = out.push(Alert {
            kind,
            stage,
            distance_m: Some(dist),
            limit_mps: limit,
        });
    };
    let ahead = matches!(state, ZoneState::Approaching | ZoneState::Warning);
    let speed = motion.speed_mps;
    let relax = if motion.was_urgent {
        URGENT_RELEASE
    } else {
        1.0
    };
    let allowed = limit.map(|l| l + cfg.overspeed_tolerance_mps);
    let too_hard =
        decel_needed(speed, allowed, dist).is_some_and(|a| a * relax > cfg.comfortable_decel_mps2);
    let over_inside =
        state == ZoneState::InZone && matches!((speed, allowed), (Some(v), Some(a)) if v > a);
    if over_inside || (state == ZoneState::Warning && too_hard) {
        push(AlertKind::Overspeed, AlertStage::Urgent);
    }
    if zone.info.lane_closed && (ahead || zone.distance.on_zone_lane) {
        if zone.distance.on_zone_lane {
            let no_room = dist - motion.lookahead_m <= cfg.lane_change_m(speed) * relax;
            let stage = if state == ZoneState::Warning && no_room {
                AlertStage::Urgent
            } else {
                ahead_stage
            };
            push(AlertKind::LaneClosedOwn, stage);
        } else {
            push(AlertKind::LaneClosedOther, ahead_stage);
        }
    }
    if ahead && limit.is_some() {
        push(AlertKind::ReducedSpeedAhead, ahead_stage);
    }
    if ahead && limit.is_none() && !zone.info.lane_closed {
        push(AlertKind::WorkZoneAhead, ahead_stage);
    }
}

/// Sorts alerts: a worker in the lane ahead first whatever the other stages (a person
/// in the vehicle's path outranks every road condition), then by stage (highest first), kind
/// priority and distance; fills `primary` and `others`. The worker alert takes the highest
/// stage among the alerts, so that an urgent closure's tone is not lowered by it.
pub(crate) fn arbitrate<const N: usize>(mut alerts: Vec<Alert, N>, hmi: &mut HmiState) {
    let top = alerts.iter().map(|a| a.stage).max();
    for a in alerts
        .iter_mut()
        .filter(|a| a.kind == AlertKind::WorkerInLane)
    {
        a.stage = top.unwrap_or(a.stage).max(a.stage);
    }
    crate::math::sort_small_by(&mut alerts, |a, b| {
        let da = a.distance_m.unwrap_or(f32::MAX);
        let db = b.distance_m.unwrap_or(f32::MAX);
        let worker = |x: &Alert| x.kind != AlertKind::WorkerInLane;
        worker(a)
            .cmp(&worker(b))
            .then(b.stage.cmp(&a.stage))
            .then(a.kind.cmp(&b.kind))
            .then(da.total_cmp(&db))
    });
    let mut it = alerts.into_iter();
    hmi.primary = it.next();
    hmi.others.clear();
    for a in it {
        if hmi.others.push(a).is_err() {
            break;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::distance::DistanceSource;
    use crate::lane::Speed;
    use crate::zone::ContentKind;

    fn d(distance_m: f32, own: bool) -> ZoneDistance {
        ZoneDistance {
            distance_m,
            length_m: 100.0,
            on_zone_lane: own,
            source: DistanceSource::Lane,
        }
    }

    fn moving(speed: f32, lookahead_m: f32) -> Motion {
        Motion {
            speed_mps: Some(speed),
            lookahead_m,
            was_urgent: false,
        }
    }

    #[test]
    fn states_by_distance() {
        let c = AlertConfig::default();
        let v = moving(40.0 / 3.6, 0.0);
        let s = |x| zone_state(&c, &d(x, true), &v);
        assert_eq!(s(301.0), ZoneState::None);
        assert_eq!(s(250.0), ZoneState::Approaching);
        assert_eq!(s(100.0), ZoneState::Warning);
        assert_eq!(s(0.0), ZoneState::InZone);
        assert_eq!(s(-100.0), ZoneState::InZone);
        assert_eq!(s(-120.0), ZoneState::Leaving);
        assert_eq!(s(-151.0), ZoneState::None);
        assert_eq!(s(f32::NAN), ZoneState::None);
        assert_eq!(
            zone_state(&c, &d(200.0, true), &moving(30.0, 0.0)),
            ZoneState::Warning,
            "270 m at 108 km/h"
        );
    }

    #[test]
    fn the_warning_starts_at_the_last_fix_before_its_distance() {
        let c = AlertConfig::default();
        // 11 m/s, 10 Hz: 1.1 m per fix, 1.1 m of display latency.
        let v = moving(11.0, c.lookahead_m(Some(11.0), 0.1));
        assert!((v.lookahead_m - 2.2).abs() < 1e-4);
        let s = |x| zone_state(&c, &d(x, false), &v);
        assert_eq!(s(102.3), ZoneState::Approaching);
        assert_eq!(s(102.1), ZoneState::Warning, "shown at 101 m, before 100 m");
        assert_eq!(s(0.5), ZoneState::Warning);
    }

    fn kinds_and_stages(out: &[Alert]) -> std::vec::Vec<(AlertKind, AlertStage)> {
        out.iter().map(|a| (a.kind, a.stage)).collect()
    }

    #[test]
    fn stages_follow_compliance() {
        let c = AlertConfig::default();
        let mut info = ZoneInfo::new(ContentKind::WorkZone);
        info.speed_limit = Speed::from_kmh(40.0);
        info.lane_closed = true;
        let zone = |x, own| ZoneView {
            info: &info,
            distance: d(x, own),
        };
        let run = |x, own, state, v: f32| {
            let mut out: Vec<Alert, 8> = Vec::new();
            zone_alerts(&c, &zone(x, own), state, &moving(v, 0.0), &mut out);
            kinds_and_stages(&out)
        };
        use AlertKind::*;
        use AlertStage::*;
        assert_eq!(
            run(250.0, true, ZoneState::Approaching, 11.0),
            [
                (LaneClosedOwn, Information),
                (ReducedSpeedAhead, Information)
            ]
        );
        assert_eq!(
            run(90.0, true, ZoneState::Warning, 11.0),
            [(LaneClosedOwn, Warning), (ReducedSpeedAhead, Warning)],
            "a lane change at 11 m/s fits in 55 m"
        );
        assert_eq!(
            run(50.0, true, ZoneState::Warning, 11.0)[0],
            (LaneClosedOwn, Urgent),
            "still in the closed lane where a lane change no longer fits"
        );
        assert_eq!(
            run(50.0, false, ZoneState::Warning, 11.0),
            [(LaneClosedOther, Warning), (ReducedSpeedAhead, Warning)],
            "changed lane: no longer urgent"
        );
        // 25 m/s to 11.1 m/s in 90 m needs 2.79 m/s²: more than comfortable.
        assert_eq!(
            run(90.0, false, ZoneState::Warning, 25.0)[0],
            (Overspeed, Urgent)
        );
        assert!(decel_needed(Some(25.0), Speed::from_kmh(40.0).mps(), 90.0)
            .is_some_and(|a| (a - 2.786).abs() < 0.01));
        assert_eq!(decel_needed(Some(10.0), Some(11.0), 90.0), Option::None);
        assert_eq!(decel_needed(Some(20.0), Some(11.0), -5.0), Option::None);
        // Inside, over the limit plus the tolerance, or in the closed lane: urgent.
        assert_eq!(
            run(-10.0, false, ZoneState::InZone, 14.0),
            [(Overspeed, Urgent)]
        );
        assert!(run(-10.0, false, ZoneState::InZone, 11.0).is_empty());
        assert_eq!(
            run(-10.0, true, ZoneState::InZone, 11.0),
            [(LaneClosedOwn, Urgent)]
        );
        assert!(run(-160.0, true, ZoneState::Leaving, 11.0).is_empty());
    }

    #[test]
    fn urgent_holds_until_a_margin_is_cleared_and_respects_the_tolerance() {
        let c = AlertConfig::default();
        let mut info = ZoneInfo::new(ContentKind::WorkZone);
        info.speed_limit = Speed::from_kmh(40.0);
        info.lane_closed = true;
        let run = |x, v, was_urgent| {
            let mut out: Vec<Alert, 8> = Vec::new();
            let motion = Motion {
                was_urgent,
                ..moving(v, 0.0)
            };
            let view = ZoneView {
                info: &info,
                distance: d(x, true),
            };
            zone_alerts(&c, &view, ZoneState::Warning, &motion, &mut out);
            out.first().map(|a| a.stage)
        };
        // 60 m out: at 13 m/s a lane change needs 65 m (urgent); braking to 11 m/s (55 m)
        // does not end it while within 1.25 x 55 m.
        assert_eq!(run(60.0, 13.0, false), Some(AlertStage::Urgent));
        assert_eq!(run(60.0, 11.0, false), Some(AlertStage::Warning));
        assert_eq!(run(60.0, 11.0, true), Some(AlertStage::Urgent));
        assert_eq!(run(80.0, 11.0, true), Some(AlertStage::Warning));
        // 45 km/h toward a 40 km/h zone is within the 5 km/h tolerance: never urgent.
        let mut out: Vec<Alert, 8> = Vec::new();
        let view = ZoneView {
            info: &info,
            distance: d(3.0, false),
        };
        zone_alerts(&c, &view, ZoneState::Warning, &moving(12.5, 0.0), &mut out);
        assert!(
            out.iter().all(|a| a.stage == AlertStage::Warning),
            "{out:?}"
        );
    }

    #[test]
    fn arbitration_puts_the_highest_stage_first() {
        let c = AlertConfig::default();
        let mut info = ZoneInfo::new(ContentKind::WorkZone);
        info.speed_limit = Speed::from_kmh(10.0);
        info.lane_closed = true;
        let mut out: Vec<Alert, 8> = Vec::new();
        let view = ZoneView {
            info: &info,
            distance: d(80.0, true),
        };
        zone_alerts(&c, &view, ZoneState::Warning, &moving(11.0, 0.0), &mut out);
        let mut hmi = HmiState::default();
        out.reverse();
        arbitrate(out, &mut hmi);
        assert_eq!(
            hmi.primary.map(|a| (a.kind, a.stage)),
            Some((AlertKind::LaneClosedOwn, AlertStage::Warning))
        );
        assert_eq!(hmi.others.len(), 1);
        let mut out: Vec<Alert, 8> = Vec::new();
        zone_alerts(&c, &view, ZoneState::Warning, &moving(21.0, 0.0), &mut out);
        arbitrate(out, &mut hmi);
        assert_eq!(
            hmi.primary.map(|a| (a.kind, a.stage)),
            Some((AlertKind::LaneClosedOwn, AlertStage::Urgent)),
            "both urgent (no room to change lane, 2.7 m/s² to 10 km/h): the lane first"
        );
        assert_eq!(
            hmi.others.first().map(|a| (a.kind, a.stage)),
            Some((AlertKind::Overspeed, AlertStage::Urgent))
        );
        let plain = ZoneInfo::new(ContentKind::WorkZone);
        let mut out: Vec<Alert, 8> = Vec::new();
        zone_alerts(
            &c,
            &ZoneView {
                info: &plain,
                distance: d(200.0, false),
            },
            ZoneState::Approaching,
            &Motion::default(),
            &mut out,
        );
        assert_eq!(
            kinds_and_stages(&out),
            [(AlertKind::WorkZoneAhead, AlertStage::Information)]
        );
    }

    #[test]
    fn a_worker_in_the_lane_leads_even_an_urgent_closure_and_keeps_its_tone() {
        let alert = |kind, stage, distance| Alert {
            kind,
            stage,
            distance_m: Some(distance),
            limit_mps: None,
        };
        let mut alerts: Vec<Alert, 4> = Vec::new();
        for a in [
            alert(AlertKind::LaneClosedOwn, AlertStage::Urgent, 30.0),
            alert(AlertKind::WorkerInLane, AlertStage::Warning, 60.0),
            alert(AlertKind::Overspeed, AlertStage::Warning, 30.0),
        ] {
            alerts.push(a).unwrap();
        }
        let mut hmi = HmiState::default();
        arbitrate(alerts, &mut hmi);
        let primary = hmi.primary.unwrap();
        assert_eq!(
            (primary.kind, primary.stage),
            (AlertKind::WorkerInLane, AlertStage::Urgent)
        );
        let rest: std::vec::Vec<AlertKind> = hmi.others.iter().map(|a| a.kind).collect();
        assert_eq!(rest, [AlertKind::LaneClosedOwn, AlertKind::Overspeed]);
    }
}
