//! Helpers shared by the integration tests.
#![allow(dead_code)]

use j2735::uper::random::{Gen, Random};
use j2735::{
    BasicSafetyMessage, MapData, MessageFrame, MessageFrameValue, TravelerInformation, SPAT,
};
use std::path::PathBuf;

/// A random valid MessageFrame of MAP, TIM, BSM or SPaT (picked by `kind`) from `seed`.
pub fn random_frame(kind: u8, seed: u64) -> MessageFrame {
    let mut g = Gen::new(seed);
    let value = match kind % 4 {
        0 => MessageFrameValue::MapData(MapData::random(&mut g)),
        1 => MessageFrameValue::TravelerInformation(TravelerInformation::random(&mut g)),
        2 => MessageFrameValue::BasicSafetyMessage(BasicSafetyMessage::random(&mut g)),
        _ => MessageFrameValue::SPAT(SPAT::random(&mut g)),
    };
    MessageFrame {
        value,
        extensions: j2735::uper::Extensions::new(),
    }
}

/// Runs `f` on a thread with room for the largest no-heap values (MapData is megabytes).
pub fn big_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .unwrap()
        .join()
        .unwrap()
}

/// Lower-case hex of `bytes`.
pub fn to_hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Bytes of a hex string (whitespace ignored).
pub fn from_hex(s: &str) -> Vec<u8> {
    let s: String = s.chars().filter(|c| !c.is_whitespace()).collect();
    (0..s.len() / 2)
        .map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).unwrap())
        .collect()
}

/// `../shared` beside the repository; panics (fails the test) when it is missing.
pub fn shared_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared");
    assert!(
        dir.is_dir(),
        "{} is missing: the shared-corpus tests need ../shared",
        dir.display()
    );
    dir
}

/// Every corpus frame, sorted by name.
pub fn corpus_frames() -> Vec<(String, Vec<u8>)> {
    let dir = shared_dir().join("corpus/frames");
    let mut out: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "hex"))
        .map(|p| {
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, from_hex(&std::fs::read_to_string(&p).unwrap()))
        })
        .collect();
    out.sort();
    assert_eq!(out.len(), 257, "the corpus has 257 frames");
    out
}
