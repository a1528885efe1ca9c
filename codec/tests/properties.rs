//! Property tests: random valid MessageFrames of MAP, TIM, BSM and SPaT encode, decode back
//! to the same value, and re-encode to the same bytes, within the type's size bound.

mod common;

use common::random_frame;
use j2735::uper::{self, Placeholder, Uper};
use j2735::MessageFrame;
use proptest::prelude::*;

fn round_trip(kind: u8, seed: u64) -> Result<(), TestCaseError> {
    let frame = random_frame(kind, seed);
    let mut buf = vec![0u8; 1 << 17];
    let n =
        uper::encode(&frame, &mut buf).map_err(|e| TestCaseError::fail(format!("encode: {e}")))?;
    prop_assert_eq!(uper::encoded_len(&frame).unwrap(), n);
    if let Some(max) = MessageFrame::MAX_UPER_BITS {
        prop_assert!(n as u64 * 8 <= max.div_ceil(8) * 8);
    }
    let mut back = Box::new(MessageFrame::placeholder());
    uper::decode_into(&buf[..n], &mut *back)
        .map_err(|e| TestCaseError::fail(format!("decode: {e}")))?;
    prop_assert_eq!(&*back, &frame);
    let mut again = vec![0u8; n];
    prop_assert_eq!(uper::encode(&*back, &mut again).unwrap(), n);
    prop_assert_eq!(&again[..], &buf[..n]);
    Ok(())
}

#[test]
fn random_frames_round_trip() {
    common::big_stack(|| {
        let mut runner = proptest::test_runner::TestRunner::new(ProptestConfig {
            cases: 160,
            ..ProptestConfig::default()
        });
        runner
            .run(&(0u8..4, any::<u64>()), |(kind, seed)| {
                round_trip(kind, seed)
            })
            .unwrap();
    });
}
