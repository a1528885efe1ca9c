//! No module imports its importer, in any crate of the repository (the workspace's, the
//! firmware's, the fuzz and bench crates): for every top-level module of a crate's `src`
//! (and of each binary under `src/bin/`), the `crate::X` paths its files use in code give an
//! edge to `X` (comments and doc comments are left out: a doc link is not a dependency; so
//! are `#[cfg(test)]` modules and test files: a test may use anything); the graph must have
//! no cycle, neither a pair importing each other nor a longer loop. The same holds one level
//! down, among the sub-modules of each folder module (`super::x`, `crate::m::x`). The
//! generated J2735 modules (`codec/src/msg/`) are left out of that second level: they
//! import each other as the standard's ASN.1 modules do.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

type Graph = BTreeMap<String, BTreeSet<String>>;

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The names after each of `prefixes` in `line`, including `prefix{a, b::c}` groups.
fn paths_after(line: &str, prefixes: &[String]) -> Vec<String> {
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect()
    };
    let mut out = Vec::new();
    for prefix in prefixes {
        for (i, _) in line.match_indices(prefix.as_str()) {
            // `crate::m::x` is no `crate::x`-style use of `m::x`'s parent by `x`'s sibling.
            if i > 0 && line[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
                continue;
            }
            let rest = &line[i + prefix.len()..];
            if let Some(group) = rest.strip_prefix('{') {
                let inner = &group[..group.find('}').unwrap_or(group.len())];
                out.extend(inner.split(',').map(|p| ident(p.trim())));
            } else {
                out.push(ident(rest));
            }
        }
    }
    out.retain(|m| !m.is_empty());
    out
}

/// The modules of the folder `dir` (`m.rs` or `m/`), without the root files and tests.
fn modules(dir: &Path) -> BTreeMap<String, PathBuf> {
    let skip = [
        "lib.rs",
        "main.rs",
        "mod.rs",
        "tests.rs",
        "tests",
        "bin",
        "testutil.rs",
        "test_support.rs",
        "testdata.rs",
    ];
    let mut out = BTreeMap::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if skip.contains(&name.as_str()) {
            continue;
        }
        if path.is_dir() || name.ends_with(".rs") {
            out.insert(name.trim_end_matches(".rs").to_string(), path);
        }
    }
    out
}

/// Module -> the sibling modules it names after one of `prefixes`, among the modules of
/// `dir` (a module `m` is both `m.rs` and the folder `m/`).
fn graph(dir: &Path, prefixes: &[String]) -> Graph {
    let mods = modules(dir);
    let mut g = Graph::new();
    for (module, path) in &mods {
        let mut files = Vec::new();
        if path.is_dir() {
            rust_files(path, &mut files);
            // `m.rs` beside a folder `m/` is the same module.
            let file = path.with_extension("rs");
            if file.is_file() {
                files.push(file);
            }
        } else {
            files.push(path.clone());
        }
        files.retain(|f| !f.components().any(|c| c.as_os_str() == "tests"));
        let uses = g.entry(module.clone()).or_default();
        for f in files {
            let text = without_test_modules(&std::fs::read_to_string(&f).unwrap());
            for line in text.lines() {
                let code = line.split("//").next().unwrap_or("");
                for m in paths_after(code, prefixes) {
                    if &m != module && mods.contains_key(&m) {
                        uses.insert(m);
                    }
                }
            }
        }
    }
    g
}

/// `text` without its `#[cfg(test)] mod name { ... }` blocks.
fn without_test_modules(text: &str) -> String {
    let mut out = String::new();
    let mut depth = 0usize;
    let mut in_test = false;
    let mut armed = false;
    for line in text.lines() {
        let code = line.split("//").next().unwrap_or("");
        if !in_test && code.trim() == "#[cfg(test)]" {
            armed = true;
            continue;
        }
        if armed && !in_test {
            armed = false;
            let t = code.trim_start();
            if (t.starts_with("mod ") || t.starts_with("pub mod ")) && t.ends_with('{') {
                in_test = true;
                depth = 0;
            }
        }
        if in_test {
            depth += code.matches('{').count();
            depth = depth.saturating_sub(code.matches('}').count());
            if depth == 0 {
                in_test = false;
            }
            continue;
        }
        out.push_str(line);
        out.push('\n');
    }
    out
}

