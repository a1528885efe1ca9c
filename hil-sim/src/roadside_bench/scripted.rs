//! The roadside unit of a scripted run (the bench's scenarios): broadcasts the MAP and one
//! TIM per zone at 10 Hz to the OBU's V2X port, following the site's timeline (TIM
//! delayed, MAP revision changed, zones shrunk or removed) through its radio faults (loss,
//! corruption), the broadcaster's fault model ([`roadside::broadcast::FaultInjector`]).

use super::camera_site::{CameraView, LiveSite};
use roadside::broadcast::{FaultInjector, Faults, LossModel, MessageKind, Verdict};
use roadside::clock::Utc;
use roadside::messages::{self, WorkZone};
use roadside::road::{Road, RoadLane};
use roadside::site::Site;
use serde::Serialize;
use std::net::UdpSocket;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Broadcast period (10 Hz).
pub const PERIOD: Duration = Duration::from_millis(100);

/// V2X datagram counts of a run.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct V2xCounts {
    /// Handed to the socket.
    pub sent: u64,
    /// Dropped by the loss model.
    pub lost: u64,
    /// Sent with a flipped bit.
    pub corrupted: u64,
}

/// The messages on the air at one moment.
struct OnAir {
    map: Vec<u8>,
    tims: Vec<Vec<u8>>,
}

/// The roadside's state over the run: which MAP revision, which zones, which `msgCnt`.
struct Timeline {
    road: Road,
    shifted: Option<Road>,
    zones: Vec<WorkZone>,
    removed: Vec<bool>,
    shrunk: Vec<bool>,
}

impl Timeline {
    /// The messages at `t` seconds (re-encoded only when something changed).
    fn at(&mut self, s: &Site, t: f64) -> Result<Option<OnAir>, String> {
        let mut changed = t == 0.0;
        for (i, spec) in s.zones.iter().enumerate() {
            if let Some((at, end_m)) = spec.shrink_at {
                if t >= at && !self.shrunk[i] {
                    self.shrunk[i] = true;
                    self.zones[i].end_m = end_m.max(self.zones[i].start_m + 1.0);
                    self.zones[i].msg_cnt = self.zones[i].msg_cnt.wrapping_add(1) % 128;
                    changed = true;
                }
            }
            if spec.removed_at_s.is_some_and(|at| t >= at) && !self.removed[i] {
                // Cones gone: the TIM is cancelled (durationTime 0) with a new msgCnt.
                self.removed[i] = true;
                self.zones[i].duration_min = 0;
                self.zones[i].msg_cnt = self.zones[i].msg_cnt.wrapping_add(1) % 128;
                changed = true;
            }
        }
        let revised = s.faults.map_revision_at_s.is_some_and(|at| t >= at);
        if revised && self.shifted.is_none() {
            self.shifted = Some(shift(&self.road, s.faults.map_shift_m));
            changed = true;
        }
        if !changed {
            return Ok(None);
        }
        let (road, revision) = match &self.shifted {
            Some(r) => (r, 2),
            None => (&self.road, 1),
        };
        let e = |x: messages::BuildError| x.to_string();
        let map = messages::build_map(road, 1, revision, self.zones.first()).map_err(e)?;
        let map = messages::encode(&map).map_err(e)?;
        let mut tims = Vec::new();
        for z in &self.zones {
            let tim = messages::build_tim(road, z).map_err(e)?;
            tims.push(messages::encode(&tim).map_err(e)?);
        }
        Ok(Some(OnAir { map, tims }))
    }
}

/// The road with every lane moved `left_m` to the left of its direction of travel (a
/// resurveyed map: new MAP revision; the attacker's forged map).
pub(crate) fn shift(road: &Road, left_m: f64) -> Road {
    let lanes = road
        .lanes
        .iter()
        .map(|l| {
            let centre = (0..l.centre.len())
                .map(|i| {
                    let s: f64 = l.centre[..=i]
                        .windows(2)
                        .map(|w| roadside::road::dist(w[0], w[1]))
                        .sum();
                    l.beside(s, left_m).map_or(l.centre[i], |o| o.point)
                })
                .collect();
            RoadLane {
                centre,
                ..l.clone()
            }
        })
        .collect();
    Road::new(road.reference, lanes)
}

/// The radio faults of a scenario as the broadcaster's fault model: losses (bursty when
/// the mean burst length is over 1), bit flips, and no TIM before the delay.
fn radio(s: &Site, t0: Instant) -> Result<FaultInjector, String> {
    let f = &s.faults;
    let loss = if f.loss_rate <= 0.0 {
        LossModel::None
    } else if f.loss_burst > 1.0 {
        LossModel::bursts(f.loss_rate, f.loss_burst).map_err(|e| format!("faults: {e}"))?
    } else {
        LossModel::independent(f.loss_rate).map_err(|e| format!("faults: {e}"))?
    };
    FaultInjector::new(Faults {
        loss,
        corrupt_fraction: f.corrupt_rate,
        tim_not_before: (f.tim_delay_s > 0.0).then(|| t0 + Duration::from_secs_f64(f.tim_delay_s)),
        seed: f.seed,
    })
    .map_err(|e| format!("faults: {e}"))
}

