//! The daemon's log. Each entry is a message, a priority and an event name (`OBU_EVENT`:
//! `ready`, `pairing`, `security`, `settings`, `systemd`, `watchdog`, `shutdown`, `error`).
//!
//! When standard error is connected to the systemd journal (systemd sets `JOURNAL_STREAM`
//! to its device and inode), entries go over the journal's native protocol as structured
//! fields: `MESSAGE`, `PRIORITY`, `SYSLOG_IDENTIFIER=obu`, `OBU_EVENT` and the entry's own
//! fields. Otherwise, and whenever a send fails, an entry is the plain line
//! `obu: MESSAGE` on standard error, as scripts and tests read it.

use std::os::unix::net::UnixDatagram;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// Where journald receives native-protocol datagrams.
pub const JOURNAL_SOCKET: &str = "/run/systemd/journal/socket";
/// The environment variable naming another journal socket (a journald in a container's
/// namespace seen from outside, or a test's own socket).
pub const JOURNAL_SOCKET_ENV: &str = "OBU_JOURNAL_SOCKET";

/// syslog priorities used by the daemon.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Priority {
    /// The daemon cannot go on.
    Error = 3,
    /// Something the integrator should look at.
    Warning = 4,
    /// A normal but significant event (start, pairing, shutdown).
    Notice = 5,
    /// Information.
    Info = 6,
}

/// A journal connection: a socket and the address of journald's.
pub struct Journal {
    socket: UnixDatagram,
    path: PathBuf,
}

impl Journal {
    /// A journal sending to the socket at `path`.
    pub fn new(path: &Path) -> std::io::Result<Self> {
        Ok(Self {
            socket: UnixDatagram::unbound()?,
            path: path.to_owned(),
        })
    }

    /// Sends one entry; an error when the datagram did not go whole.
    pub fn send(&self, fields: &[(&str, &str)]) -> std::io::Result<()> {
        let entry = encode(fields);
        let sent = self.socket.send_to(&entry, &self.path)?;
        if sent == entry.len() {
            Ok(())
        } else {
            Err(std::io::Error::other("short datagram"))
        }
    }
}

/// Encodes fields in the journal's native protocol: `KEY=value\n`, or, for a value holding
/// a newline, `KEY\n`, its length as 64-bit little-endian, the value and `\n`.
pub fn encode(fields: &[(&str, &str)]) -> Vec<u8> {
    let mut out = Vec::new();
    for (key, value) in fields {
        out.extend_from_slice(key.as_bytes());
        if value.contains('\n') {
            out.push(b'\n');
            out.extend_from_slice(&(value.len() as u64).to_le_bytes());
        } else {
            out.push(b'=');
        }
        out.extend_from_slice(value.as_bytes());
        out.push(b'\n');
    }
    out
}

/// Parses `JOURNAL_STREAM` (`DEVICE:INODE`, both decimal).
pub fn parse_journal_stream(value: &str) -> Option<(u64, u64)> {
    let (dev, ino) = value.trim().split_once(':')?;
    Some((dev.parse().ok()?, ino.parse().ok()?))
}

/// The device and inode of an open descriptor (standard error or output).
fn identity(fd: std::os::fd::BorrowedFd<'_>) -> Option<(u64, u64)> {
    use std::os::unix::fs::MetadataExt;
    let file = std::fs::File::from(fd.try_clone_to_owned().ok()?);
    let meta = file.metadata().ok()?;
    Some((meta.dev(), meta.ino()))
}

/// Whether `fd` is the stream `JOURNAL_STREAM` names.
fn is_journal_stream(fd: std::os::fd::BorrowedFd<'_>) -> bool {
    let Some(want) = std::env::var("JOURNAL_STREAM")
        .ok()
        .and_then(|v| parse_journal_stream(&v))
    else {
        return false;
    };
    identity(fd) == Some(want)
}

static JOURNAL: OnceLock<Option<Journal>> = OnceLock::new();

fn journal() -> Option<&'static Journal> {
    JOURNAL
        .get_or_init(|| {
            use std::os::fd::AsFd;
            if !is_journal_stream(std::io::stderr().as_fd()) {
                return None;
            }
            let path = std::env::var_os(JOURNAL_SOCKET_ENV)
                .filter(|p| !p.is_empty())
                .map_or_else(|| PathBuf::from(JOURNAL_SOCKET), PathBuf::from);
            Journal::new(&path).ok()
        })
        .as_ref()
}

