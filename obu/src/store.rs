//! [`SlotStore`]: the fixed-slot store under [`crate::lane::MapStore`] and
//! [`crate::zone::ZoneStore`]. `N` values live in place (a lane model or work zone is large:
//! it is never copied, only cleared and filled in its slot), each with the time it was last
//! heard and its [`Provenance`]; a slot without a last-heard time is free.
//!
//! Provenance is enforced here, once for maps and zones: an unverified value never
//! replaces, refreshes, cancels or evicts a verified one ([`SlotUpdate::Refused`]).

use crate::time::{Duration, Instant};

/// A value stored by key: the key is part of the value (set when it is filled).
pub trait Keyed {
    /// The identity of a stored value.
    type Key: PartialEq;
    /// The value's key.
    fn key(&self) -> &Self::Key;
}

/// Where a stored value came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Provenance {
    /// Signed and verified (IEEE 1609.2), or given by a trusted local caller.
    #[default]
    Verified,
    /// Received without a verified signature (only when signatures are not required).
    Unverified,
}

/// Outcome of [`SlotStore::update`].
#[derive(Debug, PartialEq)]
pub enum SlotUpdate<'a, V> {
    /// Stored and judged unchanged: only the last-heard time was refreshed.
    Unchanged,
    /// The slot to fill (its old content still there: the caller clears it).
    Fill {
        /// The slot's value.
        value: &'a mut V,
        /// True when a stored value was overwritten (a new version, or the least
        /// recently heard value evicted for a new key).
        replaced: bool,
    },
    /// Unverified, and it would have replaced or evicted a verified value: nothing changed.
    Refused,
}

/// Up to `N` values of type `V` in fixed slots, by key, with their last-heard times.
#[derive(Debug, Clone, PartialEq)]
pub struct SlotStore<V, const N: usize> {
    values: [V; N],
    heard: [Option<Instant>; N],
    provenance: [Provenance; N],
}

impl<V: Keyed, const N: usize> SlotStore<V, N> {
    /// An empty store over `values` (the empty value in every slot); `const` so that the
    /// stores can be in `static` items.
    pub const fn new(values: [V; N]) -> Self {
        Self {
            values,
            heard: [None; N],
            provenance: [Provenance::Verified; N],
        }
    }

    /// The slot holding `key`.
    pub fn find(&self, key: &V::Key) -> Option<usize> {
        (0..N).find(|&i| self.heard[i].is_some() && self.values[i].key() == key)
    }

