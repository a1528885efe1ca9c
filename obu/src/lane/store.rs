//! Several lane models keyed by [`MapId`], replaced only on a revision change.

use super::{LaneModel, MapId};
use crate::capacity::MAX_MAPS;
use crate::geo::LatLon;
use crate::store::{Keyed, Provenance, SlotStore, SlotUpdate};
use crate::time::{Duration, Instant};

/// Outcome of [`MapStore::update`].
#[derive(Debug, PartialEq)]
pub enum MapUpdate<'a> {
    /// Same id and revision as stored: only the last-heard time was refreshed.
    Unchanged,
    /// The slot to fill (cleared, identity and reference set). `replaced` is true
    /// when an older revision or another (least recently heard) map was evicted.
    Fill {
        /// The cleared model.
        model: &'a mut LaneModel,
        /// True when a stored model was overwritten.
        replaced: bool,
    },
    /// An unverified MAP for a model that came verified (or that would evict one).
    Refused,
}

/// Up to [`MAX_MAPS`] lane models, in fixed slots (no copies of large models): a typed
/// [`SlotStore`].
#[derive(Debug, Clone, PartialEq)]
pub struct MapStore {
    slots: SlotStore<LaneModel, MAX_MAPS>,
}

impl Keyed for LaneModel {
    type Key = MapId;
    fn key(&self) -> &MapId {
        &self.id
    }
}

impl Default for MapStore {
    fn default() -> Self {
        MapStore::new()
    }
}

impl MapStore {
    /// An empty store; usable in `static` items.
    pub const fn new() -> Self {
        const EMPTY: LaneModel = LaneModel::new();
        MapStore {
            slots: SlotStore::new([EMPTY; MAX_MAPS]),
        }
    }

    /// Starts storing a received model. If `id` is stored with the same `revision`
    /// only its last-heard time is refreshed; otherwise a slot is cleared (the one
    /// with `id`, else an empty one, else the least recently heard) and returned.
    pub fn update(
        &mut self,
        now: Instant,
        id: MapId,
        revision: u8,
        reference: LatLon,
        elevation_m: f32,
        provenance: Provenance,
    ) -> MapUpdate<'_> {
        match self
            .slots
            .update(now, &id, provenance, |m| m.revision == revision)
        {
            SlotUpdate::Unchanged => MapUpdate::Unchanged,
            SlotUpdate::Refused => MapUpdate::Refused,
            SlotUpdate::Fill { value, replaced } => {
                value.reset(id, revision, reference, elevation_m);
                MapUpdate::Fill {
                    model: value,
                    replaced,
                }
            }
        }
    }

    /// The stored model with `id`.
    pub fn get(&self, id: MapId) -> Option<&LaneModel> {
        self.slots.get(&id)
    }

    /// Removes the model with `id` (e.g. after a failed conversion); true if found.
    pub fn remove(&mut self, id: MapId) -> bool {
        let found = self.slots.remove(&id);
        if let Some(m) = found {
            m.reset(MapId(0), 0, LatLon::ZERO, 0.0);
            return true;
        }
        false
    }

    /// Stored models with their slot index (stable while stored).
    pub fn iter(&self) -> impl Iterator<Item = (usize, &LaneModel)> + '_ {
        self.slots.iter()
    }

    /// The model in slot `slot`, if stored.
    pub fn slot(&self, slot: usize) -> Option<&LaneModel> {
        self.slots.slot(slot)
    }

    /// Number of stored models that came unverified.
    pub fn unverified(&self) -> usize {
        self.slots.count(Provenance::Unverified)
    }

    /// Number of stored models.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// True when no model is stored.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// Drops models not heard for longer than `timeout`; returns how many.
    pub fn expire(&mut self, now: Instant, timeout: Duration) -> usize {
        self.slots.expire(now, timeout, |_| false)
    }

    /// The earliest time at which [`MapStore::expire`] would drop a model.
    pub fn next_expiry(&self, timeout: Duration) -> Option<Instant> {
        self.slots.next_expiry(timeout)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(ms: u64) -> Instant {
        Instant::from_millis(ms)
    }

    fn add(s: &mut MapStore, now: u64, id: u32, rev: u8) -> Option<bool> {
        match s.update(
            t(now),
            MapId(id),
            rev,
            LatLon::ZERO,
            0.0,
            Provenance::Verified,
        ) {
            MapUpdate::Unchanged | MapUpdate::Refused => None,
            MapUpdate::Fill { replaced, .. } => Some(replaced),
        }
    }

    #[test]
    fn replaces_only_on_revision_change() {
        let mut s = MapStore::new();
        assert_eq!(add(&mut s, 0, 1, 5), Some(false));
        assert_eq!(add(&mut s, 100, 1, 5), None);
        assert_eq!(add(&mut s, 200, 1, 6), Some(true));
        assert_eq!(s.get(MapId(1)).map(|m| m.revision), Some(6));
        assert_eq!(s.len(), 1);
    }

    #[test]
    fn evicts_least_recently_heard_and_expires() {
        let mut s = MapStore::new();
        for id in 0..MAX_MAPS as u32 {
            assert_eq!(add(&mut s, id as u64 * 10, id + 1, 0), Some(false));
        }
        assert_eq!(add(&mut s, 1000, 99, 0), Some(true));
        assert!(s.get(MapId(1)).is_none() && s.get(MapId(99)).is_some());
        assert_eq!(s.next_expiry(Duration::from_secs(1)), Some(t(1011)));
        assert_eq!(s.expire(t(1500), Duration::from_secs(1)), MAX_MAPS - 1);
        assert!(s.remove(MapId(99)) && s.is_empty());
        assert!(!s.remove(MapId(99)));
        assert!(s.slot(0).is_none() && s.slot(99).is_none());
    }
}
