//! Envelopes around J2735 `MessageFrame`s, independent of the generated message types.
//!
//! - [`ieee1609dot2`]: IEEE 1609.2 `Ieee1609Dot2Data` in COER, as received over the air
//!   (unsecured `03 80 <len> <frame>` and signed `03 81 00 40 03 80 <len> <frame> ...`):
//!   a zero-copy view (payload, PSID, times, signer, signature; no verification) and an
//!   encoder for unsecured data.
//! - [`rsu_text`]: RSU 4.1 message text records (`Version=0.7` immediate forward and
//!   store-and-repeat, and the older `Version=0.5` layout): parse and write.
//! - [`hex`]: hexadecimal text to bytes and back.
//! - [`unwrap_message_frame`]: finds the `MessageFrame` in bytes that are either a bare frame
//!   or an IEEE 1609.2 envelope, by parsing the envelope (not by searching for `00 1f`).
//!
//! Everything borrows its input and writes into caller buffers; nothing allocates.
//!
//! # Panics
//!
//! No function in this module or its submodules panics on any input: every index and length
//! is checked against the bytes that remain, arithmetic is checked or saturating, and
//! nesting is bounded ([`ieee1609dot2::MAX_NESTING_DEPTH`]).
#![cfg_attr(
    not(test),
    deny(
        clippy::indexing_slicing,
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::arithmetic_side_effects,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented
    )
)]

use core::fmt;

/// Hexadecimal text ([`crate::hex`]), also reachable here beside the envelopes that carry it.
pub use crate::hex;
pub mod ieee1609dot2;
pub mod psid;
pub mod wsmp;
pub use psid::Psid;
pub mod rsu_text;

#[cfg(all(test, feature = "shared-corpus"))]
mod corpus_tests;
#[cfg(test)]
mod wire_fixtures;

use ieee1609dot2::{looks_like_ieee1609dot2, DecodeError, Ieee1609Dot2Data};

/// What was around the `MessageFrame` found by [`unwrap_message_frame`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum EnvelopeKind {
    /// Nothing: the input is the frame itself.
    Bare,
    /// IEEE 1609.2 unsecured data.
    Unsecured,
    /// IEEE 1609.2 signed data (the signature is not verified).
    Signed,
}

/// A `MessageFrame` located in an input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnwrappedFrame<'a> {
    /// The frame's UPER bytes.
    pub frame: &'a [u8],
    /// Byte offset of the frame in the input.
    pub offset: usize,
    /// What was around it.
    pub envelope: EnvelopeKind,
}

/// Why no `MessageFrame` could be taken out of an input.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum UnwrapError {
    /// The input starts like IEEE 1609.2 data but is malformed.
    Envelope(DecodeError),
    /// A well-formed IEEE 1609.2 structure without plaintext application data (encrypted
    /// data, a certificate request, or a signature over external data).
    NoPlaintextPayload,
}

impl fmt::Display for UnwrapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Envelope(error) => error.fmt(f),
            Self::NoPlaintextPayload => {
                f.write_str("IEEE 1609.2 data carries no plaintext application data")
            }
        }
    }
}

impl core::error::Error for UnwrapError {}

impl From<DecodeError> for UnwrapError {
    fn from(error: DecodeError) -> Self {
        Self::Envelope(error)
    }
}

/// Finds the J2735 `MessageFrame` in `input`.
///
/// When `input` starts like IEEE 1609.2 data (protocol version 3, then a content tag; see
/// [`looks_like_ieee1609dot2`]) the whole input is parsed as one `Ieee1609Dot2Data` and the
/// frame is its application data, found through any signed layers. Otherwise the input is
/// taken to be a bare frame (standard J2735 frames start with `0x00`). The frame itself is
/// not decoded here.
///
/// # Errors
///
/// [`UnwrapError::Envelope`] when the IEEE 1609.2 data is malformed, and
/// [`UnwrapError::NoPlaintextPayload`] when it is well formed but carries no plaintext.
pub fn unwrap_message_frame(input: &[u8]) -> Result<UnwrappedFrame<'_>, UnwrapError> {
    if !looks_like_ieee1609dot2(input) {
        return Ok(UnwrappedFrame {
            frame: input,
            offset: 0,
            envelope: EnvelopeKind::Bare,
        });
    }
    let data = Ieee1609Dot2Data::parse(input)?;
    let (Some(frame), Some(offset)) = (data.application_data(), data.application_data_offset())
    else {
        return Err(UnwrapError::NoPlaintextPayload);
    };
    let envelope = if data.is_signed() {
        EnvelopeKind::Signed
    } else {
        EnvelopeKind::Unsecured
    };
    Ok(UnwrappedFrame {
        frame,
        offset,
        envelope,
    })
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::vec;

    const FRAME: [u8; 4] = [0x00, 0x1f, 0x01, 0x02];

    #[test]
    fn bare_frame_is_returned_whole() {
        let unwrapped = unwrap_message_frame(&FRAME).unwrap();
        assert_eq!(
            unwrapped,
            UnwrappedFrame {
                frame: &FRAME,
                offset: 0,
                envelope: EnvelopeKind::Bare
            }
        );
    }

    #[test]
    fn unsecured_envelope_is_opened() {
        let bytes = [0x03, 0x80, 0x04, 0x00, 0x1f, 0x01, 0x02];
        let unwrapped = unwrap_message_frame(&bytes).unwrap();
        assert_eq!(
            unwrapped,
            UnwrappedFrame {
                frame: &FRAME,
                offset: 3,
                envelope: EnvelopeKind::Unsecured
            }
        );
    }

    #[test]
    fn signed_envelope_is_opened() {
        let mut bytes = vec![0x03, 0x81, 0x00, 0x40, 0x03, 0x80, 0x04];
        bytes.extend_from_slice(&FRAME);
        bytes.extend_from_slice(&[0x00, 0x02, 0x80, 0x03, 0x82, 0x80, 0x80]);
        bytes.extend_from_slice(&[0x5a; 64]);
        let unwrapped = unwrap_message_frame(&bytes).unwrap();
        assert_eq!(
            unwrapped,
            UnwrappedFrame {
                frame: &FRAME,
                offset: 7,
                envelope: EnvelopeKind::Signed
            }
        );
    }

    #[test]
    fn frame_bytes_inside_an_envelope_are_not_searched_for() {
        // The length byte is wrong, so the envelope is malformed even though `00 1f` appears.
        let bytes = [0x03, 0x80, 0x09, 0x00, 0x1f, 0x01, 0x02];
        let error = unwrap_message_frame(&bytes).unwrap_err();
        let expected = DecodeError::new(ieee1609dot2::DecodeErrorKind::UnexpectedEnd, 3);
        assert_eq!(error, UnwrapError::Envelope(expected));
    }

    #[test]
    fn envelopes_without_plaintext_are_reported() {
        let mut bytes = vec![0x03, 0x82, 0x01, 0x01, 0x80, 1, 2, 3, 4, 5, 6, 7, 8, 0x80];
        bytes.extend_from_slice(&[0x00; 12]);
        bytes.extend_from_slice(&[0x01, 0xaa]);
        assert_eq!(
            unwrap_message_frame(&bytes),
            Err(UnwrapError::NoPlaintextPayload)
        );
        let request = [0x03, 0x83, 0x01, 0xaa];
        assert_eq!(
            unwrap_message_frame(&request),
            Err(UnwrapError::NoPlaintextPayload)
        );
    }
}
