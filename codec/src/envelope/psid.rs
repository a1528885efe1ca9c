//! [`Psid`]: the Provider Service Identifier that names the application of a V2X message, in
//! its two forms.
//!
//! - **The integer.** IEEE 1609.2 defines `Psid` as an `INTEGER (0..MAX)`: a signed message's
//!   header (`HeaderInfo.psid`) and a certificate's `appPermissions` and `certIssuePermissions`
//!   carry this number. TIM is 131, MAP 2113687, SPaT 130, BSM 32, PSM 39.
//! - **The p-encoded octets.** IEEE 1609.12 writes a PSID in 1 to 4 octets whose leading
//!   bits give the length: `0xxxxxxx` one octet (0-127), `10xxxxxx` two (from `80-00`,
//!   128-16511), `110xxxxx` three (from `C0-00-00`, 16512-2113663), `1110xxxx` four (from
//!   `E0-00-00-00`, 2113664-270549119). The IEEE 1609.3 WSMP T-header, RSU 4.1 text records
//!   (`PSID=0x8003`), NTCIP 1218's `RsuPsidTC` and most configuration files use these octets;
//!   `0x8003` is TIM (131), `0xE0000017` MAP (2113687).
//!
//! Mixing the two forms makes a receiver that agrees only with itself: a header carrying
//! 32771 (the octets `80 03` read as a number) is nobody's TIM. The type keeps the integer;
//! each wire form converts at its edge.

use core::fmt;

/// A PSID: the IEEE 1609.2 integer (see the [module docs](self) for the p-encoded form).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Psid(pub u32);

/// First integer of each p-encoded length (1 to 4 octets), and the length's prefix.
const RANGES: [(u32, u32, u32); 4] = [
    // (first integer, first p-encoded value, count)
    (0, 0x00, 0x80),
    (0x80, 0x8000, 0x4000),
    (0x4080, 0xC0_0000, 0x20_0000),
    (0x20_4080, 0xE000_0000, 0x1000_0000),
];

impl Psid {
    /// SAE J2735 Basic Safety Message (p-encoded `0x20`).
    pub const BSM: Self = Self(32);
    /// SAE J2945/9 Personal Safety Message (p-encoded `0x27`).
    pub const PSM: Self = Self(39);
    /// SAE J2735 Signal Phase and Timing, and intersection MAP of signalised intersections
    /// (p-encoded `0x8002`).
    pub const SPAT: Self = Self(130);
    /// SAE J2735 Traveler Information Message (p-encoded `0x8003`).
    pub const TIM: Self = Self(131);
    /// SAE J2735 MAP (intersection and road-segment geometry; p-encoded `0xE0000017`).
    pub const MAP: Self = Self(2_113_687);
    /// The largest PSID that has a p-encoding (4 octets, `0xEFFFFFFF`).
    pub const MAX_P_ENCODABLE: Self = Self(0x20_4080 + 0x0FFF_FFFF);

    /// The integer.
    #[must_use]
    pub const fn value(self) -> u32 {
        self.0
    }

    /// The PSID whose p-encoded octets are `octets` (1 to 4, the length their first bits
    /// announce); `None` when the length does not match, or the first octet starts `1111`.
    #[must_use]
    pub fn from_p_encoded(octets: &[u8]) -> Option<Self> {
        let len = p_encoded_len(*octets.first()?)?;
        if octets.len() != len {
            return None;
        }
        let value = octets
            .iter()
            .fold(0u32, |v, &b| v.wrapping_shl(8) | u32::from(b));
        Self::from_p_encoded_value(value)
    }

    /// The PSID whose p-encoded octets, read as one big-endian number, are `value`: how RSU
    /// files and configuration write them (`0x8003` is TIM). Leading zero octets are not
    /// part of the encoding (`0x0020` is BSM). `None` for a number that is no p-encoding
    /// (`0x83`, `0x7FFF`, `0xF0000000`).
    #[must_use]
    pub fn from_p_encoded_value(value: u32) -> Option<Self> {
        RANGES.iter().find_map(|&(first, encoded, count)| {
            let offset = value.checked_sub(encoded)?;
            (offset < count).then_some(Self(first.wrapping_add(offset)))
        })
    }

    /// The p-encoded octets, as one big-endian number (`0x8003` for TIM); `None` above
    /// [`Psid::MAX_P_ENCODABLE`].
    #[must_use]
    pub fn p_encoded_value(self) -> Option<u32> {
        RANGES.iter().find_map(|&(first, encoded, count)| {
            let offset = self.0.checked_sub(first)?;
            (offset < count).then_some(encoded.wrapping_add(offset))
        })
    }

    /// The p-encoded octets in `out[..n]`, with `n` returned (1 to 4); `None` above
    /// [`Psid::MAX_P_ENCODABLE`].
    #[must_use]
    pub fn p_encoded(self) -> Option<([u8; 4], usize)> {
        let [a, b, c, d] = self.p_encoded_value()?.to_be_bytes();
        Some(match self.0 {
            0..=0x7F => ([d, 0, 0, 0], 1),
            0x80..=0x407F => ([c, d, 0, 0], 2),
            0x4080..=0x20_407F => ([b, c, d, 0], 3),
            _ => ([a, b, c, d], 4),
        })
    }

