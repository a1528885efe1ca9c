//! A simulated drive along the lane map: the true pose every 100 ms (speed profile, lane
//! changes), the GNSS receiver's errors (bias, random walk, white noise, dropouts) and the
//! vehicle's CAN speed frames.

use roadside::rng::Prng;
use roadside::road::{OnLane, Road};
use serde::Deserialize;

/// Epoch period of the simulated receiver, seconds (10 Hz).
pub const EPOCH_S: f64 = 0.1;

/// A lane change: from station `at_m` of the current lane to `to_lane` over `over_m`.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LaneChange {
    /// Station (on the lane driven then) where the manoeuvre starts.
    pub at_m: f64,
    /// Lane to move to.
    pub to_lane: u8,
    /// Length of the manoeuvre, metres.
    #[serde(default = "default_change_m")]
    pub over_m: f64,
}

fn default_change_m() -> f64 {
    50.0
}

/// A first-order Gauss-Markov bias of the fixes, per axis: the slowly wandering error of a
/// real receiver (atmosphere, orbit and clock errors, multipath on a long scale).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GaussMarkov {
    /// Stationary 1-sigma, metres.
    pub sigma_m: f64,
    /// Correlation time, seconds.
    pub tau_s: f64,
}

/// Multipath jumps: now and then the fixes leap several metres for a few epochs.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Multipath {
    /// Jumps per second (on average).
    pub per_s: f64,
    /// Smallest jump, metres (sizes are uniform between the two).
    pub min_m: f64,
    /// Largest jump, metres.
    pub max_m: f64,
    /// A jump lasts 1 to this many epochs.
    #[serde(default = "default_jump_epochs")]
    pub max_epochs: u32,
}

fn default_jump_epochs() -> u32 {
    3
}

/// How the car drives and what its receiver gets wrong.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DriveSpec {
    /// Lane at the start.
    pub lane: u8,
    /// Start station on that lane, metres.
    #[serde(default)]
    pub start_m: f64,
    /// The drive ends at this station of the lane driven then (default: the lane's end).
    pub end_m: Option<f64>,
    /// Constant speed, km/h (when no profile is given).
    #[serde(default = "default_speed")]
    pub speed_kmh: f64,
    /// Speed profile: (station on the start lane's course, km/h) pairs, linear between
    /// them, held before the first and after the last.
    #[serde(default)]
    pub profile: Vec<(f64, f64)>,
    /// Lane changes in order.
    #[serde(default)]
    pub lane_changes: Vec<LaneChange>,
    /// White noise of the fixes, 1-sigma per axis, metres.
    #[serde(default)]
    pub sigma_m: f64,
    /// Random walk of the fixes, metres per square-root second per axis.
    #[serde(default)]
    pub random_walk_m: f64,
    /// Constant offset of the fixes, east/north metres.
    #[serde(default)]
    pub bias_m: [f64; 2],
    /// A wandering bias of the fixes.
    pub gauss_markov: Option<GaussMarkov>,
    /// Multipath jumps of the fixes.
    pub multipath: Option<Multipath>,
    /// The 1-sigma error the receiver reports in GST, metres (default: the white noise
    /// and the Gauss-Markov sigma together, at least 0.3 m). A larger figure than the
    /// errors is a receiver that knows it is degraded; a smaller one, a receiver that
    /// does not.
    pub reported_sigma_m: Option<f64>,
    /// GNSS dropouts: (start s, duration s) with no fix at all.
    #[serde(default)]
    pub dropouts: Vec<(f64, f64)>,
    /// Seed of the noise.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// The receiver's clock error, seconds (positive: ahead of true time).
    #[serde(default)]
    pub clock_offset_s: f64,
    /// The receiver reports dates 1024 weeks early (a GPS week-number rollover fault).
    #[serde(default)]
    pub week_rollover: bool,
    /// Replay this recorded NMEA log (relative to the scenario) at its own pace, its
    /// times restamped to now, instead of the generated sentences; the drive's other
    /// keys still give the truth the expectations use (record the log with `hil-sim
    /// record` from the same drive, or describe the recorded drive).
    pub nmea_file: Option<std::path::PathBuf>,
    /// Replay this candump log as the vehicle's CAN speed (instead of generating one).
    pub candump_file: Option<std::path::PathBuf>,
    /// What the receiver sends: `nmea` (GST, GGA, RMC), `gga-only` or `ubx` (NAV-PVT).
    #[serde(default)]
    pub receiver: crate::receiver::ReceiverKind,
    /// A UBX receiver's carrier-phase solution over the drive: `[seconds, "fixed" |
    /// "float" | "none"]`, each from its time on (RTK fixed before the first).
    #[serde(default)]
    pub rtk: Vec<(f64, crate::receiver::Carrier)>,
}

