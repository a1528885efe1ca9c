//! Hexadecimal text to bytes and back, without allocation: the one hex helper of the
//! project (RSU `Payload=` values, JER OCTET STRINGs, the CLI, tests and tools).
//!
//! Reading: digits may be upper or lower case; nothing else (no spaces, no `0x` prefix) is
//! accepted ([`decoded_len`], [`decode_into`]; callers that tolerate spaces or prefixes strip
//! them first). Writing: [`encode`] (lower case) and [`write_upper`] into any
//! [`core::fmt::Write`], or the [`Hex`] adapter in `format!` (`{}` lower, `{:X}` upper).
//!
//! # Panics
//!
//! No function in this module panics on any input.

use core::fmt;

/// Why hexadecimal text could not be decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum HexError {
    /// The text has an odd number of characters.
    OddLength,
    /// The character at byte `index` of the text is not a hexadecimal digit.
    InvalidDigit {
        /// Byte index of the offending character.
        index: usize,
    },
    /// The output buffer is too small.
    BufferTooSmall {
        /// Bytes the decoded value needs.
        needed: usize,
    },
}

impl fmt::Display for HexError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::OddLength => f.write_str("hex text has an odd number of digits"),
            Self::InvalidDigit { index } => write!(f, "invalid hex digit at index {index}"),
            Self::BufferTooSmall { needed } => {
                write!(f, "output buffer too small: {needed} bytes needed")
            }
        }
    }
}

impl core::error::Error for HexError {}

/// Number of bytes `hex` decodes to, after checking that it is valid hexadecimal text.
///
/// # Errors
///
/// [`HexError::OddLength`] or [`HexError::InvalidDigit`] when `hex` is not hexadecimal text.
pub fn decoded_len(hex: &str) -> Result<usize, HexError> {
    if !hex.len().is_multiple_of(2) {
        return Err(HexError::OddLength);
    }
    match hex.bytes().position(|digit| digit_value(digit).is_none()) {
        Some(index) => Err(HexError::InvalidDigit { index }),
        None => Ok(hex.len() / 2),
    }
}

/// Decodes `hex` into the start of `out`; returns the number of bytes written.
///
/// # Errors
///
/// As [`decoded_len`], and [`HexError::BufferTooSmall`] when `out` is shorter than the
/// decoded bytes (then nothing is written).
pub fn decode_into(hex: &str, out: &mut [u8]) -> Result<usize, HexError> {
    let needed = decoded_len(hex)?;
    let target = out
        .get_mut(..needed)
        .ok_or(HexError::BufferTooSmall { needed })?;
    for (byte, pair) in target.iter_mut().zip(hex.as_bytes().chunks_exact(2)) {
        if let [high, low] = pair {
            let high = digit_value(*high).unwrap_or(0);
            let low = digit_value(*low).unwrap_or(0);
            *byte = (high << 4) | low;
        }
    }
    Ok(needed)
}

/// Writes `bytes` as lower-case hexadecimal digits, two per byte.
///
/// # Errors
///
/// When `out` refuses the text.
pub fn encode<W: fmt::Write + ?Sized>(bytes: &[u8], out: &mut W) -> fmt::Result {
    bytes.iter().try_for_each(|byte| write!(out, "{byte:02x}"))
}

/// Shows bytes as hexadecimal text: `{}` and `{:x}` lower case, `{:X}` upper case (with
/// `alloc`, `Hex(bytes).to_string()` is the lower-case text).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hex<'a>(pub &'a [u8]);

impl fmt::Display for Hex<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        encode(self.0, f)
    }
}

impl fmt::LowerHex for Hex<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        encode(self.0, f)
    }
}

impl fmt::UpperHex for Hex<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write_upper(self.0, f)
    }
}

/// Writes `bytes` as upper-case hexadecimal digits.
///
/// # Errors
///
/// When `out` refuses the text.
pub fn write_upper<W: fmt::Write + ?Sized>(bytes: &[u8], out: &mut W) -> fmt::Result {
    bytes.iter().try_for_each(|byte| write!(out, "{byte:02X}"))
}

/// Value of one hexadecimal digit.
fn digit_value(digit: u8) -> Option<u8> {
    match digit {
        b'0'..=b'9' => digit.checked_sub(b'0'),
        b'a'..=b'f' => digit.checked_sub(b'a' - 10),
        b'A'..=b'F' => digit.checked_sub(b'A' - 10),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::string::String;

    #[test]
    fn decodes_mixed_case() {
        let mut out = [0u8; 4];
        assert_eq!(decode_into("00aB12Ff", &mut out), Ok(4));
        assert_eq!(out, [0x00, 0xab, 0x12, 0xff]);
    }

    #[test]
    fn rejects_bad_text() {
        let mut out = [0u8; 4];
        assert_eq!(decode_into("abc", &mut out), Err(HexError::OddLength));
        assert_eq!(
            decode_into("0g", &mut out),
            Err(HexError::InvalidDigit { index: 1 })
        );
        assert_eq!(
            decode_into("0011223344", &mut out),
            Err(HexError::BufferTooSmall { needed: 5 })
        );
        assert_eq!(decode_into("", &mut out), Ok(0));
    }

    #[test]
    fn writes_upper_case() {
        let mut text = String::new();
        write_upper(&[0x00, 0x1f, 0xab], &mut text).unwrap();
        assert_eq!(text, "001FAB");
    }

    #[test]
    fn writes_lower_case_and_displays() {
        use std::format;
        let mut text = String::new();
        encode(&[0x00, 0x1f, 0xab], &mut text).unwrap();
        assert_eq!(text, "001fab");
        let bytes = [0x0a, 0xff, 0x80];
        assert_eq!(format!("{}", Hex(&bytes)), "0aff80");
        assert_eq!(format!("{:x}", Hex(&bytes)), "0aff80");
        assert_eq!(format!("{:X}", Hex(&bytes)), "0AFF80");
        assert_eq!(format!("[{}]", Hex(&[])), "[]");
        // Decoding what was written gives the bytes back.
        let mut back = [0u8; 3];
        assert_eq!(decode_into(&format!("{:X}", Hex(&bytes)), &mut back), Ok(3));
        assert_eq!(back, bytes);
    }
}
