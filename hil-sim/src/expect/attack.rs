//! The checks of a run with an attacker: every forged datagram dropped and counted for its
//! reason ([`forged_dropped`]), and the real roadside's data kept throughout
//! ([`roadside_kept`]).

use super::{Record, RunFacts};
use crate::attack::{drop_reason, status_group, AttackFacts};
use obu::alert::HmiState;
use obu::security::Rejection;
use obu::v2x::DropReason;
use std::fmt;

/// The device's security drops other than `allowed` reasons, as `reason: n`.
fn security_drops(device: &crate::attack::DeviceCounts, allowed: &[DropReason]) -> Vec<String> {
    device.counters["security_errors"]
        .as_object()
        .map(|g| {
            g.iter()
                .filter(|(reason, _)| !allowed.iter().any(|a| a.as_str() == reason.as_str()))
                .map(|(reason, n)| format!("{reason}: {n}"))
                .collect()
        })
        .unwrap_or_default()
}

/// [`super::Expectation::DigestSignerTaken`].
pub(super) fn digest_signer_taken(max_unknown: u64, facts: &RunFacts) -> (bool, String) {
    let Some(device) = &facts.device else {
        return (false, "the device's counters could not be read".into());
    };
    let unknown = device.get(
        "security_errors",
        DropReason::from(Rejection::SignerUnknown).as_str(),
    );
    let allowed = [Rejection::NoTime, Rejection::SignerUnknown].map(DropReason::from);
    let drops = security_drops(device, &allowed);
    let ok = drops.is_empty() && unknown <= max_unknown;
    let mut detail =
        format!("{unknown} frames before the first whole certificate (at most {max_unknown})");
    if !drops.is_empty() {
        detail.push_str(&format!("; dropped: {}", drops.join(", ")));
    }
    (ok, detail)
}

/// [`super::Expectation::SignedOnceRepeated`].
pub(super) fn signed_once_repeated(min_share: f64, facts: &RunFacts) -> (bool, String) {
    let Some(device) = &facts.device else {
        return (false, "the device's counters could not be read".into());
    };
    let drops = security_drops(device, &[DropReason::from(Rejection::NoTime)]);
    let mut ok = drops.is_empty();
    let mut detail = match drops.is_empty() {
        true => "no signed frame dropped by the trust policy after GNSS time".to_string(),
        false => format!("dropped: {}", drops.join(", ")),
    };
    if device.every_input {
        let repeats: u64 = ["MAP", "TIM"]
            .iter()
            .map(|m| device.get("repeats", m))
            .sum();
        let taken: u64 = ["MAP", "TIM"]
            .iter()
            .map(|m| device.get("messages", m))
            .sum();
        let share = repeats as f64 / (repeats + taken).max(1) as f64;
        ok &= share >= min_share;
        detail.push_str(&format!(
            "; {repeats} repeats of {} MAP and TIM taken ({:.1} %, need {:.0} %)",
            repeats + taken,
            share * 100.0,
            min_share * 100.0
        ));
    } else {
        detail.push_str("; the firmware logs its drops only, not its repeats");
    }
    (ok, detail)
}

fn attack(facts: &RunFacts) -> Result<&AttackFacts, String> {
    facts
        .attack
        .as_ref()
        .ok_or_else(|| "the scenario has no [attacker]".to_string())
}

