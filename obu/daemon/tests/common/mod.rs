//! Helpers shared by the tests of the real `obu` binary: start and stop it, read its first
//! line, make HTTP requests, read the event stream, and the codec's committed vectors.
#![allow(dead_code)]

pub mod craft;

use std::ffi::OsStr;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpStream, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A running daemon and what it printed on its first line.
pub struct Daemon {
    child: Child,
    /// The first line, split at whitespace.
    pub words: Vec<String>,
    /// The HTTP address (`HOST:PORT`).
    pub http: String,
}

impl Daemon {
    /// Starts `obu` with `args` and reads its first line
    /// (`obu: http://ADDR v2x udp ADDR [gnss udp ADDR]` or `obu: http://ADDR bridge SOURCE`).
    pub fn start<S: AsRef<OsStr>>(args: impl IntoIterator<Item = S>) -> Self {
        let mut command = Command::new(env!("CARGO_BIN_EXE_obu"));
        command.args(args).stderr(Stdio::null());
        Self::spawn(command)
    }

    /// As [`Daemon::start`], with its log (standard error) written to `log`.
    pub fn start_logged<S: AsRef<OsStr>>(args: impl IntoIterator<Item = S>, log: &Path) -> Self {
        let mut command = Command::new(env!("CARGO_BIN_EXE_obu"));
        let file = std::fs::File::create(log).unwrap();
        command.args(args).stderr(file);
        Self::spawn(command)
    }

