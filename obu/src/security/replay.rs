//! The replay check: signed messages accepted recently, by generation time and hash, in a
//! fixed window. A message older than the allowed skew fails the time check, so only the
//! last `2 * skew` matter; when the window is full the entry with the oldest generation
//! time leaves and becomes the floor: anything generated at or before it counts as a
//! replay, since the window can no longer tell.

use heapless::Vec;

use crate::capacity::MAX_REPLAY;

/// One accepted message: its generation time (`Time64`) and the first 8 octets of its
/// signature hash (two different messages of the same microsecond collide with
/// probability 2^-64).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Seen {
    generated_us: u64,
    tag: [u8; 8],
}

/// Recently accepted messages, at most [`MAX_REPLAY`].
#[derive(Debug, Clone)]
pub struct ReplayWindow {
    seen: Vec<Seen, MAX_REPLAY>,
    floor_us: Option<u64>,
}

impl Default for ReplayWindow {
    fn default() -> Self {
        Self::new()
    }
}

impl ReplayWindow {
    /// Nothing seen.
    pub const fn new() -> Self {
        Self {
            seen: Vec::new(),
            floor_us: None,
        }
    }

    /// Whether a message generated at `generated_us` with signature hash `digest` may be
    /// new (not seen, and above the floor).
    pub fn is_new(&self, generated_us: u64, digest: &[u8; 32]) -> bool {
        let seen = Seen {
            generated_us,
            tag: tag(digest),
        };
        self.floor_us.is_none_or(|floor| generated_us > floor) && !self.seen.contains(&seen)
    }

    /// Records an accepted message; entries generated before `oldest_us` (which the time
    /// check refuses anyway) are forgotten first.
    pub fn record(&mut self, generated_us: u64, digest: &[u8; 32], oldest_us: u64) {
        self.seen.retain(|s| s.generated_us >= oldest_us);
        if self.seen.is_full() {
            if let Some(i) = (0..self.seen.len()).min_by_key(|&i| self.seen[i].generated_us) {
                let gone = self.seen.swap_remove(i);
                self.floor_us = Some(
                    self.floor_us
                        .map_or(gone.generated_us, |f| f.max(gone.generated_us)),
                );
            }
        }
        let _ = self.seen.push(Seen {
            generated_us,
            tag: tag(digest),
        });
    }

    /// Number of messages remembered.
    pub fn len(&self) -> usize {
        self.seen.len()
    }

    /// True when nothing is remembered.
    pub fn is_empty(&self) -> bool {
        self.seen.is_empty()
    }
}

fn tag(digest: &[u8; 32]) -> [u8; 8] {
    let mut t = [0u8; 8];
    t.copy_from_slice(&digest[..8]);
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn digest(n: u32) -> [u8; 32] {
        let mut d = [0u8; 32];
        d[..4].copy_from_slice(&n.to_be_bytes());
        d
    }

    #[test]
    fn same_message_twice_is_a_replay() {
        let mut w = ReplayWindow::new();
        assert!(w.is_new(1_000, &digest(1)));
        w.record(1_000, &digest(1), 0);
        assert!(!w.is_new(1_000, &digest(1)));
        assert!(w.is_new(1_000, &digest(2)) && w.is_new(1_001, &digest(1)));
    }

    #[test]
    fn a_full_window_raises_its_floor() {
        let mut w = ReplayWindow::new();
        for n in 0..MAX_REPLAY as u64 + 1 {
            w.record(10 + n, &digest(n as u32), 0);
        }
        assert_eq!(w.len(), MAX_REPLAY);
        // Generation time 10 left the window: anything at or before it is refused.
        assert!(!w.is_new(10, &digest(9_999)) && !w.is_new(5, &digest(9_999)));
        assert!(w.is_new(11, &digest(9_999)));
        // Old entries are forgotten when the time check would refuse them anyway.
        w.record(100_000, &digest(7), 50_000);
        assert_eq!(w.len(), 1);
    }
}
