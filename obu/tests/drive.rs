//! Synthetic drives: straight and curved three-lane roads, lane changes, GNSS noise
//! (seeded Gauss-Markov random walk + white noise) at sigma 0, 0.5, 1 and 2 m.
//! Prints correct-lane rate, lane flips, and distance-to-zone error; asserts the
//! goals. Run with `--nocapture` to see the table.

use obu::geo::{LatLon, LocalFrame64, Point};
use obu::lane::{LaneId, LaneKind, MapId, ModelError, TravelDirection};
use obu::zone::{ContentKind, Directionality, Region, Validity, ZoneInfo, ZoneKey};
use obu::{Fix, Instant, Obu};

const LANE_W: f32 = 3.5;
const OFFSETS: [f32; 3] = [3.5, 0.0, -3.5]; // lanes 1 (left), 2, 3 (right)
const SPEED: f64 = 20.0;
const DT_MS: u64 = 100;
const ZONE_START: f64 = 1500.0;
const ZONE_END: f64 = 1700.0;

/// Base centreline nodes and left normals.
struct Road {
    base: Vec<(f64, f64)>,
    normal: Vec<(f64, f64)>,
}

impl Road {
    fn straight() -> Road {
        let base = (0..32).map(|i| (0.0, i as f64 * 2000.0 / 31.0)).collect();
        Road {
            base,
            normal: vec![(-1.0, 0.0); 32],
        }
    }

