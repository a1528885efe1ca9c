//! Expectations of a scenario, checked on the recorded states joined with the simulated
//! truth (and, for a scenario with an attacker, the device's counters: [`crate::attack`]).

mod alerts;
mod attack;
mod deployment;
mod workers;

use obu::alert::{AlertKind, AlertStage, HmiState, ZoneState};
use serde::{Deserialize, Serialize};

/// One recorded state with what was true when its fix was taken.
#[derive(Debug, Clone)]
pub struct Record {
    /// Seconds since the drive started, when the state arrived.
    pub t_s: f64,
    /// The state.
    pub state: HmiState,
    /// Index of the drive sample of the last fix the state includes.
    pub sample: Option<usize>,
    /// The true lane then.
    pub true_lane: Option<u8>,
    /// True distance to the first zone's start along the car's lane, metres (negative
    /// past it), when the car runs the zone's way.
    pub distance_m: Option<f64>,
    /// Length of that zone, metres.
    pub zone_len_m: Option<f64>,
    /// True speed, m/s.
    pub true_speed_mps: Option<f64>,
    /// True distance to the first zone's start when the state arrived, metres.
    pub now_distance_m: Option<f64>,
}

impl Record {
    /// The true distance a state is judged at: the fix's for a live state, where the car
    /// was when it arrived for a dead-reckoned one.
    pub fn judged_distance_m(&self) -> Option<f64> {
        if self.state.gnss_ok {
            self.distance_m
        } else {
            self.now_distance_m
        }
    }
}

