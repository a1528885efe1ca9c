//! `hil-sim soak`: the real `obu` daemon under the product's whole load for a long time,
//! sampled for growth.
//!
//! The load: a car driving the bench road's work zone lap after lap (NMEA at 10 Hz;
//! [`traffic::LAP`]), the signed roadside at 10 Hz (MAP and TIM, the bench PKI), N tablets
//! following `/events` ([`clients`]), and hostile traffic mixed in: forged V2X of the four
//! attack kinds, random and truncated datagrams ([`traffic::hostile_v2x`]), unauthenticated
//! settings writes, foreign `Host` headers and slow bodies ([`http`]). Every `sample_s` the
//! daemon's RSS, open descriptors, CPU, the fix -> event latency of the window and its
//! counters are sampled ([`verdict::Sample`]); at the end the run is judged
//! ([`verdict::growth`], [`checks::checks`]) and written to `soak.json`.

pub mod checks;
pub mod clients;
pub mod http;
pub mod traffic;
pub mod verdict;

use crate::daemon::Daemon;
use serde::Serialize;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::thread::{Scope, ScopedJoinHandle};
use std::time::{Duration, Instant};
use verdict::{Check, Sample};

/// How the soak runs.
#[derive(Debug, Clone)]
pub struct SoakOptions {
    /// The `obu` executable.
    pub obu: PathBuf,
    /// Length of the run, minutes.
    pub minutes: f64,
    /// Time between samples, seconds.
    pub sample_s: f64,
    /// Tablets following `/events`.
    pub clients: usize,
    /// Where `soak.json` and the daemon's state go.
    pub out: PathBuf,
}

/// The longest run taken, minutes (a week).
pub const MAX_MINUTES: f64 = 7.0 * 24.0 * 60.0;

impl SoakOptions {
    /// Samples the run takes.
    pub fn samples(&self) -> usize {
        (self.minutes * 60.0 / self.sample_s + 1e-9)
            .floor()
            .max(0.0) as usize
    }

    /// Checks the values: at least 3 samples, 1 s between them at least, 1 to 256 clients.
    ///
    /// # Errors
    ///
    /// A message naming the value.
    pub fn validate(&self) -> Result<(), String> {
        if !(self.minutes > 0.0 && self.minutes <= MAX_MINUTES) {
            return Err(format!(
                "--minutes {}: more than 0, at most {MAX_MINUTES} (a week)",
                self.minutes
            ));
        }
        if !(self.sample_s >= 1.0 && self.sample_s.is_finite()) {
            return Err(format!("--sample-s {}: at least 1", self.sample_s));
        }
        if verdict::windows(self.samples()).is_none() {
            return Err(format!(
                "--minutes {} with --sample-s {} gives {} samples; at least 3 are needed",
                self.minutes,
                self.sample_s,
                self.samples()
            ));
        }
        if !(1..=256).contains(&self.clients) {
            return Err(format!("--clients {}: 1 to 256", self.clients));
        }
        Ok(())
    }
}

/// What a soak found.
#[derive(Debug, Clone, Serialize)]
pub struct SoakReport {
    /// Minutes asked for.
    pub minutes: f64,
    /// Seconds between samples.
    pub sample_s: f64,
    /// Tablets.
    pub clients: usize,
    /// Every sample, in order.
    pub samples: Vec<Sample>,
    /// The facts judged beside the samples.
    pub facts: checks::Facts,
    /// The checks, growth first.
    pub checks: Vec<Check>,
    /// All checks held.
    pub passed: bool,
}

/// Runs the soak, printing a row per sample; writes `out/soak.json`.
///
/// # Errors
///
/// Options out of range, the daemon not starting, the out directory not writable. A run
/// that fails its checks is a report with `passed` false.
pub fn run(opts: &SoakOptions) -> Result<SoakReport, String> {
    opts.validate()?;
    let state = opts.out.join("state");
    let _ = std::fs::remove_dir_all(&state);
    let mut config = crate::daemon::config(&state, 0, 0)?;
    config.http.request_timeout_ms = http::REQUEST_TIMEOUT_MS;
    config.http.max_clients = opts.clients.max(48) + 16;
    crate::hmi_bench::per_fix_lanes(&mut config);
    let mut daemon = Daemon::start(&opts.obu, &state, &config)?;
    let world = World::default();
    let (samples, facts) = std::thread::scope(|scope| soak(scope, opts, &mut daemon, &world))?;
    let mut checks = verdict::growth(&samples, &verdict::Limits::SOAK);
    checks.extend(checks::checks(&facts));
    let report = SoakReport {
        minutes: opts.minutes,
        sample_s: opts.sample_s,
        clients: opts.clients,
        passed: checks.iter().all(|c| c.ok),
        samples,
        facts,
        checks,
    };
    let path = opts.out.join("soak.json");
    let json = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    std::fs::write(&path, json).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(report)
}

/// What the threads share.
#[derive(Debug, Default)]
struct World {
    sent: traffic::Sent,
    shared: clients::Shared,
    http: Mutex<http::HttpTally>,
    stop_traffic: AtomicBool,
    stop_clients: AtomicBool,
}

