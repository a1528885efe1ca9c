//! The daemon's TOML configuration. [`DEFAULT_TOML`] is the documented default file that
//! `obu --print-default-config` prints; every key may be left out.

mod http;

pub use http::Http;
use j2735::envelope::Psid;
use obu::alert::settings::{LEAD_TIME_S, WARNING_DISTANCE_M};
use obu::security::{Duplicates, RequiredSsp, SecurityConfig, SecurityProfile};
use serde::{Deserialize, Serialize};
use std::net::SocketAddr;
use std::path::PathBuf;

/// The default configuration, with every key documented. Safe on a laptop with no hardware:
/// everything listens on the loopback interface and no GNSS or CAN device is opened.
pub const DEFAULT_TOML: &str = r#"# OBU daemon configuration. Every key is optional; the values shown are the defaults.

[v2x]
# UDP address where MAP/TIM datagrams arrive: a raw UPER MessageFrame, an IEEE 1609.2
# envelope around one, or an RSU 4.1 text record (port 1516 is the RSU immediate-forward port).
bind = "127.0.0.1:1516"
# Largest datagram accepted, octets; longer ones are dropped and counted.
max_datagram = 4096

[gnss]
# "none", "nmea-file" (replay), "nmea-serial" (a tty already set to its baud rate),
# "ubx-serial" (the same, named for a u-blox receiver sending UBX NAV-PVT), "nmea-tcp"
# (connect to host:port), "nmea-udp" (listen), "gpsd" (TPV over TCP). Every source but gpsd
# reads NMEA 0183 and u-blox UBX alike, mixed or not, and skips (and counts) other binary.
source = "none"
# File or device path, host:port, or the UDP bind address, by source.
address = ""
# nmea-file: replay at the pace of the sentences' own time stamps (false: as fast as read).
realtime = true
# No fix for longer than this (milliseconds) shows "no GNSS". At 10 Hz, 700 ms is seven
# missed fixes, and the tablet still shows the loss within 1 s of the last fix.
stale_after_ms = 700

[gnss.uere]
# Without GST or UBX hAcc the fix's horizontal 1-sigma error is HDOP times the
# user-equivalent range error of its kind of solution (metres): stand-alone, SBAS/DGPS,
# RTK float, RTK fixed. Set your receiver's if you know them.
autonomous_m = 3.0
differential_m = 1.0
rtk_float_m = 0.3
rtk_fixed_m = 0.03

[speed]
# Vehicle speed: "gnss" (from the fixes), "socketcan" (a CAN interface) or "candump-file".
source = "gnss"
# CAN interface for "socketcan".
interface = "can0"
# candump -l log for "candump-file", replayed at its time stamps.
file = ""
# The speed signal, DBC conventions: frame id, start bit, length, byte order
# ("little_endian" = Intel, "big_endian" = Motorola), signedness, km/h = raw * scale + offset.
id = 0x1F0
start_bit = 0
length = 16
byte_order = "little_endian"
signed = false
scale = 0.01
offset = 0.0
# CAN speed older than this (milliseconds) falls back to GNSS speed.
stale_after_ms = 500

[http]
# Where the tablet app is served (in the vehicle: the Wi-Fi interface's address).
bind = "127.0.0.1:8080"
# Driver settings (warning distance, lead time, sound, units, theme), saved atomically.
# Beside it, under the same name with the extension ".pairing.json", the daemon keeps the
# pairing PIN it made (unless `pin` is set) and the paired tablets' sessions.
settings_file = "obu-settings.json"
# The pairing PIN (4 to 32 letters or digits). A tablet sends it once (POST /api/pair)
# and gets a session cookie; changing settings needs that cookie (401 without it); reads
# stay open. Leave out to have the daemon make a random 6-digit PIN on its first start,
# keep it in the pairing file and print it in its log at every start. Five wrong PINs in a
# row lock pairing for 30 s, each further wrong one for twice as long (at most 15 min).
# pin = "204816"
# The name the tablet uses for the unit, e.g. "obu.local". A request must name in its
# Host this name, localhost, or the address it reached; others get 421 (DNS rebinding).
# hostname = "obu.local"
# Host names or addresses accepted instead of those defaults (without a port; a port in
# the Host header must be the one the request reached). Empty: the defaults.
allowed_hosts = []
# Simultaneous event-stream clients. When all are taken, a new client takes the slot of
# the oldest stream of the address that holds the most.
max_clients = 64
# Open connections at most: keep it well under the process's open-file limit (ulimit -n).
# A new connection over it closes the one that has waited longest idle or in an unfinished
# request; event streams are never closed for it. Must exceed max_clients by 16 or more.
max_connections = 512
# Events kept to resume a client that reconnects with Last-Event-ID; a stream further
# behind is dropped.
event_buffer = 256
# Heartbeat on idle event streams, milliseconds.
heartbeat_ms = 1000
# One deadline for a whole request, milliseconds: from its first octet, its head and body
# must arrive and its answer be taken within this time, or the connection is closed.
request_timeout_ms = 5000
# A kept-alive connection without a request for this long is closed, milliseconds.
idle_timeout_ms = 30000
# An event stream whose client takes no data for this long once the socket buffers are
# full is dropped, milliseconds (so is one more than event_buffer events behind).
stalled_stream_ms = 5000

