//! IEEE 1609.2 `Ieee1609Dot2Data` in COER: a zero-copy view of unsecured and signed data, and
//! an encoder for unsecured data.
//!
//! [`Ieee1609Dot2Data::parse`] reads the whole structure (protocol version 3) and exposes the
//! application data (for V2X radios: the J2735 `MessageFrame`), the PSID and times of the
//! signed header, the signer and the signature as borrowed slices of the input. Signatures
//! are not verified. Certificates and encrypted data are walked structurally so that their
//! extent is known, and handed out as raw COER bytes.
//!
//! Strictness: every length is bounded by the bytes that remain, the encoding must be
//! canonical (minimal lengths and integers, zero padding bits), unknown CHOICE alternatives
//! in fields this view exposes are errors, and signed data may nest at most
//! [`MAX_NESTING_DEPTH`] levels deep. Extension additions (of `HeaderInfo`, certificates and
//! so on) are skipped by their length and kept as raw bytes.
//!
//! # Panics
//!
//! No function in this module panics on any input.

mod certificate;
mod coer;
mod error;
mod signature;
mod skip;

use certificate::skip_certificate;
use certificate::{parse_certificate, read_psid};
use coer::{optional, within_open_type, CoerReader, DecodeResult};
use signature::{parse_hash_algorithm, parse_signature};
use skip::{skip_encrypted_data, skip_encryption_key};

pub use error::{
    BufferTooSmall, DecodeError, DecodeErrorKind, MAX_NESTING_DEPTH, PROTOCOL_VERSION,
};

/// COER CHOICE tag of `Ieee1609Dot2Content.unsecuredData`.
const UNSECURED_DATA_TAG: u8 = 0x80;

/// A decoded `Ieee1609Dot2Data`: protocol version 3 and its content, borrowing the input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ieee1609Dot2Data<'a> {
    content: Content<'a>,
    encoded: &'a [u8],
    offset: usize,
    application_data: Option<Located<'a>>,
}

/// A slice of the input and the byte offset where it starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Located<'a> {
    bytes: &'a [u8],
    offset: usize,
}

/// `Ieee1609Dot2Content`: what an `Ieee1609Dot2Data` carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
#[allow(clippy::large_enum_variant)] // a borrowed view without heap; boxing would need `alloc`
pub enum Content<'a> {
    /// `unsecuredData`: application bytes without protection.
    Unsecured(&'a [u8]),
    /// `signedData`: a payload, a header and a signature.
    Signed(SignedData<'a>),
    /// `encryptedData`: the raw COER `EncryptedData` (recipients and ciphertext).
    Encrypted(&'a [u8]),
    /// `signedCertificateRequest`: the opaque request bytes.
    SignedCertificateRequest(&'a [u8]),
    /// `signedX509CertificateRequest` (IEEE 1609.2-2022): the opaque request bytes.
    SignedX509CertificateRequest(&'a [u8]),
}

/// `SignedData`: hash algorithm, to-be-signed data, signer and signature.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SignedData<'a> {
    /// `hashId`: the hash algorithm of the signature.
    pub hash_algorithm: HashAlgorithm,
    /// `tbsData.payload`: the signed payload.
    pub payload: SignedDataPayload<'a>,
    /// `tbsData.headerInfo`: PSID, times, location and the rest of the header.
    pub header: HeaderInfo<'a>,
    /// The raw COER bytes of `tbsData` (the input to the signature's hash).
    pub to_be_signed: &'a [u8],
    /// `signer`: who signed.
    pub signer: SignerIdentifier<'a>,
    /// `signature`: the signature value, unverified.
    pub signature: Signature<'a>,
}

/// `SignedDataPayload`: the data that was signed, or a hash of external data, or both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SignedDataPayload<'a> {
    /// `data`: an inner `Ieee1609Dot2Data` (already checked by the parse).
    pub data: Option<NestedData<'a>>,
    /// `extDataHash`: the hash of data carried elsewhere.
    pub external_data_hash: Option<HashedData<'a>>,
    /// Raw extension additions (presence bitmap and open types), e.g. 2022's `omitted`.
    pub extension_additions: Option<&'a [u8]>,
}

/// An `Ieee1609Dot2Data` nested in a signed payload, kept as its raw bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NestedData<'a> {
    encoded: &'a [u8],
    offset: usize,
}

impl<'a> NestedData<'a> {
    /// The raw COER bytes of the inner `Ieee1609Dot2Data`.
    #[must_use]
    pub fn encoded(&self) -> &'a [u8] {
        self.encoded
    }

    /// Byte offset of the inner data in the outermost input.
    #[must_use]
    pub fn offset(&self) -> usize {
        self.offset
    }

    /// Decodes the inner data (errors report offsets in the outermost input).
    ///
    /// # Errors
    ///
    /// None for a value produced by a successful parse, which checked the inner data.
    pub fn parse(&self) -> Result<Ieee1609Dot2Data<'a>, DecodeError> {
        let mut reader = CoerReader::new(self.encoded, self.offset);
        let data = parse_data(&mut reader, 0)?;
        reader.expect_end()?;
        Ok(data)
    }
}

