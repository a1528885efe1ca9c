//! An attacker beside the roadside (the bench's spoofing scenarios; a scenario's
//! `[attacker]`): a second sender on the roadside's channel that broadcasts one forged or
//! replayed MAP or TIM to the OBU's V2X port at its own rate, from a given time into the
//! drive, and counts what it sent. The OBU must drop every one of them, each with its
//! reason, and keep showing the real zone.
//!
//! The attacker has what anyone near the road has: the real broadcast (MAP, TIM and the
//! RSU certificate every signed message carries), a recording of yesterday's broadcast,
//! and its own IEEE 1609.2 PKI (root, CA and RSU certificates for the same PSIDs, made
//! like the bench's but from another seed: no OBU trusts it). It never has the real RSU's
//! private key. The bench makes "yesterday's recording" with the real signer and a
//! generation time a day back ([`REPLAY_AGE_MS`]): the bytes a recorder would have kept.

use j2735::envelope::Psid;
use roadside::clock::{unix_ms_now, Utc};
use roadside::messages::{self, WorkZone, DURATION_INDEFINITE};
use roadside::pki::{Pki, PkiSpec};
use roadside::road::Road;
use roadside::signer::RsuSigner;
use serde::{Deserialize, Serialize};
use std::net::{SocketAddr, UdpSocket};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How far the forged MAP moves every lane to the left, metres.
pub const MAP_SHIFT_M: f64 = 3.0;
/// The forged MAP's revision: above the scripted roadside's (1, and 2 after a revision),
/// so that an OBU that took it would replace the real lane map.
pub const FORGED_REVISION: u8 = 3;
/// Age of the replayed recording, milliseconds (a day).
pub const REPLAY_AGE_MS: u64 = 86_400_000;
/// How much further back along the road yesterday's zone lay than today's, metres.
pub const YESTERDAY_BACK_M: f64 = 150.0;
/// `packetID` of yesterday's zone (another zone than today's).
pub const YESTERDAY_PACKET_ID: [u8; 9] = *b"YESTERDAY";
/// Seed of the attacker's PKI ([`PkiSpec::seed`]).
pub const ATTACKER_SEED: &str = "attacker";

/// What the attacker broadcasts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AttackKind {
    /// The first zone's TIM cancelled (same `packetID`, `msgCnt` + 1, `durationTime` 0),
    /// signed by the attacker's own RSU certificate (its chain ends at the attacker's
    /// root, which no OBU trusts).
    ForgedCancelUntrusted,
    /// The same cancel, unsigned.
    ForgedCancelUnsigned,
    /// The lane map with every lane [`MAP_SHIFT_M`] to the left under a higher revision
    /// ([`FORGED_REVISION`]), signed with the attacker's key under the real RSU's
    /// certificate (copied from the air): the chain is trusted, the signature is not the
    /// certificate holder's.
    MapShifted,
    /// Yesterday's recording played back at its own pace: TIMs the real RSU signed
    /// [`REPLAY_AGE_MS`] ago for yesterday's zone (the first zone's lanes and length,
    /// [`YESTERDAY_BACK_M`] further back, `packetID` [`YESTERDAY_PACKET_ID`], valid until
    /// further notice): signed by the real key, only old.
    ReplayedYesterday,
    /// The first zone's TIM exactly as the real roadside signed it, replayed after the
    /// roadside cancelled the zone: with a roadside that signs once and repeats
    /// (`[signing] pattern = "once"`) the bytes are the original's (signed by the real key,
    /// not yet expired), so only the superseded check can refuse them.
    ReplayedOriginal,
}

/// A scenario's `[attacker]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AttackerSpec {
    /// What it broadcasts.
    pub kind: AttackKind,
    /// First datagram this many seconds into the drive (after the OBU has GNSS time:
    /// before it, a signed frame is dropped for want of a clock, whoever signed it).
    #[serde(default = "default_start_s")]
    pub start_s: f64,
    /// Datagrams per second.
    #[serde(default = "default_rate_hz")]
    pub rate_hz: f64,
}

fn default_start_s() -> f64 {
    3.0
}

fn default_rate_hz() -> f64 {
    10.0
}

