//! IEEE 1609.2 trust policy: which signed MAP, TIM and PSM the core may act on. One place for
//! the daemon and the firmware; no heap.
//!
//! [`Trust::check`] takes a parsed signed message, the `messageId` of the frame inside, the
//! GNSS time (`Time64`) and the vehicle position, and accepts it or names the
//! [`Rejection`] (counted as [`DropGroup::Security`](crate::v2x::DropGroup)):
//!
//! 1. SHA-256 and ECDSA P-256 only; `self` signers are refused (no certificate ties the
//!    key to a sender).
//! 2. The signer: a `digest` must name a certificate already verified (the cache, by
//!    `HashedId8`); a `certificate` chain is walked down from a configured trust anchor
//!    (root or issuing CA): each certificate's issuer digest, signature (explicit) or ECQV
//!    reconstruction (implicit), validity inside its issuer's, and the issuer's permission
//!    to certify the PSID. The verified signer is cached, so the next message signed by
//!    the same certificate (as `digest` or as `certificate`) costs one signature check.
//! 3. The signer certificate: valid at the generation time and now, it permits the PSID
//!    (with the SSP the settings require for the message, if any), and its region holds the
//!    generation location (or the vehicle's position).
//! 4. The PSID is the one configured for the message (TIM, MAP; PSM: [`PSID_PSM`]).
//! 5. Times: a generation time within the allowed skew of GNSS time, not past expiry.
//! 6. Replay: the same generation time and signature hash accepted before.
//! 7. The signature over `SHA-256(SHA-256(ToBeSignedData) || SHA-256(signer certificate))`,
//!    unless this signer's signature on the same payload was verified less than
//!    [`SecurityConfig::reverify_ms`] ago (a roadside repeats each message at 10 Hz).
//!
//! Not checked (stated so that no one relies on it): certificate revocation (CRLs),
//! `minChainLength`, SSP semantics beyond an exact match of the configured octets, SSP
//! ranges of issuers, identified (country) regions, and regions inherited from issuers by
//! certificates without their own.

mod cert;
mod region;
mod rejection;
mod replay;
#[cfg(test)]
mod tests;

pub use cert::TrustedCert;
pub use region::{Region, RegionError};
pub use rejection::Rejection;
pub use replay::ReplayWindow;

use heapless::Vec;
use j2735::envelope::ieee1609dot2::crypto::{sha256, signing_digest_with, GeneratorTable};
use j2735::envelope::ieee1609dot2::{
    Certificate, HashAlgorithm, Issuer, SignatureScheme, SignedData, SignerIdentifier,
};
use j2735::frame::Message;
use j2735::personal_safety_message::PersonalSafetyMessage;
use j2735::{MapData, TravelerInformation};

use crate::capacity::{MAX_CACHED_CERTS, MAX_CHAIN, MAX_RECENT, MAX_TRUST_ANCHORS};
use crate::geo::LatLon;

/// The PSID of TIM (SAE J2735 traveler information).
pub const PSID_TIM: u32 = 0x8003;
/// The PSID of MAP (SAE J2735 / J2945 intersection and road geometry).
pub const PSID_MAP: u32 = 0xE000_0017;
/// The PSID of PSM (SAE J2945/9 vulnerable road user safety): a signed PSM must carry it.
/// PSMs pass every check a TIM does (chain to a configured anchor, PSID permission, region,
/// times, replay); no SSP is required of them.
pub const PSID_PSM: u32 = 0x27;

/// The trust policy's settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SecurityConfig {
    /// Drop unsigned MAP, TIM and PSM. Off: they are used, marked unverified, and can never
    /// replace, refresh, cancel or evict data that came verified.
    pub require_signed: bool,
    /// Largest allowed distance between a generation time and GNSS time, milliseconds.
    pub max_skew_ms: u32,
    /// The PSID a signed TIM must carry.
    pub tim_psid: u32,
    /// The PSID a signed MAP must carry.
    pub map_psid: u32,
    /// The service-specific permissions a signed TIM's signer certificate must grant with
    /// its PSID ([`RequiredSsp::NONE`]: any, or none).
    pub tim_ssp: RequiredSsp,
    /// The same for MAP.
    pub map_ssp: RequiredSsp,
    /// A frame whose payload is byte-identical to one this signer's signature was verified
    /// on less than this long ago (milliseconds of GNSS time), and that passes every other
    /// check (certificate, PSID, region, times, replay), is taken without verifying its
    /// signature again; 0 verifies every frame. A roadside repeats each MAP and TIM at 10 Hz:
    /// this verifies each payload about once a second (what the firmware's CPU can afford),
    /// and a forger can at most keep a zone that was really broadcast alive this much longer
    /// (never change, cancel or add one).
    pub reverify_ms: u32,
}

