//! The hub between the inputs and the tablet: it owns the OBU core, turns every input into
//! core calls, publishes each `HmiState` as a numbered event (kept in a ring for clients that
//! resume with `Last-Event-ID`), and counts everything that was dropped, with its reason.
//!
//! In bridge mode the core runs in the firmware instead: its states arrive whole and are
//! published through [`Hub::publish_state`], the same path as the core's own.

use crate::counters::Counters;
use crate::settings::Settings;
use obu::alert::{AlertConfig, HmiState};
use obu::fix::{AccuracySource, Fix};
use obu::input::nmea::{NoFix, Solution};
use obu::time::Instant;
use obu::v2x::{V2xOutcome, V2xReceiver};
use std::collections::VecDeque;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use tokio::sync::{broadcast, watch, Notify};

/// One published state: its sequence number and the JSON the event stream sends.
#[derive(Debug)]
pub struct Event {
    /// Sequence number within this run of the daemon (the SSE id is `<run>-<seq>`).
    pub seq: u64,
    /// `{"seq", "state", "gnss_age_ms", "fix_quality"}`.
    pub json: String,
}

/// The largest RSU text payload taken, octets: what a UDP datagram's hexadecimal text
/// can hold.
const RSU_PAYLOAD_MAX: usize = 32 * 1024;

struct Inner {
    core: Box<obu::Obu>,
    /// The core's receive path: MAP and TIM decode targets, RSU payload buffer, and the
    /// IEEE 1609.2 trust store.
    receiver: Box<V2xReceiver<RSU_PAYLOAD_MAX>>,
    seq: u64,
    recent: VecDeque<Arc<Event>>,
    last_fix: Option<Instant>,
    gnss: ReceiverStatus,
    /// The last no-fix reason logged (a receiver flapping between a fix and its simulator
    /// is logged once, not at every change).
    logged_no_fix: Option<NoFix>,
    /// Give the core the system clock to check GNSS time against.
    system_clock: bool,
    /// Where the superseded check's markers are kept across restarts.
    markers_file: Option<std::path::PathBuf>,
    settings: Settings,
    /// Lane models and work zones of the last external state (bridge mode).
    external: Option<(u8, u8)>,
}

/// Shared by every task of the daemon.
pub struct Hub {
    inner: Mutex<Inner>,
    events: broadcast::Sender<Arc<Event>>,
    keep: usize,
    started: std::time::Instant,
    run: u64,
    /// Woken by every input that reached the core (its next deadline may have moved).
    wake: Notify,
    /// Turns of the deadline loop: the watchdog pings systemd only while it moves.
    turns: AtomicU64,
    /// Counters of inputs and drops.
    pub counters: Counters,
}

