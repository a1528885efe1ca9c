//! `[http]`: the tablet's HTTP server, its pairing PIN, the Host names it answers to, and
//! the limits that keep it answering under a hostile Wi-Fi client (connection cap,
//! request deadline, idle timeout, stalled event streams).

use super::ConfigError;
use serde::{Deserialize, Serialize};
use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

/// `[http]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Http {
    /// Bind address.
    pub bind: SocketAddr,
    /// Settings file.
    pub settings_file: PathBuf,
    /// The configured pairing PIN; `None`: made and kept in the pairing file.
    pub pin: Option<String>,
    /// The unit's host name for the tablet.
    pub hostname: Option<String>,
    /// Host names or addresses accepted instead of the defaults; empty: the defaults.
    pub allowed_hosts: Vec<String>,
    /// Event-stream clients at most.
    pub max_clients: usize,
    /// Open connections at most.
    pub max_connections: usize,
    /// Events kept for resume.
    pub event_buffer: usize,
    /// Heartbeat period, milliseconds.
    pub heartbeat_ms: u64,
    /// Whole-request deadline, milliseconds.
    pub request_timeout_ms: u64,
    /// Keep-alive idle timeout, milliseconds.
    pub idle_timeout_ms: u64,
    /// Stalled event stream timeout, milliseconds.
    pub stalled_stream_ms: u64,
}

/// The most open connections one may configure (each is a file descriptor).
const MAX_CONNECTIONS: usize = 65_536;

/// The longest any of the timeouts may be: an hour.
const MAX_TIMEOUT_MS: u64 = 3_600_000;

impl Http {
    /// The pairing file: the settings file's name with the extension `.pairing.json`.
    pub fn pairing_file(&self) -> PathBuf {
        self.settings_file.with_extension("pairing.json")
    }

    /// The request deadline.
    pub fn request_timeout(&self) -> Duration {
        Duration::from_millis(self.request_timeout_ms)
    }

    /// The keep-alive idle timeout.
    pub fn idle_timeout(&self) -> Duration {
        Duration::from_millis(self.idle_timeout_ms)
    }

    /// The stalled event stream timeout.
    pub fn stalled_stream(&self) -> Duration {
        Duration::from_millis(self.stalled_stream_ms)
    }

    /// Checks the values; the error names the key.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let bad = |what: &str| Err(ConfigError(what.to_string()));
        if self.max_clients == 0 || self.event_buffer == 0 {
            return bad("http.max_clients and http.event_buffer must be > 0");
        }
        if self.max_connections < self.max_clients.saturating_add(16) {
            return bad("http.max_connections must be at least http.max_clients + 16");
        }
        if self.max_connections > MAX_CONNECTIONS {
            return Err(ConfigError(format!(
                "http.max_connections must be at most {MAX_CONNECTIONS}"
            )));
        }
        for (key, ms) in [
            ("request_timeout_ms", self.request_timeout_ms),
            ("idle_timeout_ms", self.idle_timeout_ms),
            ("stalled_stream_ms", self.stalled_stream_ms),
            ("heartbeat_ms", self.heartbeat_ms),
        ] {
            if !(1..=MAX_TIMEOUT_MS).contains(&ms) {
                return Err(ConfigError(format!(
                    "http.{key} must be 1..={MAX_TIMEOUT_MS}"
                )));
            }
        }
        if self
            .pin
            .as_deref()
            .is_some_and(|p| !crate::pairing::valid_pin(p))
        {
            return bad("http.pin must be 4 to 32 letters or digits");
        }
        let names = self.hostname.iter().chain(&self.allowed_hosts);
        for name in names {
            if !crate::host::valid_host_entry(name) {
                return Err(ConfigError(format!(
                    "http host {name:?}: expected a host name or an IP address, without a port"
                )));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::Config;

    #[test]
    fn defaults_leave_room_and_derive_the_pairing_file() {
        let c = Config::default_config().http;
        assert_eq!(c.pin, None, "made on first start");
        assert!(c.allowed_hosts.is_empty() && c.hostname.is_none());
        assert!(c.max_connections >= c.max_clients + 16);
        assert!(
            c.max_connections < 1024 - 64,
            "fits the usual open-file limit"
        );
        assert_eq!(c.request_timeout_ms, 5000);
        assert_eq!(c.idle_timeout_ms, 30_000);
        assert_eq!(
            c.pairing_file(),
            std::path::PathBuf::from("obu-settings.pairing.json")
        );
    }

    #[test]
    fn link_keys_are_read_and_checked() {
        let c = Config::parse(
            "[http]\npin = \"a1b2c3\"\nhostname = \"obu.local\"\nallowed_hosts = [\"10.0.0.1\", \"obu\"]\nmax_connections = 100\nidle_timeout_ms = 900",
        )
        .unwrap();
        assert_eq!(c.http.pin.as_deref(), Some("a1b2c3"));
        assert_eq!(c.http.hostname.as_deref(), Some("obu.local"));
        assert_eq!(c.http.allowed_hosts, ["10.0.0.1", "obu"]);
        assert_eq!(c.http.idle_timeout().as_millis(), 900);
        for (text, key) in [
            ("pin = \"12\"", "http.pin"),
            ("pin = \"12 34\"", "http.pin"),
            ("max_connections = 70", "http.max_connections"),
            ("max_connections = 1000000000", "at most 65536"),
            ("request_timeout_ms = 0", "http.request_timeout_ms"),
            ("stalled_stream_ms = 99999999", "http.stalled_stream_ms"),
            ("hostname = \"obu.local:8080\"", "obu.local:8080"),
            ("allowed_hosts = [\"evil example\"]", "evil example"),
            ("allowed_hosts = [\"\"]", "without a port"),
        ] {
            let e = Config::parse(&format!("[http]\n{text}")).unwrap_err();
            assert!(e.0.contains(key), "{text}: {e}");
        }
    }
}
