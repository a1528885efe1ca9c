//! The matcher with the lane filter ([`LaneMethod::Filter`]): every lane of the road near
//! the fix is a candidate, the filter decides.

use heapless::Vec;

use super::filter::{Candidate, Observation};
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
        let map = self.pick_map(&road);
        if map != self.filter_map {
            self.filter.reset();
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
        let Some(best) = verdict.best.and_then(|i| lanes.get(i)) else {
            self.last = None;
            self.current = None;
            return None;
        };
        let key = (best.map, best.lane);
        let percent = verdict.percent;
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
            position: best.position,
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