/// `HashedData`: a digest of data that is not carried in the structure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HashedData<'a> {
    /// The algorithm that produced the digest.
    pub algorithm: HashAlgorithm,
    /// The digest (32 or 48 bytes).
    pub digest: &'a [u8],
}

/// `Time64`: microseconds since 2004-01-01 00:00:00 UTC, counted in TAI (no leap seconds).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Time64(pub u64);

/// `ThreeDLocation`: where the data was generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ThreeDLocation {
    /// Latitude in 1e-7 degrees; 900000001 means unavailable.
    pub latitude: i32,
    /// Longitude in 1e-7 degrees; 1800000001 means unavailable.
    pub longitude: i32,
    /// Elevation in decimetres above -409.5 m (raw `Uint16`).
    pub elevation: u16,
}

/// `MissingCrlIdentifier`: a CRL the sender knows about but has not received.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MissingCrlIdentifier {
    /// `cracaId`: `HashedId3` of the CRL-issuing authority.
    pub craca_id: [u8; 3],
    /// `crlSeries`.
    pub crl_series: u16,
}

/// `HeaderInfo`: the signed header. Root components are decoded; extension additions
/// (`inlineP2pcdRequest`, `requestedCertificate`, ...) are kept raw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HeaderInfo<'a> {
    /// `psid`: the application the payload belongs to, as the integer IEEE 1609.2 defines
    /// (TIM 131, MAP 2113687, BSM 32; not the p-encoded `0x8003`: see [`Psid`]).
    pub psid: Psid,
    /// `generationTime`.
    pub generation_time: Option<Time64>,
    /// `expiryTime`.
    pub expiry_time: Option<Time64>,
    /// `generationLocation`.
    pub generation_location: Option<ThreeDLocation>,
    /// `p2pcdLearningRequest`: `HashedId3` of a certificate the sender wants to learn.
    pub p2pcd_learning_request: Option<[u8; 3]>,
    /// `missingCrlIdentifier`.
    pub missing_crl_identifier: Option<MissingCrlIdentifier>,
    /// `encryptionKey`, as raw COER `EncryptionKey` bytes.
    pub encryption_key: Option<&'a [u8]>,
    /// Raw extension additions (presence bitmap and open types).
    pub extension_additions: Option<&'a [u8]>,
}

/// `SignerIdentifier`: how to find the verification key.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SignerIdentifier<'a> {
    /// `digest`: `HashedId8` of the signing certificate.
    Digest([u8; 8]),
    /// `certificate`: the signing certificate first, then its issuers.
    Certificate(CertificateChain<'a>),
    /// `self`: self-signed.
    SelfSigned,
}

