//! Expectations of scenarios whose roadside is deployed (`[rsu_deployment]`): what the
//! tablet shows as the WZDx feed changes, and what the RSU and the roadside did.

use super::{quiet, Record, RunFacts};
use obu::alert::ZoneState;

/// From `from_s` + `within_s` on, every state showing a zone shows `lanes` closed (and at
/// least one does); the detail gives when the first such state came after `from_s`.
pub fn closed_lanes_shown(
    records: &[Record],
    from_s: f64,
    lanes: &[u8],
    within_s: f64,
) -> (bool, String) {
    let mut want = lanes.to_vec();
    want.sort_unstable();
    let shows = |r: &Record| {
        let mut got = r.state.closed_lanes.to_vec();
        got.sort_unstable();
        got == want
    };
    let first = records
        .iter()
        .find(|r| r.t_s >= from_s && r.state.zone_state != ZoneState::None && shows(r))
        .map(|r| r.t_s - from_s);
    let after: Vec<&Record> = records
        .iter()
        .filter(|r| r.t_s >= from_s + within_s && r.state.zone_state != ZoneState::None)
        .collect();
    let wrong = after.iter().filter(|r| !shows(r)).count();
    let passed = !after.is_empty() && wrong == 0;
    let detail = format!(
        "lanes {want:?} first shown {} after the feed changed; {wrong} of {} later zone states show other lanes",
        first.map_or("never".into(), |s| format!("{s:.2} s")),
        after.len()
    );
    (passed, detail)
}

/// The roadside counted `reason` for the RSU, deposited nothing (no row created), and the
/// RSU sent nothing; no state shows a zone.
pub fn rsu_refused(records: &[Record], facts: &RunFacts, reason: &str) -> (bool, String) {
    let Some(d) = &facts.deployment else {
        return (false, "not a [rsu_deployment] scenario".into());
    };
    let Some(rsu) = d.status.as_ref().and_then(|s| s.rsus.first()) else {
        return (false, "the roadside wrote no status".into());
    };
    let count = |k: &str| rsu.counts.get(k).copied().unwrap_or(0);
    let quiet_all = records.iter().all(|r| quiet(&r.state));
    let passed = count(reason) > 0
        && count("created") == 0
        && d.rsu_sent == 0
        && quiet_all
        && !records.is_empty();
    let detail = format!(
        "roadside counted {reason} {} times (problem: {}), created {} rows; the RSU sent {} datagrams; {} states, all quiet: {quiet_all}",
        count(reason),
        rsu.problem.as_deref().unwrap_or("none"),
        count("created"),
        d.rsu_sent,
        records.len()
    );
    (passed, detail)
}

/// After each time the RSU came up (started late or restarted), its first transmission of
/// the deposited messages came within `within_s`.
pub fn rsu_restored(facts: &RunFacts, within_s: f64) -> (bool, String) {
    let Some(d) = &facts.deployment else {
        return (false, "not a [rsu_deployment] scenario".into());
    };
    let mut worst: Option<f64> = None;
    let mut missing = 0;
    for up in d.rsu_up_s.iter().filter(|s| **s > 0.0) {
        match d.first_sent_s.iter().find(|s| **s >= *up) {
            Some(s) => worst = Some(worst.map_or(s - up, |w: f64| w.max(s - up))),
            None => missing += 1,
        }
    }
    let ups = d.rsu_up_s.iter().filter(|s| **s > 0.0).count();
    let passed = ups > 0 && missing == 0 && worst.is_some_and(|w| w <= within_s);
    let detail = format!(
        "{ups} RSU starts during the drive; messages on the air again after at most {} (goal {within_s} s); {missing} never",
        worst.map_or("-".into(), |w| format!("{w:.2} s"))
    );
    (passed, detail)
}

/// After each change of the feed, the RSU sent a new message (the new TIM, its first
/// transmission) within `within_s`.
pub fn feed_on_air(facts: &RunFacts, within_s: f64) -> (bool, String) {
    let Some(d) = &facts.deployment else {
        return (false, "not a [rsu_deployment] scenario".into());
    };
    let delays: Vec<Option<f64>> = d
        .feed_changes_s
        .iter()
        .map(|t| d.first_sent_s.iter().find(|s| **s >= *t).map(|s| s - t))
        .collect();
    let worst = delays
        .iter()
        .flatten()
        .copied()
        .fold(None, |w: Option<f64>, x| Some(w.map_or(x, |w| w.max(x))));
    let passed = !delays.is_empty() && delays.iter().all(|d| d.is_some_and(|d| d <= within_s));
    let shown: Vec<String> = delays
        .iter()
        .map(|d| d.map_or("never".into(), |d| format!("{d:.2} s")))
        .collect();
    let detail = format!(
        "feed change -> first transmission of the new message: {} (worst {}, goal {within_s} s)",
        shown.join(", "),
        worst.map_or("-".into(), |w| format!("{w:.2} s"))
    );
    (passed, detail)
}
