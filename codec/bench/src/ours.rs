//! Our codec the way the OBU runs it: a MessageFrame kept across messages and refilled in
//! place (`uper::decode_into`), and encoding into a reused buffer (`uper::encode`).

use j2735::frame::{self, Message};
use j2735::uper::{self, DecodeError, EncodeError, Placeholder};
use j2735::{BasicSafetyMessage, Decoder, MapData, MessageFrame, TravelerInformation, SPAT};

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

/// A message kept across decodes of MessageFrames that carry it
/// (`frame::decode_message_into`: what a firmware that links only MAP and TIM runs).
pub enum KeptMessage {
    /// MapData.
    Map(Box<MapData>),
    /// TravelerInformation.
    Tim(Box<TravelerInformation>),
    /// BasicSafetyMessage.
    Bsm(Box<BasicSafetyMessage>),
    /// SPAT.
    Spat(Box<SPAT>),
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
            Kind::Bsm => KeptMessage::Bsm(kept(bytes)?),
            Kind::Spat => KeptMessage::Spat(kept(bytes)?),
        })
    }

    /// Decodes the MessageFrame `bytes` into the kept message.
    #[inline]
    pub fn decode(&mut self, bytes: &[u8]) -> Result<(), DecodeError> {
        match self {
            KeptMessage::Map(m) => frame::decode_message_into(bytes, &mut **m),
            KeptMessage::Tim(m) => frame::decode_message_into(bytes, &mut **m),
            KeptMessage::Bsm(m) => frame::decode_message_into(bytes, &mut **m),
            KeptMessage::Spat(m) => frame::decode_message_into(bytes, &mut **m),
        }
    }
}

/// A [`Decoder`] (one kept value per message type) fed two frames of different types in turn:
/// a receiver hearing MAP, SPaT, TIM and BSM from one roadside.
pub struct Alternating {
    decoder: Box<Decoder<2>>,
}

impl Alternating {
    /// A decoder that has decoded `a` and `b` once each (both kept values in place).
    pub fn new(a: &[u8], b: &[u8]) -> Result<Self, DecodeError> {
        let (a, b) = (a.to_vec(), b.to_vec());
        with_large_stack(move || {
            let mut decoder = Box::new(Decoder::<2>::new());
            decoder.decode(&a)?;
            decoder.decode(&b)?;
            Ok(Alternating { decoder })
        })
    }

    /// Decodes `a` then `b`.
    #[inline]
    pub fn decode_pair(&mut self, a: &[u8], b: &[u8]) -> Result<(), DecodeError> {
        self.decoder.decode(a)?;
        self.decoder.decode(b)?;
        Ok(())
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
