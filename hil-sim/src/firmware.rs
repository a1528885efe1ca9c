//! The OBU firmware in QEMU as the device under test, in place of the Linux daemon.
//!
//! The rig: QEMU's `netduinoplus2` (STM32F405) runs the firmware image with its three
//! USARTs exposed as TCP server ports (USART1 NMEA in, USART2 V2X frames in, USART3
//! `HmiState` out). The `obu` daemon runs in bridge mode on USART3's port and serves the
//! tablet app and its event stream as it does for its own core. Two relays take what the
//! bench sends to a daemon (UDP datagrams: NMEA epochs and V2X MessageFrames) to the
//! firmware's ports: NMEA as it is (over TCP, every byte delivered, as a GNSS receiver's
//! UART with flow control would), each V2X datagram as one `obu::link` frame (COBS +
//! CRC-32) through the model of a radio chip beside the microcontroller, with a fixed
//! number of receive buffers ([`crate::radio`]; over a Unix socket). The bench then drives
//! the rig through the same [`Daemon`] handle as the daemon alone.

use crate::daemon::Daemon;
use crate::radio::RadioQueue;
use crate::rig::Rig;
use std::io::Write;
use std::net::{TcpListener, TcpStream, UdpSocket};
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Where the firmware image and the emulator are.
#[derive(Debug, Clone)]
pub struct FirmwareTarget {
    /// The firmware ELF (built with `--features qemu`).
    pub elf: PathBuf,
    /// The emulator (`qemu-system-arm`, or `$QEMU`).
    pub qemu: PathBuf,
}

impl FirmwareTarget {
    /// The image at `elf` with `$QEMU` or `qemu-system-arm` from the PATH; fails when the
    /// image is missing.
    pub fn new(elf: &Path) -> Result<Self, String> {
        if !elf.is_file() {
            return Err(format!(
                "{}: no firmware image (cd obu/firmware && cargo build --release --features qemu)",
                elf.display()
            ));
        }
        let qemu = std::env::var_os("QEMU").map_or("qemu-system-arm".into(), PathBuf::from);
        Ok(Self {
            elf: elf.to_path_buf(),
            qemu,
        })
    }
}

/// A TCP port free right now on the loopback interface.
fn free_tcp_port() -> Result<u16, String> {
    let l = TcpListener::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    l.local_addr().map(|a| a.port()).map_err(|e| e.to_string())
}

/// Connects to one of QEMU's server sockets with `connect`, retrying while the emulator
/// starts; `name` says which in an error.
fn connect<S>(
    name: &str,
    qemu: &mut Child,
    connect: impl Fn() -> std::io::Result<S>,
) -> Result<S, String> {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match connect() {
            Ok(s) => return Ok(s),
            Err(e) if Instant::now() >= deadline => {
                return Err(format!("QEMU's serial port {name}: {e}"));
            }
            Err(_) => {
                if let Ok(Some(status)) = qemu.try_wait() {
                    return Err(format!("QEMU exited at start: {status}"));
                }
                std::thread::sleep(Duration::from_millis(50));
            }
        }
    }
}

/// A path for the V2X port's Unix socket, unique to this process and `http_port` (short:
/// a socket path has at most 107 bytes).
fn v2x_socket_path(http_port: u16) -> PathBuf {
    static NEXT: AtomicU64 = AtomicU64::new(0);
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    std::env::temp_dir().join(format!(
        "hil-sim-{}-{http_port}-{n}.v2x",
        std::process::id()
    ))
}

