//! Structural walks over IEEE 1609.2 structures whose content the envelope view does not
//! expose (encrypted data, encryption keys; certificates through their view): each function checks the COER
//! structure and advances the reader past it, so that the caller learns where it ends.
//!
//! Extension alternatives of extensible CHOICEs and extension additions of extensible
//! SEQUENCEs are skipped by their open-type length. Every loop runs at most once per
//! remaining input byte and there is no recursion.
//!
//! No function in this module panics on any input.

use super::coer::{CoerReader, DecodeResult};
use super::error::DecodeErrorKind;
use super::signature::parse_curve_point;

/// A function that advances a reader past one value.
type Skip = for<'a> fn(&mut CoerReader<'a>) -> DecodeResult<()>;

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
pub(crate) fn read_root_tag(reader: &mut CoerReader<'_>, alternatives: u32) -> DecodeResult<u32> {
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
pub(crate) fn read_extensible_tag(
    reader: &mut CoerReader<'_>,
    root: u32,
) -> DecodeResult<Option<u32>> {
    let tag = reader.read_choice_tag()?;
    if tag < root {
        Ok(Some(tag))
    } else {
        reader.skip_open_type()?;
        Ok(None)
    }
}

/// Skips a SEQUENCE OF whose elements each take at least one byte.
pub(crate) fn skip_sequence_of(
    reader: &mut CoerReader<'_>,
    skip_element: Skip,
) -> DecodeResult<()> {
    let count = reader.read_quantity()?;
    for _ in 0..count {
        skip_element(reader)?;
    }
    Ok(())
}

/// Skips `PublicEncryptionKey`: a `SymmAlgorithm` and a `BasePublicEncryptionKey`.
pub(crate) fn skip_public_encryption_key(reader: &mut CoerReader<'_>) -> DecodeResult<()> {
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
