//! rasn, with the J2735 types rasn-compiler generated.
//!
//! rasn-compiler makes `MessageFrame.value` an opaque open type (`Any`, the content octets), as
//! it does for every class-constrained open type (regional extensions too). A rasn user decodes
//! the frame, then the message its `messageId` selects from those octets; encoding goes the
//! other way. That is what is measured here, against our decoding of the whole frame.

use rasn::types::Any;

use crate::kind::Kind;
use crate::rasn_j2735::basic_safety_message::BasicSafetyMessage;
use crate::rasn_j2735::map_data::MapData;
use crate::rasn_j2735::message_frame::{
    DSRCmsgID, MessageFrame, BASIC_SAFETY_MESSAGE, MAP_DATA, SIGNAL_PHASE_AND_TIMING_MESSAGE,
    TRAVELER_INFORMATION,
};
use crate::rasn_j2735::spat::SPAT;
use crate::rasn_j2735::traveler_information::TravelerInformation;

pub use rasn::error::{DecodeError, EncodeError};

/// A decoded message.
#[derive(Clone, Debug, PartialEq)]
pub enum Message {
    /// MapData.
    Map(MapData),
    /// TravelerInformation.
    Tim(TravelerInformation),
    /// BasicSafetyMessage.
    Bsm(BasicSafetyMessage),
    /// SPAT.
    Spat(SPAT),
}

/// Decodes a MessageFrame and the message it carries.
#[inline]
pub fn decode(bytes: &[u8]) -> Result<Message, DecodeError> {
    let frame: MessageFrame = rasn::uper::decode(bytes)?;
    let content = frame.value.as_bytes();
    if frame.message_id == MAP_DATA {
        Ok(Message::Map(rasn::uper::decode(content)?))
    } else if frame.message_id == TRAVELER_INFORMATION {
        Ok(Message::Tim(rasn::uper::decode(content)?))
    } else if frame.message_id == BASIC_SAFETY_MESSAGE {
        Ok(Message::Bsm(rasn::uper::decode(content)?))
    } else if frame.message_id == SIGNAL_PHASE_AND_TIMING_MESSAGE {
        Ok(Message::Spat(rasn::uper::decode(content)?))
    } else {
        Err(DecodeError::from_kind(
            rasn::error::DecodeErrorKind::Custom {
                msg: format!("messageId {} is not benchmarked", frame.message_id.0),
            },
            rasn::Codec::Uper,
        ))
    }
}

/// Encodes `message` as a MessageFrame into `out` (cleared first, its allocation reused).
#[inline]
pub fn encode(message: &Message, out: &mut Vec<u8>) -> Result<(), EncodeError> {
    let (id, content): (DSRCmsgID, Vec<u8>) = match message {
        Message::Map(m) => (MAP_DATA, rasn::uper::encode(m)?),
        Message::Tim(m) => (TRAVELER_INFORMATION, rasn::uper::encode(m)?),
        Message::Bsm(m) => (BASIC_SAFETY_MESSAGE, rasn::uper::encode(m)?),
        Message::Spat(m) => (SIGNAL_PHASE_AND_TIMING_MESSAGE, rasn::uper::encode(m)?),
    };
    let frame = MessageFrame::new(id, Any::new(content));
    rasn::uper::encode_buf(&frame, out)
}

/// The message kind of a decoded value.
pub fn kind(message: &Message) -> Kind {
    match message {
        Message::Map(_) => Kind::Map,
        Message::Tim(_) => Kind::Tim,
        Message::Bsm(_) => Kind::Bsm,
        Message::Spat(_) => Kind::Spat,
    }
}

/// Decodes `bytes` and encodes the value again; true when the bytes are identical.
pub fn round_trips(bytes: &[u8]) -> Result<bool, String> {
    let m = decode(bytes).map_err(|e| format!("decode: {e}"))?;
    let mut out = Vec::new();
    encode(&m, &mut out).map_err(|e| format!("encode: {e}"))?;
    Ok(out == bytes)
}