impl AttackerSpec {
    /// Checks the times: a start from 0 on and a rate over 0 and at most 100 Hz.
    ///
    /// # Errors
    ///
    /// A message naming the key that is out of range.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.start_s >= 0.0 && self.start_s.is_finite()) {
            return Err(format!("attacker: start_s {} is not >= 0", self.start_s));
        }
        if !(self.rate_hz > 0.0 && self.rate_hz <= 100.0) {
            return Err(format!(
                "attacker: rate_hz {} is not in (0, 100]",
                self.rate_hz
            ));
        }
        Ok(())
    }

    /// Time between two datagrams.
    pub fn period(&self) -> Duration {
        Duration::from_secs_f64(1.0 / self.rate_hz)
    }
}

/// What the attacker sent over a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct AttackCounts {
    /// Datagrams handed to the socket.
    pub sent: u64,
    /// Datagrams it could not make or send.
    pub failed: u64,
    /// Seconds after the run's start of the first datagram sent.
    pub first_sent_s: Option<f64>,
    /// Seconds after the run's start of the last datagram sent.
    pub last_sent_s: Option<f64>,
}

/// How the forged frame goes on the air.
#[derive(Debug)]
enum Wrapping {
    /// As it is.
    Unsigned,
    /// Signed at send time.
    Signed(RsuSigner),
    /// Signed by the real RSU [`REPLAY_AGE_MS`] before the send time (the recording).
    Recorded(Arc<RsuSigner>),
}

/// One attack: the forged frame and how it is wrapped.
#[derive(Debug)]
pub struct Attacker {
    frame: Vec<u8>,
    wrapping: Wrapping,
}

/// The attacker's PKI: a root, CA and RSU certificate for TIM and MAP, valid like the
/// bench's (from 2025-01-01, RSU for 2730 days), from [`ATTACKER_SEED`].
///
/// # Errors
///
/// The PKI's message (never expected: the values are fixed).
pub fn attacker_pki() -> Result<Pki, String> {
    Pki::create(&attacker_spec()).map_err(|e| e.to_string())
}

/// The specification of [`attacker_pki`].
fn attacker_spec() -> PkiSpec {
    PkiSpec {
        seed: Some(ATTACKER_SEED.into()),
        start_unix_s: 1_735_689_600,
        root_years: 20,
        ca_years: 15,
        rsu_hours: 2730 * 24,
        region: None,
        psids: vec![Psid::TIM, Psid::MAP],
        rsu_name: "rsu.attacker.example".into(),
    }
}

impl Attacker {
    /// The attack of `kind` on the real roadside's `road` and `zones`; `genuine` is the
    /// real RSU's signer, of which the attacker uses only its certificate (on the air)
    /// and, for the replay, yesterday's signatures (the recording).
    ///
    /// # Errors
    ///
    /// A message when the kind needs a zone and there is none, or a message fails to
    /// build.
    pub fn new(
        kind: AttackKind,
        road: &Road,
        zones: &[WorkZone],
        genuine: &Arc<RsuSigner>,
    ) -> Result<Self, String> {
        let first = || {
            zones
                .first()
                .cloned()
                .ok_or_else(|| format!("attacker: {kind:?} needs a work zone to forge"))
        };
        let (frame, wrapping) = match kind {
            AttackKind::ForgedCancelUntrusted => {
                let own = attacker_pki()?;
                let signer = RsuSigner::new(own.rsu.cert, own.rsu.key, None, 60_000);
                let tim = messages::build_tim(road, &cancel(first()?));
                (tim, Wrapping::Signed(signer))
            }
            AttackKind::ForgedCancelUnsigned => (
                messages::build_tim(road, &cancel(first()?)),
                Wrapping::Unsigned,
            ),
            AttackKind::MapShifted => {
                let copied = genuine.certificate().to_vec();
                let signer = RsuSigner::new(copied, attacker_pki()?.rsu.key, None, 60_000);
                let shifted = crate::roadside_bench::scripted::shift(road, MAP_SHIFT_M);
                let map = messages::build_map(&shifted, 1, FORGED_REVISION, zones.first());
                (map, Wrapping::Signed(signer))
            }
            AttackKind::ReplayedYesterday => (
                messages::build_tim(road, &yesterday(first()?)),
                Wrapping::Recorded(genuine.clone()),
            ),
            // The genuine signer's clone shares what it signed once: the original's bytes.
            AttackKind::ReplayedOriginal => (
                messages::build_tim(road, &first()?),
                Wrapping::Signed(RsuSigner::clone(genuine)),
            ),
        };
        let frame = frame
            .and_then(|f| messages::encode(&f))
            .map_err(|e| format!("attacker: {e}"))?;
        Ok(Self { frame, wrapping })
    }

