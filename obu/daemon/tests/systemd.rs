//! The real `obu` binary under a (simulated) service manager: `NOTIFY_SOCKET` is a datagram
//! socket this test binds, as systemd's is for a `Type=notify` unit with `WatchdogSec=`.

mod common;

use common::{http, temp_dir};
use std::os::unix::net::UnixDatagram;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The child, killed if the test fails before it stops it.
struct Guard(Child);

impl Drop for Guard {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn write_config(dir: &Path) -> std::path::PathBuf {
    let path = dir.join("obu.toml");
    let text = format!(
        "[v2x]\nbind = \"127.0.0.1:0\"\n[http]\nbind = \"127.0.0.1:0\"\nsettings_file = \"{}\"\n",
        dir.join("settings.json").display()
    );
    std::fs::write(&path, text).unwrap();
    path
}

/// Starts the daemon with `NOTIFY_SOCKET` at a socket bound in `dir` and the extra
/// environment `env`; returns it and the socket.
fn start(dir: &Path, env: &[(&str, &str)]) -> (Guard, UnixDatagram) {
    let sock_path = dir.join("notify");
    let sock = UnixDatagram::bind(&sock_path).unwrap();
    sock.set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_obu"));
    cmd.arg("--config")
        .arg(write_config(dir))
        .env("NOTIFY_SOCKET", &sock_path)
        .envs(env.iter().copied())
        .env_remove("JOURNAL_STREAM")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(dir.join("log")).unwrap());
    (Guard(cmd.spawn().expect("start obu")), sock)
}

fn recv(sock: &UnixDatagram) -> String {
    let mut buf = [0u8; 1024];
    let n = sock.recv(&mut buf).expect("a notification in time");
    String::from_utf8(buf[..n].to_vec()).unwrap()
}

/// Receives `READY=1`, the first notification, and returns the HTTP address its status
/// names.
fn ready(sock: &UnixDatagram) -> String {
    let first = recv(sock);
    let status = first
        .strip_prefix("READY=1\nSTATUS=serving http://")
        .unwrap_or_else(|| panic!("not READY first: {first:?}"));
    status.split_whitespace().next().unwrap().to_owned()
}

#[test]
fn ready_comes_once_serving_then_watchdog_pings_then_stopping_on_sigterm() {
    let dir = temp_dir("notify");
    let (mut child, sock) = start(&dir, &[("WATCHDOG_USEC", "200000")]);
    let addr = ready(&sock);
    // Nothing polled before READY: the daemon answers at once.
    assert_eq!(http(&addr, "GET", "/healthz", ""), (200, "ok".into()));

    // A 200 ms watchdog: a ping every 100 ms, from the first half interval on. The pings
    // sent while this test waited for READY and /healthz are taken first, so that the 1.5 s
    // counts the pings sent in it (on a starved test thread they could be many).
    sock.set_nonblocking(true).unwrap();
    let mut queued = [0u8; 1024];
    while let Ok(n) = sock.recv(&mut queued) {
        assert_eq!(&queued[..n], b"WATCHDOG=1");
    }
    sock.set_nonblocking(false).unwrap();
    let t0 = Instant::now();
    let mut pings = 0;
    while t0.elapsed() < Duration::from_millis(1500) {
        assert_eq!(recv(&sock), "WATCHDOG=1");
        pings += 1;
    }
    assert!((10..=17).contains(&pings), "{pings} pings in 1.5 s");

    let pid = child.0.id().to_string();
    assert!(Command::new("kill")
        .args(["-TERM", &pid])
        .status()
        .unwrap()
        .success());
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        match recv(&sock).as_str() {
            "WATCHDOG=1" => assert!(Instant::now() < deadline, "no STOPPING=1"),
            "STOPPING=1\nSTATUS=shutting down" => break,
            other => panic!("unexpected notification {other:?}"),
        }
    }
    assert!(child.0.wait().unwrap().success());
    // Not under the journal: the plain log lines as before.
    let log = std::fs::read_to_string(dir.join("log")).unwrap();
    assert!(log.contains("obu: pairing PIN "), "{log}");
    assert!(log.contains("obu: shutting down"), "{log}");
    assert!(!log.contains("systemd"), "no notification failed: {log}");
}