impl SecurityConfig {
    /// Signatures required, 30 s skew, the standard PSIDs.
    pub const DEFAULT: Self = Self {
        require_signed: true,
        max_skew_ms: 30_000,
        tim_psid: PSID_TIM,
        map_psid: PSID_MAP,
        tim_ssp: RequiredSsp::NONE,
        map_ssp: RequiredSsp::NONE,
        reverify_ms: 1000,
    };
}

/// Opaque service-specific permissions (SSP) that a signer certificate must grant with a
/// PSID, byte for byte: what an operator's SCMS assigns to its roadside units. Up to
/// [`RequiredSsp::MAX`] octets; empty: no requirement.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RequiredSsp {
    len: u8,
    bytes: [u8; RequiredSsp::MAX],
}

impl RequiredSsp {
    /// Longest SSP that can be required, octets.
    pub const MAX: usize = 16;
    /// No requirement.
    pub const NONE: Self = Self {
        len: 0,
        bytes: [0; Self::MAX],
    };

    /// `ssp` required; `None` when longer than [`RequiredSsp::MAX`].
    pub fn new(ssp: &[u8]) -> Option<Self> {
        let mut bytes = [0; Self::MAX];
        bytes.get_mut(..ssp.len())?.copy_from_slice(ssp);
        Some(Self {
            len: ssp.len() as u8,
            bytes,
        })
    }

    /// The required octets (empty: none required).
    pub fn as_bytes(&self) -> &[u8] {
        &self.bytes[..usize::from(self.len).min(Self::MAX)]
    }
}

impl Default for SecurityConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why a trust anchor was not added.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AnchorError {
    /// Not one canonical COER certificate.
    Malformed,
    /// Implicit, a bad self-signature or key, or beyond the capacities.
    Invalid(Rejection),
    /// [`MAX_TRUST_ANCHORS`] already held.
    Full,
}

/// Of two clocks (either may be unknown), the one nearer `generated`.
fn nearer_clock(a: Option<u64>, b: Option<u64>, generated: u64) -> Option<u64> {
    match (a, b) {
        (Some(a), Some(b)) => Some(if a.abs_diff(generated) <= b.abs_diff(generated) {
            a
        } else {
            b
        }),
        (a, b) => a.or(b),
    }
}

/// The message facts the policy needs besides the signature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CheckContext {
    /// The frame's `messageId`.
    pub message_id: u16,
    /// GNSS time as `Time64` (TAI microseconds since 2004), if known.
    pub now_us: Option<u64>,
    /// A second clock (the reference clock) while GNSS time disagrees with it
    /// ([`crate::clock::TimeStatus::Unverified`]) by no more than
    /// [`crate::clock::MAX_SECOND_CLOCK_OFFSET_MS`]: the message's times are checked against
    /// whichever of the two is nearer its generation time, so a receiver clock off by
    /// minutes does not drop every message. The replay window forgets only what is old on
    /// both clocks, and the re-verification cache runs on `now_us` alone.
    pub alt_now_us: Option<u64>,
    /// The vehicle's last position, if known.
    pub position: Option<LatLon>,
}

/// Trust anchors, the cache of verified signer certificates and the replay window.
#[derive(Debug, Clone)]
pub struct Trust {
    /// False until settings are given: [`SecurityConfig::DEFAULT`] applies. Kept apart so
    /// that an unconfigured `Trust` is all zero bytes (a firmware `static` of it, and of
    /// the receive path holding it, lands in .bss instead of .data).
    configured: bool,
    config: SecurityConfig,
    anchors: Vec<TrustedCert, MAX_TRUST_ANCHORS>,
    cache: Vec<TrustedCert, MAX_CACHED_CERTS>,
    replay: ReplayWindow,
    /// The generator's multiples, made at the first check.
    generator: Option<GeneratorTable>,
    /// Payloads whose signature was verified lately (see [`SecurityConfig::reverify_ms`]).
    recent: Vec<Recent, MAX_RECENT>,
}

