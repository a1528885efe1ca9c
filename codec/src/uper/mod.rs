//! The UPER runtime (ITU-T X.691, unaligned PER): bit reader and writer, whole numbers,
//! length determinants with fragmentation, sized values, extensions and open types, and the
//! [`Uper`] trait that every generated type implements.
//!
//! # Whole frames and trailing data
//! [`decode`] reads one complete encoding: after the value, the rest of the last octet must be
//! padding and no whole octet may follow ([`DecodeErrorKind::TrailingBytes`]). Inputs that
//! carry something after the frame (a signature, padding of a record) are decoded with
//! [`decode_prefix`], which returns the octets used.
//!
//! # Panics
//! Nothing in this module or in the generated code panics on any input: all reads are bounds
//! checked, all lengths are bounded by the bits that remain and by the no-heap capacities.
//! J2735 has no recursive types, so the nesting depth of any value is bounded by the schema.

mod boxed;
mod error;
pub(crate) mod ext;
#[cfg(feature = "_random")]
pub mod random;
mod reader;
#[cfg(feature = "std")]
mod recycle;
pub(crate) mod sized;
#[cfg(feature = "alloc")]
mod slots;
mod storage;
pub(crate) mod support;
mod writer;

pub use boxed::{Boxed, MessageBox};
pub use error::{DecodeError, DecodeErrorKind, EncodeError, EncodeErrorKind};
pub use ext::{Extensions, UnknownAdditions};
pub use reader::{DecodeResult, LengthChunk, Reader};
#[cfg(feature = "std")]
pub use recycle::release_recycled;
#[cfg(feature = "alloc")]
pub use slots::IA5_INLINE;
pub use storage::{Bits, Ia5, Octets, SeqOf, OCTETS_INLINE};
pub use writer::{EncodeResult, Writer};

/// A number outside a constrained INTEGER type's range (from `TryFrom`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OutOfRange;

impl core::fmt::Display for OutOfRange {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("value out of range")
    }
}

impl core::error::Error for OutOfRange {}

/// A cheap value of a type, to be overwritten by decoding in place. It need not satisfy the
/// type's constraints (a list may be shorter than its minimum size).
pub trait Placeholder: Sized {
    /// The placeholder value.
    fn placeholder() -> Self;

    /// The placeholder of a new list item: with `alloc` the generated types return
    /// `__private::item_placeholder` (a constant for small items), others
    /// [`Placeholder::placeholder`].
    #[doc(hidden)]
    #[inline]
    fn item_placeholder() -> Self {
        Self::placeholder()
    }

    /// The value a decode makes a CHOICE's new alternative from before decoding into it:
    /// [`Placeholder::placeholder`], except a [`MessageBox`]'s with features `alloc` and
    /// `std` (a box this thread recycled, holding a former message that the decode
    /// overwrites). Never a former value anywhere else.
    #[doc(hidden)]
    #[inline]
    fn decode_placeholder() -> Self {
        Self::placeholder()
    }
}

impl Placeholder for u8 {
    fn placeholder() -> Self {
        0
    }
}

/// A type with a UPER encoding. Implemented by every generated J2735 type.
///
/// Decoding writes into an existing value ([`Uper::decode_into`]): lists and nested values
/// are filled where they are, so that a value kept between messages (as a firmware would keep
/// one static `MapData`) is decoded without moving large no-heap storage around.
pub trait Uper: Placeholder {
    /// `Module.Type` of the ASN.1 definition (or `Module.Parent.field` for an inline type).
    const PATH: &'static str;
    /// Largest encoding in bits, where the type (with the build's storage) bounds it.
    const MAX_UPER_BITS: Option<u64>;