    /// The forged J2735 `MessageFrame` (UPER), before any signature.
    pub fn frame(&self) -> &[u8] {
        &self.frame
    }

    /// The datagram the attacker sends at `unix_ms`.
    ///
    /// # Errors
    ///
    /// The signer's message (a frame too large to sign).
    pub fn datagram(&self, unix_ms: u64) -> Result<Vec<u8>, String> {
        let signed = match &self.wrapping {
            Wrapping::Unsigned => return Ok(self.frame.clone()),
            Wrapping::Signed(signer) => signer.sign(&self.frame, unix_ms),
            Wrapping::Recorded(signer) => {
                signer.sign(&self.frame, unix_ms.saturating_sub(REPLAY_AGE_MS))
            }
        };
        signed.map_err(|e| e.to_string())
    }
}

/// `zone` cancelled: the next `msgCnt`, `durationTime` 0.
fn cancel(mut zone: WorkZone) -> WorkZone {
    zone.msg_cnt = zone.msg_cnt.wrapping_add(1) % 128;
    zone.duration_min = 0;
    zone
}

/// Yesterday's zone at the site: `zone`'s lanes and length [`YESTERDAY_BACK_M`] further
/// back (from station 0 at the least), begun a day before it, valid until further notice.
fn yesterday(zone: WorkZone) -> WorkZone {
    let length = zone.end_m - zone.start_m;
    let start_m = (zone.start_m - YESTERDAY_BACK_M).max(0.0);
    WorkZone {
        start_m,
        end_m: start_m + length,
        packet_id: YESTERDAY_PACKET_ID,
        msg_cnt: 1,
        start: Utc::from_unix_ms(zone.start.to_unix_ms().saturating_sub(REPLAY_AGE_MS)),
        duration_min: DURATION_INDEFINITE,
        ..zone
    }
}

/// Starts the attacker's thread: from `t0` + `spec.start_s` it sends
/// [`Attacker::datagram`] to `to` every [`AttackerSpec::period`] until `stop` turns
/// true, then returns what it sent. Returns the thread and the address it sends from
/// (a relay on the way can tell the attacker's datagrams by it).
///
/// # Errors
///
/// An invalid spec, or no socket.
pub fn spawn(
    spec: &AttackerSpec,
    attacker: Attacker,
    to: &str,
    t0: Instant,
    stop: Arc<AtomicBool>,
) -> Result<(JoinHandle<AttackCounts>, SocketAddr), String> {
    spec.validate()?;
    let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let from = sock.local_addr().map_err(|e| e.to_string())?;
    let to = to.to_string();
    let period = spec.period();
    let mut next = t0 + Duration::from_secs_f64(spec.start_s);
    let handle = std::thread::spawn(move || {
        let mut counts = AttackCounts::default();
        loop {
            // Sleep in short steps so that a stop is seen soon.
            while !stop.load(Ordering::Relaxed) && Instant::now() < next {
                let left = next.saturating_duration_since(Instant::now());
                std::thread::sleep(left.min(Duration::from_millis(50)));
            }
            if stop.load(Ordering::Relaxed) {
                return counts;
            }
            let sent = attacker
                .datagram(unix_ms_now())
                .is_ok_and(|d| sock.send_to(&d, &to).is_ok());
            if sent {
                let at = Some(t0.elapsed().as_secs_f64());
                counts.sent += 1;
                counts.first_sent_s = counts.first_sent_s.or(at);
                counts.last_sent_s = at;
            } else {
                counts.failed += 1;
            }
            next += period;
        }
    });
    Ok((handle, from))
}

