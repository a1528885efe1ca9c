//! Synthetic drives for the lane filter's tests and its benchmark (the drive table):
//! straight and curved three-lane roads with a work zone on the middle lane, lane changes
//! at seeded times, and GNSS error models (white noise, first-order Gauss-Markov bias,
//! multipath jumps) with the accuracy a receiver would report in GST. Our own numbers: the
//! truth is computed here, independently of the crate.

#![allow(dead_code)]

use obu::alert::{AlertConfig, AlertStage, ZoneState};
use obu::geo::{LatLon, LocalFrame64, Point};
use obu::input::nmea::FixAssembler;
use obu::lane::{LaneId, LaneKind, MapId, ModelError, TravelDirection};
use obu::matcher::MatcherConfig;
use obu::zone::{ContentKind, Directionality, Region, Validity, ZoneInfo, ZoneKey};
use obu::{Fix, Instant, Obu};

pub const LANE_W: f32 = 3.5;
const OFFSETS: [f32; 3] = [3.5, 0.0, -3.5]; // lanes 1 (left), 2, 3 (right)
pub const SPEED: f64 = 20.0;
const DT_MS: u64 = 100;
pub const ZONE_START: f64 = 1500.0;
pub const ZONE_END: f64 = 1700.0;
/// How far inside the zone a fix must truly be to count for "in zone shown", metres.
pub const IN_ZONE_MARGIN_M: f64 = 5.0;
/// Where the first warning is due at [`SPEED`]: the 9 s lead time (180 m) beats 100 m.
pub const WARNING_DUE_M: f64 = 180.0;

/// Base centreline nodes and left normals.
pub struct Road {
    base: Vec<(f64, f64)>,
    normal: Vec<(f64, f64)>,
}

impl Road {
    pub fn straight() -> Road {
        let base = (0..32).map(|i| (0.0, i as f64 * 2000.0 / 31.0)).collect();
        Road {
            base,
            normal: vec![(-1.0, 0.0); 32],
        }
    }

    pub fn curved() -> Road {
        let r = 700.0;
        let total = 2000.0 / r;
        let (mut base, mut normal) = (Vec::new(), Vec::new());
        for i in 0..32 {
            let th = total * i as f64 / 31.0;
            // Centre at (r, 0): starts at origin heading north, curving right (east).
            base.push((r - r * th.cos(), r * th.sin()));
            normal.push((-th.cos(), th.sin()));
        }
        Road { base, normal }
    }

    fn node(&self, lane: usize, i: usize) -> (f64, f64) {
        let (b, n) = (self.base[i], self.normal[i]);
        let o = OFFSETS[lane] as f64;
        (b.0 + o * n.0, b.1 + o * n.1)
    }

    /// Position on lane `lane` at parameter `u` (node index + fraction).
    fn at(&self, lane: usize, u: f64) -> (f64, f64) {
        let i = (u.floor() as usize).min(self.base.len() - 2);
        let f = u - i as f64;
        let (a, b) = (self.node(lane, i), self.node(lane, i + 1));
        (a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f)
    }

    /// Station on `lane` at `u` (chord sums, independent of the crate).
    fn station(&self, lane: usize, u: f64) -> f64 {
        let i = (u.floor() as usize).min(self.base.len() - 2);
        let chord = |k: usize| {
            let (a, b) = (self.node(lane, k), self.node(lane, k + 1));
            ((b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)).sqrt()
        };
        (0..i).map(chord).sum::<f64>() + chord(i) * (u - i as f64)
    }

    /// Parameter where lane `lane` reaches `station`.
    fn u_of(&self, lane: usize, station: f64) -> f64 {
        let (mut lo, mut hi) = (0.0, (self.base.len() - 1) as f64);
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if self.station(lane, mid) < station {
                lo = mid
            } else {
                hi = mid
            }
        }
        lo
    }

    fn bearing(&self, u: f64) -> f64 {
        let i = (u.floor() as usize).min(self.base.len() - 2);
        let (a, b) = (self.base[i], self.base[i + 1]);
        (b.0 - a.0).atan2(b.1 - a.1).to_degrees().rem_euclid(360.0)
    }
}

