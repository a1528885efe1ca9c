//! Storage of variable-size values: the one place that switches between no-heap
//! (`heapless`, fixed capacities) and feature `alloc` (`Vec`/`String`).
//!
//! Generated code uses only the API below, so it is the same in both modes. The const
//! parameter `N` is the no-heap capacity; with `alloc` it is ignored and only the ASN.1 SIZE
//! constraint bounds a value.

use core::fmt;
use core::ops::{Deref, DerefMut};

use super::Placeholder;

/// A SEQUENCE OF (or variable OCTET STRING) value: at most `N` items without `alloc`.
///
/// The items live in a `heapless::Vec` (without `alloc`) or a `Vec` (with it) whose slots
/// are initialised lazily, the first time the sequence grows to them, and then kept:
/// decoding into a kept value refills those slots in place, so it never moves large items
/// (no-heap) and reuses every nested vector's allocation (`alloc`; a decode drops the slots
/// beyond its items, see [`SeqOf::drop_spare`]). An empty sequence costs
/// nothing to create, whatever `N` (no array of placeholders is built, so no large temporary
/// lands on the stack when an absent OPTIONAL member becomes present). Only the first
/// `len()` items are the value: equality, hashing, `Debug` and iteration look at those alone.
pub struct SeqOf<T: 'static, const N: usize, const I: usize = 0> {
    len: Len,
    /// Initialised slots (at least `len`; the rest hold former items for reuse).
    items: Slots<T, N, I>,
}

#[cfg(not(feature = "alloc"))]
type Slots<T, const N: usize, const I: usize> = heapless::Vec<T, N>;
#[cfg(feature = "alloc")]
type Slots<T, const N: usize, const I: usize> = super::slots::Slots<T, I>;

/// The length of a [`SeqOf`], stored plus one so that it has a niche (zero): an
/// `Option<SeqOf>` then takes no more room than the `SeqOf` (no-heap item storage, being
/// `MaybeUninit`, has none to offer).
#[derive(Clone, Copy)]
struct Len(core::num::NonZeroUsize);

impl Len {
    const ZERO: Self = Self(core::num::NonZeroUsize::MIN);

    fn get(self) -> usize {
        self.0.get() - 1
    }

    fn set(&mut self, len: usize) {
        // `len` is at most the number of slots, itself below `usize::MAX`.
        self.0 = core::num::NonZeroUsize::new(len.wrapping_add(1)).unwrap_or(Self::ZERO.0);
    }
}

/// Octets a variable OCTET STRING keeps inside the value with `alloc` before it allocates
/// (15 take no more room than the `Vec` they spare: see `slots.rs`); real traffic's unknown
/// extension additions and open-type contents are mostly a few octets.
pub const OCTETS_INLINE: usize = 15;

/// Variable-size octets (OCTET STRING, unknown open-type content).
pub type Octets<const N: usize> = SeqOf<u8, N, OCTETS_INLINE>;

