//! The lane filter's belief: the forward algorithm of a hidden Markov model over
//! hypotheses "the car is in lane L and the receiver's error across the road has a bias
//! B", plus "off the mapped road".
//!
//! A wandering bias moves every fix the same way for a minute or more, so a fix's offset
//! alone cannot tell a car in one lane from a car in the next with the bias a lane width
//! larger. Each hypothesis therefore carries its own bias estimate, and belief carried to
//! a neighbouring lane (a lane change) carries its bias with it. A lane holds up to
//! [`PER_LANE`] hypotheses, so belief that arrives with another bias (a lane change in
//! progress) does not blur into the lane's own.

use heapless::Vec;

use super::settings::{Candidate, FilterConfig};
use crate::capacity::MAX_NEARBY_LANES;
use crate::lane::LaneId;
use crate::math::{clamp, normal_cdf};

/// Hypotheses a lane holds at most (different biases).
pub(super) const PER_LANE: usize = 2;

/// Hypotheses in all.
const MAX_HYPOTHESES: usize = PER_LANE * MAX_NEARBY_LANES;

/// Belief in "off the mapped road" when a road is first met.
const START_OFF_ROAD: f32 = 0.05;

/// Lateral motion over this long counts against the car keeping its lane's centre while
/// each hypothesis's bias learns, seconds.
const KEEP_MOTION_S: f32 = 5.0;

/// The fix interval at which one fix teaches a bias in full, seconds: at other rates a
/// fix counts in proportion to its interval, so a bias learns as fast at 1 Hz as at 20.
const LEARN_INTERVAL_S: f32 = 0.1;

/// A hypothesis's bias stays within this many sigmas of the bias prior.
const BIAS_REACH: f32 = 3.0;

/// Two bias estimates this many sigmas apart, or nearer, are one.
const SAME_BIAS_SIGMA: f32 = 3.0;

/// One hypothesis: lane and bias.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Hypothesis {
    pub(super) lane: LaneId,
    pub(super) p: f32,
    /// The lane's centre in the anchor lane's frame at the last fix, metres (left positive).
    pub(super) centre: f32,
    /// The lane's width there, metres.
    width: f32,
    /// The receiver's bias across the road, metres (left positive), and its variance, m².
    bias: f32,
    bias_var: f32,
}

impl Hypothesis {
    /// Likelihood density of a lateral position `pos` (anchor frame) in this lane: the
    /// car anywhere across the lane's width, the position blurred by `sigma`.
    fn density(&self, pos: f32, sigma: f32) -> f32 {
        let half = 0.5 * self.width.max(1.0);
        let mass = normal_cdf((self.centre + half - pos) / sigma)
            - normal_cdf((self.centre - half - pos) / sigma);
        (mass / (2.0 * half)).max(1.0e-9)
    }

    fn same_bias(&self, bias: f32, var: f32) -> bool {
        let gap = bias - self.bias;
        gap * gap <= SAME_BIAS_SIGMA * SAME_BIAS_SIGMA * (var + self.bias_var)
    }

    /// Takes in `p` of belief with bias `bias` (variance `var`): one estimate of both.
    fn merge(&mut self, p: f32, bias: f32, var: f32) {
        let total = self.p + p;
        if total <= 0.0 {
            return;
        }
        let mean = (self.p * self.bias + p * bias) / total;
        let second =
            (self.p * (self.bias_var + self.bias * self.bias) + p * (var + bias * bias)) / total;
        self.bias = mean;
        self.bias_var = (second - mean * mean).max(0.0);
        self.p = total;
    }
}

/// What one fix tells the belief (see [`Belief::weigh`]).
pub(super) struct Evidence {
    /// The fix's offset from the anchor lane's centreline, metres.
    pub(super) z: f32,
    /// The lateral track's offset and rate.
    pub(super) y: f32,
    pub(super) vy: f32,
    /// Variance of the fix's white error, m².
    pub(super) white: f32,
    /// Error of the track's offset under the bias alone, metres.
    pub(super) bias_sigma: f32,
    /// Weight of the track's likelihood under the bias alone (the bias path's start and
    /// integral terms).
    pub(super) allowed_weight: f32,
    /// Variance of the bias (its Gauss-Markov prior), m².
    pub(super) bias_prior: f32,
}

