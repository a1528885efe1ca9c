//! Per-thread recycling of list storage and message boxes (features `alloc` and `std`).
//!
//! Without it, a new value's decode with `alloc` allocates every list of the new value and
//! fills it with placeholders, and dropping the value walks it item by item and frees it,
//! which makes a new value much slower to decode than a kept one. A decoding loop drops one
//! message and decodes the next, so that storage comes back as soon as it is needed again.
//! When a list's heap storage is dropped, it goes to this thread's shelf for its item type,
//! items and all (each item keeps its own lists, as the items of a kept value do); the next
//! new list of that item type takes it and is refilled in place, as a kept value is. A
//! MessageFrame's message box (`MessageBox`) is kept the same way, value and all, for the
//! next new message of its type.
//!
//! Bounds: at most [`PER_TYPE`] storages per item type are kept, each of at most
//! [`MAX_LIST_OCTETS`] octets of items (what does not fit is freed), and a thread's shelves
//! are freed with the thread or by [`release_recycled`]. What is kept is
//! the storage of values the thread has dropped: never more than those values held.

use alloc::boxed::Box;
use alloc::vec::Vec;
use core::any::{Any, TypeId};
use core::cell::RefCell;
use core::hash::{Hash, Hasher};

/// Storages kept per item type: a loop that drops a few messages at once still finds one
/// for each of the next.
pub const PER_TYPE: usize = 4;

/// The largest list storage kept, in octets of items (the lanes of a large intersection
/// take a few KiB; a larger one is freed).
pub const MAX_LIST_OCTETS: usize = 64 * 1024;

/// The storages of one item type (`X` is `Vec<T>` for a list, `Box<T>` for a boxed value).
type Shelf<X> = heapless::Vec<X, PER_TYPE, u8>;

/// Item types a thread can keep storage for at once (a slot per type, found by the type's
/// hash; a type whose slot another type took is not kept: a few dozen types meet in a
/// thread, so that is rare).
const SLOTS: usize = 256;

/// The shelves of one thread: a slot per item type, found by its `TypeId`'s hash (no
/// table that grows, no probing).
struct Shelves {
    slots: [Option<(TypeId, Box<dyn Any>)>; SLOTS],
}

impl Shelves {
    const fn new() -> Self {
        Self {
            slots: [const { None }; SLOTS],
        }
    }

    /// The slot of `T`'s storages.
    fn slot<T: 'static>(&mut self) -> &mut Option<(TypeId, Box<dyn Any>)> {
        let id = TypeId::of::<T>();
        let mut hash = IdHash(0);
        id.hash(&mut hash);
        // The top bits of a Fibonacci multiple spread any 64 bits over the slots.
        let index = (hash.0.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 56) as usize % SLOTS;
        &mut self.slots[index]
    }

    /// `T`'s shelf, if it has one.
    fn shelf<T: 'static>(&mut self) -> Option<&mut Shelf<T>> {
        match self.slot::<T>() {
            Some((id, shelf)) if *id == TypeId::of::<T>() => shelf.downcast_mut(),
            _ => None,
        }
    }

    /// `T`'s shelf, made if its slot is free.
    fn shelf_or_new<T: 'static>(&mut self) -> Option<&mut Shelf<T>> {
        let slot = self.slot::<T>();
        if slot.is_none() {
            *slot = Some((TypeId::of::<T>(), Box::new(Shelf::<T>::new())));
        }
        self.shelf()
    }
}

/// Takes the 64 bits a `TypeId` hashes (already a hash: no mixing needed here).
struct IdHash(u64);

impl Hasher for IdHash {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = self.0.rotate_left(8) ^ u64::from(b);
        }
    }

    fn write_u64(&mut self, v: u64) {
        self.0 ^= v;
    }
}

std::thread_local! {
    static SHELVES: RefCell<Shelves> = const { RefCell::new(Shelves::new()) };
}

/// A list storage of items of `T` that this thread dropped, if one is kept. Out of line,
/// as [`put`].
#[inline(never)]
pub(super) fn take<T: 'static>() -> Option<Vec<T>> {
    take_kept()
}