[alerts]
# Defaults of the driver settings (the tablet can change the first two): the minimum
# warning distance (20..=2000 m; the warning starts at max(this, speed x lead time)) and
# the lead time (2..=30 s).
warning_distance_m = 100.0
lead_time_s = 9.0
# Overspeed tolerance, km/h: above the limit in force plus this the speed turns red, and
# inside a zone the alert is urgent.
overspeed_tolerance_kmh = 5.0
# Deceleration a driver finds comfortable, m/s². Needing more to reach the zone limit by
# the zone start turns the speed red and the alert urgent (repeating tone).
comfortable_decel_mps2 = 2.5
# Time a lane change takes, seconds: still in the closed lane closer than this (at the
# current speed, and at least 30 m) makes "change lane" urgent.
lane_change_time_s = 5.0
# Time from a fix to the driver seeing it (link, Wi-Fi, rendering), milliseconds: every
# threshold looks ahead by one fix period plus this, so no warning comes a fix late.
display_latency_ms = 100
# During a GNSS outage the position is dead-reckoned along the matched lane (CAN speed,
# else the last GNSS speed) for this long, milliseconds; then "position lost".
dead_reckoning_ms = 5000

[lane]
# How the lane shown is decided: "filter" (the lane filter: a lateral track and a belief over
# the road's lanes, over many fixes; outliers rejected) or "per-fix" (each fix on its own
# with a 300 ms / 3-fix hysteresis, as deployed matchers do; for comparison).
method = "filter"
# Probability (percent, 50 to 99) the most probable lane needs before the tablet names it;
# below it the road and its zones stay shown ("lane closure ahead, keep left"). The
# "per-fix" method has its own fixed confidence rule and ignores it.
show_percent = 80

[time]
# Check GNSS time against this computer's system clock (NTP or RTC): farther apart than
# `max_offset_ms` shows "time unverified" and no zone is judged expired by its date. A
# system clock before 2024 (never set) is not used. The GPS week rollover (1024 weeks) is
# corrected with or without it.
check_system_clock = true
max_offset_ms = 10000

[bridge]
# Bridge mode (off unless `source` is set; `obu --bridge SOURCE` sets it too): the OBU core
# runs in the firmware, which sends its HmiState as `obu::link` frames (COBS + CRC-32,
# postcard payload) out of a serial port. The daemon then starts no V2X, GNSS or CAN input:
# it reads that stream and serves it to the tablet as usual. The link is one-way: settings
# changed on the tablet are saved and served, but do not reach the firmware.
#   "tcp:HOST:PORT"  connect to a TCP server, e.g. QEMU's emulated serial port
#                    (`-serial tcp:127.0.0.1:5003,server,nowait`); connects again after a
#                    refusal or a close, waiting 100 ms doubling to 2 s
#   "serial:PATH"    read a serial device, reopened after an error or end of input. The tty
#                    must be raw at the firmware's rate (115200 8N1), set beforehand with
#                    `stty -F PATH 115200 raw -echo cs8 -cstopb -parenb`, or set `baud` below
#                    to have the daemon run that command (GNU stty) before each open.
#                    A regular file (a capture) is read once.
# source = "tcp:127.0.0.1:5003"
# serial: baud rate for `stty` (leave out to use the tty as it is set).
# baud = 115200

[security]
# IEEE 1609.2. Signed MAP, TIM and PSM must verify along a certificate chain to one of the
# trust anchors and pass their message type's profile below ([security.map], [security.tim],
# [security.psm]; [security.spat] is ready for SPaT); a failure drops the frame, counted by
# reason under "security_errors". A byte-identical copy of an accepted frame (an RSU
# repeating what it was given signed once) costs a hash, no signature check, and is counted
# under "repeats".
# Drop unsigned MAP and TIM. Off: they are used but marked "unverified" on the tablet, and
# can never replace, refresh, cancel or evict a lane map or work zone that came verified.
require_signed = true
# Root and issuing CA certificates (COER files, as `roadside pki` writes them). With none,
# every signed frame is dropped ("chain does not reach a trust anchor") and the daemon
# warns at start.
trust_anchors = []
# A frame byte-identical in payload to one whose signature (same signer) was verified less
# than this long ago is taken without verifying again (every other check still applies);
# 0 verifies every frame. It spares roadsides that sign each transmission anew; a forger
# can at most keep a real zone alive this much longer.
reverify_ms = 1000

