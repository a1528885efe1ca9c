//! [`Rejection`]: why the trust policy refused a message.

/// Why the trust policy refused a signed message (or a certificate): a closed set, each
/// counted under its [`Rejection::as_str`] name in the receive path's counters (as a
/// [`DropReason`](crate::v2x::DropReason) of the security layer). Declared in counter
/// order: [`Rejection::index`] is the declaration order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rejection {
    /// Signed by `self`: no certificate ties the key to a trusted sender.
    SelfSigned,
    /// A hash or signature algorithm other than SHA-256 / ECDSA P-256.
    UnsupportedAlgorithm,
    /// A `digest` signer whose certificate has not been seen.
    SignerUnknown,
    /// The certificate chain does not lead to a configured trust anchor.
    ChainUntrusted,
    /// More certificates in the chain than the verifier walks.
    ChainTooLong,
    /// A certificate of the chain has a bad signature, key or validity.
    CertificateInvalid,
    /// A certificate of the chain may not certify the message's PSID.
    IssuerPermission,
    /// A certificate larger than the verifier's capacities (PSIDs, region).
    CertificateTooLarge,
    /// The signer certificate's validity ended before the message.
    CertificateExpired,
    /// The signer certificate's validity starts after the message.
    CertificateNotYetValid,
    /// The signer certificate does not permit the message's PSID.
    PsidNotPermitted,
    /// The PSID is not the one configured for this message (TIM, MAP).
    PsidMismatch,
    /// The generation location is outside the signer certificate's region.
    RegionMiss,
    /// The certificate has a region, and no location is known to check it.
    NoLocation,
    /// The signature does not verify.
    SignatureInvalid,
    /// The header has no generation time.
    NoGenerationTime,
    /// No GNSS time yet to check times against.
    NoTime,
    /// Generated further ahead of GNSS time than the profile's future tolerance.
    GenerationTimeFuture,
    /// No expiry time, and generated longer ago than the profile's past window.
    GenerationTimeOld,
    /// Past the header's expiry time (plus the future tolerance).
    MessageExpired,
    /// A copy of a message accepted before, for a message type whose copies are replays.
    Replay,
    /// A newer message of the same identity (TIM packet, MAP, PSM sender) was accepted.
    Superseded,
    /// The profile requires an expiry time and the header has none.
    NoExpiryTime,
    /// The expiry time is not after the generation time.
    ExpiryBeforeGeneration,
    /// Generation to expiry is longer than the profile's longest lifetime.
    LifetimeTooLong,
    /// Not one canonical COER certificate (a certificate learnt out of band).
    CertificateMalformed,
    /// The signer certificate does not grant the SSP the settings require for the message.
    SspNotPermitted,
}

impl Rejection {
    /// Every rejection, in [`Rejection::index`] order.
    pub const ALL: [Rejection; 27] = [
        Self::SelfSigned,
        Self::UnsupportedAlgorithm,
        Self::SignerUnknown,
        Self::ChainUntrusted,
        Self::ChainTooLong,
        Self::CertificateInvalid,
        Self::IssuerPermission,
        Self::CertificateTooLarge,
        Self::CertificateExpired,
        Self::CertificateNotYetValid,
        Self::PsidNotPermitted,
        Self::PsidMismatch,
        Self::RegionMiss,
        Self::NoLocation,
        Self::SignatureInvalid,
        Self::NoGenerationTime,
        Self::NoTime,
        Self::GenerationTimeFuture,
        Self::GenerationTimeOld,
        Self::MessageExpired,
        Self::Replay,
        Self::Superseded,
        Self::NoExpiryTime,
        Self::ExpiryBeforeGeneration,
        Self::LifetimeTooLong,
        Self::CertificateMalformed,
        Self::SspNotPermitted,
    ];
    /// The number of rejections.
    pub const COUNT: usize = Self::ALL.len();

    /// Position in [`Rejection::ALL`] (the declaration order). An exhaustive match: a new
    /// kind does not compile until it has its place here and in `ALL`.
    pub const fn index(self) -> usize {
        match self {
            Self::SelfSigned => 0,
            Self::UnsupportedAlgorithm => 1,
            Self::SignerUnknown => 2,
            Self::ChainUntrusted => 3,
            Self::ChainTooLong => 4,
            Self::CertificateInvalid => 5,
            Self::IssuerPermission => 6,
            Self::CertificateTooLarge => 7,
            Self::CertificateExpired => 8,
            Self::CertificateNotYetValid => 9,
            Self::PsidNotPermitted => 10,
            Self::PsidMismatch => 11,
            Self::RegionMiss => 12,
            Self::NoLocation => 13,
            Self::SignatureInvalid => 14,
            Self::NoGenerationTime => 15,
            Self::NoTime => 16,
            Self::GenerationTimeFuture => 17,
            Self::GenerationTimeOld => 18,
            Self::MessageExpired => 19,
            Self::Replay => 20,
            Self::Superseded => 21,
            Self::NoExpiryTime => 22,
            Self::ExpiryBeforeGeneration => 23,
            Self::LifetimeTooLong => 24,
            Self::CertificateMalformed => 25,
            Self::SspNotPermitted => 26,
        }
    }

    /// The counter name: a static string, the same for every message refused this way.
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::SelfSigned => "1609.2: self-signed (no certificate)",
            Self::UnsupportedAlgorithm => "1609.2: unsupported hash or signature algorithm",
            Self::SignerUnknown => "1609.2: signer certificate unknown (digest)",
            Self::ChainUntrusted => "1609.2: chain does not reach a trust anchor",
            Self::ChainTooLong => "1609.2: certificate chain too long",
            Self::CertificateInvalid => "1609.2: certificate invalid",
            Self::IssuerPermission => "1609.2: issuer may not certify the PSID",
            Self::CertificateTooLarge => "1609.2: certificate beyond the capacities",
            Self::CertificateExpired => "1609.2: signer certificate expired",
            Self::CertificateNotYetValid => "1609.2: signer certificate not yet valid",
            Self::PsidNotPermitted => "1609.2: PSID not permitted by the signer certificate",
            Self::PsidMismatch => "1609.2: PSID does not match the message",
            Self::RegionMiss => "1609.2: outside the certificate region",
            Self::NoLocation => "1609.2: no location to check the region",
            Self::SignatureInvalid => "1609.2: signature does not verify",
            Self::NoGenerationTime => "1609.2: no generation time",
            Self::NoTime => "1609.2: no GNSS time to check against",
            Self::GenerationTimeFuture => "1609.2: generation time in the future",
            Self::GenerationTimeOld => "1609.2: generation time too old",
            Self::MessageExpired => "1609.2: message expired",
            Self::Replay => "1609.2: replay",
            Self::Superseded => "1609.2: superseded by a newer version",
            Self::NoExpiryTime => "1609.2: no expiry time",
            Self::ExpiryBeforeGeneration => "1609.2: expiry time before generation time",
            Self::LifetimeTooLong => "1609.2: lifetime longer than allowed",
            Self::CertificateMalformed => "1609.2: certificate malformed",
            Self::SspNotPermitted => "1609.2: SSP not permitted by the signer certificate",
        }
    }
}
