//! The matcher with the lane filter ([`LaneMethod::Filter`]): every lane of the road near
//! the fix is a candidate, the filter decides.

use heapless::Vec;

use super::along::{AlongConfig, AlongFix};
use super::filter::{Candidate, FilterConfig, Observation};
use super::{locate, Gate, LaneMatch, LaneMethod, Matcher, MatcherConfig, MAX_MAP_RANGE_M};
use crate::capacity::MAX_NEARBY_LANES;
use crate::fix::Fix;
use crate::lane::{LaneId, LanePosition, MapId, MapStore};
use crate::math::{clamp, heading_diff};
use crate::time::Instant;

/// A lane of the road this fix may be on.
#[derive(Clone, Copy)]
struct OnRoad {
    slot: u8,
    map: MapId,
    lane: LaneId,
    position: LanePosition,
}

impl Matcher {
    /// One fix through the lane filter; `None` when "off the mapped road" is the most
    /// probable or no lane of any map is near.
    pub(super) fn filter_update(
        &mut self,
        now: Instant,
        fix: &Fix,
        maps: &MapStore,
        cfg: &MatcherConfig,
        (heading, gate): (Option<f32>, f32),
        sigma: f32,
    ) -> Option<LaneMatch> {
        debug_assert_eq!(cfg.method, LaneMethod::Filter);
        // Lanes a few sigmas away are still candidates: the filter weighs them.
        let room = clamp(3.0 * sigma, 1.5, 8.0);
        let g = Gate {
            heading,
            gate,
            sigma,
            extra: room,
        };
        self.nearby.clear();
        let mut road: Vec<OnRoad, MAX_NEARBY_LANES> = Vec::new();
        for (slot, map) in maps.iter() {
            let p = map.frame().to_local(fix.position);
            if !(p.x.abs() < MAX_MAP_RANGE_M && p.y.abs() < MAX_MAP_RANGE_M) {
                continue;
            }
            for lane in map.lanes() {
                let Some(pos) = locate(lane, p, &g, cfg) else {
                    continue;
                };
                self.record(slot, lane.id, &pos);
                let lateral_room = 0.5 * pos.width + cfg.lateral_tolerance_m + room;
                let fits = pos.beyond <= cfg.end_tolerance_m
                    && pos.lateral.abs() <= lateral_room
                    && heading.is_none_or(|h| heading_diff(h, pos.bearing_deg) <= gate);
                if fits {
                    let _ = road.push(OnRoad {
                        slot: slot as u8,
                        map: map.id,
                        lane: lane.id,
                        position: pos,
                    });
                }
            }
        }
        // No lane near at all: the filter's road stays (its gate judges the fix).
        let map = self.pick_map(&road).or(self.filter_map);
        if map != self.filter_map {
            self.filter.reset();
            self.along.reset();
            self.filter_map = map;
        }
        let on_map = |r: &&OnRoad| Some(r.map) == map;
        let lanes: Vec<OnRoad, MAX_NEARBY_LANES> = road.iter().filter(on_map).copied().collect();
        let cands: Vec<Candidate, MAX_NEARBY_LANES> = lanes
            .iter()
            .map(|r| Candidate {
                lane: r.lane,
                lateral: r.position.lateral,
                width: r.position.width,
                bearing_deg: r.position.bearing_deg,
            })
            .collect();
        let obs = Observation {
            sigma_m: sigma,
            speed_mps: fix.speed(),
            course_deg: fix.course(),
        };
        let verdict = self.filter.update(now, &cands, &obs, &cfg.filter);
        if verdict.outlier {
            if let Some(m) = self.carried(now, fix) {
                return Some(m);
            }
        }
        // Off the road only when the belief says so and the fix is more than a few metres
        // beyond the lane: a short excursion of noisy fixes keeps the road (its lane then
        // unnamed, its zones judged).
        let best = verdict.best.and_then(|i| lanes.get(i)).filter(|b| {
            let beyond = b.position.lateral.abs() - 0.5 * b.position.width;
            verdict.off_road_percent <= verdict.percent || beyond <= cfg.filter.keep_road_m
        });
        let Some(best) = best else {
            self.last = None;
            self.along.reset();
            self.current = None;
            return None;
        };
        let key = (best.map, best.lane);
        let previous = self.along.key();
        let along = AlongFix {
            key,
            station: best.position.station,
            station_on_previous: previous.and_then(|(m, l)| {
                lanes
                    .iter()
                    .find(|r| (r.map, r.lane) == (m, l))
                    .map(|r| r.position.station)
            }),
            speed: fix.speed(),
            sigma,
        };
        let Some(station) = self.along.update(now, &along, &along_config(&cfg.filter)) else {
            // A jump along the road: the last match moved on stands for this fix.
            self.along_outliers = self.along_outliers.saturating_add(1);
            if let Some(m) = self.carried(now, fix) {
                return Some(m);
            }
            return None;
        };
        let mut position = best.position;
        position.station = station;
        let percent = if verdict.off_road_percent > verdict.percent {
            0
        } else {
            verdict.percent
        };
        if percent >= cfg.filter.show_percent {
            if self.shown.is_some_and(|s| s != key) {
                self.switches = self.switches.saturating_add(1);
            }
            self.shown = Some(key);
        }
        self.current = Some(key);
        let m = LaneMatch {
            map: best.map,
            slot: best.slot,
            lane: best.lane,
            position,
            confidence: percent,
        };
        self.last = Some((now, m));
        Some(m)
    }

    /// The last match moved on along its lane by the fix's speed: what an outlier fix is
    /// replaced with.
    fn carried(&mut self, now: Instant, fix: &Fix) -> Option<LaneMatch> {
        let (at, mut m) = self.last?;
        let dt = now.saturating_since(at).as_secs_f32();
        m.position.station += fix.speed().unwrap_or(0.0) * dt;
        self.last = Some((now, m));
        Some(m)
    }

    /// The map of the road: the filter's while it has a lane near the fix, else the one
    /// whose lane lies nearest (relative to its half width).
    fn pick_map(&self, road: &[OnRoad]) -> Option<MapId> {
        if let Some(m) = self.filter_map.filter(|m| road.iter().any(|r| r.map == *m)) {
            return Some(m);
        }
        let rel = |r: &OnRoad| r.position.lateral.abs() / (0.5 * r.position.width).max(0.5);
        road.iter()
            .min_by(|a, b| rel(a).total_cmp(&rel(b)))
            .map(|r| r.map)
    }
}

/// The along-track filter's settings from the lane filter's.
fn along_config(f: &FilterConfig) -> AlongConfig {
    AlongConfig {
        accel_mps2: f.along_accel_mps2,
        speed_sigma_mps: f.speed_sigma_mps,
        gate_sigma: f.gate_sigma,
        restart_after: f.restart_after,
        max_gap_ms: f.max_gap_ms,
    }
}
