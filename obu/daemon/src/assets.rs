//! The tablet app, embedded at build time from `hmi-web/` (see `build.rs`).
//!
//! Two files are adjusted on the way out: the web app manifest gets its own MIME type, and
//! the service worker (`sw.js`, served from `/sw.js` so that its scope is `/`) gets the
//! version of the app shell stamped in: a hash of every other app file. A daemon with other
//! app files therefore serves another `sw.js`; the browser installs it and the service
//! worker replaces its cached shell.
//!
//! `contract.json` (the alert kinds in priority order, the stages, the settings' ranges,
//! defaults and units) is written from the core ([`obu::alert::settings`]) by [`contract`],
//! so the daemon serves the contract of the core it runs. `hmi-web/contract.json`, which the
//! app imports and the tablet's unit tests read, is the same text (`obu
//! --print-hmi-contract`); a test here fails when the two differ.

use std::sync::OnceLock;

include!(concat!(env!("OUT_DIR"), "/assets.rs"));

/// The service worker, whose placeholder is replaced by [`shell_version`].
const SERVICE_WORKER: &str = "sw.js";
/// What `sw.js` holds where the shell version goes.
const VERSION_PLACEHOLDER: &[u8] = b"@HMI_SHELL_VERSION@";
/// Files `build.rs` embeds that are not part of the app (the README's screenshots).
const NOT_SERVED: &[&str] = &["screenshots/"];

/// The tablet's contract, written from the core.
const CONTRACT: &str = "contract.json";

/// The tablet's contract as JSON text, from the core's definitions (made once).
pub fn contract() -> &'static str {
    static TEXT: OnceLock<String> = OnceLock::new();
    TEXT.get_or_init(|| {
        let mut text = String::new();
        obu::alert::settings::write_contract_json(&mut text).expect("a String takes any text");
        text
    })
}

/// The MIME type and content of the embedded file at `path` (no leading slash).
pub fn find(path: &str) -> Option<(&'static str, &'static [u8])> {
    if NOT_SERVED.iter().any(|p| path.starts_with(p)) {
        return None;
    }
    if path == CONTRACT {
        return Some(("application/json", contract().as_bytes()));
    }
    let (mime, body) = ASSETS
        .iter()
        .find(|(p, _, _)| *p == path)
        .map(|(_, m, b)| (*m, *b))?;
    let body = if path == SERVICE_WORKER {
        service_worker(body)
    } else {
        body
    };
    Some((mime_of(path, mime), body))
}

