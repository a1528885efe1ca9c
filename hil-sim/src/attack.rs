//! The attack of a run (a scenario's `[attacker]`): the attacker's thread beside the
//! roadside ([`crate::roadside_bench::attacker`]), and what the device counted at the end,
//! so that the expectations can check that every forged datagram was dropped for its reason.
//!
//! The daemon's counters come from `GET /api/status` (`{group: {reason: n}}`, every V2X
//! input counted once over the V2X groups). The firmware's drops are not in the bridge's
//! status: it logs each one (`v2x: dropped: <reason>`, defmt over semihosting into
//! `firmware.log`), and [`firmware_counts`] tallies those lines into the same shape, drops
//! only.

use crate::roadside_bench::attacker::{AttackCounts, AttackKind, Attacker, AttackerSpec};
use obu::v2x::{DropGroup, DropReason};
use roadside::messages::WorkZone;
use roadside::road::Road;
use roadside::signer::RsuSigner;
use serde::Serialize;
use serde_json::{json, Value};
use std::net::SocketAddr;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// The groups of `/api/status` that count V2X inputs: each datagram once in one of them.
pub const V2X_GROUPS: &[&str] = &[
    "messages",
    "repeats",
    "v2x_dropped",
    "envelope_errors",
    "decode_errors",
    "ingest_errors",
    "security_errors",
];

/// The `/api/status` group the daemon shows a drop reason in.
pub const fn status_group(group: DropGroup) -> &'static str {
    match group {
        DropGroup::Datagram => "v2x_dropped",
        DropGroup::Envelope => "envelope_errors",
        DropGroup::Decode => "decode_errors",
        DropGroup::Ingest => "ingest_errors",
        DropGroup::Security => "security_errors",
    }
}

/// The drop reason counted as `name` under `group` (a name alone may be two groups':
/// "capacity exceeded" of the decoder and of the ingest).
pub fn drop_reason(group: &str, name: &str) -> Option<DropReason> {
    DropReason::ALL
        .iter()
        .copied()
        .find(|r| r.as_str() == name && status_group(r.group()) == group)
}

/// A running attacker.
#[derive(Debug)]
pub struct Attack {
    kind: AttackKind,
    stop: Arc<AtomicBool>,
    handle: JoinHandle<AttackCounts>,
    from: SocketAddr,
}

impl Attack {
    /// Starts the scenario's attacker against `to` (the device's V2X port), timed from
    /// `t0`; `genuine` is the real roadside's signer (see [`Attacker::new`]).
    ///
    /// # Errors
    ///
    /// The attacker's message (an invalid spec, a kind that needs a zone, no socket).
    pub fn start(
        spec: &AttackerSpec,
        road: &Road,
        zones: &[WorkZone],
        to: &str,
        t0: Instant,
        genuine: &Arc<RsuSigner>,
    ) -> Result<Self, String> {
        let attacker = Attacker::new(spec.kind, road, zones, genuine)?;
        let stop = Arc::new(AtomicBool::new(false));
        let (handle, from) =
            crate::roadside_bench::attacker::spawn(spec, attacker, to, t0, stop.clone())?;
        Ok(Self {
            kind: spec.kind,
            stop,
            handle,
            from,
        })
    }

    /// The address the attacker sends from.
    pub fn from(&self) -> SocketAddr {
        self.from
    }

    /// Stops the attacker and returns its kind and what it sent.
    ///
    /// # Errors
    ///
    /// When its thread panicked.
    pub fn finish(self) -> Result<(AttackKind, AttackCounts), String> {
        self.stop.store(true, Ordering::Relaxed);
        let counts = self
            .handle
            .join()
            .map_err(|_| "the attacker's thread panicked")?;
        Ok((self.kind, counts))
    }
}

/// What the device counted.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DeviceCounts {
    /// Where the counts come from: `/api/status` or `firmware.log`.
    pub source: &'static str,
    /// `{group: {reason: n}}` as `/api/status` shows it.
    pub counters: Value,
    /// True when every V2X input is in [`DeviceCounts::counters`] (the daemon's
    /// [`V2X_GROUPS`]); false for the firmware's log, which has the drops only.
    pub every_input: bool,
}

impl DeviceCounts {
    /// The count of `group` / `reason` (0 when absent).
    pub fn get(&self, group: &str, reason: &str) -> u64 {
        self.counters[group][reason].as_u64().unwrap_or(0)
    }

    /// Every V2X input counted (the sum over [`V2X_GROUPS`]).
    pub fn v2x_total(&self) -> u64 {
        V2X_GROUPS
            .iter()
            .filter_map(|g| self.counters[*g].as_object())
            .flat_map(|g| g.values())
            .filter_map(Value::as_u64)
            .sum()
    }
}

/// The daemon's counters from `GET /api/status` at `addr` (`host:port`).
///
/// # Errors
///
/// No answer, or an answer without counters.
pub fn daemon_counts(addr: &str) -> Result<DeviceCounts, String> {
    let body = crate::daemon::http_get(addr, "/api/status")?;
    let status: Value =
        serde_json::from_str(&body).map_err(|e| format!("/api/status: {e}: {body:?}"))?;
    let counters = status
        .get("counters")
        .filter(|c| c.is_object())
        .ok_or("/api/status has no counters")?;
    Ok(DeviceCounts {
        source: "/api/status",
        counters: counters.clone(),
        every_input: true,
    })
}

/// How long the daemon may take to count the last datagrams of a run (an ARM daemon under
/// qemu-user on a loaded host is the slowest).
pub const COUNTS_SETTLE: Duration = Duration::from_secs(5);

