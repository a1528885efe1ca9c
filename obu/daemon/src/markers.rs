//! The superseded check's markers in the state directory, so that a restart does not forget
//! which version of a message is the newest (a cancel stays a cancel across a reboot).
//!
//! One marker a line, `identity newest relevant_until` (32 hexadecimal digits, then two
//! `Time64` in decimal); written whole to a temporary file and renamed. Read back bounded:
//! at most [`MAX_FILE`] bytes and [`obu::capacity::MAX_NEWEST`] markers; a line that does not
//! read is skipped and counted.

use obu::security::{Identity, Marker};
use std::io::Read;
use std::path::{Path, PathBuf};

/// Largest markers file read, bytes (64 markers take about 4 KiB).
pub const MAX_FILE: u64 = 16 * 1024;

/// The markers file beside the settings file.
pub fn path_for(settings_file: &Path) -> PathBuf {
    settings_file.with_extension("superseded.txt")
}

/// The markers kept in `path` and the number of lines skipped; none when there is no file.
///
/// # Errors
///
/// The file system's error other than a missing file.
pub fn load(path: &Path) -> std::io::Result<(Vec<Marker>, usize)> {
    let file = match std::fs::File::open(path) {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok((Vec::new(), 0)),
        Err(e) => return Err(e),
    };
    let mut text = String::new();
    file.take(MAX_FILE).read_to_string(&mut text)?;
    let (mut markers, mut skipped) = (Vec::new(), 0);
    for line in text.lines().filter(|l| !l.trim().is_empty()) {
        match parse_line(line) {
            Some(m) if markers.len() < obu::capacity::MAX_NEWEST => markers.push(m),
            _ => skipped += 1,
        }
    }
    Ok((markers, skipped))
}

fn parse_line(line: &str) -> Option<Marker> {
    let mut fields = line.split_ascii_whitespace();
    let id = fields.next()?;
    let newest_us = fields.next()?.parse().ok()?;
    let relevant_until_us = fields.next()?.parse().ok()?;
    if fields.next().is_some() || id.len() != 32 {
        return None;
    }
    let mut identity = [0u8; 16];
    j2735::hex::decode_into(id, &mut identity).ok()?;
    Some(Marker {
        identity: Identity(identity),
        newest_us,
        relevant_until_us,
    })
}

/// Writes `markers` to `path` (a temporary file beside it, then renamed).
///
/// # Errors
///
/// The file system's error.
pub fn save(path: &Path, markers: &[Marker]) -> std::io::Result<()> {
    let mut text = String::with_capacity(markers.len() * 64);
    for m in markers {
        text.push_str(&format!(
            "{} {} {}\n",
            j2735::hex::Hex(&m.identity.0),
            m.newest_us,
            m.relevant_until_us
        ));
    }
    let tmp = path.with_extension("superseded.tmp");
    std::fs::write(&tmp, text)?;
    std::fs::rename(&tmp, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markers_read_back_as_written_and_bad_lines_are_skipped() {
        let dir = std::env::temp_dir().join(format!("obu-markers-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = path_for(&dir.join("obu-settings.json"));
        assert_eq!(load(&path).unwrap(), (Vec::new(), 0));
        let markers = [
            Marker {
                identity: Identity::of(b'T', &[1, 2, 3]),
                newest_us: 700_000_000_000_000,
                relevant_until_us: 700_000_060_000_000,
            },
            Marker {
                identity: Identity::of(b'M', &[4]),
                newest_us: 1,
                relevant_until_us: u64::MAX,
            },
        ];
        save(&path, &markers).unwrap();
        assert_eq!(load(&path).unwrap(), (markers.to_vec(), 0));
        let mut text = std::fs::read_to_string(&path).unwrap();
        text.push_str("zz 1 2\n0123 1\n\n");
        std::fs::write(&path, text).unwrap();
        assert_eq!(load(&path).unwrap(), (markers.to_vec(), 2));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