/// A payload whose signature was verified: its hash, signer, PSID and when (GNSS time).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Recent {
    payload: [u8; 16],
    signer: [u8; 32],
    psid: u32,
    verified_us: u64,
}

impl Default for Trust {
    fn default() -> Self {
        Self::unconfigured()
    }
}

impl Trust {
    /// No anchors yet: every signed message is refused until one is added.
    pub const fn new(config: SecurityConfig) -> Self {
        Self {
            configured: true,
            config,
            anchors: Vec::new(),
            cache: Vec::new(),
            replay: ReplayWindow::new(),
            generator: None,
            recent: Vec::new(),
        }
    }

    /// [`SecurityConfig::DEFAULT`] (signatures required) and no anchors, as all zero bytes.
    pub const fn unconfigured() -> Self {
        Self {
            configured: false,
            config: SecurityConfig {
                require_signed: false,
                max_skew_ms: 0,
                tim_psid: 0,
                map_psid: 0,
                tim_ssp: RequiredSsp::NONE,
                map_ssp: RequiredSsp::NONE,
                reverify_ms: 0,
            },
            anchors: Vec::new(),
            cache: Vec::new(),
            replay: ReplayWindow::new(),
            generator: None,
            recent: Vec::new(),
        }
    }

    /// The settings.
    pub fn config(&self) -> SecurityConfig {
        if self.configured {
            self.config
        } else {
            SecurityConfig::DEFAULT
        }
    }

    /// Replaces the settings.
    pub fn set_config(&mut self, config: SecurityConfig) {
        self.configured = true;
        self.config = config;
    }

    /// Trusts the certificate `coer` (a root, or an issuing CA; explicit).
    ///
    /// # Errors
    ///
    /// [`AnchorError`] when it is malformed or invalid, or the anchors are full.
    pub fn add_anchor(&mut self, coer: &[u8]) -> Result<(), AnchorError> {
        let cert = Certificate::parse(coer).map_err(|_| AnchorError::Malformed)?;
        let anchor = TrustedCert::anchor(&cert).map_err(AnchorError::Invalid)?;
        if self.anchors.iter().any(|a| a.hash == anchor.hash) {
            return Ok(());
        }
        self.anchors.push(anchor).map_err(|_| AnchorError::Full)
    }

    /// Number of trust anchors.
    pub fn anchors(&self) -> usize {
        self.anchors.len()
    }

    /// Number of cached signer certificates.
    pub fn cached(&self) -> usize {
        self.cache.len()
    }

    /// The PSID configured for `message_id`, if the OBU uses that message.
    pub fn psid_for(&self, message_id: u16) -> Option<u32> {
        let config = self.config();
        match message_id {
            TravelerInformation::MESSAGE_ID => Some(config.tim_psid),
            MapData::MESSAGE_ID => Some(config.map_psid),
            PersonalSafetyMessage::MESSAGE_ID => Some(PSID_PSM),
            _ => None,
        }
    }

    /// The SSP required for `message_id`.
    fn ssp_for(&self, message_id: u16) -> RequiredSsp {
        let config = self.config();
        match message_id {
            TravelerInformation::MESSAGE_ID => config.tim_ssp,
            MapData::MESSAGE_ID => config.map_ssp,
            _ => RequiredSsp::NONE,
        }
    }

