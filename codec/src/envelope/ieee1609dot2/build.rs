//! Writing IEEE 1609.2 in COER: signed data around a J2735 frame, and explicit or implicit
//! certificates, signed with a [`SecretKey`](crate::envelope::ieee1609dot2::crypto::SecretKey) (NIST P-256, SHA-256). No heap: everything is
//! written into the caller's buffer.
//!
//! The encodings are the canonical ones the parser in [`super`] reads back, and are
//! byte-for-byte those of the independent vectors (pycrate COER, Python `cryptography`
//! deterministic ECDSA) for the same inputs, as `codec/tests/ieee1609dot2_build.rs` checks.
//!
//! No function in this module panics on any input.

use super::crypto::{hashed_id8, sha256, signing_digest_with, PublicKey, RSigForm, SecretKey};
use super::{
    BufferTooSmall, PointForm, Psid, ThreeDLocation, Time64, TwoDLocation, PROTOCOL_VERSION,
};

/// Why nothing (or only part of a buffer) was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BuildError {
    /// The output buffer is too small.
    BufferTooSmall(BufferTooSmall),
    /// The signature could not be made (negligible: a nonce giving r or s = 0).
    Signing,
    /// A value the encoding cannot carry (a name over 255 octets, no PSIDs, ...).
    InvalidInput,
}

impl From<BufferTooSmall> for BuildError {
    fn from(e: BufferTooSmall) -> Self {
        Self::BufferTooSmall(e)
    }
}

/// A cursor writing COER into a caller buffer.
struct Writer<'a> {
    out: &'a mut [u8],
    position: usize,
}

impl<'a> Writer<'a> {
    fn new(out: &'a mut [u8]) -> Self {
        Self { out, position: 0 }
    }

    fn bytes(&mut self, bytes: &[u8]) -> Result<(), BuildError> {
        let end = self.position.saturating_add(bytes.len());
        let available = self.out.len();
        let target = self
            .out
            .get_mut(self.position..end)
            .ok_or(BuildError::BufferTooSmall(BufferTooSmall {
                needed: end,
                available,
            }))?;
        target.copy_from_slice(bytes);
        self.position = end;
        Ok(())
    }

    fn u8(&mut self, value: u8) -> Result<(), BuildError> {
        self.bytes(&[value])
    }

    /// A length determinant (short form below 128, else `0x80 | n` and n octets).
    fn length(&mut self, length: usize) -> Result<(), BuildError> {
        match u8::try_from(length) {
            Ok(short) if short < 0x80 => self.u8(short),
            _ => {
                let digits = length.to_be_bytes();
                let skip = digits.iter().take_while(|&&d| d == 0).count();
                let digits = digits.get(skip..).unwrap_or_default();
                self.u8(0x80 | u8::try_from(digits.len()).unwrap_or(0))?;
                self.bytes(digits)
            }
        }
    }

    /// A non-negative INTEGER with a length prefix, minimal octets.
    fn unsigned(&mut self, value: u64) -> Result<(), BuildError> {
        let digits = value.to_be_bytes();
        let skip = digits.iter().take_while(|&&d| d == 0).count().min(7);
        let digits = digits.get(skip..).unwrap_or_default();
        self.length(digits.len())?;
        self.bytes(digits)
    }

    /// An `EccP256CurvePoint` in compressed form, or x-only.
    fn point(&mut self, form: PointForm, x: &[u8]) -> Result<(), BuildError> {
        let tag = match form {
            PointForm::XOnly => 0x80,
            PointForm::CompressedY0 => 0x82,
            PointForm::CompressedY1 => 0x83,
            _ => return Err(BuildError::InvalidInput),
        };
        self.u8(tag)?;
        self.bytes(x)
    }

    fn written(&self) -> &[u8] {
        self.out.get(..self.position).unwrap_or_default()
    }
}

/// A compressed key as an `EccP256CurvePoint` (form and x).
fn key_point(key: &PublicKey) -> (PointForm, [u8; 32]) {
    let sec1 = key.to_compressed();
    let form = if sec1[0] == 3 {
        PointForm::CompressedY1
    } else {
        PointForm::CompressedY0
    };
    let mut x = [0u8; 32];
    x.copy_from_slice(sec1.get(1..).unwrap_or_default());
    (form, x)
}

