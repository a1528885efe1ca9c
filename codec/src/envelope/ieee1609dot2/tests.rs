//! Tests of the IEEE 1609.2 view and the unsecured encoder: each kind of data and signer,
//! the strictness errors, and truncated, flipped and random inputs.

extern crate std;

use super::*;
use std::vec;
use std::vec::Vec;

/// A made-up UPER payload (not a real J2735 message).
const PAYLOAD: [u8; 5] = [0x00, 0x14, 0xaa, 0xbb, 0xcc];
const DIGEST: [u8; 8] = [1, 2, 3, 4, 5, 6, 7, 8];

fn unsecured(payload: &[u8]) -> Vec<u8> {
    let mut out = vec![0u8; unsecured_encoded_len(payload.len())];
    let written = encode_unsecured(payload, &mut out).unwrap();
    assert_eq!(written, out.len());
    out
}

/// `03 81`, SHA-256, a payload holding `inner`, a header with `psid` and a generation
/// time, a digest signer and an x-only NIST P-256 signature.
fn signed_with_digest(inner: &[u8], psid: &[u8]) -> Vec<u8> {
    let mut out = vec![0x03, 0x81, 0x00, 0x40];
    out.extend_from_slice(inner);
    out.push(0x40); // HeaderInfo preamble: generationTime present
    out.extend_from_slice(psid);
    out.extend_from_slice(&[0, 0, 0, 0x01, 0x02, 0x03, 0x04, 0x05]);
    out.push(0x80);
    out.extend_from_slice(&DIGEST);
    out.extend_from_slice(&[0x80, 0x80]);
    out.extend_from_slice(&[0x11; 32]);
    out.extend_from_slice(&[0x22; 32]);
    out
}

/// An implicit certificate: no id, one `PsidSsp` (0x20), compressed reconstruction value.
fn implicit_certificate() -> Vec<u8> {
    let mut out = vec![0x00, 0x03, 0x01, 0x80];
    out.extend_from_slice(&DIGEST);
    out.extend_from_slice(&[0x10, 0x83, 0xaa, 0xbb, 0xcc, 0x00, 0x01]);
    out.extend_from_slice(&[0x01, 0x02, 0x03, 0x04, 0x84, 0x00, 0x10]);
    out.extend_from_slice(&[0x01, 0x01, 0x00, 0x01, 0x20]);
    out.extend_from_slice(&[0x81, 0x82]);
    out.extend_from_slice(&[0x33; 32]);
    out
}

/// Signed data with a full header, a one-certificate signer and a compressed-y-1 `r`.
fn signed_with_certificate() -> Vec<u8> {
    let mut out = vec![0x03, 0x81, 0x00, 0x40];
    out.extend_from_slice(&unsecured(&PAYLOAD));
    out.push(0x70); // generationTime, expiryTime, generationLocation
    out.extend_from_slice(&[0x01, 0x20]);
    out.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0x10, 0x00]);
    out.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0x20, 0x00]);
    out.extend_from_slice(&[0x19, 0x08, 0xb1, 0x00, 0xce, 0x87, 0x34, 0x80, 0x01, 0x00]);
    out.extend_from_slice(&[0x81, 0x01, 0x01]);
    out.extend_from_slice(&implicit_certificate());
    out.extend_from_slice(&[0x80, 0x83]);
    out.extend_from_slice(&[0x44; 32]);
    out.extend_from_slice(&[0x55; 32]);
    out
}

fn error_kind(bytes: &[u8]) -> DecodeErrorKind {
    Ieee1609Dot2Data::parse(bytes).unwrap_err().kind
}

#[test]
fn unsecured_short_form() {
    let bytes = [0x03, 0x80, 0x05, 0x00, 0x14, 0xaa, 0xbb, 0xcc];
    let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
    assert_eq!(data.content(), &Content::Unsecured(&PAYLOAD));
    assert_eq!(data.application_data(), Some(&PAYLOAD[..]));
    assert_eq!(data.application_data_offset(), Some(3));
    assert!(!data.is_signed());
    assert_eq!(data.encoded(), &bytes[..]);
}

#[test]
fn unsecured_encoding_uses_canonical_lengths() {
    assert_eq!(
        unsecured(&PAYLOAD),
        [&[0x03, 0x80, 0x05][..], &PAYLOAD].concat()
    );
    let long = vec![0x5a; 0x120];
    let encoded = unsecured(&long);
    assert_eq!(&encoded[..5], &[0x03, 0x80, 0x82, 0x01, 0x20]);
    assert_eq!(unsecured_encoded_len(0), 3);
    assert_eq!(unsecured_encoded_len(127), 130);
    assert_eq!(unsecured_encoded_len(128), 132);
    assert_eq!(unsecured_encoded_len(65_536), 65_536 + 6);
}

