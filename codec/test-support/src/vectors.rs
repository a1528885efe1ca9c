//! The codec's oracle vectors: `codec/tests/vectors/oracle_vectors.jsonl`, one JSON object
//! per line with the vector's `name`, `uper` hex, the oracle's `jer` and what it `covers`.

use serde_json::Value;

/// One oracle vector.
#[derive(Clone, Debug, PartialEq)]
pub struct Vector {
    /// Its name, such as `map_work_zone`.
    pub name: String,
    /// Its UPER MessageFrame, lower-case hex as in the file.
    pub uper: String,
    /// The oracle's JER.
    pub jer: Value,
    /// What the vector covers (feature tags such as `opentype:fragmented`).
    pub covers: Vec<String>,
}

impl Vector {
    /// The UPER bytes.
    pub fn bytes(&self) -> Vec<u8> {
        crate::from_hex(&self.uper)
    }
}

/// The file's text (compiled in: the vectors are part of the repository).
const TEXT: &str = include_str!("../../tests/vectors/oracle_vectors.jsonl");

/// Every vector, in file order.
///
/// # Panics
///
/// When a line is not a vector.
pub fn all() -> Vec<Vector> {
    TEXT.lines().map(parse).collect()
}

/// The vector named `name`.
///
/// # Panics
///
/// When there is none.
pub fn named(name: &str) -> Vector {
    all()
        .into_iter()
        .find(|v| v.name == name)
        .unwrap_or_else(|| panic!("no oracle vector named {name}"))
}

fn parse(line: &str) -> Vector {
    let v: Value = serde_json::from_str(line).unwrap_or_else(|e| panic!("{e}: {line}"));
    let text = |key: &str| {
        v[key]
            .as_str()
            .unwrap_or_else(|| panic!("no {key} in {line}"))
            .to_string()
    };
    let covers = v["covers"].as_array().map_or_else(Vec::new, |list| {
        list.iter()
            .filter_map(|c| c.as_str().map(String::from))
            .collect()
    });
    Vector {
        name: text("name"),
        uper: text("uper"),
        jer: v["jer"].clone(),
        covers,
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn vectors_are_read() {
        let all = super::all();
        assert!(all.len() > 80, "{}", all.len());
        let map = super::named("map_work_zone");
        assert_eq!(map.jer["messageId"], 18);
        assert_eq!(map.bytes().len() * 2, map.uper.len());
    }
}