/// Signs `digest` with `key` and writes the `Signature` (ECDSA P-256).
fn signature(
    w: &mut Writer<'_>,
    key: &SecretKey,
    digest: &[u8; 32],
    form: RSigForm,
) -> Result<(), BuildError> {
    let raw = key.sign(digest, form).map_err(|_| BuildError::Signing)?;
    w.u8(0x80)?; // ecdsaNistP256Signature
    w.point(raw.form, &raw.r)?;
    w.bytes(&raw.s)
}

/// The header of signed data.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header {
    /// `psid` (the integer: [`Psid::TIM`] is 131).
    pub psid: Psid,
    /// `generationTime`.
    pub generation_time: Time64,
    /// `expiryTime`, if any.
    pub expiry_time: Option<Time64>,
    /// `generationLocation`, if any.
    pub generation_location: Option<ThreeDLocation>,
}

/// How the signed data names its signer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signer<'a> {
    /// `digest`: the `HashedId8` of this certificate (COER).
    Digest(&'a [u8]),
    /// `certificate`: this certificate (COER), alone.
    Certificate(&'a [u8]),
}

impl Signer<'_> {
    fn certificate(&self) -> &[u8] {
        match self {
            Signer::Digest(c) | Signer::Certificate(c) => c,
        }
    }
}

/// Writes `Ieee1609Dot2Data` with `SignedData` around `payload` (unsecured inner data), signed
/// by `key` whose certificate `signer` names; returns the length written.
///
/// # Errors
///
/// [`BuildError::BufferTooSmall`] when `out` is too short (its content is then unspecified).
pub fn encode_signed(
    payload: &[u8],
    header: &Header,
    signer: Signer<'_>,
    key: &SecretKey,
    form: RSigForm,
    out: &mut [u8],
) -> Result<usize, BuildError> {
    let mut w = Writer::new(out);
    w.bytes(&[PROTOCOL_VERSION, 0x81, 0x00])?; // signedData, hashId sha256
    let tbs_start = w.position;
    w.u8(0x40)?; // SignedDataPayload: data present
    w.bytes(&[PROTOCOL_VERSION, 0x80])?;
    w.length(payload.len())?;
    w.bytes(payload)?;
    let presence =
        0x40 | if header.expiry_time.is_some() {
            0x20
        } else {
            0
        } | if header.generation_location.is_some() {
            0x10
        } else {
            0
        };
    w.u8(presence)?;
    w.unsigned(u64::from(header.psid.value()))?;
    w.bytes(&header.generation_time.0.to_be_bytes())?;
    if let Some(expiry) = header.expiry_time {
        w.bytes(&expiry.0.to_be_bytes())?;
    }
    if let Some(l) = header.generation_location {
        w.bytes(&l.latitude.to_be_bytes())?;
        w.bytes(&l.longitude.to_be_bytes())?;
        w.bytes(&l.elevation.to_be_bytes())?;
    }
    let tbs = w.written().get(tbs_start..).unwrap_or_default();
    let digest = signing_digest_with(tbs, &sha256(signer.certificate()));
    match signer {
        Signer::Digest(cert) => {
            w.u8(0x80)?;
            w.bytes(&hashed_id8(cert))?;
        }
        Signer::Certificate(cert) => {
            w.bytes(&[0x81, 0x01, 0x01])?; // one certificate
            w.bytes(cert)?;
        }
    }
    signature(&mut w, key, &digest, form)?;
    Ok(w.position)
}

/// The content of a certificate to issue.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CertificateSpec<'a> {
    /// `id`: `name` (a host name, up to 255 octets).
    pub name: &'a str,
    /// `validityPeriod.start` (`Time32`).
    pub start: u32,
    /// `validityPeriod.duration`.
    pub duration: super::Duration,
    /// `region`: a circle, if any.
    pub circle: Option<(TwoDLocation, u16)>,
    /// `appPermissions`: PSIDs (none: left out).
    pub app_psids: &'a [Psid],
    /// The opaque service-specific permissions given with every app PSID (`None`: none).
    pub ssp: Option<&'a [u8]>,
    /// `certIssuePermissions`: `all`, with this `minChainLength`, or left out (`None`).
    pub issue_all: Option<i64>,
}

/// Who signs a certificate: itself (a root), or an issuer (its certificate and key).
#[derive(Clone, Copy, Debug)]
pub enum IssuedBy<'a> {
    /// Self-signed with the subject's own key.
    SelfSigned,
    /// Signed by the issuer whose certificate (COER) and key are given.
    Issuer(&'a [u8], &'a SecretKey),
}