    /// Accepts `signed` (see the [module docs](self)) or names why not. An accepted
    /// message is remembered for the replay check.
    ///
    /// # Errors
    ///
    /// The [`Rejection`] of the first check that fails.
    pub fn check(&mut self, signed: &SignedData<'_>, ctx: &CheckContext) -> Result<(), Rejection> {
        let header = &signed.header;
        if signed.hash_algorithm != HashAlgorithm::Sha256
            || signed.signature.scheme != SignatureScheme::EcdsaNistP256
        {
            return Err(Rejection::UnsupportedAlgorithm);
        }
        let generated = header.generation_time.ok_or(Rejection::NoGenerationTime)?.0;
        let now = nearer_clock(ctx.now_us, ctx.alt_now_us, generated).ok_or(Rejection::NoTime)?;
        if self.generator.is_none() {
            self.generator = Some(GeneratorTable::new());
        }
        let index = self.signer(&signed.signer, header.psid)?;
        let signer = &self.cache[index];
        self.check_certified(signer, signed, ctx, now)?;
        let skew = u64::from(self.config().max_skew_ms) * 1000;
        if generated > now.saturating_add(skew) {
            return Err(Rejection::GenerationTimeFuture);
        }
        if generated < now.saturating_sub(skew) {
            return Err(Rejection::GenerationTimeOld);
        }
        if header.expiry_time.is_some_and(|e| e.0 < now) {
            return Err(Rejection::MessageExpired);
        }
        let digest = signing_digest_with(signed.to_be_signed, &signer.hash);
        if !self.replay.is_new(generated, &digest) {
            return Err(Rejection::Replay);
        }
        let payload = signed.payload.data.map(|d| payload_tag(d.encoded()));
        let signer_hash = signer.hash;
        // The re-verification cache runs on one clock only (GNSS when known), so that a
        // message checked on the other clock can never look "verified lately".
        let cache_clock = ctx.now_us.unwrap_or(now);
        if !self.verified_lately(payload, &signer_hash, header.psid, cache_clock) {
            let generator = self.generator.as_ref().ok_or(Rejection::SignatureInvalid)?;
            self.cache[index]
                .key
                .verify(generator, &digest, &signed.signature)
                .map_err(|_| Rejection::SignatureInvalid)?;
            if let Some(payload) = payload {
                self.remember(payload, signer_hash, header.psid, cache_clock);
            }
        }
        // Forget only what is old on both clocks: a message one clock forgot could still pass
        // the time check on the other.
        let earliest = match (ctx.now_us, ctx.alt_now_us) {
            (Some(a), Some(b)) => a.min(b),
            _ => now,
        };
        self.replay
            .record(generated, &digest, earliest.saturating_sub(skew));
        Ok(())
    }

    /// The checks against the signer certificate: validity (at generation and at `now`),
    /// PSID, region.
    fn check_certified(
        &self,
        signer: &TrustedCert,
        signed: &SignedData<'_>,
        ctx: &CheckContext,
        now: u64,
    ) -> Result<(), Rejection> {
        let header = &signed.header;
        let generated = header.generation_time.map_or(0, |t| t.0);
        check_validity(signer, generated.min(now), generated.max(now))?;
        let Some(granted) = signer.permission(header.psid) else {
            return Err(Rejection::PsidNotPermitted);
        };
        if self.psid_for(ctx.message_id) != Some(header.psid) {
            return Err(Rejection::PsidMismatch);
        }
        let required = self.ssp_for(ctx.message_id);
        if !required.as_bytes().is_empty() && granted != Some(required.as_bytes()) {
            return Err(Rejection::SspNotPermitted);
        }
        if let Some(region) = &signer.region {
            let at = match header.generation_location {
                Some(l) => LatLon::new(l.latitude, l.longitude),
                None => ctx.position,
            };
            if !region.contains(at.ok_or(Rejection::NoLocation)?) {
                return Err(Rejection::RegionMiss);
            }
        }
        Ok(())
    }

    /// Whether this signer's signature on `payload` (with `psid`) was verified less than
    /// `reverify_ms` before `now`.
    fn verified_lately(
        &self,
        payload: Option<[u8; 16]>,
        signer: &[u8; 32],
        psid: u32,
        now: u64,
    ) -> bool {
        let window = u64::from(self.config().reverify_ms) * 1000;
        let Some(payload) = payload else {
            return false;
        };
        window > 0
            && self.recent.iter().any(|r| {
                r.payload == payload
                    && &r.signer == signer
                    && r.psid == psid
                    && now >= r.verified_us
                    && now - r.verified_us < window
            })
    }

    /// Records a verified payload (replacing its older entry, else the oldest entry).
    fn remember(&mut self, payload: [u8; 16], signer: [u8; 32], psid: u32, now: u64) {
        let entry = Recent {
            payload,
            signer,
            psid,
            verified_us: now,
        };
        let same = |r: &Recent| r.payload == payload && r.signer == signer && r.psid == psid;
        if let Some(slot) = self.recent.iter_mut().find(|r| same(r)) {
            *slot = entry;
        } else if let Err(entry) = self.recent.push(entry) {
            if let Some(oldest) = self.recent.iter_mut().min_by_key(|r| r.verified_us) {
                *oldest = entry;
            }
        }
    }

