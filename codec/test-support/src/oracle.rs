//! The independent oracle (pycrate, `shared/oracle`): its setup script makes a Python
//! environment and prints the interpreter's path on its last line.

use std::ffi::OsStr;
use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

use crate::shared::shared_dir;

/// The Python interpreter that has the oracle's packages (runs `oracle/setup.sh`).
///
/// # Panics
///
/// When the setup fails, with its standard error.
pub fn python() -> String {
    let setup = shared_dir().join("oracle/setup.sh");
    let out = Command::new("bash")
        .arg(&setup)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", setup.display()));
    assert!(
        out.status.success(),
        "oracle setup {} failed: {}",
        setup.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).expect("UTF-8 from the oracle setup");
    let last = stdout.lines().last().unwrap_or_default().trim();
    assert!(!last.is_empty(), "the oracle setup printed no interpreter");
    last.to_owned()
}

/// Runs `python script ARGS...` with the oracle's interpreter, `input` on its standard
/// input; returns its standard output.
///
/// # Panics
///
/// When it cannot start or does not exit with success (with its standard error).
pub fn run_script<I, S>(script: &Path, args: I, input: &str) -> String
where
    I: IntoIterator<Item = S>,
    S: AsRef<OsStr>,
{
    let mut child = Command::new(python())
        .arg(script)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start the oracle on {}: {e}", script.display()));
    let mut stdin = child.stdin.take().expect("a pipe");
    let input = input.to_owned();
    let writer = std::thread::spawn(move || stdin.write_all(input.as_bytes()));
    let out = child.wait_with_output().expect("the oracle ends");
    writer
        .join()
        .expect("the writer ends")
        .expect("write to the oracle");
    assert!(
        out.status.success(),
        "the oracle script {} failed: {}",
        script.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).expect("UTF-8 from the oracle")
}