/// The belief over the road's lanes, their biases, and "off the road".
#[derive(Debug, Clone, PartialEq, Default)]
pub(super) struct Belief {
    hyps: Vec<Hypothesis, MAX_HYPOTHESES, u8>,
    off_road: f32,
}

impl Belief {
    /// No road.
    pub(super) const fn new() -> Self {
        Belief {
            hyps: Vec::new(),
            off_road: 0.0,
        }
    }

    /// The belief in `lane`.
    pub(super) fn lane(&self, lane: LaneId) -> f32 {
        self.hyps
            .iter()
            .filter(|h| h.lane == lane)
            .map(|h| h.p)
            .sum()
    }

    /// The centre of `lane` in the anchor lane's frame at the last fix.
    pub(super) fn centre(&self, lane: LaneId) -> Option<f32> {
        self.hyps.iter().find(|h| h.lane == lane).map(|h| h.centre)
    }

    /// No lane holds the fix: the belief moves off the road.
    pub(super) fn leave_road(&mut self) {
        self.hyps.clear();
        self.off_road = 1.0;
    }

    /// The forward algorithm's transition to this fix's lanes (`a` the anchor): lanes keep
    /// their belief but for what the lateral rate `vy` carries to their neighbours, and
    /// the road exchanges belief with "off the road"; biases follow the Gauss-Markov model
    /// (`bias_prior` its variance). Lanes new to the road start with a small share. True
    /// when the road starts afresh (no lane of this fix had belief).
    pub(super) fn step(
        &mut self,
        dt: f32,
        cands: &[Candidate],
        a: usize,
        vy: f32,
        bias_prior: f32,
        cfg: &FilterConfig,
    ) -> bool {
        let centre = |c: &Candidate| cands[a].lateral - c.lateral;
        let fresh = !self
            .hyps
            .iter()
            .any(|h| h.p > 0.0 && cands.iter().any(|c| c.lane == h.lane));
        if fresh {
            self.start(cands, a, bias_prior);
            return true;
        }
        let total: f32 = self.hyps.iter().map(|h| h.p).sum::<f32>() + self.off_road;
        let (bias, bias_var) = self.mean_bias().unwrap_or((0.0, bias_prior));
        self.hyps.retain(|h| cands.iter().any(|c| c.lane == h.lane));
        for c in cands {
            let mut known = false;
            for h in self.hyps.iter_mut().filter(|h| h.lane == c.lane) {
                h.centre = centre(c);
                h.width = c.width;
                known = true;
            }
            if !known {
                // A lane new to the road: a floor so that evidence can raise it.
                let _ = self.hyps.push(Hypothesis {
                    lane: c.lane,
                    p: 0.01 * total,
                    centre: centre(c),
                    width: c.width,
                    bias,
                    bias_var,
                });
            }
        }
        let phi = libm::expf(-dt / cfg.bias_time_s.max(1.0));
        for h in self.hyps.iter_mut() {
            h.bias *= phi;
            h.bias_var = phi * phi * h.bias_var + (1.0 - phi * phi) * bias_prior;
            if !(h.bias.is_finite() && h.bias_var.is_finite()) {
                (h.bias, h.bias_var) = (0.0, bias_prior);
            }
        }
        self.change_lanes(dt, cands, a, vy, cfg);
        self.exchange_off_road(dt, cfg);
        self.normalise();
        false
    }

    /// A fix near mapped lanes starts on the road, with no lane preferred and the bias
    /// from its prior (variance `var`).
    fn start(&mut self, cands: &[Candidate], a: usize, var: f32) {
        self.hyps.clear();
        let n = cands.len().max(1) as f32;
        for c in cands {
            let _ = self.hyps.push(Hypothesis {
                lane: c.lane,
                p: (1.0 - START_OFF_ROAD) / n,
                centre: cands[a].lateral - c.lateral,
                width: c.width,
                bias: 0.0,
                bias_var: var,
            });
        }
        self.off_road = START_OFF_ROAD;
    }