    /// Starts `command` (the daemon, perhaps through a shell) and reads its first line.
    pub fn spawn(mut command: Command) -> Self {
        let mut child = command.stdout(Stdio::piped()).spawn().expect("start obu");
        let mut first = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut first)
            .unwrap();
        let words: Vec<String> = first.split_whitespace().map(str::to_owned).collect();
        assert!(words.len() >= 4, "unexpected first line {first:?}");
        assert_eq!(words[0], "obu:", "{first:?}");
        let http = words[1]
            .strip_prefix("http://")
            .expect("http:// address")
            .to_owned();
        Daemon { child, words, http }
    }

    /// The V2X address of the normal mode's first line.
    pub fn v2x(&self) -> &str {
        assert_eq!(self.words[2..4], ["v2x", "udp"], "{:?}", self.words);
        &self.words[4]
    }

    /// The NMEA UDP address of the normal mode's first line (`gnss udp ADDR`): the daemon
    /// binds the configured port (tests configure 0, so no two tests race for one).
    pub fn gnss(&self) -> std::net::SocketAddr {
        assert_eq!(self.words[5..7], ["gnss", "udp"], "{:?}", self.words);
        self.words[7].parse().expect("gnss address")
    }

    /// The process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }

    /// Sends SIGTERM and waits (at most 5 s) for the exit.
    pub fn stop(mut self) -> std::process::ExitStatus {
        let pid = self.child.id().to_string();
        Command::new("kill").args(["-TERM", &pid]).status().unwrap();
        let deadline = Instant::now() + Duration::from_secs(5);
        loop {
            if let Some(status) = self.child.try_wait().unwrap() {
                return status;
            }
            assert!(Instant::now() < deadline, "obu did not stop on SIGTERM");
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

impl Drop for Daemon {
    fn drop(&mut self) {
        let _ = self.child.kill();
    }
}

/// An empty directory of this test process.
pub fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("obu-daemon-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A UDP port that was free a moment ago.
pub fn free_udp_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// One HTTP/1.1 request; returns (status, body).
pub fn http(addr: &str, method: &str, path: &str, body: &str) -> (u16, String) {
    let (status, _, body) = request(addr, method, path, &[], body);
    (status, body)
}

/// One HTTP/1.1 request (`Host` is `addr`) with extra header lines (`"Name: value"`);
/// returns (status, head, body).
pub fn request(
    addr: &str,
    method: &str,
    path: &str,
    headers: &[&str],
    body: &str,
) -> (u16, String, String) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let extra: String = headers.iter().map(|h| format!("{h}\r\n")).collect();
    write!(s, "{method} {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\nContent-Type: application/json\r\n{extra}Content-Length: {}\r\n\r\n{body}", body.len()).unwrap();
    let mut out = String::new();
    let _ = s.read_to_string(&mut out);
    let status = out
        .split_whitespace()
        .nth(1)
        .and_then(|c| c.parse().ok())
        .unwrap_or(0);
    let (head, body) = out.split_once("\r\n\r\n").unwrap_or((&out, ""));
    (status, head.to_owned(), body.to_owned())
}

/// Pairs with `pin` (`POST /api/pair`); returns the `Cookie` header line to send.
pub fn pair(addr: &str, pin: &str) -> String {
    let (status, head, body) = request(
        addr,
        "POST",
        "/api/pair",
        &[],
        &format!("{{\"pin\":\"{pin}\"}}"),
    );
    assert_eq!(status, 200, "pairing with {pin}: {body}");
    let cookie = head
        .lines()
        .find_map(|l| {
            l.strip_prefix("set-cookie: ")
                .or_else(|| l.strip_prefix("Set-Cookie: "))
        })
        .expect("a session cookie");
    let pair = cookie.split(';').next().unwrap();
    format!("Cookie: {pair}")
}

/// `GET /api/status`.
pub fn status(addr: &str) -> serde_json::Value {
    serde_json::from_str(&http(addr, "GET", "/api/status", "").1).unwrap()
}

/// Polls `GET /api/status` until `ok` holds for it (5 s at most: a daemon under qemu-user
/// on a loaded host is slow, not stuck); returns the last status read, for the caller to
/// assert on.
pub fn status_when(addr: &str, ok: impl Fn(&serde_json::Value) -> bool) -> serde_json::Value {
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        let s = status(addr);
        if ok(&s) || Instant::now() > deadline {
            return s;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The UPER octets of the codec's committed vector `name`.
pub fn vector(name: &str) -> Vec<u8> {
    test_support::vectors::named(name).bytes()
}

/// Reads SSE events (id, data) until `n` arrived or the time runs out.
pub fn read_events(stream: &mut BufReader<TcpStream>, n: usize) -> Vec<(u64, serde_json::Value)> {
    let mut out = Vec::new();
    let (mut id, mut line) = (0u64, String::new());
    let deadline = Instant::now() + Duration::from_secs(5);
    while out.len() < n && Instant::now() < deadline {
        line.clear();
        if stream.read_line(&mut line).unwrap_or(0) == 0 {
            break;
        }
        if let Some(v) = line.strip_prefix("id:") {
            // `<run>-<seq>`
            let (run, seq) = v.trim().split_once('-').expect("run-seq");
            assert!(run.parse::<u64>().is_ok(), "{v}");
            id = seq.parse().unwrap();
        } else if let Some(v) = line.strip_prefix("data:") {
            out.push((id, serde_json::from_str(v.trim()).unwrap()));
        }
    }
    out
}

/// Opens `GET /events`, resuming after `last_id` when given.
pub fn open_events(addr: &str, last_id: Option<&str>) -> BufReader<TcpStream> {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let resume = last_id
        .map(|i| format!("Last-Event-ID: {i}\r\n"))
        .unwrap_or_default();
    write!(
        s,
        "GET /events HTTP/1.1\r\nHost: {addr}\r\nAccept: text/event-stream\r\n{resume}\r\n"
    )
    .unwrap();
    let mut r = BufReader::new(s);
    let mut line = String::new();
    r.read_line(&mut line).unwrap();
    assert!(line.starts_with("HTTP/1.1 200"), "{line}");
    r
}

/// The run part of the event ids (`<run>-<seq>`) of a daemon with at least one event.
pub fn run_of(addr: &str) -> u64 {
    let mut s = open_events(addr, None);
    let mut line = String::new();
    let deadline = Instant::now() + Duration::from_secs(5);
    while Instant::now() < deadline {
        line.clear();
        s.read_line(&mut line).unwrap();
        if let Some(v) = line.strip_prefix("id:") {
            return v.trim().split_once('-').unwrap().0.parse().unwrap();
        }
    }
    panic!("no event id");
}
