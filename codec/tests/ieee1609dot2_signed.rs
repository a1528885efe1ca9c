//! The independent IEEE 1609.2 vectors (pycrate + Python `cryptography`, see
//! `codec/codegen/make_signed_vectors.py`) against the codec's view and crypto: every frame
//! parses to the header the generator wrote, every signature and certificate that the
//! generator made valid verifies, every bit flip fails, implicit keys reconstruct to the
//! generator's key, and every truncation is refused. The trust policy (chain, time,
//! region, permissions, replay) is the OBU's and is tested there with the same vectors.

use j2735::envelope::ieee1609dot2::crypto::{
    hashed_id8, sha256, signing_digest, CryptoError, GeneratorTable, PreparedKey, PublicKey,
};
use j2735::envelope::ieee1609dot2::{
    Certificate, CertificateKind, Ieee1609Dot2Data, Issuer, SignerIdentifier,
};
use j2735::envelope::Psid;
use test_support::signed_vectors::{all, SignedVector};

/// The certificate that signed the vector's data (the end entity), as COER.
fn signer_certificate(v: &SignedVector, data: &Ieee1609Dot2Data<'_>) -> Option<Vec<u8>> {
    match data.signed_data().expect("signed").signer {
        SignerIdentifier::Digest(id) => {
            // The vector's verifier has seen it, or (a digest signer not seen yet) another
            // vector's has.
            let vectors = all();
            let mut known = v
                .known_certs
                .iter()
                .chain(vectors.iter().flat_map(|w| w.known_certs.iter()));
            let found = known.find(|c| hashed_id8(c) == id);
            Some(found.expect("the digest names a known certificate").clone())
        }
        SignerIdentifier::Certificate(chain) => Some(chain.first().unwrap().encoded.to_vec()),
        SignerIdentifier::SelfSigned => None,
    }
}

/// The key of `cert`: explicit, or reconstructed from the CA (every implicit one here is
/// issued by the vectors' CA).
fn key_of(v: &SignedVector, cert: &Certificate<'_>) -> PublicKey {
    match cert.kind {
        CertificateKind::Explicit => PublicKey::of_explicit(cert).unwrap(),
        CertificateKind::Implicit => {
            let ca = Certificate::parse(&v.ca).unwrap();
            assert_eq!(cert.issuer, Issuer::Sha256Digest(hashed_id8(&v.ca)));
            let ca_hash = sha256(&v.ca);
            PublicKey::reconstruct(cert, &ca_hash, &PublicKey::of_explicit(&ca).unwrap()).unwrap()
        }
    }
}

/// Verifies the vector's data signature; the error, if any.
fn verify_data(v: &SignedVector) -> Result<(), CryptoError> {
    let data = Ieee1609Dot2Data::parse(&v.coer).unwrap();
    let signed = data.signed_data().unwrap();
    let cert_bytes = signer_certificate(v, &data);
    let key = match &cert_bytes {
        Some(bytes) => key_of(v, &Certificate::parse(bytes).unwrap()),
        None => PublicKey::from_sec1(v.self_public_key.as_ref().unwrap()).unwrap(),
    };
    let digest = signing_digest(signed.to_be_signed, cert_bytes.as_deref());
    let plain = key.verify(&digest, &signed.signature);
    let prepared = PreparedKey::new(key).verify(&GeneratorTable::new(), &digest, &signed.signature);
    assert_eq!(
        plain, prepared,
        "{}: the prepared key verifies alike",
        v.name
    );
    plain
}

#[test]
fn there_is_a_vector_of_every_case() {
    let vectors = all();
    assert!(vectors.len() >= 34, "{} vectors", vectors.len());
    for case in [
        "payload bit flipped",
        "signature bit flipped",
        "wrong PSID",
        "certificate expired",
        "certificate not yet valid",
        "chain to an untrusted root",
        "region miss",
        "generation time in the future",
        "generation time too old",
        "repeat",
        "misread PSID (p-encoded octets as the integer)",
        "expiry time before generation time",
        "lifetime over the cap",
        "digest signer before its certificate was seen",
        "valid (signed once with an expiry time, generated two hours ago)",
        "valid (implicit certificate, ECQV)",
        "valid (rectangle region)",
        "region miss (rectangle)",
        "valid (polygon region)",
        "region miss (polygon)",
    ] {
        assert!(
            vectors.iter().any(|v| v.case == case),
            "no vector for {case}"
        );
    }
    for signer in ["digest", "certificate", "certificate-chain", "self"] {
        assert!(vectors
            .iter()
            .any(|v| v.signer == signer && v.expect == "valid"));
    }
}

