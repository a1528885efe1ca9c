//! Inputs found by fuzzing the codec (`codec/fuzz`, cargo-fuzz), kept as regression tests.
//! Each is a fuzzer finding (or its hand-minimised form), not a frame of the shared corpus.

mod common;

use j2735::jer;
use j2735::uper::{self, Placeholder};
use j2735::{MessageFrame, MessageFrameValue};

/// The invariant of the `message_frame` target: decode, encode (`encoded_len` octets), decode
/// again gives an equal value, and encoding that gives the same octets. Returns the encoding.
fn round_trip(input: Vec<u8>) -> Vec<u8> {
    common::big_stack(move || {
        let mut first = Box::new(MessageFrame::placeholder());
        uper::decode_into(&input, &mut *first).expect("the input decodes");
        let len = uper::encoded_len(&*first).expect("encoded_len");
        let mut encoding = vec![0u8; len];
        assert_eq!(uper::encode(&*first, &mut encoding), Ok(len));
        let mut second = Box::new(MessageFrame::placeholder());
        uper::decode_into(&encoding, &mut *second).expect("the re-encoding decodes");
        assert!(*first == *second, "decode(encode(decode(x))) != decode(x)");
        let mut again = vec![0u8; len];
        assert_eq!(uper::encode(&*second, &mut again), Ok(len));
        assert_eq!(again, encoding, "the two encodings differ");
        encoding
    })
}

/// Finding 1, minimised: a MessageFrame of `messageId` 0 (no J2735 message, kept as an
/// unknown open type) whose open type has length 0. The encoder wrote the empty content as
/// one zero octet (`00 00 01 00`), which decodes to content `[0]`: another value.
#[test]
fn unknown_message_with_empty_open_type() {
    let input = vec![0x00, 0x00, 0x00];
    assert_eq!(round_trip(input.clone()), input);
}

/// Finding 1 as the fuzzer found it (`message_frame` target, a mutation of the project's own
/// `map_work_zone` vector): a lane's regional extension (`regionId` 184, unknown to J2735
/// 2020) with a `regExtValue` of length 0.
#[test]
fn map_with_empty_unknown_regional_extension() {
    let input = common::from_hex(concat!(
        "001271681d7180350181b5906a76038439cae1d670d4b016e1288b0608b020b814000002080084e0",
        "d168b22d405019e2811663c800280403ab0303fc51020920085c000601200000100004270674c591",
        "2202805022cc79000080a030458c0c0ff100864000001800101800004e0d0003000c0000",
    ));
    assert_eq!(round_trip(input.clone()), input);
}

/// Finding 1 through JER (the `jer` target's invariant): an unknown message with empty
/// content goes through UPER and comes back equal.
#[test]
fn jer_unknown_message_with_empty_content() {
    common::big_stack(|| {
        let text = r#"{"messageId":0,"value":""}"#;
        let value: Box<MessageFrame> = Box::new(jer::from_str(text).expect("reads"));
        assert!(matches!(value.value, MessageFrameValue::Unknown { .. }));
        let mut encoding = vec![0u8; uper::encoded_len(&*value).unwrap()];
        uper::encode(&*value, &mut encoding).unwrap();
        assert_eq!(encoding, [0x00, 0x00, 0x00]);
        let mut back = Box::new(MessageFrame::placeholder());
        uper::decode_into(&encoding, &mut *back).unwrap();
        assert!(*back == *value);
        assert_eq!(jer::to_string(&*back), text);
    });
}

/// Reads JER text and, when it reads, checks the invariant of the `jer` target: its UPER
/// encoding decodes to an equal value. Returns whether the text was read.
fn jer_through_uper(text: &'static str) -> bool {
    common::big_stack(move || {
        let Ok(value) = jer::from_str::<MessageFrame>(text) else {
            return false;
        };
        let value = Box::new(value);
        let mut encoding = vec![0u8; uper::encoded_len(&*value).expect("encodes")];
        uper::encode(&*value, &mut encoding).unwrap();
        let mut back = Box::new(MessageFrame::placeholder());
        uper::decode_into(&encoding, &mut *back).expect("decodes");
        assert!(*back == *value, "JER -> UPER -> value differs for {text}");
        assert_eq!(jer::to_string(&*back), jer::to_string(&*value));
        true
    })
}

/// Finding 2 (`jer` target, minimised): unknown extension additions in JER whose index lies
/// outside the declared bit-map (`bitmapLength` 1, addition 1; the fuzzer's input had
/// `bitmapLength` 2 and an addition 2). The value read kept the short bit-map, its UPER
/// encoding carried the longer one that the addition needs, so the decoded value differed.
/// Such text is now refused (`Extensions::from_parts`); consistent text round-trips.
#[test]
fn jer_extension_addition_outside_the_bitmap() {
    assert!(!jer_through_uper(
        r#"{"messageId":18,"value":{"msgIssueRevision":0,"_extensions":{"bitmapLength":1,"additions":[[1,"00"]]}}}"#
    ));
    assert!(!jer_through_uper(
        r#"{"messageId":18,"value":{"msgIssueRevision":0,"_extensions":{"bitmapLength":0,"additions":[[0,"00"]]}}}"#
    ));
    assert!(jer_through_uper(
        r#"{"messageId":18,"value":{"msgIssueRevision":0,"_extensions":{"bitmapLength":2,"additions":[[1,"00"]]}}}"#
    ));
}
