//! IEEE 1609.2 cryptography on NIST P-256 with SHA-256: the signature hash, `HashedId8`,
//! ECDSA verify and sign (x-only or compressed-y `rSig`), and ECQV public-key
//! reconstruction for implicit certificates. No heap; RustCrypto `p256` and `sha2`.
//!
//! The hash that is signed (1609.2 5.3.1): with `data` the COER of `ToBeSignedData` (or of a
//! certificate's `ToBeSignedCertificate`) and `signer` the COER of the signer's certificate
//! (the empty string for `self` and for a root),
//! `H = SHA-256( SHA-256(data) || SHA-256(signer) )`, and ECDSA runs with `e = H mod n`.
//!
//! ECDSA verification is written out here on `p256`'s point arithmetic rather than through
//! `VerifyingKey`, because a compressed-y `rSig` carries the whole point `R` (its x must
//! match and its y parity too), and because verification may run in variable time (its
//! inputs are public): `u1 G + u2 Q` is one interleaved width-5 NAF chain
//! (`lincomb.rs`), about twice as fast as `p256`'s constant-time `lincomb`.
//!
//! ECQV (SEC 4, as profiled by 1609.2 5.3.2): `Q_U = e * P_U + Q_CA` with
//! `e = H(ToBeSignedCertificate, issuer certificate) mod n`, the whole digest reduced (the
//! reading of the independent vectors in `codec/tests/vectors/ieee1609dot2_signed.jsonl`).
//!
//! No function in this module panics on any input.

// Scalar and point arithmetic here is modular (mod n, on the curve): it cannot overflow.
#![allow(clippy::arithmetic_side_effects)]

use core::fmt;

use p256::elliptic_curve::group::Group;
use p256::elliptic_curve::ops::{Invert, Reduce};
use p256::elliptic_curve::point::AffineCoordinates;
use p256::elliptic_curve::sec1::{FromEncodedPoint, ToEncodedPoint};
use p256::elliptic_curve::subtle::CtOption;
use p256::{AffinePoint, EncodedPoint, FieldBytes, NonZeroScalar, ProjectivePoint, Scalar, U256};
use sha2::{Digest, Sha256};

use super::{Certificate, CurvePoint, PointForm, Signature, SignatureScheme, VerifyKeyIndicator};

/// Why a key, a signature or a reconstruction was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CryptoError {
    /// A signature scheme or key type other than ECDSA NIST P-256.
    UnsupportedScheme,
    /// A point that is not on the curve, or in a form that cannot name one (`x-only`,
    /// `fill`) where a key is needed.
    InvalidPoint,
    /// `r` or `s` outside `1..n`.
    InvalidScalar,
    /// The signature does not verify under the key.
    BadSignature,
    /// The certificate has no key of the kind asked for (an explicit key where a
    /// reconstruction value was expected, or the other way round).
    WrongKeyKind,
}

impl CryptoError {
    /// A short lowercase description.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            Self::UnsupportedScheme => "unsupported signature scheme",
            Self::InvalidPoint => "invalid curve point",
            Self::InvalidScalar => "invalid signature scalar",
            Self::BadSignature => "signature does not verify",
            Self::WrongKeyKind => "wrong key kind",
        }
    }
}

impl fmt::Display for CryptoError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

impl core::error::Error for CryptoError {}

/// SHA-256 of `bytes`.
#[must_use]
pub fn sha256(bytes: &[u8]) -> [u8; 32] {
    Sha256::digest(bytes).into()
}

/// `HashedId8` of a certificate: the last eight octets of SHA-256 of its COER.
#[must_use]
pub fn hashed_id8(certificate: &[u8]) -> [u8; 8] {
    let digest = sha256(certificate);
    let mut id = [0u8; 8];
    id.copy_from_slice(digest.get(24..).unwrap_or_default());
    id
}

/// The hash that is signed: `SHA-256(SHA-256(data) || SHA-256(signer or ""))`.
#[must_use]
pub fn signing_digest(data: &[u8], signer: Option<&[u8]>) -> [u8; 32] {
    let mut hasher = Sha256::new();
    hasher.update(sha256(data));
    hasher.update(sha256(signer.unwrap_or_default()));
    hasher.finalize().into()
}