/// Starts QEMU with the firmware, the relays and the daemon in bridge mode (HTTP on
/// `http_port`, state in `state_dir`; the firmware's defmt log goes to
/// `state_dir/firmware.log`, decoded by `defmt-print` when it is on the PATH, else raw to
/// `state_dir/firmware.defmt`). The returned handle's `v2x` and `gnss` addresses are the
/// relays' UDP ports.
pub fn start(
    target: &FirmwareTarget,
    obu: &Path,
    state_dir: &Path,
    http_port: u16,
) -> Result<Daemon, String> {
    std::fs::create_dir_all(state_dir).map_err(|e| format!("{}: {e}", state_dir.display()))?;
    let [nmea_port, hmi_port] = [free_tcp_port()?, free_tcp_port()?];
    let v2x_path = v2x_socket_path(http_port);
    let _ = std::fs::remove_file(&v2x_path);
    let mut cmd = Command::new(&target.qemu);
    cmd.args(["-M", "netduinoplus2", "-nographic", "-monitor", "none"]);
    cmd.arg("-serial")
        .arg(format!("tcp:127.0.0.1:{nmea_port},server=on,wait=off"))
        .arg("-serial")
        .arg(format!("unix:{},server=on,wait=off", v2x_path.display()))
        .arg("-serial")
        .arg(format!("tcp:127.0.0.1:{hmi_port},server=on,wait=off"));
    cmd.args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(&target.elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    let qemu = cmd
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", target.qemu.display()))?;
    // Owned by the rig from here on, so that an error below stops QEMU (on drop).
    let mut rig = Rig {
        qemu,
        decoder: None,
        stop: Arc::new(AtomicBool::new(false)),
        relays: Vec::new(),
        log: state_dir.join("firmware.log"),
        nmea_relayed: Arc::new(AtomicU64::new(0)),
        radio: Arc::new(Mutex::new(RadioQueue::default())),
        v2x_socket: v2x_path.clone(),
    };
    rig.decoder = log_firmware(&mut rig.qemu, &target.elf, state_dir)?;
    wait_for_boot(&mut rig.qemu, rig.decoder.is_some(), state_dir)?;
    let nmea_link = connect("USART1 (NMEA)", &mut rig.qemu, || {
        let s = TcpStream::connect(("127.0.0.1", nmea_port))?;
        s.set_nodelay(true)?;
        Ok(s)
    })?;
    let v2x_link = connect("USART2 (V2X)", &mut rig.qemu, || {
        UnixStream::connect(&v2x_path)
    })?;
    let (gnss, nmea_relay) = nmea_relay(nmea_link, rig.stop.clone(), rig.nmea_relayed.clone())?;
    rig.relays.push(nmea_relay);
    let (v2x, v2x_relay) = radio_relay(v2x_link, rig.stop.clone(), rig.radio.clone())?;
    rig.relays.push(v2x_relay);
    let config = crate::daemon::config(state_dir, 0, http_port)?;
    let bridge = format!("tcp:127.0.0.1:{hmi_port}");
    let mut daemon = Daemon::start_bridge(obu, state_dir, &config, &bridge)?;
    daemon.v2x = v2x;
    daemon.gnss = gnss;
    daemon.rig = Some(rig);
    Ok(daemon)
}

/// Waits until the firmware has set up its USARTs (its boot line in `firmware.log`): QEMU
/// drops what reaches a USART before the firmware enables it, which would lose the first
/// fixes. Without the log decoder, waits a second.
fn wait_for_boot(qemu: &mut Child, logged: bool, dir: &Path) -> Result<(), String> {
    if !logged {
        std::thread::sleep(Duration::from_secs(1));
        return Ok(());
    }
    let deadline = Instant::now() + Duration::from_secs(10);
    let log = dir.join("firmware.log");
    loop {
        let text = std::fs::read_to_string(&log).unwrap_or_default();
        if text.contains("obu-firmware:") {
            return Ok(());
        }
        if let Ok(Some(status)) = qemu.try_wait() {
            return Err(format!("QEMU exited at boot: {status}"));
        }
        if Instant::now() >= deadline {
            return Err(format!(
                "the firmware did not boot within 10 s ({})",
                log.display()
            ));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// Sends QEMU's semihosting output (defmt frames) through `defmt-print` into
/// `dir/firmware.log`, or copies it raw into `dir/firmware.defmt` without the decoder.
fn log_firmware(qemu: &mut Child, elf: &Path, dir: &Path) -> Result<Option<Child>, String> {
    let mut out = qemu.stdout.take().ok_or("QEMU has no stdout")?;
    let create = |name: &str| {
        let p = dir.join(name);
        std::fs::File::create(&p).map_err(|e| format!("{}: {e}", p.display()))
    };
    let have_decoder = Command::new("defmt-print")
        .arg("--version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !have_decoder {
        let mut raw = create("firmware.defmt")?;
        std::thread::spawn(move || std::io::copy(&mut out, &mut raw));
        return Ok(None);
    }
    Command::new("defmt-print")
        .arg("-e")
        .arg(elf)
        .stdin(Stdio::from(out))
        .stdout(create("firmware.log")?)
        .stderr(Stdio::null())
        .spawn()
        .map(Some)
        .map_err(|e| format!("defmt-print: {e}"))
}

/// A UDP socket whose datagrams (NMEA epochs) go to `port` as they are, in a thread that
/// ends with `stop`; `relayed` counts the bytes. Returns the socket's address.
fn nmea_relay(
    mut port: TcpStream,
    stop: Arc<AtomicBool>,
    relayed: Arc<AtomicU64>,
) -> Result<(String, JoinHandle<()>), String> {
    let (sock, addr) = relay_socket()?;
    let handle = std::thread::spawn(move || {
        let mut buf = vec![0u8; 65_536];
        while !stop.load(Ordering::Relaxed) {
            let Ok(n) = sock.recv(&mut buf) else {
                continue;
            };
            // Counted before the write, which may wait while the firmware's link pauses: a
            // datagram being written is one the firmware still has to take.
            relayed.fetch_add(n as u64, Ordering::Relaxed);
            if port.write_all(&buf[..n]).is_err() {
                return;
            }
        }
    });
    Ok((addr, handle))
}

/// A UDP socket bound to the loopback interface with a 100 ms read timeout, and its address.
fn relay_socket() -> Result<(UdpSocket, String), String> {
    let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let addr = sock.local_addr().map_err(|e| e.to_string())?.to_string();
    sock.set_read_timeout(Some(RELAY_IDLE_WAIT))
        .map_err(|e| e.to_string())?;
    Ok((sock, addr))
}

/// How long a relay waits for a datagram when it has nothing to send.
const RELAY_IDLE_WAIT: Duration = Duration::from_millis(100);
/// How long the radio's relay waits for a datagram while frames wait for the link: the
/// link takes a ~400-byte frame in some 40 ms.
const RADIO_POLL: Duration = Duration::from_millis(4);

/// The radio chip's relay: a UDP socket whose datagrams go to `link` as `obu::link` frames
/// through `radio`'s receive buffers, in a thread that ends with `stop`. The link's send
/// buffer is set to the kernel's smallest, so frames wait in the radio's buffers, not in
/// the socket (see [`crate::radio`]). Returns the socket's address.
fn radio_relay(
    mut link: UnixStream,
    stop: Arc<AtomicBool>,
    radio: Arc<Mutex<RadioQueue>>,
) -> Result<(String, JoinHandle<()>), String> {
    let (sock, addr) = relay_socket()?;
    socket2::SockRef::from(&link)
        .set_send_buffer_size(1)
        .map_err(|e| format!("the V2X link's send buffer: {e}"))?;
    link.set_nonblocking(true).map_err(|e| e.to_string())?;
    let handle = std::thread::spawn(move || {
        let lock = || radio.lock().unwrap_or_else(|p| p.into_inner());
        let mut buf = vec![0u8; 65_536];
        let mut wire = vec![0u8; obu::link::encoded_len(buf.len())];
        while !stop.load(Ordering::Relaxed) {
            let wait = if lock().is_empty() {
                RELAY_IDLE_WAIT
            } else {
                RADIO_POLL
            };
            let _ = sock.set_read_timeout(Some(wait));
            if let Ok((n, from)) = sock.recv_from(&mut buf) {
                // The buffer is sized for the largest datagram: encoding cannot fail.
                if let Ok(len) = obu::link::encode(&buf[..n], &mut wire) {
                    lock().receive(from, wire[..len].to_vec());
                }
            }
            if lock().send(&mut link).is_err() {
                return;
            }
        }
    });
    Ok((addr, handle))
}

/// Waits until the firmware has taken every byte relayed to it so far: its status report
/// (every second, after a pass over both inputs) in its log shows "rx taken" at or above
/// what the NMEA relay wrote and what the radio had written once every frame it held had
/// left its buffers (sent or dropped). On a loaded host the firmware may still be working
/// through the drive when the bench is done sending; stopping it then would lose inputs
/// that were sent. Gives up after `limit`, with how far behind the firmware still is.
pub fn catch_up(rig: &Rig, limit: Duration) -> Result<(), String> {
    if rig.decoder.is_none() {
        // Without `defmt-print` the log is raw defmt: no report to read. Give the firmware
        // the time an idle host needs and say so.
        eprintln!("hil-sim: no defmt-print: cannot tell when the firmware caught up; waiting 3 s");
        std::thread::sleep(Duration::from_secs(3));
        return Ok(());
    }
    // Let the NMEA relay finish the datagram it is on (it may wait while the link pauses).
    std::thread::sleep(Duration::from_millis(200));
    let nmea_sent = rig.nmea_relayed.load(Ordering::Relaxed);
    rig.radio().set_mark();
    let start = Instant::now();
    loop {
        let v2x_sent = rig.radio().marked_written();
        let taken = std::fs::read_to_string(&rig.log)
            .ok()
            .and_then(|text| text.lines().rev().find_map(rx_taken));
        if let (Some([n, v]), Some(v2x_sent)) = (taken, v2x_sent) {
            if n >= nmea_sent && v >= v2x_sent {
                return Ok(());
            }
        }
        if start.elapsed() >= limit {
            let [n, v] = taken.unwrap_or([0, 0]);
            let v2x = v2x_sent.map_or_else(
                || "its radio still held frames from before".to_string(),
                |b| format!("it took {v} of {b} V2X bytes"),
            );
            return Err(format!(
                "the firmware had not caught up after {:.0} s: it took {n} of {nmea_sent} NMEA bytes; {v2x}",
                limit.as_secs_f64(),
            ));
        }
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The "rx taken N/M B" figures (NMEA, V2X) of a firmware status report line.
fn rx_taken(line: &str) -> Option<[u64; 2]> {
    let rest = line.split_once(" rx taken ")?.1;
    let (pair, _) = rest.split_once(' ')?;
    let (n, v) = pair.split_once('/')?;
    Some([n.parse().ok()?, v.parse().ok()?])
}

/// Why a scenario cannot run on the firmware as it is built, if it cannot: the image has
/// no CAN input and fixed alert settings (100 m warning distance, 9 s lead time).
pub fn unsupported(s: &crate::scenario::Scenario) -> Option<String> {
    if s.can_speed || s.drive.candump_file.is_some() {
        return Some("the firmware has no CAN input".into());
    }
    let d = crate::scenario::Settings::default();
    if s.settings.warning_distance_m != d.warning_distance_m
        || s.settings.lead_time_s != d.lead_time_s
    {
        return Some(format!(
            "the firmware's alert settings are fixed ({} m, {} s)",
            d.warning_distance_m, d.lead_time_s
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::rx_taken;

    #[test]
    fn reads_the_bytes_taken_from_a_status_report() {
        let line = "INFO  t=3000 ms v2x changed 2 unchanged 28 other 0 nmea errors 0 rx taken 2210/14093 B lost 0/0 stack 10580/24576 B";
        assert_eq!(rx_taken(line), Some([2210, 14093]));
        assert_eq!(rx_taken("WARN  v2x: dropped: CRC mismatch"), None);
        assert_eq!(rx_taken("INFO  rx taken 12/x B"), None);
    }
}