impl World {
    fn stop_all(&self) {
        self.stop_traffic.store(true, Ordering::Relaxed);
        self.stop_clients.store(true, Ordering::Relaxed);
    }
}

/// The run inside a thread scope: traffic and clients started, sampled, stopped. Every
/// path out sets both stop flags first, so the scope's threads end and are joined.
fn soak<'scope, 'env>(
    scope: &'scope Scope<'scope, 'env>,
    opts: &SoakOptions,
    daemon: &mut Daemon,
    w: &'env World,
) -> Result<(Vec<Sample>, checks::Facts), String> {
    let running = start(scope, opts, daemon, w).inspect_err(|_| w.stop_all())?;
    let t0 = Instant::now();
    let (samples, died) = sample_loop(opts, daemon, w, t0);
    let facts = finish(running, daemon, w, t0.elapsed().as_secs_f64(), died)?;
    Ok((samples, facts))
}

/// The threads of a run.
struct Running<'scope> {
    senders: [ScopedJoinHandle<'scope, Result<(), String>>; 2],
    http: ScopedJoinHandle<'scope, ()>,
    clients: Vec<ScopedJoinHandle<'scope, clients::Followed>>,
}

/// The drive and the roadside first, then the tablets; once the first tablet sees the
/// roadside's data and a fix, the hostile traffic.
fn start<'scope, 'env>(
    scope: &'scope Scope<'scope, 'env>,
    opts: &SoakOptions,
    daemon: &mut Daemon,
    w: &'env World,
) -> Result<Running<'scope>, String> {
    let addr = daemon.http_addr().to_string();
    let (v2x, gnss) = (daemon.v2x.clone(), daemon.gnss.clone());
    let drive = scope.spawn(move || traffic::drive(&v2x, &gnss, &w.sent, &w.stop_traffic));
    std::thread::sleep(Duration::from_millis(500));
    let followers = clients::connect(&addr, opts.clients)
        .map_err(|e| format!("connecting the tablets: {e}"))?;
    w.shared.alive.store(followers.len(), Ordering::Relaxed);
    let clients = (followers.into_iter().enumerate())
        .map(|(i, sse)| {
            scope.spawn(move || clients::follow(sse, i == 0, &w.sent, &w.shared, &w.stop_clients))
        })
        .collect();
    if !wait_ready(&w.shared, daemon) {
        return Err(
            "the daemon did not show the roadside's map and zone with a fix within 15 s".into(),
        );
    }
    let v2x = daemon.v2x.clone();
    let hostile = scope.spawn(move || traffic::hostile_v2x(&v2x, &w.sent, &w.stop_traffic));
    let http = scope.spawn(move || http::hostile_http(&addr, &w.http, &w.stop_traffic));
    Ok(Running {
        senders: [drive, hostile],
        http,
        clients,
    })
}

/// Stops the traffic, reads the daemon's counters once the last datagram is in, stops the
/// tablets and the daemon (SIGTERM); what the run left to judge.
fn finish(
    running: Running<'_>,
    daemon: &mut Daemon,
    w: &World,
    run_s: f64,
    died: Option<String>,
) -> Result<checks::Facts, String> {
    w.stop_traffic.store(true, Ordering::Relaxed);
    let mut errors = Vec::new();
    for h in running.senders {
        match h.join() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => errors.push(e),
            Err(_) => errors.push("a sender panicked".into()),
        }
    }
    let _ = running.http.join();
    let device = crate::attack::daemon_counts_settled(daemon.http_addr(), w.sent.v2x()).ok();
    w.stop_clients.store(true, Ordering::Relaxed);
    // A daemon that died was reaped by the sampling loop: its pid may be another process's.
    let stopped = match died {
        None => terminate(daemon),
        Some(_) => None,
    };
    let followed: Vec<clients::Followed> = (running.clients.into_iter())
        .map(|h| {
            h.join().unwrap_or_else(|_| clients::Followed {
                error: Some("the client's thread panicked".into()),
                ..clients::Followed::default()
            })
        })
        .collect();
    if let Some(e) = errors.first() {
        return Err(format!("the traffic stopped: {e}"));
    }
    Ok(checks::Facts {
        run_s,
        died,
        stopped,
        clients: followed,
        watch: lock(&w.shared.watch).clone(),
        laps: traffic::laps(run_s),
        forged: (traffic::FORGED.iter().zip(&w.sent.forged))
            .map(|((_, r), n)| (r.as_str(), n.load(Ordering::Relaxed)))
            .collect(),
        v2x_sent: w.sent.v2x(),
        random_sent: w.sent.garbage.load(Ordering::Relaxed),
        send_failed: w.sent.failed.load(Ordering::Relaxed),
        device,
        http: lock(&w.http).clone(),
    })
}

/// Locks `m`, taking the value of a poisoned lock too (a panicked thread is reported by its
/// join; the figures it left are still the run's).
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