impl Hub {
    /// A hub keeping `keep` events, with the core configured from `settings`.
    pub fn new(settings: Settings, base: AlertConfig, keep: usize) -> Arc<Self> {
        let (events, _) = broadcast::channel(keep.max(16));
        let mut core = Box::new(obu::Obu::new(base));
        core.set_config(alert_config(base, &settings));
        Arc::new(Self {
            inner: Mutex::new(Inner {
                core,
                receiver: Box::default(),
                seq: 0,
                recent: VecDeque::with_capacity(keep),
                last_fix: None,
                gnss: ReceiverStatus::default(),
                logged_no_fix: None,
                system_clock: false,
                markers_file: None,
                settings,
                external: None,
            }),
            events,
            keep,
            started: std::time::Instant::now(),
            run: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_millis() as u64),
            wake: Notify::new(),
            turns: AtomicU64::new(0),
            counters: Counters::default(),
        })
    }

    /// Milliseconds since the daemon started: the core's clock.
    pub fn now(&self) -> Instant {
        Instant::from_millis(self.started.elapsed().as_millis() as u64)
    }

    /// The SSE id of event `seq`: `<run>-<seq>`, where `run` (the start time in Unix
    /// milliseconds) tells a resuming client of an earlier run of the daemon from one of
    /// this run, whose sequence numbers started again at 1.
    pub fn event_id(&self, seq: u64) -> String {
        format!("{}-{seq}", self.run)
    }

    /// The sequence number of a `Last-Event-ID` of this run; `None` for an id of another
    /// run or one that does not parse (the client is served as a new one).
    pub fn resume_seq(&self, last_event_id: &str) -> Option<u64> {
        let (run, seq) = last_event_id.trim().split_once('-')?;
        (run.parse() == Ok(self.run)).then(|| seq.parse().ok())?
    }

    /// Seconds since start.
    pub fn uptime_s(&self) -> u64 {
        self.started.elapsed().as_secs()
    }

    fn lock(&self) -> MutexGuard<'_, Inner> {
        // A panic elsewhere must not stop the vehicle display: keep using the data.
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Sets the IEEE 1609.2 trust policy: its settings and the trust anchors (certificate
    /// COER bytes, each named for errors).
    pub fn configure_security(
        &self,
        config: obu::security::SecurityConfig,
        anchors: &[(String, Vec<u8>)],
        markers: Option<(std::path::PathBuf, Vec<obu::security::Marker>)>,
    ) -> Result<(), String> {
        let mut inner = self.lock();
        if let Some((path, kept)) = markers {
            // Kept markers age out as new ones are recorded (GNSS time is not known yet).
            inner.receiver.trust_mut().restore_markers(&kept, 0);
            inner.markers_file = Some(path);
        }
        let trust = inner.receiver.trust_mut();
        trust.set_config(config);
        for (name, coer) in anchors {
            trust
                .add_anchor(coer)
                .map_err(|e| format!("trust anchor {name}: {e:?}"))?;
        }
        Ok(())
    }

    /// One received V2X datagram into the core's receive path; when it changed what is
    /// stored (zones or maps stored, replaced or cancelled, a new road worker) or what a
    /// worker means for the car ([`V2xOutcome::Changed`]) the new state is published at
    /// once.
    pub fn on_datagram(&self, datagram: &[u8]) -> V2xOutcome {
        let now = self.now();
        let mut inner = self.lock();
        let Inner { core, receiver, .. } = &mut *inner;
        let outcome = core.on_datagram(now, datagram, receiver);
        match outcome {
            V2xOutcome::Changed(_) => {
                let state = inner.core.state(now);
                self.publish(&mut inner, &state);
                self.wake.notify_one();
                // A change (a zone stored, replaced or cancelled) is what a restart must not
                // undo: the markers of the newest versions go to the state directory.
                if let Some(path) = inner.markers_file.clone() {
                    let markers = inner.receiver.trust().markers().to_vec();
                    drop(inner);
                    if let Err(e) = crate::markers::save(&path, &markers) {
                        crate::log::warn("security", &format!("{}: {e}", path.display()));
                    }
                    return outcome;
                }
            }
            V2xOutcome::Unchanged(_) | V2xOutcome::Repeat(_) => self.wake.notify_one(),
            V2xOutcome::Other(_) | V2xOutcome::Dropped(_) => {}
        }
        outcome
    }

    /// A GNSS fix (the core takes the CAN speed over its speed while fresh); publishes the
    /// new state.
    pub fn on_fix(&self, fix: Fix, solution: Option<Solution>) {
        let now = self.now();
        let mut inner = self.lock();
        inner.last_fix = Some(now);
        inner.gnss.record(solution, None, fix.accuracy_source);
        if inner.system_clock {
            if let Some(utc) = system_utc() {
                inner.core.set_reference_time(now, utc);
            }
        }
        let state = inner.core.on_fix(now, fix);
        self.publish(&mut inner, &state);
        self.wake.notify_one();
    }

    /// An epoch in which the receiver gave no fix, and why (the receiver's own dead
    /// reckoning, its simulator, no fix): nothing reaches the core, the status shows it,
    /// and the log says so once for each new reason.
    pub fn on_no_fix(&self, solution: Option<Solution>, why: NoFix) {
        let mut inner = self.lock();
        if inner.logged_no_fix.replace(why) != Some(why) {
            eprintln!(
                "obu: gnss: no fix from the receiver: {} (its positions are not used)",
                why.as_str()
            );
        }
        inner.gnss.record(solution, Some(why), AccuracySource::None);
    }

    /// A vehicle speed from CAN: the core uses it over the GNSS speed while fresh
    /// (`[speed] stale_after_ms`) and dead-reckons on it through a GNSS outage.
    pub fn on_can_speed(&self, mps: f32) {
        let now = self.now();
        self.lock().core.on_speed(now, mps);
    }

    /// Checks GNSS time against this computer's system clock (`[time]`), or stops.
    pub fn check_system_clock(&self, on: bool) {
        self.lock().system_clock = on;
    }

    /// Lets time pass in the core (GNSS and data timeouts); publishes when the state
    /// changed. Returns how long until the core next has work, if it has any.
    pub fn poll(&self) -> Option<std::time::Duration> {
        let now = self.now();
        let mut inner = self.lock();
        if let Some(state) = inner.core.poll(now) {
            self.publish(&mut inner, &state);
        }
        let next = inner.core.next_deadline()?;
        Some(std::time::Duration::from_millis(
            next.saturating_since(now).millis(),
        ))
    }

    /// Runs the core's timeouts until `stop` turns true: polls, then sleeps until the
    /// core's next deadline or until an input that may have moved it arrives. With a
    /// `tick` (under a watchdog) it sleeps at most that long, so that [`Hub::turns`]
    /// moves while the loop is alive.
    pub async fn run_deadlines(
        self: Arc<Self>,
        mut stop: watch::Receiver<bool>,
        tick: Option<std::time::Duration>,
    ) {
        loop {
            let wait = match (self.poll(), tick) {
                (Some(d), Some(t)) => Some(d.min(t)),
                (d, t) => d.or(t),
            };
            self.turns.fetch_add(1, Ordering::Relaxed);
            let sleep = async {
                match wait {
                    Some(d) => tokio::time::sleep(d).await,
                    None => std::future::pending().await,
                }
            };
            tokio::select! {
                _ = sleep => {}
                _ = self.wake.notified() => {}
                _ = stop.changed() => return,
            }
        }
    }

    /// How many times the deadline loop has turned (polled the core).
    pub fn turns(&self) -> u64 {
        self.turns.load(Ordering::Relaxed)
    }

    /// The current settings.
    pub fn settings(&self) -> Settings {
        self.lock().settings
    }

    /// Applies new (validated) settings to the core.
    ///
    /// In bridge mode this changes only what the daemon stores and serves: the link from
    /// the firmware is one-way, so the firmware's core keeps its own warning distance and
    /// lead time.
    pub fn set_settings(&self, settings: Settings) {
        let mut inner = self.lock();
        let base = *inner.core.config();
        inner.core.set_config(alert_config(base, &settings));
        inner.settings = settings;
    }

    /// Milliseconds since the last fix, and what the receiver says of its last epoch.
    pub fn gnss(&self) -> (Option<u64>, ReceiverStatus) {
        let now = self.now();
        let inner = self.lock();
        (
            inner.last_fix.map(|t| now.saturating_since(t).millis()),
            inner.gnss,
        )
    }

    /// Lane models and work zones stored in the core (in bridge mode: as the last
    /// external state reports them).
    pub fn stored(&self) -> (usize, usize) {
        let inner = self.lock();
        match inner.external {
            Some((maps, zones)) => (maps.into(), zones.into()),
            None => (inner.core.maps().len(), inner.core.zones().len()),
        }
    }

    /// Road workers stored in the core and what the store did so far (new, updated,
    /// evicted, expired); `None` in bridge mode (the firmware keeps its own).
    pub fn workers(&self) -> Option<(usize, obu::worker::WorkerStats)> {
        let inner = self.lock();
        if inner.external.is_some() {
            return None;
        }
        let store = inner.core.workers();
        Some((store.len(), store.stats()))
    }

    /// Publishes a state computed outside this daemon's core (in bridge mode, the
    /// firmware's) exactly as the core's states are: numbered, kept for resume and sent to
    /// every event-stream client.
    pub fn publish_state(&self, state: &HmiState) {
        let mut inner = self.lock();
        inner.external = Some((state.maps, state.zones));
        self.publish(&mut inner, state);
    }

    /// A receiver of new events.
    pub fn subscribe(&self) -> broadcast::Receiver<Arc<Event>> {
        self.events.subscribe()
    }

    /// The kept events after `seq` (all kept ones when `seq` is older than the ring).
    pub fn since(&self, seq: u64) -> Vec<Arc<Event>> {
        self.lock()
            .recent
            .iter()
            .filter(|e| e.seq > seq)
            .cloned()
            .collect()
    }

    /// The newest event, if any.
    pub fn latest(&self) -> Option<Arc<Event>> {
        self.lock().recent.back().cloned()
    }

    fn publish(&self, inner: &mut Inner, state: &HmiState) {
        inner.seq += 1;
        let now = self.now();
        let gnss_age_ms = inner.last_fix.map(|t| now.saturating_since(t).millis());
        let body = serde_json::json!({
            "seq": inner.seq,
            "state": state,
            "gnss_age_ms": gnss_age_ms,
            "fix_quality": inner.gnss.fix_quality(),
        });
        let event = Arc::new(Event {
            seq: inner.seq,
            json: body.to_string(),
        });
        if inner.recent.len() == self.keep {
            inner.recent.pop_front();
        }
        inner.recent.push_back(event.clone());
        // No receiver is fine: nobody is watching.
        let _ = self.events.send(event);
    }
}

