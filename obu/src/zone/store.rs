//! Work zones keyed by packet id, replaced by newer versions, expired on poll.

use super::{Validity, WorkZone, ZoneKey};
use crate::capacity::MAX_ZONES;
use crate::time::{Duration, Instant};

/// Outcome of [`ZoneStore::update`].
#[derive(Debug, PartialEq)]
pub enum ZoneUpdate<'a> {
    /// Same `msgCnt` and start time as stored: only the last-heard time changed.
    Unchanged,
    /// An older start time than the stored zone's: ignored.
    Stale,
    /// `durationTime` 0: the zone was removed (true) or was not stored (false).
    Cancelled(bool),
    /// The slot to fill (cleared, identity and validity set).
    Fill {
        /// The cleared zone.
        zone: &'a mut WorkZone,
        /// True when a stored zone was overwritten.
        replaced: bool,
    },
}

/// Up to [`MAX_ZONES`] work zones in fixed slots.
#[derive(Debug, Clone, PartialEq)]
pub struct ZoneStore {
    zones: [WorkZone; MAX_ZONES],
    heard: [Option<Instant>; MAX_ZONES],
}

impl Default for ZoneStore {
    fn default() -> Self {
        ZoneStore::new()
    }
}

impl ZoneStore {
    /// An empty store; usable in `static` items.
    pub const fn new() -> Self {
        const EMPTY: WorkZone = WorkZone::new();
        ZoneStore {
            zones: [EMPTY; MAX_ZONES],
            heard: [None; MAX_ZONES],
        }
    }

