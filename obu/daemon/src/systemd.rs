//! Service-manager notifications (the `sd_notify` protocol, written here without a crate):
//! `READY=1` once the daemon serves, `STOPPING=1` at shutdown, and `WATCHDOG=1` pings
//! while the daemon's main loop keeps turning.
//!
//! systemd passes `NOTIFY_SOCKET` (a datagram socket: a path, or `@name` for an abstract
//! one) to a `Type=notify` service, and `WATCHDOG_USEC` (with `WATCHDOG_PID`) when the unit
//! sets `WatchdogSec=`. Without them every call here does nothing. A failed send is logged
//! once and never stops the daemon.

use std::ffi::OsStr;
use std::os::unix::net::UnixDatagram;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;
use tokio::sync::watch;

/// Where the service manager listens for notifications.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NotifyAddr {
    /// A socket file.
    Path(PathBuf),
    /// A Linux abstract socket (`@name` in `NOTIFY_SOCKET`): the name without the `@`.
    Abstract(Vec<u8>),
}

/// Reads `NOTIFY_SOCKET`: `None` when unset or empty, an error for a form this daemon
/// cannot send to (systemd's `vsock:` addresses, a relative path).
pub fn parse_notify_socket(value: Option<&OsStr>) -> Result<Option<NotifyAddr>, String> {
    use std::os::unix::ffi::OsStrExt;
    let Some(value) = value.filter(|v| !v.is_empty()) else {
        return Ok(None);
    };
    let bytes = value.as_bytes();
    match bytes[0] {
        b'/' => Ok(Some(NotifyAddr::Path(PathBuf::from(value)))),
        b'@' if bytes.len() > 1 => Ok(Some(NotifyAddr::Abstract(bytes[1..].to_vec()))),
        _ => Err(format!(
            "NOTIFY_SOCKET {:?}: not an absolute path or @abstract name",
            value.to_string_lossy()
        )),
    }
}

/// Reads `WATCHDOG_USEC` and `WATCHDOG_PID`: the watchdog interval when it is meant for this
/// process (`WATCHDOG_PID` absent or `own_pid`), `None` when unset or meant for another
/// process, an error for a value that does not parse or is zero.
pub fn parse_watchdog(
    usec: Option<&str>,
    pid: Option<&str>,
    own_pid: u32,
) -> Result<Option<Duration>, String> {
    let Some(usec) = usec.filter(|u| !u.is_empty()) else {
        return Ok(None);
    };
    if let Some(pid) = pid.filter(|p| !p.is_empty()) {
        let pid: u32 = pid
            .trim()
            .parse()
            .map_err(|_| format!("WATCHDOG_PID {pid:?}: not a process id"))?;
        if pid != own_pid {
            return Ok(None);
        }
    }
    match usec.trim().parse::<u64>() {
        Ok(n) if n > 0 => Ok(Some(Duration::from_micros(n))),
        _ => Err(format!("WATCHDOG_USEC {usec:?}: not a positive number")),
    }
}

/// The notification socket, if the service manager gave one, and the watchdog interval.
pub struct Notifier {
    target: Option<(UnixDatagram, NotifyAddr)>,
    watchdog: Option<Duration>,
    failed: AtomicBool,
}

impl Notifier {
    /// A notifier that sends nothing (no service manager).
    pub fn none() -> Self {
        Self {
            target: None,
            watchdog: None,
            failed: AtomicBool::new(false),
        }
    }

    /// Reads `NOTIFY_SOCKET`, `WATCHDOG_USEC` and `WATCHDOG_PID`, then removes them from the
    /// environment so that no child process (`stty`) notifies in the daemon's name. Call it
    /// before any other thread starts. A malformed variable is logged and ignored.
    pub fn from_env() -> Self {
        let socket = std::env::var_os("NOTIFY_SOCKET");
        let usec = std::env::var("WATCHDOG_USEC").ok();
        let pid = std::env::var("WATCHDOG_PID").ok();
        for name in ["NOTIFY_SOCKET", "WATCHDOG_USEC", "WATCHDOG_PID"] {
            std::env::remove_var(name);
        }
        let mut notifier = Self::none();
        let addr = match parse_notify_socket(socket.as_deref()) {
            Ok(a) => a,
            Err(e) => {
                crate::log::warn("systemd", &format!("{e}; not notifying"));
                None
            }
        };
        let Some(addr) = addr else {
            return notifier;
        };
        match UnixDatagram::unbound() {
            Ok(sock) => notifier.target = Some((sock, addr)),
            Err(e) => crate::log::warn("systemd", &format!("notify socket: {e}")),
        }
        match parse_watchdog(usec.as_deref(), pid.as_deref(), std::process::id()) {
            Ok(w) => notifier.watchdog = w,
            Err(e) => crate::log::warn("systemd", &format!("{e}; no watchdog pings")),
        }
        notifier
    }

