//! Extension additions of extensible SEQUENCEs (X.691 19.7-19.9) and open-type helpers.
//!
//! J2735 2020 declares `...` in most SEQUENCEs but defines no additions; a newer sender
//! (J2735 2024) fills them. Additions this build does not know are skipped by their length
//! on decode and kept as raw octets, with the length of the presence bit-map as received, so
//! that decode then encode gives the identical bytes.

use super::error::{DecodeError, DecodeErrorKind as DKind, EncodeError, EncodeErrorKind as EKind};
use super::reader::{DecodeResult, Reader};
use super::sized::read_octets_into;
use super::storage::Octets;
use super::writer::{EncodeResult, Writer};

/// Unknown extension additions of one SEQUENCE value, at most `N` octets of records
/// without `alloc` (each addition costs 4 octets plus its content).
///
/// With `alloc` the value is one pointer, `None` until an extension bit is received: nearly
/// every SEQUENCE of real traffic has none, and this field is in every extensible SEQUENCE
/// (a node of a lane's node list is 32 octets with it a pointer, 64 with it in place).
/// Without `alloc` it is in place, `N` octets of records.
#[derive(Clone)]
pub struct Extensions<const N: usize> {
    received: Stored<N>,
}

/// What a set extension bit brought.
#[derive(Clone)]
struct Received<const N: usize> {
    /// Length of the presence bit-map as received; 0 when the extension bit was clear.
    bitmap_len: u16,
    /// Records: index (u16 BE), content length (u16 BE), content octets.
    records: Octets<N>,
}

impl<const N: usize> Received<N> {
    const fn new() -> Self {
        Self {
            bitmap_len: 0,
            records: Octets::new(),
        }
    }
}

#[cfg(feature = "alloc")]
type Stored<const N: usize> = Option<alloc::boxed::Box<Received<N>>>;
#[cfg(not(feature = "alloc"))]
type Stored<const N: usize> = Received<N>;

/// Most extension additions one SEQUENCE value may flag (J2735 2024 adds a handful).
pub const MAX_BITMAP: u64 = 64;

/// Iterates over stored records: (index after the root, open-type content).
#[derive(Clone, Debug)]
pub struct UnknownAdditions<'a> {
    rest: &'a [u8],
}

impl<'a> Iterator for UnknownAdditions<'a> {
    type Item = (usize, &'a [u8]);
    fn next(&mut self) -> Option<Self::Item> {
        let [i0, i1, l0, l1, tail @ ..] = self.rest else {
            return None;
        };
        let index = u16::from_be_bytes([*i0, *i1]) as usize;
        let len = (u16::from_be_bytes([*l0, *l1]) as usize).min(tail.len());
        self.rest = &tail[len..];
        Some((index, &tail[..len]))
    }
}

/// Calls `f(index, content)` for each stored record until it returns false.
fn for_each_record<F: FnMut(usize, &[u8]) -> bool>(records: &[u8], mut f: F) {
    for (i, c) in (UnknownAdditions { rest: records }) {
        if !f(i, c) {
            return;
        }
    }
}

impl<const N: usize> Extensions<N> {
    /// No extension additions (the extension bit is clear).
    pub const fn new() -> Self {
        Self {
            #[cfg(feature = "alloc")]
            received: None,
            #[cfg(not(feature = "alloc"))]
            received: Received::new(),
        }
    }

    /// What was received, if anything was stored.
    #[inline]
    fn received(&self) -> Option<&Received<N>> {
        #[cfg(feature = "alloc")]
        {
            self.received.as_deref()
        }
        #[cfg(not(feature = "alloc"))]
        {
            Some(&self.received)
        }
    }

    /// What was received, writable (with `alloc`, allocated the first time).
    fn received_mut(&mut self) -> &mut Received<N> {
        #[cfg(feature = "alloc")]
        {
            self.received
                .get_or_insert_with(|| alloc::boxed::Box::new(Received::new()))
        }
        #[cfg(not(feature = "alloc"))]
        {
            &mut self.received
        }
    }

    /// The stored records.
    fn records(&self) -> &[u8] {
        self.received().map_or(&[], |r| &r.records)
    }

    /// Makes this "no extension additions" (with `alloc`, the records' allocation is kept
    /// for reuse).
    #[inline]
    pub fn clear(&mut self) {
        #[cfg(feature = "alloc")]
        let received = self.received.as_deref_mut();
        #[cfg(not(feature = "alloc"))]
        let received = Some(&mut self.received);
        if let Some(r) = received {
            r.bitmap_len = 0;
            r.records.clear();
        }
    }

    /// True when the extension bit is to be set (something was received or stored).
    pub fn is_present(&self) -> bool {
        self.bitmap_len() > 0 || !self.records().is_empty()
    }

