//! The UPER bit writer (ITU-T X.691, unaligned variant).
//!
//! A writer either fills a caller buffer or only counts bits (to learn an encoding's size
//! without writing it). Panic contract: no method panics; a write that would not fit fails
//! with [`EncodeErrorKind::BufferTooSmall`] and leaves the bits already written in place.
//!
//! Invariant: every bit of the buffer after the write position, inside the byte that holds
//! it, is zero. Bytes are zeroed when the writer enters them, so the caller's buffer does not
//! need to be cleared.

use super::error::{EncodeError, EncodeErrorKind as Kind};

/// Result of the encoding primitives.
pub type EncodeResult<T = ()> = Result<T, EncodeError>;

/// Writes bit fields into a byte buffer, most significant bit first.
#[derive(Debug)]
pub struct Writer<'a> {
    buf: &'a mut [u8],
    pos: usize,
    counting: bool,
}

impl<'a> Writer<'a> {
    /// A writer that fills `buf` from its first bit.
    pub fn new(buf: &'a mut [u8]) -> Self {
        Self {
            buf,
            pos: 0,
            counting: false,
        }
    }

    /// A writer that writes nothing and only counts bits.
    pub fn counter() -> Writer<'static> {
        Writer {
            buf: &mut [],
            pos: 0,
            counting: true,
        }
    }

    /// Bits written so far.
    #[inline]
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Whole octets needed for what was written (at least one, as for a complete encoding).
    pub fn octets(&self) -> usize {
        self.pos.div_ceil(8).max(1)
    }

    #[inline]
    fn reserve(&self, bits: usize) -> EncodeResult {
        if !self.counting && self.pos + bits > self.buf.len() * 8 {
            return Err(EncodeError::new(Kind::BufferTooSmall));
        }
        Ok(())
    }

    /// Writes one bit.
    #[inline]
    pub fn write_bit(&mut self, bit: bool) -> EncodeResult {
        self.write_bits(bit as u64, 1)
    }

    /// Writes the low `n` bits (at most 64) of `value`, most significant first.
    #[inline(always)]
    pub fn write_bits(&mut self, value: u64, n: u32) -> EncodeResult {
        // Fast path (inlined): n <= 56 and 8 bytes of room from the current byte; merge into
        // one big-endian word (the bytes after the value are zeroed, as the invariant allows).
        if !self.counting && n <= 56 {
            let used = (self.pos % 8) as u32;
            let byte = self.pos / 8;
            if let Some(dst) = self
                .buf
                .get_mut(byte..)
                .and_then(|s| s.first_chunk_mut::<8>())
            {
                let keep = ((dst[0] as u64) << 56) & !(u64::MAX >> used);
                let bits = value.checked_shl(64 - n).unwrap_or(0) >> used;
                *dst = (keep | bits).to_be_bytes();
                self.pos += n as usize;
                return Ok(());
            }
        }
        self.write_bits_slow(value, n)
    }

    /// [`Self::write_bits`] when counting, for wide values and near the end of the buffer.
    #[inline(never)]
    fn write_bits_slow(&mut self, value: u64, n: u32) -> EncodeResult {
        self.reserve(n as usize)?;
        let byte = self.pos / 8;
        if !self.counting && n <= 56 && byte + 8 <= self.buf.len() {
            // Fast path: merge into one big-endian word; the bytes after the value are zeroed,
            // which the invariant allows (they lie past the write position).
            let used = (self.pos % 8) as u32;
            let keep = if used == 0 {
                0
            } else {
                (self.buf[byte] as u64 >> (8 - used)) << (64 - used)
            };
            let bits = if n == 0 {
                0
            } else {
                (value << (64 - n)) >> used
            };
            self.buf[byte..byte + 8].copy_from_slice(&(keep | bits).to_be_bytes());
            self.pos += n as usize;
            return Ok(());
        }
        if !self.counting {
            let mut left = n;
            while left > 0 {
                let byte = self.pos / 8;
                let used = (self.pos % 8) as u32;
                if used == 0 {
                    self.buf[byte] = 0;
                }
                let take = (8 - used).min(left);
                let bits = (value >> (left - take)) & ((1u64 << take) - 1);
                self.buf[byte] |= (bits << (8 - used - take)) as u8;
                self.pos += take as usize;
                left -= take;
            }
        } else {
            self.pos += n as usize;
        }
        Ok(())
    }

    /// Overwrites `n` bits at bit position `at` (already written) without moving on.
    fn put_at(&mut self, at: usize, value: u64, n: u32) {
        if self.counting {
            return;
        }
        for i in 0..n as usize {
            let bit = (value >> (n as usize - 1 - i)) & 1;
            let p = at + i;
            let mask = 0x80u8 >> (p % 8);
            if let Some(b) = self.buf.get_mut(p / 8) {
                *b = if bit == 1 { *b | mask } else { *b & !mask };
            }
        }
    }

    /// Writes octets.
    pub fn write_octets(&mut self, octets: &[u8]) -> EncodeResult {
        self.reserve(octets.len() * 8)?;
        if !self.counting && self.pos.is_multiple_of(8) {
            let start = self.pos / 8;
            self.buf[start..start + octets.len()].copy_from_slice(octets);
            self.pos += octets.len() * 8;
            return Ok(());
        }
        octets
            .iter()
            .try_for_each(|&b| self.write_bits(b as u64, 8))
    }

    /// A constrained whole number `value` in `lb..=ub` (minimal bit field).
    #[inline]
    pub fn write_constrained(&mut self, value: i64, lb: i64, ub: i64) -> EncodeResult {
        let range = ub.wrapping_sub(lb) as u64;
        let bits = 64 - range.leading_zeros();
        self.write_bits(value.wrapping_sub(lb) as u64, bits)
    }

    /// A constrained length in `lb..=ub` (ub < 64K); refuses a length outside the range.
    #[inline]
    pub fn write_constrained_len(&mut self, len: usize, lb: usize, ub: usize) -> EncodeResult {
        if len < lb || len > ub {
            return Err(EncodeError::new(Kind::SizeOutOfRange));
        }
        if lb == ub {
            return Ok(());
        }
        self.write_constrained(len as i64, lb as i64, ub as i64)
    }

    /// An unconstrained length determinant for a length below 16K (no fragment).
    pub fn write_length(&mut self, len: usize) -> EncodeResult {
        match len {
            0..=127 => self.write_bits(len as u64, 8),
            128..=16383 => self.write_bits(0x8000 | len as u64, 16),
            _ => Err(EncodeError::new(Kind::OpenTypeTooLarge)),
        }
    }

    /// A fragment header for `m` (1..=4) times 16K units.
    pub fn write_fragment_header(&mut self, m: u8) -> EncodeResult {
        self.write_bits(0xc0 | (m as u64 & 0x3f), 8)
    }

    /// A normally small non-negative whole number.
    pub fn write_normally_small(&mut self, value: u64) -> EncodeResult {
        if value < 64 {
            return self.write_bits(value, 7);
        }
        self.write_bit(true)?;
        self.write_semi_constrained(value as i64, 0)
    }

    /// A semi-constrained whole number `value >= lb`.
    pub fn write_semi_constrained(&mut self, value: i64, lb: i64) -> EncodeResult {
        let v = value.wrapping_sub(lb) as u64;
        let n = (64 - v.leading_zeros()).div_ceil(8).max(1);
        self.write_length(n as usize)?;
        self.write_bits(v, n * 8)
    }

    /// An unconstrained whole number (two's complement, fewest octets).
    pub fn write_unconstrained(&mut self, value: i64) -> EncodeResult {
        let mut n = 1u32;
        while n < 8 {
            let shift = 64 - 8 * n;
            if ((value << shift) >> shift) == value {
                break;
            }
            n += 1;
        }
        self.write_length(n as usize)?;
        self.write_bits(value as u64, n * 8)
    }

    /// Writes an open type: `content` writes the value, and this wraps it in a length
    /// determinant and pads it to whole octets (an empty value becomes one zero octet).
    /// Content of 16K octets or more is split into fragments (X.691 11.9.3.8).
    pub fn write_open<F>(&mut self, content: F) -> EncodeResult
    where
        F: FnOnce(&mut Self) -> EncodeResult,
    {
        let start = self.pos;
        self.write_bits(0, 8)?;
        let body = self.pos;
        content(self)?;
        let bits = self.pos - body;
        let octets = bits.div_ceil(8).max(1);
        self.write_bits(0, (octets * 8 - bits) as u32)?;
        match octets {
            0..=127 => self.put_at(start, octets as u64, 8),
            128..=16383 => {
                self.shift_octets(body, body + octets * 8, 1)?;
                self.put_at(start, 0x8000 | octets as u64, 16);
            }
            _ => self.fragment(start, octets)?,
        }
        Ok(())
    }

    /// Moves the bits `from..to` (whole octets of content) on by `by` octets, making room for
    /// length determinants before them; the write position moves on by `by` octets when
    /// `to` is the current end.
    fn shift_octets(&mut self, from: usize, to: usize, by: usize) -> EncodeResult {
        let at_end = to == self.pos;
        if at_end {
            self.reserve(by * 8)?;
        }
        if !self.counting && by > 0 {
            let first = from / 8;
            let last = to.div_ceil(8);
            self.buf.copy_within(first..last, first + by);
        }
        if at_end {
            self.pos += by * 8;
        }
        Ok(())
    }

    /// Rewrites `octets` (>= 16K) of content written after a one-octet placeholder at `start`
    /// as fragments: each header and the final length are inserted by whole-octet moves,
    /// last segment first.
    fn fragment(&mut self, start: usize, octets: usize) -> EncodeResult {
        // (header value, header bits, content octets) per segment.
        let mut segs: heapless::Vec<(u64, u32, usize), 8> = heapless::Vec::new();
        let mut left = octets;
        while left >= 16384 {
            let m = (left / 16384).min(4);
            segs.push((0xc0 | m as u64, 8, m * 16384))
                .map_err(|_| EncodeError::new(Kind::OpenTypeTooLarge))?;
            left -= m * 16384;
        }
        let last = if left < 128 {
            (left as u64, 8, left)
        } else {
            (0x8000 | left as u64, 16, left)
        };
        segs.push(last)
            .map_err(|_| EncodeError::new(Kind::OpenTypeTooLarge))?;
        let header_octets: usize = segs.iter().map(|s| s.1 as usize / 8).sum();
        self.reserve((header_octets - 1) * 8)?;
        // Original content offset and final header position of each segment.
        let mut plan: heapless::Vec<(usize, usize, usize), 8> = heapless::Vec::new();
        let (mut orig, mut dest_hdr) = (start + 8, start);
        for &(_, hbits, n) in &segs {
            let _ = plan.push((orig, dest_hdr, n));
            orig += n * 8;
            dest_hdr += hbits as usize + n * 8;
        }
        let end = self.pos;
        for (i, &(orig, hdr, n)) in plan.iter().enumerate().rev() {
            let by = (hdr + segs[i].1 as usize - orig) / 8;
            let to = if i + 1 == plan.len() {
                end
            } else {
                orig + n * 8
            };
            if !self.counting && by > 0 {
                self.buf
                    .copy_within(orig / 8..to.div_ceil(8), orig / 8 + by);
            }
        }
        self.pos = end + (header_octets - 1) * 8;
        for (i, &(_, hdr, _)) in plan.iter().enumerate() {
            self.put_at(hdr, segs[i].0, segs[i].1);
        }
        Ok(())
    }

    /// Writes raw open-type content octets with their length determinant.
    pub fn write_open_octets(&mut self, octets: &[u8]) -> EncodeResult {
        self.write_length(octets.len())?;
        self.write_octets(octets)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;

    fn written(f: impl Fn(&mut Writer) -> EncodeResult) -> heapless::Vec<u8, 64> {
        let mut buf = [0xa5u8; 64];
        let mut w = Writer::new(&mut buf);
        f(&mut w).unwrap();
        let n = w.octets();
        let mut counter = Writer::counter();
        f(&mut counter).unwrap();
        assert_eq!(
            counter.position(),
            w.position(),
            "counting agrees with writing"
        );
        heapless::Vec::from_slice(&buf[..n]).unwrap()
    }

    #[test]
    fn writes_bits_over_a_dirty_buffer() {
        let out = written(|w| {
            w.write_bit(true)?;
            w.write_bits(0b010, 3)?;
            w.write_bits(0b1100_0101, 8)?;
            w.write_bits(0b0011, 4)
        });
        assert_eq!(&out[..], &[0b1010_1100, 0b0101_0011]);
    }

    #[test]
    fn constrained_and_lengths() {
        let out = written(|w| w.write_constrained(0, -900_000_000, 900_000_001));
        assert_eq!(&out[..], &(((900_000_000u32) << 1).to_be_bytes()));
        assert_eq!(&written(|w| w.write_length(288))[..], &[0x81, 0x20]);
        assert_eq!(
            &written(|w| w.write_normally_small(64))[..],
            &[0x80, 0xa0, 0x00]
        );
        assert_eq!(&written(|w| w.write_unconstrained(-1))[..], &[0x01, 0xff]);
        assert_eq!(
            &written(|w| w.write_unconstrained(128))[..],
            &[0x02, 0x00, 0x80]
        );
    }

    #[test]
    fn open_type_short_and_long() {
        // 3 bits of content, unaligned start: length 1, content padded.
        let out = written(|w| {
            w.write_bits(1, 1)?;
            w.write_open(|w| w.write_bits(0b101, 3))
        });
        assert_eq!(&out[..], &[0b1000_0000, 0b1101_0000, 0]);
        // 200 octets of content after a 3-bit prefix: two-octet length, content shifted.
        let mut buf = [0xffu8; 260];
        let mut w = Writer::new(&mut buf);
        w.write_bits(0b101, 3).unwrap();
        w.write_open(|w| (0..200u32).try_for_each(|i| w.write_bits(i as u64 & 0xff, 8)))
            .unwrap();
        w.write_bits(0b11, 2).unwrap();
        assert_eq!(w.position(), 3 + 16 + 1600 + 2);
        let mut r = super::super::reader::Reader::new(&buf);
        assert_eq!(r.read_bits(3).unwrap(), 0b101);
        let mut sub = r.read_open().unwrap();
        for i in 0..200u64 {
            assert_eq!(sub.read_bits(8).unwrap(), i & 0xff);
        }
        assert_eq!(r.read_bits(2).unwrap(), 0b11);
        assert_eq!(r.read_bits(3).unwrap(), 0, "padding is zero");
    }

    #[test]
    fn open_type_fragments() {
        // 3 prefix bits, then 40000 + 17 octets of content: headers C2 (32K), then a
        // two-octet length for the remaining 7249, all unaligned; then 2 more bits.
        for total in [16384usize, 40017, 65536 + 300] {
            let mut buf = vec_of(total + 16);
            let mut w = Writer::new(&mut buf);
            w.write_bits(0b101, 3).unwrap();
            w.write_open(|w| (0..total).try_for_each(|i| w.write_bits((i * 31 % 251) as u64, 8)))
                .unwrap();
            w.write_bits(0b11, 2).unwrap();
            let mut counter = Writer::counter();
            counter.write_bits(0b101, 3).unwrap();
            counter
                .write_open(|w| (0..total).try_for_each(|i| w.write_bits((i * 31 % 251) as u64, 8)))
                .unwrap();
            counter.write_bits(0b11, 2).unwrap();
            assert_eq!(counter.position(), w.position());
            let mut r = super::super::reader::Reader::new(&buf);
            assert_eq!(r.read_bits(3).unwrap(), 0b101);
            let mut seen = 0usize;
            loop {
                let part = r.read_length().unwrap();
                for _ in 0..part.len {
                    assert_eq!(
                        r.read_bits(8).unwrap(),
                        (seen * 31 % 251) as u64,
                        "octet {seen} of {total}"
                    );
                    seen += 1;
                }
                if !part.more {
                    break;
                }
            }
            assert_eq!(seen, total);
            assert_eq!(r.read_bits(2).unwrap(), 0b11);
        }
    }

    fn vec_of(n: usize) -> std::vec::Vec<u8> {
        std::vec![0x5a; n]
    }

    #[test]
    fn empty_open_type_is_one_zero_octet() {
        assert_eq!(&written(|w| w.write_open(|_| Ok(())))[..], &[0x01, 0x00]);
    }

    #[test]
    fn buffer_too_small_is_an_error() {
        let mut buf = [0u8; 1];
        let mut w = Writer::new(&mut buf);
        w.write_bits(0, 7).unwrap();
        assert_eq!(w.write_bits(0, 2).unwrap_err().kind, Kind::BufferTooSmall);
    }
}
