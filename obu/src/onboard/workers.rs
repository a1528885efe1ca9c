//! Road workers in the display state: their places on the own lane and the two worker
//! alerts.
//!
//! Each current worker ([`crate::worker::WorkerStore::current`]) is converted into the
//! matched lane model's local plane (as the fixes are) and placed on the matched lane
//! ([`worker::place`]). Ahead means along the own lane further than the vehicle and no
//! further than `reach_m` (the approach distance). A worker ahead in the own lane's path
//! raises [`AlertKind::WorkerInLane`] (warning), one ahead within [`worker::NEAR_ROAD_M`]
//! of a vehicle lane of that model [`AlertKind::WorkersNearRoad`] (information); each
//! with the distance to the nearest such worker. The matched lane is used whatever its
//! confidence: a worker in the path of the probable lane is warned about rather than not.
//! Without a lane match (or with the position lost) no worker is shown or alerted.

use heapless::Vec;

use super::evaluate::AlertList;
use super::Obu;
use crate::alert::{Alert, AlertKind, AlertStage, WorkerView};
use crate::capacity::MAX_HMI_WORKERS;
use crate::store::Provenance;
use crate::time::Instant;
use crate::worker::{self, Worker};

/// The workers shown, and the nearest distance of each alert.
#[derive(Default)]
pub(super) struct WorkerScan {
    /// Views of the nearest workers (unsorted).
    pub(super) views: Vec<WorkerView, MAX_HMI_WORKERS>,
    /// Distance to the nearest worker in the own lane's path ahead.
    in_lane: Option<f32>,
    /// Distance to the nearest worker near the road ahead, not in that path.
    near: Option<f32>,
}

impl WorkerScan {
    /// Appends the worker alerts to `out` (ignoring overflow).
    pub(super) fn alerts(&self, out: &mut AlertList) {
        let alerts = [
            (AlertKind::WorkerInLane, AlertStage::Warning, self.in_lane),
            (
                AlertKind::WorkersNearRoad,
                AlertStage::Information,
                self.near,
            ),
        ];
        for (kind, stage, d) in alerts {
            if let Some(d) = d {
                let _ = out.push(Alert {
                    kind,
                    stage,
                    distance_m: Some(d),
                    limit_mps: None,
                });
            }
        }
    }

    /// The views, in the lane's path ahead first, then ahead, then behind; nearest first in
    /// each.
    pub(super) fn sorted_views(mut self) -> Vec<WorkerView, MAX_HMI_WORKERS> {
        crate::math::sort_small_by(&mut self.views, |a, b| reach(a).total_cmp(&reach(b)));
        self.views
    }
}

impl Obu {
    /// Places every current worker at `now` on the matched lane, whose position is moved
    /// on by `travelled` metres (dead reckoning); `reach_m` is how far ahead the alerts
    /// look.
    pub(super) fn scan_workers(&self, now: Instant, travelled: f32, reach_m: f32) -> WorkerScan {
        let mut scan = WorkerScan::default();
        let (Some(m), Some((map, lane))) = (self.last_match, self.matched_lane()) else {
            return scan;
        };
        let mut own = m.position;
        own.station += travelled;
        for w in self.workers.current(now) {
            let Some((at, alert)) = classify(map, lane, &own, w) else {
                continue;
            };
            let d = at.distance_m;
            if d <= reach_m {
                match alert {
                    Some(AlertKind::WorkerInLane) => {
                        scan.in_lane = Some(scan.in_lane.map_or(d, |n| n.min(d)));
                    }
                    Some(_) => scan.near = Some(scan.near.map_or(d, |n| n.min(d))),
                    None => {}
                }
            }
            keep_nearest(&mut scan.views, view(w, &at, now));
        }
        scan
    }

    /// The stored record of `w`'s worker, and whether `w` changes the alert it raises (a
    /// PSM that does calls for a new state at once).
    pub(super) fn stored_worker(&self, w: &Worker) -> Option<(&Worker, bool)> {
        let old = self.workers.iter().find(|s| s.id() == w.id())?;
        Some((old, self.worker_alert(old) != self.worker_alert(w)))
    }

    /// The alert `w` raises for the vehicle where its last fix matched, however far
    /// ahead: [`AlertKind::WorkerInLane`], [`AlertKind::WorkersNearRoad`] or none (also
    /// without a lane match).
    fn worker_alert(&self, w: &Worker) -> Option<AlertKind> {
        let (m, (map, lane)) = (self.last_match?, self.matched_lane()?);
        classify(map, lane, &m.position, w)?.1
    }
}

/// Places `w` on `lane` of `map` for the vehicle at `own`, with the alert it raises when
/// ahead: in the lane's path, or near one of the map's vehicle lanes.
fn classify(
    map: &crate::lane::LaneModel,
    lane: &crate::lane::Lane,
    own: &crate::lane::LanePosition,
    w: &Worker,
) -> Option<(worker::Placement, Option<AlertKind>)> {
    let p = map.frame().to_local(w.position());
    let at = worker::place(lane, own, p)?;
    let alert = if at.distance_m <= 0.0 {
        None
    } else if at.in_path {
        Some(AlertKind::WorkerInLane)
    } else if worker::near_road(map, p) {
        Some(AlertKind::WorkersNearRoad)
    } else {
        None
    };
    Some((at, alert))
}

/// The view of `w` placed `at`, at `now`.
fn view(w: &Worker, at: &worker::Placement, now: Instant) -> WorkerView {
    WorkerView {
        id: w.id().as_u32(),
        distance_m: at.distance_m,
        lateral_m: at.lateral_m,
        in_own_lane_path: at.in_path,
        speed_mps: w.speed_mps(),
        heading_deg: w.heading_deg(),
        age_ms: w.age(now).millis().min(u64::from(u16::MAX)) as u16,
        verified: w.provenance() == Provenance::Verified,
    }
}

/// How a view ranks for the display, lowest first: workers in the lane's path ahead, then
/// others ahead, then those behind (the tablet draws only what is ahead), each by
/// straight-line distance from the vehicle, metres.
fn reach(v: &WorkerView) -> f32 {
    let tier = match (v.distance_m >= 0.0, v.in_own_lane_path) {
        (true, true) => 0.0,
        (true, false) => 1.0e5,
        (false, _) => 2.0e5,
    };
    tier + libm::hypotf(v.distance_m, v.lateral_m)
}

/// Adds `v` to `views`; when full, it replaces the farthest view if nearer.
fn keep_nearest(views: &mut Vec<WorkerView, MAX_HMI_WORKERS>, v: WorkerView) {
    if let Err(v) = views.push(v) {
        let far = views
            .iter_mut()
            .max_by(|a, b| reach(a).total_cmp(&reach(b)));
        if let Some(far) = far.filter(|f| reach(f) > reach(&v)) {
            *far = v;
        }
    }
}
