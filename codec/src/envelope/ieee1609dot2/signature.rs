//! IEEE 1609.2 `Signature` and curve points: their types and COER decoding (shared by the
//! signed-data view and the certificate walk; re-exported by [`super`]).

use super::coer::{optional, within_open_type, CoerReader, DecodeResult};
use super::error::DecodeErrorKind;

/// `Signature`: which scheme, and the raw `r` and `s` values. Not verified.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Signature<'a> {
    /// The signature scheme and curve.
    pub scheme: SignatureScheme,
    /// `rSig`: a curve point (or, for SM2, the scalar `r` given as [`PointForm::XOnly`]).
    pub r: CurvePoint<'a>,
    /// `sSig`: 32 bytes (48 for the P-384 curves).
    pub s: &'a [u8],
}

/// The alternatives of `Signature`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum SignatureScheme {
    /// `ecdsaNistP256Signature`.
    EcdsaNistP256,
    /// `ecdsaBrainpoolP256r1Signature`.
    EcdsaBrainpoolP256r1,
    /// `ecdsaBrainpoolP384r1Signature`.
    EcdsaBrainpoolP384r1,
    /// `ecdsaNistP384Signature`.
    EcdsaNistP384,
    /// `sm2Signature` (IEEE 1609.2-2022).
    Sm2,
}

/// An `EccP256CurvePoint` or `EccP384CurvePoint`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CurvePoint<'a> {
    /// Which alternative.
    pub form: PointForm,
    /// The x coordinate (empty for [`PointForm::Fill`]).
    pub x: &'a [u8],
    /// The y coordinate, present only for [`PointForm::Uncompressed`].
    pub y: Option<&'a [u8]>,
}

/// The alternatives of a curve point.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum PointForm {
    /// `x-only`.
    XOnly,
    /// `fill`: no coordinates.
    Fill,
    /// `compressed-y-0`.
    CompressedY0,
    /// `compressed-y-1`.
    CompressedY1,
    /// `uncompressedP256` / `uncompressedP384`.
    Uncompressed,
}

/// `HashAlgorithm`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum HashAlgorithm {
    /// SHA-256.
    Sha256,
    /// SHA-384.
    Sha384,
    /// SM3 (IEEE 1609.2-2022).
    Sm3,
}

/// Decodes the `HashAlgorithm` ENUMERATED.
pub(crate) fn parse_hash_algorithm(reader: &mut CoerReader<'_>) -> DecodeResult<HashAlgorithm> {
    let value_reader = *reader;
    match reader.read_enumerated()? {
        0 => Ok(HashAlgorithm::Sha256),
        1 => Ok(HashAlgorithm::Sha384),
        2 => Ok(HashAlgorithm::Sm3),
        _ => Err(value_reader.error(DecodeErrorKind::UnknownAlternative)),
    }
}

/// Decodes `Signature`.
pub(crate) fn parse_signature<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<Signature<'a>> {
    let tag_reader = *reader;
    match reader.read_choice_tag()? {
        0 => parse_ecdsa(reader, SignatureScheme::EcdsaNistP256, 32),
        1 => parse_ecdsa(reader, SignatureScheme::EcdsaBrainpoolP256r1, 32),
        2 => within_open_type(reader, |inner| {
            parse_ecdsa(inner, SignatureScheme::EcdsaBrainpoolP384r1, 48)
        }),
        3 => within_open_type(reader, |inner| {
            parse_ecdsa(inner, SignatureScheme::EcdsaNistP384, 48)
        }),
        4 => within_open_type(reader, parse_sm2),
        _ => Err(tag_reader.error(DecodeErrorKind::UnknownAlternative)),
    }
}

/// Decodes an `EcdsaP256Signature` or `EcdsaP384Signature` with coordinates of `size` bytes.
fn parse_ecdsa<'a>(
    reader: &mut CoerReader<'a>,
    scheme: SignatureScheme,
    size: usize,
) -> DecodeResult<Signature<'a>> {
    let r = parse_curve_point(reader, size)?;
    let s = reader.read_slice(size)?;
    Ok(Signature { scheme, r, s })
}

/// Decodes an `EcsigP256Signature` (SM2): two 32-byte scalars.
fn parse_sm2<'a>(reader: &mut CoerReader<'a>) -> DecodeResult<Signature<'a>> {
    let r = CurvePoint {
        form: PointForm::XOnly,
        x: reader.read_slice(32)?,
        y: None,
    };
    let s = reader.read_slice(32)?;
    Ok(Signature {
        scheme: SignatureScheme::Sm2,
        r,
        s,
    })
}

/// Decodes an `EccP256CurvePoint` (`size` 32) or `EccP384CurvePoint` (`size` 48).
pub(crate) fn parse_curve_point<'a>(
    reader: &mut CoerReader<'a>,
    size: usize,
) -> DecodeResult<CurvePoint<'a>> {
    let tag_reader = *reader;
    let form = match reader.read_choice_tag()? {
        0 => PointForm::XOnly,
        1 => PointForm::Fill,
        2 => PointForm::CompressedY0,
        3 => PointForm::CompressedY1,
        4 => PointForm::Uncompressed,
        _ => return Err(tag_reader.error(DecodeErrorKind::UnknownAlternative)),
    };
    let x = match form {
        PointForm::Fill => &[],
        _ => reader.read_slice(size)?,
    };
    let y = optional(form == PointForm::Uncompressed, || reader.read_slice(size))?;
    Ok(CurvePoint { form, x, y })
}
