//! Tests against the shared conformance corpus (feature `shared-corpus`).
//!
//! The corpus directory is `$J2735_CORPUS_DIR`, or `corpus` in the shared directory
//! (`$SHARED_DIR`, or `shared` beside the repository), as `test-support` finds it. These
//! tests fail, not skip, when it is missing.

extern crate std;

use std::path::{Path, PathBuf};

use std::string::String;
use std::vec;
use std::vec::Vec;
use test_support::shared::{files_ending_with, read_text};

use super::ieee1609dot2::{encode_unsecured, unsecured_encoded_len, Ieee1609Dot2Data};
use super::rsu_text::RsuMessage;
use super::Psid;
use super::{unwrap_message_frame, EnvelopeKind};

/// `$J2735_CORPUS_DIR`, or `corpus` in the shared directory (`test-support` finds it and
/// fails the test when it is missing).
fn corpus_dir() -> PathBuf {
    test_support::shared::corpus_dir()
}

fn read_hex(path: &Path) -> Vec<u8> {
    test_support::from_hex(&read_text(path))
}

/// One row of `wrapped/INDEX.tsv`.
struct WrappedCase {
    file: String,
    frame: String,
    envelope: String,
}

fn wrapped_index(corpus: &Path) -> Vec<WrappedCase> {
    read_text(&corpus.join("wrapped/INDEX.tsv"))
        .lines()
        .skip(1)
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let columns: Vec<&str> = line.split('\t').collect();
            assert!(columns.len() >= 3, "short INDEX.tsv row: {line}");
            WrappedCase {
                file: columns[0].into(),
                frame: columns[1].into(),
                envelope: columns[2].into(),
            }
        })
        .collect()
}

#[test]
fn every_wrapped_file_is_indexed() {
    let corpus = corpus_dir();
    let index = wrapped_index(&corpus);
    let files = files_ending_with(&corpus.join("wrapped"), ".hex");
    assert!(!files.is_empty(), "no wrapped/*.hex files");
    for path in files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            index.iter().any(|case| case.file == name),
            "{name} is not in wrapped/INDEX.tsv"
        );
    }
}

#[test]
fn wrapped_payload_equals_the_indexed_frame() {
    let corpus = corpus_dir();
    let cases = wrapped_index(&corpus);
    assert!(!cases.is_empty(), "wrapped/INDEX.tsv lists no file");
    for case in &cases {
        let wrapped = read_hex(&corpus.join("wrapped").join(&case.file));
        let frame = read_hex(
            &corpus
                .join("frames")
                .join(std::format!("{}.hex", case.frame)),
        );
        let data = Ieee1609Dot2Data::parse(&wrapped)
            .unwrap_or_else(|error| panic!("{}: {error}", case.file));
        assert_eq!(data.application_data(), Some(&frame[..]), "{}", case.file);

        let unwrapped = unwrap_message_frame(&wrapped).unwrap();
        assert_eq!(unwrapped.frame, &frame[..], "{}", case.file);
        let frame_end = unwrapped.offset + frame.len();
        assert_eq!(&wrapped[unwrapped.offset..frame_end], &frame[..]);
        let expected_kind = match case.envelope.as_str() {
            "unsecured" => EnvelopeKind::Unsecured,
            "signed" => EnvelopeKind::Signed,
            other => panic!("{}: unknown envelope kind {other}", case.file),
        };
        assert_eq!(unwrapped.envelope, expected_kind, "{}", case.file);
    }
}

#[test]
fn unsecured_encoder_reproduces_the_wrapped_bytes() {
    let corpus = corpus_dir();
    let mut checked = 0;
    for case in wrapped_index(&corpus)
        .iter()
        .filter(|case| case.envelope == "unsecured")
    {
        let wrapped = read_hex(&corpus.join("wrapped").join(&case.file));
        let frame = read_hex(
            &corpus
                .join("frames")
                .join(std::format!("{}.hex", case.frame)),
        );
        let mut out = vec![0u8; unsecured_encoded_len(frame.len())];
        let written = encode_unsecured(&frame, &mut out).unwrap();
        assert_eq!(&out[..written], &wrapped[..], "{}", case.file);
        checked += 1;
    }
    assert!(checked > 0, "no unsecured envelope in the corpus");
}

#[test]
fn signed_corpus_envelope_exposes_header_signer_and_signature() {
    let corpus = corpus_dir();
    let mut checked = 0;
    for case in wrapped_index(&corpus)
        .iter()
        .filter(|case| case.envelope == "signed")
    {
        let wrapped = read_hex(&corpus.join("wrapped").join(&case.file));
        let data = Ieee1609Dot2Data::parse(&wrapped).unwrap();
        let signed = data.signed_data().expect("signed content");
        assert!(signed.header.generation_time.is_some(), "{}", case.file);
        assert_eq!(signed.signature.s.len(), 32, "{}", case.file);
        if let Some(psid) = psid_of_frame(&case.frame) {
            assert_eq!(signed.header.psid, psid, "{}", case.file);
        }
        if let super::ieee1609dot2::SignerIdentifier::Certificate(chain) = signed.signer {
            assert_eq!(chain.iter().count(), chain.len(), "{}", case.file);
        }
        checked += 1;
    }
    assert!(checked > 0, "no signed envelope in the corpus");
}

