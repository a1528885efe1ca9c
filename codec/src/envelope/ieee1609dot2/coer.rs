//! Canonical Octet Encoding Rules (ITU-T X.696, COER) primitives for the IEEE 1609.2 parser.
//!
//! Only the pieces that IEEE 1609.2 structures use are here: fixed-size fields, length
//! determinants, OCTET STRINGs, unsigned and signed INTEGERs with a length prefix, SEQUENCE
//! OF quantities, ENUMERATED values, CHOICE tags, SEQUENCE preambles, extension additions
//! and open types. Every read is bounded by the bytes that remain; the parser is strict
//! about canonical form (minimal lengths and integers, zero padding bits).
//!
//! No function in this module panics on any input.

use super::error::{DecodeError, DecodeErrorKind};

/// Result of a COER read.
pub(crate) type DecodeResult<T> = Result<T, DecodeError>;

/// Largest number of preamble bits (extension bit plus OPTIONAL/DEFAULT bits) supported.
const MAX_PREAMBLE_BITS: u32 = 24;

/// A cursor over COER bytes that reports errors at byte offsets of the outermost input.
#[derive(Clone, Copy, Debug)]
pub(crate) struct CoerReader<'a> {
    bytes: &'a [u8],
    position: usize,
    base_offset: usize,
}

/// The presence bits that open a SEQUENCE with OPTIONAL components or an extension marker.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Preamble {
    /// The bits, left-aligned: bit 31 is the first preamble bit.
    bits: u32,
    /// Whether the first bit is the extension bit.
    extensible: bool,
}

impl Preamble {
    /// Whether the extension-additions part follows the root components.
    pub(crate) fn has_extensions(self) -> bool {
        self.extensible && self.bit(0)
    }

    /// Whether the `index`-th OPTIONAL (or DEFAULT) root component is present.
    pub(crate) fn has_optional(self, index: u32) -> bool {
        self.bit(index.saturating_add(u32::from(self.extensible)))
    }

    fn bit(self, index: u32) -> bool {
        let shifted = self.bits.checked_shl(index).unwrap_or(0);
        shifted & 0x8000_0000 != 0
    }
}

impl<'a> CoerReader<'a> {
    /// A reader over `bytes`, whose first byte lies at `base_offset` in the outermost input.
    pub(crate) fn new(bytes: &'a [u8], base_offset: usize) -> Self {
        Self {
            bytes,
            position: 0,
            base_offset,
        }
    }

    /// Byte offset of the next unread byte in the outermost input.
    pub(crate) fn offset(&self) -> usize {
        self.base_offset.saturating_add(self.position)
    }

    /// Position of the next unread byte within this reader's bytes.
    pub(crate) fn position(&self) -> usize {
        self.position
    }

