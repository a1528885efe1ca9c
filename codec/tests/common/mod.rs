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

/// With feature `std`, a new value's decode refills storage that this thread's dropped values
/// held (`uper::MessageBox`, list storage: see the codec's `recycle.rs`). Checks that decoding
/// each of `frames` as a new value, in orders where each reuses the storage of a message of
/// another shape (forward, backward, first and last alternately), gives the frame's own bytes
/// back on encoding and the value a thread with nothing to reuse decodes (it holds every
/// value, so that nothing is dropped). Returns how many decodes were checked.
#[cfg(feature = "std")]
pub fn check_decodes_from_recycled_storage(frames: &[(String, Vec<u8>)]) -> usize {
    use j2735::uper;
    let owned = frames.to_vec();
    let fresh: Vec<MessageFrame> = std::thread::spawn(move || {
        owned
            .iter()
            .map(|(name, bytes)| uper::decode(bytes).unwrap_or_else(|e| panic!("{name}: {e}")))
            .collect()
    })
    .join()
    .expect("the fresh decodes");
    let n = frames.len();
    let forward = 0..n;
    let backward = (0..n).rev();
    let alternate = (0..n).map(|i| if i % 2 == 0 { i / 2 } else { n - 1 - i / 2 });
    let mut buf = vec![0u8; 1 << 16];
    let mut checked = 0;
    for i in forward.chain(backward).chain(alternate) {
        let (name, bytes) = &frames[i];
        let value: MessageFrame = uper::decode(bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(value == fresh[i], "{name}: differs from the fresh decode");
        let len = uper::encode(&value, &mut buf).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(to_hex(&buf[..len]), to_hex(bytes), "{name}: re-encoded");
        checked += 1;
    }
    checked
}