#[test]
fn unsecured_round_trip_at_length_boundaries() {
    for len in [0usize, 1, 127, 128, 255, 256, 65_535, 65_536] {
        let payload: Vec<u8> = (0..len).map(|i| i.to_le_bytes()[0]).collect();
        let encoded = unsecured(&payload);
        let data = Ieee1609Dot2Data::parse(&encoded).unwrap();
        assert_eq!(data.application_data(), Some(&payload[..]), "length {len}");
    }
}

#[test]
fn encoder_reports_small_buffer() {
    let mut out = [0u8; 7];
    let error = encode_unsecured(&PAYLOAD, &mut out).unwrap_err();
    assert_eq!(
        error,
        BufferTooSmall {
            needed: 8,
            available: 7
        }
    );
}

#[test]
fn signed_with_digest_signer() {
    let bytes = signed_with_digest(&unsecured(&PAYLOAD), &[0x01, 0x83]);
    let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
    assert!(data.is_signed());
    assert_eq!(data.application_data(), Some(&PAYLOAD[..]));
    assert_eq!(data.application_data_offset(), Some(7));
    let signed = data.signed_data().unwrap();
    assert_eq!(signed.hash_algorithm, HashAlgorithm::Sha256);
    assert_eq!(signed.header.psid, Psid::TIM);
    assert_eq!(
        signed.header.generation_time,
        Some(Time64(0x0001_0203_0405))
    );
    assert_eq!(signed.header.expiry_time, None);
    assert_eq!(signed.signer, SignerIdentifier::Digest(DIGEST));
    assert_eq!(signed.signature.scheme, SignatureScheme::EcdsaNistP256);
    assert_eq!(signed.signature.r.form, PointForm::XOnly);
    assert_eq!(signed.signature.r.x, &[0x11; 32]);
    assert_eq!(signed.signature.s, &[0x22; 32]);
    assert_eq!(signed.to_be_signed, &bytes[3..bytes.len() - 9 - 66]);
    let inner = signed.payload.data.unwrap();
    assert_eq!(inner.offset(), 4);
    assert_eq!(
        inner.parse().unwrap().content(),
        &Content::Unsecured(&PAYLOAD)
    );
}

#[test]
fn signed_with_certificate_signer() {
    let bytes = signed_with_certificate();
    let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
    let signed = data.signed_data().unwrap();
    assert_eq!(data.application_data(), Some(&PAYLOAD[..]));
    let header = signed.header;
    assert_eq!(header.psid, Psid::BSM);
    assert_eq!(header.generation_time, Some(Time64(0x1000)));
    assert_eq!(header.expiry_time, Some(Time64(0x2000)));
    let location = header.generation_location.unwrap();
    assert_eq!(location.latitude, 420_000_000);
    assert_eq!(location.longitude, -830_000_000);
    assert_eq!(location.elevation, 0x0100);
    let SignerIdentifier::Certificate(chain) = signed.signer else {
        panic!("expected a certificate signer");
    };
    assert_eq!(chain.len(), 1);
    assert_eq!(
        chain.first().map(|c| c.encoded),
        Some(&implicit_certificate()[..])
    );
    assert_eq!(chain.iter().count(), 1);
    assert_eq!(signed.signature.r.form, PointForm::CompressedY1);
    assert_eq!(signed.signature.s, &[0x55; 32]);
}

#[test]
fn self_signed_and_other_curves() {
    let mut bytes = vec![0x03, 0x81, 0x01, 0x40];
    bytes.extend_from_slice(&unsecured(&PAYLOAD));
    bytes.extend_from_slice(&[0x00, 0x01, 0x20, 0x82]);
    // ecdsaNistP384Signature is an extension alternative: tag 0x83, open type.
    bytes.extend_from_slice(&[0x83, 0x81, 0x91, 0x84]);
    bytes.extend_from_slice(&[0x66; 96]);
    bytes.extend_from_slice(&[0x77; 48]);
    let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
    let signed = data.signed_data().unwrap();
    assert_eq!(signed.hash_algorithm, HashAlgorithm::Sha384);
    assert_eq!(signed.signer, SignerIdentifier::SelfSigned);
    assert_eq!(signed.signature.scheme, SignatureScheme::EcdsaNistP384);
    assert_eq!(signed.signature.r.form, PointForm::Uncompressed);
    assert_eq!(signed.signature.r.y, Some(&[0x66; 48][..]));
    assert_eq!(signed.signature.s, &[0x77; 48]);
}