#[test]
fn a_watchdog_meant_for_another_process_gets_no_pings() {
    let dir = temp_dir("notify-other");
    let (child, sock) = start(&dir, &[("WATCHDOG_USEC", "200000"), ("WATCHDOG_PID", "1")]);
    let addr = ready(&sock);
    assert_eq!(http(&addr, "GET", "/healthz", ""), (200, "ok".into()));
    sock.set_read_timeout(Some(Duration::from_millis(600)))
        .unwrap();
    let mut buf = [0u8; 64];
    let got = sock
        .recv(&mut buf)
        .map(|n| String::from_utf8_lossy(&buf[..n]).into_owned());
    assert!(got.is_err(), "unexpected {got:?}");
    drop(child);
}

#[test]
fn a_malformed_notify_socket_is_logged_and_the_daemon_serves() {
    let dir = temp_dir("notify-bad");
    let log = dir.join("log");
    let d = common::Daemon::spawn({
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_obu"));
        cmd.arg("--config")
            .arg(write_config(&dir))
            .env("NOTIFY_SOCKET", "vsock:2:99")
            .env("WATCHDOG_USEC", "soon")
            .stderr(std::fs::File::create(&log).unwrap());
        cmd
    });
    assert_eq!(http(&d.http, "GET", "/healthz", ""), (200, "ok".into()));
    let text = std::fs::read_to_string(&log).unwrap();
    assert!(
        text.contains("obu: NOTIFY_SOCKET \"vsock:2:99\": not an absolute path"),
        "{text}"
    );
    assert!(d.stop().success());
}

/// Standard error (and output) connected to a "journal": `JOURNAL_STREAM` names the log
/// file's device and inode, as systemd names the stream it connects, and
/// `OBU_JOURNAL_SOCKET` a datagram socket this test binds as journald's.
#[test]
fn under_the_journal_entries_are_structured_fields_not_text() {
    use std::os::unix::fs::MetadataExt;
    let dir = temp_dir("journal");
    let journal_path = dir.join("journal");
    let journal = UnixDatagram::bind(&journal_path).unwrap();
    journal
        .set_read_timeout(Some(Duration::from_secs(10)))
        .unwrap();
    let log = std::fs::File::create(dir.join("log")).unwrap();
    let meta = log.metadata().unwrap();
    let stream = format!("{}:{}", meta.dev(), meta.ino());
    let mut child = Command::new(env!("CARGO_BIN_EXE_obu"))
        .arg("--config")
        .arg(write_config(&dir))
        .env("JOURNAL_STREAM", &stream)
        .env("OBU_JOURNAL_SOCKET", &journal_path)
        .env_remove("NOTIFY_SOCKET")
        .stdout(log.try_clone().unwrap())
        .stderr(log)
        .spawn()
        .expect("start obu");
    let mut entries: Vec<String> = Vec::new();
    let mut buf = vec![0u8; 4096];
    // The warning about trust anchors, the PIN, then `ready` (stdout is the journal too).
    while !entries.iter().any(|e| e.contains("OBU_EVENT=ready\n")) {
        let n = journal.recv(&mut buf).expect("journal entries in time");
        entries.push(String::from_utf8(buf[..n].to_vec()).unwrap());
    }
    let pairing = entries
        .iter()
        .find(|e| e.contains("OBU_EVENT=pairing\n"))
        .unwrap_or_else(|| panic!("no pairing entry: {entries:?}"));
    assert!(pairing.starts_with("MESSAGE=pairing PIN "), "{pairing:?}");
    assert!(pairing.contains("\nPRIORITY=5\n"), "{pairing:?}");
    assert!(pairing.contains("\nSYSLOG_IDENTIFIER=obu\n"), "{pairing:?}");
    let ready = entries
        .iter()
        .find(|e| e.contains("OBU_EVENT=ready\n"))
        .unwrap();
    let addr = ready
        .lines()
        .find_map(|l| l.strip_prefix("OBU_HTTP="))
        .unwrap_or_else(|| panic!("no OBU_HTTP: {ready:?}"));
    assert_eq!(http(addr, "GET", "/healthz", ""), (200, "ok".into()));
    let pid = child.id().to_string();
    Command::new("kill").args(["-TERM", &pid]).status().unwrap();
    assert!(child.wait().unwrap().success());
    let text = std::fs::read_to_string(dir.join("log")).unwrap();
    assert_eq!(text, "", "nothing written as plain text under the journal");
}