/// A box of `T` that this thread dropped, with its former value, if one is kept.
#[inline(never)]
pub(super) fn take_box<T: 'static>() -> Option<Box<T>> {
    take_kept()
}

/// Keeps a box being dropped (with its value) for the next new `MessageBox<T>`, if there is
/// room.
#[inline(never)]
pub(super) fn put_box<T: 'static>(value: Box<T>) {
    if core::mem::size_of::<T>() <= MAX_LIST_OCTETS {
        keep(value);
    }
}

/// A storage `X` this thread kept, if any.
#[inline]
fn take_kept<X: 'static>() -> Option<X> {
    SHELVES
        .try_with(|cell| cell.try_borrow_mut().ok()?.shelf::<X>()?.pop())
        .ok()
        .flatten()
}

/// Keeps `storage` on its shelf if there is room; otherwise it is dropped, outside the
/// shelves (its own lists and boxes may then be kept).
#[inline]
fn keep<X: 'static>(storage: X) {
    let refused = SHELVES.try_with(move |cell| match cell.try_borrow_mut() {
        Ok(mut shelves) => match shelves.shelf_or_new::<X>() {
            Some(shelf) => shelf.push(storage).err(),
            None => Some(storage),
        },
        Err(_) => Some(storage),
    });
    drop(refused);
}

/// Keeps `items` (a list storage being dropped) for the next new list of `T`, if there is
/// room; otherwise it is dropped, outside the shelves.
// Out of line: inlined into every list's drop glue, the shelf code made a kept value's
// decode (which drops the lists an absent member held) 1-5 % slower.
#[inline(never)]
pub(super) fn put<T: 'static>(items: Vec<T>) {
    if items.capacity() * core::mem::size_of::<T>() <= MAX_LIST_OCTETS {
        keep(items);
    }
}

