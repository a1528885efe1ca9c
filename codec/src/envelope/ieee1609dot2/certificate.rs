//! IEEE 1609.2 `Certificate` in COER: a zero-copy view of what a verifier needs (issuer,
//! validity, region, permissions, verification key or ECQV reconstruction value, signature).
//!
//! [`Certificate::parse`] checks the whole structure as strictly as the signed-data view
//! (canonical COER, every length bounded by the bytes that remain). Lists (permissions,
//! rectangles, polygon vertices) stay borrowed and are read by iterators; the parse has
//! already walked them, so the iterators cannot fail. Nothing is verified here: the
//! signature, the chain and the permissions are the caller's to check
//! ([`super::crypto`] and the OBU's trust policy).
//!
//! No function in this module panics on any input.

use super::coer::{optional, CoerReader, DecodeResult};
use super::error::{DecodeError, DecodeErrorKind, PROTOCOL_VERSION};
use super::signature::{
    parse_curve_point, parse_hash_algorithm, parse_signature, CurvePoint, HashAlgorithm, Signature,
};
use super::skip::{
    read_extensible_tag, read_root_tag, skip_public_encryption_key, skip_sequence_of,
};
use crate::envelope::psid::Psid;

/// A decoded `Certificate` (`CertificateBase`), borrowing its COER bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Certificate<'a> {
    /// The whole certificate's COER bytes (what `HashedId8` and signer hashes are taken of).
    pub encoded: &'a [u8],
    /// `type`: explicit (a public key and the issuer's signature) or implicit (ECQV).
    pub kind: CertificateKind,
    /// `issuer`: who signed (or, for implicit certificates, reconstructs) it.
    pub issuer: Issuer,
    /// The COER of `toBeSigned` (the data input of the certificate's signature hash).
    pub to_be_signed: &'a [u8],
    /// `validityPeriod`.
    pub validity: ValidityPeriod,
    /// `region`, when the certificate limits where it may be used.
    pub region: Option<GeographicRegion<'a>>,
    /// `appPermissions`: what the certificate may sign.
    pub app_permissions: Option<PsidSsps<'a>>,
    /// `certIssuePermissions`: what certificates it may issue.
    pub cert_issue_permissions: Option<PsidGroups<'a>>,
    /// `verifyKeyIndicator`.
    pub verify_key: VerifyKeyIndicator<'a>,
    /// `signature` (explicit certificates only).
    pub signature: Option<Signature<'a>>,
}

/// `CertificateType`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CertificateKind {
    /// `explicit`: carries the public key and the issuer's signature.
    Explicit,
    /// `implicit`: carries an ECQV reconstruction value and no signature.
    Implicit,
}

/// `IssuerIdentifier`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Issuer {
    /// `sha256AndDigest`: `HashedId8` of the issuer's certificate.
    Sha256Digest([u8; 8]),
    /// `self`: a self-signed (root) certificate, hashed with this algorithm.
    SelfSigned(HashAlgorithm),
    /// An extension alternative (`sha384AndDigest` and later).
    Other,
}

/// `Time32`: TAI seconds since 2004-01-01 00:00:00 UTC.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Time32(pub u32);

/// `ValidityPeriod`: a start and a duration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ValidityPeriod {
    /// `start`.
    pub start: Time32,
    /// `duration`.
    pub duration: Duration,
}

impl ValidityPeriod {
    /// First valid instant, in `Time64` microseconds.
    #[must_use]
    pub const fn start_us(&self) -> u64 {
        (self.start.0 as u64).saturating_mul(1_000_000)
    }

    /// The first instant after the period, in `Time64` microseconds.
    #[must_use]
    pub const fn end_us(&self) -> u64 {
        self.start_us().saturating_add(self.duration.micros())
    }

    /// Whether `time_us` (`Time64`) lies in `[start, end)`.
    #[must_use]
    pub const fn contains(&self, time_us: u64) -> bool {
        time_us >= self.start_us() && time_us < self.end_us()
    }
}

/// `Duration`: a `Uint16` count of one unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Duration {
    /// `microseconds`.
    Microseconds(u16),
    /// `milliseconds`.
    Milliseconds(u16),
    /// `seconds`.
    Seconds(u16),
    /// `minutes`.
    Minutes(u16),
    /// `hours`.
    Hours(u16),
    /// `sixtyHours`.
    SixtyHours(u16),
    /// `years` (1609.2: 31 556 952 seconds each, the mean Gregorian year).
    Years(u16),
}

