//! The trust policy against the independent signed vectors (pycrate + Python
//! `cryptography`, `codec/codegen/make_signed_vectors.py`): each case is refused for the
//! reason the generator names, every valid one is accepted, and every truncation is
//! refused before the policy sees it.

use super::*;
use j2735::envelope::ieee1609dot2::Ieee1609Dot2Data;
use std::vec::Vec;
use test_support::signed_vectors::{all, SignedVector};

/// The verdict the generator's words name.
fn expected(v: &SignedVector) -> Result<Accepted, Rejection> {
    Err(match v.expect.as_str() {
        "valid" if v.signer == "self" => Rejection::SelfSigned,
        "valid" => return Ok(Accepted::Verified),
        "valid (repeat)" => return Ok(Accepted::Repeat),
        "PSID is not the message type's" => Rejection::PsidMismatch,
        "signer certificate not known" => Rejection::SignerUnknown,
        "expiry time not after generation time" => Rejection::ExpiryBeforeGeneration,
        "lifetime longer than allowed" => Rejection::LifetimeTooLong,
        "superseded by a newer version" => Rejection::Superseded,
        "signature does not verify" => Rejection::SignatureInvalid,
        "PSID not permitted by the signer certificate" => Rejection::PsidNotPermitted,
        "signer certificate expired" => Rejection::CertificateExpired,
        "signer certificate not yet valid" => Rejection::CertificateNotYetValid,
        "chain does not reach a trust anchor" => Rejection::ChainUntrusted,
        "generation location outside the certificate region" => Rejection::RegionMiss,
        "generation time beyond the future tolerance" => Rejection::GenerationTimeFuture,
        "generation time older than the past window" => Rejection::GenerationTimeOld,
        "message past its expiryTime" => Rejection::MessageExpired,
        other => panic!("{}: unknown expectation {other:?}", v.name),
    })
}

/// The vector's profile for `psid`.
fn profile_of(v: &SignedVector, psid: Psid) -> SecurityProfile {
    SecurityProfile {
        psid,
        future_tolerance_ms: u32::try_from(v.future_tolerance_us / 1000).unwrap(),
        past_window_ms: u32::try_from(v.past_window_us / 1000).unwrap(),
        max_lifetime_ms: v.max_lifetime_us / 1000,
        ..SecurityProfile::TIM
    }
}

/// The vector's security settings (MAP and TIM profiles).
fn config_of(v: &SignedVector) -> SecurityConfig {
    SecurityConfig {
        tim: profile_of(v, Psid::TIM),
        map: profile_of(v, Psid::MAP),
        ..SecurityConfig::DEFAULT
    }
}

/// A verifier with the vector's anchors, profile and known certificates.
fn trust_for(v: &SignedVector) -> Trust {
    let config = config_of(v);
    let mut trust = Trust::new(config);
    trust.add_anchor(&v.root).unwrap();
    trust.add_anchor(&v.ca).unwrap();
    for cert in &v.known_certs {
        trust.learn(cert).unwrap();
    }
    trust
}

/// The `messageId` of the frame inside.
fn message_id(v: &SignedVector) -> u16 {
    j2735::frame::peek_message_id(&v.frame).unwrap()
}

fn check(trust: &mut Trust, v: &SignedVector) -> Result<Accepted, Rejection> {
    let data = Ieee1609Dot2Data::parse(&v.coer).unwrap();
    let ctx = CheckContext {
        message_id: message_id(v),
        now_us: Some(v.now),
        alt_now_us: None,
        position: None,
    };
    trust.check(data.signed_data().unwrap(), &ctx)
}

#[test]
fn every_vector_gets_the_generators_verdict() {
    let vectors = all();
    let mut checked = 0;
    for v in vectors.iter().filter(|v| v.pair.is_none()) {
        let mut trust = trust_for(v);
        assert_eq!(check(&mut trust, v), expected(v), "{}", v.name);
        checked += 1;
    }
    assert!(checked >= 40, "{checked}");
}

