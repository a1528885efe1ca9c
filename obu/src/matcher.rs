//! Lane matcher: GNSS fix -> lane, station, lateral offset and confidence.
//!
//! Per fix every lane near the position is a candidate when the lateral offset is
//! within half the lane width plus a tolerance, the position is within the lane's
//! extent (plus a tolerance) and the course is within the heading gate of the lane's
//! travel direction. The best candidate (smallest offset relative to half width) wins,
//! but a new lane replaces the current one only after it has been best for a hold time
//! and a number of fixes (hysteresis). Below a low speed the course is unreliable: the
//! last good heading is frozen and the gate loosened.

use heapless::Vec;

mod along;
mod belief;
mod filter;
mod kalman;
mod road;
mod settings;

pub use filter::{FilterConfig, LaneFilter};

use crate::capacity::MAX_NEARBY_LANES;
use crate::fix::Fix;
use crate::lane::{Lane, LaneId, LaneKind, LanePosition, MapId, MapStore, TravelDirection};
use crate::math::{heading_diff, normal_cdf};
use crate::time::{Duration, Instant};

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// Largest fix error the matcher takes at its word, metres.
pub(crate) const MAX_SIGMA_M: f32 = 100.0;

/// Largest distance from a map reference considered, metres.
const MAX_MAP_RANGE_M: f32 = 20_000.0;

/// How the lane shown is decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub enum LaneMethod {
    /// The lane filter ([`LaneFilter`]): a lateral track and a belief over the road's
    /// lanes, over many fixes.
    #[default]
    Filter,
    /// Each fix on its own (nearest lane within the tolerances) with hold-time and
    /// fix-count hysteresis, as deployed matchers do; kept to compare against.
    PerFix,
}

/// Matcher thresholds.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct MatcherConfig {
    /// How the lane shown is decided.
    pub method: LaneMethod,
    /// Lane filter settings ([`LaneMethod::Filter`]).
    pub filter: FilterConfig,
    /// Heading gate at normal speed, degrees (45, as deployed matchers use).
    pub heading_gate_deg: f32,
    /// Heading gate below `low_speed_mps`, degrees.
    pub loose_gate_deg: f32,
    /// Speed below which the course is frozen, m/s.
    pub low_speed_mps: f32,
    /// Added to half the lane width before a position is off the lane, metres.
    pub lateral_tolerance_m: f32,
    /// Extra lateral room within which the current lane is still held (not newly
    /// matched) while a challenger waits out the hold, metres.
    pub hold_lateral_m: f32,
    /// How far beyond a lane's end a position still matches it, metres.
    pub end_tolerance_m: f32,
    /// A new lane must be best for this long before it replaces the current one.
    pub hold: Duration,
    /// ... and for this many consecutive fixes.
    pub hold_fixes: u8,
    /// Accuracy assumed when the fix has none, metres (1 sigma).
    pub default_accuracy_m: f32,
    /// Below this confidence (percent) the HMI does not name the lane
    /// ([`LaneMethod::PerFix`]; the filter has [`FilterConfig::show_percent`]).
    pub min_confidence: u8,
}

impl Default for MatcherConfig {
    fn default() -> Self {
        MatcherConfig::DEFAULT
    }
}

impl MatcherConfig {
    /// The documented defaults (45 degree gate, 300 ms and 3 fixes hold, ...).
    pub const DEFAULT: MatcherConfig = MatcherConfig {
        method: LaneMethod::Filter,
        filter: FilterConfig::DEFAULT,
        heading_gate_deg: 45.0,
        loose_gate_deg: 90.0,
        low_speed_mps: 1.0,
        lateral_tolerance_m: 0.5,
        hold_lateral_m: 1.5,
        end_tolerance_m: 5.0,
        hold: Duration::from_millis(300),
        hold_fixes: 3,
        default_accuracy_m: 1.5,
        min_confidence: 50,
    };

    /// The per-fix matcher of earlier releases, for comparison.
    pub const PER_FIX: MatcherConfig = MatcherConfig {
        method: LaneMethod::PerFix,
        ..MatcherConfig::DEFAULT
    };

    /// The confidence (percent) a lane needs before the HMI names it.
    pub fn show_percent(&self) -> u8 {
        match self.method {
            LaneMethod::Filter => self.filter.show_percent,
            LaneMethod::PerFix => self.min_confidence,
        }
    }
}

/// The lane a fix was matched to.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LaneMatch {
    /// Lane model.
    pub map: MapId,
    /// Slot of the model in the [`MapStore`].
    pub slot: u8,
    /// Lane.
    pub lane: LaneId,
    /// Position on the lane in its direction of travel.
    pub position: LanePosition,
    /// Confidence that the vehicle is in this lane, percent.
    pub confidence: u8,
}

/// A candidate during one update.
#[derive(Clone, Copy)]
struct Candidate {
    m: LaneMatch,
    score: f32,
    /// Passes the normal lateral tolerance (not only the hold room).
    strict: bool,
}

