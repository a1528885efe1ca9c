//! The tablet app, embedded at build time from `hmi-web/` (see `build.rs`).

include!(concat!(env!("OUT_DIR"), "/assets.rs"));

/// The MIME type and content of the embedded file at `path` (no leading slash).
pub fn find(path: &str) -> Option<(&'static str, &'static [u8])> {
    ASSETS
        .iter()
        .find(|(p, _, _)| *p == path)
        .map(|(_, m, b)| (*m, *b))
}

#[cfg(test)]
mod tests {
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
}
