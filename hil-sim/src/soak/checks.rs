//! The soak's checks beyond growth: the daemon ran throughout and stopped on SIGTERM, no
//! tablet dropped or missed an event, every forged datagram was dropped for its reason and
//! none was taken, the V2X counters add up, the laps passed through their states, and the
//! hostile HTTP traffic was refused and cut as configured.

use super::clients::{Followed, Watch, LAP_STATES};
use super::http::HttpTally;
use super::verdict::Check;
use crate::attack::{status_group, DeviceCounts};
use serde::Serialize;

/// What the run left to judge.
#[derive(Debug, Clone, Serialize)]
pub struct Facts {
    /// Seconds the traffic ran.
    pub run_s: f64,
    /// When the daemon exited before the end, with its status.
    pub died: Option<String>,
    /// How it ended on SIGTERM (`None`: it did not within 5 s).
    pub stopped: Option<String>,
    /// Every client's record.
    pub clients: Vec<Followed>,
    /// The first client's watch of the stores and the zone states.
    pub watch: Watch,
    /// Laps the car completed.
    pub laps: u64,
    /// Forged datagrams sent per kind: (drop reason, sent).
    pub forged: Vec<(&'static str, u64)>,
    /// V2X datagrams sent, all senders.
    pub v2x_sent: u64,
    /// Of them, random octets (UPER is dense: most decode as some MessageFrame, now and
    /// then as an unsigned MAP or TIM, dropped under the forged unsigned ones' reason).
    pub random_sent: u64,
    /// Datagrams that could not be made or sent.
    pub send_failed: u64,
    /// The daemon's counters after the senders stopped.
    pub device: Option<DeviceCounts>,
    /// The hostile HTTP side's tally.
    pub http: HttpTally,
}

/// Every check of [`Facts`].
pub fn checks(f: &Facts) -> Vec<Check> {
    let mut out = vec![
        Check::new(
            "the daemon ran throughout",
            f.died.is_none(),
            f.died
                .clone()
                .unwrap_or_else(|| format!("alive for the {:.0} s of the run", f.run_s)),
        ),
        Check::new(
            "the daemon stopped on SIGTERM",
            f.stopped.as_deref() == Some("exit status: 0"),
            f.stopped
                .clone()
                .unwrap_or("still running 5 s after SIGTERM".into()),
        ),
    ];
    out.extend(client_checks(f));
    out.push(stores_check(&f.watch));
    out.push(laps_check(&f.watch, f.laps));
    let Some(d) = &f.device else {
        out.push(Check::new(
            "the daemon's counters",
            false,
            "/api/status did not answer at the end".into(),
        ));
        return out;
    };
    out.push(forged_check(f, d));
    out.push(total_check(f, d));
    out.extend(http_checks(&f.http, d));
    out
}

fn client_checks(f: &Facts) -> Vec<Check> {
    let dropped: Vec<String> = (f.clients.iter().enumerate())
        .filter_map(|(i, c)| c.error.as_ref().map(|e| format!("client {i}: {e}")))
        .collect();
    let events = f.clients.iter().map(|c| c.events);
    let (lo, hi) = (events.clone().min().unwrap_or(0), events.max().unwrap_or(0));
    let gaps: u64 = f.clients.iter().map(|c| c.gaps).sum();
    vec![
        Check::new(
            "no SSE client dropped",
            dropped.is_empty() && !f.clients.is_empty(),
            if dropped.is_empty() {
                format!("{} clients, {lo}-{hi} state events each", f.clients.len())
            } else {
                format!("{} dropped: {}", dropped.len(), dropped.join("; "))
            },
        ),
        Check::new(
            "every event sequence gap-free",
            gaps == 0,
            format!("{gaps} events missing or out of order over all clients"),
        ),
    ]
}

fn stores_check(w: &Watch) -> Check {
    let (ok, detail) = match (w.held, w.first_change) {
        (None, _) => (
            false,
            "the daemon never held the roadside's map and zone".into(),
        ),
        (Some(h), None) => (
            true,
            format!(
                "{} map(s), {} zone(s), stored {}x / {}x, cancelled {}x in every state",
                h.maps, h.zones, h.maps_updated, h.zones_updated, h.zones_cancelled
            ),
        ),
        (Some(h), Some(c)) => (
            false,
            format!("{} states changed from {h:?}, first {c:?}", w.changed),
        ),
    };
    Check::new(
        "lane map and zone store untouched by the forged datagrams",
        ok,
        detail,
    )
}

fn laps_check(w: &Watch, laps: u64) -> Check {
    // Each lap enters every state once; the first one also in a run under a lap long.
    let ok = w.entered.iter().all(|&n| n >= laps.max(1));
    let seen: Vec<String> = (LAP_STATES.iter().zip(w.entered))
        .map(|(s, n)| format!("{s} {n}x"))
        .collect();
    Check::new(
        "warning, in-zone and leaving every lap",
        ok,
        format!("{laps} laps completed; entered {}", seen.join(", ")),
    )
}

/// Every forged datagram is counted under its reason; a reason may count more only by
/// random datagrams that happened to decode as such a message (at most as many as were
/// sent). That none was taken is [`stores_check`]'s.
fn forged_check(f: &Facts, d: &DeviceCounts) -> Check {
    let mut ok = f.forged.iter().all(|&(_, n)| n > 0);
    let mut surplus = 0;
    let mut parts: Vec<String> = (f.forged.iter())
        .map(|&(reason, sent)| {
            let counted = d.get("security_errors", reason);
            ok &= counted >= sent;
            surplus += counted.saturating_sub(sent);
            format!("{counted} of {sent} under {reason:?}")
        })
        .collect();
    ok &= surplus <= f.random_sent;
    if surplus > 0 {
        parts.push(format!(
            "{surplus} more from the {} random datagrams",
            f.random_sent
        ));
    }
    Check::new(
        "every forged datagram dropped for its reason",
        ok,
        parts.join("; "),
    )
}

fn total_check(f: &Facts, d: &DeviceCounts) -> Check {
    let counted = d.v2x_total();
    let taken: u64 = ["MAP", "TIM"].iter().map(|m| d.get("messages", m)).sum();
    let nmea_errors: u64 = (d.counters["nmea_errors"].as_object())
        .map_or(0, |g| g.values().filter_map(|v| v.as_u64()).sum());
    let drops: u64 = ([
        "v2x_dropped",
        "envelope_errors",
        "decode_errors",
        "ingest_errors",
    ]
    .iter())
    .chain([status_group(obu::v2x::DropGroup::Security)].iter())
    .filter_map(|g| d.counters[*g].as_object())
    .flat_map(|g| g.values())
    .filter_map(|v| v.as_u64())
    .sum();
    Check::new(
        "V2X counters add up",
        counted == f.v2x_sent && f.send_failed == 0 && nmea_errors == 0,
        format!(
            "sent {} (+{} failed to send), counted {counted}: MAP+TIM taken {taken}, dropped \
             {drops}; NMEA errors {nmea_errors}",
            f.v2x_sent, f.send_failed
        ),
    )
}

fn http_checks(t: &HttpTally, d: &DeviceCounts) -> Vec<Check> {
    let rejected = |r: &str| d.get("http_rejected", r);
    let (deadline, not_paired, wrong_host) = (
        rejected("request deadline"),
        rejected("not paired"),
        rejected("wrong host"),
    );
    let errors = if t.errors.is_empty() {
        String::new()
    } else {
        format!("; {}", t.errors.join("; "))
    };
    vec![
        Check::new(
            "unauthenticated settings writes and foreign hosts refused",
            t.settings_writes > 0
                && t.settings_refused == t.settings_writes
                && not_paired == t.settings_writes
                && t.foreign_host > 0
                && t.foreign_refused == t.foreign_host
                && wrong_host == t.foreign_host,
            format!(
                "settings writes {} sent, {} answered 401, daemon counted {not_paired} 'not paired'; \
                 foreign Host {} sent, {} answered 421, counted {wrong_host} 'wrong host'{errors}",
                t.settings_writes, t.settings_refused, t.foreign_host, t.foreign_refused
            ),
        ),
        Check::new(
            "slow bodies cut at the request deadline",
            t.slow_cut > 0
                && t.slow_not_cut == 0
                && (t.slow_cut..=t.slow_opened).contains(&deadline),
            format!(
                "{} opened, {} cut after {} s, {} not cut; daemon counted {deadline} 'request deadline'",
                t.slow_opened,
                t.slow_cut,
                t.slow_cut_s.map_or("-".into(), |(a, b)| format!("{a:.1}-{b:.1}")),
                t.slow_not_cut
            ),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn facts(random_sent: u64) -> Facts {
        Facts {
            run_s: 60.0,
            died: None,
            stopped: None,
            clients: Vec::new(),
            watch: Watch::default(),
            laps: 1,
            forged: vec![("a", 10), ("b", 10)],
            v2x_sent: 100,
            random_sent,
            send_failed: 0,
            device: None,
            http: HttpTally::default(),
        }
    }

    fn counted(a: u64, b: u64) -> DeviceCounts {
        DeviceCounts {
            source: "/api/status",
            counters: serde_json::json!({ "security_errors": { "a": a, "b": b } }),
            every_input: true,
        }
    }

    #[test]
    fn every_forged_datagram_counted_a_surplus_only_from_random_ones() {
        assert!(forged_check(&facts(0), &counted(10, 10)).ok);
        // One random datagram decoded as such a message: allowed while random ones were sent.
        assert!(forged_check(&facts(5), &counted(11, 10)).ok);
        assert!(forged_check(&facts(5), &counted(13, 12)).ok);
        assert!(
            !forged_check(&facts(5), &counted(14, 12)).ok,
            "6 over 5 random"
        );
        assert!(
            !forged_check(&facts(0), &counted(11, 10)).ok,
            "no random sent"
        );
        // A forged datagram not counted under its reason fails, whatever the other counts.
        assert!(!forged_check(&facts(5), &counted(9, 11)).ok);
    }
}