/// [`signing_digest`] when the signer certificate's SHA-256 is already known (a verifier
/// keeps the hashes of trusted certificates, not their bytes).
#[must_use]
pub fn signing_digest_with(data: &[u8], signer_hash: &[u8; 32]) -> [u8; 32] {
    let mut hasher = Sha256::new();
    hasher.update(sha256(data));
    hasher.update(signer_hash);
    hasher.finalize().into()
}

/// A P-256 public key (a point on the curve, not the identity).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PublicKey(AffinePoint);

impl PublicKey {
    /// The key named by a compressed or uncompressed `EccP256CurvePoint`.
    ///
    /// # Errors
    ///
    /// [`CryptoError::InvalidPoint`] for `x-only`, `fill`, a wrong size or a point off the curve.
    pub fn from_curve_point(point: &CurvePoint<'_>) -> Result<Self, CryptoError> {
        let mut sec1 = [0u8; 65];
        let used = match (point.form, point.y) {
            (PointForm::CompressedY0 | PointForm::CompressedY1, _) => {
                let prefix = if point.form == PointForm::CompressedY0 {
                    2
                } else {
                    3
                };
                write_sec1(&mut sec1, prefix, point.x, &[])?
            }
            (PointForm::Uncompressed, Some(y)) => write_sec1(&mut sec1, 4, point.x, y)?,
            _ => return Err(CryptoError::InvalidPoint),
        };
        Self::from_sec1(sec1.get(..used).unwrap_or_default())
    }

    /// The key in SEC 1 encoding (33 octets compressed or 65 uncompressed).
    ///
    /// # Errors
    ///
    /// [`CryptoError::InvalidPoint`] when the bytes are not a point on the curve.
    pub fn from_sec1(bytes: &[u8]) -> Result<Self, CryptoError> {
        let encoded = EncodedPoint::from_bytes(bytes).map_err(|_| CryptoError::InvalidPoint)?;
        let point: Option<AffinePoint> = AffinePoint::from_encoded_point(&encoded).into();
        match point {
            Some(point) if !bool::from(ProjectivePoint::from(point).is_identity()) => {
                Ok(Self(point))
            }
            _ => Err(CryptoError::InvalidPoint),
        }
    }

    /// The key in compressed SEC 1 form (`02`/`03` and x).
    #[must_use]
    pub fn to_compressed(&self) -> [u8; 33] {
        let encoded = self.0.to_encoded_point(true);
        let mut out = [0u8; 33];
        if let Some(bytes) = out.get_mut(..encoded.len()) {
            bytes.copy_from_slice(encoded.as_bytes());
        }
        out
    }

    /// The explicit verification key of `certificate`.
    ///
    /// # Errors
    ///
    /// [`CryptoError::WrongKeyKind`] for an implicit certificate, `UnsupportedScheme` for
    /// another curve, `InvalidPoint` for a key off the curve.
    pub fn of_explicit(certificate: &Certificate<'_>) -> Result<Self, CryptoError> {
        match certificate.verify_key {
            VerifyKeyIndicator::NistP256(point) => Self::from_curve_point(&point),
            VerifyKeyIndicator::Reconstruction(_) => Err(CryptoError::WrongKeyKind),
            VerifyKeyIndicator::OtherKey | VerifyKeyIndicator::Other => {
                Err(CryptoError::UnsupportedScheme)
            }
        }
    }

    /// ECQV: the public key of the implicit `certificate`, issued by the certificate whose
    /// COER has the SHA-256 `issuer_hash` and whose key is `issuer_key`
    /// (`Q_U = e * P_U + Q_CA`).
    ///
    /// # Errors
    ///
    /// [`CryptoError::WrongKeyKind`] for an explicit certificate, `InvalidPoint` when the
    /// reconstruction value or the result is not a valid point.
    pub fn reconstruct(
        certificate: &Certificate<'_>,
        issuer_hash: &[u8; 32],
        issuer_key: &PublicKey,
    ) -> Result<Self, CryptoError> {
        let VerifyKeyIndicator::Reconstruction(point) = certificate.verify_key else {
            return Err(CryptoError::WrongKeyKind);
        };
        let reconstruction = Self::from_curve_point(&point)?;
        let e = scalar_of_digest(&signing_digest_with(certificate.to_be_signed, issuer_hash));
        let q = ProjectivePoint::from(reconstruction.0) * e + ProjectivePoint::from(issuer_key.0);
        if bool::from(q.is_identity()) {
            return Err(CryptoError::InvalidPoint);
        }
        Ok(Self(q.to_affine()))
    }

