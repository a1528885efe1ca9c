//! [`TrustedCert`]: what the verifier keeps of a certificate it trusts (a configured anchor,
//! or one whose chain it verified), and the walk that earns that trust.

use heapless::Vec;
use j2735::envelope::ieee1609dot2::crypto::{
    sha256, signing_digest_with, CryptoError, GeneratorTable, PreparedKey, PublicKey,
};
use j2735::envelope::ieee1609dot2::{
    Certificate, CertificateKind, Issuer, Ssp, SubjectPermissions, ValidityPeriod,
};
use j2735::envelope::Psid;

use super::region::{Region, RegionError};
use super::Rejection;
use crate::capacity::{MAX_CERT_PSIDS, MAX_SSP};

/// A trusted certificate without its bytes: enough to verify what it signed or issued.
#[derive(Debug, Clone, PartialEq)]
pub struct TrustedCert {
    /// SHA-256 of the certificate's COER (its `HashedId8` is the last eight octets).
    pub hash: [u8; 32],
    /// Its verification key (explicit, or reconstructed by ECQV), with its precomputed
    /// multiples: this certificate verifies many messages.
    pub key: PreparedKey,
    /// Its validity period.
    pub validity: ValidityPeriod,
    /// `appPermissions`: the PSIDs it may sign, each with its opaque SSP if it has one.
    pub app_psids: Vec<(Psid, Option<Vec<u8, MAX_SSP>>), MAX_CERT_PSIDS>,
    /// `certIssuePermissions`: the PSIDs it may certify (`issue_all`: any).
    pub issue_psids: Vec<Psid, MAX_CERT_PSIDS>,
    /// `certIssuePermissions` has `all`.
    pub issue_all: bool,
    /// Its region, if it has one.
    pub region: Option<Region>,
}

impl TrustedCert {
    /// The certificate's `HashedId8`.
    pub fn id8(&self) -> [u8; 8] {
        let mut id = [0u8; 8];
        id.copy_from_slice(&self.hash[24..]);
        id
    }

    /// Whether it may sign `psid`, and the opaque SSP it grants with it (`Some(None)`: the
    /// PSID without SSP).
    pub fn permission(&self, psid: Psid) -> Option<Option<&[u8]>> {
        self.app_psids
            .iter()
            .find(|(p, _)| *p == psid)
            .map(|(_, ssp)| ssp.as_deref())
    }

    /// Whether it may certify `psid`.
    pub fn may_issue(&self, psid: Psid) -> bool {
        self.issue_all || self.issue_psids.contains(&psid)
    }

    /// Keeps `cert`, whose key is `key`.
    ///
    /// # Errors
    ///
    /// [`Rejection::CertificateTooLarge`] beyond the capacities, `CertificateInvalid` for
    /// a region with invalid coordinates.
    pub fn keep(cert: &Certificate<'_>, key: PublicKey) -> Result<Self, Rejection> {
        let too_large = |_| Rejection::CertificateTooLarge;
        let mut app_psids = Vec::new();
        for p in cert.app_permissions.iter().flat_map(|l| l.iter()) {
            let ssp = match p.ssp {
                Some(Ssp::Opaque(bytes)) => {
                    Some(Vec::from_slice(bytes).map_err(|_| Rejection::CertificateTooLarge)?)
                }
                Some(Ssp::Other) | None => None,
            };
            app_psids
                .push((p.psid, ssp))
                .map_err(|_| Rejection::CertificateTooLarge)?;
        }
        let mut issue_psids = Vec::new();
        let mut issue_all = false;
        for group in cert.cert_issue_permissions.iter().flat_map(|g| g.iter()) {
            match group.subject {
                SubjectPermissions::All => issue_all = true,
                SubjectPermissions::Explicit(ranges) => {
                    for psid in ranges.psids() {
                        issue_psids.push(psid).map_err(too_large)?;
                    }
                }
                SubjectPermissions::Other => {}
            }
        }
        let region = match &cert.region {
            Some(r) => Some(Region::from_certificate(r).map_err(|e| match e {
                RegionError::TooLarge => Rejection::CertificateTooLarge,
                RegionError::Invalid => Rejection::CertificateInvalid,
            })?),
            None => None,
        };
        Ok(Self {
            hash: sha256(cert.encoded),
            key: PreparedKey::new(key),
            validity: cert.validity,
            app_psids,
            issue_psids,
            issue_all,
            region,
        })
    }

    /// A configured trust anchor: an explicit certificate; a self-signed one must verify
    /// under its own key. The caller decides to trust it.
    ///
    /// # Errors
    ///
    /// [`Rejection::CertificateInvalid`] for an implicit certificate (no key without its
    /// issuer), a bad self-signature or key; `CertificateTooLarge` beyond the capacities.
    pub fn anchor(cert: &Certificate<'_>) -> Result<Self, Rejection> {
        let key = PublicKey::of_explicit(cert).map_err(|_| Rejection::CertificateInvalid)?;
        if let Issuer::SelfSigned(_) = cert.issuer {
            let digest = signing_digest_with(cert.to_be_signed, &sha256(&[]));
            let signature = cert.signature.ok_or(Rejection::CertificateInvalid)?;
            key.verify(&digest, &signature)
                .map_err(|_| Rejection::CertificateInvalid)?;
        }
        Self::keep(cert, key)
    }

    /// `cert`, issued by `self`, verified and kept: the issuer digest matches, the key
    /// verifies (explicit) or is reconstructed (implicit), the validity lies within the
    /// issuer's, and the issuer may certify each of `psids`.
    ///
    /// # Errors
    ///
    /// [`Rejection::ChainUntrusted`] when `self` is not its issuer, `IssuerPermission`,
    /// `CertificateInvalid`, `UnsupportedAlgorithm` or `CertificateTooLarge`.
    pub fn issue(
        &self,
        cert: &Certificate<'_>,
        psids: &[Psid],
        generator: &GeneratorTable,
    ) -> Result<Self, Rejection> {
        if cert.issuer != Issuer::Sha256Digest(self.id8()) {
            return Err(Rejection::ChainUntrusted);
        }
        if !psids.iter().all(|&p| self.may_issue(p)) {
            return Err(Rejection::IssuerPermission);
        }
        let inside = cert.validity.start_us() >= self.validity.start_us()
            && cert.validity.end_us() <= self.validity.end_us();
        if !inside {
            return Err(Rejection::CertificateInvalid);
        }
        let key = match cert.kind {
            CertificateKind::Explicit => {
                let key = PublicKey::of_explicit(cert).map_err(crypto_reason)?;
                let signature = cert.signature.ok_or(Rejection::CertificateInvalid)?;
                let digest = signing_digest_with(cert.to_be_signed, &self.hash);
                self.key
                    .verify(generator, &digest, &signature)
                    .map_err(crypto_reason)?;
                key
            }
            CertificateKind::Implicit => {
                if cert.signature.is_some() {
                    return Err(Rejection::CertificateInvalid);
                }
                PublicKey::reconstruct(cert, &self.hash, self.key.public())
                    .map_err(crypto_reason)?
            }
        };
        Self::keep(cert, key)
    }
}

/// The drop reason of a failed certificate check.
fn crypto_reason(e: CryptoError) -> Rejection {
    match e {
        CryptoError::UnsupportedScheme => Rejection::UnsupportedAlgorithm,
        _ => Rejection::CertificateInvalid,
    }
}
