//! The soak's hostile HTTP side, all on the loopback and bounded: an unauthenticated
//! settings write every 2 s (must be refused: 401), a request naming a foreign `Host`
//! every 2 s (must be refused: 421), and [`SLOW`] connections held open at all times that
//! dribble a request body one octet a second (a `POST /api/pair` declaring 64 octets),
//! each of which the daemon must cut at its request deadline (`request_timeout_ms`).

use serde::Serialize;
use std::io::{ErrorKind, Read, Write};
use std::net::TcpStream;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Slow-body connections kept open at once.
pub const SLOW: usize = 3;
/// The daemon's request deadline the soak configures (its default), milliseconds.
pub const REQUEST_TIMEOUT_MS: u64 = 5000;
/// A slow connection still open this long after its deadline was not cut: a failure.
pub const CUT_GRACE: Duration = Duration::from_secs(5);
/// Unexpected answers kept for the report.
const KEPT_ERRORS: usize = 10;

/// What the hostile HTTP side did and saw.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct HttpTally {
    /// Unauthenticated `PUT /api/settings` sent.
    pub settings_writes: u64,
    /// Of them, answered 401.
    pub settings_refused: u64,
    /// Requests with a foreign `Host` sent.
    pub foreign_host: u64,
    /// Of them, answered 421.
    pub foreign_refused: u64,
    /// Slow-body connections opened.
    pub slow_opened: u64,
    /// Of them, cut by the daemon.
    pub slow_cut: u64,
    /// Of them, still open [`CUT_GRACE`] after the deadline (closed by the soak).
    pub slow_not_cut: u64,
    /// Shortest and longest time from a slow connection's first octet to its cut, seconds.
    pub slow_cut_s: Option<(f64, f64)>,
    /// The first unexpected answers or errors.
    pub errors: Vec<String>,
}

impl HttpTally {
    fn error(&mut self, e: String) {
        if self.errors.len() < KEPT_ERRORS {
            self.errors.push(e);
        }
    }

    fn cut_after(&mut self, s: f64) {
        self.slow_cut += 1;
        self.slow_cut_s = Some(
            self.slow_cut_s
                .map_or((s, s), |(a, b)| (a.min(s), b.max(s))),
        );
    }
}

/// One slow-body connection.
struct Slow {
    stream: TcpStream,
    opened: Instant,
}

/// Runs the hostile HTTP side against `addr` (`host:port`) until `stop`; the tally is kept
/// in `tally` as it goes.
pub fn hostile_http(addr: &str, tally: &Mutex<HttpTally>, stop: &AtomicBool) {
    let lock = || super::lock(tally);
    let mut slow: Vec<Slow> = Vec::with_capacity(SLOW);
    let mut next = Instant::now();
    let mut k = 0u64;
    while !stop.load(Ordering::Relaxed) {
        // Every 250 ms: the slow connections; every 8th tick a settings write, every 8th
        // (4 later) a foreign Host.
        if k.is_multiple_of(8) {
            let answer = request(addr, &settings_write(addr));
            let mut t = lock();
            t.settings_writes += 1;
            match answer {
                Ok(401) => t.settings_refused += 1,
                other => t.error(format!("settings write without pairing: {other:?}")),
            }
        }
        if k % 8 == 4 {
            let answer = request(addr, &foreign_host(addr));
            let mut t = lock();
            t.foreign_host += 1;
            match answer {
                Ok(421) => t.foreign_refused += 1,
                other => t.error(format!("foreign Host: {other:?}")),
            }
        }
        dribble(addr, &mut slow, k.is_multiple_of(4), &mut lock());
        k += 1;
        next += Duration::from_millis(250);
        std::thread::sleep(next.saturating_duration_since(Instant::now()));
    }
}

/// The slow connections the daemon cut counted and replaced, the ones past the deadline
/// and the grace closed as failures; on the others one more octet when `write`.
fn dribble(addr: &str, slow: &mut Vec<Slow>, write: bool, t: &mut HttpTally) {
    let deadline = Duration::from_millis(REQUEST_TIMEOUT_MS) + CUT_GRACE;
    slow.retain_mut(|s| {
        let age = s.opened.elapsed();
        if cut(&mut s.stream) {
            t.cut_after(age.as_secs_f64());
            return false;
        }
        if age > deadline {
            t.slow_not_cut += 1;
            t.error(format!(
                "a slow body still open after {:.1} s",
                age.as_secs_f64()
            ));
            return false;
        }
        if write {
            let _ = s.stream.write_all(b" ");
        }
        true
    });
    while slow.len() < SLOW {
        match open_slow(addr) {
            Ok(s) => {
                t.slow_opened += 1;
                slow.push(s);
            }
            Err(e) => {
                t.error(format!("opening a slow body: {e}"));
                break;
            }
        }
    }
}

