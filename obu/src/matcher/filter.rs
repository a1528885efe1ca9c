//! Lane filter: which lane of the road the car is in, from a run of noisy fixes.
//!
//! Two parts, both in fixed memory:
//! * **Lateral track** (Kalman filter): the car's offset from an anchor lane's centreline
//!   and its rate, predicted with a constant-rate model (lateral acceleration as process
//!   noise), updated with the fix's offset weighted by its reported accuracy and with the
//!   lateral rate its course and speed imply. An innovation gate rejects outliers
//!   (multipath jumps) and counts them; a run of rejections restarts the track (the
//!   receiver really moved, or its bias stepped).
//! * **Lane belief** (forward algorithm of a hidden Markov model): a probability for each
//!   candidate lane of the road (same map, same direction, within the extent) and for "off
//!   the mapped road". A step moves belief to the neighbouring lane in proportion to the
//!   tracked lateral rate towards it; the fix's offset then weighs each lane by how likely
//!   it is from a position anywhere across that lane's width (from the MAP) blurred by the
//!   fix's error. Fix errors of real receivers are correlated over seconds (a wandering
//!   bias), so each fix counts with a weight below one ([`FilterConfig::evidence_weight`])
//!   rather than as independent evidence.
//!
//! The lane shown is the most probable one once its probability reaches
//! [`FilterConfig::show_percent`]; below that the road stays known but the lane is not
//! named. No fix count or hold time decides a lane change.

use heapless::Vec;

use super::kalman;
use crate::capacity::MAX_NEARBY_LANES;
use crate::lane::LaneId;
use crate::math::{clamp, normal_cdf};
use crate::time::Instant;

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// The smallest fix error the filter assumes, metres: a receiver's own figure below it
/// (an RTK fix, a noiseless simulation) would make every lateral manoeuvre an outlier.
pub(super) const MIN_SIGMA_M: f32 = 0.25;

/// Time constant of the learnt white error, seconds.
const SCATTER_TIME_S: f32 = 3.0;

/// Belief in "off the mapped road" when a road is first met.
const START_OFF_ROAD: f32 = 0.05;

/// Lane filter settings.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct FilterConfig {
    /// Probability (percent) the most probable lane needs before it is shown.
    pub show_percent: u8,
    /// Lateral acceleration the track allows (process noise), m/s².
    pub lateral_accel_mps2: f32,
    /// Error of the receiver's course, degrees (1 sigma): the lateral rate it implies.
    pub course_sigma_deg: f32,
    /// Weight of one fix's evidence (0..1): fixes' errors are correlated over seconds.
    pub evidence_weight: f32,
    /// Probability per second of a lane change with no lateral motion seen.
    pub change_per_s: f32,
    /// Innovation gate, sigmas: a fix farther from the track is an outlier.
    pub gate_sigma: f32,
    /// This many outliers in a row restart the track at the fix.
    pub restart_after: u8,
    /// Transition rate per lateral speed towards a neighbour: lane widths per second of
    /// lateral motion, times this, is the rate of moving belief there.
    pub rate_gain: f32,
    /// Probability per second of leaving the mapped road.
    pub leave_per_s: f32,
    /// Probability per second of coming back onto it.
    pub return_per_s: f32,
    /// Width over which an off-road position is spread, metres (its density is 1/width).
    pub off_road_width_m: f32,
    /// A gap between fixes longer than this starts the filter over, milliseconds.
    pub max_gap_ms: u32,
    /// A fix this far beyond the edge of its nearest lane, or nearer, keeps the road even
    /// when the belief leans off it, metres.
    pub keep_road_m: f32,
    /// Along the road: acceleration the station track allows (process noise), m/s².
    pub along_accel_mps2: f32,
    /// Along the road: error of the speed (Doppler or CAN), m/s (1 sigma).
    pub speed_sigma_mps: f32,
}

impl FilterConfig {
    /// The defaults, tuned on the drive table (`cargo bench -p obu --bench drive_table`).
    pub const DEFAULT: FilterConfig = FilterConfig {
        show_percent: 80,
        lateral_accel_mps2: 1.0,
        course_sigma_deg: 3.0,
        evidence_weight: 0.7,
        change_per_s: 0.002,
        gate_sigma: 4.0,
        restart_after: 10,
        rate_gain: 2.0,
        leave_per_s: 0.02,
        return_per_s: 1.0,
        off_road_width_m: 12.0,
        max_gap_ms: 2_000,
        keep_road_m: 5.0,
        along_accel_mps2: 2.0,
        speed_sigma_mps: 0.2,
    };
}