# One profile per message type. The defaults accept both ways deployed roadsides sign:
# each transmission anew (a generation time, no expiry time: relevant for past_window_ms)
# and once with an expiry time, repeated unchanged (relevant until the expiry time, if
# generation to expiry is at most max_lifetime_ms). Keys:
#   psid: the PSID the 1609.2 header must carry. Hexadecimal (0x8003, as a TOML number or a
#     string) is its p-encoded octets, the usual spelling; a decimal string ("131") is the
#     IEEE 1609.2 integer. TIM 0x8003 = 131, MAP 0xE0000017 = 2113687, PSM 0x27 = 39,
#     SPaT 0x8002 = 130.
#   ssp: service-specific permissions (hexadecimal, up to 16 octets) the signer certificate
#     must grant with the PSID, byte for byte (as your SCMS assigns them); "": any.
#   require_generation_time, require_expiry_time: refuse a frame without that time.
#   future_tolerance_ms: how far ahead of GNSS time a generation time may be, and how long
#     after its expiry time a frame is still taken.
#   past_window_ms: how long after its generation a frame without an expiry time is taken.
#   max_lifetime_ms: the longest generation-to-expiry lifetime accepted (7 days).
#   duplicates: "repeat" (a copy of an accepted frame is accepted and counted as a repeat)
#     or "replay" (it is dropped).
[security.map]
psid = 0xE0000017
ssp = ""
require_generation_time = true
require_expiry_time = false
future_tolerance_ms = 5000
past_window_ms = 30000
max_lifetime_ms = 604800000
duplicates = "repeat"

[security.tim]
psid = 0x8003
ssp = ""
require_generation_time = true
require_expiry_time = false
future_tolerance_ms = 5000
past_window_ms = 30000
max_lifetime_ms = 604800000
duplicates = "repeat"

[security.psm]
psid = 0x27
ssp = ""
require_generation_time = true
require_expiry_time = false
future_tolerance_ms = 5000
past_window_ms = 30000
max_lifetime_ms = 604800000
duplicates = "replay"

[security.spat]
psid = 0x8002
ssp = ""
require_generation_time = true
require_expiry_time = false
future_tolerance_ms = 5000
past_window_ms = 30000
max_lifetime_ms = 604800000
duplicates = "repeat"
"#;

/// The whole configuration.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// V2X input.
    pub v2x: V2x,
    /// GNSS input.
    pub gnss: Gnss,
    /// Vehicle speed input.
    pub speed: Speed,
    /// The tablet's HTTP server.
    pub http: Http,
    /// Alert defaults.
    pub alerts: Alerts,
    /// Lane localization.
    pub lane: Lane,
    /// GNSS time checks.
    pub time: Time,
    /// Bridge mode.
    pub bridge: Bridge,
    /// IEEE 1609.2 trust policy.
    pub security: Security,
}

/// `[security]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Security {
    /// Drop unsigned MAP and TIM.
    pub require_signed: bool,
    /// Trust anchor certificate files (COER).
    pub trust_anchors: Vec<PathBuf>,
    /// Re-verification period of repeated payloads, milliseconds (0: every frame).
    pub reverify_ms: u32,
    /// `[security.map]`.
    pub map: Profile,
    /// `[security.tim]`.
    pub tim: Profile,
    /// `[security.psm]`.
    pub psm: Profile,
    /// `[security.spat]`.
    pub spat: Profile,
}

/// `[security.map]`, `[security.tim]`, ...: one message type's security profile (see
/// [`obu::security::SecurityProfile`]).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Profile {
    /// The PSID, as written.
    pub psid: PsidText,
    /// SSP required with the PSID, hexadecimal ("": none).
    pub ssp: String,
    /// Refuse frames without a generation time.
    pub require_generation_time: bool,
    /// Refuse frames without an expiry time.
    pub require_expiry_time: bool,
    /// Future tolerance, milliseconds.
    pub future_tolerance_ms: u32,
    /// Past window without an expiry time, milliseconds.
    pub past_window_ms: u32,
    /// Longest generation-to-expiry lifetime, milliseconds.
    pub max_lifetime_ms: u64,
    /// `repeat` or `replay`.
    pub duplicates: String,
}

