//! Joining the sentences of one epoch into a fix, or the reason there is none.
//!
//! An epoch is the set of sentences stamped with one time of day. It is decided by the
//! time field, never by a fixed sentence order: a sentence stamped with another time
//! (by [`SAME_EPOCH_MS`] or more: some receivers stamp GLL to the millisecond and GGA
//! to the centisecond in one cycle) closes the epoch before it. Sentences without a time (GSA, VTG) belong to the epoch in
//! progress. An epoch is emitted as soon as it holds every timed sentence type the
//! receiver sent in the epoch before (its cycle, learned as it goes: GGA-only, RMC-only,
//! GGA + RMC + GST, ...; before it is known, GGA or GNS with RMC), or when the next epoch
//! closes it; so a receiver that alternates GGA and RMC from second to second gets a fix
//! each second too.
//!
//! A receiver that sends no velocity (GGA-only, GLL-only) gets one from its own positions:
//! the displacement from the fix about a second before ([`VELOCITY_BASE_MS`]), long
//! enough that a 0.3 m position noise is a 0.4 m/s speed noise, not 4 m/s.
//!
//! A fix needs a position and a measured solution ([`Solution::is_measured`]). What a
//! receiver flags (simulator, manual input, its own dead reckoning, integrity unsafe,
//! no fix) wins over a measured indication in another sentence of the same epoch: the
//! OBU never takes a position its receiver itself disowns.

use super::{DayMillis, Sentence, Solution};
use crate::fix::{AccuracySource, Fix};
use crate::geo::LatLon;
use crate::time::UtcTime;

/// The timed sentence types an epoch can hold (bits of [`Cycle`]).
const GGA: u8 = 1;
const RMC: u8 = 2;
const GNS: u8 = 4;
const GLL: u8 = 8;
const GST: u8 = 16;
const ZDA: u8 = 32;
/// The sentence types that carry a position.
const POSITIONS: u8 = GGA | RMC | GNS | GLL;

/// The baseline (ms) of a velocity derived from positions.
pub const VELOCITY_BASE_MS: u32 = 1000;
/// Positions kept for it, at least [`HISTORY_STEP_MS`] apart: a second at any rate.
const HISTORY: usize = 5;
/// The least time between two kept positions, ms.
const HISTORY_STEP_MS: i64 = 250;
/// Below this derived speed (m/s) the course is noise and is not given.
const MIN_COURSE_SPEED: f32 = 0.5;

/// Time stamps closer than this (ms) belong to one epoch.
pub const SAME_EPOCH_MS: u32 = 10;

/// A set of timed sentence types.
type Cycle = u8;

const DAY_MS: i64 = 86_400_000;
const HALF_DAY_MS: i64 = DAY_MS / 2;

/// Why an epoch gives no fix (a closed set: counters and `gnss-check` name them).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum NoFix {
    /// The receiver says it has no fix (GGA quality 0, status `V`, mode `N`).
    NoFix,
    /// The sentences of the epoch carry no position.
    NoPosition,
    /// No sentence of the epoch says whether its position is valid (an empty GGA quality
    /// and nothing else).
    NotQualified,
    /// The receiver's own dead reckoning (GGA 6, mode `E`).
    DeadReckoning,
    /// A position entered by hand (GGA 7, mode `M`).
    Manual,
    /// The receiver's simulator (GGA 8, mode `S`).
    Simulator,
    /// Navigational status `U`.
    Unsafe,
    /// The receiver does not mark its time valid (UBX NAV-PVT `validTime` clear).
    NoTime,
    /// A measured quality with no satellite used (GGA satellites 0).
    NoSatellites,
}

impl NoFix {
    /// Every reason, for counters that list them all.
    pub const ALL: [NoFix; 9] = [
        Self::NoFix,
        Self::NoPosition,
        Self::NotQualified,
        Self::DeadReckoning,
        Self::Manual,
        Self::Simulator,
        Self::Unsafe,
        Self::NoTime,
        Self::NoSatellites,
    ];

    /// A short lowercase name, for counters and logs.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::NoFix => "receiver has no fix",
            Self::NoPosition => "no position",
            Self::NotQualified => "validity not given",
            Self::DeadReckoning => "receiver dead reckoning",
            Self::Manual => "manual position",
            Self::Simulator => "simulator",
            Self::Unsafe => "integrity unsafe",
            Self::NoTime => "time not valid",
            Self::NoSatellites => "no satellites used",
        }
    }

    const fn of(s: Solution) -> Option<Self> {
        Some(match s {
            Solution::Invalid => Self::NoFix,
            Solution::Estimated => Self::DeadReckoning,
            Solution::Manual => Self::Manual,
            Solution::Simulator => Self::Simulator,
            Solution::Unsafe => Self::Unsafe,
            Solution::NoSatellites => Self::NoSatellites,
            _ => return None,
        })
    }
}

