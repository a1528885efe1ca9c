//! Where the shared, read-only data is: `../shared` beside the repository (the directory
//! that holds `corpus/` and `oracle/`), or `$SHARED_DIR`. The corpus alone may be moved
//! with `$J2735_CORPUS_DIR` (the variable the envelope corpus tests have always read).

use std::path::{Path, PathBuf};

/// The variable that names the shared directory.
pub const SHARED_DIR_VAR: &str = "SHARED_DIR";
/// The variable that names the corpus directory.
pub const CORPUS_DIR_VAR: &str = "J2735_CORPUS_DIR";

/// The repository's root (this crate is `codec/test-support`).
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The shared directory: `$SHARED_DIR`, else `shared` beside the repository.
///
/// # Panics
///
/// When it is not a directory, saying where it was looked for and how to point elsewhere.
pub fn shared_dir() -> PathBuf {
    let dir = std::env::var_os(SHARED_DIR_VAR)
        .map_or_else(|| repo_root().join("../shared"), PathBuf::from);
    assert!(
        dir.is_dir(),
        "{} is missing: these tests need the shared data (corpus/, oracle/) in `shared` \
         beside the repository, or set {SHARED_DIR_VAR}",
        dir.display()
    );
    dir
}

/// The conformance corpus: `$J2735_CORPUS_DIR`, else `corpus` in [`shared_dir`].
///
/// # Panics
///
/// When it has no `frames` directory.
pub fn corpus_dir() -> PathBuf {
    let dir =
        std::env::var_os(CORPUS_DIR_VAR).map_or_else(|| shared_dir().join("corpus"), PathBuf::from);
    assert!(
        dir.join("frames").is_dir(),
        "{} is not the conformance corpus (no frames/): set {CORPUS_DIR_VAR} or {SHARED_DIR_VAR}",
        dir.display()
    );
    dir
}

/// The text of `path`.
///
/// # Panics
///
/// When it cannot be read, naming the file.
pub fn read_text(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The files of `dir` whose name ends with `suffix`, sorted.
///
/// # Panics
///
/// When `dir` cannot be read.
pub fn files_ending_with(dir: &Path, suffix: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("a directory entry").path())
        .filter(|path| path.to_string_lossy().ends_with(suffix))
        .collect();
    files.sort();
    files
}