/// The two vectors of the repeat pair, first first.
fn repeat_pair(vectors: &[SignedVector]) -> Vec<&SignedVector> {
    let mut pair: Vec<&SignedVector> = vectors
        .iter()
        .filter(|v| v.pair.as_deref() == Some("repeat"))
        .collect();
    pair.sort_by(|a, b| a.name.cmp(&b.name));
    assert_eq!(pair.len(), 2);
    pair
}

#[test]
fn the_repeat_pair_is_verified_then_a_repeat_and_a_replay_where_the_profile_says() {
    let vectors = all();
    let pair = repeat_pair(&vectors);
    let mut trust = trust_for(pair[0]);
    assert_eq!(check(&mut trust, pair[0]), Ok(Accepted::Verified));
    assert_eq!(check(&mut trust, pair[1]), expected(pair[1]));
    assert_eq!(check(&mut trust, pair[1]), Ok(Accepted::Repeat));
    assert_eq!(trust.remembered(), 1);
    // A profile whose copies are replays (PSM's default).
    let mut strict = trust_for(pair[0]);
    let mut config = config_of(pair[0]);
    config.tim.duplicates = Duplicates::Replay;
    strict.set_config(config);
    assert_eq!(check(&mut strict, pair[0]), Ok(Accepted::Verified));
    assert_eq!(check(&mut strict, pair[1]), Err(Rejection::Replay));
}

#[test]
fn a_tim_signed_once_is_repeated_until_its_expiry_and_then_forgotten() {
    let vectors = all();
    let v = vectors
        .iter()
        .find(|v| v.name == "valid_tim_signed_once_expiry_ahead")
        .unwrap();
    let expiry = v.expiry_time.unwrap();
    let mut trust = trust_for(v);
    let data = Ieee1609Dot2Data::parse(&v.coer).unwrap();
    let at = |now_us| CheckContext {
        message_id: 31,
        now_us: Some(now_us),
        alt_now_us: None,
        position: None,
    };
    let signed = data.signed_data().unwrap();
    assert_eq!(trust.check(signed, &at(v.now)), Ok(Accepted::Verified));
    for hour in 1..20 {
        let now = v.now + hour * 3_600_000_000;
        assert_eq!(
            trust.check(signed, &at(now)),
            Ok(Accepted::Repeat),
            "{hour} h"
        );
    }
    let tolerance = v.future_tolerance_us;
    assert_eq!(
        trust.check(signed, &at(expiry + tolerance)),
        Ok(Accepted::Repeat)
    );
    assert_eq!(
        trust.check(signed, &at(expiry + tolerance + 1)),
        Err(Rejection::MessageExpired)
    );
    // Another message accepted after the expiry: the expired one is forgotten.
    let other = vectors
        .iter()
        .find(|v| v.name == "valid_map_signed_once_expiry_ahead")
        .unwrap();
    let other = Ieee1609Dot2Data::parse(&other.coer).unwrap();
    let map_at = CheckContext {
        message_id: 18,
        ..at(expiry - 1_000_000)
    };
    assert_eq!(
        trust.check(other.signed_data().unwrap(), &map_at),
        Ok(Accepted::Verified)
    );
    assert_eq!(trust.remembered(), 2);
    let later = CheckContext {
        message_id: 18,
        ..at(expiry + tolerance + 2)
    };
    assert_eq!(
        trust.check(other.signed_data().unwrap(), &later),
        Err(Rejection::MessageExpired)
    );
}

#[test]
fn a_repeat_still_needs_its_certificate_and_psid() {
    let vectors = all();
    let pair = repeat_pair(&vectors);
    let mut trust = trust_for(pair[0]);
    assert_eq!(check(&mut trust, pair[0]), Ok(Accepted::Verified));
    // The same bytes as a MAP: the PSID is TIM's, refused before the repeat cache answers.
    let data = Ieee1609Dot2Data::parse(&pair[1].coer).unwrap();
    let as_map = CheckContext {
        message_id: 18,
        now_us: Some(pair[1].now),
        alt_now_us: None,
        position: None,
    };
    assert_eq!(
        trust.check(data.signed_data().unwrap(), &as_map),
        Err(Rejection::PsidMismatch)
    );
}