    /// Verifies an ECDSA P-256 `signature` over the signature hash `digest`.
    ///
    /// # Errors
    ///
    /// [`CryptoError::UnsupportedScheme`] for another scheme, `InvalidScalar` for `r` or `s`
    /// outside `1..n`, `InvalidPoint` for an `rSig` form that names no point, and
    /// `BadSignature` when it does not verify (for a compressed-y `rSig`, also when the
    /// point's y parity differs).
    pub fn verify(&self, digest: &[u8; 32], signature: &Signature<'_>) -> Result<(), CryptoError> {
        let key = ProjectivePoint::from(self.0);
        check_signature(digest, signature, |u1, u2| {
            super::lincomb::mul_add_vartime(u1, &ProjectivePoint::GENERATOR, u2, &key)
        })
    }
}

/// A [`PublicKey`] with its precomputed multiples, for a key that verifies many signatures
/// (a cached signer certificate): with the generator's ([`GeneratorTable`]) a verification
/// takes about a quarter of the doublings (see `lincomb.rs`).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PreparedKey {
    key: PublicKey,
    multiples: super::lincomb::Multiples,
}

/// The generator's precomputed multiples (make one, keep it).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratorTable(super::lincomb::Multiples);

impl GeneratorTable {
    /// Computes the table (a few hundred point operations).
    #[must_use]
    pub fn new() -> Self {
        Self(super::lincomb::Multiples::new(&ProjectivePoint::GENERATOR))
    }
}

impl Default for GeneratorTable {
    fn default() -> Self {
        Self::new()
    }
}

impl PreparedKey {
    /// Computes `key`'s multiples (a few hundred point operations: once per key).
    #[must_use]
    pub fn new(key: PublicKey) -> Self {
        Self {
            key,
            multiples: super::lincomb::Multiples::new(&ProjectivePoint::from(key.0)),
        }
    }

    /// The key.
    #[must_use]
    pub fn public(&self) -> &PublicKey {
        &self.key
    }

    /// [`PublicKey::verify`], faster.
    ///
    /// # Errors
    ///
    /// As [`PublicKey::verify`].
    pub fn verify(
        &self,
        generator: &GeneratorTable,
        digest: &[u8; 32],
        signature: &Signature<'_>,
    ) -> Result<(), CryptoError> {
        check_signature(digest, signature, |u1, u2| {
            super::lincomb::mul_add_with(u1, &generator.0, u2, &self.multiples)
        })
    }
}

/// ECDSA verification with `mul_add(u1, u2) = u1 G + u2 Q`.
fn check_signature(
    digest: &[u8; 32],
    signature: &Signature<'_>,
    mul_add: impl FnOnce(&Scalar, &Scalar) -> ProjectivePoint,
) -> Result<(), CryptoError> {
    if signature.scheme != SignatureScheme::EcdsaNistP256 {
        return Err(CryptoError::UnsupportedScheme);
    }
    let parity = match signature.r.form {
        PointForm::XOnly => None,
        PointForm::CompressedY0 => Some(false),
        PointForm::CompressedY1 => Some(true),
        PointForm::Uncompressed | PointForm::Fill => return Err(CryptoError::InvalidPoint),
    };
    let r = *nonzero_scalar(signature.r.x)?;
    let s = *nonzero_scalar(signature.s)?;
    // Public values: the variable-time inversion is fine (and 2.5 times faster).
    let s_inv: Option<Scalar> = Invert::invert_vartime(&s).into();
    let s_inv = s_inv.ok_or(CryptoError::InvalidScalar)?;
    let e = scalar_of_digest(digest);
    let point = mul_add(&(e * s_inv), &(r * s_inv));
    if bool::from(point.is_identity()) {
        return Err(CryptoError::BadSignature);
    }
    let affine = point.to_affine();
    let x = affine.x();
    let matches = match parity {
        None => <Scalar as Reduce<U256>>::reduce_bytes(&x) == r,
        Some(odd) => x[..] == *signature.r.x && bool::from(affine.y_is_odd()) == odd,
    };
    if matches {
        Ok(())
    } else {
        Err(CryptoError::BadSignature)
    }
}