/// Waits up to 15 s for the first client to see the roadside's data and a fix.
fn wait_ready(shared: &clients::Shared, daemon: &mut Daemon) -> bool {
    let until = Instant::now() + Duration::from_secs(15);
    while Instant::now() < until {
        if shared.ready.load(Ordering::Relaxed) {
            return true;
        }
        if matches!(daemon.child.try_wait(), Ok(Some(_))) {
            return false;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    false
}

/// Takes the samples, one every `sample_s` from `t0`, printing each; stops early when the
/// daemon exits (returning how).
fn sample_loop(
    opts: &SoakOptions,
    daemon: &mut Daemon,
    w: &World,
    t0: Instant,
) -> (Vec<Sample>, Option<String>) {
    println!("{}", Sample::HEADER);
    let mut samples = Vec::with_capacity(opts.samples());
    lock(&w.shared.latencies_ms).clear();
    let mut last = (
        t0,
        daemon.cpu_seconds().unwrap_or(0.0),
        w.shared.events.load(Ordering::Relaxed),
    );
    for i in 1..=opts.samples() {
        let due = t0 + Duration::from_secs_f64(opts.sample_s * i as f64);
        while Instant::now() < due {
            if let Ok(Some(status)) = daemon.child.try_wait() {
                let t = t0.elapsed().as_secs_f64();
                return (
                    samples,
                    Some(format!("the daemon exited after {t:.1} s: {status}")),
                );
            }
            let left = due.saturating_duration_since(Instant::now());
            std::thread::sleep(left.min(Duration::from_millis(200)));
        }
        let s = sample(daemon, w, t0, &mut last);
        println!("{}", s.row());
        samples.push(s);
    }
    (samples, None)
}

/// One sample; `last` is the previous one's time, CPU seconds and event count.
fn sample(daemon: &Daemon, w: &World, t0: Instant, last: &mut (Instant, f64, u64)) -> Sample {
    let pid = daemon.child.id();
    let now = Instant::now();
    let cpu = daemon.cpu_seconds().unwrap_or(last.1);
    let events = w.shared.events.load(Ordering::Relaxed);
    let wall = now
        .saturating_duration_since(last.0)
        .as_secs_f64()
        .max(1e-3);
    let mut lat = std::mem::take(&mut *lock(&w.shared.latencies_ms));
    lat.sort_by(f64::total_cmp);
    let counts = crate::attack::daemon_counts(daemon.http_addr()).ok();
    let forged_dropped = counts.as_ref().map_or(0, |d| {
        (traffic::FORGED.iter())
            .map(|(_, r)| d.get("security_errors", r.as_str()))
            .sum()
    });
    let s = Sample {
        t_s: now.saturating_duration_since(t0).as_secs_f64(),
        rss_kib: verdict::rss_kib(pid).unwrap_or(0),
        fds: verdict::open_fds(pid).unwrap_or(0),
        cpu_percent: 100.0 * (cpu - last.1) / wall,
        events: events - last.2,
        latencies: lat.len(),
        p50_ms: verdict::quantile(&lat, 0.5),
        p99_ms: verdict::quantile(&lat, 0.99),
        max_ms: verdict::quantile(&lat, 1.0),
        v2x_sent: w.sent.v2x(),
        v2x_counted: counts.as_ref().map_or(0, |d| d.v2x_total()),
        forged_sent: w.sent.forged_total(),
        forged_dropped,
        clients: w.shared.alive.load(Ordering::Relaxed),
        counters: counts.map_or(serde_json::Value::Null, |d| d.counters),
    };
    *last = (now, cpu, events);
    s
}

/// SIGTERM to the daemon (the `kill` command: this crate has no unsafe code), then up to
/// 5 s for it to exit; how it ended, `None` when it did not (it is killed on drop).
fn terminate(daemon: &mut Daemon) -> Option<String> {
    let pid = daemon.child.id().to_string();
    let sent = std::process::Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .is_ok_and(|s| s.success());
    if !sent {
        return None;
    }
    let until = Instant::now() + Duration::from_secs(5);
    while Instant::now() < until {
        if let Ok(Some(status)) = daemon.child.try_wait() {
            return Some(status.to_string());
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(minutes: f64, sample_s: f64) -> SoakOptions {
        SoakOptions {
            obu: PathBuf::from("obu"),
            minutes,
            sample_s,
            clients: 50,
            out: PathBuf::from("out"),
        }
    }

    #[test]
    fn run_lengths_are_bounded_before_anything_is_allocated() {
        assert!(options(2.0, 10.0).validate().is_ok());
        assert!(options(120.0, 60.0).validate().is_ok());
        assert!(options(MAX_MINUTES, 60.0).validate().is_ok());
        for minutes in [f64::INFINITY, f64::NAN, 1e30, 0.0, -5.0, MAX_MINUTES + 1.0] {
            assert!(options(minutes, 60.0).validate().is_err(), "{minutes}");
        }
        for sample_s in [0.5, f64::INFINITY, f64::NAN] {
            assert!(options(2.0, sample_s).validate().is_err(), "{sample_s}");
        }
        assert!(options(0.5, 10.0).validate().is_ok(), "3 samples");
        assert!(options(0.4, 10.0).validate().is_err(), "2 samples");
    }
}