/// The user-equivalent range error (1 sigma, metres) per kind of solution: with no GST
/// (and no UBX hAcc) the horizontal 1-sigma error is taken as HDOP times it.
///
/// The defaults are the usual orders of magnitude of the ranging error left in each kind
/// of solution: single-frequency stand-alone 3 m; SBAS or DGPS 1 m; RTK float 0.3 m; RTK
/// fixed 0.03 m. An integrator who knows their receiver sets their own (`[gnss.uere]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccuracyModel {
    /// Stand-alone (GGA 1, mode `A`).
    pub autonomous_m: f32,
    /// SBAS, DGPS, precise (GGA 2, 3, 9; modes `D`, `P`).
    pub differential_m: f32,
    /// RTK float (GGA 5, mode `F`).
    pub rtk_float_m: f32,
    /// RTK fixed (GGA 4, mode `R`).
    pub rtk_fixed_m: f32,
}

impl AccuracyModel {
    /// The documented defaults.
    pub const DEFAULT: AccuracyModel = AccuracyModel {
        autonomous_m: 3.0,
        differential_m: 1.0,
        rtk_float_m: 0.3,
        rtk_fixed_m: 0.03,
    };

    /// The range error of a measured solution.
    pub const fn uere_m(&self, s: Solution) -> f32 {
        match s {
            Solution::RtkFixed => self.rtk_fixed_m,
            Solution::RtkFloat => self.rtk_float_m,
            Solution::Differential | Solution::Precise => self.differential_m,
            _ => self.autonomous_m,
        }
    }
}

impl Default for AccuracyModel {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What one epoch gave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Epoch {
    /// The epoch's UTC time of day.
    pub time: DayMillis,
    /// What the receiver says of its solution (combined over the epoch's sentences).
    pub solution: Option<Solution>,
    /// The fix, or why there is none.
    pub outcome: EpochOutcome,
}

/// A fix or the reason there is none.
pub type EpochOutcome = Result<Fix, NoFix>;

/// The sentences of the epoch in progress.
#[derive(Clone, Copy, Debug)]
struct Current {
    time: DayMillis,
    seen: Cycle,
    /// The position and the rank of the sentence it came from (GGA over GNS over RMC
    /// over GLL).
    position: Option<(LatLon, u8)>,
    solution: Option<Solution>,
    hdop: Option<f32>,
    gst_m: Option<f32>,
    speed_mps: Option<f32>,
    course_deg: Option<f32>,
    emitted: bool,
}

impl Current {
    const fn new(time: DayMillis) -> Self {
        Self {
            time,
            seen: 0,
            position: None,
            solution: None,
            hdop: None,
            gst_m: None,
            speed_mps: None,
            course_deg: None,
            emitted: false,
        }
    }

    /// Keeps the position of the highest-ranked sentence, and its time as the epoch's.
    fn position(&mut self, p: Option<LatLon>, rank: u8, time: Option<DayMillis>) {
        if let Some(p) = p {
            if self.position.is_none_or(|(_, r)| rank >= r) {
                self.position = Some((p, rank));
                self.time = time.unwrap_or(self.time);
            }
        }
    }

    /// True when `t` is this epoch's time stamp (to [`SAME_EPOCH_MS`]).
    fn holds(&self, t: DayMillis) -> bool {
        self.time.abs_diff(t) < SAME_EPOCH_MS
    }

    fn solution(&mut self, s: Option<Solution>) {
        if let Some(s) = s {
            self.solution = Some(self.solution.map_or(s, |have| have.with(s)));
        }
    }

    fn velocity(&mut self, speed: Option<f32>, course: Option<f32>) {
        self.speed_mps = self.speed_mps.or(speed);
        self.course_deg = self.course_deg.or(course);
    }
}

/// The UTC date a receiver last sent (RMC, ZDA) with the time of day it came with.
#[derive(Clone, Copy, Debug, PartialEq)]
struct DateAnchor {
    /// Milliseconds since 2000 of the date's midnight.
    midnight_ms: i64,
    /// The time of day it was sent at.
    time: DayMillis,
}

/// Joins the sentences of one epoch into a fix ([`Epoch`]).
#[derive(Clone, Debug)]
pub struct FixAssembler {
    current: Option<Current>,
    /// The timed sentence types of the last epoch.
    cycle: Cycle,
    date: Option<DateAnchor>,
    /// A date from elsewhere (the system clock) for receivers that send none.
    date_hint: Option<DateAnchor>,
    model: AccuracyModel,
    /// The last fixes' time and position (a ring), for a derived velocity.
    history: [(DayMillis, LatLon); HISTORY],
    history_len: usize,
    history_next: usize,
}

impl Default for FixAssembler {
    fn default() -> Self {
        Self::new()
    }
}

impl FixAssembler {
    /// An assembler with nothing seen and the default accuracy model.
    pub const fn new() -> Self {
        Self::with_model(AccuracyModel::DEFAULT)
    }