    /// Number of bytes not yet read.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.position)
    }

    /// An error of `kind` at the next unread byte.
    pub(crate) fn error(&self, kind: DecodeErrorKind) -> DecodeError {
        DecodeError::new(kind, self.offset())
    }

    /// The bytes read since `start` (a value returned earlier by [`Self::position`]).
    pub(crate) fn consumed_since(&self, start: usize) -> &'a [u8] {
        self.bytes.get(start..self.position).unwrap_or_default()
    }

    /// Fails with `TrailingBytes` unless every byte has been read.
    pub(crate) fn expect_end(&self) -> DecodeResult<()> {
        if self.remaining() == 0 {
            Ok(())
        } else {
            Err(self.error(DecodeErrorKind::TrailingBytes))
        }
    }

    /// Reads one byte.
    pub(crate) fn read_u8(&mut self) -> DecodeResult<u8> {
        let [byte] = self.read_array::<1>()?;
        Ok(byte)
    }

    /// Reads the next `len` bytes.
    pub(crate) fn read_slice(&mut self, len: usize) -> DecodeResult<&'a [u8]> {
        let end = self
            .position
            .checked_add(len)
            .filter(|&end| end <= self.bytes.len())
            .ok_or_else(|| self.error(DecodeErrorKind::UnexpectedEnd))?;
        let slice = self.bytes.get(self.position..end).unwrap_or_default();
        self.position = end;
        Ok(slice)
    }

    /// Skips the next `len` bytes.
    pub(crate) fn skip(&mut self, len: usize) -> DecodeResult<()> {
        self.read_slice(len).map(|_| ())
    }

    /// Reads a fixed-size field of `N` bytes (for example a `HashedId8`).
    pub(crate) fn read_array<const N: usize>(&mut self) -> DecodeResult<[u8; N]> {
        let slice = self.read_slice(N)?;
        let mut array = [0u8; N];
        array.copy_from_slice(slice);
        Ok(array)
    }

    /// Reads a big-endian `Uint16`.
    pub(crate) fn read_u16(&mut self) -> DecodeResult<u16> {
        self.read_array().map(u16::from_be_bytes)
    }

    /// Reads a big-endian `Uint64`.
    pub(crate) fn read_u64(&mut self) -> DecodeResult<u64> {
        self.read_array().map(u64::from_be_bytes)
    }

    /// Reads a four-byte two's complement integer (latitude, longitude).
    pub(crate) fn read_i32(&mut self) -> DecodeResult<i32> {
        self.read_array().map(i32::from_be_bytes)
    }

    /// Reads a length determinant: short form below 128, else `0x80 | n` and `n` bytes.
    pub(crate) fn read_length(&mut self) -> DecodeResult<usize> {
        let start = *self;
        let first = self.read_u8()?;
        if first < 0x80 {
            return Ok(usize::from(first));
        }
        let count = usize::from(first & 0x7f);
        if count == 0 {
            return Err(start.error(DecodeErrorKind::InvalidLength));
        }
        if count > core::mem::size_of::<usize>() {
            return Err(start.error(DecodeErrorKind::LengthTooLarge));
        }
        let digits = self.read_slice(count)?;
        let length = fold_unsigned(digits);
        let minimal = digits.first().is_some_and(|&lead| lead != 0) && length >= 0x80;
        if !minimal {
            return Err(start.error(DecodeErrorKind::NonCanonical));
        }
        usize::try_from(length).map_err(|_| start.error(DecodeErrorKind::LengthTooLarge))
    }

    /// Reads an OCTET STRING of variable size: a length determinant and that many bytes.
    pub(crate) fn read_octet_string(&mut self) -> DecodeResult<&'a [u8]> {
        let length = self.read_length()?;
        self.read_slice(length)
    }

    /// Reads an open type (a length-prefixed encoding) and returns a reader over it.
    pub(crate) fn read_open_type(&mut self) -> DecodeResult<CoerReader<'a>> {
        let length = self.read_length()?;
        let base_offset = self.offset();
        let content = self.read_slice(length)?;
        Ok(CoerReader::new(content, base_offset))
    }

    /// Skips an open type whose content this parser does not need to understand.
    pub(crate) fn skip_open_type(&mut self) -> DecodeResult<()> {
        self.read_open_type().map(|_| ())
    }

    /// Reads a non-negative INTEGER with a length prefix (`INTEGER (0..MAX)`), up to 64 bits.
    pub(crate) fn read_unsigned(&mut self) -> DecodeResult<u64> {
        let start = *self;
        let digits = self.read_integer_digits()?;
        let has_leading_zero = digits.len() > 1 && digits.first() == Some(&0);
        if has_leading_zero {
            return Err(start.error(DecodeErrorKind::NonCanonical));
        }
        if digits.len() > 8 {
            return Err(start.error(DecodeErrorKind::ValueOutOfRange));
        }
        Ok(fold_unsigned(digits))
    }

    /// Reads an unconstrained (signed) INTEGER with a length prefix, up to 64 bits.
    pub(crate) fn read_signed(&mut self) -> DecodeResult<i64> {
        let start = *self;
        let digits = self.read_integer_digits()?;
        if digits.len() > 8 {
            return Err(start.error(DecodeErrorKind::ValueOutOfRange));
        }
        let redundant = match digits {
            [0x00, next, ..] => next & 0x80 == 0,
            [0xff, next, ..] => next & 0x80 != 0,
            _ => false,
        };
        if redundant {
            return Err(start.error(DecodeErrorKind::NonCanonical));
        }
        Ok(fold_signed(digits))
    }

    /// Reads the length-prefixed digits of an INTEGER; at least one digit is required.
    fn read_integer_digits(&mut self) -> DecodeResult<&'a [u8]> {
        let start = *self;
        let digits = self.read_octet_string()?;
        if digits.is_empty() {
            return Err(start.error(DecodeErrorKind::InvalidLength));
        }
        Ok(digits)
    }

    /// Reads the quantity of a SEQUENCE OF whose elements take at least one byte each.
    ///
    /// A quantity larger than the remaining bytes is reported as `UnexpectedEnd`, so callers
    /// loop at most once per remaining byte.
    pub(crate) fn read_quantity(&mut self) -> DecodeResult<usize> {
        let start = *self;
        let quantity = self.read_unsigned()?;
        match usize::try_from(quantity) {
            Ok(count) if count <= self.remaining() => Ok(count),
            _ => Err(start.error(DecodeErrorKind::UnexpectedEnd)),
        }
    }

    /// Reads an ENUMERATED value (short form `0..=127`, or long form `0x80 | n` and `n` bytes).
    pub(crate) fn read_enumerated(&mut self) -> DecodeResult<i64> {
        let start = *self;
        let first = self.read_u8()?;
        if first < 0x80 {
            return Ok(i64::from(first));
        }
        let count = usize::from(first & 0x7f);
        if count == 0 || count > 8 {
            return Err(start.error(DecodeErrorKind::InvalidLength));
        }
        let digits = self.read_slice(count)?;
        let value = fold_signed(digits);
        if (0..0x80).contains(&value) {
            return Err(start.error(DecodeErrorKind::NonCanonical));
        }
        Ok(value)
    }

    /// Reads a CHOICE tag of the context-specific class and returns its number.
    pub(crate) fn read_choice_tag(&mut self) -> DecodeResult<u32> {
        let start = *self;
        let first = self.read_u8()?;
        if first & 0xc0 != 0x80 {
            return Err(start.error(DecodeErrorKind::InvalidTag));
        }
        let number = first & 0x3f;
        if number < 0x3f {
            return Ok(u32::from(number));
        }
        self.read_long_tag_number(start)
    }

    /// Reads the base-128 continuation bytes of a tag number of 63 or more.
    fn read_long_tag_number(&mut self, start: CoerReader<'a>) -> DecodeResult<u32> {
        let mut number: u32 = 0;
        for index in 0..5 {
            let byte = self.read_u8()?;
            if index == 0 && byte == 0x80 {
                return Err(start.error(DecodeErrorKind::NonCanonical));
            }
            number = number
                .checked_mul(128)
                .map(|shifted| shifted | u32::from(byte & 0x7f))
                .ok_or_else(|| start.error(DecodeErrorKind::InvalidTag))?;
            if byte & 0x80 == 0 {
                return if number < 0x3f {
                    Err(start.error(DecodeErrorKind::NonCanonical))
                } else {
                    Ok(number)
                };
            }
        }
        Err(start.error(DecodeErrorKind::InvalidTag))
    }

    /// Reads the preamble of a SEQUENCE with `optional_count` OPTIONAL/DEFAULT components,
    /// preceded by an extension bit when `extensible`.
    pub(crate) fn read_preamble(
        &mut self,
        extensible: bool,
        optional_count: u32,
    ) -> DecodeResult<Preamble> {
        let start = *self;
        let bit_count = optional_count
            .saturating_add(u32::from(extensible))
            .min(MAX_PREAMBLE_BITS);
        let byte_count = bit_count.div_ceil(8);
        let mut bits: u32 = 0;
        for shift in [24u32, 16, 8].into_iter().take(byte_count as usize) {
            bits |= u32::from(self.read_u8()?).checked_shl(shift).unwrap_or(0);
        }
        let padding = bits.checked_shl(bit_count).unwrap_or(0);
        if padding != 0 {
            return Err(start.error(DecodeErrorKind::NonCanonical));
        }
        Ok(Preamble { bits, extensible })
    }

    /// Skips the extension additions of a SEQUENCE (presence bitmap, then one open type per
    /// present addition) and returns their raw bytes.
    pub(crate) fn skip_extension_additions(&mut self) -> DecodeResult<&'a [u8]> {
        let start_position = self.position;
        let start = *self;
        let bitmap = self.read_octet_string()?;
        let present =
            count_bitmap_bits(bitmap).ok_or_else(|| start.error(DecodeErrorKind::NonCanonical))?;
        for _ in 0..present {
            self.skip_open_type()?;
        }
        Ok(self.consumed_since(start_position))
    }
}