/// xorshift64* with Box-Muller.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    pub fn gauss(&mut self) -> f64 {
        let (a, b) = (self.next(), self.next());
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    }
}

/// A GNSS error model, per axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Noise {
    /// White noise of this sigma, metres.
    White(f64),
    /// First-order Gauss-Markov bias (sigma metres, time constant seconds) plus 0.2 m of
    /// white noise.
    GaussMarkov(f64, f64),
    /// 0.5 m white noise, and on 1 % of fixes a multipath jump of 5-10 m for 1-3 fixes.
    Multipath,
}

impl Noise {
    /// The 1-sigma accuracy a receiver would report for it (GST), metres.
    pub fn reported_sigma(self) -> f64 {
        match self {
            Noise::White(s) => s.max(0.1),
            Noise::GaussMarkov(s, _) => (s * s + 0.04).sqrt(),
            Noise::Multipath => 0.5,
        }
    }

    pub fn label(self) -> String {
        match self {
            Noise::White(s) => format!("white {s} m"),
            Noise::GaussMarkov(s, t) => format!("Gauss-Markov {s} m / {t} s"),
            Noise::Multipath => "multipath 5-10 m".into(),
        }
    }
}

/// The error process of one drive.
struct Errors {
    model: Noise,
    rng: Rng,
    bias: (f64, f64),
    jump: (f64, f64, u32),
}

impl Errors {
    fn new(model: Noise, seed: u64) -> Self {
        let mut rng = Rng(seed | 1);
        let bias = match model {
            Noise::GaussMarkov(s, _) => (s * rng.gauss(), s * rng.gauss()),
            _ => (0.0, 0.0),
        };
        Errors {
            model,
            rng,
            bias,
            jump: (0.0, 0.0, 0),
        }
    }

    fn step(&mut self) -> (f64, f64) {
        let dt = DT_MS as f64 / 1000.0;
        match self.model {
            Noise::White(s) => (s * self.rng.gauss(), s * self.rng.gauss()),
            Noise::GaussMarkov(s, tau) => {
                let phi = (-dt / tau).exp();
                let q = s * (1.0 - phi * phi).sqrt();
                self.bias.0 = phi * self.bias.0 + q * self.rng.gauss();
                self.bias.1 = phi * self.bias.1 + q * self.rng.gauss();
                (
                    self.bias.0 + 0.2 * self.rng.gauss(),
                    self.bias.1 + 0.2 * self.rng.gauss(),
                )
            }
            Noise::Multipath => {
                if self.jump.2 == 0 && self.rng.next() < 0.01 {
                    let (r, th) = (
                        5.0 + 5.0 * self.rng.next(),
                        self.rng.next() * std::f64::consts::TAU,
                    );
                    self.jump = (
                        r * th.cos(),
                        r * th.sin(),
                        1 + (self.rng.next() * 3.0) as u32,
                    );
                }
                let (jx, jy) = if self.jump.2 > 0 {
                    self.jump.2 -= 1;
                    (self.jump.0, self.jump.1)
                } else {
                    (0.0, 0.0)
                };
                (jx + 0.5 * self.rng.gauss(), jy + 0.5 * self.rng.gauss())
            }
        }
    }
}

