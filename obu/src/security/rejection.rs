//! [`Rejection`]: why the trust policy refused a message.

/// Why the trust policy refused a signed message (or a certificate): a closed set, each
/// with its [`DropReason`](crate::v2x::DropReason) in the receive path's counters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Rejection {
    /// A hash or signature algorithm other than SHA-256 / ECDSA P-256.
    UnsupportedAlgorithm,
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
    /// The profile requires an expiry time and the header has none.
    NoExpiryTime,
    /// The expiry time is not after the generation time.
    ExpiryBeforeGeneration,
    /// Generation to expiry is longer than the profile's longest lifetime.
    LifetimeTooLong,
    /// A copy of a message accepted before, for a message type whose copies are replays.
    Replay,
    /// A newer message of the same identity (TIM packet, MAP, PSM sender) was accepted.
    Superseded,
    /// The signer certificate does not permit the message's PSID.
    PsidNotPermitted,
    /// The PSID is not the one configured for this message (TIM, MAP).
    PsidMismatch,
    /// The signer certificate does not grant the SSP the settings require for the message.
    SspNotPermitted,
    /// The certificate has a region, and no location is known to check it.
    NoLocation,
    /// The generation location is outside the signer certificate's region.
    RegionMiss,
    /// The signature does not verify.
    SignatureInvalid,
    /// Signed by `self`: no certificate ties the key to a trusted sender.
    SelfSigned,
    /// A `digest` signer whose certificate has not been seen.
    SignerUnknown,
    /// The certificate chain does not lead to a configured trust anchor.
    ChainUntrusted,
    /// More certificates in the chain than the verifier walks.
    ChainTooLong,
    /// A certificate larger than the verifier's capacities (PSIDs, region).
    CertificateTooLarge,
    /// A certificate of the chain has a bad signature, key or validity.
    CertificateInvalid,
    /// The signer certificate's validity ended before the message.
    CertificateExpired,
    /// The signer certificate's validity starts after the message.
    CertificateNotYetValid,
    /// A certificate of the chain may not certify the message's PSID.
    IssuerPermission,
    /// Not one canonical COER certificate (a certificate learnt out of band).
    CertificateMalformed,
}