/// A PSID as a configuration file writes it: a TOML number (`0x8003`: the p-encoded octets,
/// the usual spelling) or a string (`"0x8003"` likewise, `"131"` the integer).
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(untagged)]
pub enum PsidText {
    /// A number: its p-encoded octets.
    Number(u32),
    /// Text: [`Psid::parse`].
    Text(String),
}

impl PsidText {
    /// The PSID; `None` when the text or number is no PSID.
    pub fn psid(&self) -> Option<Psid> {
        match self {
            Self::Number(n) => Psid::from_p_encoded_value(*n),
            Self::Text(t) => Psid::parse(t),
        }
    }
}

impl Profile {
    /// The core's profile; `Err` names the key that is wrong.
    fn core(&self, name: &str) -> Result<SecurityProfile, ConfigError> {
        let bad = |key: &str, what: &str| ConfigError(format!("security.{name}.{key}: {what}"));
        let psid = self.psid.psid().ok_or_else(|| {
            bad(
                "psid",
                "not a PSID: give its p-encoded octets in hexadecimal (0x8003 for TIM, \
                 0xE0000017 for MAP) or the IEEE 1609.2 integer as a decimal string (\"131\")",
            )
        })?;
        let ssp = required_ssp(&self.ssp).ok_or_else(|| {
            bad(
                "ssp",
                &format!("hexadecimal, at most {} octets", RequiredSsp::MAX),
            )
        })?;
        let duplicates = match self.duplicates.as_str() {
            "repeat" => Duplicates::Repeat,
            "replay" => Duplicates::Replay,
            _ => return Err(bad("duplicates", "\"repeat\" or \"replay\"")),
        };
        let profile = SecurityProfile {
            psid,
            ssp,
            require_generation_time: self.require_generation_time,
            require_expiry_time: self.require_expiry_time,
            future_tolerance_ms: self.future_tolerance_ms,
            past_window_ms: self.past_window_ms,
            max_lifetime_ms: self.max_lifetime_ms,
            duplicates,
        };
        if profile.is_valid() {
            Ok(profile)
        } else {
            Err(bad(
                "past_window_ms",
                "past_window_ms and max_lifetime_ms must be > 0",
            ))
        }
    }
}

impl Security {
    /// The core's settings; `Err` names the key that is wrong.
    pub fn core_config(&self) -> Result<SecurityConfig, ConfigError> {
        Ok(SecurityConfig {
            require_signed: self.require_signed,
            map: self.map.core("map")?,
            tim: self.tim.core("tim")?,
            psm: self.psm.core("psm")?,
            spat: self.spat.core("spat")?,
            reverify_ms: self.reverify_ms,
        })
    }
}

/// An SSP from its hexadecimal text; `None` when it is not hexadecimal or too long.
fn required_ssp(text: &str) -> Option<RequiredSsp> {
    let mut bytes = [0u8; RequiredSsp::MAX];
    let n = j2735::hex::decode_into(text.trim(), &mut bytes).ok()?;
    RequiredSsp::new(bytes.get(..n)?)
}

/// `[v2x]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct V2x {
    /// UDP bind address.
    pub bind: SocketAddr,
    /// Largest datagram, octets.
    pub max_datagram: usize,
}

/// GNSS source kinds.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum GnssSource {
    /// No GNSS.
    None,
    /// Replay an NMEA file.
    NmeaFile,
    /// Read NMEA from a serial device.
    NmeaSerial,
    /// Read a u-blox receiver's UBX (and NMEA) from a serial device.
    UbxSerial,
    /// Read NMEA from a TCP server.
    NmeaTcp,
    /// Receive NMEA datagrams.
    NmeaUdp,
    /// gpsd JSON (TPV) over TCP.
    Gpsd,
}

impl GnssSource {
    /// Every source with its name in `[gnss] source` (and `obu gnss-check --source`).
    pub const NAMES: [(GnssSource, &'static str); 7] = [
        (GnssSource::None, "none"),
        (GnssSource::NmeaFile, "nmea-file"),
        (GnssSource::NmeaSerial, "nmea-serial"),
        (GnssSource::UbxSerial, "ubx-serial"),
        (GnssSource::NmeaTcp, "nmea-tcp"),
        (GnssSource::NmeaUdp, "nmea-udp"),
        (GnssSource::Gpsd, "gpsd"),
    ];

    /// The source's name.
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(s, _)| *s == self)
            .map_or("none", |(_, n)| n)
    }

    /// The source of a name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::NAMES
            .iter()
            .find(|(_, n)| *n == name)
            .map(|(s, _)| *s)
    }
}