/// What the receiver said of its last epoch.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReceiverStatus {
    /// Its solution (autonomous, RTK fixed, simulator, ...), when it says.
    pub solution: Option<Solution>,
    /// Why the last epoch gave no fix; `None` when it gave one.
    pub no_fix: Option<NoFix>,
    /// Where the last fix's accuracy came from.
    pub accuracy_source: AccuracySource,
}

impl ReceiverStatus {
    fn record(&mut self, solution: Option<Solution>, no_fix: Option<NoFix>, a: AccuracySource) {
        self.solution = solution;
        self.no_fix = no_fix;
        if no_fix.is_none() {
            self.accuracy_source = a;
        }
    }

    /// The GGA quality indicator of the solution (0 for none).
    pub fn fix_quality(self) -> Option<u8> {
        self.solution.map(Solution::gga_quality)
    }

    /// As `/api/status` shows it.
    pub fn to_json(self) -> serde_json::Value {
        serde_json::json!({
            "solution": self.solution.map(Solution::as_str),
            "no_fix": self.no_fix.map(NoFix::as_str),
            "accuracy_source": self.accuracy_source.as_str(),
        })
    }
}

/// Milliseconds from the Unix epoch to 2000-01-01 00:00 UTC.
const UNIX_MS_AT_2000: i64 = 946_684_800_000;