/// The MIME type of `path`: the manifest's own type, else what `build.rs` chose.
fn mime_of(path: &str, built: &'static str) -> &'static str {
    if path.ends_with(".webmanifest") {
        "application/manifest+json"
    } else {
        built
    }
}

/// `sw.js` with the shell version stamped in (made once).
fn service_worker(source: &'static [u8]) -> &'static [u8] {
    static STAMPED: OnceLock<Vec<u8>> = OnceLock::new();
    STAMPED.get_or_init(|| replace(source, VERSION_PLACEHOLDER, shell_version().as_bytes()))
}

/// The version of the app shell: 64-bit FNV-1a over the daemon's version and the path and
/// content of every served app file except the service worker, in hex.
pub fn shell_version() -> String {
    let mut hash = Fnv::new();
    hash.write(env!("CARGO_PKG_VERSION").as_bytes());
    for (path, _, body) in ASSETS {
        if *path == SERVICE_WORKER || NOT_SERVED.iter().any(|p| path.starts_with(p)) {
            continue;
        }
        let body = if *path == CONTRACT {
            contract().as_bytes()
        } else {
            body
        };
        hash.write(path.as_bytes());
        hash.write(&[0]);
        hash.write(body);
        hash.write(&(body.len() as u64).to_le_bytes());
    }
    format!("{:016x}", hash.0)
}

/// 64-bit FNV-1a.
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= u64::from(*b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
}

/// `haystack` with every `needle` replaced by `with`.
fn replace(haystack: &[u8], needle: &[u8], with: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(haystack.len() + with.len());
    let mut rest = haystack;
    while !needle.is_empty() {
        match rest.windows(needle.len()).position(|w| w == needle) {
            Some(i) => {
                out.extend_from_slice(&rest[..i]);
                out.extend_from_slice(with);
                rest = &rest[i + needle.len()..];
            }
            None => break,
        }
    }
    out.extend_from_slice(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_app_is_embedded() {
        let (mime, body) = super::find("index.html").expect("hmi-web/index.html is embedded");
        assert!(mime.starts_with("text/html"));
        assert!(!body.is_empty());
        assert!(
            super::find("tests/run.mjs").is_none(),
            "tests are not shipped"
        );
    }

    #[test]
    fn the_apps_contract_is_the_cores() {
        let embedded = ASSETS
            .iter()
            .find(|(p, _, _)| *p == CONTRACT)
            .map(|(_, _, b)| *b)
            .expect("hmi-web/contract.json is embedded");
        assert!(
            embedded == contract().as_bytes(),
            "hmi-web/contract.json differs from the core's contract: regenerate it with \
             `cargo run -p obu-daemon -- --print-hmi-contract > hmi-web/contract.json`"
        );
        assert_eq!(find(CONTRACT).unwrap().1, contract().as_bytes());
    }

    #[test]
    fn offline_files_have_their_types() {
        let types = [
            ("manifest.webmanifest", "application/manifest+json"),
            ("sw.js", "text/javascript"),
            ("app.js", "text/javascript"),
            ("icon.svg", "image/svg+xml"),
            ("icon-maskable.svg", "image/svg+xml"),
        ];
        for (path, want) in types {
            let (mime, body) = find(path).unwrap_or_else(|| panic!("{path} is embedded"));
            assert!(mime.starts_with(want), "{path}: {mime}");
            assert!(!body.is_empty(), "{path}");
        }
        let manifest = std::str::from_utf8(find("manifest.webmanifest").unwrap().1).unwrap();
        let json: serde_json::Value = serde_json::from_str(manifest).expect("the manifest is JSON");
        for icon in json["icons"].as_array().expect("icons") {
            let src = icon["src"].as_str().expect("src");
            assert!(find(src).is_some(), "the manifest's icon {src} is embedded");
        }
    }

    #[test]
    fn the_service_worker_carries_the_shell_version_and_caches_every_app_file() {
        let sw = std::str::from_utf8(find("sw.js").unwrap().1).unwrap();
        let version = shell_version();
        assert_eq!(version.len(), 16);
        assert!(sw.contains(&format!("'{version}'")), "version stamped");
        assert!(!sw.contains("@HMI_SHELL_VERSION@"));
        for (path, _, _) in ASSETS {
            let served = find(path).is_some();
            if served && *path != "sw.js" {
                assert!(
                    sw.contains(&format!("'/{path}'")),
                    "{path} is in the cached shell"
                );
            }
        }
        assert!(find("screenshots/warning-tablet.png").is_none());
        // and every file of the shell exists (one missing file fails the worker's install)
        let list = sw
            .split("const SHELL = [")
            .nth(1)
            .and_then(|r| r.split("];").next());
        let shell: Vec<&str> = list
            .expect("sw.js has its SHELL list")
            .split(',')
            .map(|p| p.trim().trim_matches('\''))
            .filter(|p| !p.is_empty())
            .collect();
        assert!(shell.len() >= 12, "{shell:?}");
        for path in shell {
            let file = path.trim_start_matches('/');
            assert!(find(file).is_some(), "the shell's {path} is served");
        }
    }

    #[test]
    fn replace_all_occurrences() {
        assert_eq!(replace(b"a@x@b@x@", b"@x@", b"1"), b"a1b1".to_vec());
        assert_eq!(replace(b"abc", b"", b"1"), b"abc".to_vec());
        assert_eq!(replace(b"abc", b"zz", b"1"), b"abc".to_vec());
    }
}