    fn curved() -> Road {
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
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    fn gauss(&mut self) -> f64 {
        let (a, b) = (self.next(), self.next());
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    }
}

/// Gauss-Markov (tau 20 s) + white noise, total 1-sigma `sigma` per axis.
struct Noise {
    rng: Rng,
    walk: (f64, f64),
    sigma: f64,
}

impl Noise {
    fn step(&mut self) -> (f64, f64) {
        let (sw, sn) = (self.sigma * 0.6, self.sigma * 0.8);
        let phi = (-(DT_MS as f64 / 1000.0) / 20.0f64).exp();
        let q = sw * (1.0 - phi * phi).sqrt();
        self.walk.0 = phi * self.walk.0 + q * self.rng.gauss();
        self.walk.1 = phi * self.walk.1 + q * self.rng.gauss();
        (
            self.walk.0 + sn * self.rng.gauss(),
            self.walk.1 + sn * self.rng.gauss(),
        )
    }
}

fn build_obu(road: &Road, reference: LatLon, frame: &LocalFrame64) -> Obu {
    let mut obu = Obu::default();
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

/// Lane index (0..3) over time: lane changes 2->3 at 20 s, 3->2 at 40 s, 2->1 at 60 s,
/// each over 4 s. Returns (from, to, blend 0..1).
fn lane_plan(t: f64) -> (usize, usize, f64) {
    let changes = [(20.0, 1, 2), (40.0, 2, 1), (60.0, 1, 0)];
    let mut cur = 1;
    for (start, from, to) in changes {
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

#[derive(Default)]
struct Result_ {
    eligible: u32,
    correct: u32,
    wrong_claims: u32,
    flips: u32,
    km: f64,
    dist_n: u32,
    dist_max: f64,
    dist_sum: f64,
}

fn run(road: &Road, sigma: f64, seed: u64) -> Result_ {
    let reference = LatLon::from_degrees(40.5, -105.0).unwrap_or_default();
    let frame = LocalFrame64::new(reference, 0.0);
    let mut obu = build_obu(road, reference, &frame);
    let mut noise = Noise {
        rng: Rng(seed),
        walk: (0.0, 0.0),
        sigma,
    };
    let mut res = Result_ {
        km: 0.0,
        ..Default::default()
    };
    let (mut u, mut last_lane) = (0.0f64, None);
    let steps = (1900.0 / SPEED * 1000.0 / DT_MS as f64) as u64;
    for k in 0..steps {
        let t = k as f64 * DT_MS as f64 / 1000.0;
        let (from, to, w) = lane_plan(t);
        let (a, b) = (road.at(from, u), road.at(to, u));
        let truth = (a.0 + (b.0 - a.0) * w, a.1 + (b.1 - a.1) * w);
        let (nx, ny) = noise.step();
        let pos = frame
            .to_wgs84(truth.0 + nx, truth.1 + ny)
            .unwrap_or_default();
        let fix = Fix {
            position: pos,
            accuracy_m: Some(sigma.max(0.1) as f32),
            speed_mps: Some(SPEED as f32),
            course_deg: Some((road.bearing(u) + noise.rng.gauss() * sigma) as f32),
            utc: None,
        };
        let hmi = obu.on_fix(Instant::from_millis(1000 + k * DT_MS), fix);
        let shown = hmi.lane.map(|l| l.lane as usize - 1);
        // Truth lane and margin to its edges (lane changes blend laterally).
        let true_lane = if w < 0.5 { from } else { to };
        let margin = if from == to {
            LANE_W as f64 / 2.0
        } else {
            (w - 0.5).abs() * LANE_W as f64
        };
        if margin > 0.5 {
            res.eligible += 1;
            res.correct += (shown == Some(true_lane)) as u32;
            res.wrong_claims += shown.is_some_and(|s| s != true_lane) as u32;
        }
        if let (Some(s), Some(l)) = (shown, last_lane) {
            res.flips += (s != l) as u32;
        }
        if shown.is_some() {
            last_lane = shown;
        }
        if from == to {
            let truth_d =
                road.station(from, road.u_of(1, ZONE_START).max(0.0)) - road.station(from, u);
            if let (Some(d), true) = (hmi.distance_m, truth_d > 0.0) {
                let e = (d as f64 - truth_d).abs();
                res.dist_n += 1;
                res.dist_sum += e;
                res.dist_max = res.dist_max.max(e);
            }
        }
        let i = (u.floor() as usize).min(road.base.len() - 2);
        let (p, q) = (road.base[i], road.base[i + 1]);
        let chord = ((q.0 - p.0).powi(2) + (q.1 - p.1).powi(2)).sqrt();
        u += SPEED * DT_MS as f64 / 1000.0 / chord;
        res.km += SPEED * DT_MS as f64 / 1000.0 / 1000.0;
    }
    res
}

#[test]
fn synthetic_drives() {
    println!("drive: 1.9 km at 20 m/s, 3 real lane changes, 10 Hz; goals: >= 99 % at 0.5 m, <= 1 flip per change, distance error < 0.5 m at 0 m");
    println!(
        "{:<8} {:>6} | {:>9} {:>11} {:>7} {:>10} {:>8} | {:>9} {:>9} {:>6}",
        "road",
        "sigma",
        "correct",
        "wrong-claim",
        "flips",
        "flips/km",
        "per-chg",
        "d-err avg",
        "d-err max",
        "d-n"
    );
    for (name, road) in [("straight", Road::straight()), ("curved", Road::curved())] {
        for sigma in [0.0, 0.5, 1.0, 2.0] {
            let r = run(&road, sigma, 0x5eed_0000 + (sigma * 10.0) as u64);
            let rate = r.correct as f64 / r.eligible.max(1) as f64 * 100.0;
            let wrong = r.wrong_claims as f64 / r.eligible.max(1) as f64 * 100.0;
            let per_change = r.flips as f64 / 3.0;
            let avg = r.dist_sum / r.dist_n.max(1) as f64;
            println!(
                "{:<8} {:>4.1} m | {:>8.2}% {:>10.2}% {:>7} {:>10.2} {:>8.2} | {:>7.3} m {:>7.3} m {:>6}",
                name, sigma, rate, wrong, r.flips, r.flips as f64 / r.km, per_change, avg, r.dist_max, r.dist_n
            );
            if sigma <= 0.5 {
                assert!(
                    rate >= 99.0,
                    "{name} sigma {sigma}: correct lane {rate:.2} %"
                );
                assert!(
                    per_change <= 1.0,
                    "{name} sigma {sigma}: {per_change} flips per change"
                );
            }
            if sigma == 0.0 {
                assert!(
                    r.dist_n > 100 && r.dist_max < 0.5,
                    "{name}: distance error {}",
                    r.dist_max
                );
            }
        }
    }
}