impl Duration {
    /// The length in microseconds.
    #[must_use]
    pub const fn micros(self) -> u64 {
        let (count, unit_us) = match self {
            Self::Microseconds(n) => (n, 1),
            Self::Milliseconds(n) => (n, 1_000),
            Self::Seconds(n) => (n, 1_000_000),
            Self::Minutes(n) => (n, 60_000_000),
            Self::Hours(n) => (n, 3_600_000_000),
            Self::SixtyHours(n) => (n, 216_000_000_000),
            Self::Years(n) => (n, 31_556_952_000_000),
        };
        (count as u64).saturating_mul(unit_us)
    }
}

/// `TwoDLocation`: latitude and longitude in 1e-7 degrees.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct TwoDLocation {
    /// Latitude, 1e-7 degrees.
    pub latitude: i32,
    /// Longitude, 1e-7 degrees.
    pub longitude: i32,
}

/// `GeographicRegion`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GeographicRegion<'a> {
    /// `circularRegion`: a centre and a radius in metres.
    Circular {
        /// The centre.
        center: TwoDLocation,
        /// The radius, metres.
        radius_m: u16,
    },
    /// `rectangularRegion`: the union of rectangles, each `(north-west, south-east)`.
    Rectangular(Locations<'a>),
    /// `polygonalRegion`: the vertices of one polygon (at least three).
    Polygonal(Locations<'a>),
    /// `identifiedRegion`: countries and their subdivisions (raw COER of the list).
    Identified(&'a [u8]),
    /// An extension alternative.
    Other,
}

/// A borrowed run of `TwoDLocation`s (8 octets each).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Locations<'a> {
    encoded: &'a [u8],
}

impl<'a> Locations<'a> {
    /// Number of locations.
    #[must_use]
    pub fn len(&self) -> usize {
        self.encoded.len() / 8
    }

    /// Whether there is none.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.encoded.is_empty()
    }

    /// The locations in order.
    pub fn iter(&self) -> impl Iterator<Item = TwoDLocation> + 'a {
        self.encoded.chunks_exact(8).map(|chunk| {
            let mut reader = CoerReader::new(chunk, 0);
            TwoDLocation {
                latitude: reader.read_i32().unwrap_or_default(),
                longitude: reader.read_i32().unwrap_or_default(),
            }
        })
    }
}

/// `ServiceSpecificPermissions`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ssp<'a> {
    /// `opaque`.
    Opaque(&'a [u8]),
    /// An extension alternative (`bitmapSsp` and later): its open-type content.
    Other,
}

/// `PsidSsp`: one application permission.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PsidSsp<'a> {
    /// The PSID (the integer).
    pub psid: Psid,
    /// Its service-specific permissions, if any.
    pub ssp: Option<Ssp<'a>>,
}

/// A borrowed `SequenceOfPsidSsp` (already checked by the parse).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PsidSsps<'a> {
    count: usize,
    encoded: &'a [u8],
}

impl<'a> PsidSsps<'a> {
    /// Number of entries.
    #[must_use]
    pub fn len(&self) -> usize {
        self.count
    }

    /// Whether the list is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The entries in order.
    pub fn iter(&self) -> impl Iterator<Item = PsidSsp<'a>> + 'a {
        let mut reader = CoerReader::new(self.encoded, 0);
        (0..self.count).map_while(move |_| parse_psid_ssp(&mut reader).ok())
    }

    /// The entry for `psid`, if the list has one.
    #[must_use]
    pub fn find(&self, psid: Psid) -> Option<PsidSsp<'a>> {
        self.iter().find(|entry| entry.psid == psid)
    }
}

/// `SubjectPermissions` of a `PsidGroupPermissions`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SubjectPermissions<'a> {
    /// `explicit`: these PSIDs (the SSP ranges are kept raw).
    Explicit(PsidRanges<'a>),
    /// `all`: any PSID.
    All,
    /// An extension alternative.
    Other,
}

/// A borrowed `SequenceOfPsidSspRange`; yields the PSIDs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PsidRanges<'a> {
    count: usize,
    encoded: &'a [u8],
}

impl<'a> PsidRanges<'a> {
    /// The PSIDs, in order.
    pub fn psids(&self) -> impl Iterator<Item = Psid> + 'a {
        let mut reader = CoerReader::new(self.encoded, 0);
        (0..self.count).map_while(move |_| parse_psid_ssp_range(&mut reader).ok())
    }
}