pub fn build_obu(
    road: &Road,
    reference: LatLon,
    frame: &LocalFrame64,
    matcher: MatcherConfig,
) -> Obu {
    let config = AlertConfig {
        matcher,
        ..Default::default()
    };
    let mut obu = Obu::new(config);
    let fill = |m: &mut obu::lane::LaneModel| -> Result<(), ModelError> {
        for lane in 0..3 {
            let l = m.add_lane(
                LaneId(lane as u8 + 1),
                TravelDirection::Egress,
                LaneKind::Vehicle,
            )?;
            for i in 0..road.base.len() {
                let (x, y) = road.node(lane, i);
                l.push_node(Point::new(x as f32, y as f32), LANE_W)?;
            }
        }
        Ok(())
    };
    let r = obu.update_map(Instant::ZERO, MapId(1), 1, reference, 0.0, fill);
    assert_eq!(r, Ok(true));
    let validity = Validity {
        start_year: 2024,
        start_minute: 0,
        duration_min: Validity::INDEFINITE,
    };
    let key = ZoneKey::packet([7; 9], 0);
    let fill_zone = |z: &mut obu::zone::WorkZone| -> Result<(), ModelError> {
        let (u0, u1) = (road.u_of(1, ZONE_START), road.u_of(1, ZONE_END));
        let pts: Vec<LatLon> = (0..=8)
            .map(|k| road.at(1, u0 + (u1 - u0) * k as f64 / 8.0))
            .filter_map(|(x, y)| frame.to_wgs84(x, y))
            .collect();
        let mut region = Region::path(pts[0], 0.0, LANE_W);
        region.directionality = Directionality::Forward;
        for p in &pts {
            region.push_latlon(*p)?;
        }
        z.push_region(region)?;
        let mut info = ZoneInfo::new(ContentKind::WorkZone);
        [268, 12569, 8720]
            .into_iter()
            .for_each(|c| info.push_itis(c));
        z.info = info;
        Ok(())
    };
    assert_eq!(
        obu.update_zone(Instant::ZERO, key, 1, validity, fill_zone),
        Ok(true)
    );
    obu
}

/// Lane changes of a drive: (start s, from, to), each over 4 s; three changes at seeded
/// times (2 -> 3, 3 -> 2, 2 -> 1), the last before the zone.
pub fn lane_changes(seed: u64) -> [(f64, usize, usize); 3] {
    let mut rng = Rng(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut at = |lo: f64| lo + 8.0 * rng.next();
    [(at(12.0), 1, 2), (at(30.0), 2, 1), (at(48.0), 1, 0)]
}

/// (from, to, blend 0..1) at time `t`.
fn lane_plan(changes: &[(f64, usize, usize)], t: f64) -> (usize, usize, f64) {
    let mut cur = 1;
    for &(start, from, to) in changes {
        if t < start {
            return (cur, cur, 0.0);
        }
        if t < start + 4.0 {
            let w = 0.5 - 0.5 * (std::f64::consts::PI * (t - start) / 4.0).cos();
            return (from, to, w);
        }
        cur = to;
    }
    (cur, cur, 0.0)
}

/// What one drive showed.
#[derive(Debug, Default, Clone)]
pub struct DriveStats {
    /// Fixes at least 0.5 m inside a lane (the truth is clear).
    pub eligible: u32,
    pub correct: u32,
    pub unknown: u32,
    /// A lane shown that is not the true one.
    pub wrong: u32,
    /// Changes of the lane shown (unknowns skipped).
    pub flips: u32,
    pub real_changes: u32,
    /// Fixes truly inside the zone, and of those the ones showing IN ZONE.
    pub in_zone: u32,
    pub in_zone_shown: u32,
    /// True distance to the zone start at the first warning minus where it was due, m.
    pub first_warning_error_m: Option<f64>,
    /// Along-lane distance error over the approach (mean, max), metres.
    pub dist_sum: f64,
    pub dist_max: f64,
    pub dist_n: u32,
    /// Fixes the filter rejected (innovation gate).
    pub outliers: u32,
}

/// What the simulated receiver reports of its accuracy.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Report {
    /// GST: the error model's own sigma ([`Noise::reported_sigma`]).
    Gst,
    /// No GST: GGA (DGPS quality, an HDOP of 1.0 drifting by 15 % over two minutes) and
    /// RMC through the core's NMEA reader, which takes HDOP times the range error of a
    /// DGPS solution (1 m by default).
    HdopOnly,
}