/// A `SequenceOfCertificate`, kept as raw COER bytes (already checked by the parse).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CertificateChain<'a> {
    count: usize,
    encoded: &'a [u8],
    offset: usize,
}

impl<'a> CertificateChain<'a> {
    /// Number of certificates.
    #[must_use]
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether the chain holds no certificate.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The certificates' COER bytes, one after the other (without the quantity prefix).
    #[must_use]
    pub fn encoded(&self) -> &'a [u8] {
        self.encoded
    }

    /// The signing certificate.
    #[must_use]
    pub fn first(&self) -> Option<Certificate<'a>> {
        self.iter().next()
    }

    /// Each certificate, signing certificate first.
    #[must_use]
    pub fn iter(&self) -> Certificates<'a> {
        Certificates {
            reader: CoerReader::new(self.encoded, self.offset),
            left: self.count,
        }
    }
}

impl<'a> IntoIterator for &CertificateChain<'a> {
    type Item = Certificate<'a>;
    type IntoIter = Certificates<'a>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

/// Iterator over the certificates of a [`CertificateChain`] (checked by the parse).
#[derive(Clone, Debug)]
pub struct Certificates<'a> {
    reader: CoerReader<'a>,
    left: usize,
}

impl<'a> Iterator for Certificates<'a> {
    type Item = Certificate<'a>;

    fn next(&mut self) -> Option<Self::Item> {
        self.left = self.left.checked_sub(1)?;
        parse_certificate(&mut self.reader).ok()
    }
}

pub use super::psid::Psid;
pub use certificate::{
    Certificate, CertificateKind, Duration, GeographicRegion, Issuer, Locations, PsidGroup,
    PsidGroups, PsidRanges, PsidSsp, PsidSsps, Ssp, SubjectPermissions, Time32, TwoDLocation,
    ValidityPeriod, VerifyKeyIndicator,
};
pub use signature::{CurvePoint, HashAlgorithm, PointForm, Signature, SignatureScheme};
/// Writing signed data and certificates (feature `crypto`).
#[cfg(feature = "crypto")]
pub mod build;
/// NIST P-256 / SHA-256: signature hashes, verify, sign, ECQV (feature `crypto`).
#[cfg(feature = "crypto")]
pub mod crypto;
#[cfg(feature = "crypto")]
mod lincomb;

impl<'a> Ieee1609Dot2Data<'a> {
    /// Decodes `bytes`, which must hold exactly one `Ieee1609Dot2Data`.
    ///
    /// # Errors
    ///
    /// A [`DecodeError`] naming what is wrong and where, when `bytes` is not one complete,
    /// canonical `Ieee1609Dot2Data` (including [`DecodeErrorKind::TrailingBytes`]).
    pub fn parse(bytes: &'a [u8]) -> Result<Self, DecodeError> {
        let (data, used) = Self::parse_prefix(bytes)?;
        if used == bytes.len() {
            Ok(data)
        } else {
            Err(DecodeError::new(DecodeErrorKind::TrailingBytes, used))
        }
    }

    /// Decodes the `Ieee1609Dot2Data` at the start of `bytes`; returns it and its length.
    ///
    /// # Errors
    ///
    /// A [`DecodeError`] when `bytes` does not start with a complete, canonical
    /// `Ieee1609Dot2Data`. Bytes after it are not looked at.
    pub fn parse_prefix(bytes: &'a [u8]) -> Result<(Self, usize), DecodeError> {
        let mut reader = CoerReader::new(bytes, 0);
        let data = parse_data(&mut reader, 0)?;
        Ok((data, reader.position()))
    }

