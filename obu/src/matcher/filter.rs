//! Lane filter: which lane of the road the car is in, from a run of noisy fixes.
//!
//! Two parts, both in fixed memory:
//! * **Lateral track** (Kalman filter): the car's offset from an anchor lane's centreline
//!   and its rate, predicted with a constant-rate model (lateral acceleration as process
//!   noise), updated with the fix's offset weighted by its reported accuracy and with the
//!   lateral rate its course and speed imply. An innovation gate rejects outliers
//!   (multipath jumps) and counts them; a run of rejections restarts the track (the
//!   receiver really moved, or its bias stepped).
//! * **Lane belief** ([`super::belief`], forward algorithm of a hidden Markov model):
//!   hypotheses "the car is in lane L and the receiver's bias across the road is B" for
//!   the candidate lanes of the road (same map, same direction, within the extent; up to
//!   two biases per lane) and "off the mapped road". Belief moves to a neighbouring lane in
//!   proportion to the tracked lateral rate towards it and carries its bias; each
//!   hypothesis weighs the fix less its bias (a position anywhere across the lane, from
//!   the MAP, blurred by the white error), its bias learns while the car keeps its lane,
//!   and the Gauss-Markov prior of the bias says which lanes it allows ([`Self::weigh`]).
//!
//! The lane shown is the most probable one once its probability reaches
//! [`FilterConfig::show_percent`]; below that the road stays known but the lane is not
//! named. No fix count or hold time decides a lane change.

use super::belief::{Belief, Evidence};
use super::kalman;
pub use super::settings::{Candidate, FilterConfig};
use crate::capacity::MAX_NEARBY_LANES;
use crate::lane::LaneId;
use crate::math::clamp;
use crate::time::Instant;

/// The smallest fix error the filter assumes, metres: a receiver's own figure below it
/// (an RTK fix, a noiseless simulation) would make every lateral manoeuvre an outlier.
pub(super) const MIN_SIGMA_M: f32 = 0.25;

/// Time constant of the learnt white error, seconds.
const SCATTER_TIME_S: f32 = 3.0;

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

/// The lane filter's state: the belief's hypotheses and the two tracks, in place (what it
/// adds to the core's RAM is in the core README's Measured table).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LaneFilter {
    belief: Belief,
    anchor: Option<LaneId>,
    track: Track,
    last: Option<Instant>,
    in_row: u8,
    outliers: u32,
    /// Variance of the white part of the fix error, learnt from the fixes, m².
    white_var: Option<f32>,
    /// The road was just met: the next fix's evidence also counts as the bias's start.
    start_term: bool,
    /// The bias integral's weight not yet taken ([`Self::weigh`]).
    allowed_due: f32,
    /// Error of the track's position under the bias alone at the last fix, metres (0
    /// before any fix was weighed).
    bias_sigma: f32,
    /// [`FilterConfig::off_road_width_m`] at the last fix.
    off_road_width: f32,
}

impl LaneFilter {
    /// A filter with no history.
    pub const fn new() -> Self {
        LaneFilter {
            belief: Belief::new(),
            anchor: None,
            track: Track {
                y: 0.0,
                vy: 0.0,
                p: [0.0; 3],
                prev_z: None,
            },
            white_var: None,
            start_term: false,
            allowed_due: 0.0,
            bias_sigma: 0.0,
            off_road_width: 1.0,
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
        // More candidates than the belief holds: the nearest come first (the matcher's
        // order), the rest are left out.
        let cands = &cands[..cands.len().min(MAX_NEARBY_LANES)];
        // The bias integral runs on time, outliers or not ([`Self::weigh`]).
        self.allowed_due += dt / (2.0 * cfg.bias_time_s.max(1.0));
        let sigma = clamp(obs.sigma_m, MIN_SIGMA_M, super::MAX_SIGMA_M);
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
            self.belief.leave_road();
            self.track = Track::default();
            return self.verdict(cands);
        };
        let gated = self.track_fix(dt, &cands[a], obs, sigma, cfg);
        let r = sigma * sigma;
        let bias_prior = r - r * self.white_share(r);
        if self
            .belief
            .step(dt, cands, a, self.track.vy, bias_prior, cfg)
        {
            // A road met afresh: the bias path starts here (time off the road is no part
            // of its integral).
            self.start_term = true;
            self.allowed_due = 0.0;
        }
        if gated {
            self.weigh(cands[a].lateral, dt, sigma, cfg);
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
            let centre = self.belief.centre(c.lane)?;
            let nu = c.lateral - (t.y + t.vy * dt - centre);
            (nu * nu <= cfg.gate_sigma * cfg.gate_sigma * s).then_some((c.lane, centre))
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
        let prob = |c: &Candidate| self.belief.lane(c.lane);
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

    /// The fix's evidence ([`Belief::weigh`]). A fix error is a white part (new at each
    /// fix) and a wandering bias (first-order Gauss-Markov, [`FilterConfig::bias_time_s`]).
    /// For two lane hypotheses a bias path's likelihood ratio is half its value at the
    /// start and half at the end, plus its integral over time at a rate of one over twice
    /// the time constant: the belief takes the track's likelihood under the bias alone at
    /// that rate (and half of it once when a road is met), and the verdict weighs the
    /// belief with half of the present one ([`Self::verdict`]).
    fn weigh(&mut self, z: f32, dt: f32, sigma: f32, cfg: &FilterConfig) {
        let r = sigma * sigma;
        let white = r * self.white_share(r);
        let bias_sigma = libm::sqrtf(r - white + self.track.p[0].max(0.0));
        // The integral is taken once a second (the bias moves little in a second), not at
        // every fix: it costs a likelihood per hypothesis.
        let rate = 1.0 / (2.0 * cfg.bias_time_s.max(1.0));
        let mut allowed_weight = 0.0;
        if self.start_term || self.allowed_due >= rate {
            allowed_weight = self.allowed_due + if self.start_term { 0.5 } else { 0.0 };
            self.allowed_due = 0.0;
            self.start_term = false;
        }
        let evidence = Evidence {
            z,
            y: self.track.y,
            vy: self.track.vy,
            white,
            bias_sigma,
            allowed_weight,
            bias_prior: r - white,
        };
        self.belief.weigh(&evidence, dt, cfg.evidence_weight, cfg);
        self.bias_sigma = bias_sigma;
        self.off_road_width = cfg.off_road_width_m.max(1.0);
    }

    /// The most probable lane: the belief weighed with half the likelihood of the track's
    /// present offset under the bias ([`Self::weigh`]).
    fn verdict(&self, cands: &[Candidate]) -> Verdict {
        let mut shares = [0.0f32; MAX_NEARBY_LANES];
        let n = cands.len().min(MAX_NEARBY_LANES);
        let off = self.belief.shares(
            &cands[..n],
            self.track.y,
            self.bias_sigma,
            self.off_road_width,
            &mut shares[..n],
        );
        let best = (0..n).max_by(|&i, &j| shares[i].total_cmp(&shares[j]));
        let percent = |q: f32| clamp(q * 100.0, 0.0, 100.0) as u8;
        Verdict {
            best,
            percent: best.map_or(0, |i| percent(shares[i])),
            off_road_percent: percent(off),
            outlier: false,
        }
    }
}

#[cfg(test)]
mod tests;
