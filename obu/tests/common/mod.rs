//! Helpers shared by the integration tests: a big stack for no-heap J2735 values, the
//! codec's oracle vectors, hex, the shared corpus (the generic ones from `test-support`).
#![allow(dead_code, unused_imports)]

use j2735::frame::{decode_message_into, Message};

pub use test_support::shared::shared_dir;
pub use test_support::{big_stack, from_hex};

/// The UPER bytes of the codec's oracle vector `name`.
pub fn vector(name: &str) -> Vec<u8> {
    test_support::vectors::named(name).bytes()
}

/// Decodes a MessageFrame carrying an `M` into a box (call on [`big_stack`]).
pub fn decode<M: Message>(bytes: &[u8]) -> Box<M> {
    let mut m = Box::new(M::placeholder());
    decode_message_into(bytes, &mut *m).expect("decodes");
    m
}

/// Every corpus frame as `(name, bytes)`, sorted by name.
pub fn corpus_frames() -> Vec<(String, Vec<u8>)> {
    test_support::corpus::frame_pairs()
}
