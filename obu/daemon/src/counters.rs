//! Counters of every input by kind and every drop by reason, shown by `GET /api/status`.
//!
//! Every reason is a `&'static str` from a closed set (error kinds' `as_str()`, the codec's
//! message short names, fixed texts): no input text can become a key, so the table stays
//! small whatever arrives. V2X outcomes are counted in the core's fixed arrays
//! ([`V2xCounters`], indexed by [`DropReason`]) and shown by their groups.

use obu::v2x::{DropGroup, DropReason, V2xCounters, V2xOutcome};
use std::collections::BTreeMap;
use std::sync::Mutex;

/// Count groups.
pub mod group {
    /// Messages the core took (MAP, TIM, or others it does not use), by the codec's short
    /// name; a MAP or TIM the core refused is counted under [`INGEST_ERRORS`] instead, so
    /// that every datagram is counted once over the V2X groups.
    pub const MESSAGES: &str = "messages";
    /// Signed messages that were byte-identical repeats of accepted ones (an RSU repeating
    /// what it was given signed once), by the codec's short name: checked for a hash, no
    /// signature verification; they refreshed what they carry.
    pub const REPEATS: &str = "repeats";
    /// UPER decode failures, by reason.
    pub const DECODE_ERRORS: &str = "decode_errors";
    /// Envelope (1609.2, RSU text) failures, by reason.
    pub const ENVELOPE_ERRORS: &str = "envelope_errors";
    /// Messages the core refused, by reason.
    pub const INGEST_ERRORS: &str = "ingest_errors";
    /// Datagrams dropped before decoding, by reason.
    pub const V2X_DROPPED: &str = "v2x_dropped";
    /// NMEA sentences refused, by reason.
    pub const NMEA_ERRORS: &str = "nmea_errors";
    /// GNSS input events (fixes, reconnects), by kind.
    pub const GNSS: &str = "gnss";
    /// GNSS epochs without a fix, by the reason ([`obu::input::nmea::NoFix`]).
    pub const GNSS_NO_FIX: &str = "gnss_no_fix";
    /// GNSS sentences and UBX messages read, by type.
    pub const GNSS_MESSAGES: &str = "gnss_messages";
    /// CAN frames refused, by reason.
    pub const CAN_ERRORS: &str = "can_errors";
    /// Bridge-mode link events (states, connects, disconnects, failures), by kind.
    pub const BRIDGE: &str = "bridge";
    /// Bridge-mode frames refused (framing, CRC, postcard payload), by reason.
    pub const BRIDGE_ERRORS: &str = "bridge_errors";
    /// Signed or unsigned MAP/TIM refused by the IEEE 1609.2 trust policy, by reason.
    pub const SECURITY_ERRORS: &str = "security_errors";
    /// HTTP requests and connections refused or cut, by reason (wrong host, request
    /// deadline, shed over the connection cap, not paired, wrong PIN, ...).
    pub const HTTP_REJECTED: &str = "http_rejected";
    /// HTTP connections closed in the normal course (idle keep-alive), by kind.
    pub const HTTP_CONNECTIONS: &str = "http_connections";
    /// Event-stream clients, by what happened to them.
    pub const SSE_CLIENTS: &str = "sse_clients";
    /// Tablets paired.
    pub const PAIRING: &str = "pairing";
}

/// The group of `/api/status` a V2X drop reason is shown in.
pub const fn drop_group(group: DropGroup) -> &'static str {
    match group {
        DropGroup::Datagram => group::V2X_DROPPED,
        DropGroup::Envelope => group::ENVELOPE_ERRORS,
        DropGroup::Decode => group::DECODE_ERRORS,
        DropGroup::Ingest => group::INGEST_ERRORS,
        DropGroup::Security => group::SECURITY_ERRORS,
    }
}