/// A P-256 private key (for the roadside's signing and for tests).
#[derive(Clone)]
pub struct SecretKey(NonZeroScalar);

impl fmt::Debug for SecretKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("SecretKey(..)")
    }
}

/// How the signer writes `rSig`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RSigForm {
    /// `x-only`: the integer r.
    XOnly,
    /// `compressed-y-0` / `compressed-y-1`: the point R.
    CompressedY,
}

/// An ECDSA P-256 signature ready to encode: the `rSig` form, its x, and `s`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RawSignature {
    /// The `rSig` alternative.
    pub form: PointForm,
    /// `rSig`'s 32 octets.
    pub r: [u8; 32],
    /// `sSig`.
    pub s: [u8; 32],
}

impl SecretKey {
    /// The key of the big-endian scalar `bytes` (`1..n`).
    ///
    /// # Errors
    ///
    /// [`CryptoError::InvalidScalar`] for zero, `n` or above, or a length other than 32.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, CryptoError> {
        nonzero_scalar(bytes).map(Self)
    }

    /// The scalar, big-endian (for storing the key).
    #[must_use]
    pub fn to_bytes(&self) -> [u8; 32] {
        self.0.to_bytes().into()
    }

    /// The matching public key.
    #[must_use]
    pub fn public_key(&self) -> PublicKey {
        PublicKey((ProjectivePoint::GENERATOR * *self.0).to_affine())
    }

    /// Signs the signature hash `digest` with a deterministic nonce (RFC 6979).
    ///
    /// # Errors
    ///
    /// [`CryptoError::InvalidScalar`] in the negligible case that the nonce gives r or s = 0.
    pub fn sign(&self, digest: &[u8; 32], form: RSigForm) -> Result<RawSignature, CryptoError> {
        let (signature, recovery) = p256::ecdsa::SigningKey::from(self.0)
            .sign_prehash_recoverable(digest)
            .map_err(|_| CryptoError::InvalidScalar)?;
        let (r, s) = signature.split_bytes();
        let form = match form {
            RSigForm::XOnly => PointForm::XOnly,
            // x(R) >= n happens with probability about 2^-128; r is then not R's x.
            RSigForm::CompressedY if recovery.is_x_reduced() => {
                return Err(CryptoError::InvalidScalar)
            }
            RSigForm::CompressedY if recovery.is_y_odd() => PointForm::CompressedY1,
            RSigForm::CompressedY => PointForm::CompressedY0,
        };
        Ok(RawSignature {
            form,
            r: r.into(),
            s: s.into(),
        })
    }
}

/// `e`: a signature hash as a scalar (reduced mod n).
fn scalar_of_digest(digest: &[u8; 32]) -> Scalar {
    <Scalar as Reduce<U256>>::reduce_bytes(&FieldBytes::from(*digest))
}

/// A scalar in `1..n` from 32 big-endian octets.
fn nonzero_scalar(bytes: &[u8]) -> Result<NonZeroScalar, CryptoError> {
    let array: [u8; 32] = bytes.try_into().map_err(|_| CryptoError::InvalidScalar)?;
    let scalar: CtOption<NonZeroScalar> = NonZeroScalar::from_repr(array.into());
    Option::from(scalar).ok_or(CryptoError::InvalidScalar)
}

/// Writes a SEC 1 point (`prefix`, x, then y if any) into `out`; returns its length.
fn write_sec1(out: &mut [u8; 65], prefix: u8, x: &[u8], y: &[u8]) -> Result<usize, CryptoError> {
    if x.len() != 32 || !(y.is_empty() || y.len() == 32) {
        return Err(CryptoError::InvalidPoint);
    }
    let used = 1usize.saturating_add(x.len()).saturating_add(y.len());
    let (head, rest) = out.split_at_mut(1);
    head.copy_from_slice(&[prefix]);
    let (x_out, rest) = rest.split_at_mut(32);
    x_out.copy_from_slice(x);
    if let Some(y_out) = rest.get_mut(..y.len()) {
        y_out.copy_from_slice(y);
    }
    Ok(used)
}