impl<T: Placeholder + 'static, const N: usize, const I: usize> SeqOf<T, N, I> {
    /// An empty sequence (a `const fn`: a sequence can start out in static memory).
    pub const fn new() -> Self {
        Self {
            len: Len::ZERO,
            items: Slots::new(),
        }
    }

    /// Appends an item; gives it back when the no-heap capacity is full.
    pub fn push(&mut self, item: T) -> Result<(), T> {
        match self.push_slot() {
            Some(slot) => {
                *slot = item;
                Ok(())
            }
            None => Err(item),
        }
    }

    /// Grows by one item and returns it to be overwritten (it holds a placeholder or a
    /// former item); `None` when the no-heap capacity is full.
    pub fn push_slot(&mut self) -> Option<&mut T> {
        let len = self.len.get();
        if len == self.items.len() {
            #[cfg(not(feature = "alloc"))]
            self.items.push(T::placeholder()).ok()?;
            #[cfg(feature = "alloc")]
            self.items
                .grow_to(len + 1, T::item_placeholder, false)
                .ok()?;
        }
        let slot = self.items.as_mut_slice().get_mut(len)?;
        self.len.set(len + 1);
        Some(slot)
    }

    /// Grows by `n` items at once and returns them to be overwritten (placeholders or
    /// former items); `None`, unchanged, when the no-heap capacity (with `alloc`, the memory)
    /// cannot hold them. With `alloc`, the new placeholders are written in place: growing a
    /// run of slots at once, not one [`SeqOf::push_slot`] per item, spares a new value's
    /// decode a copy of every item's placeholder.
    pub fn grow(&mut self, n: usize) -> Option<&mut [T]> {
        self.grow_slots(n, false)
    }

    /// As [`SeqOf::grow`], for a decode, which overwrites every slot it grows: with
    /// features `alloc` and `std`, a list without heap storage takes one that this thread
    /// dropped, with its former items in the slots (see `recycle.rs`), where `grow` would
    /// allocate and write placeholders. `grow` and `push_slot` never show another list's
    /// former items.
    pub(crate) fn grow_decoding(&mut self, n: usize) -> Option<&mut [T]> {
        self.grow_slots(n, true)
    }

    /// [`SeqOf::grow`]; `recycled`: whether a decode may take a recycled storage.
    fn grow_slots(&mut self, n: usize, recycled: bool) -> Option<&mut [T]> {
        let len = self.len.get();
        let new_len = len.checked_add(n).filter(|&l| l <= Self::capacity())?;
        // The first room exactly (a decode knows the length before the items), later room
        // amortised (a long list grows in runs, see `decode_seq_of_into`).
        #[cfg(feature = "alloc")]
        self.items
            .grow_to(new_len, T::item_placeholder, recycled)
            .ok()?;
        #[cfg(not(feature = "alloc"))]
        let _ = recycled;
        #[cfg(not(feature = "alloc"))]
        while self.items.len() < new_len {
            self.items.push(T::placeholder()).ok()?;
        }
        self.len.set(new_len);
        self.items.as_mut_slice().get_mut(len..new_len)
    }

    /// Removes and returns the last item.
    pub fn pop(&mut self) -> Option<T> {
        let last = self.len.get().checked_sub(1)?;
        self.items.truncate(last + 1);
        self.len.set(last);
        self.items.pop()
    }
}

impl<T: 'static, const N: usize, const I: usize> SeqOf<T, N, I> {
    /// How many items fit: `N` without `alloc`, unbounded (`usize::MAX`) with it.
    pub const fn capacity() -> usize {
        if cfg!(feature = "alloc") {
            usize::MAX
        } else {
            N
        }
    }

    /// Removes every item (the initialised slots, and with `alloc` their allocations, are
    /// kept for reuse).
    pub fn clear(&mut self) {
        self.len = Len::ZERO;
    }

    /// Drops the slots kept beyond the items (with `alloc`: a kept value then holds the
    /// storage of its last message's shape, not of every shape it ever had; without `alloc`
    /// the slots live in the fixed room anyway and are kept).
    pub fn drop_spare(&mut self) {
        #[cfg(feature = "alloc")]
        self.items.truncate(self.len.get());
    }

    /// Makes room for `additional` more items at once (with `alloc`; without it the room is
    /// fixed). Callers bound `additional` by the input that remains.
    pub fn reserve(&mut self, additional: usize) {
        #[cfg(feature = "alloc")]
        {
            let free = self.items.len() - self.len.get();
            self.items.reserve(additional.saturating_sub(free));
        }
        #[cfg(not(feature = "alloc"))]
        let _ = additional;
    }

    fn as_slice(&self) -> &[T] {
        &self.items.as_slice()[..self.len.get()]
    }

    fn as_mut_slice(&mut self) -> &mut [T] {
        let len = self.len.get();
        &mut self.items.as_mut_slice()[..len]
    }
}

impl<T: Clone + 'static, const N: usize, const I: usize> Clone for SeqOf<T, N, I> {
    /// Copies the items only (not the slots kept for reuse).
    fn clone(&self) -> Self {
        let live = self.as_slice();
        // `live` holds at most N items, so the no-heap copy always fits.
        #[cfg(not(feature = "alloc"))]
        let items = heapless::Vec::from_slice(live).unwrap_or_default();
        #[cfg(feature = "alloc")]
        let items = Slots::<T, N, I>::from_items(live);
        let mut len = Len::ZERO;
        len.set(items.len());
        Self { len, items }
    }
}