    /// Length of the presence bit-map as received (0: the extension bit was clear).
    pub fn bitmap_len(&self) -> usize {
        self.received().map_or(0, |r| r.bitmap_len as usize)
    }

    /// Extensions with a bit-map of `bitmap_len` and the given unknown additions (index
    /// after the root, open-type content) in ascending index order; `None` when they do not
    /// fit the storage, are out of order, or lie outside the bit-map (an index of
    /// `bitmap_len` or more: the encoding would carry a longer bit-map than the value), or
    /// when the bit-map is longer than decoding accepts (64 bits).
    pub fn from_parts<'a>(
        bitmap_len: usize,
        additions: impl IntoIterator<Item = (usize, &'a [u8])>,
    ) -> Option<Self> {
        if bitmap_len as u64 > MAX_BITMAP {
            return None;
        }
        let mut ext = Self::new();
        let received = ext.received_mut();
        received.bitmap_len = u16::try_from(bitmap_len).ok()?;
        let mut prev = None;
        for (index, content) in additions {
            if prev.is_some_and(|p| p >= index) || index >= bitmap_len {
                return None;
            }
            prev = Some(index);
            let len = u16::try_from(content.len()).ok()?;
            for b in (index as u16)
                .to_be_bytes()
                .into_iter()
                .chain(len.to_be_bytes())
                .chain(content.iter().copied())
            {
                received.records.push(b).ok()?;
            }
        }
        Some(ext)
    }

    /// The stored unknown additions: (index after the root, open-type content).
    pub fn unknown(&self) -> UnknownAdditions<'_> {
        UnknownAdditions {
            rest: self.records(),
        }
    }

    /// Decodes the bit-map and the additions. `known(index, content)` decodes an addition
    /// the type defines and returns false for one it does not; those are stored.
    pub fn decode_with<'a, F>(r: &mut Reader<'a>, key: &'static str, known: F) -> DecodeResult<Self>
    where
        F: FnMut(usize, &mut Reader<'a>) -> DecodeResult<bool>,
    {
        let mut ext = Self::new();
        ext.decode_with_into(r, key, known)?;
        Ok(ext)
    }

    /// As [`Self::decode_with`], into `self` (reusing its storage).
    pub fn decode_with_into<'a, F>(
        &mut self,
        r: &mut Reader<'a>,
        key: &'static str,
        mut known: F,
    ) -> DecodeResult<()>
    where
        F: FnMut(usize, &mut Reader<'a>) -> DecodeResult<bool>,
    {
        self.clear();
        let at = r.position();
        let n = r.read_normally_small()? + 1;
        if n as usize > r.remaining() {
            return Err(DecodeError::new(DKind::UnexpectedEnd, at));
        }
        let mut present = [0u64; 1];
        if n > MAX_BITMAP {
            return Err(DecodeError::new(DKind::LengthTooLarge, at));
        }
        self.received_mut().bitmap_len = n as u16;
        for i in 0..n as usize {
            if r.read_bit()? {
                present[i / 64] |= 1 << (i % 64);
            }
        }
        for i in (0..n as usize).filter(|i| present[i / 64] & (1 << (i % 64)) != 0) {
            let window = r.enter_open()?;
            let start = r.position();
            if known(i, r)? {
                r.finish_open()?;
            } else {
                // Whatever `known` read of an addition it does not know, the whole content
                // is kept.
                r.seek(start);
                self.store(i, r, key)?;
            }
            r.close_open(window);
        }
        Ok(())
    }

    /// Decodes the additions of a type that defines none.
    pub fn decode(r: &mut Reader<'_>, key: &'static str) -> DecodeResult<Self> {
        Self::decode_with(r, key, |_, _| Ok(false))
    }

    /// As [`Self::decode`], into `self` (reusing its storage: a value kept between messages
    /// does not allocate for them again).
    pub fn decode_into(&mut self, r: &mut Reader<'_>, key: &'static str) -> DecodeResult<()> {
        self.decode_with_into(r, key, |_, _| Ok(false))
    }

    fn store(
        &mut self,
        index: usize,
        content: &mut Reader<'_>,
        key: &'static str,
    ) -> DecodeResult<()> {
        let len = content.remaining() / 8;
        let at = content.position();
        let header = [(index >> 8) as u8, index as u8, (len >> 8) as u8, len as u8];
        let records = &mut self.received_mut().records;
        for b in header {
            records
                .push(b)
                .map_err(|_| DecodeError::at(DKind::CapacityExceeded, at, key))?;
        }
        read_octets_into(content, len, records, key)
    }

    /// Encodes the bit-map and the additions. `known_present` flags the additions the type
    /// defines and holds; `write_known(index, w)` writes one of them.
    pub fn encode_with<F>(
        &self,
        w: &mut Writer<'_>,
        known_present: &[bool],
        mut write_known: F,
    ) -> EncodeResult
    where
        F: FnMut(usize, &mut Writer<'_>) -> EncodeResult,
    {
        let mut last = known_present.iter().rposition(|&p| p).map_or(0, |i| i + 1);
        let mut ordered = true;
        let mut prev: Option<usize> = None;
        for_each_record(self.records(), |i, _| {
            ordered &= prev.is_none_or(|p| p < i) && known_present.get(i) != Some(&true);
            prev = Some(i);
            last = last.max(i + 1);
            true
        });
        if !ordered {
            return Err(EncodeError::new(EKind::InvalidExtensions));
        }
        let n = last.max(self.bitmap_len()).max(1);
        w.write_normally_small(n as u64 - 1)?;
        for i in 0..n {
            w.write_bit(known_present.get(i) == Some(&true) || self.record(i).is_some())?;
        }
        for i in 0..n {
            if known_present.get(i) == Some(&true) {
                w.write_open(|w| write_known(i, w))?;
            } else if let Some(content) = self.record(i) {
                w.write_open_octets(content)?;
            }
        }
        Ok(())
    }

    /// Encodes the additions of a type that defines none.
    pub fn encode(&self, w: &mut Writer<'_>) -> EncodeResult {
        self.encode_with(w, &[], |_, _| Ok(()))
    }

    fn record(&self, index: usize) -> Option<&[u8]> {
        self.unknown().find(|(i, _)| *i == index).map(|(_, c)| c)
    }
}

/// Equal when the bit-map lengths and the stored additions are (with `alloc`, whether or not
/// a cleared value kept its allocation).
impl<const N: usize> PartialEq for Extensions<N> {
    fn eq(&self, other: &Self) -> bool {
        self.bitmap_len() == other.bitmap_len() && self.records() == other.records()
    }
}

impl<const N: usize> Eq for Extensions<N> {}

impl<const N: usize> core::hash::Hash for Extensions<N> {
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        self.bitmap_len().hash(state);
        self.records().hash(state);
    }
}

impl<const N: usize> Default for Extensions<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> core::fmt::Debug for Extensions<N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let mut l = f.debug_list();
        for_each_record(self.records(), |i, c| {
            l.entry(&(i, c));
            true
        });
        l.finish()
    }
}