/// What must hold.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub enum Expectation {
    /// The first warning (state Warning, or a zone alert) shows at least `min_m` and at
    /// most `max_m` before the zone start (both required: a warning far too early is as
    /// wrong as a late one).
    WarningBefore {
        /// Least distance.
        min_m: f64,
        /// Greatest distance.
        max_m: f64,
    },
    /// While the car is in a closed lane and warned, the primary alert is "lane closed"
    /// with a side to move to (at least `min_fraction` of those states).
    LaneClosedAdvice {
        /// Least fraction.
        #[serde(default = "ninety")]
        min_fraction: f64,
    },
    /// Above the zone limit plus the tolerance near or in the zone, an overspeed alert.
    Overspeed {
        /// Least fraction of the states that qualify.
        #[serde(default = "ninety")]
        min_fraction: f64,
    },
    /// No zone state and no zone alert at any time (e.g. the opposite carriageway).
    NoAlert,
    /// "In zone" is shown in at least `min_fraction` of the states while the car is inside.
    InZoneShown {
        /// Least fraction.
        #[serde(default = "ninety")]
        min_fraction: f64,
    },
    /// `within_m` after the zone end no zone state and no zone alert.
    ClearedAfterZone {
        /// Metres after the end.
        within_m: f64,
    },
    /// "No GNSS" shows within `ms` of the last fix before each dropout.
    NoGnssWithin {
        /// Milliseconds.
        ms: f64,
    },
    /// `within_s` after the zone was removed (or its TIM's window ended), no zone state and
    /// no zone alert.
    ClearedAfterRemoval {
        /// Seconds.
        within_s: f64,
    },
    /// The matched lane equals the true lane in at least `min` of the states (those more
    /// than 2 s from a lane change of the truth).
    MatchedLane {
        /// Least fraction.
        min: f64,
    },
    /// Every datagram of the scenario's attacker was dropped and counted under `group` /
    /// `reason` of the device's counters: exactly as many as it sent; where the device
    /// counts every input (the daemon's `/api/status`), the V2X counters add up to the
    /// run's datagrams (roadside and attacker), so none was taken. On the firmware the
    /// drops come from its log.
    ForgedDropped {
        /// The counter group as `/api/status` names it.
        #[serde(default = "security_errors")]
        group: String,
        /// The drop reason: an `obu::v2x::DropReason` counter name.
        reason: String,
    },
    /// Through every GNSS dropout the zone stays shown: each state without GNSS while the
    /// zone is near (300 m ahead to its end) is dead-reckoned ("estimated") with the zone
    /// state and a distance within `max_error_m` of the truth, and no speed is shown as if
    /// live (the speed shown is `None` unless the scenario's speed comes from CAN).
    ZoneKeptThroughDropout {
        /// Largest error of the estimated distance, metres.
        max_error_m: f64,
    },
    /// The first urgent state comes between `min_m` and `max_m` before the zone start.
    UrgentBefore {
        /// Least distance.
        min_m: f64,
        /// Greatest distance.
        max_m: f64,
    },
    /// A complying driver: no state is urgent, and the stage rises to warning (the one
    /// tone) at most once per zone.
    NeverUrgent,
    /// At least `min_fraction` of the states with a fix show the time status `status`
    /// ("Trusted", "Unverified").
    TimeStatusShown {
        /// The status, as the state names it.
        status: String,
        /// Least fraction.
        #[serde(default = "ninety")]
        min_fraction: f64,
    },
    /// From the attacker's first datagram to the end, every state holds what the last one
    /// before it held: the real roadside's lane maps and zones, verified (or its zones as it
    /// cancelled them), none stored, replaced or cancelled since (for a roadside that
    /// changes nothing meanwhile).
    RoadsideKept,
    /// The roadside signs once and repeats (`[signing] pattern = "once"`): no signed frame
    /// is dropped by the trust policy once GNSS time is known (only "no GNSS time" drops),
    /// and where the device counts every input (the daemon), at least `min_share` of the
    /// MAP and TIM it took were repeats (each distinct message verified once, its copies
    /// counted under `repeats`). The firmware logs drops only.
    SignedOnceRepeated {
        /// Least share of repeats among the MAP and TIM taken.
        #[serde(default = "ninety")]
        min_share: f64,
    },
    /// The roadside names its certificate by `digest` between whole certificates
    /// (`[signing] certificate_every_ms`): once GNSS time is known no signed frame is dropped
    /// except at most `max_unknown` as "signer certificate not seen yet" (those before the
    /// first whole certificate reached the OBU).
    DigestSignerTaken {
        /// Most frames dropped for a signer not seen yet.
        max_unknown: u64,
    },
    /// A lane other than the true one is named in at most `max` of the states (those more
    /// than 2 s from a lane change of the truth): an uncertain lane is left unnamed.
    WrongLaneShown {
        /// Greatest fraction.
        max: f64,
    },
    /// The device rejected at least `min` fixes as outliers (its `lane_outliers` counter
    /// at the end of the run): multipath jumps are caught, not followed.
    OutliersRejected {
        /// Least count.
        min: u32,
    },
    /// The first "worker in lane ahead" shows as the primary alert at most `within_ms`
    /// after `from_s` (when the worker's truth came within the alert's margin of the car's
    /// lane) and not more than half a second before it, `min_m` to `max_m` ahead.
    WorkerInLaneShown {
        /// Seconds since the drive start.
        from_s: f64,
        /// Milliseconds.
        within_ms: f64,
        /// Least distance ahead, metres.
        min_m: f64,
        /// Greatest distance ahead, metres.
        max_m: f64,
    },
    /// Workers are shown near the road (in some state with the alert, at least
    /// `min_workers` workers ahead outside the lane's path) and never in the car's lane.
    WorkersNearOnly {
        /// Least number of workers shown at once.
        min_workers: usize,
    },
    /// The camera site's camera `camera` (from 1) saw nothing of road user `user` (from
    /// 1, the scenario's order) from `from_s` to `to_s`: the occlusion is real.
    HiddenFromCamera {
        /// Camera.
        camera: usize,
        /// Road user.
        user: usize,
        /// Seconds since the drive start.
        from_s: f64,
        /// Seconds since the drive start.
        to_s: f64,
    },
    /// At least `min_fraction` of the states with a live fix name `source` as where the
    /// fix's accuracy came from (`gst`, `ubx`, `hdop`, `gpsd`, `none`).
    AccuracyFrom {
        /// The accuracy source, as `HmiState` names it.
        source: obu::fix::AccuracySource,
        /// Least fraction.
        #[serde(default = "ninety")]
        min_fraction: f64,
    },
    /// `[rsu_deployment]`: from `from_s` + `within_s` on (a feed change, plus the feed's
    /// poll, the deposit and a repeat interval), every state showing a zone shows `lanes`
    /// closed.
    ClosedLanesShown {
        /// Seconds since the drive start (when the feed changed).
        from_s: f64,
        /// The closed lanes.
        lanes: Vec<u8>,
        /// Seconds allowed.
        within_s: f64,
    },
    /// `[rsu_deployment]`: the roadside counted `reason` (an `RsuProblem` reason, e.g.
    /// `auth_refused`) for the RSU, deposited nothing, the RSU sent nothing and no state
    /// shows a zone.
    RsuRefused {
        /// The reason.
        reason: String,
    },
    /// `[rsu_deployment]`: after each change of the WZDx feed, the RSU's first transmission
    /// of a new message came within `within_s` (the goal: one feed poll plus one repeat
    /// interval).
    FeedOnAir {
        /// Seconds.
        within_s: f64,
    },
    /// `[rsu_deployment]`: after the RSU came up late or restarted, its rows were on the
    /// air again within `within_s`.
    RsuRestored {
        /// Seconds.
        within_s: f64,
    },
}