/// Writes an explicit certificate for `subject` (its public key from its secret), signed as
/// `issuer` says; returns the length written.
///
/// # Errors
///
/// [`BuildError`] for a short buffer or a spec the encoding cannot carry.
pub fn encode_certificate(
    spec: &CertificateSpec<'_>,
    subject: &SecretKey,
    issuer: IssuedBy<'_>,
    out: &mut [u8],
) -> Result<usize, BuildError> {
    let mut w = Writer::new(out);
    w.bytes(&[0x80, PROTOCOL_VERSION, 0x00])?; // signature present; explicit
    match issuer {
        IssuedBy::SelfSigned => w.bytes(&[0x81, 0x00])?, // self: sha256
        IssuedBy::Issuer(cert, _) => {
            w.u8(0x80)?;
            w.bytes(&hashed_id8(cert))?;
        }
    }
    let tbs_start = w.position;
    to_be_signed_certificate(&mut w, spec, &subject.public_key())?;
    let tbs = w.written().get(tbs_start..).unwrap_or_default();
    let (key, issuer_hash) = match issuer {
        IssuedBy::SelfSigned => (subject, sha256(&[])),
        IssuedBy::Issuer(cert, key) => (key, sha256(cert)),
    };
    let digest = signing_digest_with(tbs, &issuer_hash);
    signature(&mut w, key, &digest, RSigForm::XOnly)?;
    Ok(w.position)
}

/// Writes `ToBeSignedCertificate` with a verification key.
fn to_be_signed_certificate(
    w: &mut Writer<'_>,
    spec: &CertificateSpec<'_>,
    key: &PublicKey,
) -> Result<(), BuildError> {
    let presence = if spec.circle.is_some() { 0x40 } else { 0 }
        | if spec.app_psids.is_empty() { 0 } else { 0x10 }
        | if spec.issue_all.is_some() { 0x08 } else { 0 };
    w.u8(presence)?;
    let name = spec.name.as_bytes();
    if name.len() > 255 {
        return Err(BuildError::InvalidInput);
    }
    w.u8(0x81)?; // id: name
    w.length(name.len())?;
    w.bytes(name)?;
    w.bytes(&[0, 0, 0, 0, 0])?; // cracaId, crlSeries
    w.bytes(&spec.start.to_be_bytes())?;
    let (tag, count) = duration_parts(spec.duration);
    w.u8(0x80 | tag)?;
    w.bytes(&count.to_be_bytes())?;
    if let Some((center, radius)) = spec.circle {
        w.u8(0x80)?; // circularRegion
        w.bytes(&center.latitude.to_be_bytes())?;
        w.bytes(&center.longitude.to_be_bytes())?;
        w.bytes(&radius.to_be_bytes())?;
    }
    if !spec.app_psids.is_empty() {
        w.unsigned(spec.app_psids.len() as u64)?;
        for &psid in spec.app_psids {
            w.u8(if spec.ssp.is_some() { 0x80 } else { 0x00 })?; // ssp present?
            w.unsigned(u64::from(psid.value()))?;
            if let Some(ssp) = spec.ssp {
                w.u8(0x80)?; // opaque
                w.length(ssp.len())?;
                w.bytes(ssp)?;
            }
        }
    }
    if let Some(min_chain) = spec.issue_all {
        w.unsigned(1)?;
        if min_chain == 1 {
            w.bytes(&[0x00, 0x81])?; // defaults; subjectPermissions all
        } else {
            let length = u8::try_from(min_chain).map_err(|_| BuildError::InvalidInput)?;
            w.bytes(&[0x80, 0x81, 0x01, length])?;
        }
    }
    let (form, x) = key_point(key);
    w.bytes(&[0x80, 0x80])?; // verificationKey, ecdsaNistP256
    w.point(form, &x)
}

/// The CHOICE index and count of a `Duration`.
fn duration_parts(duration: super::Duration) -> (u8, u16) {
    use super::Duration as D;
    match duration {
        D::Microseconds(n) => (0, n),
        D::Milliseconds(n) => (1, n),
        D::Seconds(n) => (2, n),
        D::Minutes(n) => (3, n),
        D::Hours(n) => (4, n),
        D::SixtyHours(n) => (5, n),
        D::Years(n) => (6, n),
    }
}