/// Big-endian unsigned value of up to eight bytes (callers bound the length).
fn fold_unsigned(digits: &[u8]) -> u64 {
    digits.iter().fold(0u64, |acc, &digit| {
        acc.checked_shl(8).unwrap_or(0) | u64::from(digit)
    })
}

/// Big-endian two's complement value of one to eight bytes (callers bound the length).
fn fold_signed(digits: &[u8]) -> i64 {
    let negative = digits.first().is_some_and(|&lead| lead & 0x80 != 0);
    let start = if negative { -1i64 } else { 0 };
    digits.iter().fold(start, |acc, &digit| {
        acc.checked_shl(8).unwrap_or(0) | i64::from(digit)
    })
}

/// Number of set bits in an extension presence bitmap (first byte: unused trailing bits).
///
/// `None` when the bitmap is empty, claims more than 7 unused bits, or has a set padding bit.
fn count_bitmap_bits(bitmap: &[u8]) -> Option<u32> {
    let (&unused, bits) = bitmap.split_first()?;
    if unused > 7 || (bits.is_empty() && unused != 0) {
        return None;
    }
    let padding_mask = (1u8.checked_shl(u32::from(unused)).unwrap_or(0)).wrapping_sub(1);
    if bits.last().is_some_and(|&last| last & padding_mask != 0) {
        return None;
    }
    Some(bits.iter().map(|byte| byte.count_ones()).sum())
}

