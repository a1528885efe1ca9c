//! The soak's tablets: each follows `/events` in a thread of its own, reads every event,
//! checks that its sequence numbers (the SSE ids `<run>-<seq>`) follow one another, and
//! times each new fix's state against the moment its NMEA epoch was sent. The first client
//! also watches what the daemon holds (lane maps, zones and their update counts) and the
//! zone states the laps pass through.

use super::lock;
use super::traffic::Sent;
use crate::sse::SseClient;
use serde::Serialize;
use serde_json::Value;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;

/// What all clients share while they run.
#[derive(Debug, Default)]
pub struct Shared {
    /// Latencies measured since the sampler last took them, milliseconds.
    pub latencies_ms: Mutex<Vec<f64>>,
    /// State events received, all clients.
    pub events: AtomicU64,
    /// Clients following the stream.
    pub alive: AtomicUsize,
    /// Set by the first client once the daemon holds the bench's map and zone (verified)
    /// and has a fix: the hostile traffic may start.
    pub ready: AtomicBool,
    /// The first client's watch.
    pub watch: Mutex<Watch>,
}

/// What the daemon holds of the roadside's data, from a state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Held {
    /// Lane maps stored.
    pub maps: u64,
    /// Zones stored.
    pub zones: u64,
    /// Of them, unverified.
    pub unverified: u64,
    /// Lane maps stored or replaced so far.
    pub maps_updated: u64,
    /// Zones stored or replaced so far.
    pub zones_updated: u64,
    /// Zones cancelled so far.
    pub zones_cancelled: u64,
}

impl Held {
    /// From an event's `state`.
    pub fn of(state: &Value) -> Self {
        let n = |v: &Value| v.as_u64().unwrap_or(0);
        let c = &state["counters"];
        Self {
            maps: n(&state["maps"]),
            zones: n(&state["zones"]),
            unverified: n(&state["unverified"]),
            maps_updated: n(&c["maps_updated"]),
            zones_updated: n(&c["zones_updated"]),
            zones_cancelled: n(&c["zones_cancelled"]),
        }
    }
}

/// The first client's record of the run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Watch {
    /// What the daemon held when the hostile traffic began.
    pub held: Option<Held>,
    /// States since then that held something else.
    pub changed: u64,
    /// The first of them.
    pub first_change: Option<Held>,
    /// Entries into the zone states `Warning`, `InZone`, `Leaving`.
    pub entered: [u64; 3],
    #[serde(skip)]
    last_zone_state: String,
}

/// The zone states each lap must pass through, as the state names them.
pub const LAP_STATES: [&str; 3] = ["Warning", "InZone", "Leaving"];

impl Watch {
    /// One state of the first client.
    fn on_state(&mut self, state: &Value, shared: &Shared) {
        let now = Held::of(state);
        match self.held {
            None => {
                let fixes = state["counters"]["fixes"].as_u64().unwrap_or(0);
                if now.maps > 0 && now.zones > 0 && now.unverified == 0 && fixes > 0 {
                    self.held = Some(now);
                    shared.ready.store(true, Ordering::Relaxed);
                }
            }
            Some(held) if held != now => {
                self.changed += 1;
                self.first_change.get_or_insert(now);
            }
            Some(_) => {}
        }
        let zone_state = state["zone_state"].as_str().unwrap_or("");
        if zone_state != self.last_zone_state {
            if let Some(i) = LAP_STATES.iter().position(|s| *s == zone_state) {
                self.entered[i] += 1;
            }
            self.last_zone_state = zone_state.to_string();
        }
    }
}

/// What one client saw over the run.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Followed {
    /// State events received.
    pub events: u64,
    /// Events missing between two received ones (sequence numbers skipped), and ids out of
    /// order or of another run.
    pub gaps: u64,
    /// Why the stream ended before the run did, if it did.
    pub error: Option<String>,
}

/// Follows `sse` until `stop`: events counted, sequence checked, new fixes timed.
pub fn follow(
    mut sse: SseClient,
    first: bool,
    sent: &Sent,
    shared: &Shared,
    stop: &AtomicBool,
) -> Followed {
    let mut f = Followed::default();
    let mut last: Option<(String, u64)> = None;
    let mut last_fix: Option<u64> = None;
    while !stop.load(Ordering::Relaxed) {
        let ev = match sse.next_event() {
            Ok(ev) => ev,
            Err(_) if stop.load(Ordering::Relaxed) => break,
            Err(e) => {
                f.error = Some(e);
                break;
            }
        };
        let received = std::time::Instant::now();
        if ev.event != "state" {
            continue;
        }
        f.events += 1;
        shared.events.fetch_add(1, Ordering::Relaxed);
        f.gaps += sequence_gap(last.as_ref(), &ev.id);
        last = parse_id(&ev.id);
        // The fix count without parsing the whole state: 50 clients parsing every state
        // would time the bench's JSON parser, not the daemon.
        let Some(fix) = fix_count(&ev.data) else {
            f.gaps += 1;
            continue;
        };
        // A new fix's state (not the newest state sent on connecting): time it.
        if last_fix.is_some_and(|l| fix > l) {
            if let Some(at) = sent.epoch_sent(fix) {
                let ms = received.saturating_duration_since(at).as_secs_f64() * 1e3;
                lock(&shared.latencies_ms).push(ms);
            }
        }
        last_fix = Some(fix);
        if first {
            match serde_json::from_str::<Value>(&ev.data) {
                Ok(body) => lock(&shared.watch).on_state(&body["state"], shared),
                Err(_) => f.gaps += 1,
            }
        }
    }
    shared.alive.fetch_sub(1, Ordering::Relaxed);
    f
}

