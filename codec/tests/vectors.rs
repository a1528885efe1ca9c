//! Test vectors whose bytes come from the independent oracle (pycrate), committed in
//! `tests/vectors/oracle_vectors.jsonl` by `codegen/make_vectors.py`: every vector decodes to
//! the message its JER names, and encoding gives the oracle's bytes back.

mod common;

use j2735::uper::{self, DecodeErrorKind, Placeholder};
use j2735::{MessageFrame, MessageFrameValue};

struct Vector {
    name: String,
    covers: Vec<String>,
    uper: Vec<u8>,
    message_id: i64,
}

fn vectors() -> Vec<Vector> {
    let text = include_str!("vectors/oracle_vectors.jsonl");
    let out: Vec<Vector> = text
        .lines()
        .map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).unwrap();
            Vector {
                name: v["name"].as_str().unwrap().to_owned(),
                covers: v["covers"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .map(|c| c.as_str().unwrap().to_owned())
                    .collect(),
                uper: common::from_hex(v["uper"].as_str().unwrap()),
                message_id: v["jer"]["messageId"].as_i64().unwrap(),
            }
        })
        .collect();
    assert!(
        out.len() >= 60,
        "expected the committed vectors, found {}",
        out.len()
    );
    out
}

fn fragmented(v: &Vector) -> bool {
    v.covers.iter().any(|c| c == "opentype:fragmented")
}

#[test]
fn oracle_vectors_decode_and_reencode_byte_exact() {
    common::big_stack(|| {
        let mut mf = Box::new(MessageFrame::placeholder());
        let mut buf = vec![0u8; 1 << 16];
        let mut checked = 0;
        for v in vectors() {
            let got = uper::decode_into(&v.uper, &mut *mf);
            if fragmented(&v) && !cfg!(feature = "alloc") {
                let e = got.expect_err("a fragmented open type needs feature alloc");
                assert_eq!(e.kind, DecodeErrorKind::FragmentedOpenType, "{}", v.name);
                continue;
            }
            got.unwrap_or_else(|e| panic!("{}: {e}", v.name));
            assert_eq!(mf.value.id().get() as i64, v.message_id, "{}", v.name);
            assert!(
                !matches!(mf.value, MessageFrameValue::Unknown { .. }),
                "{}: not typed",
                v.name
            );
            let n = uper::encode(&*mf, &mut buf).unwrap_or_else(|e| panic!("{}: {e}", v.name));
            assert_eq!(
                common::to_hex(&buf[..n]),
                common::to_hex(&v.uper),
                "{}",
                v.name
            );
            assert_eq!(uper::encoded_len(&*mf).unwrap(), n, "{}: size pass", v.name);
            checked += 1;
        }
        println!("{checked} oracle vectors round-trip byte-exact");
    });
}

/// With `std`: decoding every oracle vector as a new value, each from the storage that the
/// previous (differently shaped) message left, gives the oracle's bytes and the fresh value.
#[cfg(feature = "std")]
#[test]
fn new_values_decoded_from_recycled_storage_equal_fresh_ones() {
    let frames: Vec<(String, Vec<u8>)> = vectors().into_iter().map(|v| (v.name, v.uper)).collect();
    let checked = common::check_decodes_from_recycled_storage(&frames);
    assert_eq!(checked, 3 * frames.len());
    println!("{checked} new-value decodes from recycled storage match");
}

#[test]
fn vectors_cover_every_message_and_construct() {
    let all = vectors();
    let has = |tag: &str| all.iter().any(|v| v.covers.iter().any(|c| c == tag));
    for id in [18, 19, 20, 21, 22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32] {
        assert!(
            all.iter().any(|v| v.message_id == id),
            "no vector of message {id}"
        );
    }
    for id in 240..=255 {
        assert!(
            all.iter().any(|v| v.message_id == id),
            "no vector of TestMessage {id}"
        );
    }
    for tag in [
        "int:min",
        "int:max",
        "int:negative",
        "enumerated",
        "choice",
        "sequence:optional-absent",
        "sequence:optional-present",
        "seqof:upper-bound",
        "bitstring:fixed",
        "bitstring:extensible-size",
        "octetstring:fixed",
        "octetstring:variable",
        "ia5string",
        "boolean",
        "opentype:regional-known",
        "opentype:regional-unknown",
        "opentype:length-2byte",
        "node:node-XY1",
        "node:node-XY2",
        "node:node-XY3",
        "node:node-XY4",
        "node:node-XY5",
        "node:node-XY6",
        "node:node-LatLon",
        "node:node-LL1",
        "node:node-LL6",
        "tim:path-xy",
        "tim:path-ll",
        "tim:geometry-circle",
        "tim:work-zone",
    ] {
        assert!(has(tag), "no vector covers {tag}");
    }
}

#[test]
fn trailing_bytes_are_an_error_and_prefix_decoding_reports_the_length() {
    common::big_stack(|| {
        let v = vectors().into_iter().find(|v| v.message_id == 20).unwrap();
        let mut longer = v.uper.clone();
        longer.push(0);
        let mut frame = Box::new(MessageFrame::placeholder());
        let e = uper::decode_into(&longer, &mut *frame).unwrap_err();
        assert_eq!(e.kind, DecodeErrorKind::TrailingBytes);
        assert_eq!(e.bit as usize, v.uper.len() * 8);
        let used = uper::decode_prefix_into(&longer, &mut *frame).unwrap();
        assert_eq!(used, v.uper.len());
    });
}