/// Runs `decode` over the content of an open type, which it must consume entirely.
pub(crate) fn within_open_type<'a, T>(
    reader: &mut CoerReader<'a>,
    decode: impl FnOnce(&mut CoerReader<'a>) -> DecodeResult<T>,
) -> DecodeResult<T> {
    let mut inner = reader.read_open_type()?;
    let value = decode(&mut inner)?;
    inner.expect_end()?;
    Ok(value)
}

/// Runs `decode` when `present`; the value is `None` otherwise.
pub(crate) fn optional<T>(
    present: bool,
    decode: impl FnOnce() -> DecodeResult<T>,
) -> DecodeResult<Option<T>> {
    if present {
        decode().map(Some)
    } else {
        Ok(None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reader(bytes: &[u8]) -> CoerReader<'_> {
        CoerReader::new(bytes, 0)
    }

    #[test]
    fn short_and_long_lengths() {
        assert_eq!(reader(&[0x05]).read_length(), Ok(5));
        assert_eq!(reader(&[0x7f]).read_length(), Ok(127));
        assert_eq!(reader(&[0x81, 0x80]).read_length(), Ok(128));
        assert_eq!(reader(&[0x82, 0x01, 0x20]).read_length(), Ok(0x120));
    }

    #[test]
    fn non_canonical_lengths_are_rejected() {
        let kind = |bytes: &[u8]| reader(bytes).read_length().map_err(|e| e.kind);
        assert_eq!(kind(&[0x81, 0x05]), Err(DecodeErrorKind::NonCanonical));
        assert_eq!(
            kind(&[0x82, 0x00, 0x90]),
            Err(DecodeErrorKind::NonCanonical)
        );
        assert_eq!(kind(&[0x80]), Err(DecodeErrorKind::InvalidLength));
        assert_eq!(kind(&[0x82, 0x01]), Err(DecodeErrorKind::UnexpectedEnd));
        assert_eq!(kind(&[0xff]), Err(DecodeErrorKind::LengthTooLarge));
    }

    #[test]
    fn octet_string_is_bounded_by_the_input() {
        let error = reader(&[0x03, 0xaa, 0xbb]).read_octet_string().unwrap_err();
        assert_eq!(error.kind, DecodeErrorKind::UnexpectedEnd);
        assert_eq!(error.offset, 1);
    }

    #[test]
    fn unsigned_integers() {
        assert_eq!(reader(&[0x01, 0x20]).read_unsigned(), Ok(0x20));
        assert_eq!(reader(&[0x02, 0x80, 0x03]).read_unsigned(), Ok(0x8003));
        let kind = |bytes: &[u8]| reader(bytes).read_unsigned().map_err(|e| e.kind);
        assert_eq!(
            kind(&[0x02, 0x00, 0x20]),
            Err(DecodeErrorKind::NonCanonical)
        );
        assert_eq!(kind(&[0x00]), Err(DecodeErrorKind::InvalidLength));
        assert_eq!(
            kind(&[0x09, 1, 2, 3, 4, 5, 6, 7, 8, 9]),
            Err(DecodeErrorKind::ValueOutOfRange)
        );
    }

    #[test]
    fn quantity_larger_than_input_is_rejected() {
        let mut r = reader(&[0x01, 0x05, 0xaa]);
        assert_eq!(
            r.read_quantity().unwrap_err().kind,
            DecodeErrorKind::UnexpectedEnd
        );
        assert_eq!(reader(&[0x01, 0x01, 0xaa]).read_quantity(), Ok(1));
    }

    #[test]
    fn enumerated_short_and_long_forms() {
        assert_eq!(reader(&[0x01]).read_enumerated(), Ok(1));
        assert_eq!(reader(&[0x81, 0xff]).read_enumerated(), Ok(-1));
        assert_eq!(reader(&[0x82, 0x01, 0x00]).read_enumerated(), Ok(256));
        let error = reader(&[0x81, 0x05]).read_enumerated().unwrap_err();
        assert_eq!(error.kind, DecodeErrorKind::NonCanonical);
    }

    #[test]
    fn choice_tags() {
        assert_eq!(reader(&[0x80]).read_choice_tag(), Ok(0));
        assert_eq!(reader(&[0x83]).read_choice_tag(), Ok(3));
        assert_eq!(reader(&[0xbf, 0x40]).read_choice_tag(), Ok(64));
        assert_eq!(reader(&[0xbf, 0x81, 0x00]).read_choice_tag(), Ok(128));
        let kind = |bytes: &[u8]| reader(bytes).read_choice_tag().map_err(|e| e.kind);
        assert_eq!(kind(&[0x03]), Err(DecodeErrorKind::InvalidTag));
        assert_eq!(kind(&[0xbf, 0x05]), Err(DecodeErrorKind::NonCanonical));
        assert_eq!(
            kind(&[0xbf, 0xff, 0xff, 0xff, 0xff, 0xff]),
            Err(DecodeErrorKind::InvalidTag)
        );
    }

    #[test]
    fn preamble_bits() {
        let preamble = reader(&[0x40]).read_preamble(true, 2).unwrap();
        assert!(!preamble.has_extensions());
        assert!(preamble.has_optional(0));
        assert!(!preamble.has_optional(1));
        let preamble = reader(&[0x50]).read_preamble(true, 6).unwrap();
        assert!(preamble.has_optional(0));
        assert!(!preamble.has_optional(1));
        assert!(preamble.has_optional(2));
        let padded = reader(&[0x41]).read_preamble(false, 2).unwrap_err();
        assert_eq!(padded.kind, DecodeErrorKind::NonCanonical);
    }

    #[test]
    fn extension_additions_are_skipped() {
        // Bitmap of 2 bits (6 unused) with both set, then two open types.
        let bytes = [0x02, 0x06, 0xc0, 0x01, 0xaa, 0x02, 0xbb, 0xcc, 0x99];
        let mut r = reader(&bytes);
        let raw = r.skip_extension_additions().unwrap();
        assert_eq!(raw.len(), 8);
        assert_eq!(r.remaining(), 1);
        let bad_padding = [0x02, 0x06, 0xc1];
        let error = reader(&bad_padding).skip_extension_additions().unwrap_err();
        assert_eq!(error.kind, DecodeErrorKind::NonCanonical);
    }
}
