//! Building the HMI state from the stores, the last fix and the lane match.

use heapless::Vec;

use super::Obu;
use crate::alert::{
    self, Alert, AlertKind, AlertStage, HmiState, LaneAdvice, LaneInfo, Motion, PositionSource,
    ZoneState, ZoneView,
};
use crate::capacity::MAX_HMI_LANES;
use crate::distance::{zone_distance, ZoneDistance};
use crate::lane::{Lane, LaneKind, LaneModel, Speed, TravelDirection};
use crate::matcher::LaneMatch;
use crate::time::Instant;
use crate::zone::{ClosureSide, WorkZone};

/// Alerts gathered before arbitration.
pub(super) type AlertList = Vec<Alert, 16>;

/// A concerning zone with its distance and state.
#[derive(Clone, Copy)]
struct Nearest<'a> {
    zone: &'a WorkZone,
    dist: ZoneDistance,
    state: ZoneState,
}

/// What the scan of every concerning zone found.
#[derive(Default)]
struct Scan<'a> {
    /// The nearest zone (state and distance shown).
    nearest: Option<Nearest<'a>>,
    /// The nearest zone that closes a lane (closed lanes and advice shown). A TIM
    /// often sends the closure and the speed limit as two data frames of one place.
    closure: Option<Nearest<'a>>,
    /// The lowest limit of the zones the vehicle is in.
    in_force: Option<Speed>,
    /// The lowest limit of the zones ahead, and the distance to the nearest zone with it.
    ahead: Option<(Speed, f32)>,
}

impl<'a> Scan<'a> {
    fn add(&mut self, n: Nearest<'a>) {
        let l = n.zone.info.speed_limit;
        match n.state {
            ZoneState::InZone => {
                self.in_force = Some(self.in_force.map_or(l, |m| m.min_available(l)));
            }
            ZoneState::Approaching | ZoneState::Warning if l.mps().is_some() => {
                let d = n.dist.distance_m;
                let lower = |(m, md): (Speed, f32)| match (l.mps(), m.mps()) {
                    (Some(a), Some(b)) => a < b || (a == b && d < md),
                    _ => true,
                };
                if self.ahead.is_none_or(lower) {
                    self.ahead = Some((l, d));
                }
            }
            _ => {}
        }
        if n.zone.info.lane_closed && nearer(&n, self.closure.as_ref()) {
            self.closure = Some(n);
        }
        if nearer(&n, self.nearest.as_ref()) {
            self.nearest = Some(n);
        }
    }
}

/// True when `n` should be shown rather than `than`.
fn nearer(n: &Nearest<'_>, than: Option<&Nearest<'_>>) -> bool {
    than.is_none_or(|t| closer(&n.dist, &t.dist))
}

impl Obu {
    /// The display state at `now`.
    pub(super) fn evaluate(&self, now: Instant) -> HmiState {
        let position = self.position_source(now);
        let speed = self.threshold_speed(now, position);
        let mut hmi = self.base_state(now, position);
        let mut alerts = AlertList::new();
        let period_s = match position {
            PositionSource::Live => self.fix_period_ms as f32 / 1000.0,
            _ => super::ESTIMATE_PERIOD.as_secs_f32(),
        };
        let motion = Motion {
            speed_mps: speed,
            lookahead_m: self.config.lookahead_m(speed, period_s),
            was_urgent: self.was_urgent,
        };
        let travelled = match position {
            PositionSource::Live => 0.0,
            _ => self.travelled_m(now),
        };
        // The worker alerts go in first: the list is bounded, and a worker in the lane ahead
        // must never be the alert that did not fit.
        if position != PositionSource::Lost {
            let reach = self.config.warning_distance(speed) * self.config.approach_factor.max(1.0)
                + motion.lookahead_m;
            let workers = self.scan_workers(now, travelled, reach);
            workers.alerts(&mut alerts);
            hmi.workers = workers.sorted_views();
        }
        self.data_alerts(position, &mut alerts);
        let scan = self.zone_alerts(now, &motion, travelled, &mut alerts);
        self.fill_limit(&mut hmi, &scan, speed);
        if hmi.lane.is_some() {
            self.fill_road(&mut hmi);
        }
        if let Some(n) = &scan.nearest {
            hmi.zone_state = n.state;
            hmi.distance_m = Some(n.dist.distance_m);
        }
        if let Some(n) = &scan.closure {
            self.fill_closure(&mut hmi, n);
        }
        if position == PositionSource::Lost {
            forget_distances(&mut hmi, &mut alerts);
        }
        alert::arbitrate(alerts, &mut hmi);
        let zone_shown = matches!(
            hmi.zone_state,
            ZoneState::Approaching | ZoneState::Warning | ZoneState::InZone
        );
        let floor = if zone_shown {
            AlertStage::Information
        } else {
            AlertStage::None
        };
        hmi.stage = hmi.primary.map_or(floor, |a| a.stage.max(floor));
        hmi
    }

