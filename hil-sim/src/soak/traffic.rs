//! The soak's UDP traffic into the daemon: the looping drive (NMEA at 10 Hz) with the signed
//! roadside beside it (MAP and TIM at 10 Hz), and the hostile V2X (forged datagrams of the
//! four attack kinds in turn, random octets, truncated signed frames) at a few a second.

use crate::hmi_bench::{self, Scene};
use crate::nmea::{self, Epoch};
use crate::roadside_bench::attacker::{AttackKind, Attacker};
use obu::security::Rejection;
use obu::v2x::{DropReason, SecurityReason};
use roadside::clock::{unix_ms_now, Utc};
use roadside::road::Road;
use roadside::signer::RsuSigner;
use std::collections::VecDeque;
use std::net::UdpSocket;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// The lap: lane 2 of the bench road from 400 m before the zone to 100 m after it at
/// 11 m/s (under the zone's 40 km/h), then back to the start: information, warning (100 m
/// before the zone), in zone and leaving every 64 s.
pub const LAP: Scene = Scene {
    name: "soak lap",
    lane: 2,
    from_m: hmi_bench::ZONE_START_M - 400.0,
    to_m: hmi_bench::ZONE_END_M + 100.0,
    speed_mps: 11.0,
};

/// The attack kinds, in the order they are sent, with the reason each must be dropped for.
pub const FORGED: [(AttackKind, DropReason); 4] = [
    (
        AttackKind::ForgedCancelUntrusted,
        DropReason::Security(SecurityReason::Rejected(Rejection::ChainUntrusted)),
    ),
    (
        AttackKind::ForgedCancelUnsigned,
        DropReason::Security(SecurityReason::Unsigned),
    ),
    (
        AttackKind::MapShifted,
        DropReason::Security(SecurityReason::Rejected(Rejection::SignatureInvalid)),
    ),
    (
        AttackKind::ReplayedYesterday,
        DropReason::Security(SecurityReason::Rejected(Rejection::MessageExpired)),
    ),
];

/// Fixes whose send times are kept for the clients to look up.
const SENT_KEPT: usize = 1024;

/// What the senders sent, counted as they go.
#[derive(Debug, Default)]
pub struct Sent {
    /// NMEA epochs (one datagram each).
    pub epochs: AtomicU64,
    /// The roadside's signed MAP and TIM.
    pub roadside: AtomicU64,
    /// Forged datagrams per kind of [`FORGED`].
    pub forged: [AtomicU64; 4],
    /// Random octets.
    pub garbage: AtomicU64,
    /// Signed frames cut short.
    pub truncated: AtomicU64,
    /// Datagrams that could not be made or sent.
    pub failed: AtomicU64,
    /// Send time of the last [`SENT_KEPT`] epochs: (fix number from 1, when).
    times: Mutex<VecDeque<(u64, Instant)>>,
}

impl Sent {
    /// Every V2X datagram sent.
    pub fn v2x(&self) -> u64 {
        self.roadside.load(Ordering::Relaxed)
            + self.forged_total()
            + self.garbage.load(Ordering::Relaxed)
            + self.truncated.load(Ordering::Relaxed)
    }

    /// Forged datagrams sent, all kinds.
    pub fn forged_total(&self) -> u64 {
        self.forged.iter().map(|c| c.load(Ordering::Relaxed)).sum()
    }

    /// When fix number `fix` (from 1) was sent, if it is still kept.
    pub fn epoch_sent(&self, fix: u64) -> Option<Instant> {
        let times = super::lock(&self.times);
        let first = times.front()?.0;
        let (n, at) = *times.get(fix.checked_sub(first)? as usize)?;
        (n == fix).then_some(at)
    }

    fn record_epoch(&self, at: Instant) {
        let n = self.epochs.fetch_add(1, Ordering::Relaxed) + 1;
        let mut times = super::lock(&self.times);
        if times.len() == SENT_KEPT {
            times.pop_front();
        }
        times.push_back((n, at));
    }

    fn count(&self, counter: &AtomicU64, sent: bool) {
        let c = if sent { counter } else { &self.failed };
        c.fetch_add(1, Ordering::Relaxed);
    }
}

