//! The codec's IEEE 1609.2 writer against the independent vectors: with the generator's
//! keys (derived from its seeds by its published rule) and inputs, the certificates and
//! signed frames it writes are byte-for-byte those pycrate and Python `cryptography` made
//! (both sign deterministically, RFC 6979), and what it writes parses back.

use j2735::envelope::ieee1609dot2::build::{
    encode_certificate, encode_signed, CertificateSpec, Header, IssuedBy, Signer,
};
use j2735::envelope::ieee1609dot2::crypto::{sha256, RSigForm, SecretKey};
use j2735::envelope::ieee1609dot2::{
    Duration, Ieee1609Dot2Data, ThreeDLocation, Time64, TwoDLocation,
};
use j2735::envelope::Psid;
use test_support::signed_vectors::{all, SignedVector};

/// The P-256 group order n.
const N: [u8; 32] = [
    0xff, 0xff, 0xff, 0xff, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff,
    0xbc, 0xe6, 0xfa, 0xad, 0xa7, 0x17, 0x9e, 0x84, 0xf3, 0xb9, 0xca, 0xc2, 0xfc, 0x63, 0x25, 0x51,
];

/// Big-endian `a - b` (a >= b).
fn sub(a: &[u8; 32], b: &[u8; 32]) -> [u8; 32] {
    let mut out = [0u8; 32];
    let mut borrow = 0i16;
    for i in (0..32).rev() {
        let d = i16::from(a[i]) - i16::from(b[i]) - borrow;
        borrow = i16::from(d < 0);
        out[i] = (d + 256 * borrow) as u8;
    }
    out
}

/// The generator's key for `seed`: `d = SHA-256("make_signed_vectors/" + seed) mod (n - 1) + 1`.
fn key(seed: &str) -> SecretKey {
    let h = sha256(format!("make_signed_vectors/{seed}").as_bytes());
    let n_minus_1 = sub(&N, &{
        let mut one = [0u8; 32];
        one[31] = 1;
        one
    });
    // h < 2^256 < 2 (n - 1): one subtraction reduces it.
    let reduced = if h >= n_minus_1 {
        sub(&h, &n_minus_1)
    } else {
        h
    };
    let mut d = reduced;
    for i in (0..32).rev() {
        let (v, carry) = d[i].overflowing_add(1);
        d[i] = v;
        if !carry {
            break;
        }
    }
    SecretKey::from_bytes(&d).unwrap()
}

/// `Time32` of a UTC instant given as seconds since 2004-01-01 (plus 5 leap seconds).
fn time32(days_since_2004: u32) -> u32 {
    days_since_2004 * 86_400 + 5
}

/// Days from 2004-01-01 to 2025-01-01 and to 2025-06-01.
const DAYS_2025: u32 = 7671;
const DAYS_2025_06_01: u32 = DAYS_2025 + 31 + 28 + 31 + 30 + 31;

const SITE: TwoDLocation = TwoDLocation {
    latitude: 421_234_567,
    longitude: -837_654_321,
};

fn write_cert(spec: &CertificateSpec<'_>, subject: &SecretKey, issuer: IssuedBy<'_>) -> Vec<u8> {
    let mut out = vec![0u8; 1024];
    let n = encode_certificate(spec, subject, issuer, &mut out).unwrap();
    out.truncate(n);
    out
}

/// The generator's root, CA and RSU certificates, written by the codec.
fn pki() -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    let (root_key, ca_key, rsu_key) = (key("root"), key("ca"), key("rsu"));
    let root = write_cert(
        &CertificateSpec {
            name: "root.workzone.example",
            start: time32(DAYS_2025),
            duration: Duration::Years(10),
            circle: None,
            app_psids: &[],
            issue_all: Some(2),
            ssp: None,
        },
        &root_key,
        IssuedBy::SelfSigned,
    );
    let ca = write_cert(
        &CertificateSpec {
            name: "ca.workzone.example",
            start: time32(DAYS_2025),
            duration: Duration::Years(5),
            circle: None,
            app_psids: &[],
            issue_all: Some(1),
            ssp: None,
        },
        &ca_key,
        IssuedBy::Issuer(&root, &root_key),
    );
    let rsu = write_cert(
        &CertificateSpec {
            name: "rsu-17.workzone.example",
            start: time32(DAYS_2025_06_01),
            duration: Duration::Hours(24 * 30),
            circle: Some((SITE, 5000)),
            app_psids: &[Psid::TIM, Psid::MAP],
            issue_all: None,
            ssp: None,
        },
        &rsu_key,
        IssuedBy::Issuer(&ca, &ca_key),
    );
    (root, ca, rsu)
}

fn named(name: &str) -> SignedVector {
    all().into_iter().find(|v| v.name == name).unwrap()
}

#[test]
fn certificates_are_the_generators_bytes() {
    let v = named("valid_tim_certificate_x_only");
    let (root, ca, rsu) = pki();
    assert_eq!(root, v.root, "root");
    assert_eq!(ca, v.ca, "ca");
    let digest = named("valid_tim_digest_x_only");
    assert_eq!(rsu, digest.known_certs[0], "rsu");
}

fn header_of(v: &SignedVector) -> Header {
    let data = Ieee1609Dot2Data::parse(&v.coer).unwrap();
    let h = data.signed_data().unwrap().header;
    Header {
        psid: Psid(v.psid),
        generation_time: Time64(v.generation_time),
        expiry_time: v.expiry_time.map(Time64),
        generation_location: h.generation_location.map(|l| ThreeDLocation { ..l }),
    }
}

#[test]
fn signed_frames_are_the_generators_bytes() {
    let (_, _, rsu) = pki();
    let rsu_key = key("rsu");
    for (name, signer, form) in [
        (
            "valid_tim_certificate_x_only",
            Signer::Certificate(&rsu),
            RSigForm::XOnly,
        ),
        (
            "valid_tim_certificate_compressed_y",
            Signer::Certificate(&rsu),
            RSigForm::CompressedY,
        ),
        (
            "valid_map_digest_x_only",
            Signer::Digest(&rsu),
            RSigForm::XOnly,
        ),
        (
            "valid_map_digest_compressed_y",
            Signer::Digest(&rsu),
            RSigForm::CompressedY,
        ),
    ] {
        let v = named(name);
        let mut out = vec![0u8; 4096];
        let n = encode_signed(&v.frame, &header_of(&v), signer, &rsu_key, form, &mut out).unwrap();
        assert_eq!(&out[..n], &v.coer[..], "{name}");
    }
}

#[test]
fn a_short_buffer_is_an_error_at_every_length() {
    let (_, _, rsu) = pki();
    let v = named("valid_tim_certificate_x_only");
    let rsu_key = key("rsu");
    for len in 0..v.coer.len() {
        let mut out = vec![0u8; len];
        let signer = Signer::Certificate(&rsu);
        let r = encode_signed(
            &v.frame,
            &header_of(&v),
            signer,
            &rsu_key,
            RSigForm::XOnly,
            &mut out,
        );
        assert!(r.is_err(), "fits in {len}");
    }
}
