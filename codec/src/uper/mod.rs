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

mod error;
mod ext;
mod macros;
mod reader;
mod sized;
mod storage;
mod writer;

pub use error::{DecodeError, DecodeErrorKind, EncodeError, EncodeErrorKind};
pub use ext::{decode_open, decode_unknown_open, encode_unknown_open, Extensions, UnknownAdditions};
pub use reader::{DecodeResult, LengthChunk, Reader};
pub use sized::{
    decode_bits, decode_fixed_octets, decode_ia5, decode_octets, decode_seq_of, encode_bits,
    encode_ia5, encode_octets, encode_seq_of, read_octets_into, read_sized, write_sized, Size,
};
pub use storage::{Bits, Ia5, Octets, SeqOf};
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

/// A type with a UPER encoding. Implemented by every generated J2735 type.
pub trait Uper: Sized {
    /// `Module.Type` of the ASN.1 definition (or `Module.Parent.field` for an inline type).
    const PATH: &'static str;
    /// Largest encoding in bits, where the type (with the build's storage) bounds it.
    const MAX_UPER_BITS: Option<u64>;

    /// Decodes the value's encoding (without error context; use [`Uper::decode_uper`]).
    fn decode_body(r: &mut Reader<'_>) -> DecodeResult<Self>;
    /// Encodes the value (without error context; use [`Uper::encode_uper`]).
    fn encode_body(&self, w: &mut Writer<'_>) -> EncodeResult;

    /// Decodes one value from `r`; errors name this type if nothing inside it did.
    #[inline]
    fn decode_uper(r: &mut Reader<'_>) -> DecodeResult<Self> {
        Self::decode_body(r).map_err(|e| e.in_type(Self::PATH))
    }

    /// Encodes the value into `w`; errors name this type if nothing inside it did.
    #[inline]
    fn encode_uper(&self, w: &mut Writer<'_>) -> EncodeResult {
        self.encode_body(w).map_err(|e| e.in_type(Self::PATH))
    }
}

/// Picks the bound of the build's storage: `no_heap` without `alloc`, `heap` with it.
#[doc(hidden)]
pub const fn max_bits(no_heap: Option<u64>, heap: Option<u64>) -> Option<u64> {
    if cfg!(feature = "alloc") {
        heap
    } else {
        no_heap
    }
}

/// The largest encoding of `T` in whole octets, where bounded (for buffer sizing).
pub const fn max_octets<T: Uper>() -> Option<usize> {
    match T::MAX_UPER_BITS {
        Some(b) => Some(b.div_ceil(8) as usize),
        None => None,
    }
}

/// Decodes one complete encoding of `T` that fills `bytes` (see the module docs).
pub fn decode<T: Uper>(bytes: &[u8]) -> Result<T, DecodeError> {
    let (v, used) = decode_prefix(bytes)?;
    if used != bytes.len() {
        return Err(DecodeError::new(DecodeErrorKind::TrailingBytes, used * 8));
    }
    Ok(v)
}

/// Decodes one encoding of `T` from the start of `bytes`; returns it and the octets used.
pub fn decode_prefix<T: Uper>(bytes: &[u8]) -> Result<(T, usize), DecodeError> {
    let mut r = Reader::new(bytes);
    let v = T::decode_uper(&mut r)?;
    Ok((v, r.position().div_ceil(8).max(1).min(bytes.len())))
}

/// The size in octets of the complete encoding of `value`.
pub fn encoded_len<T: Uper>(value: &T) -> Result<usize, EncodeError> {
    let mut w = Writer::counter();
    value.encode_uper(&mut w)?;
    Ok(w.octets())
}

/// Encodes `value` as a complete encoding into `buf`; returns the octets written.
///
/// Fails before writing anything when `buf` is too small: a buffer of at least
/// [`max_octets`] skips the size pass.
pub fn encode<T: Uper>(value: &T, buf: &mut [u8]) -> Result<usize, EncodeError> {
    let roomy = matches!(max_octets::<T>(), Some(m) if m <= buf.len());
    if !roomy && encoded_len(value)? > buf.len() {
        return Err(EncodeError::new(EncodeErrorKind::BufferTooSmall).in_type(T::PATH));
    }
    let mut w = Writer::new(buf);
    value.encode_uper(&mut w)?;
    let n = w.octets();
    if w.position() == 0 {
        w.write_bits(0, 8)?;
    }
    Ok(n)
}

/// Encodes `value` into a new vector.
#[cfg(feature = "alloc")]
pub fn encode_to_vec<T: Uper>(value: &T) -> Result<alloc::vec::Vec<u8>, EncodeError> {
    let mut buf = alloc::vec![0u8; encoded_len(value)?];
    encode(value, &mut buf)?;
    Ok(buf)
}

impl Uper for bool {
    const PATH: &'static str = "BOOLEAN";
    const MAX_UPER_BITS: Option<u64> = Some(1);
    #[inline]
    fn decode_body(r: &mut Reader<'_>) -> DecodeResult<Self> {
        r.read_bit()
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

impl Uper for Null {
    const PATH: &'static str = "NULL";
    const MAX_UPER_BITS: Option<u64> = Some(0);
    #[inline]
    fn decode_body(_: &mut Reader<'_>) -> DecodeResult<Self> {
        Ok(Null)
    }
    #[inline]
    fn encode_body(&self, _: &mut Writer<'_>) -> EncodeResult {
        Ok(())
    }
}