#[test]
fn a_certificate_signer_is_cached_so_its_digest_verifies() {
    let vectors = all();
    let by_name = |n: &str| vectors.iter().find(|v| v.name == n).unwrap();
    let cert = by_name("valid_tim_certificate_x_only");
    // The MAP: the TIM by digest would be the same signed data as `cert` (same header,
    // payload and signer certificate, so the same hash): a repeat, not a digest lookup.
    let digest = by_name("valid_map_digest_x_only");
    let config = SecurityConfig::DEFAULT;
    let mut trust = Trust::new(config);
    trust.add_anchor(&cert.ca).unwrap();
    // Not seen yet: the digest names nothing.
    assert_eq!(check(&mut trust, digest), Err(Rejection::SignerUnknown));
    assert_eq!(check(&mut trust, cert), Ok(Accepted::Verified));
    assert_eq!(trust.cached(), 1);
    assert_eq!(check(&mut trust, digest), Ok(Accepted::Verified));
}

#[test]
fn without_anchors_nothing_verifies() {
    let v = all()
        .into_iter()
        .find(|v| v.name == "valid_tim_certificate_chain_x_only");
    let v = v.unwrap();
    let mut trust = Trust::default();
    assert_eq!(check(&mut trust, &v), Err(Rejection::ChainUntrusted));
    let mut root_only = Trust::default();
    root_only.add_anchor(&v.root).unwrap();
    assert_eq!(
        check(&mut root_only, &v),
        Ok(Accepted::Verified),
        "the chain carries the CA"
    );
}

#[test]
fn a_psid_of_another_message_is_refused() {
    let vectors = all();
    let map = vectors
        .iter()
        .find(|v| v.name == "valid_map_certificate_x_only")
        .unwrap();
    let mut trust = trust_for(map);
    let data = Ieee1609Dot2Data::parse(&map.coer).unwrap();
    let ctx = CheckContext {
        message_id: 31, // a TIM id with the MAP PSID
        now_us: Some(map.now),
        alt_now_us: None,
        position: None,
    };
    let result = trust.check(data.signed_data().unwrap(), &ctx);
    assert_eq!(result, Err(Rejection::PsidMismatch));
    let no_time = CheckContext {
        now_us: None,
        alt_now_us: None,
        ..ctx
    };
    let result = trust.check(data.signed_data().unwrap(), &no_time);
    assert_eq!(result, Err(Rejection::NoTime));
}

#[test]
fn anchors_must_be_explicit_and_self_signatures_verify() {
    let v = &all()[0];
    let mut trust = Trust::default();
    assert_eq!(trust.add_anchor(&v.root[1..]), Err(AnchorError::Malformed));
    let mut bad = v.root.clone();
    let last = bad.len() - 1;
    bad[last] ^= 1; // the self-signature's s
    assert!(matches!(
        trust.add_anchor(&bad),
        Err(AnchorError::Invalid(_))
    ));
    trust.add_anchor(&v.root).unwrap();
    trust.add_anchor(&v.root).unwrap(); // the same again: one anchor
    assert_eq!(trust.anchors(), 1);
}

/// The same TIM signed again by an attacker key under the real RSU certificate, with a new
/// generation time: its signature does not verify.
fn forged_copy(v: &SignedVector, generated_us: u64) -> Vec<u8> {
    use j2735::envelope::ieee1609dot2::build::Header;
    use j2735::envelope::ieee1609dot2::crypto::SecretKey;
    use j2735::envelope::ieee1609dot2::{SignerIdentifier, Time64};
    let data = Ieee1609Dot2Data::parse(&v.coer).unwrap();
    let signed = data.signed_data().unwrap();
    let SignerIdentifier::Certificate(chain) = signed.signer else {
        panic!("a certificate signer");
    };
    let cert = chain.first().unwrap().encoded;
    let header = Header {
        psid: signed.header.psid,
        generation_time: Time64(generated_us),
        expiry_time: signed.header.expiry_time,
        generation_location: signed.header.generation_location,
    };
    let attacker = SecretKey::from_bytes(&[7u8; 32]).unwrap();
    sign(&v.frame, &header, cert, &attacker)
}