impl<T: Placeholder + Clone + 'static, const N: usize, const I: usize> SeqOf<T, N, I> {
    /// A sequence holding a copy of `items`; `None` when they exceed the capacity.
    pub fn from_slice(items: &[T]) -> Option<Self> {
        let mut s = Self::new();
        for it in items {
            s.push(it.clone()).ok()?;
        }
        Some(s)
    }
}

impl<T: Placeholder + 'static, const N: usize, const I: usize> Default for SeqOf<T, N, I> {
    fn default() -> Self {
        Self::new()
    }
}

impl<T: Placeholder + 'static, const N: usize, const I: usize> Placeholder for SeqOf<T, N, I> {
    fn placeholder() -> Self {
        Self::new()
    }
}

impl<T: 'static, const N: usize, const I: usize> Deref for SeqOf<T, N, I> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        self.as_slice()
    }
}

impl<T: 'static, const N: usize, const I: usize> DerefMut for SeqOf<T, N, I> {
    fn deref_mut(&mut self) -> &mut [T] {
        self.as_mut_slice()
    }
}

impl<T: PartialEq + 'static, const N: usize, const I: usize> PartialEq for SeqOf<T, N, I> {
    fn eq(&self, other: &Self) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl<T: Eq + 'static, const N: usize, const I: usize> Eq for SeqOf<T, N, I> {}

impl<T: core::hash::Hash + 'static, const N: usize, const I: usize> core::hash::Hash
    for SeqOf<T, N, I>
{
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        self.as_slice().hash(state)
    }
}

impl<'a, T: 'static, const N: usize, const I: usize> IntoIterator for &'a SeqOf<T, N, I> {
    type Item = &'a T;
    type IntoIter = core::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.as_slice().iter()
    }
}

impl<T: fmt::Debug + 'static, const N: usize, const I: usize> fmt::Debug for SeqOf<T, N, I> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

/// An IA5String value (7-bit ASCII): at most `N` characters without `alloc`.
///
/// With `alloc`, up to `uper::IA5_INLINE` characters stay inside the value (no allocation for
/// a short name); a longer text is a `String`.
#[derive(Clone)]
pub struct Ia5<const N: usize> {
    #[cfg(not(feature = "alloc"))]
    text: heapless::String<N>,
    #[cfg(feature = "alloc")]
    text: super::slots::Text,
}

impl<const N: usize> Ia5<N> {
    /// An empty string.
    pub const fn new() -> Self {
        Self {
            #[cfg(not(feature = "alloc"))]
            text: heapless::String::new(),
            #[cfg(feature = "alloc")]
            text: super::slots::Text::new(),
        }
    }

    /// A copy of `s`; `None` when it is not IA5 (7-bit) or exceeds the capacity.
    pub fn try_from_str(s: &str) -> Option<Self> {
        let mut t = Self::new();
        t.reserve(s.len());
        for c in s.chars() {
            t.push(c).ok()?;
        }
        Some(t)
    }

    /// Appends one character; refuses a non-IA5 character or a full capacity.
    pub fn push(&mut self, c: char) -> Result<(), char> {
        if !c.is_ascii() {
            return Err(c);
        }
        #[cfg(not(feature = "alloc"))]
        return self.text.push(c).map_err(|_| c);
        #[cfg(feature = "alloc")]
        {
            self.text.push(c);
            Ok(())
        }
    }

    /// Appends a run of 7-bit characters (a decode's up to 64 at a time, masked to 7 bits by
    /// the caller).
    #[cfg(feature = "alloc")]
    pub(super) fn push_ascii(&mut self, run: &[u8]) {
        debug_assert!(run.is_ascii());
        self.text.push_ascii(run);
    }

    /// Makes room for `additional` more characters at once (with `alloc`; without it the
    /// room is fixed). Callers bound `additional` by the input that remains.
    pub fn reserve(&mut self, additional: usize) {
        #[cfg(feature = "alloc")]
        self.text.reserve(additional);
        #[cfg(not(feature = "alloc"))]
        let _ = additional;
    }

