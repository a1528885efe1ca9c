//! Superseded versions: for each message identity (a TIM's `packetID` or `msgId` digest, a
//! MAP's intersection and road-segment ids, a PSM's temporary id) the newest generation time
//! accepted. A signed message of the same identity with an older generation time is
//! superseded: a cancel TIM cannot be undone by replaying the signed original it replaced,
//! even while the original's expiry time is still ahead.
//!
//! Bounded: [`MAX_NEWEST`] markers. Each is kept while any message of its identity accepted
//! so far could still be relevant (the latest relevance end among them), then forgotten;
//! when the table is full the marker that ends soonest leaves.

use heapless::Vec;
use j2735::envelope::ieee1609dot2::crypto::sha256;

use crate::capacity::MAX_NEWEST;

/// A message identity: the first 16 octets of SHA-256 over a kind letter and the id's octets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Identity(pub [u8; 16]);

impl Identity {
    /// The identity of a message of `kind` (`b'T'` TIM, `b'M'` MAP, `b'P'` PSM) with `id`.
    pub fn of(kind: u8, id: &[u8]) -> Self {
        let mut input = [0u8; 1 + Self::MAX_ID];
        input[0] = kind;
        let n = id.len().min(Self::MAX_ID);
        input[1..=n].copy_from_slice(&id[..n]);
        let mut out = [0u8; 16];
        out.copy_from_slice(&sha256(&input[..=n])[..16]);
        Self(out)
    }

    /// Longest id taken (longer ids are cut: callers pass fixed-size ids).
    pub const MAX_ID: usize = 64;
}

/// One identity's newest accepted generation time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Marker {
    /// The identity.
    pub identity: Identity,
    /// The newest generation time accepted (`Time64`).
    pub newest_us: u64,
    /// Until when any accepted message of this identity could be relevant (`Time64`).
    pub relevant_until_us: u64,
}

/// The markers, at most [`MAX_NEWEST`].
#[derive(Debug, Clone, Default)]
pub struct NewestTable {
    markers: Vec<Marker, MAX_NEWEST>,
}

impl NewestTable {
    /// Empty.
    pub const fn new() -> Self {
        Self {
            markers: Vec::new(),
        }
    }

    /// Whether a message of `identity` generated at `generated_us` is superseded (a newer one
    /// of the same identity was accepted).
    pub fn is_superseded(&self, identity: &Identity, generated_us: u64) -> bool {
        self.markers
            .iter()
            .any(|m| &m.identity == identity && m.newest_us > generated_us)
    }

    /// Records an accepted message; markers no longer relevant at `now_us` are forgotten.
    pub fn record(&mut self, marker: Marker, now_us: u64) {
        self.markers.retain(|m| m.relevant_until_us >= now_us);
        if let Some(m) = self
            .markers
            .iter_mut()
            .find(|m| m.identity == marker.identity)
        {
            m.newest_us = m.newest_us.max(marker.newest_us);
            m.relevant_until_us = m.relevant_until_us.max(marker.relevant_until_us);
            return;
        }
        if self.markers.is_full() {
            let soonest =
                (0..self.markers.len()).min_by_key(|&i| self.markers[i].relevant_until_us);
            if let Some(i) = soonest {
                self.markers.swap_remove(i);
            }
        }
        let _ = self.markers.push(marker);
    }

    /// The markers (to keep them across restarts).
    pub fn markers(&self) -> &[Marker] {
        &self.markers
    }

    /// Number of markers.
    pub fn len(&self) -> usize {
        self.markers.len()
    }

    /// True when there is none.
    pub fn is_empty(&self) -> bool {
        self.markers.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn marker(id: u8, newest_us: u64, relevant_until_us: u64) -> Marker {
        Marker {
            identity: Identity::of(b'T', &[id]),
            newest_us,
            relevant_until_us,
        }
    }

    #[test]
    fn an_older_version_of_an_accepted_identity_is_superseded() {
        let mut table = NewestTable::new();
        let original = marker(1, 100, 10_000);
        table.record(original, 100);
        // The cancel, generated later, relevant for less time than the original.
        table.record(marker(1, 200, 1_000), 200);
        assert!(table.is_superseded(&original.identity, 100));
        assert!(!table.is_superseded(&original.identity, 200));
        assert!(!table.is_superseded(&marker(2, 0, 0).identity, 100));
        // Kept while the original could be relevant, then forgotten.
        table.record(marker(3, 5_000, 6_000), 9_999);
        assert!(table.is_superseded(&original.identity, 100));
        table.record(marker(3, 5_000, 6_000), 5_000);
        table.record(marker(4, 10_001, 20_000), 10_001);
        assert!(!table.is_superseded(&original.identity, 100));
    }

    #[test]
    fn kinds_do_not_share_identities_and_a_full_table_drops_what_ends_soonest() {
        assert_ne!(Identity::of(b'T', &[1]), Identity::of(b'M', &[1]));
        let mut table = NewestTable::new();
        for n in 0..MAX_NEWEST as u64 {
            table.record(marker(n as u8, 10, 1_000 + n), 0);
        }
        table.record(marker(250, 10, 5_000), 0);
        assert_eq!(table.len(), MAX_NEWEST);
        assert!(!table.is_superseded(&marker(0, 0, 0).identity, 5));
        assert!(table.is_superseded(&marker(1, 0, 0).identity, 5));
    }
}