    /// An assembler deriving accuracy from HDOP with `model` when there is no GST.
    pub const fn with_model(model: AccuracyModel) -> Self {
        Self {
            current: None,
            cycle: 0,
            date: None,
            date_hint: None,
            model,
            history: [(0, LatLon::ZERO); HISTORY],
            history_len: 0,
            history_next: 0,
        }
    }

    /// A date for receivers that send none (GGA-only): the UTC date of `utc` (another
    /// clock, e.g. the system's) is taken for the fix nearest to it. A date the receiver
    /// sends (RMC, ZDA) is always preferred.
    pub fn set_date_hint(&mut self, utc: UtcTime) {
        let ms = utc.abs_millis();
        let midnight_ms = ms.div_euclid(DAY_MS) * DAY_MS;
        self.date_hint = Some(DateAnchor {
            midnight_ms,
            time: (ms - midnight_ms) as DayMillis,
        });
    }

    /// Takes one sentence; calls `out` for each epoch it completes (at most two: the one
    /// it closed and its own).
    pub fn push(&mut self, s: &Sentence, mut out: impl FnMut(Epoch)) {
        if let Some(t) = s.time() {
            if self.current.is_some_and(|c| !c.holds(t)) {
                if let Some(e) = self.close() {
                    out(e);
                }
            }
            if self.current.is_none() {
                self.current = Some(Current::new(t));
            }
        }
        let Some(mut cur) = self.current else {
            return; // a sentence without a time before any epoch: nothing to join it to
        };
        self.absorb(&mut cur, s);
        // Before the cycle is known (the first epoch), GGA or GNS with RMC make a fix
        // (position, validity, velocity, date) at once.
        let complete = match self.cycle {
            0 => cur.seen & (GGA | GNS) != 0 && cur.seen & RMC != 0,
            cycle => cur.seen & cycle == cycle,
        };
        let emit = complete && !cur.emitted && cur.seen & POSITIONS != 0;
        cur.emitted |= emit;
        self.current = Some(cur);
        if emit {
            out(self.epoch(&cur));
        }
    }

    /// Emits the epoch in progress if it was not yet (the end of a recording).
    pub fn finish(&mut self, mut out: impl FnMut(Epoch)) {
        if let Some(e) = self.close() {
            out(e);
        }
    }

    /// Ends the epoch in progress: its cycle is learned, and it is returned unless it
    /// was emitted already.
    fn close(&mut self) -> Option<Epoch> {
        let cur = self.current.take()?;
        self.cycle = cur.seen;
        (!cur.emitted && cur.seen & POSITIONS != 0).then(|| self.epoch(&cur))
    }

    /// The velocity from the position about [`VELOCITY_BASE_MS`] before `time`.
    fn derived_velocity(&self, time: DayMillis, p: LatLon) -> Option<(f32, Option<f32>)> {
        let age = |t: DayMillis| (i64::from(time) - i64::from(t)).rem_euclid(86_400_000);
        let (t, before) = self.history[..self.history_len]
            .iter()
            .filter(|(t, _)| (200..=2 * i64::from(VELOCITY_BASE_MS)).contains(&age(*t)))
            .min_by_key(|(t, _)| (age(*t) - i64::from(VELOCITY_BASE_MS)).abs())?;
        let d = crate::geo::LocalFrame32::new(*before, 0.0).to_local(p);
        let dt = age(*t) as f32 / 1000.0;
        let speed = libm::sqrtf(d.x * d.x + d.y * d.y) / dt;
        let course = (speed >= MIN_COURSE_SPEED)
            .then(|| crate::math::wrap_360(libm::atan2f(d.x, d.y).to_degrees()));
        speed.is_finite().then_some((speed, course))
    }

    fn remember(&mut self, time: DayMillis, p: LatLon) {
        if self.history_len > 0 {
            let last = self.history[(self.history_next + HISTORY - 1) % HISTORY].0;
            let age = (i64::from(time) - i64::from(last)).rem_euclid(86_400_000);
            if age < HISTORY_STEP_MS {
                return;
            }
        }
        self.history[self.history_next] = (time, p);
        self.history_next = (self.history_next + 1) % HISTORY;
        self.history_len = (self.history_len + 1).min(HISTORY);
    }