/// The fix a GGA + RMC pair gives through the core's NMEA reader (no GST: the accuracy
/// comes from the GGA's HDOP).
fn hdop_only_fix(asm: &mut FixAssembler, k: u64, pos: LatLon, speed: f64, course: f64) -> Fix {
    let ms = 12 * 3_600_000 + k * DT_MS;
    let t = format!(
        "{:02}{:02}{:02}.{:02}",
        ms / 3_600_000,
        ms / 60_000 % 60,
        ms / 1000 % 60,
        ms / 10 % 100
    );
    let angle = |deg: f64, w: usize, pos: char, neg: char| {
        let a = deg.abs();
        let d = a.trunc();
        format!(
            "{:0w$}{:010.7},{}",
            d as u32,
            (a - d) * 60.0,
            if deg < 0.0 { neg } else { pos }
        )
    };
    let at = format!(
        "{},{}",
        angle(pos.lat_deg(), 2, 'N', 'S'),
        angle(pos.lon_deg(), 3, 'E', 'W')
    );
    let hdop =
        1.0 + 0.15 * (k as f64 * DT_MS as f64 / 1000.0 / 120.0 * std::f64::consts::TAU).sin();
    let knots = speed / 0.514_444;
    let mut fix = None;
    for body in [
        format!("GPGGA,{t},{at},2,14,{hdop:.2},1600.0,M,-17.0,M,,"),
        format!("GPRMC,{t},A,{at},{knots:.3},{course:.2},041226,,,D"),
    ] {
        let sum = body.bytes().fold(0u8, |a, b| a ^ b);
        let line = format!("${body}*{sum:02X}");
        let sentence = obu::input::nmea::parse(&line).expect("a well-formed sentence");
        asm.push(&sentence, |e| fix = e.outcome.ok());
    }
    fix.expect("GGA + RMC complete the epoch")
}

/// Drives `road` once with `noise` and `seed` through an OBU with `matcher`.
pub fn drive(road: &Road, noise: Noise, seed: u64, matcher: MatcherConfig) -> DriveStats {
    drive_with(road, noise, Report::Gst, seed, matcher)
}

/// [`drive`] with the receiver reporting its accuracy as `report` says.
pub fn drive_with(
    road: &Road,
    noise: Noise,
    report: Report,
    seed: u64,
    matcher: MatcherConfig,
) -> DriveStats {
    let mut asm = FixAssembler::new();
    let reference = LatLon::from_degrees(40.5, -105.0).unwrap_or_default();
    let frame = LocalFrame64::new(reference, 0.0);
    let mut obu = build_obu(road, reference, &frame, matcher);
    let mut errors = Errors::new(noise, seed);
    let mut course_rng = Rng(seed ^ 0xc0ffee);
    let changes = lane_changes(seed);
    let mut st = DriveStats {
        real_changes: changes.len() as u32,
        ..Default::default()
    };
    let (mut u, mut last_lane) = (0.0f64, None);
    let mut prev_truth: Option<(f64, f64)> = None;
    let steps = (1900.0 / SPEED * 1000.0 / DT_MS as f64) as u64;
    let zone_u = road.u_of(1, ZONE_START).max(0.0);
    for k in 0..steps {
        let t = k as f64 * DT_MS as f64 / 1000.0;
        let (from, to, w) = lane_plan(&changes, t);
        let (a, b) = (road.at(from, u), road.at(to, u));
        let truth = (a.0 + (b.0 - a.0) * w, a.1 + (b.1 - a.1) * w);
        // The receiver's course is the true direction of motion (lane changes included).
        let course = match prev_truth {
            Some(p) if k > 0 => (truth.0 - p.0).atan2(truth.1 - p.1).to_degrees(),
            _ => road.bearing(u),
        };
        prev_truth = Some(truth);
        let (nx, ny) = errors.step();
        let pos = frame
            .to_wgs84(truth.0 + nx, truth.1 + ny)
            .unwrap_or_default();
        let course = (course + course_rng.gauss() * 1.0).rem_euclid(360.0);
        let fix = match report {
            Report::Gst => Fix {
                accuracy_source: obu::fix::AccuracySource::Gst,
                position: pos,
                accuracy_m: Some(noise.reported_sigma() as f32),
                speed_mps: Some(SPEED as f32),
                course_deg: Some(course as f32),
                utc: None,
            },
            // The date the RMC carries is left out: as on the GST path, no time is judged.
            Report::HdopOnly => Fix {
                utc: None,
                ..hdop_only_fix(&mut asm, k, pos, SPEED, course)
            },
        };
        let hmi = obu.on_fix(Instant::from_millis(1000 + k * DT_MS), fix);
        let shown = hmi.lane.map(|l| l.lane as usize - 1);
        let true_lane = if w < 0.5 { from } else { to };
        let margin = if from == to {
            LANE_W as f64 / 2.0
        } else {
            (w - 0.5).abs() * LANE_W as f64
        };
        if margin > 0.5 {
            st.eligible += 1;
            st.correct += (shown == Some(true_lane)) as u32;
            st.unknown += shown.is_none() as u32;
            st.wrong += shown.is_some_and(|s| s != true_lane) as u32;
        }
        if let (Some(s), Some(l)) = (shown, last_lane) {
            st.flips += (s != l) as u32;
        }
        if shown.is_some() {
            last_lane = shown;
        }
        // Inside the zone by more than one fix's travel plus the noise at either end.
        let station = road.station(1, u);
        if (ZONE_START + IN_ZONE_MARGIN_M..=ZONE_END - IN_ZONE_MARGIN_M).contains(&station) {
            st.in_zone += 1;
            st.in_zone_shown += (hmi.zone_state == ZoneState::InZone) as u32;
        }
        let truth_d = road.station(from, zone_u) - road.station(from, u);
        if st.first_warning_error_m.is_none() && hmi.stage >= AlertStage::Warning {
            st.first_warning_error_m = Some(truth_d - WARNING_DUE_M);
        }
        if from == to && truth_d > 0.0 {
            if let Some(d) = hmi.distance_m {
                let e = (d as f64 - truth_d).abs();
                st.dist_n += 1;
                st.dist_sum += e;
                st.dist_max = st.dist_max.max(e);
            }
        }
        let i = (u.floor() as usize).min(road.base.len() - 2);
        let (p, q) = (road.base[i], road.base[i + 1]);
        let chord = ((q.0 - p.0).powi(2) + (q.1 - p.1).powi(2)).sqrt();
        u += SPEED * DT_MS as f64 / 1000.0 / chord;
    }
    st.outliers = obu
        .state(Instant::from_millis(1000 + steps * DT_MS))
        .counters
        .lane_outliers;
    st
}

