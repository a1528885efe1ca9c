//! `j2735` over the shared conformance corpus (feature `shared-corpus`; fails, never skips,
//! when `../shared` beside the repository is missing).
//!
//! - every frame of `corpus/frames` decodes (no error line), its JER equals the oracle's
//!   where the oracle has a clean JER, and `encode` of the output gives the hex back;
//! - every `corpus/wrapped` envelope and `corpus/rsu-text` record decodes to its frame.
#![cfg(feature = "shared-corpus")]

mod common;

use std::fs;
use std::path::{Path, PathBuf};

use common::{error_of, j2735, same_jer};
use serde_json::Value;

/// The conformance corpus (`test-support` finds it; a missing corpus fails the test).
fn corpus() -> PathBuf {
    test_support::shared::corpus_dir()
}

/// `(name, hex)` of every corpus frame, sorted by name.
fn frames(_corpus: &Path) -> Vec<(String, String)> {
    test_support::corpus::frames()
        .into_iter()
        .map(|f| (f.name, test_support::to_hex(&f.bytes)))
        .collect()
}

/// The oracle's JER of a frame, when it has a clean one (an empty `note`).
fn oracle_jer(_corpus: &Path, name: &str) -> Option<Value> {
    test_support::corpus::clean_jer(name)
}

/// The one JER line `j2735 decode` gives for the input at `path`.
fn decode_file(path: &Path) -> String {
    let run = j2735(&["decode", path.to_str().unwrap()], b"");
    assert_eq!(run.code, 0, "{}: {}", path.display(), run.stdout);
    let lines = run.lines();
    assert_eq!(lines.len(), 1, "{}: one frame", path.display());
    lines[0].to_string()
}

#[test]
fn every_corpus_frame_decodes_and_encodes_back() {
    let corpus = corpus();
    let frames = frames(&corpus);
    assert_eq!(frames.len(), 257, "the corpus has 257 frames");
    let input: String = frames.iter().map(|(_, hex)| format!("{hex}\n")).collect();
    let decoded = j2735(&["decode"], input.as_bytes());
    let lines = decoded.lines();
    assert_eq!(lines.len(), frames.len());
    let errors: Vec<String> = lines.iter().filter_map(|l| error_of(l)).collect();
    assert!(errors.is_empty(), "error lines: {errors:?}");
    assert_eq!(decoded.code, 0);

    let mut compared = 0;
    for ((name, _), line) in frames.iter().zip(&lines) {
        if let Some(expected) = oracle_jer(&corpus, name) {
            let ours: Value = serde_json::from_str(line).unwrap();
            same_jer(&ours, &expected, "").unwrap_or_else(|e| panic!("{name}: {e}"));
            compared += 1;
        }
    }
    assert!(compared >= 250, "only {compared} oracle JERs compared");

    let encoded = j2735(&["encode"], decoded.stdout.as_bytes());
    assert_eq!(encoded.code, 0, "{}", encoded.stdout);
    let back = encoded.lines();
    assert_eq!(back.len(), frames.len());
    let identical = check_encoded(&corpus, &frames, &back);
    println!(
        "{} corpus frames decoded with no error line ({compared} equal to the oracle's JER); \
         encode gave {identical}/{} byte-identical",
        frames.len(),
        frames.len()
    );
}

/// Checks that every frame re-encodes to its own bytes (the JER carries unknown J2735 2024
/// extension additions too); returns how many were compared.
fn check_encoded(_corpus: &Path, frames: &[(String, String)], back: &[&str]) -> usize {
    let differ: Vec<&str> = frames
        .iter()
        .zip(back)
        .filter(|((_, hex), again)| hex != *again)
        .map(|((name, _), _)| name.as_str())
        .collect();
    assert!(differ.is_empty(), "re-encoded bytes differ for {differ:?}");
    frames.len()
}

/// Rows `(file, frame)` of `wrapped/INDEX.tsv`.
fn wrapped_index(corpus: &Path) -> Vec<(String, String)> {
    fs::read_to_string(corpus.join("wrapped/INDEX.tsv"))
        .unwrap()
        .lines()
        .skip(1)
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let columns: Vec<&str> = line.split('\t').collect();
            (columns[0].to_string(), columns[1].to_string())
        })
        .collect()
}

#[test]
fn wrapped_files_decode_to_their_indexed_frame() {
    let corpus = corpus();
    let index = wrapped_index(&corpus);
    let files: Vec<PathBuf> = fs::read_dir(corpus.join("wrapped"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "hex"))
        .collect();
    assert!(!files.is_empty(), "no wrapped/*.hex");
    for path in &files {
        let file = path.file_name().unwrap().to_string_lossy();
        let (_, frame) = index
            .iter()
            .find(|(f, _)| *f == file)
            .unwrap_or_else(|| panic!("{file} is not in wrapped/INDEX.tsv"));
        let expected = decode_file(&corpus.join(format!("frames/{frame}.hex")));
        assert_eq!(decode_file(path), expected, "{file}");
    }
    println!(
        "{} wrapped files decoded to their indexed frame",
        files.len()
    );
}

#[test]
fn rsu_text_files_decode_to_their_frame() {
    let corpus = corpus();
    let frames = frames(&corpus);
    let mut files: Vec<PathBuf> = fs::read_dir(corpus.join("rsu-text"))
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "txt"))
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no rsu-text/*.txt");
    for path in &files {
        let payload = payload_hex(path);
        let line = decode_file(path);
        // wrapped/INDEX.tsv does not list the RSU files: the frame is the corpus frame with
        // the payload's bytes where there is one, else the payload decoded on its own.
        let expected = match frames.iter().find(|(_, hex)| *hex == payload) {
            Some((name, _)) => decode_file(&corpus.join(format!("frames/{name}.hex"))),
            None => j2735(&["decode", "--unwrap", "none"], payload.as_bytes()).stdout,
        };
        assert_eq!(line, expected.trim_end(), "{}", path.display());
        let encoded = j2735(&["encode"], line.as_bytes());
        assert_eq!(encoded.stdout.trim_end(), payload, "{}", path.display());
    }
    println!(
        "{} RSU text files decoded to their payload frame",
        files.len()
    );
}

/// The `Payload=` value of an RSU file, lower case.
fn payload_hex(path: &Path) -> String {
    let text = fs::read_to_string(path).unwrap();
    let line = text
        .lines()
        .find(|l| l.trim().to_ascii_lowercase().starts_with("payload="))
        .unwrap_or_else(|| panic!("{}: no Payload=", path.display()));
    line.trim()[8..].to_lowercase()
}
