//! [`DropReason`]: why a received V2X input was not used, from a closed set.

use j2735::envelope::hex::HexError;
use j2735::envelope::ieee1609dot2::DecodeErrorKind as EnvelopeKind;
use j2735::envelope::rsu_text::{RsuTextError, RsuTextErrorKind};
use j2735::envelope::wsmp::WsmpError;
use j2735::envelope::UnwrapError;
use j2735::uper::{DecodeError, DecodeErrorKind};

use crate::ingest::IngestError;
use crate::link::FrameError;
use crate::security::Rejection;

/// The stage of the receive path a [`DropReason`] belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DropGroup {
    /// Before the content is looked at: the transport (datagram too large, receive error) or
    /// the firmware's serial framing (COBS, CRC).
    Datagram,
    /// The envelope around the MessageFrame: IEEE 1609.2 or RSU 4.1 text.
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

/// Defines [`DropReason`] from one table: variant, group, counter name, doc.
macro_rules! drop_reasons {
    ($($(#[doc = $doc:literal])* $variant:ident: $group:ident = $name:expr,)*) => {
        /// Why a V2X input was dropped: a closed set, so that counters indexed by it are
        /// fixed arrays (`[u32; DropReason::COUNT]`) and no input text (offsets, line
        /// numbers, values) ever becomes a counter key.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        #[repr(u8)]
        pub enum DropReason {
            $($(#[doc = $doc])* $variant,)*
        }

        impl DropReason {
            /// Every reason, in [`DropReason::index`] order.
            pub const ALL: &'static [DropReason] = &[$(DropReason::$variant,)*];
            /// The number of reasons.
            pub const COUNT: usize = Self::ALL.len();

            /// The counter name: a static string, the same for every input of this kind.
            pub const fn as_str(self) -> &'static str {
                match self {
                    $(DropReason::$variant => $name,)*
                }
            }

            /// The stage this reason belongs to.
            pub const fn group(self) -> DropGroup {
                match self {
                    $(DropReason::$variant => DropGroup::$group,)*
                }
            }
        }
    };
}

drop_reasons! {
    /// The datagram is larger than the receiver accepts.
    TooLarge: Datagram = "datagram too large",
    /// The transport reported a receive error (counted by the caller).
    Receive: Datagram = "receive error",
    /// Serial link: a frame longer than the receive buffer.
    LinkTooLong: Datagram = "frame too long",
    /// Serial link: invalid COBS encoding.
    LinkCobs: Datagram = "invalid COBS encoding",
    /// Serial link: a frame with no room for its CRC.
    LinkTooShort: Datagram = "frame shorter than its CRC",
    /// Serial link: CRC mismatch.
    LinkCrc: Datagram = "CRC mismatch",
    /// IEEE 1609.2: the input ended before the value did.
    EnvelopeUnexpectedEnd: Envelope = "1609.2: unexpected end",
    /// IEEE 1609.2: a protocol version other than 3.
    EnvelopeVersion: Envelope = "1609.2: unsupported protocol version",
    /// IEEE 1609.2: a malformed CHOICE tag.
    EnvelopeTag: Envelope = "1609.2: invalid choice tag",
    /// IEEE 1609.2: an unknown CHOICE alternative or ENUMERATED value.
    EnvelopeAlternative: Envelope = "1609.2: unknown choice alternative",
    /// IEEE 1609.2: a non-canonical encoding.
    EnvelopeNonCanonical: Envelope = "1609.2: non-canonical encoding",
    /// IEEE 1609.2: a length no valid encoding has.
    EnvelopeLength: Envelope = "1609.2: invalid length",
    /// IEEE 1609.2: a length too large for this platform.
    EnvelopeLengthTooLarge: Envelope = "1609.2: length too large",
    /// IEEE 1609.2: an integer larger than its field allows.
    EnvelopeValue: Envelope = "1609.2: value out of range",
    /// IEEE 1609.2: a signed payload with neither data nor hash.
    EnvelopeEmptyPayload: Envelope = "1609.2: signed payload without data or hash",
    /// IEEE 1609.2: signed data nested too deep.
    EnvelopeNesting: Envelope = "1609.2: nesting too deep",
    /// IEEE 1609.2: bytes after a complete value.
    EnvelopeTrailing: Envelope = "1609.2: trailing bytes",
    /// IEEE 1609.2: malformed in a way this build has no name for.
    EnvelopeOther: Envelope = "1609.2: malformed",
    /// IEEE 1609.2: well formed, but no plaintext application data (encrypted, hash only).
    EnvelopeNoPlaintext: Envelope = "1609.2: no plaintext payload",
    /// RSU text: not UTF-8.
    RsuNotUtf8: Envelope = "RSU text: not UTF-8",
    /// RSU text: a line that is not `Key=Value`.
    RsuNotKeyValue: Envelope = "RSU text: line is not Key=Value",
    /// RSU text: a required key is missing.
    RsuMissingKey: Envelope = "RSU text: missing key",
    /// RSU text: a key given twice.
    RsuDuplicateKey: Envelope = "RSU text: duplicate key",
    /// RSU text: a value the key does not allow.
    RsuInvalidValue: Envelope = "RSU text: invalid value",
    /// RSU text: malformed in a way this build has no name for.
    RsuOther: Envelope = "RSU text: malformed",
    /// RSU text: the payload is not hexadecimal text.
    RsuPayloadHex: Envelope = "RSU text: payload not hexadecimal",
    /// RSU text: the payload is larger than the receive scratch holds.
    RsuPayloadTooLarge: Envelope = "RSU text: payload too large",
    /// WSMP: see [`WsmpError::Truncated`].
    WsmpTruncated: Envelope = WsmpError::Truncated.as_str(),
    /// WSMP: see [`WsmpError::Version`].
    WsmpVersion: Envelope = WsmpError::Version.as_str(),
    /// WSMP: see [`WsmpError::Unsupported`].
    WsmpUnsupported: Envelope = WsmpError::Unsupported.as_str(),
    /// WSMP: see [`WsmpError::Encoding`].
    WsmpEncoding: Envelope = WsmpError::Encoding.as_str(),
    /// WSMP: see [`WsmpError::TrailingBytes`].
    WsmpTrailing: Envelope = WsmpError::TrailingBytes.as_str(),
    /// WSMP: the T-header's PSID is not the message's (the 1609.2 header's, or the
    /// message type's for unsigned data; MAP may come with SPaT's).
    WsmpPsidMismatch: Envelope = "WSMP: PSID does not match the message",
    /// UPER: the input ended before the value did.
    DecodeUnexpectedEnd: Decode = DecodeErrorKind::UnexpectedEnd.as_str(),
    /// UPER: a whole number outside its constraint.
    DecodeValue: Decode = DecodeErrorKind::ValueOutOfRange.as_str(),
    /// UPER: a length outside its SIZE constraint.
    DecodeSize: Decode = DecodeErrorKind::SizeOutOfRange.as_str(),
    /// UPER: valid, but larger than the no-heap capacities.
    DecodeCapacity: Decode = DecodeErrorKind::CapacityExceeded.as_str(),
    /// UPER: a CHOICE index the type does not have.
    DecodeChoice: Decode = DecodeErrorKind::InvalidChoiceIndex.as_str(),
    /// UPER: an ENUMERATED index the type does not have.
    DecodeEnum: Decode = DecodeErrorKind::InvalidEnumIndex.as_str(),
    /// UPER: a character outside the string's alphabet.
    DecodeCharacter: Decode = DecodeErrorKind::InvalidCharacter.as_str(),
    /// UPER: an open type whose content did not fill its length.
    DecodeOpenType: Decode = DecodeErrorKind::OpenTypeLengthMismatch.as_str(),
    /// UPER: a fragmented open type (not used by J2735).
    DecodeFragmented: Decode = DecodeErrorKind::FragmentedOpenType.as_str(),
    /// UPER: octets after a complete MessageFrame.
    DecodeTrailing: Decode = DecodeErrorKind::TrailingBytes.as_str(),
    /// UPER: a length determinant too large for this implementation.
    DecodeLengthTooLarge: Decode = DecodeErrorKind::LengthTooLarge.as_str(),
    /// UPER: a MessageFrame of another message than its id said.
    DecodeUnexpectedMessage: Decode = DecodeErrorKind::UnexpectedMessage.as_str(),
    /// UPER: an error this build has no name for.
    DecodeOther: Decode = "malformed",
    /// Ingest: see [`IngestError::InvalidReference`].
    IngestReference: Ingest = IngestError::InvalidReference.as_str(),
    /// Ingest: see [`IngestError::UnsupportedNode`].
    IngestNode: Ingest = IngestError::UnsupportedNode.as_str(),
    /// Ingest: see [`IngestError::NoGeometry`].
    IngestGeometry: Ingest = IngestError::NoGeometry.as_str(),
    /// Ingest: see [`IngestError::ReferenceLaneMissing`].
    IngestLane: Ingest = IngestError::ReferenceLaneMissing.as_str(),
    /// Ingest: see [`IngestError::ReferenceMapMissing`].
    IngestMap: Ingest = IngestError::ReferenceMapMissing.as_str(),
    /// Ingest: see [`IngestError::DuplicateLane`].
    IngestDuplicateLane: Ingest = IngestError::DuplicateLane.as_str(),
    /// Ingest: see [`IngestError::CapacityExceeded`].
    IngestCapacity: Ingest = IngestError::CapacityExceeded.as_str(),
    /// Ingest: see [`IngestError::InvalidValue`].
    IngestValue: Ingest = IngestError::InvalidValue.as_str(),
    /// Unverified data that would have replaced, refreshed, cancelled or evicted a lane
    /// model or work zone that came verified: nothing changed.
    UnverifiedOverVerified: Ingest = "unverified data over verified data",
    /// Security: not signed, and signatures are required.
    Unsigned: Security = "unsigned (signatures required)",
    /// Security: signed by `self`: no certificate ties the key to a trusted sender.
    SelfSigned: Security = "1609.2: self-signed (no certificate)",
    /// Security: a hash or signature algorithm other than SHA-256 / ECDSA P-256.
    UnsupportedAlgorithm: Security = "1609.2: unsupported hash or signature algorithm",
    /// Security: a `digest` signer whose certificate has not been seen.
    SignerUnknown: Security = "1609.2: signer certificate unknown (digest)",
    /// Security: the certificate chain does not lead to a configured trust anchor.
    ChainUntrusted: Security = "1609.2: chain does not reach a trust anchor",
    /// Security: more certificates in the chain than the verifier walks.
    ChainTooLong: Security = "1609.2: certificate chain too long",
    /// Security: a certificate of the chain has a bad signature, key or validity.
    CertificateInvalid: Security = "1609.2: certificate invalid",
    /// Security: a certificate of the chain may not certify the message's PSID.
    IssuerPermission: Security = "1609.2: issuer may not certify the PSID",
    /// Security: a certificate larger than the verifier's capacities (PSIDs, region).
    CertificateTooLarge: Security = "1609.2: certificate beyond the capacities",
    /// Security: the signer certificate's validity ended before the message.
    CertificateExpired: Security = "1609.2: signer certificate expired",
    /// Security: the signer certificate's validity starts after the message.
    CertificateNotYetValid: Security = "1609.2: signer certificate not yet valid",
    /// Security: the signer certificate does not permit the message's PSID.
    PsidNotPermitted: Security = "1609.2: PSID not permitted by the signer certificate",
    /// Security: the PSID is not the one configured for this message (TIM, MAP).
    PsidMismatch: Security = "1609.2: PSID does not match the message",
    /// Security: the generation location is outside the signer certificate's region.
    RegionMiss: Security = "1609.2: outside the certificate region",
    /// Security: the certificate has a region, and no location is known to check it.
    NoLocation: Security = "1609.2: no location to check the region",
    /// Security: the signature does not verify.
    SignatureInvalid: Security = "1609.2: signature does not verify",
    /// Security: the header has no generation time.
    NoGenerationTime: Security = "1609.2: no generation time",
    /// Security: no GNSS time yet to check times against.
    NoTime: Security = "1609.2: no GNSS time to check against",
    /// Security: generated further ahead of GNSS time than the future tolerance.
    GenerationTimeFuture: Security = "1609.2: generation time in the future",
    /// Security: no expiry time, and generated longer ago than the past window.
    GenerationTimeOld: Security = "1609.2: generation time too old",
    /// Security: past the header's expiry time.
    MessageExpired: Security = "1609.2: message expired",
    /// Security: a copy of an accepted message whose copies are replays (PSM).
    Replay: Security = "1609.2: replay",
    /// Security: a newer version of the message (same TIM packet, MAP or PSM sender) was
    /// accepted.
    Superseded: Security = "1609.2: superseded by a newer version",
    /// Security: the profile requires an expiry time and the header has none.
    NoExpiryTime: Security = "1609.2: no expiry time",
    /// Security: the expiry time is not after the generation time.
    ExpiryBeforeGeneration: Security = "1609.2: expiry time before generation time",
    /// Security: generation to expiry is longer than the profile allows.
    LifetimeTooLong: Security = "1609.2: lifetime longer than allowed",
    /// Security: a certificate given out of band is not one canonical COER certificate.
    CertificateMalformed: Security = "1609.2: certificate malformed",
    /// Security: the signer certificate does not grant the required SSP.
    SspNotPermitted: Security = "1609.2: SSP not permitted by the signer certificate",
    /// Ingest: see [`IngestError::NotRoadWorker`].
    IngestNotWorker: Ingest = IngestError::NotRoadWorker.as_str(),
    /// Ingest: see [`IngestError::InvalidPosition`].
    IngestPosition: Ingest = IngestError::InvalidPosition.as_str(),
    /// Ingest: see [`IngestError::AccuracyUnavailable`].
    IngestAccuracy: Ingest = IngestError::AccuracyUnavailable.as_str(),
    /// Ingest: see [`IngestError::StaleMessage`].
    IngestStale: Ingest = IngestError::StaleMessage.as_str(),
    /// Ingest: see [`IngestError::StoreFull`].
    IngestStoreFull: Ingest = IngestError::StoreFull.as_str(),
    /// Ingest: see [`IngestError::NotDue`].
    IngestNotDue: Ingest = IngestError::NotDue.as_str(),
}

impl From<Rejection> for DropReason {
    fn from(r: Rejection) -> Self {
        match r {
            Rejection::UnsupportedAlgorithm => Self::UnsupportedAlgorithm,
            Rejection::NoGenerationTime => Self::NoGenerationTime,
            Rejection::NoTime => Self::NoTime,
            Rejection::GenerationTimeFuture => Self::GenerationTimeFuture,
            Rejection::GenerationTimeOld => Self::GenerationTimeOld,
            Rejection::MessageExpired => Self::MessageExpired,
            Rejection::Replay => Self::Replay,
            Rejection::NoExpiryTime => Self::NoExpiryTime,
            Rejection::Superseded => Self::Superseded,
            Rejection::ExpiryBeforeGeneration => Self::ExpiryBeforeGeneration,
            Rejection::LifetimeTooLong => Self::LifetimeTooLong,
            Rejection::PsidNotPermitted => Self::PsidNotPermitted,
            Rejection::PsidMismatch => Self::PsidMismatch,
            Rejection::SspNotPermitted => Self::SspNotPermitted,
            Rejection::NoLocation => Self::NoLocation,
            Rejection::RegionMiss => Self::RegionMiss,
            Rejection::SignatureInvalid => Self::SignatureInvalid,
            Rejection::SelfSigned => Self::SelfSigned,
            Rejection::SignerUnknown => Self::SignerUnknown,
            Rejection::ChainUntrusted => Self::ChainUntrusted,
            Rejection::ChainTooLong => Self::ChainTooLong,
            Rejection::CertificateTooLarge => Self::CertificateTooLarge,
            Rejection::CertificateInvalid => Self::CertificateInvalid,
            Rejection::CertificateExpired => Self::CertificateExpired,
            Rejection::CertificateNotYetValid => Self::CertificateNotYetValid,
            Rejection::IssuerPermission => Self::IssuerPermission,
            Rejection::CertificateMalformed => Self::CertificateMalformed,
        }
    }
}

impl DropReason {
    /// Position in [`DropReason::ALL`]: the index of its counter.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The reason of a serial-link framing error.
    pub const fn from_link(e: FrameError) -> Self {
        match e {
            // `NoRoom` is the encoder's; a receive buffer too small is the same case.
            FrameError::TooLong | FrameError::NoRoom => Self::LinkTooLong,
            FrameError::Cobs => Self::LinkCobs,
            FrameError::TooShort => Self::LinkTooShort,
            FrameError::Crc => Self::LinkCrc,
        }
    }

    /// The reason of an IEEE 1609.2 unwrap error (by kind; the offset is not kept).
    pub const fn from_unwrap(e: UnwrapError) -> Self {
        let kind = match e {
            UnwrapError::NoPlaintextPayload => return Self::EnvelopeNoPlaintext,
            UnwrapError::Envelope(e) => e.kind,
        };
        match kind {
            EnvelopeKind::UnexpectedEnd => Self::EnvelopeUnexpectedEnd,
            EnvelopeKind::UnsupportedVersion => Self::EnvelopeVersion,
            EnvelopeKind::InvalidTag => Self::EnvelopeTag,
            EnvelopeKind::UnknownAlternative => Self::EnvelopeAlternative,
            EnvelopeKind::NonCanonical => Self::EnvelopeNonCanonical,
            EnvelopeKind::InvalidLength => Self::EnvelopeLength,
            EnvelopeKind::LengthTooLarge => Self::EnvelopeLengthTooLarge,
            EnvelopeKind::ValueOutOfRange => Self::EnvelopeValue,
            EnvelopeKind::EmptySignedPayload => Self::EnvelopeEmptyPayload,
            EnvelopeKind::NestingTooDeep => Self::EnvelopeNesting,
            EnvelopeKind::TrailingBytes => Self::EnvelopeTrailing,
            _ => Self::EnvelopeOther,
        }
    }

    /// The reason of a WSMP error.
    pub const fn from_wsmp(e: WsmpError) -> Self {
        match e {
            WsmpError::Truncated => Self::WsmpTruncated,
            WsmpError::Version => Self::WsmpVersion,
            WsmpError::Unsupported => Self::WsmpUnsupported,
            WsmpError::Encoding => Self::WsmpEncoding,
            WsmpError::TrailingBytes => Self::WsmpTrailing,
        }
    }

    /// The reason of an RSU text error (by kind; the line and key are not kept).
    pub const fn from_rsu_text(e: RsuTextError) -> Self {
        match e.kind {
            RsuTextErrorKind::NotKeyValue => Self::RsuNotKeyValue,
            RsuTextErrorKind::MissingKey(_) => Self::RsuMissingKey,
            RsuTextErrorKind::DuplicateKey(_) => Self::RsuDuplicateKey,
            RsuTextErrorKind::InvalidValue(_) => Self::RsuInvalidValue,
            _ => Self::RsuOther,
        }
    }

    /// The reason of an RSU payload's hexadecimal error.
    pub const fn from_hex(e: HexError) -> Self {
        match e {
            HexError::OddLength | HexError::InvalidDigit { .. } => Self::RsuPayloadHex,
            HexError::BufferTooSmall { .. } => Self::RsuPayloadTooLarge,
        }
    }

    /// The reason of a UPER decode error (by kind; the bit and type path are not kept).
    pub const fn from_decode(e: DecodeError) -> Self {
        match e.kind {
            DecodeErrorKind::UnexpectedEnd => Self::DecodeUnexpectedEnd,
            DecodeErrorKind::ValueOutOfRange => Self::DecodeValue,
            DecodeErrorKind::SizeOutOfRange => Self::DecodeSize,
            DecodeErrorKind::CapacityExceeded => Self::DecodeCapacity,
            DecodeErrorKind::InvalidChoiceIndex => Self::DecodeChoice,
            DecodeErrorKind::InvalidEnumIndex => Self::DecodeEnum,
            DecodeErrorKind::InvalidCharacter => Self::DecodeCharacter,
            DecodeErrorKind::OpenTypeLengthMismatch => Self::DecodeOpenType,
            DecodeErrorKind::FragmentedOpenType => Self::DecodeFragmented,
            DecodeErrorKind::TrailingBytes => Self::DecodeTrailing,
            DecodeErrorKind::LengthTooLarge => Self::DecodeLengthTooLarge,
            DecodeErrorKind::UnexpectedMessage => Self::DecodeUnexpectedMessage,
            _ => Self::DecodeOther,
        }
    }

    /// The reason of the core's refusal of a MAP, TIM or PSM.
    pub const fn from_ingest(e: IngestError) -> Self {
        match e {
            IngestError::InvalidReference => Self::IngestReference,
            IngestError::UnsupportedNode => Self::IngestNode,
            IngestError::NoGeometry => Self::IngestGeometry,
            IngestError::ReferenceLaneMissing => Self::IngestLane,
            IngestError::ReferenceMapMissing => Self::IngestMap,
            IngestError::DuplicateLane => Self::IngestDuplicateLane,
            IngestError::CapacityExceeded => Self::IngestCapacity,
            IngestError::InvalidValue => Self::IngestValue,
            IngestError::NotRoadWorker => Self::IngestNotWorker,
            IngestError::InvalidPosition => Self::IngestPosition,
            IngestError::AccuracyUnavailable => Self::IngestAccuracy,
            IngestError::StaleMessage => Self::IngestStale,
            IngestError::StoreFull => Self::IngestStoreFull,
            IngestError::NotDue => Self::IngestNotDue,
        }
    }
}

impl core::fmt::Display for DropReason {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}