/// The counter name of a `messageId`: the codec's short name, or `unknown`.
pub fn message_name(id: u16) -> &'static str {
    j2735::msg::message_frame::message_short_name(id).unwrap_or("unknown")
}

#[derive(Debug, Default)]
struct Table {
    by_reason: BTreeMap<&'static str, BTreeMap<&'static str, u64>>,
    v2x: V2xCounters,
}

/// Thread-safe counters keyed by group and reason.
#[derive(Debug, Default)]
pub struct Counters {
    table: Mutex<Table>,
}

impl Counters {
    fn lock(&self) -> std::sync::MutexGuard<'_, Table> {
        self.table.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Adds one to `group`/`reason`.
    pub fn add(&self, group: &'static str, reason: &'static str) {
        self.add_n(group, reason, 1);
    }

    /// Adds `n` to `group`/`reason`.
    pub fn add_n(&self, group: &'static str, reason: &'static str, n: u64) {
        *self
            .lock()
            .by_reason
            .entry(group)
            .or_default()
            .entry(reason)
            .or_default() += n;
    }

    /// Counts one V2X input by its outcome: a message taken (MAP, TIM or other) under
    /// `messages` by its short name, a drop under its reason's group.
    pub fn v2x(&self, outcome: V2xOutcome) {
        match outcome {
            V2xOutcome::Changed(id) | V2xOutcome::Unchanged(id) | V2xOutcome::Other(id) => {
                self.add(group::MESSAGES, message_name(id));
            }
            V2xOutcome::Repeat(id) => self.add(group::REPEATS, message_name(id)),
            V2xOutcome::Dropped(_) => {}
        }
        self.lock().v2x.record(outcome);
    }

    /// One count.
    #[cfg(test)]
    pub fn get(&self, group: &str, reason: &str) -> u64 {
        self.snapshot()[group][reason].as_u64().unwrap_or(0)
    }

    /// Every non-zero count as `{group: {reason: n}}`.
    pub fn snapshot(&self) -> serde_json::Value {
        let t = self.lock();
        let mut all = t.by_reason.clone();
        for &r in &DropReason::ALL {
            let n = t.v2x.dropped(r);
            if n > 0 {
                let g = all.entry(drop_group(r.group())).or_default();
                *g.entry(r.as_str()).or_default() += u64::from(n);
            }
        }
        serde_json::to_value(&all).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_by_group_and_reason() {
        let c = Counters::default();
        c.v2x(V2xOutcome::Changed(18));
        c.v2x(V2xOutcome::Unchanged(18));
        c.v2x(V2xOutcome::Other(19));
        c.v2x(V2xOutcome::Other(4000));
        c.v2x(V2xOutcome::Repeat(31));
        c.v2x(V2xOutcome::Repeat(31));
        c.v2x(V2xOutcome::Dropped(DropReason::from(
            j2735::uper::DecodeErrorKind::UnexpectedEnd,
        )));
        c.v2x(V2xOutcome::Dropped(DropReason::Datagram(
            obu::v2x::DatagramReason::TooLarge,
        )));
        c.add(group::NMEA_ERRORS, "bad checksum");
        assert_eq!(c.get(group::MESSAGES, "MAP"), 2);
        assert_eq!(c.get(group::MESSAGES, "SPAT"), 1);
        assert_eq!(c.get(group::MESSAGES, "unknown"), 1);
        assert_eq!(c.get(group::REPEATS, "TIM"), 2);
        assert_eq!(c.get(group::MESSAGES, "TIM"), 0);
        assert_eq!(c.get(group::MESSAGES, "TIM"), 0);
        let s = c.snapshot();
        assert_eq!(s["decode_errors"]["unexpected end"], 1);
        assert_eq!(s["v2x_dropped"]["datagram too large"], 1);
        assert_eq!(s["nmea_errors"]["bad checksum"], 1);
        assert!(
            s["ingest_errors"].is_null(),
            "zero counts are not shown: {s}"
        );
    }
}