/// The system clock as UTC (`None` before 1970).
pub(crate) fn system_utc() -> Option<obu::time::UtcTime> {
    let since = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .ok()?;
    let ms = i64::try_from(since.as_millis()).ok()?;
    Some(obu::time::UtcTime::from_abs_millis(ms - UNIX_MS_AT_2000))
}

/// The core's alert configuration with the driver's settings applied.
fn alert_config(mut base: AlertConfig, s: &Settings) -> AlertConfig {
    base.warn_distance_m = s.warning_distance_m;
    base.lead_time_s = s.lead_time_s;
    base
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_system_clock_reads_as_utc() {
        // 2025-11-25T00:00:00Z is 1 764 028 800 000 ms after the Unix epoch (Python's
        // datetime): day 328 of 2025.
        let t = obu::time::UtcTime::from_abs_millis(1_764_028_800_000 - UNIX_MS_AT_2000);
        assert_eq!((t.year, t.ms_of_year), (2025, 328 * 86_400_000));
        assert!(system_utc().is_some_and(|now| now.year >= 2026));
    }

    #[tokio::test]
    async fn the_deadline_loop_publishes_the_gnss_loss_at_the_timeout() {
        let base = AlertConfig::DEFAULT;
        let hub = Hub::new(Settings::defaults(100.0, 9.0), base, 16);
        assert_eq!(hub.poll(), None, "no fix, nothing stored: no deadline");
        let (stop_tx, stop) = watch::channel(false);
        let mut events = hub.subscribe();
        let task = tokio::spawn(hub.clone().run_deadlines(stop, None));
        let t0 = std::time::Instant::now();
        hub.on_fix(Fix::at(obu::LatLon::ZERO), None);
        let fix = events.recv().await.unwrap();
        assert!(fix.json.contains("\"gnss_ok\":true"), "{}", fix.json);
        let timeout = std::time::Duration::from_millis(base.gnss_timeout.millis());
        let wait = hub.poll().expect("a fix sets a deadline");
        assert!(
            wait <= timeout + std::time::Duration::from_millis(1),
            "{wait:?}"
        );
        // The loop sleeps until the deadline (no 100 ms ticks): the loss comes at it, after
        // a turn for the start, one for the fix and one at the deadline (a loop ticking
        // every 100 ms would have turned 10 times).
        let lost = events.recv().await.unwrap();
        let at = t0.elapsed();
        assert!(lost.json.contains("\"gnss_ok\":false"), "{}", lost.json);
        assert!(at >= timeout, "not before the timeout: {at:?}");
        assert!((2..=4).contains(&hub.turns()), "{} turns", hub.turns());
        assert!(
            at < timeout + std::time::Duration::from_millis(150),
            "at it: {at:?}"
        );
        let _ = stop_tx.send(true);
        task.await.unwrap();
    }

    #[tokio::test(start_paused = true)]
    async fn with_a_tick_the_idle_loop_turns_and_without_it_sleeps() {
        let hub = Hub::new(Settings::defaults(100.0, 9.0), AlertConfig::DEFAULT, 16);
        let (stop_tx, stop) = watch::channel(false);
        let idle = tokio::spawn(hub.clone().run_deadlines(stop.clone(), None));
        tokio::time::sleep(std::time::Duration::from_secs(1)).await;
        assert_eq!(hub.turns(), 1, "nothing to do: one poll, then asleep");
        let tick = std::time::Duration::from_millis(50);
        let ticking = tokio::spawn(hub.clone().run_deadlines(stop, Some(tick)));
        tokio::time::sleep(std::time::Duration::from_millis(1025)).await;
        let turns = hub.turns() - 1;
        assert!((20..=22).contains(&turns), "{turns} turns in 1 s at 50 ms");
        let _ = stop_tx.send(true);
        idle.await.unwrap();
        ticking.await.unwrap();
    }
}