/// Whether the daemon closed (or answered and is closing) a slow connection.
fn cut(stream: &mut TcpStream) -> bool {
    let mut buf = [0u8; 64];
    // Anything to read (EOF, or an answer before the close) or an error: cut.
    match stream.peek(&mut buf) {
        Ok(_) => true,
        Err(e) => e.kind() != ErrorKind::WouldBlock,
    }
}

fn open_slow(addr: &str) -> Result<Slow, String> {
    let mut stream = TcpStream::connect(addr).map_err(|e| e.to_string())?;
    let opened = Instant::now();
    write!(
        stream,
        "POST /api/pair HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\n\
         Content-Length: 64\r\n\r\n{{"
    )
    .map_err(|e| e.to_string())?;
    stream.set_nonblocking(true).map_err(|e| e.to_string())?;
    Ok(Slow { stream, opened })
}

fn settings_write(addr: &str) -> String {
    let body = r#"{"warning_distance_m": 5.0}"#;
    format!(
        "PUT /api/settings HTTP/1.1\r\nHost: {addr}\r\nContent-Type: application/json\r\n\
         Content-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    )
}

fn foreign_host(addr: &str) -> String {
    let port = addr.rsplit(':').next().unwrap_or("80");
    format!(
        "GET /api/status HTTP/1.1\r\nHost: attacker.example:{port}\r\nConnection: close\r\n\r\n"
    )
}

/// Sends `text` on a new connection; the status code of the answer.
fn request(addr: &str, text: &str) -> Result<u16, String> {
    let mut s = TcpStream::connect(addr).map_err(|e| e.to_string())?;
    s.set_read_timeout(Some(Duration::from_secs(5)))
        .map_err(|e| e.to_string())?;
    s.write_all(text.as_bytes()).map_err(|e| e.to_string())?;
    let mut answer = Vec::new();
    s.read_to_end(&mut answer).map_err(|e| e.to_string())?;
    status_code(&answer).ok_or_else(|| format!("no status line in {} octets", answer.len()))
}

/// The status code of an HTTP/1.1 answer.
pub fn status_code(answer: &[u8]) -> Option<u16> {
    let head = std::str::from_utf8(answer.get(..answer.len().min(64))?).ok()?;
    let rest = head.strip_prefix("HTTP/1.1 ")?;
    rest.get(..3)?.parse().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_lines_give_their_code() {
        assert_eq!(
            status_code(b"HTTP/1.1 421 Misdirected Request\r\n\r\n"),
            Some(421)
        );
        assert_eq!(status_code(b"HTTP/1.1 401 Unauthorized\r\n"), Some(401));
        assert_eq!(status_code(b"HTTP/1.0 200 OK\r\n"), None);
        assert_eq!(status_code(b""), None);
    }

    #[test]
    fn the_hostile_requests_are_what_they_claim() {
        let w = settings_write("127.0.0.1:8080");
        let (head, body) = w.split_once("\r\n\r\n").unwrap();
        assert!(head.starts_with("PUT /api/settings ") && !head.contains("Cookie"));
        assert!(head.contains(&format!("Content-Length: {}", body.len())));
        let f = foreign_host("127.0.0.1:8080");
        assert!(f.contains("Host: attacker.example:8080\r\n"), "{f}");
    }

    #[test]
    fn the_tally_keeps_the_cut_range_and_few_errors() {
        let mut t = HttpTally::default();
        t.cut_after(5.2);
        t.cut_after(5.0);
        t.cut_after(5.4);
        assert_eq!((t.slow_cut, t.slow_cut_s), (3, Some((5.0, 5.4))));
        for i in 0..20 {
            t.error(format!("{i}"));
        }
        assert_eq!(t.errors.len(), KEPT_ERRORS);
    }
}
