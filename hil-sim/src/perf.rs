//! The daemon under measurement, as a separate process fed over its real sockets:
//! [`latency`] (GNSS datagram in -> its state event out on `/events`) and [`load`]
//! (many tablets following `/events` at the fix rate, with the daemon's CPU use).

use crate::hmi_bench::{start_daemon, Feeder};
use crate::sse::SseClient;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A fresh state directory for one measurement.
fn scratch(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("hil-sim-{name}-{}", std::process::id()))
}

/// Latency figures, microseconds.
#[derive(Debug, Clone, PartialEq)]
pub struct Latency {
    /// Every measured latency, sorted.
    pub sorted_us: Vec<f64>,
    /// Fixes whose event did not arrive within a second.
    pub lost: usize,
}

impl Latency {
    /// The `q` quantile (nearest rank), microseconds.
    pub fn quantile(&self, q: f64) -> f64 {
        crate::soak::verdict::quantile(&self.sorted_us, q).unwrap_or(f64::NAN)
    }
}

/// Sends `samples` NMEA epochs of the approach scene one at a time (every `gap`) and
/// times each from just before its UDP datagram leaves to the moment its state (the one
/// whose fix counter it raised) is read from `/events`.
pub fn latency(obu: &Path, samples: usize, gap: Duration) -> Result<Latency, String> {
    let dir = scratch("latency");
    let daemon = start_daemon(obu, &dir, 0, |_| {})?;
    let feeder = Feeder::new()?;
    feeder.tick(&daemon, "approach", 0.0, true);
    let mut sse = SseClient::connect(daemon.http_addr(), Duration::from_secs(2))?;
    let mut fixes = counter_of(&mut sse, "fixes", 0)?;
    let mut out = Latency {
        sorted_us: Vec::with_capacity(samples),
        lost: 0,
    };
    for i in 1..=samples {
        if i % 50 == 0 {
            feeder.tick(&daemon, "approach", i as f64 * 0.1, false);
        }
        std::thread::sleep(gap);
        let t0 = Instant::now();
        feeder.send_epoch(&daemon, "approach", i as f64 * 0.1);
        match counter_of(&mut sse, "fixes", fixes + 1) {
            Ok(n) => {
                out.sorted_us.push(t0.elapsed().as_secs_f64() * 1e6);
                fixes = n;
            }
            Err(_) => {
                out.lost += 1;
                sse = SseClient::connect(daemon.http_addr(), Duration::from_secs(2))?;
                fixes = counter_of(&mut sse, "fixes", 0)?;
            }
        }
    }
    drop(daemon);
    let _ = std::fs::remove_dir_all(dir);
    out.sorted_us.sort_by(f64::total_cmp);
    Ok(out)
}

/// Sends `samples` TIM datagrams one at a time, each a new version of the bench zone
/// (`msgCnt` bumped), and times each from just before it leaves to the moment the state
/// it caused (zone update counter raised) is read from `/events`: the roadside -> tablet
/// path without waiting for a fix.
pub fn tim_latency(obu: &Path, samples: usize, gap: Duration) -> Result<Latency, String> {
    let dir = scratch("tim-latency");
    let daemon = start_daemon(obu, &dir, 0, |_| {})?;
    let road = crate::hmi_bench::road();
    let start =
        roadside::clock::Utc::from_unix_ms(roadside::clock::unix_ms_now().saturating_sub(120_000));
    let mut versions = Vec::with_capacity(128);
    for cnt in 0..128u8 {
        let mut zone = crate::hmi_bench::zone(start);
        zone.msg_cnt = cnt;
        let tim = roadside::messages::build_tim(&road, &zone).map_err(|e| e.to_string())?;
        versions.push(roadside::messages::encode(&tim).map_err(|e| e.to_string())?);
    }
    let sock = std::net::UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let signer = crate::bench_pki::signer()?;
    let mut sse = SseClient::connect(daemon.http_addr(), Duration::from_secs(2))?;
    let mut out = Latency {
        sorted_us: Vec::with_capacity(samples),
        lost: 0,
    };
    let mut updated = 0;
    for i in 1..=samples {
        std::thread::sleep(gap);
        // Signed before the clock starts: the figure is the OBU's (verify, decode, store,
        // publish), not the roadside's signing.
        let signed = signer
            .sign(&versions[i % 128], roadside::clock::unix_ms_now())
            .map_err(|e| e.to_string())?;
        let t0 = Instant::now();
        let _ = sock.send_to(&signed, &daemon.v2x);
        match counter_of(&mut sse, "zones_updated", updated + 1) {
            Ok(n) => {
                out.sorted_us.push(t0.elapsed().as_secs_f64() * 1e6);
                updated = n;
            }
            Err(_) => out.lost += 1,
        }
    }
    drop(daemon);
    let _ = std::fs::remove_dir_all(dir);
    out.sorted_us.sort_by(f64::total_cmp);
    Ok(out)
}

