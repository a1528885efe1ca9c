//! The `alloc` slot storage of a [`super::SeqOf`]: up to `I` slots inside the value, more on
//! the heap.
//!
//! A new value's decode with `alloc` spends most of its extra time (over a kept value's)
//! in the allocator: one `malloc` and `free` per list, and glibc's slow paths once a frame
//! has more than seven lists of one size. Most lists of real traffic hold one or a few small
//! items (a SPaT movement's one event, a lane's one connection or few overlay lanes, a few
//! octets of an unknown extension), so those lists keep their first `I` slots in place and
//! allocate only when they grow past them. `I` is chosen per list type by the code generator
//! (`[inline]` in `codec/codegen/capacities.toml`); with `I = 0` the storage is exactly a
//! `Vec` (the enum takes no more room: its tag lives in the `Vec`'s capacity niche).
//!
//! Built on `heapless::Vec` and `Vec` so that this crate stays free of unsafe code.

use alloc::collections::TryReserveError;
use alloc::vec::Vec;

/// Slots of a sequence: `Inline` until more than `I` are needed, then `Heap` for good (a kept
/// value keeps its allocation for the next message).
pub(super) enum Slots<T: 'static, const I: usize> {
    /// At most `I` slots inside the value (the length fits a `u8`: `I` is a few items).
    Inline(heapless::Vec<T, I, u8>),
    /// Slots on the heap.
    Heap(Vec<T>),
}

impl<T: 'static, const I: usize> Slots<T, I> {
    /// No slots, no allocation (with `I = 0` the heap storage from the start, so that such
    /// a list never spills).
    pub(super) const fn new() -> Self {
        if I == 0 {
            Self::Heap(Vec::new())
        } else {
            Self::Inline(heapless::Vec::new())
        }
    }

    /// The initialised slots.
    #[inline]
    pub(super) fn as_slice(&self) -> &[T] {
        match self {
            Self::Inline(v) => v,
            Self::Heap(v) => v,
        }
    }

    /// The initialised slots, writable.
    #[inline]
    pub(super) fn as_mut_slice(&mut self) -> &mut [T] {
        match self {
            Self::Inline(v) => v,
            Self::Heap(v) => v,
        }
    }

    /// How many slots are initialised.
    #[inline]
    pub(super) fn len(&self) -> usize {
        self.as_slice().len()
    }

    /// Grows to `new_len` initialised slots (a no-op when there are as many already), the new
    /// ones made by `make` in place. Room beyond the inline slots is reserved exactly the
    /// first time (a decode knows the length before the items) and amortised later. With
    /// `recycled` (a decode, which overwrites them), storage without room may be one this
    /// thread dropped, whose former items then are the slots.
    #[inline]
    pub(super) fn grow_to(
        &mut self,
        new_len: usize,
        make: impl FnMut() -> T,
        recycled: bool,
    ) -> Result<(), TryReserveError> {
        let len = self.len();
        if new_len <= len {
            return Ok(());
        }
        if let Self::Inline(v) = self {
            if new_len <= I {
                let mut make = make;
                while v.len() < new_len {
                    // Cannot fail: `new_len <= I`.
                    let _ = v.push(make());
                }
                return Ok(());
            }
        }
        self.on_heap(new_len - len, recycled, |heap| {
            if recycled && heap.capacity() == 0 {
                *heap = take_recycled();
            }
            if new_len <= heap.len() {
                return Ok(());
            }
            let more = new_len - heap.len();
            if heap.capacity() == 0 {
                heap.try_reserve_exact(more)?;
            } else if heap.capacity() < new_len {
                heap.try_reserve(more)?;
            }
            heap.resize_with(new_len, make);
            Ok(())
        })
    }

    /// Makes room for `additional` more slots than are initialised.
    pub(super) fn reserve(&mut self, additional: usize) {
        if self.len().saturating_add(additional) <= I && matches!(self, Self::Inline(_)) {
            return;
        }
        // An allocation failure here leaves the room to the growth that follows.
        let _ = self.on_heap(additional, false, |heap| heap.try_reserve(additional));
    }

    /// Keeps the first `len` slots.
    #[inline]
    pub(super) fn truncate(&mut self, len: usize) {
        match self {
            Self::Inline(v) => v.truncate(len),
            Self::Heap(v) => v.truncate(len),
        }
    }

    /// Removes the last slot.
    #[inline]
    pub(super) fn pop(&mut self) -> Option<T> {
        match self {
            Self::Inline(v) => v.pop(),
            Self::Heap(v) => v.pop(),
        }
    }

    /// A copy of `items`, inline when they fit.
    pub(super) fn from_items(items: &[T]) -> Self
    where
        T: Clone,
    {
        match heapless::Vec::from_slice(items) {
            Ok(v) => Self::Inline(v),
            Err(_) => Self::Heap(items.to_vec()),
        }
    }

    /// Runs `f` on the heap storage, moving the inline slots there first with room for
    /// `additional` more (exactly: the first room of a decode is its list's length), into a
    /// storage this thread dropped if `recycled`.
    fn on_heap<R>(
        &mut self,
        additional: usize,
        recycled: bool,
        f: impl FnOnce(&mut Vec<T>) -> Result<R, TryReserveError>,
    ) -> Result<R, TryReserveError> {
        match self {
            Self::Heap(heap) => f(heap),
            Self::Inline(v) => {
                let mut heap = if recycled {
                    take_recycled()
                } else {
                    Vec::new()
                };
                let need = v.len().saturating_add(additional);
                heap.try_reserve_exact(need.saturating_sub(heap.len()))?;
                // The inline items become the first slots (a recycled storage's former
                // items beyond them stay as spare slots).
                let mut items = v.drain(..);
                for slot in heap.iter_mut() {
                    match items.next() {
                        Some(item) => *slot = item,
                        None => break,
                    }
                }
                heap.extend(items);
                let out = f(&mut heap);
                *self = Self::Heap(heap);
                out
            }
        }
    }
}