/// `PsidGroupPermissions`: what an issuer may certify.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PsidGroup<'a> {
    /// `subjectPermissions`.
    pub subject: SubjectPermissions<'a>,
    /// `minChainLength` (DEFAULT 1).
    pub min_chain_length: i64,
    /// `chainLengthRange` (DEFAULT 0).
    pub chain_length_range: i64,
    /// `eeType` bits (DEFAULT `app`, 0x80).
    pub ee_type: u8,
}

/// A borrowed `SequenceOfPsidGroupPermissions` (already checked by the parse).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PsidGroups<'a> {
    count: usize,
    encoded: &'a [u8],
}

impl<'a> PsidGroups<'a> {
    /// The groups in order.
    pub fn iter(&self) -> impl Iterator<Item = PsidGroup<'a>> + 'a {
        let mut reader = CoerReader::new(self.encoded, 0);
        (0..self.count).map_while(move |_| parse_psid_group(&mut reader).ok())
    }
}

/// `VerificationKeyIndicator`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VerifyKeyIndicator<'a> {
    /// `verificationKey` / `ecdsaNistP256`.
    NistP256(CurvePoint<'a>),
    /// `verificationKey` of another curve (Brainpool, P-384, SM2).
    OtherKey,
    /// `reconstructionValue`: the ECQV public reconstruction point.
    Reconstruction(CurvePoint<'a>),
    /// An extension alternative.
    Other,
}

impl<'a> Certificate<'a> {
    /// Decodes `bytes`, which must hold exactly one certificate.
    ///
    /// # Errors
    ///
    /// A [`DecodeError`] when `bytes` is not one complete, canonical certificate.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, DecodeError> {
        let mut reader = CoerReader::new(bytes, 0);
        let certificate = parse_certificate(&mut reader)?;
        reader.expect_end()?;
        Ok(certificate)
    }

    /// The application permission for `psid`, if the certificate grants it.
    #[must_use]
    pub fn permission(&self, psid: Psid) -> Option<PsidSsp<'a>> {
        self.app_permissions.and_then(|list| list.find(psid))
    }

    /// Whether this certificate may issue certificates carrying `psid`.
    #[must_use]
    pub fn may_issue(&self, psid: Psid) -> bool {
        self.cert_issue_permissions.is_some_and(|groups| {
            groups.iter().any(|group| match group.subject {
                SubjectPermissions::All => true,
                SubjectPermissions::Explicit(ranges) => ranges.psids().any(|p| p == psid),
                SubjectPermissions::Other => false,
            })
        })
    }
}

/// Skips a `Certificate`, checking it as [`parse_certificate`] does.
pub(crate) fn skip_certificate(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    parse_certificate(reader).map(|_| ())
}

/// Decodes a `Certificate` at the reader (used by the chain walk of signed data too).
pub(crate) fn parse_certificate<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<Certificate<'a>> {
    let start = reader.position();
    let preamble = reader.read_preamble(false, 1)?;
    let version_reader = *reader;
    if reader.read_u8()? != PROTOCOL_VERSION {
        return Err(version_reader.error(DecodeErrorKind::UnsupportedVersion));
    }
    let kind_reader = *reader;
    let kind = match reader.read_enumerated()? {
        0 => CertificateKind::Explicit,
        1 => CertificateKind::Implicit,
        _ => return Err(kind_reader.error(DecodeErrorKind::UnknownAlternative)),
    };
    let issuer = parse_issuer(reader)?;
    let tbs_start = reader.position();
    let tbs = parse_to_be_signed(reader)?;
    let to_be_signed = reader.consumed_since(tbs_start);
    let signature = optional(preamble.has_optional(0), || parse_signature(reader))?;
    Ok(Certificate {
        encoded: reader.consumed_since(start),
        kind,
        issuer,
        to_be_signed,
        validity: tbs.validity,
        region: tbs.region,
        app_permissions: tbs.app_permissions,
        cert_issue_permissions: tbs.cert_issue_permissions,
        verify_key: tbs.verify_key,
        signature,
    })
}

/// The parts of `ToBeSignedCertificate` the view keeps.
struct ToBeSigned<'a> {
    validity: ValidityPeriod,
    region: Option<GeographicRegion<'a>>,
    app_permissions: Option<PsidSsps<'a>>,
    cert_issue_permissions: Option<PsidGroups<'a>>,
    verify_key: VerifyKeyIndicator<'a>,
}

/// Decodes `IssuerIdentifier`.
fn parse_issuer(reader: &mut CoerReader<'_>) -> DecodeResult<Issuer> {
    Ok(match read_extensible_tag(reader, 2)? {
        Some(0) => Issuer::Sha256Digest(reader.read_array()?),
        Some(_) => Issuer::SelfSigned(parse_hash_algorithm(reader)?),
        None => Issuer::Other,
    })
}

