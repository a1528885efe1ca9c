//! What every part of the IEEE 1609.2 parser shares: the protocol version, the nesting bound
//! and the error types (re-exported by [`super`]).

use core::fmt;

/// The only `protocolVersion` defined by IEEE 1609.2.
pub const PROTOCOL_VERSION: u8 = 3;

/// Most levels of `Ieee1609Dot2Data` accepted, counting the outermost one.
pub const MAX_NESTING_DEPTH: usize = 4;

/// What went wrong while decoding IEEE 1609.2 data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum DecodeErrorKind {
    /// The input ended before the value did (also: a length or count beyond the input).
    UnexpectedEnd,
    /// A `protocolVersion` (or certificate version) other than 3.
    UnsupportedVersion,
    /// A CHOICE tag that is not of the context-specific class or is malformed.
    InvalidTag,
    /// A CHOICE alternative or ENUMERATED value that this parser does not know.
    UnknownAlternative,
    /// Valid OER but not canonical: a non-minimal length or integer, or a set padding bit.
    NonCanonical,
    /// A length that no valid encoding has (long form with no digits, empty integer).
    InvalidLength,
    /// A length too large to be represented on this platform.
    LengthTooLarge,
    /// An integer larger than its field allows (a PSID above 32 bits).
    ValueOutOfRange,
    /// A `SignedDataPayload` with neither data, nor a data hash, nor an extension.
    EmptySignedPayload,
    /// Signed data nested deeper than [`MAX_NESTING_DEPTH`].
    NestingTooDeep,
    /// Bytes remain after a complete value (after the whole input, or inside an open type).
    TrailingBytes,
}

impl DecodeErrorKind {
    /// Every kind, in [`DecodeErrorKind::index`] order: for tables with one entry per kind
    /// (a receiver's drop counters, for instance), which a `#[non_exhaustive]` enum cannot
    /// otherwise list outside this crate.
    pub const ALL: [DecodeErrorKind; 11] = [
        Self::UnexpectedEnd,
        Self::UnsupportedVersion,
        Self::InvalidTag,
        Self::UnknownAlternative,
        Self::NonCanonical,
        Self::InvalidLength,
        Self::LengthTooLarge,
        Self::ValueOutOfRange,
        Self::EmptySignedPayload,
        Self::NestingTooDeep,
        Self::TrailingBytes,
    ];
    /// The number of kinds.
    pub const COUNT: usize = Self::ALL.len();

    /// Position in [`DecodeErrorKind::ALL`] (the declaration order). An exhaustive match: a
    /// new kind does not compile until it has its place here and in `ALL`.
    #[must_use]
    pub const fn index(self) -> usize {
        match self {
            Self::UnexpectedEnd => 0,
            Self::UnsupportedVersion => 1,
            Self::InvalidTag => 2,
            Self::UnknownAlternative => 3,
            Self::NonCanonical => 4,
            Self::InvalidLength => 5,
            Self::LengthTooLarge => 6,
            Self::ValueOutOfRange => 7,
            Self::EmptySignedPayload => 8,
            Self::NestingTooDeep => 9,
            Self::TrailingBytes => 10,
        }
    }

    /// A short lowercase description.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::UnexpectedEnd => "unexpected end",
            Self::UnsupportedVersion => "unsupported protocol version",
            Self::InvalidTag => "invalid choice tag",
            Self::UnknownAlternative => "unknown choice alternative",
            Self::NonCanonical => "non-canonical encoding",
            Self::InvalidLength => "invalid length",
            Self::LengthTooLarge => "length too large",
            Self::ValueOutOfRange => "value out of range",
            Self::EmptySignedPayload => "signed payload without data or hash",
            Self::NestingTooDeep => "nesting too deep",
            Self::TrailingBytes => "trailing bytes",
        }
    }
}

impl fmt::Display for DecodeErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A decoding failure: what went wrong and the byte offset in the input where it was found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DecodeError {
    /// What went wrong.
    pub kind: DecodeErrorKind,
    /// Byte offset, from the start of the input, of the field where it was detected.
    pub offset: usize,
}

impl DecodeError {
    /// An error of `kind` at byte `offset`.
    #[cold]
    #[must_use]
    pub const fn new(kind: DecodeErrorKind, offset: usize) -> Self {
        Self { kind, offset }
    }
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "IEEE 1609.2: {} at byte {}", self.kind, self.offset)
    }
}

impl core::error::Error for DecodeError {}

/// The output buffer given to an encoder is too small.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BufferTooSmall {
    /// Bytes the encoding needs.
    pub needed: usize,
    /// Bytes the buffer has.
    pub available: usize,
}

impl fmt::Display for BufferTooSmall {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "output buffer too small: {} bytes needed, {} available",
            self.needed, self.available
        )
    }
}

impl core::error::Error for BufferTooSmall {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kind_is_listed_once_at_its_index() {
        for (i, k) in DecodeErrorKind::ALL.iter().enumerate() {
            assert_eq!(k.index(), i);
            let named = DecodeErrorKind::ALL
                .iter()
                .filter(|o| o.as_str() == k.as_str());
            assert_eq!(named.count(), 1, "{k}");
        }
    }
}
