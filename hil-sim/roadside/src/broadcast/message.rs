//! The messages a broadcaster sends: [`Message`] (a bare UPER `MessageFrame` and its
//! [`MessageKind`]), how it goes on the wire ([`Wrapping`]) and the shared [`MessageSlot`].

use j2735::envelope::ieee1609dot2::{
    encode_unsecured, looks_like_ieee1609dot2, unsecured_encoded_len,
};
use j2735::envelope::Psid;
use j2735::msg::message_frame::message_short_name;
use std::fmt;
use std::sync::{Arc, Mutex, PoisonError};

/// The J2735 message a frame carries, from its `messageId`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MessageKind {
    /// MapData (18).
    Map,
    /// SPaT (19).
    Spat,
    /// TravelerInformation (31).
    Tim,
    /// Any other message id.
    Other(u16),
}

impl MessageKind {
    /// The kind of message id `id`.
    pub const fn from_id(id: u16) -> Self {
        match id {
            18 => Self::Map,
            19 => Self::Spat,
            31 => Self::Tim,
            other => Self::Other(other),
        }
    }

    /// The J2735 `messageId`.
    pub const fn id(self) -> u16 {
        match self {
            Self::Map => 18,
            Self::Spat => 19,
            Self::Tim => 31,
            Self::Other(id) => id,
        }
    }

    /// The kind of a UPER `MessageFrame`: its first 16 bits are the extension bit (0) and
    /// the 15-bit `messageId` (`00 12` MAP, `00 1f` TIM). `None` for fewer than 2 bytes or
    /// a set extension bit.
    pub fn of_frame(frame: &[u8]) -> Option<Self> {
        match frame {
            [hi, lo, ..] if hi & 0x80 == 0 => Some(Self::from_id(u16::from_be_bytes([*hi, *lo]))),
            _ => None,
        }
    }

    /// The RSU record `Type` (`MAP`, `SPAT`, `TIM`, `BSM`, `RSA`, `PSM`), if it has one.
    /// The name is the codec's one spelling ([`message_short_name`]).
    pub const fn rsu_type(self) -> Option<&'static str> {
        match self.id() {
            18 | 19 | 20 | 27 | 31 | 32 => message_short_name(self.id()),
            _ => None,
        }
    }

    /// The PSID deployed RSUs forward it with (RSU 4.1 records and the WSMP header write
    /// its p-encoded octets): SPaT's (`0x8002`) for MAP and SPaT, TIM (`0x8003`), BSM
    /// (`0x20`), PSM (`0x27`); `None` for the others (give one).
    pub const fn default_psid(self) -> Option<Psid> {
        match self {
            Self::Map | Self::Spat => Some(Psid::SPAT),
            Self::Tim => Some(Psid::TIM),
            Self::Other(20) => Some(Psid::BSM),
            Self::Other(32) => Some(Psid::PSM),
            Self::Other(_) => None,
        }
    }
}

impl fmt::Display for MessageKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.rsu_type() {
            Some(name) => f.write_str(name),
            None => write!(f, "message {}", self.id()),
        }
    }
}

/// Why bytes are not a bare `MessageFrame`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Fewer than 2 bytes.
    TooShort {
        /// Bytes given.
        len: usize,
    },
    /// The bytes are an IEEE 1609.2 envelope; give the frame inside it (the
    /// [`Broadcaster`] wraps frames itself).
    ///
    /// [`Broadcaster`]: super::Broadcaster
    Enveloped,
    /// The first bit (the `MessageFrame` extension bit) is set.
    Extended,
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooShort { len } => write!(f, "{len} bytes are no MessageFrame (at least 2)"),
            Self::Enveloped => f.write_str(
                "the bytes are an IEEE 1609.2 envelope; give the bare MessageFrame (UPER)",
            ),
            Self::Extended => f.write_str("the MessageFrame extension bit is set"),
        }
    }
}

impl std::error::Error for FrameError {}

/// One message to broadcast: a bare UPER `MessageFrame` and its kind.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Message {
    kind: MessageKind,
    frame: Arc<[u8]>,
}

impl Message {
    /// A message from a bare UPER `MessageFrame` (what `messages::encode` gives).
    ///
    /// # Errors
    ///
    /// [`FrameError`] when the bytes are too short, an IEEE 1609.2 envelope, or extended.
    pub fn new(frame: Vec<u8>) -> Result<Self, FrameError> {
        if looks_like_ieee1609dot2(&frame) {
            return Err(FrameError::Enveloped);
        }
        let kind = MessageKind::of_frame(&frame).ok_or(match frame.len() {
            len @ 0..=1 => FrameError::TooShort { len },
            _ => FrameError::Extended,
        })?;
        Ok(Self {
            kind,
            frame: frame.into(),
        })
    }

    /// What the frame carries.
    pub fn kind(&self) -> MessageKind {
        self.kind
    }

    /// The frame's UPER bytes.
    pub fn frame(&self) -> &[u8] {
        &self.frame
    }
}

/// How frames go on the wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wrapping {
    /// The bare UPER `MessageFrame`.
    #[default]
    Raw,
    /// IEEE 1609.2 unsecured data: `03 80 <COER length> <frame>`.
    Ieee1609Unsecured,
}

impl Wrapping {
    /// Replaces `out` with the datagram carrying `frame`.
    pub fn wrap_into(self, frame: &[u8], out: &mut Vec<u8>) {
        out.clear();
        match self {
            Self::Raw => out.extend_from_slice(frame),
            Self::Ieee1609Unsecured => {
                out.resize(unsecured_encoded_len(frame.len()), 0);
                // The buffer has exactly the length the encoder asks for.
                let written = encode_unsecured(frame, out).unwrap_or(0);
                out.truncate(written);
            }
        }
    }

    /// The datagram carrying `frame`.
    pub fn wrap(self, frame: &[u8]) -> Vec<u8> {
        let mut out = Vec::new();
        self.wrap_into(frame, &mut out);
        out
    }
}

/// The messages a [`Broadcaster`] sends, shared: another thread (a scenario runner) may
/// replace them while the broadcaster runs; the next tick sends the new ones.
///
/// [`Broadcaster`]: super::Broadcaster
#[derive(Clone, Debug, Default)]
pub struct MessageSlot(Arc<Mutex<Arc<Vec<Message>>>>);

impl MessageSlot {
    /// A slot holding `messages`.
    pub fn new(messages: Vec<Message>) -> Self {
        Self(Arc::new(Mutex::new(Arc::new(messages))))
    }

    /// Replaces the messages.
    pub fn set(&self, messages: Vec<Message>) {
        *self.0.lock().unwrap_or_else(PoisonError::into_inner) = Arc::new(messages);
    }

    /// The current messages.
    pub fn get(&self) -> Arc<Vec<Message>> {
        Arc::clone(&self.0.lock().unwrap_or_else(PoisonError::into_inner))
    }
}
