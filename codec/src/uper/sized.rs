//! Values with a SIZE constraint: SEQUENCE OF, OCTET STRING, BIT STRING, IA5String.
//!
//! One routine reads or writes the length part for all of them (X.691 11.9 and 16-20,
//! 22 and 30): no length for a fixed size below 64K, a constrained bit field for a bounded
//! size, and the unconstrained length determinant with 16K fragments otherwise or when an
//! extensible size lies outside its root. Counts are checked against the no-heap capacity
//! before any item is stored, and items are taken one at a time (with `alloc`, at most 64
//! reserved ahead), so a hostile length costs no more than the bits that follow it.

use super::error::{DecodeError, DecodeErrorKind as DKind, EncodeError, EncodeErrorKind as EKind};
use super::reader::{DecodeResult, Reader};
use super::storage::{Bits, Ia5, Octets, SeqOf};
use super::writer::{EncodeResult, Writer};
use super::Uper;

/// Sizes at or above this use the unconstrained length determinant.
const K64: usize = 65536;
/// One fragment unit (X.691 11.9.3.8).
const K16: usize = 16384;
/// The most slots a SEQUENCE OF makes ahead of its decoded items (with `alloc`).
#[cfg(feature = "alloc")]
const RESERVE_ITEMS: usize = 64;

/// A SIZE constraint: `lb..=ub`, `ub == usize::MAX` when there is no upper bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    /// Lower bound of the root.
    pub lb: usize,
    /// Upper bound of the root (`usize::MAX`: unbounded).
    pub ub: usize,
    /// True when the constraint has an extension marker (`SIZE(lb..ub, ...)`).
    pub extensible: bool,
}

impl Size {
    /// `SIZE(lb..ub)`.
    pub const fn range(lb: usize, ub: usize) -> Self {
        Self {
            lb,
            ub,
            extensible: false,
        }
    }

    /// `SIZE(lb..ub, ...)`.
    pub const fn extensible(lb: usize, ub: usize) -> Self {
        Self {
            lb,
            ub,
            extensible: true,
        }
    }

    const fn in_root(&self, n: usize) -> bool {
        n >= self.lb && n <= self.ub
    }

    const fn constrained(&self) -> bool {
        self.ub < K64
    }
}