impl Default for FilterConfig {
    fn default() -> Self {
        FilterConfig::DEFAULT
    }
}

/// One candidate lane of a fix, as the filter needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// The lane.
    pub lane: LaneId,
    /// The fix's offset from the lane's centreline, metres, positive to the left.
    pub lateral: f32,
    /// Lane width there, metres.
    pub width: f32,
    /// Bearing of the lane there in its direction of travel, degrees.
    pub bearing_deg: f32,
}

/// What one fix tells the filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Observation {
    /// The receiver's error (1 sigma), metres.
    pub sigma_m: f32,
    /// Ground speed, m/s.
    pub speed_mps: Option<f32>,
    /// Course over ground, degrees.
    pub course_deg: Option<f32>,
}

/// The filter's verdict on one fix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Verdict {
    /// Index into the candidates of the most probable lane (`None` without candidates).
    pub best: Option<usize>,
    /// Its probability, percent.
    pub percent: u8,
    /// Probability of "off the mapped road", percent.
    pub off_road_percent: u8,
    /// The fix was rejected as an outlier: its position says nothing (the caller keeps
    /// the track's last position moved on).
    pub outlier: bool,
}

/// Belief in one lane.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Belief {
    lane: LaneId,
    p: f32,
    /// The lane's centre in the anchor lane's frame at the last fix, metres (left positive).
    centre: f32,
}

/// The lateral track: offset from the anchor lane's centreline and its rate, with their
/// covariance (pyy, pyv, pvv).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Track {
    y: f32,
    vy: f32,
    p: [f32; 3],
    /// The last fix's offset taken (for the scatter between fixes).
    prev_z: Option<f32>,
}

impl Track {
    /// A track started at offset `z` with variance `r`, rate unknown.
    fn at(z: f32, r: f32) -> Track {
        Track {
            y: z,
            vy: 0.0,
            p: [r, 0.0, 1.0],
            prev_z: Some(z),
        }
    }
}

/// The lane filter's state (about 150 bytes).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LaneFilter {
    beliefs: Vec<Belief, MAX_NEARBY_LANES, u8>,
    off_road: f32,
    anchor: Option<LaneId>,
    track: Track,
    last: Option<Instant>,
    in_row: u8,
    outliers: u32,
    /// Variance of the white part of the fix error, learnt from the fixes, m².
    white_var: Option<f32>,
}

impl LaneFilter {
    /// A filter with no history.
    pub const fn new() -> Self {
        LaneFilter {
            beliefs: Vec::new(),
            off_road: 0.0,
            anchor: None,
            track: Track {
                y: 0.0,
                vy: 0.0,
                p: [0.0; 3],
                prev_z: None,
            },
            white_var: None,
            last: None,
            in_row: 0,
            outliers: 0,
        }
    }

    /// The lane the lateral track is measured from.
    pub fn anchor(&self) -> Option<LaneId> {
        self.anchor
    }

    /// Fixes rejected by the innovation gate so far.
    pub fn outliers(&self) -> u32 {
        self.outliers
    }

    /// Forgets the road (a GNSS outage, another map).
    pub fn reset(&mut self) {
        let outliers = self.outliers;
        *self = LaneFilter::new();
        self.outliers = outliers;
    }