/// Gating inputs of one update.
struct Gate {
    heading: Option<f32>,
    gate: f32,
    sigma: f32,
    extra: f32,
}

/// A vehicle lane the last fix was located on (whether or not it matched): what the
/// lane-change advice needs, without projecting the fix again.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NearbyLane {
    /// Slot of the lane model in the [`MapStore`].
    pub slot: u8,
    /// Lane.
    pub lane: LaneId,
    /// The fix's position on the lane.
    pub position: LanePosition,
}

impl NearbyLane {
    /// True when the fix lies within the lane's extent (not beyond an end).
    pub fn within(&self) -> bool {
        self.position.beyond <= 0.0
    }
}

/// Lane matcher state (the lane filter, or the hysteresis; frozen heading).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Matcher {
    filter: LaneFilter,
    /// The map the filter's road is on.
    filter_map: Option<MapId>,
    /// The lane last shown with enough confidence (for the switch count).
    shown: Option<(MapId, LaneId)>,
    /// The filter's last match and its time (an outlier fix carries it on).
    last: Option<(Instant, LaneMatch)>,
    /// The station along the lane, filtered.
    along: along::AlongTrack,
    /// Fixes the along-track gate rejected.
    along_outliers: u32,
    current: Option<(MapId, LaneId)>,
    challenger: Option<(MapId, LaneId, Instant, u8)>,
    frozen_heading: Option<f32>,
    switches: u32,
    nearby: Vec<NearbyLane, MAX_NEARBY_LANES, u8>,
}

impl Matcher {
    /// A matcher with no history.
    pub const fn new() -> Self {
        Matcher {
            filter: LaneFilter::new(),
            filter_map: None,
            shown: None,
            last: None,
            along: along::AlongTrack::new(),
            along_outliers: 0,
            current: None,
            challenger: None,
            frozen_heading: None,
            switches: 0,
            nearby: Vec::new(),
        }
    }

    /// The vehicle lanes the last fix was located on (the first
    /// [`MAX_NEARBY_LANES`]): every lane whose box, widened by its own half width, the
    /// lateral tolerances and the end tolerance, holds the fix.
    pub fn nearby(&self) -> &[NearbyLane] {
        &self.nearby
    }

    /// Number of lane switches so far (for counters).
    pub fn switches(&self) -> u32 {
        self.switches
    }

    /// Fixes the lane filter rejected as outliers (innovation gates across and along the
    /// road) so far.
    pub fn outliers(&self) -> u32 {
        self.filter.outliers().saturating_add(self.along_outliers)
    }

    /// Forgets the current lane (e.g. after a GNSS outage).
    pub fn reset(&mut self) {
        self.filter.reset();
        self.filter_map = None;
        self.shown = None;
        self.last = None;
        self.along.reset();
        self.current = None;
        self.challenger = None;
        self.nearby.clear();
    }

    /// Heading to gate with and the gate width, from the fix and frozen state.
    fn heading(&mut self, fix: &Fix, cfg: &MatcherConfig) -> (Option<f32>, f32) {
        let moving = fix.speed().is_none_or(|v| v >= cfg.low_speed_mps);
        match (moving, fix.course()) {
            (true, Some(c)) => {
                self.frozen_heading = Some(c);
                (Some(c), cfg.heading_gate_deg)
            }
            _ => (self.frozen_heading, cfg.loose_gate_deg),
        }
    }

    /// Matches one fix; `None` means off-map.
    pub fn update(
        &mut self,
        now: Instant,
        fix: &Fix,
        maps: &MapStore,
        cfg: &MatcherConfig,
    ) -> Option<LaneMatch> {
        let (heading, gate) = self.heading(fix, cfg);
        // A receiver's figure beyond 100 m says "no idea"; larger values would only
        // overflow the filters' arithmetic.
        let sigma = crate::math::clamp(
            fix.accuracy().unwrap_or(cfg.default_accuracy_m),
            0.05,
            MAX_SIGMA_M,
        );
        if cfg.method == LaneMethod::Filter {
            return self.filter_update(now, fix, maps, cfg, (heading, gate), sigma);
        }
        self.nearby.clear();
        let mut best: Option<Candidate> = None;
        let mut current: Option<Candidate> = None;
        for (slot, map) in maps.iter() {
            let p = map.frame().to_local(fix.position);
            if !(p.x.abs() < MAX_MAP_RANGE_M && p.y.abs() < MAX_MAP_RANGE_M) {
                continue;
            }
            for lane in map.lanes() {
                let is_current = self.current == Some((map.id, lane.id));
                let extra = if is_current { cfg.hold_lateral_m } else { 0.0 };
                let g = Gate {
                    heading,
                    gate,
                    sigma,
                    extra,
                };
                let Some(pos) = locate(lane, p, &g, cfg) else {
                    continue;
                };
                self.record(slot, lane.id, &pos);
                let Some(c) = candidate(lane.id, &pos, &g, cfg) else {
                    continue;
                };
                let c = Candidate {
                    m: LaneMatch {
                        map: map.id,
                        slot: slot as u8,
                        ..c.m
                    },
                    ..c
                };
                if is_current {
                    current = Some(c);
                }
                if c.strict && best.as_ref().is_none_or(|b| c.score < b.score) {
                    best = Some(c);
                }
            }
        }
        self.decide(now, best, current, cfg)
    }