    /// The content.
    #[must_use]
    pub fn content(&self) -> &Content<'a> {
        &self.content
    }

    /// The raw COER bytes of this structure.
    #[must_use]
    pub fn encoded(&self) -> &'a [u8] {
        self.encoded
    }

    /// The signed data, when the content is signed.
    #[must_use]
    pub fn signed_data(&self) -> Option<&SignedData<'a>> {
        match &self.content {
            Content::Signed(signed) => Some(signed),
            _ => None,
        }
    }

    /// The application bytes: the unsecured data, found through any signed layers.
    ///
    /// `None` for encrypted data, certificate requests and signatures over external data.
    #[must_use]
    pub fn application_data(&self) -> Option<&'a [u8]> {
        self.application_data.map(|located| located.bytes)
    }

    /// Byte offset, in the input given to the parse, of [`Self::application_data`].
    #[must_use]
    pub fn application_data_offset(&self) -> Option<usize> {
        self.application_data.map(|located| located.offset)
    }

    /// Whether the content is signed (only signed data can hold a further layer).
    #[must_use]
    pub fn is_signed(&self) -> bool {
        matches!(self.content, Content::Signed(_))
    }
}

/// Whether `bytes` begins like an `Ieee1609Dot2Data`: version 3, then a content tag.
///
/// A J2735 `MessageFrame` in UPER starts with `0x00` for every standard message (an extension
/// bit of 0 and a message id below 256), so it never matches.
#[must_use]
pub fn looks_like_ieee1609dot2(bytes: &[u8]) -> bool {
    matches!(bytes, [PROTOCOL_VERSION, tag, ..] if (0x80..=0x84).contains(tag))
}

/// Length of the COER encoding of unsecured data around `payload_len` bytes.
///
/// Saturates at `usize::MAX` (no real payload comes near it).
#[must_use]
pub fn unsecured_encoded_len(payload_len: usize) -> usize {
    length_determinant_len(payload_len)
        .saturating_add(2)
        .saturating_add(payload_len)
}

/// Writes `payload` as unsecured `Ieee1609Dot2Data` (`03 80 <COER length> <payload>`) to the
/// start of `out`; returns the number of bytes written.
///
/// # Errors
///
/// [`BufferTooSmall`] when `out` is shorter than [`unsecured_encoded_len`] of the payload
/// (then nothing is written).
pub fn encode_unsecured(payload: &[u8], out: &mut [u8]) -> Result<usize, BufferTooSmall> {
    let needed = unsecured_encoded_len(payload.len());
    let too_small = BufferTooSmall {
        needed,
        available: out.len(),
    };
    let target = out.get_mut(..needed).ok_or(too_small)?;
    let (header, body) = target.split_at_mut(needed.saturating_sub(payload.len()));
    let (fixed, length) = header.split_at_mut(2);
    fixed.copy_from_slice(&[PROTOCOL_VERSION, UNSECURED_DATA_TAG]);
    write_length_determinant(payload.len(), length);
    body.copy_from_slice(payload);
    Ok(needed)
}

/// Number of bytes of the COER length determinant for `length`.
fn length_determinant_len(length: usize) -> usize {
    if length < 0x80 {
        1
    } else {
        significant_bytes(length).saturating_add(1)
    }
}

/// Number of bytes needed for `value` in big-endian without leading zero bytes (at least 1).
fn significant_bytes(value: usize) -> usize {
    let bits = usize::BITS.saturating_sub(value.leading_zeros());
    bits.div_ceil(8).max(1) as usize
}

/// Writes the length determinant of `length` into `out`, sized by [`length_determinant_len`].
fn write_length_determinant(length: usize, out: &mut [u8]) {
    if let [only] = out {
        *only = u8::try_from(length).unwrap_or(0);
        return;
    }
    if let Some((count, digits)) = out.split_first_mut() {
        *count = 0x80 | u8::try_from(digits.len()).unwrap_or(0);
        let be = length.to_be_bytes();
        let skip = be.len().saturating_sub(digits.len());
        digits.copy_from_slice(be.get(skip..).unwrap_or_default());
    }
}