/// `[gnss]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Gnss {
    /// Source kind.
    pub source: GnssSource,
    /// Path or address, by source.
    pub address: String,
    /// Replay at the file's pace.
    pub realtime: bool,
    /// Stale after, milliseconds.
    pub stale_after_ms: u64,
    /// Range errors for the accuracy from HDOP.
    pub uere: Uere,
}

/// `[gnss.uere]`: user-equivalent range errors (1 sigma, metres) per kind of solution.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Uere {
    /// Stand-alone.
    pub autonomous_m: f32,
    /// SBAS or DGPS.
    pub differential_m: f32,
    /// RTK float.
    pub rtk_float_m: f32,
    /// RTK fixed.
    pub rtk_fixed_m: f32,
}

impl Uere {
    /// The core's accuracy model.
    pub fn model(&self) -> obu::input::nmea::AccuracyModel {
        obu::input::nmea::AccuracyModel {
            autonomous_m: self.autonomous_m,
            differential_m: self.differential_m,
            rtk_float_m: self.rtk_float_m,
            rtk_fixed_m: self.rtk_fixed_m,
        }
    }
}

/// Speed source kinds.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum SpeedSource {
    /// GNSS speed only.
    Gnss,
    /// A SocketCAN interface.
    Socketcan,
    /// A candump log.
    CandumpFile,
}

/// `[speed]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Speed {
    /// Source kind.
    pub source: SpeedSource,
    /// CAN interface.
    pub interface: String,
    /// candump log path.
    pub file: PathBuf,
    /// Frame id.
    pub id: u32,
    /// DBC start bit.
    pub start_bit: u16,
    /// Length, bits.
    pub length: u8,
    /// Byte order.
    pub byte_order: obu::input::can::ByteOrder,
    /// Two's complement.
    pub signed: bool,
    /// km/h per raw unit.
    pub scale: f32,
    /// km/h offset.
    pub offset: f32,
    /// Stale after, milliseconds.
    pub stale_after_ms: u64,
}

impl Speed {
    /// The signal as the core's CAN decoder takes it.
    pub fn signal(&self) -> obu::input::can::SpeedSignal {
        obu::input::can::SpeedSignal {
            id: self.id,
            start_bit: self.start_bit,
            length: self.length,
            byte_order: self.byte_order,
            signed: self.signed,
            scale: self.scale,
            offset: self.offset,
        }
    }
}

/// `[alerts]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Alerts {
    /// Default warning distance, metres.
    pub warning_distance_m: f32,
    /// Default lead time, seconds.
    pub lead_time_s: f32,
    /// Overspeed tolerance, km/h.
    pub overspeed_tolerance_kmh: f32,
    /// Comfortable deceleration, m/s².
    pub comfortable_decel_mps2: f32,
    /// Lane change time, seconds.
    pub lane_change_time_s: f32,
    /// Fix-to-screen latency, milliseconds.
    pub display_latency_ms: u64,
    /// Dead-reckoning horizon, milliseconds.
    pub dead_reckoning_ms: u64,
}

impl Alerts {
    /// These thresholds applied to the core's `base` configuration.
    pub fn apply(&self, base: &mut obu::alert::AlertConfig) {
        base.overspeed_tolerance_mps = self.overspeed_tolerance_kmh / 3.6;
        base.comfortable_decel_mps2 = self.comfortable_decel_mps2;
        base.lane_change_time_s = self.lane_change_time_s;
        base.display_latency_s = self.display_latency_ms as f32 / 1000.0;
        base.dead_reckoning = obu::time::Duration::from_millis(self.dead_reckoning_ms);
    }
}

/// `[lane]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Lane {
    /// How the lane shown is decided.
    pub method: LaneMethod,
    /// Probability (percent) the lane needs before it is named (the filter only).
    pub show_percent: u8,
}

/// `[lane] method`.
#[derive(Clone, Copy, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(rename_all = "kebab-case")]
pub enum LaneMethod {
    /// The lane filter.
    Filter,
    /// Each fix on its own, with hysteresis.
    PerFix,
}

impl Lane {
    /// This choice applied to the core's `base` configuration.
    pub fn apply(&self, base: &mut obu::alert::AlertConfig) {
        base.matcher.method = match self.method {
            LaneMethod::Filter => obu::matcher::LaneMethod::Filter,
            LaneMethod::PerFix => obu::matcher::LaneMethod::PerFix,
        };
        base.matcher.filter.show_percent = self.show_percent;
    }
}

