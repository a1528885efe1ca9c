//! The real `obu` daemon as a child process: started with a configuration written for
//! the bench, its addresses read from its first line, stopped with SIGTERM semantics on
//! drop (kill, then reap).

use obu_daemon::config::{Config, GnssSource};
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{Ipv4Addr, SocketAddr, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

/// The `obu` executable: `$OBU_BIN`, else `obu` beside this executable, else on the PATH.
pub fn find_obu() -> PathBuf {
    if let Some(p) = std::env::var_os("OBU_BIN") {
        return PathBuf::from(p);
    }
    std::env::current_exe()
        .ok()
        .and_then(|exe| exe.parent().map(|d| d.join("obu")))
        .filter(|p| p.is_file())
        .unwrap_or_else(|| PathBuf::from("obu"))
}

/// The daemon's configuration for the bench: the daemon's defaults with V2X on any loopback
/// port, NMEA over UDP on `gnss_port` (0: any, named on the daemon's first line), HTTP on
/// `http_port` (0: any), settings in `state_dir` and the bench PKI's trust anchors (written
/// into `state_dir`; signatures required, the product default). Callers change what else
/// they need on the returned value.
///
/// # Errors
///
/// The file system's error writing the anchors.
pub fn config(state_dir: &Path, gnss_port: u16, http_port: u16) -> Result<Config, String> {
    let loopback = |port| SocketAddr::from((Ipv4Addr::LOCALHOST, port));
    let mut c = Config::default_config();
    c.v2x.bind = loopback(0);
    c.gnss.source = GnssSource::NmeaUdp;
    c.gnss.address = loopback(gnss_port).to_string();
    c.http.bind = loopback(http_port);
    c.http.settings_file = state_dir.join("obu-settings.json");
    c.security.trust_anchors = crate::bench_pki::write_anchors(state_dir)?;
    Ok(c)
}

/// The body of a GET to the daemon at `addr` (`host:port`; HTTP/1.1, `Connection: close`).
///
/// # Errors
///
/// The connection's error.
pub fn http_get(addr: &str, path: &str) -> Result<String, String> {
    let mut s = TcpStream::connect(addr).map_err(|e| format!("{addr}: {e}"))?;
    s.set_read_timeout(Some(Duration::from_secs(5)))
        .map_err(|e| e.to_string())?;
    write!(
        s,
        "GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .map_err(|e| e.to_string())?;
    let mut text = String::new();
    s.read_to_string(&mut text).map_err(|e| e.to_string())?;
    Ok(text
        .split_once("\r\n\r\n")
        .map_or(String::new(), |(_, b)| b.to_string()))
}

/// A running daemon.
#[derive(Debug)]
pub struct Daemon {
    /// The process.
    pub child: Child,
    /// Base URL of the tablet app, e.g. `http://127.0.0.1:8080`.
    pub http: String,
    /// UDP address of the V2X input.
    pub v2x: String,
    /// UDP address of the NMEA input.
    pub gnss: String,
    /// The emulated firmware behind a daemon in bridge mode (the firmware rig starts it).
    pub rig: Option<crate::rig::Rig>,
}

impl Daemon {
    /// Writes `config` to `state_dir/obu.toml`, starts `obu` with it and reads its
    /// first line (`obu: http://ADDR v2x udp ADDR gnss udp ADDR`, the GNSS input being NMEA
    /// over UDP).
    pub fn start(obu: &Path, state_dir: &Path, config: &Config) -> Result<Self, String> {
        let (child, words) = spawn(obu, state_dir, config, &[])?;
        match words.as_slice() {
            [_, http, v, u, v2x, g, u2, gnss]
                if v == "v2x" && u == "udp" && g == "gnss" && u2 == "udp" =>
            {
                Ok(Self {
                    http: http.clone(),
                    v2x: v2x.clone(),
                    gnss: gnss.clone(),
                    child,
                    rig: None,
                })
            }
            _ => Err(refuse(child, &words)),
        }
    }

    /// As [`Daemon::start`], in bridge mode: the daemon shows the `HmiState` stream read
    /// from `source` (`tcp:HOST:PORT`); its first line is `obu: http://ADDR bridge SOURCE`.
    /// The V2X and GNSS addresses are left empty for the caller.
    pub fn start_bridge(
        obu: &Path,
        state_dir: &Path,
        config: &Config,
        source: &str,
    ) -> Result<Self, String> {
        let (child, words) = spawn(obu, state_dir, config, &["--bridge", source])?;
        match words.as_slice() {
            [_, http, b, ..] if b == "bridge" => Ok(Self {
                http: http.clone(),
                v2x: String::new(),
                gnss: String::new(),
                child,
                rig: None,
            }),
            _ => Err(refuse(child, &words)),
        }
    }

    /// `host:port` of the HTTP server.
    pub fn http_addr(&self) -> &str {
        self.http.trim_start_matches("http://")
    }

    /// CPU time the process used so far (user + system), seconds, from `/proc`.
    pub fn cpu_seconds(&self) -> Option<f64> {
        let stat = std::fs::read_to_string(format!("/proc/{}/stat", self.child.id())).ok()?;
        // Fields after the command name (which may hold spaces) close with ')'.
        let rest = &stat[stat.rfind(')')? + 2..];
        let fields: Vec<&str> = rest.split_whitespace().collect();
        let (utime, stime): (f64, f64) =
            (fields.get(11)?.parse().ok()?, fields.get(12)?.parse().ok()?);
        Some((utime + stime) / clock_ticks_per_second())
    }
}

impl Drop for Daemon {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Writes the config, starts `obu --config FILE ARGS...` and splits its first line into
/// words (the first being `obu:`).
fn spawn(
    obu: &Path,
    state_dir: &Path,
    config: &Config,
    args: &[&str],
) -> Result<(Child, Vec<String>), String> {
    std::fs::create_dir_all(state_dir).map_err(|e| format!("{}: {e}", state_dir.display()))?;
    let text = config
        .to_toml()
        .map_err(|e| format!("the daemon's configuration: {e}"))?;
    let config = state_dir.join("obu.toml");
    std::fs::write(&config, text).map_err(|e| format!("{}: {e}", config.display()))?;
    let mut child = Command::new(obu)
        .arg("--config")
        .arg(&config)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .map_err(|e| {
            format!(
                "cannot start {}: {e} (build it, or set OBU_BIN)",
                obu.display()
            )
        })?;
    let stdout = child.stdout.take().ok_or("no stdout")?;
    let mut line = String::new();
    BufReader::new(stdout)
        .read_line(&mut line)
        .map_err(|e| format!("reading the daemon's first line: {e}"))?;
    let words: Vec<String> = line.split_whitespace().map(str::to_string).collect();
    if words.first().map(String::as_str) != Some("obu:") {
        return Err(refuse(child, &words));
    }
    Ok((child, words))
}

/// Stops a daemon whose first line was not the expected one; the error to report.
fn refuse(mut child: Child, words: &[String]) -> String {
    let _ = child.kill();
    let _ = child.wait();
    format!(
        "the daemon printed {:?}, not its addresses",
        words.join(" ")
    )
}

/// `getconf CLK_TCK` (100 on Linux unless told otherwise).
fn clock_ticks_per_second() -> f64 {
    Command::new("getconf")
        .arg("CLK_TCK")
        .output()
        .ok()
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .and_then(|s| s.trim().parse().ok())
        .unwrap_or(100.0)
}

#[cfg(test)]
mod tests {
    use obu_daemon::config::Config;

    #[test]
    fn the_bench_config_is_read_back_by_the_daemon_with_the_anchors_written() {
        let dir = std::env::temp_dir().join(format!("hil-sim-config-{}", std::process::id()));
        let mut c = super::config(&dir, 10110, 8080).unwrap();
        c.http.pin = Some("123456".into());
        c.alerts.lead_time_s = 5.0;
        let back = Config::parse(&c.to_toml().unwrap()).unwrap();
        assert_eq!(back, c);
        assert_eq!(back.http.bind.to_string(), "127.0.0.1:8080");
        assert_eq!(back.gnss.address, "127.0.0.1:10110");
        assert_eq!(back.security.trust_anchors.len(), 2);
        assert!(back.security.trust_anchors.iter().all(|p| p.is_file()));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