/// Frees this thread's kept list storage (it is freed with the thread otherwise).
pub fn release_recycled() {
    let shelves = SHELVES
        .try_with(|cell| {
            cell.try_borrow_mut()
                .map(|mut s| core::mem::replace(&mut *s, Shelves::new()))
        })
        .ok()
        .and_then(Result::ok);
    drop(shelves);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uper::{MessageBox, Placeholder, SeqOf};

    /// An item type of these tests alone (each test also starts from empty shelves: the
    /// harness may run tests on one thread).
    #[derive(Clone, Debug, PartialEq)]
    struct Item(u32);

    impl Placeholder for Item {
        fn placeholder() -> Self {
            Item(0)
        }
    }

    /// A list of `n` items numbered from `first`.
    fn list(first: u32, n: u32) -> SeqOf<Item, 64> {
        let mut s = SeqOf::new();
        for i in 0..n {
            s.push(Item(first + i)).unwrap();
        }
        s
    }

    /// How many list storages of `Item` this thread keeps (taking them).
    fn kept_lists() -> usize {
        core::iter::from_fn(take_kept::<Vec<Item>>).count()
    }

    #[test]
    fn a_dropped_list_storage_is_the_next_new_list_of_its_item_type() {
        release_recycled();
        let old = list(1, 3);
        let storage = old.as_ptr();
        drop(old);
        // A list grown for anything but a decode never shows another list's items.
        let mut built = SeqOf::<Item, 64>::new();
        assert_eq!(built.grow(2).unwrap(), [Item(0), Item(0)]);
        assert_eq!(built.push_slot().unwrap(), &Item(0));
        assert_ne!(built.as_ptr(), storage);
        let mut new = SeqOf::<Item, 64>::new();
        assert!(new.is_empty(), "a new list shows none of the former items");
        let slots = new.grow_decoding(2).unwrap();
        assert_eq!(slots.as_ptr(), storage, "the dropped storage was taken");
        // The slots hold the former items, to be overwritten by the decode.
        assert_eq!(slots, [Item(1), Item(2)]);
        assert_eq!(new.len(), 2);
        // A list of another item type does not get it.
        drop(new);
        let other = SeqOf::<u8, 64>::from_slice(&[7; 40]).unwrap();
        assert_ne!(other.as_ptr(), storage.cast::<u8>());
    }

    #[test]
    fn a_shelf_keeps_at_most_per_type_storages_and_none_too_large() {
        release_recycled();
        let lists: Vec<_> = (0..PER_TYPE as u32 + 2).map(|i| list(i, 2)).collect();
        drop(lists);
        assert_eq!(kept_lists(), PER_TYPE);
        let mut huge = SeqOf::<Item, 64>::new();
        huge.grow_decoding(MAX_LIST_OCTETS / core::mem::size_of::<Item>() + 1)
            .unwrap();
        drop(huge);
        assert_eq!(kept_lists(), 0, "over {MAX_LIST_OCTETS} octets is freed");
        drop(SeqOf::<Item, 64>::new());
        assert_eq!(kept_lists(), 0, "a list that never allocated gives nothing");
    }

    #[test]
    fn a_dropped_box_is_the_next_placeholder_with_its_former_value() {
        release_recycled();
        let old = MessageBox::new(Item(41));
        let place: *const Item = &*old;
        drop(old);
        // Only a decode's placeholder is a former message.
        let built = <MessageBox<Item> as Placeholder>::placeholder();
        assert_eq!(*built, Item(0));
        let new = <MessageBox<Item> as Placeholder>::decode_placeholder();
        assert_eq!(&*new as *const Item, place);
        assert_eq!(*new, Item(41), "to be overwritten by the decode");
        // None left: the next is a new box with the type's placeholder.
        assert_eq!(
            *<MessageBox<Item> as Placeholder>::decode_placeholder(),
            Item(0)
        );
        // A value taken out of its box leaves nothing on the shelf.
        drop(built);
        release_recycled();
        assert_eq!(new.into_inner(), Item(41));
        assert!(take_box::<Item>().is_none());
    }

    #[test]
    fn a_list_that_leaves_its_inline_slots_keeps_its_items_in_a_recycled_storage() {
        release_recycled();
        // Octets keep 15 inline; a dropped 20-octet storage waits on the shelf.
        drop(crate::uper::Octets::<64>::from_slice(&[0xEE; 20]).unwrap());
        let mut octets = crate::uper::Octets::<64>::new();
        for b in 0..15u8 {
            octets.push(b).unwrap();
        }
        octets.grow_decoding(1).unwrap()[0] = 15;
        assert_eq!(octets[..], (0..16).collect::<Vec<u8>>()[..]);
        assert!(
            take_kept::<Vec<u8>>().is_none(),
            "the spill took the kept storage"
        );
    }

    #[test]
    fn nested_lists_stay_in_their_kept_items() {
        release_recycled();
        let mut outer = SeqOf::<SeqOf<Item, 64>, 8>::new();
        outer.push(list(5, 2)).unwrap();
        outer.push(list(9, 3)).unwrap();
        let inner = outer[1].as_ptr();
        drop(outer);
        assert_eq!(
            kept_lists(),
            0,
            "the inner lists were kept inside their items"
        );
        let mut again = SeqOf::<SeqOf<Item, 64>, 8>::new();
        let slots = again.grow_decoding(2).unwrap();
        assert_eq!(slots[1].as_ptr(), inner);
    }

    #[test]
    fn shelves_are_per_thread_and_can_be_released() {
        release_recycled();
        drop(list(1, 2));
        std::thread::spawn(|| assert_eq!(kept_lists(), 0, "another thread's shelf"))
            .join()
            .unwrap();
        release_recycled();
        assert_eq!(kept_lists(), 0);
        // A thread ends with storage on its shelves: dropping them keeps nothing more
        // (the shelves are gone) and does not panic.
        std::thread::spawn(|| {
            let mut outer = SeqOf::<SeqOf<Item, 64>, 8>::new();
            outer.push(list(1, 2)).unwrap();
            drop(outer);
            drop(MessageBox::new(list(3, 2)));
        })
        .join()
        .unwrap();
    }
}
