//! Our codec the way the OBU runs it: a MessageFrame kept across messages and refilled in
//! place (`uper::decode_into`), and encoding into a reused buffer (`uper::encode`).

use j2735::frame::{self, Message};
use j2735::uper::{self, DecodeError, EncodeError, Placeholder};
use j2735::{MapData, MessageFrame, TravelerInformation};

use crate::kind::Kind;
use crate::with_large_stack;

/// Room for any benchmarked frame's encoding.
pub const BUF_LEN: usize = 64 * 1024;

/// A MessageFrame kept across decodes (boxed: without `alloc` it is megabytes).
pub struct Kept {
    frame: Box<MessageFrame>,
}

impl Kept {
    /// A kept value that already holds `bytes` decoded once, so that the message variant and
    /// every optional part are in place: later decodes of such a frame are the steady state.
    /// Built on a large-stack thread (see [`with_large_stack`]).
    pub fn new(bytes: &[u8]) -> Result<Self, DecodeError> {
        let bytes = bytes.to_vec();
        with_large_stack(move || {
            let mut frame = Box::new(MessageFrame::placeholder());
            uper::decode_into(&bytes, &mut *frame)?;
            Ok(Kept { frame })
        })
    }

    /// Decodes `bytes` into the kept value.
    #[inline]
    pub fn decode(&mut self, bytes: &[u8]) -> Result<(), DecodeError> {
        uper::decode_into(bytes, &mut *self.frame)
    }

    /// The value.
    pub fn frame(&self) -> &MessageFrame {
        &self.frame
    }
}

/// A MapData or TravelerInformation kept across decodes of MessageFrames that carry it
/// (`frame::decode_message_into`: what a firmware that links only MAP and TIM runs).
pub enum KeptMessage {
    /// MapData.
    Map(Box<MapData>),
    /// TravelerInformation.
    Tim(Box<TravelerInformation>),
}

fn kept<M: Message + Send + 'static>(bytes: &[u8]) -> Result<Box<M>, DecodeError> {
    let bytes = bytes.to_vec();
    with_large_stack(move || {
        let mut m = Box::new(M::placeholder());
        frame::decode_message_into(&bytes, &mut *m)?;
        Ok(m)
    })
}

impl KeptMessage {
    /// As [`Kept::new`], for the message of kind `kind`.
    pub fn new(kind: Kind, bytes: &[u8]) -> Result<Self, DecodeError> {
        Ok(match kind {
            Kind::Map => KeptMessage::Map(kept(bytes)?),
            Kind::Tim => KeptMessage::Tim(kept(bytes)?),
        })
    }

    /// Decodes the MessageFrame `bytes` into the kept message.
    #[inline]
    pub fn decode(&mut self, bytes: &[u8]) -> Result<(), DecodeError> {
        match self {
            KeptMessage::Map(m) => frame::decode_message_into(bytes, &mut **m),
            KeptMessage::Tim(m) => frame::decode_message_into(bytes, &mut **m),
        }
    }
}

/// Encodes `frame` into `buf`; returns the octets written.
#[inline]
pub fn encode(frame: &MessageFrame, buf: &mut [u8]) -> Result<usize, EncodeError> {
    uper::encode(frame, buf)
}

/// Decodes a new value (by value, `uper::decode`): with feature `alloc` only, where a
/// MessageFrame is small and its lists live on the heap.
#[cfg(feature = "alloc")]
#[inline]
pub fn decode_by_value(bytes: &[u8]) -> Result<MessageFrame, DecodeError> {
    uper::decode(bytes)
}

/// The storage this build of the codec uses.
pub const STORAGE: &str = if cfg!(feature = "alloc") {
    "alloc (Vec/String)"
} else {
    "no-alloc (fixed capacities)"
};

/// Decodes `bytes` and encodes the value again; true when the bytes are identical.
pub fn round_trips(bytes: &[u8]) -> Result<bool, String> {
    let kept = Kept::new(bytes).map_err(|e| format!("decode: {e}"))?;
    let mut buf = vec![0u8; BUF_LEN];
    let n = encode(kept.frame(), &mut buf).map_err(|e| format!("encode: {e}"))?;
    Ok(&buf[..n] == bytes)
}