    /// A PSID as configuration and command lines write it: `0x` and hexadecimal digits are
    /// the p-encoded octets (`0x8003` is TIM, `0xE0000017` MAP, the usual spelling), plain
    /// decimal digits the integer (`131` is TIM). `None` for anything else, and for hexadecimal
    /// that is no p-encoding (`0x83`).
    #[must_use]
    pub fn parse(text: &str) -> Option<Self> {
        let text = text.trim();
        match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
            Some(hex) if (1..=8).contains(&hex.len()) => u32::from_str_radix(hex, 16)
                .ok()
                .and_then(Self::from_p_encoded_value),
            Some(_) => None,
            None if !text.is_empty() && text.bytes().all(|b| b.is_ascii_digit()) => {
                text.parse().ok().map(Self)
            }
            None => None,
        }
    }

    /// A display of both forms: `131 (p-encoded 0x8003)`.
    #[must_use]
    pub fn both_forms(self) -> BothForms {
        BothForms(self)
    }
}

/// The length of a p-encoded PSID whose first octet is `first` (1 to 4: its leading one
/// bits plus one); `None` for `1111xxxx`.
pub(super) fn p_encoded_len(first: u8) -> Option<usize> {
    match first.leading_ones() {
        0 => Some(1),
        1 => Some(2),
        2 => Some(3),
        3 => Some(4),
        _ => None,
    }
}

impl From<u32> for Psid {
    fn from(value: u32) -> Self {
        Self(value)
    }
}

impl fmt::Display for Psid {
    /// The integer, as IEEE 1609.2 writes it.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.0)
    }
}

/// [`Psid::both_forms`]'s display.
#[derive(Clone, Copy, Debug)]
pub struct BothForms(Psid);

impl fmt::Display for BothForms {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.0.p_encoded() {
            Some((octets, len)) => {
                write!(f, "{} (p-encoded 0x", self.0 .0)?;
                for b in octets.iter().take(len) {
                    write!(f, "{b:02X}")?;
                }
                f.write_str(")")
            }
            None => write!(f, "{} (no p-encoding)", self.0 .0),
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use std::string::ToString;

    /// IEEE 1609.12's table: each length's first and last value, both ways.
    #[test]
    fn each_length_starts_and_ends_where_ieee_1609_12_says() {
        let table: [(u32, &[u8]); 8] = [
            (0, &[0x00]),
            (127, &[0x7F]),
            (128, &[0x80, 0x00]),
            (16_511, &[0xBF, 0xFF]),
            (16_512, &[0xC0, 0x00, 0x00]),
            (2_113_663, &[0xDF, 0xFF, 0xFF]),
            (2_113_664, &[0xE0, 0x00, 0x00, 0x00]),
            (270_549_119, &[0xEF, 0xFF, 0xFF, 0xFF]),
        ];
        for (integer, octets) in table {
            let psid = Psid(integer);
            assert_eq!(Psid::from_p_encoded(octets), Some(psid), "{octets:02x?}");
            let (out, len) = psid.p_encoded().unwrap();
            assert_eq!(&out[..len], octets, "{integer}");
        }
        assert_eq!(Psid::MAX_P_ENCODABLE, Psid(270_549_119));
        assert_eq!(Psid(270_549_120).p_encoded(), None);
    }

    #[test]
    fn the_j2735_messages_have_their_published_octets() {
        assert_eq!(Psid::from_p_encoded_value(0x8003), Some(Psid::TIM));
        assert_eq!(Psid::from_p_encoded_value(0x8002), Some(Psid::SPAT));
        assert_eq!(Psid::from_p_encoded_value(0xE000_0017), Some(Psid::MAP));
        assert_eq!(Psid::from_p_encoded_value(0x20), Some(Psid::BSM));
        assert_eq!(Psid::from_p_encoded_value(0x27), Some(Psid::PSM));
        assert_eq!(Psid::TIM.value(), 131);
        assert_eq!(Psid::MAP.value(), 2_113_687);
        assert_eq!(Psid::MAP.p_encoded_value(), Some(0xE000_0017));
        assert_eq!(Psid::TIM.both_forms().to_string(), "131 (p-encoded 0x8003)");
        assert_eq!(Psid::PSM.both_forms().to_string(), "39 (p-encoded 0x27)");
    }

    #[test]
    fn numbers_that_are_no_p_encoding_are_refused() {
        for value in [0x80, 0x83, 0x7FFF, 0x80_0000, 0xF000_0000, u32::MAX] {
            assert_eq!(Psid::from_p_encoded_value(value), None, "{value:#x}");
        }
        // The length the first bits announce must be the length given.
        assert_eq!(Psid::from_p_encoded(&[0x80]), None);
        assert_eq!(Psid::from_p_encoded(&[0x03, 0x00]), None);
        assert_eq!(Psid::from_p_encoded(&[0xF0, 0, 0, 0]), None);
        assert_eq!(Psid::from_p_encoded(&[]), None);
    }

    #[test]
    fn configuration_text_is_p_encoded_in_hexadecimal_and_the_integer_in_decimal() {
        assert_eq!(Psid::parse("0x8003"), Some(Psid::TIM));
        assert_eq!(Psid::parse(" 0XE0000017 "), Some(Psid::MAP));
        assert_eq!(Psid::parse("131"), Some(Psid::TIM));
        assert_eq!(Psid::parse("2113687"), Some(Psid::MAP));
        assert_eq!(Psid::parse("0x27"), Some(Psid::PSM));
        for bad in ["0x83", "0x", "0x123456789", "-1", "", "0x8003 x", "1e3"] {
            assert_eq!(Psid::parse(bad), None, "{bad:?}");
        }
    }

    #[test]
    fn every_encodable_value_round_trips_at_the_range_edges() {
        for &(first, _, count) in &RANGES {
            for integer in [first, first + 1, first + count / 2, first + count - 1] {
                let psid = Psid(integer);
                let (octets, len) = psid.p_encoded().unwrap();
                assert_eq!(Psid::from_p_encoded(&octets[..len]), Some(psid));
                let value = psid.p_encoded_value().unwrap();
                assert_eq!(Psid::from_p_encoded_value(value), Some(psid));
            }
        }
    }
}