    /// The trusted signer certificate of a message with `psid`: cached, or verified along
    /// its chain from an anchor and then cached.
    fn signer(&mut self, signer: &SignerIdentifier<'_>, psid: u32) -> Result<usize, Rejection> {
        match signer {
            SignerIdentifier::SelfSigned => Err(Rejection::SelfSigned),
            SignerIdentifier::Digest(id) => {
                let found = self.cache.iter().position(|c| &c.id8() == id);
                found.ok_or(Rejection::SignerUnknown)
            }
            SignerIdentifier::Certificate(chain) => {
                let first = chain.first().ok_or(Rejection::ChainUntrusted)?;
                let hash = sha256(first.encoded);
                match self.cache.iter().position(|c| c.hash == hash) {
                    Some(i) => Ok(i),
                    None => {
                        let verified = self.walk_chain(chain.iter(), chain.len(), &[psid])?;
                        Ok(self.cache_insert(verified))
                    }
                }
            }
        }
    }

    /// Verifies a signer certificate `coer` issued by a trust anchor (or by a certificate
    /// already verified) and caches it, so that messages naming it by `digest` verify: a
    /// certificate learnt out of band (configuration, a certificate store).
    ///
    /// # Errors
    ///
    /// [`Rejection::CertificateMalformed`] when `coer` is not a certificate, else the chain
    /// check's reason (the issuer must be allowed to certify each of its PSIDs).
    pub fn learn(&mut self, coer: &[u8]) -> Result<(), Rejection> {
        let cert = Certificate::parse(coer).map_err(|_| Rejection::CertificateMalformed)?;
        let mut psids: Vec<u32, { crate::capacity::MAX_CERT_PSIDS }> = Vec::new();
        for p in cert.app_permissions.iter().flat_map(|l| l.iter()) {
            psids
                .push(p.psid)
                .map_err(|_| Rejection::CertificateTooLarge)?;
        }
        let verified = self.walk_chain(core::iter::once(cert), 1, &psids)?;
        if !self.cache.iter().any(|c| c.hash == verified.hash) {
            self.cache_insert(verified);
        }
        Ok(())
    }

    /// Verifies a chain (signer first) down from a trust anchor; every issuer must be
    /// allowed to certify each of `psids`.
    fn walk_chain<'a>(
        &mut self,
        certs: impl Iterator<Item = Certificate<'a>>,
        len: usize,
        psids: &[u32],
    ) -> Result<TrustedCert, Rejection> {
        if len > MAX_CHAIN || len == 0 {
            return Err(Rejection::ChainTooLong);
        }
        let mut chain: Vec<Certificate<'a>, MAX_CHAIN> = Vec::new();
        for c in certs {
            chain.push(c).map_err(|_| Rejection::ChainTooLong)?;
        }
        // The topmost certificate that is an anchor itself or is issued by one.
        let (top, mut issuer) = chain
            .iter()
            .enumerate()
            .rev()
            .find_map(|(i, c)| {
                let hash = sha256(c.encoded);
                if let Some(a) = self.anchors.iter().find(|a| a.hash == hash) {
                    return (i > 0).then(|| (i - 1, a.clone()));
                }
                let Issuer::Sha256Digest(id) = c.issuer else {
                    return None;
                };
                let a = self.anchors.iter().find(|a| a.id8() == id)?;
                Some((i, a.clone()))
            })
            .ok_or(Rejection::ChainUntrusted)?;
        let generator = self.generator.get_or_insert_with(GeneratorTable::new);
        for i in (0..=top).rev() {
            issuer = issuer.issue(&chain[i], psids, generator)?;
        }
        Ok(issuer)
    }

    /// Caches a verified signer; when full, the oldest entry leaves (first in, first out).
    fn cache_insert(&mut self, cert: TrustedCert) -> usize {
        if self.cache.is_full() {
            self.cache.remove(0);
        }
        let _ = self.cache.push(cert);
        self.cache.len() - 1
    }
}

/// The first 16 octets of SHA-256 of a signed payload.
fn payload_tag(payload: &[u8]) -> [u8; 16] {
    let mut tag = [0u8; 16];
    tag.copy_from_slice(&sha256(payload)[..16]);
    tag
}

/// The certificate must be valid over `[from, to]` (generation time and now).
fn check_validity(cert: &TrustedCert, from: u64, to: u64) -> Result<(), Rejection> {
    if from < cert.validity.start_us() {
        return Err(Rejection::CertificateNotYetValid);
    }
    if to >= cert.validity.end_us() {
        return Err(Rejection::CertificateExpired);
    }
    Ok(())
}