/// Decodes `ToBeSignedCertificate`.
fn parse_to_be_signed<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<ToBeSigned<'a>> {
    let preamble = reader.read_preamble(true, 7)?;
    skip_certificate_id(reader)?;
    reader.skip(3 + 2)?; // cracaId, crlSeries
    let validity = parse_validity_period(reader)?;
    let region = optional(preamble.has_optional(0), || parse_region(reader))?;
    if preamble.has_optional(1) {
        reader.skip(1)?; // assuranceLevel
    }
    let app_permissions = optional(preamble.has_optional(2), || {
        let (count, encoded) = read_list(reader, parse_psid_ssp)?;
        Ok(PsidSsps { count, encoded })
    })?;
    let cert_issue_permissions = optional(preamble.has_optional(3), || {
        let (count, encoded) = read_list(reader, parse_psid_group)?;
        Ok(PsidGroups { count, encoded })
    })?;
    if preamble.has_optional(4) {
        read_list(reader, parse_psid_group)?; // certRequestPermissions
    }
    // canRequestRollover (index 5) is a NULL: no octets.
    if preamble.has_optional(6) {
        skip_public_encryption_key(reader)?;
    }
    let verify_key = parse_verify_key(reader)?;
    if preamble.has_extensions() {
        reader.skip_extension_additions()?;
    }
    Ok(ToBeSigned {
        validity,
        region,
        app_permissions,
        cert_issue_permissions,
        verify_key,
    })
}

/// Reads a SEQUENCE OF, checking each element with `parse`; returns the count and the raw
/// element bytes.
fn read_list<'a, T>(
    reader: &mut CoerReader<'a>,
    parse: fn(&mut CoerReader<'a>) -> DecodeResult<T>,
) -> DecodeResult<(usize, &'a [u8])> {
    let count = reader.read_quantity()?;
    let start = reader.position();
    for _ in 0..count {
        parse(reader)?;
    }
    Ok((count, reader.consumed_since(start)))
}

/// Skips `CertificateId`.
fn skip_certificate_id(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 4)? {
        Some(0) => {
            // linkageData: iCert, linkage-value, optional group-linkage-value
            let preamble = reader.read_preamble(false, 1)?;
            reader.skip(2 + 9)?;
            if preamble.has_optional(0) {
                reader.skip(4 + 9)?;
            }
            Ok(())
        }
        Some(1 | 2) => reader.read_octet_string().map(|_| ()), // name, binaryId
        Some(_) | None => Ok(()),                              // none: NULL
    }
}

/// Decodes `ValidityPeriod`.
fn parse_validity_period(reader: &mut CoerReader<'_>) -> DecodeResult<ValidityPeriod> {
    let start = Time32(u32::from_be_bytes(reader.read_array()?));
    let tag = read_root_tag(reader, 7)?;
    let count = reader.read_u16()?;
    let duration = match tag {
        0 => Duration::Microseconds(count),
        1 => Duration::Milliseconds(count),
        2 => Duration::Seconds(count),
        3 => Duration::Minutes(count),
        4 => Duration::Hours(count),
        5 => Duration::SixtyHours(count),
        _ => Duration::Years(count),
    };
    Ok(ValidityPeriod { start, duration })
}

/// Decodes `GeographicRegion`.
fn parse_region<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<GeographicRegion<'a>> {
    Ok(match read_extensible_tag(reader, 4)? {
        Some(0) => GeographicRegion::Circular {
            center: parse_two_d_location(reader)?,
            radius_m: reader.read_u16()?,
        },
        Some(1) => GeographicRegion::Rectangular(read_locations(reader, 2, 1)?),
        Some(2) => GeographicRegion::Polygonal(read_locations(reader, 1, 3)?),
        Some(_) => {
            let start = reader.position();
            skip_sequence_of(reader, skip_identified_region)?;
            GeographicRegion::Identified(reader.consumed_since(start))
        }
        None => GeographicRegion::Other,
    })
}

/// Reads a SEQUENCE OF elements of `per_element` `TwoDLocation`s, at least `minimum`.
fn read_locations<'a>(
    reader: &mut CoerReader<'a>,
    per_element: usize,
    minimum: usize,
) -> DecodeResult<Locations<'a>> {
    let count_reader = *reader;
    let count = reader.read_quantity()?;
    if count < minimum {
        return Err(count_reader.error(DecodeErrorKind::ValueOutOfRange));
    }
    let total = count
        .checked_mul(per_element.saturating_mul(8))
        .ok_or_else(|| count_reader.error(DecodeErrorKind::UnexpectedEnd))?;
    Ok(Locations {
        encoded: reader.read_slice(total)?,
    })
}

