//! IEEE 1609.2 trust policy: which signed MAP, TIM and PSM the core may act on. One place for
//! the daemon and the firmware; no heap.
//!
//! [`Trust::check`] takes a parsed signed message, the `messageId` of the frame inside, the
//! GNSS time (`Time64`) and the vehicle position, and accepts it (verified, or a repeat) or
//! names the [`Rejection`] (counted as [`DropGroup::Security`](crate::v2x::DropGroup)). Each
//! message type has its [`SecurityProfile`] (PSID, SSP, time rules, duplicates); the checks,
//! in order:
//!
//! 1. SHA-256 and ECDSA P-256 only; `self` signers are refused (no certificate ties the
//!    key to a sender).
//! 2. The signer: a `digest` must name a certificate already verified (the cache, by
//!    `HashedId8`); a `certificate` chain is walked down from a configured trust anchor
//!    (root or issuing CA): each certificate's issuer digest, signature (explicit) or ECQV
//!    reconstruction (implicit), validity inside its issuer's, and the issuer's permission
//!    to certify the PSID. The verified signer is cached, so the next message signed by
//!    the same certificate (as `digest` or as `certificate`) costs one signature check.
//!    The signer certificate permits the PSID (with the profile's SSP, if any), the PSID is
//!    the profile's, and the certificate's region holds the generation location (or the
//!    vehicle's position).
//! 3. The signature over `SHA-256(SHA-256(ToBeSignedData) || SHA-256(signer certificate))`,
//!    unless the message is byte-identical to one accepted and still relevant (a repeat:
//!    one hash, no ECDSA), or this signer's signature on the same payload was verified less
//!    than [`SecurityConfig::reverify_ms`] ago (a roadside signing each transmission anew).
//! 4. Times ([`SecurityProfile`]): generation time before expiry time, their distance at
//!    most the longest lifetime, the generation time at most the future tolerance ahead of
//!    GNSS time, the signer certificate valid at the generation time and now; with an
//!    expiry time the message is relevant until it (plus the future tolerance), without one
//!    for the past window after its generation.
//! 5. Duplicates: a byte-identical copy of an accepted message is a repeat
//!    ([`Accepted::Repeat`]) or, where the profile says so, a [`Rejection::Replay`].
//!
//! Not checked (stated so that no one relies on it): certificate revocation (CRLs),
//! `minChainLength`, SSP semantics beyond an exact match of the configured octets, SSP
//! ranges of issuers, identified (country) regions, and regions inherited from issuers by
//! certificates without their own.

mod cert;
mod newest;
mod profile;
mod region;
mod rejection;
mod repeats;
#[cfg(test)]
mod tests;
mod times;

pub use cert::TrustedCert;
pub use newest::{Identity, Marker, NewestTable};
pub use profile::{Duplicates, SecurityProfile};
pub use region::{Region, RegionError};
pub use rejection::Rejection;
pub use repeats::{RepeatCache, Seen};

use heapless::Vec;
use j2735::envelope::ieee1609dot2::crypto::{sha256, signing_digest_with, GeneratorTable};
use j2735::envelope::ieee1609dot2::{
    Certificate, HashAlgorithm, Issuer, SignatureScheme, SignedData, SignerIdentifier,
};
use j2735::envelope::Psid;
use j2735::frame::Message;
use j2735::msg::personal_safety_message::PersonalSafetyMessage;
use j2735::{MapData, TravelerInformation};

use crate::capacity::{MAX_CACHED_CERTS, MAX_CHAIN, MAX_RECENT, MAX_TRUST_ANCHORS};
use crate::geo::LatLon;