/// 1024 weeks, milliseconds: the GPS week-number rollover period.
pub const ROLLOVER_MS: i64 = 1024 * 7 * 86_400_000;

impl DriveSpec {
    /// The 1-sigma error the receiver reports (GST), metres.
    pub fn reported_sigma(&self) -> f64 {
        let gm = self.gauss_markov.map_or(0.0, |g| g.sigma_m);
        self.reported_sigma_m
            .unwrap_or_else(|| (self.sigma_m.powi(2) + gm.powi(2)).sqrt().max(0.3))
    }

    /// What the receiver's clock reads when the true time is `unix_ms`.
    pub fn receiver_clock(&self, unix_ms: u64) -> u64 {
        let mut ms = unix_ms as i64 + (self.clock_offset_s * 1000.0).round() as i64;
        if self.week_rollover {
            ms -= ROLLOVER_MS;
        }
        ms.max(0) as u64
    }
}

fn default_speed() -> f64 {
    40.0
}

fn default_seed() -> u64 {
    1
}

/// The true state of the car at one epoch and what its receiver reports.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Seconds since the start.
    pub t_s: f64,
    /// True position, east/north metres.
    pub point: [f64; 2],
    /// True course, degrees.
    pub bearing_deg: f64,
    /// True speed, m/s.
    pub speed_mps: f64,
    /// The lane the car is in (the nearer centreline during a lane change).
    pub lane: u8,
    /// Distance driven, metres.
    pub odometer_m: f64,
    /// The receiver's position (with its errors), or `None` during a dropout.
    pub reported: Option<[f64; 2]>,
}

/// Why a drive cannot be simulated.
#[derive(Debug, Clone, PartialEq)]
pub struct DriveError(pub String);

impl std::fmt::Display for DriveError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for DriveError {}

/// The drive's samples at 10 Hz until the end station (at most `max_s` seconds).
pub fn simulate(road: &Road, spec: &DriveSpec, max_s: f64) -> Result<Vec<Sample>, DriveError> {
    let err = |m: String| DriveError(m);
    let mut lane = road
        .lane(spec.lane)
        .ok_or_else(|| err(format!("drive.lane {} is not on the map", spec.lane)))?;
    for c in &spec.lane_changes {
        road.lane(c.to_lane)
            .ok_or_else(|| err(format!("lane change to {}: not on the map", c.to_lane)))?;
    }
    let mut station = spec.start_m;
    let mut changes = spec.lane_changes.iter().peekable();
    let mut active: Option<(&LaneChange, f64)> = None; // (change, station where it started)
    let mut rng = Prng::new(spec.seed);
    let mut walk = [0.0f64; 2];
    let mut errors = SlowErrors::new(spec, &mut rng);
    let mut out = Vec::new();
    let mut odometer = 0.0;
    for k in 0..=(max_s / EPOCH_S).floor() as usize {
        let t = k as f64 * EPOCH_S;
        let end = spec.end_m.unwrap_or_else(|| lane.length_m());
        if station > end.min(lane.length_m()) {
            break;
        }
        let v = speed_at(spec, odometer + spec.start_m) / 3.6;
        if active.is_none() && changes.peek().is_some_and(|c| station >= c.at_m) {
            active = changes.next().map(|c| (c, station));
        }
        let (pose, in_lane) = match active {
            Some((c, s0)) => {
                let f = ((station - s0) / c.over_m.max(1.0)).clamp(0.0, 1.0);
                let to = road.lane(c.to_lane).expect("checked above");
                let a = lane
                    .at(station)
                    .ok_or_else(|| err("lane without geometry".into()))?;
                let s_to = to.project(a.point).map_or(station, |p| p.0);
                let b = to
                    .at(s_to)
                    .ok_or_else(|| err("lane without geometry".into()))?;
                let w = f * f * (3.0 - 2.0 * f); // smooth step
                let p = [
                    a.point[0] + w * (b.point[0] - a.point[0]),
                    a.point[1] + w * (b.point[1] - a.point[1]),
                ];
                if f >= 1.0 {
                    lane = to;
                    station = s_to;
                    active = None;
                }
                let before = if f >= 1.0 { c.to_lane } else { lane.id };
                (
                    OnLane { point: p, ..a },
                    if w < 0.5 { before } else { c.to_lane },
                )
            }
            None => (
                lane.at(station)
                    .ok_or_else(|| err("lane without geometry".into()))?,
                lane.id,
            ),
        };
        for w in walk.iter_mut() {
            *w += spec.random_walk_m * EPOCH_S.sqrt() * rng.normal();
        }
        let noise = [spec.sigma_m * rng.normal(), spec.sigma_m * rng.normal()];
        let slow = errors.step(&mut rng);
        let dropped = spec.dropouts.iter().any(|&(s, d)| t >= s && t < s + d);
        let reported = (!dropped).then(|| {
            [
                pose.point[0] + spec.bias_m[0] + walk[0] + noise[0] + slow[0],
                pose.point[1] + spec.bias_m[1] + walk[1] + noise[1] + slow[1],
            ]
        });
        out.push(Sample {
            t_s: t,
            point: pose.point,
            bearing_deg: pose.bearing_deg,
            speed_mps: v,
            lane: in_lane,
            odometer_m: odometer,
            reported,
        });
        station += v * EPOCH_S;
        odometer += v * EPOCH_S;
    }
    course_from_motion(&mut out);
    Ok(out)
}