/// Decodes `TwoDLocation`.
fn parse_two_d_location(reader: &mut CoerReader<'_>) -> DecodeResult<TwoDLocation> {
    Ok(TwoDLocation {
        latitude: reader.read_i32()?,
        longitude: reader.read_i32()?,
    })
}

/// Skips `IdentifiedRegion`.
fn skip_identified_region(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 3)? {
        Some(0) => reader.skip(2), // countryOnly
        Some(1) => {
            reader.skip(2)?;
            let count = reader.read_quantity()?;
            reader.skip(count) // regions: Uint8 each
        }
        Some(_) => {
            reader.skip(2)?;
            skip_sequence_of(reader, |r| {
                r.skip(1)?;
                let count = r.read_quantity()?;
                r.skip(count.saturating_mul(2)) // subregions: Uint16 each
            })
        }
        None => Ok(()),
    }
}

/// Decodes a `Psid` (`INTEGER (0..MAX)`), which must fit 32 bits.
pub(super) fn read_psid(reader: &mut CoerReader<'_>) -> DecodeResult<Psid> {
    let start = *reader;
    let value = reader.read_unsigned()?;
    u32::try_from(value)
        .map(Psid)
        .map_err(|_| start.error(DecodeErrorKind::ValueOutOfRange))
}

/// Decodes `PsidSsp`.
fn parse_psid_ssp<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<PsidSsp<'a>> {
    let preamble = reader.read_preamble(false, 1)?;
    let psid = read_psid(reader)?;
    let ssp = optional(preamble.has_optional(0), || {
        Ok(match read_extensible_tag(reader, 1)? {
            Some(_) => Ssp::Opaque(reader.read_octet_string()?),
            None => Ssp::Other,
        })
    })?;
    Ok(PsidSsp { psid, ssp })
}

/// Decodes `PsidGroupPermissions`.
fn parse_psid_group<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<PsidGroup<'a>> {
    let preamble = reader.read_preamble(false, 3)?;
    let subject = match read_extensible_tag(reader, 2)? {
        Some(0) => {
            let (count, encoded) = read_list(reader, parse_psid_ssp_range)?;
            SubjectPermissions::Explicit(PsidRanges { count, encoded })
        }
        Some(_) => SubjectPermissions::All,
        None => SubjectPermissions::Other,
    };
    let min_chain_length = optional(preamble.has_optional(0), || reader.read_signed())?;
    let chain_length_range = optional(preamble.has_optional(1), || reader.read_signed())?;
    let ee_type = optional(preamble.has_optional(2), || reader.read_u8())?;
    Ok(PsidGroup {
        subject,
        min_chain_length: min_chain_length.unwrap_or(1),
        chain_length_range: chain_length_range.unwrap_or(0),
        ee_type: ee_type.unwrap_or(0x80),
    })
}

/// Decodes `PsidSspRange`; returns its PSID (the SSP range is checked and skipped).
fn parse_psid_ssp_range(reader: &mut CoerReader<'_>) -> DecodeResult<Psid> {
    let preamble = reader.read_preamble(false, 1)?;
    let psid = read_psid(reader)?;
    if preamble.has_optional(0) {
        // explicit: a list of octet strings; all (NULL) and extensions: nothing more.
        if let Some(0) = read_extensible_tag(reader, 2)? {
            skip_sequence_of(reader, |r| r.read_octet_string().map(|_| ()))?;
        }
    }
    Ok(psid)
}

/// Decodes `VerificationKeyIndicator`.
fn parse_verify_key<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<VerifyKeyIndicator<'a>> {
    Ok(match read_extensible_tag(reader, 2)? {
        Some(0) => match read_extensible_tag(reader, 2)? {
            Some(0) => VerifyKeyIndicator::NistP256(parse_curve_point(reader, 32)?),
            Some(_) => {
                parse_curve_point(reader, 32)?; // ecdsaBrainpoolP256r1
                VerifyKeyIndicator::OtherKey
            }
            None => VerifyKeyIndicator::OtherKey,
        },
        Some(_) => VerifyKeyIndicator::Reconstruction(parse_curve_point(reader, 32)?),
        None => VerifyKeyIndicator::Other,
    })
}
