//! Several lane models keyed by [`MapId`], replaced only on a revision change.

use super::{LaneModel, MapId};
use crate::capacity::MAX_MAPS;
use crate::geo::LatLon;
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
}

/// Up to [`MAX_MAPS`] lane models, in fixed slots (no copies of large models).
#[derive(Debug, Clone, PartialEq)]
pub struct MapStore {
    models: [LaneModel; MAX_MAPS],
    heard: [Option<Instant>; MAX_MAPS],
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
            models: [EMPTY; MAX_MAPS],
            heard: [None; MAX_MAPS],
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
    ) -> MapUpdate<'_> {
        if let Some(i) = self.slot_of(id) {
            self.heard[i] = Some(now);
            if self.models[i].revision == revision {
                return MapUpdate::Unchanged;
            }
            return self.fill(i, id, revision, reference, elevation_m, true);
        }
        let (i, replaced) = self.free_slot();
        self.heard[i] = Some(now);
        self.fill(i, id, revision, reference, elevation_m, replaced)
    }

    fn fill(
        &mut self,
        i: usize,
        id: MapId,
        revision: u8,
        reference: LatLon,
        elevation_m: f32,
        replaced: bool,
    ) -> MapUpdate<'_> {
        let model = &mut self.models[i];
        model.reset(id, revision, reference, elevation_m);
        MapUpdate::Fill { model, replaced }
    }

    /// An empty slot, or the least recently heard one (evicted).
    fn free_slot(&self) -> (usize, bool) {
        if let Some(i) = self.heard.iter().position(Option::is_none) {
            return (i, false);
        }
        let oldest = (0..MAX_MAPS).min_by_key(|&i| self.heard[i]).unwrap_or(0);
        (oldest, true)
    }

    fn slot_of(&self, id: MapId) -> Option<usize> {
        (0..MAX_MAPS).find(|&i| self.heard[i].is_some() && self.models[i].id == id)
    }

    /// The stored model with `id`.
    pub fn get(&self, id: MapId) -> Option<&LaneModel> {
        self.slot_of(id).map(|i| &self.models[i])
    }

    /// Removes the model with `id` (e.g. after a failed conversion); true if found.
    pub fn remove(&mut self, id: MapId) -> bool {
        let found = self.slot_of(id);
        if let Some(i) = found {
            self.heard[i] = None;
            self.models[i].reset(MapId(0), 0, LatLon::ZERO, 0.0);
        }
        found.is_some()
    }

    /// Stored models with their slot index (stable while stored).
    pub fn iter(&self) -> impl Iterator<Item = (usize, &LaneModel)> + '_ {
        (0..MAX_MAPS)
            .filter(|&i| self.heard[i].is_some())
            .map(|i| (i, &self.models[i]))
    }

    /// The model in slot `slot`, if stored.
    pub fn slot(&self, slot: usize) -> Option<&LaneModel> {
        self.heard.get(slot)?.as_ref()?;
        self.models.get(slot)
    }

    /// Number of stored models.
    pub fn len(&self) -> usize {
        self.heard.iter().filter(|h| h.is_some()).count()
    }

    /// True when no model is stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Drops models not heard for longer than `timeout`; returns how many.
    pub fn expire(&mut self, now: Instant, timeout: Duration) -> usize {
        let mut n = 0;
        for i in 0..MAX_MAPS {
            if self.heard[i].is_some_and(|t| now.saturating_since(t) > timeout) {
                self.heard[i] = None;
                n += 1;
            }
        }
        n
    }

    /// The earliest time at which [`MapStore::expire`] would drop a model.
    pub fn next_expiry(&self, timeout: Duration) -> Option<Instant> {
        self.heard
            .iter()
            .flatten()
            .min()
            .map(|&t| t + timeout + Duration::from_millis(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(ms: u64) -> Instant {
        Instant::from_millis(ms)
    }

    fn add(s: &mut MapStore, now: u64, id: u32, rev: u8) -> Option<bool> {
        match s.update(t(now), MapId(id), rev, LatLon::ZERO, 0.0) {
            MapUpdate::Unchanged => None,
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