/// The daemon's counters once it has counted `sent` V2X datagrams: reads `/api/status`
/// every 50 ms until [`DeviceCounts::v2x_total`] reaches `sent` or [`COUNTS_SETTLE`] has
/// passed, and returns the last counters read either way (the checks judge them). A datagram still in
/// the daemon's socket when the senders stop is counted a moment later, longer on a
/// loaded host or under qemu-user: reading once, at a fixed delay, would judge the host's
/// pace, not the daemon.
///
/// # Errors
///
/// As [`daemon_counts`], when the last read failed.
pub fn daemon_counts_settled(addr: &str, sent: u64) -> Result<DeviceCounts, String> {
    let deadline = Instant::now() + COUNTS_SETTLE;
    loop {
        let counts = daemon_counts(addr);
        let settled = counts.as_ref().is_ok_and(|c| c.v2x_total() >= sent);
        if settled || Instant::now() >= deadline {
            return counts;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// The firmware's drops, from its decoded log (`v2x: dropped: <reason>` lines; a reason
/// this build does not name is counted under `v2x_dropped` / `unknown`).
///
/// # Errors
///
/// The log is missing (no `defmt-print` on the PATH leaves only the raw defmt stream,
/// which this does not decode).
pub fn firmware_counts(log: &Path) -> Result<DeviceCounts, String> {
    let text = std::fs::read_to_string(log).map_err(|e| {
        format!(
            "{}: {e} (the firmware's drops are read from its log, decoded by defmt-print)",
            log.display()
        )
    })?;
    Ok(DeviceCounts {
        source: "firmware.log",
        counters: tally_drops(&text),
        every_input: false,
    })
}

/// `{group: {reason: n}}` of the `v2x: dropped: <reason>` lines of a firmware log. The
/// log names the reason only: a name two groups share goes to the first of
/// [`DropReason::ALL`] (the decoder's "capacity exceeded" before the ingest's).
pub fn tally_drops(log: &str) -> Value {
    const MARK: &str = "v2x: dropped: ";
    let mut out = json!({});
    for line in log.lines() {
        let Some(i) = line.find(MARK) else {
            continue;
        };
        let name = line[i + MARK.len()..].trim();
        let first = DropReason::ALL.iter().find(|r| r.as_str() == name);
        let (group, reason) = match first {
            Some(r) => (status_group(r.group()), r.as_str()),
            None => ("v2x_dropped", "unknown"),
        };
        let n = &mut out[group][reason];
        *n = json!(n.as_u64().unwrap_or(0) + 1);
    }
    out
}

/// The facts of a run's attack the expectations check.
#[derive(Debug, Clone, Serialize)]
pub struct AttackFacts {
    /// What the attacker sent.
    pub kind: AttackKind,
    /// How many, and when.
    pub sent: AttackCounts,
    /// Datagrams the real roadside sent over the run.
    pub roadside_sent: u64,
    /// Forged datagrams the firmware rig's radio dropped with its receive buffers full,
    /// before the serial link (0 for the daemon, which takes datagrams directly).
    pub radio_dropped: u64,
    /// What the device counted at the end.
    pub device: Option<DeviceCounts>,
    /// Why the device's counts could not be read, if they could not.
    pub device_error: Option<String>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use j2735::uper::DecodeErrorKind;
    use obu::ingest::IngestError;
    use obu::security::Rejection;

    #[test]
    fn a_firmware_log_tallies_into_status_groups() {
        let log = "INFO  obu-firmware: state 8920 B\n\
                   WARN  v2x: dropped: 1609.2: no GNSS time to check against\n\
                   WARN  v2x: dropped: 1609.2: chain does not reach a trust anchor\n\
                   WARN  v2x: dropped: 1609.2: chain does not reach a trust anchor\n\
                   WARN  v2x: dropped: CRC mismatch\n\
                   WARN  v2x: dropped: something new\n\
                   INFO  t=10000 ms v2x changed 2 unchanged 200 other 0\n";
        let c = DeviceCounts {
            source: "firmware.log",
            counters: tally_drops(log),
            every_input: false,
        };
        let chain = DropReason::from(Rejection::ChainUntrusted).as_str();
        assert_eq!(c.get("security_errors", chain), 2);
        assert_eq!(
            c.get(
                "security_errors",
                DropReason::from(Rejection::NoTime).as_str()
            ),
            1
        );
        assert_eq!(c.get("v2x_dropped", "CRC mismatch"), 1);
        assert_eq!(c.get("v2x_dropped", "unknown"), 1);
        assert_eq!(c.get("messages", "TIM"), 0);
    }

    #[test]
    fn the_v2x_total_sums_the_v2x_groups_only() {
        let c = DeviceCounts {
            source: "/api/status",
            counters: json!({
                "messages": {"MAP": 10, "TIM": 9},
                "security_errors": {"unsigned (signatures required)": 5},
                "nmea_errors": {"bad checksum": 7},
                "sse_clients": {"connected": 1}
            }),
            every_input: true,
        };
        assert_eq!(c.v2x_total(), 24);
    }

    #[test]
    fn every_reason_is_found_by_its_group_and_name() {
        for &r in &DropReason::ALL {
            let group = status_group(r.group());
            assert!(V2X_GROUPS.contains(&group));
            assert_eq!(drop_reason(group, r.as_str()), Some(r));
        }
        assert_eq!(drop_reason("security_errors", "no such reason"), None);
        let capacity = DropReason::from(DecodeErrorKind::CapacityExceeded).as_str();
        assert_eq!(
            capacity,
            DropReason::from(IngestError::CapacityExceeded).as_str(),
            "one name, two groups"
        );
        assert_eq!(
            drop_reason("ingest_errors", capacity),
            Some(DropReason::from(IngestError::CapacityExceeded))
        );
    }
}