/// The PSID of TIM (SAE J2735 traveler information): 131, p-encoded `0x8003`.
pub const PSID_TIM: Psid = Psid::TIM;
/// The PSID of MAP (SAE J2735 / J2945 intersection and road geometry): 2113687, p-encoded
/// `0xE0000017`.
pub const PSID_MAP: Psid = Psid::MAP;
/// The PSID of PSM (SAE J2945/9 vulnerable road user safety): 39, p-encoded `0x27`. PSMs
/// pass every check a TIM does (chain to a configured anchor, PSID permission, region,
/// times); no SSP is required of them by default, and a copy of one is a replay.
pub const PSID_PSM: Psid = Psid::PSM;

/// The trust policy's settings: one [`SecurityProfile`] per message type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SecurityConfig {
    /// Drop unsigned MAP, TIM and PSM. Off: they are used, marked unverified, and can never
    /// replace, refresh, cancel or evict data that came verified.
    pub require_signed: bool,
    /// Signed MAP.
    pub map: SecurityProfile,
    /// Signed TIM.
    pub tim: SecurityProfile,
    /// Signed PSM.
    pub psm: SecurityProfile,
    /// Signed SPaT (the row is ready; the OBU does not use SPaT yet).
    pub spat: SecurityProfile,
    /// A frame whose payload is byte-identical to one this signer's signature was verified
    /// on less than this long ago (milliseconds of GNSS time), and that passes every other
    /// check, is taken without verifying its signature again; 0 verifies every frame. A
    /// roadside that signs each transmission anew repeats each payload at 10 Hz: this
    /// verifies each payload about once a second (what the firmware's CPU can afford), and a
    /// forger can at most keep a zone that was really broadcast alive this much longer
    /// (never change, cancel or add one).
    pub reverify_ms: u32,
}

impl SecurityConfig {
    /// Signatures required, each message type's default profile
    /// ([`SecurityProfile::roadside`], [`SecurityProfile::PSM`]).
    pub const DEFAULT: Self = Self {
        require_signed: true,
        map: SecurityProfile::MAP,
        tim: SecurityProfile::TIM,
        psm: SecurityProfile::PSM,
        spat: SecurityProfile::SPAT,
        reverify_ms: 1000,
    };

    /// The profile of the message `message_id`, if the OBU uses it (MAP, TIM, PSM).
    pub fn profile(&self, message_id: u16) -> Option<&SecurityProfile> {
        match message_id {
            TravelerInformation::MESSAGE_ID => Some(&self.tim),
            MapData::MESSAGE_ID => Some(&self.map),
            PersonalSafetyMessage::MESSAGE_ID => Some(&self.psm),
            _ => None,
        }
    }
}

/// How a signed message was accepted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Accepted {
    /// Its signature was verified (or this signer's signature on the same payload was,
    /// lately).
    Verified,
    /// A byte-identical copy of a message accepted before and still relevant: what an RSU
    /// repeats. It refreshes what it carries.
    Repeat,
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

