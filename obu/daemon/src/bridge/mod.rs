//! Bridge mode: the OBU core runs in the firmware (on the microcontroller, or in QEMU), which
//! sends each `HmiState` out of a serial port as an `obu::link` frame around its postcard
//! encoding. This task reads that stream, decodes it ([`decode`]) and publishes every state
//! through [`Hub::publish_state`], so that the tablet is served exactly as in the normal mode;
//! the daemon's V2X, GNSS and CAN inputs are not started.
//!
//! - `tcp:HOST:PORT`: connects as a client (QEMU's `-serial tcp:HOST:PORT,server,nowait`).
//! - `serial:PATH`: opens the device for reading. The tty must be raw at the firmware's rate
//!   (115200 8N1): the daemon runs `stty -F PATH BAUD raw -echo cs8 -cstopb -parenb` itself
//!   when `[bridge] baud` is set (GNU stty, Linux), otherwise that must be done beforehand.
//!   A regular file (a capture) is read once.
//! - After a refused connection, an error or the end of the input the source is opened
//!   again, waiting 100 ms doubling to 2 s (100 ms again after a connection that delivered a
//!   state): QEMU may not be listening yet, a USB adapter may be replugged.
//! - Every frame becomes a published state or a count in [`group::BRIDGE_ERRORS`] with its
//!   reason, a frame cut by a disconnect included; [`Status::to_json`] is in
//!   `GET /api/status`.
//! - The link is one-way: settings changed on the tablet are stored and served as usual but
//!   never reach the firmware, whose core keeps its own warning distance and lead time.

pub mod decode;

use crate::config::BridgeSource;
use crate::counters::group;
use crate::hub::Hub;
use decode::{LinkError, StateDecoder};
use obu::HmiState;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tokio::io::{AsyncRead, AsyncReadExt};
use tokio::sync::watch;

/// First wait before opening the source again.
const BACKOFF_MIN: Duration = Duration::from_millis(100);
/// Longest wait before opening the source again.
const BACKOFF_MAX: Duration = Duration::from_secs(2);
/// A TCP connection attempt gives up after this.
const CONNECT_TIMEOUT: Duration = Duration::from_secs(3);

/// The link as the status endpoint shows it.
#[derive(Debug)]
pub struct Status {
    source: BridgeSource,
    connected: AtomicBool,
    connects: AtomicU64,
    frames: AtomicU64,
    errors: AtomicU64,
    octets: AtomicU64,
    last_frame: Mutex<Option<Instant>>,
}

impl Status {
    /// A link from `source`, not connected yet.
    pub fn new(source: BridgeSource) -> Arc<Self> {
        Arc::new(Self {
            source,
            connected: AtomicBool::new(false),
            connects: AtomicU64::new(0),
            frames: AtomicU64::new(0),
            errors: AtomicU64::new(0),
            octets: AtomicU64::new(0),
            last_frame: Mutex::new(None),
        })
    }

    /// Where the states come from.
    pub fn source(&self) -> &BridgeSource {
        &self.source
    }

    /// `{"source", "connected", "connects", "frames", "errors", "octets",
    /// "last_frame_age_ms"}`: frames are the states received and published, errors the
    /// frames refused (their reasons are in the `bridge_errors` counters).
    pub fn to_json(&self) -> serde_json::Value {
        let last = *self.last_frame.lock().unwrap_or_else(|p| p.into_inner());
        serde_json::json!({
            "source": self.source.to_string(),
            "connected": self.connected.load(Ordering::Relaxed),
            "connects": self.connects.load(Ordering::Relaxed),
            "frames": self.frames.load(Ordering::Relaxed),
            "errors": self.errors.load(Ordering::Relaxed),
            "octets": self.octets.load(Ordering::Relaxed),
            "last_frame_age_ms": last.map(|t| t.elapsed().as_millis() as u64),
        })
    }

    fn set_connected(&self, on: bool) {
        self.connected.store(on, Ordering::Relaxed);
        if on {
            self.connects.fetch_add(1, Ordering::Relaxed);
        }
    }
}

/// An opened source.
struct Link {
    reader: Box<dyn AsyncRead + Unpin + Send>,
    /// A regular file: read once, not reopened.
    once: bool,
}

/// How reading a link ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum End {
    Shutdown,
    Closed,
    Failed,
}