#[test]
fn header_extension_additions_are_kept_raw() {
    let mut bytes = vec![0x03, 0x81, 0x00, 0x40];
    bytes.extend_from_slice(&unsecured(&PAYLOAD));
    // Extension bit set; bitmap of 3 bits with pduFunctionalType (third) present.
    let extensions = [0x02, 0x05, 0x20, 0x01, 0x01];
    bytes.extend_from_slice(&[0x80, 0x01, 0x20]);
    bytes.extend_from_slice(&extensions);
    bytes.push(0x82);
    bytes.extend_from_slice(&[0x80, 0x80]);
    bytes.extend_from_slice(&[0x11; 64]);
    let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
    let header = data.signed_data().unwrap().header;
    assert_eq!(header.extension_additions, Some(&extensions[..]));
    assert_eq!(header.generation_time, None);
}

#[test]
fn nested_signed_layers_reach_the_payload() {
    let inner = signed_with_digest(&unsecured(&PAYLOAD), &[0x01, 0x20]);
    let outer = signed_with_digest(&inner, &[0x01, 0x23]);
    let data = Ieee1609Dot2Data::parse(&outer).unwrap();
    assert_eq!(data.application_data(), Some(&PAYLOAD[..]));
    assert_eq!(data.application_data_offset(), Some(4 + 7));
    assert_eq!(data.signed_data().unwrap().header.psid, Psid(0x23));
}

#[test]
fn nesting_is_bounded() {
    let mut bytes = unsecured(&PAYLOAD);
    for _ in 1..MAX_NESTING_DEPTH {
        bytes = signed_with_digest(&bytes, &[0x01, 0x20]);
    }
    assert!(Ieee1609Dot2Data::parse(&bytes).is_ok());
    bytes = signed_with_digest(&bytes, &[0x01, 0x20]);
    let error = Ieee1609Dot2Data::parse(&bytes).unwrap_err();
    assert_eq!(error.kind, DecodeErrorKind::NestingTooDeep);
    assert_eq!(error.offset, 4 * MAX_NESTING_DEPTH);
}

#[test]
fn external_hash_without_data() {
    let mut bytes = vec![0x03, 0x81, 0x00, 0x20, 0x80];
    bytes.extend_from_slice(&[0x99; 32]);
    bytes.extend_from_slice(&[0x00, 0x01, 0x20, 0x82, 0x80, 0x80]);
    bytes.extend_from_slice(&[0x11; 64]);
    let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
    let payload = data.signed_data().unwrap().payload;
    assert_eq!(payload.data, None);
    let hash = payload.external_data_hash.unwrap();
    assert_eq!(hash.algorithm, HashAlgorithm::Sha256);
    assert_eq!(hash.digest, &[0x99; 32]);
    assert_eq!(data.application_data(), None);
}

#[test]
fn empty_signed_payload_is_rejected() {
    let bytes = [0x03, 0x81, 0x00, 0x00, 0x00, 0x01, 0x20];
    assert_eq!(error_kind(&bytes), DecodeErrorKind::EmptySignedPayload);
}

#[test]
fn encrypted_data_is_walked() {
    let mut bytes = vec![0x03, 0x82, 0x01, 0x01, 0x80];
    bytes.extend_from_slice(&DIGEST);
    bytes.push(0x80);
    bytes.extend_from_slice(&[0x00; 12]);
    bytes.extend_from_slice(&[0x03, 0xaa, 0xbb, 0xcc]);
    let data = Ieee1609Dot2Data::parse(&bytes).unwrap();
    assert_eq!(data.content(), &Content::Encrypted(&bytes[2..]));
    assert_eq!(data.application_data(), None);
}

