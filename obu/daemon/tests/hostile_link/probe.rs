//! What a tablet or a monitor does, timed: `GET /healthz` on a new connection, the first
//! event of `/events`; and what the daemon process holds (open files, its limit).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

/// How long a probe may take before it counts as unreachable.
pub const PROBE_TIMEOUT: Duration = Duration::from_secs(3);

/// `GET /healthz` on a new connection: the time until the whole `ok` answer arrived, or
/// why it failed.
pub fn healthz(addr: &str) -> Result<Duration, String> {
    let t0 = Instant::now();
    let sock: SocketAddr = addr.parse().map_err(|e| format!("{addr}: {e}"))?;
    let mut s = TcpStream::connect_timeout(&sock, PROBE_TIMEOUT).map_err(|e| e.to_string())?;
    s.set_read_timeout(Some(PROBE_TIMEOUT))
        .map_err(|e| e.to_string())?;
    write!(
        s,
        "GET /healthz HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .map_err(|e| e.to_string())?;
    let mut out = String::new();
    s.read_to_string(&mut out).map_err(|e| e.to_string())?;
    if out.starts_with("HTTP/1.1 200") && out.ends_with("ok") {
        Ok(t0.elapsed())
    } else {
        Err(format!("answered {out:?}"))
    }
}

/// A new `/events` client: the time until its first state event arrived, or why none did.
/// With `keep`, it then reads on for that long and also returns how many more came.
pub fn first_event(addr: &str, keep: Duration) -> Result<(Duration, usize), String> {
    let t0 = Instant::now();
    let sock: SocketAddr = addr.parse().map_err(|e| format!("{addr}: {e}"))?;
    let mut s = TcpStream::connect_timeout(&sock, PROBE_TIMEOUT).map_err(|e| e.to_string())?;
    s.set_read_timeout(Some(PROBE_TIMEOUT))
        .map_err(|e| e.to_string())?;
    write!(
        s,
        "GET /events HTTP/1.1\r\nHost: {addr}\r\nAccept: text/event-stream\r\n\r\n"
    )
    .map_err(|e| e.to_string())?;
    let mut r = BufReader::new(s);
    let mut line = String::new();
    r.read_line(&mut line).map_err(|e| e.to_string())?;
    if !line.starts_with("HTTP/1.1 200") {
        return Err(format!("answered {line:?}"));
    }
    let mut first = None;
    let mut more = 0;
    loop {
        line.clear();
        let n = r.read_line(&mut line).map_err(|e| e.to_string())?;
        if n == 0 {
            return Err("the stream ended".into());
        }
        if line.starts_with("data:") {
            match first {
                None => first = Some(t0.elapsed()),
                Some(_) => more += 1,
            }
        }
        if let Some(f) = first {
            if t0.elapsed() >= f + keep {
                return Ok((f, more));
            }
        }
    }
}

/// Latencies in milliseconds and their order statistics.
#[derive(Debug, Default)]
pub struct Samples(pub Vec<f64>);

impl Samples {
    /// Adds one.
    pub fn push(&mut self, d: Duration) {
        self.0.push(d.as_secs_f64() * 1000.0);
    }

    /// The `p`-quantile (0..=1), nearest rank; 0 when empty.
    pub fn quantile(&self, p: f64) -> f64 {
        let mut v = self.0.clone();
        v.sort_by(f64::total_cmp);
        match v.len() {
            0 => 0.0,
            n => v[((p * n as f64).ceil() as usize).clamp(1, n) - 1],
        }
    }

    /// `n`, p50, p99, max as text.
    pub fn summary(&self) -> String {
        format!(
            "{} samples, p50 {:.2} ms, p99 {:.2} ms, max {:.2} ms",
            self.0.len(),
            self.quantile(0.5),
            self.quantile(0.99),
            self.quantile(1.0)
        )
    }
}

/// Open file descriptors of process `pid` now.
pub fn open_files(pid: u32) -> usize {
    std::fs::read_dir(format!("/proc/{pid}/fd")).map_or(0, |d| d.count())
}

/// The soft open-file limit of process `pid`.
pub fn open_file_limit(pid: u32) -> Option<u64> {
    let limits = std::fs::read_to_string(format!("/proc/{pid}/limits")).ok()?;
    let line = limits.lines().find(|l| l.starts_with("Max open files"))?;
    line.split_whitespace().nth(3)?.parse().ok()
}

/// CPU time process `pid` used so far (user + system), seconds (100 ticks a second).
pub fn cpu_seconds(pid: u32) -> Option<f64> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    let rest = &stat[stat.rfind(')')? + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let utime: f64 = fields.get(11)?.parse().ok()?;
    let stime: f64 = fields.get(12)?.parse().ok()?;
    Some((utime + stime) / 100.0)
}

#[test]
fn quantiles_are_nearest_rank() {
    let mut s = Samples::default();
    for ms in 1..=200 {
        s.push(Duration::from_millis(ms));
    }
    assert_eq!(s.quantile(0.5), 100.0);
    assert_eq!(s.quantile(0.99), 198.0);
    assert_eq!(s.quantile(1.0), 200.0);
    assert_eq!(Samples::default().quantile(0.99), 0.0);
}