/// Trust anchors, the cache of verified signer certificates and the repeat cache.
#[derive(Debug, Clone)]
pub struct Trust {
    /// False until settings are given: [`SecurityConfig::DEFAULT`] applies. Kept apart so
    /// that an unconfigured `Trust` is all zero bytes (a firmware `static` of it, and of
    /// the receive path holding it, lands in .bss instead of .data).
    configured: bool,
    config: SecurityConfig,
    anchors: Vec<TrustedCert, MAX_TRUST_ANCHORS>,
    cache: Vec<TrustedCert, MAX_CACHED_CERTS>,
    repeats: RepeatCache,
    newest: NewestTable,
    /// What the last successful check accepted: its generation time, when it stops being
    /// relevant and the clock it was checked on (all `Time64`), for [`Trust::check_version`].
    last: Option<(Marker, u64)>,
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
    psid: Psid,
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
            repeats: RepeatCache::new(),
            newest: NewestTable::new(),
            last: None,
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
                map: SecurityProfile::ZERO,
                tim: SecurityProfile::ZERO,
                psm: SecurityProfile::ZERO,
                spat: SecurityProfile::ZERO,
                reverify_ms: 0,
            },
            anchors: Vec::new(),
            cache: Vec::new(),
            repeats: RepeatCache::new(),
            newest: NewestTable::new(),
            last: None,
            generator: None,
            recent: Vec::new(),
        }
    }

    /// The settings.
    pub fn config(&self) -> SecurityConfig {
        *self.settings()
    }

    /// The settings in force.
    fn settings(&self) -> &SecurityConfig {
        if self.configured {
            &self.config
        } else {
            &SecurityConfig::DEFAULT
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

    /// Number of accepted messages remembered (while relevant) for the repeat check.
    pub fn remembered(&self) -> usize {
        self.repeats.len()
    }

    /// The PSID configured for `message_id`, if the OBU uses that message.
    pub fn psid_for(&self, message_id: u16) -> Option<Psid> {
        self.settings().profile(message_id).map(|p| p.psid)
    }

    /// Accepts `signed` (see the [module docs](self)) or names why not. An accepted
    /// message is remembered, while it is relevant, for the repeat check.
    ///
    /// # Errors
    ///
    /// The [`Rejection`] of the first check that fails.
    pub fn check(
        &mut self,
        signed: &SignedData<'_>,
        ctx: &CheckContext,
    ) -> Result<Accepted, Rejection> {
        self.last = None;
        let header = &signed.header;
        if signed.hash_algorithm != HashAlgorithm::Sha256
            || signed.signature.scheme != SignatureScheme::EcdsaNistP256
        {
            return Err(Rejection::UnsupportedAlgorithm);
        }
        let profile = *self
            .settings()
            .profile(ctx.message_id)
            .ok_or(Rejection::PsidMismatch)?;
        let generated = header.generation_time.map(|t| t.0);
        let expiry = header.expiry_time.map(|t| t.0);
        let reference = generated.or(expiry).ok_or(Rejection::NoGenerationTime)?;
        let now = nearer_clock(ctx.now_us, ctx.alt_now_us, reference).ok_or(Rejection::NoTime)?;
        let index = self.signer(&signed.signer, header.psid)?;
        check_certified(&self.cache[index], &profile, signed, ctx)?;
        let signer_hash = self.cache[index].hash;
        let digest = signing_digest_with(signed.to_be_signed, &signer_hash);
        let tag = spdu_tag(&digest, signed);
        let replay_profile = profile.duplicates == Duplicates::Replay;
        let seen = self.repeats.find(&tag, reference, replay_profile);
        if seen == Seen::New {
            self.verify_signature(index, signed, &digest, ctx.now_us.unwrap_or(now))?;
        }
        let relevant_until = times::check(&profile, generated, expiry, now)?;
        let at = generated.unwrap_or(now);
        check_validity(&self.cache[index], at.min(now), at.max(now))?;
        let marker = Marker {
            identity: Identity([0; 16]),
            newest_us: reference,
            relevant_until_us: relevant_until,
        };
        self.last = Some((marker, now));
        if seen == Seen::Before {
            return match profile.duplicates {
                Duplicates::Repeat => Ok(Accepted::Repeat),
                Duplicates::Replay => Err(Rejection::Replay),
            };
        }
        // Forget only what is no longer relevant on both clocks: a message one clock forgot
        // could still pass the time check on the other.
        let earliest = match (ctx.now_us, ctx.alt_now_us) {
            (Some(a), Some(b)) => a.min(b),
            _ => now,
        };
        self.repeats
            .record(tag, reference, relevant_until, replay_profile, earliest);
        Ok(Accepted::Verified)
    }

    /// After a successful [`Trust::check`], and once the message is decoded: refuses it as
    /// [`Rejection::Superseded`] when a message of the same `identity` with a newer
    /// generation time was accepted, else records its generation time for `identity` and
    /// returns when the message stops being relevant (`Time64`: its expiry time plus the
    /// tolerance, or its generation time plus the past window). A message checked by
    /// nothing (unsigned) passes, with `None`.
    ///
    /// # Errors
    ///
    /// [`Rejection::Superseded`].
    pub fn check_version(&mut self, identity: Identity) -> Result<Option<u64>, Rejection> {
        let Some((last, now)) = self.last.take() else {
            return Ok(None);
        };
        if self.newest.is_superseded(&identity, last.newest_us) {
            return Err(Rejection::Superseded);
        }
        self.newest.record(Marker { identity, ..last }, now);
        Ok(Some(last.relevant_until_us))
    }

    /// The superseded check's markers (to keep them across restarts).
    pub fn markers(&self) -> &[Marker] {
        self.newest.markers()
    }

    /// Takes markers kept from an earlier run (those no longer relevant at `now_us` are
    /// forgotten; beyond the capacity the ones that end soonest leave).
    pub fn restore_markers(&mut self, markers: &[Marker], now_us: u64) {
        for m in markers {
            self.newest.record(*m, now_us);
        }
    }

    /// Verifies the signature of `signed` (its signing digest `digest`) with the cached
    /// signer `index`, unless this signer's signature on the same payload was verified
    /// lately. The re-verification cache runs on one clock only (`cache_clock`: GNSS when
    /// known), so that a message checked on the other clock can never look "verified lately".
    fn verify_signature(
        &mut self,
        index: usize,
        signed: &SignedData<'_>,
        digest: &[u8; 32],
        cache_clock: u64,
    ) -> Result<(), Rejection> {
        let psid = signed.header.psid;
        let payload = signed.payload.data.map(|d| payload_tag(d.encoded()));
        let signer_hash = self.cache[index].hash;
        if self.verified_lately(payload, &signer_hash, psid, cache_clock) {
            return Ok(());
        }
        let generator = self.generator.get_or_insert_with(GeneratorTable::new);
        self.cache[index]
            .key
            .verify(generator, digest, &signed.signature)
            .map_err(|_| Rejection::SignatureInvalid)?;
        if let Some(payload) = payload {
            self.remember(payload, signer_hash, psid, cache_clock);
        }
        Ok(())
    }

    /// Whether this signer's signature on `payload` (with `psid`) was verified less than
    /// `reverify_ms` before `now`.
    fn verified_lately(
        &self,
        payload: Option<[u8; 16]>,
        signer: &[u8; 32],
        psid: Psid,
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
    fn remember(&mut self, payload: [u8; 16], signer: [u8; 32], psid: Psid, now: u64) {
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
    fn signer(&mut self, signer: &SignerIdentifier<'_>, psid: Psid) -> Result<usize, Rejection> {
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
        let mut psids: Vec<Psid, { crate::capacity::MAX_CERT_PSIDS }> = Vec::new();
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
        psids: &[Psid],
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

/// The checks against the signer certificate: PSID (permitted, and the profile's), SSP,
/// region.
fn check_certified(
    signer: &TrustedCert,
    profile: &SecurityProfile,
    signed: &SignedData<'_>,
    ctx: &CheckContext,
) -> Result<(), Rejection> {
    let header = &signed.header;
    let Some(granted) = signer.permission(header.psid) else {
        return Err(Rejection::PsidNotPermitted);
    };
    if profile.psid != header.psid {
        return Err(Rejection::PsidMismatch);
    }
    let required = profile.ssp;
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

/// The tag of a signed message as sent: SHA-256 over its signing digest (which covers the
/// signed data and the signer certificate) and its signature, first 16 octets.
fn spdu_tag(digest: &[u8; 32], signed: &SignedData<'_>) -> [u8; 16] {
    let signature = &signed.signature;
    let mut input = [0u8; 32 + 1 + 32 + 32];
    input[..32].copy_from_slice(digest);
    input[32] = signature.r.form as u8;
    for (to, from) in input[33..65].iter_mut().zip(signature.r.x) {
        *to = *from;
    }
    for (to, from) in input[65..].iter_mut().zip(signature.s) {
        *to = *from;
    }
    let mut tag = [0u8; 16];
    tag.copy_from_slice(&sha256(&input)[..16]);
    tag
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