    /// One fix at `now` with its candidate lanes (one road: same map and direction).
    pub fn update(
        &mut self,
        now: Instant,
        cands: &[Candidate],
        obs: &Observation,
        cfg: &FilterConfig,
    ) -> Verdict {
        let dt = match self.last {
            Some(t) if now.saturating_since(t).millis() <= u64::from(cfg.max_gap_ms) => {
                now.saturating_since(t).as_secs_f32()
            }
            _ => {
                self.reset();
                0.0
            }
        };
        self.last = Some(now);
        let sigma = obs.sigma_m.max(MIN_SIGMA_M);
        let kept = self
            .anchor
            .and_then(|id| cands.iter().position(|c| c.lane == id));
        // The anchor lane is gone: a lane that ended beside lanes that go on (the fix fits
        // the track in one of their frames, which the track then moves into), or a jump
        // away (an outlier until a run of them says the car or its receiver really moved).
        let moved_on =
            kept.is_none() && self.anchor.is_some() && self.hand_over(cands, dt, sigma, cfg);
        if kept.is_none()
            && !moved_on
            && self.anchor.is_some()
            && self.in_row + 1 < cfg.restart_after
        {
            self.reject();
            return Verdict {
                best: None,
                percent: 0,
                off_road_percent: 0,
                outlier: true,
            };
        }
        if !(self.track.y.is_finite() && self.track.vy.is_finite() && self.track.p[0].is_finite()) {
            self.track = Track::default();
        }
        let Some(a) = self.anchor_in(cands) else {
            self.leave_road();
            return self.verdict(cands);
        };
        let gated = self.track_fix(dt, &cands[a], obs, sigma, cfg);
        self.step_beliefs(dt, cands, a, cfg);
        if gated {
            self.weigh(cands, a, sigma, cfg);
        }
        Verdict {
            outlier: !gated,
            ..self.verdict(cands)
        }
    }

    /// Moves the track to a lane of this fix that was on the road at the last fix and whose
    /// frame the fix fits (within the gate); false when there is none.
    fn hand_over(&mut self, cands: &[Candidate], dt: f32, sigma: f32, cfg: &FilterConfig) -> bool {
        let t = self.track;
        if t.p[0] <= 0.0 {
            return false;
        }
        let s = t.p[0] + sigma * sigma;
        let fits = cands.iter().find_map(|c| {
            let b = self.beliefs.iter().find(|b| b.lane == c.lane)?;
            let nu = c.lateral - (t.y + t.vy * dt - b.centre);
            (nu * nu <= cfg.gate_sigma * cfg.gate_sigma * s).then_some((c.lane, b.centre))
        });
        let Some((lane, centre)) = fits else {
            return false;
        };
        self.track.y -= centre;
        if let Some(z) = &mut self.track.prev_z {
            *z -= centre;
        }
        self.anchor = Some(lane);
        true
    }

    /// Counts a rejected fix.
    fn reject(&mut self) {
        self.outliers = self.outliers.saturating_add(1);
        self.in_row = self.in_row.saturating_add(1);
    }

    /// The index of the anchor lane in `cands`, re-anchoring (and moving the track into
    /// the new lane's frame) when the old anchor is not among them.
    fn anchor_in(&mut self, cands: &[Candidate]) -> Option<usize> {
        if cands.is_empty() {
            self.anchor = None;
            return None;
        }
        let old = self
            .anchor
            .and_then(|id| cands.iter().position(|c| c.lane == id));
        let prob = |c: &Candidate| self.belief(c.lane);
        if let Some(i) = old {
            // Follow the most probable lane, carrying the track into its frame: the
            // car's offset from lane b is its offset from lane a less b's centre in a's.
            let top = (0..cands.len()).max_by(|&x, &y| prob(&cands[x]).total_cmp(&prob(&cands[y])));
            return Some(match top {
                Some(b) if b != i && prob(&cands[b]) > prob(&cands[i]) => {
                    let shift = cands[i].lateral - cands[b].lateral;
                    self.track.y -= shift;
                    if let Some(z) = &mut self.track.prev_z {
                        *z -= shift;
                    }
                    self.anchor = Some(cands[b].lane);
                    b
                }
                _ => i,
            });
        }
        let best = (0..cands.len()).max_by(|&i, &j| {
            prob(&cands[i])
                .total_cmp(&prob(&cands[j]))
                .then(cands[j].lateral.abs().total_cmp(&cands[i].lateral.abs()))
        })?;
        // The old anchor is gone from this fix: its frame cannot be carried over.
        self.track = Track::default();
        self.anchor = Some(cands[best].lane);
        Some(best)
    }

    fn belief(&self, lane: LaneId) -> f32 {
        self.beliefs
            .iter()
            .find(|b| b.lane == lane)
            .map_or(0.0, |b| b.p)
    }

