//! Pure alert logic: zone state from distance, alerts per zone, arbitration.

use heapless::Vec;

use super::{Alert, AlertConfig, AlertKind, HmiState, ZoneState};
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

/// The state for a zone at distance `d` for a vehicle at `speed_mps`.
pub fn zone_state(cfg: &AlertConfig, d: &ZoneDistance, speed_mps: Option<f32>) -> ZoneState {
    let warn = cfg.warning_distance(speed_mps);
    let approach = warn * cfg.approach_factor.max(1.0);
    let (dist, len) = (d.distance_m, d.length_m.max(0.0));
    if !dist.is_finite() || dist > approach {
        ZoneState::None
    } else if dist > warn {
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

/// Appends the alerts one zone raises in `state` (ignoring overflow).
pub fn zone_alerts<const N: usize>(
    cfg: &AlertConfig,
    zone: &ZoneView<'_>,
    state: ZoneState,
    speed_mps: Option<f32>,
    out: &mut Vec<Alert, N>,
) {
    if matches!(state, ZoneState::None | ZoneState::Leaving) {
        return;
    }
    let limit = zone.info.speed_limit.mps();
    let alert = |kind| Alert {
        kind,
        distance_m: Some(zone.distance.distance_m),
        limit_mps: limit,
    };
    let ahead = matches!(state, ZoneState::Approaching | ZoneState::Warning);
    let near = matches!(state, ZoneState::Warning | ZoneState::InZone);
    if let (true, Some(v), Some(l)) = (near, speed_mps, limit) {
        if v > l + cfg.overspeed_tolerance_mps {
            let _ = out.push(alert(AlertKind::Overspeed));
        }
    }
    if zone.info.lane_closed && (ahead || zone.distance.on_zone_lane) {
        let own = zone.distance.on_zone_lane;
        let _ = out.push(alert(if own {
            AlertKind::LaneClosedOwn
        } else {
            AlertKind::LaneClosedOther
        }));
    }
    if ahead && limit.is_some() {
        let _ = out.push(alert(AlertKind::ReducedSpeedAhead));
    }
    if ahead && limit.is_none() && !zone.info.lane_closed {
        let _ = out.push(alert(AlertKind::WorkZoneAhead));
    }
}

/// Sorts alerts by priority then distance and fills `primary` and `others`.
pub(crate) fn arbitrate<const N: usize>(mut alerts: Vec<Alert, N>, hmi: &mut HmiState) {
    alerts.sort_unstable_by(|a, b| {
        let da = a.distance_m.unwrap_or(f32::MAX);
        let db = b.distance_m.unwrap_or(f32::MAX);
        a.kind.cmp(&b.kind).then(da.total_cmp(&db))
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

    #[test]
    fn states_by_distance() {
        let c = AlertConfig::default();
        let v = Some(40.0 / 3.6);
        let s = |x| zone_state(&c, &d(x, true), v);
        assert_eq!(s(301.0), ZoneState::None);
        assert_eq!(s(250.0), ZoneState::Approaching);
        assert_eq!(s(100.0), ZoneState::Warning);
        assert_eq!(s(0.0), ZoneState::InZone);
        assert_eq!(s(-100.0), ZoneState::InZone);
        assert_eq!(s(-120.0), ZoneState::Leaving);
        assert_eq!(s(-151.0), ZoneState::None);
        assert_eq!(s(f32::NAN), ZoneState::None);
        assert_eq!(
            zone_state(&c, &d(200.0, true), Some(30.0)),
            ZoneState::Warning,
            "270 m at 108 km/h"
        );
    }

    #[test]
    fn alerts_and_arbitration() {
        let c = AlertConfig::default();
        let mut info = ZoneInfo::new(ContentKind::WorkZone);
        info.speed_limit = Speed::from_kmh(10.0);
        info.lane_closed = true;
        let own = ZoneView {
            info: &info,
            distance: d(80.0, true),
        };
        let mut out: Vec<Alert, 8> = Vec::new();
        zone_alerts(&c, &own, ZoneState::Warning, Some(11.0), &mut out);
        let kinds: Vec<AlertKind, 8> = out.iter().map(|a| a.kind).collect();
        assert_eq!(
            &kinds[..],
            &[
                AlertKind::Overspeed,
                AlertKind::LaneClosedOwn,
                AlertKind::ReducedSpeedAhead
            ]
        );
        let mut hmi = HmiState::default();
        out.reverse();
        arbitrate(out, &mut hmi);
        assert_eq!(hmi.primary.map(|a| a.kind), Some(AlertKind::LaneClosedOwn));
        assert_eq!(
            hmi.others.first().map(|a| a.kind),
            Some(AlertKind::Overspeed)
        );
        assert_eq!(hmi.others.len(), 2);
        // In an open lane the overspeed comes first.
        let mut out: Vec<Alert, 8> = Vec::new();
        let beside = ZoneView {
            info: &info,
            distance: d(80.0, false),
        };
        zone_alerts(&c, &beside, ZoneState::Warning, Some(11.0), &mut out);
        arbitrate(out, &mut hmi);
        assert_eq!(hmi.primary.map(|a| a.kind), Some(AlertKind::Overspeed));
        let mut out: Vec<Alert, 8> = Vec::new();
        let other = ZoneView {
            info: &info,
            distance: d(-10.0, false),
        };
        zone_alerts(&c, &other, ZoneState::InZone, Some(2.0), &mut out);
        assert!(out.is_empty(), "inside, slow, not on the closed lane");
        let plain = ZoneInfo::new(ContentKind::WorkZone);
        zone_alerts(
            &c,
            &ZoneView {
                info: &plain,
                distance: d(200.0, false),
            },
            ZoneState::Approaching,
            None,
            &mut out,
        );
        assert_eq!(out.first().map(|a| a.kind), Some(AlertKind::WorkZoneAhead));
    }
}