/// Decodes an `Ieee1609Dot2Data` at `depth` levels below the outermost one.
fn parse_data<'a>(reader: &mut CoerReader<'a>, depth: usize) -> DecodeResult<Ieee1609Dot2Data<'a>> {
    if depth >= MAX_NESTING_DEPTH {
        return Err(reader.error(DecodeErrorKind::NestingTooDeep));
    }
    let start = reader.position();
    let offset = reader.offset();
    let version_reader = *reader;
    if reader.read_u8()? != PROTOCOL_VERSION {
        return Err(version_reader.error(DecodeErrorKind::UnsupportedVersion));
    }
    let (content, application_data) = parse_content(reader, depth)?;
    Ok(Ieee1609Dot2Data {
        content,
        encoded: reader.consumed_since(start),
        offset,
        application_data,
    })
}

/// Decodes `Ieee1609Dot2Content`, with the location of the application data if it has one.
fn parse_content<'a>(
    reader: &mut CoerReader<'a>,
    depth: usize,
) -> DecodeResult<(Content<'a>, Option<Located<'a>>)> {
    let tag_reader = *reader;
    match reader.read_choice_tag()? {
        0 => {
            let length = reader.read_length()?;
            let offset = reader.offset();
            let bytes = reader.read_slice(length)?;
            Ok((Content::Unsecured(bytes), Some(Located { bytes, offset })))
        }
        1 => {
            let (signed, inner) = parse_signed_data(reader, depth)?;
            Ok((Content::Signed(signed), inner))
        }
        2 => {
            let start = reader.position();
            skip_encrypted_data(reader)?;
            Ok((Content::Encrypted(reader.consumed_since(start)), None))
        }
        3 => Ok((
            Content::SignedCertificateRequest(reader.read_octet_string()?),
            None,
        )),
        4 => {
            let request = within_open_type(reader, CoerReader::read_octet_string)?;
            Ok((Content::SignedX509CertificateRequest(request), None))
        }
        _ => Err(tag_reader.error(DecodeErrorKind::UnknownAlternative)),
    }
}

/// Decodes `SignedData`, with the location of the application data inside it.
fn parse_signed_data<'a>(
    reader: &mut CoerReader<'a>,
    depth: usize,
) -> DecodeResult<(SignedData<'a>, Option<Located<'a>>)> {
    let hash_algorithm = parse_hash_algorithm(reader)?;
    let tbs_start = reader.position();
    let (payload, application_data) = parse_signed_data_payload(reader, depth)?;
    let header = parse_header_info(reader)?;
    let to_be_signed = reader.consumed_since(tbs_start);
    let signer = parse_signer(reader)?;
    let signature = parse_signature(reader)?;
    let signed_data = SignedData {
        hash_algorithm,
        payload,
        header,
        to_be_signed,
        signer,
        signature,
    };
    Ok((signed_data, application_data))
}

/// Decodes `SignedDataPayload`, parsing (and checking) the nested data if present.
fn parse_signed_data_payload<'a>(
    reader: &mut CoerReader<'a>,
    depth: usize,
) -> DecodeResult<(SignedDataPayload<'a>, Option<Located<'a>>)> {
    let preamble_reader = *reader;
    let preamble = reader.read_preamble(true, 2)?;
    let mut application_data = None;
    let mut data = None;
    if preamble.has_optional(0) {
        let inner = parse_data(reader, depth.saturating_add(1))?;
        application_data = inner.application_data;
        data = Some(NestedData {
            encoded: inner.encoded,
            offset: inner.offset,
        });
    }
    let external_data_hash = optional(preamble.has_optional(1), || parse_hashed_data(reader))?;
    let extension_additions = optional(preamble.has_extensions(), || {
        reader.skip_extension_additions()
    })?;
    if data.is_none() && external_data_hash.is_none() && extension_additions.is_none() {
        return Err(preamble_reader.error(DecodeErrorKind::EmptySignedPayload));
    }
    let payload = SignedDataPayload {
        data,
        external_data_hash,
        extension_additions,
    };
    Ok((payload, application_data))
}