#[cfg(test)]
mod tests {
    use super::*;
    use geodesy::LatLon;
    use j2735::envelope::ieee1609dot2::{Certificate, Ieee1609Dot2Data, SignerIdentifier};

    fn road() -> Road {
        let at = LatLon::from_degrees(39.7392, -104.9903).unwrap();
        Road::straight(at, 90.0, 800.0, (2, 0), 3.6, 40.0)
    }

    fn zone() -> WorkZone {
        WorkZone {
            closed_lanes: vec![2],
            start_m: 420.0,
            end_m: 520.0,
            speed_limit: None,
            packet_id: *b"HILZONE00",
            msg_cnt: 127,
            start: Utc::from_unix_ms(1_767_225_600_000),
            duration_min: DURATION_INDEFINITE,
        }
    }

    fn genuine() -> Arc<RsuSigner> {
        let pki = Pki::create(&PkiSpec {
            seed: Some("genuine".into()),
            ..attacker_spec()
        })
        .unwrap();
        Arc::new(RsuSigner::new(pki.rsu.cert, pki.rsu.key, None, 60_000))
    }

    /// The signer certificate and generation time (µs since 2004, TAI) of a datagram.
    fn signed_by(datagram: &[u8]) -> (Vec<u8>, u64) {
        let data = Ieee1609Dot2Data::parse(datagram).unwrap();
        let signed = data.signed_data().unwrap();
        let SignerIdentifier::Certificate(chain) = signed.signer else {
            panic!("not signed with a certificate")
        };
        let cert: Certificate<'_> = chain.first().unwrap();
        let time = signed.header.generation_time.unwrap().0;
        (cert.encoded.to_vec(), time)
    }

    #[test]
    fn the_cancel_is_the_next_msg_cnt_with_duration_zero() {
        let z = cancel(zone());
        assert_eq!((z.msg_cnt, z.duration_min), (0, 0), "127 + 1 wraps to 0");
        assert_eq!(z.packet_id, *b"HILZONE00");
    }

    #[test]
    fn yesterdays_zone_lies_back_along_the_road_a_day_earlier() {
        let z = yesterday(zone());
        assert_eq!((z.start_m, z.end_m), (270.0, 370.0));
        assert_eq!(z.packet_id, YESTERDAY_PACKET_ID);
        assert_eq!(z.start.to_unix_ms(), 1_767_225_600_000 - REPLAY_AGE_MS);
        let near_start = yesterday(WorkZone {
            start_m: 100.0,
            end_m: 160.0,
            ..zone()
        });
        assert_eq!((near_start.start_m, near_start.end_m), (0.0, 60.0));
    }

    #[test]
    fn each_kind_is_wrapped_as_it_says() {
        let (road, genuine) = (road(), genuine());
        let now = 1_767_225_600_000;
        let own = attacker_pki().unwrap();
        let make = |k| Attacker::new(k, &road, &[zone()], &genuine).unwrap();

        let unsigned = make(AttackKind::ForgedCancelUnsigned);
        assert_eq!(unsigned.datagram(now).unwrap(), unsigned.frame());
        assert_eq!(&unsigned.frame()[..2], &[0x00, 0x1f], "a TIM");

        let untrusted = make(AttackKind::ForgedCancelUntrusted);
        assert_eq!(untrusted.frame(), unsigned.frame(), "the same cancel");
        let (cert, time) = signed_by(&untrusted.datagram(now).unwrap());
        assert_eq!(cert, own.rsu.cert, "the attacker's own certificate");
        assert_eq!(time, roadside::pki::time64_of_unix_ms(now));

        let map = make(AttackKind::MapShifted);
        assert_eq!(&map.frame()[..2], &[0x00, 0x12], "a MAP");
        let (cert, _) = signed_by(&map.datagram(now).unwrap());
        assert_eq!(cert, genuine.certificate(), "the real certificate, copied");

        let replay = make(AttackKind::ReplayedYesterday);
        let (cert, time) = signed_by(&replay.datagram(now).unwrap());
        assert_eq!(cert, genuine.certificate());
        assert_eq!(time, roadside::pki::time64_of_unix_ms(now - REPLAY_AGE_MS));
    }