    /// The mean and variance of the hypotheses' biases, weighted by their belief.
    fn mean_bias(&self) -> Option<(f32, f32)> {
        let mut acc = Hypothesis {
            lane: LaneId(0),
            p: 0.0,
            centre: 0.0,
            width: 0.0,
            bias: 0.0,
            bias_var: 0.0,
        };
        for h in self.hyps.iter() {
            acc.merge(h.p, h.bias, h.bias_var);
        }
        (acc.p > 0.0 && acc.bias.is_finite()).then_some((acc.bias, acc.bias_var))
    }

    /// Moves belief to the neighbouring lanes in proportion to the lateral rate towards
    /// them (and a small rate with none seen); what arrives brings its bias.
    fn change_lanes(
        &mut self,
        dt: f32,
        cands: &[Candidate],
        a: usize,
        vy: f32,
        cfg: &FilterConfig,
    ) {
        let centre = |i: usize| cands[a].lateral - cands[i].lateral;
        // (target lane, share, bias, variance) of what moves.
        // Each hypothesis may move to both sides.
        let mut moving: Vec<(LaneId, f32, f32, f32), { 2 * MAX_HYPOTHESES }, u8> = Vec::new();
        for h in self.hyps.iter_mut() {
            let Some(i) = cands.iter().position(|c| c.lane == h.lane) else {
                continue;
            };
            let from = h.p;
            for (dir, toward) in [(1.0f32, vy.max(0.0)), (-1.0, (-vy).max(0.0))] {
                let Some(k) = neighbour(cands, i, dir, &centre) else {
                    continue;
                };
                // Lane widths per second the car moves towards that side.
                let motion = cfg.rate_gain * toward / cands[i].width.max(2.0);
                let share = clamp((cfg.change_per_s + motion) * dt, 0.0, 0.45) * from;
                h.p -= share;
                if moving
                    .push((cands[k].lane, share, h.bias, h.bias_var))
                    .is_err()
                {
                    h.p += share;
                }
            }
        }
        for (lane, share, bias, var) in moving {
            self.arrive(lane, share, bias, var);
        }
    }

    /// Belief `p` arrives in `lane` with a bias: it joins the lane's hypothesis with the
    /// same bias, or becomes one of its own; a lane with no room merges it into the
    /// hypothesis with the nearest bias. (Every candidate lane holds a hypothesis after
    /// [`Belief::step`]: the filter takes at most [`MAX_NEARBY_LANES`] candidates.)
    fn arrive(&mut self, lane: LaneId, p: f32, bias: f32, var: f32) {
        let mut nearest: Option<usize> = None;
        let mut count = 0;
        for (i, h) in self.hyps.iter().enumerate().filter(|(_, h)| h.lane == lane) {
            count += 1;
            if h.same_bias(bias, var) {
                nearest = Some(i);
                break;
            }
            if nearest.is_none_or(|n| (self.hyps[n].bias - bias).abs() > (h.bias - bias).abs()) {
                nearest = Some(i);
            }
        }
        let Some(n) = nearest else {
            return;
        };
        let own = self.hyps[n];
        let apart = !own.same_bias(bias, var) && count < PER_LANE;
        let pushed = apart
            && self
                .hyps
                .push(Hypothesis {
                    p,
                    bias,
                    bias_var: var,
                    ..own
                })
                .is_ok();
        if !pushed {
            self.hyps[n].merge(p, bias, var);
        }
    }

    /// The road exchanges belief with "off the road".
    fn exchange_off_road(&mut self, dt: f32, cfg: &FilterConfig) {
        let leave = clamp(cfg.leave_per_s * dt, 0.0, 0.5);
        let back = clamp(cfg.return_per_s * dt, 0.0, 0.5);
        let on: f32 = self.hyps.iter().map(|h| h.p).sum();
        let (to_off, to_on) = (on * leave, self.off_road * back);
        let n = self.hyps.len().max(1) as f32;
        for h in self.hyps.iter_mut() {
            let share = if on > 0.0 { h.p / on } else { 1.0 / n };
            h.p = h.p * (1.0 - leave) + to_on * share;
        }
        self.off_road += to_off - to_on;
    }

