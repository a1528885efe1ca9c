//! The benchmarked frames: whole UPER MessageFrames, fed byte for byte to both codecs.
//!
//! - `map_small`, `map_mid`, `tim_work_zone`: the project's committed oracle vectors
//!   (`codec/tests/vectors/oracle_vectors.jsonl`, bytes made by pycrate, not by us).
//! - `map_largest`: the largest MAP of the shared conformance corpus, read at run time from
//!   `$J2735_CORPUS` (default `../shared/corpus/frames` beside the repository). It is not
//!   copied into the repository.
//! - `map_largest_2020`: the largest corpus MAP that rasn re-encodes to the identical bytes.
//!   The largest MAP carries J2735 2024 extension additions, which a 2020 decoder skips: ours
//!   keeps them as raw octets and writes them back, rasn drops them (its encoding is shorter),
//!   so its encode row is not the same work. This row is the same work for both.

use std::path::{Path, PathBuf};

pub use crate::kind::Kind;

/// One benchmarked frame.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Row name in benchmarks and tables (`map_small`, ...).
    pub row: &'static str,
    /// Where the bytes come from (vector name or corpus file).
    pub source: String,
    /// The message inside.
    pub kind: Kind,
    /// The complete MessageFrame encoding.
    pub bytes: Vec<u8>,
}

/// (row, oracle vector name, kind) of the frames taken from the committed vectors.
pub const VECTOR_ROWS: [(&str, &str, Kind); 3] = [
    ("map_small", "map_work_zone", Kind::Map),
    ("map_mid", "map_rich", Kind::Map),
    ("tim_work_zone", "tim_work_zone_left_lane_closed", Kind::Tim),
];

/// The order of rows in tables.
pub const ROW_ORDER: [&str; 5] = [
    "map_small",
    "map_mid",
    "map_largest",
    "map_largest_2020",
    "tim_work_zone",
];

fn bench_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The committed oracle vectors file.
pub fn vectors_path() -> PathBuf {
    bench_dir().join("../tests/vectors/oracle_vectors.jsonl")
}

/// The corpus frames directory: `$J2735_CORPUS`, else `../shared/corpus/frames` beside the
/// repository.
pub fn corpus_dir() -> PathBuf {
    match std::env::var_os("J2735_CORPUS") {
        Some(d) => PathBuf::from(d),
        None => bench_dir().join("../../../shared/corpus/frames"),
    }
}

/// Decodes lower-case or upper-case hex (whitespace ignored), with `j2735::hex`.
pub fn unhex(s: &str) -> Result<Vec<u8>, String> {
    let digits: String = s.chars().filter(|c| !c.is_ascii_whitespace()).collect();
    let mut bytes = vec![0; j2735::hex::decoded_len(&digits).map_err(|e| e.to_string())?];
    j2735::hex::decode_into(&digits, &mut bytes).map_err(|e| e.to_string())?;
    Ok(bytes)
}

/// The frame of oracle vector `name`.
pub fn vector(name: &str) -> Vec<u8> {
    let path = vectors_path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read the oracle vectors {}: {e}", path.display()));
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        let v: serde_json::Value = serde_json::from_str(line)
            .unwrap_or_else(|e| panic!("{}: bad JSON line: {e}", path.display()));
        if v["name"] == name {
            let hex = v["uper"]
                .as_str()
                .unwrap_or_else(|| panic!("vector {name} has no \"uper\" string"));
            return unhex(hex).unwrap_or_else(|e| panic!("vector {name}: {e}"));
        }
    }
    panic!("no vector named {name} in {}", path.display());
}

/// Every `MAP_*.hex` frame of the corpus: (file name, bytes), largest first (ties by name).
/// Panics with a message that says what to set when the corpus is missing.
pub fn corpus_maps() -> Vec<(String, Vec<u8>)> {
    let dir = corpus_dir();
    maps_in(&dir).unwrap_or_else(|e| {
        panic!(
            "the corpus MAPs are needed for rows map_largest and map_largest_2020: {e}\n\
             The shared conformance corpus is expected at {} (../shared/corpus/frames beside \
             the repository); set J2735_CORPUS=/path/to/corpus/frames to use another place.",
            dir.display()
        )
    })
}

fn maps_in(dir: &Path) -> Result<Vec<(String, Vec<u8>)>, String> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| format!("cannot list {}: {e}", dir.display()))?;
    let mut out = Vec::new();
    for entry in entries {
        let entry = entry.map_err(|e| e.to_string())?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if !(name.starts_with("MAP_") && name.ends_with(".hex")) {
            continue;
        }
        let text = std::fs::read_to_string(entry.path())
            .map_err(|e| format!("cannot read {name}: {e}"))?;
        let bytes = unhex(&text).map_err(|e| format!("{name}: {e}"))?;
        out.push((name, bytes));
    }
    if out.is_empty() {
        return Err(format!("no MAP_*.hex frame in {}", dir.display()));
    }
    out.sort_by(|a, b| b.1.len().cmp(&a.1.len()).then_with(|| a.0.cmp(&b.0)));
    Ok(out)
}

/// Every benchmarked frame, in [`ROW_ORDER`].
pub fn all() -> Vec<Frame> {
    let mut out: Vec<Frame> = VECTOR_ROWS
        .iter()
        .map(|&(row, name, kind)| Frame {
            row,
            source: format!("oracle vector {name}"),
            kind,
            bytes: vector(name),
        })
        .collect();
    let maps = corpus_maps();
    let (name, bytes) = maps[0].clone();
    out.push(Frame {
        row: "map_largest",
        source: format!("corpus {name}"),
        kind: Kind::Map,
        bytes,
    });
    let same = maps
        .into_iter()
        .find(|(_, b)| crate::theirs::round_trips(b) == Ok(true));
    if let Some((name, bytes)) = same {
        out.push(Frame {
            row: "map_largest_2020",
            source: format!("corpus {name}"),
            kind: Kind::Map,
            bytes,
        });
    }
    out.sort_by_key(|f| ROW_ORDER.iter().position(|r| *r == f.row));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hex() {
        assert_eq!(unhex("00ff 1A").unwrap(), vec![0, 255, 26]);
        assert!(unhex("abc").is_err());
    }
}
