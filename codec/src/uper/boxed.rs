//! [`Boxed`]: a member kept behind a pointer with `alloc`, in place without it; and
//! [`MessageBox`]: the same for a MessageFrame's message, whose box a thread reuses.

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

/// What a box shares with the value it holds, for [`Boxed`] and [`MessageBox`] (`$bound`:
/// the bound the box itself puts on `T`): `From<T>`, and `Debug`, UPER and random values as
/// if it were not boxed.
macro_rules! stands_for_its_value {
    ($box:ident $(: $bound:lifetime)?) => {
        impl<T $(: $bound)?> From<T> for $box<T> {
            fn from(value: T) -> Self {
                Self::new(value)
            }
        }

        impl<T: fmt::Debug $(+ $bound)?> fmt::Debug for $box<T> {
            /// The value's `Debug`, as if it were not boxed.
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                T::fmt(self, f)
            }
        }

        impl<T: Uper $(+ $bound)?> Uper for $box<T> {
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
        impl<T: super::random::Random $(+ $bound)?> super::random::Random for $box<T> {
            fn random(g: &mut super::random::Gen) -> Self {
                Self::new(T::random(g))
            }
        }
    };
}

stands_for_its_value!(Boxed);
stands_for_its_value!(MessageBox: 'static);

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

impl<T: Placeholder> Placeholder for Boxed<T> {
    fn placeholder() -> Self {
        Self::new(T::placeholder())
    }
}

/// A message of a MessageFrame: a [`Boxed`] whose box, with features `alloc` and `std`, this
/// thread reuses.
///
/// A dropped `MessageBox<T>` gives its box, value and all, to this thread's shelf for `T`;
/// the next new `MessageBox<T>` of a decode takes it and the decode refills it in place, as
/// it refills a kept value (its lists keep their storage). A loop that decodes new values
/// and drops them then allocates nothing in the steady state (see `recycle.rs`: at most four
/// boxes per message type are kept per thread). Without `std` it is a [`Boxed`].
///
/// Read and write it through `Deref`/`DerefMut`; make one with [`MessageBox::new`] or `From<T>`.
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct MessageBox<T: 'static>(
    /// `None` only once `drop` took the box.
    #[cfg(feature = "std")]
    Option<Boxed<T>>,
    #[cfg(not(feature = "std"))] Boxed<T>,
);

impl<T: 'static> MessageBox<T> {
    /// `value`, boxed with `alloc`.
    pub fn new(value: T) -> Self {
        Self::from_boxed(Boxed::new(value))
    }

    /// The value (its box is freed, not recycled).
    pub fn into_inner(self) -> T {
        #[cfg(feature = "std")]
        {
            let mut this = self;
            match this.0.take() {
                Some(b) => b.into_inner(),
                None => taken(),
            }
        }
        #[cfg(not(feature = "std"))]
        self.0.into_inner()
    }

    fn from_boxed(b: Boxed<T>) -> Self {
        #[cfg(feature = "std")]
        return Self(Some(b));
        #[cfg(not(feature = "std"))]
        return Self(b);
    }

    /// The box.
    #[inline]
    fn boxed(&self) -> &Boxed<T> {
        #[cfg(feature = "std")]
        return self.0.as_ref().unwrap_or_else(|| taken());
        #[cfg(not(feature = "std"))]
        return &self.0;
    }

    /// The box, writable.
    #[inline]
    fn boxed_mut(&mut self) -> &mut Boxed<T> {
        #[cfg(feature = "std")]
        return self.0.as_mut().unwrap_or_else(|| taken());
        #[cfg(not(feature = "std"))]
        return &mut self.0;
    }
}

/// A `MessageBox` without its box: only `drop` takes it, so no method ever sees one.
#[cfg(feature = "std")]
#[cold]
fn taken() -> ! {
    unreachable!("a MessageBox holds its box until it is dropped")
}

#[cfg(feature = "std")]
impl<T: 'static> Drop for MessageBox<T> {
    /// Gives the box, value and all, to this thread's next new `MessageBox<T>`.
    fn drop(&mut self) {
        if let Some(b) = self.0.take() {
            super::recycle::put_box(b.0);
        }
    }
}

impl<T: 'static> Deref for MessageBox<T> {
    type Target = T;
    #[inline]
    fn deref(&self) -> &T {
        self.boxed()
    }
}

impl<T: 'static> DerefMut for MessageBox<T> {
    #[inline]
    fn deref_mut(&mut self) -> &mut T {
        self.boxed_mut()
    }
}

impl<T: Placeholder + 'static> Placeholder for MessageBox<T> {
    /// A new box with `T`'s placeholder.
    fn placeholder() -> Self {
        Self::from_boxed(Boxed::placeholder())
    }

    /// For a decode: a box this thread recycled, holding a former message that the decode
    /// refills in place (features `alloc` and `std`), else [`Placeholder::placeholder`].
    #[inline]
    fn decode_placeholder() -> Self {
        #[cfg(feature = "std")]
        if let Some(b) = super::recycle::take_box() {
            return Self::from_boxed(Boxed(b));
        }
        Self::placeholder()
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