    /// Kalman predict and update of the lateral track; false when the fix's offset fell
    /// outside the innovation gate (an outlier, not used for the lane belief either).
    fn track_fix(
        &mut self,
        dt: f32,
        anchor: &Candidate,
        obs: &Observation,
        sigma: f32,
        cfg: &FilterConfig,
    ) -> bool {
        let z = anchor.lateral;
        let r = sigma * sigma;
        let course_rate = match (obs.speed_mps, obs.course_deg) {
            (Some(v), Some(c)) if v >= 3.0 => {
                let off = (anchor.bearing_deg - c).to_radians();
                let sd = v * cfg.course_sigma_deg.to_radians();
                Some((v * libm::sinf(off), sd * sd))
            }
            _ => None,
        };
        if self.track.p[0] <= 0.0 {
            self.track = Track::at(z, r);
            self.in_row = 0;
            return true;
        }
        let t = &mut self.track;
        kalman::predict(&mut t.y, &mut t.vy, &mut t.p, dt, cfg.lateral_accel_mps2);
        if let Some((rate, var)) = course_rate {
            kalman::update(&mut t.y, &mut t.vy, &mut t.p, 1, rate, var);
        }
        let s = t.p[0] + r;
        let nu = z - t.y;
        if nu * nu > cfg.gate_sigma * cfg.gate_sigma * s {
            self.reject();
            if self.in_row < cfg.restart_after {
                return false;
            }
            self.track = Track::at(z, r);
        } else {
            let moved = t.vy * dt;
            if let Some(prev) = t.prev_z {
                self.learn_scatter(z - prev - moved, dt, r);
            }
            let t = &mut self.track;
            kalman::update(&mut t.y, &mut t.vy, &mut t.p, 0, z, r);
            t.prev_z = Some(z);
        }
        self.in_row = 0;
        true
    }

    /// Learns the white part of the fix error from the scatter between consecutive fixes
    /// (less the motion the track saw): `d` is one such difference. A wandering bias moves
    /// little from fix to fix; white noise scatters by sqrt(2) sigma.
    fn learn_scatter(&mut self, d: f32, dt: f32, r: f32) {
        let alpha = clamp(dt / SCATTER_TIME_S, 0.0, 1.0);
        let v = self.white_var.unwrap_or(0.5 * r);
        let v = v + alpha * (0.5 * d * d - v);
        self.white_var = Some(clamp(v, 0.0025, r));
    }

    /// The share of the fix error that is white (0..1): how far one fix's evidence counts.
    fn white_share(&self, r: f32) -> f32 {
        match self.white_var {
            Some(v) if r > 0.0 => clamp(v / r, 0.02, 1.0),
            _ => 0.5,
        }
    }

    /// The forward algorithm's transition: lanes keep their belief but for what the
    /// tracked lateral rate carries to their neighbours, and the road exchanges belief
    /// with "off the road". Lanes new to the road start with a small share.
    fn step_beliefs(&mut self, dt: f32, cands: &[Candidate], a: usize, cfg: &FilterConfig) {
        let old = core::mem::take(&mut self.beliefs);
        // No lane of this fix had belief before (a first fix, or another stretch of road):
        // start the road afresh rather than from the old road's off-road share.
        let fresh = !cands
            .iter()
            .any(|c| old.iter().any(|b| b.lane == c.lane && b.p > 0.0));
        let mut next: Vec<Belief, MAX_NEARBY_LANES, u8> = Vec::new();
        for c in cands {
            let p = old.iter().find(|b| b.lane == c.lane).map_or(0.0, |b| b.p);
            let _ = next.push(Belief {
                lane: c.lane,
                p,
                centre: cands[a].lateral - c.lateral,
            });
        }
        let total: f32 = next.iter().map(|b| b.p).sum::<f32>() + self.off_road;
        if fresh || total <= 0.0 {
            // A fix near mapped lanes starts on the road, with no lane preferred.
            let n = next.len() as f32;
            for b in next.iter_mut() {
                b.p = (1.0 - START_OFF_ROAD) / n;
            }
            self.off_road = START_OFF_ROAD;
        } else {
            // Lanes new to the road: a floor so that evidence can raise them.
            let floor = 0.01 * total;
            for b in next.iter_mut() {
                b.p = b.p.max(floor);
            }
        }
        let centre = |i: usize| cands[a].lateral - cands[i].lateral;
        let vy = self.track.vy;
        let mut moved: [f32; MAX_NEARBY_LANES] = [0.0; MAX_NEARBY_LANES];
        for i in 0..next.len() {
            let from = next[i].p;
            for (dir, toward) in [(1.0f32, vy.max(0.0)), (-1.0, (-vy).max(0.0))] {
                // Lane widths per second the car moves towards that side.
                let motion = cfg.rate_gain * toward / cands[i].width.max(2.0);
                let Some(k) = neighbour(cands, i, dir, &centre) else {
                    continue;
                };
                let share = clamp((cfg.change_per_s + motion) * dt, 0.0, 0.45) * from;
                moved[i] -= share;
                moved[k] += share;
            }
        }
        for (b, m) in next.iter_mut().zip(moved.iter()) {
            b.p = (b.p + m).max(0.0);
        }
        let leave = clamp(cfg.leave_per_s * dt, 0.0, 0.5);
        let back = clamp(cfg.return_per_s * dt, 0.0, 0.5);
        let on: f32 = next.iter().map(|b| b.p).sum();
        let (to_off, to_on) = (on * leave, self.off_road * back);
        let n = next.len().max(1) as f32;
        for b in next.iter_mut() {
            let share = if on > 0.0 { b.p / on } else { 1.0 / n };
            b.p = b.p * (1.0 - leave) + to_on * share;
        }
        self.off_road += to_off - to_on;
        self.beliefs = next;
        self.normalise();
    }

