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

/// Reads bit fields from a byte slice, most significant bit first.
#[derive(Clone, Debug)]
pub struct Reader<'a> {
    data: &'a [u8],
    pos: usize,
    end: usize,
}

impl<'a> Reader<'a> {
    /// A reader over all bits of `data`.
    pub fn new(data: &'a [u8]) -> Self {
        Self {
            data,
            pos: 0,
            end: data.len().saturating_mul(8),
        }
    }

    /// Bit position from the start of the outermost input.
    #[inline]
    pub fn position(&self) -> usize {
        self.pos
    }

    /// Bits left before the end of this reader's window.
    #[inline]
    pub fn remaining(&self) -> usize {
        self.end - self.pos
    }

    #[inline]
    fn need(&self, bits: usize) -> DecodeResult<()> {
        if bits > self.remaining() {
            return Err(DecodeError::new(Kind::UnexpectedEnd, self.pos));
        }
        Ok(())
    }

    /// The 64 bits starting at the byte that holds `self.pos`, zero-padded past the data.
    #[inline(always)]
    fn window(&self) -> u64 {
        let start = self.pos / 8;
        // Fast path: 8 whole bytes remain, one unaligned load (no call to memcpy).
        if let Some(w) = self.data.get(start..).and_then(|s| s.first_chunk::<8>()) {
            return u64::from_be_bytes(*w);
        }
        self.window_tail()
    }

    /// [`Self::window`] in the last 7 bytes of the data: the data's last 8 bytes, shifted so
    /// that `start` leads and zeros follow the end. One load and a shift: a 40-octet BSM does
    /// a fifth of its reads here, and a copy into a zeroed buffer cost a third of its decode
    /// time. Out of line, so that every read site stays small (the firmware's flash).
    #[inline(never)]
    fn window_tail(&self) -> u64 {
        let start = self.pos / 8;
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

    /// Reads `n` (at most 57) bits as an unsigned number; the caller checked `need(n)`.
    #[inline]
    fn take_short(&mut self, n: u32) -> u64 {
        if n == 0 {
            return 0;
        }
        let v = (self.window() << (self.pos % 8)) >> (64 - n);
        self.pos += n as usize;
        v
    }

    /// Reads one bit.
    #[inline]
    pub fn read_bit(&mut self) -> DecodeResult<bool> {
        self.need(1)?;
        Ok(self.take_short(1) == 1)
    }

    /// Reads `n` bits (at most 64) as an unsigned number, first bit most significant.
    #[inline]
    pub fn read_bits(&mut self, n: u32) -> DecodeResult<u64> {
        self.need(n as usize)?;
        if n <= 57 {
            return Ok(self.take_short(n));
        }
        let high = self.take_short(n - 32);
        Ok((high << 32) | self.take_short(32))
    }

    /// Skips `n` bits.
    pub fn skip(&mut self, n: usize) -> DecodeResult<()> {
        self.need(n)?;
        self.pos += n;
        Ok(())
    }

    /// Fills `out` with the next `out.len()` octets.
    pub fn read_octets(&mut self, out: &mut [u8]) -> DecodeResult<()> {
        self.need(out.len().saturating_mul(8))?;
        if self.pos.is_multiple_of(8) {
            let start = self.pos / 8;
            out.copy_from_slice(&self.data[start..start + out.len()]);
            self.pos += out.len() * 8;
        } else {
            // Unaligned: seven octets per read.
            for chunk in out.chunks_mut(7) {
                let bits = 8 * chunk.len() as u32;
                let v = self.take_short(bits) << (64 - bits);
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
        let at = self.pos;
        let v = self.read_bits(bits)?;
        if v > range {
            return Err(DecodeError::new(Kind::ValueOutOfRange, at));
        }
        Ok(lb.wrapping_add(v as i64))
    }

    /// A constrained length in `lb..=ub` (ub < 64K): nothing when fixed, else a bit field.
    #[inline]
    pub fn read_constrained_len(&mut self, lb: usize, ub: usize) -> DecodeResult<usize> {
        if lb == ub {
            return Ok(lb);
        }
        let at = self.pos;
        let v = self.read_constrained(lb as i64, ub as i64)?;
        usize::try_from(v).map_err(|_| DecodeError::new(Kind::SizeOutOfRange, at))
    }

    /// An unconstrained length determinant (X.691 11.9.3.5-8), possibly a fragment.
    pub fn read_length(&mut self) -> DecodeResult<LengthChunk> {
        let at = self.pos;
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
        let at = self.pos;
        let (v, _) = self.read_magnitude(at)?;
        let v = i64::try_from(v).map_err(|_| DecodeError::new(Kind::ValueOutOfRange, at))?;
        lb.checked_add(v)
            .ok_or(DecodeError::new(Kind::ValueOutOfRange, at))
    }

    /// An unconstrained whole number (X.691 11.8): two's complement octets.
    pub fn read_unconstrained(&mut self) -> DecodeResult<i64> {
        let at = self.pos;
        let (v, n) = self.read_magnitude(at)?;
        let shift = 64 - 8 * n as u32;
        Ok(((v << shift) as i64) >> shift)
    }

    /// Opens the content of an open type (X.691 11.2): a length in octets, then a reader
    /// limited to those octets. `self` moves past them.
    pub fn read_open(&mut self) -> DecodeResult<Reader<'a>> {
        let at = self.pos;
        let chunk = self.read_length()?;
        if chunk.more {
            return Err(DecodeError::new(Kind::FragmentedOpenType, at));
        }
        let bits = chunk.len * 8;
        self.need(bits)?;
        let sub = Reader {
            data: self.data,
            pos: self.pos,
            end: self.pos + bits,
        };
        self.pos += bits;
        Ok(sub)
    }

    /// Checks that an open type's content was used up, but for at most 7 padding bits.
    pub fn finish_open(&self) -> DecodeResult<()> {
        if self.remaining() >= 8 {
            return Err(DecodeError::new(Kind::OpenTypeLengthMismatch, self.pos));
        }
        Ok(())
    }

    /// The octets of this reader's window from the current position, when it is aligned
    /// to an octet of the input; `None` otherwise.
    pub fn rest_if_aligned(&self) -> Option<&'a [u8]> {
        if !self.pos.is_multiple_of(8) || !self.end.is_multiple_of(8) {
            return None;
        }
        self.data.get(self.pos / 8..self.end / 8)
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

    #[test]
    fn unaligned_octets() {
        let mut r = Reader::new(&[0x0a, 0xbc, 0xd0]);
        r.skip(4).unwrap();
        let mut out = [0u8; 2];
        r.read_octets(&mut out).unwrap();
        assert_eq!(out, [0xab, 0xcd]);
    }
}
