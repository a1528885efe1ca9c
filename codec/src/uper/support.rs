//! What the generated types call and nothing else does: the constant placeholders of
//! `alloc`, making an OPTIONAL member present, switching a CHOICE's alternative, and the
//! storage-dependent bounds of `Uper::MAX_UPER_BITS`. Public through `crate::__private`
//! only (hidden from the docs).

use super::Placeholder;

/// A type's [`Placeholder`] as a constant, with `alloc` (where every value is small): the
/// placeholder of each new list item ([`Placeholder::item_placeholder`]).
///
/// A new value's decode with `alloc` makes a placeholder for every list item before decoding
/// into it. Made by a function, a placeholder is built in a temporary with narrow stores (a
/// CHOICE's tag, an integer, a `None`) and copied into its slot with wide loads that
/// overlap them, so each copy waits for the stores to complete (a failed store-to-load
/// forward), a visible share of a new TIM's decode time (`bash codec/bench/callgrind.sh
/// --features alloc`). A constant is copied from read-only memory instead.
///
/// Only list items of at most 64 octets use it ([`item_placeholder`]): for larger items, and
/// for present OPTIONAL members and chosen alternatives, a constant makes a new SPaT slower
/// (a large constant is copied whole, where the function writes little more than tags).
/// Without `alloc` it is not used: a large value's constant would be as large in flash.
#[cfg(feature = "alloc")]
pub trait ConstPlaceholder: Sized {
    /// The placeholder value.
    const PLACEHOLDER: Self;
}

/// A new list item's placeholder (what the generated types' [`Placeholder::item_placeholder`]
/// returns with `alloc`): the [`ConstPlaceholder`] of an item of at most 64 octets (a node, a
/// connection), else the function. A larger item's constant is copied whole, and for a SPaT's
/// 224-octet movements that took longer than the function (see `ConstPlaceholder`).
#[cfg(feature = "alloc")]
#[inline]
pub fn item_placeholder<T: Placeholder + ConstPlaceholder>() -> T {
    if core::mem::size_of::<T>() <= 64 {
        T::PLACEHOLDER
    } else {
        T::placeholder()
    }
}

/// Makes an absent optional value present (a placeholder). Without `alloc` it is out of
/// line: the large temporary lives in this function's frame, not in the hot decoding
/// function's. With `alloc` values are small and a new value's decode comes here for every
/// present member, so it is inlined (fewer instructions for a new SPaT, MAP or TIM, and a kept
/// value's about the same: `bash codec/bench/callgrind.sh --features alloc`).
#[cfg_attr(not(feature = "alloc"), cold, inline(never))]
#[cfg_attr(feature = "alloc", inline)]
pub fn fill_option<T: Placeholder>(slot: &mut Option<T>) {
    *slot = Some(T::placeholder());
}

/// Replaces `out` by `make()`, out of line (as [`fill_option`]); used to switch a CHOICE to
/// another alternative before decoding into it.
#[cold]
#[inline(never)]
pub fn replace_with<T, F: FnOnce() -> T>(out: &mut T, make: F) {
    *out = make();
}

/// Picks the bound of the build's storage: `no_heap` without `alloc`, `heap` with it.
pub const fn max_bits(no_heap: Option<u64>, heap: Option<u64>) -> Option<u64> {
    if cfg!(feature = "alloc") {
        heap
    } else {
        no_heap
    }
}

/// As [`max_bits`], for a type whose no-heap bound differs between the default capacity
/// profile and the firmware profile (feature `firmware-capacities`).
pub const fn max_bits_profiled(
    no_heap: Option<u64>,
    no_heap_firmware: Option<u64>,
    heap: Option<u64>,
) -> Option<u64> {
    if cfg!(feature = "firmware-capacities") {
        max_bits(no_heap_firmware, heap)
    } else {
        max_bits(no_heap, heap)
    }
}

#[cfg(feature = "alloc")]
impl ConstPlaceholder for bool {
    const PLACEHOLDER: Self = false;
}