fn ninety() -> f64 {
    0.9
}

fn security_errors() -> String {
    "security_errors".into()
}

/// The verdict on one expectation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Outcome {
    /// The expectation.
    pub expectation: Expectation,
    /// True when it holds.
    pub passed: bool,
    /// What was measured.
    pub detail: String,
}

/// Facts of the run the checks need besides the records.
#[derive(Debug, Clone, Default)]
pub struct RunFacts {
    /// Seconds (since the drive start) of the last fix sent before each dropout.
    pub dropout_starts_s: Vec<f64>,
    /// Each dropout of the drive: (start, end), seconds since the drive start.
    pub dropouts_s: Vec<(f64, f64)>,
    /// Seconds when a zone was removed (the TIM cancelled) or its own validity window
    /// ended (the first of them).
    pub removed_at_s: Option<f64>,
    /// Configured overspeed tolerance, m/s.
    pub overspeed_tolerance_mps: f64,
    /// Warning distance of the settings, metres.
    pub warning_distance_m: f64,
    /// The attack, when the scenario has an attacker.
    pub attack: Option<crate::attack::AttackFacts>,
    /// The device's counters after the drive, when they could be read.
    pub device: Option<crate::attack::DeviceCounts>,
    /// The vehicle speed comes from CAN (it stays shown through a GNSS dropout).
    pub can_speed: bool,
    /// What the camera site's cameras saw of each road user, frame by frame.
    pub camera_views: Vec<crate::roadside_bench::camera_site::CameraView>,
    /// What the deployed roadside did (`[rsu_deployment]` scenarios).
    pub deployment: Option<crate::deployment::DeploymentFacts>,
}

/// True for alerts about a work zone (not about the data).
pub fn is_zone_alert(kind: AlertKind) -> bool {
    !matches!(
        kind,
        AlertKind::GnssStale
            | AlertKind::NoRoadsideData
            | AlertKind::MapMissing
            | AlertKind::WorkerInLane
            | AlertKind::WorkersNearRoad
    )
}

fn zone_alerts(s: &HmiState) -> impl Iterator<Item = AlertKind> + '_ {
    s.primary
        .iter()
        .chain(s.others.iter())
        .map(|a| a.kind)
        .filter(|k| is_zone_alert(*k))
}

fn quiet(s: &HmiState) -> bool {
    s.zone_state == ZoneState::None && zone_alerts(s).next().is_none()
}