    /// Takes a received value with `key` and `provenance` at `now`. When it is stored and
    /// `unchanged` says so, only its last-heard time is refreshed; otherwise its slot (the
    /// one with `key`, else a free one, else the least recently heard that it may evict) is
    /// marked heard and returned. An unverified value never touches a verified one.
    pub fn update(
        &mut self,
        now: Instant,
        key: &V::Key,
        provenance: Provenance,
        unchanged: impl FnOnce(&V) -> bool,
    ) -> SlotUpdate<'_, V> {
        let (i, replaced) = match self.find(key) {
            Some(i) if !self.may_touch(i, provenance) => return SlotUpdate::Refused,
            Some(i) if unchanged(&self.values[i]) => {
                self.heard[i] = Some(now);
                return SlotUpdate::Unchanged;
            }
            Some(i) => (i, true),
            None => match self.free_slot(provenance) {
                Some(slot) => slot,
                None => return SlotUpdate::Refused,
            },
        };
        self.heard[i] = Some(now);
        self.provenance[i] = provenance;
        SlotUpdate::Fill {
            value: &mut self.values[i],
            replaced,
        }
    }

    /// Whether a value of `provenance` may change slot `i`.
    fn may_touch(&self, i: usize, provenance: Provenance) -> bool {
        provenance == Provenance::Verified || self.provenance[i] == Provenance::Unverified
    }

    /// A free slot, or the least recently heard one that `provenance` may evict.
    fn free_slot(&self, provenance: Provenance) -> Option<(usize, bool)> {
        if let Some(i) = self.heard.iter().position(Option::is_none) {
            return Some((i, false));
        }
        let oldest = (0..N)
            .filter(|&i| self.may_touch(i, provenance))
            .min_by_key(|&i| self.heard[i])?;
        Some((oldest, true))
    }

    /// The provenance of the value in slot `slot`, if stored.
    pub fn provenance(&self, slot: usize) -> Option<Provenance> {
        self.heard.get(slot)?.as_ref()?;
        self.provenance.get(slot).copied()
    }

    /// Number of stored values of `provenance`.
    pub fn count(&self, provenance: Provenance) -> usize {
        (0..N)
            .filter(|&i| self.heard[i].is_some() && self.provenance[i] == provenance)
            .count()
    }

    /// Frees the slot of `key` on behalf of a message of `provenance` (a cancellation);
    /// `Err(())` when an unverified message would remove a verified value.
    #[allow(clippy::result_unit_err)]
    pub fn remove_as(&mut self, key: &V::Key, provenance: Provenance) -> Result<bool, ()> {
        match self.find(key) {
            Some(i) if !self.may_touch(i, provenance) => Err(()),
            Some(i) => {
                self.heard[i] = None;
                Ok(true)
            }
            None => Ok(false),
        }
    }

    /// The value with `key`.
    pub fn get(&self, key: &V::Key) -> Option<&V> {
        self.find(key).map(|i| &self.values[i])
    }

    /// Frees the slot of `key`; its value (left in place) when it was stored.
    pub fn remove(&mut self, key: &V::Key) -> Option<&mut V> {
        let i = self.find(key)?;
        self.heard[i] = None;
        Some(&mut self.values[i])
    }

    /// The value in slot `slot`, if stored.
    pub fn slot(&self, slot: usize) -> Option<&V> {
        self.heard.get(slot)?.as_ref()?;
        self.values.get(slot)
    }

    /// Stored values with their slot index (stable while stored).
    pub fn iter(&self) -> impl Iterator<Item = (usize, &V)> + '_ {
        (0..N)
            .filter(|&i| self.heard[i].is_some())
            .map(|i| (i, &self.values[i]))
    }

    /// Stored values, mutable.
    pub fn iter_mut(&mut self) -> impl Iterator<Item = &mut V> + '_ {
        self.values
            .iter_mut()
            .zip(self.heard.iter())
            .filter(|(_, h)| h.is_some())
            .map(|(v, _)| v)
    }

    /// Number of stored values.
    pub fn len(&self) -> usize {
        self.heard.iter().filter(|h| h.is_some()).count()
    }

    /// True when nothing is stored.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Frees the slots of values not heard for longer than `timeout` or for which `ended`
    /// is true; returns how many.
    pub fn expire(&mut self, now: Instant, timeout: Duration, ended: impl Fn(&V) -> bool) -> usize {
        let mut n = 0;
        for i in 0..N {
            let Some(heard) = self.heard[i] else { continue };
            if now.saturating_since(heard) > timeout || ended(&self.values[i]) {
                self.heard[i] = None;
                n += 1;
            }
        }
        n
    }

    /// The earliest time at which [`SlotStore::expire`] would free a slot for silence.
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

    /// A small value: key and version.
    #[derive(Debug, Clone, Copy, PartialEq)]
    struct Item(u8, u8);

    impl Keyed for Item {
        type Key = u8;
        fn key(&self) -> &u8 {
            &self.0
        }
    }

    fn t(ms: u64) -> Instant {
        Instant::from_millis(ms)
    }

    /// Updates key `k` to version `v`: "same", "added" or "replaced".
    fn up(s: &mut SlotStore<Item, 2>, ms: u64, k: u8, v: u8) -> &'static str {
        match s.update(t(ms), &k, Provenance::Verified, |i| i.1 == v) {
            SlotUpdate::Unchanged => "same",
            SlotUpdate::Refused => "refused",
            SlotUpdate::Fill { value, replaced } => {
                *value = Item(k, v);
                if replaced {
                    "replaced"
                } else {
                    "added"
                }
            }
        }
    }

    #[test]
    fn update_evict_expire_and_iterate() {
        let mut s = SlotStore::new([Item(0, 0); 2]);
        assert_eq!(up(&mut s, 0, 7, 1), "added");
        assert_eq!(up(&mut s, 10, 7, 1), "same");
        assert_eq!(up(&mut s, 20, 7, 2), "replaced");
        assert_eq!(up(&mut s, 30, 8, 1), "added");
        // Full: key 9 evicts the least recently heard (7, heard at 20).
        assert_eq!(up(&mut s, 40, 9, 1), "replaced");
        assert_eq!((s.get(&7), s.get(&9)), (None, Some(&Item(9, 1))));
        assert_eq!(
            s.iter()
                .map(|(i, v)| (i, v.0))
                .collect::<std::vec::Vec<_>>(),
            [(0, 9), (1, 8)]
        );
        assert_eq!(s.next_expiry(Duration::from_millis(100)), Some(t(131)));
        assert_eq!(s.expire(t(131), Duration::from_millis(100), |_| false), 1);
        assert_eq!(
            s.expire(t(131), Duration::from_millis(100), |v| v.0 == 9),
            1
        );
        assert!(s.is_empty() && s.next_expiry(Duration::ZERO).is_none());
        assert_eq!(up(&mut s, 200, 5, 1), "added");
        assert_eq!(s.remove(&5).copied(), Some(Item(5, 1)));
        assert!(s.remove(&5).is_none() && s.slot(0).is_none() && s.slot(9).is_none());
    }

    /// Updates key `k` to version `v` as an unverified message.
    fn up_unverified(s: &mut SlotStore<Item, 2>, ms: u64, k: u8, v: u8) -> &'static str {
        match s.update(t(ms), &k, Provenance::Unverified, |i| i.1 == v) {
            SlotUpdate::Unchanged => "same",
            SlotUpdate::Refused => "refused",
            SlotUpdate::Fill { value, .. } => {
                *value = Item(k, v);
                "filled"
            }
        }
    }

    #[test]
    fn unverified_values_never_touch_verified_ones() {
        let mut s = SlotStore::new([Item(0, 0); 2]);
        assert_eq!(up(&mut s, 0, 7, 1), "added");
        // Not replaced, not even refreshed (a repeat would keep it alive).
        assert_eq!(up_unverified(&mut s, 10, 7, 2), "refused");
        assert_eq!(up_unverified(&mut s, 10, 7, 1), "refused");
        assert_eq!(s.next_expiry(Duration::ZERO), Some(t(1)));
        assert_eq!(s.remove_as(&7, Provenance::Unverified), Err(()));
        assert_eq!(up_unverified(&mut s, 20, 8, 1), "filled");
        assert_eq!(s.count(Provenance::Unverified), 1);
        assert_eq!(s.provenance(1), Some(Provenance::Unverified));
        // Full: an unverified key evicts the unverified value, never the verified one.
        assert_eq!(up_unverified(&mut s, 30, 9, 1), "filled");
        assert_eq!((s.get(&7), s.get(&8)), (Some(&Item(7, 1)), None));
        // A verified message upgrades an unverified key and may remove it.
        assert_eq!(up(&mut s, 40, 9, 2), "replaced");
        assert_eq!(s.count(Provenance::Unverified), 0);
        // Only verified values left: an unverified newcomer finds no slot.
        assert_eq!(up_unverified(&mut s, 50, 10, 1), "refused");
        assert_eq!(s.remove_as(&9, Provenance::Verified), Ok(true));
        assert_eq!(s.remove_as(&9, Provenance::Verified), Ok(false));
    }
}