/// `frame` signed with `key` under the signer certificate `cert` (x-only `rSig`).
fn sign(
    frame: &[u8],
    header: &j2735::envelope::ieee1609dot2::build::Header,
    cert: &[u8],
    key: &j2735::envelope::ieee1609dot2::crypto::SecretKey,
) -> Vec<u8> {
    use j2735::envelope::ieee1609dot2::build::{encode_signed, Signer};
    use j2735::envelope::ieee1609dot2::crypto::RSigForm;
    let mut out = std::vec![0u8; 4096];
    let n = encode_signed(
        frame,
        header,
        Signer::Certificate(cert),
        key,
        RSigForm::XOnly,
        &mut out,
    )
    .unwrap();
    out.truncate(n);
    out
}

#[test]
fn a_payload_verified_lately_is_taken_again_only_within_reverify_ms() {
    let v = all()
        .into_iter()
        .find(|v| v.name == "valid_tim_certificate_x_only")
        .unwrap();
    let forged = forged_copy(&v, v.generation_time + 500_000);
    let forged = Ieee1609Dot2Data::parse(&forged).unwrap();
    let at = |now_us| CheckContext {
        message_id: 31,
        now_us: Some(now_us),
        alt_now_us: None,
        position: None,
    };
    // Verified once at `now`: the same payload half a second later is taken without its
    // (forged) signature being verified; a second and a half later it is verified again.
    let mut trust = trust_for(&v);
    assert_eq!(check(&mut trust, &v), Ok(Accepted::Verified));
    let lately = trust.clone();
    assert_eq!(
        trust.check(forged.signed_data().unwrap(), &at(v.now + 500_000)),
        Ok(Accepted::Verified)
    );
    let mut later = lately.clone();
    assert_eq!(
        later.check(forged.signed_data().unwrap(), &at(v.now + 1_500_000)),
        Err(Rejection::SignatureInvalid)
    );
    // With reverify_ms 0 every frame is verified.
    let mut strict = trust_for(&v);
    strict.set_config(SecurityConfig {
        reverify_ms: 0,
        ..config_of(&v)
    });
    assert_eq!(check(&mut strict, &v), Ok(Accepted::Verified));
    assert_eq!(
        strict.check(forged.signed_data().unwrap(), &at(v.now + 500_000)),
        Err(Rejection::SignatureInvalid)
    );
    // Never seen verified: a forged payload is verified (and refused).
    let mut fresh = trust_for(&v);
    assert_eq!(
        fresh.check(forged.signed_data().unwrap(), &at(v.now + 500_000)),
        Err(Rejection::SignatureInvalid)
    );
}

/// A root and an RSU certificate under it (TIM PSID, SSP 01 20) made with the codec's
/// writer, and a signer of TIMs with the RSU key.
struct TestPki {
    root: Vec<u8>,
    rsu: Vec<u8>,
    rsu_key: j2735::envelope::ieee1609dot2::crypto::SecretKey,
}

impl TestPki {
    fn new() -> Self {
        use j2735::envelope::ieee1609dot2::build::{encode_certificate, CertificateSpec, IssuedBy};
        use j2735::envelope::ieee1609dot2::crypto::SecretKey;
        use j2735::envelope::ieee1609dot2::Duration;
        let root_key = SecretKey::from_bytes(&[3u8; 32]).unwrap();
        let rsu_key = SecretKey::from_bytes(&[4u8; 32]).unwrap();
        let write = |spec: &CertificateSpec<'_>, key: &SecretKey, by: IssuedBy<'_>| {
            let mut out = std::vec![0u8; 512];
            let n = encode_certificate(spec, key, by, &mut out).unwrap();
            out.truncate(n);
            out
        };
        let root_spec = CertificateSpec {
            name: "root.ssp.test",
            start: 690_000_000,
            duration: Duration::Years(10),
            circle: None,
            app_psids: &[],
            issue_all: Some(1),
            ssp: None,
        };
        let root = write(&root_spec, &root_key, IssuedBy::SelfSigned);
        let rsu_spec = CertificateSpec {
            name: "rsu.ssp.test",
            app_psids: &[Psid::TIM],
            issue_all: None,
            ssp: Some(&[0x01, 0x20]),
            ..root_spec
        };
        let rsu = write(&rsu_spec, &rsu_key, IssuedBy::Issuer(&root, &root_key));
        TestPki { root, rsu, rsu_key }
    }