/// Every forged datagram is counted under `group` / `reason`: as many as were sent (on
/// loopback none is lost); where the device counts every input (the daemon), the V2X
/// counters also add up to the datagrams of the run (the roadside's and the attacker's),
/// so no forged datagram was taken and none was counted twice. The firmware behind its
/// emulated serial link (which can damage a frame when the host is loaded) must count each
/// forged frame it was delivered under the reason or under the link's own reasons (COBS,
/// CRC): at most as many under the reason as were delivered, and with the link's drops at
/// least as many (the link may not damage more than 2 % of the run's frames, or it is the
/// link being judged). Delivered are the forged frames sent less those the rig's radio
/// dropped with its receive buffers full ([`crate::radio`]).
pub(super) fn forged_dropped(group: &str, reason: &str, facts: &RunFacts) -> (bool, String) {
    let a = match attack(facts) {
        Ok(a) => a,
        Err(e) => return (false, e),
    };
    if drop_reason(group, reason).is_none() {
        let groups: Vec<&str> = DropReason::ALL
            .iter()
            .filter(|r| r.as_str() == reason)
            .map(|r| status_group(r.group()))
            .collect();
        return match groups.as_slice() {
            [] => (false, format!("{reason:?} is no drop reason of the OBU")),
            _ => (
                false,
                format!(
                    "{reason:?} is counted under {}, not {group}",
                    groups.join(", ")
                ),
            ),
        };
    }
    let Some(device) = &a.device else {
        let why = a.device_error.as_deref().unwrap_or("not read");
        return (false, format!("the device's counters: {why}"));
    };
    let sent = a.sent.sent;
    let counted = device.get(group, reason);
    let mut ok = sent > 0 && a.sent.failed == 0;
    let mut detail = format!(
        "{counted} of {sent} forged datagrams counted under {group} / {reason:?} ({})",
        device.source
    );
    if a.sent.failed > 0 {
        detail.push_str(&format!("; {} could not be sent", a.sent.failed));
    }
    if device.every_input {
        let (total, roadside) = (device.v2x_total(), a.roadside_sent);
        ok &= counted == sent && total == roadside + sent;
        detail.push_str(&format!(
            "; V2X inputs counted {total}, sent {roadside} by the roadside + {sent} forged"
        ));
    } else {
        detail.push_str("; the firmware logs its drops only, not the inputs it took");
        let link: u64 = device.counters["v2x_dropped"].as_object().map_or(0, |g| {
            g.values().filter_map(serde_json::Value::as_u64).sum()
        });
        let frames = a.roadside_sent + sent;
        // What the rig's radio dropped with its buffers full never reached the firmware.
        let delivered = sent.saturating_sub(a.radio_dropped);
        ok &= a.radio_dropped <= sent
            && counted <= delivered
            && counted + link >= delivered
            && link * 50 <= frames;
        if a.radio_dropped > 0 {
            detail.push_str(&format!(
                "; {} forged frames dropped by the rig's radio with its {} receive buffers full, \
                 {delivered} delivered",
                a.radio_dropped,
                crate::radio::QUEUE_FRAMES
            ));
        }
        if link > 0 {
            detail.push_str(&format!(
                "; {link} of the run's {frames} frames damaged on its serial link (overrun: \
                 COBS, CRC), counted there"
            ));
        }
    }
    (ok, detail)
}

/// What the device holds of the roadside's data: stores and the core's update counts.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Held {
    maps: u8,
    zones: u8,
    unverified: u8,
    maps_updated: u32,
    zones_updated: u32,
    zones_cancelled: u32,
}

impl Held {
    fn of(s: &HmiState) -> Self {
        Self {
            maps: s.maps,
            zones: s.zones,
            unverified: s.unverified,
            maps_updated: s.counters.maps_updated,
            zones_updated: s.counters.zones_updated,
            zones_cancelled: s.counters.zones_cancelled,
        }
    }
}

impl fmt::Display for Held {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} lane map(s) and {} zone(s), {} unverified (maps stored {}x, zones stored {}x, cancelled {}x)",
            self.maps,
            self.zones,
            self.unverified,
            self.maps_updated,
            self.zones_updated,
            self.zones_cancelled
        )
    }
}