/// Reads state events until one whose counter `name` is at least `want` (0: any state);
/// returns it. Fails after a second without one.
fn counter_of(sse: &mut SseClient, name: &str, want: u64) -> Result<u64, String> {
    let deadline = Instant::now() + Duration::from_secs(1);
    while Instant::now() < deadline {
        let ev = sse.next_event()?;
        if ev.event != "state" {
            continue;
        }
        let v: serde_json::Value = serde_json::from_str(&ev.data).map_err(|e| e.to_string())?;
        let n = v["state"]["counters"][name]
            .as_u64()
            .ok_or("no such counter")?;
        if n >= want {
            return Ok(n);
        }
    }
    Err("no state event within a second".into())
}

/// Load test figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Load {
    /// Clients connected.
    pub clients: usize,
    /// Length of the run, seconds.
    pub seconds: f64,
    /// Fewest and most state events a client received.
    pub events: (u64, u64),
    /// Longest time between two events of one client, milliseconds.
    pub max_gap_ms: f64,
    /// Clients that lost their stream during the run, with the reason.
    pub dropped: Vec<String>,
    /// The daemon's CPU use over the run, percent of one core.
    pub cpu_percent: f64,
    /// The daemon's own count of event clients it dropped as too slow.
    pub daemon_dropped: u64,
}

/// Holds `clients` event streams open for `seconds` while the daemon is fed the approach
/// scene at 10 Hz; measures each client's events and the daemon's CPU time.
pub fn load(obu: &Path, clients: usize, seconds: f64) -> Result<Load, String> {
    let dir = scratch("load");
    let daemon = start_daemon(obu, &dir, 0, |_| {})?;
    let feeder = Feeder::new()?;
    feeder.tick(&daemon, "approach", 0.0, true);
    let stop = Arc::new(AtomicBool::new(false));
    let mut handles = Vec::new();
    for _ in 0..clients {
        let sse = SseClient::connect(daemon.http_addr(), Duration::from_secs(2))?;
        let stop = stop.clone();
        handles.push(std::thread::spawn(move || follow(sse, &stop)));
    }
    let cpu0 = daemon.cpu_seconds().ok_or("no CPU time in /proc")?;
    let t0 = Instant::now();
    let mut next = t0;
    let mut k = 0u64;
    while t0.elapsed().as_secs_f64() < seconds {
        k += 1;
        feeder.tick(&daemon, "approach", k as f64 * 0.1, true);
        next += Duration::from_millis(100);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
    let wall = t0.elapsed().as_secs_f64();
    let cpu = daemon.cpu_seconds().ok_or("no CPU time in /proc")? - cpu0;
    stop.store(true, Ordering::Relaxed);
    let status = crate::daemon::http_get(daemon.http_addr(), "/api/status").unwrap_or_default();
    let mut report = Load {
        clients,
        seconds: wall,
        events: (u64::MAX, 0),
        max_gap_ms: 0.0,
        dropped: Vec::new(),
        cpu_percent: 100.0 * cpu / wall,
        daemon_dropped: status_count(&status, "dropped: too slow"),
    };
    for h in handles {
        let f = h.join().map_err(|_| "a client thread panicked")?;
        report.events = (report.events.0.min(f.events), report.events.1.max(f.events));
        report.max_gap_ms = report.max_gap_ms.max(f.max_gap_ms);
        report.dropped.extend(f.error);
    }
    drop(daemon);
    let _ = std::fs::remove_dir_all(dir);
    Ok(report)
}

/// What one client saw.
struct Followed {
    events: u64,
    max_gap_ms: f64,
    error: Option<String>,
}

fn follow(mut sse: SseClient, stop: &AtomicBool) -> Followed {
    let mut f = Followed {
        events: 0,
        max_gap_ms: 0.0,
        error: None,
    };
    let mut last: Option<Instant> = None;
    while !stop.load(Ordering::Relaxed) {
        match sse.next_event() {
            // Events after the run (the "no GNSS" state once feeding stopped) do not count.
            Ok(_) if stop.load(Ordering::Relaxed) => break,
            Ok(ev) if ev.event == "state" => {
                f.events += 1;
                // The first event is the newest state, sent on connecting (before the run
                // starts); gaps are measured between live ones.
                if let Some(l) = last {
                    f.max_gap_ms = f.max_gap_ms.max(l.elapsed().as_secs_f64() * 1e3);
                }
                last = (f.events >= 2).then(Instant::now);
            }
            Ok(_) => {}
            Err(e) if !stop.load(Ordering::Relaxed) => {
                f.error = Some(e);
                break;
            }
            Err(_) => break,
        }
    }
    f
}

/// A counter of `/api/status` by reason, summed over groups.
fn status_count(status: &str, reason: &str) -> u64 {
    let Ok(v) = serde_json::from_str::<serde_json::Value>(status) else {
        return 0;
    };
    v["counters"].as_object().map_or(0, |groups| {
        groups.values().filter_map(|g| g[reason].as_u64()).sum()
    })
}