/// Heap storage for a list that has none: one this thread dropped, items and all, if it
/// kept one (feature `std`, see `recycle.rs`), else an empty `Vec`.
#[inline]
fn take_recycled<T: 'static>() -> Vec<T> {
    #[cfg(feature = "std")]
    if let Some(kept) = super::recycle::take() {
        return kept;
    }
    Vec::new()
}

#[cfg(feature = "std")]
impl<T: 'static, const I: usize> Drop for Slots<T, I> {
    /// Keeps the heap storage, items and all, for this thread's next new list of `T` (see
    /// `recycle.rs`).
    fn drop(&mut self) {
        // A list that never allocated (most absent members' and empty lists') costs a test.
        if let Self::Heap(heap) = self {
            if heap.capacity() != 0 {
                super::recycle::put(core::mem::take(heap));
            }
        }
    }
}

/// Characters an IA5String keeps inside the value with `alloc` before it allocates (15 take
/// no more room than the `String` they spare). Real traffic's names ("Lane 1", an
/// intersection's name) are mostly shorter.
pub const IA5_INLINE: usize = 15;

/// The `alloc` storage of an IA5String: inline up to [`IA5_INLINE`] characters, else a
/// `String` (kept for reuse once made, as [`Slots`]).
#[derive(Clone)]
pub(super) enum Text {
    /// A short text, inside the value.
    Inline(heapless::String<IA5_INLINE, u8>),
    /// A longer text.
    Heap(alloc::string::String),
}

impl Text {
    /// An empty text, no allocation.
    pub(super) const fn new() -> Self {
        Self::Inline(heapless::String::new())
    }

    /// The text.
    #[inline]
    pub(super) fn as_str(&self) -> &str {
        match self {
            Self::Inline(s) => s,
            Self::Heap(s) => s,
        }
    }

    /// Appends one character (the caller checked that it is ASCII).
    pub(super) fn push(&mut self, c: char) {
        debug_assert!(c.is_ascii());
        self.push_ascii(&[c as u8]);
    }

    /// Appends `run`, 7-bit characters: one at a time while they fit inside the value (a
    /// name of a few), else copied in one piece.
    pub(super) fn push_ascii(&mut self, run: &[u8]) {
        if let Self::Inline(s) = self {
            if s.len() + run.len() <= IA5_INLINE {
                for &b in run {
                    // Cannot fail: the room was checked above.
                    let _ = s.push(char::from(b));
                }
                return;
            }
            self.spill(run.len());
        }
        if let (Self::Heap(s), Ok(text)) = (self, core::str::from_utf8(run)) {
            s.push_str(text);
        }
    }

