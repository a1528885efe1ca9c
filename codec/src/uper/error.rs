//! Small, `Copy` error types of the UPER runtime.
//!
//! A decode error carries what went wrong, the bit position in the input where it was
//! found, and the J2735 type path (`Module.Type`) of the innermost generated type that was
//! being decoded, when known. Capacity errors name the capacity key of
//! `codec/codegen/capacities.toml` that was exceeded.

use core::fmt;

/// What went wrong while decoding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum DecodeErrorKind {
    /// The input ended before the value did.
    UnexpectedEnd,
    /// A whole number lies outside the type's constraint.
    ValueOutOfRange,
    /// A length lies outside the type's SIZE constraint.
    SizeOutOfRange,
    /// The value is valid but larger than the configured no-heap capacity.
    CapacityExceeded,
    /// A CHOICE index that the (non-extensible) type does not have.
    InvalidChoiceIndex,
    /// An ENUMERATED index that the (non-extensible) type does not have.
    InvalidEnumIndex,
    /// A character outside the string type's alphabet.
    InvalidCharacter,
    /// An open type whose content did not fill its length (more than 7 bits left over).
    OpenTypeLengthMismatch,
    /// A fragmented (>= 16K) open type or extension addition; not used by J2735.
    FragmentedOpenType,
    /// Whole octets remain after a complete value (see [`crate::uper::decode`]).
    TrailingBytes,
    /// A length determinant larger than this implementation can represent.
    LengthTooLarge,
    /// The MessageFrame carries another message than the one asked for.
    UnexpectedMessage,
}

impl DecodeErrorKind {
    /// Every kind, in [`DecodeErrorKind::index`] order: for tables with one entry per kind
    /// (a receiver's drop counters, for instance), which a `#[non_exhaustive]` enum cannot
    /// otherwise list outside this crate.
    pub const ALL: [DecodeErrorKind; 12] = [
        Self::UnexpectedEnd,
        Self::ValueOutOfRange,
        Self::SizeOutOfRange,
        Self::CapacityExceeded,
        Self::InvalidChoiceIndex,
        Self::InvalidEnumIndex,
        Self::InvalidCharacter,
        Self::OpenTypeLengthMismatch,
        Self::FragmentedOpenType,
        Self::TrailingBytes,
        Self::LengthTooLarge,
        Self::UnexpectedMessage,
    ];
    /// The number of kinds.
    pub const COUNT: usize = Self::ALL.len();

    /// Position in [`DecodeErrorKind::ALL`] (the declaration order). An exhaustive match: a new
    /// kind does not compile until it has its place here and in `ALL`.
    pub const fn index(self) -> usize {
        match self {
            Self::UnexpectedEnd => 0,
            Self::ValueOutOfRange => 1,
            Self::SizeOutOfRange => 2,
            Self::CapacityExceeded => 3,
            Self::InvalidChoiceIndex => 4,
            Self::InvalidEnumIndex => 5,
            Self::InvalidCharacter => 6,
            Self::OpenTypeLengthMismatch => 7,
            Self::FragmentedOpenType => 8,
            Self::TrailingBytes => 9,
            Self::LengthTooLarge => 10,
            Self::UnexpectedMessage => 11,
        }
    }

    /// A short lowercase name, as used in CLI error lines.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::UnexpectedEnd => "unexpected end",
            Self::ValueOutOfRange => "value out of range",
            Self::SizeOutOfRange => "size out of range",
            Self::CapacityExceeded => "capacity exceeded",
            Self::InvalidChoiceIndex => "invalid choice index",
            Self::InvalidEnumIndex => "invalid enumerated index",
            Self::InvalidCharacter => "invalid character",
            Self::OpenTypeLengthMismatch => "open type length mismatch",
            Self::FragmentedOpenType => "fragmented open type",
            Self::TrailingBytes => "trailing bytes",
            Self::LengthTooLarge => "length too large",
            Self::UnexpectedMessage => "unexpected message",
        }
    }
}

/// A decoding failure: kind, bit position and type path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DecodeError {
    /// What went wrong.
    pub kind: DecodeErrorKind,
    /// Bit offset from the start of the outermost input where it was detected.
    pub bit: u32,
    /// `Module.Type` of the innermost generated type, or a capacity key; empty when unknown.
    pub path: &'static str,
}

