//! The layers of [`DropReason`](super::DropReason): one reason type per stage of the receive
//! path. A layer wraps the upstream error kind where that kind is a closed set with its
//! own name and index (the codec's UPER kinds, WSMP errors, the ingest's errors, the trust
//! policy's rejections), and names its reasons itself where the upstream error carries data
//! or its names need the layer's prefix.

use j2735::envelope::ieee1609dot2::DecodeErrorKind as EnvelopeKind;
use j2735::envelope::wsmp::WsmpError;
use j2735::uper::DecodeErrorKind;

use crate::ingest::IngestError;
use crate::security::Rejection;

reasons! {
    /// Before the content is looked at: the transport, or the firmware's serial framing.
    pub enum DatagramReason {}
    names {
        /// The datagram is larger than the receiver accepts.
        TooLarge = "datagram too large",
        /// The transport reported a receive error (counted by the caller).
        Receive = "receive error",
        /// Serial link: a frame longer than the receive buffer.
        LinkTooLong = "frame too long",
        /// Serial link: invalid COBS encoding.
        LinkCobs = "invalid COBS encoding",
        /// Serial link: a frame with no room for its CRC.
        LinkTooShort = "frame shorter than its CRC",
        /// Serial link: CRC mismatch.
        LinkCrc = "CRC mismatch",
    }
}

reasons! {
    /// The envelope around the MessageFrame: IEEE 1609.2, RSU 4.1 text or WSMP.
    pub enum EnvelopeReason {
        /// IEEE 1609.2.
        Ieee1609(Ieee1609Reason),
        /// RSU 4.1 text.
        RsuText(RsuTextReason),
        /// IEEE 1609.3 WAVE Short Message.
        Wsmp(WsmpReason),
    }
}

reasons! {
    /// An IEEE 1609.2 envelope the receive path cannot open.
    pub enum Ieee1609Reason {
        /// Malformed, by the parser's kind (counted as `1609.2: ` and the kind's name).
        Malformed(EnvelopeKind) => ieee1609_name,
    }
    names {
        /// Malformed in a way with no counter of its own. No kind of this parser lands
        /// here (each has its own); the counter keeps its name in the fixed set the daemon,
        /// the simulator and the firmware know.
        Other = "1609.2: malformed",
        /// Well formed, but no plaintext application data (encrypted, hash only).
        NoPlaintext = "1609.2: no plaintext payload",
    }
}

/// The counter name of a malformed IEEE 1609.2 envelope: the parser's name of its kind
/// behind `1609.2: ` (spelt out, as counter names are static strings).
const fn ieee1609_name(kind: EnvelopeKind) -> &'static str {
    match kind {
        EnvelopeKind::UnexpectedEnd => "1609.2: unexpected end",
        EnvelopeKind::UnsupportedVersion => "1609.2: unsupported protocol version",
        EnvelopeKind::InvalidTag => "1609.2: invalid choice tag",
        EnvelopeKind::UnknownAlternative => "1609.2: unknown choice alternative",
        EnvelopeKind::NonCanonical => "1609.2: non-canonical encoding",
        EnvelopeKind::InvalidLength => "1609.2: invalid length",
        EnvelopeKind::LengthTooLarge => "1609.2: length too large",
        EnvelopeKind::ValueOutOfRange => "1609.2: value out of range",
        EnvelopeKind::EmptySignedPayload => "1609.2: signed payload without data or hash",
        EnvelopeKind::NestingTooDeep => "1609.2: nesting too deep",
        EnvelopeKind::TrailingBytes => "1609.2: trailing bytes",
        // A kind the parser gains later: the tests find its name twice in the layer.
        _ => Ieee1609Reason::Other.as_str(),
    }
}

reasons! {
    /// An RSU 4.1 text record the receive path cannot use (by kind; the line and key are
    /// not kept).
    pub enum RsuTextReason {}
    names {
        /// Not UTF-8.
        NotUtf8 = "RSU text: not UTF-8",
        /// A line that is not `Key=Value`.
        NotKeyValue = "RSU text: line is not Key=Value",
        /// A required key is missing.
        MissingKey = "RSU text: missing key",
        /// A key given twice.
        DuplicateKey = "RSU text: duplicate key",
        /// A value the key does not allow.
        InvalidValue = "RSU text: invalid value",
        /// Malformed in a way this build has no name for.
        Other = "RSU text: malformed",
        /// The payload is not hexadecimal text.
        PayloadHex = "RSU text: payload not hexadecimal",
        /// The payload is larger than the receive scratch holds.
        PayloadTooLarge = "RSU text: payload too large",
    }
}

reasons! {
    /// An IEEE 1609.3 WAVE Short Message the receive path cannot use.
    pub enum WsmpReason {
        /// Not a WSM this parser reads (counted under the error's name).
        Parse(WsmpError),
    }
    names {
        /// The T-header's PSID is not the message's (the 1609.2 header's, or the message
        /// type's for unsigned data; MAP may come with SPaT's).
        PsidMismatch = "WSMP: PSID does not match the message",
    }
}

reasons! {
    /// The UPER MessageFrame (or the MAP, TIM or PSM in it) does not decode (by kind; the
    /// bit and type path are not kept).
    pub enum DecodeReason {
        /// The codec's kind (counted under its name).
        Kind(DecodeErrorKind),
    }
    names {
        /// An error with no counter of its own. No kind of this codec lands here (each has
        /// its own); the counter keeps its name in the fixed set the daemon, the simulator
        /// and the firmware know.
        Other = "malformed",
    }
}

reasons! {
    /// The core refused the decoded MAP, TIM or PSM (or part of it).
    pub enum IngestReason {
        /// The ingest's error (counted under its name).
        Refused(IngestError),
    }
    names {
        /// Unverified data that would have replaced, refreshed, cancelled or evicted a lane
        /// model or work zone that came verified: nothing changed.
        UnverifiedOverVerified = "unverified data over verified data",
    }
}

reasons! {
    /// IEEE 1609.2 security: unsigned when signatures are required, or a check of the trust
    /// policy failed (see [`crate::security`]).
    pub enum SecurityReason {
        /// The trust policy's rejection (counted under its name).
        Rejected(Rejection),
    }
    names {
        /// Not signed, and signatures are required.
        Unsigned = "unsigned (signatures required)",
    }
}