    #[test]
    fn the_shifted_map_moves_the_lanes_three_metres_left() {
        let road = road();
        let shifted = crate::roadside_bench::scripted::shift(&road, MAP_SHIFT_M);
        for (a, b) in road.lanes.iter().zip(&shifted.lanes) {
            let ([px, py], [qx, qy]) = (a.centre[0], b.centre[0]);
            // Eastbound: left is north.
            assert!((qy - py - MAP_SHIFT_M).abs() < 1e-6 && (qx - px).abs() < 1e-6);
        }
    }

    #[test]
    fn the_cancels_need_a_zone_and_the_spec_is_checked() {
        let none = Attacker::new(AttackKind::ForgedCancelUnsigned, &road(), &[], &genuine());
        assert!(none.unwrap_err().contains("needs a work zone"));
        assert!(Attacker::new(AttackKind::MapShifted, &road(), &[], &genuine()).is_ok());
        let spec: AttackerSpec = serde_json::from_str(r#"{"kind": "map_shifted"}"#).unwrap();
        assert_eq!((spec.start_s, spec.rate_hz), (3.0, 10.0));
        assert_eq!(spec.period(), Duration::from_millis(100));
        for bad in [
            r#"{"kind": "map_shifted", "rate_hz": 0}"#,
            r#"{"kind": "map_shifted", "start_s": -1}"#,
        ] {
            let spec: AttackerSpec = serde_json::from_str(bad).unwrap();
            assert!(spec.validate().is_err(), "{bad}");
        }
    }

    #[test]
    fn the_thread_sends_at_its_rate_from_its_start_until_stopped() {
        let rx = UdpSocket::bind("127.0.0.1:0").unwrap();
        rx.set_read_timeout(Some(Duration::from_secs(2))).unwrap();
        let to = rx.local_addr().unwrap().to_string();
        let spec = AttackerSpec {
            kind: AttackKind::ForgedCancelUnsigned,
            start_s: 0.2,
            rate_hz: 50.0,
        };
        let attacker = Attacker::new(spec.kind, &road(), &[zone()], &genuine()).unwrap();
        let frame = attacker.frame().to_vec();
        let stop = Arc::new(AtomicBool::new(false));
        let t0 = Instant::now();
        let (handle, _) = spawn(&spec, attacker, &to, t0, stop.clone()).unwrap();
        let mut buf = [0u8; 2048];
        let n = rx.recv(&mut buf).unwrap();
        assert_eq!(&buf[..n], &frame[..]);
        assert!(
            t0.elapsed() >= Duration::from_millis(200),
            "not before its start"
        );
        std::thread::sleep(Duration::from_millis(300));
        stop.store(true, Ordering::Relaxed);
        let stopped_s = t0.elapsed().as_secs_f64();
        let counts = handle.join().unwrap();
        let mut received = 1;
        rx.set_read_timeout(Some(Duration::from_millis(200)))
            .unwrap();
        while rx.recv(&mut buf).is_ok() {
            received += 1;
        }
        assert_eq!((counts.sent, counts.failed), (received, 0));
        // The grid: slot k at 0.2 + k / 50 s. Never ahead of it: the last of `sent`
        // datagrams went at slot sent - 1 or later. The stop honoured: no slot after the
        // stop was set, but the one whose send may have been under way then. Bounds from
        // the attacker's own clock and the moment the stop was set, not from how late this
        // thread woke from its 300 ms (a starved thread wakes late, the attacker keeps on).
        let (first, last) = (counts.first_sent_s.unwrap(), counts.last_sent_s.unwrap());
        let slots_by = |t: f64| ((t - 0.2) * 50.0 + 1e-6).floor() as u64 + 1;
        assert!(first >= 0.2 && last > first, "{counts:?}");
        assert!(
            slots_by(last) >= counts.sent,
            "ahead of the grid: {counts:?}"
        );
        assert!(
            counts.sent <= slots_by(stopped_s) + 1,
            "{counts:?}, stopped at {stopped_s}"
        );
        // Most of the 15 slots of the 300 ms after the first one (a late attacker catches
        // up in a burst).
        assert!(counts.sent >= 10, "{counts:?}");
    }
}