    fn base_state(&self, now: Instant, position: PositionSource) -> HmiState {
        let m = self.last_match.filter(|_| position != PositionSource::Lost);
        let shown = m.filter(|m| m.confidence >= self.config.matcher.show_percent());
        HmiState {
            time_ms: now.millis(),
            speed_mps: self.shown_speed(now, position),
            lane: shown.map(|m| LaneInfo {
                map: m.map.0,
                lane: m.lane.0,
            }),
            lane_confidence: m.map_or(0, |m| m.confidence),
            gnss_ok: position == PositionSource::Live,
            position,
            time_status: self.time_status,
            accuracy_source: match position {
                PositionSource::Live => self
                    .last_fix
                    .map_or_else(Default::default, |(_, f)| f.accuracy_source),
                _ => Default::default(),
            },
            roadside_data: !(self.maps.is_empty() && self.zones.is_empty()),
            maps: self.maps.len() as u8,
            zones: self.zones.len() as u8,
            unverified: (self.maps.unverified() + self.zones.unverified()) as u8,
            counters: self.counters(),
            ..HmiState::default()
        }
    }

    fn data_alerts(&self, position: PositionSource, out: &mut AlertList) {
        let plain = |kind, stage| Alert {
            kind,
            stage,
            distance_m: None,
            limit_mps: None,
        };
        if position != PositionSource::Live {
            let _ = out.push(plain(AlertKind::GnssStale, AlertStage::Information));
        }
        if self.maps.is_empty() && self.zones.is_empty() {
            let _ = out.push(plain(AlertKind::NoRoadsideData, AlertStage::None));
        } else if self.maps.is_empty() {
            let _ = out.push(plain(AlertKind::MapMissing, AlertStage::None));
        }
    }