/// What the roadside thread returns: when each new version of the MAP/TIMs first left,
/// the datagram counts, and what the camera site's cameras saw.
#[derive(Debug, Clone, Default)]
pub struct RoadsideRun {
    /// When each new version of the messages first left.
    pub changes: Vec<Instant>,
    /// Datagram counts (PSMs included).
    pub counts: V2xCounts,
    /// The camera site's views (empty without one).
    pub views: Vec<CameraView>,
    /// Workers' PSMs sent.
    pub psms: u64,
    /// The camera site's processing time per tick (render, localize, track, build the
    /// PSMs), milliseconds: sum and largest, and the ticks. A tick over the broadcast
    /// period makes the site fall behind (its PSMs leave late).
    pub camera_ms: (f64, f64, u64),
}

/// Starts the roadside thread; it stops when `stop` turns true and returns when each new
/// version of the messages first left, and the datagram counts. With a `signer`, every
/// frame goes out as IEEE 1609.2 signed data generated at its send time (before the radio
/// faults, which then damage signed bytes as they would on the air). With a `camera`
/// site, each tick is also one camera frame: its workers' PSMs go out with the MAP and TIMs.
#[allow(clippy::too_many_arguments)]
pub fn spawn(
    s: &Site,
    road: &Road,
    zones: &[WorkZone],
    to: &str,
    t0: Instant,
    stop: Arc<AtomicBool>,
    signer: Option<Arc<roadside::signer::RsuSigner>>,
    mut camera: Option<LiveSite>,
) -> Result<JoinHandle<RoadsideRun>, String> {
    let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let to = to.to_string();
    let s = s.clone();
    let mut timeline = Timeline {
        road: road.clone(),
        shifted: None,
        zones: zones.to_vec(),
        removed: vec![false; zones.len()],
        shrunk: vec![false; zones.len()],
    };
    let mut air = timeline.at(&s, 0.0)?.ok_or("no messages at the start")?;
    let radio = radio(&s, t0)?;
    Ok(std::thread::spawn(move || {
        let mut out = Sender {
            sock,
            to,
            signer,
            radio,
            counts: V2xCounts::default(),
        };
        let mut run = RoadsideRun::default();
        // When each new version of the messages first left (the first datagram sent after
        // a change): the runner times the state it causes on the tablet.
        let mut pending = true;
        let mut next = t0;
        while !stop.load(Ordering::Relaxed) {
            let t = next.saturating_duration_since(t0).as_secs_f64();
            if let Ok(Some(new)) = timeline.at(&s, t) {
                pending |= t > 0.0;
                air = new;
            }
            let now = Instant::now();
            for frame in std::iter::once(&air.map).chain(&air.tims) {
                if out.send(frame, now) && std::mem::take(&mut pending) {
                    run.changes.push(Instant::now());
                }
            }
            if let Some(site) = camera.as_mut() {
                // The frame is taken now, not at the tick's due time: a site that fell
                // behind drops frames, as a real camera pipeline does, instead of working
                // through old ones.
                let started = Instant::now();
                let taken = started.saturating_duration_since(t0).as_secs_f64();
                let psms = site.tick(taken, Utc::from_unix_ms(roadside::clock::unix_ms_now()));
                let ms = started.elapsed().as_secs_f64() * 1000.0;
                let (sum, max, n) = &mut run.camera_ms;
                (*sum, *max, *n) = (*sum + ms, max.max(ms), *n + 1);
                for psm in psms {
                    if let Ok(frame) = messages::encode(&psm) {
                        run.psms += u64::from(out.send(&frame, Instant::now()));
                    }
                }
            }
            next += PERIOD;
            let now = Instant::now();
            if next + PERIOD < now {
                // Overrun by more than a period: start again from now rather than send the
                // missed ticks back to back.
                next = now;
            }
            std::thread::sleep(next.saturating_duration_since(now));
        }
        run.counts = out.counts;
        run.views = camera.map(|c| c.views).unwrap_or_default();
        run
    }))
}

/// The roadside's radio: signs, applies the faults, sends and counts.
struct Sender {
    sock: UdpSocket,
    to: String,
    signer: Option<Arc<roadside::signer::RsuSigner>>,
    radio: FaultInjector,
    counts: V2xCounts,
}

impl Sender {
    /// Sends one frame (signed when there is a signer) through the radio faults; true
    /// when it left.
    fn send(&mut self, frame: &[u8], now: Instant) -> bool {
        let kind = MessageKind::of_frame(frame).unwrap_or(MessageKind::Other(0));
        let mut d = match &self.signer {
            Some(signer) => match signer.sign(frame, roadside::clock::unix_ms_now()) {
                Ok(signed) => signed,
                Err(_) => return false,
            },
            None => frame.to_vec(),
        };
        match self.radio.decide(0, kind, now, &mut d) {
            Verdict::Drop(_) => {
                self.counts.lost += 1;
                return false;
            }
            Verdict::Corrupted { .. } => self.counts.corrupted += 1,
            Verdict::Send => {}
        }
        let sent = self.sock.send_to(&d, &self.to).is_ok();
        self.counts.sent += u64::from(sent);
        sent
    }
}
