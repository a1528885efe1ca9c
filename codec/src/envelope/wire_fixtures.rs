//! Literal IEEE 1609.2 envelopes, written octet by octet from the standard's COER layout
//! (IEEE Std 1609.2, `Ieee1609Dot2Data` and its parts; ITU-T X.696 for the encoding), not
//! produced by the code under test. Each is unwrapped by [`unwrap_message_frame`] and parsed
//! by [`Ieee1609Dot2Data::parse`]; the unsecured ones are also what [`encode_unsecured`]
//! writes, byte for byte.
//!
//! COER reminders: a CHOICE alternative is one tag octet, `0b10` (context class) then the
//! alternative's index (`0x80` the first, `0x81` the second); a SEQUENCE with OPTIONAL
//! components or an extension marker starts with a preamble octet (the extension bit first
//! when there is a marker, then one presence bit per OPTIONAL, zero padded); an OCTET
//! STRING without a fixed size has a length: one octet below 128, else `0x80 | n` and the
//! length in `n` octets; fixed-size strings and `Uint8`/`Uint64` have no length.

extern crate std;

use std::vec;
use std::vec::Vec;

use super::ieee1609dot2::{
    encode_unsecured, unsecured_encoded_len, Content, HashAlgorithm, Ieee1609Dot2Data, PointForm,
    SignatureScheme, SignerIdentifier, Time64,
};
use super::{unwrap_message_frame, EnvelopeKind};

/// A stand-in application payload of `n` octets (its content does not matter here).
fn payload(n: usize) -> Vec<u8> {
    (0..n).map(|i| (i % 251) as u8).collect()
}

/// Checks that `wire` is unsecured data around `frame`, found at `offset`, and that our
/// encoder writes exactly `wire` for `frame`.
fn check_unsecured(wire: &[u8], frame: &[u8], offset: usize) {
    let found = unwrap_message_frame(wire).unwrap();
    assert_eq!(found.envelope, EnvelopeKind::Unsecured);
    assert_eq!((found.frame, found.offset), (frame, offset));
    let data = Ieee1609Dot2Data::parse(wire).unwrap();
    assert_eq!(data.content(), &Content::Unsecured(frame));
    assert!(!data.is_signed());

    assert_eq!(unsecured_encoded_len(frame.len()), wire.len());
    let mut out = vec![0u8; wire.len()];
    assert_eq!(encode_unsecured(frame, &mut out), Ok(wire.len()));
    assert_eq!(out, wire);
}

#[test]
fn unsecured_short_length() {
    let frame = [0x00, 0x14, 0x25];
    let wire = [
        0x03, // protocolVersion: Uint8 3
        0x80, // content: Ieee1609Dot2Content CHOICE, alternative 0 (unsecuredData)
        0x03, // unsecuredData: Opaque (OCTET STRING), length 3 in the short form
        0x00, 0x14, 0x25, // the three octets
    ];
    check_unsecured(&wire, &frame, 3);
}

#[test]
fn unsecured_longest_short_length() {
    let frame = payload(127);
    let mut wire = vec![
        0x03, // protocolVersion 3
        0x80, // unsecuredData
        0x7f, // length 127: still the short form (bit 8 clear)
    ];
    wire.extend(&frame);
    check_unsecured(&wire, &frame, 3);
}

#[test]
fn unsecured_long_length_one_octet() {
    let frame = payload(128);
    let mut wire = vec![
        0x03, // protocolVersion 3
        0x80, // unsecuredData
        0x81, // long form: bit 8 set, one length octet follows
        0x80, // length 128
    ];
    wire.extend(&frame);
    check_unsecured(&wire, &frame, 4);
}

#[test]
fn unsecured_long_length_two_octets() {
    let frame = payload(300);
    let mut wire = vec![
        0x03, // protocolVersion 3
        0x80, // unsecuredData
        0x82, // long form: two length octets follow
        0x01, 0x2c, // length 300 = 0x012c
    ];
    wire.extend(&frame);
    check_unsecured(&wire, &frame, 5);
}

#[test]
fn a_non_minimal_length_is_refused() {
    // Length 3 written in the long form: valid OER, but COER demands the short form.
    let wire = [0x03, 0x80, 0x81, 0x03, 0x00, 0x14, 0x25];
    assert!(unwrap_message_frame(&wire).is_err());
    // Protocol version 2 is not 1609.2 data of version 3.
    assert!(Ieee1609Dot2Data::parse(&[0x02, 0x80, 0x01, 0x00]).is_err());
}