    /// The committed work-zone TIM signed by the RSU at `generated_us`.
    fn signed_tim(&self, generated_us: u64) -> Vec<u8> {
        use j2735::envelope::ieee1609dot2::build::Header;
        use j2735::envelope::ieee1609dot2::Time64;
        let frame = test_support::vectors::named("tim_work_zone_left_lane_closed").bytes();
        let header = Header {
            psid: Psid::TIM,
            generation_time: Time64(generated_us),
            expiry_time: None,
            generation_location: None,
        };
        sign(&frame, &header, &self.rsu, &self.rsu_key)
    }
}

#[test]
fn with_two_clocks_a_replay_is_caught_while_either_clock_could_take_it() {
    // GNSS time 40 s behind the system clock (unverified time), a profile whose copies are
    // replays: a TIM generated at T is taken on the system clock; a later one taken on it
    // moves the system clock's window past T; T replayed 36 s later is within the past
    // window on GNSS time (T - 4 s) and must still be caught.
    let pki = TestPki::new();
    let mut config = SecurityConfig::DEFAULT;
    config.tim.duplicates = Duplicates::Replay;
    let mut trust = Trust::new(config);
    trust.add_anchor(&pki.root).unwrap();
    let t = 700_000_000_000_000u64;
    let at = |system: u64| CheckContext {
        message_id: 31,
        now_us: Some(system - 40_000_000),
        alt_now_us: Some(system),
        position: None,
    };
    let first = pki.signed_tim(t);
    let first = Ieee1609Dot2Data::parse(&first).unwrap();
    let later = pki.signed_tim(t + 35_000_000);
    let later = Ieee1609Dot2Data::parse(&later).unwrap();
    assert_eq!(
        trust.check(first.signed_data().unwrap(), &at(t)),
        Ok(Accepted::Verified)
    );
    assert_eq!(
        trust.check(later.signed_data().unwrap(), &at(t + 35_000_000)),
        Ok(Accepted::Verified)
    );
    assert_eq!(
        trust.check(first.signed_data().unwrap(), &at(t + 36_000_000)),
        Err(Rejection::Replay)
    );
    // Old on both clocks: refused as old.
    assert_eq!(
        trust.check(first.signed_data().unwrap(), &at(t + 80_000_000)),
        Err(Rejection::GenerationTimeOld)
    );
}

#[test]
fn a_required_ssp_must_be_granted_byte_for_byte() {
    let pki = TestPki::new();
    let out = pki.signed_tim(700_000_000_000_000);
    let root = pki.root.clone();
    let n = out.len();
    let data = Ieee1609Dot2Data::parse(&out[..n]).unwrap();
    let ctx = CheckContext {
        message_id: 31,
        now_us: Some(700_000_001_000_000),
        alt_now_us: None,
        position: None,
    };
    let with = |ssp: &[u8]| {
        let mut config = SecurityConfig::DEFAULT;
        config.tim.ssp = RequiredSsp::new(ssp).unwrap();
        let mut trust = Trust::new(config);
        trust.add_anchor(&root).unwrap();
        trust.check(data.signed_data().unwrap(), &ctx)
    };
    assert_eq!(with(&[]), Ok(Accepted::Verified), "no SSP required");
    assert_eq!(
        with(&[0x01, 0x20]),
        Ok(Accepted::Verified),
        "the granted SSP"
    );
    assert_eq!(with(&[0x01, 0x21]), Err(Rejection::SspNotPermitted));
    assert_eq!(with(&[0x01]), Err(Rejection::SspNotPermitted));
    assert!(RequiredSsp::new(&[0u8; 17]).is_none());
}