    /// Keeps a located lane for [`Matcher::nearby`] (dropped when full).
    fn record(&mut self, slot: usize, lane: LaneId, pos: &LanePosition) {
        let _ = self.nearby.push(NearbyLane {
            slot: slot as u8,
            lane,
            position: *pos,
        });
    }

    /// Applies hysteresis between the best candidate and the current lane.
    fn decide(
        &mut self,
        now: Instant,
        best: Option<Candidate>,
        current: Option<Candidate>,
        cfg: &MatcherConfig,
    ) -> Option<LaneMatch> {
        let Some(best) = best.or(current) else {
            self.reset();
            return None;
        };
        let key = (best.m.map, best.m.lane);
        let Some(cur) = current else {
            self.switch_to(key);
            return Some(best.m);
        };
        if self.current == Some(key) {
            self.challenger = None;
            return Some(cur.m);
        }
        if self.challenger_ready(now, key, cfg) {
            self.switch_to(key);
            return Some(best.m);
        }
        Some(LaneMatch {
            confidence: cur.m.confidence.min(50),
            ..cur.m
        })
    }

    /// Tracks the challenger; true once it has held long enough.
    fn challenger_ready(
        &mut self,
        now: Instant,
        key: (MapId, LaneId),
        cfg: &MatcherConfig,
    ) -> bool {
        let (since, count) = match self.challenger {
            Some((m, l, since, n)) if (m, l) == key => (since, n.saturating_add(1)),
            _ => (now, 1),
        };
        self.challenger = Some((key.0, key.1, since, count));
        count >= cfg.hold_fixes && now.saturating_since(since) >= cfg.hold
    }

    fn switch_to(&mut self, key: (MapId, LaneId)) {
        if self.current.is_some() && self.current != Some(key) {
            self.switches = self.switches.saturating_add(1);
        }
        self.current = Some(key);
        self.challenger = None;
    }
}

/// The position on a vehicle lane whose box (widened by what the gates allow) holds
/// `p`. A point that passes the gates lies within half the lane width plus the lateral
/// room of the centreline, or within the end tolerance beyond an end, so within
/// `hypot(room, end tolerance)` of the box on either axis.
fn locate(
    lane: &Lane,
    p: crate::geo::Point,
    g: &Gate,
    cfg: &MatcherConfig,
) -> Option<LanePosition> {
    if lane.direction == TravelDirection::None || !matches!(lane.kind, LaneKind::Vehicle) {
        return None;
    }
    let room = lane.max_width() * 0.5 + cfg.lateral_tolerance_m + g.extra;
    let end = cfg.end_tolerance_m;
    let margin = libm::sqrtf(room * room + end * end);
    if !lane.may_contain(p, margin) {
        return None;
    }
    lane.locate(p, g.heading)
}

/// The candidate for one located lane, if the position and heading fit it.
fn candidate(lane: LaneId, pos: &LanePosition, g: &Gate, cfg: &MatcherConfig) -> Option<Candidate> {
    let pos = *pos;
    let half = pos.width * 0.5;
    let room = half + cfg.lateral_tolerance_m;
    if pos.beyond > cfg.end_tolerance_m || pos.lateral.abs() > room + g.extra {
        return None;
    }
    let diff = g.heading.map_or(0.0, |h| heading_diff(h, pos.bearing_deg));
    if diff > g.gate {
        return None;
    }
    let score = pos.lateral.abs() / half.max(0.1) + pos.beyond * 0.1 + diff / 180.0;
    let confidence = confidence(pos.lateral, half, g.sigma, g.heading.is_some());
    let m = LaneMatch {
        map: MapId(0),
        slot: 0,
        lane,
        position: pos,
        confidence,
    };
    Some(Candidate {
        m,
        score,
        strict: pos.lateral.abs() <= room,
    })
}

/// Probability (percent) that the true position lies within the lane, given the
/// measured lateral offset and a 1-sigma error; discounted without a heading.
fn confidence(lateral: f32, half: f32, sigma: f32, has_heading: bool) -> u8 {
    let p = normal_cdf((half - lateral) / sigma) - normal_cdf((-half - lateral) / sigma);
    let p = if has_heading { p } else { p * 0.8 };
    crate::math::clamp(p * 100.0, 0.0, 100.0) as u8
}

#[cfg(test)]
mod tests;