    /// Makes room for `additional` more characters (exactly, when the text leaves the value).
    pub(super) fn reserve(&mut self, additional: usize) {
        match self {
            Self::Inline(s) if s.len().saturating_add(additional) <= IA5_INLINE => {}
            Self::Inline(_) => self.spill(additional),
            Self::Heap(s) => s.reserve(additional),
        }
    }

    /// Removes every character (a heap text keeps its allocation).
    pub(super) fn clear(&mut self) {
        match self {
            Self::Inline(s) => s.clear(),
            Self::Heap(s) => s.clear(),
        }
    }

    /// Moves an inline text to the heap, with room for `additional` more characters.
    fn spill(&mut self, additional: usize) {
        if let Self::Inline(s) = self {
            let mut heap = alloc::string::String::with_capacity(s.len().saturating_add(additional));
            heap.push_str(s);
            *self = Self::Heap(heap);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn items<const I: usize>(s: &Slots<u32, I>) -> &[u32] {
        s.as_slice()
    }

    #[test]
    fn stays_inline_up_to_i_then_moves_to_the_heap_in_order() {
        let mut s = Slots::<u32, 2>::new();
        let mut next = 0;
        let mut make = || {
            next += 1;
            next
        };
        s.grow_to(2, &mut make, false).unwrap();
        assert!(matches!(s, Slots::Inline(_)));
        assert_eq!(items(&s), [1, 2]);
        s.grow_to(5, &mut make, false).unwrap();
        let Slots::Heap(v) = &s else {
            panic!("five items cannot be inline");
        };
        // The first room is exact: a decode knows its list's length.
        assert_eq!(v.capacity(), 5);
        assert_eq!(items(&s), [1, 2, 3, 4, 5]);
        s.truncate(1);
        assert_eq!(s.pop(), Some(1));
        assert_eq!(s.len(), 0);
        // Emptied, it keeps its allocation for the next message.
        assert!(matches!(&s, Slots::Heap(v) if v.capacity() >= 5));
    }

    #[test]
    fn no_inline_room_means_the_heap_from_the_start() {
        let mut s = Slots::<u32, 0>::new();
        assert!(matches!(s, Slots::Heap(_)));
        s.grow_to(3, || 9, false).unwrap();
        assert_eq!(items(&s), [9, 9, 9]);
        assert!(matches!(&s, Slots::Heap(v) if v.capacity() == 3));
    }

    #[test]
    fn a_copy_is_inline_when_it_fits() {
        assert!(matches!(
            Slots::<u32, 3>::from_items(&[1, 2]),
            Slots::Inline(_)
        ));
        let big = Slots::<u32, 3>::from_items(&[1, 2, 3, 4]);
        assert!(matches!(big, Slots::Heap(_)));
        assert_eq!(big.as_slice(), [1, 2, 3, 4]);
    }

    #[test]
    fn reserving_past_the_inline_room_moves_the_items() {
        let mut s = Slots::<u32, 2>::from_items(&[7]);
        s.reserve(1);
        assert!(matches!(s, Slots::Inline(_)));
        s.reserve(4);
        assert!(matches!(&s, Slots::Heap(v) if v.capacity() >= 5));
        assert_eq!(s.as_slice(), [7]);
    }

    #[test]
    fn a_text_stays_inline_up_to_fifteen_characters() {
        let mut t = Text::new();
        t.push_ascii(b"Lane 12");
        t.push('A');
        assert!(matches!(t, Text::Inline(_)));
        assert_eq!(t.as_str(), "Lane 12A");
        t.push_ascii(b"1234567");
        assert!(matches!(t, Text::Inline(_)));
        t.push('!');
        assert!(matches!(t, Text::Heap(_)));
        assert_eq!(t.as_str(), "Lane 12A1234567!");
        t.clear();
        t.push_ascii(b"ab");
        assert!(matches!(t, Text::Heap(_)));
        assert_eq!(t.as_str(), "ab");
    }

    #[test]
    fn a_long_run_goes_to_the_heap_in_one_piece() {
        let mut t = Text::new();
        t.reserve(3);
        assert!(matches!(t, Text::Inline(_)));
        t.push_ascii(b"abc");
        t.reserve(40);
        assert!(matches!(&t, Text::Heap(s) if s.capacity() >= 43));
        t.push_ascii(&[b'x'; 40]);
        assert_eq!(t.as_str().len(), 43);
        assert!(t.as_str().starts_with("abcx"));
    }
}
