//! The pure parts of the soak: one sample of the daemon, the windows a run is judged on,
//! the growth verdict over a series of samples, quantiles and `/proc` parsing.
//!
//! A run of `n` samples is judged on three stretches: the warm-up (the first
//! [`Windows::warmup`] samples: a tenth of the run, at least one), ignored; the baseline
//! window (the next [`Windows::span`] samples) and the last window (the last `span`
//! samples), `span` being a tenth of the run, or three samples where the run has room for
//! them, at least one. With 12 samples (CI: 2 minutes, one every 10 s) the warm-up is the
//! first sample, the baseline the 2nd-4th, the last window the 10th-12th; with 120 (2 hours,
//! one a minute) 12 each.

use serde::Serialize;
use std::ops::Range;

/// What the soak samples every period.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Sample {
    /// Seconds since the run started.
    pub t_s: f64,
    /// The daemon's resident set (`VmRSS`), KiB.
    pub rss_kib: u64,
    /// The daemon's open file descriptors.
    pub fds: u64,
    /// The daemon's CPU use since the previous sample, percent of one core.
    pub cpu_percent: f64,
    /// State events every client received since the previous sample, summed.
    pub events: u64,
    /// Fix -> state event latencies measured since the previous sample.
    pub latencies: usize,
    /// Their median, milliseconds (`None`: none measured).
    pub p50_ms: Option<f64>,
    /// Their 99th percentile, milliseconds.
    pub p99_ms: Option<f64>,
    /// The largest, milliseconds.
    pub max_ms: Option<f64>,
    /// V2X datagrams sent so far (roadside, forged, garbage, truncated).
    pub v2x_sent: u64,
    /// V2X datagrams the daemon counted so far (every V2X group of `/api/status`).
    pub v2x_counted: u64,
    /// Forged datagrams sent so far.
    pub forged_sent: u64,
    /// Datagrams the daemon counted under the forged kinds' reasons so far.
    pub forged_dropped: u64,
    /// SSE clients still following `/events`.
    pub clients: usize,
    /// The daemon's counters (`/api/status` `counters`), `null` when it did not answer.
    pub counters: serde_json::Value,
}

impl Sample {
    /// The header of [`Sample::row`].
    pub const HEADER: &'static str = "    t s   RSS KiB  fds  CPU %  events  p50 ms  p99 ms  max ms  V2X sent/counted  forged sent/dropped  clients";

    /// One line of the table printed as the run goes.
    pub fn row(&self) -> String {
        let ms = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.2}"));
        format!(
            "{:7.0} {:9} {:4} {:6.2} {:7} {:>7} {:>7} {:>7} {:>17} {:>20} {:8}",
            self.t_s,
            self.rss_kib,
            self.fds,
            self.cpu_percent,
            self.events,
            ms(self.p50_ms),
            ms(self.p99_ms),
            ms(self.max_ms),
            format!("{}/{}", self.v2x_sent, self.v2x_counted),
            format!("{}/{}", self.forged_sent, self.forged_dropped),
            self.clients
        )
    }
}

/// One check of the verdict.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Check {
    /// What is checked.
    pub name: String,
    /// Whether it held.
    pub ok: bool,
    /// The figures behind it.
    pub detail: String,
}

impl Check {
    /// A check called `name`.
    pub fn new(name: &str, ok: bool, detail: String) -> Self {
        Self {
            name: name.to_string(),
            ok,
            detail,
        }
    }
}

/// The stretches of a run of samples the growth is judged on (indices into the samples).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Windows {
    /// Samples of the warm-up, not judged.
    pub warmup: usize,
    /// Samples per window.
    pub span: usize,
    /// The baseline window.
    pub baseline: Range<usize>,
    /// The last window.
    pub last: Range<usize>,
}

/// The windows of a run of `n` samples; `None` under 3 (a warm-up, a baseline and a
/// later sample are needed).
pub fn windows(n: usize) -> Option<Windows> {
    if n < 3 {
        return None;
    }
    let warmup = (n / 10).max(1);
    // A tenth of the run; three samples when the run has room for them (a short run's
    // windows of one sample would judge single 10-s windows of a shared machine).
    let span = (n / 10).max(((n - warmup) / 3).min(3)).max(1);
    Some(Windows {
        warmup,
        span,
        baseline: warmup..warmup + span,
        last: n - span..n,
    })
}

/// How much the daemon may grow between the baseline window and the last window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// RSS and fd count: percent over the baseline.
    pub percent: f64,
    /// RSS: absolute slack, KiB (allocator pages moving).
    pub rss_slack_kib: u64,
    /// File descriptors: absolute slack (a slow connection being replaced, a status
    /// request in flight when the sample is taken).
    pub fd_slack: u64,
    /// Event p99: the last window's at most this many times the baseline's ...
    pub p99_factor: f64,
    /// ... or the baseline's plus this, milliseconds, whichever is larger.
    pub p99_slack_ms: f64,
}

impl Limits {
    /// The soak's limits: 5 %, RSS 256 KiB, fds 2, p99 max(2x, +2 ms). The p99 margin: on
    /// the loopback the p99 is about a millisecond (the daemon README's Measured table) and
    /// varies by up to 2x between windows with other builds on the machine (50 client threads and the bench share 2 cores), and a
    /// scheduler slice is a few ms; a daemon that degrades (a queue or a store growing,
    /// work per event rising with uptime) keeps rising past any fixed margin.
    pub const SOAK: Limits = Limits {
        percent: 5.0,
        rss_slack_kib: 256,
        fd_slack: 2,
        p99_factor: 2.0,
        p99_slack_ms: 2.0,
    };