#[test]
fn every_vector_parses_to_the_generators_header_and_frame() {
    for v in all() {
        let data = Ieee1609Dot2Data::parse(&v.coer).unwrap_or_else(|e| panic!("{}: {e}", v.name));
        let signed = data.signed_data().expect("signed");
        assert_eq!(signed.header.psid, Psid(v.psid), "{}", v.name);
        assert_eq!(
            signed.header.generation_time.map(|t| t.0),
            Some(v.generation_time)
        );
        assert_eq!(signed.header.expiry_time.map(|t| t.0), v.expiry_time);
        assert_eq!(data.application_data(), Some(&v.frame[..]), "{}", v.name);
    }
}

#[test]
fn certificates_verify_along_the_chain() {
    let v = &all()[0];
    let root = Certificate::parse(&v.root).unwrap();
    let ca = Certificate::parse(&v.ca).unwrap();
    assert!(matches!(root.issuer, Issuer::SelfSigned(_)));
    let root_key = PublicKey::of_explicit(&root).unwrap();
    let root_digest = signing_digest(root.to_be_signed, None);
    root_key
        .verify(&root_digest, &root.signature.unwrap())
        .unwrap();
    assert_eq!(ca.issuer, Issuer::Sha256Digest(hashed_id8(&v.root)));
    let ca_digest = signing_digest(ca.to_be_signed, Some(&v.root));
    root_key.verify(&ca_digest, &ca.signature.unwrap()).unwrap();
    // The CA's signature does not verify as the root's own (a different hash).
    assert_eq!(
        root_key.verify(&root_digest, &ca.signature.unwrap()),
        Err(CryptoError::BadSignature)
    );
    assert!(root.may_issue(Psid::TIM) && ca.may_issue(Psid::MAP));
}

#[test]
fn data_signatures_verify_unless_a_bit_was_flipped() {
    for v in all() {
        let result = verify_data(&v);
        if v.expect == "signature does not verify" {
            assert_eq!(result, Err(CryptoError::BadSignature), "{}", v.name);
        } else {
            assert_eq!(result, Ok(()), "{}", v.name);
        }
    }
}

#[test]
fn implicit_keys_reconstruct_to_the_generators_key() {
    let mut seen = 0;
    for v in all()
        .iter()
        .filter(|v| v.reconstructed_public_key.is_some())
    {
        let data = Ieee1609Dot2Data::parse(&v.coer).unwrap();
        let bytes = signer_certificate(v, &data).unwrap();
        let cert = Certificate::parse(&bytes).unwrap();
        assert_eq!(cert.kind, CertificateKind::Implicit);
        assert!(cert.signature.is_none());
        let key = key_of(v, &cert);
        assert_eq!(
            &key.to_compressed()[..],
            &v.reconstructed_public_key.clone().unwrap()[..]
        );
        seen += 1;
    }
    assert!(seen >= 6, "{seen} implicit vectors");
}

#[test]
fn signer_certificates_carry_the_permissions_and_region() {
    let v = all()
        .into_iter()
        .find(|v| v.name == "valid_tim_certificate_x_only")
        .unwrap();
    let data = Ieee1609Dot2Data::parse(&v.coer).unwrap();
    let cert_bytes = signer_certificate(&v, &data).unwrap();
    let cert = Certificate::parse(&cert_bytes).unwrap();
    assert!(cert.permission(Psid::TIM).is_some() && cert.permission(Psid::MAP).is_some());
    assert!(cert.permission(Psid::BSM).is_none());
    // The p-encoded octets of TIM and MAP are not the PSIDs a certificate grants.
    assert!(
        cert.permission(Psid(0x8003)).is_none() && cert.permission(Psid(0xE000_0017)).is_none()
    );
    assert!(matches!(
        cert.region,
        Some(j2735::envelope::ieee1609dot2::GeographicRegion::Circular { .. })
    ));
    assert!(cert.validity.contains(v.now));
}

#[test]
fn every_truncation_of_every_vector_is_refused() {
    for v in all() {
        for len in 0..v.coer.len() {
            assert!(
                Ieee1609Dot2Data::parse(&v.coer[..len]).is_err(),
                "{} cut at {len}",
                v.name
            );
        }
        for cert in [&v.root, &v.ca].into_iter().chain(&v.known_certs) {
            for len in 0..cert.len() {
                assert!(
                    Certificate::parse(&cert[..len]).is_err(),
                    "{} cert at {len}",
                    v.name
                );
            }
        }
    }
}