    /// Removes every character (with `alloc`, an allocation is kept for reuse).
    pub fn clear(&mut self) {
        self.text.clear();
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        #[cfg(not(feature = "alloc"))]
        return &self.text;
        #[cfg(feature = "alloc")]
        return self.text.as_str();
    }

    /// Number of characters (= octets, since every character is ASCII).
    pub fn len(&self) -> usize {
        self.as_str().len()
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.as_str().is_empty()
    }
}

impl<const N: usize> Default for Ia5<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> PartialEq for Ia5<N> {
    /// Equal texts (however stored).
    fn eq(&self, other: &Self) -> bool {
        self.as_str() == other.as_str()
    }
}

impl<const N: usize> Eq for Ia5<N> {}

impl<const N: usize> core::hash::Hash for Ia5<N> {
    fn hash<H: core::hash::Hasher>(&self, state: &mut H) {
        self.as_str().hash(state)
    }
}

impl<const N: usize> Placeholder for Ia5<N> {
    fn placeholder() -> Self {
        Self::new()
    }
}

impl<const N: usize> fmt::Debug for Ia5<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl<const N: usize> fmt::Display for Ia5<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A BIT STRING value of at most `8 * NBYTES` bits, first bit in the top of `bytes[0]`.
///
/// The length is kept as decoded, also for types with named bits, so that decode then
/// encode reproduces the input (X.691 would let an encoder trim trailing zero bits).
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Bits<const NBYTES: usize> {
    len: u16,
    bytes: [u8; NBYTES],
}

impl<const NBYTES: usize> Bits<NBYTES> {
    /// The largest length this storage holds.
    pub const CAPACITY: usize = NBYTES * 8;
    /// The value with no bits.
    pub const EMPTY: Self = Self {
        len: 0,
        bytes: [0; NBYTES],
    };

    /// `len` zero bits; `None` when `len` exceeds the storage.
    pub const fn zeros(len: usize) -> Option<Self> {
        if len > Self::CAPACITY {
            return None;
        }
        Some(Self {
            len: len as u16,
            bytes: [0; NBYTES],
        })
    }

    /// The first `len` bits of `bytes` (the decoder's: `len` at most [`Self::CAPACITY`],
    /// the bits past it zero, as every `Bits` keeps them).
    #[inline]
    pub(crate) fn from_filled(bytes: [u8; NBYTES], len: usize) -> Self {
        debug_assert!(len <= Self::CAPACITY);
        Self {
            len: len as u16,
            bytes,
        }
    }

    /// Number of bits.
    pub const fn len(&self) -> usize {
        self.len as usize
    }

    /// True when the value has no bits.
    pub const fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Bit `i` (0 = first); false past the end.
    pub const fn get(&self, i: usize) -> bool {
        i < self.len as usize && self.bytes[i / 8] & (0x80 >> (i % 8)) != 0
    }

    /// Sets bit `i`; returns false (and changes nothing) past the end.
    pub fn set(&mut self, i: usize, on: bool) -> bool {
        if i >= self.len() {
            return false;
        }
        let mask = 0x80 >> (i % 8);
        if on {
            self.bytes[i / 8] |= mask;
        } else {
            self.bytes[i / 8] &= !mask;
        }
        true
    }

    /// The octets holding the bits (the last one zero-padded).
    pub fn as_bytes(&self) -> &[u8] {
        &self.bytes[..self.len().div_ceil(8)]
    }

    /// Bits from octets: the first `len` bits of `bytes`; `None` when too long or short.
    pub fn from_bytes(bytes: &[u8], len: usize) -> Option<Self> {
        let mut b = Self::zeros(len)?;
        let n = len.div_ceil(8);
        b.bytes[..n].copy_from_slice(bytes.get(..n)?);
        if !len.is_multiple_of(8) {
            b.bytes[n - 1] &= 0xff << (8 - len % 8);
        }
        Some(b)
    }
}

