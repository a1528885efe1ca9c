//! [`TrustedCert`]: what the verifier keeps of a certificate it trusts (a configured anchor,
//! or one whose chain it verified), and the walk that earns that trust.

use heapless::Vec;
use j2735::envelope::ieee1609dot2::crypto::{sha256, signing_digest_with, CryptoError, PublicKey};
use j2735::envelope::ieee1609dot2::{
    Certificate, CertificateKind, Issuer, SubjectPermissions, ValidityPeriod,
};

use super::region::{Region, RegionError};
use crate::capacity::MAX_CERT_PSIDS;
use crate::v2x::DropReason;

/// A trusted certificate without its bytes: enough to verify what it signed or issued.
#[derive(Debug, Clone, PartialEq)]
pub struct TrustedCert {
    /// SHA-256 of the certificate's COER (its `HashedId8` is the last eight octets).
    pub hash: [u8; 32],
    /// Its verification key (explicit, or reconstructed by ECQV).
    pub key: PublicKey,
    /// Its validity period.
    pub validity: ValidityPeriod,
    /// `appPermissions`: the PSIDs it may sign.
    pub app_psids: Vec<u32, MAX_CERT_PSIDS>,
    /// `certIssuePermissions`: the PSIDs it may certify (`issue_all`: any).
    pub issue_psids: Vec<u32, MAX_CERT_PSIDS>,
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

    /// Whether it may certify `psid`.
    pub fn may_issue(&self, psid: u32) -> bool {
        self.issue_all || self.issue_psids.contains(&psid)
    }

    /// Keeps `cert`, whose key is `key`.
    ///
    /// # Errors
    ///
    /// [`DropReason::CertificateTooLarge`] beyond the capacities, `CertificateInvalid` for
    /// a region with invalid coordinates.
    pub fn keep(cert: &Certificate<'_>, key: PublicKey) -> Result<Self, DropReason> {
        let too_large = |_| DropReason::CertificateTooLarge;
        let mut app_psids = Vec::new();
        for p in cert.app_permissions.iter().flat_map(|l| l.iter()) {
            app_psids.push(p.psid).map_err(too_large)?;
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
                RegionError::TooLarge => DropReason::CertificateTooLarge,
                RegionError::Invalid => DropReason::CertificateInvalid,
            })?),
            None => None,
        };
        Ok(Self {
            hash: sha256(cert.encoded),
            key,
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
    /// [`DropReason::CertificateInvalid`] for an implicit certificate (no key without its
    /// issuer), a bad self-signature or key; `CertificateTooLarge` beyond the capacities.
    pub fn anchor(cert: &Certificate<'_>) -> Result<Self, DropReason> {
        let key = PublicKey::of_explicit(cert).map_err(|_| DropReason::CertificateInvalid)?;
        if let Issuer::SelfSigned(_) = cert.issuer {
            let digest = signing_digest_with(cert.to_be_signed, &sha256(&[]));
            let signature = cert.signature.ok_or(DropReason::CertificateInvalid)?;
            key.verify(&digest, &signature)
                .map_err(|_| DropReason::CertificateInvalid)?;
        }
        Self::keep(cert, key)
    }

    /// `cert`, issued by `self`, verified and kept: the issuer digest matches, the key
    /// verifies (explicit) or is reconstructed (implicit), the validity lies within the
    /// issuer's, and the issuer may certify each of `psids`.
    ///
    /// # Errors
    ///
    /// [`DropReason::ChainUntrusted`] when `self` is not its issuer, `IssuerPermission`,
    /// `CertificateInvalid`, `UnsupportedAlgorithm` or `CertificateTooLarge`.
    pub fn issue(&self, cert: &Certificate<'_>, psids: &[u32]) -> Result<Self, DropReason> {
        if cert.issuer != Issuer::Sha256Digest(self.id8()) {
            return Err(DropReason::ChainUntrusted);
        }
        if !psids.iter().all(|&p| self.may_issue(p)) {
            return Err(DropReason::IssuerPermission);
        }
        let inside = cert.validity.start_us() >= self.validity.start_us()
            && cert.validity.end_us() <= self.validity.end_us();
        if !inside {
            return Err(DropReason::CertificateInvalid);
        }
        let key = match cert.kind {
            CertificateKind::Explicit => {
                let key = PublicKey::of_explicit(cert).map_err(crypto_reason)?;
                let signature = cert.signature.ok_or(DropReason::CertificateInvalid)?;
                let digest = signing_digest_with(cert.to_be_signed, &self.hash);
                self.key
                    .verify(&digest, &signature)
                    .map_err(crypto_reason)?;
                key
            }
            CertificateKind::Implicit => {
                if cert.signature.is_some() {
                    return Err(DropReason::CertificateInvalid);
                }
                PublicKey::reconstruct(cert, &self.hash, &self.key).map_err(crypto_reason)?
            }
        };
        Self::keep(cert, key)
    }
}

/// The drop reason of a failed certificate check.
fn crypto_reason(e: CryptoError) -> DropReason {
    match e {
        CryptoError::UnsupportedScheme => DropReason::UnsupportedAlgorithm,
        _ => DropReason::CertificateInvalid,
    }
}
