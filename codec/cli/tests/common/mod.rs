//! Helpers of the CLI tests: run the built `j2735`, compare JER, scratch files; the oracle
//! vectors and hex come from `test-support`.
#![allow(dead_code, unused_imports)]

use std::io::Write;
use std::path::{Path, PathBuf};

use std::process::{Command, Stdio};

use serde_json::Value;

/// What one run of `j2735` gave.
pub struct Run {
    pub code: i32,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// The non-empty lines of standard output.
    pub fn lines(&self) -> Vec<&str> {
        self.stdout.lines().filter(|l| !l.is_empty()).collect()
    }
}

/// Runs `j2735 args...` with `stdin` as its standard input.
pub fn j2735(args: &[&str], stdin: &[u8]) -> Run {
    let mut child = Command::new(env!("CARGO_BIN_EXE_j2735"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the j2735 binary runs");
    let mut pipe = child.stdin.take().unwrap();
    let input = stdin.to_vec();
    let writer = std::thread::spawn(move || {
        // The tool may exit before reading everything (usage errors): ignore a closed pipe.
        let _ = pipe.write_all(&input);
    });
    let output = child.wait_with_output().unwrap();
    writer.join().unwrap();
    Run {
        code: output.status.code().expect("exited normally"),
        stdout: String::from_utf8(output.stdout).expect("UTF-8 output"),
        stderr: String::from_utf8(output.stderr).expect("UTF-8 errors"),
    }
}

pub use test_support::from_hex;
pub use test_support::vectors::{all as vectors, named as vector, Vector};

/// Equal as JER, where `{"value": H, "length": n}` equals the bare `H` (the oracle writes
/// bare hex for BIT STRINGs with an extensible size). `Err` says where they differ.
pub fn same_jer(ours: &Value, expected: &Value, at: &str) -> Result<(), String> {
    match (ours, expected) {
        (Value::Object(o), Value::String(_)) if o.len() == 2 && o.contains_key("length") => {
            same_jer(&o["value"], expected, at)
        }
        (Value::Object(o), Value::Object(e)) => {
            let mut ours_keys: Vec<&String> = o.keys().collect();
            let mut expected_keys: Vec<&String> = e.keys().collect();
            ours_keys.sort();
            expected_keys.sort();
            if ours_keys != expected_keys {
                return Err(format!("{at}: members {ours_keys:?} vs {expected_keys:?}"));
            }
            o.iter()
                .try_for_each(|(k, v)| same_jer(v, &e[k], &format!("{at}.{k}")))
        }
        (Value::Array(o), Value::Array(e)) if o.len() == e.len() => o
            .iter()
            .zip(e)
            .enumerate()
            .try_for_each(|(i, (a, b))| same_jer(a, b, &format!("{at}[{i}]"))),
        (a, b) if a == b => Ok(()),
        (a, b) => Err(format!("{at}: {a} vs {b}")),
    }
}

/// Writes `bytes` to a file of this test run's scratch directory and returns its path.
pub fn scratch_file(name: &str, bytes: &[u8]) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("j2735-cli-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// Whether a line is a CLI error line `{"error": "..."}`; returns the message.
pub fn error_of(line: &str) -> Option<String> {
    let v: Value = serde_json::from_str(line).ok()?;
    let map = v.as_object()?;
    (map.len() == 1)
        .then(|| map.get("error")?.as_str().map(String::from))
        .flatten()
}