    /// Decodes the value's encoding into `out` (without error context; use
    /// [`Uper::decode_into`]). After an error `out` holds an unspecified valid value.
    fn decode_body_into(r: &mut Reader<'_>, out: &mut Self) -> DecodeResult<()>;
    /// Encodes the value (without error context; use [`Uper::encode_uper`]).
    fn encode_body(&self, w: &mut Writer<'_>) -> EncodeResult;

    /// Decodes one value from `r` into `out`; errors name this type if nothing inside did.
    #[inline]
    fn decode_into(r: &mut Reader<'_>, out: &mut Self) -> DecodeResult<()> {
        Self::decode_body_into(r, out).map_err(|e| e.in_type(Self::PATH))
    }

    /// Decodes one value from `r` (values of at most [`BY_VALUE_MAX_OCTETS`]; a larger type
    /// does not compile: use [`Uper::decode_into`]).
    #[inline]
    fn decode_uper(r: &mut Reader<'_>) -> DecodeResult<Self> {
        const { small_enough_by_value::<Self>() };
        let mut v = Self::placeholder();
        Self::decode_into(r, &mut v)?;
        Ok(v)
    }

    /// Encodes the value into `w`; errors name this type if nothing inside it did.
    #[inline]
    fn encode_uper(&self, w: &mut Writer<'_>) -> EncodeResult {
        self.encode_body(w).map_err(|e| e.in_type(Self::PATH))
    }
}

/// The largest encoding of `T` in whole octets, where bounded (for buffer sizing).
pub const fn max_octets<T: Uper>() -> Option<usize> {
    match T::MAX_UPER_BITS {
        Some(b) => Some(b.div_ceil(8) as usize),
        None => None,
    }
}

/// The largest value, in octets, that [`decode`], [`decode_prefix`] and
/// [`Uper::decode_uper`] return by value. Returning a value copies it whole: without `alloc`
/// most messages are tens of KiB to megabytes (a `MessageFrame` 8.5 MB, see the crate docs'
/// table of value sizes), so asking for a larger one by value is a compile error that points to
/// [`decode_into`] (a value you keep) or [`crate::Decoder`] (kept values in a decoding loop).
/// With `alloc` every message fits (a `MessageFrame` is 136 octets, its lists and its larger
/// messages on the heap).
pub const BY_VALUE_MAX_OCTETS: usize = 1024;

/// Refuses, at compile time, to return a `T` larger than [`BY_VALUE_MAX_OCTETS`] by value.
const fn small_enough_by_value<T>() {
    assert!(
        core::mem::size_of::<T>() <= BY_VALUE_MAX_OCTETS,
        "this value is too large to decode by value (over j2735::uper::BY_VALUE_MAX_OCTETS; \
         without `alloc` most messages are KiB to MiB): decode into a value you keep with \
         uper::decode_into, or use j2735::Decoder"
    );
}

/// Decodes one complete encoding of `T` that fills `bytes` (see the module docs).
///
/// Only for values of at most [`BY_VALUE_MAX_OCTETS`] (every message with `alloc`; without it
/// a `MessageFrame` and most messages are larger); a larger `T` does not compile: use
/// [`decode_into`] or [`crate::Decoder`].
pub fn decode<T: Uper>(bytes: &[u8]) -> Result<T, DecodeError> {
    const { small_enough_by_value::<T>() };
    // Made and decoded in the result itself: `Ok(v)` of a local would copy the value.
    let mut out = Ok(T::placeholder());
    if let Ok(v) = &mut out {
        if let Err(e) = decode_into(bytes, v) {
            out = Err(e);
        }
    }
    out
}

/// Decodes one complete encoding that fills `bytes` into `out`, reusing its storage.
pub fn decode_into<T: Uper>(bytes: &[u8], out: &mut T) -> Result<(), DecodeError> {
    let used = decode_prefix_into(bytes, out)?;
    if used != bytes.len() {
        return Err(DecodeError::new(DecodeErrorKind::TrailingBytes, used * 8));
    }
    Ok(())
}

/// Decodes one encoding of `T` from the start of `bytes`; returns it and the octets used.
/// As [`decode`], only for values of at most [`BY_VALUE_MAX_OCTETS`].
pub fn decode_prefix<T: Uper>(bytes: &[u8]) -> Result<(T, usize), DecodeError> {
    const { small_enough_by_value::<T>() };
    let mut v = T::placeholder();
    let used = decode_prefix_into(bytes, &mut v)?;
    Ok((v, used))
}

/// Decodes one encoding from the start of `bytes` into `out`; returns the octets used.
pub fn decode_prefix_into<T: Uper>(bytes: &[u8], out: &mut T) -> Result<usize, DecodeError> {
    let mut r = Reader::new(bytes);
    T::decode_into(&mut r, out)?;
    Ok(r.position().div_ceil(8).max(1).min(bytes.len()))
}

/// The size in octets of the complete encoding of `value`.
pub fn encoded_len<T: Uper>(value: &T) -> Result<usize, EncodeError> {
    let mut w = Writer::counter();
    value.encode_uper(&mut w)?;
    Ok(w.octets())
}

/// Encodes `value` as a complete encoding into `buf`; returns the octets written.
///
/// A buffer of [`max_octets`] always suffices. When `buf` is too small the result is
/// [`EncodeErrorKind::BufferTooSmall`] and `buf` holds a partial encoding; [`encoded_len`]
/// gives the size needed.
pub fn encode<T: Uper>(value: &T, buf: &mut [u8]) -> Result<usize, EncodeError> {
    let mut w = Writer::new(buf);
    value.encode_uper(&mut w)?;
    if w.position() == 0 {
        w.write_bits(0, 8)?;
    }
    Ok(w.octets())
}

/// Encodes `value` into a new vector.
#[cfg(feature = "alloc")]
pub fn encode_to_vec<T: Uper>(value: &T) -> Result<alloc::vec::Vec<u8>, EncodeError> {
    let mut buf = alloc::vec![0u8; encoded_len(value)?];
    encode(value, &mut buf)?;
    Ok(buf)
}

impl Placeholder for bool {
    fn placeholder() -> Self {
        false
    }
}

impl Uper for bool {
    const PATH: &'static str = "BOOLEAN";
    const MAX_UPER_BITS: Option<u64> = Some(1);
    #[inline]
    fn decode_body_into(r: &mut Reader<'_>, out: &mut Self) -> DecodeResult<()> {
        *out = r.read_bit()?;
        Ok(())
    }
    #[inline]
    fn encode_body(&self, w: &mut Writer<'_>) -> EncodeResult {
        w.write_bit(*self)
    }
}

/// The ASN.1 NULL value (no bits).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Null;

impl Placeholder for Null {
    fn placeholder() -> Self {
        Null
    }
}

impl Uper for Null {
    const PATH: &'static str = "NULL";
    const MAX_UPER_BITS: Option<u64> = Some(0);
    #[inline]
    fn decode_body_into(_: &mut Reader<'_>, _: &mut Self) -> DecodeResult<()> {
        Ok(())
    }
    #[inline]
    fn encode_body(&self, _: &mut Writer<'_>) -> EncodeResult {
        Ok(())
    }
}
