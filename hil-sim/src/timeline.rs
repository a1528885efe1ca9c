//! Compares two runs of one scenario state by state: the firmware in QEMU against the
//! Linux daemon, fed the same scenario.
//!
//! The two runs are joined on the fix: for every fix count `k` that both reached, the last
//! state each showed after its `k`-th fix. Those are compared field by field, except the
//! clock (`time_ms`, each device's own) and the counters (the two inputs count datagrams
//! differently); numbers agree when within [`TOLERANCE`] (the firmware computes in the
//! microcontroller's floating point and `libm`, the daemon in the host's).
//!
//! The roadside broadcasts on its own clock, so a new MAP or TIM may reach one device just
//! before its `k`-th fix and the other just after: the fix then met different inputs. Such
//! fixes (the roadside version, the count of maps and zones stored, replaced or cancelled,
//! in the first state after fix `k` or in the last one before it, differs between the runs)
//! are counted apart, not compared; at most [`MAX_SKIPPED_PER_CHANGE`] per roadside change
//! are allowed, and beyond them the fixes that the measured difference of the two runs'
//! roadside -> screen delays explains ([`delay_fixes`]): the firmware's V2X crosses QEMU's
//! emulated UART one octet at a time and, on a loaded host, shows a change hundreds of
//! milliseconds after the daemon, so the fixes in between meet an older input there. That
//! delay is the rig's, reported with each run; what this comparison judges is the cores.
//!
//! The core is not memoryless: the lane filter's belief (its confidence) after fix `k`
//! follows from every fix since the MAP arrived, so a run that met the MAP one fix earlier
//! still shows a different confidence for a fix or two after the skipped ones. Right after
//! skipped fixes, up to [`MAX_SETTLING`] fixes in a row may still differ ("settling"); the
//! first one that agrees ends that, and from there every fix is compared again. A
//! disagreement that outlasts the settling fixes is a mismatch.

use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;

/// Largest difference between two numbers that still agree (metres, m/s, percent).
pub const TOLERANCE: f64 = 0.05;

/// Fixes allowed to meet different roadside inputs per change of what the roadside sends.
pub const MAX_SKIPPED_PER_CHANGE: usize = 2;

/// Fixes right after skipped ones that may still differ (the lane filter's history; see
/// the module docs): 0.3 s at 10 Hz.
pub const MAX_SETTLING: usize = 3;

/// Fields left out of the comparison.
const IGNORED: &[&str] = &["time_ms", "counters"];

/// What the comparison found.
#[derive(Debug, Clone, Serialize)]
pub struct TimelineMatch {
    /// Fix counts both runs showed a state for.
    pub fixes_compared: usize,
    /// Of those, the ones whose states agree.
    pub fixes_matching: usize,
    /// Fixes both runs reached but met different roadside inputs (not compared).
    pub fixes_skipped: usize,
    /// Fixes right after skipped ones that still differed (not compared; at most
    /// [`MAX_SETTLING`] in a row).
    pub fixes_settling: usize,
    /// Changes of the roadside version over the daemon's run (the first MAP/TIM included).
    pub roadside_changes: usize,
    /// Fixes explained by the firmware's slower delivery of the roadside's changes
    /// ([`delay_fixes`]; 0 until the caller sets it).
    pub delay_fixes: usize,
    /// The first disagreements: fix count, field path, daemon value, firmware value.
    pub mismatches: Vec<(u64, String, Value, Value)>,
    /// Largest difference of `distance_m` over the compared fixes, metres.
    pub max_distance_diff_m: f64,
}

impl TimelineMatch {
    /// True when every compared fix agrees, there was something to compare and no more
    /// fixes were left out than the roadside's changes and their delivery explain.
    pub fn matches(&self) -> bool {
        self.fixes_compared > 0
            && self.fixes_matching == self.fixes_compared
            && self.fixes_skipped <= self.allowed_skipped()
    }

    /// Fixes that may meet different roadside inputs: [`MAX_SKIPPED_PER_CHANGE`] per
    /// roadside change, plus [`TimelineMatch::delay_fixes`].
    pub fn allowed_skipped(&self) -> usize {
        MAX_SKIPPED_PER_CHANGE * self.roadside_changes.max(1) + self.delay_fixes
    }
}