/// Reads the content of an open type whose type is not known here (kept as raw octets),
/// fragmented or not.
pub fn decode_unknown_open<const N: usize>(
    r: &mut Reader<'_>,
    key: &'static str,
) -> DecodeResult<Octets<N>> {
    let mut out = Octets::new();
    loop {
        let part = r.read_length()?;
        read_octets_into(r, part.len, &mut out, key)?;
        if !part.more {
            return Ok(out);
        }
    }
}

/// Decodes a known open type: the content must fill its length but for padding.
///
/// Content of 16K octets or more arrives in fragments; with feature `alloc` it is put back
/// together and decoded (error positions then count from the start of the content), without
/// it the value is refused with [`DKind::FragmentedOpenType`]: J2735 messages on the air are
/// far smaller.
pub fn decode_open<'a, T, F>(r: &mut Reader<'a>, decode: F) -> DecodeResult<T>
where
    F: for<'b> FnOnce(&mut Reader<'b>) -> DecodeResult<T>,
{
    // Positions, not copies of the reader: open types nest (a frame's message, a regional
    // extension in it), and every level is on the firmware's stack.
    let before = r.position();
    match r.enter_open() {
        Ok(window) => {
            let v = decode(r)?;
            r.finish_open()?;
            r.close_open(window);
            Ok(v)
        }
        Err(e) if e.kind == DKind::FragmentedOpenType => {
            r.seek(before);
            decode_fragmented(r, decode)
        }
        Err(e) => Err(e),
    }
}

#[cfg(feature = "alloc")]
#[cold]
fn decode_fragmented<T, F>(r: &mut Reader<'_>, decode: F) -> DecodeResult<T>
where
    F: for<'b> FnOnce(&mut Reader<'b>) -> DecodeResult<T>,
{
    let content: Octets<0> = decode_unknown_open(r, "")?;
    let mut inner = Reader::new(&content);
    let v = decode(&mut inner)?;
    inner.finish_open()?;
    Ok(v)
}

#[cfg(not(feature = "alloc"))]
#[cold]
fn decode_fragmented<T, F>(r: &mut Reader<'_>, _decode: F) -> DecodeResult<T>
where
    F: for<'b> FnOnce(&mut Reader<'b>) -> DecodeResult<T>,
{
    Err(DecodeError::new(DKind::FragmentedOpenType, r.position()))
}

