//! Structural walks over IEEE 1609.2 structures whose content the envelope view does not
//! expose (certificates, encrypted data, encryption keys): each function checks the COER
//! structure and advances the reader past it, so that the caller learns where it ends.
//!
//! Extension alternatives of extensible CHOICEs and extension additions of extensible
//! SEQUENCEs are skipped by their open-type length. Every loop runs at most once per
//! remaining input byte and there is no recursion.
//!
//! No function in this module panics on any input.

use super::coer::{CoerReader, DecodeResult};
use super::ieee1609dot2_error::{DecodeErrorKind, PROTOCOL_VERSION};
use super::ieee1609dot2_signature::{parse_curve_point, parse_signature};

/// A function that advances a reader past one value.
type Skip = for<'a> fn(&mut CoerReader<'a>) -> DecodeResult<()>;

/// Skips a `Certificate` (`CertificateBase`).
pub(crate) fn skip_certificate(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    let preamble = reader.read_preamble(false, 1)?;
    let version_reader = *reader;
    if reader.read_u8()? != PROTOCOL_VERSION {
        return Err(version_reader.error(DecodeErrorKind::UnsupportedVersion));
    }
    reader.read_enumerated()?; // type: explicit / implicit / extension
    skip_issuer_identifier(reader)?;
    skip_to_be_signed_certificate(reader)?;
    if preamble.has_optional(0) {
        parse_signature(reader)?;
    }
    Ok(())
}

/// Skips `EncryptedData`: recipients, then the ciphertext.
pub(crate) fn skip_encrypted_data(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    skip_sequence_of(reader, skip_recipient_info)?;
    skip_symmetric_ciphertext(reader)
}

/// Skips `EncryptionKey` (public or symmetric).
pub(crate) fn skip_encryption_key(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_root_tag(reader, 2)? {
        0 => skip_public_encryption_key(reader),
        _ => skip_symmetric_encryption_key(reader),
    }
}

/// Reads the tag of a non-extensible CHOICE with `alternatives` alternatives.
fn read_root_tag(reader: &mut CoerReader<'_>, alternatives: u32) -> DecodeResult<u32> {
    let tag_reader = *reader;
    let tag = reader.read_choice_tag()?;
    if tag < alternatives {
        Ok(tag)
    } else {
        Err(tag_reader.error(DecodeErrorKind::UnknownAlternative))
    }
}

/// Reads the tag of an extensible CHOICE with `root` root alternatives; for an extension
/// alternative, skips its open type and returns `None`.
fn read_extensible_tag(reader: &mut CoerReader<'_>, root: u32) -> DecodeResult<Option<u32>> {
    let tag = reader.read_choice_tag()?;
    if tag < root {
        Ok(Some(tag))
    } else {
        reader.skip_open_type()?;
        Ok(None)
    }
}

/// Skips a SEQUENCE OF whose elements each take at least one byte.
fn skip_sequence_of(reader: &mut CoerReader<'_>, skip_element: Skip) -> DecodeResult<()> {
    let count = reader.read_quantity()?;
    for _ in 0..count {
        skip_element(reader)?;
    }
    Ok(())
}

/// Skips a SEQUENCE OF fixed-size elements of `element_size` bytes.
fn skip_sequence_of_fixed(reader: &mut CoerReader<'_>, element_size: usize) -> DecodeResult<()> {
    let count = reader.read_quantity()?;
    let total = count
        .checked_mul(element_size)
        .ok_or_else(|| reader.error(DecodeErrorKind::UnexpectedEnd))?;
    reader.skip(total)
}

/// Skips the extension additions when the preamble announces them.
fn skip_extensions_if(reader: &mut CoerReader<'_>, present: bool) -> DecodeResult<()> {
    if present {
        reader.skip_extension_additions()?;
    }
    Ok(())
}

/// Skips `IssuerIdentifier`.
fn skip_issuer_identifier(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 2)? {
        Some(0) => reader.skip(8),                       // sha256AndDigest
        Some(_) => reader.read_enumerated().map(|_| ()), // self: HashAlgorithm
        None => Ok(()),
    }
}

/// Skips `ToBeSignedCertificate`.
fn skip_to_be_signed_certificate(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    let preamble = reader.read_preamble(true, 7)?;
    skip_certificate_id(reader)?;
    reader.skip(3 + 2)?; // cracaId, crlSeries
    skip_validity_period(reader)?;
    let optional_fields: [Skip; 7] = [
        skip_geographic_region,
        |r| r.skip(1),                                        // assuranceLevel
        |r| skip_sequence_of(r, skip_psid_ssp),               // appPermissions
        |r| skip_sequence_of(r, skip_psid_group_permissions), // certIssuePermissions
        |r| skip_sequence_of(r, skip_psid_group_permissions), // certRequestPermissions
        |_| Ok(()),                                           // canRequestRollover: NULL
        skip_public_encryption_key,
    ];
    for (index, skip_field) in (0u32..).zip(optional_fields) {
        if preamble.has_optional(index) {
            skip_field(reader)?;
        }
    }
    skip_verification_key_indicator(reader)?;
    skip_extensions_if(reader, preamble.has_extensions())
}

/// Skips `CertificateId`.
fn skip_certificate_id(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 4)? {
        Some(0) => skip_linkage_data(reader),
        Some(1 | 2) => reader.read_octet_string().map(|_| ()), // name, binaryId
        Some(_) | None => Ok(()),                              // none: NULL
    }
}