/// From the attacker's first datagram to the end of the run, every state holds what the
/// last state before it held: the real roadside's lane maps and zones, all verified, none
/// stored, replaced or cancelled since (for a roadside that changes nothing during the
/// attack).
pub(super) fn roadside_kept(records: &[Record], facts: &RunFacts) -> (bool, String) {
    let a = match attack(facts) {
        Ok(a) => a,
        Err(e) => return (false, e),
    };
    let Some(t) = a.sent.first_sent_s else {
        return (false, "the attacker sent nothing".into());
    };
    let Some(before) = records.iter().take_while(|r| r.t_s < t).last() else {
        return (false, format!("no state before the attack at {t:.1} s"));
    };
    let held = Held::of(&before.state);
    // Zones the roadside cancelled before the attack are what is kept then (none shown).
    let nothing = held.zones == 0 && held.zones_cancelled == 0;
    if held.maps == 0 || nothing || held.unverified > 0 {
        return (
            false,
            format!(
                "before the attack at {t:.1} s the device held {held}: no verified zone to keep"
            ),
        );
    }
    let after: Vec<&Record> = records.iter().filter(|r| r.t_s >= t).collect();
    let changed: Vec<&&Record> = after
        .iter()
        .filter(|r| Held::of(&r.state) != held)
        .collect();
    let detail = match changed.first() {
        None => format!(
            "{} states from the first forged datagram (t = {t:.1} s) to the end hold {held}",
            after.len()
        ),
        Some(r) => format!(
            "{} of {} states from t = {t:.1} s differ from {held}; the first at t = {:.1} s: {}",
            changed.len(),
            after.len(),
            r.t_s,
            Held::of(&r.state)
        ),
    };
    (!after.is_empty() && changed.is_empty(), detail)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attack::DeviceCounts;
    use crate::roadside_bench::attacker::{AttackCounts, AttackKind};
    use serde_json::json;

    const CHAIN: &str = "1609.2: chain does not reach a trust anchor";

    fn facts(sent: u64, counters: serde_json::Value, every_input: bool) -> RunFacts {
        facts_with_radio(sent, 0, counters, every_input)
    }

    fn facts_with_radio(
        sent: u64,
        radio_dropped: u64,
        counters: serde_json::Value,
        every_input: bool,
    ) -> RunFacts {
        RunFacts {
            attack: Some(AttackFacts {
                kind: AttackKind::ForgedCancelUntrusted,
                sent: AttackCounts {
                    sent,
                    failed: 0,
                    first_sent_s: Some(3.0),
                    last_sent_s: Some(40.0),
                },
                roadside_sent: 100,
                radio_dropped,
                device: Some(DeviceCounts {
                    source: "/api/status",
                    counters,
                    every_input,
                }),
                device_error: None,
            }),
            ..RunFacts::default()
        }
    }

    #[test]
    fn forged_datagrams_must_all_be_counted_for_their_reason() {
        let status = |n: u64, tim: u64| json!({"messages": {"MAP": 50, "TIM": tim}, "security_errors": {CHAIN: n}});
        let (ok, detail) =
            forged_dropped("security_errors", CHAIN, &facts(40, status(40, 50), true));
        assert!(ok, "{detail}");
        assert!(
            detail.contains("40 of 40") && detail.contains("counted 140"),
            "{detail}"
        );
        // One forged TIM taken: counted under messages instead.
        let (ok, detail) =
            forged_dropped("security_errors", CHAIN, &facts(40, status(39, 51), true));
        assert!(!ok && detail.contains("39 of 40"), "{detail}");
        // One datagram of the run not counted at all.
        assert!(!forged_dropped("security_errors", CHAIN, &facts(40, status(40, 49), true)).0);
        // The firmware's log: drops only.
        let log = json!({"security_errors": {CHAIN: 40}});
        let (ok, detail) = forged_dropped("security_errors", CHAIN, &facts(40, log, false));
        assert!(ok && detail.contains("drops only"), "{detail}");
        // On the firmware a frame damaged on the serial link is counted there instead: the
        // forged ones under the reason and the link's drops must cover what was sent, with
        // the link damaging at most 2 % of the run's 140 frames.
        let fw = |reason: u64, crc: u64| {
            let log =
                json!({"security_errors": {CHAIN: reason}, "v2x_dropped": {"CRC mismatch": crc}});
            forged_dropped("security_errors", CHAIN, &facts(40, log, false))
        };
        let (ok, detail) = fw(39, 1);
        assert!(
            ok && detail.contains("1 of the run's 140 frames damaged"),
            "{detail}"
        );
        assert!(!fw(38, 1).0, "a forged frame neither counted nor damaged");
        assert!(!fw(38, 3).0, "the link damaged over 2 % of the frames");
        assert!(!fw(41, 0).0, "more counted than sent");
        // The rig's radio dropped 10 forged frames with its buffers full: 30 delivered.
        let radio = |reason: u64, crc: u64| {
            let log =
                json!({"security_errors": {CHAIN: reason}, "v2x_dropped": {"CRC mismatch": crc}});
            forged_dropped(
                "security_errors",
                CHAIN,
                &facts_with_radio(40, 10, log, false),
            )
        };
        let (ok, detail) = radio(30, 0);
        assert!(
            ok && detail.contains("10 forged frames dropped by the rig's radio"),
            "{detail}"
        );
        assert!(radio(29, 1).0, "one delivered frame damaged on the link");
        assert!(
            !radio(29, 0).0,
            "a delivered forged frame neither counted nor damaged"
        );
        assert!(!radio(31, 0).0, "more counted than delivered");
        assert!(!forged_dropped("security_errors", CHAIN, &facts(0, status(0, 100), true)).0);
    }

    #[test]
    fn the_reason_must_be_the_obus_and_in_its_group() {
        let f = facts(1, json!({}), true);
        let (ok, detail) = forged_dropped("security_errors", "chain untrusted", &f);
        assert!(!ok && detail.contains("no drop reason"), "{detail}");
        let (ok, detail) = forged_dropped("ingest_errors", CHAIN, &f);
        assert!(!ok && detail.contains("under security_errors"), "{detail}");
        let (ok, detail) = forged_dropped("security_errors", CHAIN, &RunFacts::default());
        assert!(!ok && detail.contains("no [attacker]"), "{detail}");
    }

    fn record(t_s: f64, zones: u8, cancelled: u32) -> Record {
        let mut state = HmiState {
            maps: 1,
            zones,
            ..HmiState::default()
        };
        state.counters.maps_updated = 1;
        state.counters.zones_updated = 2;
        state.counters.zones_cancelled = cancelled;
        Record {
            t_s,
            state,
            sample: None,
            true_lane: None,
            distance_m: None,
            zone_len_m: None,
            true_speed_mps: None,
            now_distance_m: None,
        }
    }

    #[test]
    fn the_roadsides_data_must_be_held_from_the_attack_on() {
        let f = facts(10, json!({}), true);
        let kept = [
            record(1.0, 0, 0),
            record(2.0, 2, 0),
            record(3.5, 2, 0),
            record(9.0, 2, 0),
        ];
        let (ok, detail) = roadside_kept(&kept, &f);
        assert!(ok && detail.starts_with("2 states"), "{detail}");
        let cancelled = [record(2.0, 2, 0), record(3.5, 2, 0), record(4.0, 0, 1)];
        let (ok, detail) = roadside_kept(&cancelled, &f);
        assert!(
            !ok && detail.contains("1 of 2") && detail.contains("t = 4.0"),
            "{detail}"
        );
        // Nothing to keep when the real zone was not there before the attack.
        let (ok, detail) = roadside_kept(&[record(2.0, 0, 0), record(3.5, 2, 0)], &f);
        assert!(!ok && detail.contains("no verified zone"), "{detail}");
        let mut unverified = record(2.0, 2, 0);
        unverified.state.unverified = 2;
        assert!(!roadside_kept(&[unverified, record(3.5, 2, 0)], &f).0);
    }
}
