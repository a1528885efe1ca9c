//! Signed messages accepted and still relevant, by a tag of their signed bytes: a
//! byte-identical copy is found for the cost of a hash (no ECDSA) and is a repeat or a replay
//! as its profile says. Bounded: [`MAX_REPEATS`] entries, each forgotten when its message
//! stops being relevant (its expiry time, or its generation time plus the past window); when
//! the cache is full, the entry that ends soonest leaves. If it was of a replay profile its
//! generation time becomes that profile's floor: a copy generated at or before it can no
//! longer be told from a new message, and counts as a replay.

use heapless::Vec;

use crate::capacity::MAX_REPEATS;

/// One accepted message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Accepted {
    /// The first 16 octets of SHA-256 over the signing digest and the signature.
    tag: [u8; 16],
    /// Its generation time (`Time64`).
    generated_us: u64,
    /// When it stops being relevant (`Time64`).
    relevant_until_us: u64,
    /// Whether copies are replays (else repeats).
    replay: bool,
}

/// What [`RepeatCache::find`] knows of a signed message.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Seen {
    /// Not seen (or forgotten): verify it.
    New,
    /// Accepted before.
    Before,
}

/// Accepted signed messages that are still relevant, at most [`MAX_REPEATS`].
#[derive(Debug, Clone)]
pub struct RepeatCache {
    accepted: Vec<Accepted, MAX_REPEATS>,
    /// Replay profiles: the latest generation time of an entry that left while relevant.
    replay_floor_us: Option<u64>,
}

impl Default for RepeatCache {
    fn default() -> Self {
        Self::new()
    }
}

impl RepeatCache {
    /// Empty.
    pub const fn new() -> Self {
        Self {
            accepted: Vec::new(),
            replay_floor_us: None,
        }
    }

    /// Whether the message tagged `tag` (generated at `generated_us`, of a replay profile
    /// or not) was accepted before.
    pub fn find(&self, tag: &[u8; 16], generated_us: u64, replay: bool) -> Seen {
        let below_floor = replay && self.replay_floor_us.is_some_and(|f| generated_us <= f);
        if below_floor || self.accepted.iter().any(|a| &a.tag == tag) {
            Seen::Before
        } else {
            Seen::New
        }
    }

    /// Records an accepted message, relevant until `relevant_until_us`; entries no longer
    /// relevant at `now_us` are forgotten first.
    pub fn record(
        &mut self,
        tag: [u8; 16],
        generated_us: u64,
        relevant_until_us: u64,
        replay: bool,
        now_us: u64,
    ) {
        self.forget_before(now_us);
        if self.accepted.iter().any(|a| a.tag == tag) {
            return;
        }
        if self.accepted.is_full() {
            let soonest = (0..self.accepted.len()).min_by_key(|&i| {
                let a = &self.accepted[i];
                a.relevant_until_us
            });
            if let Some(i) = soonest {
                let gone = self.accepted.swap_remove(i);
                if gone.replay {
                    let floor = self
                        .replay_floor_us
                        .map_or(gone.generated_us, |f| f.max(gone.generated_us));
                    self.replay_floor_us = Some(floor);
                }
            }
        }
        let _ = self.accepted.push(Accepted {
            tag,
            generated_us,
            relevant_until_us,
            replay,
        });
    }

    /// Forgets every message no longer relevant at `now_us`.
    pub fn forget_before(&mut self, now_us: u64) {
        self.accepted.retain(|a| a.relevant_until_us >= now_us);
    }

    /// Number of messages remembered.
    pub fn len(&self) -> usize {
        self.accepted.len()
    }

    /// True when nothing is remembered.
    pub fn is_empty(&self) -> bool {
        self.accepted.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tag(n: u32) -> [u8; 16] {
        let mut t = [0u8; 16];
        t[..4].copy_from_slice(&n.to_be_bytes());
        t
    }

    #[test]
    fn an_accepted_message_is_found_until_it_stops_being_relevant() {
        let mut cache = RepeatCache::new();
        assert_eq!(cache.find(&tag(1), 10, false), Seen::New);
        cache.record(tag(1), 10, 1_000, false, 10);
        assert_eq!(cache.find(&tag(1), 10, false), Seen::Before);
        assert_eq!(cache.find(&tag(2), 10, false), Seen::New);
        cache.record(tag(1), 10, 1_000, false, 500);
        assert_eq!(cache.len(), 1);
        cache.forget_before(1_001);
        assert!(cache.is_empty());
    }

    #[test]
    fn a_full_cache_drops_what_ends_soonest_and_raises_the_replay_floor() {
        let mut cache = RepeatCache::new();
        for n in 0..MAX_REPEATS as u32 {
            // One replay-profile entry ends soonest.
            let (until, replay) = if n == 3 { (50, true) } else { (10_000, false) };
            cache.record(tag(n), 20 + u64::from(n), until, replay, 0);
        }
        assert_eq!(cache.len(), MAX_REPEATS);
        cache.record(tag(9_999), 100, 10_000, false, 0);
        assert_eq!(cache.len(), MAX_REPEATS);
        assert_eq!(cache.find(&tag(3), 23, false), Seen::New);
        // A replay-profile message generated at or before the one that left: refused.
        assert_eq!(cache.find(&tag(7_777), 23, true), Seen::Before);
        assert_eq!(cache.find(&tag(7_777), 24, true), Seen::New);
        // Repeat profiles have no floor: an old repeat is verified again.
        assert_eq!(cache.find(&tag(7_777), 5, false), Seen::New);
    }
}
