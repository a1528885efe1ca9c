//! The UPER bit reader (ITU-T X.691, unaligned variant).
//!
//! Panic contract: no method panics on any input. Every read checks the bits that remain
//! first, and every length read from the input is compared with the bits that remain before
//! it is used, so a hostile length can never make the decoder read, loop or allocate beyond
//! the input.

use super::error::{DecodeError, DecodeErrorKind as Kind};

/// Result of the decoding primitives.
pub type DecodeResult<T> = Result<T, DecodeError>;

/// One length determinant as read from the input (X.691 11.9).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LengthChunk {
    /// Number of units (octets, bits, items or characters) in this chunk.
    pub len: usize,
    /// True when this chunk is a fragment (a multiple of 16K) and more chunks follow.
    pub more: bool,
}

/// The window around an open type's content, while [`Reader::enter_open`] has narrowed the
/// reader to it.
#[derive(Clone, Copy, Debug)]
pub(super) struct OpenWindow {
    content_end: usize,
    outer_end: usize,
}

/// Reads bit fields from a byte slice, most significant bit first.
///
/// The next bits of the window wait in a 64-bit cache (`acc`), refilled with one unaligned
/// 8-octet load when a read needs more than it holds, and never past the window's end: a
/// read of a field is then one compare with the bits cached and two shifts, and only a
/// refill looks at the input's length. A bounds check and a load per field cost twice the
/// instructions (a SPaT movement or a MAP node is a dozen short fields).
#[derive(Clone, Debug)]
pub struct Reader<'a> {
    data: &'a [u8],
    /// Bit position where this reader's window ends.
    end: usize,
    /// Bit position just past the cached bits: the position is `filled - cached`. A whole
    /// octet, except at `end`.
    filled: usize,
    /// The next `cached` bits, most significant first (the bits below them are the input's
    /// next bits, or zeros).
    acc: u64,
    /// How many bits `acc` holds, all of them before `end`.
    cached: u32,
}

/// The widest field one cached read takes: a refill leaves at least 56 bits in the cache
/// (unless the window ends first).
const CACHE_READ_MAX: u32 = 56;

