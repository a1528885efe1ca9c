//! Expectations on road workers (a scenario's `[workers]` camera site): the "worker in lane
//! ahead" alert in time after a worker steps into the car's lane, workers beside the lane
//! shown as information only, and a worker really hidden from a camera (an occlusion test
//! that tests one).

use super::{Record, RunFacts};
use obu::alert::{AlertKind, HmiState};

/// How much earlier than the step a "worker in lane" may show (the camera's error and the
/// margin of the alert), seconds: earlier is a false alarm.
pub const EARLY_S: f64 = 0.5;

fn alerts(s: &HmiState) -> impl Iterator<Item = &obu::alert::Alert> + '_ {
    s.primary.iter().chain(s.others.iter())
}

/// The first state showing "worker in lane ahead" comes at most `within_ms` after
/// `from_s`, not more than [`EARLY_S`] before it, with a distance in `[min_m, max_m]`.
pub fn worker_in_lane_shown(
    records: &[Record],
    from_s: f64,
    within_ms: f64,
    [min_m, max_m]: [f64; 2],
) -> (bool, String) {
    let in_lane = |r: &&Record| alerts(&r.state).any(|a| a.kind == AlertKind::WorkerInLane);
    let Some(first) = records.iter().find(in_lane) else {
        return (false, "\"worker in lane ahead\" never shown".into());
    };
    let late_ms = (first.t_s - from_s) * 1000.0;
    let distance = alerts(&first.state)
        .find(|a| a.kind == AlertKind::WorkerInLane)
        .and_then(|a| a.distance_m)
        .map(f64::from);
    let primary = first
        .state
        .primary
        .is_some_and(|a| a.kind == AlertKind::WorkerInLane);
    let passed = late_ms <= within_ms
        && late_ms >= -EARLY_S * 1000.0
        && primary
        && distance.is_some_and(|d| (min_m..=max_m).contains(&d));
    (
        passed,
        format!(
            "\"worker in lane ahead\" shown {late_ms:.0} ms after the step (at most {within_ms:.0}, \
             at least {:.0} early), {} m ahead (need {min_m}-{max_m}), {}",
            EARLY_S * 1000.0,
            distance.map_or("no distance".into(), |d| format!("{d:.1}")),
            if primary { "as the primary alert" } else { "not the primary alert" }
        ),
    )
}

/// Some state shows "workers near the road" together with at least `min_workers` workers
/// ahead and outside the lane's path, and none shows "worker in lane ahead".
pub fn workers_near_only(records: &[Record], min_workers: usize) -> (bool, String) {
    let showing: Vec<&Record> = records
        .iter()
        .filter(|r| alerts(&r.state).any(|a| a.kind == AlertKind::WorkersNearRoad))
        .collect();
    let beside = |w: &&obu::alert::WorkerView| w.distance_m > 0.0 && !w.in_own_lane_path;
    let most = showing
        .iter()
        .map(|r| r.state.workers.iter().filter(beside).count())
        .max()
        .unwrap_or(0);
    let in_lane = records
        .iter()
        .filter(|r| alerts(&r.state).any(|a| a.kind == AlertKind::WorkerInLane))
        .count();
    (
        !showing.is_empty() && most >= min_workers && in_lane == 0,
        format!(
            "{} states show workers near the road, at most {most} workers ahead beside the \
             lane in one of them (need {min_workers}), {in_lane} show a worker in the lane",
            showing.len()
        ),
    )
}

/// Camera `camera` saw none of road user `user` in any frame from `from_s` to `to_s`.
pub fn hidden_from_camera(
    facts: &RunFacts,
    camera: usize,
    user: usize,
    [from_s, to_s]: [f64; 2],
) -> (bool, String) {
    let views: Vec<_> = facts
        .camera_views
        .iter()
        .filter(|v| v.camera == camera && v.user == user && (from_s..=to_s).contains(&v.t_s))
        .collect();
    let seen = views.iter().filter(|v| v.pixels > 0).count();
    (
        !views.is_empty() && seen == 0,
        format!(
            "camera {camera} saw road user {user} in {seen} of {} frames from {from_s} s to {to_s} s",
            views.len()
        ),
    )
}
