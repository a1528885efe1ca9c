//! Counters of every input by kind and every drop by reason, shown by `GET /api/status`.
//!
//! Reasons come from closed sets (error kinds, message names, type paths of the schema), so
//! the table stays small whatever arrives.

use std::collections::BTreeMap;
use std::sync::Mutex;

/// Count groups.
pub mod group {
    /// Messages received, by type.
    pub const MESSAGES: &str = "messages";
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
    /// CAN frames refused, by reason.
    pub const CAN_ERRORS: &str = "can_errors";
    /// Bridge-mode link events (states, connects, disconnects, failures), by kind.
    pub const BRIDGE: &str = "bridge";
    /// Bridge-mode frames refused (framing, CRC, postcard payload), by reason.
    pub const BRIDGE_ERRORS: &str = "bridge_errors";
    /// HTTP requests refused, by reason.
    pub const HTTP_REJECTED: &str = "http_rejected";
    /// Event-stream clients, by what happened to them.
    pub const SSE_CLIENTS: &str = "sse_clients";
}

/// Thread-safe counters keyed by group and reason.
#[derive(Debug, Default)]
pub struct Counters {
    table: Mutex<BTreeMap<&'static str, BTreeMap<String, u64>>>,
}

impl Counters {
    /// Adds one to `group`/`reason`.
    pub fn add(&self, group: &'static str, reason: &str) {
        let mut t = self.table.lock().unwrap_or_else(|p| p.into_inner());
        let slot = t.entry(group).or_default();
        match slot.get_mut(reason) {
            Some(n) => *n += 1,
            None => {
                slot.insert(reason.to_owned(), 1);
            }
        }
    }

    /// One count.
    #[cfg(test)]
    pub fn get(&self, group: &str, reason: &str) -> u64 {
        let t = self.table.lock().unwrap_or_else(|p| p.into_inner());
        t.get(group)
            .and_then(|g| g.get(reason))
            .copied()
            .unwrap_or(0)
    }

    /// Every count as `{group: {reason: n}}`.
    pub fn snapshot(&self) -> serde_json::Value {
        let t = self.table.lock().unwrap_or_else(|p| p.into_inner());
        serde_json::to_value(&*t).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_by_group_and_reason() {
        let c = Counters::default();
        c.add(group::MESSAGES, "MAP");
        c.add(group::MESSAGES, "MAP");
        c.add(group::DECODE_ERRORS, "unexpected end");
        assert_eq!(c.get(group::MESSAGES, "MAP"), 2);
        assert_eq!(c.get(group::MESSAGES, "TIM"), 0);
        assert_eq!(c.snapshot()["decode_errors"]["unexpected end"], 1);
    }
}