#[test]
fn structural_errors_name_kind_and_offset() {
    let error = Ieee1609Dot2Data::parse(&[0x02, 0x80, 0x00]).unwrap_err();
    assert_eq!(
        error,
        DecodeError::new(DecodeErrorKind::UnsupportedVersion, 0)
    );
    let error = Ieee1609Dot2Data::parse(&[0x03, 0x85, 0x00]).unwrap_err();
    assert_eq!(
        error,
        DecodeError::new(DecodeErrorKind::UnknownAlternative, 1)
    );
    let error = Ieee1609Dot2Data::parse(&[0x03, 0x80, 0x05, 0x00, 0x14]).unwrap_err();
    assert_eq!(error, DecodeError::new(DecodeErrorKind::UnexpectedEnd, 3));
    let error = Ieee1609Dot2Data::parse(&[0x03, 0x80, 0x01, 0x00, 0xff]).unwrap_err();
    assert_eq!(error, DecodeError::new(DecodeErrorKind::TrailingBytes, 4));
    let error = Ieee1609Dot2Data::parse(&[0x03, 0x80, 0x81, 0x05]).unwrap_err();
    assert_eq!(error, DecodeError::new(DecodeErrorKind::NonCanonical, 2));
    let big_psid = signed_with_digest(&unsecured(&PAYLOAD), &[0x05, 1, 0, 0, 0, 0]);
    assert_eq!(error_kind(&big_psid), DecodeErrorKind::ValueOutOfRange);
    assert_eq!(Ieee1609Dot2Data::parse(&[]).unwrap_err().offset, 0);
}

#[test]
fn parse_prefix_reports_the_length_used() {
    let mut bytes = unsecured(&PAYLOAD);
    let used = bytes.len();
    bytes.extend_from_slice(&[0xde, 0xad]);
    let (data, length) = Ieee1609Dot2Data::parse_prefix(&bytes).unwrap();
    assert_eq!(length, used);
    assert_eq!(data.application_data(), Some(&PAYLOAD[..]));
}

#[test]
fn error_display_names_kind_and_offset() {
    let text = std::format!("{}", DecodeError::new(DecodeErrorKind::UnexpectedEnd, 7));
    assert_eq!(text, "IEEE 1609.2: unexpected end at byte 7");
}

#[test]
fn detection_by_first_bytes() {
    assert!(looks_like_ieee1609dot2(&[0x03, 0x80, 0x00]));
    assert!(looks_like_ieee1609dot2(&[0x03, 0x81]));
    assert!(!looks_like_ieee1609dot2(&[0x00, 0x14, 0x25]));
    assert!(!looks_like_ieee1609dot2(&[0x03]));
    assert!(!looks_like_ieee1609dot2(&[0x03, 0x00]));
    assert!(!looks_like_ieee1609dot2(&[]));
}

/// Every fixture used by the robustness tests.
fn fixtures() -> Vec<Vec<u8>> {
    let nested = signed_with_digest(
        &signed_with_digest(&unsecured(&PAYLOAD), &[0x01, 0x20]),
        &[0x02, 0x80, 0x03],
    );
    vec![
        unsecured(&PAYLOAD),
        unsecured(&[0x5a; 300]),
        signed_with_digest(&unsecured(&PAYLOAD), &[0x02, 0x80, 0x03]),
        signed_with_certificate(),
        nested,
    ]
}

#[test]
fn every_truncation_is_an_error() {
    for bytes in fixtures() {
        assert!(Ieee1609Dot2Data::parse(&bytes).is_ok());
        for len in 0..bytes.len() {
            let error = Ieee1609Dot2Data::parse(&bytes[..len]).unwrap_err();
            assert!(error.offset <= len, "offset {} beyond {len}", error.offset);
        }
    }
}

#[test]
fn bit_flips_never_panic() {
    for bytes in fixtures() {
        for index in 0..bytes.len() {
            for bit in 0..8 {
                let mut flipped = bytes.clone();
                flipped[index] ^= 1 << bit;
                if let Ok(data) = Ieee1609Dot2Data::parse(&flipped) {
                    exercise(&data);
                }
            }
        }
    }
}

#[test]
fn random_inputs_never_panic() {
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for _ in 0..20_000 {
        let len = usize::from(next().to_le_bytes()[0] % 96);
        let mut bytes: Vec<u8> = (0..len).map(|_| next().to_le_bytes()[0]).collect();
        if bytes.len() >= 2 {
            bytes[0] = PROTOCOL_VERSION;
            bytes[1] = 0x80 | (bytes[1] % 5);
        }
        if let Ok(data) = Ieee1609Dot2Data::parse(&bytes) {
            exercise(&data);
        }
    }
}

/// Calls every accessor of a successfully parsed value.
fn exercise(data: &Ieee1609Dot2Data<'_>) {
    let _ = (data.application_data(), data.application_data_offset());
    if let Some(signed) = data.signed_data() {
        if let Some(inner) = signed.payload.data {
            assert!(inner.parse().is_ok());
        }
        if let SignerIdentifier::Certificate(chain) = signed.signer {
            assert_eq!(chain.iter().count(), chain.len());
        }
    }
}