    /// The fix's evidence (`kw` the weight of one fix's position in its lane):
    ///
    /// * **Where in the lane**: each hypothesis weighs the fix less its own bias (the car
    ///   anywhere across the lane, blurred by the white error and the bias estimate's
    ///   error). A lane change shows here: the lane the car left no longer holds the fix
    ///   less the bias it had there. Each bias then learns from the fix, as a car keeping
    ///   its lane drives near the centre (not while it moves across).
    /// * **Which lane the bias allows**: the track's likelihood under the bias alone,
    ///   with [`Evidence::allowed_weight`].
    pub(super) fn weigh(&mut self, e: &Evidence, dt: f32, kw: f32, cfg: &FilterConfig) {
        let motion = KEEP_MOTION_S * e.vy;
        let per_fix = LEARN_INTERVAL_S / dt.max(0.01);
        let reach = BIAS_REACH * libm::sqrtf(e.bias_prior.max(0.0));
        let keep = (cfg.lane_keep_m * cfg.lane_keep_m + motion * motion) * per_fix + e.white;
        for h in self.hyps.iter_mut() {
            let own = libm::sqrtf(e.white + h.bias_var);
            let there = h.density(e.z - h.bias, own);
            let mut log = kw * libm::logf(there);
            if e.allowed_weight > 0.0 {
                log += e.allowed_weight * libm::logf(h.density(e.y, e.bias_sigma));
            }
            h.p *= libm::expf(log);
            let gain = h.bias_var / (h.bias_var + keep);
            // A bias beyond BIAS_REACH sigmas of its prior is not learnt: a fix that far
            // from the lane stays far from it (off the road, most likely).
            let learnt = h.bias + gain * (e.z - h.centre - h.bias);
            h.bias = if learnt.is_finite() {
                clamp(learnt, -reach, reach)
            } else {
                0.0
            };
            h.bias_var *= 1.0 - gain;
        }
        let off = -(kw + e.allowed_weight) * libm::logf(cfg.off_road_width_m.max(1.0));
        self.off_road *= libm::expf(off);
        self.normalise();
        self.tidy();
    }

    /// Hypotheses of a lane whose biases have become one are merged.
    fn tidy(&mut self) {
        let mut i = 0;
        while i < self.hyps.len() {
            let h = self.hyps[i];
            let twin = (i + 1..self.hyps.len()).find(|&j| {
                self.hyps[j].lane == h.lane && self.hyps[j].same_bias(h.bias, h.bias_var)
            });
            match twin {
                Some(j) => {
                    let t = self.hyps.swap_remove(j);
                    self.hyps[i].merge(t.p, t.bias, t.bias_var);
                }
                None => i += 1,
            }
        }
    }

    fn normalise(&mut self) {
        let total: f32 = self.hyps.iter().map(|h| h.p).sum::<f32>() + self.off_road;
        if !(total.is_finite() && total > 0.0) {
            let n = self.hyps.len() as f32 + 1.0;
            self.hyps.iter_mut().for_each(|h| h.p = 1.0 / n);
            self.off_road = 1.0 / n;
            return;
        }
        self.hyps.iter_mut().for_each(|h| h.p /= total);
        self.off_road /= total;
    }

    /// The verdict's view: for each of `cands` (and off the road) the belief weighed with
    /// the square root of the likelihood of the track's present offset `y` under the bias
    /// alone (error `sigma`, 0 for none), normalised; `out` gets one share per candidate
    /// and the off-road share is returned.
    pub(super) fn shares(
        &self,
        cands: &[Candidate],
        y: f32,
        sigma: f32,
        off_road_width: f32,
        out: &mut [f32],
    ) -> f32 {
        let mut total = 0.0;
        for (c, o) in cands.iter().zip(out.iter_mut()) {
            let mut now = None;
            let mut sum = 0.0;
            for h in self.hyps.iter().filter(|h| h.lane == c.lane) {
                // One likelihood per lane: it depends on the lane, not on the bias.
                let w = *now.get_or_insert_with(|| {
                    if sigma > 0.0 {
                        libm::sqrtf(h.density(y, sigma))
                    } else {
                        1.0
                    }
                });
                sum += h.p * w;
            }
            *o = sum;
            total += sum;
        }
        let off = if sigma > 0.0 {
            self.off_road / libm::sqrtf(off_road_width.max(1.0))
        } else {
            self.off_road
        };
        total += off;
        if !(total > 0.0 && total.is_finite()) {
            out.iter_mut().for_each(|o| *o = 0.0);
            return 0.0;
        }
        out.iter_mut().for_each(|o| *o /= total);
        off / total
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