/// Whether standard output goes to the journal too (then the first line is logged as a
/// structured entry rather than printed).
pub fn stdout_is_journal() -> bool {
    use std::os::fd::AsFd;
    journal().is_some() && is_journal_stream(std::io::stdout().as_fd())
}

/// Logs `message` with `priority`, event name `event` and `fields` of our own
/// (`OBU_*` keys: upper case letters, digits and `_`).
pub fn entry(priority: Priority, event: &str, message: &str, fields: &[(&str, &str)]) {
    if let Some(journal) = journal() {
        let prio = (priority as u8).to_string();
        let mut all = vec![
            ("MESSAGE", message),
            ("PRIORITY", prio.as_str()),
            ("SYSLOG_IDENTIFIER", "obu"),
            ("OBU_EVENT", event),
        ];
        all.extend_from_slice(fields);
        if journal.send(&all).is_ok() {
            return;
        }
    }
    eprintln!("obu: {message}");
}

/// An error.
pub fn error(event: &str, message: &str) {
    entry(Priority::Error, event, message, &[]);
}

/// A warning.
pub fn warn(event: &str, message: &str) {
    entry(Priority::Warning, event, message, &[]);
}

/// A notice: a normal but significant event.
pub fn notice(event: &str, message: &str) {
    entry(Priority::Notice, event, message, &[]);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_encode_in_both_forms() {
        let out = encode(&[("MESSAGE", "pairing PIN 1234"), ("OBU_EVENT", "pairing")]);
        assert_eq!(out, b"MESSAGE=pairing PIN 1234\nOBU_EVENT=pairing\n");
        let out = encode(&[("MESSAGE", "a\nb"), ("PRIORITY", "3")]);
        let mut want = b"MESSAGE\n".to_vec();
        want.extend_from_slice(&3u64.to_le_bytes());
        want.extend_from_slice(b"a\nb\nPRIORITY=3\n");
        assert_eq!(out, want);
    }

    #[test]
    fn journal_stream_parses() {
        assert_eq!(parse_journal_stream("8:12345"), Some((8, 12345)));
        assert_eq!(parse_journal_stream("8:12345\n"), Some((8, 12345)));
        for bad in ["", "8", "8:", ":1", "a:1", "8:1:2", "-1:2"] {
            assert_eq!(parse_journal_stream(bad), None, "{bad}");
        }
    }

    #[test]
    fn stderr_of_a_file_is_recognised_by_its_identity() {
        use std::os::fd::AsFd;
        use std::os::unix::fs::MetadataExt;
        let path = std::env::temp_dir().join(format!("obu-log-id-{}", std::process::id()));
        let file = std::fs::File::create(&path).unwrap();
        let meta = std::fs::metadata(&path).unwrap();
        assert_eq!(identity(file.as_fd()), Some((meta.dev(), meta.ino())));
        std::fs::remove_file(path).unwrap();
    }

    #[test]
    fn an_entry_reaches_a_bound_socket_whole() {
        let dir = std::env::temp_dir().join(format!("obu-journal-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("socket");
        let server = UnixDatagram::bind(&path).unwrap();
        let journal = Journal::new(&path).unwrap();
        let message = "cannot save /var/lib/obu/x\ny: denied";
        journal
            .send(&[("MESSAGE", message), ("OBU_EVENT", "pairing")])
            .unwrap();
        let mut buf = [0u8; 256];
        let n = server.recv(&mut buf).unwrap();
        let got = &buf[..n];
        // Read back as journald does: a key, then `=` and a line, or `\n` and a length.
        let (key, rest) = got.split_at(got.iter().position(|&b| b == b'\n').unwrap());
        assert_eq!(key, b"MESSAGE");
        let len = u64::from_le_bytes(rest[1..9].try_into().unwrap()) as usize;
        assert_eq!(&rest[9..9 + len], message.as_bytes());
        assert_eq!(&rest[9 + len..], b"\nOBU_EVENT=pairing\n");
        drop(server);
        std::fs::remove_dir_all(&dir).unwrap();
        assert!(
            journal.send(&[("MESSAGE", "x")]).is_err(),
            "no socket: an error"
        );
    }
}
