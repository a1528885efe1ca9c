//! MessageFrame without the object set: read the `messageId`, decode or encode one known
//! message type directly.
//!
//! Decoding a [`MessageFrame`](crate::MessageFrame) links the decoder of every J2735 message.
//! A firmware that handles only MAP and TIM uses [`decode_message_into`] and
//! [`encode_message`] instead, so that only the types it names end up in flash.

use crate::uper::{self, DecodeError, DecodeErrorKind, EncodeError, Reader, Uper, Writer};
use crate::DSRCmsgID;

/// A message of the J2735 MessageFrame object set, with its `messageId`.
pub trait Message: Uper {
    /// The `DSRCmsgID` that selects this message in a MessageFrame.
    const MESSAGE_ID: u16;
}

/// Reads the header of a MessageFrame: its extension bit and `messageId`.
fn read_header(r: &mut Reader<'_>) -> Result<(bool, u16), DecodeError> {
    let extended = r.read_bit()?;
    let id = r.read_constrained(DSRCmsgID::MIN as i64, DSRCmsgID::MAX as i64)? as u16;
    Ok((extended, id))
}

/// The `messageId` of the MessageFrame in `bytes`, without decoding the message.
pub fn peek_message_id(bytes: &[u8]) -> Result<u16, DecodeError> {
    read_header(&mut Reader::new(bytes)).map(|(_, id)| id)
}

/// Decodes a complete MessageFrame that carries an `M` into `out` (reusing its storage).
/// A frame of another message is [`DecodeErrorKind::UnexpectedMessage`]; trailing octets
/// are an error as in [`uper::decode`].
pub fn decode_message_into<M: Message>(bytes: &[u8], out: &mut M) -> Result<(), DecodeError> {
    let mut r = Reader::new(bytes);
    let (extended, id) = read_header(&mut r).map_err(|e| e.in_type("MessageFrame.MessageFrame"))?;
    if id != M::MESSAGE_ID {
        return Err(DecodeError::at(
            DecodeErrorKind::UnexpectedMessage,
            1,
            "MessageFrame.MessageFrame",
        ));
    }
    uper::ext::decode_open(&mut r, |r| M::decode_into(r, out))?;
    if extended {
        uper::Extensions::<0>::decode(&mut r, "MessageFrame.MessageFrame:ext")?;
    }
    let used = r.position().div_ceil(8);
    if used != bytes.len() {
        return Err(DecodeError::new(DecodeErrorKind::TrailingBytes, used * 8));
    }
    Ok(())
}

/// Encodes `msg` as a complete MessageFrame into `buf`; returns the octets written.
pub fn encode_message<M: Message>(msg: &M, buf: &mut [u8]) -> Result<usize, EncodeError> {
    let mut w = Writer::new(buf);
    w.write_bit(false)?;
    w.write_constrained(
        M::MESSAGE_ID as i64,
        DSRCmsgID::MIN as i64,
        DSRCmsgID::MAX as i64,
    )?;
    w.write_open(|w| msg.encode_uper(w))?;
    Ok(w.octets())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::uper::random::{Gen, Random};
    use crate::{MessageFrame, MessageFrameValue, TravelerInformation};

    #[test]
    fn direct_message_matches_the_message_frame() {
        std::thread::Builder::new()
            .stack_size(256 << 20)
            .spawn(|| {
                let tim = TravelerInformation::random(&mut Gen::new(7));
                let mut a = std::vec![0u8; 1 << 16];
                let n = encode_message(&tim, &mut a).unwrap();
                let frame = MessageFrame {
                    value: MessageFrameValue::TravelerInformation(tim.clone().into()),
                    extensions: uper::Extensions::new(),
                };
                let mut b = std::vec![0u8; 1 << 16];
                let m = uper::encode(&frame, &mut b).unwrap();
                assert_eq!(&a[..n], &b[..m]);
                assert_eq!(peek_message_id(&a[..n]).unwrap(), 31);
                let mut back = <TravelerInformation as uper::Placeholder>::placeholder();
                decode_message_into(&a[..n], &mut back).unwrap();
                assert_eq!(back, tim);
                let mut map = <crate::MapData as uper::Placeholder>::placeholder();
                let e = decode_message_into(&a[..n], &mut map).unwrap_err();
                assert_eq!(e.kind, DecodeErrorKind::UnexpectedMessage);
            })
            .unwrap()
            .join()
            .unwrap();
    }
}
