//! The matcher with the lane filter ([`LaneMethod::Filter`]): every lane of the road near
//! the fix is a candidate, the filter decides.

use heapless::Vec;

use super::along::{AlongConfig, AlongFix};
use super::filter::{Candidate, FilterConfig, Observation, Verdict};
use super::{locate, Gate, LaneMatch, LaneMethod, Matcher, MatcherConfig, MAX_MAP_RANGE_M};
use crate::capacity::MAX_NEARBY_LANES;
use crate::fix::Fix;
use crate::lane::{LaneId, LanePosition, MapId, MapStore};
use crate::math::{clamp, heading_diff};
use crate::time::Instant;

/// Lanes more than this apart in bearing are not one road's (degrees).
const SAME_WAY_DEG: f32 = 45.0;

/// A lane of the road this fix may be on.
#[derive(Clone, Copy)]
struct OnRoad {
    slot: u8,
    map: MapId,
    lane: LaneId,
    position: LanePosition,
}

impl OnRoad {
    /// Offset from the centreline relative to half the lane width (nearer is smaller).
    fn nearness(&self) -> f32 {
        self.position.lateral.abs() / (0.5 * self.position.width).max(0.5)
    }
}

type Road = Vec<OnRoad, MAX_NEARBY_LANES>;

impl Matcher {
    /// One fix through the lane filter. `None` when no lane of any map is near and none
    /// is carried over an outlier, or when "off the mapped road" is the most probable and
    /// the fix lies more than [`FilterConfig::keep_road_m`] beyond the nearest lane.
    pub(super) fn filter_update(
        &mut self,
        now: Instant,
        fix: &Fix,
        maps: &MapStore,
        cfg: &MatcherConfig,
        heading: (Option<f32>, f32),
        sigma: f32,
    ) -> Option<LaneMatch> {
        debug_assert_eq!(cfg.method, LaneMethod::Filter);
        let road = self.collect_road(fix, maps, cfg, heading, sigma);
        // No lane near at all: the filter's road stays (its gate judges the fix).
        let map = self.pick_map(&road).or(self.filter_map);
        if map != self.filter_map {
            self.filter.reset();
            self.along.reset();
            self.filter_map = map;
        }
        let lanes = one_way(&road, map, self.filter.anchor());
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
            if let Some(m) = self.carried(now, fix, maps) {
                return Some(m);
            }
        }
        let Some(best) = on_road(&verdict, &lanes, &cfg.filter) else {
            self.last = None;
            self.along.reset();
            self.current = None;
            return None;
        };
        self.place(now, fix, maps, cfg, (best, &lanes), &verdict, sigma)
    }

    /// The vehicle lanes of every map near the fix within the heading gate (the nearest
    /// [`MAX_NEARBY_LANES`] when more), recording each located lane for
    /// [`Matcher::nearby`].
    fn collect_road(
        &mut self,
        fix: &Fix,
        maps: &MapStore,
        cfg: &MatcherConfig,
        (heading, gate): (Option<f32>, f32),
        sigma: f32,
    ) -> Road {
        // Lanes a few sigmas away are still candidates: the filter weighs them.
        let room = clamp(3.0 * sigma, 1.5, 8.0);
        let g = Gate {
            heading,
            gate,
            sigma,
            extra: room,
        };
        self.nearby.clear();
        let mut road = Road::new();
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
                    keep_nearest(
                        &mut road,
                        OnRoad {
                            slot: slot as u8,
                            map: map.id,
                            lane: lane.id,
                            position: pos,
                        },
                    );
                }
            }
        }
        road
    }

    /// The match for `best`: its station through the along-track filter, its confidence
    /// from the verdict; counts a change of the lane shown.
    #[allow(clippy::too_many_arguments)]
    fn place(
        &mut self,
        now: Instant,
        fix: &Fix,
        maps: &MapStore,
        cfg: &MatcherConfig,
        (best, lanes): (&OnRoad, &[OnRoad]),
        verdict: &Verdict,
        sigma: f32,
    ) -> Option<LaneMatch> {
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
            return self.carried(now, fix, maps);
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
    /// replaced with (while its lane model is still stored).
    fn carried(&mut self, now: Instant, fix: &Fix, maps: &MapStore) -> Option<LaneMatch> {
        let (at, mut m) = self.last?;
        if maps.slot(m.slot as usize).is_none_or(|map| map.id != m.map) {
            self.last = None;
            return None;
        }
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
        road.iter()
            .min_by(|a, b| a.nearness().total_cmp(&b.nearness()))
            .map(|r| r.map)
    }
}

/// Adds `lane` to `road`; when full, it replaces the farthest lane if it is nearer.
fn keep_nearest(road: &mut Road, lane: OnRoad) {
    if let Err(lane) = road.push(lane) {
        let far = road
            .iter_mut()
            .max_by(|a, b| a.nearness().total_cmp(&b.nearness()));
        if let Some(far) = far.filter(|f| f.nearness() > lane.nearness()) {
            *far = lane;
        }
    }
}

/// The lanes of `map` that run one way: within [`SAME_WAY_DEG`] of the anchor lane's
/// bearing, else of the nearest lane's. Without a course every direction passes the heading
/// gate; the filter's frame needs parallel lanes of one direction.
fn one_way(road: &[OnRoad], map: Option<MapId>, anchor: Option<LaneId>) -> Road {
    let on_map = || road.iter().filter(|r| Some(r.map) == map);
    let reference = on_map()
        .find(|r| Some(r.lane) == anchor)
        .or_else(|| on_map().min_by(|a, b| a.nearness().total_cmp(&b.nearness())))
        .map(|r| r.position.bearing_deg);
    on_map()
        .filter(|r| {
            reference.is_some_and(|b| heading_diff(b, r.position.bearing_deg) < SAME_WAY_DEG)
        })
        .copied()
        .collect()
}

/// The lane the verdict places the fix on, unless "off the mapped road" is the most probable
/// and the fix lies more than a few metres beyond it: a short excursion of noisy fixes keeps
/// the road (its lane then unnamed, its zones judged).
fn on_road<'a>(verdict: &Verdict, lanes: &'a [OnRoad], f: &FilterConfig) -> Option<&'a OnRoad> {
    verdict.best.and_then(|i| lanes.get(i)).filter(|b| {
        let beyond = b.position.lateral.abs() - 0.5 * b.position.width;
        verdict.off_road_percent <= verdict.percent || beyond <= f.keep_road_m
    })
}

/// The along-track filter's settings from the lane filter's.
fn along_config(f: &FilterConfig) -> AlongConfig {
    AlongConfig {
        accel_mps2: f.along_accel_mps2,
        speed_sigma_mps: f.speed_sigma_mps,
        gate_sigma: f.gate_sigma,
        restart_after: f.restart_after,
        max_gap_ms: f.max_gap_ms,
        min_sigma_m: super::filter::MIN_SIGMA_M,
    }
}
