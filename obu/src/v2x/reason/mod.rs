//! [`DropReason`]: why a received V2X input was not used, from a closed set.
//!
//! A reason is its layer ([`DropGroup`]) and the layer's reason, which wraps the upstream
//! error kind where it can ([`layers`]). Every reason type has `COUNT`, `ALL`, `index` and
//! `as_str`; a layer's index is computed from its parts' (a part's reasons follow the
//! previous part's), so that [`DropReason::index`] numbers every reason of every layer
//! `0..DropReason::COUNT` and counters stay fixed arrays.

/// Defines a reason type: an enum of parts (each a reason type with `COUNT`, `ALL`,
/// `index` and `as_str`, or a name function for its values) and then named reasons (one
/// counter each). Generates `COUNT`, `ALL` (built at compile time), `index` (the position
/// in `ALL`: a part's reasons start where the previous part's end, a named reason takes
/// one), `as_str`, `From` each part's type, and a compile-time check that `index` is the
/// position in `ALL`.
macro_rules! reasons {
    (@one $unit:ident) => {
        1
    };
    (@name $r:ident) => {
        $r.as_str()
    };
    (@name $r:ident, $name_of:path) => {
        $name_of($r)
    };
    (
        $(#[doc = $doc:literal])*
        pub enum $name:ident {
            $($(#[doc = $pdoc:literal])* $part:ident($ty:ty) $(=> $name_of:path)?,)*
        }
        $(names {
            $($(#[doc = $udoc:literal])* $unit:ident = $uname:expr,)*
        })?
    ) => {
        $(#[doc = $doc])*
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum $name {
            $($(#[doc = $pdoc])* $part($ty),)*
            $($($(#[doc = $udoc])* $unit,)*)?
        }

        impl $name {
            /// The number of reasons of each variant, in declaration order.
            const SIZES: &'static [usize] = &[
                $(<$ty>::COUNT,)*
                $($(reasons!(@one $unit),)*)?
            ];
            /// The number of reasons: the length of [`ALL`](Self::ALL).
            pub const COUNT: usize = Self::start(Self::SIZES.len());
            /// Every reason, in [`index`](Self::index) order.
            pub const ALL: [Self; Self::COUNT] = {
                let mut all = [Self::at(0); Self::COUNT];
                let mut i = 1;
                while i < Self::COUNT {
                    all[i] = Self::at(i);
                    i += 1;
                }
                all
            };

            /// Position in [`ALL`](Self::ALL): the index of its counter.
            pub const fn index(self) -> usize {
                /// The variants, numbered in declaration order.
                #[repr(usize)]
                enum Ordinal {
                    $($part,)*
                    $($($unit,)*)?
                }
                match self {
                    $(Self::$part(r) => {
                        r.index() + const { Self::start(Ordinal::$part as usize) }
                    })*
                    $($(Self::$unit => const { Self::start(Ordinal::$unit as usize) },)*)?
                }
            }

            /// Where the reasons of the variant at `ordinal` start: the sum of the sizes
            /// of the variants before it.
            const fn start(ordinal: usize) -> usize {
                let mut sum = 0;
                let mut k = 0;
                while k < ordinal {
                    sum += Self::SIZES[k];
                    k += 1;
                }
                sum
            }

            /// The counter name: a static string, the same for every input of this kind.
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(Self::$part(r) => reasons!(@name r $(, $name_of)?),)*
                    $($(Self::$unit => $uname,)*)?
                }
            }

            /// The reason at position `i` of [`ALL`](Self::ALL) (builds it).
            #[allow(unused_assignments)]
            const fn at(i: usize) -> Self {
                let mut start = 0;
                $(
                    if i < start + <$ty>::COUNT {
                        return Self::$part(<$ty>::ALL[i - start]);
                    }
                    start += <$ty>::COUNT;
                )*
                $($(
                    if i == start {
                        return Self::$unit;
                    }
                    start += 1;
                )*)?
                panic!("a reason's position beyond COUNT")
            }
        }

        $(
            impl From<$ty> for $name {
                fn from(r: $ty) -> Self {
                    Self::$part(r)
                }
            }
        )*

        const _: () = {
            let mut i = 0;
            while i < $name::COUNT {
                assert!($name::ALL[i].index() == i, "index is the position in ALL");
                i += 1;
            }
        };
    };
}

mod layers;
#[cfg(test)]
mod tests;

use j2735::envelope::hex::HexError;
use j2735::envelope::ieee1609dot2::{
    DecodeError as EnvelopeError, DecodeErrorKind as EnvelopeKind,
};
use j2735::envelope::rsu_text::{RsuTextError, RsuTextErrorKind};
use j2735::envelope::wsmp::WsmpError;
use j2735::envelope::UnwrapError;
use j2735::uper::{DecodeError, DecodeErrorKind};

use crate::ingest::IngestError;
use crate::link::FrameError;
use crate::security::Rejection;

pub use layers::{
    DatagramReason, DecodeReason, EnvelopeReason, Ieee1609Reason, IngestReason, RsuTextReason,
    SecurityReason, WsmpReason,
};

/// The stage of the receive path a [`DropReason`] belongs to: its layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DropGroup {
    /// Before the content is looked at: the transport (datagram too large, receive error) or
    /// the firmware's serial framing (COBS, CRC).
    Datagram,
    /// The envelope around the MessageFrame: IEEE 1609.2, RSU 4.1 text or WSMP.
    Envelope,
    /// The UPER MessageFrame (or the MAP or TIM in it) does not decode.
    Decode,
    /// The core refused the decoded MAP, TIM or PSM (or part of it).
    Ingest,
    /// IEEE 1609.2 security: unsigned when signatures are required, or a signature,
    /// certificate chain, permission, time or replay check failed (see
    /// [`crate::security`]).
    Security,
}

reasons! {
    /// Why a V2X input was dropped: its layer and the layer's reason. A closed set, so that
    /// counters indexed by it are fixed arrays (`[u32; DropReason::COUNT]`) and no input text
    /// (offsets, line numbers, values) ever becomes a counter key.
    pub enum DropReason {
        /// Before the content is looked at ([`DropGroup::Datagram`]).
        Datagram(DatagramReason),
        /// The envelope ([`DropGroup::Envelope`]).
        Envelope(EnvelopeReason),
        /// The UPER decoder ([`DropGroup::Decode`]).
        Decode(DecodeReason),
        /// The core's ingest ([`DropGroup::Ingest`]).
        Ingest(IngestReason),
        /// IEEE 1609.2 security ([`DropGroup::Security`]).
        Security(SecurityReason),
    }
}

// Counters and outcomes carry reasons by value: a layer tag and one byte.
const _: () = assert!(core::mem::size_of::<DropReason>() <= 2);

impl DropReason {
    /// The stage this reason belongs to: its layer.
    pub const fn group(self) -> DropGroup {
        match self {
            Self::Datagram(_) => DropGroup::Datagram,
            Self::Envelope(_) => DropGroup::Envelope,
            Self::Decode(_) => DropGroup::Decode,
            Self::Ingest(_) => DropGroup::Ingest,
            Self::Security(_) => DropGroup::Security,
        }
    }
}

impl From<Ieee1609Reason> for DropReason {
    fn from(r: Ieee1609Reason) -> Self {
        Self::Envelope(r.into())
    }
}

impl From<RsuTextReason> for DropReason {
    fn from(r: RsuTextReason) -> Self {
        Self::Envelope(r.into())
    }
}

impl From<WsmpReason> for DropReason {
    fn from(r: WsmpReason) -> Self {
        Self::Envelope(r.into())
    }
}

/// A serial-link framing error.
impl From<FrameError> for DropReason {
    fn from(e: FrameError) -> Self {
        Self::Datagram(match e {
            // `NoRoom` is the encoder's; a receive buffer too small is the same case.
            FrameError::TooLong | FrameError::NoRoom => DatagramReason::LinkTooLong,
            FrameError::Cobs => DatagramReason::LinkCobs,
            FrameError::TooShort => DatagramReason::LinkTooShort,
            FrameError::Crc => DatagramReason::LinkCrc,
        })
    }
}

/// An IEEE 1609.2 unwrap error (by kind; the offset is not kept).
impl From<UnwrapError> for DropReason {
    fn from(e: UnwrapError) -> Self {
        match e {
            UnwrapError::Envelope(e) => e.into(),
            UnwrapError::NoPlaintextPayload => Ieee1609Reason::NoPlaintext.into(),
        }
    }
}

/// A malformed IEEE 1609.2 envelope (by kind; the offset is not kept).
impl From<EnvelopeError> for DropReason {
    fn from(e: EnvelopeError) -> Self {
        e.kind.into()
    }
}

/// A malformed IEEE 1609.2 envelope of this kind.
impl From<EnvelopeKind> for DropReason {
    fn from(kind: EnvelopeKind) -> Self {
        Ieee1609Reason::Malformed(kind).into()
    }
}

/// A WSMP error.
impl From<WsmpError> for DropReason {
    fn from(e: WsmpError) -> Self {
        WsmpReason::Parse(e).into()
    }
}

/// An RSU text error (by kind; the line and key are not kept).
impl From<RsuTextError> for DropReason {
    fn from(e: RsuTextError) -> Self {
        match e.kind {
            RsuTextErrorKind::NotKeyValue => RsuTextReason::NotKeyValue,
            RsuTextErrorKind::MissingKey(_) => RsuTextReason::MissingKey,
            RsuTextErrorKind::DuplicateKey(_) => RsuTextReason::DuplicateKey,
            RsuTextErrorKind::InvalidValue(_) => RsuTextReason::InvalidValue,
            _ => RsuTextReason::Other,
        }
        .into()
    }
}

/// An RSU payload's hexadecimal error.
impl From<HexError> for DropReason {
    fn from(e: HexError) -> Self {
        match e {
            HexError::OddLength | HexError::InvalidDigit { .. } => RsuTextReason::PayloadHex,
            HexError::BufferTooSmall { .. } => RsuTextReason::PayloadTooLarge,
        }
        .into()
    }
}

/// A UPER decode error (by kind; the bit and type path are not kept).
impl From<DecodeError> for DropReason {
    fn from(e: DecodeError) -> Self {
        e.kind.into()
    }
}

/// A UPER decode error of this kind.
impl From<DecodeErrorKind> for DropReason {
    fn from(kind: DecodeErrorKind) -> Self {
        Self::Decode(DecodeReason::Kind(kind))
    }
}

/// The core's refusal of a MAP, TIM or PSM.
impl From<IngestError> for DropReason {
    fn from(e: IngestError) -> Self {
        Self::Ingest(IngestReason::Refused(e))
    }
}

/// The trust policy's rejection of a signed message.
impl From<Rejection> for DropReason {
    fn from(r: Rejection) -> Self {
        Self::Security(SecurityReason::Rejected(r))
    }
}

impl core::fmt::Display for DropReason {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}