/// Checks one expectation.
pub fn check(e: &Expectation, records: &[Record], facts: &RunFacts) -> Outcome {
    let (passed, detail) = match e {
        Expectation::WarningBefore { min_m, max_m } => warning_before(records, *min_m, *max_m),
        Expectation::LaneClosedAdvice { min_fraction } => fraction(
            records.iter().filter(|r| {
                r.state.zone_state == ZoneState::Warning
                    && r.true_lane
                        .is_some_and(|l| r.state.closed_lanes.contains(&l))
            }),
            |r| {
                r.state
                    .primary
                    .is_some_and(|a| a.kind == AlertKind::LaneClosedOwn)
                    && r.state.advice != obu::alert::LaneAdvice::None
            },
            *min_fraction,
            "warned in a closed lane with lane-closed advice",
        ),
        Expectation::Overspeed { min_fraction } => fraction(
            records.iter().filter(|r| {
                matches!(r.state.zone_state, ZoneState::Warning | ZoneState::InZone)
                    && match (r.state.speed_mps, r.state.speed_limit_mps) {
                        (Some(v), Some(l)) => {
                            f64::from(v) > f64::from(l) + facts.overspeed_tolerance_mps + 0.3
                        }
                        _ => false,
                    }
            }),
            |r| zone_alerts(&r.state).any(|k| k == AlertKind::Overspeed),
            *min_fraction,
            "over the limit near the zone with an overspeed alert",
        ),
        Expectation::NoAlert => {
            let bad: Vec<_> = records.iter().filter(|r| !quiet(&r.state)).collect();
            (
                bad.is_empty() && !records.is_empty(),
                format!("{} of {} states show a zone", bad.len(), records.len()),
            )
        }
        Expectation::InZoneShown { min_fraction } => fraction(
            records.iter().filter(|r| {
                r.distance_m
                    .zip(r.zone_len_m)
                    .is_some_and(|(d, l)| d < -5.0 && d > -l + 5.0)
            }),
            |r| r.state.zone_state == ZoneState::InZone,
            *min_fraction,
            "inside the zone showing IN ZONE",
        ),
        Expectation::ClearedAfterZone { within_m } => fraction(
            records.iter().filter(|r| {
                r.distance_m
                    .zip(r.zone_len_m)
                    .is_some_and(|(d, l)| d < -l - within_m)
            }),
            |r| quiet(&r.state),
            1.0,
            "past the zone end plus the margin and quiet",
        ),
        Expectation::NoGnssWithin { ms } => no_gnss_within(records, facts, *ms),
        Expectation::ClearedAfterRemoval { within_s } => match facts.removed_at_s {
            None => (false, "the scenario removes no zone".into()),
            Some(t) => fraction(
                records.iter().filter(|r| r.t_s > t + within_s),
                |r| quiet(&r.state),
                1.0,
                "quiet after the removal",
            ),
        },
        Expectation::MatchedLane { min } => matched_lane(records, *min),
        Expectation::WrongLaneShown { max } => wrong_lane(records, *max),
        Expectation::OutliersRejected { min } => {
            let n = records.last().map_or(0, |r| r.state.counters.lane_outliers);
            (
                n >= *min,
                format!("{n} fixes rejected as outliers (need {min})"),
            )
        }
        Expectation::ForgedDropped { group, reason } => {
            attack::forged_dropped(group, reason, facts)
        }
        Expectation::RoadsideKept => attack::roadside_kept(records, facts),
        Expectation::SignedOnceRepeated { min_share } => {
            attack::signed_once_repeated(*min_share, facts)
        }
        Expectation::DigestSignerTaken { max_unknown } => {
            attack::digest_signer_taken(*max_unknown, facts)
        }
        Expectation::ZoneKeptThroughDropout { max_error_m } => {
            alerts::zone_kept_through_dropout(records, facts, *max_error_m)
        }
        Expectation::UrgentBefore { min_m, max_m } => {
            alerts::urgent_before(records, *min_m, *max_m)
        }
        Expectation::NeverUrgent => alerts::never_urgent(records),
        Expectation::ClosedLanesShown {
            from_s,
            lanes,
            within_s,
        } => deployment::closed_lanes_shown(records, *from_s, lanes, *within_s),
        Expectation::RsuRefused { reason } => deployment::rsu_refused(records, facts, reason),
        Expectation::RsuRestored { within_s } => deployment::rsu_restored(facts, *within_s),
        Expectation::FeedOnAir { within_s } => deployment::feed_on_air(facts, *within_s),
        Expectation::WorkerInLaneShown {
            from_s,
            within_ms,
            min_m,
            max_m,
        } => workers::worker_in_lane_shown(records, *from_s, *within_ms, [*min_m, *max_m]),
        Expectation::WorkersNearOnly { min_workers } => {
            workers::workers_near_only(records, *min_workers)
        }
        Expectation::HiddenFromCamera {
            camera,
            user,
            from_s,
            to_s,
        } => workers::hidden_from_camera(facts, *camera, *user, [*from_s, *to_s]),
        Expectation::AccuracyFrom {
            source,
            min_fraction,
        } => fraction(
            records
                .iter()
                .filter(|r| r.state.position == obu::alert::PositionSource::Live),
            |r| r.state.accuracy_source == *source,
            *min_fraction,
            &format!("with a live fix take its accuracy from {}", source.as_str()),
        ),
        Expectation::TimeStatusShown {
            status,
            min_fraction,
        } => fraction(
            records.iter().filter(|r| r.state.gnss_ok),
            |r| format!("{:?}", r.state.time_status) == *status,
            *min_fraction,
            &format!("with a fix showing time {status}"),
        ),
    };
    Outcome {
        expectation: e.clone(),
        passed,
        detail,
    }
}