/// Sums of many drives, as rates.
#[derive(Debug, Default, Clone)]
pub struct Table {
    pub drives: u32,
    pub total: DriveStats,
    pub warn_errors: Vec<f64>,
}

impl Table {
    pub fn add(&mut self, s: &DriveStats) {
        let t = &mut self.total;
        self.drives += 1;
        t.eligible += s.eligible;
        t.correct += s.correct;
        t.unknown += s.unknown;
        t.wrong += s.wrong;
        t.flips += s.flips;
        t.real_changes += s.real_changes;
        t.in_zone += s.in_zone;
        t.in_zone_shown += s.in_zone_shown;
        t.dist_sum += s.dist_sum;
        t.dist_n += s.dist_n;
        t.dist_max = t.dist_max.max(s.dist_max);
        t.outliers += s.outliers;
        if let Some(e) = s.first_warning_error_m {
            self.warn_errors.push(e);
        }
    }

    fn pct(n: u32, d: u32) -> f64 {
        n as f64 / d.max(1) as f64 * 100.0
    }
    pub fn correct_pct(&self) -> f64 {
        Self::pct(self.total.correct, self.total.eligible)
    }
    pub fn unknown_pct(&self) -> f64 {
        Self::pct(self.total.unknown, self.total.eligible)
    }
    pub fn wrong_pct(&self) -> f64 {
        Self::pct(self.total.wrong, self.total.eligible)
    }
    pub fn flips_per_change(&self) -> f64 {
        self.total.flips as f64 / self.total.real_changes.max(1) as f64
    }
    pub fn in_zone_pct(&self) -> f64 {
        Self::pct(self.total.in_zone_shown, self.total.in_zone)
    }
    /// (mean, largest absolute) first-warning error, metres; warnings missed count apart.
    pub fn warning_error(&self) -> (f64, f64) {
        let n = self.warn_errors.len().max(1) as f64;
        let mean = self.warn_errors.iter().sum::<f64>() / n;
        let max = self.warn_errors.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        (mean, max)
    }
    pub fn warnings_missed(&self) -> u32 {
        self.drives - self.warn_errors.len() as u32
    }
}