/// The PSID of the frame types whose PSID is unambiguous (BSM 32, PSM 39).
fn psid_of_frame(frame: &str) -> Option<Psid> {
    if frame.starts_with("BSM_") {
        Some(Psid::BSM)
    } else if frame.starts_with("PSM_") {
        Some(Psid::PSM)
    } else {
        None
    }
}

/// The real signed PSM from a deployed system carries a production certificate: its
/// permissions are IEEE 1609.2 integers (SPaT 130, MAP 2113687, TIM 131, ..., PSM 39), which
/// read as p-encoded octets would name nothing the OBU uses.
#[test]
fn the_real_signed_psm_certificate_grants_the_integer_psids() {
    let corpus = corpus_dir();
    let case = wrapped_index(&corpus)
        .into_iter()
        .find(|case| case.file.starts_with("PSM_005") && case.envelope == "signed")
        .expect("PSM_005's signed envelope in the corpus index");
    let wrapped = read_hex(&corpus.join("wrapped").join(&case.file));
    let data = Ieee1609Dot2Data::parse(&wrapped).unwrap();
    let signed = data.signed_data().unwrap();
    assert_eq!(signed.header.psid, Psid::PSM);
    let super::ieee1609dot2::SignerIdentifier::Certificate(chain) = signed.signer else {
        panic!("PSM_005 is signed with its certificate");
    };
    let cert = chain.first().unwrap();
    let granted: Vec<u32> = cert
        .app_permissions
        .unwrap()
        .iter()
        .map(|p| p.psid.value())
        .collect();
    assert_eq!(granted, [130, 2_113_687, 131, 133, 128, 2_113_685, 39]);
    for (psid, octets) in [
        (Psid::SPAT, 0x8002),
        (Psid::MAP, 0xE000_0017),
        (Psid::TIM, 0x8003),
        (Psid::PSM, 0x27),
    ] {
        assert!(cert.permission(psid).is_some(), "{}", psid.both_forms());
        assert_eq!(psid.p_encoded_value(), Some(octets));
        // The p-encoded octets read as the integer: granted by nobody.
        assert!(cert.permission(Psid(octets)).is_none() || octets < 0x80);
    }
}

#[test]
fn damaged_corpus_envelopes_never_panic() {
    let corpus = corpus_dir();
    for path in files_ending_with(&corpus.join("wrapped"), ".hex") {
        let wrapped = read_hex(&path);
        for len in 0..wrapped.len() {
            assert!(Ieee1609Dot2Data::parse(&wrapped[..len]).is_err());
        }
        for index in 0..wrapped.len() {
            for bit in 0..8 {
                let mut damaged = wrapped.clone();
                damaged[index] ^= 1 << bit;
                let _ = unwrap_message_frame(&damaged);
            }
        }
    }
}

/// The UPER `MessageFrame` prefix (extension bit and message id) for an RSU `Type`.
fn frame_prefix(message_type: &str) -> Option<[u8; 2]> {
    match message_type {
        "MAP" => Some([0x00, 0x12]),
        "SPAT" => Some([0x00, 0x13]),
        "BSM" => Some([0x00, 0x14]),
        "TIM" => Some([0x00, 0x1f]),
        _ => None,
    }
}

#[test]
fn rsu_text_files_parse_and_round_trip() {
    let corpus = corpus_dir();
    let files = files_ending_with(&corpus.join("rsu-text"), ".txt");
    assert!(!files.is_empty(), "no rsu-text/*.txt files");
    let mut versions = Vec::new();
    for path in files {
        let text = read_text(&path);
        let message =
            RsuMessage::parse(&text).unwrap_or_else(|error| panic!("{}: {error}", path.display()));
        versions.push(String::from(message.version));

        let mut payload = vec![0u8; message.payload.decoded_len().unwrap()];
        message.payload.decode_into(&mut payload).unwrap();
        let prefix = frame_prefix(message.message_type).expect("known message type");
        assert_eq!(payload[..2], prefix, "{}", path.display());
        let unwrapped = unwrap_message_frame(&payload).unwrap();
        assert_eq!(unwrapped.envelope, EnvelopeKind::Bare);

        let mut written = String::new();
        message.write_to(&mut written).unwrap();
        let reparsed = RsuMessage::parse(&written).unwrap();
        assert_eq!(
            RsuMessage {
                version: message.version,
                ..reparsed
            },
            message
        );
    }
    assert!(
        versions.iter().any(|version| version == "0.7"),
        "no Version=0.7 file"
    );
    assert!(
        versions.iter().any(|version| version == "0.5"),
        "no Version=0.5 file"
    );
}
