//! [`WorkerStore`]: at most [`MAX_WORKERS`] road workers by temporary id.

use heapless::Vec;

use super::{Worker, REPLACE_AFTER, WORKER_TIMEOUT};
use crate::capacity::MAX_WORKERS;
use crate::geo::LatLon;
use crate::ingest::IngestError;
use crate::store::Provenance;
use crate::time::Instant;

/// What [`WorkerStore::update`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum WorkerUpdate {
    /// A worker not stored before (or expired) was stored in a free slot.
    New,
    /// The stored worker of this id was replaced by its newer PSM.
    Updated,
    /// A new worker took the slot of another one ([`WorkerStats::evicted`]).
    Evicted,
    /// Unverified PSM over a worker that came verified: left alone.
    Refused,
}

/// What the store did so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct WorkerStats {
    /// Workers stored that were not stored before (evictions included).
    pub new: u32,
    /// Updates of a stored worker.
    pub updated: u32,
    /// Workers replaced by a new one while the store was full.
    pub evicted: u32,
    /// Workers dropped [`WORKER_TIMEOUT`] after their last update.
    pub expired: u32,
}

impl WorkerStats {
    /// All zero.
    pub const ZERO: WorkerStats = WorkerStats {
        new: 0,
        updated: 0,
        evicted: 0,
        expired: 0,
    };
}

/// Road workers by temporary id, at most [`MAX_WORKERS`].
///
/// An update replaces the stored worker of its id (if its `secMark` follows the stored
/// one, [`Worker::follows`]); a worker not updated for [`WORKER_TIMEOUT`] is gone. When the
/// store is full a new worker replaces, in this order:
/// 1. the stalest worker, if it has been silent for [`REPLACE_AFTER`] (it has likely left
///    the camera's view: half its lifetime without a PSM);
/// 2. else the worker farthest from the vehicle, if the new one is nearer (the ones near
///    the vehicle matter to the driver);
///
/// except that a verified worker first takes the slot of the stalest unverified one;
/// else it is refused ([`IngestError::StoreFull`]). A replacement is counted
/// ([`WorkerStats::evicted`]). Unverified PSMs never replace, refresh or evict a worker
/// that came verified.
#[derive(Debug, Clone)]
pub struct WorkerStore {
    workers: Vec<Worker, MAX_WORKERS>,
    stats: WorkerStats,
}

impl Default for WorkerStore {
    fn default() -> Self {
        Self::new()
    }
}

impl WorkerStore {
    /// Empty.
    pub const fn new() -> Self {
        WorkerStore {
            workers: Vec::new(),
            stats: WorkerStats::ZERO,
        }
    }

    /// Stores `w` (see [`WorkerStore`]); `vehicle` is the vehicle's position, if
    /// known, for the choice of a worker to replace.
    ///
    /// # Errors
    ///
    /// [`IngestError::StaleMessage`] when `w`'s `secMark` does not follow the stored one's,
    /// [`IngestError::StoreFull`] when no slot is free or may be taken.
    pub fn update(
        &mut self,
        w: Worker,
        vehicle: Option<LatLon>,
    ) -> Result<WorkerUpdate, IngestError> {
        let now = w.heard;
        if let Some(slot) = self.workers.iter_mut().find(|s| s.id == w.id) {
            let live = slot.age(now) < WORKER_TIMEOUT;
            if live && !may_replace(&w, slot) {
                return Ok(WorkerUpdate::Refused);
            }
            if live && !w.follows(slot) {
                return Err(IngestError::StaleMessage);
            }
            *slot = w;
            let n = if live {
                &mut self.stats.updated
            } else {
                &mut self.stats.new
            };
            *n = n.saturating_add(1);
            return Ok(if live {
                WorkerUpdate::Updated
            } else {
                WorkerUpdate::New
            });
        }
        self.expire(now);
        self.stats.new = self.stats.new.saturating_add(1);
        let Err(w) = self.workers.push(w) else {
            return Ok(WorkerUpdate::New);
        };
        let Some(i) = self.victim(&w, vehicle) else {
            self.stats.new = self.stats.new.saturating_sub(1);
            return Err(IngestError::StoreFull);
        };
        self.workers[i] = w;
        self.stats.evicted = self.stats.evicted.saturating_add(1);
        Ok(WorkerUpdate::Evicted)
    }