impl DecodeError {
    /// An error of `kind` at bit `bit` with no path yet.
    #[cold]
    pub const fn new(kind: DecodeErrorKind, bit: usize) -> Self {
        Self {
            kind,
            bit: bit as u32,
            path: "",
        }
    }

    /// An error of `kind` at `bit` that names `path`.
    #[cold]
    pub const fn at(kind: DecodeErrorKind, bit: usize, path: &'static str) -> Self {
        Self {
            kind,
            bit: bit as u32,
            path,
        }
    }

    /// Sets the path if none is set yet (the innermost type wins).
    #[cold]
    #[must_use]
    pub fn in_type(mut self, path: &'static str) -> Self {
        if self.path.is_empty() {
            self.path = path;
        }
        self
    }
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} at bit {}", self.kind.as_str(), self.bit)?;
        if !self.path.is_empty() {
            write!(f, " in {}", self.path)?;
        }
        Ok(())
    }
}

impl core::error::Error for DecodeError {}

/// What went wrong while encoding.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum EncodeErrorKind {
    /// The output buffer is too small for the encoding.
    BufferTooSmall,
    /// A length (SEQUENCE OF count, string size) lies outside the SIZE constraint.
    SizeOutOfRange,
    /// A character outside the string type's alphabet.
    InvalidCharacter,
    /// An open type or extension addition of 16K octets or more (needs fragmentation).
    OpenTypeTooLarge,
    /// Stored unknown extension additions are not in ascending, unique index order.
    InvalidExtensions,
}

impl EncodeErrorKind {
    /// A short lowercase name.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::BufferTooSmall => "buffer too small",
            Self::SizeOutOfRange => "size out of range",
            Self::InvalidCharacter => "invalid character",
            Self::OpenTypeTooLarge => "open type too large",
            Self::InvalidExtensions => "invalid extensions",
        }
    }
}

/// An encoding failure: kind and type path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct EncodeError {
    /// What went wrong.
    pub kind: EncodeErrorKind,
    /// `Module.Type` of the innermost generated type; empty when unknown.
    pub path: &'static str,
}

impl EncodeError {
    /// An error of `kind` with no path yet.
    #[cold]
    pub const fn new(kind: EncodeErrorKind) -> Self {
        Self { kind, path: "" }
    }

    /// An error of `kind` naming `path`.
    #[cold]
    pub const fn at(kind: EncodeErrorKind, path: &'static str) -> Self {
        Self { kind, path }
    }

    /// Sets the path if none is set yet (the innermost type wins).
    #[cold]
    #[must_use]
    pub fn in_type(mut self, path: &'static str) -> Self {
        if self.path.is_empty() {
            self.path = path;
        }
        self
    }
}

impl fmt::Display for EncodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.kind.as_str())?;
        if !self.path.is_empty() {
            write!(f, " in {}", self.path)?;
        }
        Ok(())
    }
}

impl core::error::Error for EncodeError {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn innermost_path_wins() {
        let e = DecodeError::new(DecodeErrorKind::UnexpectedEnd, 17)
            .in_type("Common.Latitude")
            .in_type("MapData.MapData");
        assert_eq!(e.path, "Common.Latitude");
        assert_eq!(
            e.to_string_for_test(),
            "unexpected end at bit 17 in Common.Latitude"
        );
    }

    impl DecodeError {
        fn to_string_for_test(self) -> heapless::String<96> {
            use core::fmt::Write;
            let mut s = heapless::String::new();
            write!(s, "{self}").unwrap();
            s
        }
    }

    #[test]
    fn every_kind_is_listed_once_at_its_index() {
        for (i, k) in DecodeErrorKind::ALL.iter().enumerate() {
            assert_eq!(k.index(), i);
            let named = DecodeErrorKind::ALL
                .iter()
                .filter(|o| o.as_str() == k.as_str());
            assert_eq!(named.count(), 1, "{}", k.as_str());
        }
    }

    #[test]
    fn errors_are_small() {
        assert!(core::mem::size_of::<DecodeError>() <= 24);
        assert!(core::mem::size_of::<EncodeError>() <= 24);
    }
}