    /// Starts storing a received zone. A stored zone with the same key is kept when
    /// `msg_cnt` and the start time are unchanged, replaced otherwise (deployed
    /// senders bump both on every change), removed when `validity` cancels it, and
    /// left alone when the start time is older than the stored one. A new
    /// key takes an empty slot or evicts the least recently heard zone.
    pub fn update(
        &mut self,
        now: Instant,
        key: ZoneKey,
        msg_cnt: u8,
        validity: Validity,
    ) -> ZoneUpdate<'_> {
        let found = self.slot_of(&key);
        if validity.is_cancelled() {
            if let Some(i) = found {
                self.heard[i] = None;
            }
            return ZoneUpdate::Cancelled(found.is_some());
        }
        let (i, replaced) = match found {
            Some(i) if self.is_same(i, msg_cnt, &validity) => {
                self.heard[i] = Some(now);
                return ZoneUpdate::Unchanged;
            }
            Some(i) if validity.start_abs() < self.zones[i].validity.start_abs() => {
                return ZoneUpdate::Stale;
            }
            Some(i) => (i, true),
            None => self.free_slot(),
        };
        self.heard[i] = Some(now);
        let zone = &mut self.zones[i];
        zone.reset(key, msg_cnt, validity);
        ZoneUpdate::Fill { zone, replaced }
    }

    fn is_same(&self, i: usize, msg_cnt: u8, validity: &Validity) -> bool {
        let z = &self.zones[i];
        z.msg_cnt == msg_cnt && z.validity == *validity
    }

    fn free_slot(&self) -> (usize, bool) {
        if let Some(i) = self.heard.iter().position(Option::is_none) {
            return (i, false);
        }
        let oldest = (0..MAX_ZONES).min_by_key(|&i| self.heard[i]).unwrap_or(0);
        (oldest, true)
    }

    fn slot_of(&self, key: &ZoneKey) -> Option<usize> {
        (0..MAX_ZONES).find(|&i| self.heard[i].is_some() && self.zones[i].key == *key)
    }

    /// The zone with `key`.
    pub fn get(&self, key: &ZoneKey) -> Option<&WorkZone> {
        self.slot_of(key).map(|i| &self.zones[i])
    }

    /// Removes the zone with `key`; true if it was stored.
    pub fn remove(&mut self, key: &ZoneKey) -> bool {
        let found = self.slot_of(key);
        if let Some(i) = found {
            self.heard[i] = None;
        }
        found.is_some()
    }

    /// Stored zones.
    pub fn iter(&self) -> impl Iterator<Item = &WorkZone> + '_ {
        (0..MAX_ZONES)
            .filter(|&i| self.heard[i].is_some())
            .map(|i| &self.zones[i])
    }

    /// Stored zones, mutable.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut WorkZone> + '_ {
        self.zones
            .iter_mut()
            .zip(self.heard.iter())
            .filter(|(_, h)| h.is_some())
            .map(|(z, _)| z)
    }

    /// Number of stored zones.
    pub fn len(&self) -> usize {
        self.heard.iter().filter(|h| h.is_some()).count()
    }

    /// True when no zone is stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Drops zones whose window has ended at `utc_min` (minutes since 2000, when the
    /// wall time is known) or that were not heard for longer than `timeout`.
    /// Returns how many were dropped.
    pub fn poll(&mut self, now: Instant, utc_min: Option<i64>, timeout: Duration) -> usize {
        let mut n = 0;
        for i in 0..MAX_ZONES {
            let Some(heard) = self.heard[i] else { continue };
            let ended = utc_min.is_some_and(|m| self.zones[i].validity.has_ended(m));
            if ended || now.saturating_since(heard) > timeout {
                self.heard[i] = None;
                n += 1;
            }
        }
        n
    }

    /// The earliest time at which [`ZoneStore::poll`] would drop a zone for silence.
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

    fn key(b: u8) -> ZoneKey {
        ZoneKey::packet([b; 9], 0)
    }

    fn valid(start: u32, dur: u16) -> Validity {
        Validity {
            start_year: 2024,
            start_minute: start,
            duration_min: dur,
        }
    }

    fn up(s: &mut ZoneStore, now: u64, k: u8, cnt: u8, v: Validity) -> &'static str {
        match s.update(Instant::from_millis(now), key(k), cnt, v) {
            ZoneUpdate::Unchanged => "same",
            ZoneUpdate::Stale => "stale",
            ZoneUpdate::Cancelled(true) => "cancelled",
            ZoneUpdate::Cancelled(false) => "unknown",
            ZoneUpdate::Fill { replaced: true, .. } => "replaced",
            ZoneUpdate::Fill {
                replaced: false, ..
            } => "added",
        }
    }

    #[test]
    fn lifecycle() {
        let mut s = ZoneStore::new();
        assert_eq!(up(&mut s, 0, 1, 1, valid(100, 60)), "added");
        assert_eq!(up(&mut s, 100, 1, 1, valid(100, 60)), "same");
        assert_eq!(up(&mut s, 200, 1, 2, valid(100, 60)), "replaced");
        assert_eq!(up(&mut s, 300, 1, 2, valid(101, 60)), "replaced");
        assert_eq!(s.get(&key(1)).map(|z| z.msg_cnt), Some(2));
        assert_eq!(up(&mut s, 350, 1, 1, valid(100, 60)), "stale");
        assert_eq!(up(&mut s, 400, 1, 3, valid(101, 0)), "cancelled");
        assert_eq!(up(&mut s, 500, 1, 3, valid(101, 0)), "unknown");
        assert!(s.is_empty());
    }

    #[test]
    fn eviction_and_expiry() {
        let mut s = ZoneStore::new();
        for k in 0..MAX_ZONES as u8 {
            assert_eq!(up(&mut s, k as u64, k, 0, valid(100, 60)), "added");
        }
        assert_eq!(up(&mut s, 50, 99, 0, valid(100, 60)), "replaced");
        assert!(s.get(&key(0)).is_none());
        let start = valid(100, 60).start_abs();
        assert_eq!(
            s.poll(
                Instant::from_millis(60),
                Some(start + 10),
                Duration::from_secs(1)
            ),
            0
        );
        assert_eq!(
            s.poll(
                Instant::from_millis(60),
                Some(start + 61),
                Duration::from_secs(1)
            ),
            MAX_ZONES
        );
        assert_eq!(up(&mut s, 0, 5, 0, valid(100, 60)), "added");
        assert_eq!(
            s.next_expiry(Duration::from_secs(1)),
            Some(Instant::from_millis(1001))
        );
        assert_eq!(
            s.poll(Instant::from_millis(1001), None, Duration::from_secs(1)),
            1
        );
        assert!(!s.remove(&key(5)));
    }
}