/// Reads the length part of a sized value and calls `chunk(r, n)` for each run of `n`
/// units (one run, or several for fragments). Returns the total count.
pub fn read_sized<'a, F>(r: &mut Reader<'a>, size: Size, mut chunk: F) -> DecodeResult<usize>
where
    F: FnMut(&mut Reader<'a>, usize) -> DecodeResult<()>,
{
    let at = r.position();
    let in_ext = size.extensible && r.read_bit()?;
    if !in_ext && size.constrained() {
        let n = r.read_constrained_len(size.lb, size.ub)?;
        chunk(r, n)?;
        return Ok(n);
    }
    let mut total = 0usize;
    loop {
        let part = r.read_length()?;
        chunk(r, part.len)?;
        total += part.len;
        if !part.more {
            break;
        }
    }
    if !in_ext && !size.in_root(total) {
        return Err(DecodeError::new(DKind::SizeOutOfRange, at));
    }
    Ok(total)
}

/// Writes the length part of a sized value of `n` units and calls `chunk(w, start, len)`
/// for each run of units.
pub fn write_sized<F>(w: &mut Writer<'_>, size: Size, n: usize, mut chunk: F) -> EncodeResult
where
    F: FnMut(&mut Writer<'_>, usize, usize) -> EncodeResult,
{
    let in_root = size.in_root(n);
    if size.extensible {
        w.write_bit(!in_root)?;
    } else if !in_root {
        return Err(EncodeError::new(EKind::SizeOutOfRange));
    }
    if in_root && size.constrained() {
        w.write_constrained_len(n, size.lb, size.ub)?;
        return chunk(w, 0, n);
    }
    let mut start = 0;
    loop {
        let left = n - start;
        if left < K16 {
            w.write_length(left)?;
            chunk(w, start, left)?;
            return Ok(());
        }
        let m = (left / K16).min(4);
        w.write_fragment_header(m as u8)?;
        chunk(w, start, m * K16)?;
        start += m * K16;
    }
}

#[cold]
fn over_capacity(at: usize, key: &'static str) -> DecodeError {
    DecodeError::at(DKind::CapacityExceeded, at, key)
}

/// Decodes a SEQUENCE OF into `out`, reusing its items' storage; `key` names the capacity
/// in errors.
pub fn decode_seq_of_into<T: Uper, const N: usize, const I: usize>(
    r: &mut Reader<'_>,
    size: Size,
    key: &'static str,
    out: &mut SeqOf<T, N, I>,
) -> DecodeResult<()> {
    out.clear();
    read_sized(r, size, |r, n| {
        if out.len() + n > SeqOf::<T, N, I>::capacity() {
            return Err(over_capacity(r.position(), key));
        }
        // With `alloc`: the announced items in runs of at most RESERVE_ITEMS slots, each run
        // made at once (new placeholders written in place, not copied in one by one; former
        // items kept) and decoded before the next, so that one hostile length makes little
        // room ahead of the input that fills it.
        #[cfg(feature = "alloc")]
        {
            let mut left = n;
            while left > 0 {
                let run = left.min(r.remaining().max(1)).min(RESERVE_ITEMS);
                let slots = out
                    .grow_decoding(run)
                    .ok_or(over_capacity(r.position(), key))?;
                for slot in slots {
                    T::decode_into(r, slot)?;
                }
                left -= run;
            }
        }
        // Without it the slots live in the fixed room: one at a time is the shorter code
        // (the firmware's flash) and measured faster for a kept value.
        #[cfg(not(feature = "alloc"))]
        for _ in 0..n {
            let slot = out.push_slot().ok_or(over_capacity(r.position(), key))?;
            T::decode_into(r, slot)?;
        }
        Ok(())
    })?;
    out.drop_spare();
    Ok(())
}

/// Encodes a SEQUENCE OF.
pub fn encode_seq_of<T: Uper>(w: &mut Writer<'_>, size: Size, items: &[T]) -> EncodeResult {
    write_sized(w, size, items.len(), |w, start, n| {
        items[start..start + n]
            .iter()
            .try_for_each(|it| it.encode_uper(w))
    })
}

/// Decodes a variable OCTET STRING into `out`.
pub fn decode_octets_into<const N: usize>(
    r: &mut Reader<'_>,
    size: Size,
    key: &'static str,
    out: &mut Octets<N>,
) -> DecodeResult<()> {
    out.clear();
    read_sized(r, size, |r, n| read_octets_into(r, n, out, key))?;
    Ok(())
}

/// Appends `n` octets from `r` to `out`.
pub fn read_octets_into<const N: usize>(
    r: &mut Reader<'_>,
    n: usize,
    out: &mut Octets<N>,
    key: &'static str,
) -> DecodeResult<()> {
    if out.len() + n > Octets::<N>::capacity() {
        return Err(over_capacity(r.position(), key));
    }
    if n.saturating_mul(8) > r.remaining() {
        return Err(DecodeError::new(DKind::UnexpectedEnd, r.position()));
    }
    let slots = out
        .grow_decoding(n)
        .ok_or(over_capacity(r.position(), key))?;
    r.read_octets(slots)
}

/// Encodes a variable OCTET STRING.
pub fn encode_octets(w: &mut Writer<'_>, size: Size, octets: &[u8]) -> EncodeResult {
    write_sized(w, size, octets.len(), |w, start, n| {
        w.write_octets(&octets[start..start + n])
    })
}

/// Decodes a BIT STRING into storage of `NB` octets.
pub fn decode_bits<const NB: usize>(
    r: &mut Reader<'_>,
    size: Size,
    key: &'static str,
) -> DecodeResult<Bits<NB>> {
    let mut bytes = [0u8; NB];
    let len = read_bit_string(r, size, key, &mut bytes)?;
    Ok(Bits::from_filled(bytes, len))
}

/// The bits of a BIT STRING into `buf`, most significant first, the bits past them zero;
/// returns their count (at most `8 * buf.len()`). Not generic over the storage, so that one
/// copy serves every bit string type (the firmware's flash).
fn read_bit_string(
    r: &mut Reader<'_>,
    size: Size,
    key: &'static str,
    buf: &mut [u8],
) -> DecodeResult<usize> {
    let n = size.ub;
    if size.lb == n && !size.extensible && n <= 57 {
        // A fixed size of at most 57 bits (nearly every J2735 bit string): no length, one
        // read for the whole string.
        let octets = n.div_ceil(8);
        if octets > buf.len() {
            return Err(over_capacity(r.position(), key));
        }
        if n > 0 {
            let word = (r.read_bits(n as u32)? << (64 - n)).to_be_bytes();
            // One or two octets: a loop, not a call to memcpy.
            for (b, w) in buf.iter_mut().zip(word).take(octets) {
                *b = w;
            }
        }
        return Ok(n);
    }
    let mut len = 0usize;
    read_sized(r, size, |r, n| {
        if len + n > buf.len() * 8 {
            return Err(over_capacity(r.position(), key));
        }
        if n > r.remaining() {
            return Err(DecodeError::new(DKind::UnexpectedEnd, r.position()));
        }
        let mut done = 0;
        while done < n {
            let take = (n - done).min(8 - (len + done) % 8);
            let v = r.read_bits(take as u32)? as u8;
            let at = len + done;
            buf[at / 8] |= v << (8 - at % 8 - take);
            done += take;
        }
        len += n;
        Ok(())
    })?;
    Ok(len)
}

/// Encodes a BIT STRING.
pub fn encode_bits<const NB: usize>(
    w: &mut Writer<'_>,
    size: Size,
    bits: &Bits<NB>,
) -> EncodeResult {
    let bytes = bits.as_bytes();
    write_sized(w, size, bits.len(), |w, start, n| {
        let mut i = start;
        while i < start + n {
            let take = (start + n - i).min(8 - i % 8);
            let v = (bytes[i / 8] >> (8 - i % 8 - take)) & ((1u16 << take) - 1) as u8;
            w.write_bits(v as u64, take as u32)?;
            i += take;
        }
        Ok(())
    })
}

/// Decodes an IA5String into `out`, reusing its storage (with `alloc`, its allocation).
pub fn decode_ia5_into<const N: usize>(
    r: &mut Reader<'_>,
    size: Size,
    key: &'static str,
    out: &mut Ia5<N>,
) -> DecodeResult<()> {
    out.clear();
    read_sized(r, size, |r, n| {
        if n.saturating_mul(7) > r.remaining() {
            return Err(DecodeError::new(DKind::UnexpectedEnd, r.position()));
        }
        out.reserve(n);
        read_ia5_chars(r, n, out).unwrap_or_else(|| Err(over_capacity(r.position(), key)))
    })?;
    Ok(())
}

/// Reads `n` 7-bit characters into `out`, eight per read; `None` when they do not fit (no-heap
/// capacity).
///
/// With `alloc` they gather in a run on the stack and join the text a run at a time (one
/// check of the storage per run, not per character). Without it each is pushed at once: no
/// run buffer on the firmware's stack.
fn read_ia5_chars<const N: usize>(
    r: &mut Reader<'_>,
    n: usize,
    out: &mut Ia5<N>,
) -> Option<DecodeResult<()>> {
    #[cfg(feature = "alloc")]
    let mut run = [0u8; 64];
    #[cfg(feature = "alloc")]
    let mut filled = 0;
    let mut left = n;
    while left > 0 {
        let k = left.min(8);
        let word = match r.read_bits(7 * k as u32) {
            Ok(word) => word,
            Err(e) => return Some(Err(e)),
        };
        left -= k;
        let chars = (0..k).rev().map(|i| ((word >> (7 * i)) & 0x7f) as u8);
        #[cfg(feature = "alloc")]
        {
            for (slot, c) in run[filled..filled + k].iter_mut().zip(chars) {
                *slot = c;
            }
            filled += k;
            if filled + 8 > run.len() || left == 0 {
                out.push_ascii(&run[..filled]);
                filled = 0;
            }
        }
        #[cfg(not(feature = "alloc"))]
        for c in chars {
            out.push(char::from(c)).ok()?;
        }
    }
    Some(Ok(()))
}

/// Encodes an IA5String.
pub fn encode_ia5<const N: usize>(w: &mut Writer<'_>, size: Size, s: &Ia5<N>) -> EncodeResult {
    let bytes = s.as_str().as_bytes();
    write_sized(w, size, bytes.len(), |w, start, n| {
        bytes[start..start + n].iter().try_for_each(|&c| {
            if c > 0x7f {
                return Err(EncodeError::new(EKind::InvalidCharacter));
            }
            w.write_bits(c as u64, 7)
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octets_fragmented_round_trip() {
        // 40000 octets, unbounded: fragments of 32K then 7232 octets.
        let data: [u8; 40000] = core::array::from_fn(|i| (i * 7) as u8);
        let mut buf = [0u8; 40010];
        let mut w = Writer::new(&mut buf);
        encode_octets(&mut w, Size::range(0, usize::MAX), &data).unwrap();
        assert_eq!(w.octets(), 1 + 32768 + 2 + 7232);
        assert_eq!(buf[0], 0xc2, "fragment header for 2 x 16K");
        let mut r = Reader::new(&buf);
        let mut total = 0;
        let n = read_sized(&mut r, Size::range(0, usize::MAX), |r, n| {
            for i in 0..n {
                assert_eq!(r.read_bits(8).unwrap() as u8, data[total + i]);
            }
            total += n;
            Ok(())
        })
        .unwrap();
        assert_eq!(n, 40000);
    }

    /// A list longer than one run of slots (with `alloc`, 64) decodes whole, refills a kept
    /// list, and a list cut short is an error, not a panic. The bytes are written out by
    /// hand: SIZE(0..255) is an 8-bit length, each `LaneID` (0..255) 8 bits.
    #[test]
    fn long_lists_decode_across_runs_of_slots() {
        use crate::msg::common::LaneID;
        let size = Size::range(0, 255);
        let long: [u8; 201] = core::array::from_fn(|i| if i == 0 { 200 } else { (i - 1) as u8 });
        let mut list = SeqOf::<LaneID, 255>::new();
        decode_seq_of_into(&mut Reader::new(&long), size, "k", &mut list).unwrap();
        assert_eq!(list.len(), 200);
        assert!(list.iter().enumerate().all(|(i, l)| l.get() == i as u8));
        decode_seq_of_into(&mut Reader::new(&[3, 9, 8, 7]), size, "k", &mut list).unwrap();
        assert_eq!(
            list.iter()
                .map(|l| l.get())
                .collect::<heapless::Vec<u8, 3>>(),
            [9, 8, 7]
        );
        let cut = &long[..101];
        let e = decode_seq_of_into(&mut Reader::new(cut), size, "k", &mut list).unwrap_err();
        assert_eq!(e.kind, DKind::UnexpectedEnd);
    }

    #[test]
    fn extensible_size_outside_root() {
        // SIZE(8, ...) with a 0-bit value: extension bit, then length 0.
        let bits = Bits::<2>::zeros(0).unwrap();
        let mut buf = [0u8; 4];
        let mut w = Writer::new(&mut buf);
        encode_bits(&mut w, Size::extensible(8, 8), &bits).unwrap();
        assert_eq!(w.position(), 9);
        assert_eq!(&buf[..2], &[0x80, 0x00]);
        let mut r = Reader::new(&buf[..2]);
        let back: Bits<2> = decode_bits(&mut r, Size::extensible(8, 8), "T").unwrap();
        assert_eq!(back.len(), 0);
    }

    #[test]
    fn capacity_is_checked_before_items() {
        // SIZE(1..255) count 200 with no items following: capacity error, not end of input.
        let mut r = Reader::new(&[199, 0]);
        let mut out = Octets::<16>::new();
        let e = decode_octets_into(&mut r, Size::range(1, 256), "Test.Key", &mut out).unwrap_err();
        if cfg!(feature = "alloc") {
            assert_eq!(e.kind, DKind::UnexpectedEnd);
        } else {
            assert_eq!((e.kind, e.path), (DKind::CapacityExceeded, "Test.Key"));
        }
    }

    #[test]
    fn size_out_of_root_refused_on_encode() {
        let mut buf = [0u8; 8];
        let mut w = Writer::new(&mut buf);
        let e = encode_octets(&mut w, Size::range(1, 4), &[]).unwrap_err();
        assert_eq!(e.kind, EKind::SizeOutOfRange);
    }
}