    fn absorb(&mut self, cur: &mut Current, s: &Sentence) {
        match *s {
            Sentence::Gga(g) => {
                cur.seen |= GGA;
                cur.position(g.position, 4, g.time);
                let quality = g.quality.and_then(Solution::from_gga_quality);
                cur.solution(match quality {
                    Some(q) if q.is_measured() && g.satellites == Some(0) => {
                        Some(Solution::NoSatellites)
                    }
                    q => q,
                });
                cur.hdop = g.hdop.or(cur.hdop);
            }
            Sentence::Gns(g) => {
                cur.seen |= GNS;
                cur.position(g.position, 3, g.time);
                cur.solution(Some(g.mode));
                cur.hdop = cur.hdop.or(g.hdop);
            }
            Sentence::Rmc(r) => {
                cur.seen |= RMC;
                cur.position(r.position, 2, r.time);
                let status = if r.valid {
                    Solution::Autonomous
                } else {
                    Solution::Invalid
                };
                cur.solution(Some(r.mode.map_or(status, |m| m.with(status))));
                cur.velocity(r.speed_mps, r.course_deg);
                self.anchor_date(r.date, r.time);
            }
            Sentence::Gll(g) => {
                cur.seen |= GLL;
                cur.position(g.position, 1, g.time);
                cur.solution(Some(g.solution));
            }
            Sentence::Gst(g) => {
                cur.seen |= GST;
                cur.gst_m = g.horizontal_m().filter(|m| m.is_finite() && *m > 0.0);
            }
            Sentence::Zda(z) => {
                cur.seen |= ZDA;
                self.anchor_date(z.date, z.time);
            }
            Sentence::Gsa(g) => cur.hdop = cur.hdop.or(g.hdop),
            Sentence::Vtg(v) => {
                if v.mode.is_none_or(Solution::is_measured) {
                    cur.velocity(v.speed_mps, v.course_deg);
                }
            }
        }
    }

    fn anchor_date(&mut self, date: Option<(u16, u8, u8)>, time: Option<DayMillis>) {
        let (Some((y, m, d)), Some(time)) = (date, time) else {
            return;
        };
        if let Some(midnight) = super::utc_from_date(y, m, d, 0) {
            self.date = Some(DateAnchor {
                midnight_ms: midnight.abs_millis(),
                time,
            });
        }
    }

    /// The fix (or the reason for none) of an epoch.
    fn epoch(&mut self, cur: &Current) -> Epoch {
        let outcome = match (cur.solution, cur.position) {
            (Some(s), _) if !s.is_measured() => Err(NoFix::of(s).unwrap_or(NoFix::NoFix)),
            (_, None) => Err(NoFix::NoPosition),
            (None, Some(_)) => Err(NoFix::NotQualified),
            (Some(s), Some((position, _))) => Ok(self.fix(cur, s, position)),
        };
        Epoch {
            time: cur.time,
            solution: cur.solution,
            outcome,
        }
    }

    fn fix(&mut self, cur: &Current, s: Solution, position: LatLon) -> Fix {
        let (accuracy_m, accuracy_source) = match (cur.gst_m, cur.hdop) {
            (Some(m), _) => (Some(m), AccuracySource::Gst),
            (None, Some(h)) if h.is_finite() && h > 0.0 && h < 99.0 => {
                (Some(h * self.model.uere_m(s)), AccuracySource::Hdop)
            }
            _ => (None, AccuracySource::None),
        };
        let (speed_mps, course_deg) = match (cur.speed_mps, cur.course_deg) {
            (None, None) => self
                .derived_velocity(cur.time, position)
                .map_or((None, None), |(v, c)| (Some(v), c)),
            given => given,
        };
        self.remember(cur.time, position);
        Fix {
            position,
            accuracy_m,
            accuracy_source,
            speed_mps,
            course_deg,
            utc: self.utc(cur.time),
        }
    }

    /// The UTC time of a time of day: on the receiver's last date (the next day once
    /// the time of day went back by more than half a day), else on the hint's.
    fn utc(&self, time: DayMillis) -> Option<UtcTime> {
        let anchor = self.date.or(self.date_hint)?;
        let (t, at) = (i64::from(time), i64::from(anchor.time));
        let day = if t + HALF_DAY_MS < at {
            DAY_MS
        } else if t > at + HALF_DAY_MS {
            -DAY_MS
        } else {
            0
        };
        Some(UtcTime::from_abs_millis(anchor.midnight_ms + day + t))
    }
}