/// The fixes that a slower delivery of the roadside's changes explains: for each change,
/// the receiver's epochs ([`crate::drive::EPOCH_S`]) within the difference of the two
/// runs' roadside -> screen delays, rounded up, summed. Lists of different lengths (a
/// change one run never showed) explain none.
pub fn delay_fixes(daemon_ms: &[f64], firmware_ms: &[f64]) -> usize {
    if daemon_ms.len() != firmware_ms.len() {
        return 0;
    }
    let epoch_ms = crate::drive::EPOCH_S * 1000.0;
    (daemon_ms.iter().zip(firmware_ms))
        .map(|(d, f)| (f - d).abs() / epoch_ms)
        .filter(|epochs| epochs.is_finite())
        .map(|epochs| epochs.ceil() as usize)
        .sum()
}

/// What a run showed for one fix count.
#[derive(Debug, Clone)]
pub struct FixStates {
    /// The roadside version the fix met (in the first state after it).
    pub met: u64,
    /// The last state before the next fix.
    pub last: Value,
}

/// The states of each fix count, from a run's `states.jsonl` lines. The run's final fix has
/// no next fix: what follows it depends on how long each rig kept running after the drive
/// (the GNSS timeout, dead reckoning), so its first state stands for it.
pub fn by_fix(states_jsonl: &str) -> BTreeMap<u64, FixStates> {
    let mut out: BTreeMap<u64, FixStates> = BTreeMap::new();
    let mut final_first: Option<(u64, Value)> = None;
    for line in states_jsonl.lines() {
        let Ok(v) = serde_json::from_str::<Value>(line) else {
            continue;
        };
        let state = &v["state"];
        if let Some(k) = state["counters"]["fixes"].as_u64().filter(|&k| k > 0) {
            let met = roadside_version(state);
            if final_first.as_ref().is_none_or(|(f, _)| k > *f) {
                final_first = Some((k, state.clone()));
            }
            out.entry(k)
                .and_modify(|f| f.last = state.clone())
                .or_insert(FixStates {
                    met,
                    last: state.clone(),
                });
        }
    }
    if let Some((k, first)) = final_first {
        if let Some(f) = out.get_mut(&k) {
            f.last = first;
        }
    }
    out
}

/// Compares the daemon's states with the firmware's, fix by fix.
pub fn compare(
    daemon: &BTreeMap<u64, FixStates>,
    firmware: &BTreeMap<u64, FixStates>,
) -> TimelineMatch {
    let mut m = TimelineMatch {
        fixes_compared: 0,
        fixes_matching: 0,
        fixes_skipped: 0,
        fixes_settling: 0,
        roadside_changes: 0,
        delay_fixes: 0,
        mismatches: Vec::new(),
        max_distance_diff_m: 0.0,
    };
    let mut last_version = 0;
    // Fixes that may still differ, since the last skipped fix.
    let mut settling_left = 0;
    for (k, fd) in daemon {
        let d = &fd.last;
        if roadside_version(d) != last_version {
            m.roadside_changes += 1;
            last_version = roadside_version(d);
        }
        let Some(ff) = firmware.get(k) else {
            continue;
        };
        let f = &ff.last;
        let before = |run: &BTreeMap<u64, FixStates>| {
            run.get(&(k - 1)).map_or(0, |s| roadside_version(&s.last))
        };
        if fd.met != ff.met
            || roadside_version(d) != roadside_version(f)
            || before(daemon) != before(firmware)
        {
            m.fixes_skipped += 1;
            settling_left = MAX_SETTLING;
            continue;
        }
        let mut diffs = Vec::new();
        diff("", d, f, &mut diffs);
        if !diffs.is_empty() && settling_left > 0 {
            settling_left -= 1;
            m.fixes_settling += 1;
            continue;
        }
        settling_left = 0;
        m.fixes_compared += 1;
        if diffs.is_empty() {
            m.fixes_matching += 1;
        }
        for (path, a, b) in diffs {
            if m.mismatches.len() < 20 {
                m.mismatches.push((*k, path, a, b));
            }
        }
        if let (Some(a), Some(b)) = (d["distance_m"].as_f64(), f["distance_m"].as_f64()) {
            m.max_distance_diff_m = m.max_distance_diff_m.max((a - b).abs());
        }
    }
    m
}

/// What the roadside had changed in the core up to a state: maps and zones stored, replaced
/// or cancelled.
fn roadside_version(state: &Value) -> u64 {
    let c = &state["counters"];
    ["maps_updated", "zones_updated", "zones_cancelled"]
        .iter()
        .map(|k| c[k].as_u64().unwrap_or(0))
        .sum()
}

