//! Building the HMI state from the stores, the last fix and the lane match.

use heapless::Vec;

use super::Obu;
use crate::alert::{self, Alert, AlertKind, HmiState, LaneAdvice, LaneInfo, ZoneState, ZoneView};
use crate::distance::{zone_distance, ZoneDistance};
use crate::lane::{Lane, LaneModel};
use crate::matcher::LaneMatch;
use crate::time::Instant;
use crate::zone::{ClosureSide, WorkZone};

/// Alerts gathered before arbitration.
type AlertList = Vec<Alert, 16>;

/// The nearest concerning zone.
struct Nearest<'a> {
    zone: &'a WorkZone,
    dist: ZoneDistance,
    state: ZoneState,
}

impl Obu {
    /// The display state at `now`.
    pub(super) fn evaluate(&self, now: Instant, gnss_ok: bool) -> HmiState {
        let fix = self.last_fix.map(|(_, f)| f);
        let speed = fix.and_then(|f| f.speed());
        let mut hmi = self.base_state(now, gnss_ok, speed);
        let mut alerts = AlertList::new();
        self.data_alerts(gnss_ok, &mut alerts);
        let nearest = if gnss_ok {
            self.zone_alerts(now, speed, &mut alerts)
        } else {
            None
        };
        self.fill_limit(&mut hmi, nearest.as_ref());
        if let Some(n) = &nearest {
            hmi.zone_state = n.state;
            hmi.distance_m = Some(n.dist.distance_m);
            self.fill_closure(&mut hmi, n);
        }
        alert::arbitrate(alerts, &mut hmi);
        hmi
    }

    fn base_state(&self, now: Instant, gnss_ok: bool, speed: Option<f32>) -> HmiState {
        let m = self.last_match.filter(|_| gnss_ok);
        let shown = m.filter(|m| m.confidence >= self.config.matcher.min_confidence);
        HmiState {
            time_ms: now.millis(),
            speed_mps: speed,
            lane: shown.map(|m| LaneInfo {
                map: m.map.0,
                lane: m.lane.0,
            }),
            lane_confidence: m.map_or(0, |m| m.confidence),
            gnss_ok,
            roadside_data: !(self.maps.is_empty() && self.zones.is_empty()),
            maps: self.maps.len() as u8,
            zones: self.zones.len() as u8,
            counters: self.counters(),
            ..HmiState::default()
        }
    }

    fn data_alerts(&self, gnss_ok: bool, out: &mut AlertList) {
        let plain = |kind| Alert {
            kind,
            distance_m: None,
            limit_mps: None,
        };
        if !gnss_ok {
            let _ = out.push(plain(AlertKind::GnssStale));
        }
        if self.maps.is_empty() && self.zones.is_empty() {
            let _ = out.push(plain(AlertKind::NoRoadsideData));
        } else if self.maps.is_empty() {
            let _ = out.push(plain(AlertKind::MapMissing));
        }
    }