    /// Alerts of every concerning zone, with distances from the last fix shortened by
    /// `travelled` metres (dead reckoning); returns what the scan found.
    fn zone_alerts(
        &self,
        now: Instant,
        motion: &Motion,
        travelled: f32,
        out: &mut AlertList,
    ) -> Scan<'_> {
        let mut scan = Scan::default();
        let Some(fix) = self.last_fix.map(|(_, f)| f) else {
            return scan;
        };
        let heading = self
            .last_match
            .map(|m| m.position.bearing_deg)
            .or(fix.course());
        let utc = self.utc_minutes(now);
        for zone in self.zones.iter() {
            let active = utc.map_or(!zone.validity.is_cancelled(), |m| {
                zone.validity.is_active(m)
            });
            if !active {
                continue;
            }
            let m = self.last_match.as_ref();
            let reach = self.config.zone_reach_m;
            let Some(mut dist) = zone_distance(zone, &self.maps, m, fix.position, heading, reach)
            else {
                continue;
            };
            // Dead reckoning never carries the car past the end of a zone it had not left
            // at the last fix: had it braked, it would still be there.
            let end = -dist.length_m.max(0.0);
            if dist.distance_m >= end {
                dist.distance_m = (dist.distance_m - travelled).max(end);
            }
            // An uncertain lane does not make the closure the driver's own: "lane closure
            // ahead" with the side to keep, not "your lane is closed".
            dist.on_zone_lane &= self.lane_sure();
            let state = alert::zone_state(&self.config, &dist, motion);
            if state == ZoneState::None {
                continue;
            }
            let view = ZoneView {
                info: &zone.info,
                distance: dist,
            };
            alert::zone_alerts(&self.config, &view, state, motion, out);
            scan.add(Nearest { zone, dist, state });
        }
        scan
    }

    /// Speed limits: in force, the lowest of the zones the vehicle is in and the lane's
    /// `maxSpeedInConstructionZone`, else the lane's limit where the vehicle is; ahead, the
    /// lowest limit of the zones ahead below that. Then the deceleration that limit needs
    /// and whether the speed calls for the driver.
    fn fill_limit(&self, hmi: &mut HmiState, scan: &Scan<'_>, speed: Option<f32>) {
        let limits = self
            .matched_lane()
            .map(|(_, l)| l.limits_at(self.last_match.map_or(0, |m| m.position.segment)));
        let lane_max = limits.and_then(|l| l.max.mps());
        let construction = limits.map_or(Speed::UNAVAILABLE, |l| l.construction_max);
        let zone_limit = scan
            .in_force
            .and_then(|z| z.min_available(construction).mps());
        let in_force = zone_limit.or(lane_max);
        hmi.speed_limit_mps = in_force;
        hmi.reduced_limit = zone_limit.is_some_and(|z| lane_max.is_none_or(|l| z < l));
        if let Some((limit, at)) = scan.ahead {
            let ahead = limit.min_available(construction).mps();
            if let Some(l) = ahead.filter(|l| in_force.is_none_or(|f| *l < f)) {
                hmi.limit_ahead_mps = Some(l);
                hmi.limit_ahead_m = Some(at);
                let allowed = l + self.config.overspeed_tolerance_mps;
                hmi.decel_needed_mps2 = alert::decel_needed(speed, Some(allowed), at);
            }
        }
        let over = match (hmi.speed_mps, in_force) {
            (Some(v), Some(l)) => v > l + self.config.overspeed_tolerance_mps,
            _ => false,
        };
        let too_hard = hmi
            .decel_needed_mps2
            .is_some_and(|a| a > self.config.comfortable_decel_mps2);
        hmi.speed_alarm = over || too_hard;
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
        if n.dist.on_zone_lane || !self.lane_sure() {
            hmi.advice = self.advice(n.zone).unwrap_or(match n.zone.info.side {
                ClosureSide::Right => LaneAdvice::MoveLeft,
                ClosureSide::Left => LaneAdvice::MoveRight,
                ClosureSide::Unknown => LaneAdvice::None,
            });
        }
    }

    /// Side of the nearest open lane running the same way as the matched lane, from the
    /// lanes the matcher located the fix on ([`crate::matcher::Matcher::nearby`]). Their
    /// offset from the own centreline is the fix's offset from theirs minus its offset
    /// from the own lane (parallel lanes).
    fn advice(&self, zone: &WorkZone) -> Option<LaneAdvice> {
        let m = self.last_match?;
        let own = m.position.lateral;
        let best = self
            .matcher
            .nearby()
            .iter()
            .filter(|n| n.slot == m.slot && n.lane != m.lane && n.within())
            .filter(|n| zone.lane(m.map, n.lane).is_none())
            .filter(|n| same_way(n.position.bearing_deg, m.position.bearing_deg))
            .map(|n| (n.position.lateral - own, n.position.width))
            .filter(|(offset, width)| offset.abs() < 2.5 * width.max(2.0))
            .min_by(|a, b| a.0.abs().total_cmp(&b.0.abs()))?;
        Some(if best.0 > 0.0 {
            LaneAdvice::MoveRight
        } else {
            LaneAdvice::MoveLeft
        })
    }

    /// The road at the vehicle, left to right ([`HmiState::road_lanes`]): the matched
    /// lane and the vehicle lanes of its map whose centreline runs the same way within
    /// [`ROAD_REACH_M`] beside the fix (and not beyond their ends); the nearest ones
    /// when there are more than the display holds.
    fn fill_road(&self, hmi: &mut HmiState) {
        let (Some(m), Some((map, _))) = (self.last_match, self.matched_lane()) else {
            return;
        };
        let Some((_, fix)) = self.last_fix else {
            return;
        };
        let p = map.frame().to_local(fix.position);
        let own = m.position;
        let mut road: Vec<(f32, u8), MAX_HMI_LANES> = Vec::new();
        for lane in map.lanes() {
            if !matches!(lane.kind, LaneKind::Vehicle) || lane.direction == TravelDirection::None {
                continue;
            }
            let offset = if lane.id == m.lane {
                0.0
            } else {
                if !lane.may_contain(p, ROAD_REACH_M) {
                    continue;
                }
                let Some(pos) = lane.locate(p, Some(own.bearing_deg)) else {
                    continue;
                };
                let beside = pos.beyond < 1.0 && same_way(pos.bearing_deg, own.bearing_deg);
                let offset = pos.lateral - own.lateral;
                if !beside || offset.is_nan() || offset.abs() >= ROAD_REACH_M {
                    continue;
                }
                offset
            };
            keep_nearest(&mut road, (offset, lane.id.0));
        }
        crate::math::sort_small_by(&mut road, |a, b| a.0.total_cmp(&b.0));
        hmi.road_lanes = road.iter().map(|&(_, id)| id).collect();
    }

    /// True when the matched lane is probable enough to be named to the driver.
    fn lane_sure(&self) -> bool {
        self.last_match
            .is_some_and(|m| m.confidence >= self.config.matcher.show_percent())
    }

    /// The matched lane and its model.
    pub(super) fn matched_lane(&self) -> Option<(&LaneModel, &Lane)> {
        let m: LaneMatch = self.last_match?;
        let map = self.maps.slot(m.slot as usize)?;
        Some((map, map.lane(m.lane)?))
    }
}

/// How far beside the vehicle lanes count as its road, metres (about five lanes).
pub const ROAD_REACH_M: f32 = 20.0;

/// Adds `lane` (offset, id) to `road`; when full, it replaces the farthest lane if nearer.
fn keep_nearest(road: &mut Vec<(f32, u8), MAX_HMI_LANES>, lane: (f32, u8)) {
    if road.iter().any(|l| l.1 == lane.1) {
        return;
    }
    if let Err(lane) = road.push(lane) {
        let far = road
            .iter_mut()
            .max_by(|a, b| a.0.abs().total_cmp(&b.0.abs()));
        if let Some(far) = far.filter(|f| f.0.abs() > lane.0.abs()) {
            *far = lane;
        }
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

/// Without a position ("position lost"), the known zones stay shown but no distance is
/// claimed and no alert is more than a warning: compliance cannot be judged.
fn forget_distances(hmi: &mut HmiState, alerts: &mut AlertList) {
    hmi.distance_m = None;
    hmi.limit_ahead_m = None;
    hmi.decel_needed_mps2 = None;
    hmi.speed_alarm = false;
    hmi.advice = LaneAdvice::None;
    for a in alerts.iter_mut() {
        a.distance_m = None;
        a.stage = a.stage.min(AlertStage::Warning);
    }
}