/// Appends the paths where `a` and `b` disagree.
fn diff(path: &str, a: &Value, b: &Value, out: &mut Vec<(String, Value, Value)>) {
    match (a, b) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            for key in keys.into_iter().filter(|k| !IGNORED.contains(&k.as_str())) {
                let (va, vb) = (
                    x.get(key).unwrap_or(&Value::Null),
                    y.get(key).unwrap_or(&Value::Null),
                );
                diff(&format!("{path}/{key}"), va, vb, out);
            }
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => {
            for (i, (va, vb)) in x.iter().zip(y).enumerate() {
                diff(&format!("{path}/{i}"), va, vb, out);
            }
        }
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (
                x.as_f64().unwrap_or(f64::NAN),
                y.as_f64().unwrap_or(f64::NAN),
            );
            if (x - y).abs() > TOLERANCE || x.is_nan() != y.is_nan() {
                out.push((path.to_string(), a.clone(), b.clone()));
            }
        }
        _ if a == b => {}
        _ => out.push((path.to_string(), a.clone(), b.clone())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn line(fixes: u64, zone: &str, d: f64, time: u64) -> String {
        json!({"t_s": 0.0, "sample": 0, "state": {"time_ms": time, "zone_state": zone,
            "distance_m": d, "closed_lanes": [2], "counters": {"fixes": fixes, "frames": time}}})
        .to_string()
    }

    #[test]
    fn clocks_and_counters_are_ignored_and_numbers_have_a_tolerance() {
        let a = by_fix(&[line(1, "Approach", 120.0, 5), line(2, "Warning", 99.0, 6)].join("\n"));
        let b = by_fix(
            &[
                line(1, "Approach", 120.04, 900),
                line(2, "Warning", 99.01, 901),
            ]
            .join("\n"),
        );
        let m = compare(&a, &b);
        assert_eq!((m.fixes_compared, m.fixes_matching), (2, 2));
        assert!(m.matches());
        assert!((m.max_distance_diff_m - 0.04).abs() < 1e-9);
    }

    #[test]
    fn a_different_zone_state_or_distance_is_a_mismatch() {
        let a = by_fix(&[line(1, "Approach", 120.0, 5), line(2, "Warning", 99.0, 6)].join("\n"));
        let b = by_fix(&[line(1, "Approach", 121.0, 5), line(2, "Approach", 99.0, 6)].join("\n"));
        let m = compare(&a, &b);
        assert_eq!((m.fixes_compared, m.fixes_matching), (2, 0));
        assert_eq!(m.mismatches[0].1, "/distance_m");
        assert_eq!(m.mismatches[1].1, "/zone_state");
        assert!(!m.matches());
    }

    fn with_version(fixes: u64, zone: &str, maps: u64) -> String {
        json!({"state": {"zone_state": zone, "counters": {"fixes": fixes, "maps_updated": maps}}})
            .to_string()
    }

    #[test]
    fn a_fix_that_met_different_roadside_inputs_is_left_out_within_a_bound() {
        let a = by_fix(
            &[
                with_version(1, "None", 0),
                with_version(2, "Approach", 1),
                with_version(3, "Approach", 1),
            ]
            .join("\n"),
        );
        let b = by_fix(
            &[
                with_version(1, "None", 1),
                with_version(2, "Approach", 1),
                with_version(3, "Approach", 1),
            ]
            .join("\n"),
        );
        let m = compare(&a, &b);
        // Fix 1 met the MAP in one run only, fix 2 followed different fix-1 states.
        assert_eq!(
            (m.fixes_skipped, m.fixes_compared, m.fixes_matching),
            (2, 1, 1)
        );
        assert_eq!(m.roadside_changes, 1);
        assert!(m.matches());
        let c = by_fix(
            &[
                with_version(1, "None", 5),
                with_version(2, "Approach", 6),
                with_version(3, "Approach", 7),
            ]
            .join("\n"),
        );
        assert!(!compare(&a, &c).matches(), "nothing comparable");
    }

    #[test]
    fn a_later_delivery_explains_the_fixes_it_spans_and_no_more() {
        // The daemon shows the MAP from fix 2, the firmware from fix 5 (its link 300 ms
        // slower): fixes 2-4 meet different inputs, fix 5 follows different fix-4 states.
        let run = |from: u64| {
            let lines: Vec<String> = (1..=8)
                .map(|k| with_version(k, "Approach", u64::from(k >= from)))
                .collect();
            by_fix(&lines.join("\n"))
        };
        let mut m = compare(&run(2), &run(5));
        assert_eq!((m.fixes_skipped, m.fixes_compared), (4, 4));
        assert!(!m.matches(), "2 allowed for the one change");
        m.delay_fixes = delay_fixes(&[1.0], &[301.0]);
        assert_eq!((m.delay_fixes, m.allowed_skipped()), (3, 5));
        assert!(m.matches());
        // A slower delivery than the skipped fixes show explains only what it spans.
        let mut m = compare(&run(2), &run(7));
        m.delay_fixes = delay_fixes(&[1.0], &[301.0]);
        assert_eq!(m.fixes_skipped, 6);
        assert!(!m.matches());
    }

    #[test]
    fn delays_are_paired_by_change_and_rounded_up_to_epochs() {
        // CI's MAP revision scenario: the daemon showed its two changes in 3.2 and 1.2 ms,
        // the firmware in 327.5 and 730.8 ms.
        assert_eq!(delay_fixes(&[3.2, 1.2], &[327.5, 730.8]), 4 + 8);
        assert_eq!(delay_fixes(&[3.2, 1.2], &[3.0, 1.5]), 2);
        assert_eq!(delay_fixes(&[3.2, 1.2], &[327.5]), 0, "a change not shown");
        assert_eq!(delay_fixes(&[], &[]), 0);
        assert_eq!(delay_fixes(&[1.0], &[f64::INFINITY]), 0);
    }

    fn with_confidence(fixes: u64, maps: u64, confidence: u64) -> String {
        json!({"state": {"lane_confidence": confidence,
            "counters": {"fixes": fixes, "maps_updated": maps}}})
        .to_string()
    }

    /// Fix 1 met the MAP on `b` only; then the confidences of fixes 2.. on each run.
    fn settling_runs(a: &[u64], b: &[u64]) -> TimelineMatch {
        let run = |first_maps: u64, conf: &[u64]| {
            let mut lines = vec![with_confidence(1, first_maps, 0)];
            for (i, &c) in conf.iter().enumerate() {
                lines.push(with_confidence(i as u64 + 2, 1, c));
            }
            by_fix(&lines.join("\n"))
        };
        compare(&run(0, a), &run(1, b))
    }

    #[test]
    fn the_lane_filter_may_settle_for_a_few_fixes_after_different_inputs() {
        // One more fix with the map on b: its confidence leads by a fix, then both agree.
        let m = settling_runs(&[98, 99, 99, 99, 99], &[99, 99, 99, 99, 99]);
        assert_eq!(
            (m.fixes_skipped, m.fixes_settling, m.fixes_compared),
            (2, 0, 4)
        );
        let m = settling_runs(&[90, 98, 99, 99, 99], &[95, 99, 99, 99, 99]);
        assert_eq!(
            (m.fixes_skipped, m.fixes_settling, m.fixes_compared),
            (2, 1, 3)
        );
        assert!(m.matches());
        assert!(m.mismatches.is_empty());
    }

    #[test]
    fn a_difference_that_outlasts_the_settling_is_a_mismatch() {
        // Still different MAX_SETTLING fixes after the skipped ones.
        let m = settling_runs(&[90, 91, 92, 93, 94, 95], &[95, 96, 97, 98, 99, 99]);
        assert_eq!((m.fixes_skipped, m.fixes_settling), (2, MAX_SETTLING));
        assert!(!m.matches());
        assert_eq!(m.mismatches[0].0, 6);
        // Once the runs agreed, a later difference is never settling.
        let m = settling_runs(&[90, 98, 99, 50, 99], &[95, 99, 99, 99, 99]);
        assert_eq!(m.fixes_settling, 1);
        assert!(!m.matches());
        assert_eq!(m.mismatches[0].0, 5);
    }

    #[test]
    fn the_last_state_of_a_fix_count_stands_for_it() {
        let a = by_fix(
            &[
                line(1, "Approach", 120.0, 5),
                line(1, "Warning", 99.0, 6),
                line(2, "Warning", 98.0, 7),
            ]
            .join("\n"),
        );
        assert_eq!(a.len(), 2);
        assert_eq!(a[&1].last["zone_state"], "Warning");
        assert!(!compare(&a, &BTreeMap::new()).matches());
    }

    #[test]
    fn the_final_fix_is_judged_on_its_first_state() {
        // One rig kept running past the GNSS timeout after the drive, the other did not.
        let a = by_fix(&[line(1, "Approach", 120.0, 5), line(2, "Warning", 99.0, 6)].join("\n"));
        let b = by_fix(
            &[
                line(1, "Approach", 120.0, 5),
                line(2, "Warning", 99.0, 6),
                line(2, "GnssStale", 99.0, 1_006),
            ]
            .join("\n"),
        );
        assert_eq!(b[&2].last["zone_state"], "Warning");
        assert!(compare(&a, &b).matches());
    }
}