/// Writes stored raw open-type content, exactly as stored (as extension additions are).
///
/// Empty content is written with length 0, as it was received: writing it as the single
/// zero octet that X.691 puts in place of an empty complete encoding would decode to other
/// content (`[0]`), so that decode then encode then decode would not give the value back.
pub fn encode_unknown_open(w: &mut Writer<'_>, content: &[u8]) -> EncodeResult {
    w.write_open_octets(content)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A SEQUENCE with one known addition (an 8-bit number) and room for unknown ones.
    fn encode_sample(ext: &Extensions<32>, known: Option<u8>) -> heapless::Vec<u8, 64> {
        let mut buf = [0u8; 64];
        let mut w = Writer::new(&mut buf);
        ext.encode_with(&mut w, &[known.is_some()], |_, w| {
            w.write_bits(known.unwrap_or(0) as u64, 8)
        })
        .unwrap();
        let n = w.octets();
        heapless::Vec::from_slice(&buf[..n]).unwrap()
    }

    #[test]
    fn unknown_additions_round_trip_byte_exact() {
        // bit-map length 3 (normally small 2), bits 101, addition 0: 1 octet 0x2a,
        // addition 2: 2 octets 0xbeef.
        let mut buf = [0u8; 16];
        let mut w = Writer::new(&mut buf);
        w.write_normally_small(2).unwrap();
        w.write_bits(0b101, 3).unwrap();
        w.write_open_octets(&[0x2a]).unwrap();
        w.write_open_octets(&[0xbe, 0xef]).unwrap();
        let n = w.octets();
        let input = &buf[..n];

        let mut r = Reader::new(input);
        let mut seen = None;
        let ext = Extensions::<32>::decode_with(&mut r, "T", |i, c| {
            if i == 0 {
                seen = Some(c.read_bits(8)? as u8);
                return Ok(true);
            }
            Ok(false)
        })
        .unwrap();
        assert_eq!(seen, Some(0x2a));
        assert!(ext.unknown().eq([(2usize, &[0xbe, 0xef][..])]));
        assert_eq!(&encode_sample(&ext, seen)[..], input);
    }

    #[test]
    fn empty_bitmap_length_is_kept() {
        // Extension bit set but nothing present: bit-map of 4 zero bits.
        let mut buf = [0u8; 4];
        let mut w = Writer::new(&mut buf);
        w.write_normally_small(3).unwrap();
        w.write_bits(0, 4).unwrap();
        let n = w.octets();
        let input = &buf[..n];
        let ext = Extensions::<0>::decode(&mut Reader::new(input), "T").unwrap();
        assert!(ext.is_present());
        assert_eq!(
            &encode_sample(
                &Extensions::<32>::decode(&mut Reader::new(input), "T").unwrap(),
                None
            )[..],
            input
        );
    }

    /// With `alloc` the field is one pointer, allocated only when an extension bit comes; a
    /// kept value cleared for a message without additions keeps that allocation and equals
    /// (and hashes as) a value that never had any.
    #[test]
    fn cleared_extensions_equal_absent_ones_whatever_they_kept() {
        use core::hash::{Hash, Hasher};
        fn hash_of(e: &Extensions<32>) -> u64 {
            let mut h = std::hash::DefaultHasher::new();
            e.hash(&mut h);
            h.finish()
        }
        let mut buf = [0u8; 8];
        let mut w = Writer::new(&mut buf);
        w.write_normally_small(0).unwrap();
        w.write_bit(true).unwrap();
        w.write_open_octets(&[7]).unwrap();
        let mut kept = Extensions::<32>::decode(&mut Reader::new(&buf), "T").unwrap();
        assert!(kept.is_present());
        assert_ne!(kept, Extensions::new());
        kept.clear();
        assert!(!kept.is_present());
        assert_eq!(kept, Extensions::new());
        assert_eq!(hash_of(&kept), hash_of(&Extensions::new()));
        assert_eq!(std::format!("{kept:?}"), "[]");
        if cfg!(feature = "alloc") {
            assert_eq!(
                core::mem::size_of::<Extensions<32>>(),
                core::mem::size_of::<usize>()
            );
        }
    }

    #[test]
    fn no_room_names_the_key() {
        let mut buf = [0u8; 8];
        let mut w = Writer::new(&mut buf);
        w.write_normally_small(0).unwrap();
        w.write_bit(true).unwrap();
        w.write_open_octets(&[1, 2, 3]).unwrap();
        let got = Extensions::<0>::decode(&mut Reader::new(&buf), "MapData.MapData:ext");
        if cfg!(feature = "alloc") {
            assert!(got.unwrap().unknown().eq([(0usize, &[1u8, 2, 3][..])]));
        } else {
            let e = got.unwrap_err();
            assert_eq!(
                (e.kind, e.path),
                (DKind::CapacityExceeded, "MapData.MapData:ext")
            );
        }
    }
}