    /// The slot a new worker `w` may take in a full store, if any. A verified worker takes
    /// an unverified one's whenever there is one, so that unsigned PSMs (accepted only with
    /// signatures not required) cannot fill the store and lock a signed worker out: of the
    /// unverified, one silent for [`REPLACE_AFTER`], else the farthest from the vehicle, else
    /// (vehicle unknown) the stalest.
    fn victim(&self, w: &Worker, vehicle: Option<LatLon>) -> Option<usize> {
        if w.provenance == Provenance::Verified {
            if let Some(i) = self.unverified_victim(w.heard, vehicle) {
                return Some(i);
            }
        }
        let allowed = || {
            self.workers
                .iter()
                .enumerate()
                .filter(|(_, s)| may_replace(w, s))
        };
        let stalest = allowed().min_by_key(|(_, s)| s.heard);
        if let Some((i, _)) = stalest.filter(|(_, s)| s.age(w.heard) >= REPLACE_AFTER) {
            return Some(i);
        }
        let v = vehicle?;
        let new = distance_key(v, w.position);
        let (i, far) = allowed()
            .map(|(i, s)| (i, distance_key(v, s.position)))
            .max_by(|a, b| a.1.total_cmp(&b.1))?;
        (far > new).then_some(i)
    }

    /// The unverified worker a verified newcomer heard at `now` replaces (see
    /// [`WorkerStore::victim`]), if any is stored.
    fn unverified_victim(&self, now: Instant, vehicle: Option<LatLon>) -> Option<usize> {
        let unverified = || {
            self.workers
                .iter()
                .enumerate()
                .filter(|(_, s)| s.provenance == Provenance::Unverified)
        };
        let (stalest, oldest) = unverified().min_by_key(|(_, s)| s.heard)?;
        if oldest.age(now) >= REPLACE_AFTER {
            return Some(stalest);
        }
        let Some(v) = vehicle else {
            return Some(stalest);
        };
        unverified()
            .map(|(i, s)| (i, distance_key(v, s.position)))
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| i)
    }

    /// Drops the workers not updated for [`WORKER_TIMEOUT`] at `now`; returns how many.
    pub fn expire(&mut self, now: Instant) -> usize {
        let before = self.workers.len();
        self.workers.retain(|w| w.age(now) < WORKER_TIMEOUT);
        let gone = before - self.workers.len();
        self.stats.expired = self.stats.expired.saturating_add(gone as u32);
        gone
    }

    /// When the next worker expires, if any is stored.
    pub fn next_expiry(&self) -> Option<Instant> {
        self.workers.iter().map(|w| w.heard + WORKER_TIMEOUT).min()
    }

    /// The workers still current at `now` (updated less than [`WORKER_TIMEOUT`] ago).
    pub fn current(&self, now: Instant) -> impl Iterator<Item = &Worker> + '_ {
        self.workers
            .iter()
            .filter(move |w| w.age(now) < WORKER_TIMEOUT)
    }

    /// Every stored worker (some may have expired since the last [`WorkerStore::expire`]).
    pub fn iter(&self) -> core::slice::Iter<'_, Worker> {
        self.workers.iter()
    }

    /// Number of workers stored.
    pub fn len(&self) -> usize {
        self.workers.len()
    }

    /// True when no worker is stored.
    pub fn is_empty(&self) -> bool {
        self.workers.is_empty()
    }

    /// What the store did so far.
    pub fn stats(&self) -> WorkerStats {
        self.stats
    }
}

/// Whether `new` may replace `old` (an unverified PSM never replaces a verified worker).
fn may_replace(new: &Worker, old: &Worker) -> bool {
    new.provenance == Provenance::Verified || old.provenance == Provenance::Unverified
}

/// A key growing with the distance between `a` and `b` (squared, in 1e-7 degree of
/// latitude): enough to compare distances from one point a few kilometres around.
fn distance_key(a: LatLon, b: LatLon) -> f32 {
    let dlat = (i64::from(a.lat_e7()) - i64::from(b.lat_e7())) as f32;
    let dlon = (i64::from(a.lon_e7()) - i64::from(b.lon_e7())) as f32;
    let cos = libm::cosf(a.lat_deg() as f32 * (core::f32::consts::PI / 180.0));
    let dx = dlon * cos;
    dlat * dlat + dx * dx
}