    /// The largest allowed value of a level measure (RSS, fds) over a `baseline`.
    pub fn allowed(&self, baseline: u64, slack: u64) -> u64 {
        let by_percent = (baseline as f64 * (1.0 + self.percent / 100.0)).floor() as u64;
        by_percent.max(baseline + slack)
    }

    /// The largest allowed event p99 over a baseline p99, milliseconds.
    pub fn allowed_p99(&self, baseline_ms: f64) -> f64 {
        (baseline_ms * self.p99_factor).max(baseline_ms + self.p99_slack_ms)
    }
}

/// The growth checks of a run: RSS and fd count (the largest of the last window against
/// the largest of the baseline window) and event p99 (the smallest of the last window's
/// per-sample p99s against the smallest of the baseline window's: why, at `p99_check`).
pub fn growth(samples: &[Sample], limits: &Limits) -> Vec<Check> {
    let Some(w) = windows(samples.len()) else {
        return vec![Check::new(
            "enough samples to judge growth",
            false,
            format!("{} samples, at least 3 needed", samples.len()),
        )];
    };
    let (base, last) = (&samples[w.baseline.clone()], &samples[w.last.clone()]);
    let max_of = |s: &[Sample], f: fn(&Sample) -> u64| s.iter().map(f).max().unwrap_or(0);
    let stretch = format!(
        "warm-up {} sample(s), baseline samples {}-{}, last {}-{}",
        w.warmup,
        w.baseline.start + 1,
        w.baseline.end,
        w.last.start + 1,
        w.last.end
    );
    let mut checks = Vec::new();
    for (name, unit, slack, f) in [
        (
            "RSS flat",
            "KiB",
            limits.rss_slack_kib,
            (|s| s.rss_kib) as fn(&Sample) -> u64,
        ),
        ("open files flat", "fds", limits.fd_slack, |s| s.fds),
    ] {
        let (b, l) = (max_of(base, f), max_of(last, f));
        let allowed = limits.allowed(b, slack);
        let change = 100.0 * (l as f64 - b as f64) / (b.max(1) as f64);
        checks.push(Check::new(
            name,
            b > 0 && l <= allowed,
            format!(
                "{l} {unit} (last window, max) vs {b} {unit} (baseline, max): {change:+.1} %, \
                 allowed {allowed} (+{}% or +{slack}); {stretch}",
                limits.percent
            ),
        ));
    }
    checks.push(p99_check(base, last, limits));
    checks
}

/// The event p99 check: each window stands for its least disturbed sample.
///
/// A sample's p99 is set by its slowest fix or two: each fix reaches every client at once,
/// so 1 % of a 10-s sample's 5,000 events is the 50 events of a single fix. A shared
/// machine only ever adds to a latency (another job holding the cores, the 50 client
/// threads waiting for them), never takes from it, so the smallest sample of a window is
/// the estimate of the daemon's own latency that such noise disturbs least. A daemon that
/// degrades (work per event rising with uptime, a queue growing) raises every sample of
/// the last window, the smallest with them. The median of a window would fail a run whose
/// host slows for its last seconds while RSS, descriptors and events stay flat.
fn p99_check(base: &[Sample], last: &[Sample], limits: &Limits) -> Check {
    let least_p99 = |s: &[Sample]| s.iter().filter_map(|s| s.p99_ms).min_by(f64::total_cmp);
    match (least_p99(base), least_p99(last)) {
        (Some(b), Some(l)) => {
            let allowed = limits.allowed_p99(b);
            Check::new(
                "event p99 unchanged",
                l <= allowed,
                format!(
                    "{l:.2} ms (last window, least) vs {b:.2} ms (baseline, least), allowed \
                     {allowed:.2} ms (max({}x, +{} ms))",
                    limits.p99_factor, limits.p99_slack_ms
                ),
            )
        }
        _ => Check::new(
            "event p99 unchanged",
            false,
            "no latency measured in the baseline or the last window".into(),
        ),
    }
}

/// The `q` quantile (nearest rank) of sorted values; `None` when there are none.
pub fn quantile(sorted: &[f64], q: f64) -> Option<f64> {
    if sorted.is_empty() {
        return None;
    }
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    Some(sorted[rank - 1])
}

/// `VmRSS` of a `/proc/PID/status` text, KiB.
pub fn vm_rss_kib(status: &str) -> Option<u64> {
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let mut words = line["VmRSS:".len()..].split_whitespace();
    let value = words.next()?.parse().ok()?;
    match words.next() {
        Some("kB") | None => Some(value),
        Some(_) => None,
    }
}

/// The resident set of process `pid`, KiB.
pub fn rss_kib(pid: u32) -> Option<u64> {
    vm_rss_kib(&std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?)
}

/// Open file descriptors of process `pid` (entries of `/proc/PID/fd`).
pub fn open_fds(pid: u32) -> Option<u64> {
    let dir = std::fs::read_dir(format!("/proc/{pid}/fd")).ok()?;
    Some(dir.filter(Result::is_ok).count() as u64)
}

#[cfg(test)]
mod tests;