/// The state's fix count (`"fixes":N`, unique in an event: the other fix counters are
/// `rollover_fixes` and `unverified_time_fixes`).
pub fn fix_count(data: &str) -> Option<u64> {
    const KEY: &str = "\"fixes\":";
    let at = data.find(KEY)? + KEY.len();
    let digits = &data[at..];
    let end = digits
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(digits.len());
    digits[..end].parse().ok()
}

/// `<run>-<seq>` of an SSE id.
pub fn parse_id(id: &str) -> Option<(String, u64)> {
    let (run, seq) = id.rsplit_once('-')?;
    Some((run.to_string(), seq.parse().ok()?))
}

/// Events missing between the last id and `id`: 0 when `id` is the next one (or the first
/// one); the count skipped; 1 for an id out of order, of another run, or unreadable.
pub fn sequence_gap(last: Option<&(String, u64)>, id: &str) -> u64 {
    let Some(now) = parse_id(id) else {
        return 1;
    };
    match last {
        None => 0,
        Some((run, seq)) if *run == now.0 && now.1 > *seq => now.1 - seq - 1,
        Some(_) => 1,
    }
}

/// Connects `n` clients to `addr`, each with a read timeout of 3 s (the daemon sends a
/// heartbeat every second on an idle stream).
pub fn connect(addr: &str, n: usize) -> Result<Vec<SseClient>, String> {
    (0..n)
        .map(|_| SseClient::connect(addr, Duration::from_secs(3)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn sequence_gaps_are_counted() {
        let run = |seq: u64| ("1700000000000".to_string(), seq);
        assert_eq!(sequence_gap(None, "1700000000000-7"), 0);
        assert_eq!(sequence_gap(Some(&run(7)), "1700000000000-8"), 0);
        assert_eq!(sequence_gap(Some(&run(7)), "1700000000000-11"), 3);
        assert_eq!(sequence_gap(Some(&run(7)), "1700000000000-7"), 1);
        assert_eq!(sequence_gap(Some(&run(7)), "1700000000001-8"), 1);
        assert_eq!(sequence_gap(Some(&run(7)), "garbage"), 1);
        assert_eq!(parse_id("17-42"), Some(("17".into(), 42)));
    }

    #[test]
    fn the_fix_count_is_read_from_a_real_state() {
        let mut st = obu::alert::HmiState::default();
        st.counters.fixes = 1234;
        st.counters.rollover_fixes = 7;
        st.counters.unverified_time_fixes = 9;
        let data = json!({"seq": 5, "state": st, "gnss_age_ms": 3}).to_string();
        assert_eq!(fix_count(&data), Some(1234), "{data}");
        assert_eq!(fix_count(r#"{"state":{}}"#), None);
    }

    fn state(maps: u64, zones: u64, cancelled: u64, zone_state: &str) -> Value {
        json!({
            "maps": maps, "zones": zones, "unverified": 0, "zone_state": zone_state,
            "counters": {"fixes": 5, "maps_updated": 1, "zones_updated": 1,
                         "zones_cancelled": cancelled}
        })
    }

    #[test]
    fn the_watch_arms_on_the_roadside_data_and_sees_changes_and_laps() {
        let shared = Shared::default();
        let mut w = Watch::default();
        w.on_state(&state(0, 0, 0, "None"), &shared);
        assert!(!shared.ready.load(Ordering::Relaxed) && w.held.is_none());
        for zs in [
            "Approaching",
            "Warning",
            "InZone",
            "InZone",
            "Leaving",
            "None",
            "Warning",
        ] {
            w.on_state(&state(1, 1, 0, zs), &shared);
        }
        assert!(shared.ready.load(Ordering::Relaxed));
        assert_eq!((w.changed, w.entered), (0, [2, 1, 1]));
        w.on_state(&state(1, 1, 1, "Warning"), &shared);
        w.on_state(&state(1, 0, 1, "None"), &shared);
        assert_eq!(w.changed, 2);
        assert_eq!(w.first_change.map(|h| h.zones_cancelled), Some(1));
    }
}
