//! "We sign -> the oracle verifies": certificates and signed frames written by the codec's
//! builder (new keys, new times, both rSig forms, digest and certificate signers) are
//! decoded, re-encoded and verified by the independent oracle (pycrate COER + Python
//! `cryptography`, `codec/codegen/oracle_verify_signed.py`); tampered copies must fail
//! there too, so the oracle's check is shown to bite. Needs ../shared (the oracle) and the
//! oracle's `cryptography` package: feature `shared-corpus` (CI).
#![cfg(feature = "shared-corpus")]

use j2735::envelope::hex;
use j2735::envelope::ieee1609dot2::build::{
    encode_certificate, encode_signed, CertificateSpec, Header, IssuedBy, Signer,
};
use j2735::envelope::ieee1609dot2::crypto::{sha256, RSigForm, SecretKey};
use j2735::envelope::ieee1609dot2::{Duration, ThreeDLocation, Time64, TwoDLocation};
use j2735::envelope::Psid;
use std::path::Path;

fn key(label: &str) -> SecretKey {
    SecretKey::from_bytes(&sha256(format!("oracle test/{label}").as_bytes())).unwrap()
}

fn cert(spec: &CertificateSpec<'_>, subject: &SecretKey, by: IssuedBy<'_>) -> Vec<u8> {
    let mut out = vec![0u8; 1024];
    let n = encode_certificate(spec, subject, by, &mut out).unwrap();
    out.truncate(n);
    out
}

fn line(name: &str, kind: &str, coer: &[u8], signer: Option<&[u8]>) -> String {
    let signer = signer.map_or(String::new(), |s| {
        format!(",\"signer\":\"{}\"", hex::Hex(s))
    });
    format!(
        "{{\"name\":\"{name}\",\"kind\":\"{kind}\",\"coer\":\"{}\"{signer}}}\n",
        hex::Hex(coer)
    )
}

#[test]
fn the_oracle_verifies_what_we_sign_and_refuses_what_was_tampered() {
    let (root_key, ca_key, rsu_key) = (key("root"), key("ca"), key("rsu"));
    let start = 700_000_000; // Time32: 2026-03
    let root_spec = CertificateSpec {
        name: "root.oracle.test",
        start,
        duration: Duration::Years(20),
        circle: None,
        app_psids: &[],
        issue_all: Some(2),
        ssp: None,
    };
    let root = cert(&root_spec, &root_key, IssuedBy::SelfSigned);
    let ca_spec = CertificateSpec {
        name: "ca.oracle.test",
        duration: Duration::Years(10),
        issue_all: Some(1),
        ssp: None,
        ..root_spec
    };
    let ca = cert(&ca_spec, &ca_key, IssuedBy::Issuer(&root, &root_key));
    let rsu_spec = CertificateSpec {
        name: "rsu.oracle.test",
        start,
        duration: Duration::Hours(24 * 7),
        circle: Some((
            TwoDLocation {
                latitude: 389_000_000,
                longitude: -771_000_000,
            },
            20_000,
        )),
        app_psids: &[Psid::TIM, Psid::MAP],
        issue_all: None,
        ssp: Some(&[0x01, 0x00, 0x80]),
    };
    let rsu = cert(&rsu_spec, &rsu_key, IssuedBy::Issuer(&ca, &ca_key));
    let frame = test_support::vectors::named("tim_work_zone_left_lane_closed").bytes();
    let mut input = String::new();
    let mut expect = Vec::new();
    let mut add = |name: String, kind: &str, coer: &[u8], signer: Option<&[u8]>, ok: bool| {
        input.push_str(&line(&name, kind, coer, signer));
        expect.push((name, ok));
    };
    add("root".into(), "certificate", &root, None, true);
    add("ca".into(), "certificate", &ca, Some(&root), true);
    add("rsu".into(), "certificate", &rsu, Some(&ca), true);
    let mut bad_rsu = rsu.clone();
    let last = bad_rsu.len() - 1;
    bad_rsu[last] ^= 0x01;
    add(
        "rsu_tampered".into(),
        "certificate",
        &bad_rsu,
        Some(&ca),
        false,
    );
    for (i, (form, signer)) in [
        (RSigForm::XOnly, Signer::Certificate(&rsu)),
        (RSigForm::CompressedY, Signer::Certificate(&rsu)),
        (RSigForm::XOnly, Signer::Digest(&rsu)),
        (RSigForm::CompressedY, Signer::Digest(&rsu)),
    ]
    .into_iter()
    .enumerate()
    {
        for k in 0..3u64 {
            let header = Header {
                psid: Psid::TIM,
                generation_time: Time64(700_000_100_000_000 + i as u64 * 1_000_000 + k * 100_000),
                expiry_time: Some(Time64(700_000_160_000_000)),
                generation_location: (k % 2 == 0).then_some(ThreeDLocation {
                    latitude: 389_001_000,
                    longitude: -771_002_000,
                    elevation: 1200,
                }),
            };
            let mut out = vec![0u8; 4096];
            let n = encode_signed(&frame, &header, signer, &rsu_key, form, &mut out).unwrap();
            out.truncate(n);
            add(format!("data_{i}_{k}"), "data", &out, Some(&rsu), true);
            // A payload bit flipped after signing.
            let mut bad = out.clone();
            bad[10] ^= 0x04;
            add(
                format!("data_{i}_{k}_tampered"),
                "data",
                &bad,
                Some(&rsu),
                false,
            );
        }
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("codegen/oracle_verify_signed.py");
    let out = test_support::oracle::run_script(&script, std::iter::empty::<&str>(), &input);
    let verdicts: Vec<&str> = out.lines().collect();
    assert_eq!(verdicts.len(), expect.len(), "{out}");
    for ((name, ok), verdict) in expect.iter().zip(&verdicts) {
        let (got_name, rest) = verdict.split_once(' ').unwrap();
        assert_eq!(got_name, name);
        assert_eq!(rest == "ok", *ok, "{name}: the oracle says {rest}");
    }
}