/// `[time]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Time {
    /// Check GNSS time against the system clock.
    pub check_system_clock: bool,
    /// Largest offset still trusted, milliseconds.
    pub max_offset_ms: u64,
}

/// `[bridge]`.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Bridge {
    /// Where the firmware's states come from; `None`: the daemon runs the core itself.
    pub source: Option<BridgeSource>,
    /// Serial sources: the baud rate the daemon sets with `stty` before opening the device.
    pub baud: Option<u32>,
}

/// Where bridge mode reads the firmware's `HmiState` stream.
#[derive(Clone, Debug, Deserialize, Serialize, PartialEq, Eq)]
#[serde(try_from = "String", into = "String")]
pub enum BridgeSource {
    /// `tcp:HOST:PORT`: a TCP server to connect to (QEMU's emulated serial port).
    Tcp(String),
    /// `serial:PATH`: a serial device (or a FIFO, or a capture file).
    Serial(PathBuf),
}

impl std::str::FromStr for BridgeSource {
    type Err = ConfigError;

    fn from_str(s: &str) -> Result<Self, ConfigError> {
        let bad = |why: &str| ConfigError(format!("bridge source {s:?}: {why}"));
        if let Some(addr) = s.strip_prefix("tcp:") {
            let (host, port) = addr.rsplit_once(':').ok_or_else(|| bad("no :PORT"))?;
            let port_ok = port.parse::<u16>().is_ok_and(|p| p > 0);
            if host.is_empty() || !port_ok || addr.contains(char::is_whitespace) {
                return Err(bad("expected tcp:HOST:PORT"));
            }
            Ok(BridgeSource::Tcp(addr.to_owned()))
        } else if let Some(path) = s.strip_prefix("serial:") {
            if path.is_empty() || path.contains(char::is_whitespace) {
                return Err(bad("expected serial:PATH (without spaces)"));
            }
            Ok(BridgeSource::Serial(PathBuf::from(path)))
        } else {
            Err(bad("expected tcp:HOST:PORT or serial:PATH"))
        }
    }
}

impl TryFrom<String> for BridgeSource {
    type Error = ConfigError;

    fn try_from(s: String) -> Result<Self, ConfigError> {
        s.parse()
    }
}

impl From<BridgeSource> for String {
    fn from(source: BridgeSource) -> String {
        source.to_string()
    }
}

impl std::fmt::Display for BridgeSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BridgeSource::Tcp(addr) => write!(f, "tcp:{addr}"),
            BridgeSource::Serial(path) => write!(f, "serial:{}", path.display()),
        }
    }
}

/// Why a configuration was refused.
#[derive(Debug)]
pub struct ConfigError(pub String);

impl std::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ConfigError {}

/// Sets every key of `values` in `target`; a sub-table (`[security.tim]`) is merged key by
/// key in the same way, so that a file may set one key of it.
fn merge(target: &mut toml::Table, values: toml::Table) {
    for (key, value) in values {
        match (target.get_mut(&key), value) {
            (Some(toml::Value::Table(inner)), toml::Value::Table(value)) => merge(inner, value),
            (_, value) => {
                target.insert(key, value);
            }
        }
    }
}

impl Config {
    /// This configuration as a TOML file the daemon reads back as the same [`Config`].
    ///
    /// # Errors
    ///
    /// A value TOML cannot hold, such as a path that is not UTF-8.
    pub fn to_toml(&self) -> Result<String, ConfigError> {
        toml::to_string(self).map_err(|e| ConfigError(e.to_string()))
    }

    /// The defaults.
    pub fn default_config() -> Self {
        Self::parse("").unwrap_or_else(|e| unreachable!("the default configuration parses: {e}"))
    }

    /// Reads a configuration: `text` overrides the keys it has, the defaults fill the rest.
    pub fn parse(text: &str) -> Result<Self, ConfigError> {
        let mut merged: toml::Table =
            toml::from_str(DEFAULT_TOML).map_err(|e| ConfigError(e.to_string()))?;
        let user: toml::Table =
            toml::from_str(text).map_err(|e| ConfigError(format!("invalid TOML: {e}")))?;
        for (section, values) in user {
            let toml::Value::Table(values) = values else {
                return Err(ConfigError(format!("`{section}` must be a [section]")));
            };
            let Some(toml::Value::Table(target)) = merged.get_mut(&section) else {
                return Err(ConfigError(format!(
                    "unknown section [{section}]; see obu --print-default-config"
                )));
            };
            merge(target, values);
        }
        let config: Config = merged
            .try_into()
            .map_err(|e: toml::de::Error| ConfigError(e.to_string()))?;
        config.validate()?;
        Ok(config)
    }