    /// The watchdog interval systemd expects pings within, when it watches this process.
    pub fn watchdog(&self) -> Option<Duration> {
        self.target.as_ref().and(self.watchdog)
    }

    /// Sends `text` (newline-separated `KEY=value` assignments); does nothing without a
    /// socket. The first failure is logged, later ones are not.
    pub fn send(&self, text: &str) {
        let Some((sock, addr)) = &self.target else {
            return;
        };
        if let Err(e) = send_to(sock, addr, text.as_bytes()) {
            if !self.failed.swap(true, Ordering::Relaxed) {
                crate::log::warn(
                    "systemd",
                    &format!(
                        "cannot notify the service manager: {e} (further failures not logged)"
                    ),
                );
            }
        }
    }

    /// `READY=1` with a status line.
    pub fn ready(&self, status: &str) {
        self.send(&format!("READY=1\nSTATUS={}", one_line(status)));
    }

    /// `STOPPING=1`.
    pub fn stopping(&self) {
        self.send("STOPPING=1\nSTATUS=shutting down");
    }
}

/// `text` with line breaks turned into spaces (a notification field is one line).
fn one_line(text: &str) -> String {
    text.replace(['\n', '\r'], " ")
}

fn send_to(sock: &UnixDatagram, addr: &NotifyAddr, data: &[u8]) -> std::io::Result<()> {
    let sent = match addr {
        NotifyAddr::Path(path) => sock.send_to(data, path)?,
        NotifyAddr::Abstract(name) => send_abstract(sock, name, data)?,
    };
    if sent == data.len() {
        Ok(())
    } else {
        Err(std::io::Error::other("short datagram"))
    }
}

#[cfg(any(target_os = "linux", target_os = "android"))]
fn send_abstract(sock: &UnixDatagram, name: &[u8], data: &[u8]) -> std::io::Result<usize> {
    #[cfg(target_os = "android")]
    use std::os::android::net::SocketAddrExt;
    #[cfg(target_os = "linux")]
    use std::os::linux::net::SocketAddrExt;
    let addr = std::os::unix::net::SocketAddr::from_abstract_name(name)?;
    sock.send_to_addr(data, &addr)
}

#[cfg(not(any(target_os = "linux", target_os = "android")))]
fn send_abstract(_: &UnixDatagram, _: &[u8], _: &[u8]) -> std::io::Result<usize> {
    Err(std::io::Error::other(
        "abstract sockets exist only on Linux",
    ))
}

/// The deadline loop's longest sleep under a watchdog of `interval`: a quarter of it, so the
/// loop turns at least twice between two checks of the watchdog task.
pub fn liveness_tick(interval: Duration) -> Duration {
    (interval / 4).max(Duration::from_millis(1))
}

/// Pings the watchdog every half `interval` while `progress` (a count the main loop
/// advances) moves; a loop that stopped turning gets no ping and systemd restarts the
/// daemon. Runs on the daemon's single-thread runtime, so a wedged runtime pings no more
/// either. Returns when `stop` turns true.
pub async fn run_watchdog(
    notifier: Arc<Notifier>,
    interval: Duration,
    progress: impl Fn() -> u64,
    mut stop: watch::Receiver<bool>,
) {
    let mut ticks = tokio::time::interval(interval / 2);
    ticks.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    ticks.tick().await;
    let mut last = progress();
    let mut stalled_logged = false;
    loop {
        tokio::select! {
            _ = ticks.tick() => {}
            _ = stop.changed() => return,
        }
        let mut now = progress();
        if now == last {
            // After a stall of the runtime this tick may run before the loop's own pending
            // turn: let it run once, then look again.
            tokio::task::yield_now().await;
            now = progress();
        }
        if now != last {
            last = now;
            stalled_logged = false;
            notifier.send("WATCHDOG=1");
        } else if !stalled_logged {
            stalled_logged = true;
            crate::log::error(
                "watchdog",
                "the main loop made no progress: not pinging the watchdog",
            );
        }
    }
}

#[cfg(test)]
mod tests;
