//! Expectations on the driver alerts under faults: dead reckoning through a GNSS dropout,
//! the urgent stage of a driver who does not comply and its absence for one who does.

use super::{Record, RunFacts};
use obu::alert::{AlertStage, PositionSource, ZoneState};

/// How far ahead of the zone a dropout state must still show it, metres.
const NEAR_M: f64 = 300.0;

/// Every state without GNSS during a dropout, while the zone is near, shows it estimated.
pub fn zone_kept_through_dropout(
    records: &[Record],
    facts: &RunFacts,
    max_error_m: f64,
) -> (bool, String) {
    if facts.dropouts_s.is_empty() {
        return (false, "the scenario has no GNSS dropout".into());
    }
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for &(start, end) in &facts.dropouts_s {
        let blind = records.iter().filter(|r| {
            r.t_s > start
                && r.t_s < end
                && !r.state.gnss_ok
                && r.now_distance_m
                    .zip(r.zone_len_m)
                    .is_some_and(|(d, len)| d < NEAR_M && d > -len)
        });
        for r in blind {
            checked += 1;
            let s = &r.state;
            if s.position != PositionSource::Estimated || s.zone_state == ZoneState::None {
                return (
                    false,
                    format!(
                        "at {:.1} s (zone {:.0} m ahead): position {:?}, zone {:?}",
                        r.t_s,
                        r.now_distance_m.unwrap_or(f64::NAN),
                        s.position,
                        s.zone_state
                    ),
                );
            }
            if s.speed_mps.is_some() && !facts.can_speed {
                return (
                    false,
                    format!("at {:.1} s a stale GNSS speed is shown", r.t_s),
                );
            }
            let (Some(shown), Some(truth)) = (s.distance_m, r.now_distance_m) else {
                return (false, format!("at {:.1} s no distance shown", r.t_s));
            };
            worst = worst.max((f64::from(shown) - truth).abs());
        }
    }
    (
        checked > 0 && worst <= max_error_m,
        format!(
            "{checked} states without GNSS near the zone, all estimated with the zone shown; \
             distance error at most {worst:.1} m (limit {max_error_m:.1} m)"
        ),
    )
}

/// The first urgent state comes between `min_m` and `max_m` before the zone start.
pub fn urgent_before(records: &[Record], min_m: f64, max_m: f64) -> (bool, String) {
    let first = records.iter().find(|r| r.state.stage == AlertStage::Urgent);
    match first.and_then(|r| r.judged_distance_m().map(|d| (r, d))) {
        None => (false, "no urgent state was shown".into()),
        Some((r, d)) => (
            (min_m..=max_m).contains(&d),
            format!(
                "first urgent state {d:.1} m before the zone start ({:?}, t = {:.1} s)",
                r.state.primary.map(|a| a.kind),
                r.t_s
            ),
        ),
    }
}

/// No urgent state, and the stage rises into warning at most once per zone.
pub fn never_urgent(records: &[Record]) -> (bool, String) {
    if let Some(r) = records.iter().find(|r| r.state.stage == AlertStage::Urgent) {
        return (
            false,
            format!(
                "urgent at {:.1} s, {:.1} m before the zone ({:?})",
                r.t_s,
                r.distance_m.unwrap_or(f64::NAN),
                r.state.primary.map(|a| a.kind)
            ),
        );
    }
    let rises = records
        .windows(2)
        .filter(|w| {
            w[0].state.stage < AlertStage::Warning && w[1].state.stage >= AlertStage::Warning
        })
        .count()
        + usize::from(
            records
                .first()
                .is_some_and(|r| r.state.stage >= AlertStage::Warning),
        );
    (
        rises <= 1 && !records.is_empty(),
        format!("never urgent; the warning (one tone) began {rises} time(s)"),
    )
}