/// The roadside's signed MAP and TIM and the car's NMEA epoch every 100 ms until `stop`.
pub fn drive(v2x: &str, gnss: &str, sent: &Sent, stop: &AtomicBool) -> Result<(), String> {
    let (map, tim) = hmi_bench::bench_messages()?;
    let (road, signer) = (hmi_bench::road(), crate::bench_pki::signer()?);
    let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let t0 = Instant::now();
    let mut next = t0;
    while !stop.load(Ordering::Relaxed) {
        let now = unix_ms_now();
        for frame in [&map, &tim] {
            let ok = signer
                .sign(frame, now)
                .is_ok_and(|d| sock.send_to(&d, v2x).is_ok());
            sent.count(&sent.roadside, ok);
        }
        let epoch = lap_epoch(&road, t0.elapsed().as_secs_f64(), Utc::now())
            .ok_or("the lap left the bench road")?;
        let text = nmea::epoch(&epoch);
        let at = Instant::now();
        if sock.send_to(text.as_bytes(), gnss).is_ok() {
            sent.record_epoch(at);
        } else {
            sent.failed.fetch_add(1, Ordering::Relaxed);
        }
        next += Duration::from_millis(100);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
    Ok(())
}

/// The receiver's epoch of the car `t_s` seconds into the run, stamped `utc`.
pub fn lap_epoch(road: &Road, t_s: f64, utc: Utc) -> Option<Epoch> {
    hmi_bench::scene_epoch(road, &LAP, t_s, utc)
}

/// Laps the car completed in `t_s` seconds.
pub fn laps(t_s: f64) -> u64 {
    (t_s * LAP.speed_mps / (LAP.to_m - LAP.from_m)).floor() as u64
}

/// A small deterministic generator (xorshift64*) for the garbage: the same run sends the
/// same octets.
#[derive(Debug, Clone)]
pub struct Noise(u64);

impl Noise {
    /// A generator from `seed` (0 is replaced).
    pub fn new(seed: u64) -> Self {
        Self(seed.max(1))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// A number in `lo..=hi`.
    pub fn between(&mut self, lo: usize, hi: usize) -> usize {
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }

    /// `len` random octets.
    pub fn octets(&mut self, len: usize) -> Vec<u8> {
        (0..len).map(|_| self.next_u64() as u8).collect()
    }
}

/// The hostile V2X sender: every 100 ms tick `k`, a forged datagram (kinds in turn) when
/// `k % 3 == 0` (3.3 a second), random octets (1-1200) when `k % 5 == 1` (2 a second) and
/// a signed MAP or TIM cut short when `k % 10 == 2` (1 a second), until `stop`.
pub fn hostile_v2x(v2x: &str, sent: &Sent, stop: &AtomicBool) -> Result<(), String> {
    let road = hmi_bench::road();
    let zone = hmi_bench::zone(Utc::from_unix_ms(unix_ms_now().saturating_sub(120_000)));
    let genuine: Arc<RsuSigner> = crate::bench_pki::signer()?;
    let attackers: Vec<Attacker> = FORGED
        .iter()
        .map(|(kind, _)| Attacker::new(*kind, &road, std::slice::from_ref(&zone), &genuine))
        .collect::<Result<_, _>>()?;
    let (map, tim) = hmi_bench::bench_messages()?;
    let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let mut noise = Noise::new(0x50a4_5eed);
    let mut next = Instant::now();
    let mut k = 0u64;
    while !stop.load(Ordering::Relaxed) {
        let now = unix_ms_now();
        if k.is_multiple_of(3) {
            let i = (k / 3 % 4) as usize;
            let ok = attackers[i]
                .datagram(now)
                .is_ok_and(|d| sock.send_to(&d, v2x).is_ok());
            sent.count(&sent.forged[i], ok);
        }
        if k % 5 == 1 {
            let len = noise.between(1, 1200);
            let ok = sock.send_to(&noise.octets(len), v2x).is_ok();
            sent.count(&sent.garbage, ok);
        }
        if k % 10 == 2 {
            let frame = if k % 20 == 2 { &map } else { &tim };
            let ok = genuine.sign(frame, now).is_ok_and(|d| {
                let cut = noise.between(1, d.len() - 1);
                sock.send_to(&d[..cut], v2x).is_ok()
            });
            sent.count(&sent.truncated, ok);
        }
        k += 1;
        next += Duration::from_millis(100);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lap_passes_warning_zone_and_leaving_every_time() {
        let road = hmi_bench::road();
        let lap_s = (LAP.to_m - LAP.from_m) / LAP.speed_mps;
        let zone_limit_mps = 40.0 / 3.6;
        assert!(LAP.speed_mps < zone_limit_mps && lap_s < 70.0, "{lap_s}");
        let mut stations = Vec::new();
        for k in 0..=1300 {
            let t = f64::from(k) * 0.1;
            assert!(lap_epoch(&road, t, Utc::from_unix_ms(0)).is_some());
            stations.push(LAP.station(t));
        }
        // Warning at 100 m: 400 m before the zone leaves room for information first.
        let before = |s: f64| hmi_bench::ZONE_START_M - s;
        assert!(stations.iter().any(|&s| before(s) > 300.0));
        assert!(stations.iter().any(|&s| s > hmi_bench::ZONE_END_M + 50.0));
        assert_eq!(
            (laps(lap_s - 0.1), laps(lap_s + 0.1), laps(130.0)),
            (0, 1, 2)
        );
    }

    #[test]
    fn sent_epochs_are_found_by_fix_number_while_kept() {
        let sent = Sent::default();
        let t0 = Instant::now();
        for _ in 0..SENT_KEPT + 5 {
            sent.record_epoch(t0);
        }
        assert_eq!(sent.epochs.load(Ordering::Relaxed), SENT_KEPT as u64 + 5);
        assert_eq!(sent.epoch_sent(5), None, "dropped from the window");
        assert_eq!(sent.epoch_sent(6), Some(t0));
        assert_eq!(sent.epoch_sent(SENT_KEPT as u64 + 5), Some(t0));
        assert_eq!(sent.epoch_sent(SENT_KEPT as u64 + 6), None);
        assert_eq!(sent.epoch_sent(0), None);
    }

    #[test]
    fn the_noise_is_reproducible_and_spread() {
        let (mut a, mut b) = (Noise::new(7), Noise::new(7));
        assert_eq!(a.octets(64), b.octets(64));
        let lens: Vec<usize> = (0..1000).map(|_| a.between(1, 1200)).collect();
        assert!(lens.iter().all(|l| (1..=1200).contains(l)));
        assert!(lens.iter().any(|&l| l < 100) && lens.iter().any(|&l| l > 1100));
    }

    #[test]
    fn every_forged_kind_has_a_security_reason_of_its_own() {
        let mut reasons: Vec<&str> = FORGED.iter().map(|(_, r)| r.as_str()).collect();
        reasons.sort_unstable();
        reasons.dedup();
        assert_eq!(reasons.len(), 4);
        for (_, r) in FORGED {
            assert_eq!(crate::attack::status_group(r.group()), "security_errors");
        }
    }
}
