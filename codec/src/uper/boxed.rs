//! [`Boxed`]: a member kept behind a pointer with `alloc`, in place without it.

use core::fmt;
use core::ops::{Deref, DerefMut};

#[cfg(feature = "alloc")]
use alloc::boxed::Box;

use super::{DecodeResult, EncodeResult, Placeholder, Reader, Uper, Writer};

/// A value of `T` that a generated type keeps on the heap with feature `alloc` and in place
/// without it.
///
/// The generator boxes a few OPTIONAL members that are large and mostly absent (a node's
/// attribute set: a quarter of a `NodeXY`'s size, present on a fifth of the corpus's nodes;
/// see `[boxed]` in `codec/codegen/capacities.toml`). With `alloc` their parent then takes a
/// pointer's room instead of the member's, so that a list of nodes is a fraction of the size
/// to allocate, write and drop. Without `alloc` nothing changes: the value is in place.
///
/// Read and write it through `Deref`/`DerefMut`; make one with [`Boxed::new`] or `From<T>`.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct Boxed<T>(
    #[cfg(feature = "alloc")] Box<T>,
    #[cfg(not(feature = "alloc"))] T,
);

impl<T> Boxed<T> {
    /// `value`, boxed with `alloc`.
    pub fn new(value: T) -> Self {
        #[cfg(feature = "alloc")]
        return Self(Box::new(value));
        #[cfg(not(feature = "alloc"))]
        return Self(value);
    }

    /// The value.
    pub fn into_inner(self) -> T {
        #[cfg(feature = "alloc")]
        return *self.0;
        #[cfg(not(feature = "alloc"))]
        return self.0;
    }
}

impl<T> From<T> for Boxed<T> {
    fn from(value: T) -> Self {
        Self::new(value)
    }
}

impl<T> Deref for Boxed<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

impl<T> DerefMut for Boxed<T> {
    fn deref_mut(&mut self) -> &mut T {
        &mut self.0
    }
}

impl<T: fmt::Debug> fmt::Debug for Boxed<T> {
    /// The value's `Debug`, as if it were not boxed.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        T::fmt(self, f)
    }
}

impl<T: Placeholder> Placeholder for Boxed<T> {
    fn placeholder() -> Self {
        Self::new(T::placeholder())
    }
}

impl<T: Uper> Uper for Boxed<T> {
    const PATH: &'static str = T::PATH;
    const MAX_UPER_BITS: Option<u64> = T::MAX_UPER_BITS;

    #[inline]
    fn decode_body_into(r: &mut Reader<'_>, out: &mut Self) -> DecodeResult<()> {
        T::decode_body_into(r, out)
    }

    #[inline]
    fn encode_body(&self, w: &mut Writer<'_>) -> EncodeResult {
        T::encode_body(self, w)
    }

    #[inline]
    fn decode_into(r: &mut Reader<'_>, out: &mut Self) -> DecodeResult<()> {
        T::decode_into(r, out)
    }

    #[inline]
    fn encode_uper(&self, w: &mut Writer<'_>) -> EncodeResult {
        T::encode_uper(self, w)
    }
}

#[cfg(feature = "_random")]
impl<T: super::random::Random> super::random::Random for Boxed<T> {
    fn random(g: &mut super::random::Gen) -> Self {
        Self::new(T::random(g))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_and_writes_through_the_box() {
        let mut b = Boxed::new(7u8);
        *b += 1;
        assert_eq!(*b, 8);
        assert_eq!(b.clone().into_inner(), 8);
        assert_eq!(Boxed::from(8u8), b);
        assert_eq!(std::format!("{b:?}"), "8");
    }

    #[test]
    fn takes_a_pointer_with_alloc_and_the_value_without() {
        let size = core::mem::size_of::<Option<Boxed<[u64; 8]>>>();
        if cfg!(feature = "alloc") {
            assert_eq!(size, core::mem::size_of::<usize>());
        } else {
            assert!(size >= 64);
        }
    }
}