/// Decodes `HashedData`.
fn parse_hashed_data<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<HashedData<'a>> {
    let tag_reader = *reader;
    let (algorithm, digest) = match reader.read_choice_tag()? {
        0 => (HashAlgorithm::Sha256, reader.read_slice(32)?),
        1 => (
            HashAlgorithm::Sha384,
            within_open_type(reader, |inner| inner.read_slice(48))?,
        ),
        2 => (
            HashAlgorithm::Sm3,
            within_open_type(reader, |inner| inner.read_slice(32))?,
        ),
        _ => return Err(tag_reader.error(DecodeErrorKind::UnknownAlternative)),
    };
    Ok(HashedData { algorithm, digest })
}

/// Decodes `HeaderInfo`: the root components, and the extension additions kept raw.
fn parse_header_info<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<HeaderInfo<'a>> {
    let preamble = reader.read_preamble(true, 6)?;
    let psid = read_psid(reader)?;
    let generation_time = optional(preamble.has_optional(0), || reader.read_u64().map(Time64))?;
    let expiry_time = optional(preamble.has_optional(1), || reader.read_u64().map(Time64))?;
    let generation_location =
        optional(preamble.has_optional(2), || parse_three_d_location(reader))?;
    let p2pcd_learning_request = optional(preamble.has_optional(3), || reader.read_array())?;
    let missing_crl_identifier = optional(preamble.has_optional(4), || {
        parse_missing_crl_identifier(reader)
    })?;
    let encryption_key = optional(preamble.has_optional(5), || {
        let start = reader.position();
        skip_encryption_key(reader)?;
        Ok(reader.consumed_since(start))
    })?;
    let extension_additions = optional(preamble.has_extensions(), || {
        reader.skip_extension_additions()
    })?;
    Ok(HeaderInfo {
        psid,
        generation_time,
        expiry_time,
        generation_location,
        p2pcd_learning_request,
        missing_crl_identifier,
        encryption_key,
        extension_additions,
    })
}

/// Decodes `ThreeDLocation` (4 + 4 + 2 bytes).
fn parse_three_d_location(reader: &mut CoerReader<'_>) -> DecodeResult<ThreeDLocation> {
    Ok(ThreeDLocation {
        latitude: reader.read_i32()?,
        longitude: reader.read_i32()?,
        elevation: reader.read_u16()?,
    })
}

/// Decodes `MissingCrlIdentifier` (extensible SEQUENCE; additions are skipped).
fn parse_missing_crl_identifier(reader: &mut CoerReader<'_>) -> DecodeResult<MissingCrlIdentifier> {
    let preamble = reader.read_preamble(true, 0)?;
    let craca_id = reader.read_array()?;
    let crl_series = reader.read_u16()?;
    if preamble.has_extensions() {
        reader.skip_extension_additions()?;
    }
    Ok(MissingCrlIdentifier {
        craca_id,
        crl_series,
    })
}

/// Decodes `SignerIdentifier`.
fn parse_signer<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<SignerIdentifier<'a>> {
    let tag_reader = *reader;
    match reader.read_choice_tag()? {
        0 => Ok(SignerIdentifier::Digest(reader.read_array()?)),
        1 => parse_certificate_chain(reader).map(SignerIdentifier::Certificate),
        2 => Ok(SignerIdentifier::SelfSigned),
        _ => Err(tag_reader.error(DecodeErrorKind::UnknownAlternative)),
    }
}

/// Decodes a `SequenceOfCertificate`, walking each certificate to find its end.
fn parse_certificate_chain<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<CertificateChain<'a>> {
    let count = reader.read_quantity()?;
    let start = reader.position();
    let offset = reader.offset();
    for _ in 0..count {
        skip_certificate(reader)?;
    }
    Ok(CertificateChain {
        count,
        encoded: reader.consumed_since(start),
        offset,
    })
}

#[cfg(test)]
mod tests;