pub(crate) fn fraction<'a>(
    set: impl Iterator<Item = &'a Record>,
    ok: impl Fn(&Record) -> bool,
    min: f64,
    what: &str,
) -> (bool, String) {
    let set: Vec<_> = set.collect();
    let good = set.iter().filter(|r| ok(r)).count();
    let f = if set.is_empty() {
        0.0
    } else {
        good as f64 / set.len() as f64
    };
    (
        !set.is_empty() && f >= min,
        format!(
            "{good} of {} states {what} ({:.1} %, need {:.1} %)",
            set.len(),
            100.0 * f,
            100.0 * min
        ),
    )
}

/// The first warning shown (state Warning, a stage of warning or more, or a zone alert
/// inside) and the true distance it was shown at.
pub fn first_warning(records: &[Record]) -> Option<(&Record, f64)> {
    records
        .iter()
        .find(|r| {
            r.state.zone_state == ZoneState::Warning
                || r.state.stage >= AlertStage::Warning
                || (r.state.zone_state == ZoneState::InZone
                    && zone_alerts(&r.state).next().is_some())
        })
        .and_then(|r| r.judged_distance_m().map(|d| (r, d)))
}

fn warning_before(records: &[Record], min_m: f64, max_m: f64) -> (bool, String) {
    match first_warning(records) {
        None => (false, "no warning was shown before the zone".into()),
        Some((r, d)) => {
            let ok = (min_m..=max_m).contains(&d);
            let speed = r.true_speed_mps.unwrap_or(f64::NAN) * 3.6;
            (ok, format!("first warning {d:.1} m before the zone start (at {speed:.1} km/h, t = {:.1} s)", r.t_s))
        }
    }
}

fn no_gnss_within(records: &[Record], facts: &RunFacts, ms: f64) -> (bool, String) {
    if facts.dropout_starts_s.is_empty() {
        return (false, "the scenario has no GNSS dropout".into());
    }
    let mut worst: f64 = 0.0;
    for &t in &facts.dropout_starts_s {
        let Some(r) = records.iter().find(|r| r.t_s > t && !r.state.gnss_ok) else {
            return (
                false,
                format!("\"no GNSS\" never shown after the dropout at {t:.1} s"),
            );
        };
        worst = worst.max((r.t_s - t) * 1000.0);
    }
    (
        worst <= ms,
        format!("\"no GNSS\" {worst:.0} ms after the last fix (limit {ms:.0} ms)"),
    )
}

/// The records with a fix more than 2 s from a lane change of the truth.
fn steady_lane(records: &[Record]) -> impl Iterator<Item = &Record> {
    let changes: Vec<f64> = records
        .windows(2)
        .filter(|w| w[0].true_lane != w[1].true_lane)
        .map(|w| w[1].t_s)
        .collect();
    records.iter().filter(move |r| {
        r.true_lane.is_some() && r.state.gnss_ok && changes.iter().all(|c| (r.t_s - c).abs() > 2.0)
    })
}

fn matched_lane(records: &[Record], min: f64) -> (bool, String) {
    fraction(
        steady_lane(records),
        |r| r.state.lane.map(|l| l.lane) == r.true_lane,
        min,
        "matched to the true lane",
    )
}

fn wrong_lane(records: &[Record], max: f64) -> (bool, String) {
    let set: Vec<&Record> = steady_lane(records).collect();
    let wrong = set
        .iter()
        .filter(|r| r.state.lane.is_some_and(|l| Some(l.lane) != r.true_lane))
        .count();
    let f = wrong as f64 / set.len().max(1) as f64;
    (
        !set.is_empty() && f <= max,
        format!(
            "{wrong} of {} states named a wrong lane ({:.1} %, at most {:.1} %)",
            set.len(),
            f * 100.0,
            max * 100.0
        ),
    )
}