    /// This configuration in bridge mode from `source` (the `--bridge` flag), checked again.
    pub fn with_bridge(mut self, source: BridgeSource) -> Result<Self, ConfigError> {
        self.bridge.source = Some(source);
        self.validate()?;
        Ok(self)
    }

    fn validate(&self) -> Result<(), ConfigError> {
        let bad = |what: &str| Err(ConfigError(what.to_string()));
        if !(64..=65_507).contains(&self.v2x.max_datagram) {
            return bad("v2x.max_datagram must be 64..=65507");
        }
        if self.gnss.source != GnssSource::None && self.gnss.address.is_empty() {
            return bad("gnss.address is needed for this gnss.source");
        }
        let u = self.gnss.uere;
        let range_errors = [
            u.autonomous_m,
            u.differential_m,
            u.rtk_float_m,
            u.rtk_fixed_m,
        ];
        if !range_errors
            .iter()
            .all(|m| m.is_finite() && (0.001..=100.0).contains(m))
        {
            return bad("gnss.uere values must lie between 0.001 and 100 metres");
        }
        if !(1..=64).contains(&self.speed.length) {
            return bad("speed.length must be 1..=64");
        }
        if !(50..=99).contains(&self.lane.show_percent) {
            return bad("lane.show_percent must be 50..=99");
        }
        self.http.validate()?;
        // The ranges the tablet's settings have: the configured defaults are the driver's
        // starting settings.
        for (range, value) in [
            (WARNING_DISTANCE_M, self.alerts.warning_distance_m),
            (LEAD_TIME_S, self.alerts.lead_time_s),
        ] {
            if let Err(e) = range.check(value) {
                return Err(ConfigError(format!("alerts.{e}")));
            }
        }
        let decel = self.alerts.comfortable_decel_mps2;
        if !(decel.is_finite() && (0.5..=10.0).contains(&decel)) {
            return bad("alerts.comfortable_decel_mps2 must be 0.5..=10");
        }
        let change = self.alerts.lane_change_time_s;
        if !(change.is_finite() && (0.0..=30.0).contains(&change)) {
            return bad("alerts.lane_change_time_s must be 0..=30");
        }
        if self.alerts.display_latency_ms > 1000 {
            return bad("alerts.display_latency_ms must be 0..=1000");
        }
        if self.alerts.dead_reckoning_ms > 60_000 {
            return bad("alerts.dead_reckoning_ms must be 0..=60000");
        }
        if self.time.max_offset_ms == 0 {
            return bad("time.max_offset_ms must be > 0");
        }
        let serial = matches!(self.bridge.source, Some(BridgeSource::Serial(_)));
        if self.bridge.baud.is_some() && !serial {
            return bad("bridge.baud needs a serial:PATH bridge.source");
        }
        if self.bridge.baud == Some(0) {
            return bad("bridge.baud must be > 0");
        }
        self.security.core_config()?;
        if self.security.trust_anchors.len() > obu::capacity::MAX_TRUST_ANCHORS {
            return bad("security.trust_anchors: at most 4 certificates");
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_safe_on_a_laptop() {
        let c = Config::default_config();
        assert!(c.v2x.bind.ip().is_loopback());
        assert!(c.http.bind.ip().is_loopback());
        assert_eq!(c.http.bind.port(), 8080);
        assert_eq!(c.gnss.source, GnssSource::None);
        assert_eq!(c.speed.source, SpeedSource::Gnss);
        assert_eq!(c.alerts.warning_distance_m, WARNING_DISTANCE_M.default);
        assert_eq!(c.alerts.lead_time_s, LEAD_TIME_S.default);
        assert_eq!(c.bridge.source, None, "normal mode");
    }

    #[test]
    fn alert_defaults_take_the_ranges_of_the_drivers_settings() {
        for (text, key) in [
            (
                "[alerts]\nwarning_distance_m = 19.5",
                "alerts.warning_distance_m",
            ),
            (
                "[alerts]\nwarning_distance_m = 2001.0",
                "alerts.warning_distance_m",
            ),
            ("[alerts]\nlead_time_s = 1.0", "alerts.lead_time_s"),
            ("[alerts]\nlead_time_s = 31.0", "alerts.lead_time_s"),
        ] {
            let e = Config::parse(text).expect_err(text).to_string();
            assert!(e.starts_with(key), "{text}: {e}");
        }
        let edges = "[alerts]\nwarning_distance_m = 20.0\nlead_time_s = 30.0";
        let c = Config::parse(edges).expect("the ranges' ends are allowed");
        assert_eq!(
            (c.alerts.warning_distance_m, c.alerts.lead_time_s),
            (20.0, 30.0)
        );
    }

    #[test]
    fn a_typed_config_written_as_toml_reads_back_the_same() {
        let mut c = Config::default_config();
        assert_eq!(Config::parse(&c.to_toml().unwrap()).unwrap(), c);
        c.http.bind = "127.0.0.1:0".parse().unwrap();
        c.alerts.lead_time_s = 5.0;
        c.lane.method = LaneMethod::PerFix;
        c.security.trust_anchors = vec![PathBuf::from("/tmp/a b/root.oer")];
        c.bridge.source = Some(BridgeSource::Tcp("127.0.0.1:4000".into()));
        let text = c.to_toml().unwrap();
        assert_eq!(Config::parse(&text).unwrap(), c, "{text}");
    }

    #[test]
    fn bridge_sources_parse_and_print_back() {
        let c = Config::parse("[bridge]\nsource = \"serial:/dev/ttyUSB0\"\nbaud = 115200").unwrap();
        let serial = BridgeSource::Serial("/dev/ttyUSB0".into());
        assert_eq!(c.bridge.source, Some(serial.clone()));
        assert_eq!(c.bridge.baud, Some(115_200));
        assert_eq!(serial.to_string(), "serial:/dev/ttyUSB0");
        let tcp: BridgeSource = "tcp:127.0.0.1:5003".parse().unwrap();
        assert_eq!(tcp, BridgeSource::Tcp("127.0.0.1:5003".into()));
        assert_eq!(tcp.to_string(), "tcp:127.0.0.1:5003");
        let host: BridgeSource = "tcp:qemu.local:5003".parse().unwrap();
        assert_eq!(host.to_string(), "tcp:qemu.local:5003");
        let c = Config::default_config().with_bridge(tcp.clone()).unwrap();
        assert_eq!(c.bridge.source, Some(tcp));
        for bad in [
            "",
            "tcp:",
            "tcp:host",
            "tcp::5003",
            "tcp:h:0",
            "tcp:h:99999",
            "serial:",
            "udp:h:1",
            "serial:/a b",
        ] {
            assert!(bad.parse::<BridgeSource>().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn bridge_mistakes_are_named() {
        let e = Config::parse("[bridge]\nsource = \"com1\"").unwrap_err();
        assert!(e.0.contains("tcp:HOST:PORT or serial:PATH"), "{e}");
        let e = Config::parse("[bridge]\nsource = \"tcp:h:1\"\nbaud = 9600").unwrap_err();
        assert!(e.0.contains("bridge.baud"), "{e}");
        let e = Config::parse("[bridge]\nport = 1").unwrap_err();
        assert!(e.0.contains("port"), "{e}");
        let serial =
            Config::parse("[bridge]\nsource = \"serial:/dev/ttyS0\"\nbaud = 9600").unwrap();
        let e = serial.with_bridge("tcp:h:1".parse().unwrap()).unwrap_err();
        assert!(
            e.0.contains("bridge.baud"),
            "a flag cannot leave a stray baud: {e}"
        );
    }

    #[test]
    fn a_file_overrides_some_keys() {
        let c = Config::parse("[http]\nbind = \"0.0.0.0:80\"\n[gnss]\nsource = \"nmea-udp\"\naddress = \"127.0.0.1:10110\"").unwrap();
        assert_eq!(c.http.bind.port(), 80);
        assert_eq!(c.http.max_clients, 64, "the rest stays default");
        assert_eq!(c.gnss.source, GnssSource::NmeaUdp);
    }

    #[test]
    fn mistakes_are_named() {
        let e = Config::parse("[htp]\nbind = \"x\"").unwrap_err();
        assert!(e.0.contains("unknown section [htp]"), "{e}");
        let e = Config::parse("[http]\nbnd = \"x\"").unwrap_err();
        assert!(e.0.contains("bnd"), "{e}");
        for (source, name) in GnssSource::NAMES {
            let text = format!("[gnss]\nsource = \"{name}\"\naddress = \"x\"");
            assert_eq!(Config::parse(&text).unwrap().gnss.source, source, "{name}");
        }
        let e = Config::parse("[gnss]\nsource = \"nmea-tcp\"").unwrap_err();
        assert!(e.0.contains("gnss.address"), "{e}");
        let e = Config::parse("[speed]\nbyte_order = \"middle\"").unwrap_err();
        assert!(e.0.contains("middle"), "{e}");
    }
}
