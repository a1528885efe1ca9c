//! Random valid values of every generated type, for property tests (feature `_random`).
//!
//! Values respect every constraint and stay small (at most a few items per list), so that
//! a random `MapData` encodes to a few hundred octets.

/// A small deterministic generator (SplitMix64).
#[derive(Clone, Debug)]
pub struct Gen {
    state: u64,
}

impl Gen {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A number in `lb..=ub`, often one of the bounds.
    pub fn range(&mut self, lb: i64, ub: i64) -> i64 {
        let span = ub.wrapping_sub(lb) as u64;
        match self.next_u64() % 8 {
            0 => lb,
            1 => ub,
            _ if span == u64::MAX => self.next_u64() as i64,
            _ => lb.wrapping_add((self.next_u64() % (span + 1)) as i64),
        }
    }

    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next_u64() % n as u64) as usize
        }
    }

    /// A fair coin.
    pub fn coin(&mut self) -> bool {
        self.next_u64() & 1 == 1
    }

    /// A list length in `lb..=ub`, at most 3 above `lb`.
    pub fn count(&mut self, lb: usize, ub: usize) -> usize {
        lb + self.below(ub.saturating_sub(lb).min(3) + 1)
    }

    /// A random octet.
    pub fn octet(&mut self) -> u8 {
        self.next_u64() as u8
    }

    /// A printable ASCII character.
    pub fn printable(&mut self) -> char {
        (b' ' + (self.next_u64() % 95) as u8) as char
    }
}

/// A type with random valid values.
pub trait Random {
    /// A random valid value.
    fn random(g: &mut Gen) -> Self;
}

impl Random for bool {
    fn random(g: &mut Gen) -> Self {
        g.coin()
    }
}

impl Random for super::Null {
    fn random(_: &mut Gen) -> Self {
        super::Null
    }
}
