//! Helpers shared by the integration tests: a big stack for no-heap J2735 values, the
//! codec's oracle vectors, hex.
#![allow(dead_code)]

use j2735::frame::{decode_message_into, Message};
use std::path::PathBuf;

/// Runs `f` on a thread with room for the largest no-heap values (MapData is megabytes).
pub fn big_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(256 << 20)
        .spawn(f)
        .expect("spawn")
        .join()
        .unwrap_or_else(|e| std::panic::resume_unwind(e))
}

/// Bytes of a hex string (whitespace ignored).
pub fn from_hex(s: &str) -> Vec<u8> {
    let s: String = s.chars().filter(|c| !c.is_whitespace()).collect();
    (0..s.len() / 2)
        .map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).expect("hex"))
        .collect()
}

/// The UPER bytes of the codec's oracle vector `name`.
pub fn vector(name: &str) -> Vec<u8> {
    let all = include_str!("../../../codec/tests/vectors/oracle_vectors.jsonl");
    let tag = format!("\"name\":\"{name}\"");
    let line = all
        .lines()
        .find(|l| l.contains(&tag))
        .expect("vector present");
    let hex = line
        .split("\"uper\":\"")
        .nth(1)
        .and_then(|s| s.split('"').next());
    from_hex(hex.expect("uper field"))
}

/// Decodes a MessageFrame carrying an `M` into a box (call on [`big_stack`]).
pub fn decode<M: Message>(bytes: &[u8]) -> Box<M> {
    let mut m = Box::new(M::placeholder());
    decode_message_into(bytes, &mut *m).expect("decodes");
    m
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
        .expect("corpus/frames")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "hex"))
        .map(|p| {
            let name = p.file_stem().expect("name").to_string_lossy().into_owned();
            (name, from_hex(&std::fs::read_to_string(&p).expect("read")))
        })
        .collect();
    out.sort();
    assert!(!out.is_empty(), "no frames in {}", dir.display());
    out
}