impl<const NBYTES: usize> fmt::Debug for Bits<NBYTES> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("'")?;
        for i in 0..self.len() {
            f.write_str(if self.get(i) { "1" } else { "0" })?;
        }
        f.write_str("'B")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_compare_and_hash_by_their_items_however_stored() {
        use core::hash::{Hash, Hasher};
        fn hash(v: &impl Hash) -> u64 {
            let mut h = std::hash::DefaultHasher::new();
            v.hash(&mut h);
            h.finish()
        }
        // A list of 2 that once held 4 (with `alloc`: on the heap) against a fresh one
        // (inline).
        let mut grown: SeqOf<u8, 4, 2> = SeqOf::new();
        grown.grow(4).unwrap().copy_from_slice(&[1, 2, 3, 4]);
        grown.pop();
        grown.pop();
        let fresh = SeqOf::<u8, 4, 2>::from_slice(&[1, 2]).unwrap();
        assert_eq!(grown, fresh);
        assert_eq!(hash(&grown), hash(&fresh));
        assert_eq!(grown.clone(), fresh);
        // The same for a text that outgrew the inline room and was refilled short.
        let mut long = Ia5::<40>::try_from_str("a name longer than fifteen").unwrap();
        long.clear();
        long.push('a').unwrap();
        long.push('b').unwrap();
        let short = Ia5::<40>::try_from_str("ab").unwrap();
        assert_eq!(long, short);
        assert_eq!(hash(&long), hash(&short));
        assert_eq!(long.as_str(), "ab");
    }

    #[test]
    fn seq_of_capacity() {
        let mut s: SeqOf<u8, 2> = SeqOf::new();
        assert!(s.push(1).is_ok());
        assert!(s.push(2).is_ok());
        if cfg!(feature = "alloc") {
            assert!(s.push(3).is_ok());
        } else {
            assert_eq!(s.push(3), Err(3));
        }
        assert_eq!(&s[..2], &[1, 2]);
    }

    #[test]
    fn a_cleared_sequence_keeps_its_items_storage_and_clones_only_its_items() {
        let mut outer: SeqOf<Octets<4>, 3> = SeqOf::new();
        for k in 0..3u8 {
            let inner = outer.push_slot().unwrap();
            assert_eq!(
                inner.grow(3).unwrap(),
                &[0, 0, 0],
                "new slots are placeholders"
            );
            inner.copy_from_slice(&[k + 1; 3]);
        }
        outer.clear();
        assert!(outer.is_empty());
        // The first slot comes back with its former items (and, with `alloc`, its vector).
        let again = outer.push_slot().unwrap();
        again.clear();
        assert_eq!(again.grow(1).unwrap(), &[1], "the kept item's former octet");
        let copy = outer.clone();
        assert_eq!(copy.len(), 1);
        assert_eq!(copy, outer);
        assert_eq!(copy.items.len(), 1, "the kept slots are not copied");
        assert_eq!(outer.items.len(), 3);
        outer.drop_spare();
        let kept = if cfg!(feature = "alloc") { 1 } else { 3 };
        assert_eq!(
            outer.items.len(),
            kept,
            "with alloc the spare slots are dropped"
        );
        assert_eq!(outer.len(), 1);
    }

    #[test]
    fn growing_past_the_no_heap_capacity_is_refused_unchanged() {
        let mut s: Octets<4> = SeqOf::new();
        assert_eq!(s.grow(3).map(|n| n.len()), Some(3));
        if cfg!(feature = "alloc") {
            assert_eq!(s.grow(2).map(|n| n.len()), Some(2));
        } else {
            assert!(s.grow(2).is_none());
            assert_eq!(s.len(), 3);
        }
        assert!(s.grow(usize::MAX).is_none());
    }

    #[test]
    fn ia5_refuses_non_ascii() {
        assert!(Ia5::<8>::try_from_str("Main St").is_some());
        assert!(Ia5::<8>::try_from_str("Straße").is_none());
    }

    #[test]
    fn bits_are_msb_first_and_masked() {
        let b = Bits::<2>::from_bytes(&[0b1010_0000, 0xff], 10).unwrap();
        assert!(b.get(0) && !b.get(1) && b.get(2) && b.get(8) && b.get(9));
        assert!(!b.get(10));
        assert_eq!(b.as_bytes(), &[0b1010_0000, 0b1100_0000]);
        assert!(Bits::<1>::zeros(9).is_none());
    }
}