    /// The fix's evidence: each lane's likelihood of the measured offset (a position
    /// anywhere across its width, blurred by the fix error), against a flat density off
    /// the road; raised to the evidence weight.
    fn weigh(&mut self, cands: &[Candidate], a: usize, sigma: f32, cfg: &FilterConfig) {
        let z = cands[a].lateral;
        // Correlated error (a wandering bias) adds nothing fix after fix: only the white
        // share of the error counts as new evidence, unless the whole error is too small
        // against the lane to carry a fix into the next lane.
        let width = cands[a].width.max(2.0);
        let harmless = clamp((width / (8.0 * sigma)) * (width / (8.0 * sigma)), 0.0, 1.0);
        let k = cfg.evidence_weight * self.white_share(sigma * sigma).max(harmless);
        for (b, c) in self.beliefs.iter_mut().zip(cands.iter()) {
            let centre = cands[a].lateral - c.lateral;
            let half = 0.5 * c.width.max(1.0);
            let mass =
                normal_cdf((centre + half - z) / sigma) - normal_cdf((centre - half - z) / sigma);
            let density = (mass / (2.0 * half)).max(1.0e-9);
            b.p *= libm::expf(k * libm::logf(density));
        }
        self.off_road *= libm::expf(-k * libm::logf(cfg.off_road_width_m.max(1.0)));
        self.normalise();
    }

    /// No lane holds the fix: the belief moves off the road.
    fn leave_road(&mut self) {
        self.beliefs.clear();
        self.off_road = 1.0;
        self.track = Track::default();
    }

    fn normalise(&mut self) {
        let total: f32 = self.beliefs.iter().map(|b| b.p).sum::<f32>() + self.off_road;
        if !(total.is_finite() && total > 0.0) {
            let n = self.beliefs.len() as f32 + 1.0;
            self.beliefs.iter_mut().for_each(|b| b.p = 1.0 / n);
            self.off_road = 1.0 / n;
            return;
        }
        self.beliefs.iter_mut().for_each(|b| b.p /= total);
        self.off_road /= total;
    }

    fn verdict(&self, cands: &[Candidate]) -> Verdict {
        let best = self
            .beliefs
            .iter()
            .enumerate()
            .filter(|(i, _)| *i < cands.len())
            .max_by(|a, b| a.1.p.total_cmp(&b.1.p));
        Verdict {
            best: best.map(|(i, _)| i),
            percent: best.map_or(0, |(_, b)| clamp(b.p * 100.0, 0.0, 100.0) as u8),
            off_road_percent: clamp(self.off_road * 100.0, 0.0, 100.0) as u8,
            outlier: false,
        }
    }
}

/// The nearest lane of `cands` beside lane `i` on side `dir` (+1 left, -1 right), if it
/// is adjacent (centres within one and a half widths).
fn neighbour(
    cands: &[Candidate],
    i: usize,
    dir: f32,
    centre: &impl Fn(usize) -> f32,
) -> Option<usize> {
    let ci = centre(i);
    let reach = 1.5 * cands[i].width.max(2.0);
    (0..cands.len())
        .filter(|&k| k != i)
        .map(|k| (k, (centre(k) - ci) * dir))
        .filter(|&(_, d)| d > 0.5 && d < reach)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k)
}

#[cfg(test)]
mod tests;
