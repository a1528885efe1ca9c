//! The conformance corpus (`corpus/frames/NAME.hex`) and the oracle's JER of each frame
//! (`corpus/jer/NAME.2020.json`: `{"jer": ..., "note": ...}`, the note saying why the JER
//! is not clean, empty when it is).

use std::path::PathBuf;

use serde_json::Value;

use crate::shared::{corpus_dir, files_ending_with, read_text};

/// One corpus frame.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Frame {
    /// The file name without `.hex` (for example `MAP_...`).
    pub name: String,
    /// The UPER MessageFrame.
    pub bytes: Vec<u8>,
}

impl Frame {
    /// The oracle's JER document of this frame, when the corpus has one.
    pub fn jer_document(&self) -> Option<Value> {
        jer_document(&self.name)
    }

    /// The oracle's JER of this frame when it is clean (the document's note is empty).
    pub fn clean_jer(&self) -> Option<Value> {
        clean_jer(&self.name)
    }
}

/// Every corpus frame, sorted by name.
///
/// # Panics
///
/// When the corpus is missing or a frame is not hex; when it has no frame.
pub fn frames() -> Vec<Frame> {
    let dir = corpus_dir().join("frames");
    let frames: Vec<Frame> = files_ending_with(&dir, ".hex")
        .iter()
        .map(|path| Frame {
            name: stem(path),
            bytes: crate::from_hex(&read_text(path)),
        })
        .collect();
    assert!(!frames.is_empty(), "no frames in {}", dir.display());
    frames
}

/// Every corpus frame as `(name, bytes)`, sorted by name.
pub fn frame_pairs() -> Vec<(String, Vec<u8>)> {
    frames().into_iter().map(|f| (f.name, f.bytes)).collect()
}

/// The path of the oracle's JER document of frame `name`.
pub fn jer_path(name: &str) -> PathBuf {
    corpus_dir().join(format!("jer/{name}.2020.json"))
}

/// The oracle's JER document of frame `name` (`None`: the corpus has none).
///
/// # Panics
///
/// When the document is not JSON.
pub fn jer_document(name: &str) -> Option<Value> {
    let path = jer_path(name);
    let text = std::fs::read_to_string(&path).ok()?;
    let doc = serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    Some(doc)
}

/// The oracle's JER of frame `name` when it has a clean one (an empty or absent note).
pub fn clean_jer(name: &str) -> Option<Value> {
    let doc = jer_document(name)?;
    let clean = doc["note"].as_str().is_none_or(str::is_empty);
    clean.then(|| doc["jer"].clone())
}

/// The file name of `path` without its extension.
fn stem(path: &std::path::Path) -> String {
    path.file_stem()
        .expect("a file name")
        .to_string_lossy()
        .into_owned()
}
