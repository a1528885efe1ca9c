//! The OBU firmware in QEMU as the device under test, in place of the Linux daemon.
//!
//! The rig: QEMU's `netduinoplus2` (STM32F405) runs the firmware image with its three
//! USARTs exposed as TCP server ports (USART1 NMEA in, USART2 V2X frames in, USART3
//! `HmiState` out). The `obu` daemon runs in bridge mode on USART3's port and serves the
//! tablet app and its event stream as it does for its own core. Two relays take what the
//! bench sends to a daemon (UDP datagrams: NMEA epochs and V2X MessageFrames) to the
//! firmware's ports: NMEA as it is, each V2X datagram as one `obu::link` frame (COBS +
//! CRC-32), as a radio chip beside the microcontroller would forward it. The bench then
//! drives the rig through the same [`Daemon`] handle as the daemon alone.

use crate::daemon::Daemon;
use crate::rig::Rig;
use std::io::Write;
use std::net::{TcpListener, TcpStream, UdpSocket};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
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

/// Connects to QEMU's server socket at `port`, retrying while the emulator starts.
fn connect(port: u16, qemu: &mut Child) -> Result<TcpStream, String> {
    let deadline = Instant::now() + Duration::from_secs(10);
    loop {
        match TcpStream::connect(("127.0.0.1", port)) {
            Ok(s) => {
                s.set_nodelay(true).map_err(|e| e.to_string())?;
                return Ok(s);
            }
            Err(e) if Instant::now() >= deadline => {
                return Err(format!("QEMU's serial port {port}: {e}"));
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
    let ports = [free_tcp_port()?, free_tcp_port()?, free_tcp_port()?];
    let mut cmd = Command::new(&target.qemu);
    cmd.args(["-M", "netduinoplus2", "-nographic", "-monitor", "none"]);
    for p in ports {
        cmd.arg("-serial")
            .arg(format!("tcp:127.0.0.1:{p},server=on,wait=off"));
    }
    cmd.args(["-semihosting-config", "enable=on,target=native", "-kernel"])
        .arg(&target.elf)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit());
    let mut qemu = cmd
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", target.qemu.display()))?;
    let decoder = log_firmware(&mut qemu, &target.elf, state_dir)?;
    wait_for_boot(&mut qemu, decoder.is_some(), state_dir)?;
    let nmea_port = connect(ports[0], &mut qemu)?;
    let v2x_port = connect(ports[1], &mut qemu)?;
    let stop = Arc::new(AtomicBool::new(false));
    let relayed = Arc::new([AtomicU64::new(0), AtomicU64::new(0)]);
    let (gnss, nmea_relay) = relay(nmea_port, false, stop.clone(), relayed.clone())?;
    let (v2x, v2x_relay) = relay(v2x_port, true, stop.clone(), relayed.clone())?;
    let config = crate::daemon::config(state_dir, 0, http_port, "")?;
    let bridge = format!("tcp:127.0.0.1:{}", ports[2]);
    let rig = Rig {
        qemu,
        decoder,
        stop,
        relays: vec![nmea_relay, v2x_relay],
        log: state_dir.join("firmware.log"),
        relayed,
    };
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

/// A UDP socket whose datagrams go to `port` (each as one link frame when `framed`), in a
/// thread that ends with `stop`. Returns the socket's address.
fn relay(
    mut port: TcpStream,
    framed: bool,
    stop: Arc<AtomicBool>,
    relayed: Arc<[AtomicU64; 2]>,
) -> Result<(String, JoinHandle<()>), String> {
    let sock = UdpSocket::bind("127.0.0.1:0").map_err(|e| e.to_string())?;
    let addr = sock.local_addr().map_err(|e| e.to_string())?.to_string();
    sock.set_read_timeout(Some(Duration::from_millis(100)))
        .map_err(|e| e.to_string())?;
    let handle = std::thread::spawn(move || {
        let mut buf = vec![0u8; 65_536];
        let mut wire = vec![0u8; obu::link::encoded_len(buf.len())];
        while !stop.load(Ordering::Relaxed) {
            let Ok(n) = sock.recv(&mut buf) else {
                continue;
            };
            let bytes = if framed {
                match obu::link::encode(&buf[..n], &mut wire) {
                    Ok(len) => &wire[..len],
                    Err(_) => continue,
                }
            } else {
                &buf[..n]
            };
            // Counted before the write, which may wait while the firmware's link pauses: a
            // datagram being written is one the firmware still has to take.
            relayed[usize::from(framed)].fetch_add(bytes.len() as u64, Ordering::Relaxed);
            if port.write_all(bytes).is_err() {
                return;
            }
        }
    });
    Ok((addr, handle))
}

/// Waits until the firmware has taken every byte relayed to it so far: its status report
/// (every second, after a pass over both inputs) in its log shows "rx taken" at or above what
/// the relays wrote. The link pauses rather than drops when the firmware is busy, so on a
/// loaded host the firmware may still be working through the drive when the bench is done
/// sending; stopping it then would lose inputs that were sent. Gives up after `limit`, with
/// how far behind the firmware still is.
pub fn catch_up(rig: &Rig, limit: Duration) -> Result<(), String> {
    if rig.decoder.is_none() {
        // Without `defmt-print` the log is raw defmt: no report to read. Give the firmware
        // the time an idle host needs and say so.
        eprintln!("hil-sim: no defmt-print: cannot tell when the firmware caught up; waiting 3 s");
        std::thread::sleep(Duration::from_secs(3));
        return Ok(());
    }
    // Let a relay finish the datagram it is on (it may wait while the link pauses).
    std::thread::sleep(Duration::from_millis(200));
    let sent = [0, 1].map(|i| rig.relayed[i].load(Ordering::Relaxed));
    let start = Instant::now();
    loop {
        let taken = std::fs::read_to_string(&rig.log)
            .ok()
            .and_then(|text| text.lines().rev().find_map(rx_taken));
        if taken.is_some_and(|t| t[0] >= sent[0] && t[1] >= sent[1]) {
            return Ok(());
        }
        if start.elapsed() >= limit {
            let [n, v] = taken.unwrap_or([0, 0]);
            return Err(format!(
                "the firmware had not caught up after {:.0} s: it took {n} of {} NMEA bytes and {v} of {} V2X bytes",
                limit.as_secs_f64(),
                sent[0],
                sent[1]
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
