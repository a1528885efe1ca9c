//! Hexadecimal text to bytes and back, without allocation (used for RSU `Payload=` values).
//!
//! Digits may be upper or lower case; nothing else (no spaces, no `0x` prefix) is accepted.
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
}