/// Signed data with a `digest` signer around `frame` (PSID 0x20, a generation time, an
/// ECDSA NIST P-256 signature with an x-only r).
fn signed_wire(frame: &[u8]) -> Vec<u8> {
    let mut wire = vec![
        0x03, // protocolVersion 3
        0x81, // content: alternative 1 (signedData)
        // SignedData ::= SEQUENCE (no OPTIONAL, no extension marker: no preamble)
        0x00, // hashId: HashAlgorithm ENUMERATED, sha256 (0)
        // tbsData: ToBeSignedData ::= SEQUENCE { payload, headerInfo } (no preamble)
        // payload: SignedDataPayload ::= SEQUENCE { data OPTIONAL, extDataHash OPTIONAL, ... }
        0x40, // preamble: extension bit 0, data present 1, extDataHash absent 0, padding
        // data: Ieee1609Dot2Data, unsecured
        0x03, // protocolVersion 3
        0x80, // unsecuredData
    ];
    wire.push(u8::try_from(frame.len()).unwrap()); // short-form length (frame < 128 octets)
    wire.extend(frame);
    wire.extend([
        // headerInfo: HeaderInfo ::= SEQUENCE { psid, 6 OPTIONAL, ... }
        0x40, // preamble: extension bit 0, generationTime present, the other five absent
        0x01, 0x20, // psid: INTEGER (0..MAX), length 1, value 0x20 (BSM)
        // generationTime: Time64 (Uint64), eight octets: 0x0000_0123_4567_89ab
        0x00, 0x00, 0x01, 0x23, 0x45, 0x67, 0x89, 0xab,
        // signer: SignerIdentifier CHOICE, alternative 0 (digest): HashedId8
        0x80, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88,
        0x80, // signature: Signature CHOICE, alternative 0 (ecdsaNistP256Signature)
        // EcdsaP256Signature ::= SEQUENCE { rSig, sSig } (no preamble)
        0x80, // rSig: EccP256CurvePoint CHOICE, alternative 0 (x-only), 32 octets follow
    ]);
    wire.extend([0xaa; 32]);
    wire.extend([0xbb; 32]); // sSig: OCTET STRING (SIZE (32))
    wire
}

#[test]
fn signed_with_a_digest_signer() {
    let frame = [0x00, 0x14, 0x25, 0x01, 0x02];
    let wire = signed_wire(&frame);
    // 03 81 00 40 03 80 05, the frame, header 40 01 20 + time, signer, two tags, r, s.
    assert_eq!(wire.len(), 7 + 5 + 1 + 2 + 8 + 9 + 1 + 1 + 32 + 32);

    let found = unwrap_message_frame(&wire).unwrap();
    assert_eq!(found.envelope, EnvelopeKind::Signed);
    // The frame starts after 03 81 00 40 03 80 05.
    assert_eq!((found.frame, found.offset), (&frame[..], 7));

    let data = Ieee1609Dot2Data::parse(&wire).unwrap();
    assert!(data.is_signed());
    assert_eq!(data.application_data(), Some(&frame[..]));
    let signed = data.signed_data().unwrap();
    assert_eq!(signed.hash_algorithm, HashAlgorithm::Sha256);
    assert_eq!(signed.header.psid, super::Psid::BSM);
    assert_eq!(
        signed.header.generation_time,
        Some(Time64(0x0123_4567_89ab))
    );
    assert_eq!(signed.header.expiry_time, None);
    assert_eq!(
        signed.signer,
        SignerIdentifier::Digest([0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88])
    );
    assert_eq!(signed.signature.scheme, SignatureScheme::EcdsaNistP256);
    assert_eq!(signed.signature.r.form, PointForm::XOnly);
    assert_eq!(signed.signature.r.x, &[0xaa; 32][..]);
    assert_eq!(signed.signature.s, &[0xbb; 32][..]);
    // tbsData: from the payload's preamble to the end of generationTime.
    assert_eq!(signed.to_be_signed, &wire[3..3 + 1 + 3 + 5 + 1 + 2 + 8]);

    // One signature octet short: the input ends inside sSig.
    assert!(unwrap_message_frame(&wire[..wire.len() - 1]).is_err());
}