/// Skips `LinkageData`.
fn skip_linkage_data(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    let preamble = reader.read_preamble(false, 1)?;
    reader.skip(2 + 9)?; // iCert, linkage-value
    if preamble.has_optional(0) {
        reader.skip(4 + 9)?; // group-linkage-value
    }
    Ok(())
}

/// Skips `ValidityPeriod`: a `Time32` and a `Duration` CHOICE of seven `Uint16`s.
fn skip_validity_period(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    reader.skip(4)?;
    read_root_tag(reader, 7)?;
    reader.skip(2)
}

/// Skips `GeographicRegion`.
fn skip_geographic_region(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 4)? {
        Some(0) => reader.skip(8 + 2),                 // circularRegion
        Some(1) => skip_sequence_of_fixed(reader, 16), // rectangularRegion
        Some(2) => skip_sequence_of_fixed(reader, 8),  // polygonalRegion
        Some(_) => skip_sequence_of(reader, skip_identified_region),
        None => Ok(()),
    }
}

/// Skips `IdentifiedRegion`.
fn skip_identified_region(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 3)? {
        Some(0) => reader.skip(2), // countryOnly
        Some(1) => {
            reader.skip(2)?;
            skip_sequence_of_fixed(reader, 1)
        }
        Some(_) => {
            reader.skip(2)?;
            skip_sequence_of(reader, skip_region_and_subregions)
        }
        None => Ok(()),
    }
}

/// Skips `RegionAndSubregions`: a `Uint8` and a SEQUENCE OF `Uint16`.
fn skip_region_and_subregions(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    reader.skip(1)?;
    skip_sequence_of_fixed(reader, 2)
}

/// Skips `PsidSsp`.
fn skip_psid_ssp(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    let preamble = reader.read_preamble(false, 1)?;
    reader.read_unsigned()?;
    if preamble.has_optional(0) {
        skip_service_specific_permissions(reader)?;
    }
    Ok(())
}

/// Skips `ServiceSpecificPermissions`.
fn skip_service_specific_permissions(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 1)? {
        Some(_) => reader.read_octet_string().map(|_| ()), // opaque
        None => Ok(()),
    }
}

/// Skips `PsidGroupPermissions`.
fn skip_psid_group_permissions(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    let preamble = reader.read_preamble(false, 3)?;
    skip_subject_permissions(reader)?;
    if preamble.has_optional(0) {
        reader.skip_signed()?; // minChainLength
    }
    if preamble.has_optional(1) {
        reader.skip_signed()?; // chainLengthRange
    }
    if preamble.has_optional(2) {
        reader.skip(1)?; // eeType: BIT STRING (SIZE (8))
    }
    Ok(())
}

/// Skips `SubjectPermissions`.
fn skip_subject_permissions(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 2)? {
        Some(0) => skip_sequence_of(reader, skip_psid_ssp_range),
        Some(_) | None => Ok(()), // all: NULL
    }
}

/// Skips `PsidSspRange`.
fn skip_psid_ssp_range(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    let preamble = reader.read_preamble(false, 1)?;
    reader.read_unsigned()?;
    if preamble.has_optional(0) {
        skip_ssp_range(reader)?;
    }
    Ok(())
}

/// Skips `SspRange`.
fn skip_ssp_range(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 2)? {
        Some(0) => skip_sequence_of(reader, |r| r.read_octet_string().map(|_| ())),
        Some(_) | None => Ok(()), // all: NULL
    }
}

/// Skips `PublicEncryptionKey`: a `SymmAlgorithm` and a `BasePublicEncryptionKey`.
fn skip_public_encryption_key(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    reader.read_enumerated()?;
    match read_extensible_tag(reader, 2)? {
        Some(_) => skip_p256_point(reader),
        None => Ok(()),
    }
}

/// Skips `SymmetricEncryptionKey`.
fn skip_symmetric_encryption_key(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 1)? {
        Some(_) => reader.skip(16), // aes128Ccm
        None => Ok(()),
    }
}

/// Skips `VerificationKeyIndicator`.
fn skip_verification_key_indicator(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 2)? {
        Some(0) => skip_public_verification_key(reader),
        Some(_) => skip_p256_point(reader), // reconstructionValue
        None => Ok(()),
    }
}

/// Skips `PublicVerificationKey`.
fn skip_public_verification_key(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 2)? {
        Some(_) => skip_p256_point(reader),
        None => Ok(()),
    }
}

/// Skips an `EccP256CurvePoint`.
fn skip_p256_point(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    parse_curve_point(reader, 32).map(|_| ())
}

/// Skips `RecipientInfo`.
fn skip_recipient_info(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    let tag = read_root_tag(reader, 5)?;
    reader.skip(8)?; // HashedId8 of the key or certificate
    match tag {
        0 => Ok(()),                                     // pskRecipInfo
        1 => skip_symmetric_ciphertext(reader),          // symmRecipInfo
        _ => skip_encrypted_data_encryption_key(reader), // PKRecipientInfo
    }
}

/// Skips `EncryptedDataEncryptionKey`.
fn skip_encrypted_data_encryption_key(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 2)? {
        Some(_) => {
            skip_p256_point(reader)?;
            reader.skip(16 + 16) // c, t
        }
        None => Ok(()),
    }
}

/// Skips `SymmetricCiphertext`.
fn skip_symmetric_ciphertext(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
    match read_extensible_tag(reader, 1)? {
        Some(_) => {
            reader.skip(12)?; // nonce
            reader.read_octet_string().map(|_| ())
        }
        None => Ok(()),
    }
}
