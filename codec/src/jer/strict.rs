//! Strict JER reading: every member of an object read as a SEQUENCE (or as the object form
//! of a BIT STRING or of `_extensions`) must be one the type looked up.
//!
//! The generated `read_jer` code looks members up one name at a time through
//! [`super::parts::member`]; it never hands the runtime the whole set of names a SEQUENCE has. So
//! while a strict read runs, this module records, per JSON object (by its address in the
//! borrowed `Value` tree, which stays alive and unmoved for the whole read), the names that
//! were looked up. After a successful read it walks the tree: a member of a recorded object
//! that nobody looked up is unknown to the type, and the read fails naming it and its path.
//! Objects never looked up by name (CHOICEs, which hold exactly one alternative) are not
//! checked. [`super::EXTENSIONS_MEMBER`] is always allowed.

use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::string::{String, ToString};

use serde_json::{Map, Value};

use super::{JerError, JerResult, EXTENSIONS_MEMBER};

std::thread_local! {
    /// The lookups of the strict read running on this thread (`None`: a lax read).
    static LOOKUPS: RefCell<Option<Lookups>> = const { RefCell::new(None) };
}

/// Per JSON object (by address): the member names looked up in it.
type Lookups = HashMap<usize, HashSet<String>>;

/// The address that identifies `map` during one read.
fn address(map: &Map<String, Value>) -> usize {
    core::ptr::from_ref(map) as usize
}

/// Records that `name` was looked up in `map` (only while a strict read runs).
pub(super) fn note_lookup(map: &Map<String, Value>, name: &str) {
    LOOKUPS.with(|cell| {
        if let Some(lookups) = cell.borrow_mut().as_mut() {
            let names = lookups.entry(address(map)).or_default();
            // The generated code looks up "" first to check that a SEQUENCE is an object.
            if !name.is_empty() {
                names.insert(name.to_string());
            }
        }
    });
}

/// Restores the previous recording state when a strict read ends (also on panic).
struct Recording {
    /// The state before this read (`Some(None)`: none ran); `None` once restored.
    previous: Option<Option<Lookups>>,
}

impl Recording {
    fn start() -> Self {
        let previous = LOOKUPS.with(|cell| cell.replace(Some(Lookups::new())));
        Self {
            previous: Some(previous),
        }
    }

    /// Ends the recording and returns what it recorded.
    fn finish(mut self) -> Lookups {
        let previous = self.previous.take().flatten();
        LOOKUPS
            .with(|cell| cell.replace(previous))
            .unwrap_or_default()
    }
}

impl Drop for Recording {
    fn drop(&mut self) {
        if let Some(previous) = self.previous.take() {
            LOOKUPS.with(|cell| cell.replace(previous));
        }
    }
}

/// Runs `read` on `value`, then fails when `value` holds a member the read did not look up.
pub(super) fn read_checked<T>(
    value: &Value,
    read: impl FnOnce(&Value) -> JerResult<T>,
) -> JerResult<T> {
    let recording = Recording::start();
    let result = read(value);
    let lookups = recording.finish();
    let read = result?;
    match first_unknown(value, &lookups, "") {
        Some(error) => Err(error),
        None => Ok(read),
    }
}

/// The first member (depth first) of a looked-up object that was not looked up.
fn first_unknown(value: &Value, lookups: &Lookups, path: &str) -> Option<JerError> {
    match value {
        Value::Object(map) => {
            if let Some(names) = lookups.get(&address(map)) {
                let unknown = map
                    .keys()
                    .find(|k| k.as_str() != EXTENSIONS_MEMBER && !names.contains(k.as_str()));
                if let Some(name) = unknown {
                    let mut error = JerError::new(std::format!("unknown member {name:?}"));
                    error.path = path.to_string();
                    return Some(error);
                }
            }
            map.iter()
                .find_map(|(k, v)| first_unknown(v, lookups, &join(path, k)))
        }
        Value::Array(items) => items
            .iter()
            .enumerate()
            .find_map(|(i, v)| first_unknown(v, lookups, &join(path, &std::format!("[{i}]")))),
        _ => None,
    }
}

/// `path.part`, in the form of [`JerError::within`].
fn join(path: &str, part: &str) -> String {
    if path.is_empty() {
        part.to_string()
    } else {
        std::format!("{path}.{part}")
    }
}