impl<'a> Reader<'a> {
    /// A reader over all bits of `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Self {
            data,
            end: data.len().saturating_mul(8),
            filled: 0,
            acc: 0,
            cached: 0,
        }
    }

    /// Bit position from the start of the outermost input.
    #[inline]
    pub fn position(&self) -> usize {
        self.filled - self.cached as usize
    }

    /// Bits left before the end of this reader's window.
    #[inline]
    pub fn remaining(&self) -> usize {
        self.end - self.position()
    }

    #[inline]
    fn need(&self, bits: usize) -> DecodeResult<()> {
        if bits > self.remaining() {
            return Err(self.unexpected_end());
        }
        Ok(())
    }

    /// The error of a read past the window's end, at the current position.
    #[cold]
    fn unexpected_end(&self) -> DecodeError {
        DecodeError::new(Kind::UnexpectedEnd, self.position())
    }

    /// Moves to bit `pos` of the window, back or forth (the caller keeps it within the
    /// window: a position this reader was at, or one it checked with `need`).
    pub(super) fn seek(&mut self, pos: usize) {
        let used = (pos % 8) as u32;
        self.filled = pos - used as usize;
        self.acc = 0;
        self.cached = 0;
        if used != 0 {
            // `pos` is at most `end`, so the refill caches at least the `used` bits.
            self.refill();
            self.acc <<= used;
            self.cached -= used;
        }
    }

    /// Tops the cache up to 56-63 bits from the octets after it, or up to the window's end.
    /// Out of line: every read site stays a compare and two shifts (the firmware's flash),
    /// and a refill comes once per 7 octets.
    #[inline(never)]
    fn refill(&mut self) {
        let avail = self.end - self.filled;
        if avail == 0 {
            return;
        }
        // `filled` is a whole octet here: it is only ever unaligned at `end`.
        let next = self.filled / 8;
        let w = match self.data.get(next..).and_then(|s| s.first_chunk::<8>()) {
            Some(w) => u64::from_be_bytes(*w),
            None => self.window_tail(next),
        };
        // Whole octets up to 56-63 bits, or the bits before the end. The bits of `w` past
        // them are the input's next bits (or zeros) as the bits below `cached` already are:
        // the next refill ORs the same bits in again.
        let add = ((63 - self.cached) & !7).min(avail.min(64) as u32);
        self.acc |= w >> self.cached;
        self.cached += add;
        self.filled += add as usize;
    }

    /// The 8 octets from octet `start` in the data's last 7: the data's last 8 octets,
    /// shifted so that `start` leads and zeros follow the end. One load and a shift: a
    /// 40-octet BSM does a fifth of its refills here.
    #[inline(never)]
    fn window_tail(&self, start: usize) -> u64 {
        if let Some(last) = self.data.last_chunk::<8>() {
            let past = start + 8 - self.data.len();
            return if past < 8 {
                u64::from_be_bytes(*last) << (past * 8)
            } else {
                0
            };
        }
        let mut w = [0u8; 8];
        if let Some(src) = self.data.get(start..) {
            let n = src.len().min(8);
            w[..n].copy_from_slice(&src[..n]);
        }
        u64::from_be_bytes(w)
    }

    /// Reads `n` (at most 56) bits as an unsigned number.
    #[inline]
    fn take_short(&mut self, n: u32) -> DecodeResult<u64> {
        if self.cached < n {
            self.refill();
            if self.cached < n {
                return Err(self.unexpected_end());
            }
        }
        // Two shifts, so that `n = 0` reads 0 without a branch of its own.
        let v = (self.acc >> 1) >> (63 - n);
        self.acc <<= n;
        self.cached -= n;
        Ok(v)
    }

    /// Reads one bit.
    #[inline]
    pub fn read_bit(&mut self) -> DecodeResult<bool> {
        Ok(self.take_short(1)? == 1)
    }

    /// Reads `n` bits (at most 64) as an unsigned number, first bit most significant.
    #[inline]
    pub fn read_bits(&mut self, n: u32) -> DecodeResult<u64> {
        if n <= CACHE_READ_MAX {
            return self.take_short(n);
        }
        self.need(n as usize)?;
        let high = self.take_short(n - 32)?;
        Ok((high << 32) | self.take_short(32)?)
    }

    /// Skips `n` bits.
    pub fn skip(&mut self, n: usize) -> DecodeResult<()> {
        self.need(n)?;
        if n < self.cached as usize {
            // `n` < 64: within the cache.
            self.acc <<= n;
            self.cached -= n as u32;
        } else {
            self.seek(self.position() + n);
        }
        Ok(())
    }

    /// Fills `out` with the next `out.len()` octets.
    pub fn read_octets(&mut self, out: &mut [u8]) -> DecodeResult<()> {
        self.need(out.len().saturating_mul(8))?;
        let pos = self.position();
        if pos.is_multiple_of(8) {
            let start = pos / 8;
            out.copy_from_slice(&self.data[start..start + out.len()]);
            self.seek(pos + out.len() * 8);
        } else {
            // Unaligned: seven octets per read.
            for chunk in out.chunks_mut(7) {
                let bits = 8 * chunk.len() as u32;
                let v = self.take_short(bits)? << (64 - bits);
                chunk.copy_from_slice(&v.to_be_bytes()[..chunk.len()]);
            }
        }
        Ok(())
    }

    /// A constrained whole number in `lb..=ub` (X.691 11.5.7, UPER: minimal bit field).
    #[inline]
    pub fn read_constrained(&mut self, lb: i64, ub: i64) -> DecodeResult<i64> {
        let range = ub.wrapping_sub(lb) as u64;
        let bits = 64 - range.leading_zeros();
        let v = self.read_bits(bits)?;
        if v > range {
            return Err(self.error_before(Kind::ValueOutOfRange, bits));
        }
        Ok(lb.wrapping_add(v as i64))
    }

    /// The index of a CHOICE alternative or an ENUMERATED item among the `n` (at least 1) of
    /// the extension root (X.691 clauses 23 and 14): a bit field of the fewest bits; an index
    /// past them is an `invalid` error at the field.
    #[inline]
    pub fn read_index(&mut self, n: u64, invalid: Kind) -> DecodeResult<u64> {
        let bits = 64 - n.saturating_sub(1).leading_zeros();
        let v = self.read_bits(bits)?;
        if v >= n {
            return Err(self.error_before(invalid, bits));
        }
        Ok(v)
    }

    /// An error at the field of `bits` bits just read (its position is found only on the
    /// error path, not before every read).
    #[cold]
    fn error_before(&self, kind: Kind, bits: u32) -> DecodeError {
        DecodeError::new(kind, self.position() - bits as usize)
    }

    /// A constrained length in `lb..=ub` (ub < 64K): nothing when fixed, else a bit field.
    #[inline]
    pub fn read_constrained_len(&mut self, lb: usize, ub: usize) -> DecodeResult<usize> {
        if lb == ub {
            return Ok(lb);
        }
        let at = self.position();
        let v = self.read_constrained(lb as i64, ub as i64)?;
        usize::try_from(v).map_err(|_| DecodeError::new(Kind::SizeOutOfRange, at))
    }

    /// An unconstrained length determinant (X.691 11.9.3.5-8), possibly a fragment.
    pub fn read_length(&mut self) -> DecodeResult<LengthChunk> {
        let at = self.position();
        if !self.read_bit()? {
            return Ok(LengthChunk {
                len: self.read_bits(7)? as usize,
                more: false,
            });
        }
        if !self.read_bit()? {
            return Ok(LengthChunk {
                len: self.read_bits(14)? as usize,
                more: false,
            });
        }
        let m = self.read_bits(6)? as usize;
        if !(1..=4).contains(&m) {
            return Err(DecodeError::new(Kind::LengthTooLarge, at));
        }
        Ok(LengthChunk {
            len: m * 16384,
            more: true,
        })
    }

    /// A normally small non-negative whole number (X.691 11.6).
    pub fn read_normally_small(&mut self) -> DecodeResult<u64> {
        if !self.read_bit()? {
            return self.read_bits(6);
        }
        self.read_semi_constrained(0).map(|v| v as u64)
    }

    /// Reads the `len`-octet big-endian magnitude of a semi-/unconstrained number.
    fn read_magnitude(&mut self, at: usize) -> DecodeResult<(u64, usize)> {
        let chunk = self.read_length()?;
        if chunk.more || chunk.len == 0 || chunk.len > 8 {
            return Err(DecodeError::new(Kind::LengthTooLarge, at));
        }
        Ok((self.read_bits(chunk.len as u32 * 8)?, chunk.len))
    }

    /// A semi-constrained whole number `>= lb` (X.691 11.7), up to 64 bits.
    pub fn read_semi_constrained(&mut self, lb: i64) -> DecodeResult<i64> {
        let at = self.position();
        let (v, _) = self.read_magnitude(at)?;
        let v = i64::try_from(v).map_err(|_| DecodeError::new(Kind::ValueOutOfRange, at))?;
        lb.checked_add(v)
            .ok_or(DecodeError::new(Kind::ValueOutOfRange, at))
    }

    /// An unconstrained whole number (X.691 11.8): two's complement octets.
    pub fn read_unconstrained(&mut self) -> DecodeResult<i64> {
        let at = self.position();
        let (v, n) = self.read_magnitude(at)?;
        let shift = 64 - 8 * n as u32;
        Ok(((v << shift) as i64) >> shift)
    }

    /// Opens the content of an open type (X.691 11.2): a length in octets, then a reader
    /// limited to those octets. `self` moves past them.
    pub fn read_open(&mut self) -> DecodeResult<Reader<'a>> {
        let window = self.enter_open()?;
        let sub = self.clone();
        self.close_open(window);
        Ok(sub)
    }

    /// Opens the content of an open type in place, as [`Self::read_open`] does in a new
    /// reader: this reader's window narrows to the content until [`Self::close_open`]. Two
    /// positions to keep, not a second reader: open types nest (a frame's message, a regional
    /// extension in it), and every level is on the firmware's stack.
    pub(super) fn enter_open(&mut self) -> DecodeResult<OpenWindow> {
        let at = self.position();
        let chunk = self.read_length()?;
        if chunk.more {
            return Err(DecodeError::new(Kind::FragmentedOpenType, at));
        }
        let bits = chunk.len * 8;
        self.need(bits)?;
        let window = OpenWindow {
            content_end: self.position() + bits,
            outer_end: self.end,
        };
        self.end = window.content_end;
        if self.filled > self.end {
            // The cache starts before the end: less than its 64 bits are past it.
            self.cached -= (self.filled - self.end) as u32;
            self.filled = self.end;
        }
        Ok(window)
    }

    /// Leaves the content opened by [`Self::enter_open`] (at its end, whatever was read of
    /// it) for the window around it.
    pub(super) fn close_open(&mut self, window: OpenWindow) {
        self.end = window.outer_end;
        self.seek(window.content_end);
    }

    /// Checks that an open type's content was used up, but for at most 7 padding bits.
    pub fn finish_open(&self) -> DecodeResult<()> {
        if self.remaining() >= 8 {
            return Err(DecodeError::new(
                Kind::OpenTypeLengthMismatch,
                self.position(),
            ));
        }
        Ok(())
    }

    /// The octets of this reader's window from the current position, when it is aligned
    /// to an octet of the input; `None` otherwise.
    pub fn rest_if_aligned(&self) -> Option<&'a [u8]> {
        let pos = self.position();
        if !pos.is_multiple_of(8) || !self.end.is_multiple_of(8) {
            return None;
        }
        self.data.get(pos / 8..self.end / 8)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_bits_across_bytes() {
        let mut r = Reader::new(&[0b1010_1100, 0b0101_0011, 0xff]);
        assert!(r.read_bit().unwrap());
        assert_eq!(r.read_bits(3).unwrap(), 0b010);
        assert_eq!(r.read_bits(8).unwrap(), 0b1100_0101);
        assert_eq!(r.read_bits(12).unwrap(), 0b0011_1111_1111);
        assert_eq!(r.remaining(), 0);
        assert_eq!(r.read_bit().unwrap_err().kind, Kind::UnexpectedEnd);
    }

    #[test]
    fn reads_64_bits() {
        let data = [0x80, 1, 2, 3, 4, 5, 6, 7, 0xff];
        let mut r = Reader::new(&data);
        r.skip(4).unwrap();
        assert_eq!(r.read_bits(64).unwrap(), 0x0010_2030_4050_607f);
    }

    #[test]
    fn constrained_whole_numbers() {
        // Latitude -900000000..900000001 needs 31 bits; value 0 is offset 900000000.
        let v: u64 = 900_000_000 << 1;
        let bytes = (v as u32).to_be_bytes();
        let mut r = Reader::new(&bytes);
        assert_eq!(r.read_constrained(-900_000_000, 900_000_001).unwrap(), 0);
        // 0..=5 in 3 bits: 7 is out of range.
        let mut r = Reader::new(&[0b1110_0000]);
        assert_eq!(
            r.read_constrained(0, 5).unwrap_err().kind,
            Kind::ValueOutOfRange
        );
        // A single-value range takes no bits.
        let mut r = Reader::new(&[]);
        assert_eq!(r.read_constrained(7, 7).unwrap(), 7);
    }

    #[test]
    fn length_determinants() {
        let mut r = Reader::new(&[0x05]);
        assert_eq!(
            r.read_length().unwrap(),
            LengthChunk {
                len: 5,
                more: false
            }
        );
        let mut r = Reader::new(&[0x81, 0x20]);
        assert_eq!(
            r.read_length().unwrap(),
            LengthChunk {
                len: 288,
                more: false
            }
        );
        let mut r = Reader::new(&[0xc2]);
        assert_eq!(
            r.read_length().unwrap(),
            LengthChunk {
                len: 32768,
                more: true
            }
        );
        let mut r = Reader::new(&[0xc5]);
        assert_eq!(r.read_length().unwrap_err().kind, Kind::LengthTooLarge);
    }

    #[test]
    fn normally_small_and_semi_constrained() {
        let mut r = Reader::new(&[0b0000_0110]);
        assert_eq!(r.read_normally_small().unwrap(), 3);
        // 1, then length 1 (8 bits), then 0x40 = 64.
        let mut r = Reader::new(&[0b1000_0000, 0b1010_0000, 0]);
        assert_eq!(r.read_normally_small().unwrap(), 64);
        let mut r = Reader::new(&[0x01, 0xff]);
        assert_eq!(r.read_unconstrained().unwrap(), -1);
        let mut r = Reader::new(&[0x02, 0x00, 0x80]);
        assert_eq!(r.read_unconstrained().unwrap(), 128);
    }

    #[test]
    fn open_type_window_is_bounded() {
        // Length 2, two content octets, then one more octet outside the window.
        let mut r = Reader::new(&[0x02, 0xab, 0xcd, 0xef]);
        let mut sub = r.read_open().unwrap();
        assert_eq!(sub.read_bits(16).unwrap(), 0xabcd);
        assert!(sub.read_bit().is_err());
        assert_eq!(r.read_bits(8).unwrap(), 0xef);
        // A length beyond the input is refused before anything is read.
        let mut r = Reader::new(&[0x7f, 0x00]);
        assert_eq!(r.read_open().unwrap_err().kind, Kind::UnexpectedEnd);
    }

    #[test]
    fn reads_in_the_last_bytes_see_zeros_past_the_end() {
        // 10 bytes: reads starting in the last 7 take the data's last 8 bytes, shifted.
        let data = [0u8, 1, 2, 3, 4, 5, 6, 7, 8, 0x9f];
        for start in 0..data.len() {
            let mut r = Reader::new(&data);
            r.skip(start * 8 + 1).unwrap();
            let mut expect = [0u8; 8];
            let n = (data.len() - start).min(8);
            expect[..n].copy_from_slice(&data[start..start + n]);
            let bits = (r.remaining()).min(57) as u32;
            let want = (u64::from_be_bytes(expect) << 1) >> (64 - bits);
            assert_eq!(r.read_bits(bits).unwrap(), want, "from byte {start}");
        }
        // Shorter than 8 bytes.
        let mut r = Reader::new(&[0xab, 0xcd, 0xef]);
        r.skip(4).unwrap();
        assert_eq!(r.read_bits(20).unwrap(), 0xbcdef);
    }

    /// The bits of `data` from `from`, `n` of them, one at a time (the model of a read).
    fn bits_of(data: &[u8], from: usize, n: u32) -> u64 {
        (0..n as usize).fold(0, |v, i| {
            let bit = from + i;
            (v << 1) | u64::from(data[bit / 8] >> (7 - bit % 8) & 1)
        })
    }

    #[test]
    fn cached_reads_agree_with_a_bit_at_a_time_model() {
        // Pseudo-random data and reads (a fixed LCG): widths 0-64, skips that stay in the
        // cache and that leave it, octet runs aligned and not, and reads past the end.
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = move |m: u64| {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (seed >> 33) % m
        };
        for len in [0usize, 1, 7, 8, 9, 23, 64] {
            let data: std::vec::Vec<u8> = (0..len).map(|_| next(256) as u8).collect();
            let mut r = Reader::new(&data);
            let mut pos = 0usize;
            for _ in 0..400 {
                let left = len * 8 - pos;
                assert_eq!((r.position(), r.remaining()), (pos, left));
                match next(4) {
                    0 | 1 => {
                        let n = next(65) as u32;
                        match r.read_bits(n) {
                            Ok(v) => {
                                assert_eq!(v, bits_of(&data, pos, n), "{n} bits at {pos}");
                                pos += n as usize;
                            }
                            Err(e) => {
                                assert!(n as usize > left);
                                assert_eq!((e.kind, e.bit as usize), (Kind::UnexpectedEnd, pos));
                            }
                        }
                    }
                    2 => {
                        let n = next(80) as usize;
                        if r.skip(n).is_ok() {
                            pos += n;
                        } else {
                            assert!(n > left);
                        }
                    }
                    _ => {
                        let mut out = [0u8; 10];
                        let k = next(11) as usize;
                        if r.read_octets(&mut out[..k]).is_ok() {
                            for (i, o) in out[..k].iter().enumerate() {
                                assert_eq!(u64::from(*o), bits_of(&data, pos + 8 * i, 8));
                            }
                            pos += 8 * k;
                        } else {
                            assert!(8 * k > left);
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn an_open_window_ends_inside_the_parents_cache() {
        // 3 bits, then an open type of 2 octets at an unaligned position, then 9 bits: the
        // parent's cache holds bits past the content when the window opens.
        let data = [
            0b1010_0000,
            0b0101_1001,
            0b1001_1110,
            0b0001_0101,
            0b0101_0000,
        ];
        let mut r = Reader::new(&data);
        assert_eq!(r.read_bits(3).unwrap(), 0b101);
        let mut sub = r.read_open().unwrap();
        assert_eq!(sub.remaining(), 16);
        assert_eq!(sub.read_bits(5).unwrap(), bits_of(&data, 11, 5));
        assert_eq!(sub.read_bits(11).unwrap(), bits_of(&data, 16, 11));
        assert_eq!(sub.read_bit().unwrap_err().bit, 27);
        sub.finish_open().unwrap();
        assert_eq!(r.position(), 27);
        assert_eq!(r.read_bits(9).unwrap(), bits_of(&data, 27, 9));
    }

    #[test]
    fn an_index_past_the_alternatives_is_the_kind_asked_for_at_the_field() {
        // 5 alternatives take 3 bits: 0b100 = 4 is the last, 0b101 = 5 is past them.
        let mut r = Reader::new(&[0b0100_1010]);
        assert!(r.read_bit().is_ok());
        assert_eq!(r.read_index(5, Kind::InvalidChoiceIndex).unwrap(), 4);
        let e = r.read_index(5, Kind::InvalidEnumIndex).unwrap_err();
        assert_eq!((e.kind, e.bit), (Kind::InvalidEnumIndex, 4));
        // One alternative takes no bits.
        assert_eq!(r.read_index(1, Kind::InvalidEnumIndex).unwrap(), 0);
    }

    #[test]
    fn unaligned_octets() {
        let mut r = Reader::new(&[0x0a, 0xbc, 0xd0]);
        r.skip(4).unwrap();
        let mut out = [0u8; 2];
        r.read_octets(&mut out).unwrap();
        assert_eq!(out, [0xab, 0xcd]);
    }
}
