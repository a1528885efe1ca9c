//! Helpers shared by the integration tests (the generic ones come from `test-support`).
#![allow(dead_code, unused_imports)]

use j2735::uper::random::{Gen, Random};
use j2735::{
    BasicSafetyMessage, MapData, MessageFrame, MessageFrameValue, TravelerInformation, SPAT,
};

/// A random valid MessageFrame of MAP, TIM, BSM or SPaT (picked by `kind`) from `seed`.
pub fn random_frame(kind: u8, seed: u64) -> MessageFrame {
    let mut g = Gen::new(seed);
    let value = match kind % 4 {
        0 => MessageFrameValue::MapData(MapData::random(&mut g).into()),
        1 => MessageFrameValue::TravelerInformation(TravelerInformation::random(&mut g).into()),
        2 => MessageFrameValue::BasicSafetyMessage(BasicSafetyMessage::random(&mut g)),
        _ => MessageFrameValue::SPAT(SPAT::random(&mut g).into()),
    };
    MessageFrame {
        value,
        extensions: j2735::uper::Extensions::new(),
    }
}

pub use test_support::shared::shared_dir;
pub use test_support::{big_stack, from_hex, to_hex};

/// Every corpus frame as `(name, bytes)`, sorted by name.
pub fn corpus_frames() -> Vec<(String, Vec<u8>)> {
    let frames = test_support::corpus::frame_pairs();
    assert_eq!(frames.len(), 257, "the corpus has 257 frames");
    frames
}