/// Reads the source until `shutdown`, publishing every state through `hub`.
pub async fn run(
    status: Arc<Status>,
    baud: Option<u32>,
    hub: Arc<Hub>,
    mut shutdown: watch::Receiver<bool>,
) {
    let mut backoff = BACKOFF_MIN;
    loop {
        let opened = tokio::select! {
            opened = open(status.source(), baud) => opened,
            _ = shutdown.changed() => return,
        };
        match opened {
            Ok(link) => {
                status.set_connected(true);
                hub.counters.add(group::BRIDGE, "connected");
                let before = status.frames.load(Ordering::Relaxed);
                let end = pump(link.reader, &status, &hub, &mut shutdown).await;
                status.set_connected(false);
                match end {
                    End::Shutdown => return,
                    End::Closed if link.once => {
                        hub.counters.add(group::BRIDGE, "capture file read");
                        return;
                    }
                    End::Closed => hub.counters.add(group::BRIDGE, "disconnected"),
                    End::Failed => hub.counters.add(group::BRIDGE, "read failed"),
                }
                if status.frames.load(Ordering::Relaxed) > before {
                    backoff = BACKOFF_MIN;
                }
            }
            Err(reason) => hub.counters.add(group::BRIDGE, reason),
        }
        tokio::select! {
            _ = tokio::time::sleep(backoff) => {}
            _ = shutdown.changed() => return,
        }
        backoff = (backoff * 2).min(BACKOFF_MAX);
    }
}

/// Connects or opens the source; the error is the counted reason.
async fn open(source: &BridgeSource, baud: Option<u32>) -> Result<Link, &'static str> {
    match source {
        BridgeSource::Tcp(addr) => {
            let connect = tokio::net::TcpStream::connect(addr.as_str());
            match tokio::time::timeout(CONNECT_TIMEOUT, connect).await {
                Ok(Ok(stream)) => Ok(Link {
                    reader: Box::new(stream),
                    once: false,
                }),
                Ok(Err(_)) => Err("connect failed"),
                Err(_) => Err("connect timed out"),
            }
        }
        BridgeSource::Serial(path) => {
            if let Some(baud) = baud {
                set_raw(path, baud).await?;
            }
            let once = tokio::fs::metadata(path).await.is_ok_and(|m| m.is_file());
            let file = tokio::fs::File::open(path)
                .await
                .map_err(|_| "open failed")?;
            Ok(Link {
                reader: Box::new(file),
                once,
            })
        }
    }
}

/// Sets the tty raw, 8N1 at `baud`, with GNU `stty` (no new dependency, no `unsafe`).
async fn set_raw(path: &Path, baud: u32) -> Result<(), &'static str> {
    let path = path.to_owned();
    let stty = move || {
        std::process::Command::new("stty")
            .arg("-F")
            .arg(&path)
            .arg(baud.to_string())
            .args(["raw", "-echo", "cs8", "-cstopb", "-parenb"])
            .stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    match tokio::task::spawn_blocking(stty).await {
        Ok(true) => Ok(()),
        _ => Err("stty failed"),
    }
}

/// Feeds one connection's octets to a fresh decoder until it ends.
async fn pump(
    mut reader: Box<dyn AsyncRead + Unpin + Send>,
    status: &Status,
    hub: &Hub,
    shutdown: &mut watch::Receiver<bool>,
) -> End {
    let mut decoder = StateDecoder::new();
    let mut buf = [0u8; 1024];
    let end = loop {
        let got = tokio::select! {
            got = reader.read(&mut buf) => got,
            _ = shutdown.changed() => break End::Shutdown,
        };
        match got {
            Ok(0) => break End::Closed,
            Ok(n) => {
                status.octets.fetch_add(n as u64, Ordering::Relaxed);
                decoder.push(&buf[..n], |r| deliver(r, status, hub));
            }
            Err(_) => break End::Failed,
        }
    };
    if let Some(e) = decoder.reset() {
        deliver(Err(e), status, hub);
    }
    end
}

/// Publishes a state, or counts why a frame gave none.
fn deliver(result: Result<HmiState, LinkError>, status: &Status, hub: &Hub) {
    match result {
        Ok(state) => {
            status.frames.fetch_add(1, Ordering::Relaxed);
            *status.last_frame.lock().unwrap_or_else(|p| p.into_inner()) = Some(Instant::now());
            hub.counters.add(group::BRIDGE, "state");
            hub.publish_state(&state);
        }
        Err(e) => {
            status.errors.fetch_add(1, Ordering::Relaxed);
            hub.counters.add(group::BRIDGE_ERRORS, e.as_str());
        }
    }
}