/// The true course is the direction the car moves: during a lane change it leans off the
/// lane's bearing (a receiver measures it from Doppler, free of the position's errors).
fn course_from_motion(samples: &mut [Sample]) {
    for i in 0..samples.len().saturating_sub(1) {
        let (a, b) = (samples[i].point, samples[i + 1].point);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        if dx.hypot(dy) > 0.05 {
            samples[i].bearing_deg = dx.atan2(dy).to_degrees().rem_euclid(360.0);
        }
    }
}

/// The Gauss-Markov bias and the multipath jumps of one drive.
struct SlowErrors {
    gm: Option<(GaussMarkov, [f64; 2])>,
    multipath: Option<Multipath>,
    jump: ([f64; 2], u32),
}

impl SlowErrors {
    fn new(spec: &DriveSpec, rng: &mut Prng) -> Self {
        // The bias starts from its stationary distribution.
        let gm = spec.gauss_markov.map(|g| {
            let start = [g.sigma_m * rng.normal(), g.sigma_m * rng.normal()];
            (g, start)
        });
        SlowErrors {
            gm,
            multipath: spec.multipath,
            jump: ([0.0; 2], 0),
        }
    }

    /// This epoch's slow errors, east/north metres.
    fn step(&mut self, rng: &mut Prng) -> [f64; 2] {
        let mut e = [0.0; 2];
        if let Some((g, b)) = &mut self.gm {
            let phi = (-EPOCH_S / g.tau_s.max(EPOCH_S)).exp();
            let q = g.sigma_m * (1.0 - phi * phi).sqrt();
            for (bi, ei) in b.iter_mut().zip(e.iter_mut()) {
                *bi = phi * *bi + q * rng.normal();
                *ei += *bi;
            }
        }
        if let Some(m) = self.multipath {
            if self.jump.1 == 0 && rng.next_f64() < m.per_s * EPOCH_S {
                let size = m.min_m + (m.max_m - m.min_m) * rng.next_f64();
                let th = rng.next_f64() * std::f64::consts::TAU;
                let epochs = 1 + (rng.next_f64() * m.max_epochs.max(1) as f64) as u32;
                self.jump = (
                    [size * th.sin(), size * th.cos()],
                    epochs.min(m.max_epochs.max(1)),
                );
            }
            if self.jump.1 > 0 {
                self.jump.1 -= 1;
                e[0] += self.jump.0[0];
                e[1] += self.jump.0[1];
            }
        }
        e
    }
}