/// The graphs of a crate's `src`: its top-level modules (`crate::x`), then the
/// sub-modules of each folder module `m` (`super::x`, `crate::m::x`).
fn levels(src: &Path) -> Vec<(String, Graph)> {
    let mut out = vec![("crate".to_string(), graph(src, &["crate::".to_string()]))];
    for (m, path) in modules(src) {
        if path.is_dir() && m != "msg" {
            let prefixes = ["super::".to_string(), format!("crate::{m}::")];
            out.push((m.clone(), graph(&path, &prefixes)));
        }
    }
    out
}

/// A cycle of `g` (its modules in order, the first repeated at the end), if any.
fn find_cycle(g: &Graph) -> Option<Vec<String>> {
    fn visit(g: &Graph, m: &str, path: &mut Vec<String>, done: &mut BTreeSet<String>) -> bool {
        if let Some(at) = path.iter().position(|p| p == m) {
            path.drain(..at);
            path.push(m.to_string());
            return true;
        }
        if done.contains(m) {
            return false;
        }
        path.push(m.to_string());
        for next in g.get(m).into_iter().flatten() {
            if visit(g, next, path, done) {
                return true;
            }
        }
        path.pop();
        done.insert(m.to_string());
        false
    }
    let mut done = BTreeSet::new();
    for m in g.keys() {
        let mut path = Vec::new();
        if visit(g, m, &mut path, &mut done) {
            return Some(path);
        }
    }
    None
}

#[test]
fn the_checker_finds_pairs_and_longer_loops() {
    let g = |edges: &[(&str, &str)]| {
        let mut g = Graph::new();
        for (a, b) in edges {
            g.entry(a.to_string()).or_default().insert(b.to_string());
        }
        g
    };
    assert_eq!(find_cycle(&g(&[("a", "b"), ("b", "c")])), None);
    assert_eq!(
        find_cycle(&g(&[("a", "b"), ("b", "a")])),
        Some(vec!["a".into(), "b".into(), "a".into()])
    );
    assert_eq!(
        find_cycle(&g(&[("x", "a"), ("a", "b"), ("b", "c"), ("c", "a")])),
        Some(vec!["a".into(), "b".into(), "c".into(), "a".into()])
    );
    let crate_prefix = ["crate::".to_string()];
    assert_eq!(
        paths_after(
            "use crate::{road::Road, clock};  let x = crate::rng::Prng::new(1);",
            &crate_prefix
        ),
        ["road", "clock", "rng"]
    );
    let sub = ["super::".to_string(), "crate::plot::".to_string()];
    assert_eq!(
        paths_after("use super::span::Span; crate::plot::style::SIZE", &sub),
        ["span", "style"]
    );
}

/// The source folders of every crate in the repository: each `src` beside a `Cargo.toml`,
/// and each binary folder under `src/bin/`.
fn source_roots(dir: &Path, out: &mut Vec<PathBuf>) {
    let name = dir.file_name().unwrap_or_default().to_string_lossy();
    if name.starts_with('.') || name.starts_with("target") || name == "node_modules" {
        return;
    }
    if dir.join("Cargo.toml").is_file() && dir.join("src").is_dir() {
        out.push(dir.join("src"));
        if let Ok(bins) = std::fs::read_dir(dir.join("src/bin")) {
            out.extend(bins.map(|e| e.unwrap().path()).filter(|p| p.is_dir()));
        }
    }
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() && path.file_name() != Some("src".as_ref()) {
            source_roots(&path, out);
        }
    }
}

#[test]
fn no_module_imports_its_importer() {
    let repo = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut roots = Vec::new();
    source_roots(&repo, &mut roots);
    // The workspace's crates and the firmware, fuzz, bench and probe crates at least.
    assert!(
        roots.len() >= 12,
        "only {} source folders found",
        roots.len()
    );
    let mut levels_checked = 0;
    for src in &roots {
        for (level, g) in levels(src) {
            levels_checked += 1;
            if let Some(cycle) = find_cycle(&g) {
                panic!(
                    "{} ({level}): module cycle {}",
                    src.display(),
                    cycle.join(" -> ")
                );
            }
        }
    }
    // Crate roots and folder modules of the codec, the core and the roadside among them.
    assert!(levels_checked >= 30, "only {levels_checked} module levels");
}