    /// Alerts of every concerning zone; returns the nearest one.
    fn zone_alerts(
        &self,
        now: Instant,
        speed: Option<f32>,
        out: &mut AlertList,
    ) -> Option<Nearest<'_>> {
        let fix = self.last_fix.map(|(_, f)| f)?;
        let heading = self
            .last_match
            .map(|m| m.position.bearing_deg)
            .or(fix.course());
        let utc = self.utc_minutes(now);
        let mut nearest: Option<Nearest<'_>> = None;
        for zone in self.zones.iter() {
            let active = utc.map_or(!zone.validity.is_cancelled(), |m| {
                zone.validity.is_active(m)
            });
            if !active {
                continue;
            }
            let m = self.last_match.as_ref();
            let reach = self.config.zone_reach_m;
            let Some(dist) = zone_distance(zone, &self.maps, m, fix.position, heading, reach)
            else {
                continue;
            };
            let state = alert::zone_state(&self.config, &dist, speed);
            if state == ZoneState::None {
                continue;
            }
            alert::zone_alerts(
                &self.config,
                &ZoneView {
                    info: &zone.info,
                    distance: dist,
                },
                state,
                speed,
                out,
            );
            if nearest.as_ref().is_none_or(|n| closer(&dist, &n.dist)) {
                nearest = Some(Nearest { zone, dist, state });
            }
        }
        nearest
    }

    /// Speed limit: the zone's when near or inside it, else the lane's.
    fn fill_limit(&self, hmi: &mut HmiState, nearest: Option<&Nearest<'_>>) {
        let lane = self.matched_lane().map(|(_, l)| l);
        let lane_max = lane.and_then(|l| l.limits.max.mps());
        let zone_near =
            nearest.filter(|n| matches!(n.state, ZoneState::Warning | ZoneState::InZone));
        let zone_limit = zone_near.and_then(|n| {
            let construction = lane.map_or(crate::lane::Speed::UNAVAILABLE, |l| {
                l.limits.construction_max
            });
            n.zone.info.speed_limit.min_available(construction).mps()
        });
        hmi.speed_limit_mps = zone_limit.or(lane_max);
        hmi.reduced_limit = zone_limit.is_some_and(|z| lane_max.is_none_or(|l| z < l));
    }

    /// Closed lanes of the nearest zone on the current map, and the advice.
    fn fill_closure(&self, hmi: &mut HmiState, n: &Nearest<'_>) {
        if !n.zone.info.lane_closed {
            return;
        }
        let map = self.last_match.map(|m| m.map);
        for z in n
            .zone
            .lanes()
            .iter()
            .filter(|z| map.is_none_or(|m| m == z.map))
        {
            if !hmi.closed_lanes.contains(&z.lane.0) {
                let _ = hmi.closed_lanes.push(z.lane.0);
            }
        }
        if n.dist.on_zone_lane || self.last_match.is_none() {
            hmi.advice = self.advice(n.zone).unwrap_or(match n.zone.info.side {
                ClosureSide::Right => LaneAdvice::MoveLeft,
                ClosureSide::Left => LaneAdvice::MoveRight,
                ClosureSide::Unknown => LaneAdvice::None,
            });
        }
    }

    /// Side of the nearest open lane running the same way as the matched lane.
    fn advice(&self, zone: &WorkZone) -> Option<LaneAdvice> {
        let (map, own) = self.matched_lane()?;
        let m = self.last_match?;
        let p = own.point_at(own.along_of_station(m.position.station, m.position.forward))?;
        let open = |l: &&Lane| {
            l.id != own.id && l.may_contain(p, 12.0) && zone.lane(map.id, l.id).is_none()
        };
        let best = map
            .lanes()
            .iter()
            .filter(open)
            .filter_map(|l| {
                l.locate(p, Some(m.position.bearing_deg))
                    .map(|pos| (l, pos))
            })
            .filter(|(_, pos)| {
                same_way(pos.bearing_deg, m.position.bearing_deg) && pos.beyond <= 0.0
            })
            .filter(|(_, pos)| pos.lateral.abs() < 2.5 * pos.width.max(2.0))
            .min_by(|a, b| a.1.lateral.abs().total_cmp(&b.1.lateral.abs()))?;
        Some(if best.1.lateral > 0.0 {
            LaneAdvice::MoveRight
        } else {
            LaneAdvice::MoveLeft
        })
    }

    /// The matched lane and its model.
    fn matched_lane(&self) -> Option<(&LaneModel, &Lane)> {
        let m: LaneMatch = self.last_match?;
        let map = self.maps.slot(m.slot as usize)?;
        Some((map, map.lane(m.lane)?))
    }
}

/// True when two bearings differ by less than 45 degrees.
fn same_way(a: f32, b: f32) -> bool {
    crate::math::heading_diff(a, b) < 45.0
}

/// True when zone distance `a` should be shown rather than `b`.
fn closer(a: &ZoneDistance, b: &ZoneDistance) -> bool {
    let key = |d: &ZoneDistance| {
        if d.distance_m >= -d.length_m {
            d.distance_m
        } else {
            1.0e6 - d.distance_m
        }
    };
    key(a) < key(b)
}