/// Speed at `station` of the profile (or the constant speed), km/h.
fn speed_at(spec: &DriveSpec, station: f64) -> f64 {
    let p = &spec.profile;
    match p.iter().position(|&(s, _)| s > station) {
        None => p.last().map_or(spec.speed_kmh, |&(_, v)| v),
        Some(0) => p[0].1,
        Some(i) => {
            let ((s0, v0), (s1, v1)) = (p[i - 1], p[i]);
            v0 + (v1 - v0) * (station - s0) / (s1 - s0).max(1e-9)
        }
    }
}

/// A candump log (`candump -l` format) of the vehicle speed: one frame every 20 ms with
/// the speed in km/h as an unsigned little-endian 16-bit value at start bit 0 with scale
/// 0.01 on CAN id 0x1F0 (the daemon's default signal), timestamps from `t0_s`.
pub fn candump(samples: &[Sample], t0_s: f64) -> String {
    let mut out = String::new();
    let Some(last) = samples.last() else {
        return out;
    };
    for i in 0..=(last.t_s / 0.02).round() as usize {
        let t = i as f64 * 0.02;
        let k = ((t / EPOCH_S + 1e-9) as usize).min(samples.len() - 1);
        let raw = (samples[k].speed_mps * 3.6 / 0.01)
            .round()
            .clamp(0.0, 65535.0) as u16;
        let [lo, hi] = raw.to_le_bytes();
        out.push_str(&format!(
            "({:.6}) vcan0 1F0#{lo:02X}{hi:02X}000000000000\n",
            t0_s + t
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use obu::LatLon;

    fn road() -> Road {
        Road::straight(
            LatLon::from_degrees(39.7392, -104.9903).unwrap(),
            90.0,
            1000.0,
            (3, 0),
            3.6,
            80.0,
        )
    }

    fn spec() -> DriveSpec {
        toml::from_str("lane = 2\nend_m = 500.0\nspeed_kmh = 36.0").unwrap()
    }

    #[test]
    fn constant_speed_along_a_lane() {
        let s = simulate(&road(), &spec(), 1000.0).unwrap();
        // 10 m/s from 0 to 500 m: 50 s at 10 Hz.
        assert_eq!(s.len(), 501);
        assert!((s[100].point[0] - 100.0).abs() < 1e-6 && (s[100].point[1] + 3.6).abs() < 1e-9);
        assert!(s.iter().all(|x| x.lane == 2 && x.reported == Some(x.point)));
    }

    #[test]
    fn lane_change_profile_dropout_and_noise() {
        let mut d = spec();
        d.lane_changes = vec![LaneChange {
            at_m: 100.0,
            to_lane: 1,
            over_m: 50.0,
        }];
        d.profile = vec![(0.0, 36.0), (200.0, 18.0)];
        d.dropouts = vec![(5.0, 3.0)];
        d.sigma_m = 1.0;
        let s = simulate(&road(), &d, 1000.0).unwrap();
        let at = |x: f64| s.iter().find(|p| p.point[0] >= x).unwrap();
        assert_eq!(at(90.0).lane, 2);
        assert!((at(125.0).point[1] + 1.8).abs() < 0.3, "halfway across");
        assert_eq!(at(160.0).lane, 1);
        assert!((at(300.0).point[1]).abs() < 1e-9);
        assert!(
            (at(100.0).speed_mps - 7.5).abs() < 0.05 && (at(300.0).speed_mps - 5.0).abs() < 1e-9
        );
        assert!(s.iter().filter(|p| p.reported.is_none()).count() == 30);
        let err: Vec<f64> = s
            .iter()
            .filter_map(|p| p.reported.map(|r| r[0] - p.point[0]))
            .collect();
        let sd = (err.iter().map(|e| e * e).sum::<f64>() / err.len() as f64).sqrt();
        assert!((sd - 1.0).abs() < 0.1, "white noise sigma {sd}");
    }

    #[test]
    fn candump_speed_signal() {
        let s = simulate(&road(), &spec(), 1.0).unwrap();
        let log = candump(&s, 1000.0);
        let first = log.lines().next().unwrap();
        // 36 km/h = 3600 = 0x0E10, little endian.
        assert_eq!(first, "(1000.000000) vcan0 1F0#100E000000000000");
        assert_eq!(log.lines().count(), 51);
    }
}
