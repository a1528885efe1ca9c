//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

/// Runs `f` on a thread with room for the largest no-heap values (MapData is megabytes).
pub fn big_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new().stack_size(256 << 20).spawn(f).unwrap().join().unwrap()
}

/// Lower-case hex of `bytes`.
pub fn to_hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Bytes of a hex string (whitespace ignored).
pub fn from_hex(s: &str) -> Vec<u8> {
    let s: String = s.chars().filter(|c| !c.is_whitespace()).collect();
    (0..s.len() / 2).map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).unwrap()).collect()
}

/// `../shared` beside the repository; panics (fails the test) when it is missing.
pub fn shared_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared");
    assert!(dir.is_dir(), "{} is missing: the shared-corpus tests need ../shared", dir.display());
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
