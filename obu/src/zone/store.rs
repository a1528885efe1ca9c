//! Work zones keyed by packet id, replaced by newer versions, expired on poll.

use super::{Validity, WorkZone, ZoneKey};
use crate::capacity::MAX_ZONES;
use crate::store::{Keyed, Provenance, SlotStore, SlotUpdate};
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
    /// The message's own window has already ended: the version it ends was removed
    /// (true) or none was stored (false); it is never stored again.
    Ended(bool),
    /// An unverified message for a zone that came verified (or that would evict one):
    /// nothing changed.
    Refused,
    /// The slot to fill (cleared, identity and validity set).
    Fill {
        /// The cleared zone.
        zone: &'a mut WorkZone,
        /// True when a stored zone was overwritten.
        replaced: bool,
    },
}

/// Up to [`MAX_ZONES`] work zones in fixed slots: a typed [`SlotStore`].
#[derive(Debug, Clone, PartialEq)]
pub struct ZoneStore {
    slots: SlotStore<WorkZone, MAX_ZONES>,
}

impl Keyed for WorkZone {
    type Key = ZoneKey;
    fn key(&self) -> &ZoneKey {
        &self.key
    }
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
            slots: SlotStore::new([EMPTY; MAX_ZONES]),
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
        provenance: Provenance,
    ) -> ZoneUpdate<'_> {
        if validity.is_cancelled() {
            return match self.slots.remove_as(&key, provenance) {
                Ok(found) => ZoneUpdate::Cancelled(found),
                Err(()) => ZoneUpdate::Refused,
            };
        }
        let same = |z: &WorkZone| z.msg_cnt == msg_cnt && z.validity == validity;
        if let Some(z) = self.slots.get(&key) {
            if !same(z) && validity.start_abs() < z.validity.start_abs() {
                return ZoneUpdate::Stale;
            }
        }
        match self.slots.update(now, &key, provenance, same) {
            SlotUpdate::Unchanged => ZoneUpdate::Unchanged,
            SlotUpdate::Refused => ZoneUpdate::Refused,
            SlotUpdate::Fill { value, replaced } => {
                value.reset(key, msg_cnt, validity);
                ZoneUpdate::Fill {
                    zone: value,
                    replaced,
                }
            }
        }
    }

    /// Takes a received zone whose window has ended at the current time (an RSU
    /// repeating a TIM past its `durationTime`): removes the stored version it ends,
    /// leaves a newer one (a later start) alone, and stores nothing.
    pub fn end(
        &mut self,
        key: ZoneKey,
        validity: Validity,
        provenance: Provenance,
    ) -> ZoneUpdate<'_> {
        if let Some(z) = self.slots.get(&key) {
            if validity.start_abs() < z.validity.start_abs() {
                return ZoneUpdate::Stale;
            }
        }
        match self.slots.remove_as(&key, provenance) {
            Ok(found) => ZoneUpdate::Ended(found),
            Err(()) => ZoneUpdate::Refused,
        }
    }

    /// The zone with `key`.
    pub fn get(&self, key: &ZoneKey) -> Option<&WorkZone> {
        self.slots.get(key)
    }

    /// Removes the zone with `key`; true if it was stored.
    pub fn remove(&mut self, key: &ZoneKey) -> bool {
        self.slots.remove(key).is_some()
    }

    /// Stored zones.
    pub fn iter(&self) -> impl Iterator<Item = &WorkZone> + '_ {
        self.slots.iter().map(|(_, z)| z)
    }

    /// Stored zones, mutable.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut WorkZone> + '_ {
        self.slots.iter_mut()
    }

    /// Number of stored zones that came unverified.
    pub fn unverified(&self) -> usize {
        self.slots.count(Provenance::Unverified)
    }

    /// Number of stored zones.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// True when no zone is stored.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// Drops zones whose window has ended at `utc_min` (minutes since 2000, when the
    /// wall time is known), whose signature is no longer relevant at `time64` (GNSS time),
    /// or that were not heard for longer than `timeout`.
    /// Returns how many were dropped.
    pub fn poll(
        &mut self,
        now: Instant,
        utc_min: Option<i64>,
        time64: Option<u64>,
        timeout: Duration,
    ) -> usize {
        self.slots.expire(now, timeout, |z| {
            let window_ended = utc_min.is_some_and(|m| z.validity.has_ended(m));
            let until_us = u64::from(z.signed_until_s) * 1_000_000;
            let signature_ended = z.signed_until_s > 0 && time64.is_some_and(|t| t > until_us);
            window_ended || signature_ended
        })
    }

    /// Bounds the zone `key` (if stored) by the signature of the message that just carried
    /// it: shown until `signed_until_us` (`Time64`) at most, none for `None`
    /// ([`WorkZone::signed_until_s`]).
    pub fn set_signed_until(&mut self, key: &ZoneKey, signed_until_us: Option<u64>) {
        let seconds = signed_until_us.map_or(0, |us| {
            u32::try_from(us.div_ceil(1_000_000)).unwrap_or(u32::MAX)
        });
        if let Some(z) = self.iter_mut().find(|z| &z.key == key) {
            z.signed_until_s = seconds;
        }
    }

    /// The earliest end (minutes since 2000, as seen at `now_abs_min`) of a stored zone's
    /// validity window; `None` when every window is indefinite or nothing is stored.
    pub fn next_end(&self, now_abs_min: i64) -> Option<i64> {
        self.iter()
            .filter_map(|z| z.validity.end_abs_at(now_abs_min))
            .min()
    }

    /// The earliest time at which [`ZoneStore::poll`] would drop a zone for silence.
    pub fn next_expiry(&self, timeout: Duration) -> Option<Instant> {
        self.slots.next_expiry(timeout)
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
        match s.update(
            Instant::from_millis(now),
            key(k),
            cnt,
            v,
            Provenance::Verified,
        ) {
            ZoneUpdate::Unchanged => "same",
            ZoneUpdate::Refused => "refused",
            ZoneUpdate::Stale => "stale",
            ZoneUpdate::Cancelled(true) => "cancelled",
            ZoneUpdate::Cancelled(false) => "unknown",
            ZoneUpdate::Ended(_) => "ended",
            ZoneUpdate::Fill { replaced: true, .. } => "replaced",
            ZoneUpdate::Fill {
                replaced: false, ..
            } => "added",
        }
    }

    #[test]
    fn an_ended_window_removes_its_version_and_leaves_a_newer_one() {
        let mut s = ZoneStore::new();
        assert_eq!(up(&mut s, 0, 1, 0, valid(100, 60)), "added");
        let ended = |s: &mut ZoneStore, v| match s.end(key(1), v, Provenance::Verified) {
            ZoneUpdate::Ended(found) => {
                if found {
                    "removed"
                } else {
                    "none"
                }
            }
            ZoneUpdate::Stale => "stale",
            _ => "other",
        };
        assert_eq!(ended(&mut s, valid(100, 60)), "removed");
        assert_eq!(ended(&mut s, valid(100, 60)), "none");
        assert_eq!(up(&mut s, 0, 1, 1, valid(200, 60)), "added");
        assert_eq!(
            ended(&mut s, valid(100, 60)),
            "stale",
            "an older version ends nothing"
        );
        assert_eq!(s.len(), 1);
        assert!(
            matches!(
                s.end(key(1), valid(200, 60), Provenance::Unverified),
                ZoneUpdate::Refused
            ),
            "unverified over verified"
        );
        assert_eq!(s.len(), 1);
    }

    #[test]
    fn a_zone_goes_when_its_signature_stops_being_relevant() {
        let mut s = ZoneStore::new();
        assert_eq!(up(&mut s, 0, 1, 0, valid(100, 60)), "added");
        assert_eq!(up(&mut s, 0, 2, 0, valid(100, 60)), "added");
        s.set_signed_until(&key(1), Some(5_000_000));
        let start = valid(100, 60).start_abs();
        let poll = |s: &mut ZoneStore, t64: u64| {
            s.poll(
                Instant::from_millis(10),
                Some(start + 10),
                Some(t64),
                Duration::from_secs(30),
            )
        };
        // Both windows open, both heard: the signed one goes once GNSS time passes its end.
        assert_eq!(s.get(&key(1)).map(|z| z.signed_until_s), Some(5));
        assert_eq!(poll(&mut s, 5_000_000), 0);
        assert_eq!(poll(&mut s, 5_000_001), 1);
        assert!(s.get(&key(1)).is_none() && s.get(&key(2)).is_some());
        // Without a trusted time nothing goes for its signature.
        s.set_signed_until(&key(2), Some(1));
        let kept = s.poll(
            Instant::from_millis(10),
            None,
            None,
            Duration::from_secs(30),
        );
        assert_eq!(kept, 0);
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
                None,
                Duration::from_secs(1)
            ),
            0
        );
        assert_eq!(
            s.poll(
                Instant::from_millis(60),
                Some(start + 61),
                None,
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
            s.poll(
                Instant::from_millis(1001),
                None,
                None,
                Duration::from_secs(1)
            ),
            1
        );
        assert!(!s.remove(&key(5)));
    }
}
