//! The conformance corpus of real J2735 frames (`../shared/corpus`, not in this repository):
//! every frame decodes, and encoding the result gives the identical bytes. Runs in whichever
//! storage mode the crate is built with (`--features alloc` or not), so `.ci/run` runs it twice.
//! Only with feature `shared-corpus`; then a missing corpus is a failure, not a skip.
#![cfg(feature = "shared-corpus")]

use j2735::uper;
use j2735::MessageFrame;
use std::path::PathBuf;

fn corpus_dir() -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../shared/corpus/frames");
    assert!(dir.is_dir(), "corpus missing: {} (feature shared-corpus needs ../shared)", dir.display());
    dir
}

fn frames() -> Vec<(String, Vec<u8>)> {
    let mut out: Vec<_> = std::fs::read_dir(corpus_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "hex"))
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            (name, hex(text.trim()))
        })
        .collect();
    out.sort();
    assert_eq!(out.len(), 257, "the corpus has 257 frames");
    out
}

fn hex(s: &str) -> Vec<u8> {
    (0..s.len() / 2).map(|i| u8::from_str_radix(&s[2 * i..2 * i + 2], 16).unwrap()).collect()
}

/// Decodes and re-encodes on a thread with room for the largest no-heap values.
fn round_trip(bytes: &[u8]) -> Result<Vec<u8>, String> {
    let bytes = bytes.to_vec();
    std::thread::Builder::new()
        .stack_size(512 << 20)
        .spawn(move || {
            let mf: Box<MessageFrame> = Box::new(uper::decode(&bytes).map_err(|e| format!("decode: {e}"))?);
            let mut buf = vec![0u8; bytes.len() + 64];
            let n = uper::encode(&*mf, &mut buf).map_err(|e| format!("encode: {e}"))?;
            buf.truncate(n);
            Ok(buf)
        })
        .unwrap()
        .join()
        .unwrap()
}

#[test]
fn every_corpus_frame_round_trips_byte_exact() {
    let mut failures = Vec::new();
    let all = frames();
    for (name, bytes) in &all {
        match round_trip(bytes) {
            Ok(again) if &again == bytes => {}
            Ok(again) => failures.push(format!("{name}: re-encoded bytes differ (len {} vs {})", again.len(), bytes.len())),
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    let mode = if cfg!(feature = "alloc") { "alloc" } else { "no-alloc" };
    println!("{mode}: {}/{} corpus frames round-trip byte-exact", all.len() - failures.len(), all.len());
    assert!(failures.is_empty(), "{} failures:\n{}", failures.len(), failures.join("\n"));
}
